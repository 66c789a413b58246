// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctreeBuilder
 * @brief   builds the multiscale octree of a triangle mesh or of a scanned point cloud
 *
 * The expensive, run-once step of PerceptualLOD: it turns its input into a vtkMultiscaleOctree
 * whose cells carry a representative vertex, a normal cone, a shape error, material bounds and
 * edge-crossing data (SRCC §2-3.3, Wakatsuki et al. 2003; TMM Table 1; Wang & Sato §3 for point
 * data). It re-executes only when its input or one of its parameters changes.
 *
 * Input (a vtkPointSet, usually vtkPolyData):
 * - a mesh: the polygons and triangle strips of a vtkPolyData. Quads and polygons are split
 *   into fans, strips into their triangles; vertices and lines are ignored. Only points used by
 *   a triangle count.
 * - a point cloud: any vtkPointSet without polygons or strips. Point normals are used when
 *   present; otherwise they are estimated by PCA over the points within one finest cell edge
 *   and oriented towards the scanner: per point from the array named ViewpointArrayName (3
 *   components, e.g. each scan's scanner position after merging scans), else towards
 *   Viewpoint when UseViewpoint is on, else away from the centroid. The surface of a cloud is
 *   the one its patches draw, so the cones of a cloud's octree are widened to contain the
 *   normals of its finest patches' triangles too (then eq. (2) again, upwards): estimated
 *   normals are smoother than that surface, and the back-face test must not hide what is
 *   drawn (measured on the merged bunny scans: without it SRCC lost 7 dB to the holes).
 *
 * Algorithm (all in the VTK-free kernel plod::BuildOctree, driven with vtkSMPTools):
 * 1. The root is a cube around the bounds with a margin of 1/32 of the extent on each side
 *    (and a shift below 1e-3 of the edge so that regular coordinates avoid grid planes).
 * 2. Finest samples: the input vertices; the points where triangles cross finest grid edges
 *    (watertight: a grid line through a shared mesh edge or vertex is counted exactly once); for
 *    clouds, the sign changes of a signed distance to the oriented points (Hoppe et al. 1992).
 *    Each crossing creates the four cells around its edge, so dual contouring never misses one.
 * 3. Per finest cell: vertex by the paper's mean rule (mean of the input vertices inside and of
 *    the crossings on the cell's edges) or by the QEF rule; normal cone with the area-weighted
 *    mean normal as axis and the largest angle to it; material min/max; crossing word.
 * 4. Coarser cells: cones by SRCC eq. (1)-(2) (near-zero sum: theta = pi); shape error by
 *    eq. (3) over all finest descendants; material min/max; crossings of each coarse edge as the
 *    signed sum of its two halves; vertex by the same rule over the cell's own samples.
 *
 * Default finest level (FinestLevel = -1): for meshes, the level whose cell edge is nearest the
 * median triangle edge length; for clouds, the deepest level whose occupied cells hold at least
 * 4 points on average; in both cases lowered until the estimated build memory fits
 * MemoryLimit. An explicit level whose estimated memory exceeds MemoryLimit is an error.
 *
 * Bad input: no points gives an empty octree; NaN or infinite coordinates, triangles that
 * refer to missing points, or parameters out of range give an error and an empty octree.
 * Degenerate triangles are skipped (counted in GetNumberOfSkippedTriangles()); duplicate
 * triangles count once per copy, and only the sign of a net crossing is kept.
 *
 * @warning Thin parts (two sheets inside one finest cell with opposite orientation) cancel in
 * the crossing data and disappear from the patches, as in any dual contouring on a grid.
 *
 * @sa vtkMultiscaleOctree vtkPerceptualLODSelector vtkMultiscalePatchGenerator
 */
#ifndef vtkMultiscaleOctreeBuilder_h
#define vtkMultiscaleOctreeBuilder_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkMultiscaleOctreeAlgorithm.h"

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctreeBuilder : public vtkMultiscaleOctreeAlgorithm
{
public:
  static vtkMultiscaleOctreeBuilder* New();
  vtkTypeMacro(vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Deepest level the octree can have (Morton keys of 3 x 21 bits).
  static int GetMaximumFinestLevel();

  ///@{
  /**
   * Finest level `L_m`. -1 (default) chooses it from the input (see the class docs); 0 builds
   * the root alone; at most GetMaximumFinestLevel(). Other values are reported as errors.
   */
  vtkSetMacro(FinestLevel, int);
  vtkGetMacro(FinestLevel, int);
  ///@}

  enum VertexRules
  {
    VERTEX_MEAN = 0, ///< SRCC: mean of vertices inside and crossings on the cell's edges
    VERTEX_QEF = 1   ///< minimiser of the plane quadrics (Lindstrom 2000, Ju et al. 2002)
  };

  ///@{
  /// How representative vertices are computed. Default VERTEX_MEAN (the paper's rule).
  vtkSetClampMacro(VertexRule, int, VERTEX_MEAN, VERTEX_QEF);
  vtkGetMacro(VertexRule, int);
  void SetVertexRuleToMean() { this->SetVertexRule(VERTEX_MEAN); }
  void SetVertexRuleToQEF() { this->SetVertexRule(VERTEX_QEF); }
  ///@}

  ///@{
  /**
   * Names of 1-component point or cell arrays holding diffuse and specular reflectances
   * (point data is searched first). Unset (default) or not found: the uniform values below.
   */
  vtkSetStringMacro(DiffuseArrayName);
  vtkGetStringMacro(DiffuseArrayName);
  vtkSetStringMacro(SpecularArrayName);
  vtkGetStringMacro(SpecularArrayName);
  ///@}

  ///@{
  /// Uniform reflectances used where no array is given. Defaults 1.0 (diffuse), 0.0 (specular),
  /// as vtkProperty.
  vtkSetMacro(UniformDiffuse, double);
  vtkGetMacro(UniformDiffuse, double);
  vtkSetMacro(UniformSpecular, double);
  vtkGetMacro(UniformSpecular, double);
  ///@}

  ///@{
  /// Orientation of estimated point-cloud normals (see the class docs). Defaults: no array,
  /// UseViewpoint off, Viewpoint (0, 0, 0).
  vtkSetStringMacro(ViewpointArrayName);
  vtkGetStringMacro(ViewpointArrayName);
  vtkSetVector3Macro(Viewpoint, double);
  vtkGetVector3Macro(Viewpoint, double);
  vtkSetMacro(UseViewpoint, bool);
  vtkGetMacro(UseViewpoint, bool);
  vtkBooleanMacro(UseViewpoint, bool);
  ///@}

  ///@{
  /// Memory the build may use, in MiB. Default 4096.
  vtkSetMacro(MemoryLimit, double);
  vtkGetMacro(MemoryLimit, double);
  ///@}

  ///@{
  /// Use vtkSMPTools threads (default on). Results do not depend on this setting.
  vtkSetMacro(MultiThreaded, bool);
  vtkGetMacro(MultiThreaded, bool);
  vtkBooleanMacro(MultiThreaded, bool);
  ///@}

  ///@{
  /// Figures of the last execution.
  vtkGetMacro(NumberOfCrossings, vtkIdType);
  vtkGetMacro(NumberOfSkippedTriangles, vtkIdType);
  vtkGetMacro(NumberOfInputTriangles, vtkIdType);
  /// Wall-clock seconds of the last build.
  vtkGetMacro(BuildTime, double);
  ///@}

protected:
  vtkMultiscaleOctreeBuilder();
  ~vtkMultiscaleOctreeBuilder() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  int FinestLevel;
  int VertexRule;
  char* DiffuseArrayName;
  char* SpecularArrayName;
  double UniformDiffuse;
  double UniformSpecular;
  char* ViewpointArrayName;
  double Viewpoint[3];
  bool UseViewpoint;
  double MemoryLimit;
  bool MultiThreaded;

  vtkIdType NumberOfCrossings;
  vtkIdType NumberOfSkippedTriangles;
  vtkIdType NumberOfInputTriangles;
  double BuildTime;

private:
  vtkMultiscaleOctreeBuilder(const vtkMultiscaleOctreeBuilder&) = delete;
  void operator=(const vtkMultiscaleOctreeBuilder&) = delete;
};

#endif
