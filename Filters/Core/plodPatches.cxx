// SPDX-License-Identifier: BSD-3-Clause
// Provenance: Wakatsuki et al. 2003 (SRCC) §2, multiscale patches from a cut; drawn here by
// vertex clustering over the octree with triangles stored where they collapse (Luebke &
// Erikson 1997, "View-dependent simplification of arbitrary polygonal environments").
#include "plodPatches.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <limits>
#include <utility>

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
    FaceNormal(this->X[0], this->X[1], this->X[2], this->F);
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
    return plod::FacesAway(this->F, this->X[0], o.Eye, o.Parallel, o.ProjectionDirection);
  }
};

using Decision = PatchDecision;

/// Decides the owned triangles of a cut (read-only: any number of them run at once).
class TriangleJudge
{
public:
  /// `remembered`: the workspace's CornerMemo for this octree, or null. `foldTest`: whether
  /// folds are told apart (by default when options.Folds is not Keep; a count that draws a fold
  /// as any triangle spares the test).
  TriangleJudge(const OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
    const uint8_t* reached, const PatchOptions& options, int32_t* remembered = nullptr)
    : TriangleJudge(
        v, state, cullMask, reached, options, remembered, options.Folds != FoldHandling::Keep)
  {
  }
  TriangleJudge(const OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
    const uint8_t* reached, const PatchOptions& options, int32_t* remembered, bool foldTest)
    : V(v)
    , State(state)
    , CullMask(cullMask)
    , Reached(reached)
    , Options(options)
    , Remembered(remembered)
    , FoldTest(foldTest)
  {
  }

  /// Triangle `t`'s fate; on Failed, `error` (if empty) receives why.
  Decision Decide(int64_t t, std::string& error) const
  {
    const OctreeView& v = this->V;
    Decision d;
    const int32_t* c = &v.Triangles[3 * t];
    if (v.PointGhost)
    {
      // another process draws it: the owner of its lead corner (an index out of range is left
      // to the representative lookup, which reports it)
      const int32_t lead = std::min({ c[0], c[1], c[2] });
      if (lead >= 0 && lead < v.NumberOfPoints && v.PointGhost[lead] != 0)
      {
        d.What = Decision::Ghost;
        return d;
      }
    }
    int64_t rep[3];
    bool drawn = false, backFacing = false;
    uint8_t masks = 0x3f;
    for (int k = 0; k < 3; ++k)
    {
      bool shown = false, back = false;
      uint8_t m = 0;
      rep[k] = this->Representative(c[k], shown, m, back, error);
      if (rep[k] == Invalid)
      {
        d.What = Decision::Failed;
        return d;
      }
      drawn = drawn || shown;
      backFacing = backFacing || back;
      if (!shown)
      {
        masks &= m;
      }
      d.Rep[k] = static_cast<int32_t>(rep[k]);
    }
    if (rep[0] == rep[1] || rep[1] == rep[2] || rep[0] == rep[2])
    {
      d.What = Decision::Collapsed; // only with an inconsistent owner; never for a valid octree
      return d;
    }
    if (!drawn && (backFacing || masks != 0))
    {
      d.What = Decision::Hidden;
      return d;
    }
    const PatchOptions& o = this->Options;
    if (this->FoldTest || o.CullBackFaces)
    {
      const Drawn tri(v, rep);
      const bool fold =
        this->FoldTest && (rep[0] >= 0 || rep[1] >= 0 || rep[2] >= 0) && tri.TurnedOver();
      if (fold && o.Folds == FoldHandling::Drop)
      {
        d.What = Decision::FoldDropped;
      }
      else if (o.CullBackFaces && tri.FacesAway(o))
      {
        d.What = Decision::BackFace;
      }
      else if (fold)
      {
        d.What = Decision::DrawFold;
      }
    }
    return d;
  }

private:
  static constexpr int64_t Invalid = std::numeric_limits<int64_t>::min();

