// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkMultiscalePatchGenerator and vtkMultiscaleOctreeCutter: every cut draws exactly the
// vertex clustering of the input (brute force, thousands of random cuts, thin parts included),
// closure and orientation, the full cut is the input, hidden and culled cells, folds, the work
// done, pipeline behaviour, bad cuts and corrupt octrees.
#include "plodCut.h"
#include "plodOctreeChecks.h"
#include "plodPatches.h"
#include "plodSelector.h"
#include "plodTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCommand.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <set>

using plodcheck::Build;
using plodcheck::Built;

namespace
{

/// Octree copy carrying the given cut states (and cull masks).
vtkSmartPointer<vtkMultiscaleOctree> WithCut(vtkMultiscaleOctree* octree,
  const std::vector<uint8_t>& cut, const std::vector<uint8_t>* mask = nullptr)
{
  auto copy = vtkSmartPointer<vtkMultiscaleOctree>::New();
  copy->ShallowCopy(octree);
  auto add = [&copy](const std::vector<uint8_t>& values, const char* name) {
    vtkNew<vtkUnsignedCharArray> a;
    a->SetName(name);
    a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
    std::copy(values.begin(), values.end(), a->GetPointer(0));
    copy->GetNodeData()->AddArray(a);
  };
  add(cut, vtkMultiscaleOctree::CutStateArrayName());
  if (mask)
  {
    add(*mask, vtkMultiscaleOctree::CullMaskArrayName());
  }
  return copy;
}

vtkSmartPointer<vtkPolyData> Patches(
  vtkMultiscaleOctree* octree, plodtest::ErrorRecorder* errors = nullptr, bool dropFolds = true)
{
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputData(octree);
  gen->GenerateNodeIdsOn();
  gen->GenerateInputPointIdsOn();
  gen->SetFoldHandling(dropFolds ? vtkMultiscalePatchGenerator::FOLDS_REVERSE_NORMALS
                                 : vtkMultiscalePatchGenerator::FOLDS_KEEP);
  if (errors)
  {
    gen->AddObserver(vtkCommand::ErrorEvent, errors);
    gen->AddObserver(vtkCommand::WarningEvent, errors);
  }
  gen->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->ShallowCopy(gen->GetOutput());
  return pd;
}

/// Random valid cut: refine with a probability that falls with depth, open some refined
/// leaves, hide some cut cells.
std::vector<uint8_t> RandomCut(const plod::OctreeView& v, std::mt19937& rng, double hidden)
{
  std::uniform_real_distribution<double> U(0, 1);
  const double bias = U(rng);
  std::vector<uint8_t> cut(v.NumberOfNodes, plod::NotInCut);
  std::vector<int32_t> stack{ 0 };
  while (!stack.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    const bool refine = U(rng) < 0.6 + 0.4 * bias - 0.04 * v.Level[n];
    if (v.IsLeaf(n) && refine)
    {
      cut[n] = plod::CutOpen;
      continue;
    }
    if (!refine)
    {
      cut[n] = U(rng) < hidden ? plod::CutHidden : plod::CutDrawn;
      continue;
    }
    for (int c = 0; c < __builtin_popcount(v.ChildMask[n]); ++c)
    {
      stack.push_back(v.FirstChild[n] + c);
    }
  }
  return cut;
}

/// Models with every kind of trouble: blobs, a tiny closed mesh, thin walls 0.1 to 1.5 finest
/// cells thick (box, disc, folded sheet), a thin tilted ring.
std::vector<std::pair<std::string, vtkSmartPointer<vtkPolyData>>> ClosedModels(int level)
{
  const double cell = 2.2 / (1 << level);
  std::vector<std::pair<std::string, vtkSmartPointer<vtkPolyData>>> m = {
    { "blob", plodtest::MakeBlob(1, 24, 0.3) }, { "blob2", plodtest::MakeBlob(2, 40, 0.35) },
    { "cube", plodtest::MakeCube(-1, 1) }, { "tetrahedron", plodtest::MakeTetrahedron() }
  };
  for (double f : { 0.1, 0.5, 1.5 })
  {
    m.push_back({ "thin box " + std::to_string(f), plodtest::MakeThinBox(f * cell, 8) });
    m.push_back({ "thin disc " + std::to_string(f), plodtest::MakeThinDisc(f * cell, 8) });
    m.push_back(
      { "folded sheet " + std::to_string(f), plodtest::MakeFoldedSheet(f * cell, 0.7 * cell, 8) });
  }
  auto ring = plodtest::MakeRing(1.0, 0.3 * cell, 80, 6);
  vtkPoints* pts = ring->GetPoints();
  for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pts->GetPoint(i, x);
    pts->SetPoint(i, x[0], 0.8 * x[1] - 0.6 * x[2], 0.6 * x[1] + 0.8 * x[2]);
  }
  m.push_back({ "ring", ring });
  return m;
}

/// `x` and `y` hold the same values, bit for bit.
void ExpectSameValues(vtkDataArray* x, vtkDataArray* y, const std::string& what)
{
  ASSERT_NE(x, nullptr) << what;
  ASSERT_NE(y, nullptr) << what;
  ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues()) << what;
  ASSERT_EQ(x->GetDataType(), y->GetDataType()) << what;
  EXPECT_EQ(std::memcmp(x->GetVoidPointer(0), y->GetVoidPointer(0),
              size_t(x->GetNumberOfValues()) * size_t(x->GetDataTypeSize())),
    0)
    << what;
}

/// A ParallelFor that runs its ranges backwards (as a thread pool may), in ranges of `grain`.
plod::ParallelFor Backwards()
{
  return [](int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body) {
    grain = std::max<int64_t>(1, grain);
    for (int64_t b = ((n - 1) / grain) * grain; b >= 0; b -= grain)
      body(b, std::min(n, b + grain));
  };
}

} // namespace

TEST(MultiscalePatchGenerator, EveryCutDrawsTheVertexClusteringOfTheInput)
{
  // Thousands of random cuts (coarse and fine cells, opened leaves) over closed models with thin
  // parts: the output is exactly the input's triangles mapped to their cut representatives, those
  // that keep three different corners; hence closed and consistently oriented (every edge used
  // as often in each direction: no crack, no cancellation), never more than the input.
  std::mt19937 rng(7);
  int cuts = 0;
  for (const auto& [name, model] : ClosedModels(4))
  {
    Built b = Build(model, 4);
    const plod::OctreeView& v = b.View;
    ASSERT_GT(v.NumberOfNodes, 0) << name;
    plod::PatchWorkspace ws;
    plod::PatchResult r;
    plod::PatchOptions keep;
    keep.Folds = plod::FoldHandling::Keep;
    for (int trial = 0; trial < 150; ++trial, ++cuts)
    {
      const std::vector<uint8_t> cut = RandomCut(v, rng, 0.0);
      std::string why;
      ASSERT_TRUE(plod::ValidateCut(v, cut.data(), &why)) << why;
      ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r, &why, &ws, keep)) << why;
      ASSERT_EQ(plodcheck::DrawnTriangles(r), plodcheck::ExpectedTriangles(v, cut.data()))
        << name << " trial " << trial;
      ASSERT_EQ(plodcheck::OpenEdges(r.Triangles), 0) << name << " trial " << trial;
      ASSERT_LE(int64_t(r.Triangles.size() / 3), v.NumberOfTriangles);
      for (size_t k = 0; k + 2 < r.Triangles.size(); k += 3)
      {
        ASSERT_NE(r.Triangles[k], r.Triangles[k + 1]);
        ASSERT_NE(r.Triangles[k + 1], r.Triangles[k + 2]);
        ASSERT_NE(r.Triangles[k], r.Triangles[k + 2]);
      }
    }
  }
  EXPECT_GE(cuts, 2000);
}

TEST(MultiscalePatchGenerator, UniformCutIsGridClusteringOfTheInput)
{
  // Independent of the octree: cluster the input points on the level's grid directly from their
  // coordinates; the uniform cut draws the same triangles, cell for cell.
  auto blob = plodtest::MakeBlob(3, 30, 0.3);
  Built b = Build(blob, 5);
  const plod::OctreeView& v = b.View;
  const double* o = b.Octree->GetOrigin();
  for (int level = 1; level <= 5; ++level)
  {
    std::vector<uint8_t> cut(v.NumberOfNodes);
    plod::UniformCut(v, level, cut.data());
    plod::PatchResult r;
    plod::PatchOptions keep;
    keep.Folds = plod::FoldHandling::Keep;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r, nullptr, nullptr, keep));
    const double h = v.CellEdge(level);
    auto cellOf = [&](vtkIdType p) {
      double x[3];
      blob->GetPoint(p, x);
      std::array<int64_t, 3> c;
      for (int a = 0; a < 3; ++a)
        c[a] = static_cast<int64_t>(std::floor((x[a] - o[a]) / h));
      return c;
    };
    std::multiset<std::array<std::array<int64_t, 3>, 3>> expected, drawn;
    auto rotate = [](std::array<std::array<int64_t, 3>, 3> t) {
      while (!(t[0] <= t[1] && t[0] <= t[2]))
        std::rotate(t.begin(), t.begin() + 1, t.end());
      return t;
    };
    for (vtkIdType c = 0; c < blob->GetNumberOfCells(); ++c)
    {
      vtkIdType n;
      const vtkIdType* ids;
      blob->GetPolys()->GetCellAtId(c, n, ids);
      const std::array<std::array<int64_t, 3>, 3> t = { cellOf(ids[0]), cellOf(ids[1]),
        cellOf(ids[2]) };
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        expected.insert(rotate(t));
    }
    for (size_t k = 0; k + 2 < r.Triangles.size(); k += 3)
    {
      std::array<std::array<int64_t, 3>, 3> t;
      for (int j = 0; j < 3; ++j)
      {
        int c[3];
        v.CellCoordinates(plodcheck::NodeOf(v, r.PointSource[r.Triangles[k + j]]), c);
        t[j] = { c[0], c[1], c[2] };
      }
      drawn.insert(rotate(t));
    }
    EXPECT_EQ(drawn, expected) << "level " << level;
  }
}

