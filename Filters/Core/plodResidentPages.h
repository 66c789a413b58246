// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodResidentPages.h
 * @brief VTK-free bound on how much of a mapped octree file a process keeps resident.
 *
 * A mapped octree file (plodOctreeFile.h) is read where the views look: the kernel maps each
 * page into the process when it is first read, and keeps it mapped. Over a flight the process's
 * resident memory then follows the file, not the view. ResidentLimit keeps the pages of one
 * mapping that the process holds within a limit: when they exceed it, the mapping's file pages
 * are dropped from the process (they stay in the kernel's page cache while memory allows, so the
 * next read maps them again without the disk) and the pages the next views read come back.
 *
 * The bound holds between frames: the caller enforces it after each frame's reads, and a page
 * loader (plodPageLoader.h) after each refinement it reads. A frame that reads more than the
 * limit holds more while it runs, and every such frame maps its pages again: the limit should
 * exceed what one view reads (a triangle budget bounds that).
 *
 * Measuring is two steps, so that a frame under the limit costs one small read of
 * /proc/self/statm (the process's resident file-backed pages): only when those grew by more
 * than the limit since the last exact count is the mapping counted page by page, from
 * /proc/self/pagemap (8 bytes read per page mapped). Other mappings that grow (libraries, other
 * octrees) make the exact count come sooner, never later; pages of other files that the kernel
 * reclaims meanwhile can let the mapping exceed the limit by as much until the next count. A page
 * that was written (a private copy: the mapping is copy-on-write) is never dropped, so edits of the
 * arrays are never lost. Linux only; elsewhere, or where /proc is unreadable, Enforce() does
 * nothing and says why.
 *
 * ZeroPages is the same idea for the filters' own arrays, one value per node, cluster or point
 * of the octree (what a frame marks, remembers or caches): zero until written, and taking memory
 * only where written, so that what they hold follows the views as the file's pages do, not the
 * octree's size. Their users store zero for "nothing here".
 */
#ifndef plodResidentPages_h
#define plodResidentPages_h

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <string>
#include <utility>

namespace plod
{

/// What a process holds of a mapping: pages of the file, and the others (pages written, private
/// copies; in an anonymous map, also the kernel's shared zero page where only read).
struct MappingResidency
{
  uint64_t FileBytes = 0;
  uint64_t PrivateBytes = 0;
};

/**
 * Counts the pages of [data, data + bytes) present in this process (from /proc/self/pagemap).
 * With `release`, the present file pages are then dropped from the process (madvise
 * MADV_DONTNEED, run by run), written pages left alone; `out` counts them as they were before.
 * False, with `why`, where the page map cannot be read.
 */
bool MeasureMappingResidency(
  void* data, uint64_t bytes, bool release, MappingResidency& out, std::string* why);

/// The resident file-backed memory of this process in bytes (/proc/self/statm's third field:
/// every mapped file and shared memory), or -1 where it cannot be read.
int64_t ProcessFileResidentBytes();

/**
 * The limit on one read-only file mapping's resident pages. Attach() names the mapping, Enforce()
 * after each frame keeps it within Limit bytes (0: no limit), less what SetHeld() counts.
 *
 * Thread safety: Enforce(), Release(), Measure() and the figures may be called from
 * any thread, at once (a frame's thread and a page loader's); Attach() and SetLimit() only
 * while no other call runs.
 */
class ResidentLimit
{
public:
  void Attach(void* data, uint64_t bytes);
  void SetLimit(uint64_t bytes) { this->Limit = bytes; }
  uint64_t GetLimit() const { return this->Limit; }
  /**
   * Bytes of the process's own memory that count against the limit beside the mapping's pages
   * (the arrays the filters keep for the octree, which grow with it): Enforce() keeps the
   * mapping within the limit less these, and at least an eighth of the limit (a view needs its
   * pages). Any thread, at any time.
   */
  void SetHeld(uint64_t bytes) { this->Held.store(bytes, std::memory_order_relaxed); }
  uint64_t GetHeld() const { return this->Held.load(std::memory_order_relaxed); }
  /// What Enforce() lets the mapping hold now (see SetHeld; 0: no limit).
  uint64_t GetAllowed() const
  {
    const uint64_t held = this->GetHeld();
    return this->Limit == 0
      ? 0
      : std::max(this->Limit / 8, this->Limit > held ? this->Limit - held : 0);
  }
  /**
   * Drops the mapping's file pages from the process when they exceed the limit. Returns false,
   * with `why`, when the limit cannot be kept (no page map, no statm), at that call and every
   * later one (it is not tried again). A call waits for one running in another thread.
   */
  bool Enforce(std::string* why);
  /// How many times Enforce() dropped the pages, and how many bytes in all (without waiting for
  /// a count running in another thread: a frame reads them after each execution).
  uint64_t GetReleases() const;
  uint64_t GetReleasedBytes() const;
  /// Counts the attached mapping's pages now (MeasureMappingResidency, nothing dropped); false
  /// when none is attached or the page map cannot be read.
  bool Measure(MappingResidency& out, std::string* why) const
  {
    return this->Data && MeasureMappingResidency(this->Data, this->Bytes, false, out, why);
  }
  /// Drops the mapping's file pages from the process now, whatever the limit (written pages
  /// kept); false, with `why`, when none is attached or the page map cannot be read.
  bool Release(std::string* why);
  /// The mapping's file pages present when Enforce() last counted them exactly.
  uint64_t GetLastCountedBytes() const;

private:
  /// Counts the mapping exactly (and drops its file pages when `release`); false when it cannot.
  /// Called under the lock.
  bool Count(bool release, std::string* why);

  mutable std::mutex Mutex; // over everything below but the mapping, the limit and the atomics
  void* Data = nullptr;
  uint64_t Bytes = 0;
  uint64_t Limit = 0;
  std::atomic<uint64_t> Held{ 0 };
  // the process's file-backed resident bytes other than this mapping's, as of the last count
  int64_t Others = 0;
  uint64_t LastCounted = 0;
  std::atomic<uint64_t> Releases{ 0 };
  std::atomic<uint64_t> ReleasedBytes{ 0 };
  bool Broken = false;
  std::string WhyBroken;
};

/// `bytes` of zero pages that take memory when first used (an anonymous private map); throws
/// std::bad_alloc when they cannot be had. Null for 0 bytes.
void* MapZeroPages(size_t bytes);
/// Gives back what MapZeroPages gave.
void UnmapZeroPages(void* data, size_t bytes);
/// Makes `bytes` from `data` (a MapZeroPages block) zero again, giving their pages back.
void ZeroPagesAgain(void* data, size_t bytes);
/// Gives `bytes` from `data` (within a MapZeroPages block) their memory, writable, keeping their
/// values (madvise MADV_POPULATE_WRITE, else a write of each page that changes nothing).
void PopulateZeroPages(void* data, size_t bytes);

/**
 * A fixed number of values of a trivially copyable `T`, all zero at first, whose memory is
 * taken a chunk at a time (64 KiB) as values are used (see the file documentation). Every
 * access goes through operator[], which gives the value's chunk its memory, writable, before
 * the first use: reading untouched anonymous memory would map the kernel's shared zero page,
 * and the first write there would then replace it under every thread of the process (a TLB
 * shootdown per page: docs/benchmarks.md). The check costs a load and a branch an access: arrays
 * used for every triangle drawn are better plain. Accesses from several threads are safe as the
 * values' own accesses are.
 */
template <class T>
class ZeroPages
{
public:
  ZeroPages() = default;
  ZeroPages(const ZeroPages& o) { *this = o; }
  ZeroPages(ZeroPages&& o) noexcept { this->Swap(o); }
  ZeroPages& operator=(const ZeroPages& o)
  {
    if (this != &o)
    {
      this->Assign(o.Size);
      if (o.Size > 0)
      {
        std::memcpy(this->Data, o.Data, o.Size * sizeof(T));
        std::memset(this->Ready, 1, this->Chunks);
      }
    }
    return *this;
  }
  ZeroPages& operator=(ZeroPages&& o) noexcept
  {
    this->Swap(o);
    return *this;
  }
  ~ZeroPages()
  {
    UnmapZeroPages(this->Data, this->Size * sizeof(T));
    delete[] this->Ready;
  }

  /// `n` values, all zero (the old ones given back).
  void Assign(size_t n)
  {
    ZeroPages fresh;
    fresh.Data = static_cast<T*>(MapZeroPages(n * sizeof(T)));
    fresh.Size = n;
    fresh.Chunks = (n * sizeof(T) + ChunkBytes - 1) / ChunkBytes;
    fresh.Ready = new uint8_t[fresh.Chunks]();
    this->Swap(fresh);
  }
  /// Every value zero again, and its memory given back.
  void Zero()
  {
    ZeroPagesAgain(this->Data, this->Size * sizeof(T));
    if (this->Chunks > 0)
      std::memset(this->Ready, 0, this->Chunks);
  }
  size_t size() const { return this->Size; }
  /// The first value's address: to measure the memory taken, or to read values where the
  /// pages read were given memory by writes through operator[] (a page only read maps the
  /// kernel's zero page, and the first write through operator[] then replaces it).
  const T* data() const { return this->Data; }
  T& operator[](size_t i) const
  {
    // relaxed: the flag only spares the call; populating twice is harmless
    const size_t k = i * sizeof(T) / ChunkBytes;
    if (__builtin_expect(!__atomic_load_n(&this->Ready[k], __ATOMIC_RELAXED), 0))
      this->Populate(k);
    return this->Data[i];
  }

private:
  static constexpr size_t ChunkBytes = size_t(1) << 16;

  void Populate(size_t k) const
  {
    const size_t first = k * ChunkBytes;
    const size_t bytes = std::min(ChunkBytes, this->Size * sizeof(T) - first);
    PopulateZeroPages(reinterpret_cast<char*>(this->Data) + first, bytes);
    __atomic_store_n(&this->Ready[k], uint8_t(1), __ATOMIC_RELAXED);
  }
  void Swap(ZeroPages& o) noexcept
  {
    std::swap(this->Data, o.Data);
    std::swap(this->Size, o.Size);
    std::swap(this->Ready, o.Ready);
    std::swap(this->Chunks, o.Chunks);
  }
  T* Data = nullptr;
  size_t Size = 0;
  uint8_t* Ready = nullptr; // per chunk: 1 once populated
  size_t Chunks = 0;
};

} // namespace plod

#endif
