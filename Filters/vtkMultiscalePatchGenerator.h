// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscalePatchGenerator
 * @brief   crack-free triangles from a cut through a multiscale octree
 *
 * Turns the cut carried by a vtkMultiscaleOctree (its "CutState" node array, made by
 * vtkPerceptualLODSelector or vtkMultiscaleOctreeCutter) into the vtkPolyData that is drawn:
 * SRCC §2 (Wakatsuki et al. 2003) and its reference 14, dual contouring on minimal edges
 * (Ju et al. 2002). The representative vertices of the cells sharing an edge the surface
 * crosses are joined; cells of different levels meet without cracks because a coarse edge's
 * crossing is the signed sum of its halves. See plodPatches.h for the algorithm.
 *
 * Output:
 * - points: the representative vertices of the cut cells used (world coordinates, double
 *   precision when the octree sits far from the origin relative to its size, else float);
 * - triangles, oriented like the input's (their normals agree with the input's outward side);
 * - point normals from the cells' normal cone axes (SRCC shades by interpolating them);
 * - optionally (GenerateColors) RGB colours from the cells' mean diffuse reflectance (grey);
 * - optionally (GenerateNodeIds) the point array "OctreeNode": the node of each point.
 *
 * Which cells: a triangle is emitted when at least one of its cells is drawn; polygons among
 * hidden cells only (culled, back-facing) are skipped. Triangles that would repeat a point
 * (coincident vertices, a coarse cell beside finer ones) are not emitted; coincident vertices
 * are merged first, so a closed input still gives a closed output.
 *
 * Without a "CutState" array the finest level is drawn (full resolution). An invalid cut (a
 * finest cell with no ancestor in it) is an error and gives an empty output.
 *
 * The filter keeps its scratch buffers between executions, so a frame allocates nothing new;
 * it re-executes only when its input or a parameter changes.
 *
 * @sa vtkMultiscaleOctree vtkMultiscaleOctreeCutter vtkPerceptualLODSelector
 */
#ifndef vtkMultiscalePatchGenerator_h
#define vtkMultiscalePatchGenerator_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for the workspace

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscalePatchGenerator : public vtkPolyDataAlgorithm
{
public:
  static vtkMultiscalePatchGenerator* New();
  vtkTypeMacro(vtkMultiscalePatchGenerator, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Point normals from the cone axes. Default on.
  vtkSetMacro(GenerateNormals, bool);
  vtkGetMacro(GenerateNormals, bool);
  vtkBooleanMacro(GenerateNormals, bool);
  ///@}

  ///@{
  /// RGB point colours (unsigned char, "Colors") from the mean diffuse reflectance. Default off.
  vtkSetMacro(GenerateColors, bool);
  vtkGetMacro(GenerateColors, bool);
  vtkBooleanMacro(GenerateColors, bool);
  ///@}

  ///@{
  /// The point array "OctreeNode" (node of each output point). Default off.
  vtkSetMacro(GenerateNodeIds, bool);
  vtkGetMacro(GenerateNodeIds, bool);
  vtkBooleanMacro(GenerateNodeIds, bool);
  ///@}

  ///@{
  /// Figures of the last execution.
  vtkGetMacro(NumberOfTriangles, vtkIdType);
  vtkGetMacro(NodesVisited, vtkIdType);
  vtkGetMacro(MergedPoints, vtkIdType);
  /// Wall-clock seconds of the last execution.
  vtkGetMacro(GenerateTime, double);
  ///@}

protected:
  vtkMultiscalePatchGenerator();
  ~vtkMultiscalePatchGenerator() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  bool GenerateNormals;
  bool GenerateColors;
  bool GenerateNodeIds;
  vtkIdType NumberOfTriangles;
  vtkIdType NodesVisited;
  vtkIdType MergedPoints;
  double GenerateTime;

private:
  vtkMultiscalePatchGenerator(const vtkMultiscalePatchGenerator&) = delete;
  void operator=(const vtkMultiscalePatchGenerator&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
