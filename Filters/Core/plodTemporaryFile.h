// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodTemporaryFile.h
 * @brief Temporary files of the builds in pieces (plodPieces, plodPieceAssembly): written
 *        forward through a buffer with every failure (a full disk) reported, and read back.
 *        Internal to the kernels.
 */
#ifndef plodTemporaryFile_h
#define plodTemporaryFile_h

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <unistd.h>
#include <vector>

namespace plod
{
namespace tempfile
{

inline std::string SystemError(const std::string& what, const std::string& path)
{
  return what + " " + path + ": " + std::strerror(errno);
}

/// A file written forward through a buffer; every failure (a full disk) reported.
class Appender
{
public:
  ~Appender()
  {
    if (this->Fd >= 0)
    {
      ::close(this->Fd);
    }
  }

  bool Open(const std::string& path, std::string* why)
  {
    this->Path = path;
    this->Fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (this->Fd < 0)
    {
      *why = SystemError("cannot create the temporary file", path);
      return false;
    }
    this->Buffer.reserve(BufferBytes);
    return true;
  }

  bool Write(const void* data, size_t bytes, std::string* why)
  {
    const char* p = static_cast<const char*>(data);
    this->Bytes += static_cast<int64_t>(bytes);
    if (this->Buffer.size() + bytes > BufferBytes && !this->Flush(why))
    {
      return false;
    }
    if (bytes >= BufferBytes) // a whole array: straight to the file, not through a copy
    {
      return this->WriteAll(p, bytes, why);
    }
    this->Buffer.insert(this->Buffer.end(), p, p + bytes);
    return true;
  }

  bool Close(std::string* why)
  {
    const bool ok = this->Flush(why);
    if (this->Fd >= 0 && ::close(this->Fd) != 0 && ok)
    {
      this->Fd = -1;
      *why = SystemError("cannot write the temporary file", this->Path);
      return false;
    }
    this->Fd = -1;
    return ok;
  }

  int64_t Size() const { return this->Bytes; }

private:
  static constexpr size_t BufferBytes = size_t(1) << 20;

  bool Flush(std::string* why)
  {
    const bool ok = this->WriteAll(this->Buffer.data(), this->Buffer.size(), why);
    this->Buffer.clear();
    return ok;
  }

  bool WriteAll(const char* p, size_t bytes, std::string* why)
  {
    size_t done = 0;
    while (done < bytes)
    {
      const ssize_t n = ::write(this->Fd, p + done, bytes - done);
      if (n < 0 && errno == EINTR)
      {
        continue;
      }
      if (n <= 0)
      {
        *why = SystemError("cannot write the temporary file", this->Path);
        return false;
      }
      done += static_cast<size_t>(n);
    }
    return true;
  }

  std::string Path;
  int Fd = -1;
  std::vector<char> Buffer;
  int64_t Bytes = 0;
};

/// Reads a whole temporary file's bytes into `out`.
template <typename Vector>
inline bool ReadBack(int fd, int64_t count, Vector* out, const std::string& path, std::string* why)
{
  out->resize(static_cast<size_t>(count));
  char* p = reinterpret_cast<char*>(out->data());
  size_t left = static_cast<size_t>(count) * sizeof(typename Vector::value_type);
  while (left > 0)
  {
    const ssize_t n = ::read(fd, p, left);
    if (n < 0 && errno == EINTR)
    {
      continue;
    }
    if (n <= 0)
    {
      *why = n < 0 ? SystemError("cannot read the temporary file", path)
                   : "the temporary file " + path + " is shorter than written";
      return false;
    }
    p += n;
    left -= static_cast<size_t>(n);
  }
  return true;
}

} // namespace tempfile
} // namespace plod

#endif
