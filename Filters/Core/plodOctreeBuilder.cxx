// SPDX-License-Identifier: BSD-3-Clause
// Provenance:
// - octree, normal cones, shape error: Wakatsuki et al. 2003 (SRCC) §2-3.3, eq. (1)-(3);
// - vertex clustering: Rossignac & Borrel 1993; its view-dependent hierarchy: Luebke & Erikson
//   1997 (triangles stored at the node where they collapse);
// - quadric-optimal cluster vertices: Lindstrom 2000, "Out-of-core simplification of large
//   polygonal models" (plane quadrics of Garland & Heckbert 1997);
// - topology: Euler characteristic V - E + F of each cell's sub-mesh against its components.
#include "plodOctreeBuilder.h"

#include "plodBuildUtil.h"
#include "plodCloudSurface.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <utility>

namespace plod
{

double EstimateBuildMemory(int64_t points, int64_t triangles, int64_t nodes, bool cloud)
{
  // outputs: the schema's arrays (plodOctreeSchema.h), with one cluster per node (a lower
  // bound: a cell has a cluster per connected part). Work arrays at the peak (cluster
  // union-find, edge lists, incidence lists, the cell sums of the level above the leaves), per
  // item as counted from the build's own allocations; docs/benchmarks.md compares the estimate
  // with the measured peak.
  const double out = double(BytesPer(ArrayGroup::Node) + BytesPer(ArrayGroup::Cluster)) * nodes +
    double(BytesPer(ArrayGroup::Point)) * points +
    double(BytesPer(ArrayGroup::Triangle)) * triangles;
  const double work = 150.0 * nodes + 28.0 * points + 24.0 * triangles;
  // a cloud's own contouring first: items, normals and corner values per point
  const double cloudWork = cloud ? 120.0 * points : 0.0;
  return out + std::max(work, cloudWork);
}

namespace
{
/// Points per leaf the default level aims at (average). Leaves of 4 rather than 2 points halve
/// the nodes and the build's memory (302 to 152 bytes per triangle over its input on a 4M model)
/// at no measured cost in the images: an opened leaf draws the input's own triangles anyway.
constexpr int64_t LeafPoints = 4;
}

int ChooseFinestLevelFromCounts(const int64_t cells[MaxFinestLevel + 1], int64_t points, bool cloud)
{
  if (!cells || cells[0] != 1)
  {
    return -1;
  }
  for (int l = 1; l <= MaxFinestLevel; ++l)
  {
    // a cell has at most 8 children (compared by division: 8 * 8^20 overflows)
    if (cells[l] < cells[l - 1] || (cells[l] - 1) / 8 >= cells[l - 1])
    {
      return -1;
    }
  }
  if (points < cells[MaxFinestLevel])
  {
    return -1;
  }
  // an infinite limit never lowers the level
  return ChooseFinestLevel(cells, points, 0, cloud, std::numeric_limits<double>::infinity());
}

double LeastBuildMemory(int64_t points, int64_t triangles, bool cloud)
{
  return EstimateBuildMemory(points, triangles, 9, cloud);
}

double EstimateOctreeBytes(int64_t points, int64_t triangles)
{
  // leaves of LeafPoints points, and a full octree's 8/7 nodes per leaf
  const double nodes = double(points) / double(LeafPoints) * 8.0 / 7.0;
  return double(BytesPer(ArrayGroup::Node) + BytesPer(ArrayGroup::Cluster)) * nodes +
    double(BytesPer(ArrayGroup::Point)) * double(points) +
    double(BytesPer(ArrayGroup::Triangle)) * double(triangles);
}

int ChooseFinestLevel(const int64_t cells[MaxFinestLevel + 1], int64_t points, int64_t triangles,
  bool cloud, double memoryLimit, std::string* reason)
{
  auto nodesUpTo = [cells](int level) {
    int64_t n = 0;
    for (int l = 0; l <= level; ++l)
    {
      n += cells[l];
    }
    return n;
  };
  int level = 0;
  std::string why;
  if (cloud)
  {
    level = 1;
    for (int l = 1; l <= MaxFinestLevel; ++l)
    {
      if (cells[l] == 0 || double(points) / double(cells[l]) < 4.0)
      {
        break;
      }
      level = l;
    }
    why = "the deepest level whose occupied cells hold at least 4 points on average";
  }
  else
  {
    const int64_t distinct = cells[MaxFinestLevel];
    level = MaxFinestLevel;
    for (int l = 0; l <= MaxFinestLevel; ++l)
    {
      if (LeafPoints * cells[l] >= distinct)
      {
        level = l;
        break;
      }
    }
    if (distinct > 1)
    {
      level = std::max(level, 1);
    }
    why = "the shallowest level whose occupied cells number at least a quarter of the distinct "
          "points";
  }
  const int wanted = level;
  while (level > 0 && EstimateBuildMemory(points, triangles, nodesUpTo(level), cloud) > memoryLimit)
  {
    --level;
  }
  if (level < wanted)
  {
    why = "lowered from " + std::to_string(wanted) + " (" + why + ") to fit the memory limit";
  }
  if (reason)
  {
    *reason = why;
  }
  return level;
}

namespace
{
using namespace build;

/// Eigenvalues of a cell's quadric below this fraction of the largest are ignored (the cell's
/// mean point decides along them). 0.1 dropped the constraint of thin rims and open boundaries,
/// whose planes weigh little beside a cell's sheets; 0.01 keeps them (+0.3 to +0.7 dB on the
/// bunny and the thin-parts model; 0.001 gained nothing more and let noise move vertices).
constexpr double QEFTruncation = 0.01;
/// Weight of a boundary edge's constraint plane (times its squared length), as for QSlim's
/// boundary planes: it keeps an open surface's rim where it is.
constexpr double BoundaryWeight = 1.0;
constexpr int64_t Block = int64_t(1) << 20;

/// The mesh a build reads: the user's input, or the mesh contoured from a point cloud.
struct Source
{
  int64_t NumberOfPoints = 0;
  int64_t NumberOfTriangles = 0;
  const double* PointsD = nullptr;
  const float* PointsF = nullptr;
  const int64_t* TrianglesD = nullptr;
  const int32_t* TrianglesF = nullptr;
  const float* Normals = nullptr;
  const int64_t* InputIds = nullptr; // null: the point's own index
  const uint8_t* Ghost = nullptr;    // per point, non-zero: a ghost (meshes only)
  // material: per point (min and max arrays, possibly the same) or per triangle
  const float* DiffuseMin = nullptr;
  const float* DiffuseMax = nullptr;
  const float* SpecularMin = nullptr;
  const float* SpecularMax = nullptr;
  const float* TriangleDiffuse = nullptr;
  const float* TriangleSpecular = nullptr;
  float UniformDiffuse = 1, UniformSpecular = 0;
  // a cloud's mesh is built in the cloud's own root cube and at its level
  bool Forced = false;
  double ForcedOrigin[3] = { 0, 0, 0 };
  double ForcedEdge = 1;
  int ForcedLevel = 0;

  double X(int64_t i, int a) const
  {
    return this->PointsD ? this->PointsD[3 * i + a] : double(this->PointsF[3 * i + a]);
  }
  int64_t T(int64_t t, int k) const
  {
    return this->TrianglesD ? this->TrianglesD[3 * t + k] : int64_t(this->TrianglesF[3 * t + k]);
  }
};

/// Sums a cell passes to its parent.
struct CellSums
{
  double N[3] = { 0, 0, 0 };           // weighted normals
  double W = 0;                        // their weight
  double NN[6] = { 0, 0, 0, 0, 0, 0 }; // weighted second moments of the normals
  double P[3] = { 0, 0, 0 };           // point positions (root-edge units)
  double XX[6] = { 0, 0, 0, 0, 0, 0 }; // their second moments (xx xy xz yy yz zz)
  int64_t Count = 0;                   // points
  Quadric Q;

  void Add(const CellSums& o)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->N[a] += o.N[a];
      this->P[a] += o.P[a];
    }
    for (int a = 0; a < 6; ++a)
    {
      this->NN[a] += o.NN[a];
      this->XX[a] += o.XX[a];
    }
    this->W += o.W;
    this->Count += o.Count;
    this->Q.Add(o.Q);
  }
  void AddPoint(const double u[3])
  {
    for (int a = 0; a < 3; ++a)
      this->P[a] += u[a];
    this->XX[0] += u[0] * u[0];
    this->XX[1] += u[0] * u[1];
    this->XX[2] += u[0] * u[2];
    this->XX[3] += u[1] * u[1];
    this->XX[4] += u[1] * u[2];
    this->XX[5] += u[2] * u[2];
    ++this->Count;
  }
  /// A triangle of unit normal n at point u, weighted by w for the normal and q for the plane.
  void AddTriangle(const double n[3], const double u[3], double w, double q)
  {
    for (int a = 0; a < 3; ++a)
      this->N[a] += w * n[a];
    this->W += w;
    this->NN[0] += w * n[0] * n[0];
    this->NN[1] += w * n[0] * n[1];
    this->NN[2] += w * n[0] * n[2];
    this->NN[3] += w * n[1] * n[1];
    this->NN[4] += w * n[1] * n[2];
    this->NN[5] += w * n[2] * n[2];
    this->Q.AddPlane(n, u, q);
  }
};

/**
 * Shading normal of a cluster: the area-weighted mean normal; where the normals cancel (a thin
 * wall folded inside one cluster: the mean is under half the weight) the principal direction of
 * the normals, turned towards the mean, so that the surface drawn there is lit like one of its
 * sheets (two-sided lighting does the rest) rather than by a meaningless average.
 */
void ShadingNormal(const CellSums& s, float out[3]);

/// 2 sqrt(2 l2), l2 the middle eigenvalue of the covariance of `count` points with sums `s`.
double Thickness(const CellSums& s, int64_t count);

/// Running min/max of a reflectance.
struct Range
{
  float Min = std::numeric_limits<float>::max();
  float Max = -std::numeric_limits<float>::max();
  void Add(float v)
  {
    if (std::isfinite(v))
    {
      this->Min = std::min(this->Min, v);
      this->Max = std::max(this->Max, v);
    }
  }
  void Add(const float* minMax)
  {
    this->Add(minMax[0]);
    this->Add(minMax[1]);
  }
  void Store(float* out, float uniform) const
  {
    out[0] = this->Min <= this->Max ? this->Min : uniform;
    out[1] = this->Min <= this->Max ? this->Max : uniform;
  }
};

void ShadingNormal(const CellSums& s, float out[3])
{
  const double len = std::sqrt(Dot(s.N, s.N));
  double n[3] = { 0, 0, 1 };
  if (s.W > 0 && len >= 0.5 * s.W)
  {
    for (int a = 0; a < 3; ++a)
      n[a] = s.N[a] / len;
  }
  else if (s.W > 0)
  {
    Eigen::Matrix3d m;
    m << s.NN[0], s.NN[1], s.NN[2], s.NN[1], s.NN[3], s.NN[4], s.NN[2], s.NN[4], s.NN[5];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(m);
    const Eigen::Vector3d e = eig.eigenvectors().col(2);
    double sign = e[0] * s.N[0] + e[1] * s.N[1] + e[2] * s.N[2];
    if (sign == 0)
    {
      // exactly cancelling: a fixed choice, the largest component positive
      const int big = std::abs(e[0]) >= std::abs(e[1]) ? (std::abs(e[0]) >= std::abs(e[2]) ? 0 : 2)
                                                       : (std::abs(e[1]) >= std::abs(e[2]) ? 1 : 2);
      sign = e[big];
    }
    for (int a = 0; a < 3; ++a)
      n[a] = sign < 0 ? -e[a] : e[a];
    if (!std::isfinite(n[0] + n[1] + n[2]))
    {
      n[0] = n[1] = 0;
      n[2] = 1;
    }
  }
  for (int a = 0; a < 3; ++a)
    out[a] = static_cast<float>(n[a]);
}

