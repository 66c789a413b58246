// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodFileInput.h
 * @brief The kernels' file reading, shared by the checks of PLY, STL and OBJ files and the
 *        streaming PLY reader: a regular file read forward through a fixed buffer (a FIFO or
 *        device refused before it is opened, the open itself never blocking), and a guard that
 *        runs a check so that no exception leaves it. Internal to the kernels.
 */
#ifndef plodFileInput_h
#define plodFileInput_h

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <memory>
#include <new>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace plod
{
namespace fileio
{

/// A regular file, read forward through a fixed buffer.
class FileInput
{
public:
  ~FileInput()
  {
    if (this->File)
    {
      std::fclose(this->File);
    }
  }

  /// Opens `path` when it is a regular file; `what` names the format for messages ("an STL
  /// file"). A FIFO or device is refused before it is opened, and the open itself does not
  /// block (the name may have been replaced in between).
  bool Open(const std::string& path, const char* what, std::string* why)
  {
    if (path.empty())
    {
      *why = "no file name given";
      return false;
    }
    struct stat st;
    if (stat(path.c_str(), &st) != 0)
    {
      *why = std::string("cannot open: ") + std::strerror(errno);
      return false;
    }
    if (S_ISDIR(st.st_mode))
    {
      *why = std::string("is a directory, not ") + what;
      return false;
    }
    if (S_ISFIFO(st.st_mode))
    {
      *why = "is not a regular file (a FIFO)";
      return false;
    }
    if (!S_ISREG(st.st_mode))
    {
      *why = "is not a regular file";
      return false;
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
    {
      *why = std::string("cannot open: ") + std::strerror(errno);
      return false;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
    {
      ::close(fd);
      *why = "is not a regular file";
      return false;
    }
    const int flags = fcntl(fd, F_GETFL);
    if (flags >= 0)
    {
      fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    }
    this->File = fdopen(fd, "rb");
    if (!this->File)
    {
      *why = std::string("cannot open: ") + std::strerror(errno);
      ::close(fd);
      return false;
    }
    this->FileSize = static_cast<int64_t>(st.st_size);
    this->Buffer.reset(new unsigned char[BufferSize]);
    return true;
  }

  int64_t Size() const { return this->FileSize; }
  int64_t Offset() const { return this->BufferStart + static_cast<int64_t>(this->Pos); }
  /// Bytes between the offset and the end of the file (as its size was when opened).
  int64_t Left() const { return this->FileSize - this->Offset(); }
  /// True when a read failed (not at the end of the file).
  bool ReadError() const { return this->Error; }

  /// The next byte, or -1 at the end of the file.
  int Get()
  {
    if (this->Pos == this->End && !this->Fill())
    {
      return -1;
    }
    return this->Buffer[this->Pos++];
  }

  /// The next byte without consuming it, or -1 at the end of the file.
  int Peek()
  {
    if (this->Pos == this->End && !this->Fill())
    {
      return -1;
    }
    return this->Buffer[this->Pos];
  }

  /// Reads up to n bytes into dst; returns how many were read.
  size_t Read(unsigned char* dst, size_t n)
  {
    size_t done = 0;
    while (done < n)
    {
      if (this->Pos == this->End && !this->Fill())
      {
        break;
      }
      const size_t k = std::min(n - done, this->End - this->Pos);
      std::memcpy(dst + done, this->Buffer.get() + this->Pos, k);
      this->Pos += k;
      done += k;
    }
    return done;
  }

  /// Reads exactly n bytes into dst; false when the file ends first.
  bool ReadExactly(unsigned char* dst, size_t n) { return this->Read(dst, n) == n; }

  /// Moves n >= 0 bytes forward (the caller has checked that they are in the file).
  bool Skip(int64_t n)
  {
    if (static_cast<int64_t>(this->End - this->Pos) >= n)
    {
      this->Pos += static_cast<size_t>(n);
      return true;
    }
    const int64_t target = this->Offset() + n;
    if (fseeko(this->File, static_cast<off_t>(target), SEEK_SET) != 0)
    {
      this->Error = true;
      return false;
    }
    this->BufferStart = target;
    this->Pos = this->End = 0;
    return true;
  }

  /// Back to the first byte.
  bool Rewind()
  {
    if (fseeko(this->File, 0, SEEK_SET) != 0)
    {
      this->Error = true;
      return false;
    }
    this->BufferStart = 0;
    this->Pos = this->End = 0;
    return true;
  }

private:
  static constexpr size_t BufferSize = 1 << 16;

  bool Fill()
  {
    this->BufferStart += static_cast<int64_t>(this->End);
    this->Pos = this->End = 0;
    const size_t n = std::fread(this->Buffer.get(), 1, BufferSize, this->File);
    this->End = n;
    if (n == 0 && std::ferror(this->File))
    {
      this->Error = true;
    }
    return n > 0;
  }

  std::FILE* File = nullptr;
  std::unique_ptr<unsigned char[]> Buffer;
  size_t Pos = 0;
  size_t End = 0;
  int64_t BufferStart = 0;
  int64_t FileSize = 0;
  bool Error = false;
};

/**
 * Runs `check(message, summary)` with its outputs made safe: `summary` (or a local one when
 * null) is reset first, and reset again on failure when `resetOnFailure`; no exception leaves
 * (out of memory and anything else become messages "... while <activity>"); `why` is "" on
 * success, the message otherwise.
 */
template <typename Summary, typename Check>
bool RunCheckSafely(std::string* why, Summary* summary, Check&& check,
  const char* activity = "checking the file", bool resetOnFailure = false)
{
  std::string message;
  Summary local;
  Summary& s = summary ? *summary : local;
  s = Summary();
  bool ok = false;
  try
  {
    ok = check(&message, &s);
  }
  catch (const std::bad_alloc&)
  {
    message = std::string("out of memory while ") + activity;
    ok = false;
  }
  catch (...)
  {
    message = std::string("unexpected error while ") + activity;
    ok = false;
  }
  if (!ok && resetOnFailure)
  {
    s = Summary();
  }
  if (why)
  {
    *why = ok ? std::string() : message;
  }
  return ok;
}

} // namespace fileio
} // namespace plod

#endif
