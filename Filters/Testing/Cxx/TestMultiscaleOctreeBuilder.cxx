// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkMultiscaleOctreeBuilder and vtkMultiscaleOctree: exact small cases, invariants over
// families of generated meshes (checked by brute force in plodOctreeChecks.h), extremes, bad
// input, and the Stanford data when present.
#include "plodOctreeBuilder.h"
#include "plodOctreeChecks.h"
#include "plodOctreeSchema.h"
#include "plodOctreeStorage.h"
#include "plodPieceAssembly.h"
#include "plodPieces.h"
#include "plodTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPLYWriter.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkSMPTools.h"
#include "vtkStaticPointLocator.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unistd.h>

using plodcheck::Angle;
using plodcheck::Build;
using plodcheck::Built;
using plodcheck::CheckOctree;
using plodcheck::Get3;
using plodcheck::Pi;

namespace
{

/// Input triangles (as input point ids, rotated to start at the smallest) of a polydata.
std::multiset<std::array<int64_t, 3>> InputTriangles(vtkPolyData* pd)
{
  std::multiset<std::array<int64_t, 3>> out;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      if (ids[0] != ids[k] && ids[k] != ids[k + 1] && ids[0] != ids[k + 1])
        out.insert(plodcheck::Canonical(ids[0], ids[k], ids[k + 1]));
    }
  }
  return out;
}

/// The octree's surface triangles, as input point ids.
std::multiset<std::array<int64_t, 3>> SurfaceTriangles(const plod::OctreeView& v)
{
  std::multiset<std::array<int64_t, 3>> out;
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
  {
    const int32_t* c = &v.Triangles[3 * t];
    out.insert(
      plodcheck::Canonical(v.InputPointId[c[0]], v.InputPointId[c[1]], v.InputPointId[c[2]]));
  }
  return out;
}

/// The surface keeps the input: same triangles (by input ids, orientation included) and the
/// same point positions (in single precision relative to the origin).
void CheckSurfaceIsTheInput(const Built& b, vtkPolyData* input, const std::string& what)
{
  const plod::OctreeView& v = b.View;
  EXPECT_EQ(SurfaceTriangles(v), InputTriangles(input)) << what;
  const double* o = b.Octree->GetOrigin();
  for (int64_t p = 0; p < v.NumberOfPoints; ++p)
  {
    double x[3];
    input->GetPoint(v.InputPointId[p], x);
    for (int a = 0; a < 3; ++a)
    {
      ASSERT_NEAR(o[a] + v.Points[3 * p + a], x[a], 1e-6 * v.RootEdge + 1e-7 * std::abs(x[a]))
        << what << " point " << p;
    }
  }
}

} // namespace

TEST(MultiscaleOctreeBuilder, PlaneHasFlatConesZeroShapeErrorAndVerticesOnThePlane)
{
  // a subdivided flat open sheet: every cone is the plane's normal with angle 0, every shape
  // error is 0, and QEF vertices stay on the plane (z = 0.3)
  vtkNew<vtkPolyData> sheet;
  {
    std::vector<double> xyz;
    std::vector<vtkIdType> tri;
    const int n = 16;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        xyz.insert(xyz.end(), { double(i) / n, double(j) / n, 0.3 });
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
      {
        const vtkIdType a = i * (n + 1) + j, b = (i + 1) * (n + 1) + j;
        tri.insert(tri.end(), { a, b, b + 1, a, b + 1, a + 1 });
      }
    sheet->DeepCopy(plodtest::MakeMesh(xyz, tri));
  }
  Built b = Build(sheet);
  CheckOctree(b, "sheet");
  CheckSurfaceIsTheInput(b, sheet, "sheet");
  const plod::OctreeView& v = b.View;
  const double up[3] = { 0, 0, 1 };
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const auto axis = Get3(&v.ConeAxis[3 * n]);
    EXPECT_LT(Angle(axis.data(), up), 1e-6) << n;
    EXPECT_LT(v.ConeAngle[n], 1e-5f) << n;
    EXPECT_LT(v.ShapeError[n], 1e-6f) << n;
    EXPECT_NEAR(b.Octree->GetOrigin()[2] + v.Vertex[3 * n + 2], 0.3, 1e-6) << n;
  }
  // an open sheet has a boundary: its rim
  EXPECT_EQ(b.Octree->GetNumberOfBoundaryEdges(), 4 * 16);
  EXPECT_EQ(b.Octree->GetNumberOfNonManifoldEdges(), 0);
}

TEST(MultiscaleOctreeBuilder, SubdividedCubeConesRootAndCorners)
{
  // a closed cube subdivided 8 x 8 per face: the root's normals cancel (theta = pi), a cell
  // holding a corner holds its three face normals, and a cell inside a face is flat
  auto cube = plodtest::MakeDeformedBox(8, 8, 8, [](const double p[3], double x[3]) {
    for (int a = 0; a < 3; ++a)
      x[a] = p[a];
  });
  Built b = Build(cube, 4);
  CheckOctree(b, "cube");
  CheckSurfaceIsTheInput(b, cube, "cube");
  const plod::OctreeView& v = b.View;
  EXPECT_NEAR(v.ConeAngle[0], Pi, 1e-6) << "a closed surface's normals cancel at the root";
  EXPECT_EQ(b.Octree->GetNumberOfBoundaryEdges(), 0);
  EXPECT_EQ(v.Flags[0] & plod::NodeTopologySafe, 0) << "a sphere (chi = 2) is not a disc";
  const double* o = b.Octree->GetOrigin();
  const double corner[3] = { 1, 1, 1 };
  const vtkIdType leaf = b.Octree->FindNode(corner, v.FinestLevel);
  ASSERT_GE(leaf, 0);
  const auto axis = Get3(&v.ConeAxis[3 * leaf]);
  for (int a = 0; a < 3; ++a)
  {
    double n[3] = { 0, 0, 0 };
    n[a] = 1;
    EXPECT_LE(Angle(axis.data(), n), v.ConeAngle[leaf] + 1e-5) << "face " << a;
  }
  // the QEF vertex of the corner cell is the corner (three planes meet there)
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(o[a] + v.Vertex[3 * leaf + a], 1.0, 1e-5);
  const double face[3] = { 0.5 + 1e-3, 0.5 + 1e-3, 1.0 };
  const vtkIdType flat = b.Octree->FindNode(face, v.FinestLevel);
  ASSERT_GE(flat, 0);
  EXPECT_LT(v.ConeAngle[flat], 1e-5f);
  EXPECT_TRUE(v.Flags[flat] & plod::NodeTopologySafe);
}

TEST(MultiscaleOctreeBuilder, TinyMeshesGetALevelThatSeparatesTheirCorners)
{
  // a tetrahedron, one triangle and a 12-triangle cube: never the root alone (level 0 would
  // still draw them through an opened leaf, but a level that separates the corners lets the
  // selector choose); the full surface is the input
  for (auto mesh : { plodtest::MakeTetrahedron(),
         plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0 }, { 0, 1, 2 }), plodtest::MakeCube(0, 1) })
  {
    Built b = Build(mesh);
    CheckOctree(b, "tiny");
    CheckSurfaceIsTheInput(b, mesh, "tiny");
    EXPECT_GE(b.View.FinestLevel, 1);
    std::set<int32_t> leaves(b.View.PointLeaf, b.View.PointLeaf + b.View.NumberOfPoints);
    EXPECT_EQ(leaves.size(), size_t(b.View.NumberOfPoints)) << "every corner in its own leaf";
  }
}

TEST(MultiscaleOctreeBuilder, RoofShapeErrorIsItsHeight)
{
  // a roof of two planes meeting at a ridge of height 0.25 over [0,1]^2 (z = 0.25 - |x - .5|/2):
  // the root's axis is vertical by symmetry, so its shape error is the roof's height
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  const int n = 8;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
    {
      const double x = double(i) / n, y = double(j) / n;
      xyz.insert(xyz.end(), { x, y, 0.25 - 0.5 * std::abs(x - 0.5) });
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      const vtkIdType a = i * (n + 1) + j, b = (i + 1) * (n + 1) + j;
      tri.insert(tri.end(), { a, b, b + 1, a, b + 1, a + 1 });
    }
  auto roof = plodtest::MakeMesh(xyz, tri);
  Built b = Build(roof);
  CheckOctree(b, "roof");
  const plod::OctreeView& v = b.View;
  EXPECT_NEAR(v.ConeAxis[2], 1.0, 1e-9) << "equal areas on both slopes";
  EXPECT_NEAR(v.ShapeError[0], 0.25, 1e-6);
  // eq. (2) holds the slopes' normals (0.46 rad from vertical), loosely above the leaves
  EXPECT_GE(v.ConeAngle[0], std::atan(0.5) - 1e-6);
  EXPECT_LE(v.ConeAngle[0], Pi / 2);
  // a leaf on one slope only is flat; a leaf across the ridge is exactly the two slopes' cone
  const double* o = b.Octree->GetOrigin();
  int flat = 0, ridge = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (!v.IsLeaf(n))
      continue;
    double lo[3], h;
    plodcheck::NodeBox(v, n, lo, h);
    if (o[0] + lo[0] > 0.5 + 0.26 * h || o[0] + lo[0] + h < 0.5 - 0.26 * h)
    {
      EXPECT_LT(v.ConeAngle[n], 1e-5) << n;
      ++flat;
    }
    else if (v.FirstPoint[n] + 1 < v.PointEnd(n))
    {
      // the area-weighted axis leans to the larger slope: at most both slopes' angle apart
      EXPECT_LE(v.ConeAngle[n], 2 * std::atan(0.5) + 1e-5) << n;
      ++ridge;
    }
  }
  EXPECT_GT(flat, 10);
  EXPECT_GT(ridge, 0);
}

TEST(MultiscaleOctreeBuilder, QEFRuleKeepsVerticesOnEdgesWhereTheMeanRuleDoesNot)
{
  // cells along an edge of a subdivided cube: the QEF vertex lies on the edge line (two planes
  // meet there); the mean of the points inside lies off it, inside the cube
  auto cube = plodtest::MakeDeformedBox(16, 16, 16, [](const double p[3], double x[3]) {
    for (int a = 0; a < 3; ++a)
      x[a] = p[a];
  });
  Built q = Build(cube, 3, vtkMultiscaleOctreeBuilder::VERTEX_QEF);
  Built m = Build(cube, 3, vtkMultiscaleOctreeBuilder::VERTEX_MEAN);
  CheckOctree(q, "qef");
  CheckOctree(m, "mean");
  const double* o = q.Octree->GetOrigin();
  int onEdge = 0, meanOff = 0, cells = 0;
  for (int64_t n = 0; n < q.View.NumberOfNodes; ++n)
  {
    if (q.View.Level[n] != 3)
      continue;
    double lo[3], h;
    plodcheck::NodeBox(q.View, n, lo, h);
    // the edge x = 1, y = 1 passes through the cell, no corner in it
    if (!(o[0] + lo[0] < 1 && o[0] + lo[0] + h > 1 && o[1] + lo[1] < 1 && o[1] + lo[1] + h > 1 &&
          o[2] + lo[2] > 0.01 && o[2] + lo[2] + h < 0.99))
      continue;
    ++cells;
    onEdge += std::abs(o[0] + q.View.Vertex[3 * n] - 1) < 1e-5 &&
      std::abs(o[1] + q.View.Vertex[3 * n + 1] - 1) < 1e-5;
    meanOff += std::abs(o[0] + m.View.Vertex[3 * n] - 1) > 1e-3;
  }
  ASSERT_GT(cells, 0);
  EXPECT_EQ(onEdge, cells);
  EXPECT_EQ(meanOff, cells);
}

TEST(MultiscaleOctreeBuilder, InvariantsOverRandomClosedBlobs)
{
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    auto blob = plodtest::MakeBlob(seed, 18 + 4 * seed, 0.3);
    for (int level : { -1, 3 })
    {
      Built b = Build(blob, level);
      CheckOctree(b, "blob " + std::to_string(seed));
      CheckSurfaceIsTheInput(b, blob, "blob");
      EXPECT_EQ(b.Octree->GetNumberOfBoundaryEdges(), 0);
      EXPECT_EQ(b.Octree->GetNumberOfNonManifoldEdges(), 0);
    }
  }
}

TEST(MultiscaleOctreeBuilder, InvariantsOverRandomSoups)
{
  for (unsigned seed = 1; seed <= 3; ++seed)
  {
    auto soup = plodtest::MakeSoup(seed, 60, 0.3);
    Built b = Build(soup);
    CheckOctree(b, "soup " + std::to_string(seed));
    CheckSurfaceIsTheInput(b, soup, "soup");
    EXPECT_EQ(b.Octree->GetNumberOfBoundaryEdges(), 3 * 60) << "every edge of a soup is open";
  }
}

TEST(MultiscaleOctreeBuilder, ThinPartsKeepEverySheet)
{
  // walls 0.1 to 1.5 finest cells thick: the octree keeps every input triangle, and each cell
  // holding both sheets of a wall is a union of two discs (safe), while a thin ring's tube cells
  // are annuli (unsafe) until the cells are finer than the tube
  const int level = 5;
  const double cell = 2.2 / 32; // about the finest cell edge of these 2-unit models at level 5
  for (double f : { 0.1, 0.4, 0.8, 1.5 })
  {
    for (auto model : { plodtest::MakeThinBox(f * cell, 10), plodtest::MakeThinDisc(f * cell, 10),
           plodtest::MakeFoldedSheet(f * cell, 0.6 * cell, 10) })
    {
      Built b = Build(model, level);
      CheckOctree(b, "thin " + std::to_string(f), false);
      CheckSurfaceIsTheInput(b, model, "thin");
      EXPECT_EQ(b.Octree->GetNumberOfBoundaryEdges(), 0);
    }
  }
  // a tilted ring: flat, it would lie on the root's mid-plane, and every cell would hold half
  // the tube (a strip, which collapses into a ribbon, not into nothing: rightly safe)
  auto ring = plodtest::MakeRing(1.0, 0.01, 200, 8);
  {
    vtkPoints* pts = ring->GetPoints();
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
    {
      double x[3];
      pts->GetPoint(i, x);
      const double y = x[1] * std::cos(0.5) - x[2] * std::sin(0.5);
      x[2] = x[1] * std::sin(0.5) + x[2] * std::cos(0.5);
      x[1] = y;
      pts->SetPoint(i, x);
    }
  }
  Built b = Build(ring, 5);
  CheckOctree(b, "ring", false);
  int64_t unsafe = 0, leaves = 0;
  for (int64_t n = 0; n < b.View.NumberOfNodes; ++n)
  {
    leaves += b.View.IsLeaf(n);
    unsafe += b.View.IsLeaf(n) && !(b.View.Flags[n] & plod::NodeTopologySafe);
  }
  EXPECT_GT(unsafe, leaves / 5) << "leaves holding whole tube sections are annuli";
}