double Thickness(const CellSums& s, int64_t count)
{
  if (count < 3)
  {
    return 0.0;
  }
  const double n = double(count);
  const double m[3] = { s.P[0] / n, s.P[1] / n, s.P[2] / n };
  Eigen::Matrix3d c;
  c << s.XX[0] / n - m[0] * m[0], s.XX[1] / n - m[0] * m[1], s.XX[2] / n - m[0] * m[2],
    s.XX[1] / n - m[0] * m[1], s.XX[3] / n - m[1] * m[1], s.XX[4] / n - m[1] * m[2],
    s.XX[2] / n - m[0] * m[2], s.XX[4] / n - m[1] * m[2], s.XX[5] / n - m[2] * m[2];
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(c, Eigen::EigenvaluesOnly);
  const double middle = std::max(0.0, eig.eigenvalues()[1]);
  return 2.0 * std::sqrt(2.0 * middle);
}

class MeshBuild
{
public:
  MeshBuild(const Source& source, const BuildParameters& parameters, const Allocator& allocate,
    const ParallelFor& pfor, Reporter& report, BuildResult& result)
    : S(source)
    , Params(parameters)
    , Allocate(allocate)
    , For(pfor)
    , Report(report)
    , R(result)
  {
  }

  bool Run()
  {
    return this->Scan() && this->PlaceRoot() && this->SortPoints() && this->ChooseLevel() &&
      this->MakeTree() && this->StoreSurface() && this->MakeIncidence() && this->ComputeNormals() &&
      this->MakeEdges() && this->NoteCoincidentPoints() && this->MakeClusters() &&
      this->FindPassingTriangles() && this->ComputeCells() && this->TightenCones() &&
      this->ComputeShapeErrors() && this->Finish();
  }

private:
  bool Scan();
  bool PlaceRoot();
  bool SortPoints();
  bool ChooseLevel();
  bool MakeTree();
  bool StoreSurface();
  bool MakeIncidence();
  bool ComputeNormals();
  bool MakeEdges();
  /// MakeEdges' steps.
  bool GroupEdgeUses();
  void AddBoundaryPlanes(
    int32_t a, int32_t b, LargeVector<std::pair<int32_t, Quadric>>& planes) const;
  void KeepBoundaryPlanes(LargeVector<std::pair<int32_t, Quadric>>& planes);
  bool NoteCoincidentPoints();
  bool FindPassingTriangles();
  bool ComputeCells();
  // the steps of ComputeCells
  bool ComputeLeavesAndParents(LargeVector<CellSums>& child);
  bool ComputeUpperCells(LargeVector<CellSums>& child);
  /// A leaf's cluster sums (into `sums`), vertices, normals, cone and material ranges.
  void LeafCell(
    int64_t leaf, LargeVector<CellSums>& sums, LargeVector<std::array<double, 3>>& normals);
  /// An inner cell at level l (index i in the level), its clusters' sums gathered from its
  /// children: its vertices, normals, cone and material ranges.
  void InnerCell(int64_t node, int l, int64_t i, CellSums* sums, int clusters,
    LargeVector<std::array<double, 3>>& normals);
  /// A node's own quantities (vertex, thickness) and its clusters' vertices and normals from
  /// its clusters' sums; `total` receives their sum.
  void FinishNode(
    int64_t node, int level, uint64_t key, const CellSums* sums, int count, CellSums& total);
  void StoreCone(int64_t node, const double axis[3], double theta, const Range& d, const Range& sp);
  /// The passing triangles of `node` (FindPassingTriangles), and their normals and material.
  std::pair<LargeVector<std::pair<int32_t, int32_t>>::const_iterator,
    LargeVector<std::pair<int32_t, int32_t>>::const_iterator>
  PassRange(int64_t node) const;
  void AddPassing(
    int64_t node, LargeVector<std::array<double, 3>>& normals, Range& d, Range& sp) const;
  /// The largest angle from `axis` to the normals.
  static double Widest(const double axis[3], const LargeVector<std::array<double, 3>>& normals);
  bool ComputeShapeErrors();
  bool MakeClusters();
  /// MakeClusters' steps.
  struct ClusterLevels;
  bool EdgesDeepestFirst(
    LargeVector<std::pair<int32_t, int32_t>>& edges, LargeVector<int64_t>& levelStart);
  bool UniteLevelByLevel(const LargeVector<std::pair<int32_t, int32_t>>& edges,
    const LargeVector<int64_t>& levelStart, LargeVector<int64_t>& delta, ClusterLevels& levels);
  bool NumberClusters(const ClusterLevels& levels);
  void MarkTopology(LargeVector<int64_t>& delta);
  bool TightenCones();
  bool Finish();

  bool Fail(const std::string& why)
  {
    this->R.Error = why;
    return false;
  }
  /// In a long sequential loop at iteration i of n: every 2^20 iterations, reports progress
  /// (from..to of the phase) and returns false when the user aborted.
  bool Tick(int64_t i, int64_t n, double from, double to)
  {
    if ((i & ((int64_t(1) << 20) - 1)) != 0 || n <= 0)
    {
      return true;
    }
    return this->Report(from + (to - from) * double(i) / double(n));
  }
  /// Position of surface point `p` in root-edge units from the root origin.
  void Position(int64_t p, double u[3]) const
  {
    for (int a = 0; a < 3; ++a)
    {
      u[a] = double(this->Out.Points[3 * p + a]) / this->Edge;
    }
  }
  /// Unit normal and area (root-edge units) of surface triangle `t`; area 0 when degenerate.
  double Face(int64_t t, double n[3]) const
  {
    const int32_t* c = &this->Out.Triangles[3 * t];
    double a[3], b[3], d[3];
    this->Position(c[0], a);
    this->Position(c[1], b);
    this->Position(c[2], d);
    const double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double e2[3] = { d[0] - a[0], d[1] - a[1], d[2] - a[2] };
    Cross(e1, e2, n);
    const double len = std::sqrt(Dot(n, n));
    if (!(len > 0) || !std::isfinite(len))
    {
      n[0] = n[1] = n[2] = 0;
      return 0;
    }
    for (int i = 0; i < 3; ++i)
    {
      n[i] /= len;
    }
    return 0.5 * len;
  }
  uint64_t NodeKey(int64_t node) const
  {
    const int l = this->Out.Level[node];
    return this->Keys[l][node - this->Offset[l]];
  }
  /// Lower corner (root-edge units) and edge of the cell with Morton key `key` at `level`.
  static void KeyBox(uint64_t key, int level, double lo[3], double& h)
  {
    uint32_t c[3];
    MortonDecode(key, c);
    h = std::ldexp(1.0, -level);
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = c[a] * h;
    }
  }
  int64_t Ancestor(int64_t node, int level) const
  {
    while (this->Out.Level[node] > level)
    {
      node = this->Out.Parent[node];
    }
    return node;
  }
  int64_t PointEnd(int64_t node) const
  {
    return (node + 1 < this->Nodes && this->Out.Level[node + 1] == this->Out.Level[node])
      ? this->Out.FirstPoint[node + 1]
      : this->Points;
  }
  uint64_t LeafKey(int64_t point) const
  {
    return this->Keys[this->L][this->Out.PointLeaf[point] - this->Offset[this->L]];
  }
  /// Lowest node holding all three corners of triangle `t` (surface indices).
  int64_t Holder(int64_t t) const
  {
    const int32_t* c = &this->Out.Triangles[3 * t];
    const uint64_t ka = this->LeafKey(c[0]), kb = this->LeafKey(c[1]), kc = this->LeafKey(c[2]);
    const int level = std::min(
      { CommonLevel(ka, kb, this->L), CommonLevel(kb, kc, this->L), CommonLevel(ka, kc, this->L) });
    return this->Ancestor(this->Out.PointLeaf[c[0]], level);
  }
  void Material(int64_t p, Range& d, Range& s) const;
  void TriangleMaterial(int64_t t, Range& d, Range& s) const;
  void Descend(int64_t t, LargeVector<std::pair<int32_t, int32_t>>& out) const;
  /// Descend's two ways: the few finest cells of the triangle's box (false when there are more
  /// than 27), or a walk down from its holder. `p`: its corners, `lo`, `hi`: its box, `key`:
  /// its corners' leaf keys.
  bool RecordByFinestCells(int64_t t, const double p[3][3], const double lo[3], const double hi[3],
    const uint64_t key[3], LargeVector<std::pair<int32_t, int32_t>>& out) const;
  void RecordByDescent(int64_t t, const double p[3][3], const double lo[3], const double hi[3],
    const uint64_t key[3], LargeVector<std::pair<int32_t, int32_t>>& out) const;
  void PlaceVertex(const CellSums& s, uint64_t key, int level, float* out) const;

  const Source& S;
  const BuildParameters& Params;
  const Allocator& Allocate;
  const ParallelFor& For;
  Reporter& Report;
  BuildResult& R;

  LargeVector<uint8_t> Keep; // per input triangle
  LargeVector<uint8_t> Used; // per input point
  int64_t Kept = 0, UsedPoints = 0;
  double Lo[3] = { 0, 0, 0 }, Hi[3] = { 0, 0, 0 };
  double Origin[3] = { 0, 0, 0 };
  double Edge = 1;
  int L = 0;
  LargeVector<int64_t> Order;  // surface point -> input point
  LargeVector<uint64_t> Key21; // surface point -> Morton key at level 21
  LargeVector<int32_t> Rank;   // input point -> surface point, -1 when unused
  int64_t Cells[MaxFinestLevel + 1] = {};
  LargeVector<LargeVector<uint64_t>> Keys; // per level, sorted
  LargeVector<int64_t> Offset;             // first node of each level, then the total
  OctreeArrays Out;
  int64_t Nodes = 0, Points = 0, Tris = 0;
  LargeVector<int64_t> TriSource; // surface triangle -> input triangle (triangle material)
  LargeVector<int64_t> IncStart;  // incidence: the triangles of each point
  LargeVector<int32_t> Inc;
  LargeVector<std::pair<int32_t, int32_t>> Pass; // (node, triangle) meeting without a corner
  LargeVector<int64_t> EdgeStart; // unique edges: the higher ends of each point's edges
  LargeVector<int32_t> EdgeTo;    // sorted per point; repeated once per use
  LargeVector<std::pair<int32_t, Quadric>> BoundaryQuadric; // per point, sorted
  LargeVector<int64_t> ClusterOffset; // first cluster of each level, then the total
};

