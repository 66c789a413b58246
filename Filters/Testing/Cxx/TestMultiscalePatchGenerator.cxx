// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkMultiscalePatchGenerator and vtkMultiscaleOctreeCutter: no crack for any cut of a
// closed model (thousands of random cuts), orientation, exact small cases, hidden cells,
// accuracy at the finest level, pipeline behaviour, bad cuts and the bunny's holes.
#include "plodOctree.h"
#include "plodTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkMath.h"
#include "vtkFeatureEdges.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStaticCellLocator.h"
#include "vtkTriangle.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <array>
#include <map>
#include <random>
#include <set>

namespace
{
vtkSmartPointer<vtkMultiscaleOctree> BuildOctree(vtkPolyData* input, int level)
{
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(input);
  builder->SetFinestLevel(level);
  builder->Update();
  return builder->GetOutput();
}

/// Octree copy carrying the given cut states.
vtkSmartPointer<vtkMultiscaleOctree> WithCut(vtkMultiscaleOctree* octree, const std::vector<uint8_t>& cut)
{
  auto copy = vtkSmartPointer<vtkMultiscaleOctree>::New();
  copy->ShallowCopy(octree);
  vtkNew<vtkUnsignedCharArray> a;
  a->SetName(vtkMultiscaleOctree::CutStateArrayName());
  a->SetNumberOfTuples(static_cast<vtkIdType>(cut.size()));
  std::copy(cut.begin(), cut.end(), a->GetPointer(0));
  copy->GetNodeData()->AddArray(a);
  return copy;
}

vtkSmartPointer<vtkPolyData> Patches(vtkMultiscaleOctree* octree, plodtest::ErrorRecorder* errors = nullptr)
{
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputData(octree);
  gen->GenerateNodeIdsOn();
  if (errors)
  {
    gen->AddObserver(vtkCommand::ErrorEvent, errors);
  }
  gen->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->ShallowCopy(gen->GetOutput());
  return pd;
}

/// Random valid cut: refine with a probability that decreases with depth; some cells hidden.
std::vector<uint8_t> RandomCut(const plod::OctreeView& v, std::mt19937& rng, double hidden)
{
  std::uniform_real_distribution<double> U(0, 1);
  const double bias = U(rng);
  std::vector<uint8_t> cut(v.NumberOfNodes, 0);
  std::vector<int32_t> stack{ 0 };
  while (!stack.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    const bool refine = v.ChildMask[n] != 0 && U(rng) < 0.55 + 0.45 * bias - 0.05 * v.Level[n];
    if (!refine && v.ChildMask[n] == 0 && v.Level[n] != v.FinestLevel)
    {
      ADD_FAILURE() << "leaf above the finest level";
    }
    if (!refine)
    {
      cut[n] = U(rng) < hidden ? 2 : 1;
      continue;
    }
    for (int c = 0; c < __builtin_popcount(v.ChildMask[n]); ++c)
    {
      stack.push_back(v.FirstChild[n] + c);
    }
  }
  return cut;
}

struct EdgeStats
{
  int Odd = 0;              // edges used an odd number of times (cracks)
  int Unbalanced = 0;       // edges not used equally in both directions (orientation)
  int Degenerate = 0;       // triangles repeating a point or of zero area
  std::set<std::pair<vtkIdType, vtkIdType>> Boundary; // odd edges
};

EdgeStats Analyse(vtkPolyData* pd)
{
  EdgeStats s;
  std::map<std::pair<vtkIdType, vtkIdType>, int> directed;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    EXPECT_EQ(n, 3);
    double a[3], b[3], c[3];
    pd->GetPoint(ids[0], a);
    pd->GetPoint(ids[1], b);
    pd->GetPoint(ids[2], c);
    double u[3], w[3], cross[3];
    vtkMath::Subtract(b, a, u);
    vtkMath::Subtract(c, a, w);
    vtkMath::Cross(u, w, cross);
    double r[3];
    vtkMath::Subtract(c, b, r);
    const double longest = std::max({ vtkMath::Dot(u, u), vtkMath::Dot(w, w), vtkMath::Dot(r, r) });
    // degenerate: a repeated point, or flatter than 1e-7 of the longest side squared
    if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2] ||
      vtkMath::Norm(cross) <= 1e-7 * longest)
    {
      if (s.Degenerate == 0)
      {
        std::cout << "degenerate: " << ids[0] << " " << ids[1] << " " << ids[2] << " (" << a[0]
                  << "," << a[1] << "," << a[2] << ") (" << b[0] << "," << b[1] << "," << b[2]
                  << ") (" << c[0] << "," << c[1] << "," << c[2] << ")\n";
      }
      ++s.Degenerate;
    }
    for (int k = 0; k < 3; ++k)
    {
      ++directed[{ ids[k], ids[(k + 1) % 3] }];
    }
  }
  for (const auto& kv : directed)
  {
    const auto rev = std::make_pair(kv.first.second, kv.first.first);
    if (kv.first > rev)
    {
      continue; // each undirected edge once
    }
    const int back = directed.count(rev) ? directed.at(rev) : 0;
    if ((kv.second + back) % 2)
    {
      ++s.Odd;
      s.Boundary.insert(kv.first);
    }
    if (kv.second != back)
    {
      ++s.Unbalanced;
    }
  }
  for (const auto& kv : directed)
  {
    const auto rev = std::make_pair(kv.first.second, kv.first.first);
    if (kv.first < rev && !directed.count(rev) && !s.Boundary.count(kv.first))
    {
      // counted above through kv; nothing more to do
    }
  }
  return s;
}
} // namespace