TEST(MultiscaleOctreeBuilder, TopologyFlagsMatchTheEulerCharacteristic)
{
  // brute force (BFS components, V - E + F) on models with tubes, folds and thin walls
  for (auto model : { plodtest::MakeRing(1.0, 0.05, 60, 8),
         plodtest::MakeFoldedSheet(0.02, 0.03, 10), plodtest::MakeBlob(3, 20, 0.3) })
  {
    for (int level : { 3, 5 })
    {
      Built b = Build(model, level);
      CheckOctree(b, "topology", true);
    }
  }
}

TEST(MultiscaleOctreeBuilder, ResultDoesNotDependOnThreads)
{
  auto blob = plodtest::MakeBlob(7, 120, 0.3);
  vtkNew<vtkMultiscaleOctreeBuilder> serial, threaded;
  serial->SetInputData(blob);
  serial->MultiThreadedOff();
  serial->Update();
  threaded->SetInputData(blob);
  threaded->Update();
  vtkMultiscaleOctree* a = serial->GetOutput();
  vtkMultiscaleOctree* c = threaded->GetOutput();
  ASSERT_EQ(a->GetNumberOfNodes(), c->GetNumberOfNodes());
  for (vtkFieldData* fa : { a->GetNodeData(), a->GetSurfaceData() })
  {
    vtkFieldData* fc = fa == a->GetNodeData() ? c->GetNodeData() : c->GetSurfaceData();
    for (int i = 0; i < fa->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* x = fa->GetArray(i);
      vtkDataArray* y = fc->GetArray(x->GetName());
      ASSERT_TRUE(y) << x->GetName();
      ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues());
      for (vtkIdType k = 0; k < x->GetNumberOfValues(); ++k)
        ASSERT_EQ(x->GetVariantValue(k), y->GetVariantValue(k)) << x->GetName() << " " << k;
    }
  }
}

TEST(MultiscaleOctreeBuilder, ReExecutesOnlyOnChange)
{
  auto blob = plodtest::MakeBlob(2, 30, 0.2);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  builder->Update();
  const vtkMTimeType t = builder->GetOutput()->GetMTime();
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetMTime(), t);
  builder->SetFinestLevel(builder->GetFinestLevel()); // same value: no Modified()
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetMTime(), t);
  builder->SetVertexRuleToMean();
  builder->Update();
  EXPECT_GT(builder->GetOutput()->GetMTime(), t);
}

TEST(MultiscaleOctreeBuilder, ShallowAndDeepCopy)
{
  Built b = Build(plodtest::MakeBlob(3, 30, 0.2));
  vtkNew<vtkMultiscaleOctree> shallow, deep;
  shallow->ShallowCopy(b.Octree);
  deep->DeepCopy(b.Octree);
  for (vtkMultiscaleOctree* o : { shallow.Get(), deep.Get() })
  {
    EXPECT_EQ(o->GetNumberOfNodes(), b.Octree->GetNumberOfNodes());
    EXPECT_EQ(o->GetNumberOfSurfacePoints(), b.Octree->GetNumberOfSurfacePoints());
    EXPECT_EQ(o->GetNumberOfSurfaceTriangles(), b.Octree->GetNumberOfSurfaceTriangles());
    EXPECT_EQ(o->GetFinestLevel(), b.Octree->GetFinestLevel());
    EXPECT_EQ(o->GetNumberOfBoundaryEdges(), 0);
    EXPECT_TRUE(o->IsConsistent());
  }
  EXPECT_EQ(
    shallow->GetNodeData()->GetArray("Vertex"), b.Octree->GetNodeData()->GetArray("Vertex"));
  EXPECT_EQ(shallow->GetSurfaceData()->GetArray("Triangles"),
    b.Octree->GetSurfaceData()->GetArray("Triangles"));
  EXPECT_NE(deep->GetSurfaceData()->GetArray("Triangles"),
    b.Octree->GetSurfaceData()->GetArray("Triangles"));
  EXPECT_GT(b.Octree->GetActualMemorySize(), 0u);
}

TEST(MultiscaleOctreeBuilder, NavigationFindsNodesAndChildren)
{
  Built b = Build(plodtest::MakeBlob(4, 40, 0.2));
  vtkMultiscaleOctree* o = b.Octree;
  const plod::OctreeView& v = b.View;
  for (int64_t n = 1; n < v.NumberOfNodes; n += 7)
  {
    const vtkIdType p = o->GetParent(n);
    int found = 0;
    for (int c = 0; c < 8; ++c)
      found += o->GetChild(p, c) == n;
    EXPECT_EQ(found, 1);
    double bounds[6], x[3];
    o->GetNodeBounds(n, bounds);
    for (int a = 0; a < 3; ++a)
      x[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    EXPECT_EQ(o->FindNode(x, o->GetNodeLevel(n)), n);
  }
  EXPECT_EQ(o->GetChild(0, 9), -1);
  EXPECT_EQ(o->GetParent(-3), -1);
  const double outside[3] = { 1e9, 0, 0 };
  EXPECT_EQ(o->FindNode(outside, 2), -1);
}

TEST(MultiscaleOctreeBuilder, EmptyInputGivesEmptyOctree)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(empty);
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0);
  EXPECT_TRUE(builder->GetOutput()->IsConsistent());
}

TEST(MultiscaleOctreeBuilder, BadTrianglesAreSkippedWithAWarning)
{
  // a blob plus triangles that repeat a point, refer to missing points, or touch a NaN point:
  // they are skipped and counted, with a warning; the rest builds and is kept whole
  auto blob = plodtest::MakeBlob(5, 20, 0.2);
  vtkNew<vtkPolyData> bad;
  bad->DeepCopy(blob);
  const vtkIdType nan = bad->GetPoints()->InsertNextPoint(std::nan(""), 0, 0);
  const vtkIdType extra[4][3] = { { 0, 0, 1 }, { 0, 1, 999999 }, { 0, 1, -2 }, { 0, 1, nan } };
  for (auto& t : extra)
    bad->GetPolys()->InsertNextCell(3, t);
  vtkNew<plodtest::ErrorRecorder> errors;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(bad);
  builder->AddObserver(vtkCommand::WarningEvent, errors);
  builder->AddObserver(vtkCommand::ErrorEvent, errors);
  builder->Update();
  EXPECT_TRUE(errors->Errors.empty());
  ASSERT_EQ(errors->Warnings.size(), 2u);
  EXPECT_NE(errors->Warnings[0].find("3 triangle(s) skipped"), std::string::npos)
    << errors->Warnings[0];
  EXPECT_NE(errors->Warnings[1].find("1 triangle(s) skipped: the same point"), std::string::npos)
    << errors->Warnings[1];
  EXPECT_EQ(builder->GetNumberOfInvalidTriangles(), 3);
  EXPECT_EQ(builder->GetNumberOfDegenerateTriangles(), 1);
  EXPECT_EQ(builder->GetOutput()->GetNumberOfSurfaceTriangles(), blob->GetNumberOfPolys());
  Built b{ builder->GetOutput(), {} };
  b.Octree->GetView(b.View);
  CheckOctree(b, "bad triangles", false);
  // nothing usable: an error that says why, and an empty octree
  auto useless = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0 }, { 0, 0, 1, 0, 1, 5 });
  vtkNew<plodtest::ErrorRecorder> e2;
  Built u = Build(useless, -1, vtkMultiscaleOctreeBuilder::VERTEX_QEF, e2);
  EXPECT_EQ(u.Octree->GetNumberOfNodes(), 0);
  EXPECT_TRUE(e2->HasError("no usable triangle among 2"));
}

TEST(MultiscaleOctreeBuilder, ZeroAreaAndDuplicateTrianglesAreKept)
{
  // zero-area triangles with three different points keep their connectivity (they draw
  // nothing); duplicated triangles are kept as given
  auto mesh =
    plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0 }, { 0, 1, 2, 0, 1, 3, 0, 1, 3 });
  Built b = Build(mesh);
  CheckOctree(b, "zero area", false);
  EXPECT_EQ(b.View.NumberOfTriangles, 3);
}

TEST(MultiscaleOctreeBuilder, InvalidParametersAreErrors)
{
  auto blob = plodtest::MakeBlob(6, 16, 0.2);
  for (int level : { -2, 22 })
  {
    vtkNew<plodtest::ErrorRecorder> errors;
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(blob);
    builder->SetFinestLevel(level);
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->Update();
    EXPECT_TRUE(errors->HasError("FinestLevel")) << level;
    EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0);
  }
  for (double limit : { -1.0, std::nan("") })
  {
    vtkNew<plodtest::ErrorRecorder> errors;
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(blob);
    builder->SetMemoryLimit(limit);
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->Update();
    EXPECT_TRUE(errors->HasError("MemoryLimit")) << limit;
  }
}

TEST(MultiscaleOctreeBuilder, ArraysOfTheWrongLengthAreErrorsNamingTheArray)
{
  auto blob = plodtest::MakeBlob(8, 16, 0.2);
  const vtkIdType np = blob->GetNumberOfPoints();
  auto shortArray = [](const char* name, vtkIdType n, int comps) {
    auto a = vtkSmartPointer<vtkFloatArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(comps);
    a->SetNumberOfTuples(n);
    a->Fill(0.5);
    return a;
  };
  struct Case
  {
    const char* What;
    std::function<void(vtkPolyData*, vtkMultiscaleOctreeBuilder*)> Setup;
    const char* Message;
  };
  const Case cases[] = {
    { "normals",
      [&](vtkPolyData* pd, vtkMultiscaleOctreeBuilder*) {
        pd->GetPointData()->SetNormals(shortArray("N", np - 1, 3));
      },
      "Normals array 'N'" },
    { "point material",
      [&](vtkPolyData* pd, vtkMultiscaleOctreeBuilder* b) {
        pd->GetPointData()->AddArray(shortArray("Kd", np / 2, 1));
        b->SetDiffuseArrayName("Kd");
      },
      "Point material array 'Kd'" },
    { "cell material",
      [&](vtkPolyData* pd, vtkMultiscaleOctreeBuilder* b) {
        pd->GetCellData()->AddArray(shortArray("Ks", pd->GetNumberOfCells() - 3, 1));
        b->SetSpecularArrayName("Ks");
      },
      "Cell material array 'Ks'" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkPolyData> pd;
    pd->DeepCopy(blob);
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    c.Setup(pd, builder);
    builder->SetInputData(pd);
    vtkNew<plodtest::ErrorRecorder> errors;
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->Update();
    EXPECT_TRUE(errors->HasError(c.Message)) << c.What;
    EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0) << c.What;
  }
  // a cloud's viewpoint array too short
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(blob->GetPoints());
  auto vp = vtkSmartPointer<vtkDoubleArray>::New();
  vp->SetName("Scanner");
  vp->SetNumberOfComponents(3);
  vp->SetNumberOfTuples(3);
  cloud->GetPointData()->AddArray(vp);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(cloud);
  builder->SetViewpointArrayName("Scanner");
  vtkNew<plodtest::ErrorRecorder> errors;
  builder->AddObserver(vtkCommand::ErrorEvent, errors);
  builder->Update();
  EXPECT_TRUE(errors->HasError("Viewpoint array 'Scanner'"));
  EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0);
}

TEST(MultiscaleOctreeBuilder, OppositeNormalsGiveConeOfPi)
{
  // two coincident triangles of opposite orientation: their normals cancel
  auto mesh = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0 }, { 0, 1, 2, 0, 2, 1 });
  Built b = Build(mesh, 2);
  CheckOctree(b, "opposite", false);
  for (int64_t n = 0; n < b.View.NumberOfNodes; ++n)
    EXPECT_NEAR(b.View.ConeAngle[n], Pi, 1e-6) << n;
}

TEST(MultiscaleOctreeBuilder, MultiClusterConeAxisIsTheAreaWeightedMeanNormal)
{
  // two separate pieces in the root cell (two clusters): a unit square facing +z (area 1) and a
  // triangle facing +x (area 0.25). The root's axis is the area-weighted mean normal of both,
  // (0.25, 0, 1) normalised; their plain mean (1, 0, 1) / sqrt 2 or one piece's normal is wrong.
  auto mesh =
    plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0, 2, 0, 0.5 },
      { 0, 1, 2, 0, 2, 3, 4, 5, 6 });
  Built b = Build(mesh, 2);
  CheckOctree(b, "two pieces", false);
  const plod::OctreeView& v = b.View;
  ASSERT_EQ(v.ClusterEnd(0) - v.FirstCluster[0], 2) << "one cluster per piece";
  const double len = std::sqrt(0.25 * 0.25 + 1.0);
  EXPECT_NEAR(v.ConeAxis[0], 0.25 / len, 1e-5);
  EXPECT_NEAR(v.ConeAxis[1], 0.0, 1e-5);
  EXPECT_NEAR(v.ConeAxis[2], 1.0 / len, 1e-5);
}

