// SPDX-License-Identifier: BSD-3-Clause
// Partition of a triangle mesh by space between processes. See plodPartition.h.
#include "plodPartition.h"
#include "plodBuildUtil.h"
#include "plodOctree.h"
#include "plodOctreeBuilder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

namespace plod
{
namespace
{

/// A triangle's box of level-k cells (inclusive).
struct Box
{
  uint32_t Lo[3], Hi[3];
};

/// Steps of the partition on one process; each collective call is made by every process.
class Partitioner
{
public:
  Partitioner(const PartitionInput& in, const PartitionParameters& p, Collective& c)
    : In(in)
    , Params(p)
    , C(c)
    , Rank(c.Rank())
    , Ranks(c.Ranks())
    , K(p.OwnershipLevel)
    , CellCount(
        p.OwnershipLevel >= 1 && p.OwnershipLevel <= 6 ? int64_t(1) << (3 * p.OwnershipLevel) : 0)
  {
  }

  PartitionResult Run()
  {
    if (this->K < 1 || this->K > 6)
    {
      this->R.Error = "the ownership level must be in [1, 6], not " + std::to_string(this->K);
      return this->R;
    }
    this->FindUsableTriangles();
    if (!this->PlaceRootCube())
    {
      return this->R;
    }
    if (this->R.NoTriangles)
    {
      this->R.FinestLevel = std::max(0, this->Params.RequestedFinestLevel);
      this->R.Ok = true;
      return this->R;
    }
    this->ShareOutCells();
    this->Exchange();
    this->MergePoints();
    this->CountOpenEdges();
    this->R.Ok = this->ChooseLevel();
    return this->R;
  }

private:
  const double* X(int64_t point) const { return this->In.Points + 3 * point; }

  void FindUsableTriangles()
  {
    const int64_t nt = this->In.NumberOfTriangles;
    this->Usable.assign(nt, 1);
    for (int64_t t = 0; t < nt; ++t)
    {
      for (int c = 0; c < 3 && this->Usable[t]; ++c)
      {
        const int64_t id = this->In.Triangles[3 * t + c];
        if (id < 0 || id >= this->In.NumberOfPoints)
        {
          this->Usable[t] = 0;
          break;
        }
        const double* x = this->X(id);
        this->Usable[t] = std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
      }
      this->R.NumberOfSkippedTriangles += this->Usable[t] ? 0 : 1;
    }
  }

  /// 1. The global bounds, the triangle count and whether all have normals; the root cube.
  bool PlaceRootCube()
  {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::numeric_limits<double>::max();
      hi[a] = -std::numeric_limits<double>::max();
    }
    for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
    {
      if (!this->Usable[t])
      {
        continue;
      }
      for (int c = 0; c < 3; ++c)
      {
        const double* x = this->X(this->In.Triangles[3 * t + c]);
        for (int a = 0; a < 3; ++a)
        {
          lo[a] = std::min(lo[a], x[a]);
          hi[a] = std::max(hi[a], x[a]);
        }
      }
    }
    int64_t counts[2] = { this->In.NumberOfTriangles - this->R.NumberOfSkippedTriangles, 0 };
    // processes without normals but with triangles: normals are carried only when this is 0
    counts[1] = (this->In.Normals || counts[0] == 0) ? 0 : 1;
    this->C.Min(lo, 3);
    this->C.Max(hi, 3);
    this->C.Sum(counts, 2);
    this->R.HasNormals = counts[1] == 0;
    if (counts[0] == 0)
    {
      this->R.NoTriangles = true;
      return true;
    }
    std::string why;
    if (!build::PlaceRootCube(lo, hi, this->R.RootOrigin, this->R.RootEdge, &why))
    {
      this->R.Error = "no root cube for the whole mesh: " + why;
      return false;
    }
    this->Grid = CellQuantizer(this->R.RootOrigin, this->R.RootEdge);
    return true;
  }

