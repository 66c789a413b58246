// SPDX-License-Identifier: BSD-3-Clause
#include "plodOctreeBuilder.h"

#include "plodPatches.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

namespace plod
{

void SerialFor(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body)
{
  grain = std::max<int64_t>(grain, 1);
  for (int64_t b = 0; b < n; b += grain)
  {
    body(b, std::min(n, b + grain));
  }
}

namespace
{

constexpr double Pi = 3.14159265358979323846;
/// Margin on each side of the bounds, as a fraction of the largest extent.
constexpr double RootMargin = 1.0 / 32.0;
/// Irrational shift of the root origin (fraction of the root edge), see the header.
constexpr double RootShift[3] = { 4.14213562e-4, 2.36067977e-4, 1.41592654e-4 };
/// Relative eigenvalue threshold of the truncated QEF solve.
constexpr double QEFTruncation = 0.1;
/// Normal weight of one crossing in each of its four cells (a quarter of a cell face).
constexpr float CrossingWeight = 0.25f;

/// A key and a payload index, sorted by key (radix sort, stable).
struct Item
{
  uint64_t Key;
  uint64_t Ref;
};

/// Samples of a finest cell: an input point (Ref = point << 3 | 4) or a crossing on one of its
/// edges (Ref = crossing << 3 | slot, slot = which of the four cells around the edge).
constexpr uint64_t PointFlag = 4;

/**
 * A point where the surface crosses a finest grid edge, in 8 bytes: the offset T along the
 * edge (from its lower corner) and a packed word `source << 3 | positive << 2 | axis`. The
 * corner is not stored: each of the four cells around the edge knows it from its own key and
 * the slot of the sample. `source` is the triangle (meshes) or the nearest point (clouds) that
 * gives the crossing its normal and material bounds.
 */
struct Crossing
{
  float T;
  uint32_t Packed;
  int Axis() const { return static_cast<int>(this->Packed & 3u); }
  int Sign() const { return (this->Packed & 4u) ? 1 : -1; }
  int64_t Source() const { return static_cast<int64_t>(this->Packed >> 3); }
  static Crossing Make(double t, int axis, int sign, int64_t source)
  {
    return { static_cast<float>(t),
      static_cast<uint32_t>((uint64_t(source) << 3) | (sign > 0 ? 4u : 0u) | uint32_t(axis)) };
  }
};
/// A crossing with the Morton key of its edge's lower corner (used to make its four samples).
struct CrossingRecord
{
  uint64_t Corner;
  Crossing C;
};

/// Largest source index a Crossing can hold.
constexpr int64_t MaxCrossingSource = (int64_t(1) << 29) - 1;

/// Quadric of planes: sum of w * (n.x - d)^2 as (A, b) with A symmetric.
struct Quadric
{
  double A[6] = { 0, 0, 0, 0, 0, 0 }; // xx xy xz yy yz zz
  double B[3] = { 0, 0, 0 };
  void AddPlane(const double n[3], const double x[3], double w)
  {
    const double d = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
    A[0] += w * n[0] * n[0];
    A[1] += w * n[0] * n[1];
    A[2] += w * n[0] * n[2];
    A[3] += w * n[1] * n[1];
    A[4] += w * n[1] * n[2];
    A[5] += w * n[2] * n[2];
    for (int i = 0; i < 3; ++i)
    {
      B[i] += w * n[i] * d;
    }
  }
  void Add(const Quadric& o)
  {
    for (int i = 0; i < 6; ++i)
    {
      A[i] += o.A[i];
    }
    for (int i = 0; i < 3; ++i)
    {
      B[i] += o.B[i];
    }
  }
  /// Minimiser nearest to `mass` (truncated pseudo-inverse), written to `x`.
  void Solve(const double mass[3], double x[3]) const
  {
    Eigen::Matrix3d a;
    a << A[0], A[1], A[2], A[1], A[3], A[4], A[2], A[4], A[5];
    const Eigen::Vector3d m(mass[0], mass[1], mass[2]);
    const Eigen::Vector3d r = Eigen::Vector3d(B[0], B[1], B[2]) - a * m;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(a);
    const Eigen::Vector3d& ev = eig.eigenvalues();
    const double top = std::max(std::abs(ev[0]), std::max(std::abs(ev[1]), std::abs(ev[2])));
    Eigen::Vector3d result = m;
    if (top > 0 && std::isfinite(top))
    {
      for (int i = 0; i < 3; ++i)
      {
        if (std::abs(ev[i]) > QEFTruncation * top)
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
};

/// Angle between two unit vectors, accurate near 0 and pi (unlike acos of the dot product).
inline double AngleBetween(const double a[3], const double b[3])
{
  const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0] };
  return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

/// A number that grows with the angle between unit vectors, cheaper than the angle.
inline double AngleKey(const double a[3], const double b[3])
{
  const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0] };
  const double s2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
  return (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) >= 0 ? s2 : 2.0 - s2;
}

/// The angle whose AngleKey is `key`.
inline double AngleFromKey(double key)
{
  return key <= 1.0 ? std::asin(std::sqrt(std::max(0.0, key)))
                    : Pi - std::asin(std::sqrt(std::max(0.0, 2.0 - key)));
}

/// Input points inside a node (additive over children).
struct PointSums
{
  double Sum[3] = { 0, 0, 0 };
  uint32_t Count = 0;
};

/// Crossings on each of a node's 12 edges: sum of their offsets along the edge (finest units,
/// from the cell's lower corner) and their count. A parent edge is its children's two halves.
struct EdgeSums
{
  float Offset[12] = { 0 };
  uint32_t Count[12] = { 0 };
};

/**
 * Stable LSD radix sort of items by key (`bits` significant key bits), parallel over a fixed
 * number of chunks: per-chunk histograms, one prefix sum over (digit, chunk), then each chunk
 * scatters its items. The result is the same for any number of threads.
 */
void RadixSort(std::vector<Item>& items, int bits, const ParallelFor& pfor = SerialFor)
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
  std::vector<Item> tmp(items.size());
  std::vector<size_t> count(buckets * chunks);
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

inline uint32_t ClampCell(double u, uint32_t cells)
{
  if (!(u >= 0))
  {
    return 0;
  }
  const double f = std::floor(u);
  return f >= cells ? cells - 1 : static_cast<uint32_t>(f);
}

/**
 * Sign of the edge function of edge A->B at the query point (x, y) perturbed by (dp, dq),
 * dp >> dq > 0 (symbolic perturbation: exact zeros are decided by the derivatives). The edge is
 * evaluated in a canonical (lexicographic) order so that the two triangles sharing it get the
 * same number with opposite signs: a grid line through a shared edge or vertex is inside
 * exactly one triangle. `value` receives E for barycentrics.
 */
inline int EdgeSide(const double a[2], const double b[2], double x, double y, double& value)
{
  const bool swap = (b[0] < a[0]) || (b[0] == a[0] && b[1] < a[1]);
  const double* s = swap ? b : a;
  const double* t = swap ? a : b;
  double e = (t[0] - s[0]) * (y - s[1]) - (t[1] - s[1]) * (x - s[0]);
  int sign;
  if (e > 0)
  {
    sign = 1;
  }
  else if (e < 0)
  {
    sign = -1;
  }
  else
  {
    const double dx = -(t[1] - s[1]);
    const double dy = (t[0] - s[0]);
    sign = dx != 0 ? (dx > 0 ? 1 : -1) : (dy > 0 ? 1 : (dy < 0 ? -1 : 0));
  }
  if (swap)
  {
    e = -e;
    sign = -sign;
  }
  value = e;
  return sign;
}

/// The input in Morton order of the finest cells, in finest grid units.
struct Prepared
{
  int64_t NumberOfPoints = 0;
  std::vector<double> U;       // 3 per point
  std::vector<uint64_t> Key;   // finest cell of each point, sorted
  std::vector<int64_t> Source; // the input index of each point (clouds only)
  std::vector<int64_t> Tri;    // 3 per triangle, renumbered, in Morton order of centroids
  std::vector<float> TriNormal; // unit normal per triangle
  std::vector<float> TriWeight; // min(area, 1), 0 for degenerate triangles
  std::vector<float> TriDiffuse, TriSpecular;     // empty: from the points or uniform
  std::vector<float> PointDiffuse, PointSpecular; // empty: uniform
  std::vector<float> Normal;      // 3 per point: vertex cone axis (mesh) or point normal (cloud)
  std::vector<float> NormalAngle; // vertex cone half angle (mesh), 0 for clouds
  std::vector<float> NormalWeight; // 0: no normal
  std::vector<Quadric> VertexQuadric; // QEF rule, meshes: planes of each vertex's triangles
  float UniformDiffuse = 1, UniformSpecular = 0;
  bool HasMaterial() const
  {
    return !(this->TriDiffuse.empty() && this->TriSpecular.empty() &&
      this->PointDiffuse.empty() && this->PointSpecular.empty());
  }
};

inline float ValueOr(const std::vector<float>& v, int64_t i, float fallback)
{
  return v.empty() ? fallback : v[i];
}

/// Crossings of one triangle with the finest grid lines along the three axes.
void TriangleCrossings(
  const Prepared& P, uint32_t cells, int64_t t, std::vector<CrossingRecord>& out)
{
  const int64_t* tri = &P.Tri[3 * t];
  const double* v[3] = { &P.U[3 * tri[0]], &P.U[3 * tri[1]], &P.U[3 * tri[2]] };
  for (int a = 0; a < 3; ++a)
  {
    const int p = (a + 1) % 3, q = (a + 2) % 3;
    const double V[3][2] = { { v[0][p], v[0][q] }, { v[1][p], v[1][q] }, { v[2][p], v[2][q] } };
    const double area2 =
      (V[1][0] - V[0][0]) * (V[2][1] - V[0][1]) - (V[1][1] - V[0][1]) * (V[2][0] - V[0][0]);
    if (area2 == 0 || !std::isfinite(area2))
    {
      continue;
    }
    const int64_t j0 =
      std::max<int64_t>(1, static_cast<int64_t>(std::ceil(std::min({ V[0][0], V[1][0], V[2][0] }))));
    const int64_t j1 = std::min<int64_t>(
      cells - 1, static_cast<int64_t>(std::floor(std::max({ V[0][0], V[1][0], V[2][0] }))));
    const int64_t k0 =
      std::max<int64_t>(1, static_cast<int64_t>(std::ceil(std::min({ V[0][1], V[1][1], V[2][1] }))));
    const int64_t k1 = std::min<int64_t>(
      cells - 1, static_cast<int64_t>(std::floor(std::max({ V[0][1], V[1][1], V[2][1] }))));
    for (int64_t j = j0; j <= j1; ++j)
    {
      for (int64_t k = k0; k <= k1; ++k)
      {
        double e0, e1, e2;
        const int s0 = EdgeSide(V[1], V[2], double(j), double(k), e0); // opposite vertex 0
        const int s1 = EdgeSide(V[2], V[0], double(j), double(k), e1); // opposite vertex 1
        const int s2 = EdgeSide(V[0], V[1], double(j), double(k), e2); // opposite vertex 2
        if (s0 == 0 || s0 != s1 || s1 != s2)
        {
          continue;
        }
        const double sum = e0 + e1 + e2;
        double w0 = 1.0 / 3, w1 = 1.0 / 3;
        if (sum != 0)
        {
          w0 = e0 / sum;
          w1 = e1 / sum;
        }
        const double w2 = 1.0 - w0 - w1;
        double depth = w0 * v[0][a] + w1 * v[1][a] + w2 * v[2][a];
        depth = std::min(std::max(depth, 0.0), double(cells) * (1 - 1e-12));
        const uint32_t ca = ClampCell(depth, cells);
        uint32_t corner[3];
        corner[a] = ca;
        corner[p] = static_cast<uint32_t>(j);
        corner[q] = static_cast<uint32_t>(k);
        out.push_back({ MortonEncode(corner[0], corner[1], corner[2]),
          Crossing::Make(std::min(depth - ca, 1.0 - 1e-7), a, s0, t) });
      }
    }
  }
}

/// Runs `body(begin, end, out)` over fixed chunks and concatenates the per-chunk outputs in
/// chunk order, so the result does not depend on the number of threads.
template <typename T, typename Body>
std::vector<T> ChunkedGather(int64_t n, int64_t chunk, const ParallelFor& pfor, Body body)
{
  const int64_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::vector<T>> parts(static_cast<size_t>(chunks));
  pfor(chunks, 1, [&](int64_t b, int64_t e) {
    for (int64_t c = b; c < e; ++c)
    {
      body(c * chunk, std::min(n, (c + 1) * chunk), parts[c]);
    }
  });
  std::vector<int64_t> start(chunks + 1, 0);
  for (int64_t c = 0; c < chunks; ++c)
  {
    start[c + 1] = start[c] + static_cast<int64_t>(parts[c].size());
  }
  std::vector<T> all(static_cast<size_t>(start[chunks]));
  pfor(chunks, 1, [&](int64_t b, int64_t e) {
    for (int64_t c = b; c < e; ++c)
    {
      std::copy(parts[c].begin(), parts[c].end(), all.begin() + start[c]);
      std::vector<T>().swap(parts[c]);
    }
  });
  return all;
}

/// Index of `key` in sorted `keys`, or -1.
inline int64_t FindKey(const std::vector<uint64_t>& keys, uint64_t key)
{
  auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return (it != keys.end() && *it == key) ? (it - keys.begin()) : -1;
}

/// Start of each run of equal point keys (the occupied cells of a cloud), and their keys.
void PointCells(const Prepared& P, std::vector<uint64_t>& cellKeys, std::vector<int64_t>& cellStart)
{
  for (int64_t i = 0; i < P.NumberOfPoints; ++i)
  {
    if (i == 0 || P.Key[i] != P.Key[i - 1])
    {
      cellKeys.push_back(P.Key[i]);
      cellStart.push_back(i);
    }
  }
  cellStart.push_back(P.NumberOfPoints);
}

/// Calls `visit(pointIndex)` for the points of the cells (c + d), d in {dlo..dhi}^3.
template <typename Visit>
void ForNeighbours(const std::vector<uint64_t>& cellKeys, const std::vector<int64_t>& cellStart,
  const int64_t c[3], int dlo, int dhi, uint32_t cells, Visit visit)
{
  for (int dz = dlo; dz <= dhi; ++dz)
    for (int dy = dlo; dy <= dhi; ++dy)
      for (int dx = dlo; dx <= dhi; ++dx)
      {
        const int64_t x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
        if (x < 0 || y < 0 || z < 0 || x >= cells || y >= cells || z >= cells)
        {
          continue;
        }
        const int64_t ci =
          FindKey(cellKeys, MortonEncode(uint32_t(x), uint32_t(y), uint32_t(z)));
        if (ci >= 0)
        {
          for (int64_t s = cellStart[ci]; s < cellStart[ci + 1]; ++s)
          {
            visit(s);
          }
        }
      }
}

/// Normals of a point cloud by PCA over the points within one cell edge, oriented towards
/// `target(i)` (a direction in grid units).
template <typename Target>
void EstimateNormals(Prepared& P, uint32_t cells, const std::vector<uint64_t>& cellKeys,
  const std::vector<int64_t>& cellStart, const ParallelFor& pfor, Target target)
{
  P.Normal.assign(3 * P.NumberOfPoints, 0.0f);
  pfor(P.NumberOfPoints, 2048, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      const double* x = &P.U[3 * i];
      uint32_t c[3];
      MortonDecode(P.Key[i], c);
      const int64_t ci[3] = { c[0], c[1], c[2] };
      Eigen::Vector3d mean(0, 0, 0);
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      int count = 0;
      ForNeighbours(cellKeys, cellStart, ci, -1, 1, cells, [&](int64_t s) {
        const double* y = &P.U[3 * s];
        const Eigen::Vector3d d(y[0] - x[0], y[1] - x[1], y[2] - x[2]);
        if (d.squaredNorm() <= 1.0)
        {
          mean += d;
          cov += d * d.transpose();
          ++count;
        }
      });
      double t[3];
      target(i, t);
      Eigen::Vector3d nrm(t[0], t[1], t[2]);
      if (count >= 3)
      {
        mean /= count;
        cov = cov / count - mean * mean.transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
        eig.computeDirect(cov);
        nrm = eig.eigenvectors().col(0);
      }
      nrm = nrm.norm() > 0 ? nrm.normalized() : Eigen::Vector3d(0, 0, 1);
      if (nrm[0] * t[0] + nrm[1] * t[1] + nrm[2] * t[2] < 0)
      {
        nrm = -nrm;
      }
      for (int a = 0; a < 3; ++a)
      {
        P.Normal[3 * i + a] = static_cast<float>(nrm[a]);
      }
    }
  });
}

