// SPDX-License-Identifier: BSD-3-Clause
// Background reads of refinements (plodPageLoader) and the selection that waits for them
// (Selector::SetPageLoader): requests are read once, coarsest first; forgotten ones are not
// read; a selection never goes below a cell whose refinement is not read, draws an ancestor of
// every cell of the full cut instead, and reaches the full cut once the reads are done.
#include "plodOctreeBuilder.h"
#include "plodOctreeStorage.h"
#include "plodPageLoader.h"
#include "plodSelector.h"
#include "plodTinyOctree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>
#if defined(__linux__)
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace
{
/// A bumpy sphere of `res` x `res` quads, built into `storage`; returns its view.
plod::OctreeView BuildSphere(plod::OctreeStorage& storage, int res)
{
  std::vector<double> points;
  std::vector<int64_t> triangles;
  for (int i = 0; i <= res; ++i)
    for (int j = 0; j < res; ++j)
    {
      const double w = M_PI * i / res, u = 2 * M_PI * j / res;
      const double r = 1.0 + 0.05 * std::sin(7 * u) * std::sin(5 * w);
      points.insert(points.end(),
        { r * std::sin(w) * std::cos(u), r * std::sin(w) * std::sin(u), r * std::cos(w) });
    }
  for (int i = 0; i < res; ++i)
    for (int j = 0; j < res; ++j)
    {
      const int64_t a = i * res + j, b = i * res + (j + 1) % res, c = a + res, d = b + res;
      triangles.insert(triangles.end(), { a, b, d, a, d, c });
    }
  plod::BuildInput in;
  in.NumberOfPoints = static_cast<int64_t>(points.size() / 3);
  in.Points = points.data();
  in.NumberOfTriangles = static_cast<int64_t>(triangles.size() / 3);
  in.Triangles = triangles.data();
  const plod::BuildResult r =
    plod::BuildOctree(in, plod::BuildParameters(), storage.MakeAllocator());
  EXPECT_TRUE(r.Ok) << r.Error;
  return storage.View(r);
}

/// A viewer at `distance` root edges from the root cell's centre, along +z.
plod::SelectionInput ViewerAt(const plod::OctreeView& v, double distance)
{
  const double c = 0.5 * v.RootEdge;
  return plodtest::Viewer(c, c, c + distance * v.RootEdge);
}

/// A cut: state and reason per node.
struct Cut
{
  std::vector<uint8_t> State, Reason, CullMask;
  explicit Cut(int64_t nodes)
    : State(nodes, plod::NotInCut)
    , Reason(nodes, plod::ReasonNone)
    , CullMask(nodes, 0)
  {
  }
  plod::SelectionStats Stats;
  void Select(plod::Selector& s, const plod::SelectionInput& in)
  {
    plod::SelectionStats& stats = this->Stats;
    s.Select(in, this->State.data(), this->Reason.data(), this->CullMask.data(), stats);
    EXPECT_EQ(stats.AwaitingPages, this->Count(plod::AwaitingPages)) << "the figure counts them";
  }
  int64_t Count(uint8_t reason) const
  {
    int64_t k = 0;
    for (size_t n = 0; n < this->State.size(); ++n)
      k += this->State[n] != plod::NotInCut && this->Reason[n] == reason ? 1 : 0;
    return k;
  }
};

/// The requests waiting: one per cell awaiting its pages (the incremental walk may also have
/// asked for cells that its coarsening then took out of the cut).
void ExpectRequests(const plod::PageLoader& loader, int64_t awaiting, const std::string& walk)
{
  if (walk == "incremental")
  {
    EXPECT_GE(loader.GetWaiting(), uint64_t(awaiting));
  }
  else
  {
    EXPECT_EQ(loader.GetWaiting(), uint64_t(awaiting));
  }
}

/// Whether node `n` or one of its ancestors is in `cut`.
bool AncestorInCut(const plod::OctreeView& v, const Cut& cut, int64_t n)
{
  for (; n >= 0; n = v.Parent[n])
    if (cut.State[n] != plod::NotInCut)
      return true;
  return false;
}

/// Every node the cut goes below (an ancestor of a cut node) or opens is read.
void ExpectRefinementsRead(const plod::OctreeView& v, const Cut& cut, const plod::PageLoader& l)
{
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (cut.State[n] == plod::CutOpen)
    {
      EXPECT_TRUE(l.IsReady(n)) << "leaf " << n << " opened before it was read";
    }
    if (cut.State[n] != plod::NotInCut && v.Parent[n] >= 0)
    {
      EXPECT_TRUE(l.IsReady(v.Parent[n])) << "node " << v.Parent[n] << " refined unread";
    }
  }
}
} // namespace

