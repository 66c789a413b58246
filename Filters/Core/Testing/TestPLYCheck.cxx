// SPDX-License-Identifier: BSD-3-Clause
// Tests of plod::CheckPLYFile: valid files in every encoding pass with their counts; each corrupt
// variant fails with a message that names its problem; valid files beyond VTK 9.1's reader fail
// only under its limits; every cut of a body, random corruption and huge counts end in a clean
// answer; faces of fewer than 3 indices pass with a warning; the Stanford files pass when
// ../shared/data is there.
#include "plodPLYCheck.h"
#include "plodPLYSamples.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

/// The samples, written once into a temporary folder.
class PLYCheck : public ::testing::Test
{
public:
  static void SetUpTestSuite()
  {
    Folder() =
      (fs::temp_directory_path() / ("plod_ply_check_" + std::to_string(::getpid()))).string();
    Valid() = plodtest::ValidPLYSamples();
    Corrupt() = plodtest::CorruptPLYSamples();
    Limits() = plodtest::ReaderLimitPLYSamples();
    ASSERT_TRUE(plodtest::WritePLYSamples(Valid(), Folder()));
    ASSERT_TRUE(plodtest::WritePLYSamples(Corrupt(), Folder()));
    ASSERT_TRUE(plodtest::WritePLYSamples(Limits(), Folder()));
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
  static std::vector<plodtest::PLYSample>& Valid()
  {
    static std::vector<plodtest::PLYSample> v;
    return v;
  }
  static std::vector<plodtest::PLYSample>& Corrupt()
  {
    static std::vector<plodtest::PLYSample> v;
    return v;
  }
  static std::vector<plodtest::PLYSample>& Limits()
  {
    static std::vector<plodtest::PLYSample> v;
    return v;
  }

  static const plodtest::PLYSample& Find(const std::string& name)
  {
    for (auto* list : { &Valid(), &Corrupt(), &Limits() })
    {
      for (const auto& s : *list)
      {
        if (s.Name == name)
        {
          return s;
        }
      }
    }
    throw std::runtime_error("no sample " + name);
  }

  /// Writes `bytes` to a file of the folder and returns its path.
  static std::string Write(const std::string& name, const std::string& bytes)
  {
    const std::string path = Folder() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
  }
};

std::string DataFolder()
{
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("PLOD_DATA_DIR"))
  {
    candidates.emplace_back(env);
  }
#ifdef PLOD_SOURCE_DIR
  candidates.emplace_back(std::string(PLOD_SOURCE_DIR) + "/../shared/data");
#endif
  for (const auto& c : candidates)
  {
    std::error_code error;
    if (fs::is_regular_file(c + "/bun_zipper.ply", error))
    {
      return c;
    }
  }
  return "";
}
} // namespace

// ---- valid files ----------------------------------------------------------------------------

TEST_F(PLYCheck, ValidFilesPassWithTheirCounts)
{
  ASSERT_GE(Valid().size(), 16u);
  for (const auto& s : Valid())
  {
    SCOPED_TRACE(s.Name);
    for (const plod::PLYReaderLimits& limits :
      { plod::PLYReaderLimits(), plod::VTKPLYReaderLimits() })
    {
      std::string why = "not cleared";
      plod::PLYSummary summary;
      EXPECT_TRUE(plod::CheckPLYFile(s.Path, &why, &summary, limits)) << why;
      EXPECT_EQ(why, "");
      EXPECT_EQ(summary.NumberOfVertices, s.Vertices);
      EXPECT_EQ(summary.NumberOfFaces, s.Faces);
      EXPECT_EQ(summary.FileBytes, static_cast<int64_t>(s.Bytes.size()));
      const plod::PLYFormat format = s.Name.find("ascii") != std::string::npos
        ? plod::PLYFormat::ASCII
        : s.Name.find("_le") != std::string::npos ? plod::PLYFormat::BinaryLittleEndian
                                                  : plod::PLYFormat::BinaryBigEndian;
      EXPECT_EQ(summary.Format, format);
    }
  }
}