/// Crossings of a point cloud: signed distance to the oriented samples at the corners of the
/// occupied cells (Gaussian-weighted tangent planes of the points in the 8 cells around each
/// corner, Hoppe et al. 1992), and a crossing on every finest edge whose two known corners
/// differ in sign.
std::vector<CrossingRecord> CloudCrossings(const Prepared& P, uint32_t cells,
  const std::vector<uint64_t>& cellKeys, const std::vector<int64_t>& cellStart,
  const ParallelFor& pfor)
{
  std::vector<Item> corners;
  corners.reserve(cellKeys.size() * 8);
  for (uint64_t key : cellKeys)
  {
    uint32_t c[3];
    MortonDecode(key, c);
    for (int k = 0; k < 8; ++k)
    {
      const uint32_t x = c[0] + (k & 1), y = c[1] + ((k >> 1) & 1), z = c[2] + ((k >> 2) & 1);
      if (x < cells && y < cells && z < cells)
      {
        corners.push_back({ MortonEncode(x, y, z), 0 });
      }
    }
  }
  int bits = 0;
  while ((uint64_t(1) << bits) < cells)
  {
    ++bits;
  }
  RadixSort(corners, 3 * bits, pfor);
  std::vector<uint64_t> cornerKeys;
  for (const Item& it : corners)
  {
    if (cornerKeys.empty() || cornerKeys.back() != it.Key)
    {
      cornerKeys.push_back(it.Key);
    }
  }
  std::vector<Item>().swap(corners);

  // signed distance at each corner, and the nearest point (heaviest weight) as its source
  struct CornerValue
  {
    double F;
    int64_t Source; // -1: no point near this corner
  };
  std::vector<CornerValue> values(cornerKeys.size());
  pfor(static_cast<int64_t>(cornerKeys.size()), 1024, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      uint32_t c[3];
      MortonDecode(cornerKeys[i], c);
      const int64_t ci[3] = { c[0], c[1], c[2] };
      double sw = 0, sf = 0, best = -1;
      int64_t source = -1;
      ForNeighbours(cellKeys, cellStart, ci, -1, 0, cells, [&](int64_t s) {
        const double* y = &P.U[3 * s];
        const double d[3] = { c[0] - y[0], c[1] - y[1], c[2] - y[2] };
        const double w = std::exp(-(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        const float* nn = &P.Normal[3 * s];
        if (P.NormalWeight[s] > 0)
        {
          sf += w * (nn[0] * d[0] + nn[1] * d[1] + nn[2] * d[2]);
          sw += w;
        }
        if (w > best)
        {
          best = w;
          source = s;
        }
      });
      values[i] = { sw > 0 ? sf / sw : 0.0, sw > 0 ? source : -1 };
    }
  });

  return ChunkedGather<CrossingRecord>(static_cast<int64_t>(cornerKeys.size()), 4096, pfor,
    [&](int64_t b, int64_t e, std::vector<CrossingRecord>& out) {
      for (int64_t i = b; i < e; ++i)
      {
        const CornerValue& v0 = values[i];
        if (v0.Source < 0)
        {
          continue;
        }
        uint32_t c[3];
        MortonDecode(cornerKeys[i], c);
        for (int a = 0; a < 3; ++a)
        {
          const int p = (a + 1) % 3, q = (a + 2) % 3;
          if (c[p] == 0 || c[q] == 0 || c[a] + 1 >= cells)
          {
            continue; // edges on the root boundary are never crossed
          }
          uint32_t d[3] = { c[0], c[1], c[2] };
          ++d[a];
          const int64_t j = FindKey(cornerKeys, MortonEncode(d[0], d[1], d[2]));
          if (j < 0 || values[j].Source < 0)
          {
            continue;
          }
          const CornerValue& v1 = values[j];
          const bool in0 = v0.F < 0, in1 = v1.F < 0;
          if (in0 == in1)
          {
            continue;
          }
          const double t = std::min(1.0 - 1e-7, std::max(0.0, v0.F / (v0.F - v1.F)));
          out.push_back(
            { cornerKeys[i], Crossing::Make(t, a, in0 ? 1 : -1, t < 0.5 ? v0.Source : v1.Source) });
        }
      }
    });
}

