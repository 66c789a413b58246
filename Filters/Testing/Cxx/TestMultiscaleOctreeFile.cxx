// SPDX-License-Identifier: BSD-3-Clause
// vtkMultiscaleOctreeWriter and vtkMultiscaleOctreeReader: every array identical after a round
// trip (mapped and read into memory), the same cut and patches as from the built octree, the
// mapping outliving the reader, copy-on-write edits, and a corrupt-file battery (truncated at
// many offsets, flipped bytes everywhere in the header and directory and across the data, wrong
// version, wrong magic, empty and missing files): a clear error and an empty octree, no crash.
#include "plodPageLoader.h"
#include "plodSelector.h"
#include "plodTestUtilities.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMath.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <csignal>
#include <initializer_list>

#include <dirent.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

namespace
{
std::string TempPath(const std::string& name)
{
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/plod_test_" + std::to_string(::getpid()) +
    "_" + name;
}

std::vector<char> ReadBytes(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteBytes(const std::string& path, const std::vector<char>& bytes)
{
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// A closed blob with per-point diffuse and specular arrays (so that the material ranges vary).
vtkSmartPointer<vtkMultiscaleOctree> BuildOctree(int res = 40)
{
  auto blob = plodtest::MakeBlob(5, res, 0.25);
  vtkNew<vtkFloatArray> kd, ks;
  kd->SetName("Kd");
  ks->SetName("Ks");
  for (vtkIdType i = 0; i < blob->GetNumberOfPoints(); ++i)
  {
    kd->InsertNextValue(0.2f + 0.6f * float(i % 7) / 7.0f);
    ks->InsertNextValue(0.1f + 0.3f * float(i % 5) / 5.0f);
  }
  blob->GetPointData()->AddArray(kd);
  blob->GetPointData()->AddArray(ks);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  builder->SetDiffuseArrayName("Kd");
  builder->SetSpecularArrayName("Ks");
  builder->Update();
  auto octree = vtkSmartPointer<vtkMultiscaleOctree>::New();
  octree->DeepCopy(builder->GetOutput());
  return octree;
}

bool Write(vtkMultiscaleOctree* octree, const std::string& path, bool compact = false)
{
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->SetInputData(octree);
  writer->SetFileName(path.c_str());
  writer->SetCompact(compact);
  return writer->Write() == 1;
}

/// Every array of the three field data byte for byte, and the octree's scalars.
void ExpectIdentical(vtkMultiscaleOctree* a, vtkMultiscaleOctree* b, const std::string& what)
{
  ASSERT_EQ(a->GetNumberOfNodes(), b->GetNumberOfNodes()) << what;
  for (int g = 0; g < 3; ++g)
  {
    vtkFieldData* fa = g == 0 ? a->GetNodeData()
      : g == 1                ? a->GetClusterData()
                              : a->GetSurfaceData();
    vtkFieldData* fb = g == 0 ? b->GetNodeData()
      : g == 1                ? b->GetClusterData()
                              : b->GetSurfaceData();
    int compared = 0;
    for (int i = 0; i < fa->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* x = fa->GetArray(i);
      if (!x || std::strcmp(x->GetName(), "CutState") == 0 ||
        std::strcmp(x->GetName(), "CullMask") == 0)
      {
        continue;
      }
      vtkDataArray* y = fb->GetArray(x->GetName());
      ASSERT_NE(y, nullptr) << what << ": " << x->GetName();
      ASSERT_EQ(x->GetDataType(), y->GetDataType()) << x->GetName();
      ASSERT_EQ(x->GetNumberOfComponents(), y->GetNumberOfComponents()) << x->GetName();
      ASSERT_EQ(x->GetNumberOfTuples(), y->GetNumberOfTuples()) << x->GetName();
      const size_t bytes = size_t(x->GetNumberOfValues()) * size_t(x->GetDataTypeSize());
      EXPECT_EQ(std::memcmp(x->GetVoidPointer(0), y->GetVoidPointer(0), bytes), 0)
        << what << ": " << x->GetName();
      ++compared;
    }
    EXPECT_EQ(compared, g == 0 ? 15 : g == 1 ? 4 : 6) << what;
  }
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(a->GetOrigin()[k], b->GetOrigin()[k]);
  }
  EXPECT_EQ(a->GetRootEdge(), b->GetRootEdge());
  EXPECT_EQ(a->GetFinestLevel(), b->GetFinestLevel());
  EXPECT_EQ(a->GetHasMaterialArrays(), b->GetHasMaterialArrays());
  EXPECT_EQ(a->GetCoarsestDrawnLevel(), b->GetCoarsestDrawnLevel());
  EXPECT_EQ(a->GetNumberOfBoundaryEdges(), b->GetNumberOfBoundaryEdges());
  EXPECT_EQ(a->GetNumberOfNonManifoldEdges(), b->GetNumberOfNonManifoldEdges());
  EXPECT_EQ(a->GetNumberOfMisorientedEdges(), b->GetNumberOfMisorientedEdges());
}

/// The selector and patch generator on `octree` from a fixed eye: the drawn triangles.
vtkSmartPointer<vtkPolyData> Draw(vtkMultiscaleOctree* octree, plodtest::ErrorRecorder* errors)
{
  vtkNew<vtkPerceptualLODSelector> selector;
  vtkNew<vtkMultiscalePatchGenerator> patches;
  selector->SetInputData(octree);
  patches->SetInputConnection(selector->GetOutputPort());
  selector->SetEyePosition(0.3, 0.2, 3.0);
  selector->SetViewportSize(640, 480);
  if (errors)
  {
    selector->AddObserver(vtkCommand::ErrorEvent, errors);
    patches->AddObserver(vtkCommand::ErrorEvent, errors);
  }
  patches->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(patches->GetOutput());
  return out;
}

struct ReadResult
{
  vtkSmartPointer<vtkMultiscaleOctree> Octree;
  std::string Error;
  bool Reported = false; // an ErrorEvent was raised
};

ReadResult Read(
  const std::string& path, bool verify = false, bool map = true, bool* compact = nullptr)
{
  vtkNew<vtkMultiscaleOctreeReader> reader;
  vtkNew<plodtest::ErrorRecorder> errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(path.c_str());
  reader->SetVerifyChecksums(verify);
  reader->SetMemoryMap(map);
  reader->Update();
  ReadResult r;
  r.Octree = reader->GetOutput();
  r.Error = reader->GetErrorMessage();
  r.Reported = !errors->Errors.empty();
  if (compact)
  {
    *compact = reader->GetCompact();
  }
  return r;
}
}

TEST(MultiscaleOctreeFile, RoundTripKeepsEveryArrayAndTheImage)
{
  auto octree = BuildOctree();
  ASSERT_GT(octree->GetNumberOfNodes(), 100);
  ASSERT_TRUE(octree->GetHasMaterialArrays());
  const auto reference = Draw(octree, nullptr);
  ASSERT_GT(reference->GetNumberOfPolys(), 0);
  for (bool compact : { false, true })
  {
    SCOPED_TRACE(compact ? "compact layout" : "mapped layout");
    const std::string path = TempPath("roundtrip.plod");
    ASSERT_TRUE(Write(octree, path, compact));
    EXPECT_TRUE(vtkMultiscaleOctreeReader::CanReadFile(path.c_str()));
    for (bool map : { true, false })
      for (bool verify : { false, true })
      {
        bool decoded = !compact;
        ReadResult r = Read(path, verify, map, &decoded);
        ASSERT_TRUE(r.Error.empty()) << r.Error;
        EXPECT_EQ(decoded, compact);
        ExpectIdentical(octree, r.Octree, map ? "mapped" : "read");
        EXPECT_TRUE(r.Octree->IsConsistent());
        // the same cut and the same triangles, at the same places
        auto drawn = Draw(r.Octree, nullptr);
        ASSERT_EQ(drawn->GetNumberOfPolys(), reference->GetNumberOfPolys());
        ASSERT_EQ(drawn->GetNumberOfPoints(), reference->GetNumberOfPoints());
        for (vtkIdType i = 0; i < drawn->GetNumberOfPoints(); i += 17)
        {
          double p[3], q[3];
          drawn->GetPoint(i, p);
          reference->GetPoint(i, q);
          EXPECT_EQ(p[0], q[0]);
          EXPECT_EQ(p[1], q[1]);
          EXPECT_EQ(p[2], q[2]);
        }
      }
    std::remove(path.c_str());
  }
}

TEST(MultiscaleOctreeFile, MappedArraysOutliveTheReaderAndEditsStayInMemory)
{
  auto octree = BuildOctree(24);
  const std::string path = TempPath("lifetime.plod");
  ASSERT_TRUE(Write(octree, path));
  const std::vector<char> before = ReadBytes(path);
  vtkSmartPointer<vtkDataArray> vertex;
  {
    vtkNew<vtkMultiscaleOctreeReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    ASSERT_TRUE(reader->GetMapped());
    vertex = reader->GetOutput()->GetNodeData()->GetArray("Vertex");
  } // the reader and its output are gone; the array keeps the mapping
  ASSERT_NE(vertex, nullptr);
  auto* original = octree->GetNodeData()->GetArray("Vertex");
  for (vtkIdType i = 0; i < vertex->GetNumberOfTuples(); ++i)
  {
    ASSERT_EQ(vertex->GetComponent(i, 1), original->GetComponent(i, 1));
  }
  vertex->SetComponent(0, 0, 123.0); // copy-on-write: the file does not change
  EXPECT_EQ(vertex->GetComponent(0, 0), 123.0);
  vertex = nullptr; // releases the mapping
  EXPECT_EQ(ReadBytes(path), before);
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, GhostFlagsAreNotStoredAndTheWriterSaysSo)
{
  // the format is unchanged: an octree with ghost points (distributed rendering) is written
  // with a warning, and reads back as the same octree without its flags
  auto octree = BuildOctree(24);
  const std::string path = TempPath("ghosts.plod");
  vtkNew<plodtest::ErrorRecorder> quiet;
  {
    vtkNew<vtkMultiscaleOctreeWriter> writer;
    writer->AddObserver(vtkCommand::WarningEvent, quiet);
    writer->SetInputData(octree);
    writer->SetFileName(path.c_str());
    ASSERT_EQ(writer->Write(), 1);
  }
  EXPECT_TRUE(quiet->Warnings.empty()) << "no ghosts, no warning";
  const std::vector<char> plain = ReadBytes(path);
  octree->AllocatePointGhosts();
  auto* flags = vtkUnsignedCharArray::SafeDownCast(
    octree->GetSurfaceData()->GetArray(vtkMultiscaleOctree::PointGhostArrayName()));
  ASSERT_NE(flags, nullptr);
  for (vtkIdType p = 0; p < flags->GetNumberOfTuples(); ++p)
    flags->SetValue(p, p % 3 == 0 ? 1 : 0);
  ASSERT_TRUE(octree->IsConsistent());
  vtkNew<plodtest::ErrorRecorder> warnings;
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->AddObserver(vtkCommand::WarningEvent, warnings);
  writer->SetInputData(octree);
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1);
  ASSERT_EQ(warnings->Warnings.size(), 1u);
  EXPECT_NE(warnings->Warnings[0].find("does not store ghost flags"), std::string::npos)
    << warnings->Warnings[0];
  EXPECT_EQ(ReadBytes(path), plain) << "the same file as without the flags";
  ReadResult r = Read(path);
  ASSERT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_FALSE(r.Octree->HasPointGhosts());
  octree->GetSurfaceData()->RemoveArray(vtkMultiscaleOctree::PointGhostArrayName());
  ExpectIdentical(octree, r.Octree, "ghosts dropped");
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, MisorientedEdgeCountRoundTrips)
{
  auto octree = BuildOctree(16);
  octree->SetNumberOfMisorientedEdges(7); // as for a mesh whose triangles disagree
  const std::string path = TempPath("misoriented.plod");
  ASSERT_TRUE(Write(octree, path));
  ReadResult r = Read(path, true);
  ASSERT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_EQ(r.Octree->GetNumberOfMisorientedEdges(), 7);
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, CoarsestDrawnLevelRoundTripsAndIsChecked)
{
  auto octree = BuildOctree(16);
  octree->SetCoarsestDrawnLevel(3); // as for an octree assembled from pieces
  const std::string path = TempPath("coarsest.plod");
  ASSERT_TRUE(Write(octree, path));
  ReadResult r = Read(path, true);
  ASSERT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_EQ(r.Octree->GetCoarsestDrawnLevel(), 3);
  // finer than the finest level: refused by the writer (a file saying so is refused by the
  // reader's header check, behind the header checksum)
  octree->SetCoarsestDrawnLevel(octree->GetFinestLevel() + 1);
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  vtkNew<plodtest::ErrorRecorder> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->SetInputData(octree);
  const std::string bad = TempPath("coarsest-bad.plod");
  writer->SetFileName(bad.c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("coarsest drawn level"), std::string::npos)
    << writer->GetErrorMessage();
  struct stat st;
  EXPECT_NE(stat(bad.c_str(), &st), 0) << "nothing written";
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, EmptyOctreeRoundTrips)
{
  vtkNew<vtkMultiscaleOctree> empty;
  const std::string path = TempPath("empty.plod");
  ASSERT_TRUE(Write(empty, path));
  ReadResult r = Read(path);
  EXPECT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_EQ(r.Octree->GetNumberOfNodes(), 0);
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, WriterRefusesBadInputWithAMessage)
{
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  vtkNew<plodtest::ErrorRecorder> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  auto octree = BuildOctree(16);
  writer->SetInputData(octree);
  EXPECT_EQ(writer->Write(), 0); // no file name
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("file name"), std::string::npos);
  writer->SetFileName("/nonexistent-folder/x.plod");
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("cannot create a temporary file"),
    std::string::npos)
    << writer->GetErrorMessage();
  // an inconsistent octree is not written
  vtkNew<vtkMultiscaleOctree> bad;
  bad->DeepCopy(octree);
  bad->GetNodeData()->GetArray("Parent")->SetComponent(3, 0, 1e6);
  bad->GetNodeData()->GetArray("Parent")->Modified();
  const std::string path = TempPath("bad.plod");
  writer->SetInputData(bad);
  writer->SetFileName(path.c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("inconsistent"), std::string::npos);
  EXPECT_FALSE(errors->Errors.empty());
  std::remove(path.c_str());
}

