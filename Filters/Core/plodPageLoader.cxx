// SPDX-License-Identifier: BSD-3-Clause
#include "plodPageLoader.h"

#include "plodOctreeSchema.h"

#include <algorithm>
#include <cerrno>
#include <string>
#include <sys/resource.h>
#include <unistd.h>
#if defined(__linux__)
#include <sys/syscall.h>
#endif

namespace plod
{

namespace
{
/// The page size, for the reads' stride.
size_t PageBytes()
{
  static const size_t bytes = [] {
    const long b = sysconf(_SC_PAGESIZE);
    return b > 0 ? static_cast<size_t>(b) : size_t(4096);
  }();
  return bytes;
}

/// The calling thread's major page faults so far.
uint64_t ThreadMajorFaults()
{
  rusage u{};
  return getrusage(RUSAGE_THREAD, &u) == 0 ? static_cast<uint64_t>(u.ru_majflt) : 0;
}

/// Makes the calling thread `niceness` nicer than the process (Linux: a thread's own priority);
/// returns the nice value it then runs at.
int RunNicer(int niceness)
{
  errno = 0;
  const int process = getpriority(PRIO_PROCESS, 0);
  if (errno != 0)
    return 0;
#if defined(__linux__)
  const id_t thread = static_cast<id_t>(syscall(SYS_gettid));
  const int wanted = std::min(19, process + niceness);
  if (setpriority(PRIO_PROCESS, thread, wanted) == 0)
    return wanted;
#else
  (void)niceness;
#endif
  return process;
}

uint64_t NextSerial()
{
  static std::atomic<uint64_t> next{ 1 };
  return next++;
}
} // namespace

PageLoader::PageLoader()
  : Serial(NextSerial())
  , Queue(MaxFinestLevel + 1)
{
}

PageLoader::~PageLoader()
{
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Stop = true;
  }
  this->Wake.notify_all();
  if (this->Thread.joinable())
    this->Thread.join();
}

void PageLoader::SetOctree(const OctreeView& view, std::shared_ptr<const void> keepAlive)
{
  std::unique_lock<std::mutex> lock(this->Mutex);
  for (std::deque<int64_t>& level : this->Queue)
    level.clear();
  this->Waiting = 0;
  this->Preloads.clear();
  this->Idle.wait(lock, [this] { return !this->Running; });
  this->View = view;
  this->KeepAlive = std::move(keepAlive);
  this->Arrays.clear();
  // InputPointId is left out: nothing a frame does reads it
#define PLOD_LOADER_ARRAY(member, group, type, comps, meaning)                                     \
  if (view.member && std::string(#member) != "InputPointId")                                       \
    this->Arrays.push_back(                                                                        \
      { ArrayGroup::group, reinterpret_cast<const char*>(view.member), sizeof(type) * (comps) });
  PLOD_OCTREE_ALL_ARRAYS(PLOD_LOADER_ARRAY)
#undef PLOD_LOADER_ARRAY
  this->Flags.Assign(static_cast<size_t>(std::max<int64_t>(view.NumberOfNodes, 0)));
  this->Idle.notify_all();
}

int PageLoader::AddRequester()
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Requesters++ % MaxRequesters;
}

void PageLoader::Request(int64_t n, int requester)
{
  const uint8_t mine = FlagRequestedBy(requester);
  if (n < 0 || static_cast<size_t>(n) >= this->Flags.size() ||
    (__atomic_load_n(&this->Flags[n], __ATOMIC_ACQUIRE) & (FlagReady | mine)) != 0)
    return;
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    const uint8_t flags = __atomic_fetch_or(&this->Flags[n], mine, __ATOMIC_ACQ_REL);
    if ((flags & (FlagReady | FlagsRequested)) != 0)
      return; // read, or queued for another requester
    const int level = std::min<int>(this->View.Level[n], MaxFinestLevel);
    this->Queue[level].push_back(n);
    ++this->Waiting;
    this->StartThread();
  }
  this->Wake.notify_one();
}

void PageLoader::Preload(int64_t n)
{
  if (n < 0 || static_cast<size_t>(n) >= this->Flags.size())
    return;
  this->MarkReady(n);
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Preloads.push_back(n);
    this->StartThread();
  }
  this->Wake.notify_one();
}

void PageLoader::StartThread()
{
  if (!this->Thread.joinable())
    this->Thread = std::thread([this] { this->Run(); });
}

void PageLoader::LoadNow(int64_t n)
{
  if (n < 0 || static_cast<size_t>(n) >= this->Flags.size())
    return;
  this->Load(n);
  this->MarkReady(n);
}

void PageLoader::ForgetRequests(int requester)
{
  const uint8_t mine = FlagRequestedBy(requester);
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    for (std::deque<int64_t>& level : this->Queue)
    {
      // keep, in order, the requests someone else still makes
      size_t kept = 0;
      for (const int64_t n : level)
      {
        const uint8_t before =
          __atomic_fetch_and(&this->Flags[n], uint8_t(~mine), __ATOMIC_ACQ_REL);
        if ((before & FlagsRequested & ~mine) != 0)
          level[kept++] = n;
      }
      this->Waiting -= level.size() - kept;
      level.resize(kept);
    }
  }
  this->Idle.notify_all();
}

