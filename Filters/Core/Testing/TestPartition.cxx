// SPDX-License-Identifier: BSD-3-Clause
// Tests of plod::PartitionMesh with simulated ranks (one thread each, talking through a
// Collective made of a barrier and shared slots): every split of a mesh over 1 to 5 ranks
// agrees on the root cube, the finest level and the open-edge count of the one-rank partition;
// every triangle of the whole is drawn (lead corner not a ghost) by exactly one rank; every cell
// a rank draws in is complete there; owned runs cover the cells; unusable triangles are skipped;
// normals travel only when every rank has them.
#include "plodOctree.h"
#include "plodOctreeBuilder.h"
#include "plodPartition.h"
#include "plodScanGenerator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

namespace
{

/// Ranks as threads: each collective call deposits its data, waits for all, reads all, waits.
class ThreadWorld
{
public:
  explicit ThreadWorld(int ranks)
    : Ranks(ranks)
    , Slots(ranks)
  {
  }

  void Barrier()
  {
    std::unique_lock<std::mutex> lock(this->Mutex);
    const int generation = this->Generation;
    if (++this->Waiting == this->Ranks)
    {
      this->Waiting = 0;
      ++this->Generation;
      this->Done.notify_all();
      return;
    }
    this->Done.wait(lock, [&] { return this->Generation != generation; });
  }

  const int Ranks;
  std::vector<std::vector<double>> Slots;

private:
  std::mutex Mutex;
  std::condition_variable Done;
  int Waiting = 0;
  int Generation = 0;
};

class ThreadCollective : public plod::Collective
{
public:
  ThreadCollective(ThreadWorld& world, int rank)
    : World(world)
    , MyRank(rank)
  {
  }
  int Rank() const override { return this->MyRank; }
  int Ranks() const override { return this->World.Ranks; }

