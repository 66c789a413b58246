// SPDX-License-Identifier: BSD-3-Clause
// Writes a scan-like test model of any size to a binary PLY file in bounded memory
// (Testing/plodScanGenerator.h): a base mesh with each triangle split n x n and displaced by
// noise at every scale. For the benchmarks of models bigger than memory.
//
//   plodGenerateScan out.ply --triangles 256M [--base model.ply] [--seed 1]
//
// The base is the given PLY mesh, else the Stanford bunny from PLOD_DATA_DIR or ../shared/data
// (69,451 triangles), else a closed octahedral sphere of 32,768 triangles. n is chosen so that
// the model has about the asked number of triangles (a multiple of the base's).
#include "plodPLYRead.h"
#include "plodScanGenerator.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <sys/resource.h>

namespace
{
/// A count with an optional suffix K, M or G (powers of 1000); negative when it is not one.
double ParseCount(const std::string& text)
{
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  const std::string unit = end;
  const double scale = unit.empty() ? 1
    : unit == "K"                   ? 1e3
    : unit == "M"                   ? 1e6
    : unit == "G"                   ? 1e9
                                    : -1;
  return end != text.c_str() && v > 0 && scale > 0 ? v * scale : -1;
}
}

int main(int argc, char* argv[])
{
  std::string out, basePath;
  double wanted = 1e6;
  uint64_t seed = 1;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--triangles" && i + 1 < argc)
      wanted = ParseCount(argv[++i]);
    else if (a == "--base" && i + 1 < argc)
      basePath = argv[++i];
    else if (a == "--seed" && i + 1 < argc)
      seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a[0] != '-')
      out = a;
    else
    {
      std::fprintf(
        stderr, "usage: %s out.ply --triangles 256M [--base model.ply] [--seed 1]\n", argv[0]);
      return 1;
    }
  }
  if (out.empty() || !(wanted > 0))
  {
    std::fprintf(
      stderr, "usage: %s out.ply --triangles 256M [--base model.ply] [--seed 1]\n", argv[0]);
    return 1;
  }
  if (basePath.empty())
  {
    const char* dir = std::getenv("PLOD_DATA_DIR");
    for (const std::string& d :
      { std::string(dir ? dir : ""), std::string(PLOD_SOURCE_DIR) + "/../shared/data" })
    {
      std::FILE* f = d.empty() ? nullptr : std::fopen((d + "/bun_zipper.ply").c_str(), "rb");
      if (f)
      {
        std::fclose(f);
        basePath = d + "/bun_zipper.ply";
        break;
      }
    }
  }
  plodtest::BaseMesh base;
  if (!basePath.empty())
  {
    plod::PLYMesh mesh;
    std::string why;
    if (!plod::ReadPLYMesh(basePath, &mesh, &why))
    {
      std::fprintf(stderr, "%s: %s\n", basePath.c_str(), why.c_str());
      return 1;
    }
    base.Points.assign(mesh.PointsFloat.begin(), mesh.PointsFloat.end());
    if (base.Points.empty())
      base.Points = mesh.PointsDouble;
    base.Triangles.assign(mesh.Triangles.begin(), mesh.Triangles.end());
    std::printf("base: %s, %lld triangles\n", basePath.c_str(),
      static_cast<long long>(mesh.NumberOfTriangles()));
  }
  else
  {
    base = plodtest::OctahedralSphere(6);
    std::printf("base: octahedral sphere, %zu triangles\n", base.Triangles.size() / 3);
  }
  const double perBase = wanted / double(std::max<size_t>(1, base.Triangles.size() / 3));
  const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(perBase))));
  const auto start = std::chrono::steady_clock::now();
  int shown = 0;
  plodtest::ScanCounts counts;
  std::string why;
  const bool ok = plodtest::GenerateScanPLY(base, n, seed, out, &counts, &why, [&](double f) {
    if (int(f * 10) > shown)
    {
      shown = int(f * 10);
      std::printf("  %3d %%\n", shown * 10);
      std::fflush(stdout);
    }
  });
  if (!ok)
  {
    std::fprintf(stderr, "%s\n", why.c_str());
    return 1;
  }
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  std::printf("wrote %s: %lld points, %lld triangles (split %d x %d), %.2f GB in %.1f s, peak "
              "memory %.0f MB\n",
    out.c_str(), static_cast<long long>(counts.Points), static_cast<long long>(counts.Triangles), n,
    n, counts.Bytes / 1e9, seconds, usage.ru_maxrss / 1024.0);
  return 0;
}
