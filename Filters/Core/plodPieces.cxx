// SPDX-License-Identifier: BSD-3-Clause
// Partition of a PLY file into pieces in bounded memory. See plodPieces.h.
#include "plodPieces.h"
#include "plodBuildUtil.h"
#include "plodFileInput.h"
#include "plodOctree.h"
#include "plodOctreeBuilder.h"
#include "plodPLYRead.h"
#include "plodPartitionSteps.h"
#include "plodTemporaryFile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <limits>
#include <numeric>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <unordered_map>

namespace plod
{
namespace
{
using tempfile::Appender;
using tempfile::ReadBack;
using tempfile::SystemError;

/// Pieces merged at once (PieceBytesPerTriangle counts their memory).
constexpr int MergedAtOnce = 2;

/// Triangles read from the triangle file at a time.
constexpr int64_t BlockTriangles = int64_t(1) << 18;

/// A temporary file mapped read-only; its resident pages can be let go.
class Mapping
{
public:
  ~Mapping() { this->Unmap(); }

  bool Map(const std::string& path, int64_t bytes, std::string* why)
  {
    this->Unmap();
    if (bytes == 0)
    {
      return true;
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
    {
      *why = SystemError("cannot open the temporary file", path);
      return false;
    }
    void* p = ::mmap(nullptr, static_cast<size_t>(bytes), PROT_READ, MAP_PRIVATE, fd, 0);
    ::close(fd);
    if (p == MAP_FAILED)
    {
      *why = SystemError("cannot map the temporary file", path);
      return false;
    }
    this->Data = static_cast<const char*>(p);
    this->Bytes = static_cast<size_t>(bytes);
    return true;
  }

  /// Lets the kernel drop the pages read so far (they are read again from the file if needed).
  void Release() const
  {
    if (this->Data)
    {
      ::madvise(const_cast<char*>(this->Data), this->Bytes, MADV_DONTNEED);
    }
  }

  const char* Data = nullptr;

private:
  void Unmap()
  {
    if (this->Data)
    {
      ::munmap(const_cast<char*>(this->Data), this->Bytes);
    }
    this->Data = nullptr;
    this->Bytes = 0;
  }

  size_t Bytes = 0;
};

/// Writes the file's rows to the point, normal and triangle files.
class SplitSink : public PLYMeshSink
{
public:
  SplitSink(Appender& points, Appender& normals, Appender& triangles)
    : Points(points)
    , Normals(normals)
    , Triangles(triangles)
  {
  }

  bool BeginVertices(int64_t count, bool doubles, bool normals, std::string* why) override
  {
    if (count > int64_t(std::numeric_limits<uint32_t>::max()))
    {
      *why = "the file has " + std::to_string(count) + " vertices, more than 2^32 - 1";
      return false;
    }
    this->NumberOfPoints = count;
    this->Doubles = doubles;
    this->HasNormals = normals;
    return true;
  }

  bool Vertex(int64_t, const double xyz[3], const double normal[3], std::string* why) override
  {
    if (this->Doubles)
    {
      if (!this->Points.Write(xyz, 3 * sizeof(double), why))
      {
        return false;
      }
    }
    else
    {
      const float x[3] = { static_cast<float>(xyz[0]), static_cast<float>(xyz[1]),
        static_cast<float>(xyz[2]) };
      if (!this->Points.Write(x, sizeof(x), why))
      {
        return false;
      }
    }
    if (normal)
    {
      const float n[3] = { static_cast<float>(normal[0]), static_cast<float>(normal[1]),
        static_cast<float>(normal[2]) };
      return this->Normals.Write(n, sizeof(n), why);
    }
    return true;
  }

  bool BeginFace(int64_t, std::string*) override { return true; }

  bool Triangle(int64_t a, int64_t b, int64_t c, std::string* why) override
  {
    const uint32_t ids[3] = { static_cast<uint32_t>(a), static_cast<uint32_t>(b),
      static_cast<uint32_t>(c) };
    ++this->NumberOfTriangles;
    return this->Triangles.Write(ids, sizeof(ids), why);
  }

