// SPDX-License-Identifier: BSD-3-Clause
#include "plodOctreeBuilder.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
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

/// A sample reference sorted by the Morton key of the finest cell it belongs to.
struct Item
{
  uint64_t Key;
  uint64_t Ref; // (index << 4) | (slot << 2) | type
};
enum : uint64_t
{
  PointSample = 0, // an input point inside the cell
  TouchSample = 1, // a triangle with a vertex inside the cell (normal, quadric, material)
  CrossSample = 2  // a crossing on one of the cell's edges; slot = which of the 4 cells
};
inline uint64_t MakeRef(uint64_t index, uint64_t slot, uint64_t type)
{
  return (index << 4) | (slot << 2) | type;
}

/// A point where the surface crosses a finest grid edge.
struct Crossing
{
  double Pos[3];      // finest grid units
  uint32_t Corner[3]; // grid corner where the edge starts
  float Normal[3];    // unit surface normal at the crossing
  float Diffuse;
  float Specular;
  int8_t Axis;
  int8_t Sign; // +1: normal towards +axis
};

/// Quadric of planes: sum of w * (n.x - d)^2 as (A, b, c) with A symmetric.
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
    Eigen::Vector3d m(mass[0], mass[1], mass[2]);
    Eigen::Vector3d r = Eigen::Vector3d(B[0], B[1], B[2]) - a * m;
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

/// Per-node accumulators used during the build only.
struct NodeAccum
{
  double SumPoints[3] = { 0, 0, 0 }; // input points inside the cell
  double SumCross[3] = { 0, 0, 0 };  // crossings on the cell's own edges
  uint32_t CountPoints = 0;
  uint32_t CountCross = 0;
  double Vertex[3] = { 0, 0, 0 }; // finest grid units, double for the shape error
};