TEST(MultiscaleOctreeBuilder, FlatTubeThicknessReadsTheMiddleEigenvalue)
{
  // An open tube along x of elliptic cross-section, semi-axes a = 0.06 (y) and b = 0.02 (z),
  // 16 points per ring: a cell holding whole rings is an annulus (not safe). Its points'
  // covariance has y variance a^2 / 2 (the middle eigenvalue: the x extent is larger, the z one
  // smaller), so its thickness is 2 sqrt(2 a^2 / 2) = 2a = 0.12; the smallest eigenvalue would
  // give 2b = 0.04, the largest the length of tube in the cell.
  const double a = 0.06, c = 0.02;
  const int nu = 33, nv = 16;
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      const double t = 2 * Pi * j / nv;
      // rings at x = 0.03 + 0.029 i: none on a cell boundary (multiples of 0.25)
      xyz.insert(xyz.end(), { 0.03 + 0.029 * i, 0.375 + a * std::cos(t), 0.375 + c * std::sin(t) });
    }
  for (int i = 0; i + 1 < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      const vtkIdType p = i * nv + j, q = i * nv + (j + 1) % nv;
      tri.insert(tri.end(), { p, p + nv, q + nv, p, q + nv, q });
    }
  auto tube = plodtest::MakeMesh(xyz, tri);
  // root cube [0, 1]^3, level 2 (cells of 0.25): the tube (y in [0.315, 0.435], z in [0.355,
  // 0.395]) lies in one row of level-2 cells, each holding whole rings
  const double origin[3] = { 0, 0, 0 };
  Built b = plodcheck::BuildInCube(tube, origin, 1.0, 2);
  CheckOctree(b, "flat tube");
  const plod::OctreeView& v = b.View;
  int checked = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.Flags[n] & plod::NodeTopologySafe)
      continue;
    // 2 sqrt(2 l2), l2 the middle eigenvalue of the covariance of the cell's points
    const int64_t p0 = v.FirstPoint[n], p1 = v.PointEnd(n);
    ASSERT_GE(p1 - p0, 3) << n;
    double mean[3] = { 0, 0, 0 }, cov[3][3] = { { 0 } };
    for (int64_t p = p0; p < p1; ++p)
      for (int r = 0; r < 3; ++r)
        mean[r] += v.Points[3 * p + r] / double(p1 - p0);
    for (int64_t p = p0; p < p1; ++p)
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s)
          cov[r][s] +=
            (v.Points[3 * p + r] - mean[r]) * (v.Points[3 * p + s] - mean[s]) / double(p1 - p0);
    double* rows[3] = { cov[0], cov[1], cov[2] };
    double w[3], e0[3], e1[3], e2[3];
    double* vectors[3] = { e0, e1, e2 };
    vtkMath::Jacobi(rows, w, vectors); // w in decreasing order
    const double expected = 2 * std::sqrt(2 * w[1]);
    EXPECT_NEAR(v.Thickness[n], expected, 1e-4 * expected) << "node " << n;
    if (v.Level[n] == 2)
    {
      EXPECT_NEAR(v.Thickness[n], 2 * a, 1e-5) << "node " << n;
      EXPECT_NEAR(2 * std::sqrt(2 * w[2]), 2 * c, 1e-5) << "the smallest eigenvalue is z's";
      EXPECT_GT(2 * std::sqrt(2 * w[0]), 1.25 * 2 * a) << "the largest eigenvalue is x's";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 4) << "the four level-2 cells along the tube are annuli";
}

TEST(MultiscaleOctreeBuilder, TinyAndFarModelsKeepTheirPrecision)
{
  // a blob of size 1e-6 at 1e6 from the origin, and one of size 1e6: the surface keeps each
  // point within 1e-6 of the model size, and every invariant holds
  for (auto [scale, offset] :
    { std::pair<double, double>{ 1e-6, 1e6 }, { 1e6, 0.0 }, { 1e-20, 0.0 }, { 1e20, 1e21 } })
  {
    const double centre[3] = { offset, -offset, offset };
    auto blob = plodtest::MakeBlob(9, 20, 0.3, scale, centre);
    Built b = Build(blob);
    CheckOctree(b, "scale " + std::to_string(scale), false);
    CheckSurfaceIsTheInput(b, blob, "scaled");
  }
  // beyond what single precision can hold: an error that says so
  for (double scale : { 1e-300, 1e300 })
  {
    auto blob = plodtest::MakeBlob(9, 12, 0.3, scale);
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = Build(blob, -1, vtkMultiscaleOctreeBuilder::VERTEX_QEF, errors);
    EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0) << scale;
    EXPECT_TRUE(errors->HasError("single-precision")) << scale;
  }
}

TEST(MultiscaleOctreeBuilder, FinestLevelZeroAndMaximum)
{
  auto blob = plodtest::MakeBlob(10, 12, 0.2);
  Built root = Build(blob, 0);
  CheckOctree(root, "level 0");
  EXPECT_EQ(root.View.NumberOfNodes, 1);
  EXPECT_EQ(root.View.NumberOfTriangles, blob->GetNumberOfPolys()) << "all owned by the root";
  Built deep = Build(blob, 21);
  CheckOctree(deep, "level 21", false);
  EXPECT_EQ(deep.View.FinestLevel, 21);
}

TEST(MultiscaleOctreeBuilder, DefaultLevelFollowsTheInputDetail)
{
  // finer meshes of the same shape get deeper levels; leaves hold about four points on average
  int previous = 0;
  for (int res : { 16, 32, 64, 128 })
  {
    auto blob = plodtest::MakeBlob(11, res, 0.2);
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(blob);
    builder->Update();
    plod::OctreeView v;
    ASSERT_TRUE(builder->GetOutput()->GetView(v));
    EXPECT_GT(v.FinestLevel, previous) << res;
    previous = v.FinestLevel;
    std::set<int32_t> leaves(v.PointLeaf, v.PointLeaf + v.NumberOfPoints);
    EXPECT_GE(4 * leaves.size(), size_t(v.NumberOfPoints));
    EXPECT_LT(leaves.size(), size_t(v.NumberOfPoints));
    EXPECT_NE(std::string(builder->GetFinestLevelReason()).find("a quarter of the distinct"),
      std::string::npos);
  }
  // duplicated points (an unwelded mesh) do not drive the level to 21
  vtkNew<vtkPolyData> soup;
  soup->DeepCopy(plodtest::Unweld(plodtest::MakeBlob(11, 30, 0.2)));
  Built s = Build(soup);
  EXPECT_LE(s.View.FinestLevel, 8);
}

TEST(MultiscaleOctreeBuilder, MemoryLimitLowersTheLevelWithAWarningOrRefuses)
{
  auto blob = plodtest::MakeBlob(12, 200, 0.2);
  vtkNew<vtkMultiscaleOctreeBuilder> free;
  free->SetInputData(blob);
  free->Update();
  const int wanted = free->GetOutput()->GetFinestLevel();
  // a limit a little below what the chosen level needs: a coarser level, and a warning naming it
  const double need = plod::EstimateBuildMemory(blob->GetNumberOfPoints(), blob->GetNumberOfPolys(),
    free->GetOutput()->GetNumberOfNodes(), false);
  vtkNew<plodtest::ErrorRecorder> errors;
  vtkNew<vtkMultiscaleOctreeBuilder> tight;
  tight->SetInputData(blob);
  tight->SetMemoryLimit(0.95 * need / (1024.0 * 1024.0));
  tight->AddObserver(vtkCommand::WarningEvent, errors);
  tight->Update();
  const int got = tight->GetOutput()->GetFinestLevel();
  EXPECT_LT(got, wanted);
  EXPECT_GT(tight->GetOutput()->GetNumberOfNodes(), 0);
  ASSERT_FALSE(errors->Warnings.empty());
  EXPECT_NE(errors->Warnings[0].find(
              "finest level " + std::to_string(got) + ": lowered from " + std::to_string(wanted)),
    std::string::npos)
    << errors->Warnings[0];
  // far too small: refused with a clear error, empty octree
  vtkNew<plodtest::ErrorRecorder> e2;
  vtkNew<vtkMultiscaleOctreeBuilder> none;
  none->SetInputData(blob);
  none->SetMemoryLimit(0.01);
  none->AddObserver(vtkCommand::ErrorEvent, e2);
  none->Update();
  EXPECT_EQ(none->GetOutput()->GetNumberOfNodes(), 0);
  EXPECT_TRUE(e2->HasError("raise the limit"));
  // automatic: three quarters of the physical memory (it once fell back to 4 GiB everywhere
  // because the system query was never run)
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  while (meminfo >> key && key != "MemTotal:")
  {
    meminfo.ignore(1 << 10, '\n');
  }
  if (key == "MemTotal:" && (meminfo >> kib) && kib > 0)
  {
    EXPECT_NEAR(free->GetEffectiveMemoryLimit(), 0.75 * kib / 1024.0, 0.01 * kib / 1024.0);
  }
  else
  {
    EXPECT_GT(free->GetEffectiveMemoryLimit(), 100.0);
  }
}

TEST(MultiscaleOctreeBuilder, QuadsStripsAndFloatInputAreRead)
{
  // a quad and a strip, with float points and 32-bit connectivity: the surface holds their
  // fan and strip triangles, oriented as the input
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  const double xyz[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 2, 0, 0.5 },
    { 2, 1, 0.5 }, { 3, 0, 1 }, { 3, 1, 1 } };
  for (auto& x : xyz)
    pts->InsertNextPoint(x);
  pd->SetPoints(pts);
  vtkNew<vtkCellArray> polys;
  polys->Use32BitStorage();
  const vtkIdType quad[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, quad);
  pd->SetPolys(polys);
  vtkNew<vtkCellArray> strips;
  const vtkIdType strip[4] = { 4, 6, 5, 7 };
  strips->InsertNextCell(4, strip);
  pd->SetStrips(strips);
  Built b = Build(pd);
  CheckOctree(b, "quads and strips", false);
  std::multiset<std::array<int64_t, 3>> expected = { plodcheck::Canonical(0, 1, 2),
    plodcheck::Canonical(0, 2, 3), plodcheck::Canonical(4, 6, 5), plodcheck::Canonical(5, 6, 7) };
  EXPECT_EQ(SurfaceTriangles(b.View), expected);
  // triangles only, 32-bit: read in place
  auto blob = plodtest::MakeBlob(13, 20, 0.2);
  vtkNew<vtkPolyData> p32;
  p32->DeepCopy(blob);
  vtkNew<vtkCellArray> c32;
  c32->Use32BitStorage();
  c32->DeepCopy(blob->GetPolys());
  c32->ConvertTo32BitStorage();
  p32->SetPolys(c32);
  Built b32 = Build(p32);
  CheckSurfaceIsTheInput(b32, blob, "32-bit");
}

TEST(MultiscaleOctreeBuilder, InputNormalsAreTheShadingNormals)
{
  // given point normals are kept; without them, they are vtkPolyDataNormals' (no splitting)
  auto blob = plodtest::MakeBlob(14, 24, 0.3);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(blob);
  normals->SplittingOff();
  normals->ComputeCellNormalsOff();
  normals->Update();
  vtkPolyData* withNormals = normals->GetOutput();
  Built computed = Build(blob);
  Built given = Build(withNormals);
  vtkDataArray* ref = withNormals->GetPointData()->GetNormals();
  for (const Built* b : { &computed, &given })
    for (int64_t p = 0; p < b->View.NumberOfPoints; ++p)
    {
      double r[3];
      ref->GetTuple(b->View.InputPointId[p], r);
      const auto n = Get3(&b->View.Normals[3 * p]);
      ASSERT_LT(Angle(n.data(), r), 1e-5) << p;
    }
}

TEST(MultiscaleOctreeBuilder, MaterialFromArrays)
{
  // point data: each cell's range is the min/max over its points (and over the corners of the
  // triangles that cross it); cell data: over its triangles
  auto blob = plodtest::MakeBlob(15, 24, 0.2);
  vtkNew<vtkFloatArray> kd;
  kd->SetName("Kd");
  for (vtkIdType i = 0; i < blob->GetNumberOfPoints(); ++i)
    kd->InsertNextValue(0.1f + 0.8f * float(i % 7) / 6.0f);
  blob->GetPointData()->AddArray(kd);
  vtkNew<vtkFloatArray> ks;
  ks->SetName("Ks");
  for (vtkIdType i = 0; i < blob->GetNumberOfCells(); ++i)
    ks->InsertNextValue(float(i % 3) / 2.0f);
  blob->GetCellData()->AddArray(ks);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  builder->SetDiffuseArrayName("Kd");
  builder->SetSpecularArrayName("Ks");
  builder->Update();
  vtkMultiscaleOctree* o = builder->GetOutput();
  EXPECT_TRUE(o->GetHasMaterialArrays());
  plod::OctreeView v;
  ASSERT_TRUE(o->GetView(v));
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    float lo = 2, hi = -1;
    for (int64_t p = v.FirstPoint[n]; p < v.PointEnd(n); ++p)
    {
      lo = std::min(lo, kd->GetValue(v.InputPointId[p]));
      hi = std::max(hi, kd->GetValue(v.InputPointId[p]));
    }
    EXPECT_LE(v.DiffuseRange[2 * n], lo) << n;
    EXPECT_GE(v.DiffuseRange[2 * n + 1], hi) << n;
    EXPECT_GE(v.DiffuseRange[2 * n], 0.1f - 1e-6f);
    EXPECT_LE(v.DiffuseRange[2 * n + 1], 0.9f + 1e-6f);
  }
  EXPECT_FLOAT_EQ(v.SpecularRange[0], 0.0f);
  EXPECT_FLOAT_EQ(v.SpecularRange[1], 1.0f);

  // the other way round: diffuse per triangle, specular per point; the root spans each array's
  // whole range, and no cell reaches outside it
  auto blob2 = plodtest::MakeBlob(16, 24, 0.2);
  vtkNew<vtkFloatArray> kdCells;
  kdCells->SetName("Kd");
  for (vtkIdType i = 0; i < blob2->GetNumberOfCells(); ++i)
    kdCells->InsertNextValue(0.25f + 0.5f * float(i % 5) / 4.0f);
  blob2->GetCellData()->AddArray(kdCells);
  vtkNew<vtkFloatArray> ksPoints;
  ksPoints->SetName("Ks");
  for (vtkIdType i = 0; i < blob2->GetNumberOfPoints(); ++i)
    ksPoints->InsertNextValue(0.1f + 0.3f * float(i % 4) / 3.0f);
  blob2->GetPointData()->AddArray(ksPoints);
  builder->SetInputData(blob2);
  builder->Update();
  ASSERT_TRUE(builder->GetOutput()->GetView(v));
  EXPECT_FLOAT_EQ(v.DiffuseRange[0], 0.25f);
  EXPECT_FLOAT_EQ(v.DiffuseRange[1], 0.75f);
  EXPECT_FLOAT_EQ(v.SpecularRange[0], 0.1f);
  EXPECT_FLOAT_EQ(v.SpecularRange[1], 0.4f);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    EXPECT_LE(v.DiffuseRange[2 * n], v.DiffuseRange[2 * n + 1]) << n;
    EXPECT_GE(v.DiffuseRange[2 * n], 0.25f - 1e-6f) << n;
    EXPECT_LE(v.DiffuseRange[2 * n + 1], 0.75f + 1e-6f) << n;
    EXPECT_GE(v.SpecularRange[2 * n], 0.1f - 1e-6f) << n;
    EXPECT_LE(v.SpecularRange[2 * n + 1], 0.4f + 1e-6f) << n;
  }
}

