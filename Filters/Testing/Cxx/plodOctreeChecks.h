// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeChecks.h
 * @brief Brute-force expectations for the octree tests: every property the builder and the patch
 * generator promise, recomputed the slow, obvious way (and with different algorithms where the
 * kernel has a clever one: triangle/box meeting by polygon clipping, components by BFS).
 */
#ifndef plodOctreeChecks_h
#define plodOctreeChecks_h

#include "plodCut.h"
#include "plodOctree.h"
#include "plodPatches.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCommand.h"
#include "vtkDataSetAttributes.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <queue>
#include <set>
#include <string>
#include <vector>

namespace plodcheck
{
constexpr double Pi = 3.14159265358979323846;

struct Built
{
  vtkSmartPointer<vtkMultiscaleOctree> Octree;
  plod::OctreeView View;
};

/// Builds `input` (level -1: chosen by the builder); in the given root cube when `cubeOrigin`
/// is not null.
inline Built Build(vtkPolyData* input, int level = -1,
  int rule = vtkMultiscaleOctreeBuilder::VERTEX_QEF, vtkCommand* errors = nullptr,
  const double* cubeOrigin = nullptr, double cubeEdge = 0)
{
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(input);
  builder->SetFinestLevel(level);
  builder->SetVertexRule(rule);
  if (cubeOrigin)
  {
    builder->UseGivenRootCubeOn();
    builder->SetRootCubeOrigin(cubeOrigin[0], cubeOrigin[1], cubeOrigin[2]);
    builder->SetRootCubeEdge(cubeEdge);
  }
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

inline double Angle(const double a[3], const double b[3])
{
  const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0] };
  return std::atan2(
    std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

inline std::array<double, 3> Get3(const float* p)
{
  return { double(p[0]), double(p[1]), double(p[2]) };
}

/// Cell box of a node, relative to the origin.
inline void NodeBox(const plod::OctreeView& v, int64_t n, double lo[3], double& h)
{
  int c[3];
  v.CellCoordinates(n, c);
  h = v.CellEdge(v.Level[n]);
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = c[a] * h;
  }
}

inline int64_t Ancestor(const plod::OctreeView& v, int64_t n, int level)
{
  while (v.Level[n] > level)
  {
    n = v.Parent[n];
  }
  return n;
}

/// Lowest common ancestor of two nodes.
inline int64_t Common(const plod::OctreeView& v, int64_t a, int64_t b)
{
  while (a != b)
  {
    if (v.Level[a] >= v.Level[b])
      a = v.Parent[a];
    else
      b = v.Parent[b];
  }
  return a;
}

/// The node that owns a triangle: the deepest of its corners' three pairwise common ancestors.
inline int64_t Owner(const plod::OctreeView& v, int64_t t)
{
  const int32_t* c = &v.Triangles[3 * t];
  int64_t best = -1;
  for (int k = 0; k < 3; ++k)
  {
    const int64_t n = Common(v, v.PointLeaf[c[k]], v.PointLeaf[c[(k + 1) % 3]]);
    if (best < 0 || v.Level[n] > v.Level[best])
      best = n;
  }
  return best;
}

/// The cluster of point p in `node` (an ancestor-or-self of its leaf).
inline int64_t ClusterIn(const plod::OctreeView& v, int64_t p, int64_t node)
{
  int64_t c = v.PointCluster[p];
  while (v.ClusterNode[c] != node)
    c = v.ClusterParent[c];
  return c;
}

/// Representative of surface point p in a cut: the cluster holding it in its cut ancestor
/// (>= 0), or -1 - p when its leaf is opened.
inline int64_t Representative(const plod::OctreeView& v, const uint8_t* state, int64_t p)
{
  int64_t n = v.PointLeaf[p];
  while (state[n] == plod::NotInCut)
    n = v.Parent[n];
  return state[n] == plod::CutOpen ? -1 - p : ClusterIn(v, p, n);
}

/// Node of a representative.
inline int64_t NodeOf(const plod::OctreeView& v, int64_t rep)
{
  return rep >= 0 ? v.ClusterNode[rep] : v.PointLeaf[-1 - rep];
}

/// Does the triangle (a, b, c) meet the closed box [lo, lo + h]^3? By clipping the triangle
/// against the six slabs (Sutherland-Hodgman), with a relative tolerance.
inline bool MeetsBox(const double a[3], const double b[3], const double c[3], const double lo[3],
  double h, double tolerance)
{
  std::vector<std::array<double, 3>> poly = { { a[0], a[1], a[2] }, { b[0], b[1], b[2] },
    { c[0], c[1], c[2] } };
  for (int axis = 0; axis < 3 && !poly.empty(); ++axis)
  {
    for (int side = 0; side < 2 && !poly.empty(); ++side)
    {
      const double bound = side ? lo[axis] + h + tolerance : lo[axis] - tolerance;
      auto inside = [&](const std::array<double, 3>& p) {
        return side ? p[axis] <= bound : p[axis] >= bound;
      };
      std::vector<std::array<double, 3>> out;
      for (size_t i = 0; i < poly.size(); ++i)
      {
        const auto& p = poly[i];
        const auto& q = poly[(i + 1) % poly.size()];
        if (inside(p))
          out.push_back(p);
        if (inside(p) != inside(q))
        {
          const double t = (bound - p[axis]) / (q[axis] - p[axis]);
          std::array<double, 3> x;
          for (int k = 0; k < 3; ++k)
            x[k] = p[k] + t * (q[k] - p[k]);
          out.push_back(x);
        }
      }
      poly.swap(out);
    }
  }
  return !poly.empty();
}

/// Unit normal and area of surface triangle t.
inline double Face(const plod::OctreeView& v, int64_t t, double n[3])
{
  const int32_t* c = &v.Triangles[3 * t];
  const auto a = Get3(&v.Points[3 * c[0]]), b = Get3(&v.Points[3 * c[1]]),
             d = Get3(&v.Points[3 * c[2]]);
  const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double e2[3] = { d[0] - a[0], d[1] - a[1], d[2] - a[2] };
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0))
    return 0;
  for (int k = 0; k < 3; ++k)
    n[k] /= len;
  return 0.5 * len;
}