/// Stable LSD radix sort of items by key, `bits` significant key bits.
void RadixSort(std::vector<Item>& items, int bits)
{
  constexpr int Digit = 11;
  constexpr size_t Buckets = size_t(1) << Digit;
  std::vector<Item> tmp(items.size());
  std::vector<size_t> count(Buckets);
  for (int shift = 0; shift < bits; shift += Digit)
  {
    std::fill(count.begin(), count.end(), 0);
    for (const Item& it : items)
    {
      ++count[(it.Key >> shift) & (Buckets - 1)];
    }
    size_t sum = 0;
    for (size_t& c : count)
    {
      const size_t v = c;
      c = sum;
      sum += v;
    }
    for (const Item& it : items)
    {
      tmp[count[(it.Key >> shift) & (Buckets - 1)]++] = it;
    }
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

/// Edge function of the canonical directed edge, and its symbolic tie-break.
/// Returns the sign (+1/-1) of E(x, y) for the edge A->B with the query point perturbed by
/// (dp, dq), dp >> dq > 0; `value` receives E for barycentrics.
inline int EdgeSide(const double a[2], const double b[2], double x, double y, double& value)
{
  // Canonical order: lexicographic on (p, q), so both triangles sharing an edge compute the
  // same number with opposite signs.
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
    const double dq = -(t[1] - s[1]); // dE/dx
    const double dp = (t[0] - s[0]);  // dE/dy
    sign = dq != 0 ? (dq > 0 ? 1 : -1) : (dp > 0 ? 1 : (dp < 0 ? -1 : 0));
  }
  if (swap)
  {
    e = -e;
    sign = -sign;
  }
  value = e;
  return sign;
}

struct MeshContext
{
  const BuildInput* In;
  int Level;
  uint32_t Cells;
  std::vector<double> U;         // grid coordinates of points
  std::vector<float> TriNormal;  // unit normal per triangle
  std::vector<double> TriWeight; // min(area, 1) in grid units, 0 for degenerate
};

float PointValue(const float* arr, int64_t i, float uniform)
{
  return arr ? arr[i] : uniform;
}

/// Crossings of one triangle with the finest grid lines along the three axes.
void TriangleCrossings(const MeshContext& ctx, int64_t t, std::vector<Crossing>& out)
{
  const BuildInput& in = *ctx.In;
  const int64_t* tri = in.Triangles + 3 * t;
  const double* v[3] = { &ctx.U[3 * tri[0]], &ctx.U[3 * tri[1]], &ctx.U[3 * tri[2]] };
  const double cells = ctx.Cells;
  for (int a = 0; a < 3; ++a)
  {
    const int p = (a + 1) % 3, q = (a + 2) % 3;
    const double P[3][2] = { { v[0][p], v[0][q] }, { v[1][p], v[1][q] }, { v[2][p], v[2][q] } };
    const double area2 = (P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) -
      (P[1][1] - P[0][1]) * (P[2][0] - P[0][0]);
    if (area2 == 0 || !std::isfinite(area2))
    {
      continue;
    }
    const double pmin = std::min({ P[0][0], P[1][0], P[2][0] });
    const double pmax = std::max({ P[0][0], P[1][0], P[2][0] });
    const double qmin = std::min({ P[0][1], P[1][1], P[2][1] });
    const double qmax = std::max({ P[0][1], P[1][1], P[2][1] });
    const int64_t j0 = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(pmin)));
    const int64_t j1 = std::min<int64_t>(ctx.Cells - 1, static_cast<int64_t>(std::floor(pmax)));
    const int64_t k0 = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(qmin)));
    const int64_t k1 = std::min<int64_t>(ctx.Cells - 1, static_cast<int64_t>(std::floor(qmax)));
    for (int64_t j = j0; j <= j1; ++j)
    {
      for (int64_t k = k0; k <= k1; ++k)
      {
        double e0, e1, e2;
        const int s0 = EdgeSide(P[1], P[2], double(j), double(k), e0); // opposite vertex 0
        const int s1 = EdgeSide(P[2], P[0], double(j), double(k), e1); // opposite vertex 1
        const int s2 = EdgeSide(P[0], P[1], double(j), double(k), e2); // opposite vertex 2
        if (s0 == 0 || s0 != s1 || s1 != s2)
        {
          continue;
        }
        const double sum = e0 + e1 + e2;
        double w0 = 1.0 / 3, w1 = 1.0 / 3, w2 = 1.0 / 3;
        if (sum != 0)
        {
          w0 = e0 / sum;
          w1 = e1 / sum;
          w2 = 1.0 - w0 - w1;
        }
        double depth = w0 * v[0][a] + w1 * v[1][a] + w2 * v[2][a];
        depth = std::min(std::max(depth, 0.0), cells - 1e-9 * cells);
        Crossing c;
        c.Pos[a] = depth;
        c.Pos[p] = double(j);
        c.Pos[q] = double(k);
        c.Corner[a] = ClampCell(depth, ctx.Cells);
        c.Corner[p] = static_cast<uint32_t>(j);
        c.Corner[q] = static_cast<uint32_t>(k);
        c.Axis = static_cast<int8_t>(a);
        c.Sign = static_cast<int8_t>(s0);
        for (int i = 0; i < 3; ++i)
        {
          c.Normal[i] = ctx.TriNormal[3 * t + i];
        }
        if (in.TriangleDiffuse)
        {
          c.Diffuse = in.TriangleDiffuse[t];
        }
        else if (in.PointDiffuse)
        {
          c.Diffuse = static_cast<float>(w0 * in.PointDiffuse[tri[0]] +
            w1 * in.PointDiffuse[tri[1]] + w2 * in.PointDiffuse[tri[2]]);
        }
        else
        {
          c.Diffuse = in.UniformDiffuse;
        }
        if (in.TriangleSpecular)
        {
          c.Specular = in.TriangleSpecular[t];
        }
        else if (in.PointSpecular)
        {
          c.Specular = static_cast<float>(w0 * in.PointSpecular[tri[0]] +
            w1 * in.PointSpecular[tri[1]] + w2 * in.PointSpecular[tri[2]]);
        }
        else
        {
          c.Specular = in.UniformSpecular;
        }
        out.push_back(c);
      }
    }
  }
}

/// Runs `body(chunk, begin, end)` over fixed chunks and concatenates per-chunk outputs in chunk
/// order, so the result does not depend on the number of threads.
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
  size_t total = 0;
  for (auto& p : parts)
  {
    total += p.size();
  }
  std::vector<T> all;
  all.reserve(total);
  for (auto& p : parts)
  {
    all.insert(all.end(), p.begin(), p.end());
    std::vector<T>().swap(p);
  }
  return all;
}

/// Index of `key` in sorted `keys`, or -1.
inline int64_t FindKey(const std::vector<uint64_t>& keys, uint64_t key)
{
  auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return (it != keys.end() && *it == key) ? (it - keys.begin()) : -1;
}