TEST_F(PLYCheck, SummaryDescribesTheHeader)
{
  // the big-endian tetrahedron: two elements, 100 body bytes after the header
  const auto& be = Find("tetra_binary_be");
  plod::PLYSummary s;
  ASSERT_TRUE(plod::CheckPLYFile(be.Path, nullptr, &s));
  EXPECT_STREQ(plod::PLYFormatName(s.Format), "binary_big_endian");
  ASSERT_EQ(s.Elements.size(), 2u);
  EXPECT_EQ(s.Elements[0].Name, "vertex");
  EXPECT_EQ(s.Elements[0].Count, 4);
  ASSERT_EQ(s.Elements[0].Properties.size(), 3u);
  EXPECT_EQ(s.Elements[0].Properties[2].Name, "z");
  EXPECT_EQ(s.Elements[0].Properties[2].Type, plod::PLYType::Float32);
  EXPECT_FALSE(s.Elements[0].Properties[2].IsList);
  ASSERT_EQ(s.Elements[1].Properties.size(), 1u);
  EXPECT_TRUE(s.Elements[1].Properties[0].IsList);
  EXPECT_EQ(s.Elements[1].Properties[0].CountType, plod::PLYType::UInt8);
  EXPECT_EQ(s.Elements[1].Properties[0].Type, plod::PLYType::Int32);
  EXPECT_EQ(s.FileBytes - s.HeaderBytes, 4 * 12 + 4 * 13);
  EXPECT_EQ(s.MaxFaceSize, 3);
  EXPECT_EQ(s.TrailingBytes, 0);
  EXPECT_EQ(plod::FindPLYElement(s, "face"), &s.Elements[1]);
  EXPECT_EQ(plod::FindPLYElement(s, "edge"), nullptr);

  // aliases are the same types; the quad and the twelve-index face set the largest face
  plod::PLYSummary a;
  ASSERT_TRUE(plod::CheckPLYFile(Find("aliases_binary_be").Path, nullptr, &a));
  EXPECT_EQ(a.Elements[0].Properties[0].Type, plod::PLYType::Float64);
  EXPECT_EQ(a.MaxFaceSize, 12);
  plod::PLYSummary q;
  ASSERT_TRUE(plod::CheckPLYFile(Find("strips_quads_binary_le").Path, nullptr, &q));
  EXPECT_EQ(q.MaxFaceSize, 4) << "tristrips are not faces";
  EXPECT_EQ(q.TrailingBytes, 3) << "the three bytes after the last row";
  plod::PLYSummary qa;
  ASSERT_TRUE(plod::CheckPLYFile(Find("strips_quads_ascii").Path, nullptr, &qa));
  EXPECT_EQ(qa.TrailingBytes, 0) << "trailing blank lines do not count";

  // every type by both of its names
  plod::PLYSummary t;
  ASSERT_TRUE(plod::CheckPLYFile(Find("all_types_ascii").Path, nullptr, &t));
  const auto& props = t.Elements[0].Properties;
  ASSERT_EQ(props.size(), 19u);
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_EQ(static_cast<int>(props[3 + i].Type), i / 2) << props[3 + i].Name;
  }
  EXPECT_STREQ(plod::PLYTypeName(plod::PLYType::UInt16), "ushort");
  EXPECT_EQ(plod::PLYTypeSize(plod::PLYType::Float64), 8);
}

TEST_F(PLYCheck, NullOutputsAreAllowed)
{
  EXPECT_TRUE(plod::CheckPLYFile(Find("tetra_ascii").Path, nullptr));
  EXPECT_FALSE(plod::CheckPLYFile(Find("empty").Path, nullptr));
  EXPECT_FALSE(plod::CheckPLYFile("", nullptr));
}

