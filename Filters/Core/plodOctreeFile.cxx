// SPDX-License-Identifier: BSD-3-Clause
#include "plodOctreeFile.h"

#include <algorithm>
#include <atomic>
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

#include <zstd.h>

namespace plod
{
namespace
{
constexpr char Magic[8] = { 'P', 'L', 'O', 'D', 'O', 'C', 'T', '\n' };
constexpr uint32_t MappedVersion = 1;  // every array stored as it is
constexpr uint32_t CompactVersion = 2; // arrays may be compressed in blocks
constexpr uint8_t EncodingRaw = 0;
constexpr uint8_t EncodingBlocks = 1;
constexpr uint32_t BlockTuples = 1u << 16; // tuples per compressed block
constexpr int CompressionLevel = 3;        // zstd's default: about 300 MB/s per core here
constexpr size_t BlocksPerBatch = 16;      // blocks compressed at once (in parallel)
constexpr uint32_t ByteOrderMark = 0x01020304u;
constexpr size_t HeaderBytes = 128;
constexpr size_t EntryBytes = 64;
constexpr size_t NameBytes = 32;
constexpr uint64_t Alignment = 4096;    // of an array stored as it is (mapped in place)
constexpr uint64_t BlocksAlignment = 8; // of a compressed array (never mapped in place)
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

uint64_t AlignUp(uint64_t x, uint64_t alignment = Alignment)
{
  return (x + alignment - 1) / alignment * alignment;
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

namespace
{
/// FileChecksum continued over `bytes` more (every earlier part a multiple of 8 bytes).
uint64_t ContinueChecksum(uint64_t h, const void* data, size_t bytes)
{
  const unsigned char* p = static_cast<const unsigned char*>(data);
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

/// Bytes of an array's values (as stored by the mapped layout).
uint64_t DataBytes(const FileArray& f)
{
  return uint64_t(f.Tuples) * uint64_t(f.Components) * uint64_t(FileTypeSize(f.Type));
}

/// Values [first, first + count) of `f` (counted in values, not tuples), little-endian, into
/// `out`: copied from Data, or made by Values at most 1 MiB at a time. False with `why`.
bool GatherValues(
  const FileArray& f, uint64_t first, uint64_t count, unsigned char* out, std::string* why)
{
  const uint64_t size = uint64_t(FileTypeSize(f.Type));
  if (f.Data)
  {
    std::memcpy(out, static_cast<const unsigned char*>(f.Data) + first * size, count * size);
  }
  else
  {
    const uint64_t perCall = std::max<uint64_t>(1, (uint64_t(1) << 20) / size);
    for (uint64_t done = 0; done < count; done += perCall)
    {
      const uint64_t n = std::min(perCall, count - done);
      if (!f.Values(
            static_cast<int64_t>(first + done), static_cast<int64_t>(n), out + done * size, why))
      {
        *why = "cannot make the array '" + f.Name + "': " + *why;
        return false;
      }
    }
  }
  if (!HostIsLittleEndian())
  {
    SwapValues(out, count * size, static_cast<int>(size));
  }
  return true;
}

/// Calls body(bytes, n) over the array's data in file order (little-endian): in place when it
/// is in memory and the host is little-endian, else through a buffer of at most 1 MiB (a
/// multiple of 8 bytes, so that checksums continue). False with `why` when the array's Values
/// or the body fail.
bool ForEachChunk(const FileArray& f, std::string* why,
  const std::function<bool(const unsigned char*, size_t)>& body)
{
  const int size = FileTypeSize(f.Type);
  const uint64_t bytes = DataBytes(f);
  if (f.Data && (HostIsLittleEndian() || size == 1))
  {
    return body(static_cast<const unsigned char*>(f.Data), static_cast<size_t>(bytes));
  }
  const uint64_t valuesPerChunk = (uint64_t(1) << 20) / 8 / uint64_t(size) * 8;
  std::vector<unsigned char> chunk;
  const uint64_t values = bytes / uint64_t(size);
  for (uint64_t first = 0; first < values; first += valuesPerChunk)
  {
    const uint64_t n = std::min(valuesPerChunk, values - first);
    chunk.resize(static_cast<size_t>(n * uint64_t(size)));
    if (!GatherValues(f, first, n, chunk.data(), why) || !body(chunk.data(), chunk.size()))
    {
      return false;
    }
  }
  return true;
}

/// FileChecksum over bytes that arrive in parts of any length.
class Checksummer
{
public:
  void Add(const unsigned char* p, size_t n)
  {
    while (n > 0 && this->Pending > 0)
    {
      this->Word[this->Pending++] = *p++;
      --n;
      if (this->Pending == 8)
      {
        this->Sum = ContinueChecksum(this->Sum, this->Word, 8);
        this->Pending = 0;
      }
    }
    const size_t whole = n / 8 * 8;
    this->Sum = ContinueChecksum(this->Sum, p, whole);
    for (size_t i = whole; i < n; ++i)
    {
      this->Word[this->Pending++] = p[i];
    }
  }
  uint64_t Finish() const { return ContinueChecksum(this->Sum, this->Word, this->Pending); }

private:
  uint64_t Sum = FnvOffset;
  unsigned char Word[8] = {};
  size_t Pending = 0;
};

/// The zigzag map: 0, -1, 1, -2, ... to 0, 1, 2, 3, ... (on the unsigned difference).
template <typename U>
U Zigzag(U d)
{
  using S = std::make_signed_t<U>;
  return static_cast<U>(
    static_cast<U>(d << 1) ^ static_cast<U>(static_cast<S>(d) >> (8 * sizeof(U) - 1)));
}

template <typename U>
U Unzigzag(U z)
{
  return static_cast<U>(static_cast<U>(z >> 1) ^ static_cast<U>(0 - (z & 1)));
}

/// A block's transform (see the header): `tuples` tuples of `components` little-endian values
/// of type U from `in` become their zigzag differences, byte planes in `out`.
template <typename U>
void ToPlanes(const unsigned char* in, size_t tuples, int components, unsigned char* out)
{
  const size_t n = tuples * size_t(components), back = size_t(components);
  for (size_t i = 0; i < n; ++i)
  {
    const U previous = i >= back ? Get<U>(in + (i - back) * sizeof(U)) : U(0);
    const U z = Zigzag<U>(static_cast<U>(Get<U>(in + i * sizeof(U)) - previous));
    for (size_t b = 0; b < sizeof(U); ++b)
    {
      out[b * n + i] = static_cast<unsigned char>(z >> (8 * b));
    }
  }
}

/// The inverse of ToPlanes, into values in the host's byte order.
template <typename U>
void FromPlanes(const unsigned char* in, size_t tuples, int components, unsigned char* out)
{
  const size_t n = tuples * size_t(components), back = size_t(components);
  for (size_t i = 0; i < n; ++i)
  {
    U z = 0;
    for (size_t b = 0; b < sizeof(U); ++b)
    {
      z = static_cast<U>(z | static_cast<U>(static_cast<U>(in[b * n + i]) << (8 * b)));
    }
    U previous = 0;
    if (i >= back)
    {
      std::memcpy(&previous, out + (i - back) * sizeof(U), sizeof(U));
    }
    const U value = static_cast<U>(Unzigzag<U>(z) + previous);
    std::memcpy(out + i * sizeof(U), &value, sizeof(U));
  }
}

/// ToPlanes or FromPlanes for values of `size` bytes.
void Transform(bool forward, int size, const unsigned char* in, size_t tuples, int components,
  unsigned char* out)
{
  switch (size)
  {
    case 1:
      forward ? ToPlanes<uint8_t>(in, tuples, components, out)
              : FromPlanes<uint8_t>(in, tuples, components, out);
      break;
    case 4:
      forward ? ToPlanes<uint32_t>(in, tuples, components, out)
              : FromPlanes<uint32_t>(in, tuples, components, out);
      break;
    default:
      forward ? ToPlanes<uint64_t>(in, tuples, components, out)
              : FromPlanes<uint64_t>(in, tuples, components, out);
      break;
  }
}

/// Compresses one block of `tuples` tuples (little-endian values at `raw`) into `out`; false
/// with `why` when zstd fails.
bool CompressBlock(const FileArray& f, const unsigned char* raw, size_t tuples,
  std::vector<unsigned char>& out, std::string* why)
{
  const int size = FileTypeSize(f.Type);
  const size_t bytes = tuples * size_t(f.Components) * size_t(size);
  std::vector<unsigned char> planes(bytes);
  Transform(true, size, raw, tuples, f.Components, planes.data());
  out.resize(ZSTD_compressBound(bytes));
  const size_t n = ZSTD_compress(out.data(), out.size(), planes.data(), bytes, CompressionLevel);
  if (ZSTD_isError(n))
  {
    *why = std::string("compressing the array '") + f.Name + "' failed: " + ZSTD_getErrorName(n);
    return false;
  }
  out.resize(n);
  return true;
}

/// Decompresses one block of `tuples` tuples into host-order values at `out`; "" or what is
/// wrong with the block.
std::string DecompressBlock(const FileArray& f, const unsigned char* stored, size_t storedBytes,
  size_t tuples, unsigned char* out)
{
  const int size = FileTypeSize(f.Type);
  const size_t bytes = tuples * size_t(f.Components) * size_t(size);
  std::vector<unsigned char> planes(bytes);
  const size_t n = ZSTD_decompress(planes.data(), bytes, stored, storedBytes);
  if (ZSTD_isError(n))
  {
    return ZSTD_getErrorName(n);
  }
  if (n != bytes)
  {
    return std::to_string(n) + " bytes where its tuples take " + std::to_string(bytes);
  }
  Transform(false, size, planes.data(), tuples, f.Components, out);
  return std::string();
}

struct StoredBlocks;
bool OpenFile(const std::string& path, bool verifyChecksums, bool mapFile, bool decode,
  OctreeFile& out, std::string* error, const ParallelFor& parallel,
  std::vector<StoredBlocks>* kept);

/// Where each array lies in the file being written, and how.
struct PlacedArray
{
  uint64_t Offset = 0; // 0 for no data
  uint64_t Checksum = FnvOffset;
  uint8_t Encoding = EncodingRaw;
};

/// False with `error` when `header` or one of `arrays` cannot be written.
bool CheckWritable(
  const OctreeFileHeader& header, const std::vector<FileArray>& arrays, std::string* error)
{
  if (arrays.size() > MaxArrays)
  {
    return Fail(error, "too many arrays (" + std::to_string(arrays.size()) + ")");
  }
  if (header.CoarsestDrawnLevel < 0 || header.CoarsestDrawnLevel > header.FinestLevel)
  {
    return Fail(error,
      "the coarsest drawn level " + std::to_string(header.CoarsestDrawnLevel) +
        " is not in [0, the finest level " + std::to_string(header.FinestLevel) + "]");
  }
  for (size_t a = 0; a < arrays.size(); ++a)
  {
    const FileArray& f = arrays[a];
    if (f.Name.empty() || f.Name.size() >= NameBytes || FileTypeSize(f.Type) == 0 ||
      f.Components < 1 || f.Components > 65535 || f.Tuples < 0 ||
      (f.Tuples > 0 && !f.Data && !f.Values))
    {
      return Fail(error, "array " + std::to_string(a) + " ('" + f.Name + "') cannot be written");
    }
  }
  return true;
}

/// The header and directory of a file of `fileSize` bytes holding `arrays` as `placed`.
std::vector<unsigned char> EncodeHeader(const OctreeFileHeader& header,
  const std::vector<FileArray>& arrays, const std::vector<PlacedArray>& placed, uint32_t version,
  uint64_t fileSize)
{
  const size_t headerSize = HeaderBytes + EntryBytes * arrays.size();
  std::vector<unsigned char> head(headerSize, 0);
  for (size_t a = 0; a < arrays.size(); ++a)
  {
    const FileArray& f = arrays[a];
    unsigned char* e = head.data() + HeaderBytes + EntryBytes * a;
    std::memcpy(e, f.Name.data(), f.Name.size());
    e[32] = static_cast<unsigned char>(f.Group);
    e[33] = static_cast<unsigned char>(f.Type);
    Put<uint16_t>(e + 34, static_cast<uint16_t>(f.Components));
    e[36] = placed[a].Encoding;
    Put<int64_t>(e + 40, f.Tuples);
    Put<uint64_t>(e + 48, placed[a].Offset);
    Put<uint64_t>(e + 56, placed[a].Checksum);
  }
  std::memcpy(head.data(), Magic, 8);
  Put<uint32_t>(head.data() + 8, version);
  Put<uint32_t>(head.data() + 12, ByteOrderMark);
  Put<uint32_t>(head.data() + 16, static_cast<uint32_t>(headerSize));
  Put<uint32_t>(head.data() + 20, static_cast<uint32_t>(arrays.size()));
  for (int k = 0; k < 3; ++k)
  {
    Put<double>(head.data() + 24 + 8 * k, header.Origin[k]);
  }
  Put<double>(head.data() + 48, header.RootEdge);
  Put<int32_t>(head.data() + 56, header.FinestLevel);
  Put<uint32_t>(head.data() + 60,
    (header.HasMaterialArrays ? 1u : 0u) | (static_cast<uint32_t>(header.CoarsestDrawnLevel) << 8));
  const int64_t counts[6] = { header.Nodes, header.Points, header.Triangles, header.Clusters,
    header.BoundaryEdges, header.NonManifoldEdges };
  for (int k = 0; k < 6; ++k)
  {
    Put<int64_t>(head.data() + 64 + 8 * k, counts[k]);
  }
  Put<uint64_t>(head.data() + 112, fileSize);
  Put<uint32_t>(head.data() + 124,
    static_cast<uint32_t>(std::min<int64_t>(
      std::max<int64_t>(header.MisorientedEdges, 0), std::numeric_limits<uint32_t>::max())));
  Put<uint32_t>(head.data() + 120, HeaderChecksum(head.data(), headerSize));
  return head;
}

/// What kind of file `mode` describes, for messages.
std::string KindOf(mode_t mode)
{
  return S_ISDIR(mode) ? "is a directory"
    : S_ISFIFO(mode)   ? "is a FIFO (named pipe)"
    : S_ISCHR(mode)    ? "is a character device"
    : S_ISBLK(mode)    ? "is a block device"
    : S_ISSOCK(mode)   ? "is a socket"
                       : "is not a regular file";
}

/// The file a write to `path` replaces: `path` itself, or the file a symbolic link (or a chain
/// of them) points to. `existing` tells whether it exists (then `mode` holds its permissions).
/// False with `error` when the target exists and is not a regular file.
bool ResolveWriteTarget(
  const std::string& path, std::string& target, bool& existing, mode_t& mode, std::string* error)
{
  target = path;
  for (int hops = 0; hops < 40; ++hops)
  {
    struct stat st;
    if (::lstat(target.c_str(), &st) != 0)
    {
      if (errno != ENOENT)
      {
        return Fail(error, "cannot write '" + path + "': " + std::strerror(errno));
      }
      existing = false; // a new file (or a dangling link's target: created)
      return true;
    }
    if (S_ISREG(st.st_mode))
    {
      existing = true;
      mode = st.st_mode & 07777;
      return true;
    }
    if (!S_ISLNK(st.st_mode))
    {
      return Fail(error,
        "cannot write '" + path + "': it " + KindOf(st.st_mode) +
          "; an octree is saved only to a regular file, which it replaces");
    }
    std::vector<char> link(static_cast<size_t>(st.st_size > 0 ? st.st_size : 4096) + 1);
    const ssize_t n = ::readlink(target.c_str(), link.data(), link.size() - 1);
    if (n < 0)
    {
      return Fail(error, "cannot write '" + path + "': " + std::strerror(errno));
    }
    std::string next(link.data(), static_cast<size_t>(n));
    if (!next.empty() && next[0] != '/')
    {
      const size_t slash = target.find_last_of('/');
      next = (slash == std::string::npos ? std::string() : target.substr(0, slash + 1)) + next;
    }
    target = next;
  }
  return Fail(error, "cannot write '" + path + "': too many levels of symbolic links");
}

/// The directory of `file` ("." for a bare name).
std::string DirectoryOf(const std::string& file)
{
  const size_t slash = file.find_last_of('/');
  return slash == std::string::npos ? std::string(".")
    : slash == 0                    ? std::string("/")
                                    : file.substr(0, slash);
}

/// Creates a new, empty temporary file beside `target`; its descriptor (or -1 with `error`).
int CreateTemporaryBeside(const std::string& target, std::string& temporary, std::string* error)
{
  const size_t slash = target.find_last_of('/');
  const std::string base = slash == std::string::npos ? target : target.substr(slash + 1);
  const std::string prefix =
    (slash == std::string::npos ? std::string() : target.substr(0, slash + 1)) + "." + base + ".";
  static std::atomic<unsigned> counter{ 0 };
  for (int attempt = 0; attempt < 100; ++attempt)
  {
    char suffix[48];
    std::snprintf(suffix, sizeof suffix, "%ld.%u.tmp", static_cast<long>(::getpid()),
      counter.fetch_add(1) * 2654435761u + static_cast<unsigned>(attempt));
    temporary = prefix + suffix;
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0)
    {
      return fd;
    }
    if (errno != EEXIST)
    {
      Fail(error,
        "cannot create a temporary file in '" + DirectoryOf(target) + "' to write '" + target +
          "': " + std::strerror(errno));
      return -1;
    }
  }
  Fail(error, "cannot create a temporary file beside '" + target + "'");
  return -1;
}

/// Writes all `bytes` at `data` to `fd`; false (errno set) on a short or failed write.
bool WriteAll(int fd, const void* data, uint64_t bytes)
{
  const char* p = static_cast<const char*>(data);
  while (bytes > 0)
  {
    const ssize_t n = ::write(fd, p, static_cast<size_t>(std::min<uint64_t>(bytes, 1u << 30)));
    if (n < 0 && errno == EINTR)
    {
      continue;
    }
    if (n <= 0)
    {
      if (n == 0)
      {
        errno = ENOSPC;
      }
      return false;
    }
    p += n;
    bytes -= static_cast<uint64_t>(n);
  }
  return true;
}

/// Writes all `bytes` at `data` to `fd` at `offset`; false (errno set) on a short or failed
/// write.
bool WriteAllAt(int fd, const void* data, uint64_t bytes, uint64_t offset)
{
  return ::lseek(fd, static_cast<off_t>(offset), SEEK_SET) >= 0 && WriteAll(fd, data, bytes) &&
    ::lseek(fd, 0, SEEK_END) >= 0;
}

/// Writes array `f` compressed in blocks from the file's position `at` (its offset) on, and
/// fills `placed` with its checksum; `at` becomes the end. False with `why` (errno set).
bool WriteBlocks(int fd, const FileArray& f, const ParallelFor& parallel, uint64_t& at,
  PlacedArray& placed, std::string* why)
{
  const int size = FileTypeSize(f.Type);
  const uint64_t tupleBytes = uint64_t(f.Components) * uint64_t(size);
  const uint64_t tuples = uint64_t(f.Tuples);
  const uint64_t blocks = (tuples + BlockTuples - 1) / BlockTuples;
  // the table is written last, when the blocks' sizes are known
  std::vector<unsigned char> table(8 + 4 * blocks, 0);
  Put<uint32_t>(table.data(), BlockTuples);
  Put<uint32_t>(table.data() + 4, static_cast<uint32_t>(blocks));
  const uint64_t tableAt = at;
  if (!WriteAll(fd, table.data(), table.size()))
  {
    *why = std::string("write: ") + std::strerror(errno);
    return false;
  }
  at += table.size();
  Checksummer sum;
  std::vector<std::vector<unsigned char>> raw(BlocksPerBatch), stored(BlocksPerBatch);
  std::vector<std::string> failed(BlocksPerBatch);
  for (uint64_t first = 0; first < blocks; first += BlocksPerBatch)
  {
    const size_t batch = static_cast<size_t>(std::min<uint64_t>(BlocksPerBatch, blocks - first));
    auto tuplesOf = [&](size_t k) {
      const uint64_t begin = (first + k) * BlockTuples;
      return std::min<uint64_t>(BlockTuples, tuples - begin);
    };
    for (size_t k = 0; k < batch; ++k) // Values are called in order, on this thread
    {
      raw[k].resize(static_cast<size_t>(tuplesOf(k) * tupleBytes));
      if (!GatherValues(f, (first + k) * BlockTuples * uint64_t(f.Components),
            tuplesOf(k) * uint64_t(f.Components), raw[k].data(), why))
      {
        errno = EIO;
        return false;
      }
    }
    parallel(static_cast<int64_t>(batch), 1, [&](int64_t b, int64_t e) {
      for (int64_t k = b; k < e; ++k)
      {
        failed[k].clear();
        CompressBlock(f, raw[k].data(), static_cast<size_t>(tuplesOf(k)), stored[k], &failed[k]);
      }
    });
    for (size_t k = 0; k < batch; ++k)
    {
      if (!failed[k].empty())
      {
        *why = failed[k];
        errno = EIO;
        return false;
      }
      if (!WriteAll(fd, stored[k].data(), stored[k].size()))
      {
        *why = std::string("write: ") + std::strerror(errno);
        return false;
      }
      sum.Add(stored[k].data(), stored[k].size());
      Put<uint32_t>(table.data() + 8 + 4 * (first + k), static_cast<uint32_t>(stored[k].size()));
      at += stored[k].size();
    }
  }
  if (!WriteAllAt(fd, table.data(), table.size(), tableAt))
  {
    *why = std::string("write: ") + std::strerror(errno);
    return false;
  }
  sum.Add(table.data(), table.size());
  placed.Checksum = sum.Finish();
  placed.Encoding = EncodingBlocks;
  return true;
}

/// Writes array `f` as it is from the file's position `at` on, and fills `placed` with its
/// checksum; `at` becomes the end. False with `why` (errno set).
bool WriteAsItIs(int fd, const FileArray& f, uint64_t& at, PlacedArray& placed, std::string* why)
{
  uint64_t sum = FnvOffset;
  if (!ForEachChunk(f, why, [&](const unsigned char* p, size_t n) {
        sum = ContinueChecksum(sum, p, n);
        if (!WriteAll(fd, p, n))
        {
          *why = std::string("write: ") + std::strerror(errno);
          return false;
        }
        at += n;
        return true;
      }))
  {
    errno = errno ? errno : EIO;
    return false;
  }
  placed.Checksum = sum;
  return true;
}

/// Writes the file: the arrays one after the other, each from a page boundary, then the header
/// and directory at the start (they hold the arrays' checksums); `fileSize` receives the size.
/// False with `why` (errno set).
bool WriteContents(int fd, const OctreeFileHeader& header, const std::vector<FileArray>& arrays,
  const FileWriteOptions& options, uint64_t& fileSize, std::string* why)
{
  const bool compact = options.Layout == FileLayout::Compact;
  const ParallelFor parallel = options.Parallel ? options.Parallel : ParallelFor(SerialFor);
  const uint64_t headerSize = HeaderBytes + EntryBytes * arrays.size();
  const std::vector<unsigned char> zeros(Alignment, 0);
  std::vector<PlacedArray> placed(arrays.size());
  // the header's place, written last; the file ends with the last array's data
  const uint64_t alignment = compact ? BlocksAlignment : Alignment;
  uint64_t at = AlignUp(headerSize, alignment);
  if (!WriteAll(fd, zeros.data(), at))
  {
    *why = std::string("write: ") + std::strerror(errno);
    return false;
  }
  for (size_t a = 0; a < arrays.size(); ++a)
  {
    const FileArray& f = arrays[a];
    if (DataBytes(f) == 0)
    {
      continue; // an empty array has no place in the file
    }
    if (!WriteAll(fd, zeros.data(), AlignUp(at, alignment) - at))
    {
      *why = std::string("write: ") + std::strerror(errno);
      return false;
    }
    at = AlignUp(at, alignment);
    placed[a].Offset = at;
    if (!(compact ? WriteBlocks(fd, f, parallel, at, placed[a], why)
                  : WriteAsItIs(fd, f, at, placed[a], why)))
    {
      return false;
    }
  }
  fileSize = at;
  const std::vector<unsigned char> head =
    EncodeHeader(header, arrays, placed, compact ? CompactVersion : MappedVersion, fileSize);
  if (!WriteAllAt(fd, head.data(), head.size(), 0))
  {
    *why = std::string("write: ") + std::strerror(errno);
    return false;
  }
  return true;
}

/// Syncs the directory `dir`, so that a rename in it survives a crash (best effort: some
/// file systems cannot sync a directory).
void SyncDirectory(const std::string& dir)
{
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0)
  {
    ::fsync(fd);
    ::close(fd);
  }
}
} // namespace

uint64_t FileChecksum(const void* data, size_t bytes)
{
  return ContinueChecksum(FnvOffset, data, bytes);
}

bool WriteOctreeFile(const std::string& path, const OctreeFileHeader& header,
  const std::vector<FileArray>& arrays, std::string* error)
{
  return WriteOctreeFile(path, header, arrays, FileWriteOptions(), error);
}

bool WriteOctreeFile(const std::string& path, const OctreeFileHeader& header,
  const std::vector<FileArray>& arrays, const FileWriteOptions& options, std::string* error)
{
  uint64_t fileSize = 0;
  std::string target, temporary;
  bool existing = false;
  mode_t mode = 0;
  if (path.empty())
  {
    return Fail(error, "no file name to write the octree to");
  }
  if (!CheckWritable(header, arrays, error) ||
    !ResolveWriteTarget(path, target, existing, mode, error))
  {
    return false; // nothing written
  }
  const int fd = CreateTemporaryBeside(target, temporary, error);
  if (fd < 0)
  {
    return false;
  }
  // from here on, a failure removes the temporary file and nothing else
  auto abandon = [&](const std::string& reason) {
    ::unlink(temporary.c_str());
    return Fail(error,
      "writing '" + path + "' failed (" + reason + "); " +
        (existing ? "the existing file is unchanged" : "no file was made"));
  };
  std::string why;
  bool ok = WriteContents(fd, header, arrays, options, fileSize, &why);
  if (ok && existing && ::fchmod(fd, mode) != 0)
  {
    ok = false;
    why = std::string("setting the permissions: ") + std::strerror(errno);
  }
  if (ok && ::fsync(fd) != 0)
  {
    ok = false;
    why = std::string("sync: ") + std::strerror(errno);
  }
  if (::close(fd) != 0 && ok)
  {
    ok = false;
    why = std::string("close: ") + std::strerror(errno);
  }
  if (!ok)
  {
    return abandon(why);
  }
  OctreeFile check;
  if (!OpenFile(temporary, true, true, false, check, &why, options.Parallel, nullptr) ||
    check.Identity.Size != static_cast<int64_t>(fileSize))
  {
    return abandon("the written file does not read back: " + why);
  }
  check = OctreeFile();
  if (::rename(temporary.c_str(), target.c_str()) != 0)
  {
    return abandon(std::string("rename over the target: ") + std::strerror(errno));
  }
  SyncDirectory(DirectoryOf(target));
  return true;
}

bool IsRegularFile(const std::string& path, std::string* why)
{
  struct stat st;
  if (path.empty() || ::stat(path.c_str(), &st) != 0)
  {
    return Fail(why, path.empty() ? "no file name" : std::strerror(errno));
  }
  if (!S_ISREG(st.st_mode))
  {
    return Fail(why, KindOf(st.st_mode) + ", not a regular file");
  }
  return true;
}

namespace
{
FileIdentity IdentityOf(const std::string& path, const struct stat& st)
{
  FileIdentity id;
  id.Path = path;
  id.Device = static_cast<uint64_t>(st.st_dev);
  id.Inode = static_cast<uint64_t>(st.st_ino);
  id.Size = static_cast<int64_t>(st.st_size);
  id.ModifiedNs = static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  return id;
}
}

FileChange CompareFileIdentity(const FileIdentity& opened, std::string* why)
{
  struct stat st;
  if (::stat(opened.Path.c_str(), &st) != 0)
  {
    Fail(why, "'" + opened.Path + "' is gone (" + std::strerror(errno) + ")");
    return FileChange::Gone;
  }
  const FileIdentity now = IdentityOf(opened.Path, st);
  if (now.Device != opened.Device || now.Inode != opened.Inode)
  {
    Fail(why, "'" + opened.Path + "' was replaced by another file");
    return FileChange::Replaced;
  }
  if (now.Size != opened.Size || now.ModifiedNs != opened.ModifiedNs)
  {
    Fail(why,
      "'" + opened.Path + "' was changed in place since it was opened (" +
        std::to_string(opened.Size) + " bytes then, " + std::to_string(now.Size) + " now)");
    return FileChange::ChangedInPlace;
  }
  return FileChange::Same;
}

namespace
{
/// The file's bytes: a private (copy-on-write) map when asked and possible, else a buffer read
/// from `fd`; null with `why` when neither works.
std::shared_ptr<void> LoadBytes(int fd, uint64_t size, bool mapFile, bool& mapped, std::string& why)
{
  mapped = false;
  if (mapFile && HostIsLittleEndian())
  {
    void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE, fd, 0);
    if (p != MAP_FAILED)
    {
      mapped = true;
      return std::shared_ptr<void>(p, [size](void* q) { ::munmap(q, size); });
    }
  }
  void* p = ::operator new(size, std::nothrow);
  if (!p)
  {
    why = "not enough memory to read " + std::to_string(size) + " bytes";
    return nullptr;
  }
  std::shared_ptr<void> memory(p, [](void* q) { ::operator delete(q); });
  uint64_t got = 0;
  while (got < size)
  {
    const ssize_t n = ::pread(fd, static_cast<char*>(p) + got, size - got, off_t(got));
    if (n <= 0)
    {
      why = "read failed after " + std::to_string(got) + " bytes";
      return nullptr;
    }
    got += static_cast<uint64_t>(n);
  }
  return memory;
}

/// The header of the `size` bytes: magic, version, byte order, directory size, checksum, the
/// stated size, then the root cube and the counts into `h`; `count` receives the number of
/// arrays. "" or what is wrong.
std::string ReadHeader(const unsigned char* bytes, uint64_t size, OctreeFileHeader& h,
  uint32_t& count, uint32_t& version)
{
  if (std::memcmp(bytes, Magic, 8) != 0)
  {
    return "not an octree file (it does not start with PLODOCT)";
  }
  version = Get<uint32_t>(bytes + 8);
  if (version != MappedVersion && version != CompactVersion)
  {
    return "octree file format version " + std::to_string(version) +
      "; this reader knows versions " + std::to_string(MappedVersion) + " and " +
      std::to_string(CompactVersion) + " (a newer PerceptualLOD wrote it?)";
  }
  if (Get<uint32_t>(bytes + 12) != ByteOrderMark)
  {
    return "corrupt header (byte-order mark)";
  }
  const uint32_t headerSize = Get<uint32_t>(bytes + 16);
  count = Get<uint32_t>(bytes + 20);
  if (count > MaxArrays || headerSize != HeaderBytes + EntryBytes * count || headerSize > size)
  {
    return "corrupt header (" + std::to_string(count) + " arrays, header of " +
      std::to_string(headerSize) + " bytes in a file of " + std::to_string(size) + ")";
  }
  if (Get<uint32_t>(bytes + 120) != HeaderChecksum(bytes, headerSize))
  {
    return "corrupt header (checksum mismatch)";
  }
  const uint64_t statedSize = Get<uint64_t>(bytes + 112);
  if (statedSize != size)
  {
    return std::string(size < statedSize ? "truncated" : "longer than written") + ": " +
      std::to_string(size) + " bytes, the header says " + std::to_string(statedSize);
  }
  for (int k = 0; k < 3; ++k)
  {
    h.Origin[k] = Get<double>(bytes + 24 + 8 * k);
  }
  h.RootEdge = Get<double>(bytes + 48);
  h.FinestLevel = Get<int32_t>(bytes + 56);
  h.HasMaterialArrays = (Get<uint32_t>(bytes + 60) & 1u) != 0;
  h.CoarsestDrawnLevel = static_cast<int32_t>((Get<uint32_t>(bytes + 60) >> 8) & 0xffu);
  int64_t* counts[6] = { &h.Nodes, &h.Points, &h.Triangles, &h.Clusters, &h.BoundaryEdges,
    &h.NonManifoldEdges };
  for (int k = 0; k < 6; ++k)
  {
    *counts[k] = Get<int64_t>(bytes + 64 + 8 * k);
  }
  h.MisorientedEdges = Get<uint32_t>(bytes + 124);
  const int64_t maxIndex = std::numeric_limits<int32_t>::max();
  if (!(std::isfinite(h.Origin[0]) && std::isfinite(h.Origin[1]) && std::isfinite(h.Origin[2]) &&
        std::isfinite(h.RootEdge) && h.RootEdge > 0) ||
    h.FinestLevel < 0 || h.FinestLevel > 21 || h.CoarsestDrawnLevel > h.FinestLevel ||
    h.Nodes < 0 || h.Nodes > maxIndex || h.Points < 0 || h.Points > maxIndex || h.Triangles < 0 ||
    h.Triangles > maxIndex || h.Clusters < 0 || h.Clusters > maxIndex || h.BoundaryEdges < 0 ||
    h.NonManifoldEdges < 0)
  {
    return "corrupt header (root cube, level or counts out of range)";
  }
  return std::string();
}

/// A compressed array's blocks, as its table gives them.
struct StoredBlocks
{
  const unsigned char* Table = nullptr; // tuples per block, count, sizes
  const unsigned char* First = nullptr; // the first block
  uint64_t TuplesPerBlock = 0;
  uint64_t Count = 0;
  std::vector<uint64_t> Start; // each block's offset from First, and the end
};

/// The blocks of the compressed array `f` stored at `offset`, checked against its tuples and
/// the file's size; "" or what is wrong. `extent` receives the bytes they span.
std::string LocateBlocks(const unsigned char* bytes, uint64_t size, uint64_t offset,
  const FileArray& f, StoredBlocks& blocks, std::pair<uint64_t, uint64_t>& extent)
{
  const uint64_t room = size - offset;
  if (room < 8)
  {
    return "its block table lies outside the file";
  }
  blocks.Table = bytes + offset;
  blocks.TuplesPerBlock = Get<uint32_t>(blocks.Table);
  blocks.Count = Get<uint32_t>(blocks.Table + 4);
  if (blocks.TuplesPerBlock == 0 ||
    blocks.Count != (uint64_t(f.Tuples) + blocks.TuplesPerBlock - 1) / blocks.TuplesPerBlock)
  {
    return "its block table does not fit its " + std::to_string(f.Tuples) + " tuples (" +
      std::to_string(blocks.Count) + " blocks of " + std::to_string(blocks.TuplesPerBlock) + ")";
  }
  const uint64_t tableBytes = 8 + 4 * blocks.Count;
  if (tableBytes > room)
  {
    return "its block table lies outside the file";
  }
  blocks.First = blocks.Table + tableBytes;
  blocks.Start.assign(1, 0);
  for (uint64_t k = 0; k < blocks.Count; ++k)
  {
    blocks.Start.push_back(blocks.Start.back() + Get<uint32_t>(blocks.Table + 8 + 4 * k));
  }
  if (blocks.Start.back() > room - tableBytes)
  {
    return "its blocks lie outside the file (" + std::to_string(blocks.Start.back()) +
      " bytes from offset " + std::to_string(offset + tableBytes) + ", file of " +
      std::to_string(size) + ")";
  }
  extent = { offset, offset + tableBytes + blocks.Start.back() };
  return std::string();
}

/// Lets go of the whole pages of [begin, end) of a mapped file (`base` is the map's start),
/// so that reading a file larger than memory does not hold it.
void ReleasePages(unsigned char* base, uint64_t begin, uint64_t end)
{
  const uint64_t page = static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  begin = (begin + page - 1) / page * page;
  end = end / page * page;
  if (end > begin)
  {
    ::madvise(base + begin, static_cast<size_t>(end - begin), MADV_DONTNEED);
  }
}

/// The checksum of a compressed array: its blocks, then its table. A mapped file's pages are
/// let go once summed, every 64 MiB.
uint64_t BlocksChecksum(unsigned char* base, const StoredBlocks& blocks, bool mapped)
{
  constexpr uint64_t window = uint64_t(64) << 20;
  Checksummer sum;
  const uint64_t first = static_cast<uint64_t>(blocks.First - base);
  for (uint64_t done = 0; done < blocks.Start.back(); done += window)
  {
    const uint64_t n = std::min(window, blocks.Start.back() - done);
    sum.Add(blocks.First + done, static_cast<size_t>(n));
    if (mapped)
    {
      ReleasePages(base, first + done, first + done + n);
    }
  }
  sum.Add(blocks.Table, static_cast<size_t>(8 + 4 * blocks.Count));
  return sum.Finish();
}

/// Array `a` of the directory: its entry checked against the header's counts and the file's
/// size, its values brought to the host's byte order, their checksum verified when asked (a
/// mapped file's pages let go once checked, so that verifying a file larger than memory does not
/// hold it); `extent` receives the bytes it spans (empty for no values). A compressed array
/// (`blocks` filled, Data left null: OpenOctreeFile decodes it) has its table checked and its
/// checksum verified always. "" or what is wrong.
std::string ReadArray(unsigned char* bytes, uint64_t size, const OctreeFileHeader& h,
  uint32_t count, uint32_t version, uint32_t a, bool verifyChecksums, bool mapped, FileArray& f,
  StoredBlocks& blocks, std::pair<uint64_t, uint64_t>& extent)
{
  const uint32_t headerSize = HeaderBytes + EntryBytes * count;
  const unsigned char* e = bytes + HeaderBytes + EntryBytes * a;
  const std::string at = "array " + std::to_string(a) + ": ";
  if (std::memchr(e, 0, NameBytes) == nullptr)
  {
    return at + "name not terminated";
  }
  f.Name = reinterpret_cast<const char*>(e);
  const uint8_t group = e[32], type = e[33];
  f.Components = Get<uint16_t>(e + 34);
  f.Tuples = Get<int64_t>(e + 40);
  const uint64_t offset = Get<uint64_t>(e + 48);
  f.Checksum = Get<uint64_t>(e + 56);
  if (group > 3 || type < 1 || type > 4 || f.Components < 1 || f.Components > 16)
  {
    return at + "'" + f.Name + "' has an unknown group, type or component count";
  }
  f.Group = static_cast<FileArrayGroup>(group);
  f.Type = static_cast<FileArrayType>(type);
  const int64_t expected[4] = { h.Nodes, h.Clusters, h.Points, h.Triangles };
  if (f.Tuples != expected[group])
  {
    return at + "'" + f.Name + "' has " + std::to_string(f.Tuples) +
      " tuples where its group has " + std::to_string(expected[group]);
  }
  const uint64_t length =
    uint64_t(f.Tuples) * uint64_t(f.Components) * uint64_t(FileTypeSize(f.Type));
  const uint8_t encoding = version == MappedVersion ? EncodingRaw : e[36];
  extent = { offset, offset };
  if (encoding != EncodingRaw && encoding != EncodingBlocks)
  {
    return at + "'" + f.Name + "' has an unknown encoding (" + std::to_string(encoding) + ")";
  }
  if (length == 0)
  {
    return std::string();
  }
  if (encoding == EncodingBlocks)
  {
    std::string why;
    if (offset % BlocksAlignment != 0 || offset < headerSize || offset > size)
    {
      why = "lies outside the file (offset " + std::to_string(offset) + ")";
    }
    else
    {
      why = LocateBlocks(bytes, size, offset, f, blocks, extent);
    }
    if (why.empty() && BlocksChecksum(bytes, blocks, mapped) != f.Checksum)
    {
      why = "is corrupt (checksum mismatch)";
    }
    return why.empty() ? why : at + "'" + f.Name + "' " + why;
  }
  if (offset % Alignment != 0 || offset < headerSize || offset > size || length > size - offset)
  {
    return at + "'" + f.Name + "' lies outside the file (offset " + std::to_string(offset) + ", " +
      std::to_string(length) + " bytes, file of " + std::to_string(size) + ")";
  }
  extent.second = offset + length;
  f.Data = bytes + offset;
  if (!HostIsLittleEndian())
  {
    SwapValues(bytes + offset, length, FileTypeSize(f.Type));
  }
  if (verifyChecksums)
  {
    uint64_t sum = FnvOffset;
    if (HostIsLittleEndian())
    {
      // in windows of 64 MiB (a multiple of the page size: the array starts on a page)
      constexpr uint64_t window = uint64_t(64) << 20;
      for (uint64_t done = 0; done < length; done += window)
      {
        const uint64_t n = std::min(window, length - done);
        sum = ContinueChecksum(sum, bytes + offset + done, static_cast<size_t>(n));
        if (mapped)
        {
          ::madvise(bytes + offset + done, static_cast<size_t>(n), MADV_DONTNEED);
        }
      }
    }
    else
    {
      std::vector<unsigned char> copy(bytes + offset, bytes + offset + length);
      SwapValues(copy.data(), length, FileTypeSize(f.Type));
      sum = FileChecksum(copy.data(), length);
    }
    if (sum != f.Checksum)
    {
      return at + "'" + f.Name + "' is corrupt (checksum mismatch)";
    }
  }
  return std::string();
}

/// The memory of an opened file: its map (or buffer), while an array stays in it, and the
/// decoded arrays.
struct OpenedMemory
{
  std::shared_ptr<void> File;
  std::vector<std::unique_ptr<unsigned char[]>> Decoded;
};

/// Decodes the compressed arrays of `out` (those with `blocks`) into memory of their own and
/// sets out.Memory, out.Mapped and out.Compact; `file` is the file's memory. "" or what is
/// wrong with which block.
std::string DecodeBlocks(OctreeFile& out, const std::vector<StoredBlocks>& blocks,
  const std::shared_ptr<void>& file, const ParallelFor& parallel)
{
  auto opened = std::make_shared<OpenedMemory>();
  struct Job
  {
    size_t Array;
    uint64_t Block;
  };
  std::vector<Job> jobs;
  bool inFile = false;
  uint64_t decoded = 0;
  for (size_t a = 0; a < out.Arrays.size(); ++a)
  {
    decoded += blocks[a].Table ? DataBytes(out.Arrays[a]) : 0;
  }
  const double machine = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
  if (machine > 0 && double(decoded) > 0.75 * machine)
  {
    // memory the kernel would grant and then not have: refused before a byte is decoded
    return "decoding this compact file takes " + std::to_string(decoded >> 20) +
      " MiB, more than three quarters of this machine's " +
      std::to_string(static_cast<uint64_t>(machine) >> 20) +
      " MiB; convert it to the mapped layout (plod::ConvertOctreeFile, PerceptualLODMain "
      "file.plod --save mapped.plod), which is read only where a view looks";
  }
  for (size_t a = 0; a < out.Arrays.size(); ++a)
  {
    FileArray& f = out.Arrays[a];
    if (!blocks[a].Table)
    {
      inFile = inFile || f.Data;
      continue;
    }
    const uint64_t bytes = DataBytes(f);
    opened->Decoded.emplace_back(new (std::nothrow) unsigned char[bytes]);
    if (!opened->Decoded.back())
    {
      return "not enough memory to decode the array '" + f.Name + "' (" + std::to_string(bytes) +
        " bytes)";
    }
    f.Data = opened->Decoded.back().get();
    for (uint64_t k = 0; k < blocks[a].Count; ++k)
    {
      jobs.push_back({ a, k });
    }
  }
  std::vector<std::string> failed(jobs.size());
  parallel(static_cast<int64_t>(jobs.size()), 1, [&](int64_t b, int64_t e) {
    for (int64_t j = b; j < e; ++j)
    {
      const FileArray& f = out.Arrays[jobs[j].Array];
      const StoredBlocks& s = blocks[jobs[j].Array];
      const uint64_t k = jobs[j].Block;
      const uint64_t first = k * s.TuplesPerBlock;
      const uint64_t tuples = std::min<uint64_t>(s.TuplesPerBlock, uint64_t(f.Tuples) - first);
      const uint64_t tupleBytes = uint64_t(f.Components) * uint64_t(FileTypeSize(f.Type));
      failed[j] = DecompressBlock(f, s.First + s.Start[k], s.Start[k + 1] - s.Start[k],
        static_cast<size_t>(tuples),
        static_cast<unsigned char*>(const_cast<void*>(f.Data)) + first * tupleBytes);
    }
  });
  for (size_t j = 0; j < jobs.size(); ++j)
  {
    if (!failed[j].empty())
    {
      return "array " + std::to_string(jobs[j].Array) + ": '" + out.Arrays[jobs[j].Array].Name +
        "' is corrupt (block " + std::to_string(jobs[j].Block) + ": " + failed[j] + ")";
    }
  }
  out.Compact = !jobs.empty();
  out.Mapped = out.Mapped && inFile;
  if (inFile)
  {
    opened->File = file; // an array stays in the file's memory
  }
  out.Memory = opened;
  return std::string();
}

/// OpenOctreeFile; `decode` false checks a compact file's blocks (table and checksum) without
/// decoding them (its compressed arrays are then left without Data), as a writer's check of
/// the file it wrote does, in bounded memory.
bool OpenFile(const std::string& path, bool verifyChecksums, bool mapFile, bool decode,
  OctreeFile& out, std::string* error, const ParallelFor& parallel, std::vector<StoredBlocks>* kept)
{
  out = OctreeFile();
  const std::string where = path + ": ";
  // decided before opening: opening a FIFO would wait for a writer
  std::string kind;
  if (!IsRegularFile(path, &kind))
  {
    return Fail(error, where + "cannot open: " + kind);
  }
  // non-blocking, should the path have become a FIFO since
  FileCloser file{ ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK) };
  if (file.Fd < 0)
  {
    return Fail(error, where + "cannot open: " + std::strerror(errno));
  }
  struct stat st;
  if (::fstat(file.Fd, &st) != 0 || !S_ISREG(st.st_mode))
  {
    return Fail(error, where + "cannot open: " + KindOf(st.st_mode) + ", not a regular file");
  }
  out.Identity = IdentityOf(path, st);
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  if (size < HeaderBytes)
  {
    return Fail(error,
      where + "too short for an octree file (" + std::to_string(size) +
        " bytes; the header alone is 128)");
  }
  std::string why;
  std::shared_ptr<void> memory = LoadBytes(file.Fd, size, mapFile, out.Mapped, why);
  if (!memory)
  {
    return Fail(error, where + why);
  }
  out.MapStart = out.Mapped ? memory.get() : nullptr;
  unsigned char* bytes = static_cast<unsigned char*>(memory.get());
  uint32_t count = 0, version = 0;
  why = ReadHeader(bytes, size, out.Header, count, version);
  if (!why.empty())
  {
    return Fail(error, where + why);
  }
  // the directory: every array checked, then no two overlapping
  std::vector<std::pair<uint64_t, uint64_t>> extents;
  std::vector<StoredBlocks> blocks(count);
  for (uint32_t a = 0; a < count; ++a)
  {
    FileArray f;
    std::pair<uint64_t, uint64_t> extent;
    why = ReadArray(bytes, size, out.Header, count, version, a, verifyChecksums, out.Mapped, f,
      blocks[a], extent);
    if (!why.empty())
    {
      out.Arrays.clear(); // nothing handed out from a file refused
      return Fail(error, where + why);
    }
    if (extent.second > extent.first)
    {
      extents.push_back(extent);
    }
    out.Arrays.push_back(f);
  }
  std::sort(extents.begin(), extents.end());
  for (size_t k = 1; k < extents.size(); ++k)
  {
    if (extents[k].first < extents[k - 1].second)
    {
      out.Arrays.clear();
      return Fail(error, where + "corrupt directory (arrays overlap)");
    }
  }
  if (!decode)
  {
    out.Memory = memory;
    if (kept)
    {
      *kept = std::move(blocks); // they point into out.Memory
    }
    return true;
  }
  why = DecodeBlocks(out, blocks, memory, parallel ? parallel : ParallelFor(SerialFor));
  if (!why.empty())
  {
    out.Arrays.clear(); // their decoded memory is gone
    return Fail(error, where + why);
  }
  return true;
}
} // namespace

