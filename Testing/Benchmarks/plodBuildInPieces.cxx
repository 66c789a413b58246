// SPDX-License-Identifier: BSD-3-Clause
// Builds a PLY model piece by piece in bounded memory (plodPieces.h, then plod::BuildOctree per
// piece) and reports each step's time, the peak resident memory, the temporary disk and the
// octree bytes per input triangle. For the benchmarks of models bigger than memory
// (docs/benchmarks.md, "Building in pieces").
//
//   plodBuildInPieces model.ply [--memory 4G] [--level k] [--pieces n] [--threads t]
//                               [--tmp folder]
//
// --memory bounds one piece (its merge, then its build); the pieces are built one after the
// other, each over --threads threads (default: all cores). Each piece's octree is measured and
// let go: putting the pieces' octrees together into one file is not built yet.
#include "plodOctreeBuilder.h"
#include "plodOctreeStorage.h"
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
  std::string path;
  plod::PiecesParameters params;
  params.MemoryLimit = 4.0 * 1024 * 1024 * 1024;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
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
    else if (a[0] != '-' && path.empty())
      path = a;
    else
    {
      std::fprintf(stderr,
        "usage: %s model.ply [--memory 4G] [--level k] [--pieces n] [--threads t] [--tmp dir]\n",
        argv[0]);
      return 1;
    }
  }
  if (path.empty() || !(params.MemoryLimit > 0))
  {
    std::fprintf(stderr, "a PLY file and a memory size such as 4G are needed\n");
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

  plod::BuildParameters build;
  build.FinestLevel = agreed.FinestLevel;
  build.HasRootCube = true;
  std::copy(agreed.RootOrigin, agreed.RootOrigin + 3, build.RootOrigin);
  build.RootEdge = agreed.RootEdge;
  build.MemoryLimit = params.MemoryLimit;
  const plod::ParallelFor parallel = ThreadFor(threads);
  double buildSeconds = 0, octreeBytes = 0;
  const int64_t usable = pieces.GetNumberOfUsableTriangles();
  int64_t received = 0;
  for (int p = 0; p < pieces.GetNumberOfPieces(); ++p)
  {
    const Clock::time_point t0 = Clock::now();
    plod::PartitionResult r;
    if (!pieces.GetPiece(p, &r, &why))
    {
      std::fprintf(stderr, "error: %s\n", why.c_str());
      return 1;
    }
    std::vector<float> normals(r.Normals.begin(), r.Normals.end());
    std::vector<double>().swap(r.Normals);
    plod::BuildInput in;
    in.NumberOfPoints = static_cast<int64_t>(r.Ghost.size());
    in.Points = r.Points.data();
    in.NumberOfTriangles = static_cast<int64_t>(r.Triangles.size() / 3);
    in.Triangles = r.Triangles.data();
    in.PointNormals = normals.empty() ? nullptr : normals.data();
    in.PointGhost = r.Ghost.data();
    plod::OctreeStorage storage;
    const plod::BuildResult b = plod::BuildOctree(in, build, storage.MakeAllocator(), parallel);
    if (!b.Ok)
    {
      std::fprintf(stderr, "error: piece %d: %s\n", p, b.Error.c_str());
      return 1;
    }
    const double seconds = Seconds(t0);
    buildSeconds += seconds;
    const double bytes = plod::EstimateOctreeBytes(b.NumberOfPoints, b.NumberOfTriangles);
    octreeBytes += bytes;
    received += in.NumberOfTriangles;
    std::printf(
      "  piece %3d: %10lld triangles (%5.1f%% halo), %8lld nodes, %6.1f s, peak %.0f MiB\n", p,
      static_cast<long long>(in.NumberOfTriangles),
      100.0 * double(r.NumberOfHaloTriangles) / double(std::max<int64_t>(1, in.NumberOfTriangles)),
      static_cast<long long>(b.NumberOfNodes), seconds, PeakResidentMiB());
  }
  const double total = Seconds(start);
  std::printf("built: %lld triangles received (%.1f%% more than the %lld usable), split %.1f s + "
              "build %.1f s = %.1f s (%.2f M input triangles/s), peak %.0f MiB, temporary disk "
              "%.0f MiB, octrees %.1f bytes per input triangle\n",
    static_cast<long long>(received),
    100.0 * (double(received) / double(std::max<int64_t>(1, usable)) - 1.0),
    static_cast<long long>(usable), splitSeconds, buildSeconds, total, double(usable) / total / 1e6,
    PeakResidentMiB(), double(pieces.GetPeakTemporaryBytes()) / 1048576.0,
    octreeBytes / double(std::max<int64_t>(1, usable)));
  return 0;
}