TEST(PageLoader, RequestsAreReadOnceCoarsestFirst)
{
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 40);
  ASSERT_GT(v.NumberOfNodes, 100);
  int64_t deep = v.NumberOfNodes - 1;
  ASSERT_GE(v.Level[deep], 3);
  plod::PageLoader loader;
  loader.SetOctree(v, nullptr);
  EXPECT_FALSE(loader.IsReady(0));
  EXPECT_EQ(loader.GetLastLoaded(), -1);
  loader.SetPaused(true);
  loader.Request(deep);
  loader.Request(0);
  loader.Request(deep); // asked twice: one request
  EXPECT_EQ(loader.GetWaiting(), 2u);
  loader.WaitUntilIdle(); // paused: returns at once
  EXPECT_FALSE(loader.IsReady(deep));
  loader.SetPaused(false);
  loader.WaitUntilIdle();
  EXPECT_TRUE(loader.IsReady(0));
  EXPECT_TRUE(loader.IsReady(deep));
  EXPECT_EQ(loader.GetLoaded(), 2u);
  EXPECT_EQ(loader.GetLastLoaded(), deep) << "the root, coarser, is read first";
  EXPECT_GT(loader.GetPagesTouched(), 0u);
  loader.Request(deep); // read: nothing to do
  EXPECT_EQ(loader.GetWaiting(), 0u);
  // out of range: refused quietly
  loader.Request(-1);
  loader.Request(v.NumberOfNodes);
  EXPECT_FALSE(loader.IsReady(-1));
  EXPECT_FALSE(loader.IsReady(v.NumberOfNodes));
  EXPECT_EQ(loader.GetWaiting(), 0u);
}

TEST(PageLoader, ARefinementReadsWhatTheFrameReadsToGoBelowIt)
{
  // What Load() reads for node n, tuple by tuple (the observer sees every range): n's children's
  // node records, their clusters, the triangles n owns, each of their corners' points and the
  // corner's walk from its leaf cluster up to a cluster of the children's level (a leaf: its
  // own level).
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 40);
  plod::PageLoader loader;
  loader.SetOctree(v, nullptr);
  std::vector<std::vector<bool>> seen(4);
  for (int g = 0; g < 4; ++g)
    seen[g].assign(size_t(v.TupleCount(plod::ArrayGroup(g))), false);
  loader.SetTouchObserver([&](plod::ArrayGroup group, int64_t first, int64_t end) {
    for (int64_t i = first; i < end; ++i)
      seen[int(group)][size_t(i)] = true;
  });
  const auto read = [&](plod::ArrayGroup g, int64_t i) { return bool(seen[int(g)][size_t(i)]); };
  int inner = 0, leaves = 0, corners = 0;
  for (int64_t n = 0; n < v.NumberOfNodes && (inner < 20 || leaves < 20); ++n)
  {
    const int64_t owned = v.TriangleEnd(n) - v.FirstTriangle[n];
    if (owned == 0 || (v.ChildMask[n] ? inner >= 20 : leaves >= 20))
      continue;
    ++(v.ChildMask[n] ? inner : leaves);
    for (auto& group : seen)
      std::fill(group.begin(), group.end(), false);
    loader.LoadNow(n);
    const int level = v.Level[n] + (v.ChildMask[n] ? 1 : 0); // where the corners' walks end
    if (v.ChildMask[n])
    {
      const int64_t first = v.FirstChild[n], last = first + __builtin_popcount(v.ChildMask[n]) - 1;
      for (int64_t c = first; c <= last; ++c)
        EXPECT_TRUE(read(plod::ArrayGroup::Node, c)) << "child " << c << " of " << n;
      for (int64_t k = v.FirstCluster[first]; k < v.ClusterEnd(last); ++k)
        EXPECT_TRUE(read(plod::ArrayGroup::Cluster, k)) << "cluster " << k << " of " << n;
    }
    for (int64_t t = v.FirstTriangle[n]; t < v.TriangleEnd(n); ++t)
    {
      EXPECT_TRUE(read(plod::ArrayGroup::Triangle, t)) << "triangle " << t << " of " << n;
      for (int k = 0; k < 3; ++k, ++corners)
      {
        const int32_t p = v.Triangles[3 * t + k];
        EXPECT_TRUE(read(plod::ArrayGroup::Point, p)) << "corner " << p << " of " << n;
        int32_t c = v.PointCluster[p];
        for (; c >= 0; c = v.ClusterParent[c])
        {
          EXPECT_TRUE(read(plod::ArrayGroup::Cluster, c)) << "walk of " << p << " at " << c;
          if (v.Level[v.ClusterNode[c]] <= level)
            break;
        }
        EXPECT_GE(c, 0);
        EXPECT_EQ(v.Level[v.ClusterNode[c]], level) << "the walk ends at the cut's level";
      }
    }
  }
  EXPECT_EQ(inner, 20);
  EXPECT_EQ(leaves, 20);
  EXPECT_GT(corners, 0);
}