  Appender& Points;
  Appender& Normals;
  Appender& Triangles;
  int64_t NumberOfPoints = 0;
  int64_t NumberOfTriangles = 0;
  bool Doubles = false;
  bool HasNormals = false;
};

/**
 * The distinct values of `ids` in increasing order (`used`), and for each entry of `ids` its
 * index in `used` (`local`): a radix sort of (id, position) pairs, in linear time.
 */
void NumberUsedPoints(
  const LargeVector<uint32_t>& ids, LargeVector<uint32_t>* used, LargeVector<int64_t>* local)
{
  const size_t n = ids.size();
  LargeVector<uint64_t> pairs(n), other(n);
  for (size_t i = 0; i < n; ++i)
  {
    pairs[i] = uint64_t(ids[i]) << 32 | uint64_t(i);
  }
  // by the id (the upper 32 bits), 11 bits at a time, stable
  for (int shift = 32; shift < 64; shift += 11)
  {
    std::vector<size_t> count(2049, 0);
    for (uint64_t v : pairs)
    {
      ++count[((v >> shift) & 2047) + 1];
    }
    std::partial_sum(count.begin(), count.end(), count.begin());
    for (uint64_t v : pairs)
    {
      other[count[(v >> shift) & 2047]++] = v;
    }
    pairs.swap(other);
  }
  used->clear();
  for (size_t i = 0; i < n; ++i)
  {
    const uint32_t id = static_cast<uint32_t>(pairs[i] >> 32);
    if (i == 0 || id != used->back())
    {
      used->push_back(id);
    }
    (*local)[pairs[i] & 0xffffffffu] = static_cast<int64_t>(used->size()) - 1;
  }
}

/**
 * Usable triangles counted by their box of level-k cells (k at most 6: each coordinate of a
 * cell in 6 bits): the boxes of one cell in a table by cell, the wider ones (triangles across a
 * cell's face) in a hash table.
 */
class BoxCounts
{
public:
  void Reset()
  {
    this->OneCell.assign(size_t(1) << 18, 0);
    this->Wider.clear();
  }

  void Add(const partition::Box& b)
  {
    const uint64_t lo = Code(b.Lo), hi = Code(b.Hi);
    if (lo == hi)
    {
      ++this->OneCell[lo];
    }
    else
    {
      ++this->Wider[lo | hi << 18];
    }
  }

  /// body(box, count) for every box with triangles, in no particular order.
  template <typename Body>
  void ForEach(Body&& body) const
  {
    for (size_t code = 0; code < this->OneCell.size(); ++code)
    {
      if (this->OneCell[code] > 0)
      {
        body(BoxOf(code, code), this->OneCell[code]);
      }
    }
    for (const auto& wide : this->Wider)
    {
      body(BoxOf(wide.first & 0x3ffff, wide.first >> 18), wide.second);
    }
  }

private:
  static uint64_t Code(const uint32_t c[3])
  {
    return uint64_t(c[0]) | uint64_t(c[1]) << 6 | uint64_t(c[2]) << 12;
  }

  static partition::Box BoxOf(uint64_t lo, uint64_t hi)
  {
    partition::Box b;
    for (int a = 0; a < 3; ++a)
    {
      b.Lo[a] = static_cast<uint32_t>(lo >> (6 * a) & 63);
      b.Hi[a] = static_cast<uint32_t>(hi >> (6 * a) & 63);
    }
    return b;
  }

