// SPDX-License-Identifier: BSD-3-Clause
// Tests of plod::PartitionMesh with simulated ranks (one thread each, talking through a
// Collective made of a barrier and shared slots): every split of a mesh over 1 to 5 ranks
// agrees on the root cube, the finest level and the open-edge count of the one-rank partition;
// every triangle of the whole is drawn (lead corner not a ghost) by exactly one rank; every cell
// a rank draws in is complete there; owned runs cover the cells; unusable triangles are skipped;
// normals travel only when every rank has them.
// Pieces of a PLY file (plodPieces.h): each piece equals the rank of the same number; the
// octree of each piece equals the whole mesh's octree in every cell of level k and finer that
// the piece owns; pieces sized by the memory limit; every fault removes the temporary files.
#include "plodOctree.h"
#include "plodOctreeBuilder.h"
#include "plodOctreeFile.h"
#include "plodOctreeStorage.h"
#include "plodPLYRead.h"
#include "plodPLYSamples.h"
#include "plodPartition.h"
#include "plodPieceAssembly.h"
#include "plodPieces.h"
#include "plodScanGenerator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <dirent.h>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

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
std::vector<plod::PartitionResult> Partition(const Mesh& m, int ranks, unsigned seed,
  bool normals = true, int level = -1, int ownershipLevel = 2)
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
      p.OwnershipLevel = ownershipLevel;
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