  /// The level-k cell of a point.
  int64_t CellOf(const double* x) const
  {
    const int shift = MaxFinestLevel - this->K;
    return static_cast<int64_t>(MortonEncode(this->Grid.Cell(x[0], 0) >> shift,
      this->Grid.Cell(x[1], 1) >> shift, this->Grid.Cell(x[2], 2) >> shift));
  }

  template <typename Body>
  static void ForEachCell(const Box& b, Body&& body)
  {
    for (uint32_t z = b.Lo[2]; z <= b.Hi[2]; ++z)
    {
      for (uint32_t y = b.Lo[1]; y <= b.Hi[1]; ++y)
      {
        for (uint32_t x = b.Lo[0]; x <= b.Hi[0]; ++x)
        {
          body(static_cast<int64_t>(MortonEncode(x, y, z)));
        }
      }
    }
  }

  /// 2. Each triangle's box; triangles per cell of their first corner, summed; owners as
  /// Morton-ordered runs of about equal counts.
  void ShareOutCells()
  {
    const int shift = MaxFinestLevel - this->K;
    constexpr uint32_t last = (1u << MaxFinestLevel) - 1;
    this->Boxes.resize(this->In.NumberOfTriangles);
    this->PerCell.assign(this->CellCount, 0);
    for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
    {
      if (!this->Usable[t])
      {
        continue;
      }
      Box& b = this->Boxes[t];
      for (int a = 0; a < 3; ++a)
      {
        b.Lo[a] = std::numeric_limits<uint32_t>::max();
        b.Hi[a] = 0;
      }
      for (int c = 0; c < 3; ++c)
      {
        const double* x = this->X(this->In.Triangles[3 * t + c]);
        for (int a = 0; a < 3; ++a)
        {
          const uint32_t u = this->Grid.Cell(x[a], a);
          b.Lo[a] = std::min(b.Lo[a], u > 0 ? u - 1 : 0u);
          b.Hi[a] = std::max(b.Hi[a], std::min(u + 1, last));
        }
      }
      for (int a = 0; a < 3; ++a)
      {
        b.Lo[a] >>= shift;
        b.Hi[a] >>= shift;
      }
      ++this->PerCell[this->CellOf(this->X(this->In.Triangles[3 * t]))];
    }
    this->C.Sum(this->PerCell.data(), this->CellCount);
    const int64_t total = std::accumulate(this->PerCell.begin(), this->PerCell.end(), int64_t(0));
    this->Owner.assign(this->CellCount, 0);
    int64_t before = 0;
    for (int64_t cell = 0; cell < this->CellCount; ++cell)
    {
      const double middle = double(before) + 0.5 * double(this->PerCell[cell]);
      this->Owner[cell] =
        std::min(this->Ranks - 1, static_cast<int>(double(this->Ranks) * middle / double(total)));
      before += this->PerCell[cell];
      if (this->Owner[cell] == this->Rank && this->PerCell[cell] > 0)
      {
        ++this->R.NumberOfOwnedCells;
      }
    }
  }