  static void Fail(std::string& error, const std::string& text)
  {
    if (error.empty())
    {
      error = text;
    }
  }

  /// The representative of surface point p: the cluster holding it in its cut ancestor-or-self,
  /// or -1 - p in an opened leaf; Invalid (and `error`) on a broken index or cut. Every index
  /// followed is checked: arrays edited after validation cannot make it read out of bounds or
  /// loop.
  int64_t Representative(
    int32_t p, bool& drawn, uint8_t& mask, bool& backFacing, std::string& error) const
  {
    const OctreeView& v = this->V;
    if (p < 0 || p >= v.NumberOfPoints)
    {
      Fail(error, "a triangle refers to point " + std::to_string(p) + ", outside the surface");
      return Invalid;
    }
    int32_t* slot = this->Remembered ? this->Remembered + p : nullptr;
    int64_t c = this->RememberedCutCluster(p, slot);
    int64_t n = c >= 0 && c < v.NumberOfClusters ? v.ClusterNode[c] : -1;
    while (n >= 0 && n < v.NumberOfNodes && this->State[n] == NotInCut)
    {
      const int64_t parent = v.ClusterParent[c];
      if (parent < 0 || parent >= c)
      {
        Fail(error, "surface point " + std::to_string(p) + " has no ancestor in the cut");
        return Invalid;
      }
      c = parent;
      n = v.ClusterNode[c];
    }
    if (n < 0 || n >= v.NumberOfNodes)
    {
      Fail(error, "surface point " + std::to_string(p) + " has a cluster outside the arrays");
      return Invalid;
    }
    if (!this->Reached[n])
    {
      Fail(error, "node " + std::to_string(n) + " is in the cut below another cut node");
      return Invalid;
    }
    if (slot && __atomic_load_n(slot, __ATOMIC_RELAXED) != c + 1)
      __atomic_store_n(slot, static_cast<int32_t>(c + 1), __ATOMIC_RELAXED); // remembered
    const uint8_t s = this->State[n];
    drawn = IsDrawnState(s);
    if (s == CutHidden)
    {
      mask = this->CullMask ? this->CullMask[n] : 0;
      backFacing = !this->CullMask || this->CullMask[n] == 0;
    }
    return s == CutOpen ? -1 - int64_t(p) : c;
  }

  /**
   * Where point p's walk starts (`slot`: its entry in the remembered walks, or null): the
   * cluster its last walk ended at, when that cluster's node
   * is a cut node the walk from the root reached (then it is p's representative: a valid cut has
   * one node on each path from the root, and the remembered cluster is an ancestor-or-self of p's
   * leaf cluster); else p's leaf cluster. Ranges decided in parallel share points, so the
   * remembered clusters are read and written atomically (relaxed: any value one of them wrote is
   * right).
   */
  int64_t RememberedCutCluster(int32_t p, const int32_t* slot) const
  {
    const OctreeView& v = this->V;
    if (slot)
    {
      const int64_t c = int64_t(__atomic_load_n(slot, __ATOMIC_RELAXED)) - 1;
      const int64_t n = c >= 0 && c < v.NumberOfClusters ? v.ClusterNode[c] : -1;
      if (n >= 0 && n < v.NumberOfNodes && this->Reached[n]) // (reached: a cut node)
        return c;
    }
    return v.PointCluster[p];
  }

  const OctreeView& V;
  const uint8_t* State;
  const uint8_t* CullMask;
  const uint8_t* Reached; // read only here: its pages are given memory where the walk writes
  const PatchOptions& Options;
  int32_t* Remembered;
  bool FoldTest;
};