Triangle Corners(const double* points, const int64_t* ids)
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
      whole[Corners(m.Points.data(), &m.Triangles[t])] = 0;
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
            const Triangle tri = Corners(p.Points.data(), &p.Triangles[t]);
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
  auto cellsOf = [&](const plod::PartitionResult& r, const double* points, const int64_t* ids) {
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
    for (uint64_t c : cellsOf(one[0], m.Points.data(), &m.Triangles[t]))
    {
      wholeByCell[c].insert(Corners(m.Points.data(), &m.Triangles[t]));
    }
  }
  for (const plod::PartitionResult& p : parts)
  {
    std::map<uint64_t, std::set<Triangle>> held;
    std::set<uint64_t> drawnIn;
    for (size_t t = 0; t < p.Triangles.size(); t += 3)
    {
      const auto cells = cellsOf(p, p.Points.data(), &p.Triangles[t]);
      for (uint64_t c : cells)
      {
        held[c].insert(Corners(p.Points.data(), &p.Triangles[t]));
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

//------------------------------------------------------------------------------
// Pieces of a PLY file

/// The mesh as a PLY file (binary little endian or ASCII), coordinates float or double,
/// normals when `normals`; the mesh is then rounded to what the file holds.
std::string WritePLY(
  Mesh& m, const std::string& name, plodtest::PLYEncoding enc, const char* type, bool normals)
{
  const std::string path = ::testing::TempDir() + name;
  const int64_t np = static_cast<int64_t>(m.Points.size() / 3);
  std::string out = std::string("ply\nformat ") + plodtest::PLYFormatWord(enc) +
    " 1.0\nelement vertex " + std::to_string(np) + "\nproperty " + type + " x\nproperty " + type +
    " y\nproperty " + type + " z\n";
  if (normals)
  {
    out += "property float nx\nproperty float ny\nproperty float nz\n";
  }
  out += "element face " + std::to_string(m.Triangles.size() / 3) +
    "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int64_t p = 0; p < np; ++p)
  {
    for (int a = 0; a < 3; ++a)
    {
      plodtest::PutPLYValue(out, type, m.Points[3 * p + a], enc);
    }
    for (int a = 0; normals && a < 3; ++a)
    {
      plodtest::PutPLYValue(out, "float", m.Normals[3 * p + a], enc);
    }
    plodtest::EndPLYRow(out, enc);
  }
  for (size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    plodtest::PutPLYValue(out, "uchar", 3, enc);
    for (int c = 0; c < 3; ++c)
    {
      plodtest::PutPLYValue(out, "int", double(m.Triangles[t + c]), enc);
    }
    plodtest::EndPLYRow(out, enc);
  }
  std::ofstream(path, std::ios::binary) << out;
  plod::PLYMesh read;
  std::string why;
  EXPECT_TRUE(plod::ReadPLYMesh(path, &read, &why)) << why;
  for (size_t i = 0; i < m.Points.size(); ++i)
  {
    m.Points[i] = read.PointsDouble.empty() ? double(read.PointsFloat[i]) : read.PointsDouble[i];
  }
  for (size_t i = 0; normals && i < m.Normals.size(); ++i)
  {
    m.Normals[i] = read.Normals[i];
  }
  return path;
}

/// Entries of a directory other than . and .. (-1 when it cannot be read).
int CountEntries(const std::string& dir)
{
  DIR* d = opendir(dir.c_str());
  if (!d)
  {
    return -1;
  }
  int n = 0;
  while (const dirent* e = readdir(d))
  {
    n += std::string(e->d_name) != "." && std::string(e->d_name) != "..";
  }
  closedir(d);
  return n;
}

/// A fresh empty directory for temporary files.
std::string FreshDirectory(const std::string& name)
{
  const std::string dir = ::testing::TempDir() + name;
  mkdir(dir.c_str(), 0700);
  EXPECT_EQ(CountEntries(dir), 0) << dir;
  return dir;
}

void ExpectSamePiece(const plod::PartitionResult& a, const plod::PartitionResult& b, int p)
{
  SCOPED_TRACE("piece " + std::to_string(p));
  ASSERT_TRUE(a.Ok) << a.Error;
  ASSERT_TRUE(b.Ok) << b.Error;
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_EQ(a.RootOrigin[i], b.RootOrigin[i]);
  }
  EXPECT_EQ(a.RootEdge, b.RootEdge);
  EXPECT_EQ(a.FinestLevel, b.FinestLevel);
  EXPECT_EQ(a.NumberOfBoundaryEdges, b.NumberOfBoundaryEdges);
  EXPECT_EQ(a.NumberOfOwnedCells, b.NumberOfOwnedCells);
  EXPECT_EQ(a.NumberOfHaloTriangles, b.NumberOfHaloTriangles);
  EXPECT_EQ(a.HasNormals, b.HasNormals);
  EXPECT_EQ(a.Points, b.Points);
  EXPECT_EQ(a.Normals, b.Normals);
  EXPECT_EQ(a.Ghost, b.Ghost);
  EXPECT_EQ(a.Triangles, b.Triangles);
}

/// Splits `path` into `pieces` pieces at ownership level k.
std::vector<plod::PartitionResult> Pieces(const std::string& path, int pieces, int k,
  const std::string& tmp, plod::PLYPieces* split = nullptr)
{
  plod::PLYPieces local;
  plod::PLYPieces& s = split ? *split : local;
  plod::PiecesParameters params;
  params.OwnershipLevel = k;
  params.NumberOfPieces = pieces;
  params.TemporaryDirectory = tmp;
  // pieces merged on threads of their own, the later range first
  params.Parallel = [](
                      int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body) {
    std::vector<std::thread> threads;
    for (int64_t b = ((n - 1) / grain) * grain; b >= 0; b -= grain)
    {
      threads.emplace_back([&body, b, n, grain]() { body(b, std::min(n, b + grain)); });
    }
    for (std::thread& t : threads)
    {
      t.join();
    }
  };
  std::string why;
  EXPECT_TRUE(s.Open(path, params, &why)) << why;
  std::vector<plod::PartitionResult> out(s.GetNumberOfPieces());
  for (int p = 0; p < s.GetNumberOfPieces(); ++p)
  {
    EXPECT_TRUE(s.GetPiece(p, &out[p], &why)) << why;
  }
  return out;
}

TEST(Pieces, EachPieceIsTheRankOfTheSameNumber)
{
  const std::string tmp = FreshDirectory("pieces-same");
  Mesh closed = MakeMesh(true);
  const std::string binary =
    WritePLY(closed, "pieces-closed.ply", plodtest::PLYEncoding::Little, "float", true);
  Mesh open = MakeMesh(false);
  const std::string ascii =
    WritePLY(open, "pieces-open.ply", plodtest::PLYEncoding::ASCII, "double", false);
  for (int pieces : { 1, 3, 5 })
  {
    const auto ranks = Partition(closed, pieces, 11);
    plod::PLYPieces split;
    const auto file = Pieces(binary, pieces, 2, tmp, &split);
    ASSERT_EQ(file.size(), size_t(pieces));
    EXPECT_GT(split.GetPeakTemporaryBytes(), 0);
    EXPECT_EQ(CountEntries(tmp), 1); // the split's own directory
    for (int p = 0; p < pieces; ++p)
    {
      ExpectSamePiece(file[p], ranks[p], p);
    }
  }
  EXPECT_EQ(CountEntries(tmp), 0) << "temporary files left behind";
  const auto ranks = Partition(open, 4, 5, false, -1, 3);
  const auto file = Pieces(ascii, 4, 3, tmp);
  ASSERT_EQ(file.size(), size_t(4));
  EXPECT_GT(file[0].NumberOfBoundaryEdges, 0);
  for (int p = 0; p < 4; ++p)
  {
    ExpectSamePiece(file[p], ranks[p], p);
  }
}

/// The node of `v` at (level, cell), or -1.
int64_t FindNode(const plod::OctreeView& v, int level, const int xyz[3])
{
  int64_t n = 0;
  for (int l = 1; l <= level && n >= 0; ++l)
  {
    const int shift = level - l;
    const int c =
      ((xyz[0] >> shift) & 1) | (((xyz[1] >> shift) & 1) << 1) | (((xyz[2] >> shift) & 1) << 2);
    n = v.Child(n, c);
  }
  return n;
}

// Built one after the other, the pieces give the whole mesh's octree in every cell of level k
// and finer that they own: the same vertex, cone, shape error, flags, clusters and points.
TEST(Pieces, EachPieceBuildsTheWholeOctreeInTheCellsItOwns)
{
  const std::string tmp = FreshDirectory("pieces-build");
  Mesh m = MakeMesh(false, 5);
  const std::string path =
    WritePLY(m, "pieces-build.ply", plodtest::PLYEncoding::Little, "float", true);
  const int k = 2;
  plod::PLYPieces split;
  const auto pieces = Pieces(path, 4, k, tmp, &split);
  ASSERT_EQ(pieces.size(), size_t(4));
  const plod::PartitionResult& agreed = split.GetAgreement();

  std::vector<float> normals(m.Normals.begin(), m.Normals.end());
  plod::BuildInput whole;
  whole.NumberOfPoints = static_cast<int64_t>(m.Points.size() / 3);
  whole.Points = m.Points.data();
  whole.NumberOfTriangles = static_cast<int64_t>(m.Triangles.size() / 3);
  whole.Triangles = m.Triangles.data();
  whole.PointNormals = normals.data();
  plod::BuildParameters params;
  params.FinestLevel = agreed.FinestLevel;
  params.HasRootCube = true;
  std::copy(agreed.RootOrigin, agreed.RootOrigin + 3, params.RootOrigin);
  params.RootEdge = agreed.RootEdge;
  plod::OctreeStorage wholeStorage;
  const plod::BuildResult wr = plod::BuildOctree(whole, params, wholeStorage.MakeAllocator());
  ASSERT_TRUE(wr.Ok) << wr.Error;
  const plod::OctreeView w = wholeStorage.View(wr);

  int64_t compared = 0, wholeNodes = 0;
  for (int64_t n = 0; n < w.NumberOfNodes; ++n)
  {
    wholeNodes += w.Level[n] >= k;
  }
  for (size_t p = 0; p < pieces.size(); ++p)
  {
    const plod::PartitionResult& r = pieces[p];
    std::vector<float> pn(r.Normals.begin(), r.Normals.end());
    plod::BuildInput in;
    in.NumberOfPoints = static_cast<int64_t>(r.Ghost.size());
    in.Points = r.Points.data();
    in.NumberOfTriangles = static_cast<int64_t>(r.Triangles.size() / 3);
    in.Triangles = r.Triangles.data();
    in.PointNormals = pn.data();
    in.PointGhost = r.Ghost.data();
    plod::OctreeStorage storage;
    const plod::BuildResult br = plod::BuildOctree(in, params, storage.MakeAllocator());
    ASSERT_TRUE(br.Ok) << br.Error;
    const plod::OctreeView v = storage.View(br);
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
    {
      // a cell the piece owns: its first point is not a ghost (every point of an owned cell is
      // owned, every point of another's cell a ghost)
      if (v.Level[n] < k || v.PointGhost[v.FirstPoint[n]])
      {
        continue;
      }
      int xyz[3];
      v.CellCoordinates(n, xyz);
      const int64_t o = FindNode(w, v.Level[n], xyz);
      ASSERT_GE(o, 0) << "piece " << p << " has a cell the whole has not";
      ++compared;
      EXPECT_EQ(v.PointEnd(n) - v.FirstPoint[n], w.PointEnd(o) - w.FirstPoint[o]);
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(v.Vertex[3 * n + a], w.Vertex[3 * o + a]) << "node " << n;
        EXPECT_EQ(v.ConeAxis[3 * n + a], w.ConeAxis[3 * o + a]) << "node " << n;
      }
      EXPECT_EQ(v.ConeAngle[n], w.ConeAngle[o]);
      EXPECT_EQ(v.ShapeError[n], w.ShapeError[o]);
      EXPECT_EQ(v.Flags[n], w.Flags[o]);
      EXPECT_EQ(v.Thickness[n], w.Thickness[o]);
      ASSERT_EQ(v.ClusterEnd(n) - v.FirstCluster[n], w.ClusterEnd(o) - w.FirstCluster[o]);
      for (int64_t c = 0; c < v.ClusterEnd(n) - v.FirstCluster[n]; ++c)
      {
        for (int a = 0; a < 3; ++a)
        {
          EXPECT_EQ(v.ClusterVertex[3 * (v.FirstCluster[n] + c) + a],
            w.ClusterVertex[3 * (w.FirstCluster[o] + c) + a]);
        }
      }
      for (int64_t i = 0; i < v.PointEnd(n) - v.FirstPoint[n]; ++i)
      {
        for (int a = 0; a < 3; ++a)
        {
          EXPECT_EQ(
            v.Points[3 * (v.FirstPoint[n] + i) + a], w.Points[3 * (w.FirstPoint[o] + i) + a]);
        }
      }
    }
  }
  EXPECT_EQ(compared, wholeNodes) << "every node of level k and finer is owned by one piece";
}

TEST(Pieces, SizedByTheMemoryLimit)
{
  const std::string tmp = FreshDirectory("pieces-memory");
  Mesh m = MakeMesh(true, 5);
  const std::string path =
    WritePLY(m, "pieces-memory.ply", plodtest::PLYEncoding::Little, "float", true);
  const double triangles = double(m.Triangles.size() / 3);
  for (double fraction : { 2.0, 0.3, 0.1 })
  {
    plod::PiecesParameters params;
    params.OwnershipLevel = 4;
    params.TemporaryDirectory = tmp;
    params.MemoryLimit = fraction * triangles * plod::PieceBytesPerTriangle(true);
    plod::PLYPieces split;
    std::string why;
    ASSERT_TRUE(split.Open(path, params, &why)) << why;
    // as many as the first guess (a quarter more for the halo), or more when a piece with
    // its halo would not fit
    EXPECT_GE(split.GetNumberOfPieces(), static_cast<int>(std::ceil(1.25 / fraction)))
      << "fraction " << fraction;
    EXPECT_EQ(split.GetNumberOfPieces() == 1, fraction >= 1.25);
    int64_t drawn = 0;
    for (int p = 0; p < split.GetNumberOfPieces(); ++p)
    {
      plod::PartitionResult r;
      ASSERT_TRUE(split.GetPiece(p, &r, &why)) << why;
      EXPECT_LE(
        double(r.Triangles.size() / 3) * plod::PieceBytesPerTriangle(true), params.MemoryLimit)
        << "piece " << p << " of " << split.GetNumberOfPieces();
      drawn += static_cast<int64_t>(r.Triangles.size() / 3) - r.NumberOfHaloTriangles;
    }
    EXPECT_GE(drawn, static_cast<int64_t>(triangles));
  }
  EXPECT_EQ(CountEntries(tmp), 0);
}

// Faults: the file, the folder, the disk, the caller; each names what was wrong and leaves no
// temporary file behind.
TEST(Pieces, FaultsSayWhatWasWrongAndLeaveNoTemporaryFiles)
{
  const std::string tmp = FreshDirectory("pieces-faults");
  Mesh m = MakeMesh(true, 4);
  const std::string path =
    WritePLY(m, "pieces-faults.ply", plodtest::PLYEncoding::Little, "float", false);
  auto refused = [&](const std::string& file, plod::PiecesParameters params,
                   const std::string& expected) {
    if (params.TemporaryDirectory.empty())
    {
      params.TemporaryDirectory = tmp;
    }
    plod::PLYPieces split;
    std::string why;
    EXPECT_FALSE(split.Open(file, params, &why));
    EXPECT_NE(why.find(expected), std::string::npos) << why;
    EXPECT_EQ(split.GetNumberOfPieces(), 0);
    EXPECT_EQ(CountEntries(tmp), 0) << "after: " << why;
    plod::PartitionResult r;
    EXPECT_FALSE(split.GetPiece(0, &r, &why));
  };
  plod::PiecesParameters params;
  params.NumberOfPieces = 3;
  params.OwnershipLevel = 2;

  // a file cut inside its faces
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string cut = ::testing::TempDir() + "pieces-cut.ply";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 100);
  refused(cut, params, "the file ends inside element 'face'");
  refused(::testing::TempDir() + "pieces-missing.ply", params, "cannot open");

  // more pieces than occupied cells, a bad level, no way to size the pieces
  plod::PiecesParameters many = params;
  many.NumberOfPieces = 1000;
  refused(path, many, "cells of level 2 are occupied");
  plod::PiecesParameters tiny = params;
  tiny.NumberOfPieces = 0;
  tiny.MemoryLimit = 1e4; // a few dozen triangles: not even a cell with its halo
  refused(path, tiny, "use a deeper ownership level or more memory");
  plod::PiecesParameters level = params;
  level.OwnershipLevel = 7;
  refused(path, level, "ownership level");
  plod::PiecesParameters sized = params;
  sized.NumberOfPieces = 0;
  sized.MemoryLimit = 0;
  refused(path, sized, "memory limit");

  // an abort from the progress callback, at each step
  for (const char* step : plod::SplitSteps)
  {
    plod::PiecesParameters abort = params;
    std::set<std::string> seen;
    abort.Progress = [&](double f, const char* s) {
      EXPECT_GE(f, 0.0);
      EXPECT_LE(f, 1.0);
      seen.insert(s);
      return std::string(s) != step;
    };
    refused(path, abort, "aborted");
    EXPECT_EQ(seen.count(step), 1u) << step;
  }

  // a folder that cannot hold the temporary directory
  plod::PiecesParameters nowhere = params;
  nowhere.TemporaryDirectory = path; // a file, not a folder
  refused(path, nowhere, "cannot make a temporary directory");

  // a full disk: the files may not grow past 64 KB (in a child process, as the limit is
  // per process); the write that fails is named and the directory removed
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0)
  {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = { 65536, 65536 };
    setrlimit(RLIMIT_FSIZE, &limit);
    plod::PiecesParameters full = params;
    full.TemporaryDirectory = tmp;
    plod::PLYPieces split;
    std::string why;
    const bool ok = split.Open(path, full, &why);
    const bool named = why.find("cannot write the temporary file") != std::string::npos;
    _exit(!ok && named && CountEntries(tmp) == 0 ? 0 : 1);
  }
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the full disk was not reported";
  EXPECT_EQ(CountEntries(tmp), 0);

  // a mesh with a non-finite point: its triangles are skipped and counted
  Mesh bad = MakeMesh(true, 2);
  bad.Points[0] = std::nan("");
  const std::string nan =
    WritePLY(bad, "pieces-nan.ply", plodtest::PLYEncoding::Little, "float", false);
  plod::PLYPieces split;
  const auto pieces = Pieces(nan, 2, 2, tmp, &split);
  EXPECT_EQ(pieces.size(), 2u);
  int64_t uses = 0;
  for (size_t t = 0; t < bad.Triangles.size(); ++t)
  {
    uses += bad.Triangles[t] == 0;
  }
  EXPECT_EQ(split.GetAgreement().NumberOfSkippedTriangles, uses);
}

