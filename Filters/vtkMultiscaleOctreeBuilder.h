// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctreeBuilder
 * @brief   builds the multiscale octree of a triangle mesh or of a scanned point cloud
 *
 * The expensive, run-once step of PerceptualLOD: it turns its input into a vtkMultiscaleOctree
 * whose cells carry a representative vertex, a normal cone, a shape error, material bounds and
 * a topology flag (SRCC §2-3.3, Wakatsuki et al. 2003; TMM Table 1; Wang & Sato §3 for point
 * data), and which keeps the input's own triangles so that the finest cut is the input. It
 * re-executes only when its input or one of its parameters changes.
 *
 * Input (a vtkPointSet, usually vtkPolyData):
 * - a mesh: the polygons and triangle strips of a vtkPolyData. Quads and polygons are split
 *   into fans, strips into their triangles; vertices and lines are ignored (with a warning). A
 *   vtkPointSet that is not a vtkPolyData but has cells (a vtkUnstructuredGrid of triangles)
 *   gives its triangles, quads, polygons, pixels and strips, with a warning naming what was
 *   taken and what was ignored (volume cells: extract their boundary first). Only points used by
 *   a triangle count. A polygon array holding only triangles is read in place (no copy), as are
 *   float or double points. Point normals, when present, are the shading normals of the finest
 *   cut; otherwise they are computed as vtkPolyDataNormals does without splitting.
 * - a point cloud: any vtkPointSet without surface cells. Point normals are used when
 *   present; otherwise they are estimated by PCA over the points within one finest cell edge
 *   and oriented towards the scanner: per point from the array named ViewpointArrayName (3
 *   components, e.g. each scan's scanner position after merging scans), else towards
 *   Viewpoint when UseViewpoint is on, else away from the centroid. The cloud is then
 *   contoured once at its finest level (a signed distance to the oriented points, Hoppe et al.
 *   1992, and dual contouring of its sign changes) and that mesh is built like any other.
 *
 * The surface is a vertex-clustering hierarchy (Lindstrom 2000; Luebke & Erikson 1997) laid out
 * as SRCC's octree:
 * 1. leaves at the finest level, one per occupied cell; every triangle stored with the node where
 *    it collapses (the deepest node holding two of its corners);
 * 2. per cell: vertex by the QEF rule (plane quadrics of the triangles at the cell's points,
 *    truncated solve about their mean, clamped to the cell: the default) or the paper's mean
 *    rule (the mean of the points inside); normal cone whose axis is the area-weighted mean
 *    normal and which holds the normal of every triangle that meets the cell (including those
 *    that only pass through it); coarser cones bound their children's by SRCC eq. (2); shape
 *    error by eq. (3) over the points inside; material min/max;
 * 3. a topology flag: the cell's sub-mesh is a union of discs (Euler characteristic).
 * See Filters/Core/plodOctreeBuilder.h for why this surface and not the dual contouring of
 * edge crossings the first version used (which never reached the input's picture and opened
 * holes in thin parts).
 *
 * Default finest level (FinestLevel = -1): for meshes, the shallowest level whose occupied cells
 * number at least a quarter of the distinct input points (leaves hold about four points); for
 * clouds, the deepest level whose occupied cells hold at least 4 points on average. It is lowered,
 * with a warning saying to which level and why, when the estimated memory exceeds the limit;
 * GetFinestLevelReason() says which rule decided. An explicit level whose estimated memory exceeds
 * MemoryLimit is an error.
 *
 * Bad input never stops the build silently: triangles with an index out of range or a point
 * with NaN or infinite coordinates are skipped with a warning (GetNumberOfInvalidTriangles()),
 * as are triangles that repeat a point (GetNumberOfDegenerateTriangles()); a normals, material
 * or viewpoint array shorter or longer than what it describes is an error naming the array; a
 * model whose extent single-precision storage cannot represent (outside [1e-30, 1e30]) is an
 * error. Errors give an empty octree.
 *
 * Distributed rendering (each process builds from its piece of a mesh; no crack may open along
 * the pieces' borders):
 * 1. every process builds with the same root cube, the cube of the global bounds
 *    (ComputeRootCube() on them, then UseGivenRootCube with RootCubeOrigin and RootCubeEdge),
 *    and the same FinestLevel (an explicit one: the automatic level and the memory limit's
 *    lowering would follow each piece; ChooseFinestLevelFromCounts() gives the automatic level
 *    of the whole from per-level counts). Cells, Morton order and the order of the surface
 *    points then agree between processes, and a cell whose points and triangles are all in a
 *    piece gets the vertices, clusters and shape error the whole mesh's build gives it;
 * 2. the point array vtkGhostType (vtkDataSetAttributes::GhostArrayName(), unsigned char), when
 *    present, is read: points with the bit DUPLICATEPOINT set are owned by another process.
 *    Ghost points take part in the build exactly like the others; the octree keeps each surface
 *    point's flag (vtkMultiscaleOctree's PointGhost array) for vtkMultiscalePatchGenerator, which
 *    draws a triangle only where its lead corner is not a ghost. Other bits are ignored, and so
 *    is a cell ghost array. A point cloud's ghost flags are ignored with a warning: its surface
 *    is contoured, so its points are not input points and no flag carries over;
 * 3. vtkPerceptualLODSelector::SetMinimumLevel makes the cells coarser than the level at which
 *    pieces are complete always refined, and the selector's back-face mode is set explicitly to
 *    the whole's (a piece is an open surface: the automatic mode would decide per piece).
 * Cells of that level or finer that a piece holds completely (their points, the triangles at
 * them and the triangles passing through them) then get the same vertices, clusters, cones,
 * errors and flags as in the whole's build, and so the same cut; the processes' outputs add up
 * to the whole's, triangle for triangle (tested at the full resolution, uniform levels and a
 * view-dependent cut). A piece that lacks a triangle passing through one of its complete cells
 * without a corner in it gets a narrower cone there.
 *
 * @warning A tube thinner than a cell collapses into a line when that cell is drawn at its
 * vertex; the topology flag makes the selector refine such cells while they cover more than a
 * pixel (vtkPerceptualLODSelector::SetTopologyTolerance).
 *
 * @sa vtkMultiscaleOctree vtkPerceptualLODSelector vtkMultiscalePatchGenerator
 */
