// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeBuilder.h
 * @brief VTK-free kernel that turns a triangle mesh or a point cloud into the multiscale octree
 * of SRCC §2-3.3 (see plodOctree.h for the layout).
 *
 * The surface: a vertex-clustering hierarchy over the input's own triangles.
 * Every octree cell stands for the input points inside it. A cut draws the input's triangles
 * with each corner moved to the representative vertex of the cut cell that holds it; triangles
 * whose corners fall into fewer than three cells vanish. Its properties, each measured or proved
 * against the dual contouring of edge crossings (Ju et al. 2002) that this project used first
 * (docs/results/surface.md):
 * - the finest cut (every leaf opened) *is* the input: its triangles, points and shading
 *   normals. Dual contouring resampled the surface on the grid and never reached the input's
 *   picture at any depth, with more triangles than the input;
 * - no crack at any cut: triangles share corners exactly as the input's do, so a cut maps a
 *   closed, consistently oriented input to a closed, consistently oriented set of triangles
 *   (every edge used as often in each direction);
 * - no cancellation: two sheets inside one cell keep all their triangles (the signed crossings
 *   of dual contouring summed to zero there and opened holes in every thin part). A thin wall
 *   collapses into coincident front and back triangles, not into a hole;
 * - a cut never draws more triangles than the input has.
 * What it cannot do: a tube thinner than a cell collapses into a line and disappears (its
 * triangles degenerate). Each node records whether its sub-mesh is a union of discs (Euler
 * characteristic, plodOctree.h); the selector refines cells that are not while they cover more
 * than a pixel, so a thin rod is drawn until it is thinner than a pixel. Chosen by measurement
 * over the Stanford bunny and Lucy: the per-component disc test flags 0-1 % of the cells of
 * levels 3-10, where counting components alone (two pieces of a jagged cell border) flagged 24-75 %
 * of the mid levels for no visible reason.
 *
 * Clusters: a cell whose sub-mesh falls apart into several connected pieces (the two sheets of
 * a thin wall, two fingers) gets one representative vertex and one shading normal per piece,
 * so that the pieces collapse separately instead of onto one point between them (plodOctree.h,
 * ClusterData). Boundary edges add constraint planes to the vertex placement (Garland-Heckbert
 * boundary quadrics) so that an open rim does not shrink.
 *
 * Phases (each parallel over fixed ranges where it pays, so that results do not depend on the
 * number of threads; progress and abort are honoured between blocks of every long loop; set
 * PLOD_BUILD_TIMING=1 to print each phase's time and memory):
 * 1. scan: triangles with an index out of range or a non-finite corner are dropped and counted;
 *    triangles repeating a point are dropped (they draw nothing at any cut); points used by no
 *    triangle are dropped;
 * 2. root cube around the bounds, with a margin of 1/32 of the extent on each side and a small
 *    irrational shift, so that no point lies on the root boundary (PlaceRootCube); or the cube
 *    the caller gives (BuildParameters::HasRootCube), which must hold every point;
 * 3. points sorted by Morton key at level 21; the finest level chosen (see ChooseFinestLevel);
 * 4. tree: one leaf per occupied finest cell, parents up to the root; point ranges;
 * 5. surface: points, triangles sorted by owner node (the deepest node holding two of its
 *    corners, where it collapses), point-to-triangle incidence, shading normals (the input's, or
 * area-weighted);
 * 6. edges: every unique edge once; boundary and non-manifold edges counted; boundary planes;
 * 7. clusters: per level, union-find over the edges inside each cell; a cluster per connected
 *    piece; topology flags (Euler characteristic equal to the number of pieces: a union of
 *    discs) and the Boundary flag;
 * 8. passing triangles: the cells a triangle crosses without a corner inside (so that cones and
 *    material ranges hold every triangle that meets the cell);
 * 9. cells, bottom-up: area-weighted normal cone axis, quadric sums, vertex per cluster (QEF or
 *    mean rule), material ranges, thickness (cells that are not unions of discs, for the
 *    selector's topology rule); leaf cone angles exact;
 * 10. cones above the leaves made exact: the largest angle from the axis to the normal of any
 *    triangle meeting the cell. SRCC eq. (2) over the children's cones is a valid bound but its
 *    slack grows level after level (median 2.25 rad against 1.29 rad really there at level 5 of
 *    a dense scan), which left most coarse cells neither front- nor back-facing;
 * 11. shape error, SRCC eq. (3), per cluster along the cluster's normal; the cell's is the
 *    largest of its clusters'.
 * Point clouds first become a mesh: normals (given, or by PCA oriented towards the scanner), a
 * signed distance to the oriented points (Hoppe et al. 1992) at the corners of the occupied cells
 * of the cloud's finest level, and dual contouring of its sign changes at that one level; then
 * the mesh is built as above, one leaf per contoured cell.
 *
 * Distributed builds (one piece of a mesh per process, drawn without cracks along the pieces'
 * borders): every process builds with the same given root cube and the same finest level, so
 * that the Morton keys, the cells and the order of the surface points agree between processes,
 * and a cell whose content (its points and the triangles at them) is complete in a piece gets
 * the vertices, clusters and shape error of the whole mesh's build. Ghost flags (BuildInput::
 * PointGhost: points owned by another process) take part in nothing the build computes; the
 * octree only keeps them (OctreeArrays::PointGhost) for the patch generator, which draws a
 * triangle only where its lead corner is not a ghost (plodPatches.h).
 */
#ifndef plodOctreeBuilder_h
#define plodOctreeBuilder_h

#include "plodOctree.h"
#include "plodParallel.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace plod
{

/// How the representative vertex of a cell is computed.
enum class VertexRule
{
  /// SRCC §2 (docs/design.md, "The octree"), as far as it applies to a cluster of input points: the
  /// mean of the input points inside the cell (the paper adds the points where the surface crosses
  /// the cell's edges; this surface has no such crossings, see the file documentation).
  Mean = 0,
  /// Minimiser of the sum of the plane quadrics of the triangles at the cell's points
  /// (Lindstrom 2000), solved by a truncated eigen-decomposition about the mean point and
  /// clamped to the cell. The default: better pictures than the mean rule at equal triangles
  /// on every model measured (docs/results/faithful.md).
  QEF = 1
};

/**
 * Input arrays. All pointers are borrowed. Each optional array, when not null, must hold one
 * entry per point or per triangle (three for vectors); the VTK layer checks the lengths.
 */
struct BuildInput
{
  int64_t NumberOfPoints = 0;
  const double* Points = nullptr;     // 3 per point: this one, or
  const float* PointsFloat = nullptr; // this one

  /// Triangles (3 point indices each). None: the input is a point cloud.
  int64_t NumberOfTriangles = 0;
  const int64_t* Triangles = nullptr;   // this one, or
  const int32_t* Triangles32 = nullptr; // this one

  /// Point normals (3 per point, need not be unit). Meshes: the shading normals of the finest
  /// cut (else the normalised sum of the unit normals of each point's triangles). Clouds: the
  /// oriented normals (else estimated by PCA and oriented).
  const float* PointNormals = nullptr;
  /// Clouds: orientation target for estimated normals, per point (3 per point) or one for all.
  const double* PointViewpoints = nullptr;
  double Viewpoint[3] = { 0, 0, 0 };
  bool HasViewpoint = false; // false: orient away from the centroid of the cloud

  /// Material reflectances, per point or per triangle (one value each); null means uniform.
  const float* PointDiffuse = nullptr;
  const float* PointSpecular = nullptr;
  const float* TriangleDiffuse = nullptr;
  const float* TriangleSpecular = nullptr;
  float UniformDiffuse = 1.0f;
  float UniformSpecular = 0.0f;

  /// Meshes, optional: per point, non-zero when the point is a ghost (owned by another process:
  /// VTK's vtkGhostType bit DUPLICATEPOINT). The flags change nothing in the build; each surface
  /// point keeps its input point's flag in OctreeArrays::PointGhost. Point clouds: ignored, with
  /// a warning (their surface's points are contoured, not input points, so no flag carries over).
  const uint8_t* PointGhost = nullptr;
};

/// Build parameters.
struct BuildParameters
{
  /// Finest level; negative: chosen from the input (see ChooseFinestLevel).
  int FinestLevel = -1;
  VertexRule Rule = VertexRule::QEF;
  /// Upper bound for the memory the build may use, in bytes (the input not counted). An
  /// automatic level is lowered to fit it; a mesh at a level set by the user that would not fit
  /// fails, and so does a point cloud whose contoured surface would not.
  double MemoryLimit = 4.0e9;
  /**
   * A root cube given by the caller instead of the one PlaceRootCube would place around the
   * input (for distributed builds: every process uses the cube of the global bounds). Meshes and
   * point clouds use it as it is: lower corner RootOrigin, edge RootEdge (world units). It must
   * pass build::ValidateRootCube (finite, an edge PlaceRootCube could give) and hold every point
   * the build uses (a mesh: the points of its valid triangles; a cloud: its finite points) in
   * the closed cube; a point outside is an error naming it (points are never clamped into it).
   * Unlike a placed cube it has no margin: a point on its upper faces falls into the last cell,
   * and a cloud's surface is not contoured across its faces.
   */
  bool HasRootCube = false;
  double RootOrigin[3] = { 0, 0, 0 };
  double RootEdge = 0;
};

/**
 * Makes the arrays to fill: `Nodes` receives the node, point and triangle counts and returns the
 * node and surface arrays; `Clusters`, called later with the cluster count, sets the cluster
 * arrays in `arrays` (keeping the others).
 */
struct Allocator
{
  std::function<OctreeArrays(int64_t numberOfNodes, int64_t numberOfPoints, int64_t triangles)>
    Nodes;
  std::function<void(int64_t numberOfClusters, OctreeArrays& arrays)> Clusters;
  /// Called after `Nodes` only when the input has ghost flags (BuildInput::PointGhost, a mesh):
  /// sets arrays.PointGhost to an array of `numberOfPoints` bytes. Unset, or leaving the pointer
  /// null, fails the build (dropping the flags would make every process draw every triangle).
  std::function<void(int64_t numberOfPoints, OctreeArrays& arrays)> PointGhost;
};

/// Called with the fraction done in [0, 1] (on the calling thread); return false to abort.
using ProgressCallback = std::function<bool(double)>;

/// Outcome of a build.
struct BuildResult
{
  bool Ok = false;
  bool Aborted = false;
  std::string Error;
  /// Problems that did not stop the build (dropped triangles, a level lowered by the memory
  /// limit, ...), one sentence each.
  std::vector<std::string> Warnings;
  int64_t NumberOfNodes = 0;
  int64_t NumberOfClusters = 0;
  int FinestLevel = 0;
  /// Why the finest level is what it is (one sentence).
  std::string LevelReason;
  double Origin[3] = { 0, 0, 0 };
  double RootEdge = 1;
  int64_t NumberOfPoints = 0;              // surface points kept
  int64_t NumberOfTriangles = 0;           // surface triangles kept
  int64_t NumberOfInvalidTriangles = 0;    // an index out of range or a non-finite corner
  int64_t NumberOfDegenerateTriangles = 0; // a point repeated
  int64_t NumberOfNonFinitePoints = 0;
  int64_t NumberOfUnsafeNodes = 0;      // nodes without NodeTopologySafe
  int64_t NumberOfBoundaryEdges = 0;    // edges used by one triangle
  int64_t NumberOfNonManifoldEdges = 0; // edges used by more than two
  /// Edges used by two triangles in the same direction: the triangles disagree on which side is
  /// the front (an inconsistently oriented mesh), so back faces cannot be hidden.
  int64_t NumberOfMisorientedEdges = 0;
  /// Surface points at the position of another surface point (a mesh whose triangles do not
  /// share their vertices there); more than a tenth of the points gives a warning.
  int64_t NumberOfCoincidentPoints = 0;
  int64_t NumberOfGhostPoints = 0; // surface points flagged as ghosts
  double EstimatedBytes = 0;       // estimated peak of the build's own memory
};

/// Estimated peak bytes of a build's own memory (outputs and work arrays, not the input).
double EstimateBuildMemory(int64_t points, int64_t triangles, int64_t nodes, bool cloud);

/// The least memory a build of that many points and triangles needs: EstimateBuildMemory at
/// its coarsest useful level (level 1, at most 9 nodes), which an automatic level is lowered
/// towards to fit a limit. An input that needs more than a limit cannot be built within it.
double LeastBuildMemory(int64_t points, int64_t triangles, bool cloud);

/// Estimated bytes of the octree of a mesh of distinct points at the automatic level (leaves
/// of about four points, one cluster per node): the arrays of the schema, which the octree
/// file stores one for one.
double EstimateOctreeBytes(int64_t points, int64_t triangles);

/**
 * The default finest level, from the number of occupied cells of each level 0..21
 * (`cellsPerLevel`, non-decreasing) over the input points:
 * - meshes: the shallowest level at which the occupied cells number at least a quarter of the
 *   distinct point positions (cells of level 21), at least 1: leaves hold about four points, so
 *   they follow the input's own detail (an opened leaf draws its input triangles), a tiny mesh
 *   (a tetrahedron, one triangle) still gets its corners apart at level 1, and duplicated points
 *   cannot drive it to level 21;
 * - point clouds: the deepest level whose occupied cells hold at least 4 points on average
 *   (about two point spacings per cell), at least 1;
 * then lowered while the estimated memory exceeds the limit. `reason` says which rule decided.
 */
int ChooseFinestLevel(const int64_t cellsPerLevel[MaxFinestLevel + 1], int64_t points,
  int64_t triangles, bool cloud, double memoryLimit, std::string* reason = nullptr);

/**
 * The automatic finest level from counts gathered elsewhere (the processes of a distributed
 * build): ChooseFinestLevel without the memory limit's lowering, after checking that the counts
 * can come from points (cellsPerLevel[0] is 1, no count decreases or grows more than 8 times
 * from one level to the next, and `points` is at least cellsPerLevel[21]). Returns -1 for
 * counts that cannot.
 */
int ChooseFinestLevelFromCounts(
  const int64_t cellsPerLevel[MaxFinestLevel + 1], int64_t points, bool cloud);

/// Builds the octree. Returns Ok == false with an error message on invalid input.
BuildResult BuildOctree(const BuildInput& input, const BuildParameters& parameters,
  const Allocator& allocate, const ParallelFor& parallelFor = SerialFor,
  const ProgressCallback& progress = nullptr);

} // namespace plod

#endif