/// The workspace's remembered corner walks for `options.OctreeStamp` (made empty when the stamp
/// or the octree's size changed), or null when not asked for.
int32_t* RememberedWalks(const OctreeView& v, const PatchOptions& options, PatchWorkspace& ws)
{
  if (options.OctreeStamp == 0 || !v.PointCluster)
    return nullptr;
  if (!ws.Memo)
    ws.Memo = std::make_shared<CornerMemo>();
  CornerMemo& memo = *ws.Memo;
  if (memo.Stamp != options.OctreeStamp ||
    static_cast<int64_t>(memo.CutCluster.size()) != v.NumberOfPoints)
  {
    memo.CutCluster.assign(size_t(v.NumberOfPoints), 0); // every walk from its leaf
    memo.Stamp = options.OctreeStamp;
    ++memo.Resets;
  }
  return memo.CutCluster.data();
}

/// Walks the nodes above the cut from the root: marks the cut nodes reached, lists the nodes
/// whose owned triangles are drawn (refined nodes and opened leaves). False (and `error`) on an
/// invalid cut.
bool WalkAboveTheCut(const OctreeView& v, const uint8_t* state, PatchWorkspace& ws,
  PatchResult& out, std::string& error)
{
  std::vector<int32_t>& stack = ws.Stack;
  stack.clear();
  stack.push_back(0);
  std::vector<int32_t>& refined = ws.Refined;
  refined.clear();
  while (!stack.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    ++out.NodesVisited;
    const uint8_t s = state[n];
    if (s > CutOpen)
    {
      error = "node " + std::to_string(n) + " has cut state " + std::to_string(int(s)) +
        " (valid states are 0 to 3)";
      return false;
    }
    if (s != NotInCut)
    {
      if (s == CutOpen && !v.IsLeaf(n))
      {
        error = "node " + std::to_string(n) + " is opened but is not a leaf";
        return false;
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
      error = "leaf " + std::to_string(n) + " has no ancestor in the cut";
      return false;
    }
    refined.push_back(n);
    const int count = __builtin_popcount(v.ChildMask[n]);
    const int32_t first = v.FirstChild[n];
    if (first <= n || first + count > v.NumberOfNodes)
    {
      error = "node " + std::to_string(n) + " has children outside the node arrays";
      return false;
    }
    for (int c = count - 1; c >= 0; --c)
    {
      stack.push_back(first + c);
    }
  }
  return true;
}

/// Assigns output points and writes the drawn triangles, in the order of the decisions (the
/// serial phase: output point numbers follow first use).
class PatchEmitter
{
public:
  PatchEmitter(const OctreeView& v, PatchWorkspace& ws, PatchResult& out)
    : V(v)
    , Ws(ws)
    , Out(out)
  {
  }

  /// Counts `d` and, when drawn, writes it; false (and `error`) on a broken leaf index.
  bool Emit(const Decision& d, std::string& error)
  {
    switch (d.What)
    {
      case Decision::Draw:
        for (int k = 0; k < 3; ++k)
        {
          const int64_t id = this->OutputPoint(d.Rep[k], error);
          if (id < 0)
          {
            return false;
          }
          this->Out.Triangles.push_back(id);
        }
        return true;
      case Decision::DrawFold:
        // its own corners, at the same places, with reversed normals
        ++this->Out.Folds;
        for (int k = 0; k < 3; ++k)
        {
          const int64_t id = static_cast<int64_t>(this->Out.PointSource.size());
          this->Out.ReversedNormals.push_back(static_cast<int32_t>(id));
          this->Out.Triangles.push_back(id);
          this->Out.PointSource.push_back(d.Rep[k]);
        }
        return true;
      case Decision::Ghost:
        ++this->Out.GhostSkipped;
        return true;
      case Decision::Hidden:
        ++this->Out.HiddenSkipped;
        return true;
      case Decision::FoldDropped:
        ++this->Out.Folds;
        return true;
      case Decision::BackFace:
        ++this->Out.BackFacesCulled;
        return true;
      case Decision::Collapsed:
        return true;
      case Decision::Failed:
        return false;
    }
    return false;
  }

private:
  /// The output point of representative `rep`; -1 (and `error`) on a broken leaf index.
  int64_t OutputPoint(int64_t rep, std::string& error)
  {
    const OctreeView& v = this->V;
    PatchResult& out = this->Out;
    if (rep >= 0)
    {
      int32_t& id = this->Ws.OutputOf[rep]; // 1 + the output point, 0 for none yet
      if (id == 0)
      {
        id = static_cast<int32_t>(out.PointSource.size()) + 1;
        out.PointSource.push_back(rep);
        this->Ws.TouchedClusters.push_back(static_cast<int32_t>(rep));
      }
      return id - 1;
    }
    // an opened leaf's points get a block of outputs, keyed by the leaf's first cluster
    const int64_t p = -1 - rep;
    const int32_t leaf = v.PointLeaf[p];
    if (leaf < 0 || leaf >= v.NumberOfNodes || v.FirstCluster[leaf] < 0 ||
      v.FirstCluster[leaf] >= v.NumberOfClusters || v.FirstPoint[leaf] > p ||
      v.PointEnd(leaf) > v.NumberOfPoints)
    {
      if (error.empty())
      {
        error = "surface point " + std::to_string(p) + " has a leaf outside the arrays";
      }
      return -1;
    }
    int32_t& base = this->Ws.OutputOf[v.FirstCluster[leaf]]; // 1 + the first output point
    if (base == 0)
    {
      base = static_cast<int32_t>(out.PointSource.size()) + 1;
      for (int64_t q = v.FirstPoint[leaf], end = v.PointEnd(leaf); q < end; ++q)
      {
        out.PointSource.push_back(-1 - q);
      }
      this->Ws.TouchedClusters.push_back(v.FirstCluster[leaf]);
    }
    return base - 1 + (p - v.FirstPoint[leaf]);
  }

  const OctreeView& V;
  PatchWorkspace& Ws;
  PatchResult& Out;
};

/// The range of triangles `node` owns, clamped to the arrays.
std::pair<int64_t, int64_t> OwnedTriangles(const OctreeView& v, int64_t node)
{
  return { std::max<int64_t>(0, v.FirstTriangle[node]),
    std::min<int64_t>(v.NumberOfTriangles, v.TriangleEnd(node)) };
}

/// Splits the refined nodes (ws.Refined) into ranges holding about `perRange` owned triangles
/// each, range r from ws.RangeBounds[r] to ws.RangeBounds[r + 1]; returns how many.
int64_t SplitIntoRanges(const OctreeView& v, PatchWorkspace& ws, int64_t perRange)
{
  const std::vector<int32_t>& refined = ws.Refined;
  const size_t per = static_cast<size_t>(std::max<int64_t>(1, perRange));
  std::vector<size_t>& bounds = ws.RangeBounds;
  bounds.assign(1, 0);
  for (size_t i = 0, sum = 0; i < refined.size(); ++i)
  {
    const auto r = OwnedTriangles(v, refined[i]);
    sum += static_cast<size_t>(std::max<int64_t>(0, r.second - r.first));
    if (sum >= per || i + 1 == refined.size())
    {
      bounds.push_back(i + 1);
      sum = 0;
    }
  }
  const int64_t ranges = static_cast<int64_t>(bounds.size()) - 1;
  if (static_cast<int64_t>(ws.Decisions.size()) < ranges)
  {
    ws.Decisions.resize(static_cast<size_t>(ranges));
    ws.RangeErrors.resize(static_cast<size_t>(ranges));
  }
  return ranges;
}

/// Decides the owned triangles of range r's refined nodes in order, each passed to `take`,
/// until a decision fails; its error in ws.RangeErrors[r] (cleared first).
template <class Take>
void DecideRange(
  const OctreeView& v, const TriangleJudge& judge, PatchWorkspace& ws, int64_t r, Take&& take)
{
  std::string& rangeError = ws.RangeErrors[r];
  rangeError.clear();
  for (size_t i = ws.RangeBounds[r]; i < ws.RangeBounds[r + 1] && rangeError.empty(); ++i)
  {
    const auto owned = OwnedTriangles(v, ws.Refined[i]);
    for (int64_t t = owned.first; t < owned.second; ++t)
    {
      const Decision d = judge.Decide(t, rangeError);
      take(d);
      if (d.What == Decision::Failed)
      {
        break;
      }
    }
  }
}

/// The owned triangles of the refined nodes decided in ranges that may run in parallel (each
/// range's decisions kept in order), then emitted in order: the same output as one pass.
bool DecideInParallel(const OctreeView& v, const TriangleJudge& judge, PatchWorkspace& ws,
  PatchEmitter& emit, const PatchOptions& options, std::string& error)
{
  const int64_t ranges = SplitIntoRanges(v, ws, options.TrianglesPerRange);
  options.For(ranges, 1, [&](int64_t begin, int64_t end) {
    for (int64_t r = begin; r < end; ++r)
    {
      std::vector<Decision>& decided = ws.Decisions[r];
      decided.clear();
      DecideRange(v, judge, ws, r, [&decided](const Decision& d) { decided.push_back(d); });
    }
  });
  for (int64_t r = 0; r < ranges; ++r)
  {
    for (const Decision& d : ws.Decisions[r])
    {
      if (!emit.Emit(d, error))
      {
        if (error.empty())
        {
          error = ws.RangeErrors[r];
        }
        return false;
      }
    }
  }
  return true;
}
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
    ws.OutputOf.assign(size_t(v.NumberOfClusters), 0);
    ws.Reached.Assign(size_t(v.NumberOfNodes));
    ws.Touched.clear();
    ws.TouchedClusters.clear();
  }
  std::string error;
  // 1. the walk: cut nodes marked as reached, the nodes whose owned triangles are drawn listed
  // (every cut node is marked before the first triangle looks for its representatives)
  bool ok = WalkAboveTheCut(v, state, ws, out, error);
  // 2. each owned triangle decided (in parallel when asked), 3. the drawn ones emitted in order
  // (remembered only in a workspace that outlives the call)
  const TriangleJudge judge(v, state, cullMask, ws.Reached.data(), options,
    workspace ? RememberedWalks(v, options, ws) : nullptr);
  PatchEmitter emit(v, ws, out);
  if (ok && options.For)
  {
    ok = DecideInParallel(v, judge, ws, emit, options, error);
  }
  else if (ok)
  {
    for (size_t i = 0; i < ws.Refined.size() && ok; ++i)
    {
      const auto owned = OwnedTriangles(v, ws.Refined[i]);
      for (int64_t t = owned.first; t < owned.second && ok; ++t)
      {
        ok = emit.Emit(judge.Decide(t, error), error);
      }
    }
  }
  // 4. the workspace made clean for the next frame
  for (int32_t n : ws.Touched)
  {
    ws.Reached[n] = 0;
  }
  for (int32_t c : ws.TouchedClusters)
  {
    ws.OutputOf[c] = 0;
  }
  ws.Touched.clear();
  ws.TouchedClusters.clear();
  if (!ok)
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