//------------------------------------------------------------------------------
// The octree file of the pieces

/// The whole mesh's octree, built in memory with the pieces' root cube and finest level.
struct WholeOctree
{
  plod::OctreeStorage Storage;
  plod::OctreeView View;
  std::vector<float> Normals;

  WholeOctree(const Mesh& m, const plod::PartitionResult& agreed)
    : Normals(m.Normals.begin(), m.Normals.end())
  {
    plod::BuildInput in;
    in.NumberOfPoints = static_cast<int64_t>(m.Points.size() / 3);
    in.Points = m.Points.data();
    in.NumberOfTriangles = static_cast<int64_t>(m.Triangles.size() / 3);
    in.Triangles = m.Triangles.data();
    in.PointNormals = this->Normals.empty() ? nullptr : this->Normals.data();
    plod::BuildParameters params;
    params.FinestLevel = agreed.FinestLevel;
    params.HasRootCube = true;
    std::copy(agreed.RootOrigin, agreed.RootOrigin + 3, params.RootOrigin);
    params.RootEdge = agreed.RootEdge;
    const plod::BuildResult r = plod::BuildOctree(in, params, this->Storage.MakeAllocator());
    EXPECT_TRUE(r.Ok) << r.Error;
    this->View = this->Storage.View(r);
  }
};

