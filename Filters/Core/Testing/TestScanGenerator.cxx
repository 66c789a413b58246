// SPDX-License-Identifier: BSD-3-Clause
// Tests of the scan-like model generator (Testing/plodScanGenerator.h), read back with
// plod::ReadPLYMesh: the counts follow the formula, a closed base gives a closed, consistently
// oriented model without duplicated points, the shape stays the base's, the noise changes with
// the seed, and a file that cannot be written leaves nothing behind.
#include "plodPLYCheck.h"
#include "plodPLYRead.h"
#include "plodScanGenerator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

std::string TempPath(const std::string& name)
{
  return (
    fs::temp_directory_path() / ("plod_scan_" + std::to_string(::getpid()) + "_" + name + ".ply"))
    .string();
}

TEST(ScanGenerator, ClosedBaseGivesAClosedModelWithTheFormulasCounts)
{
  const plodtest::BaseMesh base = plodtest::OctahedralSphere(1); // 32 triangles, 48 edges
  for (int n : { 1, 2, 3, 7 })
  {
    const std::string path = TempPath("closed");
    plodtest::ScanCounts counts;
    std::string why;
    ASSERT_TRUE(plodtest::GenerateScanPLY(base, n, 1, path, &counts, &why)) << why;
    const int64_t V = 18, E = 48, T = 32;
    EXPECT_EQ(counts.Points, V + E * (n - 1) + T * (n - 1) * (n - 2) / 2) << n;
    EXPECT_EQ(counts.Triangles, T * n * n) << n;
    ASSERT_TRUE(plod::CheckPLYFile(path, &why)) << why;
    plod::PLYMesh m;
    ASSERT_TRUE(plod::ReadPLYMesh(path, &m, &why)) << why;
    EXPECT_EQ(m.NumberOfPoints, counts.Points);
    ASSERT_EQ(m.NumberOfTriangles(), counts.Triangles);
    EXPECT_EQ(static_cast<int64_t>(fs::file_size(path)), counts.Bytes);
    // every directed edge once and its reverse once: closed and consistently oriented
    std::map<std::pair<int32_t, int32_t>, int> directed;
    std::vector<bool> used(m.NumberOfPoints, false);
    for (int64_t t = 0; t < m.NumberOfTriangles(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const int32_t a = m.Triangles[3 * t + k], b = m.Triangles[3 * t + (k + 1) % 3];
        ASSERT_NE(a, b) << "degenerate triangle " << t;
        ++directed[{ a, b }];
        used[a] = true;
      }
    }
    for (const auto& [edge, count] : directed)
    {
      ASSERT_EQ(count, 1) << n << ": edge used twice in one direction";
      ASSERT_EQ(directed.count({ edge.second, edge.first }), 1u) << n << ": open edge";
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unused points";
    // no duplicated points, all near the unit sphere
    std::set<std::array<float, 3>> positions;
    for (int64_t p = 0; p < m.NumberOfPoints; ++p)
    {
      const float* x = &m.PointsFloat[3 * p];
      positions.insert({ x[0], x[1], x[2] });
      const double r = std::sqrt(double(x[0]) * x[0] + double(x[1]) * x[1] + double(x[2]) * x[2]);
      EXPECT_GT(r, 0.4);
      EXPECT_LT(r, 1.3);
    }
    EXPECT_EQ(static_cast<int64_t>(positions.size()), m.NumberOfPoints) << n;
    fs::remove(path);
  }
}

TEST(ScanGenerator, TheSeedChangesTheNoiseAndTheSameSeedRepeatsIt)
{
  const plodtest::BaseMesh base = plodtest::OctahedralSphere(1);
  std::string why;
  plod::PLYMesh m[3];
  const uint64_t seeds[3] = { 1, 1, 2 };
  for (int k = 0; k < 3; ++k)
  {
    const std::string path = TempPath("seed" + std::to_string(k));
    ASSERT_TRUE(plodtest::GenerateScanPLY(base, 4, seeds[k], path, nullptr, &why)) << why;
    ASSERT_TRUE(plod::ReadPLYMesh(path, &m[k], &why)) << why;
    fs::remove(path);
  }
  EXPECT_EQ(m[0].PointsFloat, m[1].PointsFloat);
  EXPECT_NE(m[0].PointsFloat, m[2].PointsFloat);
  EXPECT_EQ(m[0].Triangles, m[2].Triangles);
}

TEST(ScanGenerator, AFileThatCannotBeWrittenLeavesNothing)
{
  const std::string folder = TempPath("no_such_folder");
  const std::string path = folder + "/model.ply";
  std::string why;
  EXPECT_FALSE(plodtest::GenerateScanPLY(plodtest::OctahedralSphere(0), 2, 1, path, nullptr, &why));
  EXPECT_NE(why.find("cannot write"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_FALSE(fs::exists(path));
  // a split too fine to hold one base triangle's points at once is refused before writing
  const std::string fine = TempPath("too_fine");
  EXPECT_FALSE(plodtest::GenerateScanPLY(
    plodtest::OctahedralSphere(0), plodtest::MaxScanSplit + 1, 1, fine, nullptr, &why));
  EXPECT_NE(why.find("more than"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(fine));
}

} // namespace
