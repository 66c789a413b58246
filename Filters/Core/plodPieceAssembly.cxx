// SPDX-License-Identifier: BSD-3-Clause
// An octree file from the pieces of a PLY file. See plodPieceAssembly.h.
#include "plodPieceAssembly.h"
#include "plodOctree.h"
#include "plodOctreeFile.h"
#include "plodOctreeStorage.h"
#include "plodTemporaryFile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <sys/stat.h>
#include <unistd.h>

namespace plod
{
namespace
{
using tempfile::Appender;
using tempfile::SystemError;

/// The octree's required arrays, in file order.
enum Member : int
{
#define PLOD_MEMBER_ENUM(member, group, type, comps, meaning) M##member,
  PLOD_OCTREE_ARRAYS(PLOD_MEMBER_ENUM)
#undef PLOD_MEMBER_ENUM
    MemberCount
};

/// How the values of a part of an output array are made from what it holds.
enum class Shift
{
  None,             ///< as they are
  Base,             ///< plus the part's base
  BaseKeepNegative, ///< plus the part's base, -1 kept
  Corners,          ///< packed (level-k cell, index in the cell) made point indices
  Fill              ///< the part's base, repeated
};

/// A part of an output array: values in memory (in the output type), or in a temporary file.
struct Part
{
  std::vector<char> Memory;
  std::string File;
  int64_t Values = 0;
  Shift How = Shift::None;
  int64_t Base = 0;
};

/// A packed corner: the Morton index of its level-k cell, and its index among the cell's points.
inline uint64_t PackCorner(uint64_t cell, int64_t index)
{
  return cell << 32 | uint64_t(index);
}

/// A triangle owned by a node above level k, kept for the file's first triangles: its owner
/// (level and cell), its corners packed as points and as level-k clusters (PackCorner).
struct StructureTriangle
{
  int Level;
  uint64_t Cell;
  std::array<uint64_t, 3> Corners;
  std::array<uint64_t, 3> Clusters;
};

class Assembler
{
public:
  Assembler(PLYPieces& pieces, const AssemblyParameters& params, std::string* why)
    : Pieces(pieces)
    , Params(params)
    , Why(why)
    , K(pieces.GetOwnershipLevel())
    , L(pieces.GetAgreement().FinestLevel)
    , Agreed(pieces.GetAgreement())
  {
  }

  ~Assembler()
  {
    for (const std::string& f : this->Files)
    {
      ::unlink(f.c_str());
    }
  }

  bool Run(const std::string& path, AssemblyReport* report)
  {
    if (!this->Agreed.Ok || this->Pieces.GetNumberOfPieces() == 0)
    {
      return this->Fail("no pieces to build (the file has no usable triangle)");
    }
    if (this->L < this->K)
    {
      return this->Fail("the finest level " + std::to_string(this->L) +
        " is coarser than the ownership level " + std::to_string(this->K));
    }
    if (!this->OpenPartFiles())
    {
      return false;
    }
    for (int p = 0; p < this->Pieces.GetNumberOfPieces(); ++p)
    {
      if (!this->Report(double(p) / this->Pieces.GetNumberOfPieces(), "building the pieces") ||
        !this->BuildPiece(p))
      {
        return false;
      }
      this->NoteTemporaryBytes();
    }
    if (!this->ClosePartFiles() || !this->MakeStructure() || !this->WriteFile(path))
    {
      return false;
    }
    if (report)
    {
      *report = this->Made;
    }
    return true;
  }

private:
  bool Fail(const std::string& message)
  {
    *this->Why = message;
    return false;
  }

  bool Report(double fraction, const char* step)
  {
    return !this->Params.Progress || this->Params.Progress(std::min(1.0, fraction), step) ||
      this->Fail("aborted");
  }

  int Levels() const { return this->L - this->K + 1; }

  /// The temporary file of an array's part of level l (0 for the point arrays).
  std::string PartFile(int m, int l) const
  {
    return this->Pieces.GetTemporaryDirectory() + "/part-" + std::to_string(m) + "-" +
      std::to_string(l);
  }

  bool OpenPartFiles()
  {
    this->Out.resize(static_cast<size_t>(MemberCount) * this->Levels());
    for (int m = 0; m < MemberCount; ++m)
    {
      for (int l = 0; l < this->Levels(); ++l)
      {
        const std::string f = this->PartFile(m, l);
        this->Files.push_back(f);
        if (!this->Writer(m, l).Open(f, this->Why))
        {
          return false;
        }
      }
    }
    this->NodesBefore.assign(this->L + 2, 0);
    this->ClustersBefore.assign(this->L + 2, 0);
    this->TrianglesBefore.assign(this->L + 2, 0);
    return true;
  }

  Appender& Writer(int m, int l) { return this->Out[static_cast<size_t>(m) * this->Levels() + l]; }

  bool ClosePartFiles()
  {
    bool ok = true;
    for (Appender& a : this->Out)
    {
      ok = a.Close(this->Why) && ok;
    }
    this->NoteTemporaryBytes();
    return ok;
  }

  /// The most the pieces' files and the parts' have held at once, so far.
  void NoteTemporaryBytes()
  {
    int64_t bytes = this->Pieces.GetTemporaryBytes();
    for (const Appender& a : this->Out)
    {
      bytes += a.Size();
    }
    this->Made.PeakTemporaryBytes = std::max(this->Made.PeakTemporaryBytes, bytes);
  }

  template <typename Vector>
  bool Put(int m, int l, const Vector& values)
  {
    return this->Writer(m, l).Write(
      values.data(), values.size() * sizeof(typename Vector::value_type), this->Why);
  }

  /// Tuples [a, b) of a member of `v`, as they are.
  bool PutRaw(int m, int l, const FileArray& f, int64_t a, int64_t b)
  {
    const size_t tuple = size_t(FileTypeSize(f.Type)) * size_t(f.Components);
    return this->Writer(m, l).Write(
      static_cast<const char*>(f.Data) + tuple * size_t(a), tuple * size_t(b - a), this->Why);
  }

  /// Values [a, b) of an index array made by `convert`.
  template <typename T, typename Convert>
  bool PutConverted(int m, int l, int64_t a, int64_t b, Convert&& convert)
  {
    LargeVector<T> values(static_cast<size_t>(b - a));
    for (int64_t i = a; i < b; ++i)
    {
      values[i - a] = static_cast<T>(convert(i));
    }
    return this->Put(m, l, values);
  }

