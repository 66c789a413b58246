// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkMultiscaleOctreeBuilder and vtkMultiscaleOctree: exact small cases, invariants over
// families of random meshes, extremes and bad input, and the Stanford data when present.
#include "plodOctree.h"
#include "plodPatches.h"
#include "plodTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStaticCellLocator.h"
#include "vtkTriangle.h"
#include "vtkTriangleFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace
{
constexpr double Pi = 3.14159265358979323846;

struct Built
{
  vtkSmartPointer<vtkMultiscaleOctree> Octree;
  plod::OctreeView View;
};

Built Build(vtkPolyData* input, int level = -1, int rule = vtkMultiscaleOctreeBuilder::VERTEX_MEAN,
  plodtest::ErrorRecorder* errors = nullptr)
{
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(input);
  builder->SetFinestLevel(level);
  builder->SetVertexRule(rule);
  if (errors)
  {
    builder->AddObserver(vtkCommand::ErrorEvent, errors);
    builder->AddObserver(vtkCommand::WarningEvent, errors);
  }
  builder->Update();
  Built b;
  b.Octree = builder->GetOutput();
  b.Octree->GetView(b.View);
  return b;
}

double Angle(const float* a, const double b[3])
{
  const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0] };
  return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

/// Every finest grid edge's net crossing as seen by each finest cell that holds it.
using EdgeKey = std::tuple<int, int, int, int>; // axis, corner x, y, z
std::map<EdgeKey, int> FinestEdges(const plod::OctreeView& v, bool* consistent)
{
  std::map<EdgeKey, int> edges;
  *consistent = true;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.Level[n] != v.FinestLevel)
    {
      continue;
    }
    int c[3];
    v.CellCoordinates(n, c);
    for (int e = 0; e < 12; ++e)
    {
      const int a = e / 4, p = (a + 1) % 3, q = (a + 2) % 3;
      int corner[3] = { c[0], c[1], c[2] };
      corner[p] += e & 1;
      corner[q] += (e >> 1) & 1;
      const EdgeKey key{ a, corner[0], corner[1], corner[2] };
      const int s = plod::EdgeSign(v.Edges[n], e);
      auto it = edges.find(key);
      if (it == edges.end())
      {
        edges[key] = s;
      }
      else if (it->second != s)
      {
        *consistent = false;
      }
    }
  }
  return edges;
}

/// Invariants every octree must satisfy.
void CheckInvariants(const Built& b, vtkPolyData* input, const std::string& what)
{
  SCOPED_TRACE(what);
  const plod::OctreeView& v = b.View;
  std::string why;
  ASSERT_TRUE(b.Octree->CheckConsistency(&why)) << why;
  ASSERT_GT(v.NumberOfNodes, 0);
  std::vector<int> perLevel(v.FinestLevel + 1, 0);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    ++perLevel[v.Level[n]];
    // leaves only at the finest level: no empty branch
    ASSERT_EQ(v.ChildMask[n] == 0, v.Level[n] == v.FinestLevel) << "node " << n;
    // the cell of a node lies in its parent's cell
    int c[3], pc[3];
    v.CellCoordinates(n, c);
    if (v.Parent[n] >= 0)
    {
      v.CellCoordinates(v.Parent[n], pc);
      for (int a = 0; a < 3; ++a)
      {
        ASSERT_EQ(c[a] >> 1, pc[a]);
      }
      // the parent's cone contains the child's cone (SRCC eq. 2)
      const float* pa = &v.ConeAxis[3 * v.Parent[n]];
      const double ca[3] = { v.ConeAxis[3 * n], v.ConeAxis[3 * n + 1], v.ConeAxis[3 * n + 2] };
      // (a cone of angle pi contains every direction)
      if (v.ConeAngle[v.Parent[n]] < float(Pi))
      {
        ASSERT_LE(Angle(pa, ca) + v.ConeAngle[n], v.ConeAngle[v.Parent[n]] + 1e-5)
          << "cone of node " << n << " not inside its parent's";
      }
      // a parent's edge crossing is the signed sum of its children's halves
    }
    // the vertex lies in the node's closed cell, up to its single-precision storage
    // (relative to the origin: 2^-23 of the root edge)
    const double h = v.CellEdge(v.Level[n]);
    const double tol = 1e-5 * h + std::ldexp(v.RootEdge, -23);
    for (int a = 0; a < 3; ++a)
    {
      ASSERT_GE(v.Vertex[3 * n + a], c[a] * h - tol) << "node " << n;
      ASSERT_LE(v.Vertex[3 * n + a], (c[a] + 1) * h + tol) << "node " << n;
    }
    // unit axes, angles in [0, pi], non-negative shape errors
    const float* ax = &v.ConeAxis[3 * n];
    ASSERT_NEAR(std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]), 1.0, 1e-5);
    ASSERT_GE(v.ConeAngle[n], 0.0f);
    ASSERT_LE(v.ConeAngle[n], float(Pi));
    ASSERT_GE(v.ShapeError[n], 0.0f);
    ASSERT_LE(v.Diffuse[2 * n], v.Diffuse[2 * n + 1]);
  }
  // levels run 0..finest
  for (int l = 0; l <= v.FinestLevel; ++l)
  {
    ASSERT_GT(perLevel[l], 0) << "level " << l << " is empty";
  }
  // parent edge words agree with their children
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (!v.ChildMask[n])
    {
      continue;
    }
    for (int e = 0; e < 12; ++e)
    {
      const int a = e / 4, p = (a + 1) % 3, q = (a + 2) % 3;
      int net = 0;
      for (int ab = 0; ab < 2; ++ab)
      {
        const int child = v.Child(n, (ab << a) | ((e & 1) << p) | (((e >> 1) & 1) << q));
        net += child >= 0 ? plod::EdgeSign(v.Edges[child], e) : 0;
      }
      ASSERT_EQ(plod::EdgeSign(v.Edges[n], e), (net > 0) - (net < 0)) << "node " << n;
    }
  }
  // neighbouring finest cells agree on shared edges
  bool consistent = false;
  FinestEdges(v, &consistent);
  ASSERT_TRUE(consistent) << "finest cells disagree on a shared edge";
  // no empty cell: the input surface (or a cloud point) meets every finest cell's closed box,
  // so it comes within half a diagonal of the cell's centre
  vtkNew<vtkStaticCellLocator> locator;
  const bool mesh = input->GetNumberOfPolys() + input->GetNumberOfStrips() > 0;
  if (mesh)
  {
    locator->SetDataSet(input);
    locator->BuildLocator();
  }
  const double h = v.CellEdge(v.FinestLevel);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.Level[n] != v.FinestLevel)
    {
      continue;
    }
    double bounds[6], centre[3], closest[3], d2 = 0;
    b.Octree->GetNodeBounds(n, bounds);
    for (int a = 0; a < 3; ++a)
    {
      centre[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    }
    if (mesh)
    {
      vtkIdType cell;
      int sub;
      locator->FindClosestPoint(centre, closest, cell, sub, d2);
      ASSERT_LE(std::sqrt(d2), 0.5 * std::sqrt(3.0) * h * (1 + 1e-6)) << "empty finest cell " << n;
    }
    else
    {
      ASSERT_TRUE(v.Edges[n] != 0 || b.Octree->FindNode(centre, v.FinestLevel) == n);
    }
  }
}