int64_t CountDrawnTriangles(const OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
  const PatchOptions& options, PatchWorkspace& ws, std::string* why)
{
  if (v.NumberOfNodes == 0)
  {
    return 0;
  }
  if (static_cast<int64_t>(ws.Reached.size()) != v.NumberOfNodes)
  {
    ws.Reached.Assign(size_t(v.NumberOfNodes));
    ws.Touched.clear();
  }
  // GeneratePatches' walk and decisions, each range counted alone (in parallel with For). A
  // fold is drawn as any triangle is unless folds are dropped: otherwise the fold test, which
  // reads the three corners' normals, is spared (Keep decides the rest as the others do)
  PatchResult counters;
  std::string error;
  bool ok = WalkAboveTheCut(v, state, ws, counters, error);
  const TriangleJudge judge(v, state, cullMask, ws.Reached.data(), options,
    RememberedWalks(v, options, ws), options.Folds == FoldHandling::Drop);
  const int64_t ranges = ok ? SplitIntoRanges(v, ws, options.TrianglesPerRange) : 0;
  std::vector<int64_t>& drawn = ws.RangeDrawn;
  drawn.assign(static_cast<size_t>(ranges), 0);
  const auto countRanges = [&](int64_t begin, int64_t end) {
    for (int64_t r = begin; r < end; ++r)
    {
      DecideRange(v, judge, ws, r, [&drawn, r](const Decision& d) {
        drawn[r] += d.What == Decision::Draw || d.What == Decision::DrawFold ? 1 : 0;
      });
    }
  };
  if (options.For)
  {
    options.For(ranges, 1, countRanges);
  }
  else
  {
    countRanges(0, ranges);
  }
  int64_t total = 0;
  for (int64_t r = 0; r < ranges && ok; ++r)
  {
    total += drawn[r];
    if (!ws.RangeErrors[r].empty())
    {
      error = ws.RangeErrors[r];
      ok = false;
    }
  }
  for (int32_t n : ws.Touched)
  {
    ws.Reached[n] = 0;
  }
  ws.Touched.clear();
  if (!ok)
  {
    if (why)
    {
      *why = error;
    }
    return -1;
  }
  return total;
}