TEST(MultiscaleOctreeBuilder, DenseCloudNormalsFromSampledNeighbours)
{
  // a dense tilted plane at a coarse level set by the user: thousands of points per cell, so
  // each PCA normal is fitted to the sampled candidates (at most 512 a point, at a stride).
  // The contoured surface's normals must still be the plane's.
  const double normal[3] = { 0.3, -0.4, std::sqrt(1 - 0.09 - 0.16) };
  const double u[3] = { 0.8, 0.6, 0.0 }; // orthogonal to the normal
  double w[3];
  vtkMath::Cross(normal, u, w);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> U(-1, 1);
  vtkNew<vtkPoints> pts;
  for (int i = 0; i < 60000; ++i)
  {
    const double a = U(rng), b = U(rng);
    pts->InsertNextPoint(a * u[0] + b * w[0], a * u[1] + b * w[1], a * u[2] + b * w[2]);
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(pts);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(cloud);
  builder->SetViewpoint(normal[0] * 10, normal[1] * 10, normal[2] * 10); // the scanner above
  builder->UseViewpointOn();
  builder->SetFinestLevel(4);
  builder->Update();
  Built b{ builder->GetOutput(), {} };
  ASSERT_TRUE(b.Octree->GetView(b.View));
  ASSERT_GT(b.View.NumberOfPoints, 20);
  int64_t facing = 0;
  for (int64_t p = 0; p < b.View.NumberOfPoints; ++p)
  {
    const float* n = &b.View.Normals[3 * p];
    const double d = n[0] * normal[0] + n[1] * normal[1] + n[2] * normal[2];
    facing += d > 0.98 ? 1 : 0;
  }
  // the sheet's rim cells average in few points: nearly all normals are the plane's, towards
  // the scanner
  EXPECT_GT(facing, 0.9 * b.View.NumberOfPoints) << facing << " of " << b.View.NumberOfPoints;
}

TEST(MultiscaleOctreeBuilder, PointCloudBecomesAClosedOrientedSurface)
{
  // points of a sphere without normals: oriented away from the centroid, contoured into a
  // closed surface whose triangles face outwards; towards an inner viewpoint, inwards
  auto sphere = plodtest::MakeBlob(1, 120, 0.0);
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(sphere->GetPoints());
  for (bool inward : { false, true })
  {
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(cloud);
    if (inward)
    {
      builder->SetViewpoint(0, 0, 0);
      builder->UseViewpointOn();
    }
    builder->Update();
    Built b{ builder->GetOutput(), {} };
    ASSERT_TRUE(b.Octree->GetView(b.View));
    EXPECT_GE(b.View.FinestLevel, 3);
    CheckOctree(b, "cloud", false);
    // the signed distance is known only near the points: a few quads can miss (a gap of a cell)
    EXPECT_LT(b.Octree->GetNumberOfBoundaryEdges(), b.View.NumberOfTriangles / 100);
    EXPECT_GT(b.View.NumberOfTriangles, 1000);
    int outward = 0;
    for (int64_t t = 0; t < b.View.NumberOfTriangles; ++t)
    {
      double n[3];
      plodcheck::Face(b.View, t, n);
      const int32_t* c = &b.View.Triangles[3 * t];
      double x[3];
      for (int a = 0; a < 3; ++a)
        x[a] = b.Octree->GetOrigin()[a] + b.View.Points[3 * c[0] + a];
      outward += (n[0] * x[0] + n[1] * x[1] + n[2] * x[2] > 0) != inward;
      EXPECT_EQ(b.View.InputPointId[c[0]], -1);
    }
    EXPECT_GE(outward, 0.98 * b.View.NumberOfTriangles);
  }
}

// Found by Testing/Fuzz/FuzzOctreeBuild (corpus: seed-regression-cloud-counts): the mesh phase
// of a cloud's build overwrote the cloud's level reason and non-finite count.
TEST(MultiscaleOctreeBuilder, PointCloudKeepsItsLevelReasonAndNonFiniteCount)
{
  auto sphere = plodtest::MakeBlob(1, 60, 0.0);
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(sphere->GetPoints());
  vtkNew<vtkMultiscaleOctreeBuilder> automatic;
  automatic->SetInputData(cloud);
  automatic->Update();
  EXPECT_NE(
    std::string(automatic->GetFinestLevelReason()).find("4 points on average"), std::string::npos)
    << automatic->GetFinestLevelReason();
  vtkNew<vtkMultiscaleOctreeBuilder> user;
  user->SetInputData(cloud);
  user->SetFinestLevel(4);
  user->Update();
  EXPECT_STREQ(user->GetFinestLevelReason(), "set by the user");

  // the kernel's count of the cloud's own non-finite points (was the contoured mesh's: 0)
  std::vector<double> xyz(3 * cloud->GetNumberOfPoints() + 6);
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i)
  {
    cloud->GetPoint(i, &xyz[3 * i]);
  }
  xyz[xyz.size() - 6] = std::nan("");
  xyz[xyz.size() - 2] = HUGE_VAL;
  plod::BuildInput in;
  in.NumberOfPoints = static_cast<int64_t>(xyz.size() / 3);
  in.Points = xyz.data();
  plod::OctreeStorage storage;
  const plod::BuildResult r =
    plod::BuildOctree(in, plod::BuildParameters(), storage.MakeAllocator());
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_EQ(r.NumberOfNonFinitePoints, 2);
  EXPECT_NE(r.LevelReason.find("4 points on average"), std::string::npos) << r.LevelReason;
}

// Found by Testing/Fuzz/FuzzOctreeBuild (corpus: seed-regression-cloud-memory-limit): a cloud's
// surface was built whatever the memory limit; a mesh at the same level is refused.
TEST(MultiscaleOctreeBuilder, PointCloudSurfaceHonoursTheMemoryLimit)
{
  auto sphere = plodtest::MakeBlob(1, 60, 0.0);
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(sphere->GetPoints());
  vtkNew<vtkMultiscaleOctreeBuilder> free;
  free->SetInputData(cloud);
  free->SetFinestLevel(4);
  free->Update();
  const double need = plod::EstimateBuildMemory(free->GetOutput()->GetNumberOfSurfacePoints(),
    free->GetOutput()->GetNumberOfSurfaceTriangles(), free->GetOutput()->GetNumberOfNodes(), false);
  ASSERT_GT(need, 0);
  vtkNew<plodtest::ErrorRecorder> errors;
  vtkNew<vtkMultiscaleOctreeBuilder> tight;
  tight->SetInputData(cloud);
  tight->SetFinestLevel(4);
  tight->SetMemoryLimit(0.5 * need / (1024.0 * 1024.0));
  tight->AddObserver(vtkCommand::ErrorEvent, errors);
  tight->Update();
  EXPECT_EQ(tight->GetOutput()->GetNumberOfNodes(), 0);
  EXPECT_TRUE(errors->HasError("above the memory limit"));
  // with room enough, the same build succeeds
  vtkNew<vtkMultiscaleOctreeBuilder> roomy;
  roomy->SetInputData(cloud);
  roomy->SetFinestLevel(4);
  roomy->SetMemoryLimit(2 * need / (1024.0 * 1024.0));
  roomy->Update();
  EXPECT_EQ(roomy->GetOutput()->GetNumberOfNodes(), free->GetOutput()->GetNumberOfNodes());
}

TEST(MultiscaleOctreeBuilder, ProgressIsReportedAndAbortStopsTheBuild)
{
  auto blob = plodtest::MakeBlob(16, 200, 0.2);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  std::vector<double> seen;
  vtkNew<vtkCallbackCommand> cb;
  struct Data
  {
    std::vector<double>* Seen;
    vtkMultiscaleOctreeBuilder* B;
    double AbortAt;
  } data{ &seen, builder, 2.0 };
  cb->SetClientData(&data);
  cb->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    auto* d = static_cast<Data*>(client);
    const double f = *static_cast<double*>(call);
    d->Seen->push_back(f);
    if (f >= d->AbortAt)
      d->B->SetAbortExecute(1);
  });
  builder->AddObserver(vtkCommand::ProgressEvent, cb);
  builder->Update();
  ASSERT_GT(seen.size(), 10u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GT(builder->GetOutput()->GetNumberOfNodes(), 0);
  seen.clear();
  data.AbortAt = 0.4;
  builder->Modified();
  vtkNew<plodtest::ErrorRecorder> errors;
  builder->AddObserver(vtkCommand::WarningEvent, errors);
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0);
  EXPECT_LT(seen.back(), 0.6) << "stopped soon after the abort";
  ASSERT_FALSE(errors->Warnings.empty());
  EXPECT_NE(errors->Warnings.back().find("aborted"), std::string::npos);
  builder->SetAbortExecute(0);
}

TEST(MultiscaleOctreeBuilder, ALongSliverCostsItsSizeNotItsBoundingBox)
{
  // 2,000 tiny triangles and one sliver across the whole model: the old crossing search looped
  // over the sliver's bounding box (minutes at level 17); here it must finish at once at any
  // level (CTest's timeout catches a hang) and keep every invariant
  auto mesh = plodtest::MakeSliverSoup();
  for (int level : { -1, 17, 21 })
  {
    Built b = Build(mesh, level);
    ASSERT_GT(b.View.NumberOfNodes, 0) << level;
    EXPECT_EQ(b.View.NumberOfTriangles, 2001);
  }
}

TEST(MultiscaleOctreeBuilder, CorruptArraysAreReportedNotFollowed)
{
  // arrays edited after the build (from numpy, or read from a bad file): IsConsistent names
  // the problem, and navigation returns -1 instead of looping or reading out of bounds
  Built b = Build(plodtest::MakeBlob(17, 30, 0.2));
  auto* parent = vtkIntArray::SafeDownCast(b.Octree->GetNodeData()->GetArray("Parent"));
  auto* first = vtkIntArray::SafeDownCast(b.Octree->GetNodeData()->GetArray("FirstChild"));
  auto* leaf = vtkIntArray::SafeDownCast(b.Octree->GetSurfaceData()->GetArray("PointLeaf"));
  auto* tris = vtkIntArray::SafeDownCast(b.Octree->GetSurfaceData()->GetArray("Triangles"));
  struct Edit
  {
    vtkIntArray* A;
    vtkIdType I;
    int V;
    const char* Message;
  };
  const vtkIdType last = b.Octree->GetNumberOfNodes() - 1;
  const Edit edits[] = { { parent, 5, 5, "point back" },
    { parent, last, static_cast<int>(last + 7), "point back" }, { first, 0, 1 << 30, "children" },
    { first, 1, 0, "children" }, { leaf, 3, -4, "leaf" }, { tris, 7, 1 << 30, "refers to point" } };
  for (const Edit& e : edits)
  {
    const int old = e.A->GetValue(e.I);
    e.A->SetValue(e.I, e.V);
    e.A->Modified();
    std::string why;
    EXPECT_FALSE(b.Octree->CheckConsistency(&why)) << e.Message;
    EXPECT_NE(why.find(e.Message), std::string::npos) << why;
    int ijk[3];
    b.Octree->GetNodeCellCoordinates(last, ijk);
    EXPECT_EQ(ijk[0], -1);
    const double x[3] = { 0, 0, 0 };
    EXPECT_EQ(b.Octree->FindNode(x, 3), -1);
    e.A->SetValue(e.I, old);
    e.A->Modified();
    EXPECT_TRUE(b.Octree->IsConsistent());
  }
  // a child mask that lost a bit: the child still names its parent, which no longer lists it
  // (found by fuzzing octree files: the full cut then held a node and its ancestor)
  auto* mask = vtkUnsignedCharArray::SafeDownCast(b.Octree->GetNodeData()->GetArray("ChildMask"));
  ASSERT_NE(mask, nullptr);
  const unsigned char rootMask = mask->GetValue(0);
  ASSERT_GT(rootMask & (rootMask - 1), 0) << "the root has at least two children";
  mask->SetValue(0, static_cast<unsigned char>(rootMask & (rootMask - 1))); // lowest bit off
  mask->Modified();
  std::string why;
  EXPECT_FALSE(b.Octree->CheckConsistency(&why));
  EXPECT_NE(why.find("child masks list"), std::string::npos) << why;
  mask->SetValue(0, rootMask);
  mask->Modified();
  EXPECT_TRUE(b.Octree->IsConsistent());
}

TEST(MultiscaleOctreeBuilder, StanfordBunnyMesh)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  auto bunny = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  ASSERT_TRUE(bunny);
  Built b = Build(bunny);
  CheckSurfaceIsTheInput(b, bunny, "bunny");
  std::string why;
  EXPECT_TRUE(plod::ValidateOctree(b.View, &why)) << why;
  EXPECT_EQ(b.View.NumberOfTriangles, 69451);
  EXPECT_GT(b.Octree->GetNumberOfBoundaryEdges(), 0) << "the bunny's base is open";
  // cones hold the normals of the triangles at their points (the full check is too slow here)
  for (int64_t t = 0; t < b.View.NumberOfTriangles; ++t)
  {
    double n[3];
    if (plodcheck::Face(b.View, t, n) <= 0)
      continue;
    for (int k = 0; k < 3; ++k)
    {
      for (int64_t node = b.View.PointLeaf[b.View.Triangles[3 * t + k]]; node >= 0;
           node = b.View.Parent[node])
      {
        const auto axis = Get3(&b.View.ConeAxis[3 * node]);
        ASSERT_LE(Angle(axis.data(), n), b.View.ConeAngle[node] + 1e-4) << t << " " << node;
      }
    }
  }
}

