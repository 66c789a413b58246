// SPDX-License-Identifier: BSD-3-Clause
// Tests of plod::CheckSTLFile and plod::CheckOBJFile: valid files (binary and ASCII STL, a
// binary STL whose header starts with "solid", OBJ with texture coordinates, normals and
// relative indices) pass with their counts; every cut of an STL file, non-finite vertices,
// indices out of range and malformed statements fail with a message that names the place;
// what VTK 9.1's readers cannot take fails only under their limits; polylines and degenerate
// triangles pass with a warning; random damage, FIFOs and large files end in a clean answer.
#include "plodMeshFileCheck.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace
{
namespace fs = std::filesystem;
using Triangle = std::array<float, 9>;

/// A tetrahedron's four triangles, with coordinates whose float bytes are not text.
std::vector<Triangle> Tetrahedron()
{
  const float a = 0.25f, b = -1.5f, c = 2.125f, d = 0.0f;
  return { Triangle{ a, a, a, c, b, b, b, c, b }, Triangle{ a, a, a, b, b, c, c, b, b },
    Triangle{ a, a, a, b, c, b, b, b, c }, Triangle{ c, b, b, b, b, c, b, c, d } };
}

std::string Binary32(uint32_t v)
{
  const char b[4] = { static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
    static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff) };
  return std::string(b, 4);
}

std::string BinaryFloat(float f)
{
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  return Binary32(bits);
}

/// A binary STL: `header` padded with zeros to 80 bytes, the count (the number of triangles
/// unless given), and each triangle with normal (0, 0, 1) and attribute `attribute`.
std::string BinarySTL(const std::vector<Triangle>& triangles, const std::string& header = "binary",
  int64_t count = -1, uint16_t attribute = 0)
{
  std::string bytes = header.substr(0, 80);
  bytes.resize(80, '\0');
  bytes += Binary32(static_cast<uint32_t>(count < 0 ? triangles.size() : count));
  for (const Triangle& t : triangles)
  {
    bytes += BinaryFloat(0) + BinaryFloat(0) + BinaryFloat(1);
    for (float x : t)
    {
      bytes += BinaryFloat(x);
    }
    bytes += std::string(1, static_cast<char>(attribute & 0xff)) +
      std::string(1, static_cast<char>(attribute >> 8));
  }
  return bytes;
}

/// An ASCII STL of one solid.
std::string ASCIISTL(const std::vector<Triangle>& triangles, const std::string& name = "tetra")
{
  std::string text = "solid " + name + "\n";
  for (const Triangle& t : triangles)
  {
    text += "  facet normal 0 0 1\n    outer loop\n";
    for (int k = 0; k < 3; ++k)
    {
      char line[128];
      std::snprintf(
        line, sizeof(line), "      vertex %.9g %.9g %.9g\n", t[3 * k], t[3 * k + 1], t[3 * k + 2]);
      text += line;
    }
    text += "    endloop\n  endfacet\n";
  }
  return text + "endsolid " + name + "\n";
}

/// A cube of 8 vertices, 8 texture coordinates and 6 normals; faces of every reference form,
/// some with relative (negative) indices, and statements the check skips.
std::string ValidOBJ()
{
  return "# a cube\n"
         "mtllib cube.mtl\n"
         "o cube\n"
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
         "v 0 0 1\nv 1 0 1\nv 1 1 1 1.0\nv 0 1 1 0.5 0.5 0.5\n"
         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5 0\nvt 0.25\nvt 0.1 0.2\nvt 0.3 0.4\n"
         "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 1 0 0\nvn 0 1 0\nvn -1 0 0\n"
         "g sides\nusemtl red\ns 1\n"
         "f 1/1/1 4/4/1 3/3/1 2/2/1\n"
         "f 5/1/2 6/2/2 7/3/2 8/4/2\r\n"
         "f 1//3 2//3 6//3\n"
         "f -8//3 -3//3 -4//3\n"
         "f 2/2/4 3/3/4 7/7/4 6/6/4\n"
         "f -5/-5/-2 -1/-1/-2 -2/-2/-2 -6/-6/-2\n"
         "\tf 1/1/6 5/5/6 8/8/6 4/4/6   \n"
         "\n"
         "# the end";
}
} // namespace

/// Small files written into a temporary folder.
class MeshFileCheck : public ::testing::Test
{
public:
  static void SetUpTestSuite()
  {
    Folder() =
      (fs::temp_directory_path() / ("plod_mesh_check_" + std::to_string(::getpid()))).string();
    fs::create_directories(Folder());
  }