/// For a closed surface, the oriented crossings around every finest grid face sum to zero.
void CheckClosedLoops(const plod::OctreeView& v)
{
  bool consistent;
  auto edges = FinestEdges(v, &consistent);
  auto sign = [&](int a, int x, int y, int z) {
    auto it = edges.find(EdgeKey{ a, x, y, z });
    return it == edges.end() ? 0 : it->second;
  };
  int faces = 0;
  for (const auto& kv : edges)
  {
    // faces spanned by the edge's axis a and axis p = a+1, with this edge as the low-p side
    const int a = std::get<0>(kv.first), p = (a + 1) % 3;
    int c[3] = { std::get<1>(kv.first), std::get<2>(kv.first), std::get<3>(kv.first) };
    int ca[3] = { c[0], c[1], c[2] }, cp[3] = { c[0], c[1], c[2] };
    ++ca[a];
    ++cp[p];
    // loop: +a along low p, +p at high a, -a at high p, -p at low a
    const int loop = sign(a, c[0], c[1], c[2]) + sign(p, ca[0], ca[1], ca[2]) -
      sign(a, cp[0], cp[1], cp[2]) - sign(p, c[0], c[1], c[2]);
    // Going round the loop, each crossing is an inside->outside (+) or outside->inside (-)
    // step; a closed surface leaves the loop where it entered it.
    ASSERT_EQ(loop, 0) << "face at axis " << a << " corner " << c[0] << "," << c[1] << ","
                       << c[2];
    ++faces;
  }
  ASSERT_GT(faces, 0);
}
} // namespace

// ---- exact small cases ------------------------------------------------------------------------

TEST(MultiscaleOctreeBuilder, PlaneHasFlatConesZeroShapeErrorAndExactCrossings)
{
  // A unit square at z = 0.3: every normal is +z, every vertex on the plane.
  auto plane = plodtest::MakePlane(0.3);
  Built b = Build(plane, 5);
  const plod::OctreeView& v = b.View;
  CheckInvariants(b, plane, "plane");
  EXPECT_EQ(v.FinestLevel, 5);
  const double h = v.CellEdge(5);
  int crossings = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    EXPECT_FLOAT_EQ(v.ConeAngle[n], 0.0f) << "flat sheet: cone of angle 0";
    EXPECT_NEAR(v.ConeAxis[3 * n + 2], 1.0f, 1e-7);
    EXPECT_NEAR(v.ShapeError[n], 0.0, 1e-6) << "all descendants on the plane";
    EXPECT_NEAR(v.Vertex[3 * n + 2] + v.Origin[2], 0.3, 1e-6);
    // only z edges (8..11) are crossed, all towards +z
    EXPECT_EQ(v.Edges[n] & ~0xF00u, 0u);
    if (v.Level[n] == 5)
    {
      crossings += __builtin_popcount(v.Edges[n]);
    }
  }
  // Each z grid line inside the square crosses it once, and is seen by 4 finest cells.
  int lines = 0;
  const int cells = 1 << 5;
  for (int j = 1; j < cells; ++j)
  {
    for (int k = 1; k < cells; ++k)
    {
      const double x = v.Origin[0] + j * h, y = v.Origin[1] + k * h;
      lines += (x > 0 && x < 1 && y > 0 && y < 1) ? 1 : 0;
    }
  }
  EXPECT_EQ(crossings, 4 * lines);
}