/// The triangles each node owns, as sorted sets of corner triples.
std::vector<std::set<std::array<int32_t, 3>>> OwnedTriangles(const plod::OctreeView& v)
{
  std::vector<std::set<std::array<int32_t, 3>>> owned(v.NumberOfNodes);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    for (int64_t t = v.FirstTriangle[n]; t < v.TriangleEnd(n); ++t)
    {
      owned[n].insert({ v.Triangles[3 * t], v.Triangles[3 * t + 1], v.Triangles[3 * t + 2] });
    }
  }
  return owned;
}

// Built piece by piece and put together, the octree file equals the whole mesh's octree at
// levels k and finer, node for node (clusters shifted by the levels above, which hold one
// cluster per node), and has its structure above: the same nodes, points and owned triangles.
TEST(Pieces, TheirOctreeFileIsTheWholeOctreeFromLevelKOn)
{
  const std::string tmp = FreshDirectory("pieces-file");
  for (bool closed : { false, true })
  {
    SCOPED_TRACE(closed ? "closed" : "open");
    Mesh m = MakeMesh(closed, 5);
    const std::string ply =
      WritePLY(m, "pieces-file.ply", plodtest::PLYEncoding::Little, "float", true);
    const int k = 2;
    plod::PLYPieces split;
    const auto pieces = Pieces(ply, 4, k, tmp, &split);
    ASSERT_EQ(pieces.size(), 4u);
    const std::string path = ::testing::TempDir() + "pieces-file.plod";
    plod::AssemblyParameters params;
    plod::AssemblyReport report;
    std::set<std::string> steps;
    params.Progress = [&](double, const char* step) {
      steps.insert(step);
      return true;
    };
    std::string why;
    ASSERT_TRUE(plod::WriteOctreeFileFromPieces(split, path, params, &report, &why)) << why;
    EXPECT_EQ(steps, (std::set<std::string>{ "building the pieces", "writing the file" }));
    EXPECT_EQ(CountEntries(tmp), 1) << "the assembly's temporary files are removed";

    plod::OctreeFile file;
    ASSERT_TRUE(plod::OpenOctreeFile(path, true, true, file, &why)) << why;
    plod::OctreeView f;
    ASSERT_TRUE(plod::ViewOfFile(file, f, &why)) << why;
    ASSERT_TRUE(plod::ValidateOctree(f, &why)) << why;
    EXPECT_EQ(file.Header.CoarsestDrawnLevel, 0) << "the levels above k are drawn";
    EXPECT_EQ(report.StructureOnly, "");
    EXPECT_EQ(file.Header.BoundaryEdges, split.GetAgreement().NumberOfBoundaryEdges);
    EXPECT_EQ(closed, file.Header.BoundaryEdges == 0);
    EXPECT_EQ(report.NumberOfNodes, f.NumberOfNodes);
    EXPECT_EQ(report.FileBytes, static_cast<int64_t>(file.Identity.Size));

    WholeOctree whole(m, split.GetAgreement());
    const plod::OctreeView& w = whole.View;
    ASSERT_EQ(f.NumberOfNodes, w.NumberOfNodes);
    ASSERT_EQ(f.NumberOfPoints, w.NumberOfPoints);
    ASSERT_EQ(f.NumberOfTriangles, w.NumberOfTriangles);
    int64_t structure = 0;
    while (structure < w.NumberOfNodes && w.Level[structure] < k)
    {
      ++structure;
    }
    EXPECT_EQ(report.NumberOfStructureNodes, 0);
    const int64_t shift = w.FirstCluster[structure] - f.FirstCluster[structure];
    for (int64_t n = 0; n < w.NumberOfNodes; ++n)
    {
      // the structure: the same tree, points and owned triangles
      EXPECT_EQ(f.Level[n], w.Level[n]);
      EXPECT_EQ(f.Parent[n], w.Parent[n]);
      EXPECT_EQ(f.FirstChild[n], w.FirstChild[n]);
      EXPECT_EQ(f.ChildMask[n], w.ChildMask[n]);
      EXPECT_EQ(f.FirstPoint[n], w.FirstPoint[n]);
      EXPECT_EQ(f.FirstTriangle[n], w.FirstTriangle[n]);
      if (w.Level[n] < k)
      {
        continue;
      }
      ASSERT_EQ(f.FirstCluster[n] + shift, w.FirstCluster[n]) << "node " << n;
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(f.Vertex[3 * n + a], w.Vertex[3 * n + a]) << n;
        EXPECT_EQ(f.ConeAxis[3 * n + a], w.ConeAxis[3 * n + a]) << n;
      }
      EXPECT_EQ(f.ConeAngle[n], w.ConeAngle[n]) << n;
      EXPECT_EQ(f.ShapeError[n], w.ShapeError[n]) << n;
      EXPECT_EQ(f.Flags[n], w.Flags[n]) << n;
      EXPECT_EQ(f.Thickness[n], w.Thickness[n]) << n;
      for (int a = 0; a < 2; ++a)
      {
        EXPECT_EQ(f.DiffuseRange[2 * n + a], w.DiffuseRange[2 * n + a]) << n;
        EXPECT_EQ(f.SpecularRange[2 * n + a], w.SpecularRange[2 * n + a]) << n;
      }
    }
    for (int64_t c = f.FirstCluster[structure]; c < f.NumberOfClusters; ++c)
    {
      EXPECT_EQ(f.ClusterNode[c], w.ClusterNode[c + shift]);
      const int32_t parent = w.ClusterParent[c + shift];
      if (w.Level[w.ClusterNode[c + shift]] > k)
      {
        EXPECT_EQ(f.ClusterParent[c], parent - shift);
      }
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(f.ClusterVertex[3 * c + a], w.ClusterVertex[3 * (c + shift) + a]);
        EXPECT_EQ(f.ClusterNormal[3 * c + a], w.ClusterNormal[3 * (c + shift) + a]);
      }
    }
    for (int64_t q = 0; q < f.NumberOfPoints; ++q)
    {
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(f.Points[3 * q + a], w.Points[3 * q + a]) << q;
        EXPECT_EQ(f.Normals[3 * q + a], w.Normals[3 * q + a]) << q;
      }
      EXPECT_EQ(f.PointLeaf[q], w.PointLeaf[q]);
      EXPECT_EQ(f.PointCluster[q] + shift, w.PointCluster[q]);
      EXPECT_EQ(f.InputPointId[q], -1);
    }
    EXPECT_EQ(OwnedTriangles(f), OwnedTriangles(w));
    std::remove(path.c_str());
  }
  EXPECT_EQ(CountEntries(tmp), 0);
}