TEST(MultiscaleOctreeBuilder, StanfordBunnyRangeScansMerged)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  int scans = 0;
  auto cloud = plodtest::ReadBunnyScans(dir, &scans);
  ASSERT_TRUE(cloud);
  EXPECT_EQ(scans, 10);
  EXPECT_EQ(cloud->GetNumberOfPoints(), 362272);
  // registered: the scans lie on the zippered mesh made from them (its points are about 0.5
  // mm apart; a wrong transform misses it by centimetres)
  auto mesh = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  ASSERT_TRUE(mesh);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(mesh);
  locator->BuildLocator();
  std::vector<double> distances;
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); i += 97)
  {
    double x[3], y[3];
    cloud->GetPoint(i, x);
    mesh->GetPoint(locator->FindClosestPoint(x), y);
    distances.push_back(std::sqrt(vtkMath::Distance2BetweenPoints(x, y)));
  }
  std::sort(distances.begin(), distances.end());
  EXPECT_LT(distances[distances.size() / 2], 0.001) << "median distance to the mesh, m";
  EXPECT_LT(distances[distances.size() * 9 / 10], 0.003) << "90th percentile, m";
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(cloud);
  builder->SetViewpointArrayName("ScannerPosition");
  builder->Update();
  Built b{ builder->GetOutput(), {} };
  ASSERT_TRUE(b.Octree->GetView(b.View));
  std::string why;
  EXPECT_TRUE(plod::ValidateOctree(b.View, &why)) << why;
  // The merged scans and the zippered mesh are the same object in the same frame: the scan
  // surface's triangles face the same way as the mesh's nearby (oriented towards the scanners)
  Built m = Build(mesh, b.View.FinestLevel);
  int agree = 0, compared = 0, sampled = 0;
  for (int64_t t = 0; t < b.View.NumberOfTriangles; t += 7)
  {
    ++sampled;
    double n[3], x[3];
    if (plodcheck::Face(b.View, t, n) <= 0)
      continue;
    for (int a = 0; a < 3; ++a)
      x[a] = b.Octree->GetOrigin()[a] + b.View.Points[3 * b.View.Triangles[3 * t] + a];
    const vtkIdType k = m.Octree->FindNode(x, m.View.FinestLevel);
    if (k < 0 || m.View.ConeAngle[k] > 0.5f)
      continue;
    const auto axis = Get3(&m.View.ConeAxis[3 * k]);
    agree += Angle(axis.data(), n) < Pi / 3;
    ++compared;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GE(agree, 0.9 * compared) << "scan normals oriented towards their scanners";
  EXPECT_GE(compared, sampled / 2) << "the scan surface lies where the mesh is";
}

// ---- distributed rendering: a given root cube, the automatic level from counts, ghosts -------

namespace
{
/// Every array of `a` but `skip` is in `b`, byte for byte.
void ExpectSameArrays(
  vtkFieldData* a, vtkFieldData* b, const std::string& what, const char* skip = nullptr)
{
  auto count = [skip](vtkFieldData* f) {
    return f->GetNumberOfArrays() - ((skip && f->GetAbstractArray(skip)) ? 1 : 0);
  };
  ASSERT_EQ(count(a), count(b)) << what;
  for (int i = 0; i < a->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* x = a->GetArray(i);
    ASSERT_TRUE(x) << what;
    const std::string name = x->GetName();
    if (skip && name == skip)
      continue;
    vtkDataArray* y = b->GetArray(name.c_str());
    ASSERT_TRUE(y) << what << ": " << name;
    ASSERT_EQ(x->GetDataType(), y->GetDataType()) << what << ": " << name;
    ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues()) << what << ": " << name;
    const size_t bytes = size_t(x->GetNumberOfValues()) * size_t(x->GetDataTypeSize());
    EXPECT_EQ(std::memcmp(x->GetVoidPointer(0), y->GetVoidPointer(0), bytes), 0)
      << what << ": array " << name << " differs";
  }
}

/// The same octree: root cube, level, and every node, cluster and surface array (ghosts apart).
void ExpectSameOctree(vtkMultiscaleOctree* a, vtkMultiscaleOctree* b, const std::string& what)
{
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(a->GetOrigin()[k], b->GetOrigin()[k]) << what;
  EXPECT_EQ(a->GetRootEdge(), b->GetRootEdge()) << what;
  EXPECT_EQ(a->GetFinestLevel(), b->GetFinestLevel()) << what;
  ExpectSameArrays(a->GetNodeData(), b->GetNodeData(), what + " (nodes)");
  ExpectSameArrays(a->GetClusterData(), b->GetClusterData(), what + " (clusters)");
  ExpectSameArrays(a->GetSurfaceData(), b->GetSurfaceData(), what + " (surface)",
    vtkMultiscaleOctree::PointGhostArrayName());
}

/// Occupied cells of every level 0..21 of the cube over the points of `pd` (all used).
std::array<long long, 22> CountCells(vtkPointSet* pd, const double origin[3], double edge)
{
  std::array<std::set<std::array<uint32_t, 3>>, 22> cells;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pd->GetPoint(i, x);
    const auto c = plodcheck::CellOf(x, origin, edge, 21);
    for (int l = 0; l <= 21; ++l)
      cells[l].insert({ c[0] >> (21 - l), c[1] >> (21 - l), c[2] >> (21 - l) });
  }
  std::array<long long, 22> counts;
  for (int l = 0; l <= 21; ++l)
    counts[l] = static_cast<long long>(cells[l].size());
  return counts;
}

/// The kernel's input for a triangle mesh with double points.
struct KernelMesh
{
  std::vector<double> Points;
  std::vector<int64_t> Triangles;
  plod::BuildInput Input() const
  {
    plod::BuildInput in;
    in.NumberOfPoints = static_cast<int64_t>(this->Points.size() / 3);
    in.Points = this->Points.data();
    in.NumberOfTriangles = static_cast<int64_t>(this->Triangles.size() / 3);
    in.Triangles = this->Triangles.data();
    return in;
  }
};
KernelMesh ToKernel(vtkPolyData* pd)
{
  KernelMesh m;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pd->GetPoint(i, x);
    m.Points.insert(m.Points.end(), x, x + 3);
  }
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
      m.Triangles.insert(m.Triangles.end(), { ids[0], ids[k], ids[k + 1] });
  }
  return m;
}
} // namespace

TEST(MultiscaleOctreeBuilder, GivenRootCubeIsTheOctreesCube)
{
  // a cube other than the one the builder would place: the octree's origin and edge are exactly
  // the given ones, the level the given one, and the octree keeps every promise
  auto blob = plodtest::MakeBlob(21, 30, 0.3);
  const double origin[3] = { -1.75, -1.5, -1.625 };
  const double edge = 3.5;
  vtkNew<plodtest::ErrorRecorder> errors;
  Built b = plodcheck::BuildInCube(blob, origin, edge, 5, errors);
  EXPECT_TRUE(errors->Errors.empty());
  ASSERT_GT(b.View.NumberOfNodes, 0);
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(b.Octree->GetOrigin()[a], origin[a]);
  EXPECT_EQ(b.Octree->GetRootEdge(), edge);
  EXPECT_EQ(b.Octree->GetFinestLevel(), 5);
  CheckOctree(b, "given cube");
  CheckSurfaceIsTheInput(b, blob, "given cube");

  // the kernel alone, and a point exactly on the cube's upper faces (closed cube: in the last
  // cell), another exactly on its lower corner
  KernelMesh m = ToKernel(blob);
  const int64_t corner = static_cast<int64_t>(m.Points.size() / 3);
  m.Points.insert(m.Points.end(), { origin[0] + edge, origin[1] + edge, origin[2] + edge });
  m.Points.insert(m.Points.end(), { origin[0], origin[1], origin[2] });
  m.Triangles.insert(m.Triangles.end(), { 0, corner, corner + 1 });
  plod::BuildParameters params;
  params.FinestLevel = 4;
  params.HasRootCube = true;
  std::copy(origin, origin + 3, params.RootOrigin);
  params.RootEdge = edge;
  plod::OctreeStorage storage;
  const plod::BuildResult r = plod::BuildOctree(m.Input(), params, storage.MakeAllocator());
  ASSERT_TRUE(r.Ok) << r.Error;
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(r.Origin[a], origin[a]);
  EXPECT_EQ(r.RootEdge, edge);
  EXPECT_EQ(r.FinestLevel, 4);
  std::string why;
  EXPECT_TRUE(plod::ValidateOctree(storage.View(r), &why)) << why;

  // a point cloud uses the given cube for its own
  auto sphere = plodtest::MakeBlob(1, 60, 0.0);
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(sphere->GetPoints());
  Built c = plodcheck::BuildInCube(cloud, origin, edge, 4, errors);
  EXPECT_TRUE(errors->Errors.empty());
  ASSERT_GT(c.View.NumberOfTriangles, 100);
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(c.Octree->GetOrigin()[a], origin[a]);
  EXPECT_EQ(c.Octree->GetRootEdge(), edge);
  EXPECT_EQ(c.Octree->GetFinestLevel(), 4);
  EXPECT_TRUE(plod::ValidateOctree(c.View, &why)) << why;
}

TEST(MultiscaleOctreeBuilder, PointsOutsideTheGivenRootCubeAreErrorsNamingThem)
{
  // the cube [-1, 0.5]^3 cuts the blob (radius about 1): an error naming a point outside it and
  // the cube, and an empty octree; nothing is clamped
  auto blob = plodtest::MakeBlob(22, 20, 0.2);
  const double origin[3] = { -1, -1, -1 };
  {
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = plodcheck::BuildInCube(blob, origin, 1.5, 4, errors);
    EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);
    ASSERT_TRUE(errors->HasError("lies outside the given root cube [-1, 0.5] x [-1, 0.5] x [-1, "
                                 "0.5]"))
      << (errors->Errors.empty() ? "" : errors->Errors[0]);
    // the point named is one of the input's and really lies outside
    const std::string& text = errors->Errors[0];
    const size_t at = text.find("point ");
    ASSERT_NE(at, std::string::npos);
    const vtkIdType id = std::stoll(text.substr(at + 6));
    double x[3];
    blob->GetPoint(id, x);
    EXPECT_TRUE(x[0] > 0.5 || x[1] > 0.5 || x[2] > 0.5 || x[0] < -1 || x[1] < -1 || x[2] < -1);
  }
  // one point a rounding step outside an upper face: still outside
  {
    const double e = 2.0;
    std::vector<double> xyz = { 0, 0, 0, 1, 0, 0, 0, 1, std::nextafter(-1.0 + e, 10.0) };
    auto tri = plodtest::MakeMesh(xyz, { 0, 1, 2 });
    const double o[3] = { -1, -1, -1 };
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = plodcheck::BuildInCube(tri, o, e, 3, errors);
    EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);
    EXPECT_TRUE(errors->HasError("point 2 (0, 1, 1.0000000000000002) lies outside"))
      << (errors->Errors.empty() ? "" : errors->Errors[0]);
    // exactly on the face: inside; a point no triangle uses is not looked at
    xyz[8] = 1.0;
    xyz.insert(xyz.end(), { 50, 50, 50 });
    auto onFace = plodtest::MakeMesh(xyz, { 0, 1, 2 });
    vtkNew<plodtest::ErrorRecorder> none;
    Built f = plodcheck::BuildInCube(onFace, o, e, 3, none);
    EXPECT_TRUE(none->Errors.empty());
    EXPECT_EQ(f.View.NumberOfPoints, 3);
    CheckOctree(f, "point on the upper face");
  }
  // a point cloud too
  {
    auto sphere = plodtest::MakeBlob(1, 30, 0.0);
    vtkNew<vtkPolyData> cloud;
    cloud->SetPoints(sphere->GetPoints());
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = plodcheck::BuildInCube(cloud, origin, 1.5, 4, errors);
    EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);
    EXPECT_TRUE(errors->HasError("lies outside the given root cube"));
  }
}

TEST(MultiscaleOctreeBuilder, InvalidGivenRootCubesAreErrors)
{
  // the limits the builder's own placement respects: finite, an edge it could place, an edge the
  // double coordinates can resolve at the cube's distance; the default edge (0) must be set
  auto blob = plodtest::MakeBlob(23, 16, 0.2);
  const double nan = std::nan("");
  struct Case
  {
    double Origin[3];
    double Edge;
  };
  const Case cases[] = { { { -2, -2, -2 }, 0 }, { { -2, -2, -2 }, -4 }, { { -2, -2, -2 }, nan },
    { { -2, -2, -2 }, HUGE_VAL }, { { -2, -2, -2 }, 1e31 }, { { nan, -2, -2 }, 4 },
    { { -2, -HUGE_VAL, -2 }, 4 }, { { 1e13, -2, -2 }, 4 } };
  for (const Case& c : cases)
  {
    vtkNew<plodtest::ErrorRecorder> errors;
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(blob);
    builder->UseGivenRootCubeOn();
    builder->SetRootCubeOrigin(c.Origin[0], c.Origin[1], c.Origin[2]);
    builder->SetRootCubeEdge(c.Edge);
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->Update();
    EXPECT_TRUE(errors->HasError("UseGivenRootCube: the given root cube")) << c.Edge;
    EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0);
    // the kernel refuses it as well
    KernelMesh m = ToKernel(blob);
    plod::BuildParameters params;
    params.HasRootCube = true;
    std::copy(c.Origin, c.Origin + 3, params.RootOrigin);
    params.RootEdge = c.Edge;
    plod::OctreeStorage storage;
    const plod::BuildResult r = plod::BuildOctree(m.Input(), params, storage.MakeAllocator());
    EXPECT_FALSE(r.Ok);
    EXPECT_NE(r.Error.find("the given root cube"), std::string::npos) << r.Error;
  }
  // off, the cube's values are not looked at
  vtkNew<vtkMultiscaleOctreeBuilder> off;
  off->SetInputData(blob);
  off->SetRootCubeEdge(-1);
  off->Update();
  EXPECT_GT(off->GetOutput()->GetNumberOfNodes(), 0);
}

