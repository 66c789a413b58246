// SPDX-License-Identifier: BSD-3-Clause
#include "plodOctreeFile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace plod
{
namespace
{
constexpr char Magic[8] = { 'P', 'L', 'O', 'D', 'O', 'C', 'T', '\n' };
constexpr uint32_t Version = 1;
constexpr uint32_t ByteOrderMark = 0x01020304u;
constexpr size_t HeaderBytes = 128;
constexpr size_t EntryBytes = 64;
constexpr size_t NameBytes = 32;
constexpr uint64_t Alignment = 4096;
constexpr uint32_t MaxArrays = 256;
constexpr uint64_t FnvOffset = 14695981039346656037ull;
constexpr uint64_t FnvPrime = 1099511628211ull;

bool HostIsLittleEndian()
{
  const uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// Little-endian encoding into / decoding from a byte buffer.
template <typename T>
void Put(unsigned char* at, T value)
{
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (!HostIsLittleEndian())
  {
    std::reverse(bytes, bytes + sizeof(T));
  }
  std::memcpy(at, bytes, sizeof(T));
}

template <typename T>
T Get(const unsigned char* at)
{
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, at, sizeof(T));
  if (!HostIsLittleEndian())
  {
    std::reverse(bytes, bytes + sizeof(T));
  }
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

uint64_t AlignUp(uint64_t x)
{
  return (x + Alignment - 1) / Alignment * Alignment;
}

/// Swaps the bytes of each `size`-byte value in place.
void SwapValues(unsigned char* data, uint64_t bytes, int size)
{
  if (size <= 1)
  {
    return;
  }
  for (uint64_t i = 0; i + size <= bytes; i += size)
  {
    std::reverse(data + i, data + i + size);
  }
}

uint32_t HeaderChecksum(const unsigned char* header, size_t bytes)
{
  // the checksum field (120..124) counts as zero
  uint64_t h = FnvOffset;
  for (size_t i = 0; i < bytes; ++i)
  {
    const unsigned char b = (i >= 120 && i < 124) ? 0 : header[i];
    h = (h ^ b) * FnvPrime;
  }
  return static_cast<uint32_t>(h ^ (h >> 32));
}

bool Fail(std::string* error, const std::string& what)
{
  if (error)
  {
    *error = what;
  }
  return false;
}

struct FileCloser
{
  int Fd;
  ~FileCloser()
  {
    if (this->Fd >= 0)
    {
      ::close(this->Fd);
    }
  }
};
} // namespace

const std::vector<ArraySpec>& OctreeFileSchema()
{
  static const std::vector<ArraySpec> schema(OctreeSchema, OctreeSchema + OctreeRequiredArrays);
  return schema;
}

std::vector<FileArray> FileArraysOf(const OctreeView& v)
{
  std::vector<FileArray> arrays;
  ForEachArray(v, [&](const ArraySpec& spec, const void* pointer) {
    if (spec.Optional)
    {
      return; // not stored in files
    }
    FileArray f;
    f.Name = spec.Name;
    f.Group = spec.Group;
    f.Type = spec.Type;
    f.Components = spec.Components;
    f.Tuples = v.TupleCount(spec.Group);
    f.Data = pointer;
    arrays.push_back(f);
  });
  return arrays;
}

bool ViewOfFile(const OctreeFile& file, OctreeView& v, std::string* why)
{
  std::vector<const FileArray*> found;
  v = OctreeView();
  if (!MatchSchema(file, found, why))
  {
    return false;
  }
  const OctreeFileHeader& h = file.Header;
  v.NumberOfNodes = h.Nodes;
  v.FinestLevel = h.FinestLevel;
  std::copy(h.Origin, h.Origin + 3, v.Origin);
  v.RootEdge = h.RootEdge;
  v.NumberOfClusters = h.Clusters;
  v.NumberOfPoints = h.Points;
  v.NumberOfTriangles = h.Triangles;
  size_t k = 0;
  ForEachArray(v, [&](const ArraySpec& spec, auto& pointer) {
    if (!spec.Optional)
    {
      pointer = static_cast<std::remove_reference_t<decltype(pointer)>>(found[k++]->Data);
    }
  });
  return true;
}

bool MatchSchema(const OctreeFile& file, std::vector<const FileArray*>& arrays, std::string* why)
{
  arrays.clear();
  for (const ArraySpec& spec : OctreeFileSchema())
  {
    const FileArray* match = nullptr;
    for (const FileArray& f : file.Arrays)
    {
      if (f.Group == spec.Group && f.Name == spec.Name)
      {
        match = &f;
      }
    }
    if (!match || match->Type != spec.Type || match->Components != spec.Components)
    {
      arrays.clear();
      return Fail(why,
        std::string("the array '") + spec.Name +
          (match ? "' has the wrong type or components" : "' is missing"));
    }
    arrays.push_back(match);
  }
  return true;
}

int FileTypeSize(FileArrayType type)
{
  return ArrayTypeSize(type);
}

uint64_t FileChecksum(const void* data, size_t bytes)
{
  const unsigned char* p = static_cast<const unsigned char*>(data);
  uint64_t h = FnvOffset;
  size_t i = 0;
  for (; i + 8 <= bytes; i += 8)
  {
    h = (h ^ Get<uint64_t>(p + i)) * FnvPrime;
  }
  for (; i < bytes; ++i)
  {
    h = (h ^ p[i]) * FnvPrime;
  }
  return h;
}

bool WriteOctreeFile(const std::string& path, const OctreeFileHeader& header,
  const std::vector<FileArray>& arrays, std::string* error)
{
  if (arrays.size() > MaxArrays)
  {
    return Fail(error, "too many arrays (" + std::to_string(arrays.size()) + ")");
  }
  const size_t headerSize = HeaderBytes + EntryBytes * arrays.size();
  std::vector<unsigned char> head(headerSize, 0);
  std::vector<uint64_t> offset(arrays.size());
  uint64_t end = AlignUp(headerSize);
  for (size_t a = 0; a < arrays.size(); ++a)
  {
    const FileArray& f = arrays[a];
    const int size = FileTypeSize(f.Type);
    if (f.Name.empty() || f.Name.size() >= NameBytes || size == 0 || f.Components < 1 ||
      f.Components > 65535 || f.Tuples < 0 || (f.Tuples > 0 && !f.Data))
    {
      return Fail(error, "array " + std::to_string(a) + " ('" + f.Name + "') cannot be written");
    }
    const uint64_t bytes = uint64_t(f.Tuples) * uint64_t(f.Components) * uint64_t(size);
    offset[a] = bytes > 0 ? end : 0; // an empty array has no place in the file
    end = bytes > 0 ? AlignUp(end + bytes) : end;
    unsigned char* e = head.data() + HeaderBytes + EntryBytes * a;
    std::memcpy(e, f.Name.data(), f.Name.size());
    e[32] = static_cast<unsigned char>(f.Group);
    e[33] = static_cast<unsigned char>(f.Type);
    Put<uint16_t>(e + 34, static_cast<uint16_t>(f.Components));
    Put<int64_t>(e + 40, f.Tuples);
    Put<uint64_t>(e + 48, offset[a]);
    uint64_t sum = 0;
    if (HostIsLittleEndian() || size == 1)
    {
      sum = FileChecksum(f.Data, bytes);
    }
    else
    {
      std::vector<unsigned char> copy(static_cast<const unsigned char*>(f.Data),
        static_cast<const unsigned char*>(f.Data) + bytes);
      SwapValues(copy.data(), bytes, size);
      sum = FileChecksum(copy.data(), bytes);
    }
    Put<uint64_t>(e + 56, sum);
  }
  // the file ends with the last array (no padding after it)
  uint64_t fileSize = AlignUp(headerSize);
  for (size_t a = 0; a < arrays.size(); ++a)
  {
    const uint64_t bytes = uint64_t(arrays[a].Tuples) * uint64_t(arrays[a].Components) *
      uint64_t(FileTypeSize(arrays[a].Type));
    fileSize = std::max(fileSize, offset[a] + bytes);
  }
  std::memcpy(head.data(), Magic, 8);
  Put<uint32_t>(head.data() + 8, Version);
  Put<uint32_t>(head.data() + 12, ByteOrderMark);
  Put<uint32_t>(head.data() + 16, static_cast<uint32_t>(headerSize));
  Put<uint32_t>(head.data() + 20, static_cast<uint32_t>(arrays.size()));
  for (int k = 0; k < 3; ++k)
  {
    Put<double>(head.data() + 24 + 8 * k, header.Origin[k]);
  }
  Put<double>(head.data() + 48, header.RootEdge);
  Put<int32_t>(head.data() + 56, header.FinestLevel);
  Put<uint32_t>(head.data() + 60, header.HasMaterialArrays ? 1u : 0u);
  const int64_t counts[6] = { header.Nodes, header.Points, header.Triangles, header.Clusters,
    header.BoundaryEdges, header.NonManifoldEdges };
  for (int k = 0; k < 6; ++k)
  {
    Put<int64_t>(head.data() + 64 + 8 * k, counts[k]);
  }
  Put<uint64_t>(head.data() + 112, fileSize);
  Put<uint32_t>(head.data() + 120, HeaderChecksum(head.data(), headerSize));

  std::FILE* out = std::fopen(path.c_str(), "wb");
  if (!out)
  {
    return Fail(error, "cannot open '" + path + "' for writing: " + std::strerror(errno));
  }
  bool ok = std::fwrite(head.data(), 1, head.size(), out) == head.size();
  uint64_t at = head.size();
  const std::vector<unsigned char> zeros(Alignment, 0);
  for (size_t a = 0; a < arrays.size() && ok; ++a)
  {
    const FileArray& f = arrays[a];
    const int size = FileTypeSize(f.Type);
    const uint64_t bytes = uint64_t(f.Tuples) * uint64_t(f.Components) * uint64_t(size);
    if (bytes == 0)
    {
      continue;
    }
    ok = ok && std::fwrite(zeros.data(), 1, offset[a] - at, out) == offset[a] - at;
    const unsigned char* p = static_cast<const unsigned char*>(f.Data);
    if (HostIsLittleEndian() || size == 1)
    {
      ok = ok && std::fwrite(p, 1, bytes, out) == bytes;
    }
    else
    {
      std::vector<unsigned char> chunk;
      for (uint64_t done = 0; done < bytes && ok; done += chunk.size())
      {
        chunk.assign(p + done, p + std::min<uint64_t>(bytes, done + (1u << 20)));
        SwapValues(chunk.data(), chunk.size(), size);
        ok = std::fwrite(chunk.data(), 1, chunk.size(), out) == chunk.size();
      }
    }
    at = offset[a] + bytes;
  }
  if (ok && at < AlignUp(headerSize))
  {
    ok = std::fwrite(zeros.data(), 1, AlignUp(headerSize) - at, out) == AlignUp(headerSize) - at;
  }
  ok = (std::fclose(out) == 0) && ok;
  if (!ok)
  {
    std::remove(path.c_str());
    return Fail(error, "writing '" + path + "' failed: " + std::strerror(errno));
  }
  return true;
}

bool OpenOctreeFile(
  const std::string& path, bool verifyChecksums, bool mapFile, OctreeFile& out, std::string* error)
{
  out = OctreeFile();
  const std::string where = path + ": ";
  FileCloser file{ ::open(path.c_str(), O_RDONLY | O_CLOEXEC) };
  if (file.Fd < 0)
  {
    return Fail(error, where + "cannot open: " + std::strerror(errno));
  }
  struct stat st;
  if (::fstat(file.Fd, &st) != 0 || !S_ISREG(st.st_mode))
  {
    return Fail(error, where + (S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file"));
  }
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  if (size < HeaderBytes)
  {
    return Fail(error,
      where + "too short for an octree file (" + std::to_string(size) +
        " bytes; the header alone is 128)");
  }
  // the bytes: a private (copy-on-write) map, or a buffer read from the file
  std::shared_ptr<void> memory;
  const bool map = mapFile && HostIsLittleEndian();
  if (map)
  {
    void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE, file.Fd, 0);
    if (p != MAP_FAILED)
    {
      memory = std::shared_ptr<void>(p, [size](void* q) { ::munmap(q, size); });
      out.Mapped = true;
    }
  }
  if (!memory)
  {
    void* p = ::operator new(size, std::nothrow);
    if (!p)
    {
      return Fail(error, where + "not enough memory to read " + std::to_string(size) + " bytes");
    }
    memory = std::shared_ptr<void>(p, [](void* q) { ::operator delete(q); });
    uint64_t got = 0;
    while (got < size)
    {
      const ssize_t n = ::pread(file.Fd, static_cast<char*>(p) + got, size - got, off_t(got));
      if (n <= 0)
      {
        return Fail(error, where + "read failed after " + std::to_string(got) + " bytes");
      }
      got += static_cast<uint64_t>(n);
    }
  }
  unsigned char* bytes = static_cast<unsigned char*>(memory.get());

  if (std::memcmp(bytes, Magic, 8) != 0)
  {
    return Fail(error, where + "not an octree file (it does not start with PLODOCT)");
  }
  const uint32_t version = Get<uint32_t>(bytes + 8);
  if (version != Version)
  {
    return Fail(error,
      where + "octree file format version " + std::to_string(version) +
        "; this reader knows version " + std::to_string(Version));
  }
  if (Get<uint32_t>(bytes + 12) != ByteOrderMark)
  {
    return Fail(error, where + "corrupt header (byte-order mark)");
  }
  const uint32_t headerSize = Get<uint32_t>(bytes + 16);
  const uint32_t count = Get<uint32_t>(bytes + 20);
  if (count > MaxArrays || headerSize != HeaderBytes + EntryBytes * count || headerSize > size)
  {
    return Fail(error,
      where + "corrupt header (" + std::to_string(count) + " arrays, header of " +
        std::to_string(headerSize) + " bytes in a file of " + std::to_string(size) + ")");
  }
  if (Get<uint32_t>(bytes + 120) != HeaderChecksum(bytes, headerSize))
  {
    return Fail(error, where + "corrupt header (checksum mismatch)");
  }
  const uint64_t statedSize = Get<uint64_t>(bytes + 112);
  if (statedSize != size)
  {
    return Fail(error,
      where + (size < statedSize ? "truncated" : "longer than written") + ": " +
        std::to_string(size) + " bytes, the header says " + std::to_string(statedSize));
  }
  OctreeFileHeader& h = out.Header;
  for (int k = 0; k < 3; ++k)
  {
    h.Origin[k] = Get<double>(bytes + 24 + 8 * k);
  }
  h.RootEdge = Get<double>(bytes + 48);
  h.FinestLevel = Get<int32_t>(bytes + 56);
  h.HasMaterialArrays = (Get<uint32_t>(bytes + 60) & 1u) != 0;
  int64_t* counts[6] = { &h.Nodes, &h.Points, &h.Triangles, &h.Clusters, &h.BoundaryEdges,
    &h.NonManifoldEdges };
  for (int k = 0; k < 6; ++k)
  {
    *counts[k] = Get<int64_t>(bytes + 64 + 8 * k);
  }
  const int64_t maxIndex = std::numeric_limits<int32_t>::max();
  if (!(std::isfinite(h.Origin[0]) && std::isfinite(h.Origin[1]) && std::isfinite(h.Origin[2]) &&
        std::isfinite(h.RootEdge) && h.RootEdge > 0) ||
    h.FinestLevel < 0 || h.FinestLevel > 21 || h.Nodes < 0 || h.Nodes > maxIndex || h.Points < 0 ||
    h.Points > maxIndex || h.Triangles < 0 || h.Triangles > maxIndex || h.Clusters < 0 ||
    h.Clusters > maxIndex || h.BoundaryEdges < 0 || h.NonManifoldEdges < 0)
  {
    return Fail(error, where + "corrupt header (root cube, level or counts out of range)");
  }

  std::vector<std::pair<uint64_t, uint64_t>> extents;
  for (uint32_t a = 0; a < count; ++a)
  {
    const unsigned char* e = bytes + HeaderBytes + EntryBytes * a;
    const std::string at = where + "array " + std::to_string(a) + ": ";
    if (std::memchr(e, 0, NameBytes) == nullptr)
    {
      return Fail(error, at + "name not terminated");
    }
    FileArray f;
    f.Name = reinterpret_cast<const char*>(e);
    const uint8_t group = e[32], type = e[33];
    f.Components = Get<uint16_t>(e + 34);
    f.Tuples = Get<int64_t>(e + 40);
    const uint64_t offset = Get<uint64_t>(e + 48);
    f.Checksum = Get<uint64_t>(e + 56);
    if (group > 3 || type < 1 || type > 4 || f.Components < 1 || f.Components > 16)
    {
      return Fail(error, at + "'" + f.Name + "' has an unknown group, type or component count");
    }
    f.Group = static_cast<FileArrayGroup>(group);
    f.Type = static_cast<FileArrayType>(type);
    const int64_t expected[4] = { h.Nodes, h.Clusters, h.Points, h.Triangles };
    if (f.Tuples != expected[group])
    {
      return Fail(error,
        at + "'" + f.Name + "' has " + std::to_string(f.Tuples) + " tuples where its group has " +
          std::to_string(expected[group]));
    }
    const uint64_t length =
      uint64_t(f.Tuples) * uint64_t(f.Components) * uint64_t(FileTypeSize(f.Type));
    if (length > 0 &&
      (offset % Alignment != 0 || offset < headerSize || offset > size || length > size - offset))
    {
      return Fail(error,
        at + "'" + f.Name + "' lies outside the file (offset " + std::to_string(offset) + ", " +
          std::to_string(length) + " bytes, file of " + std::to_string(size) + ")");
    }
    if (length > 0)
    {
      extents.emplace_back(offset, offset + length);
      f.Data = bytes + offset;
      if (!HostIsLittleEndian())
      {
        SwapValues(bytes + offset, length, FileTypeSize(f.Type));
      }
      if (verifyChecksums)
      {
        uint64_t sum = 0;
        if (HostIsLittleEndian())
        {
          sum = FileChecksum(bytes + offset, length);
        }
        else
        {
          std::vector<unsigned char> copy(bytes + offset, bytes + offset + length);
          SwapValues(copy.data(), length, FileTypeSize(f.Type));
          sum = FileChecksum(copy.data(), length);
        }
        if (sum != f.Checksum)
        {
          return Fail(error, at + "'" + f.Name + "' is corrupt (checksum mismatch)");
        }
      }
    }
    out.Arrays.push_back(f);
  }
  std::sort(extents.begin(), extents.end());
  for (size_t k = 1; k < extents.size(); ++k)
  {
    if (extents[k].first < extents[k - 1].second)
    {
      return Fail(error, where + "corrupt directory (arrays overlap)");
    }
  }
  out.Memory = memory;
  return true;
}

} // namespace plod
