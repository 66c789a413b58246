// SPDX-License-Identifier: BSD-3-Clause
#include "plodBuildUtil.h"

#include <Eigen/Dense>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace plod
{
namespace build
{

void RadixSort(LargeVector<Item>& items, int bits, const ParallelFor& pfor)
{
  const int64_t n = static_cast<int64_t>(items.size());
  if (bits <= 0 || n < 2)
  {
    return;
  }
  const int passes = (bits + 10) / 11;
  const int digit = (bits + passes - 1) / passes; // balanced digits, at most 11 bits
  const size_t buckets = size_t(1) << digit;
  const int64_t chunks = n < 65536 ? 1 : 16;
  const int64_t chunkSize = (n + chunks - 1) / chunks;
  LargeVector<Item> tmp(items.size());
  LargeVector<size_t> count(buckets * chunks);
  for (int shift = 0; shift < bits; shift += digit)
  {
    std::fill(count.begin(), count.end(), 0);
    pfor(chunks, 1, [&](int64_t cb, int64_t ce) {
      for (int64_t c = cb; c < ce; ++c)
      {
        size_t* h = &count[c * buckets];
        for (int64_t i = c * chunkSize, e = std::min(n, (c + 1) * chunkSize); i < e; ++i)
        {
          ++h[(items[i].Key >> shift) & (buckets - 1)];
        }
      }
    });
    size_t sum = 0;
    for (size_t d = 0; d < buckets; ++d)
    {
      for (int64_t c = 0; c < chunks; ++c)
      {
        const size_t v = count[c * buckets + d];
        count[c * buckets + d] = sum;
        sum += v;
      }
    }
    pfor(chunks, 1, [&](int64_t cb, int64_t ce) {
      for (int64_t c = cb; c < ce; ++c)
      {
        size_t* h = &count[c * buckets];
        for (int64_t i = c * chunkSize, e = std::min(n, (c + 1) * chunkSize); i < e; ++i)
        {
          tmp[h[(items[i].Key >> shift) & (buckets - 1)]++] = items[i];
        }
      }
    });
    items.swap(tmp);
  }
}

void Quadric::Solve(const double mass[3], double truncation, double x[3]) const
{
  Eigen::Matrix3d a;
  a << this->A[0], this->A[1], this->A[2], this->A[1], this->A[3], this->A[4], this->A[2],
    this->A[4], this->A[5];
  const Eigen::Vector3d m(mass[0], mass[1], mass[2]);
  const Eigen::Vector3d r = Eigen::Vector3d(this->B[0], this->B[1], this->B[2]) - a * m;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(a);
  const Eigen::Vector3d& ev = eig.eigenvalues();
  const double top = std::max(std::abs(ev[0]), std::max(std::abs(ev[1]), std::abs(ev[2])));
  Eigen::Vector3d result = m;
  if (top > 0 && std::isfinite(top))
  {
    for (int i = 0; i < 3; ++i)
    {
      if (std::abs(ev[i]) > truncation * top)
      {
        const Eigen::Vector3d u = eig.eigenvectors().col(i);
        result += u * (u.dot(r) / ev[i]);
      }
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    x[i] = std::isfinite(result[i]) ? result[i] : mass[i];
  }
}

std::string FormatNumber(double x, int digits)
{
  char text[64];
  std::snprintf(text, sizeof(text), "%.*g", digits, x);
  return text;
}

namespace
{
double Seconds()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}

Reporter::Reporter(const ProgressCallback& callback)
  : Callback(callback)
  , Timing(std::getenv("PLOD_BUILD_TIMING") != nullptr)
  , Clock(Seconds())
{
}

namespace
{
/// Resident and peak resident memory in MB (Linux), for the timing report.
void Resident(double& now, double& peak)
{
  now = peak = -1;
  if (FILE* f = std::fopen("/proc/self/status", "r"))
  {
    char line[256];
    while (std::fgets(line, sizeof(line), f))
    {
      if (std::strncmp(line, "VmRSS:", 6) == 0)
        now = std::atof(line + 6) / 1024.0;
      else if (std::strncmp(line, "VmHWM:", 6) == 0)
        peak = std::atof(line + 6) / 1024.0;
    }
    std::fclose(f);
  }
}
}

void Reporter::Finish()
{
  if (this->Timing && this->Name)
  {
    const double now = Seconds();
    double rss, peak;
    Resident(rss, peak);
    std::fprintf(stderr, "plod build: %-16s %9.1f ms   resident %8.1f MB, peak %8.1f MB\n",
      this->Name, 1e3 * (now - this->Clock), rss, peak);
    this->Clock = now;
  }
}

bool Reporter::Phase(const char* name, double start, double end)
{
  this->Finish();
  this->Name = name;
  this->Clock = Seconds();
  this->Start = start;
  this->End = end;
  return (*this)(0.0);
}

bool Reporter::operator()(double fraction)
{
  if (this->Stopped)
  {
    return false;
  }
  if (this->Callback &&
    !this->Callback(
      this->Start + (this->End - this->Start) * std::min(1.0, std::max(0.0, fraction))))
  {
    this->Stopped = true;
  }
  return !this->Stopped;
}

bool PlaceRootCube(
  const double lo[3], const double hi[3], double origin[3], double& rootEdge, std::string* why)
{
  constexpr double margin = RootMargin;
  constexpr double shift[3] = { 4.14213562e-4, 2.36067977e-4, 1.41592654e-4 };
  double extent = std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] });
  const double far = std::max({ std::abs(lo[0]), std::abs(hi[0]), std::abs(lo[1]), std::abs(hi[1]),
    std::abs(lo[2]), std::abs(hi[2]) });
  if (!(extent > far * 1e-12) || !std::isfinite(extent))
  {
    // all points coincide (or the extent is below double resolution at that distance): give
    // the root a size that the coordinates can still resolve
    extent = far > 0 ? far * 1e-6 : 1.0;
  }
  // single-precision storage of vertices and shape errors relative to the origin: cells of the
  // finest level must stay normal floats, and the extent finite as a float
  if (!(extent >= MinRootExtent) || !(extent <= MaxRootExtent))
  {
    if (why)
    {
      *why = "the model's extent " + FormatNumber(extent) +
        " is outside [1e-30, 1e30], which single-precision vertices cannot represent; scale "
        "the coordinates";
    }
    return false;
  }
  rootEdge = extent * (1.0 + 2.0 * margin);
  for (int a = 0; a < 3; ++a)
  {
    origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * rootEdge - shift[a] * rootEdge;
  }
  return true;
}

