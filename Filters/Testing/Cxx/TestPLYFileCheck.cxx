// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkPLYFileCheck and of the readers the programs use (plodtest::ReadPLY/ReadModel):
// every corrupt PLY variant gives nullptr and one line naming the file and the problem, without
// a crash in vtkPLYReader; valid files read with the checked counts; missing, empty, directory
// and garbage STL/OBJ/VTP files give a message, not a crash; faces of fewer than 3 indices pass
// with a warning; the Stanford files read.
#include "plodPLYSamples.h"
#include "plodTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkOBJWriter.h"
#include "vtkPLYFileCheck.h"
#include "vtkPLYReader.h"
#include "vtkPolyData.h"
#include "vtkSTLWriter.h"
#include "vtkXMLPolyDataWriter.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

class PLYFileCheck : public ::testing::Test
{
public:
  static void SetUpTestSuite()
  {
    Folder() =
      (fs::temp_directory_path() / ("plod_ply_file_check_" + std::to_string(::getpid()))).string();
    Valid() = plodtest::ValidPLYSamples();
    Corrupt() = plodtest::CorruptPLYSamples();
    const auto limits = plodtest::ReaderLimitPLYSamples();
    Corrupt().insert(Corrupt().end(), limits.begin(), limits.end());
    ASSERT_TRUE(plodtest::WritePLYSamples(Valid(), Folder()));
    ASSERT_TRUE(plodtest::WritePLYSamples(Corrupt(), Folder()));
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

  static std::string Write(const std::string& name, const std::string& bytes)
  {
    const std::string path = Folder() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
  }

  /// ReadModel(path), with what it wrote on stderr.
  static vtkSmartPointer<vtkPolyData> Read(const std::string& path, std::string* err)
  {
    ::testing::internal::CaptureStderr();
    auto model = plodtest::ReadModel(path);
    *err = ::testing::internal::GetCapturedStderr();
    return model;
  }
};
} // namespace

// ---- the class ----------------------------------------------------------------------------------

TEST_F(PLYFileCheck, AcceptsValidFilesWithTheirCounts)
{
  vtkNew<vtkPLYFileCheck> check;
  EXPECT_TRUE(check->GetReaderLimits());
  EXPECT_STREQ(check->GetErrorMessage(), "");
  for (const auto& s : Valid())
  {
    SCOPED_TRACE(s.Name);
    check->SetFileName(s.Path.c_str());
    EXPECT_TRUE(check->Check()) << check->GetErrorMessage();
    EXPECT_STREQ(check->GetErrorMessage(), "");
    EXPECT_EQ(check->GetNumberOfVertices(), s.Vertices);
    EXPECT_EQ(check->GetNumberOfFaces(), s.Faces);
    EXPECT_TRUE(vtkPLYFileCheck::CheckFile(s.Path.c_str()));
  }
  check->SetFileName(Valid()[1].Path.c_str()); // all types, ASCII
  ASSERT_TRUE(check->Check());
  EXPECT_EQ(check->GetFormat(), vtkPLYFileCheck::FORMAT_ASCII);
  EXPECT_STREQ(check->GetFormatAsString(), "ascii");
  EXPECT_EQ(check->GetMaxFaceSize(), 3);
}

TEST_F(PLYFileCheck, RejectsCorruptFilesWithTheReason)
{
  vtkNew<vtkPLYFileCheck> check;
  for (const auto& s : Corrupt())
  {
    SCOPED_TRACE(s.Name);
    check->SetFileName(s.Path.c_str());
    EXPECT_FALSE(check->Check());
    EXPECT_NE(std::string(check->GetErrorMessage()).find(s.Expect), std::string::npos)
      << check->GetErrorMessage();
    EXPECT_FALSE(vtkPLYFileCheck::CheckFile(s.Path.c_str()));
  }
  // a success clears the message
  check->SetFileName(Valid()[0].Path.c_str());
  EXPECT_TRUE(check->Check());
  EXPECT_STREQ(check->GetErrorMessage(), "");
  // no file name
  check->SetFileName(nullptr);
  EXPECT_FALSE(check->Check());
  EXPECT_STREQ(check->GetErrorMessage(), "no file name given");
  EXPECT_FALSE(vtkPLYFileCheck::CheckFile(nullptr));
}