  // One piece: built, and the part of its octree it owns kept.
  bool BuildPiece(int p)
  {
    PartitionResult r;
    if (!this->Pieces.GetPiece(p, &r, this->Why))
    {
      return false;
    }
    if (this->Params.RemovePiecesAsBuilt)
    {
      this->Pieces.RemovePiece(p);
    }
    LargeVector<float> normals(r.Normals.begin(), r.Normals.end());
    LargeVector<double>().swap(r.Normals);
    BuildInput in;
    in.NumberOfPoints = static_cast<int64_t>(r.Ghost.size());
    in.Points = r.Points.data();
    in.NumberOfTriangles = static_cast<int64_t>(r.Triangles.size() / 3);
    in.Triangles = r.Triangles.data();
    in.PointNormals = normals.empty() ? nullptr : normals.data();
    in.PointGhost = r.Ghost.data();
    BuildParameters bp;
    bp.FinestLevel = this->L;
    bp.Rule = this->Params.Rule;
    // the pieces were sized to fit the limit (PieceBytesPerTriangle); the build's own estimate
    // counts a cluster per node and is larger than what it takes, so it checks against twice
    // the limit: a refusal here would only stop a build that fits
    bp.MemoryLimit = 2.0 * this->Params.MemoryLimit;
    bp.HasRootCube = true;
    std::copy(this->Agreed.RootOrigin, this->Agreed.RootOrigin + 3, bp.RootOrigin);
    bp.RootEdge = this->Agreed.RootEdge;
    OctreeStorage storage;
    const BuildResult built = BuildOctree(in, bp, storage.MakeAllocator(), this->Params.Parallel);
    if (!built.Ok)
    {
      return this->Fail("piece " + std::to_string(p) + ": " + built.Error);
    }
    r = PartitionResult(); // the piece's input is no longer needed
    const OctreeView v = storage.View(built);
    this->NonManifoldEdges += built.NumberOfNonManifoldEdges;
    this->MisorientedEdges += built.NumberOfMisorientedEdges;
    return this->FindOwned(v, p) && this->KeepOwned(v);
  }

  /// The nodes, clusters, points and triangles the piece owns, per level: each a contiguous
  /// range (the owned level-k cells are a Morton run).
  bool FindOwned(const OctreeView& v, int p)
  {
    this->LevelStart.assign(this->L + 2, v.NumberOfNodes);
    for (int64_t n = v.NumberOfNodes - 1; n >= 0; --n)
    {
      this->LevelStart[v.Level[n]] = n;
    }
    for (int l = this->L; l >= 0; --l)
    {
      this->LevelStart[l] = std::min(this->LevelStart[l], this->LevelStart[l + 1]);
    }
    this->A.assign(this->L + 2, 0);
    this->B.assign(this->L + 2, 0);
    for (int l = this->K; l <= this->L; ++l)
    {
      int64_t a = -1, b = -1;
      for (int64_t n = this->LevelStart[l]; n < this->LevelStart[l + 1]; ++n)
      {
        if (!v.PointGhost[v.FirstPoint[n]])
        {
          if (b >= 0 && b != n)
          {
            return this->Fail("piece " + std::to_string(p) + " owns cells of level " +
              std::to_string(l) + " that are not one run");
          }
          a = a < 0 ? n : a;
          b = n + 1;
        }
      }
      this->A[l] = a < 0 ? this->LevelStart[l] : a;
      this->B[l] = a < 0 ? this->LevelStart[l] : b;
    }
    this->PointsA = this->A[this->K] < this->B[this->K] ? v.FirstPoint[this->A[this->K]] : 0;
    this->PointsB = this->A[this->K] < this->B[this->K] ? v.PointEnd(this->B[this->K] - 1) : 0;
    // the Morton index of each level-k node's cell
    this->CellOfK.assign(this->LevelStart[this->K + 1] - this->LevelStart[this->K], 0);
    for (int64_t n = this->LevelStart[this->K]; n < this->LevelStart[this->K + 1]; ++n)
    {
      int xyz[3];
      v.CellCoordinates(n, xyz);
      this->CellOfK[n - this->LevelStart[this->K]] = MortonEncode(xyz[0], xyz[1], xyz[2]);
    }
    return true;
  }

  int64_t ClustersA(const OctreeView& v, int l) const
  {
    return this->A[l] < this->B[l] ? v.FirstCluster[this->A[l]] : 0;
  }
  int64_t ClustersB(const OctreeView& v, int l) const
  {
    return this->A[l] < this->B[l] ? v.ClusterEnd(this->B[l] - 1) : 0;
  }
  int64_t TrianglesA(const OctreeView& v, int l) const
  {
    return this->A[l] < this->B[l] ? v.FirstTriangle[this->A[l]] : 0;
  }
  int64_t TrianglesB(const OctreeView& v, int l) const
  {
    return this->A[l] < this->B[l] ? v.TriangleEnd(this->B[l] - 1) : 0;
  }

  /// A point as its level-k cell and its index among the cell's points.
  uint64_t Corner(const OctreeView& v, int64_t point) const
  {
    int64_t n = v.PointLeaf[point];
    while (v.Level[n] > this->K)
    {
      n = v.Parent[n];
    }
    return PackCorner(this->CellOfK[n - this->LevelStart[this->K]], point - v.FirstPoint[n]);
  }

  /// A point's cluster of level k as its level-k cell and its index among the cell's clusters.
  /// A structure triangle's corners lie in cells complete in the piece (plodPartition.h), so
  /// this is the cluster the piece owning the cell numbers the same way.
  uint64_t ClusterOfK(const OctreeView& v, int64_t point) const
  {
    int64_t c = v.PointCluster[point];
    while (v.Level[v.ClusterNode[c]] > this->K)
    {
      c = v.ClusterParent[c];
    }
    const int64_t n = v.ClusterNode[c];
    return PackCorner(this->CellOfK[n - this->LevelStart[this->K]], c - v.FirstCluster[n]);
  }

  bool KeepOwned(const OctreeView& v)
  {
    const std::vector<FileArray> arrays = FileArraysOf(v);
    for (int l = this->K; l <= this->L; ++l)
    {
      if (!this->KeepNodes(v, arrays, l) || !this->KeepClusters(v, arrays, l) ||
        !this->KeepTriangles(v, l))
      {
        return false;
      }
    }
    if (!this->KeepPoints(v, arrays) || !this->KeepStructureTriangles(v))
    {
      return false;
    }
    // the level-k cells in order, with their first point in the file
    for (int64_t n = this->A[this->K]; n < this->B[this->K]; ++n)
    {
      this->CellsK.push_back(this->CellOfK[n - this->LevelStart[this->K]]);
      this->CellsKFirstPoint.push_back(this->PointsBefore + v.FirstPoint[n] - this->PointsA);
      this->CellsKFirstCluster.push_back(
        this->ClustersBefore[this->K] + v.FirstCluster[n] - this->ClustersA(v, this->K));
    }
    for (int l = this->K; l <= this->L; ++l)
    {
      this->NodesBefore[l] += this->B[l] - this->A[l];
      this->ClustersBefore[l] += this->ClustersB(v, l) - this->ClustersA(v, l);
      this->TrianglesBefore[l] += this->TrianglesB(v, l) - this->TrianglesA(v, l);
    }
    this->PointsBefore += this->PointsB - this->PointsA;
    return true;
  }

