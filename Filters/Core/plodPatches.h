// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPatches.h
 * @brief VTK-free multiscale patches: the triangles of a cut (SRCC §2's crack-free patches, made
 * by vertex clustering over the octree, Luebke & Erikson 1997).
 *
 * The walk visits the nodes above the cut from the root. Every triangle owned by a refined node
 * (or by an opened leaf) is drawn, each corner replaced by its representative: the vertex of its
 * cluster in the cut cell that holds it (one per connected part of the cell's surface), or the
 * input point itself in an opened leaf. Owned triangles of
 * refined nodes never collapse (their three corners lie in three different cut cells), and every
 * other triangle has collapsed, so the work is proportional to what is drawn plus the nodes above
 * the cut, not to the input.
 *
 * A corner's representative is found by walking the cluster tree up from its point's leaf
 * cluster to the first cluster whose node is in the cut. With PatchOptions::OctreeStamp, the
 * workspace remembers where each point's walk ended, and the next call starts there when that
 * cluster is still a reached cut cluster (then it is the representative), so a corner whose cut
 * cell did not change costs one check instead of a walk.
 *
 * Cracks cannot open: neighbouring triangles share corners in the output exactly as they do in
 * the input. A closed, consistently oriented input gives, at any cut, a set of triangles in which
 * every edge is used as often in one direction as in the other.
 *
 * Folds: clustering turns a few triangles over (their face normal then opposes the normals of
 * all three corners; at least one corner a representative vertex, input triangles never are).
 * Drawn as they are, two-sided lighting shades them from behind, as dark specks in the middle
 * of lit surfaces. Dropped, they leave see-through slits where nothing lies behind them. The
 * default draws each on three corners of its own, at the same places, with the corners' normals
 * reversed: lit as the surface facing the viewer, covering what it covers: the picture of
 * dropping them without the slits (docs/results/surface.md). Those own corners are the one
 * exception to the closure property below, which holds with FoldHandling::Keep; geometrically
 * nothing opens.
 *
 * Back faces: when the selector hid back-facing cells (a closed surface seen from outside), it
 * passes the eye along; then every drawn triangle that faces away from the eye is skipped too.
 * Cells near the contour hold both sides of the surface, and on a detailed scan they are most
 * of the cut, so a large share of the triangles of such cells face away. Seen from outside, a
 * closed surface only ever shows front faces (the first surface a ray meets is entered), so
 * nothing visible is lost.
 *
 * Hidden cells: a triangle is drawn when one of its representatives is drawn. When all three are
 * hidden it is skipped if one of them faces away (its cone holds the triangle's normal, so the
 * triangle faces away too), or if all three were culled by one common frustum plane (then the
 * whole triangle is outside it). Triangles among cells culled by different planes are drawn: a
 * large triangle can cross the view while its corners lie outside it.
 *
 * Ghosts (distributed rendering, OctreeView::PointGhost not null): a triangle is drawn only if
 * its lead corner, the corner with the smallest surface point index, is not a ghost. The rule
 * comes before every other one and applies to every triangle the walk would emit: those of
 * refined nodes, of opened leaves, among hidden cells, and folds. Surface points are sorted by
 * the Morton key of their level-21 cell, so the lead corner is the corner in the lowest cell;
 * processes that build with the same root cube agree on it whatever else their pieces hold.
 * With VTK's ghost convention (every point owned by exactly one process: a ghost everywhere
 * else), each triangle held by several processes is therefore drawn by exactly one of them, the
 * owner of its lead corner. One exception: two corners in the same level-21 cell are ordered by
 * their index in each process's input, which processes need not share; they agree anyway when
 * the points of a cell have one owner, as when ownership is assigned by cells (a cell of level
 * 21 or coarser).
 */
#ifndef plodPatches_h
#define plodPatches_h