  std::vector<int64_t> OneCell;                // by the cell's code
  std::unordered_map<uint64_t, int64_t> Wider; // by the codes of the box's corners
};

} // namespace

//------------------------------------------------------------------------------
double PieceBytesPerTriangle(bool normals)
{
  // MergePoints at its peak, per triangle received, for each of the pieces merged at once (about
  // half a point each): the triangles' indices (3 x int64, then sorted: as many again), half a
  // point read (position and normal as doubles), sorted (a key of 3 x int64 and an index) and
  // mapped (an int64), half a point kept (position, normal, ghost flag), the triangles kept (3 x
  // int64)
  const double point = 24.0 + (normals ? 24.0 : 0.0);
  const double kept = 24.0 + 0.5 * (point + 1.0);
  const double merge = MergedAtOnce * (48.0 + 0.5 * (point + 32.0 + 8.0) + kept);
  // the build of the piece, beside the piece it reads: its octree and work arrays for half a
  // point and 0.57 node per triangle, per 1000 triangles (every point in a leaf of its own,
  // and the ancestors: the pieces share the whole's finest level, which may be deep for them)
  const double build = EstimateBuildMemory(500, 1000, 570, false) / 1000.0 + kept;
  return std::max(merge, build);
}

struct PLYPieces::Internals
{
  PiecesParameters Params;
  std::string Directory;
  PartitionResult Agreed;
  partition::CellGrid Cells;
  std::vector<int64_t> PerCell;
  BoxCounts Boxes;
  std::vector<int> Owner;
  std::vector<std::vector<int>> NeededBy;
  std::vector<int64_t> PieceTriangles;
  std::vector<int64_t> PiecePoints;
  std::vector<int64_t> PieceOwnedCells;
  std::vector<int64_t> PieceHalo;
  std::vector<char> Removed; // per piece: its file removed (RemovePiece)
  int Pieces = 0;
  int64_t NumberOfPoints = 0;
  int64_t NumberOfTriangles = 0;
  bool Doubles = false;
  Mapping PointMap;
  Mapping NormalMap;
  int64_t TemporaryBytes = 0;
  int64_t PeakTemporaryBytes = 0;
  std::string* Why = nullptr;

  ~Internals() { this->RemoveDirectory(); }

  std::string PathOf(const std::string& name) const { return this->Directory + "/" + name; }
  std::string PieceFile(int p, const char* kind) const
  {
    return this->PathOf("piece-" + std::to_string(p) + kind);
  }

  void AddTemporary(int64_t bytes)
  {
    this->TemporaryBytes += bytes;
    this->PeakTemporaryBytes = std::max(this->PeakTemporaryBytes, this->TemporaryBytes);
  }

  void RemoveFile(const std::string& path)
  {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0)
    {
      this->TemporaryBytes -= static_cast<int64_t>(st.st_size);
      ::unlink(path.c_str());
    }
  }

  void RemoveDirectory()
  {
    if (this->Directory.empty())
    {
      return;
    }
    if (DIR* d = ::opendir(this->Directory.c_str()))
    {
      while (const dirent* e = ::readdir(d))
      {
        const std::string name = e->d_name;
        if (name != "." && name != "..")
        {
          ::unlink(this->PathOf(name).c_str());
        }
      }
      ::closedir(d);
    }
    ::rmdir(this->Directory.c_str());
    this->Directory.clear();
  }

  bool Fail(const std::string& message)
  {
    *this->Why = message;
    return false;
  }

  bool Report(double fraction, const char* step)
  {
    if (this->Params.Progress && !this->Params.Progress(std::min(1.0, fraction), step))
    {
      return this->Fail("aborted");
    }
    return true;
  }

  bool MakeDirectory()
  {
    std::string base = this->Params.TemporaryDirectory;
    if (base.empty())
    {
      const char* env = std::getenv("TMPDIR");
      base = env && *env ? env : "/tmp";
    }
    std::string pattern = base + "/plod-pieces-XXXXXX";
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    if (!::mkdtemp(name.data()))
    {
      return this->Fail(SystemError("cannot make a temporary directory in", base));
    }
    this->Directory = name.data();
    return true;
  }

  // 1. The file's points, normals and triangles to temporary files, the points mapped.
  bool SplitFile(const std::string& path)
  {
    Appender points, normals, triangles;
    if (!points.Open(this->PathOf("points"), this->Why) ||
      !normals.Open(this->PathOf("normals"), this->Why) ||
      !triangles.Open(this->PathOf("triangles"), this->Why))
    {
      return false;
    }
    SplitSink sink(points, normals, triangles);
    const bool read = StreamPLYMesh(
      path, &sink, this->Why, [this](double f) { return this->Report(f, split_step::Reading); });
    const bool closed =
      points.Close(this->Why) && normals.Close(this->Why) && triangles.Close(this->Why);
    this->AddTemporary(points.Size() + normals.Size() + triangles.Size());
    if (!read || !closed)
    {
      return false;
    }
    this->NumberOfPoints = sink.NumberOfPoints;
    this->NumberOfTriangles = sink.NumberOfTriangles;
    this->Doubles = sink.Doubles;
    this->Agreed.HasNormals = sink.HasNormals;
    return this->PointMap.Map(this->PathOf("points"), points.Size(), this->Why) &&
      this->NormalMap.Map(this->PathOf("normals"), normals.Size(), this->Why);
  }