TEST(MultiscaleOctreeBuilder, CubeCrossingsConesAndRoot)
{
  auto cube = plodtest::MakeCube(-1.0, 1.0);
  Built b = Build(cube, 4);
  const plod::OctreeView& v = b.View;
  CheckInvariants(b, cube, "cube");
  CheckClosedLoops(v);
  const double h = v.CellEdge(4);
  // Every grid line through the square cross-section crosses the cube twice: entering through
  // the face with normal -a (negative crossing), leaving through +a (positive).
  int lines = 0;
  for (int a = 0; a < 3; ++a)
  {
    const int p = (a + 1) % 3, q = (a + 2) % 3;
    for (int j = 1; j < 16; ++j)
      for (int k = 1; k < 16; ++k)
      {
        const double y = v.Origin[p] + j * h, z = v.Origin[q] + k * h;
        lines += (std::abs(y) < 1 && std::abs(z) < 1) ? 1 : 0;
      }
  }
  int positive = 0, negative = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.Level[n] != 4)
      continue;
    for (int e = 0; e < 12; ++e)
    {
      const int s = plod::EdgeSign(v.Edges[n], e);
      positive += s > 0;
      negative += s < 0;
    }
  }
  EXPECT_EQ(positive, 4 * lines);
  EXPECT_EQ(negative, 4 * lines);
  // Root: the eight children hold the eight corners; their axes cancel, so theta = pi.
  EXPECT_FLOAT_EQ(v.ConeAngle[0], float(Pi));
  // A level-1 cell holds one corner with three faces: its cone contains the three normals, so
  // theta >= acos(1/sqrt(3)) about the diagonal.
  for (int c = 0; c < 8; ++c)
  {
    const int32_t n = v.Child(0, c);
    ASSERT_GE(n, 0);
    for (int a = 0; a < 3; ++a)
    {
      double normal[3] = { 0, 0, 0 };
      normal[a] = ((c >> a) & 1) ? 1 : -1;
      EXPECT_LE(Angle(&v.ConeAxis[3 * n], normal), v.ConeAngle[n] + 1e-5);
    }
    EXPECT_GE(v.ConeAngle[n], std::acos(1.0 / std::sqrt(3.0)) - 1e-4);
  }
  // Cells inside one face (no cube edge within one cell) are flat: theta = 0, shape error 0.
  int flat = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    double bounds[6];
    b.Octree->GetNodeBounds(n, bounds);
    int touching = 0;
    for (int a = 0; a < 3; ++a)
    {
      touching += (bounds[2 * a] < -1 + 1e-9 && bounds[2 * a + 1] > -1) ||
        (bounds[2 * a] < 1 && bounds[2 * a + 1] > 1 - 1e-9);
    }
    // touching == 1: the cell meets only one face plane
    if (touching == 1 && v.Level[n] >= 2)
    {
      EXPECT_NEAR(v.ConeAngle[n], 0.0, 1e-6);
      EXPECT_NEAR(v.ShapeError[n], 0.0, 1e-6);
      ++flat;
    }
  }
  EXPECT_GT(flat, 0);
}

TEST(MultiscaleOctreeBuilder, TetrahedronFaceCellsHaveFaceNormals)
{
  auto tet = plodtest::MakeTetrahedron();
  Built b = Build(tet, 5);
  const plod::OctreeView& v = b.View;
  CheckInvariants(b, tet, "tetrahedron");
  CheckClosedLoops(v);
  // face normals of the regular tetrahedron, outward
  const double s = 1.0 / std::sqrt(3.0);
  const double normals[4][3] = { { s, s, -s }, { s, -s, s }, { -s, s, s }, { -s, -s, -s } };
  int flat = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.ConeAngle[n] < 1e-6f)
    {
      // a flat cell's axis is one face normal, and its descendants lie on that face
      double best = Pi;
      for (auto& nn : normals)
      {
        best = std::min(best, Angle(&v.ConeAxis[3 * n], nn));
      }
      EXPECT_LT(best, 1e-5);
      EXPECT_NEAR(v.ShapeError[n], 0.0, 1e-6);
      ++flat;
    }
    else
    {
      // a cell on a ridge holds two faces 109.47 degrees apart in normals (dihedral 70.53)
      EXPECT_GE(v.ConeAngle[n], 0.5 * std::acos(-1.0 / 3.0) - 1e-4);
    }
  }
  EXPECT_GT(flat, 100);
  EXPECT_FLOAT_EQ(v.ConeAngle[0], float(Pi));
  // the shape error of the root spans the whole tetrahedron along its axis (at most the
  // diameter 2*sqrt(2), at least the smallest width 4/sqrt(3) minus a cell on each side)
  EXPECT_LE(v.ShapeError[0], 2 * std::sqrt(2.0) + 1e-6);
  EXPECT_GE(v.ShapeError[0], 4 / std::sqrt(3.0) * 0.5);
}

