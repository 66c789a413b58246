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
 * The bound holds between frames (the caller enforces it after each frame's reads). A frame
 * that reads more than the limit holds more while it runs, and every such frame maps its pages
 * again: the limit should exceed what one view reads (a triangle budget bounds that).
 *
 * Measuring is two steps, so that a frame under the limit costs one small read of
 * /proc/self/statm (the process's resident file-backed pages): only when those grew by more
 * than the limit since the last exact count is the mapping counted page by page, from
 * /proc/self/pagemap (8 bytes read per page mapped). Other mappings that grow (libraries, other
 * octrees) make the exact count come sooner, never later; pages of other files that the kernel
 * reclaims meanwhile can let the mapping exceed the limit by as much until the next count. A page that was written (a private copy:
 * the mapping is copy-on-write) is never dropped, so edits of the arrays are never lost.
 * Linux only; elsewhere, or where /proc is unreadable, Enforce() does nothing and says why.
 */
#ifndef plodResidentPages_h
#define plodResidentPages_h

#include <cstdint>
#include <string>

namespace plod
{

/// What a process holds of a mapping: pages of the file, and pages written (private copies).
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
 * after each frame keeps it within Limit bytes (0: no limit).
 */
class ResidentLimit
{
public:
  void Attach(void* data, uint64_t bytes);
  void SetLimit(uint64_t bytes) { this->Limit = bytes; }
  uint64_t GetLimit() const { return this->Limit; }
  /**
   * Drops the mapping's file pages from the process when they exceed the limit. Returns false,
   * with `why`, when the limit cannot be kept (no page map, no statm): it is then not tried
   * again.
   */
  bool Enforce(std::string* why);
  /// How many times Enforce() dropped the pages, and how many bytes in all.
  uint64_t GetReleases() const { return this->Releases; }
  uint64_t GetReleasedBytes() const { return this->ReleasedBytes; }
  /// The mapping's file pages present when Enforce() last counted them exactly.
  uint64_t GetLastCountedBytes() const { return this->LastCounted; }

private:
  /// Counts the mapping exactly (and drops its file pages when `release`); false when it cannot.
  bool Count(bool release, std::string* why);

  void* Data = nullptr;
  uint64_t Bytes = 0;
  uint64_t Limit = 0;
  // the process's file-backed resident bytes other than this mapping's, as of the last count
  int64_t Others = 0;
  uint64_t LastCounted = 0;
  uint64_t Releases = 0;
  uint64_t ReleasedBytes = 0;
  bool Broken = false;
};

} // namespace plod

#endif
