// SPDX-License-Identifier: BSD-3-Clause
// Provenance: Wang & Sato (octree levels from scattered range data); Hoppe et al. 1992
// (signed distance to tangent planes); dual contouring / surface nets at one level (Gibson
// 1998, Ju et al. 2002).
#include "plodCloudSurface.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace plod
{
namespace build
{
namespace
{

/// The cloud in Morton order of its finest cells, in grid units of that level.
struct Cloud
{
  int64_t NumberOfPoints = 0;
  uint32_t Cells = 1;
  LargeVector<double> U;         // 3 per point
  LargeVector<uint64_t> Key;     // finest cell of each point, sorted
  LargeVector<int64_t> Source;   // input index of each point
  LargeVector<float> Normal;     // 3 per point, unit (0 when unknown)
  LargeVector<uint64_t> CellKey; // occupied cells
  LargeVector<int64_t> CellStart;
};

inline int64_t FindKey(const LargeVector<uint64_t>& keys, uint64_t key)
{
  auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return (it != keys.end() && *it == key) ? (it - keys.begin()) : -1;
}

/// Calls `visit(point)` for the points of the occupied cells (c + d), d in {dlo..dhi}^3.
template <typename Visit>
void ForNeighbours(const Cloud& C, const int64_t c[3], int dlo, int dhi, Visit visit)
{
  for (int dz = dlo; dz <= dhi; ++dz)
    for (int dy = dlo; dy <= dhi; ++dy)
      for (int dx = dlo; dx <= dhi; ++dx)
      {
        const int64_t x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
        if (x < 0 || y < 0 || z < 0 || x >= C.Cells || y >= C.Cells || z >= C.Cells)
        {
          continue;
        }
        const int64_t ci = FindKey(C.CellKey, MortonEncode(uint32_t(x), uint32_t(y), uint32_t(z)));
        if (ci >= 0)
        {
          for (int64_t s = C.CellStart[ci]; s < C.CellStart[ci + 1]; ++s)
          {
            visit(s);
          }
        }
      }
}

/// About this many candidate points (of the 27 cells around a point) enter its PCA normal, at
/// most this many plus 27. Beyond it each cell's candidates are taken at an even stride: a cell
/// piled with k points (duplicates, float rounding, a coarse level set by the user) would otherwise
/// cost k^2 (measured: 65,536 points, half on one spot, 26.6 s). A plane fit from 512 spread
/// samples is as good as one from all; clouds at their automatic level hold a few points per cell
/// and never reach it.
constexpr int64_t MaxNormalCandidates = 512;

/// Normals by PCA over the points within one cell edge, oriented towards `target(i)`.
template <typename Target>
bool EstimateNormals(Cloud& C, const ParallelFor& pfor, Reporter& report, Target target)
{
  return BlockedFor(
    C.NumberOfPoints, 2048, int64_t(1) << 16, pfor,
    [&](int64_t b, int64_t e) {
      for (int64_t i = b; i < e; ++i)
      {
        if (C.Normal[3 * i] != 0 || C.Normal[3 * i + 1] != 0 || C.Normal[3 * i + 2] != 0)
        {
          continue; // given
        }
        const double* x = &C.U[3 * i];
        uint32_t c[3];
        MortonDecode(C.Key[i], c);
        // the candidate ranges of the 27 cells around the point
        int64_t range[27][2];
        int ranges = 0;
        int64_t candidates = 0;
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
            {
              const int64_t u = int64_t(c[0]) + dx, v = int64_t(c[1]) + dy, w = int64_t(c[2]) + dz;
              if (u < 0 || v < 0 || w < 0 || u >= C.Cells || v >= C.Cells || w >= C.Cells)
              {
                continue;
              }
              const int64_t ci =
                FindKey(C.CellKey, MortonEncode(uint32_t(u), uint32_t(v), uint32_t(w)));
              if (ci >= 0)
              {
                range[ranges][0] = C.CellStart[ci];
                range[ranges][1] = C.CellStart[ci + 1];
                candidates += range[ranges][1] - range[ranges][0];
                ++ranges;
              }
            }
        const int64_t stride = (candidates + MaxNormalCandidates - 1) / MaxNormalCandidates;
        Eigen::Vector3d mean(0, 0, 0);
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        int count = 0;
        for (int r = 0; r < ranges; ++r)
        {
          // every stride-th candidate of each cell (at most MaxNormalCandidates + 27 in all)
          for (int64_t s = range[r][0]; s < range[r][1]; s += stride)
          {
            const double* y = &C.U[3 * s];
            const Eigen::Vector3d d(y[0] - x[0], y[1] - x[1], y[2] - x[2]);
            if (d.squaredNorm() <= 1.0)
            {
              mean += d;
              cov += d * d.transpose();
              ++count;
            }
          }
        }
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
          C.Normal[3 * i + a] = static_cast<float>(nrm[a]);
        }
      }
    },
    [&](double f) { return report(f); });
}

/// A sign change of the signed distance on a finest grid edge.
struct Crossing
{
  uint64_t Corner; // Morton key of the edge's lower corner
  double T;        // offset along the edge from that corner, in [0, 1)
  int Axis;
  int Sign;       // +1: the inside (negative distance) is at the lower corner
  int64_t Source; // the point nearest the corner it is closest to
};

/// Signed distance at the corners of the occupied cells, and its sign changes.
LargeVector<Crossing> SignChanges(const Cloud& C, const ParallelFor& pfor, Reporter& report)
{
  LargeVector<Item> corners;
  corners.reserve(C.CellKey.size() * 8);
  for (uint64_t key : C.CellKey)
  {
    uint32_t c[3];
    MortonDecode(key, c);
    for (int k = 0; k < 8; ++k)
    {
      const uint32_t x = c[0] + (k & 1), y = c[1] + ((k >> 1) & 1), z = c[2] + ((k >> 2) & 1);
      if (x < C.Cells && y < C.Cells && z < C.Cells)
      {
        corners.push_back({ MortonEncode(x, y, z), 0 });
      }
    }
  }
  int bits = 0;
  while ((uint64_t(1) << bits) < C.Cells)
  {
    ++bits;
  }
  RadixSort(corners, 3 * bits, pfor);
  LargeVector<uint64_t> cornerKeys;
  for (const Item& it : corners)
  {
    if (cornerKeys.empty() || cornerKeys.back() != it.Key)
    {
      cornerKeys.push_back(it.Key);
    }
  }
  LargeVector<Item>().swap(corners);
  struct CornerValue
  {
    double F;
    int64_t Source; // -1: no point near this corner
  };
  LargeVector<CornerValue> values(cornerKeys.size());
  const int64_t nk = static_cast<int64_t>(cornerKeys.size());
  const bool ok = BlockedFor(
    nk, 1024, int64_t(1) << 18, pfor,
    [&](int64_t b, int64_t e) {
      for (int64_t i = b; i < e; ++i)
      {
        uint32_t c[3];
        MortonDecode(cornerKeys[i], c);
        const int64_t ci[3] = { c[0], c[1], c[2] };
        double sw = 0, sf = 0, best = -1;
        int64_t source = -1;
        ForNeighbours(C, ci, -1, 0, [&](int64_t s) {
          const double* y = &C.U[3 * s];
          const double d[3] = { c[0] - y[0], c[1] - y[1], c[2] - y[2] };
          const double w = std::exp(-(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
          const float* nn = &C.Normal[3 * s];
          sf += w * (nn[0] * d[0] + nn[1] * d[1] + nn[2] * d[2]);
          sw += w;
          if (w > best)
          {
            best = w;
            source = s;
          }
        });
        values[i] = { sw > 0 ? sf / sw : 0.0, sw > 0 ? source : -1 };
      }
    },
    [&](double f) { return report(0.3 + 0.5 * f); });
  if (!ok)
  {
    return {};
  }
  return ChunkedGather<Crossing>(
    nk, 4096, pfor, [&](int64_t b, int64_t e, LargeVector<Crossing>& out) {
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
          if (c[p] == 0 || c[q] == 0 || c[a] + 1 >= C.Cells)
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
          out.push_back({ cornerKeys[i], t, a, in0 ? 1 : -1, t < 0.5 ? v0.Source : v1.Source });
        }
      }
    });
}

} // namespace

namespace
{
/// Coordinate `a` of input point `i`, in double.
double Coordinate(const BuildInput& in, int64_t i, int a)
{
  return in.Points ? in.Points[3 * i + a] : double(in.PointsFloat[3 * i + a]);
}

/// The finite points' indices, and the root cube (the caller's, which must hold them, or one
/// placed around them) into `out`. False with result.Error set.
bool PlaceCloud(const BuildInput& in, const BuildParameters& params, CloudMesh& out,
  BuildResult& result, LargeVector<int64_t>& finite)
{
  const int64_t np = in.NumberOfPoints;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = std::numeric_limits<double>::max();
    hi[a] = -std::numeric_limits<double>::max();
  }
  finite.clear();
  finite.reserve(np);
  for (int64_t i = 0; i < np; ++i)
  {
    const double x[3] = { Coordinate(in, i, 0), Coordinate(in, i, 1), Coordinate(in, i, 2) };
    if (std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))
    {
      finite.push_back(i);
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = std::min(lo[a], x[a]);
        hi[a] = std::max(hi[a], x[a]);
      }
    }
  }
  result.NumberOfNonFinitePoints = np - static_cast<int64_t>(finite.size());
  if (finite.empty())
  {
    result.Error = "every point of the cloud has NaN or infinite coordinates";
    return false;
  }
  if (result.NumberOfNonFinitePoints)
  {
    result.Warnings.push_back(std::to_string(result.NumberOfNonFinitePoints) +
      " point(s) with NaN or infinite coordinates skipped");
  }
  if (!params.HasRootCube)
  {
    return PlaceRootCube(lo, hi, out.Origin, out.RootEdge, &result.Error);
  }
  // the caller's cube (validated by BuildOctree), which must hold every finite point
  std::copy(params.RootOrigin, params.RootOrigin + 3, out.Origin);
  out.RootEdge = params.RootEdge;
  if (InsideRootCube(lo, out.Origin, out.RootEdge) && InsideRootCube(hi, out.Origin, out.RootEdge))
  {
    return true;
  }
  for (int64_t i : finite)
  {
    const double x[3] = { Coordinate(in, i, 0), Coordinate(in, i, 1), Coordinate(in, i, 2) };
    if (!InsideRootCube(x, out.Origin, out.RootEdge))
    {
      result.Error = PointOutsideRootCube(i, x, out.Origin, out.RootEdge);
      return false;
    }
  }
  return true;
}