bool DrawnTriangleRanges(const OctreeView& v, const uint8_t* state, std::vector<int64_t>& first,
  std::vector<int64_t>& count, std::string* why, PatchWorkspace* workspace)
{
  first.clear();
  count.clear();
  if (v.NumberOfNodes == 0)
  {
    return true;
  }
  PatchWorkspace local;
  PatchWorkspace& ws = workspace ? *workspace : local;
  if (static_cast<int64_t>(ws.Reached.size()) != v.NumberOfNodes)
  {
    ws.Reached.Assign(size_t(v.NumberOfNodes));
    ws.Touched.clear();
  }
  PatchResult counters;
  std::string error;
  const bool ok = WalkAboveTheCut(v, state, ws, counters, error);
  for (int32_t n : ws.Touched)
  {
    ws.Reached[n] = 0;
  }
  ws.Touched.clear();
  if (!ok)
  {
    if (why)
    {
      *why = error;
    }
    return false;
  }
  // owned ranges follow the node order: sorted, they are disjoint and increasing
  std::vector<int32_t>& nodes = ws.Refined;
  std::sort(nodes.begin(), nodes.end());
  for (int32_t n : nodes)
  {
    const auto owned = OwnedTriangles(v, n);
    if (owned.second <= owned.first)
    {
      continue;
    }
    if (!first.empty() && first.back() + count.back() == owned.first)
    {
      count.back() += owned.second - owned.first; // touches the previous range
    }
    else
    {
      first.push_back(owned.first);
      count.push_back(owned.second - owned.first);
    }
  }
  return true;
}

int64_t ChangedSpans(const uint8_t* before, const uint8_t* now, int64_t n, int64_t gap,
  std::vector<std::pair<int64_t, int64_t>>& spans)
{
  spans.clear();
  int64_t bytes = 0;
  constexpr int64_t Block = 64;
  for (int64_t i = 0; i < n;)
  {
    // equal stretches (most of the state on a small move) skipped a block at a time
    while (i + Block <= n && std::memcmp(before + i, now + i, Block) == 0)
    {
      i += Block;
    }
    if (i >= n)
    {
      break;
    }
    if (before[i] == now[i])
    {
      ++i;
      continue;
    }
    // a difference: extend while the next difference is closer than `gap`
    int64_t end = i + 1, equal = 0;
    for (int64_t j = i + 1; j < n && equal < gap; ++j)
    {
      if (before[j] != now[j])
      {
        end = j + 1;
        equal = 0;
      }
      else
      {
        ++equal;
      }
    }
    spans.emplace_back(i, end);
    bytes += end - i;
    i = end;
  }
  return bytes;
}

} // namespace plod
