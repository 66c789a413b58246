// SPDX-License-Identifier: BSD-3-Clause
#include "plodPatches.h"

#include <algorithm>
#include <array>
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

  /// Splits a quad along its shorter diagonal; triangles repeating a node are skipped.
  void Quad(const int32_t q[4])
  {
    auto d2 = [this](int32_t x, int32_t y) {
      const float* a = &this->V.Vertex[3 * x];
      const float* b = &this->V.Vertex[3 * y];
      const double d[3] = { double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2] };
      return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    };
    const bool first = d2(q[0], q[2]) <= d2(q[1], q[3]);
    const int32_t t[2][3] = { { q[0], q[1], q[2] }, { q[0], q[2], q[3] } };
    const int32_t u[2][3] = { { q[1], q[2], q[3] }, { q[1], q[3], q[0] } };
    for (int k = 0; k < 2; ++k)
    {
      const int32_t* tri = first ? t[k] : u[k];
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
  // detect coincident vertices of distinct nodes inside a triangle (rare)
  auto same = [&](int64_t a, int64_t b) {
    return std::memcmp(&v.Vertex[3 * out.PointNode[a]], &v.Vertex[3 * out.PointNode[b]],
             3 * sizeof(float)) == 0;
  };
  bool coincident = false;
  for (size_t t = 0; t + 2 < out.Triangles.size() && !coincident; t += 3)
  {
    const int64_t* tri = &out.Triangles[t];
    coincident = same(tri[0], tri[1]) || same(tri[1], tri[2]) || same(tri[0], tri[2]);
  }
  if (!coincident)
  {
    return true;
  }
  // merge: every point maps to the first point with the same position
  struct Hash
  {
    size_t operator()(const std::array<uint32_t, 3>& k) const
    {
      return (size_t(k[0]) * 73856093u) ^ (size_t(k[1]) * 19349663u) ^ (size_t(k[2]) * 83492791u);
    }
  };
  std::unordered_map<std::array<uint32_t, 3>, int64_t, Hash> first;
  std::vector<int64_t> remap(out.PointNode.size());
  std::vector<int64_t> kept;
  for (size_t i = 0; i < out.PointNode.size(); ++i)
  {
    std::array<uint32_t, 3> key;
    std::memcpy(key.data(), &v.Vertex[3 * out.PointNode[i]], sizeof(key));
    auto it = first.find(key);
    if (it == first.end())
    {
      it = first.emplace(key, static_cast<int64_t>(kept.size())).first;
      kept.push_back(out.PointNode[i]);
    }
    else
    {
      ++out.MergedPoints;
    }
    remap[i] = it->second;
  }
  std::vector<int64_t> tris;
  tris.reserve(out.Triangles.size());
  for (size_t t = 0; t + 2 < out.Triangles.size(); t += 3)
  {
    const int64_t a = remap[out.Triangles[t]], b = remap[out.Triangles[t + 1]],
                  c = remap[out.Triangles[t + 2]];
    if (a == b || b == c || a == c)
    {
      ++out.DroppedTriangles;
      continue;
    }
    tris.insert(tris.end(), { a, b, c });
  }
  out.Triangles.swap(tris);
  out.PointNode.swap(kept);
  return true;
}

} // namespace plod