TEST(MultiscaleOctreeBuilder, ComputeRootCubeIsTheCubeABuildPlaces)
{
  // from the bounds of models whose every point is used: exactly the cube of an unconstrained
  // build; building in that cube gives the same octree, array for array
  const double far[3] = { 1e4, -3e3, 7e2 };
  const std::vector<std::pair<std::string, vtkSmartPointer<vtkPolyData>>> models = {
    { "blob", plodtest::MakeBlob(24, 30, 0.3) }, { "cube", plodtest::MakeCube(-1, 2) },
    { "tetrahedron", plodtest::MakeTetrahedron() }, { "flat plane", plodtest::MakePlane(0.3) },
    { "far blob", plodtest::MakeBlob(25, 20, 0.3, 0.01, far) }
  };
  for (const auto& [name, model] : models)
  {
    double bounds[6], origin[3] = { 7, 7, 7 }, edge = 7;
    model->GetBounds(bounds);
    ASSERT_TRUE(vtkMultiscaleOctreeBuilder::ComputeRootCube(bounds, origin, &edge)) << name;
    Built b = Build(model);
    ASSERT_GT(b.View.NumberOfNodes, 0) << name;
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(origin[a], b.Octree->GetOrigin()[a]) << name;
    EXPECT_EQ(edge, b.Octree->GetRootEdge()) << name;
    Built g = plodcheck::BuildInCube(model, origin, edge, -1);
    ExpectSameOctree(b.Octree, g.Octree, name);
  }
  // bounds that hold nothing, are not finite or too large: false, outputs untouched
  const double nan = std::nan("");
  const double bad[][6] = { { 1, -1, 1, -1, 1, -1 }, { 0, 1, 0, nan, 0, 1 },
    { 0, HUGE_VAL, 0, 1, 0, 1 }, { 0, 1e31, 0, 1, 0, 1 } };
  for (const auto& bounds : bad)
  {
    double origin[3] = { 7, 7, 7 }, edge = 7;
    EXPECT_FALSE(vtkMultiscaleOctreeBuilder::ComputeRootCube(bounds, origin, &edge));
    EXPECT_EQ(origin[0], 7);
    EXPECT_EQ(edge, 7);
  }
}

TEST(MultiscaleOctreeBuilder, ChooseFinestLevelFromCountsIsTheBuildsAutomaticLevel)
{
  // counts of occupied cells per level, made outside the builder, give the level the builder
  // chooses: meshes of growing detail, an unwelded mesh (duplicated points), a point cloud
  std::vector<std::pair<vtkSmartPointer<vtkPointSet>, bool>> inputs;
  for (int res : { 6, 16, 40, 90 })
    inputs.push_back({ plodtest::MakeBlob(26, res, 0.3), false });
  inputs.push_back({ plodtest::Unweld(plodtest::MakeBlob(27, 20, 0.2)), false });
  for (int res : { 40, 150 })
  {
    auto sphere = plodtest::MakeBlob(1, res, 0.1);
    auto cloud = vtkSmartPointer<vtkPolyData>::New();
    cloud->SetPoints(sphere->GetPoints());
    inputs.push_back({ cloud, true });
  }
  std::set<int> levels;
  for (const auto& [input, cloud] : inputs)
  {
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(input);
    builder->Update();
    const int built = builder->GetOutput()->GetFinestLevel();
    ASSERT_GT(builder->GetOutput()->GetNumberOfNodes(), 0);
    double bounds[6], origin[3], edge;
    input->GetBounds(bounds);
    ASSERT_TRUE(vtkMultiscaleOctreeBuilder::ComputeRootCube(bounds, origin, &edge));
    const auto counts = CountCells(input, origin, edge);
    EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(
                counts.data(), input->GetNumberOfPoints(), cloud),
      built)
      << input->GetNumberOfPoints() << " points, cloud " << cloud;
    levels.insert(built);
  }
  EXPECT_GE(levels.size(), 4u); // the cases really differ
  // counts no set of points can give
  std::array<long long, 22> counts;
  counts.fill(1);
  EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(counts.data(), 1, false), 0);
  counts[0] = 2;
  EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(counts.data(), 9, false), -1);
  counts.fill(8);
  counts[0] = 1;
  counts[5] = 7; // decreasing
  EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(counts.data(), 9, false), -1);
  counts[5] = 8;
  counts[1] = 9; // more than 8 children
  EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(counts.data(), 9, false), -1);
  counts[1] = 8;
  EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(counts.data(), 7, true), -1);
  EXPECT_EQ(vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(counts.data(), 8, false), 1);
}

TEST(MultiscaleOctreeBuilder, GhostPointsChangeNothingButTheirFlags)
{
  // vtkGhostType on the input: the octree is the one built without it, array for array, plus
  // each surface point's flag (bit DUPLICATEPOINT of its input point; other bits ignored)
  auto blob = plodtest::MakeBlob(28, 40, 0.3);
  auto ghosted = vtkSmartPointer<vtkPolyData>::New();
  ghosted->ShallowCopy(blob);
  vtkNew<vtkUnsignedCharArray> flags;
  flags->SetName(vtkDataSetAttributes::GhostArrayName());
  flags->SetNumberOfTuples(blob->GetNumberOfPoints());
  int64_t expectedGhosts = 0;
  for (vtkIdType i = 0; i < blob->GetNumberOfPoints(); ++i)
  {
    double x[3];
    blob->GetPoint(i, x);
    unsigned char f = x[0] > 0.2 ? vtkDataSetAttributes::DUPLICATEPOINT : 0;
    if (x[1] > 0.5)
      f |= vtkDataSetAttributes::HIDDENPOINT; // not a ghost
    flags->SetValue(i, f);
    expectedGhosts += x[0] > 0.2;
  }
  ghosted->GetPointData()->AddArray(flags);
  Built plain = Build(blob, 6);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(ghosted);
  builder->SetFinestLevel(6);
  builder->Update();
  Built g{ builder->GetOutput(), {} };
  ASSERT_TRUE(g.Octree->GetView(g.View));
  ExpectSameOctree(plain.Octree, g.Octree, "ghosts");
  EXPECT_FALSE(plain.Octree->HasPointGhosts());
  EXPECT_EQ(plain.View.PointGhost, nullptr);
  ASSERT_TRUE(g.Octree->HasPointGhosts());
  ASSERT_NE(g.View.PointGhost, nullptr);
  for (int64_t p = 0; p < g.View.NumberOfPoints; ++p)
  {
    const bool ghost =
      flags->GetValue(g.View.InputPointId[p]) & vtkDataSetAttributes::DUPLICATEPOINT;
    ASSERT_EQ(g.View.PointGhost[p], ghost ? 1 : 0) << "surface point " << p;
  }
  EXPECT_GT(expectedGhosts, 100);
  EXPECT_LT(expectedGhosts, blob->GetNumberOfPoints() - 100);
  EXPECT_EQ(g.Octree->GetNumberOfGhostPoints(), expectedGhosts);
  EXPECT_EQ(builder->GetNumberOfGhostPoints(), expectedGhosts);
  CheckOctree(g, "ghosts");
  // copies carry the flags; PrintSelf tells
  vtkNew<vtkMultiscaleOctree> shallow, deep;
  shallow->ShallowCopy(g.Octree);
  deep->DeepCopy(g.Octree);
  for (vtkMultiscaleOctree* o : { shallow.Get(), deep.Get() })
  {
    EXPECT_EQ(o->GetNumberOfGhostPoints(), expectedGhosts);
    plod::OctreeView v;
    ASSERT_TRUE(o->GetView(v));
    EXPECT_EQ(std::memcmp(v.PointGhost, g.View.PointGhost, size_t(v.NumberOfPoints)), 0);
  }
  const char* name = vtkMultiscaleOctree::PointGhostArrayName();
  EXPECT_EQ(shallow->GetSurfaceData()->GetArray(name), g.Octree->GetSurfaceData()->GetArray(name));
  EXPECT_NE(deep->GetSurfaceData()->GetArray(name), g.Octree->GetSurfaceData()->GetArray(name));
  std::ostringstream text;
  g.Octree->PrintSelf(text, vtkIndent());
  EXPECT_NE(text.str().find("PointGhosts: " + std::to_string(expectedGhosts) + " ghost points"),
    std::string::npos);
  // an array of that name with another type or size makes the octree inconsistent
  vtkNew<vtkIntArray> wrong;
  wrong->SetName(name);
  wrong->SetNumberOfTuples(g.View.NumberOfPoints);
  deep->GetSurfaceData()->AddArray(wrong);
  EXPECT_FALSE(deep->IsConsistent());

  // a ghost array of the wrong type or length: an error naming it, an empty octree
  for (int wrongCase = 0; wrongCase < 2; ++wrongCase)
  {
    auto bad = vtkSmartPointer<vtkPolyData>::New();
    bad->ShallowCopy(blob);
    vtkSmartPointer<vtkDataArray> a;
    if (wrongCase == 0)
      a = vtkSmartPointer<vtkIntArray>::New();
    else
      a = vtkSmartPointer<vtkUnsignedCharArray>::New();
    a->SetName(vtkDataSetAttributes::GhostArrayName());
    a->SetNumberOfTuples(blob->GetNumberOfPoints() - wrongCase);
    a->Fill(0);
    bad->GetPointData()->AddArray(a);
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = Build(bad, 4, vtkMultiscaleOctreeBuilder::VERTEX_QEF, errors);
    EXPECT_TRUE(errors->HasError("Ghost array 'vtkGhostType'")) << wrongCase;
    EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);
  }

  // a point cloud's flags are ignored, with a warning
  {
    auto sphere = plodtest::MakeBlob(1, 60, 0.0);
    vtkNew<vtkPolyData> cloud;
    cloud->SetPoints(sphere->GetPoints());
    vtkNew<vtkUnsignedCharArray> cloudFlags;
    cloudFlags->SetName(vtkDataSetAttributes::GhostArrayName());
    cloudFlags->SetNumberOfTuples(cloud->GetNumberOfPoints());
    cloudFlags->Fill(vtkDataSetAttributes::DUPLICATEPOINT);
    cloud->GetPointData()->AddArray(cloudFlags);
    vtkNew<plodtest::ErrorRecorder> warnings;
    Built c = Build(cloud, 4, vtkMultiscaleOctreeBuilder::VERTEX_QEF, warnings);
    ASSERT_GT(c.View.NumberOfTriangles, 0);
    EXPECT_FALSE(c.Octree->HasPointGhosts());
    bool warned = false;
    for (const auto& w : warnings->Warnings)
      warned = warned || w.find("ghost flags ignored") != std::string::npos;
    EXPECT_TRUE(warned);
  }

  // the kernel with an allocator that gives no place for the flags: an error, not a silent drop
  {
    KernelMesh m = ToKernel(blob);
    std::vector<uint8_t> ghost(m.Points.size() / 3, 1);
    plod::BuildInput in = m.Input();
    in.PointGhost = ghost.data();
    plod::OctreeStorage storage;
    plod::Allocator allocate = storage.MakeAllocator();
    allocate.PointGhost = nullptr;
    const plod::BuildResult r = plod::BuildOctree(in, plod::BuildParameters(), allocate);
    EXPECT_FALSE(r.Ok);
    EXPECT_NE(r.Error.find("ghost"), std::string::npos) << r.Error;
  }
}

TEST(MultiscaleOctreeBuilder, PiecesWithASharedCubeAndLevelMatchTheWholeBuild)
{
  // Distributed rendering as the plugin does it: the level-k cells of the cube are owned by two
  // processes (split by the plane x = centre); each piece holds the triangles at its own cells
  // and complete copies of the neighbour cells they touch, its points outside its own cells
  // flagged as ghosts. Built with the cube of the whole and its level, every cell of level k or
  // finer that a piece holds completely exists in the whole's build, with the same children,
  // vertex, clusters, cone, shape error and flags; and every such cell of the whole exists in the
  // piece.
  auto blob = plodtest::MakeBlob(29, 48, 0.3);
  double bounds[6], origin[3], edge;
  blob->GetBounds(bounds);
  ASSERT_TRUE(vtkMultiscaleOctreeBuilder::ComputeRootCube(bounds, origin, &edge));
  const int L = 5, k = 2;
  Built whole = plodcheck::BuildInCube(blob, origin, edge, L);
  ASSERT_GT(whole.View.NumberOfNodes, 0);
  const plod::OctreeView& w = whole.View;
  std::map<std::array<int, 4>, int64_t> wholeNodes;
  for (int64_t n = 0; n < w.NumberOfNodes; ++n)
  {
    int c[3];
    w.CellCoordinates(n, c);
    wholeNodes[{ w.Level[n], c[0], c[1], c[2] }] = n;
  }
  for (int side = 0; side < 2; ++side)
  {
    const std::string what = "piece " + std::to_string(side);
    const plodcheck::Piece piece = plodcheck::MakePiece(blob, origin, edge, k,
      [side](const std::array<uint32_t, 3>& c) { return (c[0] < 2) == (side == 0); });
    ASSERT_FALSE(piece.Owned.empty());
    ASSERT_GT(piece.Complete.size(), piece.Owned.size()); // it holds neighbours
    ASSERT_LT(piece.Mesh->GetNumberOfCells(), blob->GetNumberOfCells());
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = plodcheck::BuildInCube(piece.Mesh, origin, edge, L, errors);
    EXPECT_TRUE(errors->Errors.empty()) << what;
    const plod::OctreeView& v = b.View;
    ASSERT_GT(v.NumberOfNodes, 0) << what;
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(b.Octree->GetOrigin()[a], origin[a]) << what;
    EXPECT_EQ(b.Octree->GetRootEdge(), edge) << what;
    EXPECT_EQ(v.FinestLevel, L) << what;
    CheckOctree(b, what);
    int64_t compared = 0;
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    {
      if (v.Level[n] < k)
        continue;
      int c[3];
      v.CellCoordinates(n, c);
      const int shift = v.Level[n] - k;
      if (!piece.Complete.count(
            { uint32_t(c[0] >> shift), uint32_t(c[1] >> shift), uint32_t(c[2] >> shift) }))
        continue;
      const auto found = wholeNodes.find({ v.Level[n], c[0], c[1], c[2] });
      ASSERT_NE(found, wholeNodes.end()) << what << " node " << n;
      const int64_t m = found->second;
      ++compared;
      EXPECT_EQ(v.ChildMask[n], w.ChildMask[m]) << what << " node " << n;
      EXPECT_EQ(v.Flags[n], w.Flags[m]) << what << " node " << n;
      EXPECT_EQ(v.ShapeError[n], w.ShapeError[m]) << what << " node " << n;
      EXPECT_EQ(v.ConeAngle[n], w.ConeAngle[m]) << what << " node " << n;
      EXPECT_EQ(v.PointEnd(n) - v.FirstPoint[n], w.PointEnd(m) - w.FirstPoint[m]) << what;
      ASSERT_EQ(v.ClusterEnd(n) - v.FirstCluster[n], w.ClusterEnd(m) - w.FirstCluster[m]) << what;
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(v.Vertex[3 * n + a], w.Vertex[3 * m + a]) << what << " node " << n;
        EXPECT_EQ(v.ConeAxis[3 * n + a], w.ConeAxis[3 * m + a]) << what << " node " << n;
        for (int64_t j = 0; j < v.ClusterEnd(n) - v.FirstCluster[n]; ++j)
          EXPECT_EQ(v.ClusterVertex[3 * (v.FirstCluster[n] + j) + a],
            w.ClusterVertex[3 * (w.FirstCluster[m] + j) + a])
            << what << " node " << n << " cluster " << j;
      }
    }
    // and the whole has no cell there that the piece lacks
    int64_t expected = 0;
    for (const auto& [key, m] : wholeNodes)
    {
      const int shift = key[0] - k;
      expected += key[0] >= k &&
        piece.Complete.count(
          { uint32_t(key[1] >> shift), uint32_t(key[2] >> shift), uint32_t(key[3] >> shift) });
    }
    EXPECT_EQ(compared, expected) << what;
    EXPECT_GT(compared, 200) << what;
  }
}

