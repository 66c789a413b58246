// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctree
 * @brief   sparse multiscale octree of a surface, with per-node normal cones and shape errors
 *
 * vtkMultiscaleOctree is the data object that flows between the PerceptualLOD filters: built
 * once by vtkMultiscaleOctreeBuilder, read every frame by vtkPerceptualLODSelector and
 * vtkMultiscalePatchGenerator. It follows SRCC §2-3.3 (Wakatsuki et al. 2003) and TMM Table 1:
 * the root is a cube around the input; level `L` cells have edge `GetRootEdge() / 2^L`; only
 * cells that hold input points exist (sparse); every leaf is at the finest level.
 *
 * It is a vertex-clustering hierarchy over the input mesh: each cell stands for the input
 * points inside it, drawn at its representative vertex `v`; a cut through the tree draws the
 * input's own triangles with each corner at the representative of its cut cell, and the finest
 * cut (every leaf opened) draws the input itself. The input's points and triangles are
 * therefore kept, in GetSurfaceData(). See plodOctree.h and plodOctreeBuilder.h (Filters/Core)
 * for the construction and the reasons for it.
 *
 * Every per-node quantity is a named array in GetNodeData() with one tuple per node, so that
 * Python users read them as numpy arrays (`vtk.util.numpy_support.vtk_to_numpy`). A cell's
 * points fall into clusters, one per connected part of its surface, each with its own
 * representative vertex (the two sheets of a thin wall keep their own vertices at every level):
 * their arrays are in GetClusterData(). The input's points, normals and triangles are in
 * GetSurfaceData(). Every array, with its type, components and meaning, is listed once in
 * `Filters/Core/plodOctreeSchema.h` and shown as a table in `docs/octree-schema.md`; the
 * `...ArrayName()` functions below return their names. Nodes are stored level by level and,
 * inside a level, in Morton order (plodOctree.h gives the rules that tie the arrays together).
 *
 * One optional surface array, `PointGhost` (unsigned char, 1 component, one per point), exists
 * when the builder's input carried VTK's point ghost array (vtkGhostType): 1 for a point owned by
 * another process (bit DUPLICATEPOINT), else 0. vtkMultiscalePatchGenerator then draws a
 * triangle only where its lead corner is not a ghost (distributed rendering: see there). Shallow
 * and deep copies carry it with the other surface arrays; the .plod file does not store it
 * (vtkMultiscaleOctreeWriter warns). An array of that name with another type or size makes the
 * octree inconsistent.
 *
 * Vertices and points are stored in single precision relative to the root origin, which is
 * kept in double: a model far from the world origin keeps full precision. GetNodeVertex()
 * returns world coordinates.
 *
 * Filters validate an octree that reaches them (IsConsistent, linear in its size) once per
 * modification of its arrays: after editing an array in place (from numpy, say), call
 * Modified() on that array, as VTK asks of in-place edits, so that the next filter checks the
 * octree again and refuses it with an error if it is inconsistent. Unsignalled edits cannot make
 * a filter crash or loop either: every index the kernels follow is checked.
 *
 * @warning Node, point and triangle indices are 32-bit: at most 2^31 - 1 of each.
 *
 * @sa vtkMultiscaleOctreeBuilder vtkMultiscaleOctreeAlgorithm
 */
#ifndef vtkMultiscaleOctree_h
#define vtkMultiscaleOctree_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkDataObject.h"

#include <atomic> // for the held bytes
#include <memory> // for the checked view
#include <string> // for CheckConsistency
#include <vector> // for the check's key

#ifndef __VTK_WRAP__
#include <cstdint> // for the schema's enums
namespace plod
{
struct OctreeView;
struct OctreeArrays;
struct ArraySpec;
struct FileIdentity;
struct CornerMemo;
class PageLoader;
enum class ArrayGroup : uint8_t;
enum class ArrayType : uint8_t;
}
#endif