TEST_F(PLYCheck, FacesOfFewerThanThreeIndicesPassWithAWarning)
{
  // issue 24: faces of 0, 1 or 2 indices are valid PLY, and vtkPLYReader reads them, but
  // vtkPolyDataNormals crashes on them. The check passes (the file is sound) and says how many
  // there are and where the first is, so that a program drops them.
  for (plodtest::PLYEncoding enc :
    { plodtest::PLYEncoding::ASCII, plodtest::PLYEncoding::Little, plodtest::PLYEncoding::Big })
  {
    plodtest::TetraPLY t;
    t.Encoding = enc;
    t.Faces = { { 0, 1, 2 }, { 0, 3, 1 }, { 2, 3 }, { 0, 2, 3 }, { 1 }, {}, { 1, 3, 2 } };
    t.DeclaredFaces = 7;
    const std::string path = Write("short_faces.ply", t.Bytes());
    for (const plod::PLYReaderLimits& limits :
      { plod::PLYReaderLimits(), plod::VTKPLYReaderLimits() })
    {
      SCOPED_TRACE(static_cast<int>(enc));
      std::string why = "not cleared";
      plod::PLYSummary s;
      ASSERT_TRUE(plod::CheckPLYFile(path, &why, &s, limits)) << why;
      EXPECT_EQ(why, "");
      EXPECT_EQ(s.NumberOfFaces, 7);
      EXPECT_EQ(s.NumberOfShortFaces, 3) << "rows 2, 4 and 5 (an empty face counts)";
      EXPECT_EQ(s.FirstShortFace, 2);
      EXPECT_EQ(s.MaxFaceSize, 3);
      // face rows 0 and 1 take 13 bytes each in binary; row 2 is line 9 + 4 + 3 in ASCII
      const std::string where = enc == plodtest::PLYEncoding::ASCII
        ? "(line 16)"
        : "(byte offset " + std::to_string(s.HeaderBytes + 48 + 26) + ")";
      EXPECT_EQ(s.Warning,
        "3 of 7 faces have fewer than 3 vertex indices (the first: element 'face' row 2 with 2 "
        "indices " +
          where +
          "); they are not polygons and must be dropped (vtkPolyDataNormals crashes on them)");
    }
  }
  // one short face: "1 index"
  plodtest::TetraPLY one;
  one.Faces[3] = { 1 };
  plod::PLYSummary s;
  ASSERT_TRUE(plod::CheckPLYFile(Write("one_short_face.ply", one.Bytes()), nullptr, &s));
  EXPECT_EQ(s.NumberOfShortFaces, 1);
  EXPECT_EQ(s.FirstShortFace, 3);
  EXPECT_NE(s.Warning.find("1 of 4 faces have fewer than 3 vertex indices (the first: element "
                           "'face' row 3 with 1 index (line 17))"),
    std::string::npos)
    << s.Warning;
  // no short faces in sound files or in lists of other elements (range grids, strips, whose
  // own warning is SurfaceElementsThatAreNotReadAreNamed's), and no warning after a failure
  for (const char* name : { "tetra_ascii", "range_scan_binary_le", "strips_quads_ascii" })
  {
    ASSERT_TRUE(plod::CheckPLYFile(Find(name).Path, nullptr, &s)) << name;
    EXPECT_EQ(s.NumberOfShortFaces, 0) << name;
    EXPECT_EQ(s.FirstShortFace, -1) << name;
    EXPECT_EQ(s.Warning.find("fewer than 3"), std::string::npos) << name;
  }
  one.Faces[1] = { 0, 3 };
  one.Faces[2] = { 0, 9, 2 }; // a short face, then an index out of range
  std::string why;
  EXPECT_FALSE(plod::CheckPLYFile(Write("short_then_bad.ply", one.Bytes()), &why, &s));
  EXPECT_NE(why.find("vertex index 9 is not in [0, 4)"), std::string::npos) << why;
  EXPECT_EQ(s.Warning, "") << "a failed check warns of nothing";
}

// ---- corrupt files ----------------------------------------------------------------------------

// Triangle strips are a surface VTK's reader drops: said, and with no faces beside them the
// points would be taken for a point cloud (issue 24). A range scan's grid is not warned of.
TEST_F(PLYCheck, SurfaceElementsThatAreNotReadAreNamed)
{
  plod::PLYSummary q;
  ASSERT_TRUE(plod::CheckPLYFile(Find("strips_quads_ascii").Path, nullptr, &q));
  EXPECT_EQ(q.Warning,
    "element 'tristrips' (1 rows) describes a surface that is not read (only 'vertex' and 'face' "
    "are)");
  const std::string onlyStrips = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                 "property float y\nproperty float z\nelement tristrips 1\n"
                                 "property list int int vertex_indices\nend_header\n"
                                 "0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0 1 2 3\n";
  plod::PLYSummary o;
  ASSERT_TRUE(plod::CheckPLYFile(Write("only_strips.ply", onlyStrips), nullptr, &o));
  EXPECT_NE(
    o.Warning.find("without faces the points are taken for a point cloud"), std::string::npos)
    << o.Warning;
  plod::PLYSummary r;
  ASSERT_TRUE(plod::CheckPLYFile(Find("range_scan_ascii").Path, nullptr, &r));
  EXPECT_EQ(r.Warning, "") << "a range scan is read as the point cloud it is";
}