/// The finite points sorted by their finest-level cell (`items`: key, input index), and the
/// level to contour at (the user's, or the cloud rule's from the occupied cells of every
/// level) into out.Level. False with result.Error set.
bool ChooseCloudLevel(const BuildInput& in, const BuildParameters& params, const ParallelFor& pfor,
  const LargeVector<int64_t>& finite, CloudMesh& out, BuildResult& result, LargeVector<Item>& items)
{
  const int64_t n = static_cast<int64_t>(finite.size());
  items.resize(n);
  const CellQuantizer grid(out.Origin, out.RootEdge);
  for (int64_t r = 0; r < n; ++r)
  {
    const int64_t i = finite[r];
    items[r] = { grid.Key(Coordinate(in, i, 0), Coordinate(in, i, 1), Coordinate(in, i, 2)),
      uint64_t(i) };
  }
  RadixSort(items, 3 * MaxFinestLevel, pfor);
  int64_t cells[MaxFinestLevel + 1];
  CountOccupiedCells(
    n, [&items](int64_t r) { return items[r].Key; }, cells);
  int level = params.FinestLevel;
  if (level < 0)
  {
    level = ChooseFinestLevel(cells, n, 0, true, params.MemoryLimit, &result.LevelReason);
  }
  else
  {
    result.LevelReason = "set by the user";
  }
  if (level < 1)
  {
    result.Error = "a point cloud needs a finest level of at least 1 to be contoured";
    return false;
  }
  out.Level = level;
  return true;
}

