// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodCut.h
 * @brief VTK-free cuts through the multiscale octree: states, simple cuts, validation.
 *
 * A cut is one state per node. Every point of the surface has exactly one node on its path from
 * its leaf to the root whose state is not NotInCut: the point is drawn at that node's
 * representative vertex, or as itself when that node is an opened leaf (CutOpen). The nodes
 * strictly above the cut are refined; their owned triangles are the ones drawn.
 *
 * Cut cells are drawn, or hidden (culled or back-facing: they stay in the cut so that a triangle
 * joining them to a drawn cell keeps its corner). An opened leaf draws its input points and the
 * input triangles among them: the finest cut (every leaf opened) is the input itself.
 */
#ifndef plodCut_h
#define plodCut_h

#include "plodOctree.h"

#include <cstdint>
#include <functional>
#include <string>

namespace plod
{

/// Per-node cut state.
enum CutState : uint8_t
{
  NotInCut = 0,
  CutDrawn = 1,  ///< in the cut, drawn at its representative vertex
  CutHidden = 2, ///< in the cut, not drawn (culled or back-facing)
  CutOpen = 3    ///< a leaf drawn at full resolution: its own input points and triangles
};

/// True for the states that draw their cell.
inline bool IsDrawnState(uint8_t s)
{
  return s == CutDrawn || s == CutOpen;
}

/**
 * Uniform cut: every node at `level` drawn at its representative vertex. A negative level, or
 * one above the finest level, opens every leaf: the input at full resolution.
 */
void UniformCut(const OctreeView& v, int level, uint8_t* state);

/**
 * Cut from a refinement predicate, from the root: a node is refined when `refine(node)` is
 * true; a refined leaf is opened. The cut is where refinement stops. All drawn.
 */
void PredicateCut(const OctreeView& v, const std::function<bool(int64_t)>& refine, uint8_t* state);

/**
 * Checks, in one pass over the nodes, that states are 0..3, that only leaves are opened and
 * that every leaf has exactly one ancestor-or-self in the cut. Assumes a valid octree
 * (ValidateOctree). Returns false and explains in `why`.
 */
bool ValidateCut(const OctreeView& v, const uint8_t* state, std::string* why = nullptr);

} // namespace plod

#endif