TEST(PageLoader, ForgottenRequestsAreNotRead)
{
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 30);
  plod::PageLoader loader;
  loader.SetOctree(v, nullptr);
  loader.SetPaused(true);
  loader.Request(1);
  loader.Request(2);
  loader.ForgetRequests();
  EXPECT_EQ(loader.GetWaiting(), 0u);
  loader.SetPaused(false);
  loader.WaitUntilIdle();
  EXPECT_FALSE(loader.IsReady(1));
  EXPECT_FALSE(loader.IsReady(2));
  EXPECT_EQ(loader.GetLoaded(), 0u);
  loader.Request(2); // asked again after being forgotten: read
  loader.WaitUntilIdle();
  EXPECT_TRUE(loader.IsReady(2));
  EXPECT_EQ(loader.GetLoaded(), 1u);
  // read in the caller's thread: ready, not counted as the background's
  loader.LoadNow(1);
  EXPECT_TRUE(loader.IsReady(1));
  EXPECT_EQ(loader.GetLoaded(), 1u);
  // a new octree: nothing read
  loader.SetOctree(v, nullptr);
  EXPECT_FALSE(loader.IsReady(1));
  EXPECT_FALSE(loader.IsReady(2));
}

TEST(PageLoader, EachRequesterForgetsOnlyItsOwnRequests)
{
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 30);
  plod::PageLoader loader;
  loader.SetOctree(v, nullptr);
  const int a = loader.AddRequester(), b = loader.AddRequester();
  EXPECT_NE(a, b);
  loader.SetPaused(true);
  loader.Request(1, a);
  loader.Request(2, b);
  loader.Request(3, a);
  loader.Request(3, b); // asked by both: one request
  EXPECT_EQ(loader.GetWaiting(), 3u);
  loader.ForgetRequests(a); // b's stay, 3 among them
  EXPECT_EQ(loader.GetWaiting(), 2u);
  loader.SetPaused(false);
  loader.WaitUntilIdle();
  EXPECT_FALSE(loader.IsReady(1));
  EXPECT_TRUE(loader.IsReady(2));
  EXPECT_TRUE(loader.IsReady(3));
  EXPECT_EQ(loader.GetLoaded(), 2u);
  // forgotten by both: not read
  loader.SetPaused(true);
  loader.Request(4, a);
  loader.Request(4, b);
  loader.ForgetRequests(b);
  EXPECT_EQ(loader.GetWaiting(), 1u);
  loader.ForgetRequests(a);
  EXPECT_EQ(loader.GetWaiting(), 0u);
  loader.SetPaused(false);
  loader.WaitUntilIdle();
  EXPECT_FALSE(loader.IsReady(4));
  // ids go round past MaxRequesters
  for (int k = 2; k < plod::PageLoader::MaxRequesters; ++k)
    loader.AddRequester();
  EXPECT_EQ(loader.AddRequester(), a);
}

