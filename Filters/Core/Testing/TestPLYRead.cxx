// SPDX-License-Identifier: BSD-3-Clause
// Tests of plod::ReadPLYMesh and plod::ReadPLYHeader: every valid sample is read with its points
// and its faces as fans, in every encoding and type; every corrupt sample but those only VTK's
// reader cannot take is refused with an empty mesh; every cut of a body is refused; the header
// alone gives the counts and the memory estimate; normals and double coordinates are kept;
// the Stanford files read when ../shared/data is there.
#include "plodPLYRead.h"
#include "plodPLYSamples.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

class PLYRead : public ::testing::Test
{
protected:
  void SetUp() override
  {
    this->Folder =
      (fs::temp_directory_path() / ("plod_ply_read_" + std::to_string(::getpid()))).string();
    fs::create_directories(this->Folder);
  }
  void TearDown() override
  {
    std::error_code error;
    fs::remove_all(this->Folder, error);
  }

  std::string Write(const std::string& name, const std::string& bytes)
  {
    const std::string path = this->Folder + "/" + name + ".ply";
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  std::string Folder;
};

const double Tetra[4][3] = { { 1, 1, 1 }, { 1, -1, -1 }, { -1, 1, -1 }, { -1, -1, 1 } };

void ExpectTetraPoints(const plod::PLYMesh& m)
{
  ASSERT_EQ(m.NumberOfPoints, 4);
  for (int p = 0; p < 4; ++p)
  {
    for (int a = 0; a < 3; ++a)
    {
      const double v =
        m.PointsDouble.empty() ? m.PointsFloat[3 * p + a] : m.PointsDouble[3 * p + a];
      EXPECT_EQ(v, Tetra[p][a]) << p << " " << a;
    }
  }
}

TEST_F(PLYRead, TetrahedronInEveryEncodingAndIndexType)
{
  const plodtest::PLYEncoding encodings[3] = { plodtest::PLYEncoding::ASCII,
    plodtest::PLYEncoding::Little, plodtest::PLYEncoding::Big };
  for (auto enc : encodings)
  {
    for (const char* index : { "char", "uchar", "short", "ushort", "int", "uint" })
    {
      for (const char* coord : { "float", "double" })
      {
        plodtest::TetraPLY t;
        t.Encoding = enc;
        t.IndexType = index;
        t.CoordType = coord;
        const std::string path = this->Write("tetra", t.Bytes());
        plod::PLYMesh m;
        std::string why;
        ASSERT_TRUE(plod::ReadPLYMesh(path, &m, &why)) << why << " " << index << " " << coord;
        EXPECT_EQ(m.PointsDouble.empty(), std::string(coord) == "float");
        ExpectTetraPoints(m);
        EXPECT_TRUE(m.Normals.empty());
        const std::vector<int32_t> want = { 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2 };
        EXPECT_EQ(m.Triangles, want);
        EXPECT_EQ(m.NumberOfFaces, 4);
      }
    }
  }
}

TEST_F(PLYRead, PolygonsBecomeFansAndShortFacesAreDropped)
{
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Little;
  t.Faces = { { 0, 1, 2, 3 }, { 0, 3 }, { 0, 2, 3 }, { 1, 3, 2, 0, 1 } };
  const std::string path = this->Write("fans", t.Bytes());
  plod::PLYMesh m;
  std::string why;
  ASSERT_TRUE(plod::ReadPLYMesh(path, &m, &why)) << why;
  const std::vector<int32_t> want = { 0, 1, 2, 0, 2, 3, 0, 2, 3, 1, 3, 2, 1, 2, 0, 1, 0, 1 };
  EXPECT_EQ(m.Triangles, want);
  EXPECT_EQ(m.NumberOfShortFaces, 1);
  EXPECT_EQ(m.NumberOfSplitFaces, 2);
}

TEST_F(PLYRead, NormalsAndOtherPropertiesAndElements)
{
  for (auto enc : { plodtest::PLYEncoding::ASCII, plodtest::PLYEncoding::Big })
  {
    std::string h = std::string("ply\nformat ") + plodtest::PLYFormatWord(enc) + " 1.0\n" +
      "element camera 1\nproperty list uchar float pose\n" +
      "element vertex 3\nproperty uchar red\nproperty float nz\nproperty double x\n" +
      "property float y\nproperty float z\nproperty float nx\nproperty float ny\n" +
      "element face 1\nproperty uchar flags\nproperty list uchar uint vertex_indices\n" +
      "property list uchar int texture\nend_header\n";
    std::string b;
    plodtest::PutPLYValue(b, "uchar", 2, enc);
    plodtest::PutPLYValue(b, "float", 0.5, enc);
    plodtest::PutPLYValue(b, "float", 1.5, enc);
    plodtest::EndPLYRow(b, enc);
    for (int p = 0; p < 3; ++p)
    {
      plodtest::PutPLYValue(b, "uchar", 200, enc);
      plodtest::PutPLYValue(b, "float", 3 + p, enc); // nz
      plodtest::PutPLYValue(b, "double", 1e8 + p, enc);
      plodtest::PutPLYValue(b, "float", -p, enc);
      plodtest::PutPLYValue(b, "float", 0.25 * p, enc);
      plodtest::PutPLYValue(b, "float", 1 + p, enc); // nx
      plodtest::PutPLYValue(b, "float", 2 + p, enc); // ny
      plodtest::EndPLYRow(b, enc);
    }
    plodtest::PutPLYValue(b, "uchar", 7, enc);
    plodtest::PutPLYValue(b, "uchar", 3, enc);
    for (int i : { 2, 0, 1 })
    {
      plodtest::PutPLYValue(b, "uint", i, enc);
    }
    plodtest::PutPLYValue(b, "uchar", 1, enc);
    plodtest::PutPLYValue(b, "int", 9, enc);
    plodtest::EndPLYRow(b, enc);
    const std::string path = this->Write("normals", h + b);

    plod::PLYSummary header;
    std::string why;
    ASSERT_TRUE(plod::ReadPLYHeader(path, &why, &header)) << why;
    EXPECT_TRUE(plod::PLYHasNormals(header));
    EXPECT_TRUE(plod::PLYHasDoubleCoordinates(header));
    EXPECT_EQ(plod::EstimatePLYMeshBytes(header), 3 * 24 + 3 * 12 + 1 * 12);

    plod::PLYMesh m;
    ASSERT_TRUE(plod::ReadPLYMesh(path, &m, &why)) << why;
    ASSERT_EQ(m.NumberOfPoints, 3);
    ASSERT_EQ(m.PointsDouble.size(), 9u);
    ASSERT_EQ(m.Normals.size(), 9u);
    for (int p = 0; p < 3; ++p)
    {
      EXPECT_EQ(m.PointsDouble[3 * p], 1e8 + p); // kept in double: float would round it
      EXPECT_EQ(m.PointsDouble[3 * p + 1], -p);
      EXPECT_EQ(m.PointsDouble[3 * p + 2], 0.25 * p);
      EXPECT_EQ(m.Normals[3 * p], 1 + p);
      EXPECT_EQ(m.Normals[3 * p + 1], 2 + p);
      EXPECT_EQ(m.Normals[3 * p + 2], 3 + p);
    }
    EXPECT_EQ(m.Triangles, (std::vector<int32_t>{ 2, 0, 1 }));
  }
}

TEST_F(PLYRead, EveryValidSampleReads)
{
  for (const plodtest::PLYSample& s : plodtest::ValidPLYSamples())
  {
    const std::string path = this->Write(s.Name, s.Bytes);
    plod::PLYMesh m;
    std::string why;
    EXPECT_TRUE(plod::ReadPLYMesh(path, &m, &why)) << s.Name << ": " << why;
    EXPECT_EQ(m.NumberOfPoints, s.Vertices) << s.Name;
    EXPECT_EQ(m.NumberOfFaces, s.Faces) << s.Name;
  }
}

// Samples that only VTK 9.1's reader cannot take (plodPLYCheck's reader limits) are valid PLY;
// every other corrupt sample is refused, with an empty mesh.
TEST_F(PLYRead, EveryCorruptSampleIsRefused)
{
  for (const plodtest::PLYSample& s : plodtest::CorruptPLYSamples())
  {
    if (s.NotAFile)
    {
      continue;
    }
    const std::string path = this->Write(s.Name, s.Bytes);
    plod::PLYMesh m;
    m.NumberOfPoints = 99;
    std::string why;
    EXPECT_FALSE(plod::ReadPLYMesh(path, &m, &why)) << s.Name;
    EXPECT_FALSE(why.empty()) << s.Name;
    EXPECT_EQ(m.NumberOfPoints, 0) << s.Name;
    EXPECT_TRUE(m.PointsFloat.empty() && m.PointsDouble.empty() && m.Triangles.empty()) << s.Name;
  }
  std::string why;
  EXPECT_FALSE(plod::ReadPLYMesh(this->Folder + "/none.ply", nullptr, &why));
  EXPECT_NE(why.find("cannot open"), std::string::npos) << why;
  EXPECT_FALSE(plod::ReadPLYMesh(this->Folder, nullptr, &why));
  EXPECT_NE(why.find("directory"), std::string::npos) << why;
}

TEST_F(PLYRead, EveryCutOfABodyIsRefused)
{
  for (auto enc : { plodtest::PLYEncoding::ASCII, plodtest::PLYEncoding::Little })
  {
    plodtest::TetraPLY t;
    t.Encoding = enc;
    const std::string bytes = t.Bytes();
    const size_t header = t.Header().size();
    for (size_t n = header; n < bytes.size(); ++n)
    {
      // an ASCII cut right after a row's last digit leaves a complete file without its
      // final newline, which this reader takes; any other cut is refused
      const std::string cut = bytes.substr(0, n);
      if (enc == plodtest::PLYEncoding::ASCII && n + 1 == bytes.size())
      {
        continue;
      }
      const std::string path = this->Write("cut", cut);
      plod::PLYMesh m;
      std::string why;
      EXPECT_FALSE(plod::ReadPLYMesh(path, &m, &why)) << n << " of " << bytes.size();
      EXPECT_TRUE(m.Triangles.empty());
    }
  }
}

// Random bytes changed in valid files: the reader never crashes, and whatever the full check
// passes, the reader reads with the check's counts; what it refuses leaves an empty mesh.
TEST_F(PLYRead, RandomCorruptionAgreesWithTheCheck)
{
  std::mt19937 random(7);
  int agreed = 0;
  for (const plodtest::PLYSample& s : plodtest::ValidPLYSamples())
  {
    for (int trial = 0; trial < 60; ++trial)
    {
      std::string bytes = s.Bytes;
      const int changes = 1 + static_cast<int>(random() % 3);
      for (int c = 0; c < changes; ++c)
      {
        bytes[random() % bytes.size()] = static_cast<char>(random() % 256);
      }
      const std::string path = this->Write("random", bytes);
      plod::PLYSummary summary;
      std::string why;
      const bool checked = plod::CheckPLYFile(path, &why, &summary);
      plod::PLYMesh m;
      const bool read = plod::ReadPLYMesh(path, &m, &why);
      if (checked)
      {
        ASSERT_TRUE(read) << s.Name << " " << trial << ": " << why;
        EXPECT_EQ(m.NumberOfPoints, summary.NumberOfVertices);
        EXPECT_EQ(m.NumberOfFaces, summary.NumberOfFaces);
        ++agreed;
      }
      if (!read)
      {
        EXPECT_TRUE(m.Triangles.empty() && m.PointsFloat.empty() && m.PointsDouble.empty());
      }
    }
  }
  EXPECT_GT(agreed, 0) << "no corrupted file passed the check: the comparison never ran";
}

TEST_F(PLYRead, HeaderAloneRefusesAShortBinaryBody)
{
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Little;
  t.DeclaredFaces = 400000000; // a lying header: the body holds 4
  const std::string path = this->Write("lying", t.Bytes());
  plod::PLYSummary header;
  std::string why;
  EXPECT_FALSE(plod::ReadPLYHeader(path, &why, &header));
  EXPECT_NE(why.find("truncated or its counts are wrong"), std::string::npos) << why;

  t.DeclaredFaces = 4;
  ASSERT_TRUE(plod::ReadPLYHeader(this->Write("true", t.Bytes()), &why, &header)) << why;
  EXPECT_EQ(header.NumberOfVertices, 4);
  EXPECT_EQ(header.NumberOfFaces, 4);
  EXPECT_EQ(plod::EstimatePLYMeshBytes(header), 4 * 12 + 4 * 12);
}

// What the header and the memory limit cannot see is refused as it is read: faces that split into
// more triangles than the limit holds, ASCII headers that claim more rows than the file holds,
// values too long to be numbers, and vertex indices that are not whole numbers.
TEST_F(PLYRead, HostileFacesHeadersAndValues)
{
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Little;
  t.CountType = "ushort";
  std::vector<int64_t> big(3000, 0);
  for (size_t i = 0; i < big.size(); ++i)
    big[i] = static_cast<int64_t>(i % 4);
  t.Faces[0] = big;
  const std::string fan = this->Write("fan", t.Bytes());
  plod::PLYMesh m;
  std::string why;
  EXPECT_FALSE(plod::ReadPLYMesh(fan, &m, &why, nullptr, 10000));
  EXPECT_NE(why.find("beyond the memory limit"), std::string::npos) << why;
  EXPECT_TRUE(m.Triangles.empty());
  ASSERT_TRUE(plod::ReadPLYMesh(fan, &m, &why, nullptr, 1e6)) << why;
  EXPECT_EQ(m.NumberOfTriangles(), 2998 + 3);

  plodtest::TetraPLY lying;
  lying.DeclaredVertices = 1000000; // ASCII: the body cannot hold a million rows
  plod::PLYSummary header;
  EXPECT_FALSE(plod::ReadPLYHeader(this->Write("lying_ascii", lying.Bytes()), &why, &header));
  EXPECT_NE(why.find("truncated or its counts are wrong"), std::string::npos) << why;
  plodtest::TetraPLY exact; // and an honest one passes, with or without a final newline
  EXPECT_TRUE(plod::ReadPLYHeader(this->Write("ascii", exact.Bytes()), &why, &header)) << why;
  std::string noNewline = exact.Bytes();
  noNewline.pop_back();
  EXPECT_TRUE(plod::ReadPLYHeader(this->Write("ascii_end", noNewline), &why, &header)) << why;

  plodtest::TetraPLY longValue;
  std::string bytes = longValue.Bytes();
  const size_t at = bytes.find("end_header\n") + 11;
  bytes.insert(at, "1." + std::string(200, '0'));
  bytes.erase(at + 202, 1); // the first coordinate "1" becomes 1.000...0
  EXPECT_FALSE(plod::ReadPLYMesh(this->Write("long_value", bytes), &m, &why));
  EXPECT_NE(why.find("longer than"), std::string::npos) << why;

  plodtest::TetraPLY fractional;
  fractional.IndexType = "float";
  fractional.Faces[1] = { 0, 2, 1 };
  std::string text = fractional.Bytes();
  text.replace(text.rfind("3 0 2 1"), 7, "3 0 2.5 1");
  EXPECT_FALSE(plod::ReadPLYMesh(this->Write("fractional", text), &m, &why));
  EXPECT_NE(why.find("not a whole number"), std::string::npos) << why;
}

TEST_F(PLYRead, AbortStopsTheRead)
{
  plodtest::TetraPLY t;
  const std::string path = this->Write("abort", t.Bytes());
  plod::PLYMesh m;
  std::string why;
  EXPECT_FALSE(plod::ReadPLYMesh(path, &m, &why, [](double) { return false; }));
  EXPECT_EQ(why, "aborted");
  int calls = 0;
  EXPECT_TRUE(plod::ReadPLYMesh(path, &m, &why, [&calls](double f) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
    ++calls;
    return true;
  }));
  EXPECT_EQ(calls, 2); // the first row of `vertex` and of `face`
}

TEST_F(PLYRead, StanfordScans)
{
  const char* dir = std::getenv("PLOD_DATA_DIR");
  const std::string data = dir ? dir : "";
  if (data.empty() || !fs::exists(data + "/bun_zipper.ply"))
  {
    GTEST_SKIP() << "../shared/data (PLOD_DATA_DIR) is not there: the Stanford scans are skipped";
  }
  for (const char* name : { "bun_zipper.ply", "lucy.ply", "bun000.ply" })
  {
    const std::string path = data + "/" + name;
    plod::PLYSummary header;
    std::string why;
    ASSERT_TRUE(plod::CheckPLYFile(path, &why, &header)) << name << ": " << why;
    plod::PLYMesh m;
    ASSERT_TRUE(plod::ReadPLYMesh(path, &m, &why)) << name << ": " << why;
    EXPECT_EQ(m.NumberOfPoints, header.NumberOfVertices) << name;
    EXPECT_EQ(m.NumberOfTriangles(), header.NumberOfFaces) << name; // all triangles
    for (int32_t i : m.Triangles)
    {
      ASSERT_TRUE(i >= 0 && i < m.NumberOfPoints) << name;
    }
  }
}

} // namespace