TEST(MultiscalePatchGenerator, FullResolutionIsTheInput)
{
  // the cutter's default (every leaf opened) draws the input's triangles with its points and
  // shading normals; the finest level of cells alone (leaves not opened) draws fewer
  auto blob = plodtest::MakeBlob(4, 40, 0.3);
  Built b = Build(blob);
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(b.Octree);
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputConnection(cutter->GetOutputPort());
  gen->GenerateInputPointIdsOn();
  gen->Update();
  vtkPolyData* out = gen->GetOutput();
  ASSERT_EQ(out->GetNumberOfPolys(), blob->GetNumberOfPolys());
  auto* ids = vtkIdTypeArray::SafeDownCast(out->GetPointData()->GetArray("InputPointId"));
  ASSERT_TRUE(ids);
  std::multiset<std::array<int64_t, 3>> got, want;
  auto it = vtk::TakeSmartPointer(out->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* p;
    it->GetCurrentCell(n, p);
    got.insert(plodcheck::Canonical(ids->GetValue(p[0]), ids->GetValue(p[1]), ids->GetValue(p[2])));
  }
  for (vtkIdType c = 0; c < blob->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* p;
    blob->GetPolys()->GetCellAtId(c, n, p);
    want.insert(plodcheck::Canonical(p[0], p[1], p[2]));
  }
  EXPECT_EQ(got, want);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    out->GetPoint(i, x);
    blob->GetPoint(ids->GetValue(i), y);
    for (int a = 0; a < 3; ++a)
      ASSERT_NEAR(x[a], y[a], 1e-6);
  }
  cutter->SetLevel(b.View.FinestLevel);
  gen->Update();
  EXPECT_LT(gen->GetOutput()->GetNumberOfPolys(), blob->GetNumberOfPolys());
  EXPECT_GT(gen->GetOutput()->GetNumberOfPolys(), blob->GetNumberOfPolys() / 8);
}

TEST(MultiscalePatchGenerator, HiddenCellsAndCullMasks)
{
  // Hidden cells stay in the cut: a triangle with a drawn corner is drawn. Among hidden cells
  // only: skipped when one faces away (cull mask 0) or all lie outside one common plane; drawn
  // when they lie outside different planes (a large triangle can cross the view).
  auto blob = plodtest::MakeBlob(5, 32, 0.3);
  Built b = Build(blob, 5);
  const plod::OctreeView& v = b.View;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> plane(0, 5);
  plod::PatchOptions keep;
  keep.Folds = plod::FoldHandling::Keep;
  for (int trial = 0; trial < 100; ++trial)
  {
    std::vector<uint8_t> cut = RandomCut(v, rng, 0.5);
    std::vector<uint8_t> mask(v.NumberOfNodes, 0);
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      if (cut[n] == plod::CutHidden && trial % 2)
        mask[n] = static_cast<uint8_t>(1u << plane(rng)) | (rng() % 3 == 0 ? 1u : 0u);
    plod::PatchResult r;
    ASSERT_TRUE(plod::GeneratePatches(
      v, cut.data(), trial % 2 ? mask.data() : nullptr, r, nullptr, nullptr, keep));
    // expected: all of the clustering, minus the triangles the rule hides
    std::multiset<std::array<int64_t, 3>> expected;
    for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    {
      int64_t rep[3];
      bool drawn = false, back = false;
      uint8_t common = 0x3f;
      for (int k = 0; k < 3; ++k)
      {
        rep[k] = plodcheck::Representative(v, cut.data(), v.Triangles[3 * t + k]);
        const int64_t node = plodcheck::NodeOf(v, rep[k]);
        drawn = drawn || cut[node] != plod::CutHidden;
        if (cut[node] == plod::CutHidden)
        {
          const uint8_t m = trial % 2 ? mask[node] : 0;
          back = back || m == 0;
          common &= m;
        }
      }
      if (rep[0] == rep[1] || rep[1] == rep[2] || rep[0] == rep[2])
        continue;
      if (!drawn && (back || common))
        continue;
      expected.insert(plodcheck::Canonical(rep[0], rep[1], rep[2]));
    }
    ASSERT_EQ(plodcheck::DrawnTriangles(r), expected) << trial;
  }
}

TEST(MultiscalePatchGenerator, OrientationIsKept)
{
  // the same model with every triangle reversed gives every output triangle reversed
  auto blob = plodtest::MakeBlob(6, 20, 0.3);
  vtkNew<vtkPolyData> reversed;
  reversed->DeepCopy(blob);
  reversed->ReverseCell(0);
  for (vtkIdType c = 1; c < reversed->GetNumberOfCells(); ++c)
    reversed->ReverseCell(c);
  Built a = Build(blob, 4), r = Build(reversed, 4);
  for (int level : { 2, 3, 4, -1 })
  {
    std::vector<uint8_t> cut(a.View.NumberOfNodes);
    plod::UniformCut(a.View, level, cut.data());
    plod::PatchResult pa, pr;
    plod::PatchOptions keep;
    keep.Folds = plod::FoldHandling::Keep;
    ASSERT_TRUE(plod::GeneratePatches(a.View, cut.data(), nullptr, pa, nullptr, nullptr, keep));
    ASSERT_TRUE(plod::GeneratePatches(r.View, cut.data(), nullptr, pr, nullptr, nullptr, keep));
    std::multiset<std::array<int64_t, 3>> ta = plodcheck::DrawnTriangles(pa), flipped;
    for (const auto& t : plodcheck::DrawnTriangles(pr))
      flipped.insert(plodcheck::Canonical(t[0], t[2], t[1]));
    EXPECT_EQ(ta, flipped) << level;
  }
}

TEST(MultiscalePatchGenerator, ParallelBackFaceCullingFollowsTheProjectionDirection)
{
  // A closed cube at full resolution seen along the projection direction dop = (1, -2, -3): a
  // triangle is culled exactly when its face normal has a positive component along dop (it faces
  // away from the viewer): the +x, -y and -z faces, 6 of 12. The eye, read by a perspective
  // projection only, is put inside the cube, from where every face would face away.
  auto cube = plodtest::MakeCube(0, 1);
  Built b = Build(cube, 2);
  const plod::OctreeView& v = b.View;
  std::vector<uint8_t> cut(v.NumberOfNodes);
  plod::UniformCut(v, -1, cut.data());
  plod::PatchOptions options;
  options.Folds = plod::FoldHandling::Keep;
  options.CullBackFaces = true;
  options.Parallel = true;
  const double dop[3] = { 1, -2, -3 };
  const double* o = b.Octree->GetOrigin();
  for (int a = 0; a < 3; ++a)
  {
    options.ProjectionDirection[a] = dop[a];
    options.Eye[a] = 0.5 - o[a];
  }
  plod::PatchResult r;
  std::string why;
  ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r, &why, nullptr, options)) << why;
  std::multiset<std::array<int64_t, 3>> drawn, want;
  for (size_t k = 0; k + 2 < r.Triangles.size(); k += 3)
  {
    int64_t id[3];
    for (int c = 0; c < 3; ++c)
    {
      const int64_t source = r.PointSource[r.Triangles[k + c]];
      ASSERT_LT(source, 0) << "every leaf is opened: surface points only";
      id[c] = v.InputPointId[-1 - source];
    }
    drawn.insert(plodcheck::Canonical(id[0], id[1], id[2]));
  }
  for (vtkIdType c = 0; c < cube->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* p;
    cube->GetPolys()->GetCellAtId(c, n, p);
    double x[3][3], e1[3], e2[3], normal[3];
    for (int k = 0; k < 3; ++k)
      cube->GetPoint(p[k], x[k]);
    for (int a = 0; a < 3; ++a)
    {
      e1[a] = x[1][a] - x[0][a];
      e2[a] = x[2][a] - x[0][a];
    }
    vtkMath::Cross(e1, e2, normal);
    if (vtkMath::Dot(normal, dop) <= 0)
      want.insert(plodcheck::Canonical(p[0], p[1], p[2]));
  }
  EXPECT_EQ(want.size(), 6u);
  EXPECT_EQ(drawn, want);
  EXPECT_EQ(r.BackFacesCulled, 6);
}