  void Position(uint32_t id, double x[3]) const
  {
    if (this->Doubles)
    {
      std::memcpy(x, this->PointMap.Data + 24 * size_t(id), 24);
      return;
    }
    float f[3];
    std::memcpy(f, this->PointMap.Data + 12 * size_t(id), 12);
    x[0] = f[0];
    x[1] = f[1];
    x[2] = f[2];
  }

  void Normal(uint32_t id, double n[3]) const
  {
    float f[3];
    std::memcpy(f, this->NormalMap.Data + 12 * size_t(id), 12);
    n[0] = f[0];
    n[1] = f[1];
    n[2] = f[2];
  }

  /// body(ids, corners) for every usable triangle of the triangle file, in file order; the
  /// mapped points let go at the end.
  template <typename Body>
  bool ForEachTriangle(const char* step, Body&& body)
  {
    const std::string path = this->PathOf("triangles");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
    {
      return this->Fail(SystemError("cannot open the temporary file", path));
    }
    std::vector<uint32_t> block;
    double x[3][3];
    bool ok = true;
    for (int64_t first = 0; ok && first < this->NumberOfTriangles; first += BlockTriangles)
    {
      const int64_t n = std::min(BlockTriangles, this->NumberOfTriangles - first);
      ok = this->Report(double(first) / double(this->NumberOfTriangles), step) &&
        ReadBack(fd, 3 * n, &block, path, this->Why);
      for (int64_t t = 0; ok && t < n; ++t)
      {
        const uint32_t* ids = &block[3 * t];
        bool usable = true;
        for (int c = 0; c < 3; ++c)
        {
          this->Position(ids[c], x[c]);
          usable =
            usable && std::isfinite(x[c][0]) && std::isfinite(x[c][1]) && std::isfinite(x[c][2]);
        }
        if (usable)
        {
          ok = body(ids, x);
        }
      }
    }
    ::close(fd);
    this->PointMap.Release();
    this->NormalMap.Release();
    return ok;
  }

  // 2. The bounds and the root cube.
  bool PlaceRootCube()
  {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::numeric_limits<double>::max();
      hi[a] = -std::numeric_limits<double>::max();
    }
    int64_t usable = 0;
    const bool ok =
      this->ForEachTriangle(split_step::Bounds, [&](const uint32_t*, const double x[3][3]) {
        for (int c = 0; c < 3; ++c)
        {
          for (int a = 0; a < 3; ++a)
          {
            lo[a] = std::min(lo[a], x[c][a]);
            hi[a] = std::max(hi[a], x[c][a]);
          }
        }
        ++usable;
        return true;
      });
    if (!ok)
    {
      return false;
    }
    this->Agreed.NumberOfSkippedTriangles = this->NumberOfTriangles - usable;
    if (usable == 0)
    {
      this->Agreed.NoTriangles = true;
      return true;
    }
    std::string why;
    if (!build::PlaceRootCube(lo, hi, this->Agreed.RootOrigin, this->Agreed.RootEdge, &why))
    {
      return this->Fail("no root cube for the whole mesh: " + why);
    }
    this->Cells = partition::CellGrid(
      this->Agreed.RootOrigin, this->Agreed.RootEdge, this->Params.OwnershipLevel);
    return true;
  }