namespace
{
/// The corrupt-file battery on a file of either layout.
void ExpectCorruptFilesRefused(bool compact)
{
  auto octree = BuildOctree(20);
  const std::string good = TempPath("good.plod");
  ASSERT_TRUE(Write(octree, good, compact));
  const std::vector<char> bytes = ReadBytes(good);
  const size_t header = 128 + 64 * 25;
  ASSERT_GT(bytes.size(), header + 4096);
  const std::string path = TempPath("corrupt.plod");
  int cases = 0;
  auto expectRefused = [&](const std::vector<char>& b, const std::string& what,
                         const std::string& phrase = "") {
    WriteBytes(path, b);
    for (bool map : { true, false })
    {
      ReadResult r = Read(path, false, map);
      EXPECT_FALSE(r.Error.empty()) << what;
      EXPECT_TRUE(r.Reported) << what;
      EXPECT_EQ(r.Octree->GetNumberOfNodes(), 0) << what;
      if (!phrase.empty())
      {
        EXPECT_NE(r.Error.find(phrase), std::string::npos) << what << ": " << r.Error;
      }
    }
    ++cases;
  };
  // truncated: inside the header, the directory, at page boundaries, one byte short
  for (size_t cut : { size_t(0), size_t(1), size_t(7), size_t(64), size_t(127), size_t(128),
         size_t(200), header - 1, header, size_t(4096), size_t(8191), bytes.size() / 2,
         bytes.size() - 4096, bytes.size() - 1 })
  {
    std::vector<char> b(bytes.begin(), bytes.begin() + std::min(cut, bytes.size() - 1));
    expectRefused(b, "truncated at " + std::to_string(cut));
  }
  expectRefused(
    std::vector<char>(bytes.begin(), bytes.begin() + 4096 * 3), "truncated", "truncated");
  // longer than written
  {
    std::vector<char> b = bytes;
    b.push_back(0);
    expectRefused(b, "one byte appended", "longer than written");
  }
  // foreign and wrong-version files
  {
    std::vector<char> b = bytes;
    b[0] = 'X';
    expectRefused(b, "wrong magic", "not an octree file");
    b = bytes;
    b[8] = 3;
    expectRefused(b, "version 3", "version 3");
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n";
    expectRefused(std::vector<char>(ply.begin(), ply.end()), "a PLY file");
    expectRefused(std::vector<char>(200, 0), "zeros", "not an octree file");
  }
  // every byte of the header and directory flipped in turn: refused by the checks or the
  // header checksum
  for (size_t i = 0; i < header; ++i)
  {
    std::vector<char> b = bytes;
    b[i] = static_cast<char>(b[i] ^ 0x5a);
    expectRefused(b, "byte " + std::to_string(i) + " flipped");
  }
  // data damaged: refused with VerifyChecksums; without it, the filters refuse what they
  // cannot use, and nothing crashes. A compact file's damaged block is refused on every open.
  std::mt19937 rng(9);
  std::uniform_int_distribution<size_t> at(4096, bytes.size() - 1);
  int caughtLater = 0;
  for (int trial = 0; trial < 60; ++trial)
  {
    std::vector<char> b = bytes;
    const size_t i = at(rng);
    b[i] = static_cast<char>(b[i] ^ 0xff);
    WriteBytes(path, b);
    ReadResult checked = Read(path, true, true);
    if (checked.Error.empty())
    {
      // the byte was padding between arrays: nothing read changed
      ExpectIdentical(octree, checked.Octree, "padding byte " + std::to_string(i));
      continue;
    }
    // a compact array's table (its blocks' sizes) may be caught before its checksum
    EXPECT_TRUE(checked.Error.find("checksum") != std::string::npos ||
      (compact && checked.Error.find("block") != std::string::npos))
      << "byte " << i << ": " << checked.Error;
    EXPECT_EQ(checked.Octree->GetNumberOfNodes(), 0);
    ReadResult unchecked = Read(path, false, true);
    if (compact)
    {
      EXPECT_EQ(unchecked.Error, checked.Error) << "byte " << i;
      EXPECT_EQ(unchecked.Octree->GetNumberOfNodes(), 0);
      ++caughtLater;
      ++cases;
      continue;
    }
    ASSERT_TRUE(unchecked.Error.empty());
    vtkNew<plodtest::ErrorRecorder> errors;
    Draw(unchecked.Octree, errors);
    caughtLater += errors->Errors.empty() ? 0 : 1;
    ++cases;
  }
  EXPECT_GT(caughtLater, 0) << "some damage is structural and the filters refuse it";
  // missing file, a folder
  expectRefused({}, "empty file");
  {
    ReadResult r = Read(TempPath("does-not-exist.plod"));
    EXPECT_NE(r.Error.find("cannot open"), std::string::npos) << r.Error;
    r = Read("/tmp");
    EXPECT_FALSE(r.Error.empty());
    EXPECT_EQ(r.Octree->GetNumberOfNodes(), 0);
  }
  EXPECT_GT(cases, header);
  std::remove(path.c_str());
  std::remove(good.c_str());
}
}