bool MeshBuild::Scan()
{
  this->Report.Phase("scan", 0.0, 0.05);
  const int64_t np = this->S.NumberOfPoints, nt = this->S.NumberOfTriangles;
  LargeVector<uint8_t> finite(np);
  this->For(np, 65536, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i)
    {
      finite[i] = std::isfinite(this->S.X(i, 0)) && std::isfinite(this->S.X(i, 1)) &&
        std::isfinite(this->S.X(i, 2));
    }
  });
  this->Keep.assign(nt, 0);
  this->Used.assign(np, 0);
  int64_t invalid = 0, degenerate = 0;
  for (int64_t start = 0; start < nt; start += Block)
  {
    for (int64_t t = start, end = std::min(nt, start + Block); t < end; ++t)
    {
      const int64_t a = this->S.T(t, 0), b = this->S.T(t, 1), c = this->S.T(t, 2);
      if (a < 0 || b < 0 || c < 0 || a >= np || b >= np || c >= np || !finite[a] || !finite[b] ||
        !finite[c])
      {
        ++invalid;
        continue;
      }
      if (a == b || b == c || a == c)
      {
        ++degenerate;
        continue;
      }
      this->Keep[t] = 1;
      this->Used[a] = this->Used[b] = this->Used[c] = 1;
      ++this->Kept;
    }
    if (!this->Report(double(std::min(nt, start + Block)) / double(nt)))
    {
      return false;
    }
  }
  this->R.NumberOfInvalidTriangles = invalid;
  this->R.NumberOfDegenerateTriangles = degenerate;
  int64_t nonFinite = 0;
  for (int64_t i = 0; i < np; ++i)
  {
    nonFinite += finite[i] ? 0 : 1;
  }
  if (!this->S.Forced)
  {
    // a cloud's mesh has only finite points: keep the count of the cloud's own (MakeCloudMesh)
    this->R.NumberOfNonFinitePoints = nonFinite;
  }
  if (invalid)
  {
    this->R.Warnings.push_back(std::to_string(invalid) +
      " triangle(s) skipped: a point index outside [0, " + std::to_string(np) +
      ") or a point with NaN or infinite coordinates");
  }
  if (degenerate)
  {
    this->R.Warnings.push_back(
      std::to_string(degenerate) + " triangle(s) skipped: the same point used twice");
  }
  if (this->Kept == 0)
  {
    return this->Fail("no usable triangle among " + std::to_string(nt) + " (" +
      std::to_string(invalid) + " with an index out of range or a non-finite corner, " +
      std::to_string(degenerate) + " repeating a point)");
  }
  if (this->Kept > MaxIndex)
  {
    return this->Fail("too many triangles (" + std::to_string(this->Kept) + ", at most " +
      std::to_string(MaxIndex) + ")");
  }
  for (int a = 0; a < 3; ++a)
  {
    this->Lo[a] = std::numeric_limits<double>::max();
    this->Hi[a] = -std::numeric_limits<double>::max();
  }
  for (int64_t i = 0; i < np; ++i)
  {
    if (this->Used[i])
    {
      ++this->UsedPoints;
      for (int a = 0; a < 3; ++a)
      {
        this->Lo[a] = std::min(this->Lo[a], this->S.X(i, a));
        this->Hi[a] = std::max(this->Hi[a], this->S.X(i, a));
      }
    }
  }
  if (this->UsedPoints > MaxIndex)
  {
    return this->Fail("too many points (" + std::to_string(this->UsedPoints) + ", at most " +
      std::to_string(MaxIndex) + ")");
  }
  return true;
}

bool MeshBuild::PlaceRoot()
{
  if (this->S.Forced)
  {
    std::copy(this->S.ForcedOrigin, this->S.ForcedOrigin + 3, this->Origin);
    this->Edge = this->S.ForcedEdge;
  }
  else if (this->Params.HasRootCube)
  {
    // the caller's cube (validated by BuildOctree): every point the build uses must be inside,
    // since a clamped point would land in a cell that does not hold it
    std::copy(this->Params.RootOrigin, this->Params.RootOrigin + 3, this->Origin);
    this->Edge = this->Params.RootEdge;
    if (!InsideRootCube(this->Lo, this->Origin, this->Edge) ||
      !InsideRootCube(this->Hi, this->Origin, this->Edge))
    {
      for (int64_t i = 0; i < this->S.NumberOfPoints; ++i)
      {
        const double x[3] = { this->S.X(i, 0), this->S.X(i, 1), this->S.X(i, 2) };
        if (this->Used[i] && !InsideRootCube(x, this->Origin, this->Edge))
        {
          return this->Fail(PointOutsideRootCube(i, x, this->Origin, this->Edge));
        }
      }
    }
  }
  else
  {
    std::string why;
    if (!PlaceRootCube(this->Lo, this->Hi, this->Origin, this->Edge, &why))
    {
      return this->Fail(why);
    }
  }
  std::copy(this->Origin, this->Origin + 3, this->R.Origin);
  this->R.RootEdge = this->Edge;
  return true;
}

bool MeshBuild::SortPoints()
{
  this->Report.Phase("sort points", 0.05, 0.15);
  const int64_t np = this->S.NumberOfPoints;
  LargeVector<Item> items;
  items.reserve(this->UsedPoints);
  const CellQuantizer grid(this->Origin, this->Edge);
  for (int64_t i = 0; i < np; ++i)
  {
    if (this->Used[i])
    {
      items.push_back({ grid.Key(this->S.X(i, 0), this->S.X(i, 1), this->S.X(i, 2)), uint64_t(i) });
    }
  }
  LargeVector<uint8_t>().swap(this->Used);
  if (!this->Report(0.2))
  {
    return false;
  }
  RadixSort(items, 3 * MaxFinestLevel, this->For);
  if (!this->Report(0.8))
  {
    return false;
  }
  this->Points = this->UsedPoints;
  this->Order.resize(this->Points);
  this->Key21.resize(this->Points);
  this->Rank.assign(np, -1);
  for (int64_t r = 0; r < this->Points; ++r)
  {
    this->Order[r] = static_cast<int64_t>(items[r].Ref);
    this->Key21[r] = items[r].Key;
    this->Rank[this->Order[r]] = static_cast<int32_t>(r);
  }
  CountOccupiedCells(
    this->Points, [this](int64_t r) { return this->Key21[r]; }, this->Cells);
  return true;
}

/// A size in MB for messages, to three significant digits (a tiny limit reads 0.0001 MB, not 0).
std::string Megabytes(double bytes)
{
  char text[32];
  const double mb = bytes / 1e6;
  std::snprintf(text, sizeof(text), mb >= 100 ? "%.0f" : "%.3g", mb);
  return text;
}

bool MeshBuild::ChooseLevel()
{
  auto nodesUpTo = [this](int level) {
    int64_t n = 0;
    for (int l = 0; l <= level; ++l)
    {
      n += this->Cells[l];
    }
    return n;
  };
  if (this->S.Forced)
  {
    this->L = this->S.ForcedLevel; // MakeCloudMesh chose it and set LevelReason
    // the limit holds for the cloud's surface too, as for a mesh (whatever chose the level)
    const double need = EstimateBuildMemory(this->Points, this->Kept, nodesUpTo(this->L), false);
    if (need > this->Params.MemoryLimit)
    {
      return this->Fail("the point cloud's surface at level " + std::to_string(this->L) +
        " would need about " + Megabytes(need) + " MB, above the memory limit of " +
        Megabytes(this->Params.MemoryLimit) + " MB; lower the finest level or raise the limit");
    }
  }
  else if (this->Params.FinestLevel >= 0)
  {
    this->L = this->Params.FinestLevel;
    this->R.LevelReason = "set by the user";
    const double need = EstimateBuildMemory(this->Points, this->Kept, nodesUpTo(this->L), false);
    if (need > this->Params.MemoryLimit)
    {
      return this->Fail("finest level " + std::to_string(this->L) + " would need about " +
        Megabytes(need) + " MB, above the memory limit of " + Megabytes(this->Params.MemoryLimit) +
        " MB; lower the finest level or raise the limit");
    }
  }
  else
  {
    std::string reason;
    this->L = ChooseFinestLevel(
      this->Cells, this->Points, this->Kept, false, this->Params.MemoryLimit, &reason);
    this->R.LevelReason = reason;
    const double need = EstimateBuildMemory(this->Points, this->Kept, nodesUpTo(this->L), false);
    if (need > this->Params.MemoryLimit)
    {
      return this->Fail("the model needs about " + Megabytes(need) + " MB even at level " +
        std::to_string(this->L) + ", above the memory limit of " +
        Megabytes(this->Params.MemoryLimit) + " MB; raise the limit");
    }
    if (reason.rfind("lowered", 0) == 0)
    {
      this->R.Warnings.push_back("finest level " + std::to_string(this->L) + ": " + reason +
        " of " + Megabytes(this->Params.MemoryLimit) +
        " MB; cells coarser than the input's detail hold several points each, and opening a "
        "leaf then draws them all at once");
    }
  }
  this->R.FinestLevel = this->L;
  this->R.EstimatedBytes = EstimateBuildMemory(this->Points, this->Kept, nodesUpTo(this->L), false);
  return true;
}

bool MeshBuild::MakeTree()
{
  this->Report.Phase("tree", 0.15, 0.2);
  const int L = this->L;
  this->Keys.assign(L + 1, {});
  LargeVector<int64_t> leafStart;
  const int shift = 3 * (MaxFinestLevel - L);
  for (int64_t r = 0; r < this->Points; ++r)
  {
    const uint64_t k = this->Key21[r] >> shift;
    if (r == 0 || k != this->Keys[L].back())
    {
      this->Keys[L].push_back(k);
      leafStart.push_back(r);
    }
  }
  LargeVector<uint64_t>().swap(this->Key21);
  for (int l = L - 1; l >= 0; --l)
  {
    for (uint64_t k : this->Keys[l + 1])
    {
      if (this->Keys[l].empty() || this->Keys[l].back() != (k >> 3))
      {
        this->Keys[l].push_back(k >> 3);
      }
    }
  }
  this->Offset.assign(L + 2, 0);
  for (int l = 0; l <= L; ++l)
  {
    this->Offset[l + 1] = this->Offset[l] + static_cast<int64_t>(this->Keys[l].size());
  }
  this->Nodes = this->Offset[L + 1];
  if (this->Nodes > MaxIndex)
  {
    return this->Fail("too many nodes (" + std::to_string(this->Nodes) +
      ") for 32-bit node indices; lower the finest level");
  }
  this->Tris = this->Kept;
  this->Out = this->Allocate.Nodes(this->Nodes, this->Points, this->Tris);
  if (!this->Out.Level || !this->Out.Points || !this->Out.Triangles)
  {
    return this->Fail("could not allocate the octree arrays");
  }
  if (this->S.Ghost)
  {
    if (this->Allocate.PointGhost)
    {
      this->Allocate.PointGhost(this->Points, this->Out);
    }
    if (!this->Out.PointGhost)
    {
      return this->Fail("the input has ghost flags but the allocator gives no array for them");
    }
  }
  this->R.NumberOfNodes = this->Nodes;
  this->R.NumberOfPoints = this->Points;
  this->R.NumberOfTriangles = this->Tris;
  OctreeArrays& o = this->Out;
  for (int l = 0; l <= L; ++l)
  {
    const int64_t n = static_cast<int64_t>(this->Keys[l].size());
    const int64_t base = this->Offset[l];
    std::fill(o.Level + base, o.Level + base + n, static_cast<uint8_t>(l));
    std::fill(o.FirstChild + base, o.FirstChild + base + n, -1);
    std::fill(o.ChildMask + base, o.ChildMask + base + n, 0);
    if (l == 0)
    {
      o.Parent[0] = -1;
      continue;
    }
    int64_t parent = -1;
    uint64_t parentKey = ~uint64_t(0);
    for (int64_t i = 0; i < n; ++i)
    {
      const uint64_t k = this->Keys[l][i];
      if ((k >> 3) != parentKey)
      {
        parentKey = k >> 3;
        ++parent;
        o.FirstChild[this->Offset[l - 1] + parent] = static_cast<int32_t>(base + i);
      }
      o.Parent[base + i] = static_cast<int32_t>(this->Offset[l - 1] + parent);
      o.ChildMask[this->Offset[l - 1] + parent] |= static_cast<uint8_t>(1u << (k & 7));
    }
  }
  const int64_t leaves = static_cast<int64_t>(leafStart.size());
  leafStart.push_back(this->Points);
  for (int64_t i = 0; i < leaves; ++i)
  {
    const int64_t leaf = this->Offset[L] + i;
    o.FirstPoint[leaf] = static_cast<int32_t>(leafStart[i]);
    for (int64_t r = leafStart[i]; r < leafStart[i + 1]; ++r)
    {
      o.PointLeaf[r] = static_cast<int32_t>(leaf);
    }
  }
  for (int64_t n = this->Offset[L] - 1; n >= 0; --n)
  {
    o.FirstPoint[n] = o.FirstPoint[o.FirstChild[n]];
  }
  return true;
}