TEST_F(PLYCheck, CorruptFilesFailWithAMessageNamingTheProblem)
{
  ASSERT_GE(Corrupt().size(), 60u);
  for (const auto& s : Corrupt())
  {
    SCOPED_TRACE(s.Name);
    std::string why;
    plod::PLYSummary summary;
    EXPECT_FALSE(plod::CheckPLYFile(s.Path, &why, &summary));
    EXPECT_NE(why.find(s.Expect), std::string::npos) << "message: " << why;
    EXPECT_EQ(why.find('\n'), std::string::npos) << "one line";
    EXPECT_FALSE(plod::CheckPLYFile(s.Path, &why, nullptr, plod::VTKPLYReaderLimits()));
  }
}

TEST_F(PLYCheck, MessagesGiveTheByteOffsetOrTheLine)
{
  std::string why;
  // the cut inside face row 1's list: the count is at 48 + 13 bytes into the body
  const auto& cut = Find("cut_binary_le_inside_list");
  plod::PLYSummary s;
  EXPECT_FALSE(plod::CheckPLYFile(cut.Path, &why, &s));
  EXPECT_NE(why.find("(byte offset " + std::to_string(s.HeaderBytes + 61) + ")"), std::string::npos)
    << why;
  // the big-endian index 9 is face row 2's second item
  EXPECT_FALSE(plod::CheckPLYFile(Find("index_out_of_range_binary_be").Path, &why, &s));
  EXPECT_NE(why.find("(byte offset " + std::to_string(s.HeaderBytes + 48 + 26 + 1 + 4) + ")"),
    std::string::npos)
    << why;
  // the ASCII index 9: face row 2 is line 9 + 4 + 3
  EXPECT_FALSE(plod::CheckPLYFile(Find("index_out_of_range_ascii").Path, &why));
  EXPECT_NE(why.find("(line 16)"), std::string::npos) << why;
  // a header problem names its line
  EXPECT_FALSE(plod::CheckPLYFile(Find("unknown_property_type").Path, &why));
  EXPECT_EQ(why.rfind("header line 5: ", 0), 0u) << why;
}

TEST_F(PLYCheck, ReaderLimitsRejectOnlyWhenAsked)
{
  ASSERT_GE(Limits().size(), 6u);
  for (const auto& s : Limits())
  {
    SCOPED_TRACE(s.Name);
    std::string why;
    EXPECT_TRUE(plod::CheckPLYFile(s.Path, &why)) << "valid PLY: " << why;
    EXPECT_FALSE(plod::CheckPLYFile(s.Path, &why, nullptr, plod::VTKPLYReaderLimits()));
    EXPECT_NE(why.find(s.Expect), std::string::npos) << "message: " << why;
    EXPECT_NE(why.find("vtkPLYReader (VTK 9.1)"), std::string::npos) << why;
  }
  // at the limit itself: a face of 255 vertices and a line of 4000 bytes are taken
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Little;
  t.Faces[0].assign(255, 2);
  EXPECT_TRUE(plod::CheckPLYFile(
    Write("face_255.ply", t.Bytes()), nullptr, nullptr, plod::VTKPLYReaderLimits()));
  plodtest::TetraPLY c;
  c.ExtraHeader = "comment " + std::string(4000 - 8, 'x') + "\n";
  EXPECT_TRUE(plod::CheckPLYFile(
    Write("line_4000.ply", c.Bytes()), nullptr, nullptr, plod::VTKPLYReaderLimits()));
  c.ExtraHeader = "comment " + std::string(4001 - 8, 'x') + "\n";
  EXPECT_FALSE(plod::CheckPLYFile(
    Write("line_4001.ply", c.Bytes()), nullptr, nullptr, plod::VTKPLYReaderLimits()));
}

