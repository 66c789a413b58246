// SPDX-License-Identifier: BSD-3-Clause
// PerceptualLOD's main program. Today: builds the multiscale octree of a model (or opens one
// saved before), prints what it holds level by level, and the crack-free patches of each
// uniform cut. Usage:
//
//   PerceptualLODMain [model.ply|.stl|.obj|.vtp|.plod] [--level N] [--mean] [--serial]
//                     [--memory SIZE] [--save octree.plod] [--pieces] [--compact]
//
// Without a file it uses a generated detailed model (a displaced sphere of about 500k
// triangles), so it runs anywhere. --save writes the built octree to a file that this program,
// the viewer and vtkMultiscaleOctreeReader open without building again. A PLY file is read by
// the builder itself (vtkMultiscaleOctreeBuilder::SetFileName: no vtkPolyData of the model),
// after its header's counts are checked against --memory (a number of MiB, or with a suffix
// K, M, G or T; default: three quarters of the machine's memory): a model that cannot fit is
// refused before anything is read, unless --save names a file: a PLY model too large for the
// memory limit is then built in pieces, one after the other, each within the limit
// (plodPieces.h, plodPieceAssembly.h), straight into the octree file, with temporary files
// beside it; --pieces builds that way whatever the size. --compact saves the compact layout
// (arrays compressed, about a third of the bytes, decoded into memory when opened) instead of
// the mapped one; an octree file given with --save is converted to the layout asked for, block
// by block (plod::ConvertOctreeFile: a compact file larger than memory becomes a mapped one).
// Progress, with the time left, goes to stdout.
#include "plodMeshFileCheck.h"
#include "plodOctreeBuilder.h"
#include "plodOctreeFile.h"
#include "plodPLYRead.h"
#include "plodTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{
/// The level table makes each uniform cut's patches in memory up to this many triangles (a
/// model built in pieces may be far larger than memory).
constexpr vtkIdType MaxTableTriangles = 40000000;

/// A memory size: a number of MiB, or a number with a suffix K, M, G or T (powers of 1024).
/// Returns the MiB, or a negative number for text that is not a size.
double ParseMiB(const std::string& text)
{
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !(value > 0) || !std::isfinite(value))
  {
    return -1;
  }
  const std::string unit = end;
  const double scale = unit.empty() || unit == "M" || unit == "MiB" ? 1.0
    : unit == "K" || unit == "KiB"                                  ? 1.0 / 1024.0
    : unit == "G" || unit == "GiB"                                  ? 1024.0
    : unit == "T" || unit == "TiB"                                  ? 1024.0 * 1024.0
                                                                    : -1.0;
  return scale > 0 ? value * scale : -1;
}

/// What a build of `header`'s model in pieces into `save` will take on disk, printed.
void PrintPiecesEstimate(
  const plod::PLYSummary& header, const std::string& save, double limitMiB, bool compact)
{
  const double MiB = 1024.0 * 1024.0;
  // temporary disk at its peak: while splitting, the points and triangles (as read, then in
  // pieces with their halo); while building, the kept parts of the octrees (about the file's
  // size) beside the pieces not yet built (each piece's file is removed once read)
  const double vertexBytes = (plod::PLYHasDoubleCoordinates(header) ? 24.0 : 12.0) +
    (plod::PLYHasNormals(header) ? 12.0 : 0.0);
  const double file = plod::EstimateOctreeBytes(header.NumberOfVertices, header.NumberOfFaces);
  const double temporary =
    std::max(vertexBytes * double(header.NumberOfVertices) + 40.0 * double(header.NumberOfFaces),
      1.15 * file);
  std::printf("building in pieces within %.0f MiB into %s: about %.0f MiB of temporary files "
              "beside it, a file of about %.0f MiB%s\n",
    limitMiB, save.c_str(), temporary / MiB, file / MiB,
    compact ? " in the mapped layout (compact: about 40 % of that, by content)" : "");
  std::fflush(stdout);
}

