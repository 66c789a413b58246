// SPDX-License-Identifier: BSD-3-Clause
#include "plodPatches.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace plod
{

void UniformCut(const OctreeView& v, int level, uint8_t* state)
{
  level = std::max(0, std::min(level, v.FinestLevel));
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    state[n] = v.Level[n] == level ? CutDrawn : NotInCut;
  }
}

void PredicateCut(const OctreeView& v, const std::function<bool(int64_t)>& refine, uint8_t* state)
{
  std::fill(state, state + v.NumberOfNodes, NotInCut);
  if (v.NumberOfNodes == 0)
  {
    return;
  }
  std::vector<int32_t> stack{ 0 };
  while (!stack.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    if (v.ChildMask[n] == 0 || !refine(n))
    {
      state[n] = CutDrawn;
      continue;
    }
    const int count = __builtin_popcount(v.ChildMask[n]);
    for (int c = 0; c < count; ++c)
    {
      stack.push_back(v.FirstChild[n] + c);
    }
  }
}

bool ValidateCut(const OctreeView& v, const uint8_t* state, std::string* why)
{
  // depth-first: count cut ancestors-or-self on the way down
  struct Entry
  {
    int32_t Node;
    int Above;
  };
  if (v.NumberOfNodes == 0)
  {
    return true;
  }
  std::vector<Entry> stack{ { 0, 0 } };
  while (!stack.empty())
  {
    const Entry e = stack.back();
    stack.pop_back();
    const uint8_t s = state[e.Node];
    if (s > CutHidden)
    {
      if (why)
        *why = "node " + std::to_string(e.Node) + " has cut state " + std::to_string(int(s));
      return false;
    }
    const int above = e.Above + (s != NotInCut ? 1 : 0);
    if (above > 1)
    {
      if (why)
        *why = "node " + std::to_string(e.Node) + " is in the cut below another cut node";
      return false;
    }
    if (v.ChildMask[e.Node] == 0)
    {
      if (above == 0)
      {
        if (why)
          *why = "finest cell " + std::to_string(e.Node) + " has no ancestor in the cut";
        return false;
      }
      continue;
    }
    const int count = __builtin_popcount(v.ChildMask[e.Node]);
    for (int c = 0; c < count; ++c)
    {
      stack.push_back({ v.FirstChild[e.Node] + c, above });
    }
  }
  return true;
}

namespace
{

/// Squared relative cross-product length below which a triangle counts as flat (1e-6 squared).
constexpr double ZeroAreaTolerance = 1e-12;

/// Dual contouring walk (cell, face and edge procedures) with the cut cells as leaves.
class Walker
{
public:
  Walker(const OctreeView& v, const uint8_t* state, std::vector<int32_t>& triangles)
    : V(v)
    , State(state)
    , Triangles(triangles)
  {
    this->Triangles.clear();
  }

  bool Leaf(int32_t n) const { return this->State[n] != NotInCut; }

  /// Child `c` of `n`, or `n` itself when it is a leaf of the cut.
  int32_t Sub(int32_t n, int c) const { return this->Leaf(n) ? n : this->V.Child(n, c); }

  void Cell(int32_t n)
  {
    if (n < 0 || this->Failed)
    {
      return;
    }
    ++this->Visited;
    if (this->Leaf(n))
    {
      return;
    }
    if (this->V.ChildMask[n] == 0)
    {
      this->Failed = true;
      this->FailedNode = n;
      return;
    }
    int32_t c[8];
    for (int i = 0; i < 8; ++i)
    {
      c[i] = this->V.Child(n, i);
    }
    for (int i = 0; i < 8; ++i)
    {
      this->Cell(c[i]);
    }
    for (int a = 0; a < 3; ++a)
    {
      const int p = (a + 1) % 3, q = (a + 2) % 3;
      for (int pb = 0; pb < 2; ++pb)
        for (int qb = 0; qb < 2; ++qb)
        {
          const int lo = (pb << p) | (qb << q);
          this->Face(c[lo], c[lo | (1 << a)], a);
        }
      for (int ab = 0; ab < 2; ++ab)
      {
        const int32_t e[4] = { c[(ab << a)], c[(ab << a) | (1 << p)],
          c[(ab << a) | (1 << p) | (1 << q)], c[(ab << a) | (1 << q)] };
        this->Edge(e, a);
      }
    }
  }