/// For each node, whether its clusters are exactly the connected components of its sub-mesh
/// (BFS over the edges with both ends inside); returns the first node where they are not, or -1.
inline int64_t ClustersAreComponents(const plod::OctreeView& v)
{
  std::vector<std::vector<int32_t>> adjacent(v.NumberOfPoints);
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int32_t a = v.Triangles[3 * t + k], b = v.Triangles[3 * t + (k + 1) % 3];
      adjacent[a].push_back(b);
      adjacent[b].push_back(a);
    }
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const int64_t p0 = v.FirstPoint[n], p1 = v.PointEnd(n);
    std::vector<int64_t> component(p1 - p0, -1);
    int64_t comps = 0;
    for (int64_t p = p0; p < p1; ++p)
    {
      if (component[p - p0] >= 0)
        continue;
      std::vector<int64_t> stack{ p };
      component[p - p0] = comps;
      while (!stack.empty())
      {
        const int64_t x = stack.back();
        stack.pop_back();
        for (int32_t y : adjacent[x])
          if (y >= p0 && y < p1 && component[y - p0] < 0)
          {
            component[y - p0] = comps;
            stack.push_back(y);
          }
      }
      ++comps;
    }
    if (comps != v.ClusterEnd(n) - v.FirstCluster[n])
      return n;
    // same partition: points share a cluster exactly when they share a component
    std::map<int64_t, int64_t> clusterOfComponent;
    for (int64_t p = p0; p < p1; ++p)
    {
      const int64_t c = ClusterIn(v, p, n);
      auto it = clusterOfComponent.insert({ component[p - p0], c }).first;
      if (it->second != c)
        return n;
    }
  }
  return -1;
}

/// Number of nodes that are not a union of discs, by BFS components and V - E + F per node.
inline std::vector<bool> BruteForceSafe(const plod::OctreeView& v)
{
  std::vector<bool> safe(v.NumberOfNodes);
  std::set<std::pair<int32_t, int32_t>> edges;
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int32_t a = v.Triangles[3 * t + k], b = v.Triangles[3 * t + (k + 1) % 3];
      edges.insert({ std::min(a, b), std::max(a, b) });
    }
  std::vector<std::vector<int32_t>> adjacent(v.NumberOfPoints);
  for (const auto& e : edges)
  {
    adjacent[e.first].push_back(e.second);
    adjacent[e.second].push_back(e.first);
  }
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const int64_t p0 = v.FirstPoint[n], p1 = v.PointEnd(n);
    auto inside = [&](int64_t p) { return p >= p0 && p < p1; };
    int64_t V = p1 - p0, E = 0, F = 0, comps = 0;
    for (const auto& e : edges)
      E += inside(e.first) && inside(e.second);
    for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
      F += inside(v.Triangles[3 * t]) && inside(v.Triangles[3 * t + 1]) &&
        inside(v.Triangles[3 * t + 2]);
    std::vector<bool> seen(p1 - p0, false);
    for (int64_t p = p0; p < p1; ++p)
    {
      if (seen[p - p0])
        continue;
      ++comps;
      std::queue<int64_t> q;
      q.push(p);
      seen[p - p0] = true;
      while (!q.empty())
      {
        const int64_t x = q.front();
        q.pop();
        for (int32_t y : adjacent[x])
          if (inside(y) && !seen[y - p0])
          {
            seen[y - p0] = true;
            q.push(y);
          }
      }
    }
    safe[n] = (V - E + F) == comps;
  }
  return safe;
}

