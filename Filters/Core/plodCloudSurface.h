// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodCloudSurface.h
 * @brief Internal (not installed): the mesh of a point cloud, for the octree build.
 *
 * Wang & Sato build the finest level from scattered range data; the octree here needs a mesh,
 * so a cloud is contoured once, at its finest level:
 * 1. normals: given, or by PCA over the points within one cell edge, oriented towards each
 *    point's scanner, a common viewpoint, or away from the centroid (at most 512 candidates
 *    per point, at an even stride, so that a cell piled with points costs linear time);
 * 2. a signed distance to the oriented points (Hoppe et al. 1992: Gaussian-weighted distances to
 *    the tangent planes of the points in the 8 cells around a grid corner) at the corners of the
 *    occupied cells;
 * 3. dual contouring of its sign changes at that one level: one vertex per cell next to a sign
 *    change, at the mean of the crossings on its edges (surface nets), with the mean normal and
 *    the material range of the points that gave those crossings; one quad per crossed edge,
 *    oriented by the sign change and split along its shorter diagonal.
 * The result is a closed-where-sampled, consistently oriented mesh whose vertices lie one per
 * cell; the octree build then clusters it like any mesh. Sheets closer than a cell edge merge
 * in the signed distance, as in any grid reconstruction.
 */
#ifndef plodCloudSurface_h
#define plodCloudSurface_h

#include "plodBuildUtil.h"
#include "plodOctreeBuilder.h"

#include <vector>

namespace plod
{
namespace build
{

/// A point cloud's contoured mesh, in world coordinates.
struct CloudMesh
{
  LargeVector<double> Points;     // 3 per vertex
  LargeVector<int64_t> Triangles; // 3 per triangle
  LargeVector<float> Normals;     // 3 per vertex
  LargeVector<int64_t> InputIds;  // -1 per vertex (contoured points are not input points)
  LargeVector<float> DiffuseMin, DiffuseMax, SpecularMin, SpecularMax; // per vertex, or empty
  double Origin[3] = { 0, 0, 0 };
  double RootEdge = 1;
  int Level = 0;
};

/**
 * Contours the cloud `in` (no triangles) at its finest level (params.FinestLevel, or the cloud
 * rule of ChooseFinestLevel). Returns false with result.Error set (or on abort).
 */
bool MakeCloudMesh(const BuildInput& in, const BuildParameters& params, const ParallelFor& pfor,
  Reporter& report, CloudMesh& out, BuildResult& result);

} // namespace build
} // namespace plod

#endif