  // 3. Triangles per level-k cell and per box of cells; the pieces: as many as asked, or as
  // few as fit the memory limit with their halo; the cells each piece needs whole (from the
  // boxes: one pass over the triangles for every number of pieces tried).
  bool ShareOutCells()
  {
    this->PerCell.assign(this->Cells.CellCount(), 0);
    this->Boxes.Reset();
    if (!this->ForEachTriangle(split_step::Cells, [&](const uint32_t*, const double x[3][3]) {
          ++this->PerCell[this->Cells.CellOf(x[0])];
          this->Boxes.Add(this->Cells.BoxOf(x[0], x[1], x[2]));
          return true;
        }))
    {
      return false;
    }
    const int64_t usable = this->NumberOfTriangles - this->Agreed.NumberOfSkippedTriangles;
    const int64_t occupied = static_cast<int64_t>(
      std::count_if(this->PerCell.begin(), this->PerCell.end(), [](int64_t n) { return n > 0; }));
    const bool sized = this->Params.NumberOfPieces <= 0;
    const double fit = this->Params.MemoryLimit / PieceBytesPerTriangle(this->Agreed.HasNormals);
    // a first guess with a margin of a quarter for the halo, then more pieces while one does
    // not fit with its halo
    this->Pieces = sized ? static_cast<int>(std::max(1.0, std::ceil(1.25 * double(usable) / fit)))
                         : this->Params.NumberOfPieces;
    for (int attempt = 0;; ++attempt)
    {
      if (this->Pieces > occupied)
      {
        return this->Fail(std::to_string(this->Pieces) + " pieces needed but only " +
          std::to_string(occupied) + " cells of level " + std::to_string(this->Cells.K) +
          " are occupied: use a deeper ownership level" +
          (sized ? " or more memory" : " or fewer pieces"));
      }
      this->Owner = partition::ShareOutCells(this->PerCell, this->Pieces);
      this->FindNeededCells();
      this->CountPieceTriangles();
      const int64_t largest =
        *std::max_element(this->PieceTriangles.begin(), this->PieceTriangles.end());
      if (!sized || double(largest) <= fit)
      {
        break;
      }
      if (attempt == 8 || this->Pieces == occupied)
      {
        return this->Fail("a piece of " + std::to_string(largest) +
          " triangles (with its halo) does not fit the memory limit of " +
          std::to_string(static_cast<int64_t>(fit)) + " triangles; with " +
          std::to_string(this->Pieces) + " pieces at ownership level " +
          std::to_string(this->Cells.K) + ": use a deeper ownership level or more memory");
      }
      this->Pieces = static_cast<int>(std::min<double>(
        double(occupied), std::ceil(double(this->Pieces) * 1.1 * double(largest) / fit)));
    }
    this->PieceOwnedCells.assign(this->Pieces, 0);
    for (int64_t cell = 0; cell < this->Cells.CellCount(); ++cell)
    {
      this->PieceOwnedCells[this->Owner[cell]] += this->PerCell[cell] > 0;
    }
    return true;
  }

  /// The cells each piece needs whole, as the pieces needing each cell.
  void FindNeededCells()
  {
    const int64_t cellCount = this->Cells.CellCount();
    std::vector<uint8_t> needs(static_cast<size_t>(this->Pieces) * cellCount, 0);
    std::vector<int64_t> touched;
    this->Boxes.ForEach([&](const partition::Box& box, int64_t) {
      partition::MarkNeededCells(box, this->Owner, cellCount, needs.data(), touched);
    });
    this->NeededBy.assign(cellCount, {});
    for (int p = 0; p < this->Pieces; ++p)
    {
      for (int64_t cell = 0; cell < cellCount; ++cell)
      {
        if (needs[static_cast<size_t>(p) * cellCount + cell])
        {
          this->NeededBy[cell].push_back(p);
        }
      }
    }
  }

  /// body(ids, p) for each piece p needing each triangle.
  template <typename Body>
  bool ForEachPieceTriangle(const char* step, Body&& body)
  {
    std::vector<int64_t> seen(this->Pieces, -1);
    int64_t t = 0;
    return this->ForEachTriangle(step, [&](const uint32_t* ids, const double x[3][3]) {
      ++t;
      bool ok = true;
      partition::ForEachCell(this->Cells.BoxOf(x[0], x[1], x[2]), [&](int64_t cell) {
        for (int p : this->NeededBy[cell])
        {
          if (seen[p] != t)
          {
            seen[p] = t;
            ok = ok && body(ids, p);
          }
        }
      });
      return ok;
    });
  }