// ---- the central property: no crack for any cut ----------------------------------------------

TEST(MultiscalePatchGenerator, AnyCutOfAClosedModelIsClosedOrientedAndNonDegenerate)
{
  std::vector<vtkSmartPointer<vtkPolyData>> models = { plodtest::MakeBlob(1, 24, 0.3),
    plodtest::MakeBlob(2, 40, 0.35), plodtest::MakeCube(-1, 1), plodtest::MakeTetrahedron(),
    plodtest::MakeBlob(3, 32, 0.0) };
  std::mt19937 rng(12345);
  int cuts = 0, triangles = 0;
  for (size_t m = 0; m < models.size(); ++m)
  {
    auto octree = BuildOctree(models[m], 5);
    plod::OctreeView v;
    ASSERT_TRUE(octree->GetView(v));
    for (int k = 0; k < 500; ++k, ++cuts)
    {
      auto cut = RandomCut(v, rng, 0.0);
      auto pd = Patches(WithCut(octree, cut));
      const EdgeStats s = Analyse(pd);
      ASSERT_EQ(s.Odd, 0) << "crack: model " << m << " cut " << k;
      ASSERT_EQ(s.Unbalanced, 0) << "inconsistent orientation: model " << m << " cut " << k;
      ASSERT_EQ(s.Degenerate, 0) << "degenerate triangle: model " << m << " cut " << k;
      triangles += pd->GetNumberOfPolys();
    }
  }
  EXPECT_EQ(cuts, 2500);
  EXPECT_GT(triangles, 100000);
}

TEST(MultiscalePatchGenerator, HiddenCellsOpenTheSurfaceOnlyAmongThemselves)
{
  auto octree = BuildOctree(plodtest::MakeBlob(5, 32, 0.3), 5);
  plod::OctreeView v;
  ASSERT_TRUE(octree->GetView(v));
  std::mt19937 rng(7);
  for (int k = 0; k < 300; ++k)
  {
    auto cut = RandomCut(v, rng, 0.3);
    auto pd = Patches(WithCut(octree, cut));
    const EdgeStats s = Analyse(pd);
    EXPECT_EQ(s.Unbalanced, s.Odd) << "only boundary edges may be unbalanced";
    EXPECT_EQ(s.Degenerate, 0);
    auto* node = vtkIdTypeArray::SafeDownCast(pd->GetPointData()->GetArray("OctreeNode"));
    ASSERT_TRUE(node);
    for (const auto& e : s.Boundary)
    {
      // a boundary edge joins two hidden cells (a polygon of hidden cells only was skipped)
      ASSERT_EQ(cut[node->GetValue(e.first)], 2);
      ASSERT_EQ(cut[node->GetValue(e.second)], 2);
    }
    // a triangle with no drawn corner is the other half of a quad that has one: it shares an
    // edge with a triangle that has a drawn corner
    std::map<std::pair<vtkIdType, vtkIdType>, int> drawnEdges;
    std::vector<std::array<vtkIdType, 3>> hiddenOnly;
    auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      const bool drawn = cut[node->GetValue(ids[0])] == 1 || cut[node->GetValue(ids[1])] == 1 ||
        cut[node->GetValue(ids[2])] == 1;
      if (!drawn)
      {
        hiddenOnly.push_back({ ids[0], ids[1], ids[2] });
        continue;
      }
      for (int e = 0; e < 3; ++e)
        ++drawnEdges[{ std::min(ids[e], ids[(e + 1) % 3]), std::max(ids[e], ids[(e + 1) % 3]) }];
    }
    for (const auto& t : hiddenOnly)
    {
      bool mate = false;
      for (int e = 0; e < 3; ++e)
        mate = mate ||
          drawnEdges.count({ std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3]) });
      ASSERT_TRUE(mate);
    }
  }
  // all hidden: nothing is drawn
  std::vector<uint8_t> cut(v.NumberOfNodes, 0);
  plod::OctreeView view;
  octree->GetView(view);
  for (int64_t n = 0; n < view.NumberOfNodes; ++n)
    cut[n] = view.Level[n] == 3 ? 2 : 0;
  EXPECT_EQ(Patches(WithCut(octree, cut))->GetNumberOfPolys(), 0);
}

