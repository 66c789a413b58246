// SPDX-License-Identifier: BSD-3-Clause
// The bound on a mapped file's resident pages (plodResidentPages): the pages a process holds of a
// mapping are counted page by page (file pages apart from written ones), dropping them keeps the
// bytes and every edit, and ResidentLimit drops them exactly when they exceed its limit.
#include "plodResidentPages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace
{
/// A file of `pages` pages whose every 8-byte word holds its own index, mapped copy-on-write as
/// the octree reader maps (read and write, private).
struct MappedFile
{
  std::string Path;
  uint64_t Bytes = 0;
  uint64_t Page = 0;
  char* Data = nullptr;

  explicit MappedFile(uint64_t pages)
  {
    this->Page = uint64_t(::sysconf(_SC_PAGESIZE));
    this->Bytes = pages * this->Page;
    this->Path = ::testing::TempDir() + "plod_resident_" + std::to_string(::getpid());
    {
      std::vector<uint64_t> words(this->Bytes / 8);
      for (uint64_t i = 0; i < words.size(); ++i)
        words[i] = i;
      std::ofstream out(this->Path, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(words.data()), std::streamsize(this->Bytes));
    }
    const int fd = ::open(this->Path.c_str(), O_RDONLY);
    void* p = ::mmap(nullptr, this->Bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE, fd, 0);
    ::close(fd);
    this->Data = p == MAP_FAILED ? nullptr : static_cast<char*>(p);
  }
  ~MappedFile()
  {
    if (this->Data)
      ::munmap(this->Data, this->Bytes);
    std::remove(this->Path.c_str());
  }
  /// Reads one word of each page in [first, first + count): the sum of their values.
  uint64_t Touch(uint64_t first, uint64_t count) const
  {
    uint64_t sum = 0;
    for (uint64_t p = first; p < first + count; ++p)
      sum += *reinterpret_cast<const volatile uint64_t*>(this->Data + p * this->Page);
    return sum;
  }
  plod::MappingResidency Measure(bool release = false) const
  {
    plod::MappingResidency r;
    std::string why;
    EXPECT_TRUE(plod::MeasureMappingResidency(this->Data, this->Bytes, release, r, &why)) << why;
    return r;
  }
};

bool PageMapReadable()
{
  std::FILE* f = std::fopen("/proc/self/pagemap", "rb");
  if (f)
    std::fclose(f);
  return f != nullptr;
}

/// A mapped file of 4096 pages, none of them resident, and a limit attached to it (no limit
/// set); not usable where the page map cannot be read or the file not mapped.
struct LimitedFile
{
  MappedFile File{ 4096 };
  plod::ResidentLimit Limit;
  bool Usable() const { return this->File.Data && PageMapReadable(); }
  LimitedFile()
  {
    if (this->Usable())
    {
      this->File.Measure(true);
      this->Limit.Attach(this->File.Data, this->File.Bytes);
    }
  }
};
} // namespace

TEST(ResidentPages, CountsAndDropsFilePagesKeepingEdits)
{
  if (!PageMapReadable())
    GTEST_SKIP() << "/proc/self/pagemap cannot be read here";
  MappedFile f(256);
  ASSERT_NE(f.Data, nullptr);
  f.Measure(true); // whatever writing the file left mapped (nothing: it was written, not mapped)
  EXPECT_EQ(f.Measure().FileBytes, 0u);
  // every page read: all present, none written
  const uint64_t wordsPerPage = f.Page / 8;
  uint64_t expected = 0;
  for (uint64_t p = 0; p < 256; ++p)
    expected += p * wordsPerPage;
  EXPECT_EQ(f.Touch(0, 256), expected);
  plod::MappingResidency r = f.Measure();
  EXPECT_EQ(r.FileBytes, f.Bytes);
  EXPECT_EQ(r.PrivateBytes, 0u);
  // two pages written: private copies, no longer file pages
  reinterpret_cast<uint64_t*>(f.Data + 10 * f.Page)[3] = 777;
  reinterpret_cast<uint64_t*>(f.Data + 200 * f.Page)[0] = 888;
  r = f.Measure();
  EXPECT_EQ(r.FileBytes, f.Bytes - 2 * f.Page);
  EXPECT_EQ(r.PrivateBytes, 2 * f.Page);
  // dropped: the count is the one before, then only the written pages remain
  r = f.Measure(true);
  EXPECT_EQ(r.FileBytes, f.Bytes - 2 * f.Page);
  r = f.Measure();
  EXPECT_EQ(r.FileBytes, 0u);
  EXPECT_EQ(r.PrivateBytes, 2 * f.Page);
  // the bytes read again are the file's, and the edits are kept
  EXPECT_EQ(reinterpret_cast<const uint64_t*>(f.Data + 10 * f.Page)[3], 777u);
  EXPECT_EQ(reinterpret_cast<const uint64_t*>(f.Data + 200 * f.Page)[0], 888u);
  EXPECT_EQ(reinterpret_cast<const uint64_t*>(f.Data + 10 * f.Page)[4], 10 * wordsPerPage + 4);
  EXPECT_EQ(f.Touch(0, 256), expected - 200 * wordsPerPage + 888);
  EXPECT_EQ(f.Measure().FileBytes, f.Bytes - 2 * f.Page);
}