#include "plodCut.h"
#include "plodOctree.h"
#include "plodParallel.h"
#include "plodResidentPages.h"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace plod
{

/// Patches of a cut.
struct PatchResult
{
  /// What each output point is: a cluster (>= 0, its representative vertex) or a surface point
  /// (-1 - index) of an opened leaf.
  std::vector<int64_t> PointSource;
  std::vector<int64_t> Triangles; // 3 output point indices per triangle
  int64_t NodesVisited = 0;       // nodes reached by the walk
  int64_t HiddenSkipped = 0;      // owned triangles skipped among hidden cells
  int64_t Folds = 0;              // turned-over triangles found (dropped or given own corners)
  int64_t BackFacesCulled = 0;    // triangles facing away from the eye (CullBackFaces)
  int64_t GhostSkipped = 0;       // triangles whose lead corner is a ghost (drawn elsewhere)
  /// FoldHandling::ReverseNormals: the output points (each a fold's own corner) whose normal
  /// is the reverse of their source's.
  std::vector<int32_t> ReversedNormals;
};

/// What to do with a triangle that clustering turned over (see the file documentation).
enum class FoldHandling
{
  Keep = 0,          ///< draw it as it is (two-sided lighting shades it from behind: dark)
  Drop = 1,          ///< do not draw it (a see-through slit where nothing lies behind it)
  ReverseNormals = 2 ///< draw it on its own three corners with reversed normals (the default)
};

/// The face normal (x1 - x0) x (x2 - x0) of a triangle with float corners, in double.
inline void FaceNormal(const float* x0, const float* x1, const float* x2, double f[3])
{
  const double e1[3] = { double(x1[0]) - x0[0], double(x1[1]) - x0[1], double(x1[2]) - x0[2] };
  const double e2[3] = { double(x2[0]) - x0[0], double(x2[1]) - x0[1], double(x2[2]) - x0[2] };
  f[0] = e1[1] * e2[2] - e1[2] * e2[1];
  f[1] = e1[2] * e2[0] - e1[0] * e2[2];
  f[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/// The back-face rule (PatchOptions::CullBackFaces, and the selector's count of what a budget
/// draws): a triangle of face normal `f` and first corner `x0` faces away when `f` points away
/// from the eye, `eye - x0`, or under a parallel projection along `direction`.
inline bool FacesAway(
  const double f[3], const float* x0, const double eye[3], bool parallel, const double direction[3])
{
  double d[3];
  for (int a = 0; a < 3; ++a)
  {
    d[a] = parallel ? -direction[a] : eye[a] - double(x0[a]);
  }
  return f[0] * d[0] + f[1] * d[1] + f[2] * d[2] < 0;
}

/// Options of GeneratePatches.
struct PatchOptions
{
  /**
   * When set, the owned triangles are decided in ranges run through it (vtkSMPTools in the VTK
   * layer), then written in order: the output is the same, point for point, as without it.
   */
  ParallelFor For;
  /// With For: about how many owned triangles one range decides.
  int64_t TrianglesPerRange = 16384;
  FoldHandling Folds = FoldHandling::ReverseNormals;
  /// Skip triangles facing away from the eye (a closed surface seen from outside).
  bool CullBackFaces = false;
  double Eye[3] = { 0, 0, 0 }; // octree-local coordinates (relative to the origin)
  bool Parallel = false;
  double ProjectionDirection[3] = { 0, 0, -1 }; // parallel projection
  /**
   * The octree's identity for the corner walks the workspace remembers (PatchWorkspace::Memo):
   * a value that changes whenever the octree's arrays do, and that no other octree drawn with
   * the same memo has (the VTK layer passes vtkMultiscaleOctree's checked stamp). Non-zero, with a
   * workspace given, each corner first tries the cluster its walk ended at in the last call with
   * the same value, and walks from its leaf only when that cluster's node is no longer a reached
   * cut node. 0 (default): every corner walks from its leaf. The output is the same either way for
   * a valid cut.
   */
  uint64_t OctreeStamp = 0;
};

/// What one owned triangle becomes, decided from the cut alone (GeneratePatches' phase that may
/// run in parallel; kept in the workspace between frames).
struct PatchDecision
{
  enum Kind : uint8_t
  {
    Draw,        ///< its three representatives
    DrawFold,    ///< turned over: on its own corners with reversed normals
    Collapsed,   ///< two corners share a representative (an inconsistent owner)
    Ghost,       ///< its lead corner is a ghost
    Hidden,      ///< among hidden cells, facing away or outside one common plane
    FoldDropped, ///< turned over, FoldHandling::Drop
    BackFace,    ///< facing away from the eye (CullBackFaces)
    Failed       ///< an index out of range or an invalid cut
  };
  Kind What = Draw;
  int32_t Rep[3] = { 0, 0, 0 }; ///< cluster >= 0, or -1 - surface point of an opened leaf
};

/**
 * Corner walks remembered for one octree (PatchOptions::OctreeStamp): per surface point, 1 + the
 * cluster its last walk ended at (a cut cluster then), 0 before its first walk. Workspaces that
 * draw the same octree can share one (the VTK layer's selector, for its exact count, and patch
 * generator: one array per point instead of two); they must not run at the same time with
 * different stamps. Any cut may use what another cut's walks remembered: an entry is used only
 * when its cluster's node is a cut node that the current walk reached.
 */
struct CornerMemo
{
  std::vector<int32_t> CutCluster;
  uint64_t Stamp = 0;
  int64_t Resets = 0; // how many times it was made empty for a new stamp or size
};

/**
 * Buffers kept between frames so that a frame allocates nothing new. Reached is zero pages
 * (plodResidentPages.h), written through its check where the walk marks the cut and read
 * directly: it takes memory where the cuts have been, not in proportion to the octree. The
 * arrays per cluster and per point are used for every corner, where that check would cost (see
 * docs/benchmarks.md): they are plain vectors, made zero when the octree changes.
 */
struct PatchWorkspace
{
  std::vector<int32_t> OutputOf; // 1 + output point of a cluster (or of an opened leaf's first
                                 // point), 0 for none
  ZeroPages<uint8_t> Reached;    // 1 for cut nodes the walk reached
  std::vector<int32_t> Touched;  // nodes whose entries must be cleared
  std::vector<int32_t> TouchedClusters;
  std::vector<int32_t> Stack;
  std::vector<int32_t> Refined; // nodes whose owned triangles are drawn
  // PatchOptions::For: the ranges of Refined, and each range's decisions and first error
  std::vector<size_t> RangeBounds;
  std::vector<std::vector<PatchDecision>> Decisions;
  std::vector<std::string> RangeErrors;
  std::vector<int64_t> RangeDrawn; // CountDrawnTriangles: each range's count
  // PatchOptions::OctreeStamp: the remembered corner walks (made when first needed, unless a
  // shared one was given)
  std::shared_ptr<CornerMemo> Memo;
};

/**
 * The triangles of the cut `state` (see plodCut.h). `cullMask`, when not null, holds for each
 * hidden node the frustum planes (bit i: plane i) wholly outside which its cell lies, 0 for a
 * back-facing cell; without it, triangles among hidden cells are skipped. Returns false when
 * the walk meets an invalid cut (a state above 3, an opened inner node, a leaf with no cut
 * ancestor, a corner whose cut cell lies below another cut node) and explains in `why`. The
 * walk reads no state below a cut node unless a drawn triangle's corner leads there, so errors
 * in such a subtree can pass unnoticed: the output is then the cut as seen from the root, and
 * it is always in range (found by the fuzzer: 64 of 137 corrupted cuts). ValidateCut checks
 * every node, at a cost proportional to the whole octree. The octree must be valid
 * (ValidateOctree). `out`'s vectors keep their capacity between calls.
 */
bool GeneratePatches(const OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
  PatchResult& out, std::string* why = nullptr, PatchWorkspace* workspace = nullptr,
  const PatchOptions& options = PatchOptions());

/**
 * How many triangles GeneratePatches would output for the cut `state` with `options` (folds
 * drawn or dropped, back faces, hidden cells and ghosts decided as it decides them), without
 * making them: its walk and its per-triangle rules, not its output. -1 (and `why`) on an
 * invalid cut.
 */
int64_t CountDrawnTriangles(const OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
  const PatchOptions& options, PatchWorkspace& workspace, std::string* why = nullptr);

/**
 * The triangles a cut draws, as ranges of the owner-sorted triangle array (the GPU path: the
 * triangles stay on the device and only these ranges are drawn, each corner moved to its
 * representative by the vertex shader). Those owned by the refined nodes and by the opened
 * leaves, in increasing order, ranges that touch merged: `first[i]`, `count[i]`. The same
 * triangles GeneratePatches considers, before its per-triangle rules (hidden cells, folds,
 * back faces, ghosts). False (and `why`) on an invalid cut, as GeneratePatches.
 */
bool DrawnTriangleRanges(const OctreeView& v, const uint8_t* state, std::vector<int64_t>& first,
  std::vector<int64_t>& count, std::string* why = nullptr, PatchWorkspace* workspace = nullptr);

/**
 * The spans [begin, end) of the `n` bytes where `now` differs from `before`, spans separated
 * by fewer than `gap` equal bytes merged (one upload instead of two small ones). Returns the
 * bytes the spans hold. The GPU path uploads only these spans of the cut's state.
 */
int64_t ChangedSpans(const uint8_t* before, const uint8_t* now, int64_t n, int64_t gap,
  std::vector<std::pair<int64_t, int64_t>>& spans);

} // namespace plod

#endif