/// The cloud in grid units of out.Level, in the order of `items`, with the input's normals
/// where it has them (unit length; zero where missing or degenerate).
void MakeCloud(const BuildInput& in, const CloudMesh& out, const LargeVector<Item>& items, Cloud& C)
{
  const int64_t n = static_cast<int64_t>(items.size());
  C.NumberOfPoints = n;
  C.Cells = 1u << out.Level;
  const double h = out.RootEdge / double(C.Cells);
  C.U.resize(3 * n);
  C.Key.resize(n);
  C.Source.resize(n);
  C.Normal.assign(3 * n, 0.0f);
  const int shift = 3 * (MaxFinestLevel - out.Level);
  for (int64_t r = 0; r < n; ++r)
  {
    const int64_t i = static_cast<int64_t>(items[r].Ref);
    C.Source[r] = i;
    C.Key[r] = items[r].Key >> shift;
    for (int a = 0; a < 3; ++a)
    {
      C.U[3 * r + a] = (Coordinate(in, i, a) - out.Origin[a]) / h;
    }
    if (in.PointNormals)
    {
      const float* g = in.PointNormals + 3 * i;
      const double len = std::sqrt(double(g[0]) * g[0] + double(g[1]) * g[1] + double(g[2]) * g[2]);
      if (len > 0 && std::isfinite(len))
      {
        for (int a = 0; a < 3; ++a)
        {
          C.Normal[3 * r + a] = static_cast<float>(g[a] / len);
        }
      }
    }
    if (r == 0 || C.Key[r] != C.Key[r - 1])
    {
      C.CellKey.push_back(C.Key[r]);
      C.CellStart.push_back(r);
    }
  }
  C.CellStart.push_back(n);
}