TEST(PageLoader, ThreadRunsNicerThanTheProcess)
{
#if defined(__linux__)
  errno = 0;
  const int process = getpriority(PRIO_PROCESS, 0);
  ASSERT_EQ(errno, 0);
  if (process > 19 - plod::PageLoader::ThreadNiceness)
    GTEST_SKIP() << "the process runs at nice " << process << ": no room to be nicer";
  bool allowed = false; // whether a thread may make itself nicer here (seccomp may refuse)
  std::thread probe([&allowed, process] {
    allowed = setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), process + 1) == 0;
  });
  probe.join();
  if (!allowed)
    GTEST_SKIP() << "a thread cannot change its own nice value here";
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 30);
  plod::PageLoader loader;
  loader.SetOctree(v, nullptr);
  loader.Request(1); // starts the thread
  loader.WaitUntilIdle();
  EXPECT_EQ(loader.GetThreadNice(), process + plod::PageLoader::ThreadNiceness);
#else
  GTEST_SKIP() << "a thread's own priority is set on Linux only";
#endif
}

TEST(PageLoader, ANewLoaderAtAFreedAddressIsNew)
{
  // a loader made where a freed one was (an octree read again): the selection reads its first
  // view whole again, as with any new loader, rather than taking it for the old one
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 60);
  alignas(plod::PageLoader) unsigned char place[sizeof(plod::PageLoader)];
  plod::Selector selector;
  selector.SetOctree(v);
  Cut cut(v.NumberOfNodes);
  const plod::SelectionInput close = ViewerAt(v, 0.7);
  for (int k = 0; k < 2; ++k)
  {
    auto* loader = new (place) plod::PageLoader();
    loader->SetOctree(v, nullptr);
    loader->SetPaused(true);
    selector.SetPageLoader(loader);
    cut.Select(selector, close);
    EXPECT_EQ(cut.Count(plod::AwaitingPages), 0) << "loader " << k << ": the first view is whole";
    EXPECT_EQ(loader->GetWaiting(), 0u);
    loader->~PageLoader(); // (the selector is given the next one before it selects again)
  }
}

TEST(PageLoader, TwoSelectionsSharingALoaderKeepEachOthersRequests)
{
  // Two views of one file (two selectors on one loader), the reads held: each selection forgets
  // only its own requests, so a view that keeps selecting does not starve the other; once the
  // reads are let go, both reach their full cuts.
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 80);
  const double c = 0.5 * v.RootEdge;
  plod::SelectionInput front = plodtest::Viewer(c, c, c + 0.7 * v.RootEdge),
                       back = plodtest::Viewer(c, c, c - 0.7 * v.RootEdge);
  front.PixelScale = back.PixelScale = 4000;
  plod::PageLoader loader;
  loader.SetOctree(v, nullptr);
  plod::Selector one, two;
  for (plod::Selector* s : { &one, &two })
  {
    s->SetOctree(v);
    s->SetPageLoader(&loader);
  }
  Cut oneCut(v.NumberOfNodes), twoCut(v.NumberOfNodes);
  const plod::SelectionInput far = ViewerAt(v, 3.0);
  oneCut.Select(one, far); // the first views: read whole, in the frame
  twoCut.Select(two, far);
  loader.WaitUntilIdle();
  loader.SetPaused(true);
  oneCut.Select(one, front);
  twoCut.Select(two, back);
  const auto awaited = [&](const Cut& cut) {
    std::vector<int64_t> nodes;
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      if (cut.State[n] != plod::NotInCut && cut.Reason[n] == plod::AwaitingPages)
        nodes.push_back(n);
    return nodes;
  };
  std::vector<int64_t> both = awaited(oneCut), twos = awaited(twoCut);
  ASSERT_FALSE(twos.empty());
  both.insert(both.end(), twos.begin(), twos.end());
  std::sort(both.begin(), both.end());
  both.erase(std::unique(both.begin(), both.end()), both.end());
  ASSERT_GT(both.size(), awaited(oneCut).size()) << "the views should await different cells";
  EXPECT_EQ(loader.GetWaiting(), both.size());
  oneCut.Select(one, front); // forgets its own requests and asks again: two's stay
  EXPECT_EQ(loader.GetWaiting(), both.size());
  // one keeps selecting, two selects only when all is read: two's view is read all the same
  loader.SetPaused(false);
  for (int frame = 0; frame <= 2 * plod::MaxFinestLevel; ++frame)
  {
    loader.WaitUntilIdle();
    oneCut.Select(one, front);
  }
  loader.WaitUntilIdle();
  for (const int64_t n : twos)
  {
    EXPECT_TRUE(loader.IsReady(n)) << "node " << n << " of the second view was not read";
  }
}