// ---- exact small cases ------------------------------------------------------------------------

TEST(MultiscalePatchGenerator, RootAloneAndLevelOneOfAConvexModel)
{
  auto octree = BuildOctree(plodtest::MakeCube(-1, 1), 4);
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(octree);
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputConnection(cutter->GetOutputPort());
  // the root alone: no edge inside a single cell is crossed, so nothing is drawn
  cutter->SetLevel(0);
  gen->Update();
  EXPECT_EQ(gen->GetOutput()->GetNumberOfPolys(), 0);
  EXPECT_EQ(gen->GetOutput()->GetNumberOfPoints(), 0);
  // level 1: eight cells around the centre; each of the 6 half-axes is crossed once, giving 6
  // quads (12 triangles) on the 8 cell vertices: a closed "cube" of the corner cells
  cutter->SetLevel(1);
  gen->Update();
  EXPECT_EQ(gen->GetOutput()->GetNumberOfPolys(), 12);
  EXPECT_EQ(gen->GetOutput()->GetNumberOfPoints(), 8);
  EXPECT_EQ(Analyse(gen->GetOutput()).Odd, 0);
  // triangles face outwards, like the input's: normal . centroid > 0
  vtkPolyData* pd = gen->GetOutput();
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    double a[3], b[3], c[3], normal[3];
    pd->GetPoint(ids[0], a);
    pd->GetPoint(ids[1], b);
    pd->GetPoint(ids[2], c);
    vtkTriangle::ComputeNormal(a, b, c, normal);
    const double centre[3] = { (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3,
      (a[2] + b[2] + c[2]) / 3 };
    EXPECT_GT(vtkMath::Dot(normal, centre), 0.0);
  }
  // point normals are the cone axes of the corner cells: pointing outwards
  vtkDataArray* normals = pd->GetPointData()->GetNormals();
  ASSERT_TRUE(normals);
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3], n[3];
    pd->GetPoint(i, x);
    normals->GetTuple(i, n);
    EXPECT_GT(vtkMath::Dot(x, n), 0.0);
  }
}

TEST(MultiscalePatchGenerator, InputTrianglesOrientationIsKept)
{
  // the same cube with every triangle reversed gives every output triangle reversed
  auto cube = plodtest::MakeCube(-1, 1);
  vtkNew<vtkPolyData> reversed;
  reversed->DeepCopy(cube);
  vtkNew<vtkCellArray> polys;
  auto it = vtk::TakeSmartPointer(cube->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    const vtkIdType r[3] = { ids[0], ids[2], ids[1] };
    polys->InsertNextCell(3, r);
  }
  reversed->SetPolys(polys);
  auto a = Patches(BuildOctree(cube, 3));
  auto b = Patches(BuildOctree(reversed, 3));
  ASSERT_EQ(a->GetNumberOfPolys(), b->GetNumberOfPolys());
  ASSERT_GT(a->GetNumberOfPolys(), 0);
  // signed volume by the divergence theorem: positive for outward triangles
  auto volume = [](vtkPolyData* pd) {
    double v = 0;
    for (vtkIdType t = 0; t < pd->GetNumberOfPolys(); ++t)
    {
      vtkIdType n;
      const vtkIdType* ids;
      pd->GetCellPoints(t, n, ids);
      double p[3][3], c[3];
      for (int k = 0; k < 3; ++k)
        pd->GetPoint(ids[k], p[k]);
      vtkMath::Cross(p[1], p[2], c);
      v += vtkMath::Dot(p[0], c) / 6.0;
    }
    return v;
  };
  const double va = volume(a), vb = volume(b);
  EXPECT_GT(va, 6.0) << "outward, close to the cube's volume 8";
  EXPECT_NEAR(vb, -va, 1e-9 * va);
}