/// The cloud's normals (EstimateNormals) oriented towards the point's own viewpoint, the
/// cloud's viewpoint, or away from the centroid, in that order of preference.
bool OrientNormals(
  const BuildInput& in, const CloudMesh& out, const ParallelFor& pfor, Reporter& report, Cloud& C)
{
  const int64_t n = C.NumberOfPoints;
  const double h = out.RootEdge / double(C.Cells);
  double centroid[3] = { 0, 0, 0 };
  for (int64_t r = 0; r < n; ++r)
    for (int a = 0; a < 3; ++a)
      centroid[a] += C.U[3 * r + a] / double(n);
  double vp[3];
  for (int a = 0; a < 3; ++a)
    vp[a] = (in.Viewpoint[a] - out.Origin[a]) / h;
  return EstimateNormals(C, pfor, report, [&](int64_t r, double t[3]) {
    const double* x = &C.U[3 * r];
    for (int a = 0; a < 3; ++a)
    {
      if (in.PointViewpoints)
      {
        t[a] = (in.PointViewpoints[3 * C.Source[r] + a] - out.Origin[a]) / h - x[a];
      }
      else
      {
        t[a] = in.HasViewpoint ? vp[a] - x[a] : x[a] - centroid[a];
      }
      if (!std::isfinite(t[a]))
      {
        t[a] = 0;
      }
    }
  });
}

/// The vertex of each of the four cells around every crossing: `vertexOf[4 x + slot]` indexes
/// `vertexKey`, the cells' Morton keys at the contour level, each cell once.
void CellsAroundCrossings(const LargeVector<Crossing>& crossings, int level,
  const ParallelFor& pfor, LargeVector<uint64_t>& vertexKey, LargeVector<int64_t>& vertexOf)
{
  LargeVector<Item> around(4 * crossings.size());
  for (size_t x = 0; x < crossings.size(); ++x)
  {
    const Crossing& k = crossings[x];
    const int a = k.Axis, p = (a + 1) % 3, q = (a + 2) % 3;
    uint32_t corner[3];
    MortonDecode(k.Corner, corner);
    for (int slot = 0; slot < 4; ++slot)
    {
      uint32_t cc[3];
      cc[a] = corner[a];
      cc[p] = corner[p] - (slot & 1);
      cc[q] = corner[q] - ((slot >> 1) & 1);
      around[4 * x + slot] = { MortonEncode(cc[0], cc[1], cc[2]), uint64_t(4 * x + slot) };
    }
  }
  RadixSort(around, 3 * level, pfor);
  vertexKey.clear();
  vertexOf.resize(around.size());
  for (size_t i = 0; i < around.size(); ++i)
  {
    if (vertexKey.empty() || vertexKey.back() != around[i].Key)
    {
      vertexKey.push_back(around[i].Key);
    }
    vertexOf[around[i].Ref] = static_cast<int64_t>(vertexKey.size()) - 1;
  }
}