bool MeshBuild::StoreSurface()
{
  this->Report.Phase("surface", 0.2, 0.3);
  OctreeArrays& o = this->Out;
  this->For(this->Points, 65536, [&](int64_t b, int64_t e) {
    for (int64_t r = b; r < e; ++r)
    {
      const int64_t i = this->Order[r];
      for (int a = 0; a < 3; ++a)
      {
        o.Points[3 * r + a] = static_cast<float>(this->S.X(i, a) - this->Origin[a]);
      }
      o.InputPointId[r] = this->S.InputIds ? this->S.InputIds[i] : i;
      if (o.PointGhost)
      {
        // each surface point keeps its input point's flag (and nothing else reads it here)
        o.PointGhost[r] = this->S.Ghost[i] != 0 ? 1 : 0;
      }
    }
  });
  if (o.PointGhost)
  {
    this->R.NumberOfGhostPoints = std::count(o.PointGhost, o.PointGhost + this->Points, 1);
  }
  // owner of each triangle: the deepest of the three pairwise common ancestors of its corners
  const int64_t nt = this->S.NumberOfTriangles;
  LargeVector<int32_t> owner(nt, -1);
  const bool ok = BlockedFor(
    nt, 16384, Block, this->For,
    [&](int64_t b, int64_t e) {
      for (int64_t t = b; t < e; ++t)
      {
        if (!this->Keep[t])
        {
          continue;
        }
        int32_t r[3];
        uint64_t k[3];
        for (int c = 0; c < 3; ++c)
        {
          r[c] = this->Rank[this->S.T(t, c)];
          k[c] = this->LeafKey(r[c]);
        }
        const int ab = CommonLevel(k[0], k[1], this->L);
        const int bc = CommonLevel(k[1], k[2], this->L);
        const int ca = CommonLevel(k[2], k[0], this->L);
        const int deepest = std::max({ ab, bc, ca });
        const int32_t from = (deepest == ab || deepest == ca) ? r[0] : r[1];
        owner[t] = static_cast<int32_t>(this->Ancestor(o.PointLeaf[from], deepest));
      }
    },
    [&](double f) { return this->Report(0.7 * f); });
  if (!ok)
  {
    return false;
  }
  // counting sort by owner; FirstTriangle counts, then holds starts
  std::fill(o.FirstTriangle, o.FirstTriangle + this->Nodes, 0);
  for (int64_t t = 0; t < nt; ++t)
  {
    if (!this->Tick(t, nt, 0.7, 0.75))
    {
      return false;
    }
    if (owner[t] >= 0)
    {
      ++o.FirstTriangle[owner[t]];
    }
  }
  int64_t sum = 0;
  for (int64_t n = 0; n < this->Nodes; ++n)
  {
    const int64_t c = o.FirstTriangle[n];
    o.FirstTriangle[n] = sum;
    sum += c;
  }
  const bool triangleMaterial = this->S.TriangleDiffuse || this->S.TriangleSpecular;
  if (triangleMaterial)
  {
    this->TriSource.resize(this->Tris);
  }
  for (int64_t t = 0; t < nt; ++t)
  {
    if (!this->Tick(t, nt, 0.75, 1.0))
    {
      return false;
    }
    if (owner[t] < 0)
    {
      continue;
    }
    const int64_t pos = o.FirstTriangle[owner[t]]++;
    for (int c = 0; c < 3; ++c)
    {
      o.Triangles[3 * pos + c] = this->Rank[this->S.T(t, c)];
    }
    if (triangleMaterial)
    {
      this->TriSource[pos] = t;
    }
  }
  // the counters now hold each node's end: shift them back to starts
  for (int64_t n = this->Nodes - 1; n > 0; --n)
  {
    o.FirstTriangle[n] = o.FirstTriangle[n - 1];
  }
  o.FirstTriangle[0] = 0;
  LargeVector<int32_t>().swap(this->Rank);
  LargeVector<uint8_t>().swap(this->Keep);
  return this->Report(1.0);
}

bool MeshBuild::MakeIncidence()
{
  this->Report.Phase("incidence", 0.3, 0.35);
  this->IncStart.assign(this->Points + 1, 0);
  const int32_t* tri = this->Out.Triangles;
  for (int64_t i = 0; i < 3 * this->Tris; ++i)
  {
    if (!this->Tick(i, 3 * this->Tris, 0.0, 0.5))
    {
      return false;
    }
    ++this->IncStart[tri[i] + 1];
  }
  for (int64_t p = 0; p < this->Points; ++p)
  {
    this->IncStart[p + 1] += this->IncStart[p];
  }
  this->Inc.resize(3 * this->Tris);
  LargeVector<int64_t> cursor(this->IncStart.begin(), this->IncStart.end() - 1);
  for (int64_t t = 0; t < this->Tris; ++t)
  {
    if (!this->Tick(t, this->Tris, 0.5, 1.0))
    {
      return false;
    }
    for (int c = 0; c < 3; ++c)
    {
      this->Inc[cursor[tri[3 * t + c]]++] = static_cast<int32_t>(t);
    }
  }
  return this->Report(1.0);
}

bool MeshBuild::ComputeNormals()
{
  this->Report.Phase("normals", 0.35, 0.4);
  float* normals = this->Out.Normals;
  return BlockedFor(
    this->Points, 8192, Block, this->For,
    [&](int64_t b, int64_t e) {
      for (int64_t p = b; p < e; ++p)
      {
        double n[3] = { 0, 0, 0 };
        bool done = false;
        if (this->S.Normals)
        {
          const float* given = this->S.Normals + 3 * this->Order[p];
          const double g[3] = { given[0], given[1], given[2] };
          const double len = std::sqrt(Dot(g, g));
          if (len > 0 && std::isfinite(len))
          {
            for (int a = 0; a < 3; ++a)
              n[a] = g[a] / len;
            done = true;
          }
        }
        if (!done)
        {
          // as vtkPolyDataNormals without splitting: the sum of the unit triangle normals
          for (int64_t i = this->IncStart[p]; i < this->IncStart[p + 1]; ++i)
          {
            double f[3];
            if (this->Face(this->Inc[i], f) > 0)
            {
              for (int a = 0; a < 3; ++a)
                n[a] += f[a];
            }
          }
          const double len = std::sqrt(Dot(n, n));
          if (len > 0 && std::isfinite(len))
          {
            for (int a = 0; a < 3; ++a)
              n[a] /= len;
          }
          else
          {
            n[0] = n[1] = 0;
            n[2] = 1;
          }
        }
        for (int a = 0; a < 3; ++a)
        {
          normals[3 * p + a] = static_cast<float>(n[a]);
        }
      }
    },
    [&](double f) { return this->Report(f); });
}

namespace
{
/// The other end of an edge use stored by MakeEdges (a downward use is stored complemented).
inline int32_t EdgeEnd(int32_t stored)
{
  return stored < 0 ? ~stored : stored;
}
}

bool MeshBuild::MakeEdges()
{
  this->Report.Phase("edges", 0.4, 0.45);
  OctreeArrays& o = this->Out;
  if (!this->GroupEdgeUses())
  {
    return false;
  }
  LargeVector<int64_t>& start = this->EdgeStart;
  LargeVector<int32_t>& to = this->EdgeTo;
  // uses of each edge: once on the boundary, twice inside a manifold. A boundary edge adds to
  // the cells of its two ends the plane through it perpendicular to its triangle, so that
  // representatives stay on an open surface's rim; their leaves are flagged.
  std::fill(o.Flags, o.Flags + this->Nodes, 0);
  LargeVector<std::pair<int32_t, Quadric>> planes;
  for (int64_t p = 0; p < this->Points; ++p)
  {
    if (!this->Tick(p, this->Points, 0.5, 0.9))
    {
      return false;
    }
    for (int64_t i = start[p]; i < start[p + 1];)
    {
      int64_t j = i + 1;
      while (j < start[p + 1] && EdgeEnd(to[j]) == EdgeEnd(to[i]))
      {
        ++j;
      }
      this->R.NumberOfNonManifoldEdges += (j - i > 2) ? 1 : 0;
      // two triangles that agree on their orientation use their shared edge in opposite
      // directions (the upward use sorts first)
      this->R.NumberOfMisorientedEdges += (j - i == 2 && (to[i] < 0) == (to[i + 1] < 0)) ? 1 : 0;
      if (j - i == 1)
      {
        ++this->R.NumberOfBoundaryEdges;
        const int32_t a = static_cast<int32_t>(p), b = EdgeEnd(to[i]);
        this->AddBoundaryPlanes(a, b, planes);
        o.Flags[o.PointLeaf[a]] |= NodeBoundary;
        o.Flags[o.PointLeaf[b]] |= NodeBoundary;
      }
      i = j;
    }
  }
  // the later phases read the plain ends
  for (int32_t& x : to)
  {
    x = EdgeEnd(x);
  }
  for (int64_t n = this->Nodes - 1; n > 0; --n)
  {
    o.Flags[o.Parent[n]] |= o.Flags[n] & NodeBoundary;
  }
  this->KeepBoundaryPlanes(planes);
  return this->Report(1.0);
}

/// Every edge use (EdgeStart, EdgeTo), grouped by its lower end point and sorted by the other
/// end, upward uses before downward ones (a use from the higher end down is stored as the
/// complement of the higher end, so that the orientation of every use is known).
bool MeshBuild::GroupEdgeUses()
{
  const OctreeArrays& o = this->Out;
  LargeVector<int64_t>& start = this->EdgeStart;
  LargeVector<int32_t>& to = this->EdgeTo;
  start.assign(this->Points + 1, 0);
  for (int64_t t = 0; t < this->Tris; ++t)
  {
    if (!this->Tick(t, this->Tris, 0.0, 0.2))
    {
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      const int32_t a = o.Triangles[3 * t + k], b = o.Triangles[3 * t + (k + 1) % 3];
      ++start[std::min(a, b) + 1];
    }
  }
  for (int64_t p = 0; p < this->Points; ++p)
  {
    start[p + 1] += start[p];
  }
  to.resize(3 * this->Tris);
  LargeVector<int64_t> cursor(start.begin(), start.end() - 1);
  for (int64_t t = 0; t < this->Tris; ++t)
  {
    if (!this->Tick(t, this->Tris, 0.2, 0.4))
    {
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      const int32_t a = o.Triangles[3 * t + k], b = o.Triangles[3 * t + (k + 1) % 3];
      to[cursor[std::min(a, b)]++] = a < b ? b : ~a;
    }
  }
  this->For(this->Points, 4096, [&](int64_t b, int64_t e) {
    for (int64_t p = b; p < e; ++p)
    {
      std::sort(to.begin() + start[p], to.begin() + start[p + 1], [](int32_t x, int32_t y) {
        return EdgeEnd(x) != EdgeEnd(y) ? EdgeEnd(x) < EdgeEnd(y) : x > y;
      });
    }
  });
  return this->Report(0.5);
}