TEST(MultiscaleOctreeBuilder, RoofShapeErrorIsItsHeight)
{
  // z = s|x| over [-1,1]^2: ridge along y. The root's axis is +z by symmetry (up to the
  // root's small shift), its finest vertices span heights [0, s].
  const double s = 0.25;
  auto roof = plodtest::MakeMesh({ -1, -1, s, 0, -1, 0, 0, 1, 0, -1, 1, s, 1, -1, s, 1, 1, s },
    { 0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2 });
  Built b = Build(roof, 6);
  const plod::OctreeView& v = b.View;
  CheckInvariants(b, roof, "roof");
  const double h = v.CellEdge(6);
  EXPECT_NEAR(v.ConeAxis[2], 1.0, 1e-3);
  // the axis tilts by the root's shift (< 1e-3 rad), which adds up to 2e-3 over the width 2
  EXPECT_LE(v.ShapeError[0], s + 2e-3);
  EXPECT_GE(v.ShapeError[0], s - 2 * h * s); // finest vertices within a cell of the rims
  // the root cone contains both face normals, each std::atan(s) from +z
  EXPECT_GE(v.ConeAngle[0], std::atan(s) - 1e-4);
}

TEST(MultiscaleOctreeBuilder, QEFRuleKeepsVerticesOnPlanes)
{
  // Near a cube corner the mean of samples is pulled inside; the QEF vertex sits on the faces.
  auto cube = plodtest::MakeCube(-1.0, 1.0);
  Built mean = Build(cube, 3, vtkMultiscaleOctreeBuilder::VERTEX_MEAN);
  Built qef = Build(cube, 3, vtkMultiscaleOctreeBuilder::VERTEX_QEF);
  CheckInvariants(qef, cube, "cube QEF");
  ASSERT_EQ(mean.View.NumberOfNodes, qef.View.NumberOfNodes);
  double worstMean = 0, worstQEF = 0;
  for (int64_t n = 0; n < qef.View.NumberOfNodes; ++n)
  {
    if (qef.View.Level[n] != 3)
      continue;
    double xq[3], xm[3];
    qef.Octree->GetNodeVertex(n, xq);
    mean.Octree->GetNodeVertex(n, xm);
    // distance to the cube surface: max |x_a| should be 1
    auto dist = [](const double x[3]) {
      return std::abs(std::max({ std::abs(x[0]), std::abs(x[1]), std::abs(x[2]) }) - 1.0);
    };
    worstMean = std::max(worstMean, dist(xm));
    worstQEF = std::max(worstQEF, dist(xq));
  }
  EXPECT_LT(worstQEF, 1e-5);
  EXPECT_GT(worstMean, 1e-2);
}

// ---- invariants over families of random inputs -------------------------------------------------

TEST(MultiscaleOctreeBuilder, InvariantsOverRandomClosedBlobs)
{
  for (unsigned seed = 1; seed <= 6; ++seed)
  {
    auto blob = plodtest::MakeBlob(seed, 12 + 4 * seed, 0.3);
    for (int rule : { 0, 1 })
    {
      Built b = Build(blob, 3 + seed % 4, rule);
      CheckInvariants(b, blob, "blob " + std::to_string(seed));
      CheckClosedLoops(b.View);
    }
  }
}

TEST(MultiscaleOctreeBuilder, InvariantsOverRandomSoups)
{
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    auto soup = plodtest::MakeSoup(seed, 50 * seed, 0.2);
    Built b = Build(soup, 4 + seed % 3);
    CheckInvariants(b, soup, "soup " + std::to_string(seed));
  }
}

TEST(MultiscaleOctreeBuilder, ResultDoesNotDependOnThreads)
{
  auto blob = plodtest::MakeBlob(7, 60, 0.2);
  vtkNew<vtkMultiscaleOctreeBuilder> a, b;
  a->SetInputData(blob);
  b->SetInputData(blob);
  a->MultiThreadedOff();
  b->MultiThreadedOn();
  a->SetFinestLevel(6);
  b->SetFinestLevel(6);
  a->Update();
  b->Update();
  vtkFieldData* fa = a->GetOutput()->GetNodeData();
  vtkFieldData* fb = b->GetOutput()->GetNodeData();
  ASSERT_EQ(fa->GetNumberOfArrays(), fb->GetNumberOfArrays());
  for (int i = 0; i < fa->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* x = fa->GetArray(i);
    vtkDataArray* y = fb->GetArray(x->GetName());
    ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues());
    for (vtkIdType k = 0; k < x->GetNumberOfValues(); ++k)
    {
      ASSERT_EQ(x->GetVariantValue(k), y->GetVariantValue(k)) << x->GetName() << " " << k;
    }
  }
}