TEST(MultiscaleOctreeFile, CorruptFilesAreClearErrorsNeverCrashes)
{
  ExpectCorruptFilesRefused(false);
}

TEST(MultiscaleOctreeFile, CorruptCompactFilesAreRefusedOnEveryOpen)
{
  ExpectCorruptFilesRefused(true);
}

// ------------------------------------------------------------------------------------------------
// Nothing lost, nothing hung: safe writes, files changed underneath, files that are not files

namespace
{
/// The entries of the temporary folder whose name starts with `prefix` (a writer's temporary
/// files are `.<name>.<random>.tmp` beside the target).
int CountEntries(const std::string& prefix)
{
  const size_t slash = prefix.find_last_of('/');
  const std::string dir = prefix.substr(0, slash);
  const std::string start = prefix.substr(slash + 1);
  int n = 0;
  if (DIR* d = ::opendir(dir.c_str()))
  {
    while (dirent* e = ::readdir(d))
    {
      n += std::string(e->d_name).rfind(start, 0) == 0 ? 1 : 0;
    }
    ::closedir(d);
  }
  return n;
}

/// The temporary files a save to `path` may have left: `.<name>.*` beside it.
int LeftoverTemporaries(const std::string& path)
{
  const size_t slash = path.find_last_of('/');
  return CountEntries(path.substr(0, slash + 1) + "." + path.substr(slash + 1) + ".");
}

/// Writes `octree` to `path` while the process may write files of at most `limit` bytes (as a
/// full disk would stop it: writes past the limit fail with EFBIG); the writer's message.
std::string WriteWithFileSizeLimit(vtkMultiscaleOctree* octree, const std::string& path,
  rlim_t limit, int* result, bool compact = false)
{
  struct rlimit old;
  ::getrlimit(RLIMIT_FSIZE, &old);
  struct rlimit small = old;
  small.rlim_cur = limit;
  auto* previous = std::signal(SIGXFSZ, SIG_IGN);
  ::setrlimit(RLIMIT_FSIZE, &small);
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  vtkNew<plodtest::ErrorRecorder> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->SetInputData(octree);
  writer->SetFileName(path.c_str());
  writer->SetCompact(compact);
  *result = writer->Write();
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  return writer->GetErrorMessage();
}

bool IsFifo(const std::string& path)
{
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}
}

