// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPageLoader.h
 * @brief VTK-free background reads of a mapped octree's pages, so that a frame never waits on
 * the disk.
 *
 * A mapped octree file (plodOctreeFile.h) is read where the views look: a page that is not in
 * memory is read from the disk by the first access, in the thread that makes it. When that
 * thread is the frame's, the frame waits. PageLoader moves those reads to a thread of its own,
 * one refinement at a time:
 *
 * - **What a refinement reads.** Refining node n (the selector puts its children in the cut, or
 *   opens a leaf) makes the selection and the patch generator read: every node array at n's
 *   children (and at the node after them, whose first indices end theirs), every cluster array
 *   at the children's clusters, the triangles n owns, and for each of their corners every point
 *   array at the corner and every cluster array along the corner's walk from its leaf cluster up
 *   to the children's level (plodPatches.h). Load() reads one byte of each page of all that,
 *   and of n's own node and clusters, then marks n ready. The cells the cut already draws were
 *   read by the refinements that put them there (the root, by the first view).
 * - **Ready flags**, one byte a node (plod::ZeroPages: memory only where the views have been),
 *   set once a node's refinement has been read, never cleared: the pages then are in the
 *   kernel's page cache, and a cache limit that drops them from the process (plodResidentPages.h)
 *   costs a minor fault, not a read of the disk. A page the kernel evicts under memory pressure
 *   is read again by whoever touches it first.
 * - **Requests** come from the selection (plodSelector.h, Selector::SetPageLoader): a node the
 *   tolerances would refine whose refinement is not ready is drawn as it is (its ancestor's
 *   level, reason AwaitingPages) and requested. The loader takes the coarsest requested level
 *   first (a coarser refinement is seen over more of the screen, and opens the way to the finer
 *   ones), in the order asked within a level. ForgetRequests() drops what no one has started,
 *   so each frame asks again for what it still needs and a view left behind is not loaded.
 *   Several selections may share a loader (two views of one file): each asks as a requester of
 *   its own (AddRequester), and forgets only its own requests; a node asked for by two is one
 *   request, dropped when both have forgotten it.
 * - **Progress**: GetLoaded() counts the nodes made ready in the background; when it changes,
 *   the next selection can refine further (vtkPerceptualLODSelector re-executes then, and the
 *   actor renders again while loads are pending).
 *
 * - **Behind the frame**: the thread runs ThreadNiceness nicer than the process (Linux), so that
 *   on a machine whose cores are busy with the frame (the patch generator's threads, a software
 *   renderer) the reads take what the frame leaves.
 * - **Within a cache limit**: with SetResidentLimit(), the thread keeps the mapping's resident
 *   pages within the limit after each refinement it reads (ResidentLimit::Enforce), so that what
 *   it reads between frames is not held past the limit until the next frame.
 *
 * Thread safety: Request(), Preload(), IsReady(), LoadNow(), ForgetRequests() and the figures
 * may be called from any thread, at once; SetOctree(), SetResidentLimit() and
 * SetTouchObserver() only while no other call runs. The view's arrays must
 * stay valid while the loader exists (SetOctree keeps `keepAlive`, the map's owner).
 */
#ifndef plodPageLoader_h
#define plodPageLoader_h

#include "plodOctree.h"
#include "plodResidentPages.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace plod
{

class PageLoader
{
public:
  PageLoader();
  /// Stops the thread (a read in progress is finished first).
  ~PageLoader();
  PageLoader(const PageLoader&) = delete;
  PageLoader& operator=(const PageLoader&) = delete;

  /// The octree whose refinements are read; drops every flag and request. `keepAlive` owns the
  /// memory the view's arrays point into.
  void SetOctree(const OctreeView& view, std::shared_ptr<const void> keepAlive);

  /// This loader's number, unique in the process (a new loader may take a freed one's address).
  uint64_t GetSerial() const { return this->Serial; }

  /// The limit the thread enforces after each read (null: none). It must outlive the loader.
  void SetResidentLimit(ResidentLimit* limit) { this->Limit = limit; }

  /// Whether node `n`'s refinement has been read (false for a node out of range).
  bool IsReady(int64_t n) const
  {
    return n >= 0 && static_cast<size_t>(n) < this->Flags.size() &&
      (__atomic_load_n(&this->Flags[n], __ATOMIC_ACQUIRE) & FlagReady) != 0;
  }
  /// How much nicer than the process the thread runs (Linux), so that on a busy machine the
  /// frame's threads (the patches, a software renderer) go before the reads.
  static constexpr int ThreadNiceness = 10;
  /// The nice value the thread runs at (0 before it started).
  int GetThreadNice() const { return this->ThreadNice.load(); }

  /// The most requesters told apart; later ones share their ids (and forget each other's).
  static constexpr int MaxRequesters = 7;
  /// A new requester's id, for Request() and ForgetRequests() (ids go round after
  /// MaxRequesters; the default, 0, is the first).
  int AddRequester();
  /// Asks for node `n`'s refinement to be read in the background, for `requester`; asked again
  /// before it is, by anyone, it is one request.
  void Request(int64_t n, int requester = 0);
  /**
   * Marks node `n` ready now and reads its refinement in the background after every request
   * (ForgetRequests() leaves it): for a refinement the caller has read itself, in part (the
   * first view, read in the frame, skips what it culls), so that the rest follows.
   */
  void Preload(int64_t n);
  /// Reads node `n`'s refinement now, in the calling thread (again if it was read), and marks
  /// it ready.
  void LoadNow(int64_t n);
  /// Drops `requester`'s requests no read has started on (those others asked for too stay).
  void ForgetRequests(int requester = 0);

  /// While paused, requests wait and the thread reads nothing (a read in progress ends first).
  void SetPaused(bool paused);
  /// Returns once no request or preload waits and no read runs (at once when paused with none
  /// running).
  void WaitUntilIdle();

  /**
   * For tests and diagnostics: called with each range of tuples a read covers, [first, end)
   * of `group` (every array of the group, one byte per page). Set before any read starts.
   */
  void SetTouchObserver(std::function<void(ArrayGroup group, int64_t first, int64_t end)> f)
  {
    this->TouchObserver = std::move(f);
  }
  /// The node the background thread read last (-1 before any): which request went first.
  int64_t GetLastLoaded() const { return this->LastLoaded.load(); }
  /// Nodes made ready by the background thread so far.
  uint64_t GetLoaded() const { return this->Loaded.load(); }
  /// Requests waiting now (not preloads).
  uint64_t GetWaiting() const;
  /// Pages the reads touched so far (background and LoadNow), and the major page faults the
  /// background thread took (reads of the disk; getrusage RUSAGE_THREAD).
  uint64_t GetPagesTouched() const { return this->PagesTouched.load(); }
  uint64_t GetMajorFaults() const { return this->MajorFaults.load(); }

private:
  static constexpr uint8_t FlagReady = 1;
  /// requested by requester r: bit r + 1
  static constexpr uint8_t FlagsRequested = 0xFE;
  static uint8_t FlagRequestedBy(int requester)
  {
    return uint8_t(2u << (static_cast<unsigned>(requester) % MaxRequesters));
  }

  /// Reads node `n`'s refinement (see the file documentation).
  void Load(int64_t n);
  /// Reads one byte of each page of tuples [first, end) of every array of `group`.
  void TouchTuples(ArrayGroup group, int64_t first, int64_t end);
  /// Reads the corner's point arrays and its walk's clusters up to level `level`.
  void TouchCornerWalk(int64_t point, int level);
  void MarkReady(int64_t n);
  void Run();
  /// Starts the thread at the first request (called under the lock).
  void StartThread();

  OctreeView View;
  std::shared_ptr<const void> KeepAlive;
  /// per array of the view: its group, start and bytes per tuple
  struct Array
  {
    ArrayGroup Group;
    const char* Data;
    size_t TupleBytes;
  };
  std::vector<Array> Arrays;
  ZeroPages<uint8_t> Flags;
  std::function<void(ArrayGroup, int64_t, int64_t)> TouchObserver;
  ResidentLimit* Limit = nullptr;
  const uint64_t Serial;

  mutable std::mutex Mutex;
  std::condition_variable Wake, Idle;
  std::vector<std::deque<int64_t>> Queue; // per level
  std::deque<int64_t> Preloads;
  uint64_t Waiting = 0;
  int Requesters = 0;   // ids given so far
  bool Running = false; // a read in progress
  bool Paused = false;
  bool Stop = false;
  std::thread Thread;

  std::atomic<uint64_t> Loaded{ 0 };
  std::atomic<int64_t> LastLoaded{ -1 };
  std::atomic<uint64_t> PagesTouched{ 0 };
  std::atomic<uint64_t> MajorFaults{ 0 };
  std::atomic<int> ThreadNice{ 0 };
};

} // namespace plod

#endif