// ---- pipeline behaviour ------------------------------------------------------------------------

TEST(MultiscaleOctreeBuilder, ReExecutesOnlyOnChange)
{
  auto blob = plodtest::MakeBlob(3, 20, 0.2);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  builder->Update();
  const vtkMTimeType t0 = builder->GetOutput()->GetMTime();
  builder->Update();
  builder->SetFinestLevel(builder->GetFinestLevel()); // same value: no Modified()
  builder->Update();
  EXPECT_EQ(builder->GetOutput()->GetMTime(), t0);
  builder->SetFinestLevel(3);
  builder->Update();
  EXPECT_GT(builder->GetOutput()->GetMTime(), t0);
  EXPECT_EQ(builder->GetOutput()->GetFinestLevel(), 3);
}

TEST(MultiscaleOctreeBuilder, ShallowAndDeepCopy)
{
  auto blob = plodtest::MakeBlob(2, 16, 0.2);
  Built b = Build(blob, 4);
  vtkNew<vtkMultiscaleOctree> shallow, deep;
  shallow->ShallowCopy(b.Octree);
  deep->DeepCopy(b.Octree);
  EXPECT_EQ(shallow->GetNumberOfNodes(), b.View.NumberOfNodes);
  EXPECT_EQ(deep->GetNumberOfNodes(), b.View.NumberOfNodes);
  EXPECT_EQ(shallow->GetNodeData()->GetArray("Vertex"), b.Octree->GetNodeData()->GetArray("Vertex"));
  EXPECT_NE(deep->GetNodeData()->GetArray("Vertex"), b.Octree->GetNodeData()->GetArray("Vertex"));
  // adding an array to the shallow copy leaves the source alone
  vtkNew<vtkFloatArray> extra;
  extra->SetName("Extra");
  shallow->GetNodeData()->AddArray(extra);
  EXPECT_EQ(b.Octree->GetNodeData()->GetArray("Extra"), nullptr);
  EXPECT_EQ(deep->GetFinestLevel(), 4);
  EXPECT_DOUBLE_EQ(deep->GetRootEdge(), b.Octree->GetRootEdge());
  // 62 bytes of arrays per node, plus the field data's fixed overhead
  EXPECT_LE(double(b.Octree->GetActualMemorySize()) * 1024.0 / b.View.NumberOfNodes, 64.0 + 1e4 / b.View.NumberOfNodes);
}

TEST(MultiscaleOctreeBuilder, NavigationFindsNodesAndChildren)
{
  auto blob = plodtest::MakeBlob(4, 24, 0.2);
  Built b = Build(blob, 5);
  vtkMultiscaleOctree* o = b.Octree;
  for (vtkIdType i = 0; i < blob->GetNumberOfPoints(); i += 7)
  {
    double x[3];
    blob->GetPoint(i, x);
    vtkIdType prev = -1;
    for (int l = 0; l <= 5; ++l)
    {
      const vtkIdType n = o->FindNode(x, l);
      ASSERT_GE(n, 0);
      ASSERT_EQ(o->GetNodeLevel(n), l);
      ASSERT_EQ(o->GetParent(n), prev);
      double bounds[6];
      o->GetNodeBounds(n, bounds);
      for (int a = 0; a < 3; ++a)
      {
        ASSERT_GE(x[a], bounds[2 * a]);
        ASSERT_LE(x[a], bounds[2 * a + 1]);
      }
      if (prev >= 0)
      {
        bool found = false;
        for (int c = 0; c < 8; ++c)
          found = found || o->GetChild(prev, c) == n;
        ASSERT_TRUE(found);
      }
      prev = n;
    }
  }
  const double outside[3] = { 100, 0, 0 };
  EXPECT_EQ(o->FindNode(outside, 2), -1);
  EXPECT_EQ(o->GetChild(-5, 0), -1);
  EXPECT_EQ(o->GetChild(0, 9), -1);
  EXPECT_EQ(o->GetNumberOfChildren(1 << 30), 0);
}

// ---- extremes and bad input --------------------------------------------------------------------

TEST(MultiscaleOctreeBuilder, EmptyInputGivesEmptyOctree)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<plodtest::ErrorRecorder> errors;
  Built b = Build(empty, -1, 0, errors);
  EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);
  EXPECT_TRUE(errors->Errors.empty());
  EXPECT_TRUE(b.Octree->IsConsistent());
}

TEST(MultiscaleOctreeBuilder, SingleTriangle)
{
  auto tri = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0.5 }, { 0, 1, 2 });
  Built b = Build(tri);
  CheckInvariants(b, tri, "single triangle");
  for (int64_t n = 0; n < b.View.NumberOfNodes; ++n)
  {
    EXPECT_NEAR(b.View.ConeAngle[n], 0.0, 1e-6);
  }
}