// ---- every cut, random damage, extremes ---------------------------------------------------

TEST_F(PLYCheck, EveryCutOfABinaryBodyFails)
{
  for (const char* name : { "tetra_binary_le", "tetra_binary_be", "all_types_binary_le",
         "range_scan_binary_be", "aliases_binary_be" })
  {
    const auto& s = Find(name);
    plod::PLYSummary summary;
    ASSERT_TRUE(plod::CheckPLYFile(s.Path, nullptr, &summary)) << name;
    for (int64_t cut = summary.HeaderBytes; cut < summary.FileBytes; ++cut)
    {
      std::string why;
      const std::string path = Write("cut.ply", s.Bytes.substr(0, static_cast<size_t>(cut)));
      ASSERT_FALSE(plod::CheckPLYFile(path, &why)) << name << " cut at " << cut;
      const bool named = why.find("ends inside element") != std::string::npos ||
        why.find("are left in the file") != std::string::npos;
      EXPECT_TRUE(named) << name << " cut at " << cut << ": " << why;
    }
  }
}

TEST_F(PLYCheck, EveryCutOfAnASCIIBodyBeforeItsLastValueFails)
{
  for (const char* name : { "tetra_ascii", "all_types_ascii", "range_scan_ascii" })
  {
    const auto& s = Find(name);
    plod::PLYSummary summary;
    ASSERT_TRUE(plod::CheckPLYFile(s.Path, nullptr, &summary)) << name;
    // the last value's first byte: a cut after it may leave a shorter but valid number
    const size_t last = s.Bytes.find_last_of(' ') + 1;
    for (size_t cut = static_cast<size_t>(summary.HeaderBytes); cut < last; ++cut)
    {
      std::string why;
      ASSERT_FALSE(plod::CheckPLYFile(Write("cut.ply", s.Bytes.substr(0, cut)), &why))
        << name << " cut at " << cut;
      EXPECT_NE(why.find("element '"), std::string::npos)
        << name << " cut at " << cut << ": " << why;
    }
  }
}

TEST_F(PLYCheck, RandomDamageNeverCrashesOrHangs)
{
  // byte changes, insertions, deletions and cuts of valid files: the check must answer, with a
  // message when it rejects
  std::mt19937 rng(2024);
  int rejected = 0;
  for (int trial = 0; trial < 3000; ++trial)
  {
    const auto& s = Valid()[rng() % Valid().size()];
    std::string bytes = s.Bytes;
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
    std::string why;
    plod::PLYSummary summary;
    const bool ok =
      plod::CheckPLYFile(Write("damaged.ply", bytes), &why, &summary, plod::VTKPLYReaderLimits());
    if (!ok)
    {
      ++rejected;
      ASSERT_FALSE(why.empty());
    }
    else
    {
      ASSERT_GE(summary.FileBytes, summary.HeaderBytes);
    }
  }
  EXPECT_GT(rejected, 1500) << "most damage is found";
}

TEST_F(PLYCheck, HugeCountsAndLongHeadersEndQuickly)
{
  std::string why;
  // the largest count the header takes, with a tiny body: the arithmetic or the first list
  // shows the body is too short, without walking two billion rows
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Little;
  t.DeclaredVertices = 2147483647;
  t.WithFaces = false;
  EXPECT_FALSE(plod::CheckPLYFile(Write("huge_vertices.ply", t.Bytes()), &why));
  EXPECT_NE(why.find("ends inside element 'vertex' row 4 of 2147483647"), std::string::npos) << why;
  t.DeclaredVertices = 4;
  t.WithFaces = true;
  t.DeclaredFaces = 2147483647;
  EXPECT_FALSE(plod::CheckPLYFile(Write("huge_faces.ply", t.Bytes()), &why));
  EXPECT_NE(why.find("ends inside element 'face' row 4 of 2147483647"), std::string::npos) << why;
  t.Encoding = plodtest::PLYEncoding::ASCII;
  EXPECT_FALSE(plod::CheckPLYFile(Write("huge_faces_ascii.ply", t.Bytes()), &why));
  EXPECT_NE(why.find("ends inside element 'face' row 4 of 2147483647"), std::string::npos) << why;
  // a header that never ends: the check stops after MaxPLYHeaderBytes
  std::string endless = "ply\nformat ascii 1.0\n";
  while (endless.size() < 3 * static_cast<size_t>(plod::MaxPLYHeaderBytes))
  {
    endless += "comment and so on and so on\n";
  }
  EXPECT_FALSE(plod::CheckPLYFile(Write("endless_header.ply", endless), &why));
  EXPECT_NE(why.find("no end_header line in the first 1048576 bytes"), std::string::npos) << why;
  // one endless line
  EXPECT_FALSE(plod::CheckPLYFile(
    Write("endless_line.ply", "ply\nformat ascii 1.0\ncomment " + std::string(2 << 20, 'x')),
    &why));
  EXPECT_NE(why.find("no end_header line in the first"), std::string::npos) << why;
}