/**
 * Every promise of the builder, checked by brute force (for small inputs: the cone check is
 * O(triangles x nodes)). `input` may have dropped triangles (bad indices, repeated points).
 */
inline void CheckOctree(const Built& b, const std::string& what, bool topology = true)
{
  const plod::OctreeView& v = b.View;
  std::string why;
  ASSERT_TRUE(plod::ValidateOctree(v, &why)) << what << ": " << why;
  ASSERT_TRUE(b.Octree->IsConsistent()) << what;
  const double tol = 1e-5 * v.RootEdge;
  // points lie in their leaves; leaves are at the finest level
  for (int64_t p = 0; p < v.NumberOfPoints; ++p)
  {
    double lo[3], h;
    NodeBox(v, v.PointLeaf[p], lo, h);
    for (int a = 0; a < 3; ++a)
    {
      ASSERT_GE(v.Points[3 * p + a], lo[a] - tol) << what << " point " << p;
      ASSERT_LE(v.Points[3 * p + a], lo[a] + h + tol) << what << " point " << p;
    }
    const double len = std::sqrt(double(v.Normals[3 * p]) * v.Normals[3 * p] +
      double(v.Normals[3 * p + 1]) * v.Normals[3 * p + 1] +
      double(v.Normals[3 * p + 2]) * v.Normals[3 * p + 2]);
    ASSERT_NEAR(len, 1.0, 1e-5) << what << " normal of point " << p;
  }
  // triangles belong to their owner, in owner order
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    for (int64_t t = v.FirstTriangle[n]; t < v.TriangleEnd(n); ++t)
      ASSERT_EQ(Owner(v, t), n) << what << " triangle " << t;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const auto axis = Get3(&v.ConeAxis[3 * n]);
    ASSERT_NEAR(std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]), 1.0, 1e-5)
      << what << " node " << n;
    ASSERT_GE(v.ConeAngle[n], 0.0f);
    ASSERT_LE(v.ConeAngle[n], float(Pi) + 1e-6f);

    // the vertices, the cell's and its clusters': inside the cell (QEF is clamped to it; the
    // mean of points inside is inside)
    double lo[3], h;
    NodeBox(v, n, lo, h);
    for (int a = 0; a < 3; ++a)
    {
      ASSERT_GE(v.Vertex[3 * n + a], lo[a] - tol) << what << " vertex of " << n;
      ASSERT_LE(v.Vertex[3 * n + a], lo[a] + h + tol) << what << " vertex of " << n;
      for (int64_t c = v.FirstCluster[n]; c < v.ClusterEnd(n); ++c)
      {
        ASSERT_GE(v.ClusterVertex[3 * c + a], lo[a] - tol) << what << " cluster " << c;
        ASSERT_LE(v.ClusterVertex[3 * c + a], lo[a] + h + tol) << what << " cluster " << c;
      }
    }
    // SRCC eq. (3) per cluster, along its normal, about its vertex; the cell's is the largest
    std::map<int64_t, std::pair<double, double>> spread;
    for (int64_t p = v.FirstPoint[n]; p < v.PointEnd(n); ++p)
    {
      const int64_t c = ClusterIn(v, p, n);
      double d = 0;
      for (int a = 0; a < 3; ++a)
        d += double(v.ClusterNormal[3 * c + a]) *
          (double(v.Points[3 * p + a]) - v.ClusterVertex[3 * c + a]);
      auto it = spread.insert({ c, { d, d } }).first;
      it->second.first = std::min(it->second.first, d);
      it->second.second = std::max(it->second.second, d);
    }
    double error = 0;
    for (const auto& c : spread)
      error = std::max(error, c.second.second - c.second.first);
    ASSERT_NEAR(v.ShapeError[n], error, 1e-4 * v.RootEdge) << what << " node " << n;
  }
  // cones hold the normal of every triangle that meets the cell, and no more: the angle is the
  // largest one to such a normal (up to a hair's contact at a cell face, which either test may
  // count), or pi where the normals cancel
  std::vector<double> reach(v.NumberOfNodes, 0.0), loose(v.NumberOfNodes, 0.0);
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
  {
    double nt[3];
    if (Face(v, t, nt) <= 1e-12 * v.RootEdge * v.RootEdge)
      continue;
    const int32_t* c = &v.Triangles[3 * t];
    const auto a = Get3(&v.Points[3 * c[0]]), bb = Get3(&v.Points[3 * c[1]]),
               d = Get3(&v.Points[3 * c[2]]);
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    {
      double lo[3], h;
      NodeBox(v, n, lo, h);
      const auto axis = Get3(&v.ConeAxis[3 * n]);
      if (MeetsBox(a.data(), bb.data(), d.data(), lo, h, 1e-6 * h + 1e-6 * v.RootEdge))
        loose[n] = std::max(loose[n], Angle(axis.data(), nt));
      if (!MeetsBox(a.data(), bb.data(), d.data(), lo, h, -1e-6 * h))
        continue;
      reach[n] = std::max(reach[n], Angle(axis.data(), nt));
      ASSERT_LE(Angle(axis.data(), nt), v.ConeAngle[n] + 1e-4)
        << what << ": triangle " << t << " meets node " << n << " (level " << int(v.Level[n])
        << ") outside its cone";
    }
  }
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.ConeAngle[n] < Pi - 1e-5)
    {
      ASSERT_LE(v.ConeAngle[n], loose[n] + 1e-4)
        << what << ": node " << n << "'s cone is wider than its normals need";
    }
  }
  ASSERT_EQ(ClustersAreComponents(v), -1) << what << ": clusters are not the components";
  if (topology)
  {
    const std::vector<bool> safe = BruteForceSafe(v);
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      ASSERT_EQ(safe[n], (v.Flags[n] & plod::NodeTopologySafe) != 0) << what << " node " << n;
  }
}