namespace
{
/// A save that fails half way (a full disk), in either layout.
void FailedOverwrite(bool compact)
{
  auto small = BuildOctree(16);
  auto large = BuildOctree(40);
  const std::string path = TempPath("keep.plod");
  ASSERT_TRUE(Write(small, path, compact));
  const std::vector<char> before = ReadBytes(path);
  // a disk that fills up half way through the new file
  int result = 1;
  const std::string message = WriteWithFileSizeLimit(large, path, 48 * 1024, &result, compact);
  EXPECT_EQ(result, 0);
  EXPECT_NE(message.find("failed"), std::string::npos) << message;
  EXPECT_NE(message.find("the existing file is unchanged"), std::string::npos) << message;
  EXPECT_EQ(ReadBytes(path), before) << "the old file was touched by a failed save";
  EXPECT_EQ(LeftoverTemporaries(path), 0);
  ReadResult r = Read(path, true);
  EXPECT_TRUE(r.Error.empty()) << r.Error;
  ExpectIdentical(small, r.Octree, "after a failed overwrite");
  // and a new file that cannot be finished is not made at all
  const std::string fresh = TempPath("never.plod");
  std::remove(fresh.c_str());
  const std::string second = WriteWithFileSizeLimit(large, fresh, 48 * 1024, &result, compact);
  EXPECT_EQ(result, 0);
  EXPECT_NE(second.find("no file was made"), std::string::npos) << second;
  EXPECT_NE(::access(fresh.c_str(), F_OK), 0) << "a partial file was left";
  EXPECT_EQ(LeftoverTemporaries(fresh), 0);
  // a save that succeeds replaces the file and keeps its permissions
  ASSERT_EQ(::chmod(path.c_str(), 0640), 0);
  ASSERT_TRUE(Write(large, path, compact));
  struct stat st;
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  ExpectIdentical(large, Read(path).Octree, "after a good overwrite");
  std::remove(path.c_str());
}
}

TEST(MultiscaleOctreeFile, FailedOverwriteLeavesTheOldFileByteIdentical)
{
  for (bool compact : { false, true })
  {
    SCOPED_TRACE(compact ? "compact layout" : "mapped layout");
    FailedOverwrite(compact);
  }
}