  // Index arrays hold indices within their level (the level's start is added when the file is
  // written) and point indices in the file.
  bool KeepNodes(const OctreeView& v, const std::vector<FileArray>& arrays, int l)
  {
    const int64_t a = this->A[l], b = this->B[l];
    const int i = l - this->K;
    const int64_t ta = this->TrianglesA(v, l), ca = this->ClustersA(v, l);
    const int64_t childA = l < this->L ? this->A[l + 1] : 0;
    const int64_t parentA = l > this->K ? this->A[l - 1] : 0;
    for (int m = MLevel; m <= MFirstCluster; ++m)
    {
      bool ok = true;
      switch (m)
      {
        case MParent:
          // level k's parents are structure nodes, made when the file is written
          ok = l == this->K || this->PutConverted<int32_t>(m, i, a, b, [&](int64_t n) {
            return v.Parent[n] - parentA + this->NodesBefore[l - 1];
          });
          break;
        case MFirstChild:
          ok = this->PutConverted<int32_t>(m, i, a, b, [&](int64_t n) {
            return v.FirstChild[n] < 0 ? -1 : v.FirstChild[n] - childA + this->NodesBefore[l + 1];
          });
          break;
        case MFirstPoint:
          ok = this->PutConverted<int32_t>(m, i, a, b,
            [&](int64_t n) { return v.FirstPoint[n] - this->PointsA + this->PointsBefore; });
          break;
        case MFirstTriangle:
          ok = this->PutConverted<int64_t>(m, i, a, b,
            [&](int64_t n) { return v.FirstTriangle[n] - ta + this->TrianglesBefore[l]; });
          break;
        case MFirstCluster:
          ok = this->PutConverted<int32_t>(m, i, a, b,
            [&](int64_t n) { return v.FirstCluster[n] - ca + this->ClustersBefore[l]; });
          break;
        default:
          ok = this->PutRaw(m, i, arrays[m], a, b);
      }
      if (!ok)
      {
        return false;
      }
    }
    return true;
  }

  bool KeepClusters(const OctreeView& v, const std::vector<FileArray>& arrays, int l)
  {
    const int i = l - this->K;
    const int64_t ca = this->ClustersA(v, l), cb = this->ClustersB(v, l);
    const int64_t parentClustersA = l > this->K ? this->ClustersA(v, l - 1) : 0;
    auto nodeInLevel = [&](int64_t c) {
      return v.ClusterNode[c] - this->A[l] + this->NodesBefore[l];
    };
    return this->PutConverted<int32_t>(MClusterNode, i, ca, cb, nodeInLevel) &&
      // level k: the cluster's node (its parent cluster, a structure node's, is made later)
      this->PutConverted<int32_t>(MClusterParent, i, ca, cb,
        [&](int64_t c) {
          return l == this->K ? nodeInLevel(c)
                              : v.ClusterParent[c] - parentClustersA + this->ClustersBefore[l - 1];
        }) &&
      this->PutRaw(MClusterVertex, i, arrays[MClusterVertex], ca, cb) &&
      this->PutRaw(MClusterNormal, i, arrays[MClusterNormal], ca, cb);
  }

  bool KeepPoints(const OctreeView& v, const std::vector<FileArray>& arrays)
  {
    const int64_t pa = this->PointsA, pb = this->PointsB;
    const int fl = this->L;
    return this->PutRaw(MPoints, 0, arrays[MPoints], pa, pb) &&
      this->PutRaw(MNormals, 0, arrays[MNormals], pa, pb) &&
      this->PutConverted<int32_t>(MPointLeaf, 0, pa, pb,
        [&](int64_t q) { return v.PointLeaf[q] - this->A[fl] + this->NodesBefore[fl]; }) &&
      this->PutConverted<int32_t>(MPointCluster, 0, pa, pb, [&](int64_t q) {
        return v.PointCluster[q] - this->ClustersA(v, fl) + this->ClustersBefore[fl];
      });
  }

  bool KeepTriangles(const OctreeView& v, int l)
  {
    const int64_t ta = this->TrianglesA(v, l), tb = this->TrianglesB(v, l);
    std::vector<uint64_t> corners(static_cast<size_t>(3 * (tb - ta)));
    for (int64_t t = ta; t < tb; ++t)
    {
      for (int c = 0; c < 3; ++c)
      {
        corners[3 * (t - ta) + c] = this->Corner(v, v.Triangles[3 * t + c]);
      }
    }
    return this->Put(MTriangles, l - this->K, corners);
  }

  /// The triangles owned by the piece's nodes above level k whose lead corner (the lowest
  /// point index) it owns: each such triangle of the whole in exactly one piece.
  bool KeepStructureTriangles(const OctreeView& v)
  {
    for (int64_t n = 0; n < this->LevelStart[this->K]; ++n)
    {
      int xyz[3];
      v.CellCoordinates(n, xyz);
      const uint64_t cell = MortonEncode(xyz[0], xyz[1], xyz[2]);
      for (int64_t t = v.FirstTriangle[n]; t < v.TriangleEnd(n); ++t)
      {
        const int32_t* c = v.Triangles + 3 * t;
        if (!v.PointGhost[std::min({ c[0], c[1], c[2] })])
        {
          this->Structure.push_back({ v.Level[n], cell,
            { this->Corner(v, c[0]), this->Corner(v, c[1]), this->Corner(v, c[2]) },
            { this->ClusterOfK(v, c[0]), this->ClusterOfK(v, c[1]), this->ClusterOfK(v, c[2]) } });
        }
      }
    }
    return true;
  }

