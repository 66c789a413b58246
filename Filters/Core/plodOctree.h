// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctree.h
 * @brief VTK-free description of the multiscale octree shared by the builder, the selector and
 * the patch generator.
 *
 * The octree is a vertex-clustering hierarchy over the input's own triangles (Rossignac &
 * Borrel 1993, Luebke & Erikson 1997, Lindstrom 2000) laid out as the sparse octree of SRCC §2:
 * every cell stands for the input points inside it, represented by one vertex `v` with a normal
 * cone and a shape error; a cut through the tree draws the input's triangles with each corner
 * replaced by the representative of the cut cell that holds it. Why not dual contouring of
 * edge crossings (SRCC's reference 14, this project's first surface): see
 * plodOctreeBuilder.h.
 *
 * Nodes (structure of arrays, one entry per node):
 * - Stored level by level (level 0, the root, first), and inside one level in Morton order of
 *   their integer cell coordinates. The children of a node are contiguous, start at
 *   `FirstChild[n]` and appear in increasing child index; `ChildMask[n]` has bit `c` set when
 *   child `c` exists. Every leaf is at the finest level; a leaf has `FirstChild == -1` and
 *   `ChildMask == 0`. A child's index is always greater than its parent's.
 * - Child index `c = xbit | ybit << 1 | zbit << 2`: bit set means the upper half on that axis.
 * - Vertices are stored in single precision *relative to the root origin* (kept in double), so
 *   a model far from the world origin keeps its precision.
 * - `FirstPoint[n]`: the surface points are sorted by the Morton key of their leaf, so the points
 *   inside any node are the contiguous range [FirstPoint[n], PointEnd(n)).
 * - `FirstTriangle[n]`: the triangles *owned* by node n are [FirstTriangle[n], TriangleEnd(n)).
 *   A triangle is owned by the deepest node that holds two of its corners (the deepest of the
 *   three pairwise lowest common ancestors of its corners' leaves; the leaf itself when two
 *   corners share a leaf). It collapses (two corners get one representative) exactly when a
 *   cut accepts its owner or an ancestor, so a cut draws the triangles owned by the nodes
 *   strictly above it (and by opened leaves).
 * - `Flags[n]` bit 0 (NodeTopologySafe): every connected component of the sub-mesh made of the
 *   node's points (the triangles and edges whose corners are all inside) is a disc, judged by
 *   Euler characteristic: V - E + F equals the number of components. Collapsing such a cell to
 *   one point cannot close a tube or a handle (which would drop the tube's triangles and open a
 *   see-through hole). Bit 1 (NodeBoundary): the cell holds an end of a boundary edge (an open
 *   surface's rim, a silhouette from any side).
 * - `FirstCluster[n]`: a cell's points fall into clusters, one per connected component of its
 *   sub-mesh (the points joined by its edges inside the cell): [FirstCluster[n],
 *   ClusterEnd(n)). Each cluster has its own representative vertex and shading normal, so the
 *   two sheets of a thin wall, or two separate parts that share a cell, keep their own vertices
 *   at every level. Clusters form a tree finer than the octree: `ClusterParent[c]` is the
 *   cluster of the parent node holding cluster c's points, `ClusterNode[c]` its node. Which
 *   triangles a cut draws does not depend on clusters (two corners of a triangle in one cell
 *   are joined by the triangle's own edge, so they share a cluster); where they go does.
 * - `Thickness[n]`: for a cell that is not topologically safe, how thick a part collapsing it
 *   could make vanish: 2 sqrt(2 l2), l2 the middle eigenvalue of the covariance of the cell's
 *   points (a tube of radius r gives 2 r); 0 for safe cells. The selector refines an unsafe cell
 *   while its thickness covers more than a pixel.
 *
 * Surface (the input mesh, kept so that the finest cut is the input itself):
 * - `Points` (3 floats per point, relative to the root origin), `Normals` (unit, 3 floats per
 *   point: the input's point normals, or the normalised sum of the unit normals of the point's
 *   triangles, as vtkPolyDataNormals computes without splitting), `PointLeaf` (the leaf node of
 *   each point), `InputPointId` (the index of each point in the input mesh, -1 for the points a
 *   point cloud's contouring made), `Triangles` (3 point indices each, oriented as in the input,
 *   sorted by owner).
 * - `PointGhost` (optional, null when the input had no ghost flags): non-zero for a point owned
 *   by another process (a distributed build's ghost); the patch generator draws a triangle only
 *   when its lead corner, the corner with the smallest point index, is not a ghost
 *   (plodPatches.h). Nothing else reads it.
 */
#ifndef plodOctree_h
#define plodOctree_h

#include "plodOctreeSchema.h"

#include <cmath>
#include <cstdint>
#include <string>

namespace plod
{

/// Deepest level the Morton keys (3 x 21 bits) can address.
constexpr int MaxFinestLevel = 21;

/// Largest number of nodes, points or triangles (32-bit indices in the arrays).
constexpr int64_t MaxIndex = 2147483647;

/// Node flag: the cell's sub-mesh is a union of discs (see the file documentation).
constexpr uint8_t NodeTopologySafe = 1;
/// Node flag: the cell holds an end of a boundary edge of the surface (an edge of one triangle).
constexpr uint8_t NodeBoundary = 2;

/// Read-only view of the octree arrays. Pointers are owned elsewhere (the vtkMultiscaleOctree).
struct OctreeView
{
  int64_t NumberOfNodes = 0;
  int FinestLevel = 0;
  double Origin[3] = { 0, 0, 0 };
  double RootEdge = 1;

  int64_t NumberOfClusters = 0;
  int64_t NumberOfPoints = 0;
  int64_t NumberOfTriangles = 0;

  // one pointer per array of plodOctreeSchema.h (optional ones may be null)
#define PLOD_VIEW_MEMBER(member, group, type, comps, meaning) const type* member = nullptr;
  PLOD_OCTREE_ALL_ARRAYS(PLOD_VIEW_MEMBER)
#undef PLOD_VIEW_MEMBER

  /// Number of tuples of the arrays of `group`.
  int64_t TupleCount(ArrayGroup group) const
  {
    return group == ArrayGroup::Node ? this->NumberOfNodes
      : group == ArrayGroup::Cluster ? this->NumberOfClusters
      : group == ArrayGroup::Point   ? this->NumberOfPoints
                                     : this->NumberOfTriangles;
  }

  bool IsLeaf(int64_t node) const
  {
    return this->ChildMask[node] == 0;
  }

  /// One past the last point inside `node`.
  int64_t PointEnd(int64_t node) const
  {
    return (node + 1 < this->NumberOfNodes && this->Level[node + 1] == this->Level[node])
      ? this->FirstPoint[node + 1]
      : this->NumberOfPoints;
  }

  /// One past the last cluster of `node`.
  int64_t ClusterEnd(int64_t node) const
  {
    return node + 1 < this->NumberOfNodes ? this->FirstCluster[node + 1] : this->NumberOfClusters;
  }

  /// One past the last triangle owned by `node`.
  int64_t TriangleEnd(int64_t node) const
  {
    return node + 1 < this->NumberOfNodes ? this->FirstTriangle[node + 1] : this->NumberOfTriangles;
  }

  /// Index of child `c` of `node`, or -1 when that child does not exist.
  int32_t Child(int64_t node, int c) const
  {
    const unsigned mask = this->ChildMask[node];
    if (!(mask & (1u << c)))
    {
      return -1;
    }
    return this->FirstChild[node] + __builtin_popcount(mask & ((1u << c) - 1u));
  }

  /// Child index (0..7) of `node` inside its parent; -1 for the root.
  int ChildIndexInParent(int64_t node) const
  {
    const int32_t p = this->Parent[node];
    if (p < 0)
    {
      return -1;
    }
    const int rank = static_cast<int>(node - this->FirstChild[p]);
    unsigned mask = this->ChildMask[p];
    for (int c = 0, seen = 0; c < 8; ++c)
    {
      if (mask & (1u << c))
      {
        if (seen == rank)
        {
          return c;
        }
        ++seen;
      }
    }
    return -1;
  }

  /// Integer coordinates of `node`'s cell at its own level (walks up to the root). Relies on a
  /// consistent tree (see ValidateOctree): parents have smaller indices, so the walk ends.
  void CellCoordinates(int64_t node, int xyz[3]) const
  {
    xyz[0] = xyz[1] = xyz[2] = 0;
    int shift = 0;
    for (int64_t n = node; n > 0 && this->Parent[n] >= 0 && this->Parent[n] < n && shift < 32;
         n = this->Parent[n], ++shift)
    {
      const int c = this->ChildIndexInParent(n);
      for (int a = 0; a < 3; ++a)
      {
        xyz[a] |= ((c >> a) & 1) << shift;
      }
    }
  }

  /// Edge length of a cell at `level`.
  double CellEdge(int level) const
  {
    return this->RootEdge / static_cast<double>(1u << level);
  }
};

/// Writable arrays, filled by the builder after it has counted nodes, points and triangles.
struct OctreeArrays
{
#define PLOD_ARRAYS_MEMBER(member, group, type, comps, meaning) type* member = nullptr;
  PLOD_OCTREE_ALL_ARRAYS(PLOD_ARRAYS_MEMBER)
#undef PLOD_ARRAYS_MEMBER
};

/**
 * Calls `f(spec, pointer)` for every array of plodOctreeSchema.h, in schema order, with the
 * array's ArraySpec and a reference to its member in `arrays` (an OctreeView, OctreeArrays or
 * any struct with a member per array, such as OctreeStorage's vectors).
 */
template <typename Arrays, typename F>
void ForEachArray(Arrays& arrays, F&& f)
{
  int k = 0;
#define PLOD_VISIT_ARRAY(member, group, type, comps, meaning) f(OctreeSchema[k++], arrays.member);
  PLOD_OCTREE_ALL_ARRAYS(PLOD_VISIT_ARRAY)
#undef PLOD_VISIT_ARRAY
}

/**
 * Checks, in time linear in the size of the arrays, everything the kernels rely on: array
 * pointers present, root first, levels, parents before children and pointing back, child masks
 * and first children agreeing, leaves exactly at the finest level, point ranges nested and
 * covering every point once, each point's leaf holding it, triangle ranges increasing and
 * covering every triangle, triangle corners in range, clusters in node order with parents in the
 * parent node, each point's cluster in its leaf, cone angles in [0, pi], finite vertices. The
 * optional PointGhost array may be null; any byte value is valid in it (non-zero: a ghost).
 * Returns false and explains in `why`. An empty octree (no nodes) is valid.
 */
bool ValidateOctree(const OctreeView& v, std::string* why = nullptr);

/// Morton key of integer cell coordinates (x in bit 0, y in bit 1, z in bit 2 of each triple).
inline uint64_t MortonEncode(uint32_t x, uint32_t y, uint32_t z)
{
  auto spread = [](uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

/**
 * The project's one quantisation of positions into cells: the level-21 cell of a coordinate
 * in the root cube (lower corner `origin`, edge `rootEdge`) is
 * c = min(2^21 - 1, floor((x - origin) * s)) with s = 2^21 / rootEdge computed first, and 0
 * for a coordinate below the cube or NaN; the level-l cell is c >> (21 - l). The builder, the
 * cloud surface and the partition of distributed builds all use it, so a point lies in the
 * same cell for each of them, to the last bit.
 */
struct CellQuantizer
{
  double Origin[3] = { 0, 0, 0 };
  double Scale = 1;

  CellQuantizer() = default;
  CellQuantizer(const double origin[3], double rootEdge)
    : Origin{ origin[0], origin[1], origin[2] }
    , Scale(std::ldexp(1.0, MaxFinestLevel) / rootEdge)
  {
  }

  /// The level-21 cell coordinate of `x` on `axis`.
  uint32_t Cell(double x, int axis) const
  {
    constexpr uint32_t cells = 1u << MaxFinestLevel;
    const double u = (x - this->Origin[axis]) * this->Scale;
    if (!(u >= 0))
    {
      return 0u;
    }
    return u >= double(cells) ? cells - 1 : static_cast<uint32_t>(u);
  }

  /// The Morton key of the level-21 cell of a point.
  uint64_t Key(double x, double y, double z) const
  {
    return MortonEncode(this->Cell(x, 0), this->Cell(y, 1), this->Cell(z, 2));
  }
};

/**
 * The occupied cells of every level 0..21 (`cells[l]`) over `n` level-21 Morton keys sorted in
 * increasing order (duplicates allowed), `keyAt(r)` giving the r-th: the number of distinct
 * keys >> 3 (21 - l). All zero when n is 0.
 */
template <typename KeyAt>
void CountOccupiedCells(int64_t n, KeyAt keyAt, int64_t cells[MaxFinestLevel + 1])
{
  int64_t firstDiffers[MaxFinestLevel + 2] = {};
  for (int64_t r = 1; r < n; ++r)
  {
    const uint64_t x = keyAt(r) ^ keyAt(r - 1);
    if (x != 0)
    {
      // two cells first differ one level below their lowest common ancestor's
      const int common = MaxFinestLevel - (63 - __builtin_clzll(x)) / 3 - 1;
      ++firstDiffers[common + 1];
    }
  }
  int64_t sum = n > 0 ? 1 : 0;
  for (int l = 0; l <= MaxFinestLevel; ++l)
  {
    sum += firstDiffers[l];
    cells[l] = sum;
  }
}

/// Inverse of MortonEncode.
inline void MortonDecode(uint64_t key, uint32_t xyz[3])
{
  auto compact = [](uint64_t v) {
    v &= 0x1249249249249249ULL;
    v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3ULL;
    v = (v ^ (v >> 4)) & 0x100f00f00f00f00fULL;
    v = (v ^ (v >> 8)) & 0x1f0000ff0000ffULL;
    v = (v ^ (v >> 16)) & 0x1f00000000ffffULL;
    v = (v ^ (v >> 32)) & 0x1fffff;
    return static_cast<uint32_t>(v);
  };
  xyz[0] = compact(key);
  xyz[1] = compact(key >> 1);
  xyz[2] = compact(key >> 2);
}

} // namespace plod

#endif