TEST(MultiscalePatchGenerator, CoincidentVerticesAreMerged)
{
  // Move a cell's vertex onto its neighbour's: the two points merge, triangles that would
  // repeat it are dropped, and the surface stays closed.
  auto octree = BuildOctree(plodtest::MakeBlob(4, 24, 0.2), 4);
  auto copy = vtkSmartPointer<vtkMultiscaleOctree>::New();
  copy->DeepCopy(octree);
  plod::OctreeView v;
  ASSERT_TRUE(copy->GetView(v));
  auto* vertex = vtkFloatArray::SafeDownCast(copy->GetNodeData()->GetArray("Vertex"));
  auto before = Patches(copy);
  // pick the two cells of the first triangle
  auto* node = vtkIdTypeArray::SafeDownCast(before->GetPointData()->GetArray("OctreeNode"));
  vtkIdType n;
  const vtkIdType* ids;
  before->GetCellPoints(0, n, ids);
  const vtkIdType a = node->GetValue(ids[0]), b = node->GetValue(ids[1]);
  float x[3];
  vertex->GetTypedTuple(a, x);
  vertex->SetTypedTuple(b, x);
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputData(copy);
  gen->Update();
  EXPECT_GE(gen->GetMergedPoints(), 1);
  EXPECT_LT(gen->GetOutput()->GetNumberOfPolys(), before->GetNumberOfPolys());
  const EdgeStats s = Analyse(gen->GetOutput());
  EXPECT_EQ(s.Odd, 0);
  EXPECT_EQ(s.Degenerate, 0);
}

// ---- accuracy and real data --------------------------------------------------------------------

TEST(MultiscalePatchGenerator, FinestCutStaysWithinOneCellOfTheInput)
{
  for (unsigned seed : { 1u, 2u })
  {
    auto blob = plodtest::MakeBlob(seed, 64, 0.3);
    auto octree = BuildOctree(blob, 6);
    auto pd = Patches(octree); // no cut array: the finest level
    ASSERT_GT(pd->GetNumberOfPolys(), 1000);
    vtkNew<vtkStaticCellLocator> locator;
    locator->SetDataSet(blob);
    locator->BuildLocator();
    const double h = octree->GetCellEdge(6);
    double worst = 0;
    for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    {
      double x[3], closest[3], d2;
      vtkIdType cell;
      int sub;
      pd->GetPoint(i, x);
      locator->FindClosestPoint(x, closest, cell, sub, d2);
      worst = std::max(worst, std::sqrt(d2));
    }
    // measured: the worst vertex is a fraction of a cell from the surface
    EXPECT_LE(worst, h) << "worst distance " << worst << " finest cell " << h;
    std::cout << "finest cut: worst vertex-to-surface distance " << worst / h << " cells\n";
  }
}