/// Unit normal and clipped area weight of every triangle, then the normal cone of every vertex
/// over its triangles (area-weighted axis, largest angle to it).
void MeshFrames(Prepared& P, bool quadrics, const ParallelFor& pfor)
{
  const int64_t nt = static_cast<int64_t>(P.Tri.size() / 3);
  P.TriNormal.assign(3 * nt, 0.0f);
  P.TriWeight.assign(nt, 0.0f);
  pfor(nt, 8192, [&](int64_t b, int64_t e) {
    for (int64_t t = b; t < e; ++t)
    {
      const int64_t* tri = &P.Tri[3 * t];
      const double* a = &P.U[3 * tri[0]];
      const double* bb = &P.U[3 * tri[1]];
      const double* c = &P.U[3 * tri[2]];
      const double e1[3] = { bb[0] - a[0], bb[1] - a[1], bb[2] - a[2] };
      const double e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      const double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0] };
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len > 0 && std::isfinite(len))
      {
        for (int i = 0; i < 3; ++i)
        {
          P.TriNormal[3 * t + i] = static_cast<float>(n[i] / len);
        }
        P.TriWeight[t] = static_cast<float>(std::min(0.5 * len, 1.0));
      }
    }
  });
  // vertex cones (sequential scatter: triangles are in Morton order, so this stays local)
  const int64_t np = P.NumberOfPoints;
  std::vector<double> sum(3 * np, 0.0);
  P.NormalWeight.assign(np, 0.0f);
  if (quadrics)
  {
    P.VertexQuadric.assign(np, Quadric());
  }
  for (int64_t t = 0; t < nt; ++t)
  {
    const float w = P.TriWeight[t];
    if (w <= 0)
    {
      continue;
    }
    const double n[3] = { P.TriNormal[3 * t], P.TriNormal[3 * t + 1], P.TriNormal[3 * t + 2] };
    for (int k = 0; k < 3; ++k)
    {
      const int64_t v = P.Tri[3 * t + k];
      for (int i = 0; i < 3; ++i)
      {
        sum[3 * v + i] += w * n[i];
      }
      P.NormalWeight[v] += w;
      if (quadrics)
      {
        P.VertexQuadric[v].AddPlane(n, &P.U[3 * v], w);
      }
    }
  }
  P.Normal.assign(3 * np, 0.0f);
  P.NormalAngle.assign(np, 0.0f);
  for (int64_t v = 0; v < np; ++v)
  {
    const double* s = &sum[3 * v];
    const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (len > 1e-9 * P.NormalWeight[v])
    {
      for (int i = 0; i < 3; ++i)
      {
        P.Normal[3 * v + i] = static_cast<float>(s[i] / len);
      }
    }
    else if (P.NormalWeight[v] > 0)
    {
      P.Normal[3 * v + 2] = 1.0f; // opposite normals cancel: any axis, angle pi
      P.NormalAngle[v] = static_cast<float>(Pi);
    }
  }
  std::vector<double> key(np, 0.0); // AngleKey of the widest triangle normal at each vertex
  for (int64_t t = 0; t < nt; ++t)
  {
    if (P.TriWeight[t] <= 0)
    {
      continue;
    }
    const double n[3] = { P.TriNormal[3 * t], P.TriNormal[3 * t + 1], P.TriNormal[3 * t + 2] };
    for (int k = 0; k < 3; ++k)
    {
      const int64_t v = P.Tri[3 * t + k];
      const double a[3] = { P.Normal[3 * v], P.Normal[3 * v + 1], P.Normal[3 * v + 2] };
      key[v] = std::max(key[v], AngleKey(a, n));
    }
  }
  for (int64_t v = 0; v < np; ++v)
  {
    if (P.NormalAngle[v] == 0.0f)
    {
      // never exactly 0 for a vertex with two non-parallel triangles: flat stays flat
      P.NormalAngle[v] = key[v] > 0 ? static_cast<float>(AngleFromKey(key[v])) : 0.0f;
    }
  }
}