TEST(MultiscaleOctreeFile, TargetsThatAreNotRegularFilesAreRefusedAndKept)
{
  auto octree = BuildOctree(16);
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  vtkNew<plodtest::ErrorRecorder> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->SetInputData(octree);
  // a FIFO (writing would wait for a reader), and a link to it
  const std::string fifo = TempPath("target.fifo");
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string link = TempPath("fifo-link.plod");
  std::remove(link.c_str());
  ASSERT_EQ(::symlink(fifo.c_str(), link.c_str()), 0);
  for (const std::string& target : { fifo, link })
  {
    writer->SetFileName(target.c_str());
    EXPECT_EQ(writer->Write(), 0) << target;
    EXPECT_NE(std::string(writer->GetErrorMessage()).find("is a FIFO"), std::string::npos)
      << writer->GetErrorMessage();
    EXPECT_TRUE(IsFifo(fifo)) << "the FIFO was replaced";
  }
  struct stat st;
  ASSERT_EQ(::lstat(link.c_str(), &st), 0);
  EXPECT_TRUE(S_ISLNK(st.st_mode));
  // a directory
  const std::string dir = TempPath("target-dir");
  ::mkdir(dir.c_str(), 0700);
  writer->SetFileName(dir.c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("is a directory"), std::string::npos)
    << writer->GetErrorMessage();
  ASSERT_EQ(::stat(dir.c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode));
  // a device node (made only where the test may: as root)
  const std::string device = TempPath("target-null");
  std::remove(device.c_str());
  if (::mknod(device.c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0)
  {
    writer->SetFileName(device.c_str());
    EXPECT_EQ(writer->Write(), 0);
    EXPECT_NE(
      std::string(writer->GetErrorMessage()).find("is a character device"), std::string::npos)
      << writer->GetErrorMessage();
    ASSERT_EQ(::lstat(device.c_str(), &st), 0) << "the device node was deleted";
    EXPECT_TRUE(S_ISCHR(st.st_mode));
    std::remove(device.c_str());
  }
  EXPECT_EQ(LeftoverTemporaries(fifo), 0);
  std::remove(link.c_str());
  std::remove(fifo.c_str());
  ::rmdir(dir.c_str());
}

TEST(MultiscaleOctreeFile, SymbolicLinkStaysALinkAndItsTargetIsReplaced)
{
  auto a = BuildOctree(16);
  auto b = BuildOctree(24);
  const std::string file = TempPath("linked.plod");
  const std::string link = TempPath("link.plod");
  ASSERT_TRUE(Write(a, file));
  std::remove(link.c_str());
  ASSERT_EQ(::symlink(file.c_str(), link.c_str()), 0);
  ASSERT_TRUE(Write(b, link));
  struct stat st;
  ASSERT_EQ(::lstat(link.c_str(), &st), 0);
  EXPECT_TRUE(S_ISLNK(st.st_mode)) << "the link was replaced by a file";
  ExpectIdentical(b, Read(file).Octree, "the link's target");
  EXPECT_EQ(LeftoverTemporaries(file), 0);
  std::remove(link.c_str());
  std::remove(file.c_str());
}

TEST(MultiscaleOctreeFile, SavingOverAnOpenFileKeepsItsReadersDrawing)
{
  auto a = BuildOctree(16);
  auto b = BuildOctree(40);
  const std::string path = TempPath("open.plod");
  ASSERT_TRUE(Write(a, path));
  vtkNew<vtkMultiscaleOctreeReader> reader;
  vtkNew<plodtest::ErrorRecorder> errors;
  reader->SetFileName(path.c_str());
  vtkNew<vtkPerceptualLODSelector> selector;
  vtkNew<vtkMultiscalePatchGenerator> patches;
  selector->SetInputConnection(reader->GetOutputPort());
  patches->SetInputConnection(selector->GetOutputPort());
  selector->SetViewportSize(640, 480);
  for (vtkAlgorithm* alg : std::initializer_list<vtkAlgorithm*>{ reader, selector, patches })
  {
    alg->AddObserver(vtkCommand::ErrorEvent, errors);
    alg->AddObserver(vtkCommand::WarningEvent, errors);
  }
  selector->SetEyePosition(0.3, 0.2, 3.0);
  patches->Update();
  ASSERT_TRUE(reader->GetMapped());
  reader->GetOutput()->AddObserver(vtkCommand::WarningEvent, errors); // the octree warns
  const vtkIdType drawnBefore = patches->GetOutput()->GetNumberOfPolys();
  ASSERT_GT(drawnBefore, 0);
  ASSERT_EQ(Draw(a, nullptr)->GetNumberOfPolys(), drawnBefore);
  // another writer (here the same process) saves a different octree over the open file
  ASSERT_TRUE(Write(b, path));
  selector->SetEyePosition(0.3, 0.2, 3.0001); // the next frame
  patches->Update();
  EXPECT_TRUE(errors->Errors.empty()) << errors->Errors.front();
  EXPECT_EQ(patches->GetOutput()->GetNumberOfPolys(), drawnBefore)
    << "the open octree changed under its reader";
  bool warned = false;
  for (const std::string& w : errors->Warnings)
  {
    warned = warned || w.find("was replaced by another file") != std::string::npos;
  }
  EXPECT_TRUE(warned) << "no warning that the file was replaced";
  EXPECT_EQ(errors->Warnings.size(), 1u) << "the replacement was reported more than once";
  // the new file is read when asked
  reader->Modified();
  patches->Update();
  EXPECT_TRUE(errors->Errors.empty());
  EXPECT_EQ(patches->GetOutput()->GetNumberOfPolys(), Draw(b, nullptr)->GetNumberOfPolys());
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, FileChangedInPlaceIsRefusedNotACrash)
{
  auto a = BuildOctree(24);
  const std::string path = TempPath("inplace.plod");
  ASSERT_TRUE(Write(a, path));
  vtkNew<vtkMultiscaleOctreeReader> reader;
  vtkNew<plodtest::ErrorRecorder> errors;
  reader->SetFileName(path.c_str());
  vtkNew<vtkPerceptualLODSelector> selector;
  vtkNew<vtkMultiscalePatchGenerator> patches;
  selector->SetInputConnection(reader->GetOutputPort());
  patches->SetInputConnection(selector->GetOutputPort());
  selector->AddObserver(vtkCommand::ErrorEvent, errors);
  patches->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  selector->SetViewportSize(640, 480);
  selector->SetEyePosition(0.3, 0.2, 3.0);
  patches->Update();
  ASSERT_GT(patches->GetOutput()->GetNumberOfPolys(), 0);
  ASSERT_TRUE(errors->Errors.empty());
  // a program that truncates and rewrites the file where it lies: the mapped pages past the new
  // end would fault (SIGBUS) if read
  ASSERT_EQ(::truncate(path.c_str(), 4096), 0);
  selector->SetEyePosition(0.3, 0.2, 3.0001);
  patches->Update();
  EXPECT_TRUE(errors->HasError("changed in place")) << "no error for a file changed in place";
  EXPECT_EQ(patches->GetOutput()->GetNumberOfPolys(), 0);
  // a writer refuses to save an octree whose mapped file changed
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->SetInputConnection(reader->GetOutputPort());
  const std::string copy = TempPath("inplace-copy.plod");
  writer->SetFileName(copy.c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("changed in place"), std::string::npos)
    << writer->GetErrorMessage();
  // reading again says what the file now is
  errors->Errors.clear();
  reader->Modified();
  patches->Update();
  EXPECT_NE(std::string(reader->GetErrorMessage()).find("truncated"), std::string::npos)
    << reader->GetErrorMessage();
  std::remove(path.c_str());
  std::remove(copy.c_str());
}

TEST(MultiscaleOctreeFile, FifoIsRefusedWithoutWaiting)
{
  // a FIFO with no writer: opening it to read would block forever (the alarm ends a hang)
  const std::string fifo = TempPath("model.plod");
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ::alarm(60);
  EXPECT_FALSE(vtkMultiscaleOctreeReader::CanReadFile(fifo.c_str()));
  ReadResult r = Read(fifo);
  EXPECT_NE(r.Error.find("is a FIFO"), std::string::npos) << r.Error;
  EXPECT_TRUE(r.Reported);
  EXPECT_EQ(r.Octree->GetNumberOfNodes(), 0);
  const std::string dir = TempPath("model-dir.plod");
  ::mkdir(dir.c_str(), 0700);
  r = Read(dir);
  EXPECT_NE(r.Error.find("is a directory"), std::string::npos) << r.Error;
  EXPECT_FALSE(vtkMultiscaleOctreeReader::CanReadFile(dir.c_str()));
  ::alarm(0);
  std::remove(fifo.c_str());
  ::rmdir(dir.c_str());
}

// The compact layout on a real scan: lossless (the same arrays bit for bit) and at most 24 bytes
// per input triangle, under half the mapped file; the octree built into a compact file in pieces
// (vtkMultiscaleOctreeBuilder::SetCompactOctreeFile) is the octree built into a mapped one.
TEST(MultiscaleOctreeFile, CompactFileOfAScanIsLosslessAndSmall)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  const std::string ply = dir + "/bun_zipper.ply";
  auto bunny = plodtest::ReadPLY(ply);
  ASSERT_NE(bunny, nullptr);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(bunny);
  builder->Update();
  vtkMultiscaleOctree* octree = builder->GetOutput();
  const double triangles = double(bunny->GetNumberOfPolys());
  const std::string mapped = TempPath("bunny.plod"), compact = TempPath("bunny-compact.plod");
  ASSERT_TRUE(Write(octree, mapped, false));
  ASSERT_TRUE(Write(octree, compact, true));
  const double mappedBytes = double(ReadBytes(mapped).size());
  const double compactBytes = double(ReadBytes(compact).size());
  EXPECT_LE(compactBytes / triangles, 24.0) << compactBytes << " bytes";
  EXPECT_LT(compactBytes, 0.5 * mappedBytes) << compactBytes << " of " << mappedBytes;
  bool decoded = false;
  ReadResult r = Read(compact, false, true, &decoded);
  ASSERT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_TRUE(decoded);
  ExpectIdentical(octree, r.Octree, "the bunny, compact");

  // built in pieces into a compact file: the same arrays as into a mapped one
  const std::string pieces = TempPath("bunny-pieces.plod");
  const std::string compactPieces = TempPath("bunny-pieces-compact.plod");
  vtkSmartPointer<vtkMultiscaleOctree> built[2];
  for (bool c : { false, true })
  {
    vtkNew<vtkMultiscaleOctreeBuilder> fromFile;
    fromFile->SetFileName(ply.c_str());
    fromFile->SetOctreeFileName((c ? compactPieces : pieces).c_str());
    fromFile->SetBuildInPieces(true);
    fromFile->SetCompactOctreeFile(c);
    fromFile->Update();
    ASSERT_GT(fromFile->GetOutput()->GetNumberOfNodes(), 0);
    built[c] = vtkSmartPointer<vtkMultiscaleOctree>::New();
    built[c]->ShallowCopy(fromFile->GetOutput());
  }
  ExpectIdentical(built[0], built[1], "built in pieces, compact");
  EXPECT_LT(ReadBytes(compactPieces).size(), ReadBytes(pieces).size() / 2);
  for (const std::string& p : { mapped, compact, pieces, compactPieces })
  {
    std::remove(p.c_str());
  }
}