TEST(MultiscalePatchGenerator, OpenSheetHasBoundaryOnlyAtItsRim)
{
  // A wavy open sheet: output boundary edges lie within two cells of the sheet's rim.
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  const int n = 40;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      xyz.insert(xyz.end(), { double(i) / n, double(j) / n, 0.1 * std::sin(6.0 * i / n) });
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const vtkIdType a = j * (n + 1) + i;
      tri.insert(tri.end(), { a, a + 1, a + n + 2, a, a + n + 2, a + n + 1 });
    }
  auto sheet = plodtest::MakeMesh(xyz, tri);
  auto octree = BuildOctree(sheet, 6);
  for (int level = 3; level <= 6; ++level)
  {
    vtkNew<vtkMultiscaleOctreeCutter> cutter;
    cutter->SetInputData(octree);
    cutter->SetLevel(level);
    cutter->Update();
    auto pd = Patches(cutter->GetOutput());
    const EdgeStats s = Analyse(pd);
    EXPECT_GT(s.Odd, 0) << "an open sheet has a rim";
    EXPECT_EQ(s.Unbalanced, s.Odd);
    const double h = octree->GetCellEdge(level);
    for (const auto& e : s.Boundary)
    {
      double x[3];
      pd->GetPoint(e.first, x);
      const double rim = std::min({ x[0], 1 - x[0], x[1], 1 - x[1] });
      ASSERT_LE(rim, 2 * h) << "boundary edge inside the sheet at level " << level;
    }
  }
}

TEST(MultiscalePatchGenerator, StanfordBunnyBoundaryOnlyAtItsHoles)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  auto bunny = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  ASSERT_TRUE(bunny);
  vtkNew<vtkFeatureEdges> holes;
  holes->SetInputData(bunny);
  holes->BoundaryEdgesOn();
  holes->FeatureEdgesOff();
  holes->NonManifoldEdgesOff();
  holes->ManifoldEdgesOff();
  holes->Update();
  ASSERT_GT(holes->GetOutput()->GetNumberOfCells(), 0) << "the bunny has holes";
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(holes->GetOutput());
  locator->BuildLocator();
  auto octree = BuildOctree(bunny, 8);
  for (int level = 2; level <= 8; ++level)
  {
    vtkNew<vtkMultiscaleOctreeCutter> cutter;
    cutter->SetInputData(octree);
    cutter->SetLevel(level);
    cutter->Update();
    auto pd = Patches(cutter->GetOutput());
    const EdgeStats s = Analyse(pd);
    EXPECT_EQ(s.Degenerate, 0);
    EXPECT_EQ(s.Unbalanced, s.Odd) << "orientation consistent away from the holes";
    // Every output boundary edge lies within two cells (of its level) of an input hole, or of a
    // thin part whose two sheets cancel inside one cell (the ears at coarse levels), which we
    // count separately: measured, not asserted below level 6.
    const double h = octree->GetCellEdge(level);
    int far = 0;
    for (const auto& e : s.Boundary)
    {
      double a[3], b[3], mid[3], closest[3], d2;
      pd->GetPoint(e.first, a);
      pd->GetPoint(e.second, b);
      for (int k = 0; k < 3; ++k)
        mid[k] = 0.5 * (a[k] + b[k]);
      vtkIdType cell;
      int sub;
      locator->FindClosestPoint(mid, closest, cell, sub, d2);
      far += std::sqrt(d2) > 2 * std::sqrt(3.0) * h;
    }
    std::cout << "bunny level " << level << ": " << pd->GetNumberOfPolys() << " triangles, "
              << s.Odd << " boundary edges, " << far << " away from the holes\n";
    if (level >= 6)
    {
      EXPECT_EQ(far, 0) << "level " << level;
    }
  }
}

// ---- pipeline and bad input --------------------------------------------------------------------