/// The plane through boundary edge a-b perpendicular to its triangle, weighted by the edge's
/// squared length, for the cells of both ends. The edge's triangle: among the triangles of
/// whichever end has fewer, the one holding the other end (a hub of d boundary spokes then
/// costs d, not d^2). A degenerate triangle or edge adds nothing.
void MeshBuild::AddBoundaryPlanes(
  int32_t a, int32_t b, LargeVector<std::pair<int32_t, Quadric>>& planes) const
{
  const OctreeArrays& o = this->Out;
  int64_t tri = -1;
  const bool fromA =
    this->IncStart[a + 1] - this->IncStart[a] <= this->IncStart[b + 1] - this->IncStart[b];
  const int32_t from = fromA ? a : b, other = fromA ? b : a;
  for (int64_t k = this->IncStart[from]; k < this->IncStart[from + 1] && tri < 0; ++k)
  {
    const int32_t* c = &o.Triangles[3 * this->Inc[k]];
    if (c[0] == other || c[1] == other || c[2] == other)
    {
      tri = this->Inc[k];
    }
  }
  double n[3], x[3], y[3];
  if (tri < 0 || this->Face(tri, n) <= 0)
  {
    return;
  }
  this->Position(a, x);
  this->Position(b, y);
  const double e[3] = { y[0] - x[0], y[1] - x[1], y[2] - x[2] };
  double m[3];
  Cross(e, n, m);
  const double len = std::sqrt(Dot(m, m));
  if (len > 0)
  {
    for (int k = 0; k < 3; ++k)
      m[k] /= len;
    Quadric q;
    q.AddPlane(m, x, BoundaryWeight * Dot(e, e));
    planes.emplace_back(a, q);
    planes.emplace_back(b, q);
  }
}

/// The boundary planes summed per point, in point order (BoundaryQuadric).
void MeshBuild::KeepBoundaryPlanes(LargeVector<std::pair<int32_t, Quadric>>& planes)
{
  std::stable_sort(planes.begin(), planes.end(),
    [](const std::pair<int32_t, Quadric>& x, const std::pair<int32_t, Quadric>& y) {
      return x.first < y.first;
    });
  for (const auto& pl : planes)
  {
    if (this->BoundaryQuadric.empty() || this->BoundaryQuadric.back().first != pl.first)
    {
      this->BoundaryQuadric.push_back(pl);
    }
    else
    {
      this->BoundaryQuadric.back().second.Add(pl.second);
    }
  }
}

bool MeshBuild::NoteCoincidentPoints()
{
  // points at one position lie in one leaf: compare each with the others of its leaf (a few, at
  // the default level), sorting the leaves that hold many
  const OctreeArrays& o = this->Out;
  const int64_t first = this->Offset[this->L], last = this->Nodes;
  LargeVector<std::array<float, 3>> many;
  int64_t coincident = 0;
  for (int64_t leaf = first; leaf < last; ++leaf)
  {
    const int64_t b = o.FirstPoint[leaf];
    const int64_t e = leaf + 1 < last ? o.FirstPoint[leaf + 1] : this->Points;
    auto at = [&o](int64_t p) {
      return std::array<float, 3>{ o.Points[3 * p], o.Points[3 * p + 1], o.Points[3 * p + 2] };
    };
    if (e - b <= 32)
    {
      for (int64_t p = b + 1; p < e; ++p)
      {
        for (int64_t q = b; q < p; ++q)
        {
          if (at(p) == at(q))
          {
            ++coincident;
            break;
          }
        }
      }
      continue;
    }
    many.clear();
    for (int64_t p = b; p < e; ++p)
    {
      many.push_back(at(p));
    }
    std::sort(many.begin(), many.end());
    coincident += static_cast<int64_t>(many.end() - std::unique(many.begin(), many.end()));
  }
  this->R.NumberOfCoincidentPoints = coincident;
  if (coincident > 0 && 10 * coincident > this->Points)
  {
    this->R.Warnings.push_back(std::to_string(coincident) + " of " + std::to_string(this->Points) +
      " surface points repeat the position of another point: the triangles meeting there do not "
      "share their vertices (a mesh split along texture or normal seams, or an STL file), so the "
      "LOD cannot merge across those seams and simplifies little; merge coincident points first "
      "(vtkCleanPolyData or vtkStaticCleanPolyData)");
  }
  return this->Report(1.0);
}

void MeshBuild::Descend(int64_t t, LargeVector<std::pair<int32_t, int32_t>>& out) const
{
  const int32_t* c = &this->Out.Triangles[3 * t];
  const int32_t leaf[3] = { this->Out.PointLeaf[c[0]], this->Out.PointLeaf[c[1]],
    this->Out.PointLeaf[c[2]] };
  if (leaf[0] == leaf[1] && leaf[1] == leaf[2])
  {
    return; // inside one leaf: it meets no other cell
  }
  double n[3];
  if (this->Face(t, n) <= 0)
  {
    return; // no normal to hold
  }
  double p[3][3];
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k)
  {
    this->Position(c[k], p[k]);
  }
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = std::min({ p[0][a], p[1][a], p[2][a] });
    hi[a] = std::max({ p[0][a], p[1][a], p[2][a] });
  }
  const uint64_t key[3] = { this->LeafKey(c[0]), this->LeafKey(c[1]), this->LeafKey(c[2]) };
  if (!this->RecordByFinestCells(t, p, lo, hi, key, out))
  {
    this->RecordByDescent(t, p, lo, hi, key, out);
  }
}

bool MeshBuild::RecordByFinestCells(int64_t t, const double p[3][3], const double lo[3],
  const double hi[3], const uint64_t key[3], LargeVector<std::pair<int32_t, int32_t>>& out) const
{
  // the usual case, a triangle about a cell across: test the few finest cells of its bounding
  // box; a cell it meets without a corner records the triangle at its deepest existing
  // ancestor-or-self, unless that node holds a corner (then its cone has the normal already)
  const double scale = std::ldexp(1.0, this->L);
  const double slack = 1e-6; // positions are floats: a hair's rounding at a cell face
  int64_t ilo[3], ihi[3], cells = 1;
  for (int a = 0; a < 3; ++a)
  {
    ilo[a] = std::max<int64_t>(0, static_cast<int64_t>(std::floor(lo[a] * scale - slack)));
    ihi[a] = std::min<int64_t>(
      int64_t(1) << this->L, static_cast<int64_t>(std::floor(hi[a] * scale + slack)));
    cells *= ihi[a] - ilo[a] + 1;
  }
  if (cells > 27)
  {
    return false;
  }
  const double h = 1.0 / scale;
  const TriangleBoxTester tester(p[0], p[1], p[2]);
  for (int64_t z = ilo[2]; z <= ihi[2]; ++z)
    for (int64_t y = ilo[1]; y <= ihi[1]; ++y)
      for (int64_t x = ilo[0]; x <= ihi[0]; ++x)
      {
        if (x >= (int64_t(1) << this->L) || y >= (int64_t(1) << this->L) ||
          z >= (int64_t(1) << this->L))
          continue;
        const uint64_t cell = MortonEncode(uint32_t(x), uint32_t(y), uint32_t(z));
        if (cell == key[0] || cell == key[1] || cell == key[2])
          continue;
        const double clo[3] = { x * h, y * h, z * h };
        if (!tester.Meets(clo, h))
          continue;
        for (int l = this->L; l >= 0; --l)
        {
          const int shift = 3 * (this->L - l);
          const uint64_t k = cell >> shift;
          if ((key[0] >> shift) == k || (key[1] >> shift) == k || (key[2] >> shift) == k)
            break; // a corner's ancestor: its cone holds the normal
          const auto& level = this->Keys[l];
          auto it = std::lower_bound(level.begin(), level.end(), k);
          if (it != level.end() && *it == k)
          {
            out.emplace_back(static_cast<int32_t>(this->Offset[l] + (it - level.begin())),
              static_cast<int32_t>(t));
            break;
          }
        }
      }
  return true;
}

/// A walk down from the triangle's holder: a cell it meets without a corner records it at the
/// cell's node, or at the node where the cell has no child.
void MeshBuild::RecordByDescent(int64_t t, const double p[3][3], const double lo[3],
  const double hi[3], const uint64_t key[3], LargeVector<std::pair<int32_t, int32_t>>& out) const
{
  const TriangleBoxTester tester(p[0], p[1], p[2]);
  int32_t stack[8 * (MaxFinestLevel + 1)];
  int top = 0;
  stack[top++] = static_cast<int32_t>(this->Holder(t));
  while (top > 0)
  {
    const int32_t node = stack[--top];
    const int l = this->Out.Level[node];
    const uint64_t nodeKey = this->NodeKey(node);
    bool recorded = false;
    for (int ci = 0; ci < 8; ++ci)
    {
      const uint64_t childKey = (nodeKey << 3) | uint64_t(ci);
      const int shift = 3 * (this->L - l - 1);
      const bool corner = (key[0] >> shift) == childKey || (key[1] >> shift) == childKey ||
        (key[2] >> shift) == childKey;
      const unsigned mask = this->Out.ChildMask[node];
      const bool exists = (mask & (1u << ci)) != 0;
      if (corner)
      {
        if (l + 1 < this->L)
        {
          stack[top++] = this->Out.FirstChild[node] + __builtin_popcount(mask & ((1u << ci) - 1u));
        }
        continue; // a leaf holding a corner counts the triangle through its points
      }
      if (recorded && !exists)
      {
        continue;
      }
      double clo[3], h;
      KeyBox(childKey, l + 1, clo, h);
      if (hi[0] < clo[0] || hi[1] < clo[1] || hi[2] < clo[2] || lo[0] > clo[0] + h ||
        lo[1] > clo[1] + h || lo[2] > clo[2] + h || !tester.Meets(clo, h))
      {
        continue;
      }
      if (!exists)
      {
        out.emplace_back(node, static_cast<int32_t>(t)); // meets the node where it has no child
        recorded = true;
        continue;
      }
      const int32_t child =
        this->Out.FirstChild[node] + __builtin_popcount(mask & ((1u << ci) - 1u));
      if (l + 1 == this->L)
      {
        out.emplace_back(child, static_cast<int32_t>(t));
      }
      else
      {
        stack[top++] = child;
      }
    }
  }
}

bool MeshBuild::FindPassingTriangles()
{
  this->Report.Phase("passing", 0.55, 0.6);
  for (int64_t start = 0; start < this->Tris; start += Block)
  {
    const int64_t end = std::min(this->Tris, start + Block);
    auto part = ChunkedGather<std::pair<int32_t, int32_t>>(end - start, 4096, this->For,
      [&](int64_t b, int64_t e, LargeVector<std::pair<int32_t, int32_t>>& out) {
        for (int64_t t = start + b; t < start + e; ++t)
        {
          this->Descend(t, out);
        }
      });
    this->Pass.insert(this->Pass.end(), part.begin(), part.end());
    if (!this->Report(double(end) / double(this->Tris)))
    {
      return false;
    }
  }
  std::sort(this->Pass.begin(), this->Pass.end());
  this->Pass.erase(std::unique(this->Pass.begin(), this->Pass.end()), this->Pass.end());
  return true;
}

