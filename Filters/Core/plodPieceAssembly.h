// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPieceAssembly.h
 * @brief VTK-free build of an octree file from a PLY file split into pieces (plodPieces.h):
 *        each piece built on its own, the pieces' cells put together into one octree file,
 *        in bounded memory.
 *
 * Each piece is built in memory (BuildOctree, with the agreed root cube and finest level) and
 * the part of its octree it owns is kept in temporary files, one per array and level: its
 * nodes of level k (the ownership level) and finer, their clusters, its points and the
 * triangles they own. Piece p owns a Morton run of level-k cells, so its part of each level
 * follows the parts of pieces 0 .. p-1, and the octree file is their concatenation, level by
 * level, with every index shifted to its place. Each owned cell is complete in its piece
 * (plodPartition.h), so levels k and finer are the whole mesh's octree, node for node:
 * vertices, clusters, cones, shape errors, flags, points and the triangles each node owns.
 *
 * The levels above k: one node per occupied cell (the ancestors of the level-k cells, as in
 * the whole mesh's octree) and the triangles they own (those whose corners lie in three level-k
 * cells), taken from the piece that owns their lead corner. Those triangles, with their corners
 * at the clusters of level k, are the level-k cut, every triangle a cut above k can draw: an
 * octree of that mesh alone (BuildOctree over the level-k clusters as points, the agreed root
 * cube, finest level k) gives the cells above k their clusters (the connected pieces of the cut
 * inside them), the clusters' vertices (the vertex rule over the cut's planes) and normals, the
 * cluster tree from level k up, the node vertices and the topology flags and thickness. What
 * the children bound is added: the cone holds the level-k cones inside (SRCC eq. (2)), the
 * shape error adds the largest level-k error inside to the cut's own, the boundary flag is the
 * children's; the material ranges are uniform, as everywhere in a build from a PLY file's
 * pieces (they carry no materials). A cell the cut's octree lacks (only triangles of finer
 * levels inside) keeps one cluster at its first surface point, a cone of pi, an error and a
 * thickness of its diagonal. The differences from the whole mesh's octree are named and
 * measured (docs/benchmarks.md, "The levels above the pieces"): above k, vertices, cones,
 * errors, flags and clusters come from the level-k cut rather than the input (a cut there draws
 * the same triangles with corners moved a few percent of a cell); the input point ids are -1
 * (the pieces renumber the points); the non-manifold and misoriented edge counts are sums over
 * the pieces (edges near a piece's border may be counted twice: zero stays zero); the
 * boundary-edge count is the partition's. Where the cut's octree cannot be built (more than the
 * memory limit), the levels above k hold structure only and the file's coarsest drawn level is
 * k (AssemblyReport::StructureOnly says why), as a distributed build's are.
 *
 * The file is written by WriteOctreeFile from the temporary files (FileArray::Values), never
 * rewriting the target in place.
 */
#ifndef plodPieceAssembly_h
#define plodPieceAssembly_h

#include "plodOctreeBuilder.h"
#include "plodOctreeFile.h"
#include "plodParallel.h"
#include "plodPieces.h"

#include <cstdint>
#include <functional>
#include <string>

namespace plod
{

struct AssemblyParameters
{
  /// The vertex rule of every piece's build.
  VertexRule Rule = VertexRule::QEF;
  /// Bytes one piece may use, as its pieces were sized (PiecesParameters::MemoryLimit). The
  /// build's own estimate, which is larger than what it takes, is checked against twice it.
  double MemoryLimit = 4.0e9;
  /// How each piece's build runs its ranges (and the compact file's compression).
  ParallelFor Parallel = SerialFor;
  /// How the file stores its arrays (FileLayout::Compact: compressed, see plodOctreeFile.h).
  FileLayout Layout = FileLayout::Mapped;
  /// Remove each piece's temporary file once it is read (PLYPieces::RemovePiece), so that the
  /// temporary disk holds the pieces not yet built beside the parts kept so far, not every piece
  /// to the end. The pieces cannot then be assembled again.
  bool RemovePiecesAsBuilt = false;
  /// Called with the fraction done of the current step, in [0, 1], and the step's name
  /// ("building the pieces", "writing the file"); return false to abort.
  std::function<bool(double, const char*)> Progress;
};

/// What the assembly made.
struct AssemblyReport
{
  int64_t NumberOfNodes = 0;
  int64_t NumberOfClusters = 0;
  int64_t NumberOfPoints = 0;
  int64_t NumberOfTriangles = 0;
  int FinestLevel = 0;
  int CoarsestDrawnLevel = 0;
  /// Nodes above the coarsest drawn level (structure only; none unless StructureOnly says why).
  int64_t NumberOfStructureNodes = 0;
  /// Empty when the levels above k were built from the level-k cut; else why they hold
  /// structure only (the coarsest drawn level is then k).
  std::string StructureOnly;
  /// Triangles owned by the nodes above k (taken from the pieces as they are).
  int64_t NumberOfStructureTriangles = 0;
  /// The most bytes the temporary files held at once while the assembly ran: its own and
  /// what the pieces' still held.
  int64_t PeakTemporaryBytes = 0;
  /// Bytes of the octree file written.
  int64_t FileBytes = 0;
};

/**
 * Builds every piece of `pieces` and writes the octree they make to `path` (see the file's
 * documentation). False with the reason in `why` on a piece whose build fails, a temporary file
 * that cannot be written, an octree too large for one file (2^31 - 1 nodes, points or
 * triangles), an abort or a file that cannot be written; `path` is then left as it was. The
 * temporary files go in the pieces' temporary directory and are removed. Never throws.
 */
bool WriteOctreeFileFromPieces(PLYPieces& pieces, const std::string& path,
  const AssemblyParameters& parameters, AssemblyReport* report, std::string* why);

} // namespace plod

#endif