TEST(MultiscaleOctreeBuilder, DegenerateAndDuplicateTriangles)
{
  // a quad, one triangle repeated, one zero-area triangle, one with repeated vertex
  auto mesh = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 0 },
    { 0, 1, 2, 0, 2, 3, 0, 2, 3, 0, 4, 2, 1, 1, 3 });
  vtkNew<plodtest::ErrorRecorder> errors;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(mesh);
  builder->SetFinestLevel(4);
  builder->AddObserver(vtkCommand::ErrorEvent, errors);
  builder->Update();
  EXPECT_TRUE(errors->Errors.empty());
  EXPECT_EQ(builder->GetNumberOfSkippedTriangles(), 2);
  Built b;
  b.Octree = builder->GetOutput();
  b.Octree->GetView(b.View);
  CheckInvariants(b, mesh, "degenerate");
}

TEST(MultiscaleOctreeBuilder, NonFiniteCoordinatesAreAnError)
{
  for (double bad : { std::nan(""), HUGE_VAL, -HUGE_VAL })
  {
    auto mesh = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 0, bad, 0 }, { 0, 1, 2 });
    vtkNew<plodtest::ErrorRecorder> errors;
    Built b = Build(mesh, -1, 0, errors);
    EXPECT_TRUE(errors->HasError("NaN or infinite")) << bad;
    EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);
  }
}

TEST(MultiscaleOctreeBuilder, InvalidIndicesAndParametersAreErrors)
{
  auto mesh = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0 }, { 0, 1, 7 });
  vtkNew<plodtest::ErrorRecorder> errors;
  Built b = Build(mesh, -1, 0, errors);
  EXPECT_TRUE(errors->HasError("refers to point 7"));
  EXPECT_EQ(b.Octree->GetNumberOfNodes(), 0);

  auto good = plodtest::MakePlane(0);
  for (int level : { -2, 22, 1000 })
  {
    vtkNew<plodtest::ErrorRecorder> e;
    Built x = Build(good, level, 0, e);
    EXPECT_TRUE(e->HasError("FinestLevel")) << level;
    EXPECT_EQ(x.Octree->GetNumberOfNodes(), 0);
  }
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  vtkNew<plodtest::ErrorRecorder> e;
  builder->AddObserver(vtkCommand::ErrorEvent, e);
  builder->SetInputData(good);
  builder->SetMemoryLimit(-1);
  builder->Update();
  EXPECT_TRUE(e->HasError("MemoryLimit"));
}

TEST(MultiscaleOctreeBuilder, OppositeNormalsGiveConeOfPi)
{
  // The same square twice with opposite orientations: normals sum to zero in every cell.
  auto mesh = plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 },
    { 0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2 });
  Built b = Build(mesh, 4);
  for (int64_t n = 0; n < b.View.NumberOfNodes; ++n)
  {
    EXPECT_FLOAT_EQ(b.View.ConeAngle[n], float(Pi)) << n;
    EXPECT_EQ(b.View.Edges[n], 0u) << "opposite sheets cancel";
  }
}

TEST(MultiscaleOctreeBuilder, TinyAndFarModelsKeepTheirPrecision)
{
  struct Case
  {
    double Radius;
    double Centre[3];
  };
  for (const Case& c : { Case{ 1e-6, { 0, 0, 0 } }, Case{ 1.0, { 1e6, -1e6, 1e6 } },
         Case{ 1e-3, { 1e6, 2e6, -3e6 } }, Case{ 1e6, { 0, 0, 0 } } })
  {
    SCOPED_TRACE(c.Radius);
    auto blob = plodtest::MakeBlob(5, 30, 0.0, c.Radius, c.Centre); // a sphere
    Built b = Build(blob, 6);
    CheckInvariants(b, blob, "scaled sphere");
    CheckClosedLoops(b.View);
    const double h = b.View.CellEdge(6);
    EXPECT_NEAR(b.View.RootEdge, 2 * c.Radius * (1 + 2.0 / 32), 1e-3 * c.Radius);
    for (int64_t n = 0; n < b.View.NumberOfNodes; ++n)
    {
      if (b.View.Level[n] != 6)
        continue;
      double x[3];
      b.Octree->GetNodeVertex(n, x);
      const double r = std::sqrt(vtkMath::Distance2BetweenPoints(x, c.Centre));
      // the mean of samples on a chord lies within a cell of the sphere
      ASSERT_NEAR(r, c.Radius, h) << n;
      // the cone axis points outwards
      double out[3];
      for (int a = 0; a < 3; ++a)
        out[a] = (x[a] - c.Centre[a]) / r;
      ASSERT_LT(Angle(&b.View.ConeAxis[3 * n], out), 0.35) << n;
    }
  }
}