double MedianEdgeLength(const BuildInput& in)
{
  std::vector<double> lengths;
  const int64_t step = std::max<int64_t>(1, in.NumberOfTriangles / 20000);
  for (int64_t t = 0; t < in.NumberOfTriangles; t += step)
  {
    const int64_t* tri = in.Triangles + 3 * t;
    for (int k = 0; k < 3; ++k)
    {
      const double* a = in.Points + 3 * tri[k];
      const double* b = in.Points + 3 * tri[(k + 1) % 3];
      const double d = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
        (a[2] - b[2]) * (a[2] - b[2]));
      if (d > 0)
      {
        lengths.push_back(d);
      }
    }
  }
  if (lengths.empty())
  {
    return 0;
  }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return lengths[lengths.size() / 2];
}

bool IsCloud(const BuildInput& in)
{
  return in.Triangles == nullptr || in.NumberOfTriangles == 0;
}

/// Morton order of the used points and of the triangles (by centroid), in grid units.
void Prepare(const BuildInput& in, const std::vector<char>& used, const double origin[3],
  double h, uint32_t cells, int level, const ParallelFor& pfor, Prepared& P)
{
  const bool cloud = IsCloud(in);
  std::vector<Item> order;
  order.reserve(in.NumberOfPoints);
  for (int64_t i = 0; i < in.NumberOfPoints; ++i)
  {
    if (used[i])
    {
      const double* x = in.Points + 3 * i;
      order.push_back({ MortonEncode(ClampCell((x[0] - origin[0]) / h, cells),
                          ClampCell((x[1] - origin[1]) / h, cells),
                          ClampCell((x[2] - origin[2]) / h, cells)),
        uint64_t(i) });
    }
  }
  RadixSort(order, 3 * level, pfor);
  const int64_t np = static_cast<int64_t>(order.size());
  P.NumberOfPoints = np;
  P.U.resize(3 * np);
  P.Key.resize(np);
  std::vector<int64_t> rank(cloud ? 0 : in.NumberOfPoints, -1);
  P.Source.resize(cloud ? np : 0);
  pfor(np, 16384, [&](int64_t b, int64_t e) {
    for (int64_t r = b; r < e; ++r)
    {
      const int64_t i = static_cast<int64_t>(order[r].Ref);
      for (int a = 0; a < 3; ++a)
      {
        P.U[3 * r + a] = (in.Points[3 * i + a] - origin[a]) / h;
      }
      P.Key[r] = order[r].Key;
      if (cloud)
      {
        P.Source[r] = i;
      }
      else
      {
        rank[i] = r;
      }
    }
  });
  auto permute = [&](const float* src, int comps, std::vector<float>& dst) {
    if (!src)
    {
      return;
    }
    dst.resize(comps * np);
    for (int64_t r = 0; r < np; ++r)
    {
      for (int c = 0; c < comps; ++c)
      {
        dst[comps * r + c] = src[comps * order[r].Ref + c];
      }
    }
  };
  permute(in.PointDiffuse, 1, P.PointDiffuse);
  permute(in.PointSpecular, 1, P.PointSpecular);
  if (cloud && in.PointNormals)
  {
    permute(in.PointNormals, 3, P.Normal);
    for (int64_t r = 0; r < np; ++r)
    {
      float* n = &P.Normal[3 * r];
      const double l = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
      for (int a = 0; a < 3; ++a)
      {
        n[a] = (l > 0 && std::isfinite(l)) ? static_cast<float>(n[a] / l) : 0.0f;
      }
    }
  }
  if (cloud)
  {
    return;
  }
  // triangles by the Morton key of their centroid
  const int64_t nt = in.NumberOfTriangles;
  std::vector<Item> tris(nt);
  pfor(nt, 16384, [&](int64_t b, int64_t e) {
    for (int64_t t = b; t < e; ++t)
    {
      double c[3] = { 0, 0, 0 };
      for (int k = 0; k < 3; ++k)
      {
        const double* u = &P.U[3 * rank[in.Triangles[3 * t + k]]];
        for (int a = 0; a < 3; ++a)
        {
          c[a] += u[a] / 3.0;
        }
      }
      tris[t] = { MortonEncode(ClampCell(c[0], cells), ClampCell(c[1], cells),
                    ClampCell(c[2], cells)),
        uint64_t(t) };
    }
  });
  RadixSort(tris, 3 * level, pfor);
  P.Tri.resize(3 * nt);
  if (in.TriangleDiffuse)
  {
    P.TriDiffuse.resize(nt);
  }
  if (in.TriangleSpecular)
  {
    P.TriSpecular.resize(nt);
  }
  pfor(nt, 16384, [&](int64_t b, int64_t e) {
    for (int64_t t = b; t < e; ++t)
    {
      const int64_t src = static_cast<int64_t>(tris[t].Ref);
      for (int k = 0; k < 3; ++k)
      {
        P.Tri[3 * t + k] = rank[in.Triangles[3 * src + k]];
      }
      if (in.TriangleDiffuse)
      {
        P.TriDiffuse[t] = in.TriangleDiffuse[src];
      }
      if (in.TriangleSpecular)
      {
        P.TriSpecular[t] = in.TriangleSpecular[src];
      }
    }
  });
}

} // namespace

double EstimateBuildMemory(const BuildInput& in, double rootEdge, int level)
{
  const double h = rootEdge / std::ldexp(1.0, level);
  double crossings = 0, cells = 0;
  if (IsCloud(in))
  {
    cells = std::min(double(in.NumberOfPoints), std::pow(8.0, level));
    crossings = 3 * cells;
  }
  else
  {
    // Expected number of grid lines through each triangle: |area vector component| / h^2.
    const int64_t step = std::max<int64_t>(1, in.NumberOfTriangles / 20000);
    double sampled = 0;
    int64_t count = 0;
    for (int64_t t = 0; t < in.NumberOfTriangles; t += step, ++count)
    {
      const int64_t* tri = in.Triangles + 3 * t;
      const double* a = in.Points + 3 * tri[0];
      const double* b = in.Points + 3 * tri[1];
      const double* c = in.Points + 3 * tri[2];
      const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
      const double e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      sampled += 0.5 *
        (std::abs(e1[1] * e2[2] - e1[2] * e2[1]) + std::abs(e1[2] * e2[0] - e1[0] * e2[2]) +
          std::abs(e1[0] * e2[1] - e1[1] * e2[0]));
    }
    crossings = count ? sampled / count * in.NumberOfTriangles / (h * h) : 0;
    cells = crossings + in.NumberOfPoints;
  }
  const double items = in.NumberOfPoints + 4 * crossings;
  const double nodes = cells * 4.0 / 3.0;
  return items * 2 * sizeof(Item) + crossings * sizeof(Crossing) +
    nodes * (62 + sizeof(PointSums) + sizeof(EdgeSums) + 24 + sizeof(Quadric)) +
    in.NumberOfPoints * 64.0 + in.NumberOfTriangles * 56.0;
}

