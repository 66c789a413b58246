// SPDX-License-Identifier: BSD-3-Clause
// plod::LargeAllocator: large buffers mapped on their own, 2 MiB aligned, advised for huge pages,
// unmapped whole; small ones from operator new; no memory gives std::bad_alloc.
#include "plodLargeArrays.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <new>
#include <sstream>
#include <string>

namespace
{

/// The mappings of this process (/proc/self/smaps) that overlap [p, p + bytes): how many there
/// are, and whether every one of them is advised for huge pages (VmFlags "hg").
struct Overlap
{
  int Mappings = 0;
  bool AllAdvised = true;
};

Overlap MappingsOver(const void* p, size_t bytes)
{
  const uintptr_t lo = reinterpret_cast<uintptr_t>(p), hi = lo + bytes;
  std::ifstream smaps("/proc/self/smaps");
  Overlap o;
  bool inside = false;
  std::string line;
  while (std::getline(smaps, line))
  {
    uintptr_t a = 0, b = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> a >> dash >> b && dash == '-')
    {
      inside = a < hi && b > lo;
      o.Mappings += inside;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0)
    {
      o.AllAdvised = o.AllAdvised && line.find(" hg") != std::string::npos;
    }
  }
  return o;
}

bool KernelHasHugePages()
{
  return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good();
}

#define SKIP_UNLESS_MAPPED()                                                                       \
  if (!plod::LargeArraysAreMapped())                                                               \
  {                                                                                                \
    GTEST_SKIP() << "built with a sanitizer: large buffers come from operator new";                \
  }

TEST(LargeArrays, LargeBuffersAreAlignedAdvisedAndKeepTheirValues)
{
  SKIP_UNLESS_MAPPED();
  if (!KernelHasHugePages())
  {
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  }
  const size_t n = (size_t(9) << 20) / sizeof(double); // 9 MiB: not a whole number of 2 MiB
  plod::LargeVector<double> v(n);
  const uintptr_t at = reinterpret_cast<uintptr_t>(v.data());
  EXPECT_EQ(at % plod::HugePageBytes, 0u) << "not on a huge page boundary";
  const Overlap o = MappingsOver(v.data(), n * sizeof(double));
  EXPECT_EQ(o.Mappings, 1) << "the buffer is not one mapping of its own";
  EXPECT_TRUE(o.AllAdvised) << "the buffer is not advised for huge pages";
  for (size_t i = 0; i < n; ++i)
  {
    v[i] = double(i) * 0.5;
  }
  // growth copies the values into a new buffer of its own
  v.push_back(-1.0);
  for (size_t i = 0; i < n; i += 4099)
  {
    ASSERT_EQ(v[i], double(i) * 0.5);
  }
  EXPECT_EQ(v.back(), -1.0);
}

TEST(LargeArrays, AFreedBufferLeavesNoMappingBehind)
{
  SKIP_UNLESS_MAPPED();
  const size_t bytes = (size_t(5) << 20) + 12345;
  void* p = plod::AllocateLarge(bytes);
  ASSERT_NE(p, nullptr);
  static_cast<char*>(p)[bytes - 1] = 1; // the last byte is usable
  EXPECT_EQ(MappingsOver(p, bytes).Mappings, 1);
  plod::FreeLarge(p, bytes);
  // up to the next huge page boundary: the rounded length is unmapped too
  const size_t rounded =
    (bytes + plod::HugePageBytes - 1) / plod::HugePageBytes * plod::HugePageBytes;
  EXPECT_EQ(MappingsOver(p, rounded).Mappings, 0) << "part of the buffer is still mapped";
}

TEST(LargeArrays, SmallBuffersComeFromOperatorNew)
{
  // below LargeAllocationBytes: the heap's memory, shared with other allocations, not advised
  const size_t bytes = plod::LargeAllocationBytes / 4;
  void* p = plod::AllocateLarge(bytes);
  ASSERT_NE(p, nullptr);
  EXPECT_FALSE(reinterpret_cast<uintptr_t>(p) % plod::HugePageBytes == 0 && KernelHasHugePages() &&
    MappingsOver(p, bytes).AllAdvised)
    << "a small buffer was mapped and advised on its own";
  plod::FreeLarge(p, bytes);
  plod::FreeLarge(nullptr, bytes); // as operator delete: nothing
}

TEST(LargeArrays, AnotherAllocatorsBufferIsAdvisedWithin)
{
  SKIP_UNLESS_MAPPED(); // the sanitizer's malloc places buffers its own way
  if (!KernelHasHugePages())
  {
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  }
  // malloc maps a buffer this large on its own, not aligned to 2 MiB: the whole huge pages
  // inside it are advised, nothing outside it
  const size_t bytes = size_t(16) << 20;
  char* p = static_cast<char*>(std::malloc(bytes));
  ASSERT_NE(p, nullptr);
  const uintptr_t first = (reinterpret_cast<uintptr_t>(p) + plod::HugePageBytes - 1) /
    plod::HugePageBytes * plod::HugePageBytes;
  plod::AdviseHugePages(p, bytes);
  const Overlap inner = MappingsOver(reinterpret_cast<void*>(first), size_t(12) << 20);
  EXPECT_GE(inner.Mappings, 1);
  EXPECT_TRUE(inner.AllAdvised) << "the huge pages inside the buffer are not advised";
  if (first > reinterpret_cast<uintptr_t>(p))
  {
    EXPECT_FALSE(MappingsOver(p, 1).AllAdvised) << "advice before the first whole huge page";
  }
  std::free(p);
}

TEST(LargeArrays, NoMemoryIsBadAlloc)
{
  SKIP_UNLESS_MAPPED(); // a sanitizer reports the allocation instead of throwing
  EXPECT_THROW(plod::AllocateLarge(~size_t(0) - 10), std::bad_alloc); // rounding overflows
  EXPECT_THROW(plod::AllocateLarge(size_t(1) << 60), std::bad_alloc); // no such memory
}

} // namespace