void MeshBuild::Material(int64_t p, Range& d, Range& s) const
{
  const int64_t i = this->Order[p];
  if (this->S.DiffuseMin)
  {
    d.Add(this->S.DiffuseMin[i]);
    d.Add(this->S.DiffuseMax[i]);
  }
  if (this->S.SpecularMin)
  {
    s.Add(this->S.SpecularMin[i]);
    s.Add(this->S.SpecularMax[i]);
  }
}

void MeshBuild::TriangleMaterial(int64_t t, Range& d, Range& s) const
{
  if (this->S.TriangleDiffuse)
  {
    d.Add(this->S.TriangleDiffuse[this->TriSource[t]]);
  }
  if (this->S.TriangleSpecular)
  {
    s.Add(this->S.TriangleSpecular[this->TriSource[t]]);
  }
}

void MeshBuild::PlaceVertex(const CellSums& s, uint64_t key, int level, float* out) const
{
  double mean[3], x[3];
  for (int a = 0; a < 3; ++a)
  {
    mean[a] = s.Count > 0 ? s.P[a] / double(s.Count) : 0.0;
  }
  if (this->Params.Rule == VertexRule::QEF && s.W > 0)
  {
    s.Q.Solve(mean, QEFTruncation, x);
    double lo[3], h;
    KeyBox(key, level, lo, h);
    for (int a = 0; a < 3; ++a)
    {
      x[a] = std::min(std::max(x[a], lo[a]), lo[a] + h);
      assert(std::isfinite(x[a]) && "a QEF vertex lies in its cell");
    }
  }
  else
  {
    std::copy(mean, mean + 3, x);
  }
  for (int a = 0; a < 3; ++a)
  {
    out[a] = static_cast<float>(x[a] * this->Edge);
  }
}

/// Clusters per level, with level-local ids (MakeClusters): a point standing for each, its
/// parent cluster's level-local id, and each node's first cluster.
struct MeshBuild::ClusterLevels
{
  LargeVector<LargeVector<int32_t>> RepPoint, ParentLocal;
  LargeVector<int32_t> FirstLocal;
};

bool MeshBuild::MakeClusters()
{
  this->Report.Phase("clusters", 0.45, 0.55);
  // per node, F + U - E of the triangles, edges and unions whose lowest common node it is
  LargeVector<int64_t> delta(this->Nodes, 0);
  for (int64_t t = 0; t < this->Tris; ++t)
  {
    if (!this->Tick(t, this->Tris, 0.0, 0.1))
    {
      return false;
    }
    ++delta[this->Holder(t)];
  }
  LargeVector<std::pair<int32_t, int32_t>> edges;
  LargeVector<int64_t> levelStart;
  ClusterLevels levels;
  if (!this->EdgesDeepestFirst(edges, levelStart) ||
    !this->UniteLevelByLevel(edges, levelStart, delta, levels) || !this->NumberClusters(levels))
  {
    return false;
  }
  this->MarkTopology(delta);
  return this->Report(1.0);
}

/// The unique edges (EdgeStart, EdgeTo, released here) ordered by the level of their lowest
/// common node, deepest first, so that unions inside a cell happen before those of its parent:
/// level l's are [levelStart[L - l], levelStart[L - l + 1]).
bool MeshBuild::EdgesDeepestFirst(
  LargeVector<std::pair<int32_t, int32_t>>& edges, LargeVector<int64_t>& levelStart)
{
  const int L = this->L;
  LargeVector<int64_t>& start = this->EdgeStart;
  LargeVector<int32_t>& to = this->EdgeTo;
  LargeVector<int64_t> perLevel(L + 1, 0);
  LargeVector<uint8_t> level(to.size(), 255);
  this->For(this->Points, 4096, [&](int64_t b, int64_t e) {
    for (int64_t p = b; p < e; ++p)
    {
      const uint64_t kp = this->LeafKey(p);
      for (int64_t i = start[p]; i < start[p + 1]; ++i)
      {
        if (i > start[p] && to[i] == to[i - 1])
        {
          continue; // the same edge again
        }
        level[i] = static_cast<uint8_t>(CommonLevel(kp, this->LeafKey(to[i]), L));
      }
    }
  });
  for (uint8_t l : level)
  {
    if (l != 255)
    {
      ++perLevel[l];
    }
  }
  if (!this->Report(0.2))
  {
    return false;
  }
  levelStart.assign(L + 2, 0);
  for (int l = L; l >= 0; --l)
  {
    levelStart[L - l + 1] = levelStart[L - l] + perLevel[l];
  }
  edges.resize(levelStart[L + 1]);
  LargeVector<int64_t> cursor(levelStart.begin(), levelStart.end() - 1);
  for (int64_t p = 0; p < this->Points; ++p)
  {
    for (int64_t i = start[p]; i < start[p + 1]; ++i)
    {
      if (level[i] != 255)
      {
        edges[cursor[L - level[i]]++] = { static_cast<int32_t>(p), to[i] };
      }
    }
  }
  LargeVector<int64_t>().swap(start);
  LargeVector<int32_t>().swap(to);
  return this->Report(0.4);
}

/**
 * Union-find over the points, level by level from the leaves: after the unions of level l, the
 * roots of a level-l cell's points are its clusters (the components of its sub-mesh). Each
 * edge takes one from its lowest common node's `delta`, each union gives one back. The leaves'
 * clusters are numbered from their points (PointCluster, level-local for now), each inner
 * node's from its children's.
 */
bool MeshBuild::UniteLevelByLevel(const LargeVector<std::pair<int32_t, int32_t>>& edges,
  const LargeVector<int64_t>& levelStart, LargeVector<int64_t>& delta, ClusterLevels& levels)
{
  OctreeArrays& o = this->Out;
  const int L = this->L;
  LargeVector<int32_t> root(this->Points);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&root](int32_t x) {
    while (root[x] != x)
    {
      root[x] = root[root[x]];
      x = root[x];
    }
    return x;
  };
  bool stopped = false;
  auto unite = [&](int l) {
    for (int64_t i = levelStart[L - l]; i < levelStart[L - l + 1] && !stopped; ++i)
    {
      stopped = !this->Tick(i, levelStart[L + 1], 0.4, 0.9);
      const int32_t a = edges[i].first, b = edges[i].second;
      const int64_t node = this->Ancestor(o.PointLeaf[a], l);
      --delta[node]; // the edge
      const int32_t ra = find(a), rb = find(b);
      if (ra != rb)
      {
        root[std::max(ra, rb)] = std::min(ra, rb);
        ++delta[node]; // a union: one component fewer
      }
    }
  };
  LargeVector<LargeVector<int32_t>>& repPoint = levels.RepPoint;
  LargeVector<LargeVector<int32_t>>& parentLocal = levels.ParentLocal;
  LargeVector<int32_t>& firstLocal = levels.FirstLocal;
  repPoint.assign(L + 1, {});
  parentLocal.assign(L + 1, {});
  firstLocal.assign(this->Nodes, 0);
  LargeVector<int32_t> tag(this->Points, -1);
  LargeVector<int32_t> touched;
  unite(L);
  if (stopped)
  {
    return false;
  }
  for (int64_t leaf = this->Offset[L]; leaf < this->Offset[L + 1]; ++leaf)
  {
    firstLocal[leaf] = static_cast<int32_t>(repPoint[L].size());
    for (int64_t p = o.FirstPoint[leaf], end = this->PointEnd(leaf); p < end; ++p)
    {
      const int32_t r = find(static_cast<int32_t>(p));
      if (tag[r] < 0)
      {
        tag[r] = static_cast<int32_t>(repPoint[L].size());
        repPoint[L].push_back(static_cast<int32_t>(p));
        touched.push_back(r);
      }
      o.PointCluster[p] = tag[r]; // level-local for now
    }
    for (int32_t r : touched)
      tag[r] = -1;
    touched.clear();
  }
  for (int l = L - 1; l >= 0; --l)
  {
    unite(l);
    if (stopped)
    {
      return false;
    }
    parentLocal[l + 1].assign(repPoint[l + 1].size(), -1);
    for (int64_t n = this->Offset[l]; n < this->Offset[l + 1]; ++n)
    {
      firstLocal[n] = static_cast<int32_t>(repPoint[l].size());
      const int children = __builtin_popcount(o.ChildMask[n]);
      for (int c = 0; c < children; ++c)
      {
        const int64_t ch = o.FirstChild[n] + c;
        const int32_t end = ch + 1 < this->Offset[l + 2]
          ? firstLocal[ch + 1]
          : static_cast<int32_t>(repPoint[l + 1].size());
        for (int32_t k = firstLocal[ch]; k < end; ++k)
        {
          const int32_t r = find(repPoint[l + 1][k]);
          if (tag[r] < 0)
          {
            tag[r] = static_cast<int32_t>(repPoint[l].size());
            repPoint[l].push_back(repPoint[l + 1][k]);
            touched.push_back(r);
          }
          parentLocal[l + 1][k] = tag[r];
        }
      }
      for (int32_t r : touched)
        tag[r] = -1;
      touched.clear();
    }
  }
  return true;
}

/// The clusters' global ids (level by level from the root, in node order inside a level) and
/// their arrays: FirstCluster, ClusterNode, ClusterParent, PointCluster.
bool MeshBuild::NumberClusters(const ClusterLevels& levels)
{
  OctreeArrays& o = this->Out;
  const int L = this->L;
  this->ClusterOffset.assign(L + 2, 0);
  for (int l = 0; l <= L; ++l)
  {
    this->ClusterOffset[l + 1] =
      this->ClusterOffset[l] + static_cast<int64_t>(levels.RepPoint[l].size());
  }
  const int64_t clusters = this->ClusterOffset[L + 1];
  if (clusters > MaxIndex)
  {
    return this->Fail("too many clusters (" + std::to_string(clusters) + ") for 32-bit indices");
  }
  this->Allocate.Clusters(clusters, o);
  if (!o.ClusterNode || !o.ClusterParent || !o.ClusterVertex || !o.ClusterNormal)
  {
    return this->Fail("could not allocate the cluster arrays");
  }
  this->R.NumberOfClusters = clusters;
  for (int l = 0; l <= L; ++l)
  {
    for (int64_t n = this->Offset[l]; n < this->Offset[l + 1]; ++n)
    {
      o.FirstCluster[n] = static_cast<int32_t>(this->ClusterOffset[l] + levels.FirstLocal[n]);
    }
  }
  for (int l = 0; l <= L; ++l)
  {
    for (int64_t n = this->Offset[l]; n < this->Offset[l + 1]; ++n)
    {
      const int64_t end = n + 1 < this->Nodes ? o.FirstCluster[n + 1] : clusters;
      for (int64_t c = o.FirstCluster[n]; c < end; ++c)
      {
        o.ClusterNode[c] = static_cast<int32_t>(n);
        o.ClusterParent[c] = l == 0 ? -1
                                    : static_cast<int32_t>(this->ClusterOffset[l - 1] +
                                        levels.ParentLocal[l][c - this->ClusterOffset[l]]);
      }
    }
  }
  for (int64_t p = 0; p < this->Points; ++p)
  {
    o.PointCluster[p] = static_cast<int32_t>(this->ClusterOffset[L] + o.PointCluster[p]);
  }
  return true;
}