  /// Face between n0 (lower along a) and n1 (upper).
  void Face(int32_t n0, int32_t n1, int a)
  {
    if (n0 < 0 || n1 < 0 || (this->Leaf(n0) && this->Leaf(n1)))
    {
      return;
    }
    const int p = (a + 1) % 3, q = (a + 2) % 3;
    int32_t s0[2][2], s1[2][2]; // [pb][qb]
    for (int pb = 0; pb < 2; ++pb)
      for (int qb = 0; qb < 2; ++qb)
      {
        s0[pb][qb] = this->Sub(n0, (1 << a) | (pb << p) | (qb << q));
        s1[pb][qb] = this->Sub(n1, (pb << p) | (qb << q));
        this->Face(s0[pb][qb], s1[pb][qb], a);
      }
    // edges along p inside the face: cells around it in the (q, a) plane
    for (int pb = 0; pb < 2; ++pb)
    {
      const int32_t e[4] = { s0[pb][0], s0[pb][1], s1[pb][1], s1[pb][0] };
      this->Edge(e, p);
    }
    // edges along q inside the face: cells around it in the (a, p) plane
    for (int qb = 0; qb < 2; ++qb)
    {
      const int32_t e[4] = { s0[0][qb], s1[0][qb], s1[1][qb], s0[1][qb] };
      this->Edge(e, q);
    }
  }

  /// Edge along a; n[0..3] at (p-,q-), (p+,q-), (p+,q+), (p-,q+) around it.
  void Edge(const int32_t n[4], int a)
  {
    if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[3] < 0)
    {
      return;
    }
    // the corner of cell i that touches the edge: (pbit, qbit)
    static const int pbit[4] = { 1, 0, 0, 1 };
    static const int qbit[4] = { 1, 1, 0, 0 };
    const int p = (a + 1) % 3, q = (a + 2) % 3;
    if (this->Leaf(n[0]) && this->Leaf(n[1]) && this->Leaf(n[2]) && this->Leaf(n[3]))
    {
      // the minimal edge is the edge of the deepest of the four leaves
      int deepest = 0;
      for (int i = 1; i < 4; ++i)
      {
        if (this->V.Level[n[i]] > this->V.Level[n[deepest]])
        {
          deepest = i;
        }
      }
      const int sign = EdgeSign(
        this->V.Edges[n[deepest]], EdgeIndex(a, pbit[deepest], qbit[deepest]));
      if (sign == 0)
      {
        return;
      }
      if (this->State[n[0]] != CutDrawn && this->State[n[1]] != CutDrawn &&
        this->State[n[2]] != CutDrawn && this->State[n[3]] != CutDrawn)
      {
        return; // every cell around the edge is hidden
      }
      const int32_t quad[4] = { n[0], sign > 0 ? n[1] : n[3], n[2], sign > 0 ? n[3] : n[1] };
      this->Quad(quad);
      return;
    }
    for (int ab = 0; ab < 2; ++ab)
    {
      int32_t s[4];
      for (int i = 0; i < 4; ++i)
      {
        s[i] = this->Sub(n[i], (ab << a) | (pbit[i] << p) | (qbit[i] << q));
      }
      this->Edge(s, a);
    }
  }

