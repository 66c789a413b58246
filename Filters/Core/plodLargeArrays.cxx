// SPDX-License-Identifier: BSD-3-Clause
// Large work arrays advised for huge pages. See plodLargeArrays.h.
#include "plodLargeArrays.h"

#include <cstdint>
#include <new>

#include <sys/mman.h>

namespace plod
{

namespace
{

// Under a sanitizer every buffer comes from operator new, where the sanitizer checks the
// accesses (it does not watch memory mapped apart).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool Mapped = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer)
constexpr bool Mapped = false;
#else
constexpr bool Mapped = true;
#endif
#else
constexpr bool Mapped = true;
#endif

size_t RoundUpToHugePages(size_t bytes)
{
  return (bytes + HugePageBytes - 1) / HugePageBytes * HugePageBytes;
}

} // namespace

//------------------------------------------------------------------------------
bool LargeArraysAreMapped()
{
  return Mapped;
}

//------------------------------------------------------------------------------
void* AllocateLarge(size_t bytes)
{
  if (!Mapped || bytes < LargeAllocationBytes)
  {
    return ::operator new(bytes);
  }
  // a mapping one huge page longer than needed, trimmed to the aligned part, so that every
  // page of the array can be a huge page
  const size_t length = RoundUpToHugePages(bytes);
  if (length < bytes || length + HugePageBytes < length)
  {
    throw std::bad_alloc();
  }
  void* mapped = ::mmap(
    nullptr, length + HugePageBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED)
  {
    throw std::bad_alloc();
  }
  const uintptr_t start = reinterpret_cast<uintptr_t>(mapped);
  const uintptr_t aligned = (start + HugePageBytes - 1) / HugePageBytes * HugePageBytes;
  if (aligned > start)
  {
    ::munmap(mapped, aligned - start);
  }
  const uintptr_t end = aligned + length;
  const uintptr_t mappedEnd = start + length + HugePageBytes;
  if (mappedEnd > end)
  {
    ::munmap(reinterpret_cast<void*>(end), mappedEnd - end);
  }
  void* p = reinterpret_cast<void*>(aligned);
#ifdef MADV_HUGEPAGE
  ::madvise(p, length, MADV_HUGEPAGE); // advice only: ignored without transparent huge pages
#endif
  return p;
}

//------------------------------------------------------------------------------
void AdviseHugePages(void* p, size_t bytes) noexcept
{
  if (!p || bytes < LargeAllocationBytes)
  {
    return;
  }
  const uintptr_t start = reinterpret_cast<uintptr_t>(p);
  const uintptr_t first = (start + HugePageBytes - 1) / HugePageBytes * HugePageBytes;
  const uintptr_t last = (start + bytes) / HugePageBytes * HugePageBytes;
#ifdef MADV_HUGEPAGE
  if (last > first)
  {
    ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#endif
}

//------------------------------------------------------------------------------
void FreeLarge(void* p, size_t bytes) noexcept
{
  if (!p)
  {
    return;
  }
  if (!Mapped || bytes < LargeAllocationBytes)
  {
    ::operator delete(p);
    return;
  }
  ::munmap(p, RoundUpToHugePages(bytes));
}

} // namespace plod