  /// The triangles each piece receives: a box's triangles go to every piece needing a cell of
  /// it (as ForEachPieceTriangle sends them).
  void CountPieceTriangles()
  {
    this->PieceTriangles.assign(this->Pieces, 0);
    std::vector<char> seen(this->Pieces);
    this->Boxes.ForEach([&](const partition::Box& box, int64_t count) {
      std::fill(seen.begin(), seen.end(), 0);
      partition::ForEachCell(box, [&](int64_t cell) {
        for (int p : this->NeededBy[cell])
        {
          this->PieceTriangles[p] += seen[p] ? 0 : count;
          seen[p] = 1;
        }
      });
    });
  }

  // 4. Each triangle's indices to every piece needing it.
  bool Distribute()
  {
    std::vector<Appender> files(this->Pieces);
    for (int p = 0; p < this->Pieces; ++p)
    {
      if (!files[p].Open(this->PieceFile(p, ".ids"), this->Why))
      {
        return false;
      }
    }
    const bool ok =
      this->ForEachPieceTriangle(split_step::Distributing, [&](const uint32_t* ids, int p) {
        return files[p].Write(ids, 3 * sizeof(uint32_t), this->Why);
      });
    bool closed = true;
    for (int p = 0; p < this->Pieces; ++p)
    {
      closed = files[p].Close(this->Why) && closed;
      this->AddTemporary(files[p].Size());
    }
    this->RemoveFile(this->PathOf("triangles"));
    return ok && closed;
  }

  // 5. Each piece merged and kept; its open edges and owned cells counted for all.
  bool MergePieces()
  {
    int64_t counts[MaxFinestLevel + 2] = {};
    this->PiecePoints.assign(this->Pieces, 0);
    this->PieceHalo.assign(this->Pieces, 0);
    this->Removed.assign(this->Pieces, 0);
    for (int first = 0; first < this->Pieces; first += MergedAtOnce)
    {
      if (!this->Report(double(first) / double(this->Pieces), split_step::Merging))
      {
        return false;
      }
      // MergedAtOnce pieces at a time, over the caller's threads
      const int n = std::min(MergedAtOnce, this->Pieces - first);
      std::vector<PartitionResult> merged(n);
      std::vector<std::string> why(n);
      std::vector<char> ok(n, 0);
      for (PartitionResult& r : merged)
      {
        std::copy(this->Agreed.RootOrigin, this->Agreed.RootOrigin + 3, r.RootOrigin);
        r.RootEdge = this->Agreed.RootEdge;
      }
      this->Params.Parallel(n, 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i)
        {
          ok[i] = this->MergePiece(first + int(i), &merged[i], &why[i]);
        }
      });
      this->PointMap.Release();
      this->NormalMap.Release();
      for (int i = 0; i < n; ++i)
      {
        this->TemporaryBytes -= 12 * this->PieceTriangles[first + i]; // its ids, removed
        if (!ok[i])
        {
          return this->Fail(why[i]);
        }
      }
      for (int i = 0; i < n; ++i)
      {
        const int p = first + i;
        const PartitionResult& r = merged[i];
        this->Agreed.NumberOfBoundaryEdges += partition::CountOpenEdges(r);
        int64_t owned[MaxFinestLevel + 2] = {};
        partition::CountOwnedCells(r, this->Cells, owned);
        for (int l = 0; l < MaxFinestLevel + 2; ++l)
        {
          counts[l] += owned[l];
        }
        this->PiecePoints[p] = static_cast<int64_t>(r.Ghost.size());
        this->PieceHalo[p] = r.NumberOfHaloTriangles;
        if (!this->KeepPiece(p, r))
        {
          return false;
        }
      }
    }
    // every piece holds its points: the file's are no longer needed
    this->RemoveFile(this->PathOf("points"));
    this->RemoveFile(this->PathOf("normals"));
    if (this->Params.RequestedFinestLevel >= 0)
    {
      this->Agreed.FinestLevel = std::min(this->Params.RequestedFinestLevel, MaxFinestLevel);
      return true;
    }
    partition::CountCoarseCells(this->PerCell, this->Cells.K, counts);
    this->Agreed.FinestLevel =
      ChooseFinestLevelFromCounts(counts, counts[MaxFinestLevel + 1], false);
    return this->Agreed.FinestLevel >= 0 ||
      this->Fail("inconsistent occupied-cell counts over the pieces: no common level");
  }

  /// Piece p merged from its ids file (which it removes); distinct pieces may be merged at
  /// once on different threads. False with `why`.
  bool MergePiece(int p, PartitionResult* r, std::string* why) const
  {
    const std::string path = this->PieceFile(p, ".ids");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
    {
      *why = SystemError("cannot open the temporary file", path);
      return false;
    }
    LargeVector<uint32_t> ids;
    const bool read = ReadBack(fd, 3 * this->PieceTriangles[p], &ids, path, why);
    ::close(fd);
    if (!read)
    {
      return false;
    }
    ::unlink(path.c_str());
    if (ids.size() >= (size_t(1) << 32))
    {
      *why = "piece " + std::to_string(p) + " has more than 2^32 corners";
      return false;
    }
    // the points the piece uses, in the order of their index in the file, and each corner's
    // index among them
    LargeVector<uint32_t> used;
    LargeVector<int64_t> triangles(ids.size());
    NumberUsedPoints(ids, &used, &triangles);
    const bool hasNormals = this->Agreed.HasNormals;
    LargeVector<double> points(3 * used.size()), normals(hasNormals ? 3 * used.size() : 0);
    for (size_t i = 0; i < used.size(); ++i)
    {
      this->Position(used[i], &points[3 * i]);
      if (hasNormals)
      {
        this->Normal(used[i], &normals[3 * i]);
      }
    }
    LargeVector<uint32_t>().swap(ids);
    LargeVector<uint32_t>().swap(used);
    partition::MergePoints(points, normals, triangles, this->Cells, this->Owner, p, r);
    return true;
  }

  bool KeepPiece(int p, const PartitionResult& r)
  {
    Appender file;
    const bool ok = file.Open(this->PieceFile(p, ".piece"), this->Why) &&
      file.Write(r.Points.data(), r.Points.size() * sizeof(double), this->Why) &&
      file.Write(r.Normals.data(), r.Normals.size() * sizeof(double), this->Why) &&
      file.Write(r.Ghost.data(), r.Ghost.size(), this->Why) &&
      file.Write(r.Triangles.data(), r.Triangles.size() * sizeof(int64_t), this->Why);
    const bool closed = file.Close(this->Why);
    this->AddTemporary(file.Size());
    return ok && closed;
  }
};

