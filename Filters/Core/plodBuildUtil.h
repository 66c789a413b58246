// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodBuildUtil.h
 * @brief Internal helpers of the octree build (not installed): radix sort, deterministic
 * parallel gather, plane quadrics (Garland & Heckbert 1997, Lindstrom 2000), normal cones
 * (SRCC eq. 1-2) and the triangle/box overlap test (separating axes, Akenine-Moeller 2001).
 */
#ifndef plodBuildUtil_h
#define plodBuildUtil_h

#include "plodLargeArrays.h"
#include "plodOctreeBuilder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace plod
{
namespace build
{

constexpr double Pi = 3.14159265358979323846;

/// A key and a payload index, sorted by key (radix sort, stable).
struct Item
{
  uint64_t Key;
  uint64_t Ref;
};

/**
 * Stable LSD radix sort of items by key (`bits` significant key bits), parallel over a fixed
 * number of chunks: per-chunk histograms, one prefix sum over (digit, chunk), then each chunk
 * scatters its items. The result is the same for any number of threads.
 */
void RadixSort(LargeVector<Item>& items, int bits, const ParallelFor& pfor);

/// Runs `body(begin, end, out)` over fixed chunks and concatenates the per-chunk outputs in
/// chunk order, so the result does not depend on the number of threads.
template <typename T, typename Body>
LargeVector<T> ChunkedGather(int64_t n, int64_t chunk, const ParallelFor& pfor, Body body)
{
  const int64_t chunks = (n + chunk - 1) / chunk;
  LargeVector<LargeVector<T>> parts(static_cast<size_t>(chunks));
  pfor(chunks, 1, [&](int64_t b, int64_t e) {
    for (int64_t c = b; c < e; ++c)
    {
      body(c * chunk, std::min(n, (c + 1) * chunk), parts[c]);
    }
  });
  size_t total = 0;
  for (const auto& p : parts)
  {
    total += p.size();
  }
  LargeVector<T> all;
  all.reserve(total);
  for (auto& p : parts)
  {
    all.insert(all.end(), p.begin(), p.end());
    LargeVector<T>().swap(p);
  }
  return all;
}

inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline void Cross(const double a[3], const double b[3], double c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/// Angle between two unit vectors, accurate near 0 and pi (unlike acos of the dot product).
inline double AngleBetween(const double a[3], const double b[3])
{
  double c[3];
  Cross(a, b, c);
  return std::atan2(std::sqrt(Dot(c, c)), Dot(a, b));
}

/// Quadric of planes: sum of w (n.x - d)^2, kept as (A, b, c) with A symmetric (xx xy xz yy yz
/// zz), b = sum w n d, c = sum w d^2.
struct Quadric
{
  double A[6] = { 0, 0, 0, 0, 0, 0 };
  double B[3] = { 0, 0, 0 };
  double C = 0;

  /// Adds the plane with unit normal `n` through `x`, with weight `w`.
  void AddPlane(const double n[3], const double x[3], double w)
  {
    const double d = Dot(n, x);
    this->A[0] += w * n[0] * n[0];
    this->A[1] += w * n[0] * n[1];
    this->A[2] += w * n[0] * n[2];
    this->A[3] += w * n[1] * n[1];
    this->A[4] += w * n[1] * n[2];
    this->A[5] += w * n[2] * n[2];
    for (int i = 0; i < 3; ++i)
    {
      this->B[i] += w * n[i] * d;
    }
    this->C += w * d * d;
  }

  void Add(const Quadric& o)
  {
    for (int i = 0; i < 6; ++i)
    {
      this->A[i] += o.A[i];
    }
    for (int i = 0; i < 3; ++i)
    {
      this->B[i] += o.B[i];
    }
    this->C += o.C;
  }

  /**
   * The minimiser nearest to `mass` (truncated pseudo-inverse: eigenvalues below `truncation`
   * times the largest are ignored, so a flat or ridge-like cell keeps the mass point's
   * tangential position), written to `x`.
   */
  void Solve(const double mass[3], double truncation, double x[3]) const;
};

/**
 * SRCC eq. (1)-(2) in one place: the cone around `axis` (unit) that holds the child cones
 * (axes `childAxis[i]`, unit; angles `childAngle[i]`): theta = max_i(angle(axis, n_i) + theta_i),
 * clamped to [0, pi]. Returns pi when `axisValid` is false (the children's normals sum to about
 * zero: no axis bounds them better).
 */
inline double EnclosingConeAngle(const double axis[3], bool axisValid, const double (*childAxis)[3],
  const double* childAngle, int count)
{
  if (!axisValid)
  {
    return Pi;
  }
  double theta = 0;
  for (int i = 0; i < count; ++i)
  {
    theta = std::max(theta, AngleBetween(axis, childAxis[i]) + childAngle[i]);
  }
  return std::min(theta, Pi);
}

/**
 * Normalises a sum of weighted normals into a cone axis. The axis is valid when the sum is at
 * least `1e-6` of the total weight: opposite normals that cancel leave no meaningful axis.
 */
inline bool NormaliseAxis(const double sum[3], double weight, double axis[3])
{
  const double len = std::sqrt(Dot(sum, sum));
  if (len > 1e-6 * weight && len > 0 && std::isfinite(len))
  {
    for (int a = 0; a < 3; ++a)
    {
      axis[a] = sum[a] / len;
    }
    return true;
  }
  axis[0] = axis[1] = 0;
  axis[2] = 1;
  return false;
}

/**
 * Whether the triangle (a, b, c) meets axis-aligned cubes [lo, lo + h]^3 (closed), by the
 * separating axis theorem: the box axes, the triangle's normal and the nine edge cross
 * products. The 13 axes and the triangle's extent along each are computed once, so one tester
 * serves every cube (of any size) a triangle is tried against.
 */
class TriangleBoxTester
{
public:
  TriangleBoxTester(const double a[3], const double b[3], const double c[3]);
  bool Meets(const double lo[3], double h) const;

private:
  double Axis[13][3];
  double Min[13], Max[13];
  double Spread[13]; // half the L1 norm of the axis: times h, the cube's half extent along it
  int Count = 0;
};

/// Runs `pfor` over [0, n) in blocks of `block` items and calls `progress(fraction of n done)`
/// between blocks, on the calling thread; returns false as soon as progress returns false.
template <typename Body, typename Progress>
bool BlockedFor(
  int64_t n, int64_t grain, int64_t block, const ParallelFor& pfor, Body body, Progress progress)
{
  for (int64_t start = 0; start < n; start += block)
  {
    const int64_t end = std::min(n, start + block);
    pfor(end - start, grain, [&](int64_t b, int64_t e) { body(start + b, start + e); });
    if (!progress(double(end) / double(n)))
    {
      return false;
    }
  }
  return true;
}

/**
 * Progress of a build in phases: each phase owns a range of [0, 1]; the reporter maps a
 * fraction of the phase into it, calls the user's callback (on the calling thread) and
 * remembers an abort. PLOD_BUILD_TIMING=1 in the environment prints each phase's time.
 */
class Reporter
{
public:
  explicit Reporter(const ProgressCallback& callback);
  /// Starts a phase covering [start, end] of the build.
  bool Phase(const char* name, double start, double end);
  /// Reports `fraction` of the current phase; false when the user aborted.
  bool operator()(double fraction);
  bool Aborted() const { return this->Stopped; }
  /// Prints the last phase's time when timing is on.
  void Finish();

private:
  ProgressCallback Callback;
  double Start = 0, End = 0;
  bool Stopped = false;
  bool Timing = false;
  const char* Name = nullptr;
  double Clock = 0;
};

/**
 * The root cube around the bounds [lo, hi] (finite): a margin of 1/32 of the largest extent on
 * each side and a shift below 1e-3 of the edge along irrational fractions, so that no point lies
 * on the root boundary and regular coordinates rarely fall on grid planes. A zero extent (one
 * point) gets an edge the coordinates can still resolve. Returns false with a message when the
 * extent is outside what single-precision storage can represent.
 */
bool PlaceRootCube(
  const double lo[3], const double hi[3], double origin[3], double& rootEdge, std::string* why);

/// Margin PlaceRootCube adds on each side, as a fraction of the largest extent.
constexpr double RootMargin = 1.0 / 32.0;
/// Extents PlaceRootCube accepts (single-precision vertices and cells relative to the origin).
constexpr double MinRootExtent = 1e-30;
constexpr double MaxRootExtent = 1e30;

/**
 * Checks a root cube given by the caller (BuildParameters::HasRootCube) against the limits
 * PlaceRootCube enforces on the cubes it places: a finite origin; an edge in [MinRootExtent,
 * MaxRootExtent (1 + 2 RootMargin)], the range of the edges it can give; an edge above 1e-12 of
 * the origin's largest coordinate (below it, double coordinates cannot resolve the cells, and
 * PlaceRootCube never places such a cube); the far corner finite. Returns false with a message.
 */
bool ValidateRootCube(const double origin[3], double rootEdge, std::string* why);

/// True when `x` lies in the closed cube [origin, origin + rootEdge]^3.
inline bool InsideRootCube(const double x[3], const double origin[3], double rootEdge)
{
  for (int a = 0; a < 3; ++a)
  {
    if (!(x[a] >= origin[a] && x[a] <= origin[a] + rootEdge))
    {
      return false;
    }
  }
  return true;
}

/// The error for input point `id` at `x` outside the given root cube.
std::string PointOutsideRootCube(
  int64_t id, const double x[3], const double origin[3], double rootEdge);

/// A number in %g notation with `digits` significant digits (std::to_string prints 1e-300 as
/// 0.000000); 17 digits give a double exactly.
std::string FormatNumber(double x, int digits = 6);

/// Index of the most significant set bit of a non-zero 64-bit word.
inline int HighestBit(uint64_t x)
{
  return 63 - __builtin_clzll(x);
}

/// Level of the lowest common ancestor of two cells of level `level` with Morton keys a, b.
inline int CommonLevel(uint64_t a, uint64_t b, int level)
{
  const uint64_t x = a ^ b;
  return x == 0 ? level : level - HighestBit(x) / 3 - 1;
}

} // namespace build
} // namespace plod

#endif
