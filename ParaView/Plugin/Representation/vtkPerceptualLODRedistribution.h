// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODRedistribution
 * @brief   shares a distributed mesh out between ranks so that their octrees draw it crack-free
 *
 * Each rank holds a piece of a triangle mesh (any split: ParaView's readers, D3, a partition).
 * Built piece by piece, the octrees would not agree along the piece borders: a cell that two
 * pieces share gets a different representative vertex on each rank (from different points),
 * so a crack opens there even at full resolution. This filter makes every rank's octree agree
 * with the octree of the whole mesh on every cell whose triangles it draws. The partition is the
 * kernel plod::PartitionMesh (plodPartition.h, where its steps are stated): one root cube for
 * all ranks, owned cells of the ownership level k in Morton runs of about equal triangle counts,
 * every triangle meeting an owned cell or the cells those triangles touch (the halo), ghost
 * points (the point-data array vtkGhostType, vtkDataSetAttributes::DUPLICATEPOINT) where
 * another rank owns the point's level-k cell, the boundary edges of the whole mesh, and one
 * finest level. This filter gathers each rank's triangles, runs the kernel over the controller
 * and makes the rank's piece a vtkPolyData.
 *
 * Cells coarser than k hold points of several ranks and are complete nowhere: the selector must
 * refine them (vtkPerceptualLODSelector::SetMinimumLevel(k)); ConfigureBuilder and the
 * representation do it.
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
namespace plod
{
struct PartitionResult;
}
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
  /// The rank's piece as a vtkPolyData: double points, triangles, ghost flags and normals.
  void MakeOutput(const plod::PartitionResult& piece, vtkPolyData* output);

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