/// The cluster of level `level` holding point q.
int64_t ClusterAt(const plod::OctreeView& v, int64_t q, int level)
{
  int64_t c = v.PointCluster[q];
  while (v.Level[v.ClusterNode[c]] > level)
  {
    c = v.ClusterParent[c];
  }
  return c;
}

/// The angle between two unit vectors.
double AngleBetween(const float* a, const double* b)
{
  const double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::acos(std::min(1.0, std::max(-1.0, d)));
}

// The levels above k of the file built in pieces come from the octree of the level-k cut. They
// are not the whole mesh's node for node; what they promise, on a scan-like model split in 4:
// the same tree, points and owned triangles; the same material ranges and boundary flags;
// vertices inside their cells; as many clusters as the whole's in nine cells of ten (two sheets
// share the cells here); the whole's topology flags in 85 % of the cells, here never safe where
// the whole's cell is not, a thickness where unsafe; a cone that holds the normal of every triangle
// with a corner in the cell; an error at least that of each level-k cell inside; each point's
// cluster at a level above k with a vertex near the whole octree's (0.15 of a cell on average, half
// a cell at most); a cluster tree the validation accepts.
TEST(Pieces, TheirLevelsAboveKFollowTheWholeOctree)
{
  const std::string tmp = FreshDirectory("pieces-coarse");
  const std::string ply = ::testing::TempDir() + "pieces-coarse.ply";
  plodtest::ScanCounts counts;
  std::string why;
  ASSERT_TRUE(plodtest::GenerateScanPLY(plodtest::OctahedralSphere(3), 6, 11, ply, &counts, &why))
    << why;
  plod::PLYMesh read;
  ASSERT_TRUE(plod::ReadPLYMesh(ply, &read, &why)) << why;
  // the scan and a copy of it shrunk inside: two sheets in every cell of the top levels, each
  // its own cluster there
  Mesh m;
  for (double scale : { 1.0, 0.8 })
  {
    const int64_t base = static_cast<int64_t>(m.Points.size() / 3);
    for (float x : read.PointsFloat)
    {
      m.Points.push_back(scale * x);
    }
    for (int32_t i : read.Triangles)
    {
      m.Triangles.push_back(base + i);
    }
  }
  const std::string sheets =
    WritePLY(m, "pieces-coarse-sheets.ply", plodtest::PLYEncoding::Little, "float", false);
  const int k = 3;
  plod::PLYPieces split;
  ASSERT_EQ(Pieces(sheets, 4, k, tmp, &split).size(), 4u);
  const std::string path = ::testing::TempDir() + "pieces-coarse.plod";
  plod::AssemblyReport report;
  ASSERT_TRUE(plod::WriteOctreeFileFromPieces(split, path, {}, &report, &why)) << why;
  EXPECT_EQ(report.StructureOnly, "");
  plod::OctreeFile file;
  ASSERT_TRUE(plod::OpenOctreeFile(path, true, true, file, &why)) << why;
  plod::OctreeView f;
  ASSERT_TRUE(plod::ViewOfFile(file, f, &why)) << why;
  ASSERT_TRUE(plod::ValidateOctree(f, &why)) << why;
  EXPECT_EQ(file.Header.CoarsestDrawnLevel, 0);
  WholeOctree whole(m, split.GetAgreement());
  const plod::OctreeView& w = whole.View;
  ASSERT_EQ(f.NumberOfNodes, w.NumberOfNodes);
  ASSERT_EQ(f.NumberOfPoints, w.NumberOfPoints);
  EXPECT_EQ(OwnedTriangles(f), OwnedTriangles(w));

  int64_t structure = 0;
  while (w.Level[structure] < k)
  {
    ++structure;
  }
  int64_t sameClusterCount = 0, severalClusters = 0, sameSafety = 0;
  for (int64_t n = 0; n < structure; ++n)
  {
    EXPECT_EQ(f.Level[n], w.Level[n]);
    EXPECT_EQ(f.ChildMask[n], w.ChildMask[n]);
    EXPECT_EQ(f.FirstPoint[n], w.FirstPoint[n]);
    EXPECT_EQ(f.Flags[n] & plod::NodeBoundary, w.Flags[n] & plod::NodeBoundary) << n;
    for (int a = 0; a < 2; ++a)
    {
      EXPECT_EQ(f.DiffuseRange[2 * n + a], w.DiffuseRange[2 * n + a]) << n;
      EXPECT_EQ(f.SpecularRange[2 * n + a], w.SpecularRange[2 * n + a]) << n;
    }
    const double edge = f.RootEdge / double(1 << f.Level[n]);
    int xyz[3];
    f.CellCoordinates(n, xyz);
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_GE(f.Vertex[3 * n + a], edge * xyz[a]) << "inside its cell: node " << n;
      EXPECT_LE(f.Vertex[3 * n + a], edge * (xyz[a] + 1)) << "inside its cell: node " << n;
    }
    EXPECT_GE(f.ShapeError[n], 0.0f);
    sameClusterCount += f.ClusterEnd(n) - f.FirstCluster[n] == w.ClusterEnd(n) - w.FirstCluster[n];
    severalClusters += w.ClusterEnd(n) - w.FirstCluster[n] > 1;
    const bool safe = f.Flags[n] & plod::NodeTopologySafe;
    sameSafety += safe == bool(w.Flags[n] & plod::NodeTopologySafe);
    EXPECT_TRUE(!safe || (w.Flags[n] & plod::NodeTopologySafe)) << "unsafe in the whole: " << n;
    EXPECT_EQ(f.Thickness[n] > 0, !safe) << "a thickness for an unsafe cell only: " << n;
  }
  EXPECT_GT(severalClusters, structure / 2) << "the two sheets share cells";
  EXPECT_GE(10 * sameClusterCount, 9 * structure) << "as many clusters as the whole's";
  EXPECT_GE(100 * sameSafety, 85 * structure) << "the whole's topology flags";
  // an error at least the largest of the level-k cells inside
  for (int64_t n = structure; n < f.NumberOfNodes && f.Level[n] == k; ++n)
  {
    for (int64_t a = f.Parent[n]; a >= 0; a = f.Parent[a])
    {
      EXPECT_GE(f.ShapeError[a], f.ShapeError[n]) << "node " << a << " above " << n;
    }
  }

  // every triangle's normal lies in the cone of each cell above k holding one of its corners
  for (int64_t t = 0; t < f.NumberOfTriangles; ++t)
  {
    const int32_t* c = f.Triangles + 3 * t;
    double e1[3], e2[3], normal[3];
    for (int a = 0; a < 3; ++a)
    {
      e1[a] = double(f.Points[3 * c[1] + a]) - f.Points[3 * c[0] + a];
      e2[a] = double(f.Points[3 * c[2] + a]) - f.Points[3 * c[0] + a];
    }
    normal[0] = e1[1] * e2[2] - e1[2] * e2[1];
    normal[1] = e1[2] * e2[0] - e1[0] * e2[2];
    normal[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double length =
      std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (length == 0)
    {
      continue;
    }
    for (double& x : normal)
    {
      x /= length;
    }
    for (int corner = 0; corner < 3; ++corner)
    {
      for (int64_t n = f.PointLeaf[c[corner]]; n >= 0; n = f.Parent[n])
      {
        if (f.Level[n] < k)
        {
          ASSERT_LE(AngleBetween(&f.ConeAxis[3 * n], normal), f.ConeAngle[n] + 1e-4)
            << "triangle " << t << " node " << n;
        }
      }
    }
  }

  // each point's cluster vertex at the levels above k, against the whole octree's
  for (int l = 0; l < k; ++l)
  {
    const double edge = f.RootEdge / double(1 << l);
    double sum = 0, worst = 0;
    for (int64_t q = 0; q < f.NumberOfPoints; ++q)
    {
      const float* a = &f.ClusterVertex[3 * ClusterAt(f, q, l)];
      const float* b = &w.ClusterVertex[3 * ClusterAt(w, q, l)];
      const double d =
        std::sqrt(double(a[0] - b[0]) * (a[0] - b[0]) + double(a[1] - b[1]) * (a[1] - b[1]) +
          double(a[2] - b[2]) * (a[2] - b[2])) /
        edge;
      sum += d;
      worst = std::max(worst, d);
    }
    EXPECT_LT(sum / f.NumberOfPoints, 0.15) << "level " << l;
    EXPECT_LT(worst, 0.5) << "level " << l;
  }
  std::remove(path.c_str());
  std::remove(ply.c_str());
  std::remove(sheets.c_str());
}