  static void TearDownTestSuite()
  {
    std::error_code error;
    fs::remove_all(Folder(), error);
  }

  static std::string& Folder()
  {
    static std::string folder;
    return folder;
  }

  /// Writes `bytes` to a file of the folder and returns its path.
  static std::string Write(const std::string& name, const std::string& bytes)
  {
    const std::string path = Folder() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
  }

  /// The message of a check that must fail.
  static std::string STLFails(
    const std::string& bytes, const plod::STLReaderLimits& limits = plod::STLReaderLimits())
  {
    std::string why;
    EXPECT_FALSE(plod::CheckSTLFile(Write("fails.stl", bytes), &why, nullptr, limits));
    EXPECT_FALSE(why.empty());
    return why;
  }

  static std::string OBJFails(
    const std::string& text, const plod::OBJReaderLimits& limits = plod::OBJReaderLimits())
  {
    std::string why;
    EXPECT_FALSE(plod::CheckOBJFile(Write("fails.obj", text), &why, nullptr, limits));
    EXPECT_FALSE(why.empty());
    return why;
  }
};

#define EXPECT_SAYS(why, part) EXPECT_NE((why).find(part), std::string::npos) << (why)

// ---- STL: valid files ----------------------------------------------------------------------

TEST_F(MeshFileCheck, BinarySTLPasses)
{
  const std::string bytes = BinarySTL(Tetrahedron());
  for (const auto& limits : { plod::STLReaderLimits(), plod::VTKSTLReaderLimits() })
  {
    std::string why = "unchanged";
    plod::STLSummary s;
    ASSERT_TRUE(plod::CheckSTLFile(Write("tetra.stl", bytes), &why, &s, limits)) << why;
    EXPECT_EQ(why, "");
    EXPECT_EQ(s.Format, plod::STLFormat::Binary);
    EXPECT_EQ(s.NumberOfTriangles, 4);
    EXPECT_EQ(s.FileBytes, 84 + 4 * 50);
    EXPECT_EQ(s.NumberOfNonFiniteTriangles, 0);
    EXPECT_EQ(s.FirstNonFiniteTriangle, -1);
    EXPECT_EQ(s.Warning, "");
  }
}