/// Each cell's vertex: the mean of its crossings, kept inside the cell so that the vertex gets
/// its own leaf; its normal, the mean of the crossings' normals; its material range, from the
/// crossings' source points (or the uniform material where none has one).
void PlaceVertices(const BuildInput& in, const Cloud& C, const LargeVector<Crossing>& crossings,
  const LargeVector<uint64_t>& vertexKey, const LargeVector<int64_t>& vertexOf, CloudMesh& out)
{
  const int64_t nv = static_cast<int64_t>(vertexKey.size());
  const double h = out.RootEdge / double(C.Cells);
  LargeVector<double> sum(3 * nv, 0.0), nsum(3 * nv, 0.0);
  LargeVector<int> count(nv, 0);
  const bool material = in.PointDiffuse || in.PointSpecular; // clouds carry material per point only
  if (in.PointDiffuse)
  {
    out.DiffuseMin.assign(nv, std::numeric_limits<float>::max());
    out.DiffuseMax.assign(nv, -std::numeric_limits<float>::max());
  }
  if (in.PointSpecular)
  {
    out.SpecularMin.assign(nv, std::numeric_limits<float>::max());
    out.SpecularMax.assign(nv, -std::numeric_limits<float>::max());
  }
  for (size_t x = 0; x < crossings.size(); ++x)
  {
    const Crossing& k = crossings[x];
    uint32_t corner[3];
    MortonDecode(k.Corner, corner);
    double at[3] = { double(corner[0]), double(corner[1]), double(corner[2]) };
    at[k.Axis] += k.T;
    const float* nn = &C.Normal[3 * k.Source];
    const int64_t src = C.Source[k.Source];
    for (int slot = 0; slot < 4; ++slot)
    {
      const int64_t v = vertexOf[4 * x + slot];
      for (int a = 0; a < 3; ++a)
      {
        sum[3 * v + a] += at[a];
        nsum[3 * v + a] += nn[a];
      }
      ++count[v];
      if (material)
      {
        if (in.PointDiffuse && std::isfinite(in.PointDiffuse[src]))
        {
          out.DiffuseMin[v] = std::min(out.DiffuseMin[v], in.PointDiffuse[src]);
          out.DiffuseMax[v] = std::max(out.DiffuseMax[v], in.PointDiffuse[src]);
        }
        if (in.PointSpecular && std::isfinite(in.PointSpecular[src]))
        {
          out.SpecularMin[v] = std::min(out.SpecularMin[v], in.PointSpecular[src]);
          out.SpecularMax[v] = std::max(out.SpecularMax[v], in.PointSpecular[src]);
        }
      }
    }
  }
  auto fixRange = [](LargeVector<float>& lo, LargeVector<float>& hi, float uniform) {
    for (size_t v = 0; v < lo.size(); ++v)
    {
      if (lo[v] > hi[v])
      {
        lo[v] = hi[v] = uniform;
      }
    }
  };
  fixRange(out.DiffuseMin, out.DiffuseMax, in.UniformDiffuse);
  fixRange(out.SpecularMin, out.SpecularMax, in.UniformSpecular);
  out.Points.resize(3 * nv);
  out.Normals.resize(3 * nv);
  out.InputIds.assign(nv, -1);
  for (int64_t v = 0; v < nv; ++v)
  {
    uint32_t c[3];
    MortonDecode(vertexKey[v], c);
    const double len = std::sqrt(nsum[3 * v] * nsum[3 * v] + nsum[3 * v + 1] * nsum[3 * v + 1] +
      nsum[3 * v + 2] * nsum[3 * v + 2]);
    for (int a = 0; a < 3; ++a)
    {
      double u = sum[3 * v + a] / count[v];
      u = std::min(std::max(u, c[a] + 1e-6), c[a] + 1 - 1e-6);
      out.Points[3 * v + a] = out.Origin[a] + u * h;
      out.Normals[3 * v + a] = len > 0 ? static_cast<float>(nsum[3 * v + a] / len) : 0.0f;
    }
  }
}