/// The bytes of a file.
std::string FileBytes(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Once split, only the pieces' files remain (the file's points are in them); an assembly that
// removes each piece as it reads it writes the same octree file with fewer temporary bytes at
// its peak, leaves the split no file, and a removed piece cannot be read again.
TEST(Pieces, RemovedAsBuiltTheyLeaveLessOnDiskAndTheSameFile)
{
  const std::string tmp = FreshDirectory("pieces-removed");
  Mesh m = MakeMesh(true, 5);
  const std::string ply =
    WritePLY(m, "pieces-removed.ply", plodtest::PLYEncoding::Little, "float", true);
  std::string files[2];
  plod::AssemblyReport reports[2];
  for (int removing = 0; removing < 2; ++removing)
  {
    plod::PLYPieces split;
    ASSERT_EQ(Pieces(ply, 4, 2, tmp, &split).size(), 4u);
    EXPECT_EQ(CountEntries(split.GetTemporaryDirectory()), 4) << "one file per piece, no more";
    EXPECT_LT(split.GetTemporaryBytes(), split.GetPeakTemporaryBytes());
    files[removing] = ::testing::TempDir() + "pieces-removed-" + std::to_string(removing) + ".plod";
    plod::AssemblyParameters params;
    params.RemovePiecesAsBuilt = removing;
    std::string why;
    ASSERT_TRUE(
      plod::WriteOctreeFileFromPieces(split, files[removing], params, &reports[removing], &why))
      << why;
    EXPECT_EQ(CountEntries(split.GetTemporaryDirectory()), removing ? 0 : 4);
    EXPECT_EQ(split.GetTemporaryBytes() == 0, bool(removing));
    plod::PartitionResult piece;
    EXPECT_EQ(split.GetPiece(1, &piece, &why), !removing);
    EXPECT_EQ(why, removing ? "piece 1 was removed" : "");
  }
  EXPECT_EQ(FileBytes(files[0]), FileBytes(files[1]));
  EXPECT_LT(reports[1].PeakTemporaryBytes, reports[0].PeakTemporaryBytes);
  EXPECT_GT(reports[1].PeakTemporaryBytes, 0);
  std::remove(files[0].c_str());
  std::remove(files[1].c_str());
}