TEST(MultiscalePatchGenerator, FoldsAreDroppedOrGivenReversedNormalsAndNothingElse)
{
  // the turned-over triangles are exactly those whose face normal opposes all three corner
  // normals (and that have a representative corner): input triangles never are. Drop removes
  // exactly them; ReverseNormals draws every triangle of Keep, the folds on points of their
  // own (same sources) listed in ReversedNormals, and nothing else there
  auto blob = plodtest::MakeBlob(7, 60, 0.4);
  Built b = Build(blob);
  const plod::OctreeView& v = b.View;
  std::mt19937 rng(3);
  int64_t folds = 0;
  for (int trial = 0; trial < 40; ++trial)
  {
    const std::vector<uint8_t> cut = RandomCut(v, rng, 0.0);
    plod::PatchResult all, dropped, reversed;
    plod::PatchOptions keep, drop;
    keep.Folds = plod::FoldHandling::Keep;
    drop.Folds = plod::FoldHandling::Drop;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, all, nullptr, nullptr, keep));
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, dropped, nullptr, nullptr, drop));
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, reversed));
    std::multiset<std::array<int64_t, 3>> expected, turned;
    for (size_t k = 0; k + 2 < all.Triangles.size(); k += 3)
    {
      const int64_t s[3] = { all.PointSource[all.Triangles[k]],
        all.PointSource[all.Triangles[k + 1]], all.PointSource[all.Triangles[k + 2]] };
      double x[3][3], n[3][3];
      for (int j = 0; j < 3; ++j)
        for (int a = 0; a < 3; ++a)
        {
          x[j][a] = s[j] >= 0 ? v.ClusterVertex[3 * s[j] + a] : v.Points[3 * (-1 - s[j]) + a];
          n[j][a] = s[j] >= 0 ? v.ClusterNormal[3 * s[j] + a] : v.Normals[3 * (-1 - s[j]) + a];
        }
      const double e1[3] = { x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2] };
      const double e2[3] = { x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2] };
      const double f[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0] };
      bool over = s[0] >= 0 || s[1] >= 0 || s[2] >= 0;
      for (int j = 0; j < 3 && over; ++j)
        over = f[0] * n[j][0] + f[1] * n[j][1] + f[2] * n[j][2] < 0;
      (over ? turned : expected).insert(plodcheck::Canonical(s[0], s[1], s[2]));
    }
    ASSERT_EQ(plodcheck::DrawnTriangles(dropped), expected) << trial;
    ASSERT_EQ(dropped.Folds, int64_t(turned.size()));
    ASSERT_TRUE(dropped.ReversedNormals.empty());
    // ReverseNormals: the same triangles as Keep (by source), the folds on own points
    ASSERT_EQ(plodcheck::DrawnTriangles(reversed), plodcheck::DrawnTriangles(all)) << trial;
    ASSERT_EQ(reversed.Folds, int64_t(turned.size()));
    ASSERT_EQ(reversed.ReversedNormals.size(), 3 * turned.size());
    std::set<int64_t> own(reversed.ReversedNormals.begin(), reversed.ReversedNormals.end());
    ASSERT_EQ(own.size(), reversed.ReversedNormals.size()) << "each fold corner is its own point";
    std::multiset<std::array<int64_t, 3>> onOwn;
    std::map<int64_t, int> uses;
    for (size_t k = 0; k + 2 < reversed.Triangles.size(); k += 3)
    {
      const int64_t* t = &reversed.Triangles[k];
      for (int j = 0; j < 3; ++j)
        ++uses[t[j]];
      const int ownCorners = int(own.count(t[0]) + own.count(t[1]) + own.count(t[2]));
      ASSERT_TRUE(ownCorners == 0 || ownCorners == 3) << trial;
      if (ownCorners == 3)
        onOwn.insert(plodcheck::Canonical(
          reversed.PointSource[t[0]], reversed.PointSource[t[1]], reversed.PointSource[t[2]]));
    }
    ASSERT_EQ(onOwn, turned) << trial;
    for (int64_t p : own)
      ASSERT_EQ(uses[p], 1) << "a fold's own point serves that fold only";
    folds += reversed.Folds;
  }
  EXPECT_GT(folds, 0) << "random cuts of a bumpy blob do turn triangles over";
  // the full resolution has none
  std::vector<uint8_t> full(v.NumberOfNodes);
  plod::UniformCut(v, -1, full.data());
  plod::PatchResult r;
  ASSERT_TRUE(plod::GeneratePatches(v, full.data(), nullptr, r));
  EXPECT_EQ(int64_t(r.Triangles.size() / 3), v.NumberOfTriangles);
  EXPECT_EQ(r.Folds, 0);
  EXPECT_TRUE(r.ReversedNormals.empty());
}

TEST(MultiscalePatchGenerator, FoldHandlingShowsNoTurnedOverTriangle)
{
  // in the output, a triangle whose face normal opposes the normals of its three points is
  // shaded from behind. Keep draws the folds so; Drop and ReverseNormals draw none, Drop with
  // fewer triangles, ReverseNormals with all of Keep's on 3 more points per fold
  auto blob = plodtest::MakeBlob(7, 60, 0.4);
  Built b = Build(blob);
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(b.Octree);
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputConnection(cutter->GetOutputPort());
  auto turned = [](vtkPolyData* pd) {
    vtkDataArray* normals = pd->GetPointData()->GetNormals();
    int count = 0;
    auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* p;
      it->GetCurrentCell(n, p);
      double x[3][3], f[3];
      for (int j = 0; j < 3; ++j)
        pd->GetPoint(p[j], x[j]);
      const double e1[3] = { x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2] };
      const double e2[3] = { x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2] };
      vtkMath::Cross(e1, e2, f);
      bool over = true;
      for (int j = 0; j < 3 && over; ++j)
        over = vtkMath::Dot(f, normals->GetTuple3(p[j])) < 0;
      count += over ? 1 : 0;
    }
    return count;
  };
  int total = 0;
  for (int level = 2; level <= b.View.FinestLevel; ++level)
  {
    cutter->SetLevel(level);
    gen->SetFoldHandlingToKeep();
    gen->Update();
    const vtkIdType keepTris = gen->GetOutput()->GetNumberOfPolys();
    const vtkIdType keepPoints = gen->GetOutput()->GetNumberOfPoints();
    EXPECT_EQ(gen->GetNumberOfFolds(), 0) << "not looked for";
    const vtkIdType folds = turned(gen->GetOutput());
    gen->SetFoldHandlingToDrop();
    gen->Update();
    EXPECT_EQ(gen->GetNumberOfFolds(), folds);
    EXPECT_EQ(gen->GetOutput()->GetNumberOfPolys(), keepTris - folds);
    EXPECT_EQ(turned(gen->GetOutput()), 0) << level;
    gen->SetFoldHandlingToReverseNormals();
    gen->Update();
    EXPECT_EQ(gen->GetNumberOfFolds(), folds);
    EXPECT_EQ(gen->GetOutput()->GetNumberOfPolys(), keepTris);
    EXPECT_EQ(gen->GetOutput()->GetNumberOfPoints(), keepPoints + 3 * folds);
    EXPECT_EQ(turned(gen->GetOutput()), 0) << level;
    total += static_cast<int>(folds);
  }
  EXPECT_GT(total, 0) << "uniform levels of a bumpy blob turn triangles over";
}

TEST(MultiscalePatchGenerator, OpenSheetHasBoundaryOnlyAtItsRim)
{
  // a wavy open sheet: every open edge of any cut is the image of an edge of the sheet's rim
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  const int n = 30;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
    {
      const double x = double(i) / n, y = double(j) / n;
      xyz.insert(xyz.end(), { x, y, 0.1 * std::sin(6 * x) * std::cos(5 * y) });
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      const vtkIdType a = i * (n + 1) + j, c = (i + 1) * (n + 1) + j;
      tri.insert(tri.end(), { a, c, c + 1, a, c + 1, a + 1 });
    }
  auto sheet = plodtest::MakeMesh(xyz, tri);
  Built b = Build(sheet);
  const plod::OctreeView& v = b.View;
  std::mt19937 rng(5);
  plod::PatchOptions keep;
  keep.Folds = plod::FoldHandling::Keep;
  for (int trial = 0; trial < 100; ++trial)
  {
    const std::vector<uint8_t> cut = RandomCut(v, rng, 0.0);
    plod::PatchResult r;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r, nullptr, nullptr, keep));
    // the rim's edges mapped to representatives: the only edges allowed to be open
    std::set<std::pair<int64_t, int64_t>> rim;
    auto rep = [&](vtkIdType input) {
      for (int64_t p = 0; p < v.NumberOfPoints; ++p)
        if (v.InputPointId[p] == input)
          return plodcheck::Representative(v, cut.data(), p);
      return int64_t(-999);
    };
    std::vector<int64_t> sourceOf(r.PointSource.begin(), r.PointSource.end());
    for (int i = 0; i < n; ++i)
    {
      const vtkIdType edges[4][2] = { { i * (n + 1), (i + 1) * (n + 1) },
        { i * (n + 1) + n, (i + 1) * (n + 1) + n }, { i, i + 1 },
        { n * (n + 1) + i, n * (n + 1) + i + 1 } };
      for (auto& e : edges)
      {
        const int64_t a = rep(e[0]), c = rep(e[1]);
        rim.insert({ std::min(a, c), std::max(a, c) });
      }
    }
    std::map<std::pair<int64_t, int64_t>, int> use;
    for (size_t k = 0; k + 2 < r.Triangles.size(); k += 3)
      for (int e = 0; e < 3; ++e)
      {
        const int64_t a = sourceOf[r.Triangles[k + e]], c = sourceOf[r.Triangles[k + (e + 1) % 3]];
        use[{ std::min(a, c), std::max(a, c) }] += a < c ? 1 : -1;
      }
    for (const auto& u : use)
    {
      if (u.second != 0)
      {
        ASSERT_TRUE(rim.count(u.first)) << "an open edge inside the sheet, trial " << trial;
      }
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
  Built b = Build(bunny);
  const plod::OctreeView& v = b.View;
  // the input's open edges (its holes), as point pairs
  std::map<std::pair<int32_t, int32_t>, int> use;
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    for (int e = 0; e < 3; ++e)
    {
      const int32_t a = v.Triangles[3 * t + e], c = v.Triangles[3 * t + (e + 1) % 3];
      use[{ std::min(a, c), std::max(a, c) }] += a < c ? 1 : -1;
    }
  std::vector<std::pair<int32_t, int32_t>> holes;
  for (const auto& u : use)
    if (u.second != 0)
      holes.push_back(u.first);
  EXPECT_GT(holes.size(), 0u);
  for (int level : { 3, 5, 7, -1 })
  {
    std::vector<uint8_t> cut(v.NumberOfNodes);
    plod::UniformCut(v, level, cut.data());
    plod::PatchResult r;
    plod::PatchOptions keep;
    keep.Folds = plod::FoldHandling::Keep;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r, nullptr, nullptr, keep));
    std::set<std::pair<int64_t, int64_t>> allowed;
    for (const auto& h : holes)
    {
      const int64_t a = plodcheck::Representative(v, cut.data(), h.first);
      const int64_t c = plodcheck::Representative(v, cut.data(), h.second);
      allowed.insert({ std::min(a, c), std::max(a, c) });
    }
    std::map<std::pair<int64_t, int64_t>, int> out;
    for (size_t k = 0; k + 2 < r.Triangles.size(); k += 3)
      for (int e = 0; e < 3; ++e)
      {
        const int64_t a = r.PointSource[r.Triangles[k + e]];
        const int64_t c = r.PointSource[r.Triangles[k + (e + 1) % 3]];
        out[{ std::min(a, c), std::max(a, c) }] += a < c ? 1 : -1;
      }
    for (const auto& u : out)
    {
      if (u.second != 0)
      {
        ASSERT_TRUE(allowed.count(u.first))
          << "an open edge away from the bunny's holes, level " << level;
      }
    }
  }
}