/// Normals of a point cloud by PCA over the points within one cell edge, oriented towards the
/// viewpoint (per point, global, or away from the centroid).
void EstimateNormals(const BuildInput& in, const std::vector<double>& u, uint32_t cells,
  const std::vector<uint64_t>& pointKeys, const std::vector<int64_t>& order,
  const std::vector<uint64_t>& cellKeys, const std::vector<int64_t>& cellStart,
  const double origin[3], double h, const ParallelFor& pfor, std::vector<float>& normals)
{
  const int64_t n = in.NumberOfPoints;
  normals.assign(3 * n, 0.0f);
  double centroid[3] = { 0, 0, 0 };
  for (int64_t i = 0; i < n; ++i)
  {
    for (int a = 0; a < 3; ++a)
    {
      centroid[a] += in.Points[3 * i + a] / double(n);
    }
  }
  pfor(n, 2048, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      const double* x = &u[3 * i];
      uint32_t c[3];
      MortonDecode(pointKeys[i], c);
      Eigen::Vector3d mean(0, 0, 0);
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      int count = 0;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
          {
            const int64_t cx = int64_t(c[0]) + dx, cy = int64_t(c[1]) + dy,
                          cz = int64_t(c[2]) + dz;
            if (cx < 0 || cy < 0 || cz < 0 || cx >= cells || cy >= cells || cz >= cells)
            {
              continue;
            }
            const int64_t ci = FindKey(cellKeys, MortonEncode(uint32_t(cx), uint32_t(cy), uint32_t(cz)));
            if (ci < 0)
            {
              continue;
            }
            for (int64_t s = cellStart[ci]; s < cellStart[ci + 1]; ++s)
            {
              const double* y = &u[3 * order[s]];
              const Eigen::Vector3d d(y[0] - x[0], y[1] - x[1], y[2] - x[2]);
              if (d.squaredNorm() <= 1.0)
              {
                mean += d;
                cov += d * d.transpose();
                ++count;
              }
            }
          }
      Eigen::Vector3d nrm(0, 0, 1);
      if (count >= 3)
      {
        mean /= count;
        cov = cov / count - mean * mean.transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
        eig.computeDirect(cov);
        nrm = eig.eigenvectors().col(0);
      }
      double target[3];
      if (in.PointViewpoints)
      {
        for (int a = 0; a < 3; ++a)
          target[a] = in.PointViewpoints[3 * i + a] - in.Points[3 * i + a];
      }
      else if (in.HasViewpoint)
      {
        for (int a = 0; a < 3; ++a)
          target[a] = in.Viewpoint[a] - in.Points[3 * i + a];
      }
      else
      {
        for (int a = 0; a < 3; ++a)
          target[a] = in.Points[3 * i + a] - centroid[a];
      }
      if (count < 3)
      {
        nrm = Eigen::Vector3d(target[0], target[1], target[2]);
        if (nrm.norm() > 0)
          nrm.normalize();
        else
          nrm = Eigen::Vector3d(0, 0, 1);
      }
      if (nrm[0] * target[0] + nrm[1] * target[1] + nrm[2] * target[2] < 0)
      {
        nrm = -nrm;
      }
      for (int a = 0; a < 3; ++a)
      {
        normals[3 * i + a] = static_cast<float>(nrm[a]);
      }
    }
  });
  (void)origin;
  (void)h;
}

