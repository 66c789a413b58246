// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctreeCutter
 * @brief   makes a cut through a multiscale octree without a view: uniform level, array, callback
 *
 * The output is a shallow copy of the input octree with a "CutState" node array (see
 * vtkMultiscaleOctree::CutStateArrayName()) in which every cut cell is drawn. It is the simple
 * way to make cuts for tests and for users who choose the detail themselves; the perceptual
 * choice from a view is vtkPerceptualLODSelector's.
 *
 * Modes:
 * - CUT_UNIFORM (default): every node at Level, drawn at its representative vertex. Level -1
 *   (the default), or any level above the finest, opens every leaf: the full resolution, the
 *   input itself. A level coarser than the octree's coarsest drawn level (an octree built in
 *   pieces, vtkMultiscaleOctree::GetCoarsestDrawnLevel) cuts at that level. The other modes
 *   cut where they are told: the levels above it hold placeholders.
 * - CUT_REFINE_ARRAY: a node is refined when the node array named RefineArrayName is non-zero
 *   for it (a refined leaf is opened); the cut is where refinement stops (the root is always
 *   considered). From Python, set such an array with numpy on the builder's output, then
 *   connect it here.
 * - CUT_CALLBACK (C++ only): SetRefineCallback(std::function<bool(vtkIdType)>) decides.
 *
 * @sa vtkMultiscaleOctree vtkMultiscalePatchGenerator vtkPerceptualLODSelector
 */
#ifndef vtkMultiscaleOctreeCutter_h
#define vtkMultiscaleOctreeCutter_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkMultiscaleOctreeAlgorithm.h"

#ifndef __VTK_WRAP__
#include <functional> // for the refine callback
#endif

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctreeCutter : public vtkMultiscaleOctreeAlgorithm
{
public:
  static vtkMultiscaleOctreeCutter* New();
  vtkTypeMacro(vtkMultiscaleOctreeCutter, vtkMultiscaleOctreeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Modes
  {
    CUT_UNIFORM = 0,
    CUT_REFINE_ARRAY = 1,
    CUT_CALLBACK = 2
  };

  ///@{
  /// How the cut is made. Default CUT_UNIFORM.
  vtkSetClampMacro(Mode, int, CUT_UNIFORM, CUT_CALLBACK);
  vtkGetMacro(Mode, int);
  void SetModeToUniform() { this->SetMode(CUT_UNIFORM); }
  void SetModeToRefineArray() { this->SetMode(CUT_REFINE_ARRAY); }
  void SetModeToCallback() { this->SetMode(CUT_CALLBACK); }
  ///@}

  ///@{
  /// Level of the uniform cut; -1 (default) or above the finest level: full resolution.
  vtkSetMacro(Level, int);
  vtkGetMacro(Level, int);
  ///@}

  ///@{
  /// Node array whose non-zero values mark nodes to refine (CUT_REFINE_ARRAY). Default "Refine".
  vtkSetStringMacro(RefineArrayName);
  vtkGetStringMacro(RefineArrayName);
  ///@}

#ifndef __VTK_WRAP__
  /// Refinement predicate of CUT_CALLBACK (called with node ids). Calls Modified().
  void SetRefineCallback(std::function<bool(vtkIdType)> refine);
#endif

protected:
  vtkMultiscaleOctreeCutter();
  ~vtkMultiscaleOctreeCutter() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Mode;
  int Level;
  char* RefineArrayName;
#ifndef __VTK_WRAP__
  std::function<bool(vtkIdType)> RefineCallback;
#endif

private:
  vtkMultiscaleOctreeCutter(const vtkMultiscaleOctreeCutter&) = delete;
  void operator=(const vtkMultiscaleOctreeCutter&) = delete;
};

#endif
