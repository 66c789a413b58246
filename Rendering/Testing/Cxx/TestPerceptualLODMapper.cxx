// SPDX-License-Identifier: BSD-3-Clause
// vtkPerceptualLODMapper, the GPU draw path: over random cuts, the image and the triangles of
// the CPU path (vtkMultiscalePatchGenerator drawn by a vtkPolyDataMapper), folds kept on both
// and treated by each path's default; ghost-led triangles not drawn; a still frame uploads
// nothing; a change of cut uploads the changed spans of the state.
#include "plodCut.h"
#include "plodOctree.h"
#include "plodTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkImageData.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODMapper.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace
{
/// A window, a renderer and an actor drawing `mapper`; the image of one render.
struct View
{
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkActor> Actor;
  explicit View(vtkMapper* mapper)
  {
    this->Window->SetOffScreenRendering(1);
    this->Window->SetSize(300, 300);
    this->Window->AddRenderer(this->Renderer);
    this->Renderer->SetBackground(0.1, 0.6, 0.9);
    this->Actor->SetMapper(mapper);
    this->Renderer->AddActor(this->Actor);
  }
  std::vector<unsigned char> Image()
  {
    this->Window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(this->Window);
    grab->ReadFrontBufferOff();
    grab->Update();
    auto* px = vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
    return std::vector<unsigned char>(
      px->GetPointer(0), px->GetPointer(0) + px->GetNumberOfValues());
  }
};

/// The octree of `model` at the builder's defaults, a copy of its own (tests edit its arrays).
vtkSmartPointer<vtkMultiscaleOctree> BuildOctree(vtkPolyData* model)
{
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(model);
  builder->Update();
  auto octree = vtkSmartPointer<vtkMultiscaleOctree>::New();
  octree->DeepCopy(builder->GetOutput());
  return octree;
}

/// Pixels covered in `a` (not the background of its first pixel), and pixels where `a` and `b`
/// differ by more than 8 in a channel.
std::pair<int, int> CoveredAndDiffering(
  const std::vector<unsigned char>& a, const std::vector<unsigned char>& b)
{
  int covered = 0, differ = 0;
  for (size_t i = 0; i + 2 < a.size(); i += 3)
  {
    covered += (a[i] != a[0] || a[i + 1] != a[1] || a[i + 2] != a[2]) ? 1 : 0;
    const int d = std::max(
      { std::abs(a[i] - b[i]), std::abs(a[i + 1] - b[i + 1]), std::abs(a[i + 2] - b[i + 2]) });
    differ += d > 8 ? 1 : 0;
  }
  return { covered, differ };
}

/// A random valid cut of `v` (refinement falling with depth, some leaves opened).
std::vector<uint8_t> RandomCut(const plod::OctreeView& v, std::mt19937& rng)
{
  std::uniform_real_distribution<double> U(0, 1);
  const double bias = U(rng);
  std::vector<uint8_t> cut(v.NumberOfNodes, plod::NotInCut);
  std::vector<int32_t> stack{ 0 };
  while (!stack.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    const bool refine = U(rng) < 0.75 + 0.25 * bias - 0.05 * v.Level[n];
    if (v.IsLeaf(n) && refine)
      cut[n] = plod::CutOpen;
    else if (!refine)
      cut[n] = plod::CutDrawn;
    else
      for (int c = 0; c < __builtin_popcount(v.ChildMask[n]); ++c)
        stack.push_back(v.FirstChild[n] + c);
  }
  return cut;
}

void SetCut(vtkMultiscaleOctree* octree, const std::vector<uint8_t>& cut)
{
  vtkNew<vtkUnsignedCharArray> a;
  a->SetName(vtkMultiscaleOctree::CutStateArrayName());
  a->SetNumberOfTuples(static_cast<vtkIdType>(cut.size()));
  std::copy(cut.begin(), cut.end(), a->GetPointer(0));
  octree->GetNodeData()->AddArray(a);
  octree->Modified();
}
}