/// A triangle with its corners rotated so that the smallest comes first (orientation kept).
inline std::array<int64_t, 3> Canonical(int64_t a, int64_t b, int64_t c)
{
  if (b < a && b < c)
    return { b, c, a };
  if (c < a && c < b)
    return { c, a, b };
  return { a, b, c };
}

/// The triangles a cut must draw (all drawn cells), by mapping every input triangle's corners.
inline std::multiset<std::array<int64_t, 3>> ExpectedTriangles(
  const plod::OctreeView& v, const uint8_t* state)
{
  std::multiset<std::array<int64_t, 3>> out;
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
  {
    int64_t r[3];
    for (int k = 0; k < 3; ++k)
      r[k] = Representative(v, state, v.Triangles[3 * t + k]);
    if (r[0] != r[1] && r[1] != r[2] && r[0] != r[2])
      out.insert(Canonical(r[0], r[1], r[2]));
  }
  return out;
}

/// The triangles of a patch result, as representatives.
inline std::multiset<std::array<int64_t, 3>> DrawnTriangles(const plod::PatchResult& r)
{
  std::multiset<std::array<int64_t, 3>> out;
  for (size_t k = 0; k + 2 < r.Triangles.size(); k += 3)
    out.insert(Canonical(r.PointSource[r.Triangles[k]], r.PointSource[r.Triangles[k + 1]],
      r.PointSource[r.Triangles[k + 2]]));
  return out;
}

/**
 * Closure of a set of triangles: every undirected edge is used as often in one direction as in
 * the other (a closed, consistently oriented surface, possibly with coincident sheets). Returns
 * the number of edges that break it.
 */
inline int64_t OpenEdges(const std::vector<int64_t>& triangles)
{
  std::map<std::pair<int64_t, int64_t>, int64_t> use;
  for (size_t k = 0; k + 2 < triangles.size(); k += 3)
    for (int e = 0; e < 3; ++e)
    {
      const int64_t a = triangles[k + e], b = triangles[k + (e + 1) % 3];
      if (a < b)
        ++use[{ a, b }];
      else
        --use[{ b, a }];
    }
  int64_t open = 0;
  for (const auto& u : use)
    open += u.second != 0;
  return open;
}

/// Edges used by more than two triangles.
inline int64_t NonManifoldEdges(const std::vector<int64_t>& triangles)
{
  std::map<std::pair<int64_t, int64_t>, int64_t> use;
  for (size_t k = 0; k + 2 < triangles.size(); k += 3)
    for (int e = 0; e < 3; ++e)
    {
      const int64_t a = triangles[k + e], b = triangles[k + (e + 1) % 3];
      ++use[{ std::min(a, b), std::max(a, b) }];
    }
  int64_t bad = 0;
  for (const auto& u : use)
    bad += u.second > 2;
  return bad;
}