class vtkDataArray;
class vtkFieldData;
class vtkInformation;
class vtkInformationVector;

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctree : public vtkDataObject
{
public:
  static vtkMultiscaleOctree* New();
  vtkTypeMacro(vtkMultiscaleOctree, vtkDataObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Returns VTK_DATA_OBJECT: the octree is a custom data object, identified in pipeline
   * information by its class name.
   */
  int GetDataObjectType() override { return VTK_DATA_OBJECT; }

  /// Removes every node and resets the geometry to the unit cube at the origin.
  void Initialize() override;

  ///@{
  /// Shallow copy shares the node arrays (adding an array to the copy does not touch the
  /// source); deep copy duplicates them.
  void ShallowCopy(vtkDataObject* src) override;
  void DeepCopy(vtkDataObject* src) override;
  ///@}

  /// Memory used by the node and surface arrays, in kibibytes (VTK convention).
  unsigned long GetActualMemorySize() override;

  /// The per-node arrays (see the class documentation for the names).
  vtkFieldData* GetNodeData() { return this->NodeData; }

  /// The surface arrays: points, normals, point leaves and clusters, input ids, triangles.
  vtkFieldData* GetSurfaceData() { return this->SurfaceData; }

  /// The cluster arrays: node, parent, vertex, normal.
  vtkFieldData* GetClusterData() { return this->ClusterData; }

  /// Number of clusters (at least one per node).
  vtkIdType GetNumberOfClusters();

  /// Number of nodes (0 when empty).
  vtkIdType GetNumberOfNodes();

  ///@{
  /// Number of surface points and triangles (the input's, as kept by the builder).
  vtkIdType GetNumberOfSurfacePoints();
  vtkIdType GetNumberOfSurfaceTriangles();
  ///@}

  ///@{
  /// Root cube: lower corner in world coordinates and edge length. Default: (0,0,0) and 1.
  vtkGetVector3Macro(Origin, double);
  vtkGetMacro(RootEdge, double);
  ///@}

  /// Finest level `L_m` (0: the root alone).
  vtkGetMacro(FinestLevel, int);

  /// True when the material ranges came from input arrays (else they hold uniform values and a
  /// selector should use its own material).
  vtkGetMacro(HasMaterialArrays, bool);
  vtkSetMacro(HasMaterialArrays, bool);

  /**
   * Levels coarser than this hold the tree's structure only, not surfaces to draw: an octree
   * assembled from pieces built one after the other (plodPieceAssembly.h) whose levels above
   * the pieces' level could not be built has no vertices or cones there.
   * vtkPerceptualLODSelector refines them at once (as its MinimumLevel does). Default 0: every
   * level is drawn.
   */
  vtkGetMacro(CoarsestDrawnLevel, int);
  vtkSetClampMacro(CoarsestDrawnLevel, int, 0, 21);

  ///@{
  /**
   * Edges of the surface used by one triangle only (its boundary; 0 for a closed surface), and
   * edges used by more than two (non-manifold). Set by the builder; the selector hides back
   * faces by default only when there is no boundary edge.
   */
  vtkGetMacro(NumberOfBoundaryEdges, vtkIdType);
  vtkSetMacro(NumberOfBoundaryEdges, vtkIdType);
  vtkGetMacro(NumberOfNonManifoldEdges, vtkIdType);
  vtkSetMacro(NumberOfNonManifoldEdges, vtkIdType);
  ///@}

  ///@{
  /**
   * Edges used by two triangles in the same direction: the two disagree on which side is the
   * front, as in a mesh whose triangles are not consistently oriented (scans often arrive so).
   * Set by the builder; the selector hides back faces by default only when this is 0 too, since
   * a closed surface seen through such a triangle would show a see-through hole.
   */
  vtkGetMacro(NumberOfMisorientedEdges, vtkIdType);
  vtkSetMacro(NumberOfMisorientedEdges, vtkIdType);
  ///@}

  /// Sets the root cube and the finest level together.
  void SetGeometry(const double origin[3], double rootEdge, int finestLevel);

  /// Edge length of cells at `level`.
  double GetCellEdge(int level) const;

  /**
   * Creates the node arrays for `nodes` nodes and the surface arrays for `points` points and
   * `triangles` triangles (contents undefined), removing any other array. Used by the builder
   * and by readers; users normally never call it.
   */
  void Allocate(vtkIdType nodes, vtkIdType points, vtkIdType triangles);
  /// Creates the cluster arrays for `clusters` clusters (after Allocate).
  void AllocateClusters(vtkIdType clusters);
  /// Creates the optional PointGhost surface array, one value per surface point (after
  /// Allocate; contents undefined).
  void AllocatePointGhosts();

  ///@{
  /// Whether the octree has the PointGhost surface array, and how many points it flags.
  bool HasPointGhosts();
  vtkIdType GetNumberOfGhostPoints();
  ///@}

  ///@{
  /// Navigation. Invalid node ids give -1 (or 0 children).
  int GetNodeLevel(vtkIdType node);
  vtkIdType GetParent(vtkIdType node);
  int GetNumberOfChildren(vtkIdType node);
  /// Child `childIndex` (0..7, x + 2y + 4z) of `node`, or -1 when it does not exist.
  vtkIdType GetChild(vtkIdType node, int childIndex);
  /// Integer cell coordinates of the node at its own level.
  void GetNodeCellCoordinates(vtkIdType node, int ijk[3]);
  /// World bounds (xmin, xmax, ymin, ymax, zmin, zmax) of the node's cell.
  void GetNodeBounds(vtkIdType node, double bounds[6]);
  /// Representative vertex in world coordinates.
  void GetNodeVertex(vtkIdType node, double x[3]);
  /**
   * The node at `level` whose cell contains `x` (world coordinates), or -1 when that cell does
   * not exist (empty space) or `x` is outside the root.
   */
  vtkIdType FindNode(const double x[3], int level);
  ///@}

  /**
   * Checks that the arrays exist with the documented types and sizes and that everything the
   * filters rely on holds (plod::ValidateOctree: parents, children, levels, point and triangle
   * ranges, point leaves, triangle corners, finite vertices, cone angles). Linear in the size;
   * the result is cached until the octree or one of its arrays is modified. An empty octree
   * is consistent.
   */
  bool IsConsistent() { return this->CheckConsistency(nullptr); }

  ///@{
  /// Names of the arrays (plodOctreeSchema.h): node arrays, cluster arrays, surface arrays.
  static const char* LevelArrayName();
  static const char* ParentArrayName();
  static const char* FirstChildArrayName();
  static const char* ChildMaskArrayName();
  static const char* VertexArrayName();
  static const char* ConeAxisArrayName();
  static const char* ConeAngleArrayName();
  static const char* ShapeErrorArrayName();
  static const char* DiffuseRangeArrayName();
  static const char* SpecularRangeArrayName();
  static const char* FlagsArrayName();
  static const char* ThicknessArrayName();
  static const char* FirstPointArrayName();
  static const char* FirstTriangleArrayName();
  static const char* FirstClusterArrayName();
  static const char* ClusterNodeArrayName();
  static const char* ClusterParentArrayName();
  static const char* ClusterVertexArrayName();
  static const char* ClusterNormalArrayName();
  static const char* PointsArrayName();
  static const char* NormalsArrayName();
  static const char* PointLeafArrayName();
  static const char* PointClusterArrayName();
  static const char* InputPointIdArrayName();
  static const char* TrianglesArrayName();
  static const char* PointGhostArrayName();
  ///@}

  /// Bits of the Flags array: the cell's sub-mesh is a union of discs; it holds boundary points.
  static int GetTopologySafeFlag() { return 1; }
  static int GetBoundaryFlag() { return 2; }

  ///@{
  /**
   * The cut travels with the octree as the unsigned char node array "CutState": 0 not in the
   * cut, 1 in the cut and drawn at its representative vertex, 2 in the cut but not drawn
   * (culled or back-facing), 3 a leaf opened: drawn at full resolution, its own points and
   * triangles. A valid cut gives every leaf exactly one ancestor-or-self in the cut; only
   * leaves are opened. vtkMultiscaleOctreeCutter and vtkPerceptualLODSelector make it,
   * vtkMultiscalePatchGenerator reads it. The selector also writes "CullMask": for each culled
   * cell, the frustum planes (bit i: plane i) its cell lies wholly outside.
   */
  static const char* CutStateArrayName() { return "CutState"; }
  static const char* CullMaskArrayName() { return "CullMask"; }
  /**
   * The selector also stores, in the octree's field data (GetFieldData()), the double array
   * "CutView": the eye (3, octree-local: relative to the origin, object coordinates), 1 for a
   * parallel projection, its direction (3), and 1 when back faces were hidden. The patch
   * generator then culls the triangles facing away from that eye.
   */
  static const char* CutViewArrayName() { return "CutView"; }
  enum CutStates
  {
    NOT_IN_CUT = 0,
    CUT_DRAWN = 1,
    CUT_HIDDEN = 2,
    CUT_OPEN = 3
  };
  /// True when a CutState array exists and forms a valid cut.
  bool HasValidCut();
  ///@}

  ///@{
  /// Retrieve an instance of this class from an information object.
  static vtkMultiscaleOctree* GetData(vtkInformation* info);
  static vtkMultiscaleOctree* GetData(vtkInformationVector* v, int i = 0);
  ///@}

#ifndef __VTK_WRAP__
  /**
   * Raw view of the node arrays for the VTK-free kernels. Returns false when the arrays are
   * missing or malformed (then `view` is left empty).
   */
  bool GetView(plod::OctreeView& view);
  /// Writable pointers to the arrays made by Allocate().
  bool GetArrays(plod::OctreeArrays& arrays);
  /// IsConsistent(), telling what is wrong in `why`.
  bool CheckConsistency(std::string* why);
  /**
   * CheckConsistency() and GetView() in one, for the filters that run every frame: the view is
   * made when the check is, and kept while the arrays it covers are the same objects, with the
   * same storage, sizes and modification times (a few pointer comparisons a call instead of a
   * look-up of every array by name). Returns false, with an empty view, when the octree is
   * empty or inconsistent. `time`, when given, receives a stamp that changes whenever the view
   * is made again: caches derived from the arrays can follow it.
   */
  bool GetCheckedView(plod::OctreeView& view, vtkMTimeType* time, std::string* why);
  /**
   * The file whose mapped bytes the arrays hold (set by vtkMultiscaleOctreeReader), or null.
   * GetCheckedView then compares it with the file on disk: rewritten in place, the octree is
   * refused (its pages are no longer safe to read); replaced by another file (a rename over
   * it), the mapped one is intact and used, with one warning (from the first octree that
   * notices: the shallow copies share the file). Initialize() and DeepCopy() clear
   * it; ShallowCopy() shares it.
   */
  void SetSourceFile(std::shared_ptr<const plod::FileIdentity> file);
  /**
   * The map of the source file (`bytes` from `start`, kept alive by `memory`) and the limit on
   * how much of it this process keeps resident, in bytes (0: none; see plodResidentPages.h).
   * Set by vtkMultiscaleOctreeReader after SetSourceFile(), from its CacheLimit; shared by
   * shallow copies.
   */
  void SetMappedPages(std::shared_ptr<void> memory, void* start, uint64_t bytes, uint64_t limit);
  /**
   * The corner walks remembered for this octree's cuts (plod::CornerMemo), made at the first
   * call and shared by shallow copies: the selector's exact count and the patch generator keep
   * one array per surface point between them, under the checked stamp (GetCheckedView).
   * Initialize() and DeepCopy() drop it.
   */
  std::shared_ptr<plod::CornerMemo> GetCornerMemo();
  /**
   * Counts memory a filter keeps for this octree against the reader's CacheLimit, beside the
   * mapped pages: `bytes` is the filter's own count, which it keeps up to date; each
   * EnforceResidentLimit() adds up the counts of the filters still alive (the octree keeps a weak
   * reference: a filter deleted stops counting), with the remembered corner walks
   * (GetCornerMemo), and keeps the mapped pages within the limit less that sum, and at least an
   * eighth of the limit (plod::ResidentLimit::SetHeld). Counting the same one again changes
   * nothing. Shared by shallow copies; does nothing for an octree not mapped from a file.
   */
  void CountHeldBytes(const std::shared_ptr<const std::atomic<uint64_t>>& bytes);
  /**
   * The background reader of the mapped file's pages (plod::PageLoader), made at the first
   * call when SetBackgroundLoading() is on and the octree is mapped and consistent; null
   * otherwise. Shared by shallow copies (vtkPerceptualLODSelector passes it to its walks).
   */
  plod::PageLoader* GetPageLoader();
#endif
  /**
   * Reading the mapped file off the frame (default off; vtkMultiscaleOctreeReader's
   * BackgroundLoading sets it): a refinement whose pages have not been read is not made in the
   * frame that first wants it; the selector draws the coarser cell instead and a thread of the
   * octree's reads the pages, most urgent (coarsest) first; a later frame refines once they are
   * read (plodPageLoader.h). So the frame never waits on the disk, and the view refines over
   * the next frames as the pages arrive. The first view is read whole. Off, each frame reads
   * what it refines, and the same views always draw the same cut. Only a mapped file has pages
   * to read: otherwise it does nothing. Shared by shallow copies: several selectors (views of
   * one file) share the thread, and each frame drops only its own selector's requests.
   */
  void SetBackgroundLoading(bool on);
  bool GetBackgroundLoading();
  /// Refinements whose pages the background thread has read so far: when this changes, a new
  /// selection can refine further (the actor renders again while loads are waiting).
  vtkIdType GetNumberOfBackgroundLoads();
  /// Major page faults (reads of the disk) the background thread has taken so far: the
  /// process's own (getrusage) less these are the frames' waits on the disk.
  vtkIdType GetNumberOfBackgroundMajorFaults();
  /// Refinements waiting for their pages now.
  vtkIdType GetNumberOfWaitingLoads();
  /// Returns once no refinement waits for its pages (for scripts and tests).
  void WaitForLoads();
  /**
   * Keeps the mapped file's pages that this process holds within the reader's CacheLimit: when
   * they exceed it, they are dropped (the kernel's page cache keeps them while memory allows,
   * and the next views map again what they read). The selector and the patch generator call it
   * after each execution; an octree that was not mapped from a file has nothing to keep. The
   * memory the filters keep for the octree counts against the same limit (CountHeldBytes). Warns
   * once where the limit cannot be kept (no /proc/self/pagemap).
   */
  void EnforceResidentLimit();
  /// Drops the mapped file's pages from the process now, as EnforceResidentLimit() does past
  /// the limit (say, when the application goes idle); false when the octree is not mapped or
  /// the pages cannot be counted.
  bool ReleaseMappedPages();
  /// How many times EnforceResidentLimit() dropped the mapped pages (0 without a limit).
  vtkIdType GetNumberOfResidentReleases();
  /// The bytes that counted against the reader's CacheLimit beside the mapped pages at the last
  /// EnforceResidentLimit() (see CountHeldBytes; 0 for an octree not mapped from a file).
  vtkIdType GetHeldBytes();
  /// The bytes of the mapped file that this process holds now, counted page by page (-1 when
  /// the octree was not mapped from a file or the pages cannot be counted).
  vtkIdType GetMappedResidentBytes();
#ifndef __VTK_WRAP__
  /// True unless the source file (if any) was changed in place since it was mapped; `why`
  /// says what changed.
  bool IsSourceFileIntact(std::string* why);
  /// The field data that holds the arrays of `group` (node, cluster, or surface).
  vtkFieldData* GetFieldDataOf(plod::ArrayGroup group);
  /// A new, empty VTK array for values of `type` (vtkIdTypeArray for int64).
  static vtkDataArray* NewArray(plod::ArrayType type);
#endif

protected:
  vtkMultiscaleOctree();
  ~vtkMultiscaleOctree() override;

  vtkFieldData* NodeData;
  vtkFieldData* SurfaceData;
  vtkFieldData* ClusterData;
  double Origin[3];
  double RootEdge;
  int FinestLevel;
  bool HasMaterialArrays;
  int CoarsestDrawnLevel = 0;
  vtkIdType NumberOfBoundaryEdges = 0;
  vtkIdType NumberOfNonManifoldEdges = 0;
  vtkIdType NumberOfMisorientedEdges = 0;
  // IsConsistent's cache: the identity and modification times of the arrays it checked (not of
  // the cut arrays, which change every frame), copied by ShallowCopy with the arrays it covers
  struct CheckKey
  {
    /// one array: the object, its storage, its number of values and its modification time
    struct Array
    {
      const void* Object;
      const void* Storage;
      vtkIdType Values;
      vtkMTimeType Time;
      bool operator==(const Array& o) const
      {
        return this->Object == o.Object && this->Storage == o.Storage && this->Values == o.Values &&
          this->Time == o.Time;
      }
    };
    std::vector<Array> Arrays;
    int Finest = -1;
    double Origin[3] = { 0, 0, 0 };
    double Edge = 0;
    bool operator==(const CheckKey& o) const;
  };
  /// The key of the arrays as they are now, in `key` (its storage is reused).
  void MakeCheckKey(CheckKey& key);
  CheckKey CheckedKey, ScratchKey;
  bool CheckedValid = false;
  bool CheckedResult = false;
  std::string CheckedWhy;
  // the view made with the check (when consistent), and the stamp GetCheckedView reports
  std::shared_ptr<const plod::OctreeView> CheckedView;
  vtkMTimeType CheckedStamp = 0;
#ifndef __VTK_WRAP__
  // the mapped file and whether its replacement was reported (shared by shallow copies, so that
  // it is reported once)
  struct SourceFileState;
  std::shared_ptr<SourceFileState> SourceFile;
  std::shared_ptr<plod::CornerMemo> CornerMemo;
  /// The page loader if one was made (GetPageLoader makes it), else null.
  plod::PageLoader* CurrentPageLoader();
  /// Adds the schema's array `spec` with `tuples` tuples (contents undefined).
  void AddSchemaArray(const plod::ArraySpec& spec, vtkIdType tuples);
#endif

private:
  /**
   * Warns once per file when the pages were dropped after at least a quarter of the last 64
   * EnforceResidentLimit() calls (the limit, less the filters' arrays, is below what the views
   * read, so the frames map their pages again); called by EnforceResidentLimit().
   */
  void WarnIfDroppedMostFrames();
  vtkMultiscaleOctree(const vtkMultiscaleOctree&) = delete;
  void operator=(const vtkMultiscaleOctree&) = delete;
};

#endif