int ChooseFinestLevel(
  const BuildInput& in, const double origin[3], double rootEdge, double memoryLimit)
{
  int level = 0;
  if (IsCloud(in))
  {
    const int64_t n = in.NumberOfPoints;
    std::vector<uint64_t> keys(n);
    const double scale = std::ldexp(1.0, MaxFinestLevel) / rootEdge;
    const uint32_t cells = 1u << MaxFinestLevel;
    for (int64_t i = 0; i < n; ++i)
    {
      const double* x = in.Points + 3 * i;
      keys[i] = MortonEncode(ClampCell((x[0] - origin[0]) * scale, cells),
        ClampCell((x[1] - origin[1]) * scale, cells), ClampCell((x[2] - origin[2]) * scale, cells));
    }
    std::sort(keys.begin(), keys.end());
    for (int l = 1; l <= MaxFinestLevel; ++l)
    {
      const int shift = 3 * (MaxFinestLevel - l);
      int64_t occupied = 0;
      uint64_t last = ~uint64_t(0);
      for (uint64_t k : keys)
      {
        if ((k >> shift) != last)
        {
          ++occupied;
          last = k >> shift;
        }
      }
      if (occupied == 0 || double(n) / double(occupied) < 4.0)
      {
        break;
      }
      level = l;
    }
  }
  else
  {
    const double e = MedianEdgeLength(in);
    level = e > 0 ? static_cast<int>(std::lround(std::log2(rootEdge / e))) : 0;
  }
  level = std::max(0, std::min(MaxFinestLevel, level));
  while (level > 0 && EstimateBuildMemory(in, rootEdge, level) > memoryLimit)
  {
    --level;
  }
  return level;
}