  template <typename T, typename Op>
  void Reduce(T* values, int64_t n, Op op)
  {
    this->World.Slots[this->MyRank].assign(values, values + n);
    this->World.Barrier();
    for (int64_t i = 0; i < n; ++i)
    {
      T v = static_cast<T>(this->World.Slots[0][i]);
      for (int r = 1; r < this->World.Ranks; ++r)
      {
        v = op(v, static_cast<T>(this->World.Slots[r][i]));
      }
      values[i] = v;
    }
    this->World.Barrier();
  }
  void Sum(int64_t* v, int64_t n) override
  {
    this->Reduce(v, n, [](int64_t a, int64_t b) { return a + b; });
  }
  void Min(double* v, int n) override
  {
    this->Reduce(v, n, [](double a, double b) { return std::min(a, b); });
  }
  void Max(double* v, int n) override
  {
    this->Reduce(v, n, [](double a, double b) { return std::max(a, b); });
  }
  void Max(uint8_t* v, int64_t n) override
  {
    this->Reduce(v, n, [](uint8_t a, uint8_t b) { return std::max(a, b); });
  }
  void Gather(const std::vector<double>& send, int root, std::vector<double>* received) override
  {
    this->World.Slots[this->MyRank] = send;
    this->World.Barrier();
    if (this->MyRank == root)
    {
      received->clear();
      for (const auto& s : this->World.Slots)
      {
        received->insert(received->end(), s.begin(), s.end());
      }
    }
    this->World.Barrier();
  }

private:
  ThreadWorld& World;
  const int MyRank;
};

struct Mesh
{
  std::vector<double> Points;
  std::vector<double> Normals;
  std::vector<int64_t> Triangles;
};

/// A bumpy sphere (closed) or its upper part (open), with normals.
Mesh MakeMesh(bool closed, int subdivisions = 4)
{
  plodtest::BaseMesh base = plodtest::OctahedralSphere(subdivisions);
  Mesh m;
  m.Points = base.Points;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> bump(0.97, 1.03);
  for (size_t p = 0; p < m.Points.size(); p += 3)
  {
    const double s = bump(random);
    for (int a = 0; a < 3; ++a)
    {
      m.Normals.push_back(m.Points[p + a]);
      m.Points[p + a] *= s;
    }
  }
  for (size_t t = 0; t < base.Triangles.size(); t += 3)
  {
    bool keep = closed;
    for (int c = 0; c < 3; ++c)
    {
      keep = keep || m.Points[3 * base.Triangles[t + c] + 2] > -0.2;
    }
    if (keep)
    {
      m.Triangles.insert(m.Triangles.end(), &base.Triangles[t], &base.Triangles[t] + 3);
    }
  }
  return m;
}

/// Each rank's share of the mesh: its triangles (in a random split), with all points.
std::vector<plod::PartitionResult> Partition(
  const Mesh& m, int ranks, unsigned seed, bool normals = true, int level = -1)
{
  std::mt19937 random(seed);
  std::vector<std::vector<int64_t>> shares(ranks);
  for (size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    auto& share = shares[random() % ranks];
    share.insert(share.end(), &m.Triangles[t], &m.Triangles[t] + 3);
  }
  ThreadWorld world(ranks);
  std::vector<plod::PartitionResult> results(ranks);
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
  {
    threads.emplace_back([&, r]() {
      ThreadCollective c(world, r);
      plod::PartitionInput in;
      in.NumberOfPoints = static_cast<int64_t>(m.Points.size() / 3);
      in.Points = m.Points.data();
      in.Normals = normals || r > 0 ? m.Normals.data() : nullptr;
      in.NumberOfTriangles = static_cast<int64_t>(shares[r].size() / 3);
      in.Triangles = shares[r].data();
      plod::PartitionParameters p;
      p.OwnershipLevel = 2;
      p.RequestedFinestLevel = level;
      results[r] = plod::PartitionMesh(in, p, c);
    });
  }
  for (auto& t : threads)
  {
    t.join();
  }
  return results;
}

using Triangle = std::array<std::array<double, 3>, 3>;

Triangle Corners(const std::vector<double>& points, const int64_t* ids)
{
  Triangle t;
  for (int c = 0; c < 3; ++c)
  {
    for (int a = 0; a < 3; ++a)
    {
      t[c][a] = points[3 * ids[c] + a];
    }
  }
  return t;
}

/// The corner in the lowest level-21 cell (Morton order), as the patch generator's lead corner
/// is the corner in the lowest leaf; ties cannot occur for distinct points of this mesh.
int LeadCorner(const plod::PartitionResult& r, const int64_t* ids)
{
  const plod::CellQuantizer q(r.RootOrigin, r.RootEdge);
  int lead = 0;
  uint64_t best = ~0ULL;
  for (int c = 0; c < 3; ++c)
  {
    const double* x = &r.Points[3 * ids[c]];
    const uint64_t k = q.Key(x[0], x[1], x[2]);
    if (k < best)
    {
      best = k;
      lead = c;
    }
  }
  return lead;
}

TEST(Partition, EverySplitAgreesWithOneRankAndDrawsEachTriangleOnce)
{
  for (bool closed : { true, false })
  {
    const Mesh m = MakeMesh(closed);
    const auto one = Partition(m, 1, 1);
    ASSERT_TRUE(one[0].Ok) << one[0].Error;
    EXPECT_EQ(closed, one[0].NumberOfBoundaryEdges == 0);
    EXPECT_EQ(std::count(one[0].Ghost.begin(), one[0].Ghost.end(), 1), 0);
    EXPECT_EQ(one[0].NumberOfHaloTriangles, 0);
    EXPECT_EQ(
      static_cast<int64_t>(one[0].Triangles.size()), static_cast<int64_t>(m.Triangles.size()));
    EXPECT_TRUE(one[0].HasNormals);
    std::map<Triangle, int> whole;
    for (size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      whole[Corners(m.Points, &m.Triangles[t])] = 0;
    }
    for (int ranks : { 2, 3, 5 })
    {
      for (unsigned seed : { 1u, 2u })
      {
        const auto parts = Partition(m, ranks, seed);
        std::map<Triangle, int> drawn = whole;
        int64_t owned = 0;
        for (int r = 0; r < ranks; ++r)
        {
          const plod::PartitionResult& p = parts[r];
          ASSERT_TRUE(p.Ok) << p.Error;
          for (int a = 0; a < 3; ++a)
          {
            EXPECT_EQ(p.RootOrigin[a], one[0].RootOrigin[a]);
          }
          EXPECT_EQ(p.RootEdge, one[0].RootEdge);
          EXPECT_EQ(p.FinestLevel, one[0].FinestLevel) << ranks << " ranks";
          EXPECT_EQ(closed, p.NumberOfBoundaryEdges == 0) << ranks << " ranks";
          owned += p.NumberOfOwnedCells;
          for (size_t t = 0; t < p.Triangles.size(); t += 3)
          {
            const Triangle tri = Corners(p.Points, &p.Triangles[t]);
            ASSERT_EQ(drawn.count(tri), 1u) << "a triangle that is not the mesh's";
            if (!p.Ghost[p.Triangles[t + LeadCorner(p, &p.Triangles[t])]])
            {
              ++drawn[tri];
            }
          }
        }
        EXPECT_EQ(owned, one[0].NumberOfOwnedCells) << "owned cells cover the occupied cells";
        for (const auto& [tri, count] : drawn)
        {
          ASSERT_EQ(count, 1) << ranks << " ranks, seed " << seed << ": drawn " << count
                              << " times";
        }
      }
    }
  }
}

// A cell of level >= k that a rank draws in (its drawn triangles' boxes meet it) holds there
// every triangle of the whole mesh whose box meets it.
void ExpectCompleteCells(const Mesh& m, int ranks, unsigned seed)
{
  const auto one = Partition(m, 1, 1);
  const auto parts = Partition(m, ranks, seed);
  const int k = 2, shift = plod::MaxFinestLevel - k;
  auto cellsOf = [&](const plod::PartitionResult& r, const std::vector<double>& points,
                   const int64_t* ids) {
    const plod::CellQuantizer q(r.RootOrigin, r.RootEdge);
    std::set<uint64_t> cells;
    uint32_t lo[3] = { ~0u, ~0u, ~0u }, hi[3] = { 0, 0, 0 };
    for (int c = 0; c < 3; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        const uint32_t u = q.Cell(points[3 * ids[c] + a], a);
        lo[a] = std::min(lo[a], u > 0 ? u - 1 : 0u);
        hi[a] = std::max(hi[a], std::min(u + 1, (1u << plod::MaxFinestLevel) - 1));
      }
    }
    for (uint32_t z = lo[2] >> shift; z <= hi[2] >> shift; ++z)
      for (uint32_t y = lo[1] >> shift; y <= hi[1] >> shift; ++y)
        for (uint32_t x = lo[0] >> shift; x <= hi[0] >> shift; ++x)
          cells.insert(plod::MortonEncode(x, y, z));
    return cells;
  };
  std::map<uint64_t, std::set<Triangle>> wholeByCell;
  for (size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    for (uint64_t c : cellsOf(one[0], m.Points, &m.Triangles[t]))
    {
      wholeByCell[c].insert(Corners(m.Points, &m.Triangles[t]));
    }
  }
  for (const plod::PartitionResult& p : parts)
  {
    std::map<uint64_t, std::set<Triangle>> held;
    std::set<uint64_t> drawnIn;
    for (size_t t = 0; t < p.Triangles.size(); t += 3)
    {
      const auto cells = cellsOf(p, p.Points, &p.Triangles[t]);
      for (uint64_t c : cells)
      {
        held[c].insert(Corners(p.Points, &p.Triangles[t]));
      }
      if (!p.Ghost[p.Triangles[t + LeadCorner(p, &p.Triangles[t])]])
      {
        drawnIn.insert(cells.begin(), cells.end());
      }
    }
    ASSERT_FALSE(drawnIn.empty());
    for (uint64_t c : drawnIn)
    {
      EXPECT_EQ(held[c], wholeByCell[c]) << "cell " << c << " is not complete";
    }
  }
}