//------------------------------------------------------------------------------
PLYPieces::PLYPieces()
  : Internal(new Internals)
{
}

//------------------------------------------------------------------------------
PLYPieces::~PLYPieces() = default;

//------------------------------------------------------------------------------
bool PLYPieces::Open(const std::string& path, const PiecesParameters& parameters, std::string* why)
{
  this->Internal.reset(new Internals);
  Internals& s = *this->Internal;
  s.Params = parameters;
  std::string message;
  s.Why = &message;
  bool ok = false;
  try
  {
    if (parameters.OwnershipLevel < 1 || parameters.OwnershipLevel > 6)
    {
      ok = s.Fail(
        "the ownership level must be in [1, 6], not " + std::to_string(parameters.OwnershipLevel));
    }
    else if (parameters.NumberOfPieces <= 0 && !(parameters.MemoryLimit > 0))
    {
      ok = s.Fail("a memory limit above 0 is needed to size the pieces");
    }
    else
    {
      ok = s.MakeDirectory() && s.SplitFile(path) && s.PlaceRootCube() &&
        (s.Agreed.NoTriangles || (s.ShareOutCells() && s.Distribute() && s.MergePieces()));
    }
  }
  catch (const std::bad_alloc&)
  {
    ok = s.Fail("out of memory while splitting the file into pieces");
  }
  if (s.Agreed.NoTriangles && ok)
  {
    s.Agreed.FinestLevel = std::max(0, parameters.RequestedFinestLevel);
  }
  s.Agreed.Ok = ok;
  s.Agreed.Error = ok ? std::string() : message;
  if (why)
  {
    *why = s.Agreed.Error;
  }
  if (!ok)
  {
    s.RemoveDirectory();
    s.Pieces = 0;
  }
  else if (!s.Agreed.NoTriangles && s.Agreed.FinestLevel >= 1 &&
    s.Agreed.FinestLevel < parameters.OwnershipLevel)
  {
    // a model whose finest level is coarser than the cells shared out: split again at that
    // level, so that every piece's cells are levels of its octree
    PiecesParameters coarser = parameters;
    coarser.OwnershipLevel = s.Agreed.FinestLevel;
    return this->Open(path, coarser, why);
  }
  return ok;
}

