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

/// Whether a buffer of `bytes` is mapped apart (else it comes from operator new).
bool MappedApart(size_t bytes)
{
  return Mapped && bytes >= LargeAllocationBytes;
}

uintptr_t RoundUpToHugePages(uintptr_t x)
{
  return (x + HugePageBytes - 1) / HugePageBytes * HugePageBytes;
}

uintptr_t RoundDownToHugePages(uintptr_t x)
{
  return x / HugePageBytes * HugePageBytes;
}

/// Advises [first, last), whole huge pages, for huge pages (advice only: ignored by a kernel
/// without transparent huge pages).
void Advise(uintptr_t first, uintptr_t last)
{
#ifdef MADV_HUGEPAGE
  if (last > first)
  {
    ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#else
  (void)first;
  (void)last;
#endif
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
  if (!MappedApart(bytes))
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
  const uintptr_t aligned = RoundUpToHugePages(start);
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
  Advise(aligned, end);
  return reinterpret_cast<void*>(aligned);
}

//------------------------------------------------------------------------------
void AdviseHugePages(void* p, size_t bytes) noexcept
{
  if (!p || bytes < LargeAllocationBytes)
  {
    return;
  }
  const uintptr_t start = reinterpret_cast<uintptr_t>(p);
  Advise(RoundUpToHugePages(start), RoundDownToHugePages(start + bytes));
}

//------------------------------------------------------------------------------
void FreeLarge(void* p, size_t bytes) noexcept
{
  if (!p)
  {
    return;
  }
  if (!MappedApart(bytes))
  {
    ::operator delete(p);
    return;
  }
  ::munmap(p, RoundUpToHugePages(bytes));
}

} // namespace plod