  // The levels above k: one node per occupied cell, in Morton order, with the data of the
  // octree of the level-k cut (BuildCoarseLevels).
  bool MakeStructure()
  {
    const int K = this->K;
    this->Cells.assign(K, {});
    for (int l = K - 1; l >= 0; --l)
    {
      const std::vector<uint64_t>& finer = l == K - 1 ? this->CellsK : this->Cells[l + 1];
      for (uint64_t c : finer)
      {
        if (this->Cells[l].empty() || this->Cells[l].back() != c >> 3)
        {
          this->Cells[l].push_back(c >> 3);
        }
      }
    }
    this->NodeStart.assign(this->L + 2, 0);
    for (int l = 0; l < K; ++l)
    {
      this->NodeStart[l + 1] = this->NodeStart[l] + static_cast<int64_t>(this->Cells[l].size());
    }
    this->TriangleStart.assign(this->L + 2, 0);
    // the structure's triangles, ordered by their owner
    std::vector<int64_t> owner(this->Structure.size());
    for (size_t t = 0; t < this->Structure.size(); ++t)
    {
      owner[t] = this->StructureNode(this->Structure[t].Level, this->Structure[t].Cell);
    }
    std::vector<size_t> order(this->Structure.size());
    for (size_t t = 0; t < order.size(); ++t)
    {
      order[t] = t;
    }
    std::stable_sort(
      order.begin(), order.end(), [&](size_t a, size_t b) { return owner[a] < owner[b]; });
    this->TriangleStart[K] = static_cast<int64_t>(this->Structure.size());
    for (int l = K; l <= this->L; ++l)
    {
      this->NodeStart[l + 1] = this->NodeStart[l] + this->NodesBefore[l];
      this->TriangleStart[l + 1] = this->TriangleStart[l] + this->TrianglesBefore[l];
    }
    // the first point and the first cluster of each level-k cell, by its Morton index
    this->CellFirstPoint.assign(size_t(1) << (3 * K), -1);
    this->CellFirstCluster.assign(size_t(1) << (3 * K), -1);
    for (size_t i = 0; i < this->CellsK.size(); ++i)
    {
      this->CellFirstPoint[this->CellsK[i]] = this->CellsKFirstPoint[i];
      this->CellFirstCluster[this->CellsK[i]] = this->CellsKFirstCluster[i];
    }
    if (!this->BuildCoarseLevels())
    {
      return false;
    }
    this->LayOutStructureClusters();
    const int64_t structure = this->NodeStart[K];
    this->Made.NumberOfNodes = this->NodeStart[this->L + 1];
    this->Made.NumberOfClusters = this->ClusterStart[this->L + 1];
    this->Made.NumberOfPoints = this->PointsBefore;
    this->Made.NumberOfTriangles = this->TriangleStart[this->L + 1];
    this->Made.FinestLevel = this->L;
    this->Made.CoarsestDrawnLevel = this->Made.StructureOnly.empty() ? 0 : K;
    this->Made.NumberOfStructureNodes = this->Made.StructureOnly.empty() ? 0 : structure;
    this->Made.NumberOfStructureTriangles = this->TriangleStart[K];
    for (int64_t count : { this->Made.NumberOfNodes, this->Made.NumberOfClusters,
           this->Made.NumberOfPoints, this->Made.NumberOfTriangles })
    {
      if (count > MaxIndex)
      {
        return this->Fail("the octree has more than 2^31 - 1 nodes, clusters, points or "
                          "triangles: too large for one octree file");
      }
    }
    return this->MakeStructureArrays(owner, order);
  }

  /// The index of the structure node of (level, cell).
  int64_t StructureNode(int level, uint64_t cell) const
  {
    const std::vector<uint64_t>& c = this->Cells[level];
    return this->NodeStart[level] + (std::lower_bound(c.begin(), c.end(), cell) - c.begin());
  }

  int64_t ResolveCorner(uint64_t packed) const
  {
    return this->CellFirstPoint[packed >> 32] + int64_t(packed & 0xffffffffu);
  }

  /// A packed level-k cluster (ClusterOfK) as its index among the clusters of level k.
  int64_t ResolveCluster(uint64_t packed) const
  {
    return this->CellFirstCluster[packed >> 32] + int64_t(packed & 0xffffffffu);
  }

  /// Tuples `rows` (sorted) of array m's part file of level k (the points' for a point array),
  /// `bytes` each, read block by block.
  bool PickTuples(int m, size_t bytes, const std::vector<int64_t>& rows, void* out)
  {
    const std::string path = this->PartFile(m, 0);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
    {
      return this->Fail(SystemError("cannot open the temporary file", path));
    }
    constexpr int64_t Block = 65536;
    std::vector<char> block(Block * bytes);
    int64_t loaded = -1;
    bool ok = true;
    for (size_t i = 0; i < rows.size() && ok; ++i)
    {
      const int64_t b = rows[i] / Block;
      if (b != loaded)
      {
        const ssize_t got = ::pread(fd, block.data(), block.size(), off_t(b * Block * bytes));
        ok = got >= ssize_t((rows[i] - b * Block + 1) * bytes) ||
          this->Fail(got < 0 ? SystemError("cannot read the temporary file", path)
                             : "the temporary file " + path + " is shorter than written");
        loaded = b;
      }
      if (ok)
      {
        std::memcpy(
          static_cast<char*>(out) + i * bytes, block.data() + (rows[i] - b * Block) * bytes, bytes);
      }
    }
    ::close(fd);
    return ok;
  }