  /// Twice the area of triangle (a, b, c) of node vertices.
  double Area2(int32_t a, int32_t b, int32_t c) const
  {
    const float* x = &this->V.Vertex[3 * a];
    const float* y = &this->V.Vertex[3 * b];
    const float* z = &this->V.Vertex[3 * c];
    const double u[3] = { double(y[0]) - x[0], double(y[1]) - x[1], double(y[2]) - x[2] };
    const double w[3] = { double(z[0]) - x[0], double(z[1]) - x[1], double(z[2]) - x[2] };
    const double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
      u[0] * w[1] - u[1] * w[0] };
    return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }

  /**
   * Splits a quad into two triangles along the diagonal that gives no zero-area triangle
   * (on flat regions the mean vertices can make three corners collinear), the shorter one when
   * both do. Triangles repeating a node (a leaf met twice around the edge) are skipped.
   */
  void Quad(const int32_t q[4])
  {
    auto d2 = [this](int32_t x, int32_t y) {
      const float* a = &this->V.Vertex[3 * x];
      const float* b = &this->V.Vertex[3 * y];
      const double d[3] = { double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2] };
      return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    };
    const int32_t t[2][2][3] = { { { q[0], q[1], q[2] }, { q[0], q[2], q[3] } },
      { { q[1], q[2], q[3] }, { q[1], q[3], q[0] } } };
    auto flat = [this](const int32_t* tri) {
      return tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] &&
        this->Area2(tri[0], tri[1], tri[2]) == 0.0;
    };
    const bool flat0 = flat(t[0][0]) || flat(t[0][1]);
    const bool flat1 = flat(t[1][0]) || flat(t[1][1]);
    const int split = flat0 != flat1 ? (flat0 ? 1 : 0) : (d2(q[0], q[2]) <= d2(q[1], q[3]) ? 0 : 1);
    for (int k = 0; k < 2; ++k)
    {
      const int32_t* tri = t[split][k];
      if (tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2])
      {
        this->Triangles.insert(this->Triangles.end(), tri, tri + 3);
      }
    }
  }

  const OctreeView& V;
  const uint8_t* State;
  std::vector<int32_t>& Triangles; // node indices
  int64_t Visited = 0;
  bool Failed = false;
  int32_t FailedNode = -1;
};

} // namespace