TEST_F(PLYCheck, LargeBinaryFilePasses)
{
  // 100k vertices, 200k triangles: streamed, counted exactly
  std::string body;
  const int nv = 100000, nf = 200000;
  for (int i = 0; i < nv; ++i)
  {
    for (int a = 0; a < 3; ++a)
    {
      plodtest::PutPLYValue(body, "float", i * 1e-3 + a, plodtest::PLYEncoding::Big);
    }
  }
  for (int f = 0; f < nf; ++f)
  {
    plodtest::PutPLYValue(body, "uchar", 3, plodtest::PLYEncoding::Big);
    for (int k = 0; k < 3; ++k)
    {
      plodtest::PutPLYValue(body, "int", (f + k) % nv, plodtest::PLYEncoding::Big);
    }
  }
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Big;
  t.DeclaredVertices = nv;
  t.DeclaredFaces = nf;
  plod::PLYSummary s;
  std::string why;
  ASSERT_TRUE(
    plod::CheckPLYFile(Write("large.ply", t.Header() + body), &why, &s, plod::VTKPLYReaderLimits()))
    << why;
  EXPECT_EQ(s.NumberOfVertices, nv);
  EXPECT_EQ(s.NumberOfFaces, nf);
  // the last index out of range is found at the end
  body[body.size() - 4] = static_cast<char>(0x7f); // big endian: the high byte
  EXPECT_FALSE(plod::CheckPLYFile(Write("large.ply", t.Header() + body), &why));
  EXPECT_NE(why.find("element 'face' row 199999"), std::string::npos) << why;
}

// ---- the Stanford files ------------------------------------------------------------------------

TEST(PLYCheckData, StanfordFilesPass)
{
  const std::string dir = DataFolder();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  // counts from the data folder's README
  const std::map<std::string, std::pair<int64_t, int64_t>> known = {
    { "bun_zipper.ply", { 35947, 69451 } }, { "bun_zipper_res2.ply", { 8171, 16301 } },
    { "bun_zipper_res3.ply", { 1889, 3851 } }, { "bun_zipper_res4.ply", { 453, 948 } },
    { "lucy.ply", { 7502, 15000 } }, { "bun000.ply", { 40256, 0 } }, { "top3.ply", { 36023, 0 } }
  };
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir))
  {
    if (entry.path().extension() != ".ply")
    {
      continue;
    }
    ++files;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    std::string why;
    plod::PLYSummary s;
    EXPECT_TRUE(plod::CheckPLYFile(entry.path().string(), &why, &s, plod::VTKPLYReaderLimits()))
      << why;
    EXPECT_EQ(s.TrailingBytes, 0);
    const auto k = known.find(name);
    if (k != known.end())
    {
      EXPECT_EQ(s.NumberOfVertices, k->second.first);
      EXPECT_EQ(s.NumberOfFaces, k->second.second);
    }
    if (name == "lucy.ply")
    {
      EXPECT_EQ(s.Format, plod::PLYFormat::BinaryLittleEndian);
    }
    if (name == "bun000.ply")
    {
      EXPECT_EQ(plod::FindPLYElement(s, "range_grid")->Count, 204800);
    }
  }
  EXPECT_GE(files, 15);
}