TEST(MultiscalePatchGenerator, WorkFollowsWhatIsDrawn)
{
  // the walk visits the refined nodes and the cut nodes under them, nothing below the cut
  auto blob = plodtest::MakeBlob(8, 100, 0.3);
  Built b = Build(blob);
  const plod::OctreeView& v = b.View;
  for (int level = 0; level <= v.FinestLevel; ++level)
  {
    std::vector<uint8_t> cut(v.NumberOfNodes);
    plod::UniformCut(v, level, cut.data());
    plod::PatchResult r;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r));
    int64_t upTo = 0;
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      upTo += v.Level[n] <= level;
    EXPECT_EQ(r.NodesVisited, upTo) << level;
  }
  std::vector<uint8_t> root(v.NumberOfNodes, 0);
  root[0] = plod::CutDrawn;
  plod::PatchResult r;
  ASSERT_TRUE(plod::GeneratePatches(v, root.data(), nullptr, r));
  EXPECT_EQ(r.NodesVisited, 1);
  EXPECT_EQ(r.Triangles.size(), 0u) << "the root alone is one point: no triangle";
}

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
  countBuild->SetCallback(
    [](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
  countPatch->SetClientData(&patches);
  countPatch->SetCallback(
    [](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
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

TEST(MultiscalePatchGenerator, InvalidCutsAreErrorsAndEmptyOutputs)
{
  auto blob = plodtest::MakeBlob(2, 16, 0.2);
  Built b = Build(blob, 4);
  const plod::OctreeView& v = b.View;
  std::vector<uint8_t> good(v.NumberOfNodes);
  plod::UniformCut(v, 3, good.data());
  int32_t inner = 0;
  while (v.Level[inner] < 2)
    inner = v.FirstChild[inner];
  struct Case
  {
    const char* What;
    std::function<void(std::vector<uint8_t>&)> Edit;
    const char* Message;
  };
  const Case cases[] = {
    { "state 7", [&](std::vector<uint8_t>& c) { c[inner] = 7; }, "cut state 7" },
    { "opened inner node",
      [&](std::vector<uint8_t>& c) {
        std::fill(c.begin(), c.end(), 0);
        c[0] = plod::CutOpen;
      },
      "opened but is not a leaf" },
    { "uncovered leaf", [&](std::vector<uint8_t>& c) { c[v.FirstChild[inner]] = 0; },
      "no ancestor in the cut" },
    { "covered twice", [&](std::vector<uint8_t>& c) { c[inner] = plod::CutDrawn; },
      "below another cut node" },
  };
  for (const Case& k : cases)
  {
    std::vector<uint8_t> cut = good;
    k.Edit(cut);
    std::string why;
    EXPECT_FALSE(plod::ValidateCut(v, cut.data(), &why)) << k.What;
    vtkNew<plodtest::ErrorRecorder> errors;
    auto pd = Patches(WithCut(b.Octree, cut), errors);
    EXPECT_TRUE(errors->HasError(k.Message))
      << k.What << ": " << (errors->Errors.empty() ? "" : errors->Errors[0]);
    EXPECT_EQ(pd->GetNumberOfPolys(), 0) << k.What;
    EXPECT_FALSE(WithCut(b.Octree, cut)->HasValidCut()) << k.What;
  }
  // empty input
  vtkNew<vtkMultiscaleOctree> empty;
  EXPECT_EQ(Patches(empty)->GetNumberOfPoints(), 0);
  // refine-array mode without the array
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  vtkNew<plodtest::ErrorRecorder> cutErrors;
  cutter->AddObserver(vtkCommand::ErrorEvent, cutErrors);
  cutter->SetInputData(b.Octree);
  cutter->SetModeToRefineArray();
  cutter->Update();
  EXPECT_TRUE(cutErrors->HasError("Refine array"));
  EXPECT_EQ(cutter->GetOutput()->GetNumberOfNodes(), 0);
}

TEST(MultiscalePatchGenerator, CorruptOctreesAreErrorsNotCrashes)
{
  // arrays edited after the build: the generator and the cutter refuse the octree with a clear
  // error instead of following a bad index or looping on a cycle
  auto blob = plodtest::MakeBlob(9, 20, 0.2);
  Built b = Build(blob, 4);
  auto* parent = vtkIntArray::SafeDownCast(b.Octree->GetNodeData()->GetArray("Parent"));
  auto* first = vtkIntArray::SafeDownCast(b.Octree->GetNodeData()->GetArray("FirstChild"));
  auto* tris = vtkIntArray::SafeDownCast(b.Octree->GetSurfaceData()->GetArray("Triangles"));
  auto* owned = vtkIdTypeArray::SafeDownCast(b.Octree->GetNodeData()->GetArray("FirstTriangle"));
  const vtkIdType last = b.Octree->GetNumberOfNodes() - 1;
  struct Edit
  {
    vtkDataArray* A;
    vtkIdType I;
    double V;
  };
  const Edit edits[] = { { first, 0, 1e9 }, { first, 3, 1 }, { parent, last, double(last) },
    { tris, 5, -1 }, { owned, 4, 1e12 } };
  for (const Edit& e : edits)
  {
    const double old = e.A->GetComponent(e.I, 0);
    e.A->SetComponent(e.I, 0, e.V);
    e.A->Modified();
    vtkNew<plodtest::ErrorRecorder> errors;
    vtkNew<vtkMultiscaleOctreeCutter> cutter;
    cutter->SetInputData(b.Octree);
    cutter->AddObserver(vtkCommand::ErrorEvent, errors);
    vtkNew<vtkMultiscalePatchGenerator> gen;
    gen->SetInputData(b.Octree);
    gen->AddObserver(vtkCommand::ErrorEvent, errors);
    cutter->Update();
    gen->Update();
    EXPECT_EQ(cutter->GetOutput()->GetNumberOfNodes(), 0) << e.A->GetName();
    EXPECT_EQ(gen->GetOutput()->GetNumberOfPolys(), 0) << e.A->GetName();
    EXPECT_TRUE(errors->HasError("invalid")) << e.A->GetName();
    e.A->SetComponent(e.I, 0, old);
    e.A->Modified();
  }
  EXPECT_TRUE(b.Octree->IsConsistent());
}

TEST(MultiscalePatchGenerator, CutterModesMakeValidCuts)
{
  auto blob = plodtest::MakeBlob(3, 24, 0.3);
  Built b = Build(blob, 5);
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(b.Octree);
  for (int level : { -1, 0, 3, 5, 40 })
  {
    cutter->SetLevel(level);
    cutter->Update();
    EXPECT_TRUE(cutter->GetOutput()->HasValidCut()) << level;
  }
  // callback: refine the upper half (z > 0) down to the input, the rest stops at level 2
  cutter->SetModeToCallback();
  vtkMultiscaleOctree* o = b.Octree;
  cutter->SetRefineCallback([o](vtkIdType n) {
    double x[3];
    o->GetNodeVertex(n, x);
    return o->GetNodeLevel(n) < 2 || x[2] > 0;
  });
  cutter->Update();
  EXPECT_TRUE(cutter->GetOutput()->HasValidCut());
  auto pd = Patches(cutter->GetOutput(), nullptr, false);
  std::vector<int64_t> tris;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    tris.insert(tris.end(), ids, ids + 3);
  }
  EXPECT_EQ(plodcheck::OpenEdges(tris), 0);
  // refine array: refined leaves are opened
  vtkNew<vtkUnsignedCharArray> refine;
  refine->SetName("Refine");
  refine->SetNumberOfTuples(b.Octree->GetNumberOfNodes());
  for (vtkIdType n = 0; n < b.Octree->GetNumberOfNodes(); ++n)
    refine->SetValue(n, b.Octree->GetNodeLevel(n) < 3 ? 1 : 0);
  auto withArray = vtkSmartPointer<vtkMultiscaleOctree>::New();
  withArray->ShallowCopy(b.Octree);
  withArray->GetNodeData()->AddArray(refine);
  cutter->SetInputData(withArray);
  cutter->SetModeToRefineArray();
  cutter->Update();
  EXPECT_TRUE(cutter->GetOutput()->HasValidCut());
  auto* cut = vtkUnsignedCharArray::SafeDownCast(
    cutter->GetOutput()->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  for (vtkIdType n = 0; n < b.Octree->GetNumberOfNodes(); ++n)
    ASSERT_EQ(cut->GetValue(n) != 0, b.Octree->GetNodeLevel(n) == 3);
  refine->FillValue(1);
  cutter->Modified();
  cutter->Update();
  cut = vtkUnsignedCharArray::SafeDownCast(
    cutter->GetOutput()->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  for (vtkIdType n = 0; n < b.Octree->GetNumberOfNodes(); ++n)
  {
    const bool leaf = b.Octree->GetNumberOfChildren(n) == 0;
    ASSERT_EQ(cut->GetValue(n), leaf ? plod::CutOpen : plod::NotInCut);
  }
}

// ---- distributed rendering: ghost points and the lead-corner rule ---------------------------

namespace
{
/// Output triangles by their corners' coordinates, each rotated to start at its smallest corner
/// (orientation kept).
std::multiset<std::array<double, 9>> TrianglesByCoordinates(vtkPolyData* pd)
{
  std::multiset<std::array<double, 9>> out;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
      pd->GetPoint(ids[k], c[k].data());
    while (!(c[0] <= c[1] && c[0] <= c[2]))
      std::rotate(c.begin(), c.begin() + 1, c.end());
    out.insert({ c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2] });
  }
  return out;
}

/// A copy of `mesh` whose points with x above `split` (or not above, `above` false) are ghosts.
vtkSmartPointer<vtkPolyData> WithGhosts(vtkPolyData* mesh, double split, bool above)
{
  auto copy = vtkSmartPointer<vtkPolyData>::New();
  copy->ShallowCopy(mesh);
  vtkNew<vtkUnsignedCharArray> flags;
  flags->SetName(vtkDataSetAttributes::GhostArrayName());
  flags->SetNumberOfTuples(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double x[3];
    mesh->GetPoint(i, x);
    flags->SetValue(i, (x[0] > split) == above ? vtkDataSetAttributes::DUPLICATEPOINT : 0);
  }
  copy->GetPointData()->AddArray(flags);
  return copy;
}

/// One process's pipeline: builder (optionally in a given cube), selector, cutter, generator.
struct Process
{
  vtkNew<vtkMultiscaleOctreeBuilder> Builder;
  vtkNew<vtkPerceptualLODSelector> Selector;
  vtkNew<vtkMultiscaleOctreeCutter> Cutter;
  vtkNew<vtkMultiscalePatchGenerator> Generator;
  Process(vtkPolyData* mesh, int level, const double* origin = nullptr, double edge = 0)
  {
    this->Builder->SetInputData(mesh);
    this->Builder->SetFinestLevel(level);
    if (origin)
    {
      this->Builder->UseGivenRootCubeOn();
      this->Builder->SetRootCubeOrigin(origin[0], origin[1], origin[2]);
      this->Builder->SetRootCubeEdge(edge);
    }
    this->Selector->SetInputConnection(this->Builder->GetOutputPort());
    this->Cutter->SetInputConnection(this->Builder->GetOutputPort());
  }
  /// Patches of the full resolution (no cut), a uniform level (>= 0) or the selector's cut (-2).
  vtkPolyData* Draw(int level)
  {
    if (level == -1)
      this->Generator->SetInputConnection(this->Builder->GetOutputPort());
    else if (level == -2)
      this->Generator->SetInputConnection(this->Selector->GetOutputPort());
    else
    {
      this->Cutter->SetLevel(level);
      this->Generator->SetInputConnection(this->Cutter->GetOutputPort());
    }
    this->Generator->Update();
    return this->Generator->GetOutput();
  }
  void Look(const double eye[3], const double focus[3])
  {
    vtkNew<vtkCamera> camera;
    camera->SetPosition(eye);
    camera->SetFocalPoint(focus);
    camera->SetViewAngle(30);
    double planes[24];
    camera->GetFrustumPlanes(16.0 / 9.0, planes);
    this->Selector->SetEyePosition(eye[0], eye[1], eye[2]);
    this->Selector->SetViewAngle(30);
    this->Selector->SetFrustumPlanes(planes);
    this->Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
  }
};

/// The two processes' outputs are the whole's, triangle for triangle (coordinates compared
/// exactly); processes that hold the whole mesh leave to each other at least what the other
/// draws (`copies`).
void ExpectSplit(
  Process& a, Process& b, Process& whole, int level, const std::string& what, bool copies)
{
  const auto all = TrianglesByCoordinates(whole.Draw(level));
  const vtkIdType nWhole = whole.Generator->GetNumberOfTriangles();
  EXPECT_EQ(whole.Generator->GetNumberOfGhostTriangles(), 0) << what;
  auto mine = TrianglesByCoordinates(a.Draw(level));
  const vtkIdType nA = a.Generator->GetNumberOfTriangles();
  const vtkIdType leftByA = a.Generator->GetNumberOfGhostTriangles();
  const auto theirs = TrianglesByCoordinates(b.Draw(level));
  const vtkIdType nB = b.Generator->GetNumberOfTriangles();
  const vtkIdType leftByB = b.Generator->GetNumberOfGhostTriangles();
  EXPECT_EQ(nA + nB, nWhole) << what;
  if (nWhole > 20) // both draw a share
  {
    EXPECT_GT(nA, 0) << what;
    EXPECT_GT(nB, 0) << what;
  }
  if (copies)
  {
    EXPECT_GE(leftByA, nB) << what;
    EXPECT_GE(leftByB, nA) << what;
  }
  else
  {
    EXPECT_GT(leftByA + leftByB, 0) << what; // the pieces overlap
  }
  mine.insert(theirs.begin(), theirs.end());
  EXPECT_TRUE(mine == all) << what << ": the union differs from the whole's output";
}
} // namespace

TEST(MultiscalePatchGenerator, GhostLeadCornerRuleOverRandomCuts)
{
  // The rule, exactly: over random cuts with hidden cells and cull masks, the output is the
  // expected clustering of the input minus every triangle whose corner of smallest surface index
  // is a ghost; with the complementary flags the two outputs add up to the output without ghosts,
  // folds included.
  auto blob = plodtest::MakeBlob(31, 32, 0.3);
  Built b = Build(WithGhosts(blob, 0.1, true), 5);
  const plod::OctreeView& v = b.View;
  ASSERT_NE(v.PointGhost, nullptr);
  std::vector<uint8_t> complement(v.NumberOfPoints);
  for (int64_t p = 0; p < v.NumberOfPoints; ++p)
    complement[p] = v.PointGhost[p] ? 0 : 1;
  plod::OctreeView other = v, none = v;
  other.PointGhost = complement.data();
  none.PointGhost = nullptr;
  std::mt19937 rng(13);
  std::uniform_int_distribution<int> plane(0, 5);
  plod::PatchOptions keep, reverse;
  keep.Folds = plod::FoldHandling::Keep;
  int64_t split = 0;
  for (int trial = 0; trial < 120; ++trial)
  {
    std::vector<uint8_t> cut = RandomCut(v, rng, 0.3);
    std::vector<uint8_t> mask(v.NumberOfNodes, 0);
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      if (cut[n] == plod::CutHidden)
        mask[n] = static_cast<uint8_t>(1u << plane(rng));
    plod::PatchResult r, c, all;
    std::string why;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), mask.data(), r, &why, nullptr, keep)) << why;
    std::multiset<std::array<int64_t, 3>> expected;
    int64_t ghosts = 0;
    for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    {
      const int32_t* corner = &v.Triangles[3 * t];
      int64_t rep[3];
      bool drawn = false;
      uint8_t common = 0x3f;
      for (int k = 0; k < 3; ++k)
      {
        rep[k] = plodcheck::Representative(v, cut.data(), corner[k]);
        const int64_t node = plodcheck::NodeOf(v, rep[k]);
        drawn = drawn || cut[node] != plod::CutHidden;
        if (cut[node] == plod::CutHidden)
          common &= mask[node];
      }
      if (rep[0] == rep[1] || rep[1] == rep[2] || rep[0] == rep[2])
        continue;
      if (v.PointGhost[std::min({ corner[0], corner[1], corner[2] })])
      {
        ++ghosts;
        continue;
      }
      if (!drawn && common)
        continue;
      expected.insert(plodcheck::Canonical(rep[0], rep[1], rep[2]));
    }
    ASSERT_EQ(plodcheck::DrawnTriangles(r), expected) << trial;
    EXPECT_EQ(r.GhostSkipped, ghosts) << trial;
    // complementary flags: the two halves are the whole, with either fold handling
    for (const plod::PatchOptions& options : { keep, reverse })
    {
      ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), mask.data(), r, &why, nullptr, options));
      ASSERT_TRUE(plod::GeneratePatches(other, cut.data(), mask.data(), c, &why, nullptr, options));
      ASSERT_TRUE(
        plod::GeneratePatches(none, cut.data(), mask.data(), all, &why, nullptr, options));
      EXPECT_EQ(r.Triangles.size() + c.Triangles.size(), all.Triangles.size()) << trial;
      EXPECT_EQ(r.Folds + c.Folds, all.Folds) << trial;
      EXPECT_EQ(all.GhostSkipped, 0);
      auto both = plodcheck::DrawnTriangles(r);
      const auto second = plodcheck::DrawnTriangles(c);
      both.insert(second.begin(), second.end());
      EXPECT_EQ(both, plodcheck::DrawnTriangles(all)) << trial;
      split += r.Triangles.empty() || c.Triangles.empty() ? 0 : 1;
    }
  }
  EXPECT_GT(split, 100); // both sides drew something in most cuts
}