TEST(Partition, CellsARankDrawsInAreComplete)
{
  ExpectCompleteCells(MakeMesh(true), 3, 9);
  // small triangles with a corner exactly on the faces of level-2 cells: the builder counts a
  // triangle touching a face as meeting the cell beyond it, so that cell's owner needs it
  Mesh m = MakeMesh(true);
  const auto one = Partition(m, 1, 1);
  const double* o = one[0].RootOrigin;
  const double quarter = one[0].RootEdge / 4;
  const double d = one[0].RootEdge * 1e-3;
  for (int i = 1; i <= 3; ++i)
  {
    for (int j = 1; j <= 3; ++j)
    {
      const double x = o[0] + i * quarter, y = o[1] + j * quarter, z = o[2] + 2 * quarter + d;
      const int64_t first = static_cast<int64_t>(m.Points.size() / 3);
      for (const std::array<double, 3>& p :
        { std::array<double, 3>{ x, y, z }, { x + d, y, z }, { x, y + d, z }, { x - d, y - d, z } })
      {
        m.Points.insert(m.Points.end(), p.begin(), p.end());
        m.Normals.insert(m.Normals.end(), { 0.0, 0.0, 1.0 });
      }
      m.Triangles.insert(m.Triangles.end(), { first, first + 1, first + 2 });
      m.Triangles.insert(m.Triangles.end(), { first + 3, first, first + 2 });
    }
  }
  for (unsigned seed : { 1u, 2u, 3u })
  {
    ExpectCompleteCells(m, 4, seed);
  }
}