/// Topology: a node's sub-mesh is a union of discs when V - E + F equals its number of
/// components, that is when the sum of `delta` over its subtree is 0 (NodeTopologySafe).
void MeshBuild::MarkTopology(LargeVector<int64_t>& delta)
{
  OctreeArrays& o = this->Out;
  for (int64_t n = this->Nodes - 1; n > 0; --n)
  {
    delta[o.Parent[n]] += delta[n];
  }
  int64_t unsafe = 0;
  for (int64_t n = 0; n < this->Nodes; ++n)
  {
    o.Flags[n] =
      static_cast<uint8_t>((o.Flags[n] & NodeBoundary) | (delta[n] == 0 ? NodeTopologySafe : 0));
    unsafe += delta[n] == 0 ? 0 : 1;
  }
  this->R.NumberOfUnsafeNodes = unsafe;
}

std::pair<LargeVector<std::pair<int32_t, int32_t>>::const_iterator,
  LargeVector<std::pair<int32_t, int32_t>>::const_iterator>
MeshBuild::PassRange(int64_t node) const
{
  auto lo = std::lower_bound(this->Pass.begin(), this->Pass.end(),
    std::make_pair(static_cast<int32_t>(node), std::numeric_limits<int32_t>::min()));
  auto hi = lo;
  while (hi != this->Pass.end() && hi->first == node)
  {
    ++hi;
  }
  return { lo, hi };
}

void MeshBuild::AddPassing(
  int64_t node, LargeVector<std::array<double, 3>>& normals, Range& d, Range& sp) const
{
  // the triangles that pass through a node without a corner in it: they widen its cone and
  // its material range; they do not weigh in its axis (they would be counted again in every
  // cell they cross, and tilt the axes of the cells above)
  const auto range = this->PassRange(node);
  for (auto it = range.first; it != range.second; ++it)
  {
    double n[3];
    if (this->Face(it->second, n) > 0)
    {
      normals.push_back({ n[0], n[1], n[2] });
    }
    this->TriangleMaterial(it->second, d, sp);
    for (int k = 0; k < 3; ++k)
    {
      this->Material(this->Out.Triangles[3 * it->second + k], d, sp);
    }
  }
}

double MeshBuild::Widest(const double axis[3], const LargeVector<std::array<double, 3>>& normals)
{
  // the smallest dot product picks the normal, one accurate angle is computed from it
  const std::array<double, 3>* far = nullptr;
  double least = 2.0;
  for (const auto& n : normals)
  {
    const double d = Dot(axis, n.data());
    if (d < least)
    {
      least = d;
      far = &n;
    }
  }
  return far ? AngleBetween(axis, far->data()) : 0.0;
}

void MeshBuild::FinishNode(
  int64_t node, int level, uint64_t key, const CellSums* sums, int count, CellSums& total)
{
  OctreeArrays& o = this->Out;
  for (int k = 0; k < count; ++k)
  {
    total.Add(sums[k]);
    const int64_t c = o.FirstCluster[node] + k;
    this->PlaceVertex(sums[k], key, level, &o.ClusterVertex[3 * c]);
    ShadingNormal(sums[k], &o.ClusterNormal[3 * c]);
  }
  if (count == 1)
  {
    // one cluster: the cell's sums are its sums, and so is its vertex
    std::copy_n(&o.ClusterVertex[3 * o.FirstCluster[node]], 3, &o.Vertex[3 * node]);
  }
  else
  {
    this->PlaceVertex(total, key, level, &o.Vertex[3 * node]);
  }
  // only read for cells that are not topologically safe (known by now)
  o.Thickness[node] = (o.Flags[node] & NodeTopologySafe)
    ? 0.0f
    : static_cast<float>(Thickness(total, total.Count) * this->Edge);
}

void MeshBuild::StoreCone(
  int64_t node, const double axis[3], double theta, const Range& d, const Range& sp)
{
  OctreeArrays& o = this->Out;
  for (int a = 0; a < 3; ++a)
    o.ConeAxis[3 * node + a] = static_cast<float>(axis[a]);
  o.ConeAngle[node] = static_cast<float>(theta);
  d.Store(&o.DiffuseRange[2 * node], this->S.UniformDiffuse);
  sp.Store(&o.SpecularRange[2 * node], this->S.UniformSpecular);
}

void MeshBuild::LeafCell(
  int64_t leaf, LargeVector<CellSums>& sums, LargeVector<std::array<double, 3>>& normals)
{
  // its points and the triangles at them; `sums` receives the leaf's cluster sums
  OctreeArrays& o = this->Out;
  const int64_t cf = o.FirstCluster[leaf];
  const int64_t end =
    leaf + 1 < this->Nodes ? o.FirstCluster[leaf + 1] : this->ClusterOffset[this->L + 1];
  const int count = static_cast<int>(end - cf);
  sums.assign(count, CellSums());
  Range d, sp;
  normals.clear();
  const int64_t p0 = o.FirstPoint[leaf], p1 = this->PointEnd(leaf);
  for (int64_t p = p0; p < p1; ++p)
  {
    CellSums& s = sums[o.PointCluster[p] - cf];
    double u[3];
    this->Position(p, u);
    s.AddPoint(u);
    this->Material(p, d, sp);
    auto bq = std::lower_bound(this->BoundaryQuadric.begin(), this->BoundaryQuadric.end(),
      static_cast<int32_t>(p),
      [](const std::pair<int32_t, Quadric>& x, int32_t k) { return x.first < k; });
    if (bq != this->BoundaryQuadric.end() && bq->first == p)
    {
      s.Q.Add(bq->second);
    }
    for (int64_t j = this->IncStart[p]; j < this->IncStart[p + 1]; ++j)
    {
      const int32_t t = this->Inc[j];
      const int32_t* c = &o.Triangles[3 * t];
      int inside = 0, first = -1;
      for (int k = 0; k < 3; ++k)
      {
        if (o.PointLeaf[c[k]] == leaf)
        {
          ++inside;
          first = first < 0 ? k : first;
        }
      }
      if (c[first] != p)
      {
        continue; // counted once per leaf, at its first corner inside
      }
      double n[3];
      const double area = this->Face(t, n);
      if (area > 0)
      {
        // the corners inside share one cluster (the triangle's edges join them)
        s.AddTriangle(n, u, area * inside / 3.0, area * inside);
        normals.push_back({ n[0], n[1], n[2] });
      }
      this->TriangleMaterial(t, d, sp);
    }
  }
  this->AddPassing(leaf, normals, d, sp);
  CellSums total;
  this->FinishNode(
    leaf, this->L, this->Keys[this->L][leaf - this->Offset[this->L]], sums.data(), count, total);
  double axis[3];
  const bool valid = NormaliseAxis(total.N, total.W, axis);
  const double theta = valid ? std::min(Pi, Widest(axis, normals)) : Pi;
  this->StoreCone(leaf, axis, theta, d, sp);
}

void MeshBuild::InnerCell(int64_t node, int l, int64_t i, CellSums* sums, int clusters,
  LargeVector<std::array<double, 3>>& normals)
{
  // its clusters' sums already gathered from its children
  OctreeArrays& o = this->Out;
  Range d, sp;
  normals.clear();
  const int children = __builtin_popcount(o.ChildMask[node]);
  double childAxis[8][3], childAngle[8];
  for (int c = 0; c < children; ++c)
  {
    const int64_t ch = o.FirstChild[node] + c;
    for (int a = 0; a < 3; ++a)
    {
      childAxis[c][a] = o.ConeAxis[3 * ch + a];
    }
    childAngle[c] = o.ConeAngle[ch];
    d.Add(&o.DiffuseRange[2 * ch]);
    sp.Add(&o.SpecularRange[2 * ch]);
  }
  this->AddPassing(node, normals, d, sp);
  CellSums total;
  this->FinishNode(node, l, this->Keys[l][i], sums, clusters, total);
  double axis[3];
  const bool valid = NormaliseAxis(total.N, total.W, axis);
  double theta = EnclosingConeAngle(axis, valid, childAxis, childAngle, children);
  if (valid)
  {
    theta = std::min(Pi, std::max(theta, Widest(axis, normals)));
  }
  this->StoreCone(node, axis, theta, d, sp);
}

bool MeshBuild::ComputeLeavesAndParents(LargeVector<CellSums>& child)
{
  // each parent sums its leaves' clusters as they are made, so that the leaves' sums (240
  // bytes per cluster, the most numerous) are never all held at once; the order of the sums
  // is the same as level by level
  OctreeArrays& o = this->Out;
  const int l = this->L - 1;
  const int64_t base = this->Offset[l], count = this->Offset[l + 1] - base;
  const int64_t clusterBase = this->ClusterOffset[l];
  child.resize(this->ClusterOffset[l + 1] - clusterBase);
  return BlockedFor(
    count, 256, Block / 16, this->For,
    [&](int64_t b, int64_t e) {
      LargeVector<std::array<double, 3>> normals;
      LargeVector<CellSums> leafSums;
      for (int64_t i = b; i < e; ++i)
      {
        const int64_t node = base + i;
        const int64_t cf = o.FirstCluster[node];
        CellSums* sums = &child[cf - clusterBase];
        const int clusters = static_cast<int>(o.FirstCluster[node + 1] - cf);
        const int children = __builtin_popcount(o.ChildMask[node]);
        for (int c = 0; c < children; ++c)
        {
          const int64_t ch = o.FirstChild[node] + c;
          this->LeafCell(ch, leafSums, normals);
          const int64_t chFirst = o.FirstCluster[ch];
          for (size_t k = 0; k < leafSums.size(); ++k)
          {
            sums[o.ClusterParent[chFirst + static_cast<int64_t>(k)] - cf].Add(leafSums[k]);
          }
        }
        this->InnerCell(node, l, i, sums, clusters, normals);
      }
    },
    [&](double f) { return this->Report(0.7 * f); });
}

bool MeshBuild::ComputeUpperCells(LargeVector<CellSums>& child)
{
  // each level from its children's clusters (`child`: those of level l + 1)
  OctreeArrays& o = this->Out;
  const int L = this->L;
  for (int l = L - 2; l >= 0; --l)
  {
    const int64_t base = this->Offset[l], count = this->Offset[l + 1] - base;
    const int64_t clusterBase = this->ClusterOffset[l];
    const int64_t childClusterBase = this->ClusterOffset[l + 1];
    const int64_t childClusterEnd = this->ClusterOffset[l + 2];
    LargeVector<CellSums> parent(this->ClusterOffset[l + 1] - clusterBase);
    this->For(count, 256, [&](int64_t b, int64_t e) {
      LargeVector<std::array<double, 3>> normals;
      for (int64_t i = b; i < e; ++i)
      {
        const int64_t node = base + i;
        const int64_t cf = o.FirstCluster[node];
        CellSums* sums = &parent[cf - clusterBase];
        const int clusters = static_cast<int>(o.FirstCluster[node + 1] - cf);
        const int children = __builtin_popcount(o.ChildMask[node]);
        for (int c = 0; c < children; ++c)
        {
          const int64_t ch = o.FirstChild[node] + c;
          const int64_t chEnd = ch + 1 < this->Nodes ? o.FirstCluster[ch + 1] : childClusterEnd;
          for (int64_t k = o.FirstCluster[ch]; k < chEnd; ++k)
          {
            sums[o.ClusterParent[k] - cf].Add(child[k - childClusterBase]);
          }
        }
        this->InnerCell(node, l, i, sums, clusters, normals);
      }
    });
    child.swap(parent);
    if (!this->Report(0.7 + 0.3 * double(L - 1 - l) / double(L)))
    {
      return false;
    }
  }
  return true;
}