// A failed assembly (an abort at each step, a folder that does not exist) leaves the target as
// it was and removes its own temporary files.
TEST(Pieces, AFailedOctreeFileLeavesTheTargetAndNoTemporaryFile)
{
  const std::string tmp = FreshDirectory("pieces-file-faults");
  Mesh m = MakeMesh(true, 4);
  const std::string ply =
    WritePLY(m, "pieces-file-faults.ply", plodtest::PLYEncoding::Little, "float", false);
  plod::PLYPieces split;
  ASSERT_EQ(Pieces(ply, 2, 2, tmp, &split).size(), 2u);
  const int before = CountEntries(split.GetTemporaryDirectory());
  const std::string target = ::testing::TempDir() + "pieces-file-faults.plod";
  std::ofstream(target) << "the old file";
  for (const char* step : { "building the pieces", "writing the file" })
  {
    plod::AssemblyParameters params;
    params.Progress = [&](double, const char* s) { return std::string(s) != step; };
    std::string why;
    EXPECT_FALSE(plod::WriteOctreeFileFromPieces(split, target, params, nullptr, &why));
    EXPECT_EQ(why, "aborted") << step;
    std::ifstream in(target);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "the old file") << step;
    EXPECT_EQ(CountEntries(split.GetTemporaryDirectory()), before) << step;
  }
  std::string why;
  EXPECT_FALSE(plod::WriteOctreeFileFromPieces(
    split, ::testing::TempDir() + "no-such-folder/x.plod", {}, nullptr, &why));
  EXPECT_NE(why.find("no-such-folder"), std::string::npos) << why;
  EXPECT_EQ(CountEntries(split.GetTemporaryDirectory()), before);
  plod::PLYPieces none;
  EXPECT_FALSE(plod::WriteOctreeFileFromPieces(none, target, {}, nullptr, &why));
  EXPECT_NE(why.find("no pieces"), std::string::npos) << why;
  std::remove(target.c_str());
}

} // namespace
