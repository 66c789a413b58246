// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodLargeArrays.h
 * @brief Work arrays of the builds, in memory the kernel may back with huge pages.
 *
 * A build writes every element of arrays of hundreds of megabytes once and reads them a few
 * times. In small pages, each 4 KiB costs a page fault the first time it is touched and a TLB
 * entry while it is read; on a kernel whose transparent huge pages are enabled only "madvise"
 * (a common default) that is a fault per 4 KiB of every array. LargeAllocator maps allocations
 * of LargeAllocationBytes and more on their own, aligned to 2 MiB, and advises them for huge
 * pages (`madvise(MADV_HUGEPAGE)`); smaller ones come from `operator new`. Where the kernel has
 * no transparent huge pages the advice is ignored and the arrays are ordinary pages. Built with
 * a sanitizer, every buffer comes from `operator new` (the sanitizer watches those).
 *
 * Meant for arrays written whole soon after they are made (a build's): an array touched only
 * here and there would take 2 MiB where it touches a byte. Where free memory is fragmented, the
 * kernel may compact it when a huge page is first touched (its `defrag` setting decides).
 *
 * @code
 * plod::LargeVector<double> points(3 * n); // a std::vector with LargeAllocator
 * @endcode
 */
#ifndef plodLargeArrays_h
#define plodLargeArrays_h

#include <cstddef>
#include <vector>

namespace plod
{

/// Allocations from this size on are mapped on their own and advised for huge pages.
constexpr size_t LargeAllocationBytes = size_t(4) << 20;

/// The alignment and granularity of a large allocation (the huge page size on x86-64 and most
/// arm64 kernels).
constexpr size_t HugePageBytes = size_t(2) << 20;

/// Whether large buffers are mapped apart: not in a build with a sanitizer, whose checks watch
/// the buffers of operator new only.
bool LargeArraysAreMapped();

/// `bytes` of memory: mapped and advised for huge pages from LargeAllocationBytes on, from
/// `operator new` below. Throws std::bad_alloc when there is no memory.
void* AllocateLarge(size_t bytes);

/// Frees what AllocateLarge(bytes) returned (the same `bytes`).
void FreeLarge(void* p, size_t bytes) noexcept;

/// Advises the whole huge pages within [p, p + bytes) for huge pages, when `bytes` is at least
/// LargeAllocationBytes: for arrays another allocator made and nothing has touched yet.
void AdviseHugePages(void* p, size_t bytes) noexcept;

/// A standard allocator over AllocateLarge/FreeLarge (stateless: all instances are equal).
template <typename T>
struct LargeAllocator
{
  using value_type = T;

  LargeAllocator() = default;
  template <typename U>
  LargeAllocator(const LargeAllocator<U>&) noexcept
  {
  }

  T* allocate(size_t n) { return static_cast<T*>(AllocateLarge(n * sizeof(T))); }
  void deallocate(T* p, size_t n) noexcept { FreeLarge(p, n * sizeof(T)); }

  template <typename U>
  bool operator==(const LargeAllocator<U>&) const noexcept
  {
    return true;
  }
  template <typename U>
  bool operator!=(const LargeAllocator<U>&) const noexcept
  {
    return false;
  }
};

/// A std::vector whose large buffers may be backed by huge pages.
template <typename T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

} // namespace plod

#endif