bool MeshBuild::ComputeCells()
{
  this->Report.Phase("cells", 0.6, 0.8);
  if (this->L == 0)
  {
    // the root is the only leaf
    LargeVector<CellSums> sums;
    LargeVector<std::array<double, 3>> normals;
    this->LeafCell(0, sums, normals);
    LargeVector<std::pair<int32_t, Quadric>>().swap(this->BoundaryQuadric);
    LargeVector<int64_t>().swap(this->TriSource);
    return this->Report(1.0);
  }
  // the leaves with their parents, then each coarser level from the one below
  LargeVector<CellSums> child;
  if (!this->ComputeLeavesAndParents(child))
  {
    return false;
  }
  LargeVector<std::pair<int32_t, Quadric>>().swap(this->BoundaryQuadric);
  if (!this->ComputeUpperCells(child))
  {
    return false;
  }
  LargeVector<int64_t>().swap(this->TriSource);
  return true;
}

bool MeshBuild::TightenCones()
{
  this->Report.Phase("cones", 0.8, 0.88);
  OctreeArrays& o = this->Out;
  const int L = this->L;
  // unit normals of the triangles (zero for degenerate ones)
  LargeVector<float> normal(3 * this->Tris);
  this->For(this->Tris, 16384, [&](int64_t b, int64_t e) {
    for (int64_t t = b; t < e; ++t)
    {
      double n[3];
      this->Face(t, n);
      for (int a = 0; a < 3; ++a)
        normal[3 * t + a] = static_cast<float>(n[a]);
    }
  });
  // Above the leaves, eq. (2) bounds the children's cones, and its slack grows level after
  // level: measured on a dense scan (Lucy subdivided), the median angle at level 5 was 2.25
  // rad against 1.29 for the normals really there, and 64 % of the cells (34 % exact) could be
  // neither front- nor back-facing. Here every inner cell's angle is the largest angle from its
  // axis to the normal of a triangle that meets it: at its points, or passing through it (then
  // recorded at it or at a descendant). Every normal stays inside; the angle is the least that
  // holds them.
  LargeVector<double> minDot(this->Nodes, 2.0);
  LargeVector<int32_t> widest(this->Nodes, -1); // the triangle reaching it
  auto consider = [&](int64_t node, int32_t t) {
    const float* n = &normal[3 * t];
    if (n[0] == 0 && n[1] == 0 && n[2] == 0)
      return;
    const float* a = &o.ConeAxis[3 * node];
    const double d = double(a[0]) * n[0] + double(a[1]) * n[1] + double(a[2]) * n[2];
    if (d < minDot[node])
    {
      minDot[node] = d;
      widest[node] = t;
    }
  };
  for (int l = L - 1; l >= 0; --l)
  {
    const int64_t base = this->Offset[l], count = this->Offset[l + 1] - base;
    this->For(count, 64, [&](int64_t b, int64_t e) {
      for (int64_t n = base + b; n < base + e; ++n)
      {
        for (int64_t p = o.FirstPoint[n], end = this->PointEnd(n); p < end; ++p)
        {
          for (int64_t j = this->IncStart[p]; j < this->IncStart[p + 1]; ++j)
          {
            consider(n, this->Inc[j]);
          }
        }
      }
    });
    if (!this->Report(0.9 * double(L - l) / double(L)))
    {
      return false;
    }
  }
  for (size_t i = 0; i < this->Pass.size(); ++i)
  {
    const auto& pass = this->Pass[i];
    if (!this->Tick(static_cast<int64_t>(i), static_cast<int64_t>(this->Pass.size()), 0.9, 0.95))
    {
      return false;
    }
    for (int64_t n = pass.first; n >= 0; n = o.Parent[n])
    {
      consider(n, pass.second);
    }
  }
  for (int64_t n = 0; n < this->Offset[L]; ++n)
  {
    if (o.ConeAngle[n] >= float(Pi) || widest[n] < 0)
    {
      continue; // no meaningful axis (normals cancel), or no area: keep pi / the bound
    }
    const double axis[3] = { o.ConeAxis[3 * n], o.ConeAxis[3 * n + 1], o.ConeAxis[3 * n + 2] };
    const float* w = &normal[3 * widest[n]];
    const double far[3] = { w[0], w[1], w[2] };
    // the exact angle never exceeds eq. (2)'s bound; rounding must not make it larger either
    o.ConeAngle[n] = std::min(o.ConeAngle[n], static_cast<float>(AngleBetween(axis, far)));
    assert(o.ConeAngle[n] >= 0 && o.ConeAngle[n] <= float(Pi));
  }
  LargeVector<int64_t>().swap(this->IncStart);
  LargeVector<int32_t>().swap(this->Inc);
  LargeVector<std::pair<int32_t, int32_t>>().swap(this->Pass);
  return this->Report(1.0);
}

bool MeshBuild::ComputeShapeErrors()
{
  this->Report.Phase("shape errors", 0.88, 0.99);
  OctreeArrays& o = this->Out;
  const int L = this->L;
  // SRCC eq. (3), per cluster: the spread along its normal of its points, relative to its
  // vertex; a cell's shape error is the largest of its clusters' (each collapses on its own).
  // `current` follows each point's cluster up the levels.
  LargeVector<int32_t> current(o.PointCluster, o.PointCluster + this->Points);
  for (int l = L; l >= 0; --l)
  {
    if (l < L)
    {
      this->For(this->Points, 65536, [&](int64_t b, int64_t e) {
        for (int64_t p = b; p < e; ++p)
          current[p] = o.ClusterParent[current[p]];
      });
    }
    const int64_t base = this->Offset[l], count = this->Offset[l + 1] - base;
    this->For(count, 64, [&](int64_t b, int64_t e) {
      LargeVector<double> lo, hi;
      for (int64_t i = b; i < e; ++i)
      {
        const int64_t n = base + i;
        const int64_t cf = o.FirstCluster[n];
        const int64_t ce = n + 1 < this->Nodes ? o.FirstCluster[n + 1] : this->ClusterOffset[L + 1];
        lo.assign(ce - cf, std::numeric_limits<double>::max());
        hi.assign(ce - cf, -std::numeric_limits<double>::max());
        for (int64_t p = o.FirstPoint[n], end = this->PointEnd(n); p < end; ++p)
        {
          const int64_t c = current[p];
          const float* x = &o.Points[3 * p];
          const float* v = &o.ClusterVertex[3 * c];
          const float* m = &o.ClusterNormal[3 * c];
          const double d = double(m[0]) * (double(x[0]) - v[0]) +
            double(m[1]) * (double(x[1]) - v[1]) + double(m[2]) * (double(x[2]) - v[2]);
          lo[c - cf] = std::min(lo[c - cf], d);
          hi[c - cf] = std::max(hi[c - cf], d);
        }
        double error = 0;
        for (int64_t k = 0; k < ce - cf; ++k)
        {
          if (hi[k] >= lo[k])
            error = std::max(error, hi[k] - lo[k]);
        }
        assert(error >= 0 && std::isfinite(error));
        o.ShapeError[n] = static_cast<float>(error);
      }
    });
    if (!this->Report(double(L - l + 1) / double(L + 1)))
    {
      return false;
    }
  }
  return true;
}

bool MeshBuild::Finish()
{
#ifndef NDEBUG
  // internal invariants (debug builds): parents are stored before their children, one level up;
  // a cluster's parent cluster belongs to its node's parent
  const OctreeArrays& o = this->Out;
  for (int64_t n = 1; n < this->Nodes; ++n)
  {
    assert(o.Parent[n] >= 0 && o.Parent[n] < n);
    assert(o.Level[n] == o.Level[o.Parent[n]] + 1);
  }
  for (int64_t c = 0; c < this->R.NumberOfClusters; ++c)
  {
    const int64_t p = o.ClusterParent[c];
    assert(p < 0 || o.ClusterNode[p] == o.Parent[o.ClusterNode[c]]);
  }
#endif
  this->Report.Finish();
  this->R.Ok = true;
  return true;
}

} // namespace

BuildResult BuildOctree(const BuildInput& in, const BuildParameters& params,
  const Allocator& allocate, const ParallelFor& pfor, const ProgressCallback& progress)
{
  BuildResult result;
  build::Reporter report(progress);
  if (in.NumberOfPoints <= 0 || !(in.Points || in.PointsFloat))
  {
    result.Error = "the input has no points";
    return result;
  }
  if (params.FinestLevel > MaxFinestLevel)
  {
    result.Error = "finest level " + std::to_string(params.FinestLevel) + " is above the maximum " +
      std::to_string(MaxFinestLevel);
    return result;
  }
  if (!(params.MemoryLimit > 0))
  {
    result.Error = "the memory limit must be positive";
    return result;
  }
  if (params.HasRootCube &&
    !build::ValidateRootCube(params.RootOrigin, params.RootEdge, &result.Error))
  {
    return result;
  }
  Source source;
  build::CloudMesh cloud;
  const bool isCloud = in.NumberOfTriangles <= 0 || !(in.Triangles || in.Triangles32);
  if (isCloud)
  {
    if (!build::MakeCloudMesh(in, params, pfor, report, cloud, result))
    {
      result.Aborted = report.Aborted();
      if (result.Aborted)
      {
        result.Error = "build aborted";
      }
      return result;
    }
    source.NumberOfPoints = static_cast<int64_t>(cloud.Points.size() / 3);
    source.NumberOfTriangles = static_cast<int64_t>(cloud.Triangles.size() / 3);
    source.PointsD = cloud.Points.data();
    source.TrianglesD = cloud.Triangles.data();
    source.Normals = cloud.Normals.data();
    source.InputIds = cloud.InputIds.data();
    if (!cloud.DiffuseMin.empty())
    {
      source.DiffuseMin = cloud.DiffuseMin.data();
      source.DiffuseMax = cloud.DiffuseMax.data();
    }
    if (!cloud.SpecularMin.empty())
    {
      source.SpecularMin = cloud.SpecularMin.data();
      source.SpecularMax = cloud.SpecularMax.data();
    }
    if (in.PointGhost)
    {
      result.Warnings.push_back(
        "ghost flags ignored: a point cloud's surface is contoured, its points are not input "
        "points, so no flag carries over (every process draws its whole surface)");
    }
    source.Forced = true;
    std::copy(cloud.Origin, cloud.Origin + 3, source.ForcedOrigin);
    source.ForcedEdge = cloud.RootEdge;
    source.ForcedLevel = cloud.Level;
  }
  else
  {
    source.NumberOfPoints = in.NumberOfPoints;
    source.NumberOfTriangles = in.NumberOfTriangles;
    source.PointsD = in.Points;
    source.PointsF = in.Points ? nullptr : in.PointsFloat;
    source.TrianglesD = in.Triangles;
    source.TrianglesF = in.Triangles ? nullptr : in.Triangles32;
    source.Normals = in.PointNormals;
    source.DiffuseMin = source.DiffuseMax = in.PointDiffuse;
    source.SpecularMin = source.SpecularMax = in.PointSpecular;
    source.TriangleDiffuse = in.TriangleDiffuse;
    source.TriangleSpecular = in.TriangleSpecular;
    source.Ghost = in.PointGhost;
  }
  source.UniformDiffuse = in.UniformDiffuse;
  source.UniformSpecular = in.UniformSpecular;
  MeshBuild build(source, params, allocate, pfor, report, result);
  if (!build.Run())
  {
    result.Ok = false;
    result.Aborted = report.Aborted();
    if (result.Aborted)
    {
      result.Error = "build aborted";
    }
  }
  return result;
}

} // namespace plod