bool ValidateRootCube(const double origin[3], double rootEdge, std::string* why)
{
  auto fail = [why](const std::string& text) {
    if (why)
    {
      *why = text;
    }
    return false;
  };
  const std::string cube = "the given root cube (origin (" + FormatNumber(origin[0]) + ", " +
    FormatNumber(origin[1]) + ", " + FormatNumber(origin[2]) + "), edge " + FormatNumber(rootEdge) +
    ")";
  if (!std::isfinite(origin[0]) || !std::isfinite(origin[1]) || !std::isfinite(origin[2]))
  {
    return fail(cube + " has a non-finite origin");
  }
  const double maxEdge = MaxRootExtent * (1.0 + 2.0 * RootMargin);
  if (!(rootEdge >= MinRootExtent) || !(rootEdge <= maxEdge))
  {
    return fail(cube + " has an edge outside [" + FormatNumber(MinRootExtent) + ", " +
      FormatNumber(maxEdge) + "], which single-precision vertices cannot represent");
  }
  const double far = std::max({ std::abs(origin[0]), std::abs(origin[1]), std::abs(origin[2]) });
  if (!(rootEdge > far * 1e-12))
  {
    return fail(cube + " is too small for its distance from the world origin: double " +
      "coordinates cannot resolve its cells (the edge must exceed 1e-12 of the largest origin " +
      "coordinate)");
  }
  for (int a = 0; a < 3; ++a)
  {
    if (!std::isfinite(origin[a] + rootEdge))
    {
      return fail(cube + " has a far corner that is not finite");
    }
  }
  return true;
}

std::string PointOutsideRootCube(
  int64_t id, const double x[3], const double origin[3], double rootEdge)
{
  // all the digits: a point just outside a face must not print as lying on it
  std::string text = "point " + std::to_string(id) + " (" + FormatNumber(x[0], 17) + ", " +
    FormatNumber(x[1], 17) + ", " + FormatNumber(x[2], 17) + ") lies outside the given root cube [";
  for (int a = 0; a < 3; ++a)
  {
    text += (a ? "] x [" : "") + FormatNumber(origin[a], 17) + ", " +
      FormatNumber(origin[a] + rootEdge, 17);
  }
  return text + "]; give a cube that holds every point (the build does not clamp points into it)";
}

TriangleBoxTester::TriangleBoxTester(const double a[3], const double b[3], const double c[3])
{
  const double* v[3] = { a, b, c };
  const double e[3][3] = { { b[0] - a[0], b[1] - a[1], b[2] - a[2] },
    { c[0] - b[0], c[1] - b[1], c[2] - b[2] }, { a[0] - c[0], a[1] - c[1], a[2] - c[2] } };
  auto add = [&](const double axis[3]) {
    double* x = this->Axis[this->Count];
    for (int i = 0; i < 3; ++i)
      x[i] = axis[i];
    double mn = Dot(x, v[0]), mx = mn;
    for (int k = 1; k < 3; ++k)
    {
      const double d = Dot(x, v[k]);
      mn = std::min(mn, d);
      mx = std::max(mx, d);
    }
    this->Min[this->Count] = mn;
    this->Max[this->Count] = mx;
    this->Spread[this->Count] = 0.5 * (std::abs(x[0]) + std::abs(x[1]) + std::abs(x[2]));
    ++this->Count;
  };
  // the box axes first (the bounding boxes: the usual early exit), the triangle's plane, then
  // the nine edge x box-axis directions
  for (int j = 0; j < 3; ++j)
  {
    const double unit[3] = { j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0 };
    add(unit);
  }
  double n[3];
  Cross(e[0], e[1], n);
  add(n);
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      const double unit[3] = { j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0 };
      double axis[3];
      Cross(e[i], unit, axis);
      add(axis);
    }
  }
}

bool TriangleBoxTester::Meets(const double lo[3], double h) const
{
  const double half = 0.5 * h;
  const double centre[3] = { lo[0] + half, lo[1] + half, lo[2] + half };
  for (int i = 0; i < this->Count; ++i)
  {
    const double c = Dot(this->Axis[i], centre);
    const double radius = h * this->Spread[i]; // the cube's half extent along the axis
    if (this->Min[i] - c > radius || this->Max[i] - c < -radius)
    {
      return false;
    }
  }
  return true;
}

} // namespace build
} // namespace plod
