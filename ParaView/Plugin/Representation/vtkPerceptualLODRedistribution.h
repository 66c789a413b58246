// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODRedistribution
 * @brief   shares a distributed mesh out between ranks so that their octrees draw it crack-free
 *
 * Each rank holds a piece of a triangle mesh (any split: ParaView's readers, D3, a partition).
 * Built piece by piece, the octrees would not agree along the piece borders: a cell that two
 * pieces share gets a different representative vertex on each rank (from different points),
 * so a crack opens there even at full resolution. This filter makes every rank's octree agree
 * with the octree of the whole mesh on every cell whose triangles it draws:
 *
 * 1. **One root cube**: the global bounds (all ranks) give the cube the builder would place for
 *    the whole mesh (plod::PlaceRootCube), so the levels of every rank align.
 * 2. **Owned cells**: the occupied cells of the ownership level k (default 3) are counted
 *    (triangles per cell, summed over the ranks) and shared out in Morton order into
 *    contiguous runs of about equal triangle counts, one run per rank.
 * 3. **Complete cells**: rank r receives every triangle whose bounding box meets a cell it owns,
 *    and every triangle whose bounding box meets a cell those triangles touch (the "halo").
 *    Each cell of level >= k that rank r's drawn triangles touch is then complete on r: it
 *    holds every triangle that meets it, as in the whole mesh, so its vertex, cone, error and
 *    clusters are the whole mesh's.
 * 4. **Ghost points**: points whose level-k cell another rank owns are marked in the point-data
 *    array vtkGhostType (vtkDataSetAttributes::DUPLICATEPOINT). The patch generator draws a
 *    triangle only on the rank that owns its lead corner (its corner in the lowest leaf), so
 *    every triangle is drawn by exactly one rank, with the same corners as in a one-rank build.
 * 5. **Closed or open**: the boundary edges of the whole mesh are counted (each rank counts
 *    the edges with an end it owns), for the selector's automatic back-face rule: each rank's
 *    own octree has the halo's rim as boundary and would always draw back faces.
 * 6. **One finest level**: the automatic level (plod::ChooseFinestLevel) from occupied-cell
 *    counts summed over the ranks (each rank counts its owned points; levels above k from the
 *    shared histogram), or RequestedFinestLevel when it is not negative.
 *
 * Cells coarser than k hold points of several ranks and are complete nowhere: the selector must
 * refine them (vtkPerceptualLODSelector::SetMinimumLevel(k)); ConfigureBuilder and the
 * representation do it. Coincident points are merged (a piece border duplicates the points it
 * cuts through, not always to the last bit): points within RootEdge / 2^32 on every axis, far
 * below the single precision of the octree's points, become one. Points and triangles are put
 * in a canonical order (by position), so every rank holds a cell's points and triangles in the
 * same order and computes the same floating-point sums.
 *
 * Ghost cells of the input (cell array vtkGhostType, DUPLICATECELL or HIDDENCELL: the ghost
 * layers ParaView's filters ask for) are left out, since the rank that owns a cell sends it; the
 * input's own vtkGhostType point array is replaced by this filter's.
 * Carried with the triangles: coordinates and point normals (when every piece has them).
 * Other point and cell arrays (material arrays) are not carried in parallel.
 * Point clouds (no triangles) are not redistributed: each rank builds its own cloud with the
 * shared root cube and level, so levels align but a seam can show along piece borders.
 *
 * Every rank must execute it together (it is collective), with or without a piece.
 *
 * @sa vtkPerceptualLODRepresentation vtkMultiscaleOctreeBuilder vtkMultiscalePatchGenerator
 */
#ifndef vtkPerceptualLODRedistribution_h
#define vtkPerceptualLODRedistribution_h

#include "PerceptualLODParaViewRepresentationModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class vtkMultiProcessController;
class vtkMultiscaleOctreeBuilder;

class PERCEPTUALLODPARAVIEWREPRESENTATION_EXPORT vtkPerceptualLODRedistribution
  : public vtkPolyDataAlgorithm
{
public:
  static vtkPerceptualLODRedistribution* New();
  vtkTypeMacro(vtkPerceptualLODRedistribution, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The ranks (default: the global controller).
  void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  ///@{
  /// Level of the owned cells (default 3; 1 to 6).
  vtkSetClampMacro(OwnershipLevel, int, 1, 6);
  vtkGetMacro(OwnershipLevel, int);
  /// The finest level to build at; negative (default): chosen from the whole mesh.
  vtkSetMacro(RequestedFinestLevel, int);
  vtkGetMacro(RequestedFinestLevel, int);
  ///@}

  ///@{
  /// Results of the last execution (the same on every rank but the counts).
  vtkGetVector3Macro(RootOrigin, double);
  vtkGetMacro(RootEdge, double);
  vtkGetMacro(FinestLevel, int);
  vtkGetMacro(NumberOfOwnedCells, int);
  vtkGetMacro(NumberOfHaloTriangles, vtkIdType);
  /**
   * Edges of the whole mesh used by one triangle, or by two triangles in the same direction
   * (inconsistently oriented); an edge seen by two ranks counts twice; zero means the mesh is
   * closed and consistently oriented, so back faces can be hidden. Each rank's octree also has its
   * halo's rim as boundary, so the selector's automatic back-face rule must use this number instead
   * (the representation does).
   */
  vtkGetMacro(NumberOfBoundaryEdges, vtkIdType);
  ///@}

  /// Sets the builder to this cube and level (UseGivenRootCube, RootCubeOrigin, RootCubeEdge,
  /// FinestLevel).
  void ConfigureBuilder(vtkMultiscaleOctreeBuilder* builder);

protected:
  vtkPerceptualLODRedistribution();
  ~vtkPerceptualLODRedistribution() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkMultiProcessController* Controller = nullptr;
  int OwnershipLevel = 3;
  int RequestedFinestLevel = -1;
  double RootOrigin[3] = { 0, 0, 0 };
  double RootEdge = 1;
  int FinestLevel = 0;
  int NumberOfOwnedCells = 0;
  vtkIdType NumberOfHaloTriangles = 0;
  vtkIdType NumberOfBoundaryEdges = 0;

private:
  vtkPerceptualLODRedistribution(const vtkPerceptualLODRedistribution&) = delete;
  void operator=(const vtkPerceptualLODRedistribution&) = delete;
};

#endif