  /**
   * The levels above k, built from the level-k cut: a mesh whose points are the level-k
   * clusters its triangles use (vertices, nudged into their cells, and normals) and whose
   * triangles are the structure triangles (those joining three level-k cells: every triangle
   * a cut above k can draw), built in memory with the agreed root cube and k as its finest
   * level. Its nodes above k give the structure nodes their vertices and clusters, the cluster
   * tree over level k, and cones, errors and flags (MakeStructureArrays). A build that fails
   * (no memory for it) leaves the levels above k as structure only, the reason in the report.
   */
  bool BuildCoarseLevels()
  {
    std::vector<int64_t>& used = this->CoarseClusters;
    for (const StructureTriangle& t : this->Structure)
    {
      for (uint64_t c : t.Clusters)
      {
        used.push_back(this->ResolveCluster(c));
      }
    }
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    if (used.empty())
    {
      return true; // no triangle is drawn above k: nothing to build
    }
    const size_t n = used.size();
    std::vector<float> vertex(3 * n), normal(3 * n);
    std::vector<int32_t> node(n);
    if (!this->PickTuples(MClusterVertex, 12, used, vertex.data()) ||
      !this->PickTuples(MClusterNormal, 12, used, normal.data()) ||
      !this->PickTuples(MClusterNode, 4, used, node.data()))
    {
      return false;
    }
    // each cluster's vertex inside its level-k cell, so that the build finds it there
    std::vector<double> points(3 * n);
    const double edge = this->Agreed.RootEdge / double(1u << this->K);
    for (size_t j = 0; j < n; ++j)
    {
      uint32_t xyz[3];
      MortonDecode(this->CellsK[node[j]], xyz);
      for (int a = 0; a < 3; ++a)
      {
        const double lo = edge * (xyz[a] + 1e-3), hi = edge * (xyz[a] + 1 - 1e-3);
        points[3 * j + a] =
          this->Agreed.RootOrigin[a] + std::min(hi, std::max(lo, double(vertex[3 * j + a])));
      }
    }
    std::vector<int64_t> triangles(3 * this->Structure.size());
    for (size_t t = 0; t < this->Structure.size(); ++t)
    {
      for (int c = 0; c < 3; ++c)
      {
        const int64_t g = this->ResolveCluster(this->Structure[t].Clusters[c]);
        triangles[3 * t + c] = std::lower_bound(used.begin(), used.end(), g) - used.begin();
      }
    }
    BuildInput in;
    in.NumberOfPoints = static_cast<int64_t>(n);
    in.Points = points.data();
    in.NumberOfTriangles = static_cast<int64_t>(this->Structure.size());
    in.Triangles = triangles.data();
    in.PointNormals = normal.data();
    BuildParameters bp;
    bp.FinestLevel = this->K;
    bp.Rule = this->Params.Rule;
    bp.MemoryLimit = 2.0 * this->Params.MemoryLimit; // as a piece's (BuildPiece)
    bp.HasRootCube = true;
    std::copy(this->Agreed.RootOrigin, this->Agreed.RootOrigin + 3, bp.RootOrigin);
    bp.RootEdge = this->Agreed.RootEdge;
    const BuildResult built =
      BuildOctree(in, bp, this->Coarse.MakeAllocator(), this->Params.Parallel);
    if (!built.Ok)
    {
      this->Made.StructureOnly = "the octree of the level-" + std::to_string(this->K) +
        " cut could not be built: " + built.Error;
      return true;
    }
    const OctreeView& cv = this->CoarseView = this->Coarse.View(built);
    this->CoarsePointOf.assign(n, -1);
    for (int64_t i = 0; i < cv.NumberOfPoints; ++i)
    {
      this->CoarsePointOf[cv.InputPointId[i]] = i;
    }
    // the structure node of each of its nodes above k, and the other way
    this->CoarseNodeOf.assign(this->NodeStart[this->K], -1);
    this->StructureOfCoarse.assign(cv.NumberOfNodes, -1);
    for (int64_t c = 0; c < cv.NumberOfNodes && cv.Level[c] < this->K; ++c)
    {
      int xyz[3];
      cv.CellCoordinates(c, xyz);
      const uint64_t cell = MortonEncode(xyz[0], xyz[1], xyz[2]);
      const int64_t s = this->StructureNode(cv.Level[c], cell);
      const std::vector<uint64_t>& cells = this->Cells[cv.Level[c]];
      if (s >= this->NodeStart[cv.Level[c] + 1] || cells[s - this->NodeStart[cv.Level[c]]] != cell)
      {
        return this->Fail("the octree of the level-" + std::to_string(this->K) +
          " cut has a cell the pieces do not");
      }
      this->CoarseNodeOf[s] = c;
      this->StructureOfCoarse[c] = s;
    }
    this->HasCoarse = true;
    return true;
  }

  /// The structure's clusters: those of the coarse octree's node of each cell, one where it
  /// has none; then each level's first cluster.
  void LayOutStructureClusters()
  {
    const int64_t structure = this->NodeStart[this->K];
    this->StructureFirstCluster.assign(structure + 1, 0);
    for (int64_t s = 0; s < structure; ++s)
    {
      const int64_t c = this->CoarseNode(s);
      this->StructureFirstCluster[s + 1] = this->StructureFirstCluster[s] +
        (c < 0 ? 1 : this->CoarseView.ClusterEnd(c) - this->CoarseView.FirstCluster[c]);
    }
    this->ClusterStart.assign(this->L + 2, 0);
    for (int l = 0; l <= this->K; ++l)
    {
      this->ClusterStart[l] = this->StructureFirstCluster[this->NodeStart[l]];
    }
    for (int l = this->K; l <= this->L; ++l)
    {
      this->ClusterStart[l + 1] = this->ClusterStart[l] + this->ClustersBefore[l];
    }
  }

  /// The coarse octree's node of structure node s; -1 if it has none.
  int64_t CoarseNode(int64_t s) const { return this->HasCoarse ? this->CoarseNodeOf[s] : -1; }

  /// A cluster of the coarse octree (above k) as its index in the file.
  int64_t CoarseClusterInFile(int64_t c) const
  {
    const OctreeView& cv = this->CoarseView;
    const int64_t node = cv.ClusterNode[c];
    return this->StructureFirstCluster[this->StructureOfCoarse[node]] + c - cv.FirstCluster[node];
  }

  /// The parent (a cluster of level k - 1) of cluster `g` of level k, in the file, whose cell
  /// is `cell`: the coarse octree's, or the first cluster of the parent cell's node.
  int64_t ParentOfClusterK(int64_t g, uint64_t cell) const
  {
    const std::vector<int64_t>& used = this->CoarseClusters;
    const auto it = std::lower_bound(used.begin(), used.end(), g);
    if (this->HasCoarse && it != used.end() && *it == g)
    {
      const int64_t p = this->CoarsePointOf[it - used.begin()];
      if (p >= 0)
      {
        return this->CoarseClusterInFile(
          this->CoarseView.ClusterParent[this->CoarseView.PointCluster[p]]);
      }
    }
    return this->StructureFirstCluster[this->StructureNode(this->K - 1, cell >> 3)];
  }

  template <typename T>
  static Part MemoryPart(const std::vector<T>& values)
  {
    Part part;
    part.Values = static_cast<int64_t>(values.size());
    part.Memory.resize(values.size() * sizeof(T));
    if (!values.empty())
    {
      std::memcpy(part.Memory.data(), values.data(), part.Memory.size());
    }
    return part;
  }

  /// What a node's parent takes from it: its cone and flags, and the largest shape error of
  /// level k inside it.
  struct ChildData
  {
    float Axis[3];
    float Angle;
    float ErrorK;
    uint8_t Flags;
  };

  /// The ChildData of level k's nodes, from their part files.
  bool ReadLevelKChildData(std::vector<ChildData>* out)
  {
    const int64_t nodes = this->NodesBefore[this->K];
    std::vector<float> axis, angle, error;
    std::vector<uint8_t> flags;
    if (!this->ReadPart(this->PartFile(MConeAxis, 0), 3 * nodes, &axis) ||
      !this->ReadPart(this->PartFile(MConeAngle, 0), nodes, &angle) ||
      !this->ReadPart(this->PartFile(MShapeError, 0), nodes, &error) ||
      !this->ReadPart(this->PartFile(MFlags, 0), nodes, &flags))
    {
      return false;
    }
    out->resize(static_cast<size_t>(nodes));
    for (int64_t n = 0; n < nodes; ++n)
    {
      ChildData& d = (*out)[n];
      std::copy(&axis[3 * n], &axis[3 * n] + 3, d.Axis);
      d.Angle = angle[n];
      d.ErrorK = error[n];
      d.Flags = flags[n];
    }
    return true;
  }