TEST(ResidentPages, LimitDropsPagesOnlyAboveIt)
{
  // How many pages one read maps depends on the kernel (fault-around, large folios of the page
  // cache): the limits are set from what is counted present, to the page.
  LimitedFile limited;
  if (!limited.Usable())
    GTEST_SKIP() << "/proc/self/pagemap cannot be read here, or the file cannot be mapped";
  MappedFile& f = limited.File;
  plod::ResidentLimit& limit = limited.Limit;
  std::string why;
  // no limit: nothing dropped whatever is read
  f.Touch(0, 4096);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 0u);
  EXPECT_EQ(f.Measure().FileBytes, f.Bytes);
  f.Measure(true);
  // a quarter of the file read, the limit exactly what is present: kept
  f.Touch(0, 1024);
  const uint64_t present = f.Measure().FileBytes;
  ASSERT_GE(present, 1024 * f.Page);
  ASSERT_LT(present, f.Bytes);
  limit.SetLimit(present);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 0u);
  EXPECT_EQ(f.Measure().FileBytes, present);
  EXPECT_EQ(limit.GetLastCountedBytes(), present);
  // one page less: dropped, all of them
  limit.SetLimit(present - f.Page);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 1u);
  EXPECT_EQ(limit.GetReleasedBytes(), present);
  EXPECT_EQ(f.Measure().FileBytes, 0u);
  // under the limit again (the cheap check from the process's figures): nothing dropped
  f.Touch(0, 16);
  const uint64_t few = f.Measure().FileBytes;
  ASSERT_LE(few, limit.GetLimit());
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 1u);
  EXPECT_EQ(f.Measure().FileBytes, few);
  // everything read: over the limit, dropped again, and the bytes read again are the file's
  const uint64_t wordsPerPage = f.Page / 8;
  uint64_t expected = 0;
  for (uint64_t p = 0; p < 4096; ++p)
    expected += p * wordsPerPage;
  EXPECT_EQ(f.Touch(0, 4096), expected);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 2u);
  EXPECT_EQ(limit.GetReleasedBytes(), present + f.Bytes);
  EXPECT_EQ(f.Measure().FileBytes, 0u);
  EXPECT_EQ(f.Touch(0, 4096), expected);
}

TEST(ResidentPages, HeldBytesCountAgainstTheLimit)
{
  // The filters' own arrays (SetHeld) share the limit with the mapping: the mapping is kept
  // within the limit less them, and at least an eighth of the limit.
  std::string why;
  LimitedFile limited;
  if (!limited.Usable())
    GTEST_SKIP() << "/proc/self/pagemap cannot be read here, or the file cannot be mapped";
  MappedFile& f = limited.File;
  plod::ResidentLimit& limit = limited.Limit;
  f.Touch(0, 1024);
  const uint64_t present = f.Measure().FileBytes;
  ASSERT_GE(present, 1024 * f.Page);
  ASSERT_LT(present, f.Bytes / 2);
  // the limit twice what is present, half of it held: kept, exactly
  limit.SetLimit(2 * present);
  limit.SetHeld(present);
  EXPECT_EQ(limit.GetHeld(), present);
  EXPECT_EQ(limit.GetAllowed(), present);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 0u);
  EXPECT_EQ(f.Measure().FileBytes, present);
  // a page more held: the mapping is over what is left, dropped
  limit.SetHeld(present + f.Page);
  EXPECT_EQ(limit.GetAllowed(), present - f.Page);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 1u);
  EXPECT_EQ(f.Measure().FileBytes, 0u);
  // held beyond the limit: the mapping keeps an eighth of it (here what the quarter maps)
  limit.SetLimit(8 * present);
  limit.SetHeld(100 * present);
  EXPECT_EQ(limit.GetAllowed(), present);
  f.Touch(0, 1024);
  ASSERT_EQ(f.Measure().FileBytes, present);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 1u);
  EXPECT_EQ(f.Measure().FileBytes, present);
  f.Touch(0, 2048);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 2u);
  EXPECT_EQ(f.Measure().FileBytes, 0u);
  // no limit: nothing held counts
  limit.SetLimit(0);
  EXPECT_EQ(limit.GetAllowed(), 0u);
  f.Touch(0, 4096);
  EXPECT_TRUE(limit.Enforce(&why)) << why;
  EXPECT_EQ(limit.GetReleases(), 2u);
}