/// Crossings of a point cloud: signed distance to the oriented samples at the corners of the
/// occupied cells (Gaussian-weighted tangent planes of the points in the 8 cells around each
/// corner), and a crossing on every finest edge whose two known corners differ in sign.
std::vector<Crossing> CloudCrossings(const BuildInput& in, const std::vector<double>& u,
  uint32_t cells, const float* normals, const std::vector<int64_t>& order,
  const std::vector<uint64_t>& cellKeys, const std::vector<int64_t>& cellStart,
  const ParallelFor& pfor)
{
  // Unique corners of occupied cells.
  std::vector<uint64_t> corners;
  corners.reserve(cellKeys.size() * 8);
  for (uint64_t key : cellKeys)
  {
    uint32_t c[3];
    MortonDecode(key, c);
    for (int k = 0; k < 8; ++k)
    {
      corners.push_back(MortonEncode(c[0] + (k & 1), c[1] + ((k >> 1) & 1), c[2] + ((k >> 2) & 1)));
    }
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());

  struct CornerValue
  {
    double F;
    float Normal[3];
    float Diffuse, Specular;
    bool Known;
  };
  std::vector<CornerValue> values(corners.size());
  pfor(static_cast<int64_t>(corners.size()), 1024, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      uint32_t c[3];
      MortonDecode(corners[i], c);
      double sw = 0, sf = 0, sd = 0, ss = 0;
      double sn[3] = { 0, 0, 0 };
      for (int k = 0; k < 8; ++k)
      {
        const int64_t cx = int64_t(c[0]) - (k & 1), cy = int64_t(c[1]) - ((k >> 1) & 1),
                      cz = int64_t(c[2]) - ((k >> 2) & 1);
        if (cx < 0 || cy < 0 || cz < 0 || cx >= cells || cy >= cells || cz >= cells)
        {
          continue;
        }
        const int64_t ci = FindKey(cellKeys, MortonEncode(uint32_t(cx), uint32_t(cy), uint32_t(cz)));
        if (ci < 0)
        {
          continue;
        }
        for (int64_t s = cellStart[ci]; s < cellStart[ci + 1]; ++s)
        {
          const int64_t pi = order[s];
          const double* y = &u[3 * pi];
          const double d[3] = { c[0] - y[0], c[1] - y[1], c[2] - y[2] };
          const double w = std::exp(-(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
          const float* nn = normals + 3 * pi;
          sf += w * (nn[0] * d[0] + nn[1] * d[1] + nn[2] * d[2]);
          for (int a = 0; a < 3; ++a)
          {
            sn[a] += w * nn[a];
          }
          sd += w * PointValue(in.PointDiffuse, pi, in.UniformDiffuse);
          ss += w * PointValue(in.PointSpecular, pi, in.UniformSpecular);
          sw += w;
        }
      }
      CornerValue& v = values[i];
      v.Known = sw > 0;
      v.F = sw > 0 ? sf / sw : 0;
      const double nl = std::sqrt(sn[0] * sn[0] + sn[1] * sn[1] + sn[2] * sn[2]);
      for (int a = 0; a < 3; ++a)
      {
        v.Normal[a] = nl > 0 ? static_cast<float>(sn[a] / nl) : (a == 2 ? 1.0f : 0.0f);
      }
      v.Diffuse = sw > 0 ? static_cast<float>(sd / sw) : in.UniformDiffuse;
      v.Specular = sw > 0 ? static_cast<float>(ss / sw) : in.UniformSpecular;
    }
  });

  return ChunkedGather<Crossing>(static_cast<int64_t>(corners.size()), 4096, pfor,
    [&](int64_t b, int64_t e, std::vector<Crossing>& out) {
      for (int64_t i = b; i < e; ++i)
      {
        const CornerValue& v0 = values[i];
        if (!v0.Known)
        {
          continue;
        }
        uint32_t c[3];
        MortonDecode(corners[i], c);
        for (int a = 0; a < 3; ++a)
        {
          uint32_t d[3] = { c[0], c[1], c[2] };
          ++d[a];
          const int p = (a + 1) % 3, q = (a + 2) % 3;
          if (c[p] == 0 || c[q] == 0 || c[p] >= cells || c[q] >= cells || c[a] >= cells)
          {
            continue;
          }
          const int64_t j = FindKey(corners, MortonEncode(d[0], d[1], d[2]));
          if (j < 0 || !values[j].Known)
          {
            continue;
          }
          const CornerValue& v1 = values[j];
          const bool in0 = v0.F < 0, in1 = v1.F < 0;
          if (in0 == in1)
          {
            continue;
          }
          const double t = std::min(1.0, std::max(0.0, v0.F / (v0.F - v1.F)));
          Crossing x;
          for (int k = 0; k < 3; ++k)
          {
            x.Pos[k] = c[k];
            x.Corner[k] = c[k];
            x.Normal[k] = static_cast<float>((1 - t) * v0.Normal[k] + t * v1.Normal[k]);
          }
          x.Pos[a] += std::min(t, 1.0 - 1e-9);
          const double nl = std::sqrt(double(x.Normal[0]) * x.Normal[0] +
            double(x.Normal[1]) * x.Normal[1] + double(x.Normal[2]) * x.Normal[2]);
          for (int k = 0; k < 3; ++k)
          {
            x.Normal[k] = nl > 0 ? static_cast<float>(x.Normal[k] / nl) : 0.0f;
          }
          x.Diffuse = static_cast<float>((1 - t) * v0.Diffuse + t * v1.Diffuse);
          x.Specular = static_cast<float>((1 - t) * v0.Specular + t * v1.Specular);
          x.Axis = static_cast<int8_t>(a);
          x.Sign = in0 ? 1 : -1;
          out.push_back(x);
        }
      }
    });
}