  bool MakeStructureArrays(const std::vector<int64_t>& owner, const std::vector<size_t>& order)
  {
    const int K = this->K;
    const int64_t structure = this->NodeStart[K];
    std::vector<uint8_t> level(structure), mask(structure, 0), flags(structure, 0);
    std::vector<int32_t> parent(structure), firstChild(structure), firstPoint(structure),
      firstCluster(structure);
    std::vector<int64_t> firstTriangle(structure, 0);
    // a build in pieces has no materials (a PLY file's pieces carry none): every cell's ranges
    // are the builder's uniform reflectances, as the pieces' cells are
    std::vector<float> vertex(3 * structure), axis(3 * structure), angle(structure, float(M_PI)),
      error(structure), thickness(structure), diffuse(2 * structure, BuildInput().UniformDiffuse),
      specular(2 * structure, BuildInput().UniformSpecular);
    std::vector<int64_t> owned(structure + 1, 0);
    for (int64_t o : owner)
    {
      ++owned[o + 1];
    }
    // the tree, points and owned triangles, top-down
    for (int l = 0; l < K; ++l)
    {
      const std::vector<uint64_t>& finer = l + 1 < K ? this->Cells[l + 1] : this->CellsK;
      size_t child = 0;
      for (size_t i = 0; i < this->Cells[l].size(); ++i)
      {
        const int64_t n = this->NodeStart[l] + static_cast<int64_t>(i);
        const uint64_t c = this->Cells[l][i];
        level[n] = static_cast<uint8_t>(l);
        parent[n] = l == 0 ? -1 : static_cast<int32_t>(this->StructureNode(l - 1, c >> 3));
        while (child < finer.size() && (finer[child] >> 3) < c)
        {
          ++child;
        }
        firstChild[n] = static_cast<int32_t>(this->NodeStart[l + 1] + int64_t(child));
        for (size_t k = child; k < finer.size() && (finer[k] >> 3) == c; ++k)
        {
          mask[n] |= uint8_t(1u << (finer[k] & 7));
        }
        // the first point: that of the first level-k cell inside
        const uint64_t kCell = c << (3 * (K - l));
        const auto it = std::lower_bound(this->CellsK.begin(), this->CellsK.end(), kCell);
        firstPoint[n] = static_cast<int32_t>(this->CellsKFirstPoint[it - this->CellsK.begin()]);
        firstCluster[n] = static_cast<int32_t>(this->StructureFirstCluster[n]);
        firstTriangle[n] = owned[n];
        owned[n + 1] += owned[n];
      }
    }
    // the cells' data, bottom-up: the coarse octree's where it has the cell, and what the
    // children bound
    std::vector<ChildData> kData, data(structure);
    std::vector<int64_t> rows; // the first points of the cells the coarse octree lacks
    for (int64_t n = 0; n < structure; ++n)
    {
      if (this->CoarseNode(n) < 0)
      {
        rows.push_back(firstPoint[n]);
      }
    }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    std::vector<float> rowPoints(3 * rows.size()), rowNormals(3 * rows.size());
    if (!this->ReadLevelKChildData(&kData) ||
      !this->PickTuples(MPoints, 12, rows, rowPoints.data()) ||
      !this->PickTuples(MNormals, 12, rows, rowNormals.data()))
    {
      return false;
    }
    const OctreeView& cv = this->CoarseView;
    for (int64_t n = structure - 1; n >= 0; --n)
    {
      const int64_t c = this->CoarseNode(n);
      if (c >= 0)
      {
        std::copy(&cv.Vertex[3 * c], &cv.Vertex[3 * c] + 3, &vertex[3 * n]);
        std::copy(&cv.ConeAxis[3 * c], &cv.ConeAxis[3 * c] + 3, &axis[3 * n]);
        angle[n] = cv.ConeAngle[c];
      }
      else
      {
        // a point of the surface inside the cell, with its normal: where a corner goes when
        // the frustum culls the cell (its triangles leave the view towards the surface)
        const size_t r = std::lower_bound(rows.begin(), rows.end(), firstPoint[n]) - rows.begin();
        std::copy(&rowPoints[3 * r], &rowPoints[3 * r] + 3, &vertex[3 * n]);
        std::copy(&rowNormals[3 * r], &rowNormals[3 * r] + 3, &axis[3 * n]);
      }
      float errorK = 0;
      uint8_t boundary = 0;
      for (int i = 0; i < 8; ++i)
      {
        if (!(mask[n] >> i & 1))
        {
          continue;
        }
        const int64_t ch = firstChild[n] + __builtin_popcount(mask[n] & ((1u << i) - 1));
        const ChildData& d = ch >= structure ? kData[ch - structure] : data[ch];
        const double dot = double(axis[3 * n]) * d.Axis[0] + double(axis[3 * n + 1]) * d.Axis[1] +
          double(axis[3 * n + 2]) * d.Axis[2];
        angle[n] = std::max(
          angle[n], float(std::acos(std::min(1.0, std::max(-1.0, dot))) + double(d.Angle)));
        errorK = std::max(errorK, d.ErrorK);
        boundary |= d.Flags & NodeBoundary;
      }
      angle[n] = std::min(angle[n], float(M_PI));
      const double diagonal = this->Agreed.RootEdge / double(1u << level[n]) * std::sqrt(3.0);
      error[n] = c >= 0 ? cv.ShapeError[c] + errorK : float(diagonal);
      thickness[n] = c >= 0 ? cv.Thickness[c] : float(diagonal);
      flags[n] = static_cast<uint8_t>((c >= 0 ? cv.Flags[c] & NodeTopologySafe : 0) | boundary);
      ChildData& mine = data[n];
      std::copy(&axis[3 * n], &axis[3 * n] + 3, mine.Axis);
      mine.Angle = angle[n];
      mine.ErrorK = errorK;
      mine.Flags = flags[n];
    }
    // the structure's clusters: the coarse octree's, or one per cell at its node's vertex
    const int64_t clusters = this->StructureFirstCluster[structure];
    std::vector<int32_t> clusterNode(clusters), clusterParent(clusters);
    std::vector<float> clusterVertex(3 * clusters), clusterNormal(3 * clusters);
    for (int64_t n = 0; n < structure; ++n)
    {
      const int64_t c = this->CoarseNode(n);
      const int64_t first = this->StructureFirstCluster[n];
      const int64_t count = this->StructureFirstCluster[n + 1] - first;
      for (int64_t i = 0; i < count; ++i)
      {
        const int64_t at = first + i;
        clusterNode[at] = static_cast<int32_t>(n);
        const float* v = c >= 0 ? &cv.ClusterVertex[3 * (cv.FirstCluster[c] + i)] : &vertex[3 * n];
        const float* m = c >= 0 ? &cv.ClusterNormal[3 * (cv.FirstCluster[c] + i)] : &axis[3 * n];
        std::copy(v, v + 3, &clusterVertex[3 * at]);
        std::copy(m, m + 3, &clusterNormal[3 * at]);
        clusterParent[at] = static_cast<int32_t>(level[n] == 0 ? -1
            : c >= 0 ? this->CoarseClusterInFile(cv.ClusterParent[cv.FirstCluster[c] + i])
                     : this->StructureFirstCluster[parent[n]]);
      }
    }
    auto nodePart = [&](int m) -> Part {
      switch (m)
      {
        case MLevel:
          return MemoryPart(level);
        case MParent:
          return MemoryPart(parent);
        case MFirstChild:
          return MemoryPart(firstChild);
        case MChildMask:
          return MemoryPart(mask);
        case MVertex:
          return MemoryPart(vertex);
        case MConeAxis:
          return MemoryPart(axis);
        case MConeAngle:
          return MemoryPart(angle);
        case MShapeError:
          return MemoryPart(error);
        case MDiffuseRange:
          return MemoryPart(diffuse);
        case MSpecularRange:
          return MemoryPart(specular);
        case MFlags:
          return MemoryPart(flags);
        case MThickness:
          return MemoryPart(thickness);
        case MFirstPoint:
          return MemoryPart(firstPoint);
        case MFirstTriangle:
          return MemoryPart(firstTriangle);
        default:
          return MemoryPart(firstCluster);
      }
    };
    this->Parts.assign(MemberCount, {});
    for (int m = MLevel; m <= MFirstCluster; ++m)
    {
      this->Parts[m].push_back(nodePart(m));
    }
    this->Parts[MClusterNode].push_back(MemoryPart(clusterNode));
    this->Parts[MClusterParent].push_back(MemoryPart(clusterParent));
    this->Parts[MClusterVertex].push_back(MemoryPart(clusterVertex));
    this->Parts[MClusterNormal].push_back(MemoryPart(clusterNormal));
    // structure triangles
    std::vector<int32_t> triangles(3 * order.size());
    for (size_t t = 0; t < order.size(); ++t)
    {
      for (int c = 0; c < 3; ++c)
      {
        triangles[3 * t + c] =
          static_cast<int32_t>(this->ResolveCorner(this->Structure[order[t]].Corners[c]));
      }
    }
    this->Parts[MTriangles].push_back(MemoryPart(triangles));
    return true;
  }

