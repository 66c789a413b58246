// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPartitionSteps.h
 * @brief The rules of the partition by space (plodPartition.h), as steps shared by the
 *        partition between processes (PartitionMesh) and the partition of a file into pieces
 *        built one after the other (plodPieces.h). Internal to the kernels.
 *
 * Both apply the same rules to the same numbers, so a piece of a file equals the share of the
 * process of the same rank when the mesh is split over as many processes.
 */
#ifndef plodPartitionSteps_h
#define plodPartitionSteps_h

#include "plodOctree.h"
#include "plodPartition.h"

#include <cstdint>
#include <vector>

namespace plod
{
namespace partition
{

/// A triangle's box of level-k cells (inclusive).
struct Box
{
  uint32_t Lo[3], Hi[3];
};

/// The level-k cells of the root cube.
struct CellGrid
{
  CellQuantizer Grid;
  int K = 0;

  CellGrid() = default;
  CellGrid(const double origin[3], double rootEdge, int k)
    : Grid(origin, rootEdge)
    , K(k)
  {
  }

  int64_t CellCount() const { return int64_t(1) << (3 * this->K); }

  /// The level-k cell (Morton index) of a point.
  int64_t CellOf(const double* x) const;

  /// The level-k cells of the corners' level-21 cells, one level-21 cell wider on each side
  /// (the builder counts a triangle touching a cell's face as meeting it).
  Box BoxOf(const double* x0, const double* x1, const double* x2) const;
};

/// Calls body(cell) for every level-k cell of the box, cell a Morton index.
template <typename Body>
void ForEachCell(const Box& b, Body&& body)
{
  for (uint32_t z = b.Lo[2]; z <= b.Hi[2]; ++z)
  {
    for (uint32_t y = b.Lo[1]; y <= b.Hi[1]; ++y)
    {
      for (uint32_t x = b.Lo[0]; x <= b.Hi[0]; ++x)
      {
        body(static_cast<int64_t>(MortonEncode(x, y, z)));
      }
    }
  }
}

/// The owner of each level-k cell: Morton-ordered runs of about equal triangle counts (counted
/// at each triangle's first corner), one run per rank.
std::vector<int> ShareOutCells(const std::vector<int64_t>& perCell, int ranks);

/// Marks, in `needs` (ranks x cells, row r for rank r), the cells that the owner of each cell
/// of the box needs whole: every cell of the box. `touched` is scratch.
void MarkNeededCells(const Box& box, const std::vector<int>& owner, int64_t cellCount,
  uint8_t* needs, std::vector<int64_t>& touched);

/// Whether a triangle's box meets a cell of `mask` (one byte per level-k cell).
bool BoxMeets(const Box& box, const uint8_t* mask);

/**
 * A piece's points (3 doubles each, with 3 normal components each when `normals` is not
 * empty) and its triangles (3 indices into them each), made into `r`'s points, normals, ghost
 * flags and triangles: points closer than RootEdge / 2^32 on every axis merged (the first in
 * the order of their position, then of their index, stands for the others), points and
 * triangles in canonical order (by position), a point flagged as a ghost when another rank
 * owns its cell. Releases `triangles`.
 */
void MergePoints(const LargeVector<double>& points, const LargeVector<double>& normals,
  LargeVector<int64_t>& triangles, const CellGrid& cells, const std::vector<int>& owner, int rank,
  PartitionResult* r);

/**
 * A piece's triangles, received as a soup (per triangle: 3 corners x 3 doubles, then 3 normals
 * x 3 doubles when `hasNormals`), made into `r`'s points, normals, ghost flags and triangles:
 * points closer than RootEdge / 2^32 on every axis merged, points and triangles in canonical
 * order (by position), a point flagged as a ghost when another rank owns its cell: MergePoints
 * over the corners. Releases the soup.
 */
void MergeCorners(std::vector<double>& soup, bool hasNormals, const CellGrid& cells,
  const std::vector<int>& owner, int rank, PartitionResult* r);

/// Boundary and misoriented edges with an end `r` owns (all their triangles are in `r`).
int64_t CountOpenEdges(const PartitionResult& r);

/**
 * Occupied cells per level of the points `r` owns, for levels k and finer (coarser ones 0),
 * and in cells[MaxFinestLevel + 1] the number of owned points: summed over the pieces, the
 * whole mesh's counts at those levels.
 */
void CountOwnedCells(const PartitionResult& r, const CellGrid& cells, int64_t* counts);

/// The whole mesh's occupied cells of the levels above k, from the level-k triangle counts.
void CountCoarseCells(const std::vector<int64_t>& perCell, int k, int64_t* counts);

} // namespace partition
} // namespace plod

#endif
