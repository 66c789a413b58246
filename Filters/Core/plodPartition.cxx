// SPDX-License-Identifier: BSD-3-Clause
// Partition of a triangle mesh by space between processes. See plodPartition.h.
#include "plodPartition.h"
#include "plodBuildUtil.h"
#include "plodOctree.h"
#include "plodOctreeBuilder.h"
#include "plodPartitionSteps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

namespace plod
{
namespace partition
{

//------------------------------------------------------------------------------
int64_t CellGrid::CellOf(const double* x) const
{
  const int shift = MaxFinestLevel - this->K;
  return static_cast<int64_t>(MortonEncode(this->Grid.Cell(x[0], 0) >> shift,
    this->Grid.Cell(x[1], 1) >> shift, this->Grid.Cell(x[2], 2) >> shift));
}

//------------------------------------------------------------------------------
Box CellGrid::BoxOf(const double* x0, const double* x1, const double* x2) const
{
  const int shift = MaxFinestLevel - this->K;
  constexpr uint32_t last = (1u << MaxFinestLevel) - 1;
  Box b;
  for (int a = 0; a < 3; ++a)
  {
    b.Lo[a] = std::numeric_limits<uint32_t>::max();
    b.Hi[a] = 0;
  }
  for (const double* x : { x0, x1, x2 })
  {
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
  return b;
}

//------------------------------------------------------------------------------
std::vector<int> ShareOutCells(const std::vector<int64_t>& perCell, int ranks)
{
  const int64_t total = std::accumulate(perCell.begin(), perCell.end(), int64_t(0));
  std::vector<int> owner(perCell.size(), 0);
  int64_t before = 0;
  for (size_t cell = 0; cell < perCell.size(); ++cell)
  {
    const double middle = double(before) + 0.5 * double(perCell[cell]);
    owner[cell] = std::min(
      ranks - 1, static_cast<int>(double(ranks) * middle / double(std::max<int64_t>(total, 1))));
    before += perCell[cell];
  }
  return owner;
}

//------------------------------------------------------------------------------
void MarkNeededCells(const Box& box, const std::vector<int>& owner, int64_t cellCount,
  uint8_t* needs, std::vector<int64_t>& touched)
{
  touched.clear();
  ForEachCell(box, [&](int64_t cell) { touched.push_back(cell); });
  for (int64_t cell : touched)
  {
    uint8_t* mask = needs + static_cast<size_t>(owner[cell]) * cellCount;
    for (int64_t other : touched)
    {
      mask[other] = 1;
    }
  }
}

//------------------------------------------------------------------------------
bool BoxMeets(const Box& box, const uint8_t* mask)
{
  bool meets = false;
  ForEachCell(box, [&](int64_t cell) { meets = meets || mask[cell]; });
  return meets;
}

//------------------------------------------------------------------------------
void MergePoints(const LargeVector<double>& points, const LargeVector<double>& normals,
  LargeVector<int64_t>& triangles, const CellGrid& cells, const std::vector<int>& owner, int rank,
  PartitionResult* r)
{
  // each point's position on the grid of RootEdge / 2^32, sorted with its position and index
  struct Item
  {
    std::array<int64_t, 3> Key;
    int64_t Index;
  };
  const int64_t n = static_cast<int64_t>(points.size() / 3);
  const double quantum = std::ldexp(r->RootEdge, -32);
  LargeVector<Item> items(n);
  for (int64_t i = 0; i < n; ++i)
  {
    for (int a = 0; a < 3; ++a)
    {
      items[i].Key[a] = std::llround((points[3 * i + a] - r->RootOrigin[a]) / quantum);
    }
    items[i].Index = i;
  }
  std::sort(items.begin(), items.end(), [&](const Item& a, const Item& b) {
    if (a.Key != b.Key)
    {
      return a.Key < b.Key;
    }
    const double* p = &points[3 * a.Index];
    const double* q = &points[3 * b.Index];
    return std::lexicographical_compare(p, p + 3, q, q + 3) ||
      (std::equal(p, p + 3, q) && a.Index < b.Index);
  });
  LargeVector<int64_t> merged(n);
  int64_t kept = 0;
  for (int64_t i = 0; i < n; ++i)
  {
    const double* p = &points[3 * items[i].Index];
    if (i == 0 || items[i].Key != items[i - 1].Key)
    {
      r->Points.insert(r->Points.end(), p, p + 3);
      if (!normals.empty())
      {
        r->Normals.insert(
          r->Normals.end(), &normals[3 * items[i].Index], &normals[3 * items[i].Index] + 3);
      }
      r->Ghost.push_back(owner[cells.CellOf(p)] != rank ? 1 : 0);
      ++kept;
    }
    merged[items[i].Index] = kept - 1;
  }
  LargeVector<Item>().swap(items);
  // triangles in lexicographic order of their merged corners: bucketed by the first corner,
  // then each bucket (a few triangles) sorted by the other two
  const int64_t nt = static_cast<int64_t>(triangles.size() / 3);
  LargeVector<int64_t> start(kept + 1, 0);
  for (int64_t t = 0; t < nt; ++t)
  {
    ++start[merged[triangles[3 * t]] + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  LargeVector<std::array<int64_t, 2>> rest(nt);
  {
    LargeVector<int64_t> fill(start.begin(), start.end() - 1);
    for (int64_t t = 0; t < nt; ++t)
    {
      rest[fill[merged[triangles[3 * t]]]++] = { merged[triangles[3 * t + 1]],
        merged[triangles[3 * t + 2]] };
    }
  }
  LargeVector<int64_t>().swap(triangles);
  LargeVector<int64_t>().swap(merged);
  r->Triangles.resize(3 * nt);
  for (int64_t first = 0; first < kept; ++first)
  {
    std::sort(rest.begin() + start[first], rest.begin() + start[first + 1]);
    for (int64_t t = start[first]; t < start[first + 1]; ++t)
    {
      int64_t* out = &r->Triangles[3 * t];
      out[0] = first;
      out[1] = rest[t][0];
      out[2] = rest[t][1];
      r->NumberOfHaloTriangles += r->Ghost[first] && r->Ghost[out[1]] && r->Ghost[out[2]];
    }
  }
}

//------------------------------------------------------------------------------
void MergeCorners(std::vector<double>& soup, bool hasNormals, const CellGrid& cells,
  const std::vector<int>& owner, int rank, PartitionResult* r)
{
  const int stride = 9 * (hasNormals ? 2 : 1);
  const size_t n = soup.size() / stride;
  LargeVector<double> points(9 * n), normals(hasNormals ? 9 * n : 0);
  LargeVector<int64_t> triangles(3 * n);
  for (size_t t = 0; t < n; ++t)
  {
    std::copy(&soup[t * stride], &soup[t * stride] + 9, &points[9 * t]);
    if (hasNormals)
    {
      std::copy(&soup[t * stride] + 9, &soup[t * stride] + 18, &normals[9 * t]);
    }
  }
  std::iota(triangles.begin(), triangles.end(), int64_t(0));
  std::vector<double>().swap(soup);
  MergePoints(points, normals, triangles, cells, owner, rank, r);
}

//------------------------------------------------------------------------------
int64_t CountOpenEdges(const PartitionResult& r)
{
  // the uses of each edge with an owned end, bucketed by the lower end: (higher end, 1 when
  // downward) pairs, each bucket then sorted (a few uses)
  const LargeVector<int64_t>& tri = r.Triangles;
  const LargeVector<uint8_t>& ghost = r.Ghost;
  const int64_t np = static_cast<int64_t>(ghost.size());
  auto forEachUse = [&](auto&& body) {
    for (size_t t = 0; t < tri.size(); t += 3)
    {
      for (int e = 0; e < 3; ++e)
      {
        const int64_t a = tri[t + e], b = tri[t + (e + 1) % 3];
        if (!ghost[a] || !ghost[b])
        {
          body(std::min(a, b), std::max(a, b), a > b ? 1 : 0);
        }
      }
    }
  };
  LargeVector<int64_t> start(np + 1, 0);
  forEachUse([&](int64_t lower, int64_t, int) { ++start[lower + 1]; });
  std::partial_sum(start.begin(), start.end(), start.begin());
  LargeVector<std::pair<int64_t, int>> uses(start[np]);
  {
    LargeVector<int64_t> fill(start.begin(), start.end() - 1);
    forEachUse([&](int64_t lower, int64_t higher, int down) {
      uses[fill[lower]++] = { higher, down };
    });
  }
  int64_t open = 0;
  for (int64_t p = 0; p < np; ++p)
  {
    std::sort(uses.begin() + start[p], uses.begin() + start[p + 1]);
    for (int64_t i = start[p]; i < start[p + 1];)
    {
      int64_t j = i + 1;
      while (j < start[p + 1] && uses[j].first == uses[i].first)
      {
        ++j;
      }
      open += (j - i == 1) || (j - i == 2 && uses[i].second == uses[i + 1].second);
      i = j;
    }
  }
  return open;
}

//------------------------------------------------------------------------------
void CountOwnedCells(const PartitionResult& r, const CellGrid& cells, int64_t* counts)
{
  LargeVector<uint64_t> keys;
  const int64_t np = static_cast<int64_t>(r.Ghost.size());
  for (int64_t p = 0; p < np; ++p)
  {
    if (!r.Ghost[p])
    {
      const double* x = &r.Points[3 * p];
      keys.push_back(cells.Grid.Key(x[0], x[1], x[2]));
    }
  }
  std::sort(keys.begin(), keys.end());
  CountOccupiedCells(
    static_cast<int64_t>(keys.size()), [&keys](int64_t i) { return keys[i]; }, counts);
  for (int l = 0; l < cells.K; ++l)
  {
    counts[l] = 0; // complete nowhere: from CountCoarseCells
  }
  counts[MaxFinestLevel + 1] = static_cast<int64_t>(keys.size());
}

//------------------------------------------------------------------------------
void CountCoarseCells(const std::vector<int64_t>& perCell, int k, int64_t* counts)
{
  for (int l = 0; l < k; ++l)
  {
    std::vector<char> seen(size_t(1) << (3 * l), 0);
    counts[l] = 0;
    for (size_t cell = 0; cell < perCell.size(); ++cell)
    {
      const size_t parent = cell >> (3 * (k - l));
      if (perCell[cell] > 0 && !seen[parent])
      {
        seen[parent] = 1;
        ++counts[l];
      }
    }
  }
}

} // namespace partition

namespace
{

using partition::Box;

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
    partition::MergeCorners(
      this->Received, this->R.HasNormals, this->Cells, this->Owner, this->Rank, &this->R);
    this->R.NumberOfBoundaryEdges = partition::CountOpenEdges(this->R);
    this->C.Sum(&this->R.NumberOfBoundaryEdges, 1);
    this->R.Ok = this->ChooseLevel();
    return this->R;
  }

private:
  const double* X(int64_t point) const { return this->In.Points + 3 * point; }
  const double* Corner(int64_t t, int c) const { return this->X(this->In.Triangles[3 * t + c]); }

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
        const double* x = this->Corner(t, c);
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
    this->Cells = partition::CellGrid(this->R.RootOrigin, this->R.RootEdge, this->K);
    return true;
  }

  /// 2. Each triangle's box; triangles per cell of their first corner, summed; owners as
  /// Morton-ordered runs of about equal counts.
  void ShareOutCells()
  {
    this->Boxes.resize(this->In.NumberOfTriangles);
    this->PerCell.assign(this->Cells.CellCount(), 0);
    for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
    {
      if (this->Usable[t])
      {
        this->Boxes[t] =
          this->Cells.BoxOf(this->Corner(t, 0), this->Corner(t, 1), this->Corner(t, 2));
        ++this->PerCell[this->Cells.CellOf(this->Corner(t, 0))];
      }
    }
    this->C.Sum(this->PerCell.data(), this->Cells.CellCount());
    this->Owner = partition::ShareOutCells(this->PerCell, this->Ranks);
    for (int64_t cell = 0; cell < this->Cells.CellCount(); ++cell)
    {
      this->R.NumberOfOwnedCells += this->Owner[cell] == this->Rank && this->PerCell[cell] > 0;
    }
  }

  /// 3. The cells each process needs whole (its own and every cell a triangle meeting its own
  /// meets), then every triangle meeting a needed cell sent to that process.
  void Exchange()
  {
    const int64_t cellCount = this->Cells.CellCount();
    std::vector<uint8_t> needs(static_cast<size_t>(this->Ranks) * cellCount, 0);
    std::vector<int64_t> touched;
    for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
    {
      if (this->Usable[t])
      {
        partition::MarkNeededCells(this->Boxes[t], this->Owner, cellCount, needs.data(), touched);
      }
    }
    this->C.Max(needs.data(), static_cast<int64_t>(needs.size()));

    for (int destination = 0; destination < this->Ranks; ++destination)
    {
      const uint8_t* mask = needs.data() + static_cast<size_t>(destination) * cellCount;
      std::vector<double> send;
      for (int64_t t = 0; t < this->In.NumberOfTriangles; ++t)
      {
        if (!this->Usable[t] || !partition::BoxMeets(this->Boxes[t], mask))
        {
          continue;
        }
        for (int c = 0; c < 3; ++c)
        {
          const double* x = this->Corner(t, c);
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

  /// 6. One finest level: owned points' occupied cells summed over the processes for levels
  /// k and finer, the shared histogram of level-k cells for the levels above.
  bool ChooseLevel()
  {
    if (this->Params.RequestedFinestLevel >= 0)
    {
      this->R.FinestLevel = std::min(this->Params.RequestedFinestLevel, MaxFinestLevel);
      return true;
    }
    int64_t cells[MaxFinestLevel + 2] = {};
    partition::CountOwnedCells(this->R, this->Cells, cells);
    this->C.Sum(cells, MaxFinestLevel + 2);
    partition::CountCoarseCells(this->PerCell, this->K, cells);
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
  PartitionResult R;
  partition::CellGrid Cells;
  std::vector<uint8_t> Usable;
  std::vector<Box> Boxes;
  std::vector<int64_t> PerCell;
  std::vector<int> Owner;
  std::vector<double> Received;
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
