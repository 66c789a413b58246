// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeBuilder.h
 * @brief VTK-free kernel that turns a triangle mesh or a point cloud into the multiscale octree
 * of SRCC §2-3.3 (see plodOctree.h for the layout).
 *
 * Algorithm, in phases (each parallel over fixed-size ranges, so that results do not depend on
 * the number of threads):
 * 1. Root cube around the bounds of the used points, with a margin of 1/32 of the extent on each
 *    side and a small irrational shift, so that no sample lies on the root boundary and regular
 *    ("nice") input coordinates almost never fall exactly on a grid plane.
 * 2. Samples at the finest level: every used input vertex; every point where a triangle crosses
 *    a finest grid edge (found by a watertight 2D point-in-triangle test per grid line, with
 *    ties broken by symbolic perturbation, so that a line through a shared mesh edge or vertex is
 *    counted once); for point clouds, crossings where a signed distance to the oriented samples
 *    (Hoppe et al. 1992) changes sign along a finest edge. A crossing belongs to the four cells
 *    around its edge, which therefore always exist.
 * 3. Samples are sorted by Morton key (radix sort); each run of equal keys is one finest cell.
 *    Per cell: vertex (mean rule or QEF rule), normal cone, material range, edge-crossing word.
 * 4. Coarser levels from the finer ones: cones by SRCC eq. (1)-(2), shape error by eq. (3) over
 *    the finest descendants, material by min/max, crossings by summing the two half edges,
 *    vertices by the same rule as the finest level over the cell's own samples.
 */
#ifndef plodOctreeBuilder_h
#define plodOctreeBuilder_h

#include "plodOctree.h"

#include <cstdint>
#include <functional>
#include <string>

namespace plod
{

/// How the representative vertex of a cell is computed.
enum class VertexRule
{
  /// SRCC §2 / METHOD §1: mean of the input vertices inside the cell and of the points where the
  /// surface crosses the cell's own edges (falls back to the mean of the children's vertices).
  Mean = 0,
  /// Minimiser of the sum of the plane quadrics of the surface in the cell (Lindstrom 2000,
  /// Ju et al. 2002), solved by a truncated eigen-decomposition about the mean, clamped to the
  /// cell.
  QEF = 1
};

/// Input arrays. Only `Points` is mandatory. All pointers are borrowed.
struct BuildInput
{
  int64_t NumberOfPoints = 0;
  const double* Points = nullptr; // 3 per point

  /// Triangles (3 point indices each). Null or zero triangles: the input is a point cloud.
  int64_t NumberOfTriangles = 0;
  const int64_t* Triangles = nullptr;

  /// Point cloud normals (3 per point, need not be unit). Null: estimated (PCA) and oriented.
  const float* PointNormals = nullptr;
  /// Orientation target for estimated normals: per point (3 per point) or one for all.
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
};

/// Build parameters.
struct BuildParameters
{
  /// Finest level; negative: chosen from the input (see ChooseFinestLevel).
  int FinestLevel = -1;
  VertexRule Rule = VertexRule::Mean;
  /// Upper bound for the memory the build may use, in bytes.
  double MemoryLimit = 4.0e9;
};

/// Runs `body(begin, end)` over [0, n) split in ranges of at most `grain`, possibly in parallel.
using ParallelFor =
  std::function<void(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body)>;

/// Sequential ParallelFor, for tests and for the single-threaded benchmark.
void SerialFor(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body);

/// Receives the total node count and returns the arrays to fill.
using Allocator = std::function<OctreeArrays(int64_t numberOfNodes)>;

/// Called with the fraction done in [0, 1]; return false to abort.
using ProgressCallback = std::function<bool(double)>;

/// Outcome of a build.
struct BuildResult
{
  bool Ok = false;
  bool Aborted = false;
  std::string Error;
  int64_t NumberOfNodes = 0;
  int FinestLevel = 0;
  double Origin[3] = { 0, 0, 0 };
  double RootEdge = 1;
  int64_t NumberOfCrossings = 0; // finest-level edge crossings found
  int64_t NumberOfSkippedTriangles = 0; // degenerate triangles (no area)
};

/**
 * Chooses the finest level from the input, with the root cube already known:
 * - meshes: the level whose cell edge is closest (in log scale) to the median triangle edge;
 * - point clouds: the deepest level where occupied cells hold on average at least 4 points
 *   (about two point spacings per cell, so neighbouring cells overlap in their samples);
 * then lowered until the estimated memory fits `memoryLimit`.
 */
int ChooseFinestLevel(const BuildInput& input, const double origin[3], double rootEdge,
  double memoryLimit);

/// Estimated peak bytes of a build at `level` (samples, sort buffers and nodes).
double EstimateBuildMemory(const BuildInput& input, double rootEdge, int level);

/// Builds the octree. Returns Ok == false with an error message on invalid input.
BuildResult BuildOctree(const BuildInput& input, const BuildParameters& parameters,
  const Allocator& allocate, const ParallelFor& parallelFor = SerialFor,
  const ProgressCallback& progress = nullptr);

} // namespace plod

#endif