  /// The parts of each array beyond the structure: the levels' files.
  bool AddLevelParts()
  {
    const int K = this->K;
    for (int l = K; l <= this->L; ++l)
    {
      const int i = l - K;
      auto file = [&](int m, Shift how, int64_t base, int64_t values) {
        Part part;
        part.File = this->PartFile(m, i);
        part.How = how;
        part.Base = base;
        part.Values = values;
        this->Parts[m].push_back(std::move(part));
      };
      const int64_t nodes = this->NodesBefore[l], clusters = this->ClustersBefore[l];
      for (int m = MLevel; m <= MFirstCluster; ++m)
      {
        const int comps = OctreeFileSchema()[m].Components;
        if (m == MParent && l == K)
        {
          // level k's parents: the structure nodes of their cells' parents
          std::vector<int32_t> parent;
          for (uint64_t c : this->CellsK)
          {
            parent.push_back(static_cast<int32_t>(this->StructureNode(K - 1, c >> 3)));
          }
          this->Parts[m].push_back(MemoryPart(parent));
          continue;
        }
        const Shift how = m == MParent                ? Shift::Base
          : m == MFirstChild                          ? Shift::BaseKeepNegative
          : m == MFirstTriangle || m == MFirstCluster ? Shift::Base
                                                      : Shift::None;
        const int64_t base = m == MParent ? this->NodeStart[l - 1]
          : m == MFirstChild              ? this->NodeStart[l + 1]
          : m == MFirstTriangle           ? this->TriangleStart[l]
          : m == MFirstCluster            ? this->ClusterStart[l]
                                          : 0;
        file(m, how, base, nodes * comps);
      }
      file(MClusterNode, Shift::Base, this->NodeStart[l], clusters);
      if (l == K)
      {
        // level k's clusters: their parents in the coarse octree (ParentOfClusterK)
        std::vector<int32_t> nodeInLevel, parent;
        if (!this->ReadPart(this->PartFile(MClusterParent, 0), clusters, &nodeInLevel))
        {
          return false;
        }
        for (size_t g = 0; g < nodeInLevel.size(); ++g)
        {
          parent.push_back(
            static_cast<int32_t>(this->ParentOfClusterK(int64_t(g), this->CellsK[nodeInLevel[g]])));
        }
        this->Parts[MClusterParent].push_back(MemoryPart(parent));
      }
      else
      {
        file(MClusterParent, Shift::Base, this->ClusterStart[l - 1], clusters);
      }
      file(MClusterVertex, Shift::None, 0, 3 * clusters);
      file(MClusterNormal, Shift::None, 0, 3 * clusters);
      file(MTriangles, Shift::Corners, 0, 3 * this->TrianglesBefore[l]);
    }
    const int64_t points = this->PointsBefore;
    auto pointFile = [&](int m, Shift how, int64_t base, int64_t values) {
      Part part;
      part.File = this->PartFile(m, 0);
      part.How = how;
      part.Base = base;
      part.Values = values;
      this->Parts[m].push_back(std::move(part));
    };
    pointFile(MPoints, Shift::None, 0, 3 * points);
    pointFile(MNormals, Shift::None, 0, 3 * points);
    pointFile(MPointLeaf, Shift::Base, this->NodeStart[this->L], points);
    pointFile(MPointCluster, Shift::Base, this->ClusterStart[this->L], points);
    Part ids; // the pieces renumber the points: no input ids
    ids.How = Shift::Fill;
    ids.Base = -1;
    ids.Values = points;
    this->Parts[MInputPointId].push_back(std::move(ids));
    return true;
  }

  template <typename T>
  bool ReadPart(const std::string& path, int64_t count, std::vector<T>* out)
  {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
    {
      return this->Fail(SystemError("cannot open the temporary file", path));
    }
    const bool ok = tempfile::ReadBack(fd, count, out, path, this->Why);
    ::close(fd);
    return ok;
  }

  /// Values [first, first + count) of array m into `out` (its type).
  bool Values(int m, int64_t first, int64_t count, void* out, std::string* why) const
  {
    const ArraySpec& spec = OctreeFileSchema()[m];
    const int size = FileTypeSize(spec.Type);
    char* o = static_cast<char*>(out);
    int64_t at = 0;
    for (const Part& part : this->Parts[m])
    {
      const int64_t lo = std::max(first, at), hi = std::min(first + count, at + part.Values);
      if (lo < hi && !this->PartValues(part, size, lo - at, hi - lo, o + (lo - first) * size, why))
      {
        return false;
      }
      at += part.Values;
    }
    return true;
  }

