// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPatches.h
 * @brief VTK-free cuts and multiscale patches (SRCC §2, dual contouring on minimal edges of
 * Ju et al. 2002).
 *
 * A cut is a per-node state (CutState): every finest-level cell has exactly one ancestor-or-self
 * in the cut. Cells in the cut are drawn, or hidden (culled or back-facing: they stay in the cut
 * so the surface stays closed, but emit nothing of their own).
 *
 * Patches: the octree is walked from the root with the cut cells as leaves (cell, face and edge
 * procedures of Ju et al.). Each minimal edge shared by four leaves is the edge of the smallest
 * of them; when the surface crosses it, the four leaves' representative vertices form a quad,
 * oriented by the crossing's sign (so the triangles turn like the input's) and split along its
 * shorter diagonal. A leaf repeated around an edge (a coarse cell beside finer ones) makes the
 * quad a triangle. Because the crossing of a coarse edge is the signed sum of its halves, cells of
 * different levels agree on every edge and no crack opens.
 *
 * A polygon is emitted when at least one of its cells is drawn: the polygons between drawn and
 * hidden cells are kept, so no gap opens where a drawn region meets a hidden one, and polygons
 * whose cells are all hidden are skipped. Coincident representative vertices (bitwise equal)
 * are merged into one point and triangles that then repeat a point are dropped; merging keeps
 * every edge shared an even number of times on a closed surface.
 */
#ifndef plodPatches_h
#define plodPatches_h

#include "plodOctree.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace plod
{

/// Per-node cut state.
enum CutState : uint8_t
{
  NotInCut = 0,
  CutDrawn = 1,
  CutHidden = 2
};

/// Cut of every node at `level` (clamped to the finest level): all drawn.
void UniformCut(const OctreeView& v, int level, uint8_t* state);

/// Cut from a refinement predicate: a node is refined when `refine(node)` is true and it has
/// children; the cut is where refinement stops. All drawn.
void PredicateCut(const OctreeView& v, const std::function<bool(int64_t)>& refine, uint8_t* state);

/**
 * Checks that every finest cell has exactly one ancestor-or-self in the cut and that states are
 * 0, 1 or 2. Returns false and explains in `why`.
 */
bool ValidateCut(const OctreeView& v, const uint8_t* state, std::string* why = nullptr);

/// Patches of a cut.
struct PatchResult
{
  std::vector<int64_t> PointNode;  // octree node of each output point
  std::vector<int64_t> Triangles;  // 3 output point indices per triangle
  int64_t NodesVisited = 0;        // nodes reached by the walk
  int64_t MergedPoints = 0;        // cells whose vertex coincided with another's
  int64_t DroppedTriangles = 0;    // triangles that repeated a point
};

/// Buffers kept between frames so that a frame allocates (and page-faults) nothing new.
struct PatchWorkspace
{
  std::vector<int32_t> NodeTriangles; // triangles as node indices, before compaction
  std::vector<int32_t> PointOf;       // output point of each node, -1 between frames
};

/**
 * Dual contouring of the cut. Returns false when the cut does not cover a finest cell (then
 * `why` says where). `out`'s vectors keep their capacity between calls.
 */
bool GeneratePatches(const OctreeView& v, const uint8_t* state, PatchResult& out,
  std::string* why = nullptr, PatchWorkspace* workspace = nullptr);

} // namespace plod

#endif