bool OpenOctreeFile(const std::string& path, bool verifyChecksums, bool mapFile, OctreeFile& out,
  std::string* error, const ParallelFor& parallel)
{
  return OpenFile(path, verifyChecksums, mapFile, true, out, error, parallel, nullptr);
}

bool ConvertOctreeFile(const std::string& from, const std::string& to,
  const FileWriteOptions& options, std::string* error)
{
  OctreeFile in;
  std::vector<StoredBlocks> blocks;
  if (!OpenFile(from, true, true, false, in, error, options.Parallel, &blocks))
  {
    return false;
  }
  std::vector<FileArray> arrays = in.Arrays;
  for (size_t a = 0; a < arrays.size(); ++a)
  {
    if (!blocks[a].Table)
    {
      continue; // stored as it is: written from the map
    }
    // a compressed array is decoded block by block as the writer asks for its values
    struct Decoded
    {
      uint64_t Block = ~uint64_t(0);
      std::vector<unsigned char> Values;
    };
    auto cache = std::make_shared<Decoded>();
    const StoredBlocks* b = &blocks[a];
    const FileArray f = arrays[a];
    unsigned char* base = in.Mapped ? static_cast<unsigned char*>(in.Memory.get()) : nullptr;
    arrays[a].Data = nullptr;
    arrays[a].Values = [b, f, cache, base](
                         int64_t first, int64_t count, void* out, std::string* why) {
      const uint64_t size = uint64_t(FileTypeSize(f.Type));
      const uint64_t perBlock = b->TuplesPerBlock * uint64_t(f.Components);
      unsigned char* to = static_cast<unsigned char*>(out);
      for (uint64_t v = uint64_t(first); v < uint64_t(first + count);)
      {
        const uint64_t k = v / perBlock;
        if (cache->Block != k)
        {
          const uint64_t tuples =
            std::min<uint64_t>(b->TuplesPerBlock, uint64_t(f.Tuples) - k * b->TuplesPerBlock);
          cache->Values.resize(static_cast<size_t>(tuples * f.Components * size));
          const std::string wrong = DecompressBlock(f, b->First + b->Start[k],
            b->Start[k + 1] - b->Start[k], static_cast<size_t>(tuples), cache->Values.data());
          if (!wrong.empty())
          {
            *why = "block " + std::to_string(k) + " is corrupt: " + wrong;
            return false;
          }
          cache->Block = k;
          if (base) // the block's pages are not needed again
          {
            const uint64_t at = static_cast<uint64_t>(b->First - base);
            ReleasePages(base, at + b->Start[k], at + b->Start[k + 1]);
          }
        }
        const uint64_t n = std::min<uint64_t>(uint64_t(first + count) - v, (k + 1) * perBlock - v);
        std::memcpy(to, cache->Values.data() + (v - k * perBlock) * size, n * size);
        to += n * size;
        v += n;
      }
      return true;
    };
  }
  if (!WriteOctreeFile(to, in.Header, arrays, options, error))
  {
    return false;
  }
  return true;
}

} // namespace plod
