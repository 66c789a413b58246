// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctree
 * @brief   sparse multiscale octree of a surface, with per-node normal cones and shape errors
 *
 * vtkMultiscaleOctree is the data object that flows between the PerceptualLOD filters: built
 * once by vtkMultiscaleOctreeBuilder, read every frame by vtkPerceptualLODSelector and
 * vtkMultiscalePatchGenerator. It follows SRCC §2-3.3 (Wakatsuki et al. 2003) and TMM Table 1:
 * the root is a cube around the input; level `L` cells have edge `GetRootEdge() / 2^L`; only
 * cells that meet the surface exist (sparse).
 *
 * Every per-node quantity is a named array in GetNodeData() with one tuple per node, so that
 * Python users read them as numpy arrays (`vtk.util.numpy_support.vtk_to_numpy`):
 *
 * | name | type | comps | meaning |
 * | --- | --- | --- | --- |
 * | `Level` | unsigned char | 1 | 0 for the root |
 * | `Parent` | int | 1 | parent node, -1 for the root |
 * | `FirstChild` | int | 1 | first child node (children are contiguous), -1 for a leaf |
 * | `ChildMask` | unsigned char | 1 | bit `c` set when child `c = x + 2y + 4z` exists |
 * | `Vertex` | float | 3 | representative vertex `v`, *relative to GetOrigin()* |
 * | `ConeAxis` | float | 3 | normal cone axis `n` (unit) |
 * | `ConeAngle` | float | 1 | normal cone half angle `theta` in radians, in [0, pi] |
 * | `ShapeError` | float | 1 | SRCC eq. (3), world units |
 * | `DiffuseRange` | float | 2 | (min, max) diffuse reflectance in the cell |
 * | `SpecularRange` | float | 2 | (min, max) specular reflectance in the cell |
 * | `EdgeCrossings` | unsigned int | 1 | `F_e(i)`: bit i (0..11) edge i crossed; bit 12+i the crossing is oriented towards -axis |
 *
 * That is 62 bytes per node. Nodes are stored level by level and, inside a level, in Morton
 * order. Edge `i = 4a + pbit + 2qbit` runs along axis `a`; `(p, q)` are the two other axes in
 * cyclic order ((y,z) for x, (z,x) for y, (x,y) for z) and `pbit`/`qbit` say on which side of
 * the cell it lies. A coarse edge's crossing is the signed sum of the crossings of the finer
 * edges it is made of, so a cell and its children always agree.
 *
 * Vertices are stored in single precision relative to the root origin, which is kept in double:
 * a model far from the world origin keeps full precision. GetNodeVertex() returns world
 * coordinates.
 *
 * @warning Node indices are 32-bit: an octree holds at most 2^31 - 1 nodes.
 *
 * @sa vtkMultiscaleOctreeBuilder vtkMultiscaleOctreeAlgorithm
 */
#ifndef vtkMultiscaleOctree_h
#define vtkMultiscaleOctree_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkDataObject.h"

#include <string> // for CheckConsistency

#ifndef __VTK_WRAP__
namespace plod
{
struct OctreeView;
struct OctreeArrays;
}
#endif

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

  /// Memory used by the node arrays, in kibibytes (VTK convention).
  unsigned long GetActualMemorySize() override;

  /// The per-node arrays (see the class documentation for the names).
  vtkFieldData* GetNodeData() { return this->NodeData; }

  /// Number of nodes (0 when empty).
  vtkIdType GetNumberOfNodes();

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

  /// Sets the root cube and the finest level together.
  void SetGeometry(const double origin[3], double rootEdge, int finestLevel);

  /// Edge length of cells at `level`.
  double GetCellEdge(int level) const;

  /**
   * Creates the node arrays for `n` nodes (contents undefined) and removes any other node
   * array. Used by the builder; users normally never call it.
   */
  void AllocateNodes(vtkIdType n);

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
   * Checks that the node arrays exist with the documented types and sizes and that the tree
   * structure is consistent (parents, children, levels). An empty octree is consistent.
   */
  bool IsConsistent() { return this->CheckConsistency(nullptr); }

  ///@{
  /// Names of the node arrays.
  static const char* LevelArrayName() { return "Level"; }
  static const char* ParentArrayName() { return "Parent"; }
  static const char* FirstChildArrayName() { return "FirstChild"; }
  static const char* ChildMaskArrayName() { return "ChildMask"; }
  static const char* VertexArrayName() { return "Vertex"; }
  static const char* ConeAxisArrayName() { return "ConeAxis"; }
  static const char* ConeAngleArrayName() { return "ConeAngle"; }
  static const char* ShapeErrorArrayName() { return "ShapeError"; }
  static const char* DiffuseRangeArrayName() { return "DiffuseRange"; }
  static const char* SpecularRangeArrayName() { return "SpecularRange"; }
  static const char* EdgeCrossingsArrayName() { return "EdgeCrossings"; }
  ///@}

  ///@{
  /**
   * The cut travels with the octree as the unsigned char node array "CutState": 0 not in the
   * cut, 1 in the cut and drawn, 2 in the cut but not drawn (culled or back-facing). A valid cut
   * gives every finest cell exactly one ancestor-or-self in the cut.
   * vtkMultiscaleOctreeCutter and vtkPerceptualLODSelector make it, vtkMultiscalePatchGenerator
   * reads it.
   */
  static const char* CutStateArrayName() { return "CutState"; }
  enum CutStates
  {
    NOT_IN_CUT = 0,
    CUT_DRAWN = 1,
    CUT_HIDDEN = 2
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
  /// Writable pointers to the arrays made by AllocateNodes().
  bool GetArrays(plod::OctreeArrays& arrays);
  /// IsConsistent(), telling what is wrong in `why`.
  bool CheckConsistency(std::string* why);
#endif

protected:
  vtkMultiscaleOctree();
  ~vtkMultiscaleOctree() override;

  vtkFieldData* NodeData;
  double Origin[3];
  double RootEdge;
  int FinestLevel;
  bool HasMaterialArrays;

private:
  vtkMultiscaleOctree(const vtkMultiscaleOctree&) = delete;
  void operator=(const vtkMultiscaleOctree&) = delete;
};

#endif
