// SPDX-License-Identifier: BSD-3-Clause
// Provenance: Wakatsuki et al. 2003 (SRCC) §2, multiscale patches from a cut; drawn here by
// vertex clustering over the octree with triangles stored where they collapse (Luebke &
// Erikson 1997, "View-dependent simplification of arbitrary polygonal environments").
#include "plodPatches.h"

#include <algorithm>
#include <cassert>

namespace plod
{

namespace
{
/// The drawn triangle of representatives `rep`: corners, their normals, its face normal.
struct Drawn
{
  const float* X[3];
  const float* N[3];
  double F[3];
  Drawn(const OctreeView& v, const int64_t rep[3])
  {
    for (int k = 0; k < 3; ++k)
    {
      if (rep[k] >= 0)
      {
        this->X[k] = &v.ClusterVertex[3 * rep[k]];
        this->N[k] = &v.ClusterNormal[3 * rep[k]];
      }
      else
      {
        this->X[k] = &v.Points[3 * (-1 - rep[k])];
        this->N[k] = &v.Normals[3 * (-1 - rep[k])];
      }
    }
    const double e1[3] = { double(this->X[1][0]) - this->X[0][0],
      double(this->X[1][1]) - this->X[0][1], double(this->X[1][2]) - this->X[0][2] };
    const double e2[3] = { double(this->X[2][0]) - this->X[0][0],
      double(this->X[2][1]) - this->X[0][1], double(this->X[2][2]) - this->X[0][2] };
    this->F[0] = e1[1] * e2[2] - e1[2] * e2[1];
    this->F[1] = e1[2] * e2[0] - e1[0] * e2[2];
    this->F[2] = e1[0] * e2[1] - e1[1] * e2[0];
  }
  /// Turned over: the face normal opposes the normals of all three corners.
  bool TurnedOver() const
  {
    for (int k = 0; k < 3; ++k)
    {
      if (this->F[0] * this->N[k][0] + this->F[1] * this->N[k][1] + this->F[2] * this->N[k][2] >= 0)
      {
        return false;
      }
    }
    return true;
  }
  /// Facing away from the eye (or along the projection direction).
  bool FacesAway(const PatchOptions& o) const
  {
    double d[3];
    for (int a = 0; a < 3; ++a)
    {
      d[a] = o.Parallel ? -o.ProjectionDirection[a] : o.Eye[a] - double(this->X[0][a]);
    }
    return this->F[0] * d[0] + this->F[1] * d[1] + this->F[2] * d[2] < 0;
  }
};
}

bool GeneratePatches(const OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
  PatchResult& out, std::string* why, PatchWorkspace* workspace, const PatchOptions& options)
{
  out.PointSource.clear();
  out.Triangles.clear();
  out.NodesVisited = 0;
  out.HiddenSkipped = 0;
  out.Folds = 0;
  out.BackFacesCulled = 0;
  out.GhostSkipped = 0;
  out.ReversedNormals.clear();
  if (v.NumberOfNodes == 0)
  {
    return true;
  }
  PatchWorkspace local;
  PatchWorkspace& ws = workspace ? *workspace : local;
  if (static_cast<int64_t>(ws.OutputOf.size()) != v.NumberOfClusters ||
    static_cast<int64_t>(ws.Reached.size()) != v.NumberOfNodes)
  {
    ws.OutputOf.assign(v.NumberOfClusters, -1);
    ws.Reached.assign(v.NumberOfNodes, 0);
    ws.Touched.clear();
    ws.TouchedClusters.clear();
  }
  std::string error;
  auto fail = [&error](const std::string& text) {
    if (error.empty())
    {
      error = text;
    }
  };

  // the representative of surface point p: the cluster holding it in its cut ancestor-or-self,
  // or p itself in an opened leaf
  // (every index followed is checked: arrays edited after validation cannot make it read out
  // of bounds or loop)
  auto representative = [&](int32_t p, bool& drawn, uint8_t& mask, bool& backFacing) -> int64_t {
    if (p < 0 || p >= v.NumberOfPoints)
    {
      fail("a triangle refers to point " + std::to_string(p) + ", outside the surface");
      return -1;
    }
    int64_t c = v.PointCluster[p];
    int64_t n = c >= 0 && c < v.NumberOfClusters ? v.ClusterNode[c] : -1;
    while (n >= 0 && n < v.NumberOfNodes && state[n] == NotInCut)
    {
      const int64_t parent = v.ClusterParent[c];
      if (parent < 0 || parent >= c)
      {
        fail("surface point " + std::to_string(p) + " has no ancestor in the cut");
        return -1;
      }
      c = parent;
      n = v.ClusterNode[c];
    }
    if (n < 0 || n >= v.NumberOfNodes)
    {
      fail("surface point " + std::to_string(p) + " has a cluster outside the arrays");
      return -1;
    }
    if (!ws.Reached[n])
    {
      fail("node " + std::to_string(n) + " is in the cut below another cut node");
      return -1;
    }
    const uint8_t s = state[n];
    drawn = IsDrawnState(s);
    if (s == CutHidden)
    {
      mask = cullMask ? cullMask[n] : 0;
      backFacing = !cullMask || cullMask[n] == 0;
    }
    return s == CutOpen ? -1 - int64_t(p) : c;
  };
  auto outputPoint = [&](int64_t rep) -> int64_t {
    if (rep >= 0)
    {
      int32_t& id = ws.OutputOf[rep];
      if (id < 0)
      {
        id = static_cast<int32_t>(out.PointSource.size());
        out.PointSource.push_back(rep);
        ws.TouchedClusters.push_back(static_cast<int32_t>(rep));
      }
      return id;
    }
    // an opened leaf's points get a block of outputs, keyed by the leaf's first cluster
    const int64_t p = -1 - rep;
    const int32_t leaf = v.PointLeaf[p];
    if (leaf < 0 || leaf >= v.NumberOfNodes || v.FirstCluster[leaf] < 0 ||
      v.FirstCluster[leaf] >= v.NumberOfClusters || v.FirstPoint[leaf] > p ||
      v.PointEnd(leaf) > v.NumberOfPoints)
    {
      fail("surface point " + std::to_string(p) + " has a leaf outside the arrays");
      return int64_t(0);
    }
    int32_t& base = ws.OutputOf[v.FirstCluster[leaf]];
    if (base < 0)
    {
      base = static_cast<int32_t>(out.PointSource.size());
      for (int64_t q = v.FirstPoint[leaf], end = v.PointEnd(leaf); q < end; ++q)
      {
        out.PointSource.push_back(-1 - q);
      }
      ws.TouchedClusters.push_back(v.FirstCluster[leaf]);
    }
    return base + (p - v.FirstPoint[leaf]);
  };
  auto emitOwned = [&](int64_t node) {
    const int64_t begin = std::max<int64_t>(0, v.FirstTriangle[node]);
    const int64_t end = std::min<int64_t>(v.NumberOfTriangles, v.TriangleEnd(node));
    for (int64_t t = begin; t < end; ++t)
    {
      const int32_t* c = &v.Triangles[3 * t];
      if (v.PointGhost)
      {
        // another process draws it: the owner of its lead corner (an index out of range is
        // left to the representative lookup, which reports it)
        const int32_t lead = std::min({ c[0], c[1], c[2] });
        if (lead >= 0 && lead < v.NumberOfPoints && v.PointGhost[lead] != 0)
        {
          ++out.GhostSkipped;
          continue;
        }
      }
      int64_t rep[3];
      bool drawn = false, backFacing = false;
      uint8_t masks = 0x3f;
      for (int k = 0; k < 3; ++k)
      {
        bool d = false, back = false;
        uint8_t m = 0;
        rep[k] = representative(c[k], d, m, back);
        drawn = drawn || d;
        backFacing = backFacing || back;
        if (!d)
        {
          masks &= m;
        }
      }
      if (!error.empty())
      {
        return;
      }
      if (rep[0] == rep[1] || rep[1] == rep[2] || rep[0] == rep[2])
      {
        continue; // collapsed (only with an inconsistent owner; never for a valid octree)
      }
      if (!drawn && (backFacing || masks != 0))
      {
        ++out.HiddenSkipped;
        continue;
      }
      if (options.Folds != FoldHandling::Keep || options.CullBackFaces)
      {
        const Drawn tri(v, rep);
        const bool fold = options.Folds != FoldHandling::Keep &&
          (rep[0] >= 0 || rep[1] >= 0 || rep[2] >= 0) && tri.TurnedOver();
        if (fold && options.Folds == FoldHandling::Drop)
        {
          ++out.Folds;
          continue;
        }
        if (options.CullBackFaces && tri.FacesAway(options))
        {
          ++out.BackFacesCulled;
          continue;
        }
        if (fold)
        {
          // its own corners, at the same places, with reversed normals
          ++out.Folds;
          for (int k = 0; k < 3; ++k)
          {
            const int64_t id = static_cast<int64_t>(out.PointSource.size());
            out.ReversedNormals.push_back(static_cast<int32_t>(id));
            out.Triangles.push_back(id);
            out.PointSource.push_back(rep[k]);
          }
          continue;
        }
      }
      for (int k = 0; k < 3; ++k)
      {
        out.Triangles.push_back(outputPoint(rep[k]));
      }
    }
  };

  // the walk: refined nodes emit their triangles; cut nodes are marked as reached
  std::vector<int32_t>& stack = ws.Stack;
  stack.clear();
  stack.push_back(0);
  std::vector<int32_t>& refined = ws.Refined;
  refined.clear();
  while (!stack.empty() && error.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    ++out.NodesVisited;
    const uint8_t s = state[n];
    if (s > CutOpen)
    {
      fail("node " + std::to_string(n) + " has cut state " + std::to_string(int(s)) +
        " (valid states are 0 to 3)");
      break;
    }
    if (s != NotInCut)
    {
      if (s == CutOpen && !v.IsLeaf(n))
      {
        fail("node " + std::to_string(n) + " is opened but is not a leaf");
        break;
      }
      ws.Reached[n] = 1;
      ws.Touched.push_back(n);
      if (s == CutOpen)
      {
        refined.push_back(n);
      }
      continue;
    }
    if (v.IsLeaf(n))
    {
      fail("leaf " + std::to_string(n) + " has no ancestor in the cut");
      break;
    }
    refined.push_back(n);
    const int count = __builtin_popcount(v.ChildMask[n]);
    const int32_t first = v.FirstChild[n];
    if (first <= n || first + count > v.NumberOfNodes)
    {
      fail("node " + std::to_string(n) + " has children outside the node arrays");
      break;
    }
    for (int c = count - 1; c >= 0; --c)
    {
      stack.push_back(first + c);
    }
  }
  // every cut node is marked before the first triangle looks for its representatives
  for (size_t i = 0; i < refined.size() && error.empty(); ++i)
  {
    emitOwned(refined[i]);
  }
  for (int32_t n : ws.Touched)
  {
    ws.Reached[n] = 0;
  }
  for (int32_t c : ws.TouchedClusters)
  {
    ws.OutputOf[c] = -1;
  }
  ws.Touched.clear();
  ws.TouchedClusters.clear();
  if (!error.empty())
  {
    out.PointSource.clear();
    out.Triangles.clear();
    if (why)
    {
      *why = error;
    }
    return false;
  }
#ifndef NDEBUG
  // internal invariants (debug builds): every corner is an output point, no triangle collapsed
  for (size_t t = 0; t + 2 < out.Triangles.size(); t += 3)
  {
    const int64_t* c = &out.Triangles[t];
    for (int k = 0; k < 3; ++k)
      assert(c[k] >= 0 && c[k] < int64_t(out.PointSource.size()));
    assert(c[0] != c[1] && c[1] != c[2] && c[0] != c[2]);
  }
#endif
  return true;
}

} // namespace plod