/// Prints a filter's progress every tenth, with the time spent and the time left at this pace.
void ShowProgress(vtkAlgorithm* filter, const char* what)
{
  struct State
  {
    std::string What;
    std::chrono::steady_clock::time_point Start = std::chrono::steady_clock::now();
    int Shown = 0;
  };
  auto* state = new State{ what };
  vtkNew<vtkCallbackCommand> command;
  command->SetClientData(state);
  command->SetClientDataDeleteCallback([](void* d) { delete static_cast<State*>(d); });
  command->SetCallback([](vtkObject*, unsigned long, void* d, void* call) {
    auto* st = static_cast<State*>(d);
    const double f = *static_cast<double*>(call);
    const int tenth = static_cast<int>(f * 10.0 + 1e-9);
    if (tenth <= st->Shown || f <= 0)
    {
      return;
    }
    st->Shown = tenth;
    const double spent =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - st->Start).count();
    std::printf("%s: %3d %%, %.1f s spent, about %.1f s left\n", st->What.c_str(),
      static_cast<int>(100 * f + 0.5), spent, spent * (1.0 - f) / f);
    std::fflush(stdout);
  });
  filter->AddObserver(vtkCommand::ProgressEvent, command);
}
}

/**
 * STL and OBJ models are read by VTK's readers into a vtkPolyData before the build: their
 * counts (from the file checks, one pass through a small buffer) give the least memory that
 * takes (float points, 64-bit cells, and for STL the unmerged corners the reader holds first)
 * plus the build's; a model over `limitMiB` is refused with what would fit, before the reader
 * runs. Other formats pass (a bad file is named by ReadModel).
 */
bool FitsInMemory(const std::string& file, double limitMiB)
{
  const std::string ext = file.size() > 4 ? file.substr(file.size() - 4) : std::string();
  int64_t points = 0, triangles = 0;
  std::string why;
  if (ext == ".stl" || ext == ".STL")
  {
    plod::STLSummary summary;
    if (!plod::CheckSTLFile(file, &why, &summary, plod::VTKSTLReaderLimits()))
    {
      return true; // ReadModel names the problem
    }
    triangles = summary.NumberOfTriangles;
    points = 3 * triangles;
  }
  else if (ext == ".obj" || ext == ".OBJ")
  {
    plod::OBJSummary summary;
    if (!plod::CheckOBJFile(file, &why, &summary, plod::VTKOBJReaderLimits()))
    {
      return true;
    }
    points = summary.NumberOfVertices;
    triangles = summary.NumberOfFaces * std::max<int64_t>(1, summary.MaxFaceSize - 2);
  }
  else
  {
    return true;
  }
  const double MiB = 1024.0 * 1024.0;
  const double polydata = 12.0 * double(points) + 32.0 * double(triangles);
  const double least =
    polydata + plod::LeastBuildMemory(std::min(points, triangles), triangles, triangles == 0);
  if (least <= limitMiB * MiB)
  {
    return true;
  }
  const double perTriangle = least / double(std::max<int64_t>(1, triangles));
  std::fprintf(stderr,
    "%s: %lld triangles need at least %.0f MiB in memory (VTK's reader's polydata %.0f MiB and "
    "the build), more than the memory limit of %.0f MiB: at most %lld triangles fit. Nothing "
    "was read; as PLY the builder reads the file itself with less memory.\n"
    "cannot read a model from '%s' (PLY, STL, OBJ, VTP or .plod)\n",
    file.c_str(), static_cast<long long>(triangles), least / MiB, polydata / MiB, limitMiB,
    static_cast<long long>(limitMiB * MiB / perTriangle), file.c_str());
  return false;
}

