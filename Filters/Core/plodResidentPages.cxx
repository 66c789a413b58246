// SPDX-License-Identifier: BSD-3-Clause
#include "plodResidentPages.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#if defined(__linux__)
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace plod
{

namespace
{
void Fail(std::string* why, const std::string& what)
{
  if (why)
    *why = what;
}

#if defined(__linux__)
/// Drops the pages [first, first + count) of the mapping that starts at `base`.
void DropPages(char* base, uint64_t first, uint64_t count, uint64_t page)
{
  if (count > 0)
    ::madvise(base + first * page, static_cast<size_t>(count * page), MADV_DONTNEED);
}
#endif
} // namespace

bool MeasureMappingResidency(
  void* data, uint64_t bytes, bool release, MappingResidency& out, std::string* why)
{
  out = MappingResidency();
#if defined(__linux__)
  const long pageSize = ::sysconf(_SC_PAGESIZE);
  if (pageSize <= 0 || !data || reinterpret_cast<uintptr_t>(data) % uint64_t(pageSize) != 0)
  {
    Fail(why, "the mapping does not start on a page");
    return false;
  }
  const uint64_t page = uint64_t(pageSize);
  const int fd = ::open("/proc/self/pagemap", O_RDONLY | O_CLOEXEC);
  if (fd < 0)
  {
    Fail(why, std::string("/proc/self/pagemap cannot be read (") + std::strerror(errno) + ")");
    return false;
  }
  // bits of a page map entry (the kernel's Documentation/admin-guide/mm/pagemap.rst)
  constexpr uint64_t Present = uint64_t(1) << 63;
  constexpr uint64_t FilePage = uint64_t(1) << 61;
  const uint64_t firstPage = reinterpret_cast<uintptr_t>(data) / page;
  const uint64_t pages = (bytes + page - 1) / page;
  char* base = static_cast<char*>(data);
  std::vector<uint64_t> entries(std::min<uint64_t>(pages, 65536));
  uint64_t runStart = 0, runLength = 0; // the file pages present, to drop together
  bool ok = true;
  for (uint64_t done = 0; done < pages && ok;)
  {
    const uint64_t n = std::min<uint64_t>(entries.size(), pages - done);
    const size_t want = static_cast<size_t>(n * sizeof(uint64_t));
    size_t got = 0;
    while (got < want)
    {
      const ssize_t r = ::pread(fd, reinterpret_cast<char*>(entries.data()) + got, want - got,
        off_t((firstPage + done) * sizeof(uint64_t) + got));
      if (r <= 0)
      {
        Fail(why, "/proc/self/pagemap ended early");
        ok = false;
        break;
      }
      got += size_t(r);
    }
    for (uint64_t i = 0; ok && i < n; ++i)
    {
      const uint64_t e = entries[i];
      const bool file = (e & Present) && (e & FilePage);
      if (e & Present)
        (file ? out.FileBytes : out.PrivateBytes) += page;
      if (!release)
        continue;
      if (file && runLength > 0 && runStart + runLength == done + i)
        ++runLength;
      else if (file)
      {
        DropPages(base, runStart, runLength, page);
        runStart = done + i;
        runLength = 1;
      }
    }
    done += n;
  }
  if (release)
    DropPages(base, runStart, runLength, page);
  ::close(fd);
  return ok;
#else
  (void)data;
  (void)bytes;
  (void)release;
  Fail(why, "counting a mapping's resident pages needs Linux's /proc/self/pagemap");
  return false;
#endif
}

int64_t ProcessFileResidentBytes()
{
#if defined(__linux__)
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f)
    return -1;
  long long size = 0, resident = 0, shared = 0;
  const int fields = std::fscanf(f, "%lld %lld %lld", &size, &resident, &shared);
  std::fclose(f);
  const long pageSize = ::sysconf(_SC_PAGESIZE);
  if (fields != 3 || pageSize <= 0 || shared < 0)
    return -1;
  return int64_t(shared) * int64_t(pageSize);
#else
  return -1;
#endif
}

void ResidentLimit::Attach(void* data, uint64_t bytes)
{
  this->Data = data;
  this->Bytes = bytes;
  this->Others = -1; // counted exactly at the first Enforce()
  this->LastCounted = 0;
  this->Broken = false;
}

bool ResidentLimit::Count(bool release, std::string* why)
{
  MappingResidency r;
  if (!MeasureMappingResidency(this->Data, this->Bytes, release, r, why))
  {
    this->Broken = true;
    return false;
  }
  this->LastCounted = release ? 0 : r.FileBytes;
  if (release)
  {
    ++this->Releases;
    this->ReleasedBytes += r.FileBytes;
  }
  return true;
}

bool ResidentLimit::Enforce(std::string* why)
{
  if (this->Limit == 0 || !this->Data || this->Bytes == 0 || this->Broken)
    return true;
  const int64_t before = ProcessFileResidentBytes();
  if (before < 0)
  {
    this->Broken = true;
    Fail(why, "/proc/self/statm cannot be read: the resident limit is not kept");
    return false;
  }
  // the mapping holds at most what the process's file pages grew by since the last count
  if (this->Others >= 0 && before - this->Others <= int64_t(this->Limit))
    return true;
  if (!this->Count(false, why))
    return false;
  if (this->LastCounted > this->Limit && !this->Count(true, why))
    return false;
  const int64_t after = ProcessFileResidentBytes();
  this->Others = std::max<int64_t>(0, (after < 0 ? before : after) - int64_t(this->LastCounted));
  return true;
}

} // namespace plod