//------------------------------------------------------------------------------
int PLYPieces::GetNumberOfPieces() const
{
  return this->Internal->Agreed.NoTriangles ? 0 : this->Internal->Pieces;
}

//------------------------------------------------------------------------------
int PLYPieces::GetOwnershipLevel() const
{
  return this->Internal->Params.OwnershipLevel;
}

//------------------------------------------------------------------------------
const PartitionResult& PLYPieces::GetAgreement() const
{
  return this->Internal->Agreed;
}

//------------------------------------------------------------------------------
bool PLYPieces::GetPiece(int p, PartitionResult* piece, std::string* why) const
{
  const Internals& s = *this->Internal;
  *piece = PartitionResult();
  std::string message;
  if (p < 0 || p >= this->GetNumberOfPieces())
  {
    message = "no piece " + std::to_string(p) + " (the file has " +
      std::to_string(this->GetNumberOfPieces()) + ")";
  }
  else if (s.Removed[p])
  {
    message = "piece " + std::to_string(p) + " was removed";
  }
  else
  {
    const std::string path = s.PieceFile(p, ".piece");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    const int64_t points = s.PiecePoints[p];
    const int64_t triangles = s.PieceTriangles[p];
    const bool ok = fd >= 0 && ReadBack(fd, 3 * points, &piece->Points, path, &message) &&
      ReadBack(fd, s.Agreed.HasNormals ? 3 * points : 0, &piece->Normals, path, &message) &&
      ReadBack(fd, points, &piece->Ghost, path, &message) &&
      ReadBack(fd, 3 * triangles, &piece->Triangles, path, &message);
    if (fd < 0)
    {
      message = SystemError("cannot open the temporary file", path);
    }
    else
    {
      ::close(fd);
    }
    if (ok)
    {
      std::copy(s.Agreed.RootOrigin, s.Agreed.RootOrigin + 3, piece->RootOrigin);
      piece->RootEdge = s.Agreed.RootEdge;
      piece->FinestLevel = s.Agreed.FinestLevel;
      piece->HasNormals = s.Agreed.HasNormals;
      piece->NumberOfBoundaryEdges = s.Agreed.NumberOfBoundaryEdges;
      piece->NumberOfOwnedCells = s.PieceOwnedCells[p];
      piece->NumberOfHaloTriangles = s.PieceHalo[p];
      piece->Ok = true;
      return true;
    }
    *piece = PartitionResult();
  }
  piece->Error = message;
  if (why)
  {
    *why = message;
  }
  return false;
}

//------------------------------------------------------------------------------
int64_t PLYPieces::GetNumberOfUsableTriangles() const
{
  const Internals& s = *this->Internal;
  return s.Agreed.Ok ? s.NumberOfTriangles - s.Agreed.NumberOfSkippedTriangles : 0;
}

//------------------------------------------------------------------------------
int64_t PLYPieces::GetPeakTemporaryBytes() const
{
  return this->Internal->PeakTemporaryBytes;
}

//------------------------------------------------------------------------------
int64_t PLYPieces::GetTemporaryBytes() const
{
  return this->Internal->TemporaryBytes;
}

//------------------------------------------------------------------------------
void PLYPieces::RemovePiece(int p)
{
  Internals& s = *this->Internal;
  if (p >= 0 && p < this->GetNumberOfPieces() && !s.Removed[p])
  {
    s.RemoveFile(s.PieceFile(p, ".piece"));
    s.Removed[p] = 1;
  }
}

//------------------------------------------------------------------------------
const std::string& PLYPieces::GetTemporaryDirectory() const
{
  return this->Internal->Directory;
}

} // namespace plod