int main(int argc, char* argv[])
{
  std::string file, save;
  int level = -1;
  double memory = 0; // MiB, 0: automatic
  bool mean = false, serial = false, inPieces = false, builtInPieces = false, compact = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--level" && i + 1 < argc)
      level = std::atoi(argv[++i]);
    else if (a == "--mean")
      mean = true;
    else if (a == "--serial")
      serial = true;
    else if (a == "--pieces")
      inPieces = true;
    else if (a == "--compact")
      compact = true;
    else if (a == "--save" && i + 1 < argc)
      save = argv[++i];
    else if (a == "--memory" && i + 1 < argc)
    {
      memory = ParseMiB(argv[++i]);
      if (memory <= 0)
      {
        std::fprintf(
          stderr, "--memory takes a size such as 4G, 512M or 2048 (MiB), not '%s'\n", argv[i]);
        return 1;
      }
    }
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: %s [model.ply|.stl|.obj|.vtp|.plod] [--level N] [--mean] [--serial] "
                  "[--memory SIZE] [--save octree.plod] [--pieces] [--compact]\n",
        argv[0]);
      return 0;
    }
    else
      file = a;
  }
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  vtkNew<vtkMultiscaleOctreeReader> reader;
  vtkMultiscaleOctree* octree = nullptr;
  bool converted = false;
  if (!file.empty() && vtkMultiscaleOctreeReader::CanReadFile(file.c_str()))
  {
    if (!save.empty())
    {
      // an octree file saved again (in the other layout, say): converted block by block, so
      // that a compact file larger than memory becomes a mapped one; then the copy is opened
      plod::FileWriteOptions options;
      options.Layout = compact ? plod::FileLayout::Compact : plod::FileLayout::Mapped;
      std::string why;
      if (!plod::ConvertOctreeFile(file, save, options, &why))
      {
        std::fprintf(stderr, "cannot save the octree: %s\n", why.c_str());
        return 1;
      }
      std::printf("saved: %s (%s layout), converted from %s\n", save.c_str(),
        compact ? "compact" : "mapped", file.c_str());
      file = save;
      converted = true;
    }
    reader->SetFileName(file.c_str());
    reader->Update();
    octree = reader->GetOutput();
    if (octree->GetNumberOfNodes() == 0)
    {
      std::fprintf(stderr, "%s\ncannot read a model from '%s' (an octree file)\n",
        reader->GetErrorMessage(), file.c_str());
      return 1;
    }
    std::printf("octree file: %s, opened in %.2f ms (%s)\n", file.c_str(),
      reader->GetReadTime() * 1e3,
      reader->GetCompact()    ? "compact, decoded into memory"
        : reader->GetMapped() ? "mapped"
                              : "read into memory");
  }
  else
  {
    builder->SetFinestLevel(level);
    if (mean)
      builder->SetVertexRuleToMean();
    builder->SetMultiThreaded(!serial);
    builder->SetMemoryLimit(memory);
    ShowProgress(builder, "build");
    const bool ply = file.size() > 4 &&
      (file.substr(file.size() - 4) == ".ply" || file.substr(file.size() - 4) == ".PLY");
    if (ply)
    {
      // read by the builder itself: its header is checked against the memory limit first
      std::printf("model: %s (read by the builder, memory limit %.0f MiB)\n", file.c_str(),
        builder->GetEffectiveMemoryLimit());
      // the header first: its counts give the estimates, and a model that cannot fit is left
      // to the builder, which refuses it before reading a row; one that can is checked in full
      // (one pass through a small buffer), so a corrupt body is named to the row before the
      // build starts
      plod::PLYSummary header;
      std::string why;
      auto refuse = [&]() {
        std::fprintf(stderr,
          "%s: %s\ncannot read a model from '%s' (PLY, STL, OBJ, VTP or .plod)\n", file.c_str(),
          why.c_str(), file.c_str());
        return 1;
      };
      if (!plod::ReadPLYHeader(file, &why, &header))
      {
        std::string where; // the full check names the row where the body parts from the header
        if (!plod::CheckPLYFile(file, &where))
        {
          why = where;
        }
        return refuse();
      }
      const double MiB = 1024.0 * 1024.0;
      const double least = plod::EstimatePLYMeshBytes(header) +
        plod::LeastBuildMemory(
          header.NumberOfVertices, header.NumberOfFaces, header.NumberOfFaces == 0);
      std::printf("header: %lld points, %lld faces; memory at least %.0f MiB (the mesh's "
                  "arrays %.0f MiB and the build); octree file about %.0f MiB\n",
        static_cast<long long>(header.NumberOfVertices),
        static_cast<long long>(header.NumberOfFaces), least / MiB,
        plod::EstimatePLYMeshBytes(header) / MiB,
        plod::EstimateOctreeBytes(header.NumberOfVertices, header.NumberOfFaces) / MiB);
      const bool fits = least <= builder->GetEffectiveMemoryLimit() * MiB;
      if (!save.empty() && (inPieces || !fits))
      {
        // the builder writes the file, and its output is the file
        PrintPiecesEstimate(header, save, builder->GetEffectiveMemoryLimit(), compact);
        builder->SetOctreeFileName(save.c_str());
        builder->SetBuildInPieces(inPieces);
        builder->SetCompactOctreeFile(compact);
        builtInPieces = true;
      }
      else if (!fits)
      {
        std::printf("with --save, the model is built in pieces within the memory limit\n");
      }
      else
      {
        if (!plod::CheckPLYFile(file, &why, &header))
        {
          return refuse();
        }
        if (!header.Warning.empty())
        {
          std::fprintf(stderr, "warning: %s: %s\n", file.c_str(), header.Warning.c_str());
        }
      }
      std::fflush(stdout);
      builder->SetFileName(file.c_str());
    }
    else if (inPieces)
    {
      std::fprintf(stderr, "--pieces builds a PLY file into the octree file --save names\n");
      return 1;
    }
    else
    {
      vtkSmartPointer<vtkPolyData> model;
      if (file.empty())
      {
        std::printf("model: generated displaced sphere\n");
        model = plodtest::MakeBlob(11, 500, 0.2);
      }
      else
      {
        if (!FitsInMemory(file, builder->GetEffectiveMemoryLimit()))
        {
          return 1;
        }
        model = plodtest::ReadModel(file);
        if (!model)
        {
          std::fprintf(
            stderr, "cannot read a model from '%s' (PLY, STL, OBJ, VTP or .plod)\n", file.c_str());
          return 1;
        }
        std::printf("model: %s\n", file.c_str());
      }
      std::printf("input: %lld points, %lld polygons\n",
        static_cast<long long>(model->GetNumberOfPoints()),
        static_cast<long long>(model->GetNumberOfPolys() + model->GetNumberOfStrips()));
      builder->SetInputData(model);
    }
    builder->Update();
    octree = builder->GetOutput();
    if (octree->GetNumberOfNodes() == 0)
    {
      std::fprintf(stderr, "the octree is empty (see the builder's messages above)\n");
      return 1;
    }
    std::printf("finest level: %s\n", builder->GetFinestLevelReason());
    if (ply)
      std::printf("read: %.1f ms, %lld triangles\n", builder->GetReadTime() * 1e3,
        static_cast<long long>(builder->GetNumberOfInputTriangles()));
    std::printf("build: %.1f ms (%s), %lld triangles kept, %lld skipped, %lld nodes not "
                "topologically safe\n",
      builder->GetBuildTime() * 1e3, serial ? "1 thread" : "vtkSMPTools",
      static_cast<long long>(octree->GetNumberOfSurfaceTriangles()),
      static_cast<long long>(builder->GetNumberOfSkippedTriangles()),
      static_cast<long long>(builder->GetNumberOfUnsafeNodes()));
  }
  std::printf("octree: %lld nodes, finest level %d, root edge %g at (%g, %g, %g)\n",
    static_cast<long long>(octree->GetNumberOfNodes()), octree->GetFinestLevel(),
    octree->GetRootEdge(), octree->GetOrigin()[0], octree->GetOrigin()[1], octree->GetOrigin()[2]);
  std::printf("memory: %.1f MiB (%.1f bytes per input triangle)\n",
    octree->GetActualMemorySize() / 1024.0,
    octree->GetActualMemorySize() * 1024.0 /
      std::max<vtkIdType>(1, octree->GetNumberOfSurfaceTriangles()));
  if (builtInPieces)
  {
    std::printf("saved: %s, built in pieces (open it with this program, the viewer or "
                "vtkMultiscaleOctreeReader)\n",
      save.c_str());
  }
  else if (!save.empty() && !converted)
  {
    vtkNew<vtkMultiscaleOctreeWriter> writer;
    writer->SetInputData(octree);
    writer->SetFileName(save.c_str());
    writer->SetCompact(compact);
    if (!writer->Write())
    {
      std::fprintf(stderr, "cannot save the octree: %s\n", writer->GetErrorMessage());
      return 1;
    }
    std::printf("saved: %s (open it with this program, the viewer or vtkMultiscaleOctreeReader)\n",
      save.c_str());
  }

  vtkFieldData* nd = octree->GetNodeData();
  auto* lv = vtkUnsignedCharArray::SafeDownCast(nd->GetArray("Level"));
  auto* angle =
    vtkFloatArray::SafeDownCast(nd->GetArray(vtkMultiscaleOctree::ConeAngleArrayName()));
  auto* shape = vtkFloatArray::SafeDownCast(nd->GetArray("ShapeError"));
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(octree);
  vtkNew<vtkMultiscalePatchGenerator> patches;
  patches->SetInputConnection(cutter->GetOutputPort());
  std::printf("\nlevel     nodes   cell edge   cone angle (deg) mean/max   shape error mean/max"
              "   patches: triangles    ms\n");
  for (int l = 0; l <= octree->GetFinestLevel() + 1; ++l)
  {
    if (l > octree->GetFinestLevel() && octree->GetNumberOfSurfaceTriangles() > MaxTableTriangles)
    {
      std::printf(" full   (not made: %lld triangles, more than this table makes in memory)\n",
        static_cast<long long>(octree->GetNumberOfSurfaceTriangles()));
      break;
    }
    if (l > octree->GetFinestLevel())
    {
      cutter->SetLevel(-1);
      patches->Update();
      std::printf(" full %9lld   (every leaf opened: the input)%46lld %6.1f\n",
        static_cast<long long>(octree->GetNumberOfSurfacePoints()),
        static_cast<long long>(patches->GetNumberOfTriangles()), patches->GetGenerateTime() * 1e3);
      break;
    }
    if (l < octree->GetCoarsestDrawnLevel())
    {
      std::printf("%5d   (structure only: the octree was built in pieces of level %d)\n", l,
        octree->GetCoarsestDrawnLevel());
      continue;
    }
    long long count = 0;
    double am = 0, ax = 0, sm = 0, sx = 0;
    for (vtkIdType n = 0; n < octree->GetNumberOfNodes(); ++n)
    {
      if (lv->GetValue(n) != l)
        continue;
      ++count;
      const double a = angle->GetValue(n) * 180.0 / 3.14159265358979;
      am += a;
      ax = std::max(ax, a);
      sm += shape->GetValue(n);
      sx = std::max(sx, double(shape->GetValue(n)));
    }
    if (count > MaxTableTriangles / 4)
    {
      std::printf("%5d %9lld   %9.3g   (patches not made: too many cells for this table)\n", l,
        count, octree->GetCellEdge(l));
      continue;
    }
    cutter->SetLevel(l);
    patches->Update();
    std::printf("%5d %9lld   %9.3g   %8.1f / %6.1f            %9.3g / %9.3g   %18lld %6.1f\n", l,
      count, octree->GetCellEdge(l), am / count, ax, sm / count, sx,
      static_cast<long long>(patches->GetNumberOfTriangles()), patches->GetGenerateTime() * 1e3);
  }
  return 0;
}