/// Level-`level` cell of world point x in the root cube (origin, edge), computed as the builder
/// does: its level-21 cell (clamped into the cube), shifted.
inline std::array<uint32_t, 3> CellOf(
  const double x[3], const double origin[3], double edge, int level)
{
  const double scale = std::ldexp(1.0, plod::MaxFinestLevel) / edge;
  const uint32_t cells = 1u << plod::MaxFinestLevel;
  std::array<uint32_t, 3> c;
  for (int a = 0; a < 3; ++a)
  {
    const double u = (x[a] - origin[a]) * scale;
    c[a] = !(u >= 0) ? 0u : u >= double(cells) ? cells - 1 : static_cast<uint32_t>(u);
    c[a] >>= plod::MaxFinestLevel - level;
  }
  return c;
}

/// One process's piece of a mesh in a distributed rendering (what the plugin's redistribution
/// makes), with the level-k cells it owns and those it holds completely.
struct Piece
{
  vtkSmartPointer<vtkPolyData> Mesh; // all the input's points (unused ones are dropped by the
                                     // builder), the piece's triangles in input order, and the
                                     // point array vtkGhostType
  std::set<std::array<uint32_t, 3>> Owned;    // level-k cells owned
  std::set<std::array<uint32_t, 3>> Complete; // level-k cells held with all their content
};

/**
 * The piece of the process owning the level-`k` cells for which `owns(cell)` is true: every
 * triangle with a corner in an owned cell, plus every triangle meeting a level-k cell those
 * triangles touch (complete copies of the neighbour cells: their points, the triangles at those
 * points, and the triangles passing through them); points outside the owned cells are ghosts
 * (vtkGhostType, bit DUPLICATEPOINT).
 */
template <typename Owns>
Piece MakePiece(vtkPolyData* mesh, const double origin[3], double edge, int k, Owns owns)
{
  Piece piece;
  const vtkIdType np = mesh->GetNumberOfPoints();
  std::vector<std::array<uint32_t, 3>> cell(np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    double x[3];
    mesh->GetPoint(i, x);
    cell[i] = CellOf(x, origin, edge, k);
    if (owns(cell[i]))
      piece.Owned.insert(cell[i]);
  }
  std::vector<std::array<vtkIdType, 3>> tris;
  {
    auto it = vtk::TakeSmartPointer(mesh->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      for (vtkIdType j = 1; j + 1 < n; ++j)
        tris.push_back({ ids[0], ids[j], ids[j + 1] });
    }
  }
  for (const auto& t : tris)
    if (piece.Owned.count(cell[t[0]]) || piece.Owned.count(cell[t[1]]) ||
      piece.Owned.count(cell[t[2]]))
      for (int j = 0; j < 3; ++j)
        piece.Complete.insert(cell[t[j]]);
  const double h = std::ldexp(edge, -k);
  vtkNew<vtkCellArray> polys;
  for (const auto& t : tris)
  {
    bool keep = piece.Complete.count(cell[t[0]]) || piece.Complete.count(cell[t[1]]) ||
      piece.Complete.count(cell[t[2]]);
    double x[3][3];
    for (int j = 0; j < 3; ++j)
      mesh->GetPoint(t[j], x[j]);
    for (auto c = piece.Complete.begin(); !keep && c != piece.Complete.end(); ++c)
    {
      const double lo[3] = { origin[0] + (*c)[0] * h, origin[1] + (*c)[1] * h,
        origin[2] + (*c)[2] * h };
      keep = MeetsBox(x[0], x[1], x[2], lo, h, 1e-9 * edge);
    }
    if (keep)
      polys->InsertNextCell(3, t.data());
  }
  vtkNew<vtkUnsignedCharArray> ghost;
  ghost->SetName(vtkDataSetAttributes::GhostArrayName());
  ghost->SetNumberOfTuples(np);
  for (vtkIdType i = 0; i < np; ++i)
    ghost->SetValue(i, piece.Owned.count(cell[i]) ? 0 : vtkDataSetAttributes::DUPLICATEPOINT);
  piece.Mesh = vtkSmartPointer<vtkPolyData>::New();
  piece.Mesh->SetPoints(mesh->GetPoints());
  piece.Mesh->SetPolys(polys);
  piece.Mesh->GetPointData()->AddArray(ghost);
  return piece;
}

/// Builds `input` in the given root cube at finest level `level`.
inline Built BuildInCube(
  vtkPolyData* input, const double origin[3], double edge, int level, vtkCommand* errors = nullptr)
{
  return Build(input, level, vtkMultiscaleOctreeBuilder::VERTEX_QEF, errors, origin, edge);
}

} // namespace plodcheck

#endif