BuildResult BuildOctree(const BuildInput& in, const BuildParameters& params,
  const Allocator& allocate, const ParallelFor& pfor, const ProgressCallback& progress)
{
  BuildResult result;
  // PLOD_BUILD_TIMING=1 prints the time of each phase to stderr (for profiling).
  static const bool timing = std::getenv("PLOD_BUILD_TIMING") != nullptr;
  auto clock = std::chrono::steady_clock::now();
  auto report = [&](double f, const char* phase) {
    if (timing)
    {
      const auto now = std::chrono::steady_clock::now();
      std::fprintf(stderr, "plod build: %-12s %8.1f ms\n", phase,
        std::chrono::duration<double, std::milli>(now - clock).count());
      clock = now;
    }
    if (progress && !progress(f))
    {
      result.Aborted = true;
      result.Error = "build aborted";
      return false;
    }
    return true;
  };
  const bool cloud = IsCloud(in);

  // ---- validation and root cube -------------------------------------------------------------
  if (in.NumberOfPoints <= 0 || !in.Points)
  {
    result.Error = "input has no points";
    return result;
  }
  std::vector<char> used(in.NumberOfPoints, cloud ? 1 : 0);
  if (!cloud)
  {
    for (int64_t i = 0; i < 3 * in.NumberOfTriangles; ++i)
    {
      const int64_t id = in.Triangles[i];
      if (id < 0 || id >= in.NumberOfPoints)
      {
        result.Error = "triangle " + std::to_string(i / 3) + " refers to point " +
          std::to_string(id) + ", outside [0, " + std::to_string(in.NumberOfPoints) + ")";
        return result;
      }
      used[id] = 1;
    }
  }
  double lo[3] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  double hi[3] = { -lo[0], -lo[1], -lo[2] };
  int64_t bad = 0, usedCount = 0;
  for (int64_t i = 0; i < in.NumberOfPoints; ++i)
  {
    if (!used[i])
    {
      continue;
    }
    const double* x = in.Points + 3 * i;
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      ++bad;
      continue;
    }
    ++usedCount;
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], x[a]);
      hi[a] = std::max(hi[a], x[a]);
    }
  }
  if (bad)
  {
    result.Error = std::to_string(bad) + " point(s) have NaN or infinite coordinates";
    return result;
  }
  if (usedCount == 0)
  {
    result.Error = "no point is used by a triangle";
    return result;
  }
  double extent = std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] });
  const double far = std::max({ std::abs(lo[0]), std::abs(hi[0]), std::abs(lo[1]),
    std::abs(hi[1]), std::abs(lo[2]), std::abs(hi[2]) });
  if (!(extent > far * 1e-12) || !std::isfinite(extent))
  {
    // All points coincide (or the extent is below double resolution at that distance):
    // give the root a size that the coordinates can still resolve.
    extent = far > 0 ? far * 1e-6 : 1.0;
  }
  const double rootEdge = extent * (1.0 + 2.0 * RootMargin);
  double origin[3];
  for (int a = 0; a < 3; ++a)
  {
    // The bounds keep a margin of extent/32 minus the shift (< 1e-3 of the edge) on each side.
    origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * rootEdge - RootShift[a] * rootEdge;
  }
  std::copy(origin, origin + 3, result.Origin);
  result.RootEdge = rootEdge;

  // ---- finest level ------------------------------------------------------------------------
  int level = params.FinestLevel;
  if (level < 0)
  {
    level = ChooseFinestLevel(in, origin, rootEdge, params.MemoryLimit);
  }
  else if (level > MaxFinestLevel)
  {
    result.Error = "finest level " + std::to_string(level) + " is above the maximum " +
      std::to_string(MaxFinestLevel);
    return result;
  }
  else
  {
    const double need = EstimateBuildMemory(in, rootEdge, level);
    if (need > params.MemoryLimit)
    {
      result.Error = "finest level " + std::to_string(level) + " would need about " +
        std::to_string(static_cast<long long>(need / 1e6)) + " MB, above the memory limit of " +
        std::to_string(static_cast<long long>(params.MemoryLimit / 1e6)) +
        " MB; lower the finest level or raise the limit";
      return result;
    }
  }
  result.FinestLevel = level;
  const uint32_t cells = 1u << level;
  const double h = rootEdge / double(cells);
  if (!report(0.02, "validate"))
  {
    return result;
  }

  // ---- input in Morton order, normals, crossings ----------------------------------------------
  Prepared P;
  P.UniformDiffuse = in.UniformDiffuse;
  P.UniformSpecular = in.UniformSpecular;
  Prepare(in, used, origin, h, cells, level, pfor, P);
  std::vector<char>().swap(used);
  if (!report(0.1, "prepare"))
  {
    return result;
  }
  std::vector<CrossingRecord> crossings;
  if (cloud)
  {
    std::vector<uint64_t> cellKeys;
    std::vector<int64_t> cellStart;
    PointCells(P, cellKeys, cellStart);
    if (P.Normal.empty())
    {
      // orientation targets in grid units
      double centroid[3] = { 0, 0, 0 };
      for (int64_t i = 0; i < P.NumberOfPoints; ++i)
        for (int a = 0; a < 3; ++a)
          centroid[a] += P.U[3 * i + a] / double(P.NumberOfPoints);
      std::vector<double> viewpoints;
      if (in.PointViewpoints)
      {
        viewpoints.resize(3 * P.NumberOfPoints);
        for (int64_t r = 0; r < P.NumberOfPoints; ++r)
          for (int a = 0; a < 3; ++a)
            viewpoints[3 * r + a] = (in.PointViewpoints[3 * P.Source[r] + a] - origin[a]) / h;
      }
      double vp[3];
      for (int a = 0; a < 3; ++a)
        vp[a] = (in.Viewpoint[a] - origin[a]) / h;
      EstimateNormals(P, cells, cellKeys, cellStart, pfor, [&](int64_t i, double t[3]) {
        const double* x = &P.U[3 * i];
        for (int a = 0; a < 3; ++a)
        {
          t[a] = !viewpoints.empty() ? viewpoints[3 * i + a] - x[a]
            : in.HasViewpoint        ? vp[a] - x[a]
                                     : x[a] - centroid[a];
        }
      });
    }
    P.NormalAngle.assign(P.NumberOfPoints, 0.0f);
    P.NormalWeight.resize(P.NumberOfPoints);
    for (int64_t i = 0; i < P.NumberOfPoints; ++i)
    {
      const float* n = &P.Normal[3 * i];
      P.NormalWeight[i] = (n[0] != 0 || n[1] != 0 || n[2] != 0) ? 1.0f : 0.0f;
    }
    if (!report(0.2, "normals"))
    {
      return result;
    }
    if (P.NumberOfPoints > MaxCrossingSource)
    {
      result.Error = "too many points (" + std::to_string(P.NumberOfPoints) + ", at most " +
        std::to_string(MaxCrossingSource) + ")";
      return result;
    }
    crossings = CloudCrossings(P, cells, cellKeys, cellStart, pfor);
  }
  else
  {
    MeshFrames(P, params.Rule == VertexRule::QEF, pfor);
    if (!report(0.2, "frames"))
    {
      return result;
    }
    const int64_t nt = static_cast<int64_t>(P.Tri.size() / 3);
    if (nt > MaxCrossingSource)
    {
      result.Error = "too many triangles (" + std::to_string(nt) + ", at most " +
        std::to_string(MaxCrossingSource) + ")";
      return result;
    }
    crossings = ChunkedGather<CrossingRecord>(nt, 4096, pfor,
      [&](int64_t b, int64_t e, std::vector<CrossingRecord>& out) {
        for (int64_t t = b; t < e; ++t)
        {
          if (P.TriWeight[t] > 0)
          {
            TriangleCrossings(P, cells, t, out);
          }
        }
      });
    for (int64_t t = 0; t < nt; ++t)
    {
      result.NumberOfSkippedTriangles += P.TriWeight[t] > 0 ? 0 : 1;
    }
  }
  result.NumberOfCrossings = static_cast<int64_t>(crossings.size());
  if (!report(0.45, "crossings"))
  {
    return result;
  }

  // ---- samples sorted by finest cell ----------------------------------------------------------
  const int64_t np = P.NumberOfPoints;
  const int64_t nc = static_cast<int64_t>(crossings.size());
  std::vector<Item> items(np + 4 * nc);
  pfor(np, 65536, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      items[i] = { P.Key[i], (uint64_t(i) << 3) | PointFlag };
    }
  });
  pfor(nc, 16384, [&](int64_t b, int64_t e) {
    for (int64_t x = b; x < e; ++x)
    {
      const int a = crossings[x].C.Axis(), p = (a + 1) % 3, q = (a + 2) % 3;
      uint32_t corner[3];
      MortonDecode(crossings[x].Corner, corner);
      for (int slot = 0; slot < 4; ++slot)
      {
        uint32_t cc[3];
        cc[a] = corner[a];
        cc[p] = corner[p] - (slot & 1);
        cc[q] = corner[q] - ((slot >> 1) & 1);
        items[np + 4 * x + slot] = { MortonEncode(cc[0], cc[1], cc[2]), (uint64_t(x) << 3) | slot };
      }
    }
  });
  if (!report(0.5, "samples"))
  {
    return result;
  }
  RadixSort(items, 3 * level, pfor);
  if (!report(0.6, "sort"))
  {
    return result;
  }

  // ---- keys of every level and the tree structure --------------------------------------------
  std::vector<std::vector<uint64_t>> keys(level + 1);
  std::vector<int64_t> finestStart; // item range of each finest cell
  for (size_t i = 0; i < items.size(); ++i)
  {
    if (i == 0 || items[i].Key != items[i - 1].Key)
    {
      keys[level].push_back(items[i].Key);
      finestStart.push_back(static_cast<int64_t>(i));
    }
  }
  finestStart.push_back(static_cast<int64_t>(items.size()));
  for (int l = level - 1; l >= 0; --l)
  {
    for (uint64_t k : keys[l + 1])
    {
      if (keys[l].empty() || keys[l].back() != (k >> 3))
      {
        keys[l].push_back(k >> 3);
      }
    }
  }
  std::vector<int64_t> offset(level + 2, 0);
  for (int l = 0; l <= level; ++l)
  {
    offset[l + 1] = offset[l] + static_cast<int64_t>(keys[l].size());
  }
  const int64_t total = offset[level + 1];
  if (total > std::numeric_limits<int32_t>::max())
  {
    result.Error = "too many nodes for 32-bit node indices";
    return result;
  }
  OctreeArrays out = allocate(total);
  result.NumberOfNodes = total;
  for (int l = 0; l <= level; ++l)
  {
    const int64_t n = static_cast<int64_t>(keys[l].size());
    std::fill(out.Level + offset[l], out.Level + offset[l] + n, static_cast<uint8_t>(l));
    std::fill(out.FirstChild + offset[l], out.FirstChild + offset[l] + n, -1);
    std::fill(out.ChildMask + offset[l], out.ChildMask + offset[l] + n, 0);
    if (l == 0)
    {
      out.Parent[0] = -1;
      continue;
    }
    int64_t parent = -1;
    uint64_t parentKey = ~uint64_t(0);
    for (int64_t i = 0; i < n; ++i)
    {
      const uint64_t k = keys[l][i];
      if ((k >> 3) != parentKey)
      {
        parentKey = k >> 3;
        ++parent;
        out.FirstChild[offset[l - 1] + parent] = static_cast<int32_t>(offset[l] + i);
      }
      out.Parent[offset[l] + i] = static_cast<int32_t>(offset[l - 1] + parent);
      out.ChildMask[offset[l - 1] + parent] |= static_cast<uint8_t>(1u << (k & 7));
    }
  }
  if (!report(0.62, "structure"))
  {
    return result;
  }

  // ---- finest cells ------------------------------------------------------------------------
  std::vector<PointSums> pointSums(total);
  std::vector<double> vertex(3 * total); // finest grid units, for the shape error
  std::vector<Quadric> quadrics(params.Rule == VertexRule::QEF ? total : 0);
  // crossings on the edges of the nodes one level above the one being computed
  std::vector<EdgeSums> levelEdges(level > 0 ? keys[level - 1].size() : 0);
  const int64_t nFinest = static_cast<int64_t>(keys[level].size());
  // vertex of a node from its sums (mean rule, or QEF about that mean), clamped for QEF
  auto placeVertex = [&](int64_t node, const double mean[3], const uint32_t cc[3], double size) {
    double* x = &vertex[3 * node];
    if (quadrics.empty())
    {
      std::copy(mean, mean + 3, x);
      return;
    }
    quadrics[node].Solve(mean, x);
    for (int k = 0; k < 3; ++k)
    {
      x[k] = std::min(std::max(x[k], cc[k] * size), (cc[k] + 1.0) * size);
    }
  };
  // mean of the node's input points and of the crossings on its edges
  auto meanOf = [&](const PointSums& ps, const EdgeSums& es, const uint32_t cc[3], double size,
                  double mean[3]) -> bool {
    double sum[3] = { ps.Sum[0], ps.Sum[1], ps.Sum[2] };
    double count = ps.Count;
    for (int e = 0; e < 12; ++e)
    {
      if (!es.Count[e])
      {
        continue;
      }
      const int a = e / 4, p = (a + 1) % 3, q = (a + 2) % 3;
      const double n = es.Count[e];
      sum[a] += n * cc[a] * size + es.Offset[e];
      sum[p] += n * (cc[p] + (e & 1)) * size;
      sum[q] += n * (cc[q] + ((e >> 1) & 1)) * size;
      count += n;
    }
    if (count == 0)
    {
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      mean[k] = sum[k] / count;
    }
    return true;
  };
  // normal, own cone angle and weight of a sample
  auto normalOf = [&](uint64_t ref, double n[3], double& angle, double& w) {
    const int64_t i =
      (ref & PointFlag) ? static_cast<int64_t>(ref >> 3) : crossings[ref >> 3].C.Source();
    if (ref & PointFlag || cloud)
    {
      for (int k = 0; k < 3; ++k)
        n[k] = P.Normal[3 * i + k];
      angle = (ref & PointFlag) ? P.NormalAngle[i] : 0.0;
      w = (ref & PointFlag) ? P.NormalWeight[i] : CrossingWeight * P.NormalWeight[i];
    }
    else
    {
      for (int k = 0; k < 3; ++k)
        n[k] = P.TriNormal[3 * i + k];
      angle = 0;
      w = CrossingWeight;
    }
  };
  // material bounds of a sample: its point's values, or for a crossing the values of its
  // triangle (cell data) or of its triangle's three vertices (point data), or of its point
  auto materialOf = [&](uint64_t ref, float& dmin, float& dmax, float& smin, float& smax) {
    auto take = [](float v, float& lo, float& hi) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    };
    if ((ref & PointFlag) || cloud)
    {
      const int64_t i =
        (ref & PointFlag) ? static_cast<int64_t>(ref >> 3) : crossings[ref >> 3].C.Source();
      take(ValueOr(P.PointDiffuse, i, P.UniformDiffuse), dmin, dmax);
      take(ValueOr(P.PointSpecular, i, P.UniformSpecular), smin, smax);
      return;
    }
    const int64_t t = crossings[ref >> 3].C.Source();
    for (int k = 0; k < 3; ++k)
    {
      const int64_t v = P.Tri[3 * t + k];
      take(!P.TriDiffuse.empty() ? P.TriDiffuse[t] : ValueOr(P.PointDiffuse, v, P.UniformDiffuse),
        dmin, dmax);
      take(!P.TriSpecular.empty() ? P.TriSpecular[t]
                                  : ValueOr(P.PointSpecular, v, P.UniformSpecular),
        smin, smax);
    }
  };
  const bool material = P.HasMaterial();
  // One task per parent, so that the parent's edge sums are written by one thread.
  const int64_t nGroups = level > 0 ? static_cast<int64_t>(keys[level - 1].size()) : 1;
  pfor(nGroups, 256, [&](int64_t gb, int64_t ge) {
    for (int64_t g = gb; g < ge; ++g)
    {
      const int64_t c0 = level > 0 ? out.FirstChild[offset[level - 1] + g] - offset[level] : 0;
      const int64_t c1 =
        level > 0 ? c0 + __builtin_popcount(out.ChildMask[offset[level - 1] + g]) : 1;
      for (int64_t ci = c0; ci < c1; ++ci)
      {
        const int64_t node = offset[level] + ci;
        const int childIndex = static_cast<int>(keys[level][ci] & 7);
        PointSums& ps = pointSums[node];
        EdgeSums es;
        uint32_t cc[3];
        MortonDecode(keys[level][ci], cc);
        double nsum[3] = { 0, 0, 0 }, wsum = 0;
        float dmin = std::numeric_limits<float>::max(), dmax = -dmin, smin = dmin, smax = -dmin;
        int net[12] = { 0 };
        Quadric* Q = quadrics.empty() ? nullptr : &quadrics[node];
        for (int64_t s = finestStart[ci]; s < finestStart[ci + 1]; ++s)
        {
          const uint64_t ref = items[s].Ref;
          double at[3];
          if (ref & PointFlag)
          {
            const int64_t i = static_cast<int64_t>(ref >> 3);
            for (int k = 0; k < 3; ++k)
            {
              at[k] = P.U[3 * i + k];
              ps.Sum[k] += at[k];
            }
            ++ps.Count;
          }
          else
          {
            const Crossing& c = crossings[ref >> 3].C;
            const int slot = static_cast<int>(ref & 3), a = c.Axis();
            const int p = (a + 1) % 3, q = (a + 2) % 3;
            const int pb = slot & 1, qb = (slot >> 1) & 1;
            const int edge = EdgeIndex(a, pb, qb);
            at[a] = cc[a] + c.T;
            at[p] = cc[p] + pb;
            at[q] = cc[q] + qb;
            net[edge] += c.Sign();
            es.Offset[edge] += c.T;
            ++es.Count[edge];
            if (level > 0 && ((childIndex >> p) & 1) == pb && ((childIndex >> q) & 1) == qb)
            {
              // this edge of the cell lies on the same edge of its parent
              EdgeSums& pe = levelEdges[g];
              pe.Offset[edge] += c.T + float((childIndex >> a) & 1);
              ++pe.Count[edge];
            }
          }
          if (material)
          {
            materialOf(ref, dmin, dmax, smin, smax);
          }
          double n[3], angle, w;
          normalOf(ref, n, angle, w);
          if (w > 0)
          {
            for (int k = 0; k < 3; ++k)
              nsum[k] += w * n[k];
            wsum += w;
            if (Q && (ref & PointFlag) && !P.VertexQuadric.empty())
              Q->Add(P.VertexQuadric[ref >> 3]); // the planes of the vertex's triangles
            else if (Q)
              Q->AddPlane(n, at, w);
          }
        }
        // vertex
        double mean[3];
        if (!meanOf(ps, es, cc, 1.0, mean))
        {
          for (int k = 0; k < 3; ++k)
            mean[k] = cc[k] + 0.5; // unreachable: a cell exists because it has samples
        }
        placeVertex(node, mean, cc, 1.0);
        // cone: area-weighted axis; angle = max over samples of (angle to axis + own angle)
        const double len = std::sqrt(nsum[0] * nsum[0] + nsum[1] * nsum[1] + nsum[2] * nsum[2]);
        double axis[3] = { 0, 0, 1 };
        double theta = Pi;
        if (wsum > 0 && len > 1e-9 * wsum)
        {
          for (int k = 0; k < 3; ++k)
            axis[k] = nsum[k] / len;
          double flatKey = 0;
          theta = 0;
          for (int64_t s = finestStart[ci]; s < finestStart[ci + 1]; ++s)
          {
            double n[3], angle, w;
            normalOf(items[s].Ref, n, angle, w);
            if (w <= 0)
              continue;
            const double key = AngleKey(n, axis);
            if (angle > 0)
              theta = std::max(theta, AngleFromKey(key) + angle);
            else
              flatKey = std::max(flatKey, key);
          }
          theta = std::min(Pi, std::max(theta, AngleFromKey(flatKey)));
        }
        for (int k = 0; k < 3; ++k)
        {
          out.Vertex[3 * node + k] = static_cast<float>(vertex[3 * node + k] * h);
          out.ConeAxis[3 * node + k] = static_cast<float>(axis[k]);
        }
        out.ConeAngle[node] = static_cast<float>(theta);
        out.ShapeError[node] = 0.0f;
        if (!material)
        {
          dmin = dmax = P.UniformDiffuse;
          smin = smax = P.UniformSpecular;
        }
        out.Diffuse[2 * node] = dmin;
        out.Diffuse[2 * node + 1] = dmax;
        out.Specular[2 * node] = smin;
        out.Specular[2 * node + 1] = smax;
        uint32_t word = 0;
        for (int k = 0; k < 12; ++k)
        {
          word |= EncodeEdge(k, net[k]);
        }
        out.Edges[node] = word;
      }
    }
  });
  std::vector<Item>().swap(items);
  std::vector<CrossingRecord>().swap(crossings);
  if (!report(0.75, "finest cells"))
  {
    return result;
  }

  // ---- coarser levels ----------------------------------------------------------------------
  for (int l = level - 1; l >= 0; --l)
  {
    const double size = std::ldexp(1.0, level - l);     // cell edge in finest units
    const double half = 0.5 * size;                      // child edge
    // edge sums of level l: computed by the finest pass for l = level - 1, else from level l+1
    std::vector<EdgeSums> edges;
    const bool edgesDone = l == level - 1;
    if (edgesDone)
    {
      edges.swap(levelEdges);
    }
    else
    {
      edges.resize(keys[l].size());
    }
    pfor(static_cast<int64_t>(keys[l].size()), 1024, [&](int64_t b, int64_t e) {
      for (int64_t i = b; i < e; ++i)
      {
        const int64_t node = offset[l] + i;
        PointSums& ps = pointSums[node];
        EdgeSums& es = edges[i];
        const int32_t first = out.FirstChild[node];
        const unsigned mask = out.ChildMask[node];
        int32_t child[8];
        double nsum[3] = { 0, 0, 0 }, childMean[3] = { 0, 0, 0 };
        int nchild = 0;
        for (int c = 0, r = 0; c < 8; ++c)
        {
          child[c] = (mask & (1u << c)) ? first + r++ : -1;
          if (child[c] < 0)
            continue;
          const PointSums& cs = pointSums[child[c]];
          for (int k = 0; k < 3; ++k)
          {
            ps.Sum[k] += cs.Sum[k];
            nsum[k] += out.ConeAxis[3 * child[c] + k];
            childMean[k] += vertex[3 * child[c] + k];
          }
          ps.Count += cs.Count;
          if (!quadrics.empty())
            quadrics[node].Add(quadrics[child[c]]);
          ++nchild;
        }
        // edges: a coarse edge is its two halves, held by the children on that edge
        uint32_t word = 0;
        for (int a = 0; a < 3; ++a)
        {
          const int p = (a + 1) % 3, q = (a + 2) % 3;
          for (int pb = 0; pb < 2; ++pb)
            for (int qb = 0; qb < 2; ++qb)
            {
              const int edge = EdgeIndex(a, pb, qb);
              int net = 0;
              for (int ab = 0; ab < 2; ++ab)
              {
                const int c = (ab << a) | (pb << p) | (qb << q);
                if (child[c] < 0)
                  continue;
                net += EdgeSign(out.Edges[child[c]], edge);
                if (!edgesDone)
                {
                  const EdgeSums& ce = levelEdges[child[c] - offset[l + 1]];
                  es.Offset[edge] += ce.Offset[edge] + float(ab * half * ce.Count[edge]);
                  es.Count[edge] += ce.Count[edge];
                }
              }
              word |= EncodeEdge(edge, net);
            }
        }
        out.Edges[node] = word;
        // vertex
        uint32_t cc[3];
        MortonDecode(keys[l][i], cc);
        double mean[3];
        if (!meanOf(ps, es, cc, size, mean))
        {
          for (int k = 0; k < 3; ++k)
            mean[k] = childMean[k] / nchild;
        }
        placeVertex(node, mean, cc, size);
        // cone, SRCC eq. (1)-(2); a near-zero sum gives theta = pi
        const double len = std::sqrt(nsum[0] * nsum[0] + nsum[1] * nsum[1] + nsum[2] * nsum[2]);
        double axis[3] = { 0, 0, 1 };
        double theta = Pi;
        if (len > 1e-6)
        {
          theta = 0;
          for (int k = 0; k < 3; ++k)
            axis[k] = nsum[k] / len;
          for (int c = 0; c < 8; ++c)
          {
            if (child[c] < 0)
              continue;
            const float* cf = &out.ConeAxis[3 * child[c]];
            const double cn[3] = { cf[0], cf[1], cf[2] };
            theta = std::max(theta, AngleBetween(axis, cn) + double(out.ConeAngle[child[c]]));
          }
          theta = std::min(theta, Pi);
        }
        for (int k = 0; k < 3; ++k)
        {
          out.Vertex[3 * node + k] = static_cast<float>(vertex[3 * node + k] * h);
          out.ConeAxis[3 * node + k] = static_cast<float>(axis[k]);
        }
        out.ConeAngle[node] = static_cast<float>(theta);
        // material
        float dmin = std::numeric_limits<float>::max(), dmax = -dmin, smin = dmin, smax = -dmin;
        for (int c = 0; c < 8; ++c)
        {
          if (child[c] < 0)
            continue;
          dmin = std::min(dmin, out.Diffuse[2 * child[c]]);
          dmax = std::max(dmax, out.Diffuse[2 * child[c] + 1]);
          smin = std::min(smin, out.Specular[2 * child[c]]);
          smax = std::max(smax, out.Specular[2 * child[c] + 1]);
        }
        out.Diffuse[2 * node] = dmin;
        out.Diffuse[2 * node + 1] = dmax;
        out.Specular[2 * node] = smin;
        out.Specular[2 * node + 1] = smax;
      }
    });
    levelEdges.swap(edges);
  }
  if (!report(0.9, "coarse cells"))
  {
    return result;
  }

  // ---- shape error, SRCC eq. (3), over the finest descendants ------------------------------
  // The finest descendants of a node are a contiguous range of the finest level.
  const std::vector<uint64_t>& fk = keys[level];
  pfor(offset[level], 256, [&](int64_t b, int64_t e) {
    for (int64_t node = b; node < e; ++node)
    {
      const int l = out.Level[node];
      const int64_t i = node - offset[l];
      const int s = 3 * (level - l);
      const int64_t f0 = std::lower_bound(fk.begin(), fk.end(), keys[l][i] << s) - fk.begin();
      const int64_t f1 =
        std::lower_bound(fk.begin() + f0, fk.end(), (keys[l][i] + 1) << s) - fk.begin();
      const double n[3] = { out.ConeAxis[3 * node], out.ConeAxis[3 * node + 1],
        out.ConeAxis[3 * node + 2] };
      const double* v = &vertex[3 * node];
      double dmin = std::numeric_limits<double>::max(), dmax = -dmin;
      for (int64_t f = offset[level] + f0; f < offset[level] + f1; ++f)
      {
        const double* vc = &vertex[3 * f];
        const double d = n[0] * vc[0] + n[1] * vc[1] + n[2] * vc[2];
        dmin = std::min(dmin, d);
        dmax = std::max(dmax, d);
      }
      out.ShapeError[node] = dmax >= dmin ? static_cast<float>((dmax - dmin) * h) : 0.0f;
    }
  });
  if (cloud)
  {
    // A point cloud's surface is the one its patches draw: widen the finest cones so that they
    // contain the normals of the finest patches' triangles (estimated point normals are
    // smoother than that surface, and the back-face test must not hide what is drawn), then
    // redo SRCC eq. (2) upwards with the axes unchanged.
    OctreeView v;
    v.NumberOfNodes = total;
    v.FinestLevel = level;
    v.RootEdge = rootEdge;
    v.Level = out.Level;
    v.Parent = out.Parent;
    v.FirstChild = out.FirstChild;
    v.ChildMask = out.ChildMask;
    v.Vertex = out.Vertex;
    v.ConeAxis = out.ConeAxis;
    v.ConeAngle = out.ConeAngle;
    v.ShapeError = out.ShapeError;
    v.Diffuse = out.Diffuse;
    v.Specular = out.Specular;
    v.Edges = out.Edges;
    std::vector<uint8_t> cut(total);
    UniformCut(v, level, cut.data());
    PatchResult patches;
    GeneratePatches(v, cut.data(), patches);
    for (size_t t = 0; t + 2 < patches.Triangles.size(); t += 3)
    {
      const int64_t node[3] = { patches.PointNode[patches.Triangles[t]],
        patches.PointNode[patches.Triangles[t + 1]], patches.PointNode[patches.Triangles[t + 2]] };
      const float* a = &out.Vertex[3 * node[0]];
      const float* b = &out.Vertex[3 * node[1]];
      const float* c = &out.Vertex[3 * node[2]];
      const double u[3] = { double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2] };
      const double w[3] = { double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2] };
      double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0] };
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(len > 0))
        continue;
      for (double& x : n)
        x /= len;
      for (int64_t k : node)
      {
        const double axis[3] = { out.ConeAxis[3 * k], out.ConeAxis[3 * k + 1],
          out.ConeAxis[3 * k + 2] };
        out.ConeAngle[k] =
          std::max(out.ConeAngle[k], static_cast<float>(std::min(Pi, AngleBetween(axis, n))));
      }
    }
    for (int l = level - 1; l >= 0; --l)
    {
      for (int64_t node = offset[l]; node < offset[l + 1]; ++node)
      {
        if (out.ConeAngle[node] >= static_cast<float>(Pi))
          continue;
        const double axis[3] = { out.ConeAxis[3 * node], out.ConeAxis[3 * node + 1],
          out.ConeAxis[3 * node + 2] };
        double theta = out.ConeAngle[node];
        const int count = __builtin_popcount(out.ChildMask[node]);
        for (int c = 0; c < count; ++c)
        {
          const int64_t child = out.FirstChild[node] + c;
          const double cn[3] = { out.ConeAxis[3 * child], out.ConeAxis[3 * child + 1],
            out.ConeAxis[3 * child + 2] };
          theta = std::max(theta, AngleBetween(axis, cn) + double(out.ConeAngle[child]));
        }
        out.ConeAngle[node] = static_cast<float>(std::min(theta, Pi));
      }
    }
  }
  report(1.0, "shape error");
  result.Ok = true;
  return result;
}

} // namespace plod