/// Whether this process can count its mapped pages (the cache limit's tests need it).
bool PageMapReadable()
{
  std::FILE* pagemap = std::fopen("/proc/self/pagemap", "rb");
  if (pagemap)
    std::fclose(pagemap);
  return pagemap != nullptr;
}

/// The cells of `selector`'s last cut drawn coarser while their pages are read.
vtkIdType AwaitingCells(vtkPerceptualLODSelector* selector)
{
  auto* state = selector->GetOutput()->GetNodeData()->GetArray("CutState");
  auto* reason = selector->GetOutput()->GetNodeData()->GetArray("CutReason");
  vtkIdType k = 0;
  for (vtkIdType n = 0; state && reason && n < state->GetNumberOfTuples(); ++n)
    k += state->GetTuple1(n) != plod::NotInCut && reason->GetTuple1(n) == plod::AwaitingPages;
  return k;
}

TEST(MultiscaleOctreeFile, BackgroundLoadingReadsOffTheFrame)
{
  // A mapped file read with BackgroundLoading: the first view is the plain pipeline's; a move
  // closer while the loader is held draws cells awaiting their pages (an ancestor of what the
  // plain cut draws); once the reads arrive the pipeline runs again by itself (the selector's
  // modification time follows the loads) and reaches the plain drawing. Then what the frame
  // reads of the file: with the pages dropped and every read refinement read again by the
  // loader, a frame maps no page more.
  if (!PageMapReadable())
    GTEST_SKIP() << "/proc/self/pagemap cannot be read here";
  auto octree = BuildOctree(160);
  const std::string path = TempPath("background.plod");
  ASSERT_TRUE(Write(octree, path));
  struct Pipeline
  {
    vtkNew<vtkMultiscaleOctreeReader> Reader;
    vtkNew<vtkPerceptualLODSelector> Selector;
    vtkNew<vtkMultiscalePatchGenerator> Patches;
    Pipeline(const std::string& file, bool background)
    {
      this->Reader->SetFileName(file.c_str());
      this->Reader->SetCacheLimit(0);
      this->Reader->SetBackgroundLoading(background);
      this->Selector->SetInputConnection(this->Reader->GetOutputPort());
      this->Patches->SetInputConnection(this->Selector->GetOutputPort());
      this->Selector->SetViewportSize(1920, 1080);
      this->Selector->ScaleTolerances(0.25);
    }
    vtkSmartPointer<vtkPolyData> Draw(double d)
    {
      this->Selector->SetEyePosition(0.3 * d, 0.3 * d, d);
      this->Patches->Update();
      auto frame = vtkSmartPointer<vtkPolyData>::New();
      frame->DeepCopy(this->Patches->GetOutput());
      return frame;
    }
    vtkIdType Awaiting() { return AwaitingCells(this->Selector); }
  };
  const double far = 3.0, close = 1.2;
  Pipeline plain(path, false);
  const auto plainFar = plain.Draw(far), plainClose = plain.Draw(close);
  ASSERT_GT(plainClose->GetNumberOfPolys(), 0);
  EXPECT_EQ(plain.Reader->GetOutput()->GetPageLoader(), nullptr);

  Pipeline gated(path, true);
  EXPECT_TRUE(plodtest::SameDrawing(gated.Draw(far), plainFar)) << "the first view is whole";
  vtkMultiscaleOctree* mapped = gated.Reader->GetOutput();
  plod::PageLoader* loader = mapped->GetPageLoader();
  ASSERT_NE(loader, nullptr);
  EXPECT_TRUE(mapped->GetBackgroundLoading());
  loader->SetPaused(true);
  const auto held = gated.Draw(close);
  const vtkIdType awaiting = gated.Awaiting();
  EXPECT_GT(awaiting, 0);
  EXPECT_EQ(gated.Selector->GetNumberOfAwaitingCells(), awaiting);
  EXPECT_EQ(mapped->GetNumberOfWaitingLoads(), awaiting);
  EXPECT_FALSE(plodtest::SameDrawing(held, plainClose)) << "cells wait, drawn coarser";
  loader->SetPaused(false);
  int frames = 0;
  for (; frames < 50 && (gated.Awaiting() > 0 || mapped->GetNumberOfWaitingLoads() > 0); ++frames)
  {
    mapped->WaitForLoads();
    gated.Patches->Update(); // no Modified(): the loads make the selector run again
  }
  EXPECT_GT(frames, 0);
  EXPECT_EQ(gated.Awaiting(), 0);
  EXPECT_GT(mapped->GetNumberOfBackgroundLoads(), 0);
  EXPECT_TRUE(plodtest::SameDrawing(gated.Draw(close), plainClose));

  // what a frame reads of the file: dropped, a frame maps pages again...
  ASSERT_TRUE(mapped->ReleaseMappedPages());
  EXPECT_EQ(mapped->GetMappedResidentBytes(), 0);
  gated.Selector->Modified();
  gated.Patches->Update();
  const vtkIdType frameAlone = mapped->GetMappedResidentBytes();
  EXPECT_GT(frameAlone, 0);
  // ...and none that the loader's reads of the refinements did not map first
  ASSERT_TRUE(mapped->ReleaseMappedPages());
  vtkIdType read = 0;
  for (vtkIdType n = 0; n < mapped->GetNumberOfNodes(); ++n)
  {
    if (loader->IsReady(n))
    {
      loader->LoadNow(n);
      ++read;
    }
  }
  const vtkIdType byLoader = mapped->GetMappedResidentBytes();
  gated.Selector->Modified();
  gated.Patches->Update();
  EXPECT_EQ(mapped->GetMappedResidentBytes(), byLoader) << "the frame read pages not loaded";
  EXPECT_TRUE(plodtest::SameDrawing(gated.Patches->GetOutput(), plainClose));
  std::cout << awaiting << " cells awaited their pages; " << frames << " frames to the full cut; "
            << read << " refinements read; a frame alone maps " << (frameAlone >> 10)
            << " KiB, the loader " << (byLoader >> 10) << " KiB\n";
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, StanfordBunnyFileViewedWithinACacheLimitAndOffTheFrame)
{
  // A real scan saved as a mapped file and flown as a viewer flies it: the camera at the
  // distance vtkRenderer::ResetCamera gives for the model's bounds (30 degree view angle),
  // then an orbit closing to a tenth of it. Read with a cache limit below the file and its
  // pages read in the background, every frame (once the reads it asked for have arrived) draws
  // what the plain reader draws, point for point, and the mapped pages are within the limit,
  // after each frame and after the thread's reads between frames; after a frame, within the
  // limit less the filters' own arrays, which count against it.
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  if (!PageMapReadable())
    GTEST_SKIP() << "/proc/self/pagemap cannot be read here";
  auto bunny = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  ASSERT_TRUE(bunny);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(bunny);
  builder->Update();
  const std::string path = TempPath("bunny.plod");
  ASSERT_TRUE(Write(builder->GetOutput(), path));
  const vtkIdType fileBytes = static_cast<vtkIdType>(ReadBytes(path).size());
  ASSERT_GT(fileBytes, 2 << 20);
  double b[6];
  bunny->GetBounds(b);
  const double centre[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  const double radius = 0.5 *
    std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
      (b[5] - b[4]) * (b[5] - b[4]));
  const double reset = radius / std::sin(vtkMath::RadiansFromDegrees(15.0));
  struct Flight
  {
    vtkNew<vtkMultiscaleOctreeReader> Reader;
    vtkNew<vtkPerceptualLODSelector> Selector;
    vtkNew<vtkMultiscalePatchGenerator> Patches;
  };
  const auto setUp = [&](Flight& f, int limitMiB, bool background) {
    f.Reader->SetFileName(path.c_str());
    f.Reader->SetCacheLimit(limitMiB);
    f.Reader->SetBackgroundLoading(background);
    f.Selector->SetInputConnection(f.Reader->GetOutputPort());
    f.Patches->SetInputConnection(f.Selector->GetOutputPort());
    f.Selector->SetViewportSize(1280, 1024);
  };
  Flight plain, streamed;
  setUp(plain, 0, false);
  setUp(streamed, 1, true);
  vtkIdType reads = 0, waited = 0;
  for (int k = 0; k < 10; ++k)
  {
    const double a = 0.5 * k, d = reset * (1.0 - 0.9 * k / 9.0);
    const double eye[3] = { centre[0] + d * std::sin(a), centre[1] + 0.2 * d,
      centre[2] + d * std::cos(a) };
    for (Flight* f : { &plain, &streamed })
    {
      f->Selector->SetEyePosition(eye[0], eye[1], eye[2]);
      f->Patches->Update();
    }
    vtkMultiscaleOctree* mapped = streamed.Reader->GetOutput();
    waited += AwaitingCells(streamed.Selector) > 0 ? 1 : 0;
    for (int again = 0; again < 40 && AwaitingCells(streamed.Selector) > 0; ++again)
    {
      mapped->WaitForLoads();
      streamed.Patches->Update(); // runs again by itself: the loads arrived
    }
    EXPECT_EQ(AwaitingCells(streamed.Selector), 0) << "frame " << k;
    // the limit holds once the thread's reads are done, before any frame drops them
    mapped->WaitForLoads();
    EXPECT_LE(mapped->GetMappedResidentBytes(), vtkIdType(1) << 20) << "loads after frame " << k;
    // and after a frame
    streamed.Selector->Modified();
    streamed.Patches->Update();
    ASSERT_GT(plain.Patches->GetOutput()->GetNumberOfPolys(), 0);
    EXPECT_TRUE(plodtest::SameDrawing(plain.Patches->GetOutput(), streamed.Patches->GetOutput()))
      << "frame " << k;
    EXPECT_LE(mapped->GetMappedResidentBytes(), vtkIdType(1) << 20) << "frame " << k;
    // the filters' own arrays count against the limit: the remembered corner walks (a point
    // each), the output index (a cluster each) and the cut arrays (three bytes a node); the
    // mapped pages are within what they leave
    const vtkIdType held =
      vtkIdType(mapped->GetCornerMemo()->CutCluster.capacity() * sizeof(int32_t)) +
      4 * mapped->GetNumberOfClusters() + 3 * mapped->GetNumberOfNodes();
    EXPECT_EQ(mapped->GetHeldBytes(), held) << "frame " << k;
    ASSERT_LT(held, vtkIdType(1) << 20);
    EXPECT_LE(mapped->GetMappedResidentBytes(), (vtkIdType(1) << 20) - held) << "frame " << k;
    reads = mapped->GetNumberOfBackgroundLoads();
  }
  EXPECT_GT(waited, 0) << "the closing orbit should need pages the first view did not read";
  EXPECT_GT(streamed.Reader->GetOutput()->GetNumberOfResidentReleases(), 0);
  std::cout << "bunny file " << (fileBytes >> 10) << " KiB; " << waited
            << " of 10 frames waited for pages, " << reads << " refinements read\n";
  std::remove(path.c_str());
}

