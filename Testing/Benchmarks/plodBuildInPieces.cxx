// SPDX-License-Identifier: BSD-3-Clause
// Builds a PLY model piece by piece in bounded memory into an octree file (plodPieces.h,
// plodPieceAssembly.h) and reports each step's time, the peak resident memory, the temporary
// disk and the file's bytes per input triangle, without VTK. For the benchmarks of models
// bigger than memory (docs/benchmarks.md, "Building in pieces").
//
//   plodBuildInPieces model.ply --save out.plod [--memory 4G] [--level k] [--pieces n]
//                               [--threads t] [--tmp folder] [--compact]
//
// --memory bounds one piece (its merge, then its build); the pieces are built one after the
// other, each over --threads threads (default: all cores).
#include "plodPieceAssembly.h"
#include "plodPieces.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since)
{
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// The process's peak resident memory (VmHWM), in MiB.
double PeakResidentMiB()
{
  FILE* f = std::fopen("/proc/self/status", "r");
  char line[256];
  double kib = 0;
  while (f && std::fgets(line, sizeof(line), f))
  {
    if (std::strncmp(line, "VmHWM:", 6) == 0)
    {
      kib = std::atof(line + 6);
    }
  }
  if (f)
  {
    std::fclose(f);
  }
  return kib / 1024.0;
}

/// A size in bytes: a number with an optional suffix K, M, G (powers of 1024); <= 0 if not.
double ParseBytes(const std::string& text)
{
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  const std::string unit = end;
  const double scale = unit.empty() ? 1
    : unit == "K"                   ? 1024.0
    : unit == "M"                   ? 1024.0 * 1024
    : unit == "G"                   ? 1024.0 * 1024 * 1024
                                    : -1;
  return end != text.c_str() && v > 0 && scale > 0 ? v * scale : -1;
}

/// Ranges run over `threads` threads, each taking the next range (the build's results do not
/// depend on the order).
plod::ParallelFor ThreadFor(int threads)
{
  return [threads](int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body) {
    grain = std::max<int64_t>(1, grain);
    const int64_t ranges = (n + grain - 1) / grain;
    std::atomic<int64_t> next(0);
    auto run = [&]() {
      for (int64_t r = next++; r < ranges; r = next++)
      {
        body(r * grain, std::min(n, (r + 1) * grain));
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::min<int64_t>(threads, ranges); ++t)
    {
      pool.emplace_back(run);
    }
    run();
    for (auto& t : pool)
    {
      t.join();
    }
  };
}
}

int main(int argc, char* argv[])
{
  std::string path, save;
  plod::PiecesParameters params;
  params.MemoryLimit = 4.0 * 1024 * 1024 * 1024;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  bool compact = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--memory" && i + 1 < argc)
      params.MemoryLimit = ParseBytes(argv[++i]);
    else if (a == "--level" && i + 1 < argc)
      params.OwnershipLevel = std::atoi(argv[++i]);
    else if (a == "--pieces" && i + 1 < argc)
      params.NumberOfPieces = std::atoi(argv[++i]);
    else if (a == "--threads" && i + 1 < argc)
      threads = std::max(1, std::atoi(argv[++i]));
    else if (a == "--tmp" && i + 1 < argc)
      params.TemporaryDirectory = argv[++i];
    else if (a == "--save" && i + 1 < argc)
      save = argv[++i];
    else if (a == "--compact")
      compact = true;
    else if (a[0] != '-' && path.empty())
      path = a;
    else
    {
      std::fprintf(stderr,
        "usage: %s model.ply --save out.plod [--memory 4G] [--level k] [--pieces n] "
        "[--threads t] [--tmp dir] [--compact]\n",
        argv[0]);
      return 1;
    }
  }
  if (path.empty() || save.empty() || !(params.MemoryLimit > 0))
  {
    std::fprintf(stderr, "a PLY file, --save and a memory size such as 4G are needed\n");
    return 1;
  }
  std::string step;
  Clock::time_point stepStart = Clock::now();
  params.Progress = [&](double, const char* s) {
    if (step != s)
    {
      if (!step.empty())
      {
        std::printf("  %-20s %7.1f s\n", step.c_str(), Seconds(stepStart));
      }
      step = s;
      stepStart = Clock::now();
    }
    return true;
  };

  params.Parallel = ThreadFor(threads);
  const Clock::time_point start = Clock::now();
  plod::PLYPieces pieces;
  std::string why;
  std::printf("splitting %s (memory %.0f MiB a piece, level %d)\n", path.c_str(),
    params.MemoryLimit / 1048576.0, params.OwnershipLevel);
  if (!pieces.Open(path, params, &why))
  {
    std::fprintf(stderr, "error: %s\n", why.c_str());
    return 1;
  }
  std::printf("  %-20s %7.1f s\n", step.c_str(), Seconds(stepStart));
  const double splitSeconds = Seconds(start);
  const plod::PartitionResult& agreed = pieces.GetAgreement();
  std::printf("split: %d pieces, finest level %d, %lld open edges, %lld unusable triangles, "
              "%.1f s, peak %.0f MiB, temporary disk %.0f MiB\n",
    pieces.GetNumberOfPieces(), agreed.FinestLevel,
    static_cast<long long>(agreed.NumberOfBoundaryEdges),
    static_cast<long long>(agreed.NumberOfSkippedTriangles), splitSeconds, PeakResidentMiB(),
    double(pieces.GetPeakTemporaryBytes()) / 1048576.0);

  plod::AssemblyParameters assembly;
  assembly.MemoryLimit = params.MemoryLimit;
  assembly.Parallel = ThreadFor(threads);
  assembly.Progress = params.Progress;
  assembly.Layout = compact ? plod::FileLayout::Compact : plod::FileLayout::Mapped;
  assembly.RemovePiecesAsBuilt = true;
  plod::AssemblyReport report;
  const Clock::time_point built = Clock::now();
  if (!plod::WriteOctreeFileFromPieces(pieces, save, assembly, &report, &why))
  {
    std::fprintf(stderr, "error: %s\n", why.c_str());
    return 1;
  }
  std::printf("  %-20s %7.1f s\n", step.c_str(), Seconds(stepStart));
  const double total = Seconds(start);
  const int64_t usable = pieces.GetNumberOfUsableTriangles();
  std::printf("built: %s, split %.1f s + build and write %.1f s = %.1f s (%.2f M input "
              "triangles/s), peak %.0f MiB, temporary disk %.0f MiB, file %.1f bytes per "
              "input triangle, levels above %d %s%s\n",
    save.c_str(), splitSeconds, Seconds(built), total, double(usable) / total / 1e6,
    PeakResidentMiB(),
    double(std::max(pieces.GetPeakTemporaryBytes(), report.PeakTemporaryBytes)) / 1048576.0,
    double(report.FileBytes) / double(std::max<int64_t>(1, usable)), pieces.GetOwnershipLevel(),
    report.StructureOnly.empty() ? "built from its cut" : "structure only: ",
    report.StructureOnly.c_str());
  return 0;
}
