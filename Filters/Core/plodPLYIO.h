// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPLYIO.h
 * @brief The PLY format's low-level pieces shared by the check (plodPLYCheck) and the
 *        streaming reader (plodPLYRead): type table, number parsing and binary decoding (the
 *        file itself is read by plodFileInput.h). Internal to the kernels.
 */
#ifndef plodPLYIO_h
#define plodPLYIO_h

#include "plodFileInput.h"
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

using Input = fileio::FileInput;

} // namespace plyio
} // namespace plod

#endif