// Orientation: a closed mesh whose triangles disagree on their front side is counted edge by
// edge (an edge used twice in the same direction), so that back faces are not hidden on it.
TEST(MultiscaleOctreeBuilder, MisorientedEdgesAreCountedExactly)
{
  auto cube = plodtest::MakeDeformedBox(4, 4, 4, [](const double p[3], double x[3]) {
    for (int a = 0; a < 3; ++a)
      x[a] = p[a];
  });
  Built consistent = Build(cube, 3);
  EXPECT_EQ(consistent.Octree->GetNumberOfBoundaryEdges(), 0);
  EXPECT_EQ(consistent.Octree->GetNumberOfMisorientedEdges(), 0);
  // reverse one triangle that shares no edge with another reversed one: its three edges are
  // now each used twice in one direction
  vtkNew<vtkCellArray> polys;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  cube->GetPolys()->InitTraversal();
  for (vtkIdType k = 0; cube->GetPolys()->GetNextCell(n, ids); ++k)
  {
    ASSERT_EQ(n, 3);
    if (k == 5)
      polys->InsertNextCell({ ids[2], ids[1], ids[0] });
    else
      polys->InsertNextCell(n, ids);
  }
  vtkNew<vtkPolyData> flipped;
  flipped->SetPoints(cube->GetPoints());
  flipped->SetPolys(polys);
  vtkNew<plodtest::ErrorRecorder> warnings;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->AddObserver(vtkCommand::WarningEvent, warnings);
  builder->SetInputData(flipped);
  builder->SetFinestLevel(3);
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetNumberOfBoundaryEdges(), 0);
  EXPECT_EQ(builder->GetOutput()->GetNumberOfMisorientedEdges(), 3);
  ASSERT_EQ(warnings->Warnings.size(), 1u);
  EXPECT_NE(warnings->Warnings[0].find("3 edges are used by two triangles in the same direction"),
    std::string::npos)
    << warnings->Warnings[0];
  // the surface is still the input, the reversed triangle as given
  Built b = Build(flipped, 3);
  CheckSurfaceIsTheInput(b, flipped, "one triangle reversed");
}

// A vtkUnstructuredGrid of triangles is built as a surface (not contoured as a cloud of its
// points), with a warning naming what was taken and what was ignored; a mesh's lines too.
TEST(MultiscaleOctreeBuilder, NonPolyDataCellsAreTakenAndIgnoredCellsNamed)
{
  auto blob = plodtest::MakeBlob(3, 30, 0.2);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(blob->GetPoints());
  grid->Allocate(blob->GetNumberOfPolys() + 2);
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  blob->GetPolys()->InitTraversal();
  while (blob->GetPolys()->GetNextCell(n, ids))
  {
    grid->InsertNextCell(VTK_TRIANGLE, n, ids);
  }
  const vtkIdType tet[4] = { 0, 1, 2, 3 };
  grid->InsertNextCell(VTK_TETRA, 4, tet);
  const vtkIdType line[2] = { 4, 5 };
  grid->InsertNextCell(VTK_LINE, 2, line);
  vtkNew<plodtest::ErrorRecorder> warnings;
  vtkNew<vtkMultiscaleOctreeBuilder> fromGrid;
  fromGrid->AddObserver(vtkCommand::WarningEvent, warnings);
  fromGrid->SetInputData(grid);
  fromGrid->SetFinestLevel(5);
  fromGrid->Update();
  vtkNew<vtkMultiscaleOctreeBuilder> fromMesh;
  fromMesh->SetInputData(blob);
  fromMesh->SetFinestLevel(5);
  fromMesh->Update();
  EXPECT_EQ(fromGrid->GetOutput()->GetNumberOfSurfaceTriangles(), blob->GetNumberOfPolys());
  EXPECT_EQ(fromGrid->GetOutput()->GetNumberOfNodes(), fromMesh->GetOutput()->GetNumberOfNodes());
  ASSERT_EQ(warnings->Warnings.size(), 1u);
  const std::string& w = warnings->Warnings[0];
  EXPECT_NE(w.find("vtkUnstructuredGrid, not a vtkPolyData"), std::string::npos) << w;
  EXPECT_NE(w.find(std::to_string(blob->GetNumberOfPolys()) + " surface cells"), std::string::npos)
    << w;
  EXPECT_NE(w.find("1 volume cells are ignored"), std::string::npos) << w;
  EXPECT_NE(w.find("1 vertex and line cells are ignored"), std::string::npos) << w;
  // a mesh with lines: built from its polygons, the lines named
  vtkNew<vtkPolyData> withLines;
  withLines->DeepCopy(blob);
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell({ 0, 1 });
  lines->InsertNextCell({ 1, 2 });
  withLines->SetLines(lines);
  vtkNew<plodtest::ErrorRecorder> second;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->AddObserver(vtkCommand::WarningEvent, second);
  builder->SetInputData(withLines);
  builder->SetFinestLevel(5);
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetNumberOfSurfaceTriangles(), blob->GetNumberOfPolys());
  ASSERT_EQ(second->Warnings.size(), 1u);
  EXPECT_NE(second->Warnings[0].find("0 vertex and 2 line cells are ignored"), std::string::npos)
    << second->Warnings[0];
}

// A mesh whose triangles share no vertices (an STL, an OBJ split by texture seams) is said to
// be one, with the count of points that repeat another's position.
TEST(MultiscaleOctreeBuilder, UnsharedVerticesAreNamed)
{
  auto cube = plodtest::MakeDeformedBox(4, 4, 4, [](const double p[3], double x[3]) {
    for (int a = 0; a < 3; ++a)
      x[a] = p[a];
  });
  ASSERT_EQ(cube->GetNumberOfPoints(), 5 * 5 * 5 - 3 * 3 * 3);
  // every triangle with three points of its own
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  cube->GetPolys()->InitTraversal();
  while (cube->GetPolys()->GetNextCell(n, ids))
  {
    vtkIdType own[3];
    for (int k = 0; k < 3; ++k)
      own[k] = points->InsertNextPoint(cube->GetPoint(ids[k]));
    polys->InsertNextCell(3, own);
  }
  vtkNew<vtkPolyData> soup;
  soup->SetPoints(points);
  soup->SetPolys(polys);
  const vtkIdType total = 3 * cube->GetNumberOfPolys();
  for (vtkPolyData* mesh : { static_cast<vtkPolyData*>(soup), cube.GetPointer() })
  {
    vtkNew<plodtest::ErrorRecorder> warnings;
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->AddObserver(vtkCommand::WarningEvent, warnings);
    builder->SetInputData(mesh);
    builder->SetFinestLevel(3);
    builder->Update();
    bool named = false;
    for (const std::string& w : warnings->Warnings)
      named = named ||
        w.find(std::to_string(total - cube->GetNumberOfPoints()) + " of " + std::to_string(total) +
          " surface points repeat the position of another point") != std::string::npos;
    EXPECT_EQ(named, mesh == soup.GetPointer()) << (mesh == soup.GetPointer() ? "soup" : "cube");
  }
}

/// A mesh written to a PLY file by vtkPLYWriter (binary or ASCII), in a temporary folder.
std::string WritePLYFile(vtkPolyData* mesh, const std::string& name, bool binary)
{
  const std::string path = (std::filesystem::temp_directory_path() /
    ("plod_builder_" + std::to_string(::getpid()) + "_" + name + ".ply"))
                             .string();
  vtkNew<vtkPLYWriter> writer;
  writer->SetInputData(mesh);
  writer->SetFileName(path.c_str());
  if (binary)
    writer->SetFileTypeToBinary();
  else
    writer->SetFileTypeToASCII();
  writer->Write();
  return path;
}

// The build from a file name reads the file itself (no vtkPolyData): it gives the octree of the
// mesh vtkPLYReader reads from the same file, array for array, with and without normals, in
// binary and ASCII, and for a real scan.
TEST(MultiscaleOctreeBuilder, BuildFromAFileIsTheBuildOfItsMesh)
{
  auto blob = plodtest::MakeBlob(5, 40, 0.2);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(blob);
  normals->SplittingOff();
  normals->Update();
  std::vector<std::string> files = { WritePLYFile(blob, "plain", true),
    WritePLYFile(blob, "ascii", false), WritePLYFile(normals->GetOutput(), "normals", true) };
  const std::string dir = plodtest::DataDir();
  const bool scan = !dir.empty();
  if (scan)
    files.push_back(dir + "/bun_zipper.ply");
  for (const std::string& file : files)
  {
    auto mesh = plodtest::ReadPLY(file);
    ASSERT_TRUE(mesh) << file;
    vtkNew<vtkMultiscaleOctreeBuilder> fromMesh;
    fromMesh->SetInputData(mesh);
    fromMesh->Update();
    vtkNew<plodtest::ErrorRecorder> errors;
    vtkNew<vtkMultiscaleOctreeBuilder> fromFile;
    fromFile->AddObserver(vtkCommand::ErrorEvent, errors);
    fromFile->SetFileName(file.c_str());
    fromFile->Update();
    EXPECT_TRUE(errors->Errors.empty()) << file;
    ASSERT_GT(fromFile->GetOutput()->GetNumberOfNodes(), 0) << file;
    EXPECT_EQ(fromFile->GetNumberOfInputTriangles(), fromMesh->GetNumberOfInputTriangles());
    EXPECT_GE(fromFile->GetReadTime(), 0.0); // wall time: reported, never judged by its size
    ExpectSameOctree(fromMesh->GetOutput(), fromFile->GetOutput(), file);
    if (file.find("plod_builder_") != std::string::npos)
      std::remove(file.c_str());
  }
  if (!scan)
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: the scan was left out";
}

/// The CutState array of an octree a selector or a cutter made.
std::vector<uint8_t> CutStateOf(vtkMultiscaleOctree* cut)
{
  auto* a = vtkUnsignedCharArray::SafeDownCast(
    cut->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  return a ? std::vector<uint8_t>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues())
           : std::vector<uint8_t>();
}

/// The triangles of a polydata as corner coordinates, in no order.
std::multiset<std::array<double, 9>> TrianglesOf(vtkPolyData* pd)
{
  std::multiset<std::array<double, 9>> out;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    pd->GetCellPoints(c, n, ids);
    std::array<double, 9> t{};
    for (int k = 0; k < 3 && k < n; ++k)
    {
      pd->GetPoint(ids[k], &t[3 * k]);
    }
    out.insert(t);
  }
  return out;
}