TEST(MultiscalePatchGenerator, GhostFlagsSplitEveryCutBetweenTwoCopies)
{
  // Two processes hold the whole mesh, each point owned by exactly one of them (a plane splits
  // them): at the full resolution, at every uniform level and at a view-dependent cut (back faces
  // culled, folds on their own points), their outputs add up to the output of the mesh without
  // ghosts, triangle for triangle.
  auto blob = plodtest::MakeBlob(32, 40, 0.3);
  const int L = 5;
  Process whole(blob, L), a(WithGhosts(blob, -0.2, true), L), b(WithGhosts(blob, -0.2, false), L);
  for (int level : { -1, 0, 1, 2, 3, 4, 5 })
    ExpectSplit(a, b, whole, level, "level " + std::to_string(level), true);
  const double eye[3] = { 2.5, 1.2, 3.0 }, focus[3] = { 0.2, 0, 0 };
  for (Process* p : { &whole, &a, &b })
    p->Look(eye, focus);
  ExpectSplit(a, b, whole, -2, "view-dependent cut", true);
  EXPECT_GT(whole.Generator->GetNumberOfCulledBackFaces(), 0);
  EXPECT_TRUE(whole.Selector->GetOutput()->HasValidCut());
  // without the ghost array, nothing changes: a process draws everything
  Process plain(blob, L);
  plain.Draw(3);
  whole.Draw(3);
  EXPECT_EQ(plain.Generator->GetNumberOfTriangles(), whole.Generator->GetNumberOfTriangles());
  EXPECT_EQ(plain.Generator->GetNumberOfGhostTriangles(), 0);
}