TEST(MultiscaleOctreeFile, CacheLimitKeepsTheMappedPagesWithinIt)
{
  // A flight over a mapped file larger than the reader's CacheLimit: after every frame (the
  // selector and the patch generator), the pages of the file the process holds are within the
  // limit, and every frame draws what it draws without a limit, point for point. Without a
  // limit, the same flight holds more than it; with one above the file, nothing is dropped.
  // Read with BackgroundLoading, the pages are within the limit after the thread's reads too.
  // A limit that every frame exceeds (the views read more than it leaves beside the filters'
  // arrays) makes each frame map its pages again: after 40 frames the octree has warned once,
  // saying how much of the limit the arrays hold and to raise it; the other flights say nothing.
  if (!PageMapReadable())
    GTEST_SKIP() << "/proc/self/pagemap cannot be read here";
  auto octree = BuildOctree(160);
  const std::string path = TempPath("cachelimit.plod");
  ASSERT_TRUE(Write(octree, path));
  const vtkIdType fileBytes = static_cast<vtkIdType>(ReadBytes(path).size());
  ASSERT_GT(fileBytes, 3 << 20) << "the model should make a file of several MiB";
  struct Flight
  {
    std::vector<vtkSmartPointer<vtkPolyData>> Frames;
    vtkIdType MostResident = 0;
    vtkIdType Releases = 0;
    vtkIdType Loads = 0;
    std::vector<std::string> Warnings;
  };
  const auto fly = [&](int limitMiB, bool background, int frames = 12) {
    Flight f;
    vtkNew<vtkMultiscaleOctreeReader> reader;
    reader->SetFileName(path.c_str());
    reader->SetCacheLimit(limitMiB);
    reader->SetBackgroundLoading(background);
    vtkNew<vtkPerceptualLODSelector> selector;
    vtkNew<vtkMultiscalePatchGenerator> patches;
    selector->SetInputConnection(reader->GetOutputPort());
    patches->SetInputConnection(selector->GetOutputPort());
    selector->SetViewportSize(1920, 1080);
    selector->ScaleTolerances(0.25);
    vtkNew<plodtest::ErrorRecorder> messages;
    for (int k = 0; k < frames; ++k)
    {
      // an orbit closing in (again after 12 frames)
      const double a = 0.6 * k, d = 1.5 + 1.5 * (11 - k % 12) / 11.0;
      selector->SetEyePosition(d * std::sin(a), 0.3 * d, d * std::cos(a));
      patches->Update();
      EXPECT_TRUE(reader->GetMapped());
      if (k == 0)
      {
        reader->GetOutput()->AddObserver(vtkCommand::WarningEvent, messages);
        selector->GetOutput()->AddObserver(vtkCommand::WarningEvent, messages);
      }
      if (background)
      {
        // the thread's reads between frames are within the limit too, before any frame
        reader->GetOutput()->WaitForLoads();
        f.Loads = reader->GetOutput()->GetNumberOfBackgroundLoads();
      }
      const vtkIdType resident = reader->GetOutput()->GetMappedResidentBytes();
      EXPECT_GE(resident, 0);
      f.MostResident = std::max(f.MostResident, resident);
      if (limitMiB > 0)
      {
        EXPECT_LE(resident, vtkIdType(limitMiB) << 20) << "frame " << k;
      }
      auto frame = vtkSmartPointer<vtkPolyData>::New();
      frame->DeepCopy(patches->GetOutput());
      f.Frames.push_back(frame);
    }
    f.Releases = reader->GetOutput()->GetNumberOfResidentReleases();
    f.Warnings = messages->Warnings;
    return f;
  };
  const Flight free = fly(0, false);
  ASSERT_GT(free.MostResident, 2 << 20) << "the flight should read more than the limit tried";
  EXPECT_EQ(free.Releases, 0);
  const Flight limited = fly(2, false);
  EXPECT_GT(limited.Releases, 0);
  const Flight above = fly(int(fileBytes >> 20) + 1, false);
  EXPECT_EQ(above.Releases, 0);
  // read in the background: the limit holds after the thread's reads as after the frames
  const Flight loaded = fly(2, true);
  EXPECT_GT(loaded.Loads, 0);
  EXPECT_GT(loaded.Releases, 0);
  for (size_t k = 0; k < free.Frames.size(); ++k)
  {
    for (const Flight* other : { &limited, &above })
    {
      ASSERT_GT(free.Frames[k]->GetNumberOfPolys(), 0) << "frame " << k;
      EXPECT_TRUE(plodtest::SameDrawing(free.Frames[k], other->Frames[k])) << "frame " << k;
    }
  }
  for (const Flight* quiet : { &free, &limited, &above, &loaded })
  {
    EXPECT_TRUE(quiet->Warnings.empty()) << quiet->Warnings.front();
  }
  // a limit every frame exceeds: reported once, with the limit, the arrays' share and the remedy
  const Flight small = fly(1, false, 40);
  EXPECT_GE(small.Releases, 30) << "frames that did not drop the pages";
  ASSERT_EQ(small.Warnings.size(), 1u) << "one warning, once";
  EXPECT_NE(small.Warnings[0].find("cache limit (1 MiB, of which"), std::string::npos)
    << small.Warnings[0];
  EXPECT_NE(small.Warnings[0].find("Raise the reader's CacheLimit"), std::string::npos)
    << small.Warnings[0];
  // a negative limit is no limit; a file read into memory has no mapped pages to keep
  {
    vtkNew<vtkMultiscaleOctreeReader> reader;
    reader->SetCacheLimit(-5);
    EXPECT_EQ(reader->GetCacheLimit(), 0);
    reader->SetFileName(path.c_str());
    reader->SetMemoryMap(false);
    reader->SetCacheLimit(1);
    reader->Update();
    EXPECT_FALSE(reader->GetMapped());
    EXPECT_EQ(reader->GetOutput()->GetMappedResidentBytes(), -1);
    reader->GetOutput()->EnforceResidentLimit();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfResidentReleases(), 0);
  }
  std::cout << "file " << (fileBytes >> 10) << " KiB; without a limit the flight held up to "
            << (free.MostResident >> 10) << " KiB; with 2 MiB, " << limited.Releases
            << " releases\n";
  std::remove(path.c_str());
}