TEST(ResidentPages, NothingToKeepWithoutAMapping)
{
  plod::ResidentLimit limit;
  limit.SetLimit(4096);
  std::string why;
  EXPECT_TRUE(limit.Enforce(&why));
  EXPECT_EQ(limit.GetReleases(), 0u);
  plod::MappingResidency r;
  int unaligned[4];
  EXPECT_FALSE(plod::MeasureMappingResidency(unaligned + 1, 8, false, r, &why));
  EXPECT_NE(why.find("page"), std::string::npos) << why;
  EXPECT_GE(plod::ProcessFileResidentBytes(), 0);
}

TEST(ResidentPages, ZeroPagesTakeMemoryWhereWritten)
{
  // 64 MiB of zeros, three values written and two read: at most five chunks of 64 KiB taken, or
  // five huge pages where the kernel backs anonymous memory with them (2 MiB each)
  const size_t n = size_t(16) << 20;
  plod::ZeroPages<int32_t> a;
  a.Assign(n);
  ASSERT_EQ(a.size(), n);
  EXPECT_EQ(a[0], 0);
  EXPECT_EQ(a[n / 2], 0);
  EXPECT_EQ(a[n - 1], 0);
  a[12] = 7;
  a[n / 3] = -5;
  a[n - 1] = 9;
  plod::MappingResidency r;
  std::string why;
  if (PageMapReadable())
  {
    ASSERT_TRUE(plod::MeasureMappingResidency(
      const_cast<int32_t*>(a.data()), n * sizeof(int32_t), false, r, &why))
      << why;
    EXPECT_EQ(r.FileBytes, 0u);
    EXPECT_GT(r.PrivateBytes, 0u);
    EXPECT_LE(r.PrivateBytes, size_t(5) << 21);
  }
  // a copy holds the same values; the original zeroed gives its memory back and reads zero
  plod::ZeroPages<int32_t> b = a;
  a.Zero();
  if (PageMapReadable())
  {
    ASSERT_TRUE(plod::MeasureMappingResidency(
      const_cast<int32_t*>(a.data()), n * sizeof(int32_t), false, r, &why))
      << why;
    EXPECT_EQ(r.PrivateBytes + r.FileBytes, 0u);
  }
  EXPECT_EQ(a[12], 0);
  EXPECT_EQ(a[n / 3], 0);
  EXPECT_EQ(a[n - 1], 0);
  EXPECT_EQ(b[12], 7);
  EXPECT_EQ(b[n / 3], -5);
  EXPECT_EQ(b[n - 1], 9);
  EXPECT_EQ(b[13], 0);
  // a size that is not a whole number of pages: the tail is zeroed too
  plod::ZeroPages<uint8_t> c;
  c.Assign(5000);
  c[4999] = 1;
  c[100] = 2;
  c.Zero();
  EXPECT_EQ(c[4999], 0);
  EXPECT_EQ(c[100], 0);
  // moved: the source is empty; assigned again: zero
  plod::ZeroPages<int32_t> d = std::move(b);
  EXPECT_EQ(b.size(), 0u);
  EXPECT_EQ(d[n / 3], -5);
  d.Assign(10);
  EXPECT_EQ(d.size(), 10u);
  EXPECT_EQ(d[3], 0);
}