bool GeneratePatches(const OctreeView& v, const uint8_t* state, PatchResult& out,
  std::string* why, PatchWorkspace* workspace)
{
  out.PointNode.clear();
  out.Triangles.clear();
  out.NodesVisited = out.MergedPoints = out.DroppedTriangles = 0;
  if (v.NumberOfNodes == 0)
  {
    return true;
  }
  PatchWorkspace local;
  PatchWorkspace& ws = workspace ? *workspace : local;
  Walker w(v, state, ws.NodeTriangles);
  w.Cell(0);
  out.NodesVisited = w.Visited;
  if (w.Failed)
  {
    if (why)
    {
      *why = "finest cell " + std::to_string(w.FailedNode) + " has no ancestor in the cut";
    }
    return false;
  }
  // output points: one per node used, in order of first use (a per-node index, reset after)
  if (static_cast<int64_t>(ws.PointOf.size()) != v.NumberOfNodes)
  {
    ws.PointOf.assign(v.NumberOfNodes, -1);
  }
  out.Triangles.resize(w.Triangles.size());
  for (size_t i = 0; i < w.Triangles.size(); ++i)
  {
    const int32_t node = w.Triangles[i];
    int32_t& point = ws.PointOf[node];
    if (point < 0)
    {
      point = static_cast<int32_t>(out.PointNode.size());
      out.PointNode.push_back(node);
    }
    out.Triangles[i] = point;
  }
  for (int64_t node : out.PointNode)
  {
    ws.PointOf[node] = -1;
  }
  // Degenerate triangles of distinct points (rare): coincident vertices, or three collinear
  // vertices (flat regions, ridges). Both are resolved by identifying points, which keeps every
  // edge's parity (a simplicial map sends a closed surface to a closed surface): coincident
  // points become one, and the middle point of a collinear triple joins its nearer end.
  auto position = [&](int64_t point) { return &v.Vertex[3 * out.PointNode[point]]; };
  // "zero area" at single precision: |cross| below 1e-6 of the longest side squared, so that a
  // triangle flat in the float output coordinates is caught whatever their rounding
  auto zeroArea = [&](int64_t a, int64_t b, int64_t c) {
    const float* x = position(a);
    const float* y = position(b);
    const float* z = position(c);
    const double u[3] = { double(y[0]) - x[0], double(y[1]) - x[1], double(y[2]) - x[2] };
    const double w[3] = { double(z[0]) - x[0], double(z[1]) - x[1], double(z[2]) - x[2] };
    const double r[3] = { w[0] - u[0], w[1] - u[1], w[2] - u[2] };
    const double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
      u[0] * w[1] - u[1] * w[0] };
    const double longest = std::max({ u[0] * u[0] + u[1] * u[1] + u[2] * u[2],
      w[0] * w[0] + w[1] * w[1] + w[2] * w[2], r[0] * r[0] + r[1] * r[1] + r[2] * r[2] });
    return n[0] * n[0] + n[1] * n[1] + n[2] * n[2] <= ZeroAreaTolerance * longest * longest;
  };
  bool degenerate = false;
  for (size_t t = 0; t + 2 < out.Triangles.size() && !degenerate; t += 3)
  {
    const int64_t* tri = &out.Triangles[t];
    degenerate = zeroArea(tri[0], tri[1], tri[2]);
  }
  if (!degenerate)
  {
    return true;
  }
  const int64_t np = static_cast<int64_t>(out.PointNode.size());
  std::vector<int64_t> rep(np);
  for (int64_t i = 0; i < np; ++i)
  {
    rep[i] = i;
  }
  auto find = [&](int64_t x) {
    while (rep[x] != x)
    {
      rep[x] = rep[rep[x]];
      x = rep[x];
    }
    return x;
  };
  // 1. coincident positions
  struct Hash
  {
    size_t operator()(const std::array<uint32_t, 3>& k) const
    {
      return (size_t(k[0]) * 73856093u) ^ (size_t(k[1]) * 19349663u) ^ (size_t(k[2]) * 83492791u);
    }
  };
  std::unordered_map<std::array<uint32_t, 3>, int64_t, Hash> first;
  for (int64_t i = 0; i < np; ++i)
  {
    std::array<uint32_t, 3> key;
    std::memcpy(key.data(), position(i), sizeof(key));
    auto it = first.emplace(key, i).first;
    if (it->second != i)
    {
      rep[i] = it->second;
      ++out.MergedPoints;
    }
  }
  // 2. collinear triples, until none is left (each pass removes points, so this ends)
  for (bool changed = true; changed;)
  {
    changed = false;
    for (size_t t = 0; t + 2 < out.Triangles.size(); t += 3)
    {
      const int64_t p[3] = { find(out.Triangles[t]), find(out.Triangles[t + 1]),
        find(out.Triangles[t + 2]) };
      if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2] || !zeroArea(p[0], p[1], p[2]))
      {
        continue;
      }
      // the middle point is the one opposite the longest side
      auto d2 = [&](int64_t a, int64_t b) {
        const float* x = position(a);
        const float* y = position(b);
        return (double(x[0]) - y[0]) * (double(x[0]) - y[0]) +
          (double(x[1]) - y[1]) * (double(x[1]) - y[1]) +
          (double(x[2]) - y[2]) * (double(x[2]) - y[2]);
      };
      const double side[3] = { d2(p[1], p[2]), d2(p[2], p[0]), d2(p[0], p[1]) };
      const int mid = side[0] >= side[1] && side[0] >= side[2] ? 0 : (side[1] >= side[2] ? 1 : 2);
      const int64_t m = p[mid], e1 = p[(mid + 1) % 3], e2 = p[(mid + 2) % 3];
      rep[m] = d2(m, e1) <= d2(m, e2) ? e1 : e2;
      ++out.MergedPoints;
      changed = true;
    }
  }
  // compact: keep the representatives that are still used
  std::vector<int64_t> newIndex(np, -1);
  std::vector<int64_t> kept;
  std::vector<int64_t> tris;
  tris.reserve(out.Triangles.size());
  for (size_t t = 0; t + 2 < out.Triangles.size(); t += 3)
  {
    int64_t p[3];
    for (int k = 0; k < 3; ++k)
    {
      p[k] = find(out.Triangles[t + k]);
    }
    if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2])
    {
      ++out.DroppedTriangles;
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      if (newIndex[p[k]] < 0)
      {
        newIndex[p[k]] = static_cast<int64_t>(kept.size());
        kept.push_back(out.PointNode[p[k]]);
      }
      tris.push_back(newIndex[p[k]]);
    }
  }
  out.Triangles.swap(tris);
  out.PointNode.swap(kept);
  return true;
}

} // namespace plod