/// Unit normal and clipped area weight of every triangle, in grid units.
void TriangleFrames(MeshContext& ctx, const ParallelFor& pfor)
{
  const BuildInput& in = *ctx.In;
  ctx.TriNormal.assign(3 * in.NumberOfTriangles, 0.0f);
  ctx.TriWeight.assign(in.NumberOfTriangles, 0.0);
  pfor(in.NumberOfTriangles, 8192, [&](int64_t b, int64_t e) {
    for (int64_t t = b; t < e; ++t)
    {
      const int64_t* tri = in.Triangles + 3 * t;
      const double* a = &ctx.U[3 * tri[0]];
      const double* bb = &ctx.U[3 * tri[1]];
      const double* c = &ctx.U[3 * tri[2]];
      const double e1[3] = { bb[0] - a[0], bb[1] - a[1], bb[2] - a[2] };
      const double e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      const double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0] };
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len > 0 && std::isfinite(len))
      {
        for (int i = 0; i < 3; ++i)
        {
          ctx.TriNormal[3 * t + i] = static_cast<float>(n[i] / len);
        }
        ctx.TriWeight[t] = std::min(0.5 * len, 1.0);
      }
    }
  });
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
      const double d =
        std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
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
  const double items = in.NumberOfPoints + 3.0 * in.NumberOfTriangles + 4 * crossings;
  const double nodes = cells * 4.0 / 3.0;
  return items * 2 * sizeof(Item) + crossings * sizeof(Crossing) +
    nodes * (62 + sizeof(NodeAccum) + 12 + sizeof(Quadric)) + in.NumberOfPoints * 48.0 +
    in.NumberOfTriangles * 24.0;
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
  auto report = [&](double f) {
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
  if (!report(0.02))
  {
    return result;
  }

  MeshContext ctx;
  ctx.In = &in;
  ctx.Level = level;
  ctx.Cells = cells;
  ctx.U.resize(3 * in.NumberOfPoints);
  std::vector<uint64_t> pointKey(in.NumberOfPoints);
  pfor(in.NumberOfPoints, 16384, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      for (int a = 0; a < 3; ++a)
      {
        ctx.U[3 * i + a] = (in.Points[3 * i + a] - origin[a]) / h;
      }
      pointKey[i] = MortonEncode(ClampCell(ctx.U[3 * i], cells), ClampCell(ctx.U[3 * i + 1], cells),
        ClampCell(ctx.U[3 * i + 2], cells));
    }
  });

  // ---- crossings -----------------------------------------------------------------------------
  std::vector<Crossing> crossings;
  std::vector<float> cloudNormals;
  const float* pointNormals = in.PointNormals;
  if (cloud)
  {
    // Points sorted by cell, for neighbourhood queries.
    std::vector<Item> pitems(in.NumberOfPoints);
    for (int64_t i = 0; i < in.NumberOfPoints; ++i)
    {
      pitems[i] = { pointKey[i], uint64_t(i) };
    }
    RadixSort(pitems, 3 * level);
    std::vector<int64_t> order(in.NumberOfPoints);
    std::vector<uint64_t> cellKeys;
    std::vector<int64_t> cellStart;
    for (int64_t i = 0; i < in.NumberOfPoints; ++i)
    {
      order[i] = static_cast<int64_t>(pitems[i].Ref);
      if (i == 0 || pitems[i].Key != pitems[i - 1].Key)
      {
        cellKeys.push_back(pitems[i].Key);
        cellStart.push_back(i);
      }
    }
    cellStart.push_back(in.NumberOfPoints);
    if (!pointNormals)
    {
      EstimateNormals(in, ctx.U, cells, pointKey, order, cellKeys, cellStart, origin, h, pfor,
        cloudNormals);
      pointNormals = cloudNormals.data();
    }
    if (!report(0.2))
    {
      return result;
    }
    crossings = CloudCrossings(in, ctx.U, cells, pointNormals, order, cellKeys, cellStart, pfor);
  }
  else
  {
    TriangleFrames(ctx, pfor);
    crossings = ChunkedGather<Crossing>(in.NumberOfTriangles, 2048, pfor,
      [&](int64_t b, int64_t e, std::vector<Crossing>& out) {
        for (int64_t t = b; t < e; ++t)
        {
          if (ctx.TriWeight[t] > 0)
          {
            TriangleCrossings(ctx, t, out);
          }
          else
          {
            // counted below
          }
        }
      });
    for (int64_t t = 0; t < in.NumberOfTriangles; ++t)
    {
      result.NumberOfSkippedTriangles += ctx.TriWeight[t] > 0 ? 0 : 1;
    }
  }
  result.NumberOfCrossings = static_cast<int64_t>(crossings.size());
  if (!report(0.45))
  {
    return result;
  }

  // ---- items sorted by finest cell ------------------------------------------------------------
  std::vector<Item> items;
  items.reserve(usedCount + (cloud ? 0 : 3 * in.NumberOfTriangles) + 4 * crossings.size());
  for (int64_t i = 0; i < in.NumberOfPoints; ++i)
  {
    if (used[i])
    {
      items.push_back({ pointKey[i], MakeRef(i, 0, PointSample) });
    }
  }
  if (!cloud)
  {
    for (int64_t t = 0; t < in.NumberOfTriangles; ++t)
    {
      if (ctx.TriWeight[t] <= 0)
      {
        continue;
      }
      const int64_t* tri = in.Triangles + 3 * t;
      const uint64_t k0 = pointKey[tri[0]], k1 = pointKey[tri[1]], k2 = pointKey[tri[2]];
      items.push_back({ k0, MakeRef(t, 0, TouchSample) });
      if (k1 != k0)
      {
        items.push_back({ k1, MakeRef(t, 1, TouchSample) });
      }
      if (k2 != k0 && k2 != k1)
      {
        items.push_back({ k2, MakeRef(t, 2, TouchSample) });
      }
    }
  }
  for (size_t x = 0; x < crossings.size(); ++x)
  {
    const Crossing& c = crossings[x];
    const int a = c.Axis, p = (a + 1) % 3, q = (a + 2) % 3;
    for (int slot = 0; slot < 4; ++slot)
    {
      uint32_t cc[3];
      cc[a] = c.Corner[a];
      cc[p] = c.Corner[p] - (slot & 1);
      cc[q] = c.Corner[q] - ((slot >> 1) & 1);
      items.push_back({ MortonEncode(cc[0], cc[1], cc[2]), MakeRef(x, slot, CrossSample) });
    }
  }
  RadixSort(items, 3 * level);
  if (!report(0.6))
  {
    return result;
  }

  // ---- keys of every level -------------------------------------------------------------------
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

  // structure: parent, first child, mask, level
  for (int l = 0; l <= level; ++l)
  {
    const int64_t n = static_cast<int64_t>(keys[l].size());
    for (int64_t i = 0; i < n; ++i)
    {
      const int64_t node = offset[l] + i;
      out.Level[node] = static_cast<uint8_t>(l);
      out.FirstChild[node] = -1;
      out.ChildMask[node] = 0;
    }
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

  // ---- finest cells ------------------------------------------------------------------------
  std::vector<NodeAccum> acc(total);
  std::vector<Quadric> quadrics(params.Rule == VertexRule::QEF ? total : 0);
  const int64_t nFinest = static_cast<int64_t>(keys[level].size());
  std::vector<int> nets(12 * nFinest, 0);
  pfor(nFinest, 1024, [&](int64_t b, int64_t e) {
    for (int64_t ci = b; ci < e; ++ci)
    {
      const int64_t node = offset[level] + ci;
      NodeAccum& A = acc[node];
      double nsum[3] = { 0, 0, 0 }, wsum = 0;
      float dmin = std::numeric_limits<float>::max(), dmax = -dmin;
      float smin = dmin, smax = -dmin;
      int* net = &nets[12 * ci];
      Quadric* Q = quadrics.empty() ? nullptr : &quadrics[node];
      auto sampleNormal = [&](const Item& it, double n[3], double& w, const double*& at) {
        const uint64_t type = it.Ref & 3, slot = (it.Ref >> 2) & 3, idx = it.Ref >> 4;
        at = nullptr;
        if (type == PointSample)
        {
          w = cloud ? 1.0 : 0.0;
          if (cloud)
          {
            const float* pn = pointNormals + 3 * idx;
            const double l = std::sqrt(double(pn[0]) * pn[0] + double(pn[1]) * pn[1] +
              double(pn[2]) * pn[2]);
            w = l > 0 ? 1.0 : 0.0;
            for (int k = 0; k < 3; ++k)
              n[k] = l > 0 ? pn[k] / l : 0.0;
          }
          at = &ctx.U[3 * idx];
        }
        else if (type == TouchSample)
        {
          w = ctx.TriWeight[idx];
          for (int k = 0; k < 3; ++k)
            n[k] = ctx.TriNormal[3 * idx + k];
          at = &ctx.U[3 * in.Triangles[3 * idx + slot]];
        }
        else
        {
          const Crossing& c = crossings[idx];
          w = 0.25;
          for (int k = 0; k < 3; ++k)
            n[k] = c.Normal[k];
          at = c.Pos;
        }
      };
      for (int64_t s = finestStart[ci]; s < finestStart[ci + 1]; ++s)
      {
        const Item& it = items[s];
        const uint64_t type = it.Ref & 3, slot = (it.Ref >> 2) & 3, idx = it.Ref >> 4;
        float d = in.UniformDiffuse, sp = in.UniformSpecular;
        bool hasMaterial = true;
        if (type == PointSample)
        {
          for (int k = 0; k < 3; ++k)
            A.SumPoints[k] += ctx.U[3 * idx + k];
          ++A.CountPoints;
          d = PointValue(in.PointDiffuse, idx, in.UniformDiffuse);
          sp = PointValue(in.PointSpecular, idx, in.UniformSpecular);
        }
        else if (type == TouchSample)
        {
          hasMaterial = in.TriangleDiffuse || in.TriangleSpecular;
          d = PointValue(in.TriangleDiffuse, idx, d);
          sp = PointValue(in.TriangleSpecular, idx, sp);
        }
        else
        {
          const Crossing& c = crossings[idx];
          for (int k = 0; k < 3; ++k)
            A.SumCross[k] += c.Pos[k];
          ++A.CountCross;
          const int a = c.Axis;
          net[EdgeIndex(a, slot & 1, (slot >> 1) & 1)] += c.Sign;
          d = c.Diffuse;
          sp = c.Specular;
        }
        if (hasMaterial)
        {
          dmin = std::min(dmin, d);
          dmax = std::max(dmax, d);
          smin = std::min(smin, sp);
          smax = std::max(smax, sp);
        }
        double n[3], w;
        const double* at;
        sampleNormal(it, n, w, at);
        if (w > 0)
        {
          for (int k = 0; k < 3; ++k)
            nsum[k] += w * n[k];
          wsum += w;
          if (Q)
            Q->AddPlane(n, at, w);
        }
      }
      // vertex
      const uint32_t cnt = A.CountPoints + A.CountCross;
      double mean[3];
      for (int k = 0; k < 3; ++k)
      {
        mean[k] = (A.SumPoints[k] + A.SumCross[k]) / std::max<uint32_t>(cnt, 1);
      }
      uint32_t cc[3];
      MortonDecode(keys[level][ci], cc);
      if (Q)
      {
        Q->Solve(mean, A.Vertex);
        for (int k = 0; k < 3; ++k)
          A.Vertex[k] = std::min(std::max(A.Vertex[k], double(cc[k])), double(cc[k]) + 1.0);
      }
      else
      {
        std::copy(mean, mean + 3, A.Vertex);
      }
      // cone
      const double len = std::sqrt(nsum[0] * nsum[0] + nsum[1] * nsum[1] + nsum[2] * nsum[2]);
      double axis[3] = { 0, 0, 1 };
      double theta = Pi;
      if (wsum > 0 && len > 1e-9 * wsum)
      {
        for (int k = 0; k < 3; ++k)
          axis[k] = nsum[k] / len;
        theta = 0;
        for (int64_t s = finestStart[ci]; s < finestStart[ci + 1]; ++s)
        {
          double n[3], w;
          const double* at;
          sampleNormal(items[s], n, w, at);
          if (w > 0)
            theta = std::max(theta, AngleBetween(n, axis));
        }
      }
      for (int k = 0; k < 3; ++k)
      {
        out.Vertex[3 * node + k] = static_cast<float>(A.Vertex[k] * h);
        out.ConeAxis[3 * node + k] = static_cast<float>(axis[k]);
      }
      out.ConeAngle[node] = static_cast<float>(theta);
      out.ShapeError[node] = 0.0f;
      if (dmin > dmax)
      {
        dmin = dmax = in.UniformDiffuse;
      }
      if (smin > smax)
      {
        smin = smax = in.UniformSpecular;
      }
      out.Diffuse[2 * node] = dmin;
      out.Diffuse[2 * node + 1] = dmax;
      out.Specular[2 * node] = smin;
      out.Specular[2 * node + 1] = smax;
      uint32_t word = 0;
      for (int e = 0; e < 12; ++e)
      {
        word |= EncodeEdge(e, net[e]);
      }
      out.Edges[node] = word;
    }
  });
  if (!report(0.75))
  {
    return result;
  }

  // Crossings on the edges of coarser cells (for the mean rule): a finest crossing whose edge
  // lies on the grid lines of level l belongs to the four level-l cells around that line.
  for (const Crossing& c : crossings)
  {
    const int a = c.Axis, p = (a + 1) % 3, q = (a + 2) % 3;
    for (int l = level - 1; l >= 0; --l)
    {
      const int s = level - l;
      const uint32_t mask = (1u << s) - 1u;
      if ((c.Corner[p] & mask) || (c.Corner[q] & mask))
      {
        break;
      }
      for (int slot = 0; slot < 4; ++slot)
      {
        const int64_t cp = int64_t(c.Corner[p] >> s) - (slot & 1);
        const int64_t cq = int64_t(c.Corner[q] >> s) - ((slot >> 1) & 1);
        if (cp < 0 || cq < 0)
        {
          continue;
        }
        uint32_t cc[3];
        cc[a] = c.Corner[a] >> s;
        cc[p] = static_cast<uint32_t>(cp);
        cc[q] = static_cast<uint32_t>(cq);
        const int64_t i = FindKey(keys[l], MortonEncode(cc[0], cc[1], cc[2]));
        if (i >= 0)
        {
          NodeAccum& A = acc[offset[l] + i];
          for (int k = 0; k < 3; ++k)
            A.SumCross[k] += c.Pos[k];
          ++A.CountCross;
        }
      }
    }
  }

  // ---- coarser levels ----------------------------------------------------------------------
  for (int l = level - 1; l >= 0; --l)
  {
    const double scale = std::ldexp(1.0, level - l); // finest units per cell at level l
    pfor(static_cast<int64_t>(keys[l].size()), 1024, [&](int64_t b, int64_t e) {
      for (int64_t i = b; i < e; ++i)
      {
        const int64_t node = offset[l] + i;
        NodeAccum& A = acc[node];
        const int32_t first = out.FirstChild[node];
        const unsigned mask = out.ChildMask[node];
        int32_t child[8];
        double nsum[3] = { 0, 0, 0 };
        double childMean[3] = { 0, 0, 0 };
        int nchild = 0;
        for (int c = 0, r = 0; c < 8; ++c)
        {
          child[c] = (mask & (1u << c)) ? first + r++ : -1;
          if (child[c] < 0)
          {
            continue;
          }
          const NodeAccum& C = acc[child[c]];
          for (int k = 0; k < 3; ++k)
          {
            A.SumPoints[k] += C.SumPoints[k];
            nsum[k] += out.ConeAxis[3 * child[c] + k];
            childMean[k] += C.Vertex[k];
          }
          A.CountPoints += C.CountPoints;
          if (!quadrics.empty())
          {
            quadrics[node].Add(quadrics[child[c]]);
          }
          ++nchild;
        }
        // vertex
        double mean[3];
        const uint32_t cnt = A.CountPoints + A.CountCross;
        for (int k = 0; k < 3; ++k)
        {
          mean[k] = cnt ? (A.SumPoints[k] + A.SumCross[k]) / cnt : childMean[k] / nchild;
        }
        uint32_t cc[3];
        MortonDecode(keys[l][i], cc);
        if (!quadrics.empty())
        {
          quadrics[node].Solve(mean, A.Vertex);
          for (int k = 0; k < 3; ++k)
            A.Vertex[k] = std::min(std::max(A.Vertex[k], cc[k] * scale), (cc[k] + 1.0) * scale);
        }
        else
        {
          std::copy(mean, mean + 3, A.Vertex);
        }
        // cone, SRCC eq. (1)-(2)
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
          out.Vertex[3 * node + k] = static_cast<float>(A.Vertex[k] * h);
          out.ConeAxis[3 * node + k] = static_cast<float>(axis[k]);
        }
        out.ConeAngle[node] = static_cast<float>(theta);
        // material
        float dmin = std::numeric_limits<float>::max(), dmax = -dmin, smin = dmin, smax = -dmin;
        uint32_t word = 0;
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
        // edges: a coarse edge is its two halves, held by the children on that edge
        for (int a = 0; a < 3; ++a)
        {
          const int p = (a + 1) % 3, q = (a + 2) % 3;
          for (int pb = 0; pb < 2; ++pb)
            for (int qb = 0; qb < 2; ++qb)
            {
              const int e = EdgeIndex(a, pb, qb);
              int net = 0;
              for (int ab = 0; ab < 2; ++ab)
              {
                const int c = (ab << a) | (pb << p) | (qb << q);
                if (child[c] >= 0)
                {
                  net += EdgeSign(out.Edges[child[c]], e);
                }
              }
              word |= EncodeEdge(e, net);
            }
        }
        out.Edges[node] = word;
      }
    });
    if (!report(0.75 + 0.15 * double(level - l) / double(level)))
    {
      return result;
    }
  }

  // ---- shape error, SRCC eq. (3), over the finest descendants ------------------------------
  const std::vector<uint64_t>& fk = keys[level];
  pfor(offset[level], 256, [&](int64_t b, int64_t e) {
    for (int64_t node = b; node < e; ++node)
    {
      const int l = out.Level[node];
      const int64_t i = node - offset[l];
      const int s = 3 * (level - l);
      const uint64_t k0 = keys[l][i] << s, k1 = (keys[l][i] + 1) << s;
      const int64_t f0 = std::lower_bound(fk.begin(), fk.end(), k0) - fk.begin();
      const int64_t f1 = std::lower_bound(fk.begin(), fk.end(), k1) - fk.begin();
      const float* n = &out.ConeAxis[3 * node];
      const double* v = acc[node].Vertex;
      double dmin = 0, dmax = 0;
      bool first = true;
      for (int64_t f = f0; f < f1; ++f)
      {
        const double* vc = acc[offset[level] + f].Vertex;
        const double d = n[0] * (vc[0] - v[0]) + n[1] * (vc[1] - v[1]) + n[2] * (vc[2] - v[2]);
        dmin = first ? d : std::min(dmin, d);
        dmax = first ? d : std::max(dmax, d);
        first = false;
      }
      out.ShapeError[node] = static_cast<float>((dmax - dmin) * h);
    }
  });
  report(1.0);
  result.Ok = true;
  return result;
}

} // namespace plod