TEST(PageLoader, SelectionDrawsAncestorsUntilTheReadsArrive)
{
  plod::OctreeStorage storage;
  const plod::OctreeView v = BuildSphere(storage, 80);
  for (const char* walk : { "tolerances", "triangle budget", "incremental" })
  {
    SCOPED_TRACE(walk);
    const bool budget = walk[0] == 't' && walk[1] == 'r';
    plod::SelectionInput far = ViewerAt(v, 3.0), close = ViewerAt(v, 0.7);
    close.PixelScale = far.PixelScale = 4000;
    if (budget)
      far.TriangleBudget = close.TriangleBudget = 1500;
    far.Incremental = close.Incremental = walk[0] == 'i';
    // the cuts without a loader
    plod::Selector plain;
    plain.SetOctree(v);
    Cut farCut(v.NumberOfNodes), closeCut(v.NumberOfNodes);
    farCut.Select(plain, far);
    plain.SetOctree(v);
    closeCut.Select(plain, close);
    ASSERT_EQ(closeCut.Count(plod::AwaitingPages), 0);
    EXPECT_EQ(closeCut.Stats.BudgetBinding, budget) << "the budget should bind";

    plod::PageLoader loader;
    loader.SetOctree(v, nullptr);
    plod::Selector gated;
    gated.SetOctree(v);
    gated.SetPageLoader(&loader);
    Cut cut(v.NumberOfNodes);
    // 1. the first view is read whole, in the frame: the plain cut
    cut.Select(gated, far);
    EXPECT_EQ(cut.State, farCut.State);
    EXPECT_EQ(cut.Reason, farCut.Reason);
    EXPECT_EQ(loader.GetWaiting(), 0u);
    EXPECT_EQ(loader.GetLoaded(), 0u);
    ExpectRefinementsRead(v, cut, loader);
    loader.WaitUntilIdle(); // its refinements read again in the background (Preload)
    EXPECT_GT(loader.GetPagesTouched(), 0u);
    EXPECT_EQ(loader.GetLoaded(), 0u);
    // 2. closer, the reads held: what is not read waits, drawn at an ancestor
    loader.SetPaused(true);
    cut.Select(gated, close);
    const int64_t awaiting = cut.Count(plod::AwaitingPages);
    EXPECT_GT(awaiting, 0);
    ExpectRequests(loader, awaiting, walk);
    ExpectRefinementsRead(v, cut, loader);
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    {
      if (cut.State[n] != plod::NotInCut && cut.Reason[n] == plod::AwaitingPages)
      {
        EXPECT_FALSE(loader.IsReady(n));
      }
      if (closeCut.State[n] != plod::NotInCut)
      {
        EXPECT_TRUE(AncestorInCut(v, cut, n)) << "node " << n << " has no ancestor drawn";
      }
    }
    // a view left behind is not loaded: back to the far view, its requests are dropped
    cut.Select(gated, far);
    EXPECT_EQ(loader.GetWaiting(), 0u);
    EXPECT_EQ(cut.State, farCut.State);
    cut.Select(gated, close);
    ExpectRequests(loader, awaiting, walk);
    // 3. reads let go: each frame refines further, until the plain cut
    loader.SetPaused(false);
    int frames = 0;
    for (; frames <= 2 * plod::MaxFinestLevel && cut.Count(plod::AwaitingPages) > 0; ++frames)
    {
      loader.WaitUntilIdle();
      cut.Select(gated, close);
      ExpectRefinementsRead(v, cut, loader);
    }
    EXPECT_GT(frames, 0);
    EXPECT_EQ(cut.Count(plod::AwaitingPages), 0);
    EXPECT_EQ(cut.State, closeCut.State);
    EXPECT_EQ(cut.Reason, closeCut.Reason);
    EXPECT_GT(loader.GetLoaded(), 0u);
    std::cout << walk << ": " << awaiting << " cells waited at first; the full cut after " << frames
              << " more frames, " << loader.GetLoaded() << " refinements read in the background\n";
  }
}