TEST(MultiscalePatchGenerator, PiecesWithGhostsDrawTheWholeOnce)
{
  // The plugin's scheme end to end: two processes own the level-k cells on either side of the
  // cube's middle plane, hold their triangles plus complete copies of the neighbour cells, flag
  // the points of cells they do not own as ghosts, build with the whole's cube and level, and
  // refine every cell coarser than k. Their outputs add up to the whole's at the full
  // resolution, at every uniform level from k on and at a view-dependent cut.
  auto blob = plodtest::MakeBlob(33, 48, 0.3);
  double bounds[6], origin[3], edge;
  blob->GetBounds(bounds);
  ASSERT_TRUE(vtkMultiscaleOctreeBuilder::ComputeRootCube(bounds, origin, &edge));
  const int L = 5, k = 2;
  auto half = [&](bool low) {
    return plodcheck::MakePiece(
      blob, origin, edge, k, [low](const std::array<uint32_t, 3>& c) { return (c[0] < 2) == low; });
  };
  const plodcheck::Piece p0 = half(true), p1 = half(false);
  Process whole(blob, L, origin, edge), a(p0.Mesh, L, origin, edge), b(p1.Mesh, L, origin, edge);
  for (int level : { -1, 2, 3, 4, 5 })
    ExpectSplit(a, b, whole, level, "pieces, level " + std::to_string(level), false);
  const double eye[3] = { -1.5, 2.0, 3.0 }, focus[3] = { 0.1, 0, 0 };
  for (Process* p : { &whole, &a, &b })
  {
    p->Look(eye, focus);
    p->Selector->SetMinimumLevel(k);
    // a piece is an open surface: the automatic back-face mode would draw its back faces where
    // the whole (closed) hides them; every process must use the whole's mode
    p->Selector->SetBackFaceModeToHidden();
  }
  ExpectSplit(a, b, whole, -2, "pieces, view-dependent cut", false);
  EXPECT_GT(whole.Generator->GetNumberOfCulledBackFaces(), 0);
  // every cut cell is of level k or finer, or culled
  plod::OctreeView v;
  vtkMultiscaleOctree* cut = a.Selector->GetOutput();
  ASSERT_TRUE(cut->GetView(v));
  auto* state = vtkUnsignedCharArray::SafeDownCast(
    cut->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  auto* reason = vtkUnsignedCharArray::SafeDownCast(
    cut->GetNodeData()->GetArray(vtkPerceptualLODSelector::CutReasonArrayName()));
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (state->GetValue(n) != plod::NotInCut && v.Level[n] < k)
    {
      EXPECT_EQ(reason->GetValue(n), plod::Culled) << n;
    }
  }
}

// The parallel phase decides the owned triangles in ranges run in any order: the output is the
// serial one, point for point and counter for counter, whatever the ranges and their order.
// CountDrawnTriangles (the selector's exact budget) counts that output exactly, serial or in
// ranges, and finds the same error in an invalid cut.
TEST(MultiscalePatchGenerator, ParallelRangesGiveTheSerialOutput)
{
  const plod::ParallelFor backwards = Backwards();
  std::mt19937 rng(5);
  int compared = 0;
  for (const auto& model : ClosedModels(5))
  {
    Built b = Build(model.second, 5);
    const plod::OctreeView& v = b.View;
    plod::PatchWorkspace serialWs, parallelWs;
    for (int trial = 0; trial < 12; ++trial)
    {
      std::vector<uint8_t> cut = RandomCut(v, rng, trial % 3 == 0 ? 0.4 : 0.0);
      std::vector<uint8_t> mask(v.NumberOfNodes, 0);
      for (int64_t n = 0; n < v.NumberOfNodes; ++n)
        if (cut[n] == plod::CutHidden)
          mask[n] = static_cast<uint8_t>(rng() % 4);
      plod::PatchOptions serial;
      serial.Folds = static_cast<plod::FoldHandling>(trial % 3);
      serial.CullBackFaces = trial % 2 == 1;
      serial.Eye[0] = 0.3 * trial;
      serial.Eye[2] = 3.0;
      plod::PatchOptions parallel = serial;
      parallel.For = backwards;
      parallel.TrianglesPerRange = 1 + trial % 7;
      plod::PatchResult a, c;
      std::string whyA, whyC;
      const bool okA =
        plod::GeneratePatches(v, cut.data(), mask.data(), a, &whyA, &serialWs, serial);
      const bool okC =
        plod::GeneratePatches(v, cut.data(), mask.data(), c, &whyC, &parallelWs, parallel);
      ASSERT_TRUE(okA) << whyA;
      ASSERT_TRUE(okC) << whyC;
      const std::string what = model.first + " trial " + std::to_string(trial);
      EXPECT_EQ(a.PointSource, c.PointSource) << what;
      EXPECT_EQ(a.Triangles, c.Triangles) << what;
      EXPECT_EQ(a.ReversedNormals, c.ReversedNormals) << what;
      EXPECT_EQ(a.NodesVisited, c.NodesVisited) << what;
      EXPECT_EQ(a.HiddenSkipped, c.HiddenSkipped) << what;
      EXPECT_EQ(a.Folds, c.Folds) << what;
      EXPECT_EQ(a.BackFacesCulled, c.BackFacesCulled) << what;
      compared += a.Triangles.empty() ? 0 : 1;
      // the count alone (the selector's exact budget), serial and in ranges: what is drawn
      const int64_t drawn = static_cast<int64_t>(a.Triangles.size() / 3);
      EXPECT_EQ(plod::CountDrawnTriangles(v, cut.data(), mask.data(), serial, serialWs), drawn)
        << what;
      EXPECT_EQ(plod::CountDrawnTriangles(v, cut.data(), mask.data(), parallel, parallelWs), drawn)
        << what;
    }
    // an invalid cut (a level-1 node in the cut above the level-2 cut): the same first error
    std::vector<uint8_t> bad(v.NumberOfNodes);
    plod::UniformCut(v, std::min(2, v.FinestLevel), bad.data());
    bad[v.FirstChild[0]] = plod::CutDrawn;
    plod::PatchOptions parallel;
    parallel.For = backwards;
    parallel.TrianglesPerRange = 3;
    plod::PatchResult a, c;
    std::string whyA, whyC;
    const bool okA = plod::GeneratePatches(v, bad.data(), nullptr, a, &whyA);
    const bool okC = plod::GeneratePatches(v, bad.data(), nullptr, c, &whyC, nullptr, parallel);
    EXPECT_EQ(okA, okC) << model.first;
    EXPECT_EQ(whyA, whyC) << model.first;
    std::string whyCount;
    EXPECT_EQ(plod::CountDrawnTriangles(v, bad.data(), nullptr, parallel, serialWs, &whyCount), -1)
      << model.first;
    EXPECT_EQ(whyCount, whyA) << model.first;
  }
  EXPECT_GT(compared, 100);
}