/// `ply` built in memory and in 3 pieces of level k into an octree file: through the reader,
/// the selector and the patch generator, the file draws the in-core build's cut and triangles
/// (both selectors' minimum level at k) from three distances, the camera placed from the
/// model's root cube with the model in view; a uniform cut at each level above k draws as many
/// triangles as the in-core build's (the same owners; their corners at the file's own vertices
/// of those levels, plodPieceAssembly.h), fewer than at k.
void ExpectPiecesDrawAsTheInCoreBuild(const std::string& ply, int k)
{
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetFileName(ply.c_str());
  builder->Update();
  vtkMultiscaleOctree* inCore = builder->GetOutput();
  ASSERT_GT(inCore->GetNumberOfNodes(), 0);

  plod::PiecesParameters params;
  params.OwnershipLevel = k;
  params.NumberOfPieces = 3;
  plod::PLYPieces pieces;
  std::string why;
  ASSERT_TRUE(pieces.Open(ply, params, &why)) << why;
  ASSERT_EQ(pieces.GetAgreement().FinestLevel, inCore->GetFinestLevel());
  const std::string octreeFile = (std::filesystem::temp_directory_path() /
    ("plod_builder_" + std::to_string(::getpid()) + "_pieces.plod"))
                                   .string();
  ASSERT_TRUE(plod::WriteOctreeFileFromPieces(pieces, octreeFile, {}, nullptr, &why)) << why;
  vtkNew<vtkMultiscaleOctreeReader> reader;
  reader->SetFileName(octreeFile.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetOutput()->GetCoarsestDrawnLevel(), 0) << "the levels above k are drawn";
  ASSERT_EQ(reader->GetOutput()->GetNumberOfNodes(), inCore->GetNumberOfNodes());

  vtkNew<vtkPerceptualLODSelector> whole, built;
  whole->SetInputConnection(builder->GetOutputPort());
  whole->SetMinimumLevel(k);
  built->SetInputConnection(reader->GetOutputPort());
  built->SetMinimumLevel(k);
  vtkNew<vtkMultiscalePatchGenerator> wholePatches, builtPatches;
  wholePatches->SetInputConnection(whole->GetOutputPort());
  builtPatches->SetInputConnection(built->GetOutputPort());
  // the camera from the model's root cube: its centre, at distances in half edges
  double centre[3];
  const double half = 0.5 * inCore->GetRootEdge();
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = inCore->GetOrigin()[a] + half;
  }
  int refined = 0;
  for (double distance : { 2.5, 5.0, 12.0 })
  {
    const double away = distance * half / std::sqrt(1.0 + 0.09 + 0.04);
    const double eye[3] = { centre[0] + 0.3 * away, centre[1] + 0.2 * away, centre[2] + away };
    vtkNew<vtkCamera> camera;
    camera->SetPosition(eye);
    camera->SetFocalPoint(centre);
    camera->SetViewAngle(80);
    double planes[24];
    camera->GetFrustumPlanes(4.0 / 3.0, planes);
    for (vtkPerceptualLODSelector* s : { whole.GetPointer(), built.GetPointer() })
    {
      s->SetEyePosition(eye[0], eye[1], eye[2]);
      s->SetViewAngle(80);
      s->SetFrustumPlanes(planes);
    }
    wholePatches->Update();
    builtPatches->Update();
    EXPECT_EQ(CutStateOf(whole->GetOutput()), CutStateOf(built->GetOutput()))
      << "distance " << distance;
    // the same triangles at the same places (a node's triangles may come in another order)
    vtkPolyData* a = wholePatches->GetOutput();
    vtkPolyData* b = builtPatches->GetOutput();
    EXPECT_GT(a->GetNumberOfCells(), 0);
    EXPECT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells()) << "distance " << distance;
    EXPECT_TRUE(TrianglesOf(a) == TrianglesOf(b)) << "distance " << distance;
    refined += whole->GetNumberOfCutNodes() > 1;
  }
  EXPECT_EQ(refined, 3);
  // uniform cuts above the pieces' level: the in-core build's triangle count, fewer than at k
  vtkNew<vtkMultiscaleOctreeCutter> fileCut, inCoreCut;
  fileCut->SetInputConnection(reader->GetOutputPort());
  inCoreCut->SetInputConnection(builder->GetOutputPort());
  vtkNew<vtkMultiscalePatchGenerator> filePatches, inCorePatches;
  filePatches->SetInputConnection(fileCut->GetOutputPort());
  inCorePatches->SetInputConnection(inCoreCut->GetOutputPort());
  fileCut->SetLevel(k);
  filePatches->Update();
  const vtkIdType atK = filePatches->GetOutput()->GetNumberOfCells();
  for (int l = 0; l < k; ++l)
  {
    fileCut->SetLevel(l);
    inCoreCut->SetLevel(l);
    filePatches->Update();
    inCorePatches->Update();
    EXPECT_EQ(
      filePatches->GetOutput()->GetNumberOfCells(), inCorePatches->GetOutput()->GetNumberOfCells())
      << "level " << l;
    EXPECT_LT(filePatches->GetOutput()->GetNumberOfCells(), atK) << "level " << l;
  }
  std::remove(octreeFile.c_str());
}

// A PLY file built in pieces into an octree file draws what its in-core build draws from level
// k on, and as many triangles above: a generated blob, and the Stanford bunny (a real scan).
// With the model in view: a cell above level k that the frustum culls takes its triangles'
// corners to the file's own vertex of that cell, not to the whole's.
TEST(MultiscaleOctreeBuilder, AFileBuiltInPiecesDrawsAsItsInCoreBuildFromLevelK)
{
  auto blob = plodtest::MakeBlob(7, 160, 0.3);
  const std::string ply = WritePLYFile(blob, "pieces", true);
  ExpectPiecesDrawAsTheInCoreBuild(ply, 3);
  std::remove(ply.c_str());
  const std::string bunny = plodtest::DataDir() + "/bun_zipper.ply";
  struct stat st;
  if (plodtest::DataDir().empty() || stat(bunny.c_str(), &st) != 0)
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: the bunny was left out";
  }
  ExpectPiecesDrawAsTheInCoreBuild(bunny, 4);
}

// With an OctreeFileName, a PLY file too large for the memory limit is built in pieces into that
// file and the output is the file; BuildInPieces builds that way whatever the size; an abort
// leaves no file.
// A model whose finest level is coarser than the pieces' cells (level 6), built in pieces: split
// again at its own level, it gives the in-core build's tree, not an error.
TEST(MultiscaleOctreeBuilder, AModelCoarserThanThePiecesCellsIsSplitAtItsOwnLevel)
{
  auto blob = plodtest::MakeBlob(3, 20, 0.3);
  const std::string ply = WritePLYFile(blob, "coarse-pieces", true);
  const std::string octreeFile = ply + ".plod";
  vtkNew<vtkMultiscaleOctreeBuilder> inCore;
  inCore->SetFileName(ply.c_str());
  inCore->Update();
  ASSERT_LT(inCore->GetOutput()->GetFinestLevel(), 6) << "the model is not coarse enough";
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  vtkNew<plodtest::ErrorRecorder> errors;
  builder->AddObserver(vtkCommand::ErrorEvent, errors);
  builder->SetFileName(ply.c_str());
  builder->SetOctreeFileName(octreeFile.c_str());
  builder->BuildInPiecesOn();
  builder->Update();
  EXPECT_FALSE(errors->HasError()) << "an error for a coarse model";
  vtkMultiscaleOctree* out = builder->GetOutput();
  EXPECT_EQ(out->GetNumberOfNodes(), inCore->GetOutput()->GetNumberOfNodes());
  EXPECT_EQ(out->GetFinestLevel(), inCore->GetOutput()->GetFinestLevel());
  std::remove(octreeFile.c_str());
  std::remove(ply.c_str());
}

TEST(MultiscaleOctreeBuilder, AFileTooLargeForTheLimitIsBuiltInPiecesIntoTheOctreeFile)
{
  auto blob = plodtest::MakeBlob(5, 200, 0.3);
  const std::string ply = WritePLYFile(blob, "too-large", true);
  const std::string octreeFile = ply + ".plod";
  for (bool forced : { false, true })
  {
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    vtkNew<plodtest::ErrorRecorder> errors;
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->AddObserver(vtkCommand::WarningEvent, errors);
    std::vector<double> progress;
    vtkNew<vtkCallbackCommand> watch;
    watch->SetClientData(&progress);
    watch->SetCallback([](vtkObject*, unsigned long, void* d, void* call) {
      static_cast<std::vector<double>*>(d)->push_back(*static_cast<double*>(call));
    });
    builder->AddObserver(vtkCommand::ProgressEvent, watch);
    builder->SetFileName(ply.c_str());
    builder->SetMemoryLimit(forced ? 4096 : 3); // MiB: the in-memory build needs more than 3
    builder->SetBuildInPieces(forced);
    builder->Update();
    if (!forced) // without a file: refused, naming the way; forced: built in memory
    {
      ASSERT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0) << "refused without a file";
      EXPECT_TRUE(errors->HasError("OctreeFileName")) << "the refusal names the way";
    }
    EXPECT_EQ(builder->GetOutput()->GetCoarsestDrawnLevel(), 0);
    builder->SetOctreeFileName(octreeFile.c_str());
    progress.clear();
    builder->Update();
    vtkMultiscaleOctree* out = builder->GetOutput();
    ASSERT_GT(out->GetNumberOfNodes(), 0);
    // the levels above the pieces are built (their octree fits 3 MiB here; where it does not,
    // they hold structure only with a warning: Testing/memory_limit.py)
    EXPECT_EQ(out->GetCoarsestDrawnLevel(), 0);
    EXPECT_EQ(builder->GetNumberOfInputTriangles(), blob->GetNumberOfPolys());
    vtkNew<vtkMultiscaleOctreeReader> reader;
    reader->SetFileName(octreeFile.c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfNodes(), out->GetNumberOfNodes());
    ASSERT_FALSE(progress.empty());
    EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
    EXPECT_EQ(progress.back(), 1.0);
    std::remove(octreeFile.c_str());
  }
  // an abort while building the pieces: an empty octree, a warning, no file
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  vtkNew<plodtest::ErrorRecorder> errors;
  builder->AddObserver(vtkCommand::WarningEvent, errors);
  vtkNew<vtkCallbackCommand> stop;
  stop->SetClientData(builder.GetPointer());
  stop->SetCallback([](vtkObject*, unsigned long, void* d, void* call) {
    if (*static_cast<double*>(call) > 0.5)
      static_cast<vtkMultiscaleOctreeBuilder*>(d)->SetAbortExecute(1);
  });
  builder->AddObserver(vtkCommand::ProgressEvent, stop);
  builder->SetFileName(ply.c_str());
  builder->SetOctreeFileName(octreeFile.c_str());
  builder->BuildInPiecesOn();
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0);
  EXPECT_FALSE(errors->Warnings.empty());
  struct stat st;
  EXPECT_NE(stat(octreeFile.c_str(), &st), 0) << "no file after an abort";
  std::remove(ply.c_str());
}

// A file that cannot fit is refused from its header's counts before a row is read, with what
// would fit; missing files, other formats and an input beside a file name are errors. Each
// gives an empty octree.
TEST(MultiscaleOctreeBuilder, BuildFromAFileRefusesWhatCannotFitOrBeRead)
{
  auto blob = plodtest::MakeBlob(6, 40, 0.2);
  const std::string file = WritePLYFile(blob, "limit", true);
  const long long faces = blob->GetNumberOfPolys();
  struct Case
  {
    std::string Name;
    std::function<void(vtkMultiscaleOctreeBuilder*)> Set;
    std::string Expect;
  };
  const std::string missing = file + ".missing";
  const std::string notPLY = std::string(PLOD_SOURCE_DIR) + "/README.md";
  const std::vector<Case> cases = {
    { "tiny limit",
      [&](vtkMultiscaleOctreeBuilder* b) {
        b->SetFileName(file.c_str());
        b->SetMemoryLimit(0.05);
      },
      "faces: building it in memory needs at least" },
    { "missing", [&](vtkMultiscaleOctreeBuilder* b) { b->SetFileName(missing.c_str()); },
      "cannot open" },
    { "not PLY", [&](vtkMultiscaleOctreeBuilder* b) { b->SetFileName(notPLY.c_str()); },
      "FileName takes a PLY file" },
    { "both",
      [&](vtkMultiscaleOctreeBuilder* b) {
        b->SetFileName(file.c_str());
        b->SetInputData(blob);
      },
      "Both an input and a FileName" },
  };
  for (const Case& c : cases)
  {
    vtkNew<plodtest::ErrorRecorder> errors;
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    c.Set(builder);
    builder->Update();
    EXPECT_TRUE(errors->HasError(c.Expect))
      << c.Name << ": " << (errors->Errors.empty() ? "" : errors->Errors[0]);
    EXPECT_EQ(builder->GetOutput()->GetNumberOfNodes(), 0) << c.Name;
    EXPECT_EQ(builder->GetNumberOfInputTriangles(), 0) << c.Name << ": nothing read";
  }
  // the refusal says how many faces fit: the least need scaled to the limit
  vtkNew<plodtest::ErrorRecorder> errors;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->AddObserver(vtkCommand::ErrorEvent, errors);
  builder->SetFileName(file.c_str());
  builder->SetMemoryLimit(0.05);
  builder->Update();
  ASSERT_EQ(errors->Errors.size(), 1u);
  const std::string& e = errors->Errors[0];
  const size_t at = e.find("at most ");
  ASSERT_NE(at, std::string::npos) << e;
  const long long fit = std::atoll(e.c_str() + at + 8);
  EXPECT_GT(fit, 0) << e;
  EXPECT_LT(fit, faces) << e;
  // and a limit with room builds it
  builder->SetMemoryLimit(64);
  builder->Update();
  EXPECT_GT(builder->GetOutput()->GetNumberOfNodes(), 0);
  std::remove(file.c_str());
}

// The estimates a file's header is judged by, pinned to the schema's bytes: the octree file at
// leaves of four points (8/7 nodes per leaf, a cluster per node), and the least a build needs
// (its estimate at level 1's at most 9 nodes); and the estimate of the bunny's octree is within
// a factor of two of the octree built.
TEST(MultiscaleOctreeBuilder, FileEstimatesFollowTheSchema)
{
  using plod::ArrayGroup;
  const double node =
    double(plod::BytesPer(ArrayGroup::Node) + plod::BytesPer(ArrayGroup::Cluster));
  const double point = double(plod::BytesPer(ArrayGroup::Point));
  const double triangle = double(plod::BytesPer(ArrayGroup::Triangle));
  EXPECT_DOUBLE_EQ(plod::EstimateOctreeBytes(7000, 14000),
    node * (7000.0 / 4 * 8 / 7) + point * 7000 + triangle * 14000);
  EXPECT_DOUBLE_EQ(
    plod::LeastBuildMemory(7000, 14000, false), plod::EstimateBuildMemory(7000, 14000, 9, false));
  EXPECT_LT(
    plod::LeastBuildMemory(7000, 14000, false), plod::EstimateBuildMemory(7000, 14000, 10, false));
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: the bunny was left out";
  }
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetFileName((dir + "/bun_zipper.ply").c_str());
  builder->Update();
  vtkMultiscaleOctree* octree = builder->GetOutput();
  const double built = octree->GetActualMemorySize() * 1024.0;
  const double estimate = plod::EstimateOctreeBytes(
    octree->GetNumberOfSurfacePoints(), octree->GetNumberOfSurfaceTriangles());
  EXPECT_GT(estimate, 0.5 * built);
  EXPECT_LT(estimate, 2.0 * built);
}