void PageLoader::SetPaused(bool paused)
{
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Paused = paused;
  }
  this->Wake.notify_all();
  this->Idle.notify_all();
}

void PageLoader::WaitUntilIdle()
{
  std::unique_lock<std::mutex> lock(this->Mutex);
  this->Idle.wait(lock, [this] {
    return !this->Running &&
      ((this->Waiting == 0 && this->Preloads.empty()) || this->Paused || this->Stop);
  });
}

uint64_t PageLoader::GetWaiting() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Waiting;
}

void PageLoader::MarkReady(int64_t n)
{
  __atomic_fetch_or(&this->Flags[n], FlagReady, __ATOMIC_ACQ_REL);
  __atomic_fetch_and(&this->Flags[n], uint8_t(~FlagsRequested), __ATOMIC_ACQ_REL);
}

void PageLoader::TouchTuples(ArrayGroup group, int64_t first, int64_t end)
{
  first = std::max<int64_t>(first, 0);
  end = std::min(end, this->View.TupleCount(group));
  if (end <= first)
    return;
  if (this->TouchObserver)
    this->TouchObserver(group, first, end);
  const size_t page = PageBytes();
  uint64_t touched = 0;
  for (const Array& a : this->Arrays)
  {
    if (a.Group != group)
      continue;
    const char* p = a.Data + first * a.TupleBytes;
    const char* last = a.Data + end * a.TupleBytes - 1;
    // the first byte, then the first byte of each later page: all within the array
    for (; p <= last; ++touched)
    {
      (void)*static_cast<const volatile char*>(p);
      p = reinterpret_cast<const char*>((reinterpret_cast<uintptr_t>(p) / page + 1) * page);
    }
  }
  this->PagesTouched += touched;
}

void PageLoader::TouchCornerWalk(int64_t point, int level)
{
  const OctreeView& v = this->View;
  if (point < 0 || point >= v.NumberOfPoints)
    return;
  this->TouchTuples(ArrayGroup::Point, point, point + 1);
  int64_t c = v.PointCluster[point];
  for (int step = 0; step <= MaxFinestLevel && c >= 0 && c < v.NumberOfClusters; ++step)
  {
    this->TouchTuples(ArrayGroup::Cluster, c, c + 1);
    const int64_t node = v.ClusterNode[c];
    if (node < 0 || node >= v.NumberOfNodes || v.Level[node] <= level)
      break;
    c = v.ClusterParent[c];
  }
}

void PageLoader::Load(int64_t n)
{
  const OctreeView& v = this->View;
  const int level = v.Level[n];
  const unsigned mask = v.ChildMask[n];
  this->TouchTuples(ArrayGroup::Node, n, n + 1);
  this->TouchTuples(ArrayGroup::Cluster, v.FirstCluster[n], v.ClusterEnd(n));
  if (mask != 0)
  {
    const int64_t first = v.FirstChild[n];
    const int64_t last = first + __builtin_popcount(mask) - 1;
    if (first > n && last < v.NumberOfNodes)
    {
      this->TouchTuples(ArrayGroup::Node, first, std::min(last + 2, v.NumberOfNodes));
      this->TouchTuples(ArrayGroup::Cluster, v.FirstCluster[first], v.ClusterEnd(last));
    }
  }
  const int64_t t0 = std::max<int64_t>(v.FirstTriangle[n], 0);
  const int64_t t1 = std::min(v.TriangleEnd(n), v.NumberOfTriangles);
  this->TouchTuples(ArrayGroup::Triangle, t0, t1);
  const int walkLevel = mask != 0 ? level + 1 : level;
  for (int64_t t = t0; t < t1; ++t)
    for (int k = 0; k < 3; ++k)
      this->TouchCornerWalk(v.Triangles[3 * t + k], walkLevel);
}

void PageLoader::Run()
{
  this->ThreadNice = RunNicer(ThreadNiceness); // the frame's threads go first
  const uint64_t faults0 = ThreadMajorFaults();
  std::unique_lock<std::mutex> lock(this->Mutex);
  while (true)
  {
    this->Wake.wait(lock, [this] {
      return this->Stop || (!this->Paused && (this->Waiting > 0 || !this->Preloads.empty()));
    });
    if (this->Stop)
      return;
    int64_t n = -1;
    for (std::deque<int64_t>& level : this->Queue)
    {
      if (!level.empty())
      {
        n = level.front();
        level.pop_front();
        break;
      }
    }
    bool load = true;
    if (n >= 0)
    {
      --this->Waiting;
      load = !this->IsReady(n);
    }
    else if (!this->Preloads.empty()) // (after every request)
    {
      n = this->Preloads.front();
      this->Preloads.pop_front();
      load = false; // (ready already: not counted as a load the cut waits for)
    }
    else
    {
      this->Waiting = 0; // (never: the count follows the queues)
      continue;
    }
    this->Running = true;
    lock.unlock();
    this->Load(n); // (a request read meanwhile by LoadNow is read again: harmless)
    this->MarkReady(n);
    if (load)
    {
      this->LastLoaded = n;
      ++this->Loaded;
    }
    this->MajorFaults = ThreadMajorFaults() - faults0;
    if (this->Limit)
      this->Limit->Enforce(nullptr); // (a failure is kept for the frame's thread to report)
    lock.lock();
    this->Running = false;
    this->Idle.notify_all();
  }
}

} // namespace plod