// Remembered corner walks (PatchOptions::OctreeStamp): over a sequence of cuts (random ones, and
// each one's neighbour: some cut cells refined or coarsened, as a moving camera changes a cut),
// serial and in ranges, the output is the one of walks from the leaves; an invalid cut after
// valid ones gives the same first error; a new octree with the same points under a new stamp
// is not read with the old one's clusters.
TEST(MultiscalePatchGenerator, RememberedCornerWalksGiveTheFreshOutput)
{
  const plod::ParallelFor backwards = Backwards();
  // `cut` with about a fifth of its cut cells refined one level (a leaf opened) and a fifth of
  // the refined parents of cut cells coarsened: another valid cut
  auto neighbour = [](const plod::OctreeView& v, std::vector<uint8_t> cut, std::mt19937& rng) {
    for (int64_t n = v.NumberOfNodes - 1; n > 0; --n)
    {
      const int32_t p = v.Parent[n];
      if (cut[n] != plod::NotInCut && cut[n] != plod::CutOpen && rng() % 5 == 0)
      {
        bool all = true; // coarsen p when all its children are kept cells
        for (int k = 0; k < __builtin_popcount(v.ChildMask[p]); ++k)
          all = all && cut[v.FirstChild[p] + k] != plod::NotInCut &&
            cut[v.FirstChild[p] + k] != plod::CutOpen;
        if (all)
        {
          for (int k = 0; k < __builtin_popcount(v.ChildMask[p]); ++k)
            cut[v.FirstChild[p] + k] = plod::NotInCut;
          cut[p] = plod::CutDrawn;
        }
      }
    }
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    {
      if ((cut[n] == plod::CutDrawn || cut[n] == plod::CutHidden) && rng() % 5 == 0)
      {
        if (v.IsLeaf(n))
        {
          cut[n] = plod::CutOpen;
          continue;
        }
        cut[n] = plod::NotInCut;
        for (int k = 0; k < __builtin_popcount(v.ChildMask[n]); ++k)
          cut[v.FirstChild[n] + k] = plod::CutDrawn;
      }
    }
    return cut;
  };
  auto same = [](const plod::PatchResult& a, const plod::PatchResult& b, const std::string& what) {
    EXPECT_EQ(a.PointSource, b.PointSource) << what;
    EXPECT_EQ(a.Triangles, b.Triangles) << what;
    EXPECT_EQ(a.ReversedNormals, b.ReversedNormals) << what;
    EXPECT_EQ(a.BackFacesCulled, b.BackFacesCulled) << what;
  };
  std::mt19937 rng(11);
  int compared = 0, refused = 0;
  for (const auto& model : ClosedModels(5))
  {
    Built b = Build(model.second, 5);
    const plod::OctreeView& v = b.View;
    plod::PatchWorkspace serialWs, rangesWs;
    plod::PatchOptions remembered;
    remembered.OctreeStamp = 7;
    remembered.CullBackFaces = true;
    remembered.Eye[2] = 3.0;
    plod::PatchOptions ranges = remembered;
    ranges.For = backwards;
    ranges.TrianglesPerRange = 5;
    plod::PatchOptions fresh = remembered;
    fresh.OctreeStamp = 0;
    std::vector<uint8_t> cut = RandomCut(v, rng, 0.2);
    for (int frame = 0; frame < 16; ++frame)
    {
      cut = frame % 4 == 0 ? RandomCut(v, rng, 0.2) : neighbour(v, cut, rng);
      std::string why;
      ASSERT_TRUE(plod::ValidateCut(v, cut.data(), &why)) << why;
      plod::PatchResult a, c, d;
      ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, a, &why, nullptr, fresh)) << why;
      ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, c, &why, &serialWs, remembered))
        << why;
      ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, d, &why, &rangesWs, ranges)) << why;
      const std::string what = model.first + " frame " + std::to_string(frame);
      same(a, c, what + " (remembered)");
      same(a, d, what + " (remembered, in ranges)");
      // the count alone (the selector's exact budget) with the same remembered walks
      const int64_t drawn = static_cast<int64_t>(a.Triangles.size() / 3);
      EXPECT_EQ(plod::CountDrawnTriangles(v, cut.data(), nullptr, remembered, serialWs), drawn)
        << what;
      EXPECT_EQ(plod::CountDrawnTriangles(v, cut.data(), nullptr, ranges, rangesWs), drawn) << what;
      compared += a.Triangles.empty() ? 0 : 1;
    }
    // an invalid cut after valid ones: a cut cell's parent put in the cut above it
    std::vector<uint8_t> bad = cut;
    for (int64_t n = v.NumberOfNodes - 1; n > 0; --n)
    {
      if (bad[n] == plod::CutDrawn && v.Level[n] >= 2)
      {
        bad[v.Parent[n]] = plod::CutDrawn;
        break;
      }
    }
    // (the walk finds the error only where a drawn triangle's corner leads below the parent)
    plod::PatchResult a, c;
    std::string whyA, whyC;
    const bool okA = plod::GeneratePatches(v, bad.data(), nullptr, a, &whyA, nullptr, fresh);
    const bool okC = plod::GeneratePatches(v, bad.data(), nullptr, c, &whyC, &serialWs, remembered);
    EXPECT_EQ(okC, okA) << model.first;
    EXPECT_EQ(whyC, whyA) << model.first;
    if (okA && okC)
      same(a, c, model.first + " (a cut cell's parent in the cut)");
    refused += okA ? 0 : 1;
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(refused, 3);

  // a uniform cut, then the same with one refined parent put in the cut above its children (no
  // longer reached): every corner leading there was remembered at a child, and is refused
  auto blob = plodtest::MakeBlob(2, 40, 0.35);
  Built built = Build(blob, 5);
  const plod::OctreeView& bv = built.View;
  std::vector<uint8_t> uniform(bv.NumberOfNodes);
  plod::UniformCut(bv, 3, uniform.data());
  std::vector<uint8_t> covered = uniform;
  for (int64_t n = 0; n < bv.NumberOfNodes; ++n)
  {
    if (bv.Level[n] == 2 && !bv.IsLeaf(n))
    {
      covered[n] = plod::CutDrawn;
      break;
    }
  }
  plod::PatchWorkspace coveredWs;
  plod::PatchOptions stamped;
  stamped.OctreeStamp = 9;
  plod::PatchResult a, c;
  std::string whyA, whyC;
  ASSERT_TRUE(plod::GeneratePatches(bv, uniform.data(), nullptr, c, &whyC, &coveredWs, stamped));
  EXPECT_FALSE(plod::GeneratePatches(bv, covered.data(), nullptr, a, &whyA));
  EXPECT_FALSE(plod::GeneratePatches(bv, covered.data(), nullptr, c, &whyC, &coveredWs, stamped));
  EXPECT_EQ(whyC, whyA);

  // another octree with as many points (the blob turned) under a new stamp: not read with the
  // first one's clusters
  auto turned = vtkSmartPointer<vtkPolyData>::New();
  turned->DeepCopy(blob);
  for (vtkIdType i = 0; i < turned->GetNumberOfPoints(); ++i)
  {
    double x[3];
    turned->GetPoints()->GetPoint(i, x);
    turned->GetPoints()->SetPoint(i, 0.8 * x[0] - 0.6 * x[1], 0.6 * x[0] + 0.8 * x[1], x[2]);
  }
  Built other = Build(turned, 5);
  ASSERT_EQ(other.View.NumberOfPoints, bv.NumberOfPoints);
  plod::PatchOptions next = stamped;
  next.OctreeStamp = 10;
  for (int level : { 3, 4 })
  {
    std::vector<uint8_t> cut(other.View.NumberOfNodes);
    plod::UniformCut(other.View, level, cut.data());
    std::string why;
    ASSERT_TRUE(plod::GeneratePatches(other.View, cut.data(), nullptr, a, &why)) << why;
    ASSERT_TRUE(plod::GeneratePatches(other.View, cut.data(), nullptr, c, &why, &coveredWs, next))
      << why;
    same(a, c, "another octree, level " + std::to_string(level));
  }
}

