// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPartition.h
 * @brief VTK-free partition of a triangle mesh by space between processes (or pieces), such
 *        that each one's octree draws its part exactly as the octree of the whole mesh would.
 *
 * Every process holds some triangles of one mesh (any split). PartitionMesh, called by every
 * process together, gives each one a piece to build:
 * 1. **One root cube**: the bounds of every usable triangle over all processes give the cube the
 *    builder would place for the whole mesh (build::PlaceRootCube), so levels align.
 * 2. **Owned cells**: the occupied cells of the ownership level k are counted (triangles per
 *    cell of their first corner, summed over the processes) and shared out in Morton order into
 *    contiguous runs of about equal triangle counts, one run per process.
 * 3. **Complete cells**: process r receives every triangle whose box of cells meets a cell it
 *    owns, and every triangle whose box meets a cell those triangles touch (the halo). A
 *    triangle's box is the level-k cells of its corners' level-21 cells, one level-21 cell wider
 *    on each side, since the builder counts a triangle touching a cell's face as meeting it.
 *    Each cell of level >= k that r's drawn triangles touch then holds, on r, every triangle of
 *    the whole mesh that meets it.
 * 4. **Ghost points**: the points whose level-k cell another process owns are flagged; the patch
 *    generator draws a triangle only where its lead corner is not a ghost, so every triangle is
 *    drawn by exactly one process.
 * 5. **Closed or open**: boundary and misoriented edges of the whole mesh, counted over the
 *    processes (each counts the edges with an end it owns), for the selector's back-face rule.
 * 6. **One finest level**: the builder's automatic level (ChooseFinestLevel, without memory
 *    lowering) from occupied-cell counts summed over the processes, or the requested one.
 * Points closer than RootEdge / 2^32 on every axis are merged (piece borders duplicate points,
 * not always to the last bit), and points and triangles are put in a canonical order (by
 * position), so every process holds a cell's points and triangles in the same order and
 * computes the same floating-point sums as a one-process build.
 *
 * Cells coarser than k hold points of several processes and are complete nowhere: the selector
 * must refine them (a minimum level of k).
 *
 * The processes talk through a Collective: MPI ranks in the ParaView plugin, threads in the
 * tests, a single process (SerialCollective) for a mesh split into pieces on one machine.
 */
#ifndef plodPartition_h
#define plodPartition_h

#include "plodLargeArrays.h"

#include <cstdint>
#include <string>
#include <vector>

namespace plod
{

/**
 * What the partition needs from the processes it shares a mesh between. Every process calls
 * each function in the same order (they are collective); each returns when all have called it.
 */
class Collective
{
public:
  virtual ~Collective() = default;
  virtual int Rank() const = 0;
  virtual int Ranks() const = 0;
  /// Element-wise sum, minimum or maximum over the processes, in place.
  virtual void Sum(int64_t* values, int64_t n) = 0;
  virtual void Min(double* values, int n) = 0;
  virtual void Max(double* values, int n) = 0;
  virtual void Max(uint8_t* values, int64_t n) = 0;
  /// Every process's `send`, concatenated in rank order, into `received` on `root` (left
  /// untouched elsewhere).
  virtual void Gather(const std::vector<double>& send, int root, std::vector<double>* received) = 0;
};

/// One process: every reduction is the identity.
class SerialCollective : public Collective
{
public:
  int Rank() const override { return 0; }
  int Ranks() const override { return 1; }
  void Sum(int64_t*, int64_t) override {}
  void Min(double*, int) override {}
  void Max(double*, int) override {}
  void Max(uint8_t*, int64_t) override {}
  void Gather(const std::vector<double>& send, int, std::vector<double>* received) override
  {
    *received = send;
  }
};

/// This process's triangles. Triangles with an index out of range or a non-finite corner are
/// left out (counted in PartitionResult::NumberOfSkippedTriangles).
struct PartitionInput
{
  int64_t NumberOfPoints = 0;
  const double* Points = nullptr; ///< 3 per point
  /// 3 per point, or null; used only when every process has normals (or no triangles)
  const double* Normals = nullptr;
  int64_t NumberOfTriangles = 0;
  const int64_t* Triangles = nullptr; ///< 3 point ids per triangle
};

struct PartitionParameters
{
  int OwnershipLevel = 3;        ///< k, 1 to 6
  int RequestedFinestLevel = -1; ///< negative: the builder's automatic level of the whole
};

/// This process's piece and what all processes agreed on.
struct PartitionResult
{
  bool Ok = false;
  std::string Error;
  /// No process holds a usable triangle: nothing was shared out (the piece is empty).
  bool NoTriangles = false;
  double RootOrigin[3] = { 0, 0, 0 };
  double RootEdge = 0;
  int FinestLevel = 0;
  int64_t NumberOfOwnedCells = 0;       ///< occupied level-k cells this process owns
  int64_t NumberOfHaloTriangles = 0;    ///< triangles all of whose corners are ghosts
  int64_t NumberOfBoundaryEdges = 0;    ///< over all processes: boundary + misoriented edges
  int64_t NumberOfSkippedTriangles = 0; ///< this process's unusable input triangles
  bool HasNormals = false;              ///< every process had normals

  LargeVector<double> Points;     ///< 3 per point, in canonical order
  LargeVector<double> Normals;    ///< 3 per point when HasNormals
  LargeVector<uint8_t> Ghost;     ///< 1 per point: owned by another process
  LargeVector<int64_t> Triangles; ///< 3 per triangle, in canonical order
};

/// Shares the mesh out (see the file's documentation). Collective: every process calls it.
PartitionResult PartitionMesh(
  const PartitionInput& input, const PartitionParameters& parameters, Collective& collective);

} // namespace plod

#endif
