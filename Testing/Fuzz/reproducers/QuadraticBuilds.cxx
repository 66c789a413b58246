// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file QuadraticBuilds.cxx
 * @brief Reproducer (not built by default) for two build costs that grew with the square of a
 * local count, found by fuzzing plod::BuildOctree (docs/fuzzing.md). Both are fixed; the
 * program is kept to measure them, and BadInput.APiledPointCloudDoesNotHang and
 * BadInput.AHubOfBoundarySpokesDoesNotHang test them.
 *
 * 1. `cloud N`: a point cloud of N points, half on a unit sphere and half piled on one spot.
 *    The PCA normals (plodCloudSurface.cxx, EstimateNormals) visit, for every point, every
 *    point of the 27 cells around it: a cell holding k points costs k^2. The fuzzer met it as a
 *    cloud of 4096 points whose float coordinates collapsed onto a few values (14 s under
 *    ASan). The phase reports no progress, so an abort waits for its end.
 * 2. `star N`: N triangles (0, 2i + 1, 2i + 2) around one hub point, corners at random. Every
 *    spoke is a boundary edge, and MakeEdges looks for a boundary edge's triangle among all the
 *    triangles of its lower end: the hub's N triangles, N times. (The "passing" phase grows too,
 *    but as the cells these big triangles cross: the cost of what the cones promise.)
 *
 * Build and run from the repository root, after the normal build (`build/lib/libplod_core.a`):
 *
 *     g++ -O2 -std=c++17 -IFilters/Core Testing/Fuzz/reproducers/QuadraticBuilds.cxx \
 *       build/lib/libplod_core.a -o /tmp/quadratic -lpthread
 *     PLOD_BUILD_TIMING=1 /tmp/quadratic cloud 16384
 *     PLOD_BUILD_TIMING=1 /tmp/quadratic star 32000
 *
 * Measured (Release, g++ 12, one thread), before the fixes: cloud 4096 / 16384 / 65536 points:
 * the normals took 0.12 / 1.6 / 26.6 s. star 2000 / 8000 / 32000: edges 0.06 / 0.20 / 1.1 s.
 * After (at most 512 PCA candidates a point; a boundary edge's triangle searched from the end
 * with fewer triangles): cloud 65536: normals 0.26 s; star 32000: edges 0.18 s.
 */
#include "plodOctreeBuilder.h"
#include "plodOctreeStorage.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

int main(int argc, char** argv)
{
  const bool star = argc > 1 && std::strcmp(argv[1], "star") == 0;
  const int n = argc > 2 ? std::atoi(argv[2]) : 16384;
  std::mt19937 rng(1);
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<double> points;
  std::vector<int64_t> triangles;
  if (star)
  {
    points.assign(3 * (2 * int64_t(n) + 1), 0.0);
    for (size_t i = 3; i < points.size(); ++i)
      points[i] = uniform(rng);
    for (int i = 0; i < n; ++i)
    {
      triangles.insert(triangles.end(), { 0, 2 * int64_t(i) + 1, 2 * int64_t(i) + 2 });
    }
  }
  else
  {
    points.resize(3 * int64_t(n));
    for (int i = 0; i < n; ++i)
    {
      const double x = gauss(rng), y = gauss(rng), z = gauss(rng);
      const double l = std::sqrt(x * x + y * y + z * z);
      const bool pile = i % 2 == 1;
      points[3 * i] = pile ? 0.5 : x / l;
      points[3 * i + 1] = pile ? 0.5 : y / l;
      points[3 * i + 2] = pile ? 0.5 : z / l;
    }
  }
  plod::OctreeStorage storage;
  plod::BuildInput in;
  in.NumberOfPoints = static_cast<int64_t>(points.size() / 3);
  in.Points = points.data();
  in.NumberOfTriangles = static_cast<int64_t>(triangles.size() / 3);
  in.Triangles = triangles.empty() ? nullptr : triangles.data();
  const auto start = std::chrono::steady_clock::now();
  const plod::BuildResult r =
    plod::BuildOctree(in, plod::BuildParameters(), storage.MakeAllocator());
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s of %d: %s, level %d, %.3f s\n", star ? "star" : "cloud", n,
    r.Ok ? "built" : r.Error.c_str(), r.FinestLevel, seconds);
  return r.Ok ? 0 : 1;
}
