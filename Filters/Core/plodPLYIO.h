// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPLYIO.h
 * @brief The PLY format's low-level pieces shared by the check (plodPLYCheck) and the
 *        streaming reader (plodPLYRead): type table, number parsing, binary decoding and a file
 *        read forward through a fixed buffer. Internal to the kernels.
 */
#ifndef plodPLYIO_h
#define plodPLYIO_h

#include "plodPLYCheck.h"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <sys/stat.h>
#include <system_error>

namespace plod
{
namespace plyio
{
struct TypeInfo
{
  const char* Name;
  const char* Alias;
  int Size;
  bool Integer;
  int64_t Min; ///< range of an integer type
  int64_t Max;
};

// indexed by PLYType
inline constexpr TypeInfo Types[] = {
  { "char", "int8", 1, true, -128, 127 },
  { "uchar", "uint8", 1, true, 0, 255 },
  { "short", "int16", 2, true, -32768, 32767 },
  { "ushort", "uint16", 2, true, 0, 65535 },
  { "int", "int32", 4, true, -2147483648LL, 2147483647LL },
  { "uint", "uint32", 4, true, 0, 4294967295LL },
  { "float", "float32", 4, false, 0, 0 },
  { "double", "float64", 8, false, 0, 0 },
};

inline const TypeInfo& Info(PLYType t)
{
  return Types[static_cast<int>(t)];
}

/// Word separators of Turk's reader (it turns tabs and carriage returns into spaces).
inline bool IsBlank(int c)
{
  return c == ' ' || c == '\t' || c == '\r';
}

/// A decimal integer (optional sign, digits only); false when it is not one or overflows.
inline bool ParseInteger(const char* begin, const char* end, int64_t* value)
{
  if (begin != end && *begin == '+')
  {
    ++begin;
    if (begin != end && *begin == '-')
    {
      return false;
    }
  }
  if (begin == end)
  {
    return false;
  }
  const auto r = std::from_chars(begin, end, *value, 10);
  return r.ec == std::errc() && r.ptr == end;
}

/// A decimal floating-point number (nan and inf included); false when it is not one.
/// Out-of-range magnitudes are numbers (a reader makes them infinite or zero).
inline bool ParseReal(const char* begin, const char* end, double* value)
{
  if (begin != end && *begin == '+')
  {
    ++begin;
    if (begin != end && *begin == '-')
    {
      return false;
    }
  }
  if (begin == end)
  {
    return false;
  }
  const auto r = std::from_chars(begin, end, *value, std::chars_format::general);
  return (r.ec == std::errc() || r.ec == std::errc::result_out_of_range) && r.ptr == end;
}

inline bool HostIsLittleEndian()
{
  const uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

/// A binary value of type `t` (bytes in file order) as a double: exact for every integer type.
inline double Decode(const unsigned char* bytes, PLYType t, bool swap)
{
  unsigned char b[8];
  const int n = Info(t).Size;
  for (int i = 0; i < n; ++i)
  {
    b[i] = swap ? bytes[n - 1 - i] : bytes[i];
  }
  switch (t)
  {
    case PLYType::Int8:
    {
      int8_t v;
      std::memcpy(&v, b, 1);
      return v;
    }
    case PLYType::UInt8:
      return b[0];
    case PLYType::Int16:
    {
      int16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case PLYType::UInt16:
    {
      uint16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case PLYType::Int32:
    {
      int32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case PLYType::UInt32:
    {
      uint32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case PLYType::Float32:
    {
      float v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case PLYType::Float64:
    {
      double v;
      std::memcpy(&v, b, 8);
      return v;
    }
  }
  return 0;
}

/// The file, read forward through a fixed buffer.
class Input
{
public:
  ~Input()
  {
    if (this->File)
    {
      std::fclose(this->File);
    }
  }

  bool Open(const std::string& path, std::string* why)
  {
    struct stat st;
    if (path.empty())
    {
      *why = "no file name given";
      return false;
    }
    if (stat(path.c_str(), &st) != 0)
    {
      *why = std::string("cannot open: ") + std::strerror(errno);
      return false;
    }
    if (S_ISDIR(st.st_mode))
    {
      *why = "is a directory, not a PLY file";
      return false;
    }
    if (!S_ISREG(st.st_mode))
    {
      *why = "is not a regular file";
      return false;
    }
    this->File = std::fopen(path.c_str(), "rb");
    if (!this->File)
    {
      *why = std::string("cannot open: ") + std::strerror(errno);
      return false;
    }
    this->FileSize = static_cast<int64_t>(st.st_size);
    this->Buffer.reset(new unsigned char[BufferSize]);
    return true;
  }

  int64_t Size() const { return this->FileSize; }
  int64_t Offset() const { return this->BufferStart + static_cast<int64_t>(this->Pos); }
  int64_t Left() const { return this->FileSize - this->Offset(); }

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

  /// Reads exactly n bytes (n <= 8) into dst; false at the end of the file.
  bool Read(unsigned char* dst, int n)
  {
    if (this->End - this->Pos >= static_cast<size_t>(n))
    {
      std::memcpy(dst, this->Buffer.get() + this->Pos, n);
      this->Pos += n;
      return true;
    }
    for (int i = 0; i < n; ++i)
    {
      const int c = this->Get();
      if (c < 0)
      {
        return false;
      }
      dst[i] = static_cast<unsigned char>(c);
    }
    return true;
  }

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
      return false;
    }
    this->BufferStart = target;
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
    return n > 0;
  }

  std::FILE* File = nullptr;
  std::unique_ptr<unsigned char[]> Buffer;
  size_t Pos = 0;
  size_t End = 0;
  int64_t BufferStart = 0;
  int64_t FileSize = 0;
};

} // namespace plyio
} // namespace plod

#endif