TEST(MultiscaleOctreeBuilder, FinestLevelZeroAndMaximum)
{
  auto blob = plodtest::MakeBlob(1, 12, 0.2);
  Built zero = Build(blob, 0);
  ASSERT_EQ(zero.View.NumberOfNodes, 1);
  EXPECT_EQ(zero.View.FinestLevel, 0);
  EXPECT_EQ(zero.View.Parent[0], -1);
  EXPECT_EQ(zero.View.Edges[0], 0u) << "the surface never crosses the root's edges";

  // Level 21 on two tiny triangles one unit apart: cells of 5e-7 units.
  auto tiny = plodtest::MakeMesh({ 0, 0, 0, 1e-6, 0, 0, 0, 1e-6, 1e-7, 1, 1, 1, 1 + 1e-6, 1, 1,
                                   1, 1 + 1e-6, 1 + 1e-7 },
    { 0, 1, 2, 3, 4, 5 });
  Built top = Build(tiny, vtkMultiscaleOctreeBuilder::GetMaximumFinestLevel());
  EXPECT_EQ(top.View.FinestLevel, 21);
  CheckInvariants(top, tiny, "level 21");

  // Level 21 on the blob would need terabytes: a clear error, not a crash.
  vtkNew<plodtest::ErrorRecorder> errors;
  Built huge = Build(blob, 21, 0, errors);
  EXPECT_TRUE(errors->HasError("memory limit"));
  EXPECT_EQ(huge.Octree->GetNumberOfNodes(), 0);
}

TEST(MultiscaleOctreeBuilder, DefaultLevelFollowsEdgeLength)
{
  for (int res : { 16, 64, 256 })
  {
    auto sphere = plodtest::MakeBlob(1, res, 0.0);
    Built b = Build(sphere);
    // median edge ~ 2*pi/res on a unit sphere; root edge ~ 2.125
    const double expected = std::log2(2.125 / (2 * Pi / res * 0.75));
    EXPECT_NEAR(b.View.FinestLevel, expected, 1.01) << res;
  }
}

TEST(MultiscaleOctreeBuilder, QuadsAndStripsAreTriangulated)
{
  auto cube = plodtest::MakeCube(0, 1);
  // The same cube as 6 quads.
  vtkNew<vtkPolyData> quads;
  quads->SetPoints(cube->GetPoints());
  vtkNew<vtkCellArray> cells;
  const vtkIdType q[6][4] = { { 0, 4, 6, 2 }, { 1, 3, 7, 5 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 },
    { 0, 2, 3, 1 }, { 4, 5, 7, 6 } };
  for (auto& f : q)
    cells->InsertNextCell(4, f);
  quads->SetPolys(cells);
  Built a = Build(cube, 4), b = Build(quads, 4);
  ASSERT_EQ(a.View.NumberOfNodes, b.View.NumberOfNodes);
  for (int64_t n = 0; n < a.View.NumberOfNodes; ++n)
    ASSERT_EQ(a.View.Edges[n], b.View.Edges[n]);
  // and as triangle strips (two per face: 0-1-3-2 order)
  vtkNew<vtkPolyData> strips;
  strips->SetPoints(cube->GetPoints());
  vtkNew<vtkCellArray> sc;
  for (auto& f : q)
  {
    const vtkIdType s[4] = { f[1], f[2], f[0], f[3] };
    sc->InsertNextCell(4, s);
  }
  strips->SetStrips(sc);
  Built c = Build(strips, 4);
  CheckClosedLoops(c.View);
  ASSERT_EQ(a.View.NumberOfNodes, c.View.NumberOfNodes);
}

TEST(MultiscaleOctreeBuilder, MaterialFromArrays)
{
  auto blob = plodtest::MakeBlob(8, 24, 0.1);
  vtkNew<vtkFloatArray> kd;
  kd->SetName("kd");
  for (vtkIdType i = 0; i < blob->GetNumberOfPoints(); ++i)
  {
    double x[3];
    blob->GetPoint(i, x);
    kd->InsertNextValue(static_cast<float>(0.5 + 0.4 * (x[2] > 0 ? 1 : -1)));
  }
  blob->GetPointData()->AddArray(kd);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  builder->SetFinestLevel(4);
  builder->SetDiffuseArrayName("kd");
  builder->SetUniformSpecular(0.3);
  builder->Update();
  vtkMultiscaleOctree* o = builder->GetOutput();
  EXPECT_TRUE(o->GetHasMaterialArrays());
  plod::OctreeView v;
  ASSERT_TRUE(o->GetView(v));
  EXPECT_NEAR(v.Diffuse[0], 0.1, 1e-6);
  EXPECT_NEAR(v.Diffuse[1], 0.9, 1e-6);
  EXPECT_NEAR(v.Specular[0], 0.3, 1e-6);
  EXPECT_NEAR(v.Specular[1], 0.3, 1e-6);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    ASSERT_GE(v.Diffuse[2 * n], 0.1f - 1e-6f);
    ASSERT_LE(v.Diffuse[2 * n + 1], 0.9f + 1e-6f);
    if (v.Parent[n] >= 0)
    {
      ASSERT_LE(v.Diffuse[2 * v.Parent[n]], v.Diffuse[2 * n]);
      ASSERT_GE(v.Diffuse[2 * v.Parent[n] + 1], v.Diffuse[2 * n + 1]);
    }
  }
}