TEST(PerceptualLODMapper, RandomCutsDrawTheCPUPathsImageAndTriangles)
{
  std::vector<std::pair<std::string, vtkSmartPointer<vtkPolyData>>> models = {
    { "blob", plodtest::MakeBlob(3, 60, 0.3) },
    { "thin box", plodtest::MakeThinBox(0.02, 10) },
    { "thin disc", plodtest::MakeThinDisc(0.02, 10) },
  };
  const std::string bunny =
    plodtest::DataDir().empty() ? "" : plodtest::DataDir() + "/bun_zipper.ply";
  if (!bunny.empty())
  {
    models.push_back({ "bunny", plodtest::ReadModel(bunny) });
  }
  std::mt19937 rng(3);
  int foldPixels = 0, defaultsDifferTotal = 0;
  for (const auto& model : models)
  {
    ASSERT_NE(model.second, nullptr) << model.first;
    vtkSmartPointer<vtkMultiscaleOctree> octree = BuildOctree(model.second);
    plod::OctreeView v;
    ASSERT_TRUE(octree->GetView(v)) << model.first;
    vtkNew<vtkTrivialProducer> source;
    source->SetOutput(octree);
    // each path twice: folds kept, and each path's default (reversed normals)
    vtkNew<vtkMultiscalePatchGenerator> patches, patchesDefault;
    patches->SetInputConnection(source->GetOutputPort());
    patches->SetFoldHandling(vtkMultiscalePatchGenerator::FOLDS_KEEP);
    patchesDefault->SetInputConnection(source->GetOutputPort());
    vtkNew<vtkPolyDataMapper> cpuMapper, cpuDefaultMapper;
    cpuMapper->SetInputConnection(patches->GetOutputPort());
    cpuMapper->ScalarVisibilityOff();
    cpuDefaultMapper->SetInputConnection(patchesDefault->GetOutputPort());
    cpuDefaultMapper->ScalarVisibilityOff();
    vtkNew<vtkPerceptualLODMapper> gpuMapper, gpuDefaultMapper;
    gpuMapper->SetOctreeConnection(source->GetOutputPort());
    gpuMapper->SetFoldHandling(vtkMultiscalePatchGenerator::FOLDS_KEEP);
    gpuDefaultMapper->SetOctreeConnection(source->GetOutputPort());
    ASSERT_EQ(gpuDefaultMapper->GetFoldHandling(), patchesDefault->GetFoldHandling());
    View cpu(cpuMapper), gpu(gpuMapper), cpuDefault(cpuDefaultMapper), gpuDefault(gpuDefaultMapper);
    cpu.Renderer->ResetCamera(model.second->GetBounds());
    cpu.Renderer->GetActiveCamera()->Azimuth(35);
    cpu.Renderer->GetActiveCamera()->Elevation(20);
    cpu.Renderer->ResetCameraClippingRange();
    for (View* other : { &gpu, &cpuDefault, &gpuDefault })
    {
      other->Renderer->SetActiveCamera(cpu.Renderer->GetActiveCamera());
    }
    for (int trial = 0; trial < 6; ++trial)
    {
      SetCut(octree, RandomCut(v, rng));
      source->Modified();
      const std::vector<unsigned char> a = cpu.Image(), b = gpu.Image();
      ASSERT_EQ(a.size(), b.size());
      const std::string what = model.first + " cut " + std::to_string(trial);
      // the same triangles (no hidden cells, no back-face culling, folds kept)
      EXPECT_EQ(gpuMapper->GetNumberOfDrawnTriangles(), patches->GetNumberOfTriangles()) << what;
      const auto [covered, differ] = CoveredAndDiffering(a, b);
      if (patches->GetNumberOfTriangles() > 200)
      {
        EXPECT_GT(covered, 500) << what;
      }
      // the defaults: folds lit as the surface facing the viewer on both paths; the GPU path
      // decides per fragment, so fragments of triangles with only some corner normals opposing
      // the face are treated as folds too (the patch generator draws those as they are)
      const std::vector<unsigned char> c = cpuDefault.Image(), d = gpuDefault.Image();
      const int defaultsDiffer = CoveredAndDiffering(c, d).second;
      const int foldsShow = CoveredAndDiffering(a, c).second;
      std::printf("%s: %lld triangles (%lld folds), %d pixels covered, %d differ folds kept, "
                  "%d differ by default; the default changes %d pixels\n",
        what.c_str(), static_cast<long long>(patches->GetNumberOfTriangles()),
        static_cast<long long>(patchesDefault->GetNumberOfFolds()), covered, differ, defaultsDiffer,
        foldsShow);
      // the same picture, up to pixels at edges where the two paths' single-precision
      // positions round differently (the GPU path adds the origin in the shader)
      EXPECT_LE(differ, covered / 200 + 5) << what << ": pixels that differ by more than 8";
      EXPECT_LE(defaultsDiffer, covered / 200 + 5) << what << ": by default";
      foldPixels += foldsShow;
      defaultsDifferTotal += defaultsDiffer;
    }
  }
  // the fold rule at work: the pixels that reversing the folds changes on the CPU path are
  // changed the same way on the GPU path
  EXPECT_GT(foldPixels, 100) << "too few folds in view to test the rule";
  EXPECT_LE(defaultsDifferTotal, foldPixels / 10);
}