  /// 3. The cells each process needs whole (its own and every cell a triangle meeting its own
  /// meets), then every triangle meeting a needed cell sent to that process.
  void Exchange()
  {
    std::vector<uint8_t> needs(static_cast<size_t>(this->Ranks) * this->CellCount, 0);
    std::vector<int64_t> touched;
    for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
    {
      if (!this->Usable[t])
      {
        continue;
      }
      touched.clear();
      ForEachCell(this->Boxes[t], [&](int64_t cell) { touched.push_back(cell); });
      for (int64_t cell : touched)
      {
        uint8_t* mask = needs.data() + static_cast<size_t>(this->Owner[cell]) * this->CellCount;
        for (int64_t other : touched)
        {
          mask[other] = 1;
        }
      }
    }
    this->C.Max(needs.data(), static_cast<int64_t>(needs.size()));

    this->Stride = 9 * (this->R.HasNormals ? 2 : 1);
    for (int destination = 0; destination < this->Ranks; ++destination)
    {
      const uint8_t* mask = needs.data() + static_cast<size_t>(destination) * this->CellCount;
      std::vector<double> send;
      for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
      {
        if (!this->Usable[t])
        {
          continue;
        }
        bool meets = false;
        ForEachCell(this->Boxes[t], [&](int64_t cell) { meets = meets || mask[cell]; });
        if (!meets)
        {
          continue;
        }
        for (int c = 0; c < 3; ++c)
        {
          const double* x = this->X(this->In.Triangles[3 * t + c]);
          send.insert(send.end(), x, x + 3);
        }
        if (this->R.HasNormals)
        {
          for (int c = 0; c < 3; ++c)
          {
            const double* n = this->In.Normals + 3 * this->In.Triangles[3 * t + c];
            send.insert(send.end(), n, n + 3);
          }
        }
      }
      this->C.Gather(send, destination, &this->Received);
    }
  }

  /// 4. Coincident points merged, points and triangles in canonical order, ghosts flagged.
  void MergePoints()
  {
    const int64_t n = static_cast<int64_t>(this->Received.size()) / this->Stride;
    std::vector<int64_t> corner(3 * n);
    std::iota(corner.begin(), corner.end(), 0);
    auto position = [&](int64_t c) {
      return this->Received.data() + (c / 3) * this->Stride + (c % 3) * 3;
    };
    const double quantum = std::ldexp(this->R.RootEdge, -32);
    std::vector<std::array<int64_t, 3>> key(3 * n);
    for (int64_t c = 0; c < 3 * n; ++c)
    {
      const double* p = position(c);
      for (int a = 0; a < 3; ++a)
      {
        key[c][a] = std::llround((p[a] - this->R.RootOrigin[a]) / quantum);
      }
    }
    std::sort(corner.begin(), corner.end(), [&](int64_t a, int64_t b) {
      if (key[a] != key[b])
      {
        return key[a] < key[b];
      }
      const double* p = position(a);
      const double* q = position(b);
      return std::lexicographical_compare(p, p + 3, q, q + 3) || (std::equal(p, p + 3, q) && a < b);
    });
    std::vector<int64_t> pointOf(3 * n);
    int64_t points = 0;
    for (size_t i = 0; i < corner.size(); ++i)
    {
      const double* p = position(corner[i]);
      if (i == 0 || key[corner[i]] != key[corner[i - 1]])
      {
        this->R.Points.insert(this->R.Points.end(), p, p + 3);
        if (this->R.HasNormals)
        {
          this->R.Normals.insert(this->R.Normals.end(), p + 9, p + 12);
        }
        this->R.Ghost.push_back(this->Owner[this->CellOf(p)] != this->Rank ? 1 : 0);
        ++points;
      }
      pointOf[corner[i]] = points - 1;
    }
    std::vector<std::array<int64_t, 3>> triangles(n);
    for (int64_t t = 0; t < n; ++t)
    {
      triangles[t] = { pointOf[3 * t], pointOf[3 * t + 1], pointOf[3 * t + 2] };
    }
    std::sort(triangles.begin(), triangles.end());
    this->R.Triangles.reserve(3 * n);
    for (const auto& t : triangles)
    {
      this->R.Triangles.insert(this->R.Triangles.end(), t.begin(), t.end());
      this->R.NumberOfHaloTriangles +=
        this->R.Ghost[t[0]] && this->R.Ghost[t[1]] && this->R.Ghost[t[2]];
    }
    std::vector<double>().swap(this->Received);
  }