// The filter on the Stanford bunny as a camera reset to its bounds orbits and dollies in, its
// input switching between the bunny's octree and the octree of the bunny turned about its
// centre (the same number of points, other clusters):
// every frame, the output of the generator that remembers its walks (and the octree's stamp
// that keys them) equals, bit for bit, a new generator's, which walks every corner afresh.
TEST(MultiscalePatchGenerator, RememberedWalksOnTheBunnyFollowTheCutAndTheOctree)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  auto bunny = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  ASSERT_TRUE(bunny);
  // the camera vtkRenderer::ResetCamera places: the bounds' sphere fills the 30-degree view
  double bounds[6], centre[3], radius = 0;
  bunny->GetBounds(bounds);
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    radius += 0.25 * (bounds[2 * a + 1] - bounds[2 * a]) * (bounds[2 * a + 1] - bounds[2 * a]);
  }
  auto turned = vtkSmartPointer<vtkPolyData>::New();
  turned->DeepCopy(bunny);
  for (vtkIdType i = 0; i < turned->GetNumberOfPoints(); ++i)
  {
    double x[3];
    turned->GetPoints()->GetPoint(i, x);
    const double u = x[0] - centre[0], w = x[2] - centre[2];
    turned->GetPoints()->SetPoint(
      i, centre[0] + 0.8 * u - 0.6 * w, x[1], centre[2] + 0.6 * u + 0.8 * w);
  }
  const Built octrees[2] = { Build(bunny, 8), Build(turned, 8) };
  ASSERT_EQ(octrees[0].View.NumberOfPoints, octrees[1].View.NumberOfPoints);
  const double reset = std::sqrt(radius) / std::sin(vtkMath::RadiansFromDegrees(15.0));
  vtkNew<vtkPerceptualLODSelector> selector;
  selector->SetViewportSize(640, 480);
  selector->AddLight(false, 0, 0, 1, 1, 0);
  vtkNew<vtkMultiscalePatchGenerator> kept;
  kept->SetInputConnection(selector->GetOutputPort());
  kept->GenerateNodeIdsOn();
  int64_t drawn = 0;
  for (int frame = 0; frame < 24; ++frame)
  {
    selector->SetInputData(octrees[(frame / 4) % 2].Octree);
    const double az = vtkMath::RadiansFromDegrees(3.0 * frame);
    const double d = reset * (frame % 3 == 2 ? 0.35 : 1.0); // every third frame dollied in
    vtkNew<vtkCamera> camera;
    camera->SetFocalPoint(centre);
    camera->SetPosition(
      centre[0] + d * std::sin(az), centre[1] + 0.2 * d, centre[2] + d * std::cos(az));
    camera->SetViewAngle(30);
    camera->SetClippingRange(0.01 * d, 10 * d);
    double planes[24];
    camera->GetFrustumPlanes(640.0 / 480.0, planes);
    selector->SetEyePosition(camera->GetPosition());
    selector->SetFrustumPlanes(planes);
    selector->SetLight(
      0, false, camera->GetPosition()[0], camera->GetPosition()[1], camera->GetPosition()[2], 1, 0);
    kept->Update();
    vtkNew<vtkMultiscalePatchGenerator> fresh;
    fresh->SetInputData(selector->GetOutput());
    fresh->GenerateNodeIdsOn();
    fresh->Update();
    vtkPolyData* a = fresh->GetOutput();
    vtkPolyData* b = kept->GetOutput();
    const std::string what = "frame " + std::to_string(frame);
    ASSERT_GT(a->GetNumberOfPolys(), 0) << what;
    ExpectSameValues(a->GetPoints()->GetData(), b->GetPoints()->GetData(), what + ": points");
    ExpectSameValues(
      a->GetPointData()->GetNormals(), b->GetPointData()->GetNormals(), what + ": normals");
    ExpectSameValues(a->GetPointData()->GetArray("OctreeNode"),
      b->GetPointData()->GetArray("OctreeNode"), what + ": nodes");
    ExpectSameValues(a->GetPolys()->GetConnectivityArray(), b->GetPolys()->GetConnectivityArray(),
      what + ": triangles");
    drawn += a->GetNumberOfPolys();
  }
  EXPECT_GT(drawn, 24 * 1000);
}

// The filter on 1, 2 and 8 threads: the same arrays, value for value.
TEST(MultiscalePatchGenerator, AnyThreadCountGivesTheSameOutput)
{
  auto blob = plodtest::MakeBlob(7, 160, 0.3);
  Built b = Build(blob, 7);
  std::vector<uint8_t> cut(b.View.NumberOfNodes);
  plod::UniformCut(b.View, -1, cut.data()); // every leaf opened: many ranges
  auto octree = WithCut(b.Octree, cut);
  auto run = [&](int threads, bool multi) {
    vtkSMPTools::Initialize(threads);
    vtkNew<vtkMultiscalePatchGenerator> gen;
    gen->SetInputData(octree);
    gen->SetMultiThreaded(multi);
    gen->GenerateNodeIdsOn();
    gen->Update();
    auto pd = vtkSmartPointer<vtkPolyData>::New();
    pd->DeepCopy(gen->GetOutput());
    return pd;
  };
  const auto same = ExpectSameValues;
  const auto reference = run(1, false);
  ASSERT_GT(reference->GetNumberOfPolys(), 2 * 16384) << "too small to split in ranges";
  for (int threads : { 1, 2, 8 })
  {
    const auto pd = run(threads, true);
    const std::string what = std::to_string(threads) + " threads";
    same(reference->GetPoints()->GetData(), pd->GetPoints()->GetData(), what + ": points");
    same(reference->GetPointData()->GetNormals(), pd->GetPointData()->GetNormals(),
      what + ": normals");
    same(reference->GetPointData()->GetArray("OctreeNode"),
      pd->GetPointData()->GetArray("OctreeNode"), what + ": nodes");
    same(reference->GetPolys()->GetConnectivityArray(), pd->GetPolys()->GetConnectivityArray(),
      what + ": triangles");
  }
  vtkSMPTools::Initialize(0);
}

// The GPU path's triangles: the ranges of the owner-sorted array owned by refined nodes and
// opened leaves, sorted, merged where they touch, covering exactly the triangles the patch
// generator considers (those it draws or culls by its per-triangle rules).
TEST(MultiscalePatchGenerator, DrawnTriangleRangesAreTheCutsTrianglesMerged)
{
  std::mt19937 rng(17);
  for (const auto& model : ClosedModels(5))
  {
    Built b = Build(model.second, 5);
    const plod::OctreeView& v = b.View;
    plod::PatchWorkspace ws;
    for (int trial = 0; trial < 10; ++trial)
    {
      const std::vector<uint8_t> cut = RandomCut(v, rng, 0.0);
      std::vector<int64_t> first, count;
      std::string why;
      ASSERT_TRUE(plod::DrawnTriangleRanges(v, cut.data(), first, count, &why, &ws)) << why;
      // expected: every triangle whose owner is above the cut (or an opened leaf)
      std::vector<bool> expected(v.NumberOfTriangles, false);
      for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      {
        bool above = cut[n] == plod::CutOpen;
        for (int64_t a = n; !above && a >= 0; a = v.Parent[a])
        {
          if (cut[a] != plod::NotInCut)
            break; // n is in or below the cut
          if (a == 0)
            above = true; // no cut node on the way up: n is above the cut
        }
        if (above)
          for (int64_t t = v.FirstTriangle[n]; t < v.TriangleEnd(n); ++t)
            expected[t] = true;
      }
      std::vector<bool> got(v.NumberOfTriangles, false);
      for (size_t i = 0; i < first.size(); ++i)
      {
        ASSERT_GT(count[i], 0);
        if (i > 0)
        {
          EXPECT_GT(first[i], first[i - 1] + count[i - 1]) << "ranges not sorted, or touching";
        }
        for (int64_t t = first[i]; t < first[i] + count[i]; ++t)
          got[t] = true;
      }
      ASSERT_EQ(got, expected) << model.first << " trial " << trial;
      // the patch generator considers the same triangles: drawn + culled + collapsed
      plod::PatchResult r;
      plod::PatchOptions keep;
      keep.Folds = plod::FoldHandling::Keep;
      ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), nullptr, r, nullptr, nullptr, keep));
      int64_t total = 0;
      for (int64_t c : count)
        total += c;
      EXPECT_EQ(total, static_cast<int64_t>(r.Triangles.size() / 3)) << model.first;
    }
  }
}

// The spans of a state that changed: exactly the differing bytes, spans closer than the gap
// merged, the bytes counted.
TEST(MultiscalePatchGenerator, ChangedSpansCoverEveryDifferenceAndMergeCloseOnes)
{
  std::mt19937 rng(23);
  for (int trial = 0; trial < 200; ++trial)
  {
    const int64_t n = 1 + rng() % 2000;
    const int64_t gap = 1 + rng() % 80;
    std::vector<uint8_t> before(n), now(n);
    for (int64_t i = 0; i < n; ++i)
      before[i] = now[i] = static_cast<uint8_t>(rng() % 4);
    const int changes = static_cast<int>(rng() % 30);
    for (int k = 0; k < changes; ++k)
      now[rng() % n] ^= 1;
    std::vector<std::pair<int64_t, int64_t>> spans;
    const int64_t bytes = plod::ChangedSpans(before.data(), now.data(), n, gap, spans);
    int64_t sum = 0;
    std::vector<bool> inSpan(n, false);
    for (size_t i = 0; i < spans.size(); ++i)
    {
      ASSERT_LT(spans[i].first, spans[i].second);
      EXPECT_NE(before[spans[i].first], now[spans[i].first]) << "a span starts on a difference";
      EXPECT_NE(before[spans[i].second - 1], now[spans[i].second - 1]) << "and ends on one";
      if (i > 0)
      {
        EXPECT_GE(spans[i].first - spans[i - 1].second, gap) << "close spans not merged";
      }
      sum += spans[i].second - spans[i].first;
      for (int64_t j = spans[i].first; j < spans[i].second; ++j)
        inSpan[j] = true;
    }
    EXPECT_EQ(bytes, sum);
    for (int64_t i = 0; i < n; ++i)
    {
      if (before[i] != now[i])
      {
        ASSERT_TRUE(inSpan[i]) << "a difference outside every span";
      }
    }
  }
}