TEST(MultiscalePatchGenerator, OnlyWhatChangedReExecutes)
{
  auto blob = plodtest::MakeBlob(6, 32, 0.2);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  builder->SetFinestLevel(5);
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputConnection(builder->GetOutputPort());
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputConnection(cutter->GetOutputPort());
  int builds = 0, patches = 0;
  vtkNew<vtkCallbackCommand> countBuild, countPatch;
  countBuild->SetClientData(&builds);
  countBuild->SetCallback([](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
  countPatch->SetClientData(&patches);
  countPatch->SetCallback([](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
  builder->AddObserver(vtkCommand::EndEvent, countBuild);
  gen->AddObserver(vtkCommand::EndEvent, countPatch);
  gen->Update();
  EXPECT_EQ(builds, 1);
  EXPECT_EQ(patches, 1);
  gen->Update();
  cutter->SetLevel(cutter->GetLevel()); // no change
  gen->Update();
  EXPECT_EQ(builds, 1);
  EXPECT_EQ(patches, 1) << "nothing changed, nothing re-executes";
  for (int level = 1; level <= 5; ++level)
  {
    cutter->SetLevel(level);
    gen->Update();
  }
  EXPECT_EQ(builds, 1) << "a new cut never rebuilds the octree";
  EXPECT_EQ(patches, 6);
  gen->GenerateColorsOn();
  gen->Update();
  EXPECT_EQ(patches, 7);
  EXPECT_TRUE(gen->GetOutput()->GetPointData()->GetArray("Colors"));
}

TEST(MultiscalePatchGenerator, InvalidCutIsAnErrorAndEmptyOutputs)
{
  auto octree = BuildOctree(plodtest::MakeBlob(2, 16, 0.2), 4);
  plod::OctreeView v;
  ASSERT_TRUE(octree->GetView(v));
  // a finest cell without an ancestor in the cut
  std::vector<uint8_t> cut(v.NumberOfNodes, 0);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    cut[n] = v.Level[n] == 3 ? 1 : 0;
  cut[v.FirstChild[0]] = 0; // leave a subtree uncovered
  int32_t uncovered = v.FirstChild[0];
  while (v.Level[uncovered] < 3)
    uncovered = v.FirstChild[uncovered];
  cut[uncovered] = 0;
  vtkNew<plodtest::ErrorRecorder> errors;
  auto pd = Patches(WithCut(octree, cut), errors);
  EXPECT_TRUE(errors->HasError("Invalid cut"));
  EXPECT_EQ(pd->GetNumberOfPolys(), 0);
  EXPECT_FALSE(WithCut(octree, cut)->HasValidCut());
  // empty input
  vtkNew<vtkMultiscaleOctree> empty;
  EXPECT_EQ(Patches(empty)->GetNumberOfPoints(), 0);
  // refine-array mode without the array
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  vtkNew<plodtest::ErrorRecorder> cutErrors;
  cutter->AddObserver(vtkCommand::ErrorEvent, cutErrors);
  cutter->SetInputData(octree);
  cutter->SetModeToRefineArray();
  cutter->Update();
  EXPECT_TRUE(cutErrors->HasError("Refine array"));
  EXPECT_EQ(cutter->GetOutput()->GetNumberOfNodes(), 0);
}

TEST(MultiscalePatchGenerator, CutterModesMakeValidCuts)
{
  auto octree = BuildOctree(plodtest::MakeBlob(3, 24, 0.3), 5);
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(octree);
  for (int level : { -1, 0, 3, 5, 40 })
  {
    cutter->SetLevel(level);
    cutter->Update();
    EXPECT_TRUE(cutter->GetOutput()->HasValidCut()) << level;
  }
  // callback: refine the upper half (z > 0) to the finest level, the rest stops at level 2
  cutter->SetModeToCallback();
  vtkMultiscaleOctree* o = octree;
  cutter->SetRefineCallback([o](vtkIdType n) {
    double x[3];
    o->GetNodeVertex(n, x);
    return o->GetNodeLevel(n) < 2 || x[2] > 0;
  });
  cutter->Update();
  EXPECT_TRUE(cutter->GetOutput()->HasValidCut());
  const EdgeStats s = Analyse(Patches(cutter->GetOutput()));
  EXPECT_EQ(s.Odd, 0);
  // refine array
  vtkNew<vtkUnsignedCharArray> refine;
  refine->SetName("Refine");
  refine->SetNumberOfTuples(octree->GetNumberOfNodes());
  for (vtkIdType n = 0; n < octree->GetNumberOfNodes(); ++n)
    refine->SetValue(n, octree->GetNodeLevel(n) < 3 ? 1 : 0);
  auto withArray = vtkSmartPointer<vtkMultiscaleOctree>::New();
  withArray->ShallowCopy(octree);
  withArray->GetNodeData()->AddArray(refine);
  cutter->SetInputData(withArray);
  cutter->SetModeToRefineArray();
  cutter->Update();
  EXPECT_TRUE(cutter->GetOutput()->HasValidCut());
  auto* cut = vtkUnsignedCharArray::SafeDownCast(
    cutter->GetOutput()->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  for (vtkIdType n = 0; n < octree->GetNumberOfNodes(); ++n)
    ASSERT_EQ(cut->GetValue(n) != 0, octree->GetNodeLevel(n) == 3);
}