/// One quad per crossed edge, counter-clockwise about the crossing's outward direction, split
/// along its shorter diagonal.
void MakeQuads(
  const LargeVector<Crossing>& crossings, const LargeVector<int64_t>& vertexOf, CloudMesh& out)
{
  out.Triangles.reserve(6 * crossings.size());
  const int ring[4] = { 0, 1, 3, 2 }; // slots in turn: (+p+q), (-p+q), (-p-q), (+p-q)
  auto dist2 = [&out](int64_t i, int64_t j) {
    double s = 0;
    for (int a = 0; a < 3; ++a)
    {
      const double d = out.Points[3 * i + a] - out.Points[3 * j + a];
      s += d * d;
    }
    return s;
  };
  for (size_t x = 0; x < crossings.size(); ++x)
  {
    int64_t quad[4];
    for (int i = 0; i < 4; ++i)
    {
      quad[i] = vertexOf[4 * x + ring[i]];
    }
    if (crossings[x].Sign < 0)
    {
      std::swap(quad[1], quad[3]);
    }
    const int64_t tris[2][3] = { { quad[0], quad[1], quad[2] }, { quad[0], quad[2], quad[3] } };
    const int64_t alt[2][3] = { { quad[0], quad[1], quad[3] }, { quad[1], quad[2], quad[3] } };
    const bool first = dist2(quad[0], quad[2]) <= dist2(quad[1], quad[3]);
    for (int t = 0; t < 2; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        out.Triangles.push_back(first ? tris[t][k] : alt[t][k]);
      }
    }
  }
}
} // namespace

bool MakeCloudMesh(const BuildInput& in, const BuildParameters& params, const ParallelFor& pfor,
  Reporter& report, CloudMesh& out, BuildResult& result)
{
  report.Phase("cloud scan", 0.0, 0.02);
  LargeVector<int64_t> finite;
  if (!PlaceCloud(in, params, out, result, finite))
  {
    return false;
  }
  report.Phase("cloud level", 0.02, 0.06);
  LargeVector<Item> items;
  const bool placed = ChooseCloudLevel(in, params, pfor, finite, out, result, items);
  LargeVector<int64_t>().swap(finite);
  if (!placed || !report(1.0))
  {
    return false;
  }
  report.Phase("cloud normals", 0.06, 0.2);
  Cloud C;
  MakeCloud(in, out, items, C);
  LargeVector<Item>().swap(items);
  if (!OrientNormals(in, out, pfor, report, C) || !report(1.0))
  {
    return false;
  }
  report.Phase("cloud distance", 0.2, 0.3);
  const LargeVector<Crossing> crossings = SignChanges(C, pfor, report);
  if (report.Aborted())
  {
    return false;
  }
  if (crossings.empty())
  {
    result.Error = "the point cloud gives no surface at level " + std::to_string(out.Level) +
      " (its signed distance never changes sign: too few points, or a finer level is needed)";
    return false;
  }
  // one vertex per cell next to a sign change (the four cells around each crossed edge), one
  // quad per crossed edge
  report.Phase("cloud contour", 0.3, 0.35);
  LargeVector<uint64_t> vertexKey;
  LargeVector<int64_t> vertexOf;
  CellsAroundCrossings(crossings, out.Level, pfor, vertexKey, vertexOf);
  PlaceVertices(in, C, crossings, vertexKey, vertexOf, out);
  MakeQuads(crossings, vertexOf, out);
  return report(1.0);
}

} // namespace build
} // namespace plod
