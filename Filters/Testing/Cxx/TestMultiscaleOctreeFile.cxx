// SPDX-License-Identifier: BSD-3-Clause
// vtkMultiscaleOctreeWriter and vtkMultiscaleOctreeReader: every array identical after a round
// trip (mapped and read into memory), the same cut and patches as from the built octree, the
// mapping outliving the reader, copy-on-write edits, and a corrupt-file battery (truncated at
// many offsets, flipped bytes everywhere in the header and directory and across the data, wrong
// version, wrong magic, empty and missing files): a clear error and an empty octree, no crash.
#include "plodTestUtilities.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

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

bool Write(vtkMultiscaleOctree* octree, const std::string& path)
{
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->SetInputData(octree);
  writer->SetFileName(path.c_str());
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
  EXPECT_EQ(a->GetNumberOfBoundaryEdges(), b->GetNumberOfBoundaryEdges());
  EXPECT_EQ(a->GetNumberOfNonManifoldEdges(), b->GetNumberOfNonManifoldEdges());
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

ReadResult Read(const std::string& path, bool verify = false, bool map = true)
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
  return r;
}
}

TEST(MultiscaleOctreeFile, RoundTripKeepsEveryArrayAndTheImage)
{
  auto octree = BuildOctree();
  ASSERT_GT(octree->GetNumberOfNodes(), 100);
  ASSERT_TRUE(octree->GetHasMaterialArrays());
  const std::string path = TempPath("roundtrip.plod");
  ASSERT_TRUE(Write(octree, path));
  EXPECT_TRUE(vtkMultiscaleOctreeReader::CanReadFile(path.c_str()));
  const auto reference = Draw(octree, nullptr);
  ASSERT_GT(reference->GetNumberOfPolys(), 0);
  for (bool map : { true, false })
    for (bool verify : { false, true })
    {
      ReadResult r = Read(path, verify, map);
      ASSERT_TRUE(r.Error.empty()) << r.Error;
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
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("cannot open"), std::string::npos);
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

TEST(MultiscaleOctreeFile, CorruptFilesAreClearErrorsNeverCrashes)
{
  auto octree = BuildOctree(20);
  const std::string good = TempPath("good.plod");
  ASSERT_TRUE(Write(octree, good));
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
    b[8] = 2;
    expectRefused(b, "version 2", "version 2");
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
  // cannot use, and nothing crashes
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
    EXPECT_NE(checked.Error.find("checksum"), std::string::npos) << "byte " << i;
    EXPECT_EQ(checked.Octree->GetNumberOfNodes(), 0);
    ReadResult unchecked = Read(path, false, true);
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