TEST_F(MeshFileCheck, ASCIISTLPasses)
{
  const std::string one = ASCIISTL(Tetrahedron());
  std::string crlf;
  for (char c : one)
  {
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  }
  std::string upper = one;
  for (char& c : upper)
  {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  std::string loose = one; // blank lines, a colour line, tabs, no final newline
  loose.insert(loose.find("  facet"), "\n\t\ncolor 1 0 0\n");
  loose.pop_back();
  struct Case
  {
    const char* Name;
    std::string Bytes;
    int64_t Triangles;
    int64_t Solids;
  };
  const Case cases[] = { { "plain", one, 4, 1 }, { "crlf", crlf, 4, 1 }, { "upper", upper, 4, 1 },
    { "loose", loose, 4, 1 }, { "two solids", one + one, 8, 2 } };
  for (const Case& c : cases)
  {
    for (const auto& limits : { plod::STLReaderLimits(), plod::VTKSTLReaderLimits() })
    {
      std::string why;
      plod::STLSummary s;
      ASSERT_TRUE(plod::CheckSTLFile(Write("ascii.stl", c.Bytes), &why, &s, limits))
        << c.Name << ": " << why;
      EXPECT_EQ(s.Format, plod::STLFormat::ASCII) << c.Name;
      EXPECT_EQ(s.NumberOfTriangles, c.Triangles) << c.Name;
      EXPECT_EQ(s.NumberOfSolids, c.Solids) << c.Name;
      EXPECT_EQ(s.Warning, "") << c.Name;
    }
  }
}

TEST_F(MeshFileCheck, BinarySTLStartingWithSolidIsBinary)
{
  // many binary writers start the header with "solid": the size decides
  for (const std::string header :
    { "solid tetra", "solid", "SOLID tetra exported as binary", "  solid x\nfacet normal" })
  {
    std::string why;
    plod::STLSummary s;
    ASSERT_TRUE(plod::CheckSTLFile(Write("solid_binary.stl", BinarySTL(Tetrahedron(), header)),
      &why, &s, plod::VTKSTLReaderLimits()))
      << header << ": " << why;
    EXPECT_EQ(s.Format, plod::STLFormat::Binary) << header;
    EXPECT_EQ(s.NumberOfTriangles, 4) << header;
  }
  // a header of spaces after "solid" (no zero byte in it) too
  std::string spaces = "solid tetra";
  spaces.resize(80, ' ');
  plod::STLSummary s;
  ASSERT_TRUE(
    plod::CheckSTLFile(Write("spaces.stl", BinarySTL(Tetrahedron(), spaces)), nullptr, &s));
  EXPECT_EQ(s.Format, plod::STLFormat::Binary);
}

TEST_F(MeshFileCheck, NullOutputsAreAllowed)
{
  EXPECT_TRUE(plod::CheckSTLFile(Write("null.stl", BinarySTL(Tetrahedron())), nullptr));
  EXPECT_FALSE(plod::CheckSTLFile(Write("null.stl", ""), nullptr));
  EXPECT_TRUE(plod::CheckOBJFile(Write("null.obj", ValidOBJ()), nullptr));
  EXPECT_FALSE(plod::CheckOBJFile(Write("null.obj", ""), nullptr));
}

// ---- STL: cut, damaged and empty files -----------------------------------------------------

TEST_F(MeshFileCheck, EveryCutOfABinarySTLFails)
{
  for (const std::string header : { "binary", "solid tetra" })
  {
    const std::string bytes = BinarySTL(Tetrahedron(), header);
    for (size_t cut = 0; cut < bytes.size(); ++cut)
    {
      std::string why;
      ASSERT_FALSE(plod::CheckSTLFile(Write("cut.stl", bytes.substr(0, cut)), &why))
        << header << " cut at " << cut;
      EXPECT_FALSE(why.empty()) << header << " cut at " << cut;
      if (cut >= 84)
      {
        const bool named = why.find("is cut inside triangle") != std::string::npos ||
          why.find("the file ends after") != std::string::npos;
        EXPECT_TRUE(named) << header << " cut at " << cut << ": " << why;
        EXPECT_SAYS(why, std::to_string(bytes.size() - cut) + " bytes");
      }
    }
  }
  // the message names the triangle, how much of it is there and what is missing
  const std::string bytes = BinarySTL(Tetrahedron());
  std::string why = STLFails(bytes.substr(0, 84 + 50 + 17));
  EXPECT_SAYS(why,
    "the file is cut inside triangle 1 of 4 (triangles count from 0; 17 of its 50 "
    "bytes are there, from byte 134)");
  EXPECT_SAYS(why, "84 + 50 * 4 = 284 bytes, the file has 151; 133 bytes are missing");
  why = STLFails(bytes.substr(0, 84 + 100));
  EXPECT_SAYS(why, "the file ends after triangle 1 of 4");
  EXPECT_SAYS(why, "100 bytes (2 triangles) are missing");
  why = STLFails(bytes.substr(0, 84));
  EXPECT_SAYS(why, "the file ends after its header");
  why = STLFails(bytes.substr(0, 40));
  EXPECT_SAYS(why, "too short for a binary STL file");
}

TEST_F(MeshFileCheck, EveryCutOfAnASCIISTLFails)
{
  const std::string text = ASCIISTL(Tetrahedron());
  // up to the end of the word endsolid: a cut after it leaves a shorter but valid name
  const size_t end = text.rfind("endsolid") + 8;
  for (size_t cut = 0; cut < end; ++cut)
  {
    std::string why;
    ASSERT_FALSE(plod::CheckSTLFile(Write("cut.stl", text.substr(0, cut)), &why))
      << "cut at " << cut;
    EXPECT_FALSE(why.empty()) << "cut at " << cut;
  }
  EXPECT_TRUE(plod::CheckSTLFile(Write("cut.stl", text.substr(0, end)), nullptr));
  // the messages give the line
  const size_t line11 = text.find("vertex", text.find("facet normal", 20));
  std::string why = STLFails(text.substr(0, line11 - 6));
  EXPECT_SAYS(why,
    "the file is cut inside facet 1 (opened at line 9): the file ends at line 10 "
    "after 0 of its 3 vertices");
  why = STLFails(text.substr(0, line11 + 10));
  EXPECT_SAYS(why,
    "the file is cut inside facet 1 (opened at line 9): the file ends at line 11 "
    "inside a vertex");
  why = STLFails(text.substr(0, text.rfind("endsolid")));
  EXPECT_SAYS(why, "the file ends at line 29 without 'endsolid' (the solid opened at line 1)");
}

TEST_F(MeshFileCheck, BinarySTLWithExtraBytesFails)
{
  std::string why = STLFails(BinarySTL(Tetrahedron()) + "1234567");
  EXPECT_SAYS(why,
    "the header's count of 4 triangles needs 84 + 50 * 4 = 284 bytes, the file has "
    "291: 7 bytes more than the count needs");
  // the count says fewer triangles than follow
  why = STLFails(BinarySTL(Tetrahedron(), "binary", 3));
  EXPECT_SAYS(why, "50 bytes more than the count needs (1 more triangles than it says?)");
}

TEST_F(MeshFileCheck, STLWithNonFiniteVertexFails)
{
  auto triangles = Tetrahedron();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  triangles[1][4] = nan;
  triangles[3][8] = -inf;
  plod::STLSummary s;
  std::string why;
  EXPECT_FALSE(plod::CheckSTLFile(Write("nan.stl", BinarySTL(triangles)), &why, &s));
  EXPECT_SAYS(why, "triangle 1 (byte 134) has a non-finite vertex coordinate (nan)");
  EXPECT_SAYS(why, "2 of 4 triangles have a NaN or infinite coordinate");
  EXPECT_EQ(s.NumberOfNonFiniteTriangles, 2);
  EXPECT_EQ(s.FirstNonFiniteTriangle, 1);
  // a non-finite normal is not read
  std::string bytes = BinarySTL(Tetrahedron());
  bytes.replace(84, 4, BinaryFloat(nan));
  EXPECT_TRUE(plod::CheckSTLFile(Write("nan_normal.stl", bytes), &why)) << why;
  // ASCII: nan, inf, and a value beyond the range of float
  const std::string text = ASCIISTL(Tetrahedron());
  const size_t second = text.find("vertex", text.find("facet", 100));
  for (const char* value : { "nan", "-inf", "1e39", "NaN" })
  {
    std::string bad = text;
    bad.replace(second + 7, 4, value); // the first coordinate of facet 1's first vertex
    why = STLFails(bad);
    EXPECT_SAYS(why, "triangle 1 (facet at line 9) has a non-finite vertex coordinate") << value;
    EXPECT_SAYS(why, "1 of 4 triangles") << value;
  }
  // tiny values are zero, not errors
  std::string tiny = text;
  tiny.replace(second + 7, 4, "1e-60");
  EXPECT_TRUE(plod::CheckSTLFile(Write("tiny.stl", tiny), &why)) << why;
}

TEST_F(MeshFileCheck, EmptyOrTriangleFreeSTLFails)
{
  EXPECT_SAYS(STLFails(""), "the file is empty");
  EXPECT_SAYS(STLFails(BinarySTL({})), "no triangle: the header's count is 0");
  EXPECT_SAYS(STLFails("solid empty\nendsolid empty\n"), "no triangle: the file holds no facet");
  EXPECT_SAYS(STLFails("solid"), "without 'endsolid'");
  EXPECT_SAYS(STLFails("   \n\n"), "not an STL file");
  EXPECT_SAYS(STLFails("ply\nformat ascii 1.0\n"), "not an STL file");
}

TEST_F(MeshFileCheck, ASCIISTLStructureErrorsNameTheLine)
{
  const std::string text = ASCIISTL(Tetrahedron());
  const size_t third = text.find("vertex", text.find("vertex", text.find("vertex") + 1) + 1);
  const size_t thirdEnd = text.find('\n', third) + 1;
  std::string why = STLFails(text.substr(0, third) + text.substr(thirdEnd));
  EXPECT_SAYS(why, "line 6: facet 0 (line 2) has 2 vertices; a facet needs 3");
  why = STLFails(text.substr(0, thirdEnd) + text.substr(third));
  EXPECT_SAYS(why, "line 7: facet 0 (line 2) has more than 3 vertices");
  std::string bad = text;
  bad.replace(text.find("vertex") + 7, 1, "x");
  EXPECT_SAYS(STLFails(bad), "line 4: 'x.25' is not a number (a vertex coordinate of facet 0");
  bad = text;
  bad.insert(text.find('\n', text.find("vertex")), " 7");
  EXPECT_SAYS(STLFails(bad), "line 4: a vertex of facet 0 (line 2) has more than 3 numbers");
  bad = text;
  const size_t newline = text.find('\n', text.find("vertex"));
  bad.erase(text.rfind(' ', newline), newline - text.rfind(' ', newline));
  EXPECT_SAYS(STLFails(bad), "line 4: a vertex of facet 0 (line 2) has 2 numbers; it needs 3");
  bad = text;
  bad.replace(text.find("outer loop"), 10, "outer");
  EXPECT_SAYS(STLFails(bad), "line 3: expected 'outer loop'");
  EXPECT_SAYS(STLFails(text + "garbage\n"), "line 31: expected 'solid' or the end of the file");
  EXPECT_SAYS(STLFails("solid x\nvertex 1 2 3\n"), "line 2: expected 'facet' or 'endsolid'");
  // a zero byte in the first 1024 bytes makes the file binary; later, it is named
  const std::string four = ASCIISTL(std::vector<Triangle>(16, Tetrahedron()[0]));
  ASSERT_GT(four.size(), 1500u);
  EXPECT_SAYS(STLFails(four.substr(0, 1500) + std::string(1, '\0') + four.substr(1501)),
    "a zero byte (byte 1500): not a text file");
}

TEST_F(MeshFileCheck, DegenerateTrianglesPassWithAWarning)
{
  auto triangles = Tetrahedron();
  for (int a = 0; a < 3; ++a)
  {
    triangles[2][3 + a] = triangles[2][6 + a]; // corners 1 and 2 of triangle 2 are equal
  }
  plod::STLSummary s;
  std::string why;
  ASSERT_TRUE(plod::CheckSTLFile(Write("degenerate.stl", BinarySTL(triangles)), &why, &s)) << why;
  EXPECT_EQ(s.NumberOfDegenerateTriangles, 1);
  EXPECT_EQ(s.FirstDegenerateTriangle, 2);
  EXPECT_SAYS(s.Warning, "1 of 4 triangles have two equal corners (the first: triangle 2)");
}

TEST_F(MeshFileCheck, WhatVTKsSTLReaderMisreadsFailsOnlyUnderItsLimits)
{
  const auto vtk = plod::VTKSTLReaderLimits();
  // a solid named in UTF-8: vtkSTLReader takes the file for binary
  std::string name;
  for (int k = 0; k < 12; ++k)
  {
    name += "\xc3\xbc";
  }
  const std::string utf8 = ASCIISTL(Tetrahedron(), name);
  EXPECT_TRUE(plod::CheckSTLFile(Write("utf8.stl", utf8), nullptr));
  EXPECT_SAYS(STLFails(utf8, vtk),
    "vtkSTLReader (VTK 9.1) would read this ASCII file as binary: "
    "24 of its first 256 bytes are not ASCII text");
  // a line longer than vtkSTLReader's 254 bytes
  const std::string longName = ASCIISTL(Tetrahedron(), std::string(300, 'n'));
  EXPECT_TRUE(plod::CheckSTLFile(Write("long.stl", longName), nullptr));
  EXPECT_SAYS(STLFails(longName, vtk), "line 1: the line is longer than 254 bytes");
  const std::string exact = ASCIISTL(Tetrahedron(), std::string(254 - 9, 'n')); // endsolid line
  EXPECT_TRUE(plod::CheckSTLFile(Write("exact.stl", exact), nullptr, nullptr, vtk));
  // a binary file whose bytes look like text: vtkSTLReader takes it for ASCII
  // (each float 0x41414141, 12.078431: "AAAA"; only the count's bytes are not text)
  std::string looksText = std::string(80, ' ') + Binary32(4);
  for (int t = 0; t < 4; ++t)
  {
    looksText += std::string(48, 'A') + "  ";
  }
  EXPECT_TRUE(plod::CheckSTLFile(Write("text_binary.stl", looksText), nullptr));
  EXPECT_SAYS(STLFails(looksText, vtk), "would read this binary file as ASCII: only");
}

// ---- OBJ -----------------------------------------------------------------------------------

TEST_F(MeshFileCheck, ValidOBJPasses)
{
  for (const auto& limits : { plod::OBJReaderLimits(), plod::VTKOBJReaderLimits() })
  {
    std::string why = "unchanged";
    plod::OBJSummary s;
    ASSERT_TRUE(plod::CheckOBJFile(Write("cube.obj", ValidOBJ()), &why, &s, limits)) << why;
    EXPECT_EQ(why, "");
    EXPECT_EQ(s.NumberOfVertices, 8);
    EXPECT_EQ(s.NumberOfTextureCoordinates, 8);
    EXPECT_EQ(s.NumberOfNormals, 6);
    EXPECT_EQ(s.NumberOfFaces, 7);
    EXPECT_EQ(s.MaxFaceSize, 4);
    EXPECT_EQ(s.NumberOfLines, 37);
    EXPECT_EQ(s.NumberOfPolylines, 0);
    EXPECT_EQ(s.NumberOfNonFiniteVertices, 0);
    EXPECT_EQ(s.Warning, "");
  }
  // plain faces of a triangle, without a final newline
  plod::OBJSummary s;
  ASSERT_TRUE(plod::CheckOBJFile(
    Write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -3 -2 -1"), nullptr, &s));
  EXPECT_EQ(s.NumberOfFaces, 2);
  EXPECT_EQ(s.NumberOfLines, 5);
}

TEST_F(MeshFileCheck, OBJNonFiniteVertexFailsNamingTheLine)
{
  const std::string head = "# two bad vertices\nv 0 0 0\n";
  plod::OBJSummary s;
  std::string why;
  EXPECT_FALSE(plod::CheckOBJFile(
    Write("nan.obj", head + "v nan nan nan\nv 1 0 0\nv 0 inf 0\nf 1 2 3\nf 2 3 4\n"), &why, &s));
  EXPECT_SAYS(why,
    "line 3: vertex 2 (OBJ counts from 1) has the coordinate 'nan', which is not "
    "a finite float");
  EXPECT_SAYS(why, "2 of 4 vertices have a NaN, infinite or out-of-range coordinate");
  EXPECT_EQ(s.NumberOfNonFiniteVertices, 2);
  EXPECT_EQ(s.FirstNonFiniteVertexLine, 3);
  // beyond the range of float (VTK's reader keeps floats), and in z
  EXPECT_SAYS(OBJFails(head + "v 0 0 1e39\nf 1 1 2\n"), "line 3: vertex 2");
  EXPECT_SAYS(OBJFails(head + "v 0 0 -Infinity\n"), "'-Infinity'");
  // a later structural error is said first, with the vertex
  why = OBJFails(head + "v nan 0 0\nf 1 2 x\n");
  EXPECT_SAYS(why, "line 4: 'x' is not a reference");
  EXPECT_SAYS(why, "(and before it, line 3: vertex 2");
  // texture coordinates and normals are not geometry
  EXPECT_TRUE(
    plod::CheckOBJFile(Write("nan_normal.obj",
                         "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan nan nan\nvt nan\nf 1//1 2//1 3//1\n"),
      &why))
    << why;
}

TEST_F(MeshFileCheck, OBJIndexOutOfRangeFails)
{
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  EXPECT_SAYS(OBJFails(v + "f 1 2 9\n"),
    "line 5: vertex index 9 in '9' is out of range: 4 are defined before this line");
  EXPECT_SAYS(OBJFails(v + "f -1 -2 -5\n"),
    "line 5: relative vertex index -5 in '-5' is out of range: 4 are defined before this line "
    "(-1 is the last of them)");
  EXPECT_SAYS(OBJFails(v + "f 1 0 2\n"), "line 5: vertex index 0 in '0' (OBJ indices count from 1");
  // indices count what is defined before the statement, not after
  EXPECT_SAYS(OBJFails("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n"), "line 3: vertex index 3");
  EXPECT_SAYS(OBJFails(v + "vt 0 0\nf 1/1 2/2 3/1\n"),
    "line 6: texture coordinate index 2 in '2/2' is out of range: 1 are defined");
  EXPECT_SAYS(
    OBJFails(v + "f 1/1 2/1 3/1\n"), "texture coordinate index 1 in '1/1' is out of range");
  EXPECT_SAYS(OBJFails(v + "vn 0 0 1\nf 1//1 2//1 3//-2\n"), "relative normal index -2");
  EXPECT_SAYS(OBJFails(v + "vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/2\n"), "normal index 2 in '3/1/2'");
  EXPECT_SAYS(OBJFails(v + "f 1 2 99999999999999999999\n"), "vertex index 99999999999999999999");
  EXPECT_SAYS(OBJFails(v + "l 1 5\n"), "line 5: vertex index 5");
  EXPECT_SAYS(OBJFails(v + "p -5\n"), "line 5: relative vertex index -5");
}

TEST_F(MeshFileCheck, OBJMalformedStatementsFail)
{
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  // a face of fewer than 3 references: an error (vtkOBJReader reads nothing from the file)
  EXPECT_SAYS(OBJFails(v + "f 1 2\n"), "line 5: a face of 2 references; it needs 3 or more");
  EXPECT_SAYS(OBJFails(v + "f\n"), "line 5: a face of 0 references");
  EXPECT_SAYS(OBJFails(v + "l 1\n"), "line 5: a polyline of 1 references; it needs 2 or more");
  EXPECT_SAYS(OBJFails(v + "vt 0 0\nf 1/1 2 3\n"),
    "line 6: references of different forms in one face ('1/1' is i/t, '2' is i)");
  for (const char* ref : { "1/", "1//", "/1", "1/1/1/1", "a", "1.0", "1/x", "--1" })
  {
    EXPECT_SAYS(OBJFails(v + "vt 0 0\nvn 0 0 1\nf " + ref + " 2 3\n"), "is not a reference") << ref;
  }
  EXPECT_SAYS(OBJFails("v 0 0\n"), "line 1: a vertex has 2 coordinates; it needs 3");
  EXPECT_SAYS(OBJFails("v 0 0 x\n"), "line 1: 'x' is not a number (in a vertex)");
  EXPECT_SAYS(OBJFails("v 0 0 0 1 1 1 1 1\n"), "line 1: a vertex has more than 7 numbers");
  EXPECT_SAYS(OBJFails(v + "vn 0 0\n"), "line 5: a normal has 2 numbers; it needs 3");
  EXPECT_SAYS(OBJFails(v + "vt\n"), "line 5: a texture coordinate has 0 numbers; it needs 1");
  EXPECT_SAYS(OBJFails("v 0 0 0\n" + std::string(1, '\0')), "line 2: a zero byte");
  EXPECT_SAYS(OBJFails(""), "the file is empty");
  EXPECT_SAYS(OBJFails("# nothing\n\ng none\n"), "no vertex: the file holds no 'v' line");
}

TEST_F(MeshFileCheck, OBJPolylinesAndPointsPassWithAWarning)
{
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\n";
  plod::OBJSummary s;
  std::string why;
  ASSERT_TRUE(
    plod::CheckOBJFile(Write("lines.obj", v + "f 1 2 3\nl 1 2 3 4\nl 1/1 -1/1\np 1 2\n"), &why, &s))
    << why;
  EXPECT_EQ(s.NumberOfFaces, 1);
  EXPECT_EQ(s.NumberOfPolylines, 2);
  EXPECT_EQ(s.FirstPolylineLine, 7);
  EXPECT_EQ(s.NumberOfPointElements, 1);
  EXPECT_SAYS(s.Warning, "2 'l' polylines (the first at line 7) are ignored: only faces are drawn");
  EXPECT_SAYS(s.Warning, "1 'p' point elements (the first at line 9) are ignored");
  // no face at all: a point cloud
  ASSERT_TRUE(plod::CheckOBJFile(Write("cloud.obj", v), &why, &s)) << why;
  EXPECT_SAYS(s.Warning, "no face ('f' line): the 4 vertices are read as a point cloud");
}

TEST_F(MeshFileCheck, WhatVTKsOBJReaderCannotTakeFailsOnlyUnderItsLimits)
{
  const auto vtk = plod::VTKOBJReaderLimits();
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\n";
  // a comment after a face: vtkOBJReader 9.1 reads nothing from the file
  const std::string comment = v + "f 1 2 3 # the base\n";
  EXPECT_TRUE(plod::CheckOBJFile(Write("comment.obj", comment), nullptr));
  EXPECT_SAYS(OBJFails(comment, vtk), "line 6: a comment after the references of 'f'");
  // a comment after a vertex is fine for it
  EXPECT_TRUE(plod::CheckOBJFile(
    Write("comment.obj", v + "v 1 1 1 # top\nf 1 2 3\n"), nullptr, nullptr, vtk));
  // faces without normals beside faces with them: vtkOBJReader skips them
  plod::OBJSummary s;
  const std::string mixed = v + "f 1//1 2//1 3//1\nf 1 2 4\nf 2 3 4\n";
  ASSERT_TRUE(plod::CheckOBJFile(Write("mixed.obj", mixed), nullptr, &s));
  EXPECT_EQ(s.Warning, "");
  ASSERT_TRUE(plod::CheckOBJFile(Write("mixed.obj", mixed), nullptr, &s, vtk));
  EXPECT_EQ(s.NumberOfFacesWithoutNormals, 2);
  EXPECT_EQ(s.FirstFaceWithoutNormalsLine, 7);
  EXPECT_SAYS(s.Warning,
    "2 of 3 faces have no normal reference while others have one (the "
    "first: line 7); vtkOBJReader (VTK 9.1) skips them");
}

// ---- both: FIFOs, random damage, large files -----------------------------------------------

TEST_F(MeshFileCheck, FifoAndFolderAreRefusedAtOnce)
{
  const std::string fifo = Folder() + "/model.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string why;
  // no writer: opening it for reading would block
  EXPECT_FALSE(plod::CheckSTLFile(fifo, &why));
  EXPECT_EQ(why, "is not a regular file (a FIFO)");
  EXPECT_FALSE(plod::CheckOBJFile(fifo, &why));
  EXPECT_EQ(why, "is not a regular file (a FIFO)");
  ::unlink(fifo.c_str());
  EXPECT_FALSE(plod::CheckSTLFile(Folder(), &why));
  EXPECT_EQ(why, "is a directory, not an STL file");
  EXPECT_FALSE(plod::CheckOBJFile(Folder(), &why));
  EXPECT_EQ(why, "is a directory, not an OBJ file");
  EXPECT_FALSE(plod::CheckOBJFile(Folder() + "/missing.obj", &why));
  EXPECT_EQ(why, "cannot open: No such file or directory");
  EXPECT_FALSE(plod::CheckSTLFile("", &why));
  EXPECT_EQ(why, "no file name given");
}

TEST_F(MeshFileCheck, RandomDamageNeverCrashesOrHangs)
{
  // byte changes, insertions, deletions and cuts of valid files, and random bytes: the checks
  // must answer, with a message when they reject
  const std::vector<std::string> valid = { BinarySTL(Tetrahedron()),
    BinarySTL(Tetrahedron(), "solid x"), ASCIISTL(Tetrahedron()), ValidOBJ() };
  std::mt19937 rng(2025);
  int rejected = 0;
  const int trials = 800;
  for (int trial = 0; trial < trials; ++trial)
  {
    std::string bytes;
    if (trial % 20 == 19)
    {
      bytes.resize(rng() % 600);
      for (char& c : bytes)
      {
        c = static_cast<char>(rng() & 0xff);
      }
    }
    else
    {
      bytes = valid[rng() % valid.size()];
      const int edits = 1 + static_cast<int>(rng() % 3);
      for (int e = 0; e < edits && !bytes.empty(); ++e)
      {
        const size_t at = rng() % bytes.size();
        switch (rng() % 4)
        {
          case 0:
            bytes[at] = static_cast<char>(rng() & 0xff);
            break;
          case 1:
            bytes.insert(at, 1 + rng() % 8, static_cast<char>(rng() & 0xff));
            break;
          case 2:
            bytes.erase(at, 1 + rng() % 8);
            break;
          default:
            bytes.resize(at);
        }
      }
    }
    const bool vtk = (trial & 1) != 0;
    std::string why;
    plod::STLSummary stl;
    const bool stlOk = plod::CheckSTLFile(Write("damaged.stl", bytes), &why, &stl,
      vtk ? plod::VTKSTLReaderLimits() : plod::STLReaderLimits());
    ASSERT_EQ(stlOk, why.empty()) << "trial " << trial;
    if (stlOk)
    {
      ASSERT_GT(stl.NumberOfTriangles, 0) << "trial " << trial;
      ASSERT_EQ(stl.NumberOfNonFiniteTriangles, 0) << "trial " << trial;
    }
    plod::OBJSummary obj;
    const bool objOk = plod::CheckOBJFile(Write("damaged.obj", bytes), &why, &obj,
      vtk ? plod::VTKOBJReaderLimits() : plod::OBJReaderLimits());
    ASSERT_EQ(objOk, why.empty()) << "trial " << trial;
    if (objOk)
    {
      ASSERT_GT(obj.NumberOfVertices, 0) << "trial " << trial;
    }
    rejected += stlOk ? 0 : 1;
  }
  EXPECT_GT(rejected, trials / 2) << "most damage to STL files is found";
}

TEST_F(MeshFileCheck, LargeFilesAreStreamed)
{
  // 200,000 binary triangles (10 MB), and an OBJ with a 4 MB comment line and a 4 MB group line
  std::vector<Triangle> many;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> U(-1, 1);
  for (int t = 0; t < 200000; ++t)
  {
    Triangle x;
    for (float& c : x)
    {
      c = U(rng);
    }
    many.push_back(x);
  }
  plod::STLSummary s;
  std::string why;
  ASSERT_TRUE(
    plod::CheckSTLFile(Write("large.stl", BinarySTL(many)), &why, &s, plod::VTKSTLReaderLimits()))
    << why;
  EXPECT_EQ(s.NumberOfTriangles, 200000);
  const std::string text = "#" + std::string(4 << 20, 'c') + "\ng " + std::string(4 << 20, 'g') +
    "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  plod::OBJSummary o;
  ASSERT_TRUE(plod::CheckOBJFile(Write("long_lines.obj", text), &why, &o)) << why;
  EXPECT_EQ(o.NumberOfFaces, 1);
  EXPECT_EQ(o.NumberOfLines, 6);
}
