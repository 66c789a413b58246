// SPDX-License-Identifier: BSD-3-Clause
#include "plodResidentPages.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
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
  // read into a buffer of its own: called after every frame, it allocates nothing
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    return -1;
  char text[160];
  const ssize_t got = ::read(fd, text, sizeof(text) - 1);
  ::close(fd);
  if (got <= 0)
    return -1;
  text[got] = '\0';
  long long size = 0, resident = 0, shared = 0;
  const long pageSize = ::sysconf(_SC_PAGESIZE);
  if (std::sscanf(text, "%lld %lld %lld", &size, &resident, &shared) != 3 || pageSize <= 0 ||
    shared < 0)
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
  this->WhyBroken.clear();
}

bool ResidentLimit::Count(bool release, std::string* why)
{
  MappingResidency r;
  if (!MeasureMappingResidency(this->Data, this->Bytes, release, r, &this->WhyBroken))
  {
    this->Broken = true;
    Fail(why, this->WhyBroken);
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
  if (this->Limit == 0 || !this->Data || this->Bytes == 0)
    return true;
  const std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->Broken)
  {
    Fail(why, this->WhyBroken);
    return false;
  }
  const int64_t before = ProcessFileResidentBytes();
  if (before < 0)
  {
    this->Broken = true;
    this->WhyBroken = "/proc/self/statm cannot be read: the resident limit is not kept";
    Fail(why, this->WhyBroken);
    return false;
  }
  // the mapping holds at most what the process's file pages grew by since the last count
  const uint64_t allowed = this->GetAllowed();
  if (this->Others >= 0 && before - this->Others <= int64_t(allowed))
    return true;
  if (!this->Count(false, why))
    return false;
  const uint64_t counted = this->LastCounted;
  if (counted > allowed && !this->Count(true, why))
    return false;
  // the other pages as of `before`: the mapping, counted after it, can only have grown
  // meanwhile (a page loader reads beside the frame), so this errs low and the next exact count
  // comes sooner, never later (read after the drop, the loader's new pages would count as
  // others, and the mapping could then grow past the limit unseen)
  this->Others = std::max<int64_t>(0, before - int64_t(counted));
  return true;
}

uint64_t ResidentLimit::GetReleases() const
{
  return this->Releases.load(std::memory_order_relaxed);
}

uint64_t ResidentLimit::GetReleasedBytes() const
{
  return this->ReleasedBytes.load(std::memory_order_relaxed);
}

uint64_t ResidentLimit::GetLastCountedBytes() const
{
  const std::lock_guard<std::mutex> lock(this->Mutex);
  return this->LastCounted;
}

bool ResidentLimit::Release(std::string* why)
{
  if (!this->Data)
    return false;
  const std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Count(true, why);
}

void* MapZeroPages(size_t bytes)
{
  if (bytes == 0)
    return nullptr;
#if defined(__linux__)
  void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED)
    throw std::bad_alloc();
  return p;
#else
  void* p = std::calloc(1, bytes);
  if (!p)
    throw std::bad_alloc();
  return p;
#endif
}

void UnmapZeroPages(void* data, size_t bytes)
{
  if (!data)
    return;
#if defined(__linux__)
  ::munmap(data, bytes);
#else
  (void)bytes;
  std::free(data);
#endif
}

void ZeroPagesAgain(void* data, size_t bytes)
{
  if (!data || bytes == 0)
    return;
#if defined(__linux__)
  // whole pages are given back (they read as zero again); the part of a page before the first
  // whole one and after the last is written as zero (the map starts on a page: only the tail)
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  const size_t whole = bytes / page * page;
  if (whole > 0)
    ::madvise(data, whole, MADV_DONTNEED);
  std::memset(static_cast<char*>(data) + whole, 0, bytes - whole);
#else
  std::memset(data, 0, bytes);
#endif
}

void PopulateZeroPages(void* data, size_t bytes)
{
  if (!data || bytes == 0)
    return;
#if defined(__linux__)
#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23 // Linux 5.14
#endif
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  char* first = static_cast<char*>(data) - reinterpret_cast<uintptr_t>(data) % page;
  const size_t span = static_cast<char*>(data) + bytes - first;
  if (::madvise(first, span, MADV_POPULATE_WRITE) == 0)
    return;
  // older kernels: an atomic add of zero to one byte of each page (a write fault that keeps
  // whatever another thread wrote there meanwhile)
  for (char* p = static_cast<char*>(data); p < static_cast<char*>(data) + bytes;
       p += page - reinterpret_cast<uintptr_t>(p) % page)
    __atomic_fetch_add(p, char(0), __ATOMIC_RELAXED);
#else
  (void)data;
  (void)bytes;
#endif
}

} // namespace plod