  bool PartValues(
    const Part& part, int size, int64_t first, int64_t n, char* out, std::string* why) const
  {
    if (part.How == Shift::Fill)
    {
      for (int64_t i = 0; i < n; ++i)
      {
        const int64_t v = part.Base;
        std::memcpy(out + i * size, &v, size); // int64 arrays only
      }
      return true;
    }
    if (part.File.empty())
    {
      std::memcpy(out, part.Memory.data() + first * size, static_cast<size_t>(n * size));
      return true;
    }
    const int stored = part.How == Shift::Corners ? 8 : size;
    std::vector<char> buffer(static_cast<size_t>(n * stored));
    const int fd = ::open(part.File.c_str(), O_RDONLY | O_CLOEXEC);
    ssize_t got = -1;
    if (fd >= 0)
    {
      got = ::pread(fd, buffer.data(), buffer.size(), static_cast<off_t>(first * stored));
      ::close(fd);
    }
    if (got != static_cast<ssize_t>(buffer.size()))
    {
      *why = got < 0 ? SystemError("cannot read the temporary file", part.File)
                     : "the temporary file " + part.File + " is shorter than written";
      return false;
    }
    for (int64_t i = 0; i < n; ++i)
    {
      const char* in = buffer.data() + i * stored;
      if (part.How == Shift::Corners)
      {
        uint64_t packed;
        std::memcpy(&packed, in, 8);
        const int32_t point = static_cast<int32_t>(this->ResolveCorner(packed));
        std::memcpy(out + i * size, &point, 4);
      }
      else if (part.How == Shift::None)
      {
        std::memcpy(out + i * size, in, size);
      }
      else if (size == 8)
      {
        int64_t v;
        std::memcpy(&v, in, 8);
        v += part.Base;
        std::memcpy(out + i * size, &v, 8);
      }
      else
      {
        int32_t v;
        std::memcpy(&v, in, 4);
        v =
          (part.How == Shift::BaseKeepNegative && v < 0) ? v : static_cast<int32_t>(v + part.Base);
        std::memcpy(out + i * size, &v, 4);
      }
    }
    return true;
  }

  bool WriteFile(const std::string& path)
  {
    if (!this->AddLevelParts() || !this->Report(0, "writing the file"))
    {
      return false;
    }
    OctreeFileHeader header;
    std::copy(this->Agreed.RootOrigin, this->Agreed.RootOrigin + 3, header.Origin);
    header.RootEdge = this->Agreed.RootEdge;
    header.FinestLevel = this->L;
    header.CoarsestDrawnLevel = this->Made.CoarsestDrawnLevel;
    header.Nodes = this->Made.NumberOfNodes;
    header.Points = this->Made.NumberOfPoints;
    header.Triangles = this->Made.NumberOfTriangles;
    header.Clusters = this->Made.NumberOfClusters;
    header.BoundaryEdges = this->Agreed.NumberOfBoundaryEdges;
    header.NonManifoldEdges = this->NonManifoldEdges;
    header.MisorientedEdges = this->MisorientedEdges;
    std::vector<FileArray> arrays;
    const std::vector<ArraySpec>& schema = OctreeFileSchema();
    for (int m = 0; m < MemberCount; ++m)
    {
      FileArray f;
      f.Name = schema[m].Name;
      f.Group = schema[m].Group;
      f.Type = schema[m].Type;
      f.Components = schema[m].Components;
      f.Tuples = f.Group == ArrayGroup::Node ? header.Nodes
        : f.Group == ArrayGroup::Cluster     ? header.Clusters
        : f.Group == ArrayGroup::Point       ? header.Points
                                             : header.Triangles;
      f.Values = [this, m](int64_t first, int64_t count, void* out, std::string* why) {
        return this->Values(m, first, count, out, why);
      };
      arrays.push_back(std::move(f));
    }
    FileWriteOptions options;
    options.Layout = this->Params.Layout;
    options.Parallel = this->Params.Parallel;
    if (!WriteOctreeFile(path, header, arrays, options, this->Why))
    {
      return false;
    }
    struct stat st;
    this->Made.FileBytes = ::stat(path.c_str(), &st) == 0 ? int64_t(st.st_size) : 0;
    return this->Report(1, "writing the file");
  }

  PLYPieces& Pieces;
  const AssemblyParameters& Params;
  std::string* Why;
  const int K;
  const int L;
  const PartitionResult& Agreed;
  AssemblyReport Made;
  std::vector<std::string> Files;
  std::vector<Appender> Out;
  // per level: what the pieces before have put in
  std::vector<int64_t> NodesBefore, ClustersBefore, TrianglesBefore;
  int64_t PointsBefore = 0;
  int64_t NonManifoldEdges = 0, MisorientedEdges = 0;
  // the piece being kept: each level's first node, its owned nodes [A, B), its owned points
  std::vector<int64_t> LevelStart, A, B;
  int64_t PointsA = 0, PointsB = 0;
  std::vector<uint64_t> CellOfK;
  // the whole
  std::vector<uint64_t> CellsK;
  std::vector<int64_t> CellsKFirstPoint, CellsKFirstCluster;
  std::vector<StructureTriangle> Structure;
  std::vector<std::vector<uint64_t>> Cells; // the structure's cells per level
  std::vector<int64_t> NodeStart, ClusterStart, TriangleStart, CellFirstPoint, CellFirstCluster;
  // the levels above k: the coarse octree (BuildCoarseLevels), the level-k clusters its points
  // stand for (sorted) and its point of each (-1: dropped), its node of each structure node and
  // the other way (-1: none), and each structure node's first cluster in the file
  OctreeStorage Coarse;
  OctreeView CoarseView;
  bool HasCoarse = false;
  std::vector<int64_t> CoarseClusters, CoarsePointOf, CoarseNodeOf, StructureOfCoarse,
    StructureFirstCluster;
  std::vector<std::vector<Part>> Parts;
};

} // namespace

//------------------------------------------------------------------------------
bool WriteOctreeFileFromPieces(PLYPieces& pieces, const std::string& path,
  const AssemblyParameters& parameters, AssemblyReport* report, std::string* why)
{
  std::string message;
  bool ok = false;
  try
  {
    Assembler assembler(pieces, parameters, &message);
    ok = assembler.Run(path, report);
  }
  catch (const std::bad_alloc&)
  {
    message = "out of memory while building the pieces";
  }
  if (why)
  {
    *why = ok ? std::string() : message;
  }
  return ok;
}

} // namespace plod
