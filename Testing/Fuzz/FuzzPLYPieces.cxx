// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file FuzzPLYPieces.cxx
 * @brief libFuzzer target for the build of a PLY file in pieces: the streaming PLY reader
 * (StreamPLYMesh), the split (plod::PLYPieces) and the octree file made from the pieces
 * (plod::WriteOctreeFileFromPieces), on hostile PLY files.
 *
 * The input is the PLY file itself; its length chooses the number of pieces (1 to 3) and the
 * ownership level (1 or 2). Checked: nothing crashes or leaks; a refused file leaves no
 * temporary file; every piece's ghost flags and normals match its points and its triangles
 * index them; an octree file, when made, opens with its checksums and passes ValidateOctree,
 * with the coarsest drawn level its report gives (0, or k where the levels above hold
 * structure only), and the temporary directory is empty afterwards.
 *
 * Build and run: docs/fuzzing.md (`PLOD_FUZZ_TARGET=FuzzPLYPieces bash scripts/run-fuzz.sh`).
 */
#include "plodFuzzCheck.h"
#include "plodOctree.h"
#include "plodOctreeFile.h"
#include "plodPieceAssembly.h"
#include "plodPieces.h"

#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace
{
#define CHECK(cond, what) PLOD_FUZZ_CHECK("FuzzPLYPieces", cond, what)

/// Entries of a directory other than . and ..
int CountEntries(const std::string& dir)
{
  DIR* d = opendir(dir.c_str());
  int n = 0;
  while (const dirent* e = d ? readdir(d) : nullptr)
  {
    n += std::string(e->d_name) != "." && std::string(e->d_name) != "..";
  }
  if (d)
  {
    closedir(d);
  }
  return n;
}
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const char* tmp = std::getenv("TMPDIR");
  const std::string base =
    std::string(tmp && *tmp ? tmp : "/tmp") + "/plod-fuzz-pieces-" + std::to_string(::getpid());
  ::mkdir(base.c_str(), 0700);
  const std::string ply = base + "/in.ply", plod = base + "/out.plod", work = base + "/work";
  ::mkdir(work.c_str(), 0700);
  if (FILE* f = std::fopen(ply.c_str(), "wb"))
  {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  {
    plod::PiecesParameters params;
    params.NumberOfPieces = 1 + static_cast<int>(size % 3);
    params.OwnershipLevel = 1 + static_cast<int>((size / 3) % 2);
    params.TemporaryDirectory = work;
    plod::PLYPieces pieces;
    std::string why;
    const bool opened = pieces.Open(ply, params, &why);
    CHECK(opened || !why.empty(), "a refusal says why");
    CHECK(opened || CountEntries(work) == 0, "a refused file leaves no temporary file");
    for (int p = 0; opened && p < pieces.GetNumberOfPieces(); ++p)
    {
      plod::PartitionResult r;
      CHECK(pieces.GetPiece(p, &r, &why), why);
      const size_t points = r.Ghost.size();
      CHECK(r.Points.size() == 3 * points, "a position per point");
      CHECK(r.Normals.empty() || r.Normals.size() == 3 * points, "a normal per point");
      for (int64_t id : r.Triangles)
      {
        CHECK(id >= 0 && size_t(id) < points, "triangles index the piece's points");
      }
    }
    if (opened && pieces.GetNumberOfPieces() > 0)
    {
      plod::AssemblyReport report;
      if (plod::WriteOctreeFileFromPieces(pieces, plod, {}, &report, &why))
      {
        plod::OctreeFile file;
        CHECK(plod::OpenOctreeFile(plod, true, true, file, &why), why);
        plod::OctreeView v;
        CHECK(plod::ViewOfFile(file, v, &why), why);
        CHECK(plod::ValidateOctree(v, &why), why);
        CHECK(file.Header.CoarsestDrawnLevel ==
            (report.StructureOnly.empty() ? 0 : pieces.GetOwnershipLevel()),
          "coarsest level");
        CHECK(report.NumberOfTriangles == v.NumberOfTriangles, "the report's triangles");
      }
      else
      {
        CHECK(!why.empty(), "a failed assembly says why");
      }
    }
  }
  CHECK(CountEntries(work) == 0, "the temporary files are removed");
  std::remove(ply.c_str());
  std::remove(plod.c_str());
  ::rmdir(work.c_str());
  ::rmdir(base.c_str());
  return 0;
}