TEST(PerceptualLODMapper, GhostLedTrianglesAreNotDrawn)
{
  auto blob = plodtest::MakeBlob(5, 60, 0.3);
  vtkSmartPointer<vtkMultiscaleOctree> octree = BuildOctree(blob);
  // every third point a ghost, in runs (as a piece of a distributed mesh has them)
  octree->AllocatePointGhosts();
  auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
    octree->GetSurfaceData()->GetArray(vtkMultiscaleOctree::PointGhostArrayName()));
  ASSERT_NE(ghosts, nullptr);
  for (vtkIdType p = 0; p < ghosts->GetNumberOfValues(); ++p)
    ghosts->SetValue(p, (p / 50) % 3 == 0 ? 1 : 0);
  octree->Modified();
  plod::OctreeView v;
  ASSERT_TRUE(octree->GetView(v));
  ASSERT_NE(v.PointGhost, nullptr);
  vtkNew<vtkTrivialProducer> source;
  source->SetOutput(octree);
  vtkNew<vtkMultiscalePatchGenerator> patches;
  patches->SetInputConnection(source->GetOutputPort());
  patches->SetFoldHandling(vtkMultiscalePatchGenerator::FOLDS_KEEP);
  vtkNew<vtkPolyDataMapper> cpuMapper;
  cpuMapper->SetInputConnection(patches->GetOutputPort());
  cpuMapper->ScalarVisibilityOff();
  vtkNew<vtkPerceptualLODMapper> gpuMapper;
  gpuMapper->SetOctreeConnection(source->GetOutputPort());
  gpuMapper->SetFoldHandling(vtkMultiscalePatchGenerator::FOLDS_KEEP);
  View cpu(cpuMapper), gpu(gpuMapper);
  cpu.Renderer->ResetCamera(blob->GetBounds());
  gpu.Renderer->SetActiveCamera(cpu.Renderer->GetActiveCamera());
  std::mt19937 rng(11);
  int compared = 0;
  for (int trial = 0; trial < 6; ++trial)
  {
    SetCut(octree, RandomCut(v, rng));
    source->Modified();
    const std::vector<unsigned char> a = cpu.Image(), b = gpu.Image();
    const std::string what = "cut " + std::to_string(trial);
    if (patches->GetNumberOfTriangles() + patches->GetNumberOfGhostTriangles() < 100)
    {
      continue; // a cut near the root: too few triangles to tell
    }
    ++compared;
    EXPECT_GT(patches->GetNumberOfGhostTriangles(), 0) << what;
    EXPECT_EQ(gpuMapper->GetNumberOfDrawnTriangles(), patches->GetNumberOfTriangles()) << what;
    const auto [covered, differ] = CoveredAndDiffering(a, b);
    EXPECT_GT(covered, 500) << what;
    EXPECT_LE(differ, covered / 200 + 5) << what << ": pixels that differ by more than 8";
  }
  EXPECT_GE(compared, 3);
}

TEST(PerceptualLODMapper, StillFramesUploadNothingAndChangesUploadTheirSpans)
{
  auto blob = plodtest::MakeBlob(4, 80, 0.3);
  vtkSmartPointer<vtkMultiscaleOctree> octree = BuildOctree(blob);
  plod::OctreeView v;
  ASSERT_TRUE(octree->GetView(v));
  vtkNew<vtkTrivialProducer> source;
  source->SetOutput(octree);
  vtkNew<vtkPerceptualLODMapper> mapper;
  mapper->SetOctreeConnection(source->GetOutputPort());
  View view(mapper);
  view.Renderer->ResetCamera(blob->GetBounds());
  std::vector<uint8_t> cut(v.NumberOfNodes);
  plod::UniformCut(v, 3, cut.data());
  SetCut(octree, cut);
  view.Window->Render();
  EXPECT_GT(mapper->GetLastUploadBytes(), v.NumberOfNodes) << "the first frame sends the octree";
  EXPECT_EQ(mapper->GetLastStateUploadBytes(), v.NumberOfNodes);
  // a still frame: nothing sent
  view.Window->Render();
  EXPECT_EQ(mapper->GetLastUploadBytes(), 0);
  const vtkIdType before = mapper->GetNumberOfDrawnTriangles();
  EXPECT_GT(before, 0);
  // one node of level 3 that owns triangles, refined into its children: a few bytes, far fewer
  // than the state, and its triangles drawn
  int32_t node = -1;
  for (int32_t n = 0; n < v.NumberOfNodes && node < 0; ++n)
    if (v.Level[n] == 3 && v.TriangleEnd(n) > v.FirstTriangle[n] && !v.IsLeaf(n))
      node = n;
  ASSERT_GE(node, 0);
  std::vector<uint8_t> next = cut;
  next[node] = plod::NotInCut;
  int changed = 1;
  for (int c = 0; c < __builtin_popcount(v.ChildMask[node]); ++c, ++changed)
    next[v.FirstChild[node] + c] = plod::CutDrawn;
  SetCut(octree, next);
  source->Modified();
  view.Window->Render();
  EXPECT_GE(mapper->GetLastStateUploadBytes(), changed);
  EXPECT_LE(mapper->GetLastStateUploadBytes(), 2 * 64 + changed) << "more than the change";
  EXPECT_EQ(mapper->GetLastUploadBytes(), mapper->GetLastStateUploadBytes());
  EXPECT_EQ(
    mapper->GetNumberOfDrawnTriangles(), before + (v.TriangleEnd(node) - v.FirstTriangle[node]));
  EXPECT_LT(mapper->GetLastStateUploadBytes(), v.NumberOfNodes / 4);
}

TEST(PerceptualLODMapper, MissingFeatureIsNamed)
{
  vtkNew<vtkPerceptualLODMapper> mapper;
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->Render();
  EXPECT_TRUE(mapper->IsSupported(window)) << mapper->GetUnsupportedReason();
  mapper->SetSimulatedMissingFeature("glMultiDrawElements");
  EXPECT_FALSE(mapper->IsSupported(window));
  EXPECT_STREQ(mapper->GetUnsupportedReason(), "glMultiDrawElements");
}