TEST(Partition, UnusableTrianglesAreSkippedAndNormalsNeedEveryRank)
{
  Mesh m = MakeMesh(true, 2);
  m.Points.insert(m.Points.end(), { std::nan(""), 0.0, 0.0 });
  m.Normals.insert(m.Normals.end(), { 0.0, 0.0, 1.0 });
  const int64_t nanPoint = static_cast<int64_t>(m.Points.size() / 3) - 1;
  m.Triangles.insert(m.Triangles.end(), { 0, 1, nanPoint, 0, 1, nanPoint + 5 });
  const auto one = Partition(m, 1, 1);
  ASSERT_TRUE(one[0].Ok);
  EXPECT_EQ(one[0].NumberOfSkippedTriangles, 2);
  EXPECT_EQ(
    static_cast<int64_t>(one[0].Triangles.size()), static_cast<int64_t>(m.Triangles.size()) - 6);
  const auto mixed = Partition(m, 2, 4, false); // rank 0 without normals
  EXPECT_FALSE(mixed[0].HasNormals);
  EXPECT_FALSE(mixed[1].HasNormals);
  EXPECT_TRUE(mixed[1].Normals.empty());
  const auto requested = Partition(m, 2, 4, true, 7);
  EXPECT_EQ(requested[0].FinestLevel, 7);
  EXPECT_EQ(requested[1].FinestLevel, 7);
}

// The finest level of the one-rank partition is the builder's automatic level of the mesh.
TEST(Partition, OneRankLevelIsTheBuildersLevel)
{
  const Mesh m = MakeMesh(false, 5);
  const auto one = Partition(m, 1, 1);
  ASSERT_TRUE(one[0].Ok);
  std::vector<uint64_t> keys;
  const plod::CellQuantizer q(one[0].RootOrigin, one[0].RootEdge);
  std::set<int64_t> used(m.Triangles.begin(), m.Triangles.end());
  for (int64_t p : used)
  {
    keys.push_back(q.Key(m.Points[3 * p], m.Points[3 * p + 1], m.Points[3 * p + 2]));
  }
  std::sort(keys.begin(), keys.end());
  int64_t cells[plod::MaxFinestLevel + 1];
  plod::CountOccupiedCells(
    static_cast<int64_t>(keys.size()), [&](int64_t r) { return keys[r]; }, cells);
  EXPECT_EQ(one[0].FinestLevel,
    plod::ChooseFinestLevel(cells, static_cast<int64_t>(keys.size()), 0, false, 1e300));
  EXPECT_GT(one[0].FinestLevel, 2);
}

TEST(Partition, NoTrianglesAnywhereAndBadLevels)
{
  Mesh m = MakeMesh(true, 1);
  m.Triangles.clear();
  const auto none = Partition(m, 3, 1, true, -1);
  for (const auto& r : none)
  {
    EXPECT_TRUE(r.Ok);
    EXPECT_TRUE(r.NoTriangles);
    EXPECT_TRUE(r.Triangles.empty());
  }
  plod::SerialCollective serial;
  plod::PartitionInput in;
  plod::PartitionParameters p;
  for (int level : { -1, 0, 7, 30 })
  {
    p.OwnershipLevel = level;
    const auto bad = plod::PartitionMesh(in, p, serial);
    EXPECT_FALSE(bad.Ok);
    EXPECT_NE(bad.Error.find("ownership level"), std::string::npos) << bad.Error;
  }
}

} // namespace