#ifndef vtkMultiscaleOctreeBuilder_h
#define vtkMultiscaleOctreeBuilder_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkMultiscaleOctreeAlgorithm.h"
#include "vtkSmartPointer.h" // for TakeSurfaceCells

#include <functional> // for RunBuild's progress
#include <string>     // for the level reason
#include <vector>     // for TakeMaterialArray

class vtkPointSet;
class vtkPolyData;
namespace plod
{
struct BuildInput;
}

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctreeBuilder : public vtkMultiscaleOctreeAlgorithm
{
public:
  static vtkMultiscaleOctreeBuilder* New();
  vtkTypeMacro(vtkMultiscaleOctreeBuilder, vtkMultiscaleOctreeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Deepest level the octree can have (Morton keys of 3 x 21 bits).
  static int GetMaximumFinestLevel();

  /**
   * The root cube the builder places around points with the given bounds (xmin, xmax, ymin,
   * ymax, zmin, zmax), by the same kernel function (plod::build::PlaceRootCube): a margin of
   * 1/32 of the largest extent on each side and a small irrational shift. The bounds are those
   * of the points the build uses: a mesh's points of at least one valid triangle, a cloud's
   * finite points (vtkDataSet::GetBounds() also counts unused points, which gives another,
   * equally usable cube). Returns false, leaving the outputs untouched, for bounds that are not
   * finite or are empty (a minimum above its maximum, VTK's uninitialised bounds) and for an
   * extent single-precision storage cannot represent (outside [1e-30, 1e30]).
   */
  static bool ComputeRootCube(const double bounds[6], double origin[3], double* edge);

  /**
   * The automatic finest level (FinestLevel -1) from counts, by the same kernel function
   * (plod::ChooseFinestLevel), without the memory limit's lowering (the limit is per process;
   * an explicit FinestLevel whose build would not fit fails instead). For distributed builds,
   * where every process must use the same level:
   * - `cellsPerLevel[l]`, l = 0..21: the number of occupied cells of level l of the root cube
   *   over the points the build uses (see ComputeRootCube); non-decreasing, cellsPerLevel[0] = 1.
   *   A point x lies in the level-21 cell c = min(2^21 - 1, floor((x - origin) * s)) on each
   *   axis, s = 2^21 / edge computed first (as the builder does, for the same rounding), and in
   *   the level-l cell c >> (21 - l). With ownership by cells of a level k,
   *   the counts of levels k and finer are the sums over processes of the counts over their
   *   own points; coarser levels need the union of the processes' occupied cells;
   * - `numberOfPoints`: the number of points the build uses, duplicates included. The point-cloud
   *   rule averages points per occupied cell; the mesh rule reads the number of distinct
   *   positions from cellsPerLevel[21] and uses this number only to check the counts;
   * - `cloud`: true for a point cloud (no polygons), false for a mesh.
   * Returns the level (0 to 21), or -1 for counts that cannot come from points (cellsPerLevel[0]
   * not 1, a count that decreases or grows more than 8 times from one level to the next, fewer
   * points than cells of level 21). A cloud's level below 1 fails its build (see FinestLevel).
   */
  static int ChooseFinestLevelFromCounts(
    const long long cellsPerLevel[22], long long numberOfPoints, bool cloud);

  ///@{
  /**
   * A PLY file to build from instead of the input (default: none). The builder then reads the
   * file itself, straight into the compact arrays the build takes (plodPLYRead.h: float or
   * double points as the file has them, 32-bit indices, the normals nx ny nz when present;
   * other vertex properties and elements are skipped, polygons split into fans), so no
   * vtkPolyData of the model is ever made: the input costs about half of what vtkPLYReader's
   * polydata does (the build's own memory, the larger part, is unchanged).
   * Before any row is read, the header's counts give the least memory the build needs (the
   * mesh's arrays and the build at its coarsest levels); a file that needs more than the
   * memory limit is refused with an error that says how many faces would fit, and nothing is
   * read. Here the limit counts the mesh's arrays too. A file that is not PLY, or whose body
   * does not match its header, is an error naming the problem. Setting both an input connection
   * and a FileName is an error. Material arrays and viewpoint arrays do not apply; the uniform
   * reflectances, UseViewpoint and Viewpoint do.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /**
   * An octree file to build a PLY FileName into, in pieces, when the memory limit cannot hold
   * its in-memory build (default: none, such a file is refused), or always when BuildInPieces is
   * on. The file is split by space into pieces that each fit the limit, built one after the
   * other and written to this file (plodPieces.h, plodPieceAssembly.h; temporary files beside
   * it, removed at the end); the output is then the file, mapped, as vtkMultiscaleOctreeReader
   * gives it. Levels of the pieces' level and finer are the in-memory build's, node for node;
   * coarser ones are built from the octree of the cut at the pieces' level
   * (plodPieceAssembly.h says how they differ from the in-memory build's), or, where that
   * cannot be built, hold structure only, with a warning
   * (vtkMultiscaleOctree::GetCoarsestDrawnLevel). The vertex rule and the threads apply; the
   * root cube and the finest level are the file's own (the pieces' automatic level: a
   * FinestLevel that differs is not used, with a warning). A model whose finest level is
   * coarser than the pieces' cells (level 6) is split at its own level (plodPieces.h). An existing
   * file is replaced only once the new one is complete and verified.
   */
  vtkSetFilePathMacro(OctreeFileName);
  vtkGetFilePathMacro(OctreeFileName);
  vtkSetMacro(BuildInPieces, bool);
  vtkGetMacro(BuildInPieces, bool);
  vtkBooleanMacro(BuildInPieces, bool);
  ///@}

  ///@{
  /**
   * Write OctreeFileName in the compact layout (arrays compressed, decoded into memory when the
   * file is read; see vtkMultiscaleOctreeWriter::SetCompact) instead of the mapped one. The
   * output is then the file as vtkMultiscaleOctreeReader decodes it. Default off.
   */
  vtkSetMacro(CompactOctreeFile, bool);
  vtkGetMacro(CompactOctreeFile, bool);
  vtkBooleanMacro(CompactOctreeFile, bool);
  ///@}

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
    VERTEX_MEAN = 0, ///< SRCC: mean of the input points inside the cell
    VERTEX_QEF = 1   ///< minimiser of the plane quadrics (Lindstrom 2000), clamped to the cell
  };

  ///@{
  /// How representative vertices are computed. Default VERTEX_QEF (better images at equal
  /// triangles than the paper's mean rule; see docs/results).
  vtkSetClampMacro(VertexRule, int, VERTEX_MEAN, VERTEX_QEF);
  vtkGetMacro(VertexRule, int);
  void SetVertexRuleToMean() { this->SetVertexRule(VERTEX_MEAN); }
  void SetVertexRuleToQEF() { this->SetVertexRule(VERTEX_QEF); }
  ///@}

  ///@{
  /**
   * A root cube given by the caller instead of the one placed around the input: lower corner
   * RootCubeOrigin and edge RootCubeEdge, in the input's coordinates, used when
   * UseGivenRootCube is on (default off; origin default (0, 0, 0), edge default 0, which must be
   * set). The octree's GetOrigin() and GetRootEdge() are then exactly these values, for meshes
   * and point clouds. Every point the build uses must lie in the closed cube: a point outside
   * is an error naming it and the cube, and gives an empty octree (points are never clamped).
   * A cube that is not finite, has an edge outside [1e-30, 1.0625e30] (the edges the builder
   * can place) or an edge below 1e-12 of its largest origin coordinate is an invalid parameter
   * (error, RequestData fails). Unlike a placed cube it has no margin: points on its upper
   * faces fall into its last cells, and a point cloud's surface is not contoured across its
   * faces. For distributed rendering (see the class documentation).
   */
  vtkSetMacro(UseGivenRootCube, bool);
  vtkGetMacro(UseGivenRootCube, bool);
  vtkBooleanMacro(UseGivenRootCube, bool);
  vtkSetVector3Macro(RootCubeOrigin, double);
  vtkGetVector3Macro(RootCubeOrigin, double);
  vtkSetMacro(RootCubeEdge, double);
  vtkGetMacro(RootCubeEdge, double);
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
  /**
   * Memory the build may use for itself (the input not counted, except with FileName), in MiB.
   * 0 (default): automatic, three quarters of the machine's physical memory
   * (GetEffectiveMemoryLimit(); 4096 MiB where the system cannot say). An automatic finest
   * level is lowered to fit it; a coarser level saves little, since the octree keeps the
   * input's surface at any level. What the build needs per triangle is measured in
   * docs/benchmarks.md.
   */
  vtkSetMacro(MemoryLimit, double);
  vtkGetMacro(MemoryLimit, double);
  double GetEffectiveMemoryLimit();
  ///@}

  ///@{
  /// Use vtkSMPTools threads (default on). Results do not depend on this setting.
  vtkSetMacro(MultiThreaded, bool);
  vtkGetMacro(MultiThreaded, bool);
  vtkBooleanMacro(MultiThreaded, bool);
  ///@}

  ///@{
  /// Figures of the last execution: triangles read, skipped (invalid + degenerate), nodes whose
  /// sub-mesh is not a union of discs, and why the finest level is what it is.
  vtkGetMacro(NumberOfInputTriangles, vtkIdType);
  vtkGetMacro(NumberOfSkippedTriangles, vtkIdType);
  vtkGetMacro(NumberOfInvalidTriangles, vtkIdType);
  vtkGetMacro(NumberOfDegenerateTriangles, vtkIdType);
  vtkGetMacro(NumberOfUnsafeNodes, vtkIdType);
  const char* GetFinestLevelReason() { return this->FinestLevelReason.c_str(); }
  /// Wall-clock seconds of the last build (the octree's construction).
  vtkGetMacro(BuildTime, double);
  /// Wall-clock seconds the last execution took to take its input before the build: reading
  /// FileName (or, built in pieces, splitting it), or gathering the input's arrays.
  vtkGetMacro(ReadTime, double);
  /// Surface points flagged as ghosts (the input's vtkGhostType) in the last build.
  vtkGetMacro(NumberOfGhostPoints, vtkIdType);
  /// The estimate, in bytes, of the last build's own peak memory at the level it built (what
  /// the memory limit is compared with; the input not counted). 0 before a build.
  vtkGetMacro(EstimatedMemory, double);
  ///@}

protected:
  vtkMultiscaleOctreeBuilder();
  ~vtkMultiscaleOctreeBuilder() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  /// The triangles, quads, polygons, pixels and strips of a point set that is not a
  /// vtkPolyData, as one (its points and point data shared, its cell data copied), with a
  /// warning that says what was taken and what was ignored.
  vtkSmartPointer<vtkPolyData> TakeSurfaceCells(vtkPointSet* input);
  /// Warns when a mesh's vertex and line cells are left out of its surface.
  void ReportIgnoredCells(vtkPolyData* input);
  /// Reports invalid parameters as errors; false when there is one.
  bool CheckParameters();
  ///@{
  /// The input's arrays for the kernel, each checked against what it describes (false: an
  /// error was reported). Arrays the kernel cannot use in place are copied into InputCopies.
  struct InputCopies;
  void TakePoints(vtkPointSet* input, plod::BuildInput& in, InputCopies& copies);
  void TakeTriangles(vtkPointSet* input, plod::BuildInput& in, InputCopies& copies);
  bool TakeNormals(vtkPointSet* input, plod::BuildInput& in, InputCopies& copies);
  bool TakeViewpoints(vtkPointSet* input, plod::BuildInput& in, InputCopies& copies);
  bool TakeGhosts(vtkPointSet* input, plod::BuildInput& in, InputCopies& copies);
  bool TakeMaterial(vtkPointSet* input, plod::BuildInput& in, InputCopies& copies);
  bool TakeMaterialArray(vtkPointSet* input, const char* name, std::vector<float>& pointValues,
    std::vector<float>& triangleValues, const float*& pointOut, const float*& triangleOut,
    const plod::BuildInput& in, InputCopies& copies);
  void ReportLengthError(const char* what, const char* name, vtkIdType has, int components,
    vtkIdType needs, const char* per);
  ///@}
  /// The build from FileName: header, memory check, streaming read, build.
  int BuildFromFile(vtkMultiscaleOctree* output);
  /// The build of FileName in pieces into OctreeFileName, then the file read into `output`.
  int BuildFromFileInPieces(vtkMultiscaleOctree* output);
  /// Builds the octree of `in` into `output` within `memoryLimit` bytes and reports what the
  /// build found.
  int RunBuild(const plod::BuildInput& in, bool hasMaterial, double memoryLimit,
    const std::function<bool(double)>& progress, vtkMultiscaleOctree* output);

  char* FileName;
  char* OctreeFileName = nullptr;
  bool BuildInPieces = false;
  bool CompactOctreeFile = false;
  int FinestLevel;
  double EstimatedMemory;
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
  bool UseGivenRootCube;
  double RootCubeOrigin[3];
  double RootCubeEdge;

  vtkIdType NumberOfSkippedTriangles;
  vtkIdType NumberOfInvalidTriangles;
  vtkIdType NumberOfDegenerateTriangles;
  vtkIdType NumberOfInputTriangles;
  vtkIdType NumberOfUnsafeNodes;
  vtkIdType NumberOfGhostPoints;
  std::string FinestLevelReason;
  double BuildTime;
  double ReadTime;

private:
  vtkMultiscaleOctreeBuilder(const vtkMultiscaleOctreeBuilder&) = delete;
  void operator=(const vtkMultiscaleOctreeBuilder&) = delete;
};

#endif