// ---- point clouds ------------------------------------------------------------------------------

TEST(MultiscaleOctreeBuilder, PointCloudNormalsAreEstimatedAndOriented)
{
  // points of a sphere without normals: oriented away from the centroid by default, towards
  // the viewpoint when one is given (then they point inwards for a viewpoint at the centre).
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
    vtkMultiscaleOctree* o = builder->GetOutput();
    plod::OctreeView v;
    ASSERT_TRUE(o->GetView(v));
    EXPECT_GE(v.FinestLevel, 3);
    Built b{ o, v };
    CheckInvariants(b, cloud, "cloud");
    int good = 0, total = 0, crossed = 0;
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    {
      if (v.Level[n] != v.FinestLevel)
        continue;
      double x[3];
      o->GetNodeVertex(n, x);
      const double r = vtkMath::Norm(x);
      double out[3] = { x[0] / r, x[1] / r, x[2] / r };
      if (inward)
        vtkMath::MultiplyScalar(out, -1.0);
      good += Angle(&v.ConeAxis[3 * n], out) < 0.5;
      crossed += v.Edges[n] != 0;
      ++total;
    }
    EXPECT_GE(good, 0.98 * total);
    EXPECT_GE(crossed, 0.9 * total) << "signed distance gives crossings around the sphere";
    // the cones of a cloud's octree contain the normals of its finest patches' triangles
    std::vector<uint8_t> cut(v.NumberOfNodes);
    plod::UniformCut(v, v.FinestLevel, cut.data());
    plod::PatchResult patches;
    ASSERT_TRUE(plod::GeneratePatches(v, cut.data(), patches));
    ASSERT_GT(patches.Triangles.size(), 1000u);
    for (size_t k = 0; k + 2 < patches.Triangles.size(); k += 3)
    {
      const int64_t nodes[3] = { patches.PointNode[patches.Triangles[k]],
        patches.PointNode[patches.Triangles[k + 1]], patches.PointNode[patches.Triangles[k + 2]] };
      double p[3][3];
      for (int j = 0; j < 3; ++j)
        for (int a = 0; a < 3; ++a)
          p[j][a] = v.Vertex[3 * nodes[j] + a];
      double n[3];
      vtkTriangle::ComputeNormal(p[0], p[1], p[2], n);
      for (int64_t node : nodes)
        ASSERT_LE(Angle(&v.ConeAxis[3 * node], n), v.ConeAngle[node] + 1e-4) << node;
    }
  }
}

// ---- real data ---------------------------------------------------------------------------------

TEST(MultiscaleOctreeBuilder, StanfordBunnyMesh)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  auto bunny = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  ASSERT_TRUE(bunny);
  EXPECT_EQ(bunny->GetNumberOfPolys(), 69451);
  for (int level : { -1, 8 })
  {
    Built b = Build(bunny, level);
    CheckInvariants(b, bunny, "bunny");
    EXPECT_GE(b.View.FinestLevel, 6);
    // finest vertices are near the input: within a finest cell of some input point's cell
    const double h = b.View.CellEdge(b.View.FinestLevel);
    for (int64_t n = 0; n < b.View.NumberOfNodes; n += 97)
    {
      if (b.View.Level[n] != b.View.FinestLevel)
        continue;
      double x[3];
      b.Octree->GetNodeVertex(n, x);
      double bounds[6];
      b.Octree->GetNodeBounds(n, bounds);
      for (int a = 0; a < 3; ++a)
      {
        ASSERT_GE(x[a], bounds[2 * a] - 1e-6 * h - std::ldexp(b.View.RootEdge, -23));
        ASSERT_LE(x[a], bounds[2 * a + 1] + 1e-6 * h + std::ldexp(b.View.RootEdge, -23));
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
  auto mesh = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(cloud);
  builder->SetViewpointArrayName("ScannerPosition");
  builder->Update();
  vtkMultiscaleOctree* o = builder->GetOutput();
  plod::OctreeView v;
  ASSERT_TRUE(o->GetView(v));
  Built b{ o, v };
  CheckInvariants(b, cloud, "merged scans");
  // The merged scans and the zippered mesh are the same object in the same frame: the scan
  // octree's finest cells are near the mesh, and their normals agree with the mesh octree's.
  Built m = Build(mesh, v.FinestLevel);
  int agree = 0, compared = 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.Level[n] != v.FinestLevel)
      continue;
    double x[3];
    o->GetNodeVertex(n, x);
    const vtkIdType k = m.Octree->FindNode(x, v.FinestLevel);
    if (k < 0 || m.View.ConeAngle[k] > 0.5f)
      continue;
    const double axis[3] = { m.View.ConeAxis[3 * k], m.View.ConeAxis[3 * k + 1],
      m.View.ConeAxis[3 * k + 2] };
    agree += Angle(&v.ConeAxis[3 * n], axis) < Pi / 4;
    ++compared;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GE(agree, 0.9 * compared) << "scan normals oriented towards their scanners";
}
