// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscalePatchGenerator
 * @brief   crack-free triangles from a cut through a multiscale octree
 *
 * Turns the cut carried by a vtkMultiscaleOctree (its "CutState" node array, made by
 * vtkPerceptualLODSelector or vtkMultiscaleOctreeCutter) into the vtkPolyData that is drawn:
 * SRCC §2's multiscale patches (Wakatsuki et al. 2003), made by vertex clustering over the
 * octree. Every input triangle whose three corners fall into three different cut cells is
 * drawn, each corner at the representative vertex of its cluster (the connected part of the
 * cell's surface that holds it), or as itself in a leaf the cut opened. The work is
 * proportional to the triangles drawn plus the nodes above the cut. See plodPatches.h for the
 * algorithm.
 *
 * Output:
 * - points: the representative vertices of the cut clusters used, the points of opened
 *   leaves, and the own corners of turned-over triangles (see FoldHandling) (world coordinates,
 * double precision when the octree sits far from the origin relative to its size, else float);
 * - triangles, oriented as the input's;
 * - point normals: the clusters' shading normals (area-weighted mean normals), and for the
 *   points of opened leaves their input shading normals (SRCC shades by interpolation);
 * - optionally (GenerateColors) RGB colours from the cells' mean diffuse reflectance (grey);
 * - optionally (GenerateNodeIds) the point array "OctreeNode": the node of each point (the leaf
 *   for a point of an opened leaf);
 * - optionally (GenerateInputPointIds) the point array "InputPointId": the builder input's point
 *   drawn there, -1 for a representative vertex (a picked point maps back to the input only
 *   where the cut is at full resolution).
 *
 * No crack can open between cells of different levels: triangles share corners as in the
 * input. A closed, consistently oriented input gives a closed, consistently oriented output at
 * every cut (point for point with FoldHandling KEEP; with the default, turned-over triangles
 * sit on points of their own at the same places). The cut of every leaf opened draws the input
 * itself, triangle for triangle.
 *
 * Which cells: a triangle is emitted when at least one of its cells is drawn; among hidden
 * cells only, it is skipped when one of them faces away or when all were culled by one common
 * frustum plane (the "CullMask" array), and drawn otherwise (a large triangle can cross the view
 * while its corners lie outside it).
 *
 * Distributed rendering (the octree has ghost flags: its builder's input carried vtkGhostType,
 * see vtkMultiscaleOctreeBuilder): a triangle is drawn only if its lead corner, the corner with
 * the smallest surface point index, is not a ghost. The rule applies to every triangle emitted
 * (those of refined cells, of opened leaves, among hidden cells, and folds), before the others.
 * Surface points are sorted by the Morton key of their finest cell (level 21), so the lead
 * corner is the corner in the lowest cell, and every process that built with the same root cube
 * and finest level agrees on it. With VTK's usual ghost convention, each point owned by exactly
 * one process (a ghost on all the others), every triangle is therefore drawn by exactly one
 * process: the owner of its lead corner. Only corners in one level-21 cell are ordered by their
 * index in each process's own input; processes agree on those too when ownership goes by cells,
 * as with a redistribution by the cells of some level. GetNumberOfGhostTriangles() counts the
 * triangles left to other processes.
 *
 * Without a "CutState" array the full resolution is drawn. An invalid octree or cut (a leaf
 * with no ancestor in it, a cut node below another, a state above 3) is an error and gives an
 * empty output.
 *
 * The filter keeps its scratch buffers between executions, so a frame allocates nothing new;
 * it re-executes only when its input or a parameter changes. It also remembers, for every
 * surface point, the cluster its corner walk ended at (4 bytes a point, kept while the octree's
 * arrays are the same): the next execution starts each corner there when that cluster is still
 * a cut cluster, instead of walking from the point's leaf, so a cut that moved little costs
 * little more than its triangles (docs/benchmarks.md, "Multiscale patches").
 *
 * @warning The remembered walks make a corner's representative depend on nothing but the
 * octree and the current cut (the same output as walking from the leaves); an octree whose
 * arrays are edited in place without Modified() is not supported, as everywhere in VTK.
 *
 * @sa vtkMultiscaleOctree vtkMultiscaleOctreeCutter vtkPerceptualLODSelector
 */
#ifndef vtkMultiscalePatchGenerator_h
#define vtkMultiscalePatchGenerator_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <cstdint> // for uint8_t
#include <memory>  // for the workspace

class vtkMultiscaleOctree;
namespace plod
{
struct OctreeView;
struct PatchOptions;
struct PatchResult;
}

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscalePatchGenerator : public vtkPolyDataAlgorithm
{
public:
  static vtkMultiscalePatchGenerator* New();
  vtkTypeMacro(vtkMultiscalePatchGenerator, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Point normals: the clusters' shading normals, the input's at opened leaves. Default on.
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

  enum FoldHandlings
  {
    FOLDS_KEEP = 0,
    FOLDS_DROP = 1,
    FOLDS_REVERSE_NORMALS = 2
  };

  ///@{
  /**
   * What to do with the triangles clustering turned over (face normal against all three corner
   * normals, at least one corner a representative vertex). Drawn as they are (KEEP), two-sided
   * lighting shades them from behind, as dark specks; dropped (DROP), they leave see-through
   * slits where nothing lies behind them. REVERSE_NORMALS, the default, draws each on three
   * output points of its own, at its corners' places, with their normals reversed: no speck,
   * no slit (measured: see plodPatches.h). KEEP is the one setting under which the output of a
   * closed input is closed point for point (each edge used as often in both directions); with
   * the others it is closed geometrically.
   */
  vtkSetClampMacro(FoldHandling, int, FOLDS_KEEP, FOLDS_REVERSE_NORMALS);
  vtkGetMacro(FoldHandling, int);
  void SetFoldHandlingToKeep() { this->SetFoldHandling(FOLDS_KEEP); }
  void SetFoldHandlingToDrop() { this->SetFoldHandling(FOLDS_DROP); }
  void SetFoldHandlingToReverseNormals() { this->SetFoldHandling(FOLDS_REVERSE_NORMALS); }
  const char* GetFoldHandlingAsString() const;
  ///@}

  ///@{
  /**
   * When the cut comes from a vtkPerceptualLODSelector that hid back faces (a closed surface
   * seen from outside), skip the triangles facing away from its eye. Default on. Near the
   * contour, cells hold both sides of the surface: on detailed scans 40 to 47 % of the
   * triangles of a cut faced away, none of them visible.
   */
  vtkSetMacro(CullBackFaces, bool);
  vtkGetMacro(CullBackFaces, bool);
  vtkBooleanMacro(CullBackFaces, bool);
  ///@}

  ///@{
  /// The point array "InputPointId" (input point of each output point, -1 for a cell's
  /// representative vertex). Default off.
  vtkSetMacro(GenerateInputPointIds, bool);
  vtkGetMacro(GenerateInputPointIds, bool);
  vtkBooleanMacro(GenerateInputPointIds, bool);
  ///@}

  ///@{
  /**
   * Run the patches' two parallel phases with vtkSMPTools: each owned triangle's corners are
   * looked up in ranges of the cut, and the output's points and normals are filled in ranges.
   * The output is the same, point for point, on any number of threads. Default on.
   */
  vtkSetMacro(MultiThreaded, bool);
  vtkGetMacro(MultiThreaded, bool);
  vtkBooleanMacro(MultiThreaded, bool);
  ///@}

  ///@{
  /// Figures of the last execution.
  vtkGetMacro(NumberOfTriangles, vtkIdType);
  vtkGetMacro(NumberOfOutputPoints, vtkIdType);
  vtkGetMacro(NodesVisited, vtkIdType);
  /// Turned-over triangles met (dropped or drawn on their own points, see FoldHandling; 0
  /// with KEEP, which does not look for them).
  vtkGetMacro(NumberOfFolds, vtkIdType);
  vtkGetMacro(NumberOfCulledBackFaces, vtkIdType);
  /// Triangles not drawn because their lead corner is a ghost (another process draws them).
  vtkGetMacro(NumberOfGhostTriangles, vtkIdType);
  /// Wall-clock seconds of the last execution.
  vtkGetMacro(GenerateTime, double);
  ///@}

protected:
  vtkMultiscalePatchGenerator();
  ~vtkMultiscalePatchGenerator() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  ///@{
  /// The steps of RequestData.
  /// The input's cut, or full resolution (with a warning for a CutState of the wrong shape).
  const uint8_t* TakeCut(vtkMultiscaleOctree* input, const plod::OctreeView& v);
  /// The kernel's options: fold rule, back faces as the selector asked, threads, and the
  /// octree's checked stamp `checked` (the corner walks remembered between frames).
  plod::PatchOptions MakeOptions(vtkMultiscaleOctree* input, vtkMTimeType checked);
  /// The Get...() figures from the kernel's result and the time taken.
  void RecordFigures(const plod::PatchResult& r, double seconds);
  ///@}
  int FillInputPortInformation(int port, vtkInformation* info) override;

  bool GenerateNormals;
  bool GenerateColors;
  bool GenerateNodeIds;
  bool GenerateInputPointIds;
  int FoldHandling;
  bool CullBackFaces;
  bool MultiThreaded = true;
  vtkIdType NumberOfFolds;
  vtkIdType NumberOfCulledBackFaces;
  vtkIdType NumberOfGhostTriangles;
  vtkIdType NumberOfTriangles;
  vtkIdType NumberOfOutputPoints;
  vtkIdType NodesVisited;
  double GenerateTime;

private:
  vtkMultiscalePatchGenerator(const vtkMultiscalePatchGenerator&) = delete;
  void operator=(const vtkMultiscalePatchGenerator&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