  /// 5. Boundary and misoriented edges of the whole: an edge with an end this process owns has
  /// all its triangles here, so its uses are exact; summed (only zero matters).
  void CountOpenEdges()
  {
    const std::vector<int64_t>& tri = this->R.Triangles;
    const std::vector<uint8_t>& ghost = this->R.Ghost;
    std::vector<std::tuple<int64_t, int64_t, int>> edges; // (lower, higher, 1 when downward)
    edges.reserve(tri.size());
    for (size_t t = 0; t < tri.size(); t += 3)
    {
      for (int e = 0; e < 3; ++e)
      {
        const int64_t a = tri[t + e], b = tri[t + (e + 1) % 3];
        if (!ghost[a] || !ghost[b])
        {
          edges.emplace_back(std::min(a, b), std::max(a, b), a > b ? 1 : 0);
        }
      }
    }
    std::sort(edges.begin(), edges.end());
    int64_t open = 0;
    for (size_t i = 0; i < edges.size();)
    {
      size_t j = i + 1;
      while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
        std::get<1>(edges[j]) == std::get<1>(edges[i]))
      {
        ++j;
      }
      open += (j - i == 1) || (j - i == 2 && std::get<2>(edges[i]) == std::get<2>(edges[i + 1]));
      i = j;
    }
    this->C.Sum(&open, 1);
    this->R.NumberOfBoundaryEdges = open;
  }

  /// 6. One finest level: owned points' occupied cells summed over the processes for levels
  /// k and finer, the shared histogram of level-k cells for the levels above.
  bool ChooseLevel()
  {
    if (this->Params.RequestedFinestLevel >= 0)
    {
      this->R.FinestLevel = std::min(this->Params.RequestedFinestLevel, MaxFinestLevel);
      return true;
    }
    std::vector<uint64_t> keys;
    const int64_t np = static_cast<int64_t>(this->R.Ghost.size());
    for (int64_t p = 0; p < np; ++p)
    {
      if (!this->R.Ghost[p])
      {
        const double* x = &this->R.Points[3 * p];
        keys.push_back(this->Grid.Key(x[0], x[1], x[2]));
      }
    }
    std::sort(keys.begin(), keys.end());
    int64_t cells[MaxFinestLevel + 2] = {};
    CountOccupiedCells(
      static_cast<int64_t>(keys.size()), [&keys](int64_t r) { return keys[r]; }, cells);
    for (int l = 0; l < this->K; ++l)
    {
      cells[l] = 0; // complete nowhere: from the histogram below
    }
    cells[MaxFinestLevel + 1] = static_cast<int64_t>(keys.size());
    this->C.Sum(cells, MaxFinestLevel + 2);
    for (int l = 0; l < this->K; ++l)
    {
      std::vector<char> seen(size_t(1) << (3 * l), 0);
      for (int64_t cell = 0; cell < this->CellCount; ++cell)
      {
        const int64_t parent = cell >> (3 * (this->K - l));
        if (this->PerCell[cell] > 0 && !seen[parent])
        {
          seen[parent] = 1;
          ++cells[l];
        }
      }
    }
    this->R.FinestLevel = ChooseFinestLevelFromCounts(cells, cells[MaxFinestLevel + 1], false);
    if (this->R.FinestLevel < 0)
    {
      this->R.Error = "inconsistent occupied-cell counts over the processes: no common level";
      return false;
    }
    return true;
  }

  const PartitionInput& In;
  const PartitionParameters& Params;
  Collective& C;
  const int Rank;
  const int Ranks;
  const int K;
  const int64_t CellCount;
  PartitionResult R;
  CellQuantizer Grid;
  std::vector<uint8_t> Usable;
  std::vector<Box> Boxes;
  std::vector<int64_t> PerCell;
  std::vector<int> Owner;
  std::vector<double> Received;
  int Stride = 9;
};

} // namespace

//------------------------------------------------------------------------------
PartitionResult PartitionMesh(
  const PartitionInput& input, const PartitionParameters& parameters, Collective& collective)
{
  Partitioner p(input, parameters, collective);
  return p.Run();
}

} // namespace plod