TEST_F(PLYFileCheck, ReaderLimitsCanBeTurnedOff)
{
  vtkNew<vtkPLYFileCheck> check;
  for (const auto& s : plodtest::ReaderLimitPLYSamples())
  {
    SCOPED_TRACE(s.Name);
    check->SetFileName((Folder() + "/" + s.Name + ".ply").c_str());
    check->ReaderLimitsOn();
    EXPECT_FALSE(check->Check());
    check->ReaderLimitsOff();
    EXPECT_TRUE(check->Check()) << check->GetErrorMessage();
  }
  std::ostringstream os;
  check->Print(os);
  EXPECT_NE(os.str().find("ReaderLimits: Off"), std::string::npos);
  EXPECT_NE(os.str().find("NumberOfVertices: 4"), std::string::npos);
}

// ---- the programs' reader
// ------------------------------------------------------------------------

TEST_F(PLYFileCheck, ReadModelReturnsNullForEveryCorruptPLYWithOneLine)
{
  for (const auto& s : Corrupt())
  {
    SCOPED_TRACE(s.Name);
    std::string err;
    EXPECT_EQ(Read(s.Path, &err), nullptr);
    EXPECT_EQ(err.rfind(s.Path + ": ", 0), 0u) << "prefixed with the file name: " << err;
    EXPECT_NE(err.find(s.Expect), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "one line: " << err;
  }
}

TEST_F(PLYFileCheck, ReadModelReadsValidPLYFiles)
{
  for (const auto& s : Valid())
  {
    SCOPED_TRACE(s.Name);
    std::string err;
    auto model = Read(s.Path, &err);
    ASSERT_NE(model, nullptr) << err;
    if (s.Name.find("strips") != std::string::npos)
    {
      EXPECT_NE(err.find("element 'tristrips' (1 rows) describes a surface that is not read"),
        std::string::npos)
        << err;
    }
    else
    {
      EXPECT_EQ(err, "");
    }
    EXPECT_EQ(model->GetNumberOfPoints(), s.Vertices);
    EXPECT_EQ(model->GetNumberOfPolys(), s.Faces);
  }
  // a valid file without points is refused with a reason
  std::string err;
  const std::string path = Write("no_points.ply",
    "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
    "property float z\nend_header\n");
  EXPECT_EQ(Read(path, &err), nullptr);
  EXPECT_EQ(err, path + ": the file holds no vertices\n");
}

TEST_F(PLYFileCheck, ShortFacesPassWithAWarning)
{
  // issue 24: a valid PLY with faces of fewer than 3 indices passes, with a warning (how many,
  // the first one) from the check and through the programs' reader; the reader keeps them as
  // polygons of 0, 1 or 2 points, which a program must drop before vtkPolyDataNormals
  plodtest::TetraPLY t;
  t.Encoding = plodtest::PLYEncoding::Little;
  t.Faces = { { 0, 1, 2 }, { 0, 3, 1 }, { 2, 3 }, { 0, 2, 3 }, { 1 }, { 1, 3, 2 } };
  t.DeclaredFaces = 6;
  const std::string path = Write("short_faces.ply", t.Bytes());
  const std::string warning =
    "2 of 6 faces have fewer than 3 vertex indices (the first: element 'face' row 2 with 2 "
    "indices (byte offset ";

  vtkNew<vtkPLYFileCheck> check;
  vtkNew<plodtest::ErrorRecorder> messages;
  check->AddObserver(vtkCommand::WarningEvent, messages);
  check->SetFileName(path.c_str());
  ASSERT_TRUE(check->Check()) << check->GetErrorMessage();
  EXPECT_STREQ(check->GetErrorMessage(), "");
  EXPECT_EQ(check->GetNumberOfFaces(), 6);
  EXPECT_EQ(check->GetNumberOfShortFaces(), 2);
  EXPECT_EQ(std::string(check->GetWarningMessage()).rfind(warning, 0), 0u)
    << check->GetWarningMessage();
  ASSERT_EQ(messages->Warnings.size(), 1u);
  EXPECT_NE(messages->Warnings[0].find(path + ": " + warning), std::string::npos)
    << messages->Warnings[0];
  EXPECT_TRUE(vtkPLYFileCheck::CheckFile(path.c_str()));
  std::ostringstream os;
  check->Print(os);
  EXPECT_NE(os.str().find("NumberOfShortFaces: 2"), std::string::npos);

  // a sound file clears the warning, and says none
  check->SetFileName(Valid()[0].Path.c_str());
  ASSERT_TRUE(check->Check());
  EXPECT_STREQ(check->GetWarningMessage(), "");
  EXPECT_EQ(check->GetNumberOfShortFaces(), 0);
  EXPECT_EQ(messages->Warnings.size(), 1u);

  // the programs' reader: the model, and the warning on stderr
  std::string err;
  auto model = Read(path, &err);
  ASSERT_NE(model, nullptr) << err;
  EXPECT_NE(err.find(warning), std::string::npos) << err;
  EXPECT_EQ(model->GetNumberOfPolys(), 6) << "vtkPLYReader keeps them";
  vtkIdType shortPolys = 0;
  vtkIdType n;
  const vtkIdType* ids;
  auto cells = vtk::TakeSmartPointer(model->GetPolys()->NewIterator());
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
  {
    cells->GetCurrentCell(n, ids);
    shortPolys += n < 3 ? 1 : 0;
  }
  EXPECT_EQ(shortPolys, 2);
}

TEST_F(PLYFileCheck, OtherFormatsGiveAMessageNotACrash)
{
  const std::string dir = Folder() + "/other";
  fs::create_directories(dir);
  std::mt19937 rng(3);
  std::string noise;
  for (int i = 0; i < 3000; ++i)
  {
    noise += static_cast<char>(rng() & 0xff);
  }
  // a binary STL whose triangle count (2^31 - 1) is far beyond its 84 bytes: VTK's reader
  // throws std::bad_alloc
  std::string lyingSTL(84, '\0');
  lyingSTL[80] = lyingSTL[81] = lyingSTL[82] = static_cast<char>(0xff);
  lyingSTL[83] = 0x7f;
  for (const char* ext : { ".stl", ".obj", ".vtp" })
  {
    SCOPED_TRACE(ext);
    std::string err;
    const std::string missing = dir + "/missing" + ext;
    EXPECT_EQ(Read(missing, &err), nullptr);
    EXPECT_EQ(err, missing + ": cannot open: No such file or directory\n");
    const std::string empty = Write(std::string("other/empty") + ext, "");
    EXPECT_EQ(Read(empty, &err), nullptr);
    EXPECT_EQ(err, empty + ": the file is empty\n");
    const std::string folder = dir + "/folder" + ext;
    fs::create_directories(folder);
    EXPECT_EQ(Read(folder, &err), nullptr);
    EXPECT_EQ(err, folder + ": is a directory, not a model file\n");
    // garbage: VTK's readers may read something or nothing, but must not crash
    Read(Write(std::string("other/garbage") + ext, noise), &err);
  }
  std::string err;
  const std::string stl = Write("other/lying_count.stl", lyingSTL);
  EXPECT_EQ(Read(stl, &err), nullptr);
  EXPECT_NE(err.find(stl + ": "), std::string::npos) << err;
  const std::string unknown = Write("other/model.xyz", "1 2 3\n");
  EXPECT_EQ(Read(unknown, &err), nullptr);
  EXPECT_EQ(err, unknown + ": unknown model type '.xyz' (PLY, STL, OBJ or VTP)\n");
  EXPECT_EQ(Read(dir + "/no_extension", &err), nullptr);
  EXPECT_EQ(err, dir + "/no_extension: cannot open: No such file or directory\n");
}

TEST_F(PLYFileCheck, OtherFormatsStillRead)
{
  auto cube = plodtest::MakeCube(0, 1);
  const std::string stl = Folder() + "/cube.stl", obj = Folder() + "/cube.obj",
                    vtp = Folder() + "/cube.vtp";
  vtkNew<vtkSTLWriter> w1;
  w1->SetInputData(cube);
  w1->SetFileName(stl.c_str());
  w1->SetFileTypeToBinary();
  w1->Write();
  vtkNew<vtkOBJWriter> w2;
  w2->SetInputData(cube);
  w2->SetFileName(obj.c_str());
  w2->Write();
  vtkNew<vtkXMLPolyDataWriter> w3;
  w3->SetInputData(cube);
  w3->SetFileName(vtp.c_str());
  w3->Write();
  for (const std::string& path : { stl, obj, vtp })
  {
    SCOPED_TRACE(path);
    std::string err;
    auto model = Read(path, &err);
    ASSERT_NE(model, nullptr) << err;
    EXPECT_EQ(model->GetNumberOfPolys(), 12);
  }
}

TEST_F(PLYFileCheck, WhatPassesTheCheckReadsWithoutACrash)
{
  // damaged copies of the valid samples (byte changes, insertions, deletions, cuts, header
  // numbers replaced): every file the check accepts is read by vtkPLYReader in a child process,
  // which must end normally with the checked counts and every polygon's ids in range
  std::mt19937 rng(99);
  const char* numbers[] = { "0", "1", "3", "5", "255", "256", "65535", "2147483647", "-1" };
  int accepted = 0;
  for (int trial = 0; trial < 1500; ++trial)
  {
    std::string bytes = Valid()[rng() % Valid().size()].Bytes;
    const size_t end = bytes.find("end_header");
    for (int e = 0, edits = 1 + static_cast<int>(rng() % 2); e < edits && !bytes.empty(); ++e)
    {
      const size_t at = rng() % bytes.size();
      switch (rng() % 5)
      {
        case 0:
          bytes[at] = static_cast<char>(rng() & 0xff);
          break;
        case 1:
          bytes.insert(at, 1 + rng() % 4, static_cast<char>(rng() & 0xff));
          break;
        case 2:
          bytes.erase(at, 1 + rng() % 4);
          break;
        case 3:
          bytes.resize(at);
          break;
        default:
        {
          const size_t digit = bytes.find_first_of("0123456789", rng() % end);
          if (digit < end)
          {
            const size_t stop = bytes.find_first_not_of("0123456789", digit);
            bytes.replace(digit, stop - digit, numbers[rng() % 9]);
          }
        }
      }
    }
    const std::string path = Write("damaged.ply", bytes);
    vtkNew<vtkPLYFileCheck> check;
    check->SetFileName(path.c_str());
    if (!check->Check())
    {
      continue;
    }
    ++accepted;
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0)
    {
      std::freopen("/dev/null", "w", stderr);
      alarm(30);
      vtkNew<vtkPLYReader> reader;
      reader->SetFileName(path.c_str());
      reader->Update();
      vtkPolyData* out = reader->GetOutput();
      if (out->GetNumberOfPoints() != check->GetNumberOfVertices() ||
        out->GetNumberOfPolys() != check->GetNumberOfFaces())
      {
        _exit(2);
      }
      vtkIdType n;
      const vtkIdType* ids;
      auto cells = vtk::TakeSmartPointer(out->GetPolys()->NewIterator());
      for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
      {
        cells->GetCurrentCell(n, ids);
        for (vtkIdType k = 0; k < n; ++k)
        {
          if (ids[k] < 0 || ids[k] >= out->GetNumberOfPoints())
          {
            _exit(3);
          }
        }
      }
      _exit(0);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << "trial " << trial << ": vtkPLYReader "
      << (WIFEXITED(status) ? "misread (exit " + std::to_string(WEXITSTATUS(status)) + ")"
                            : "died of signal " + std::to_string(WTERMSIG(status)))
      << " a file the check accepted";
  }
  EXPECT_GT(accepted, 100) << "some damage leaves a sound file (e.g. a changed coordinate)";
}

TEST(PLYFileCheckData, StanfordFilesPassAndRead)
{
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  }
  vtkNew<vtkPLYFileCheck> check;
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir))
  {
    if (entry.path().extension() != ".ply")
    {
      continue;
    }
    ++files;
    SCOPED_TRACE(entry.path().filename().string());
    check->SetFileName(entry.path().c_str());
    ASSERT_TRUE(check->Check()) << check->GetErrorMessage();
    auto model = plodtest::ReadPLY(entry.path().string());
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(model->GetNumberOfPoints(), check->GetNumberOfVertices());
    EXPECT_EQ(model->GetNumberOfPolys(), check->GetNumberOfFaces());
  }
  EXPECT_GE(files, 15);
}
