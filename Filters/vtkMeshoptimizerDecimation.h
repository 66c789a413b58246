// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMeshoptimizerDecimation
 * @brief   a static simplification of a triangle mesh by meshoptimizer, as a VTK filter
 *
 * A second static baseline beside vtkQuadricDecimation for judging the perceptual LOD: the
 * simplified mesh a VTK user could make once with Debian's meshoptimizer 0.18
 * (`meshopt_simplify`: edge collapses ordered by quadric error, Garland & Heckbert 1997, that
 * keep the topology). The filter is built only when meshoptimizer is found at configure time.
 *
 * Input: any vtkPolyData; polygons are used as triangles (polygons of more than three points
 * and strips are refused with an error: run vtkTriangleFilter first). Output: the input's points
 * that remaining triangles use (double precision kept), and the remaining triangles; no point or
 * cell data is passed (recompute normals with vtkPolyDataNormals). The simplifier works in
 * single precision, as meshoptimizer does, on coordinates relative to the bounds' centre.
 *
 * The simplifier may stop above the target: it refuses collapses that would change the
 * topology, and with LockBorder it keeps boundary points in place. GetNumberOfTriangles() says
 * what it reached.
 *
 * @warning meshoptimizer indexes points with 32-bit unsigned integers: inputs with 2^32 points
 * or more are refused.
 *
 * @sa vtkQuadricDecimation vtkMultiscalePatchGenerator
 */
#ifndef vtkMeshoptimizerDecimation_h
#define vtkMeshoptimizerDecimation_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class PERCEPTUALLODFILTERS_EXPORT vtkMeshoptimizerDecimation : public vtkPolyDataAlgorithm
{
public:
  static vtkMeshoptimizerDecimation* New();
  vtkTypeMacro(vtkMeshoptimizerDecimation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Number of triangles to reach. When positive it wins over TargetReduction. Default 0 (use
   * TargetReduction).
   */
  vtkSetClampMacro(TargetNumberOfTriangles, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(TargetNumberOfTriangles, vtkIdType);
  ///@}

  ///@{
  /// Fraction of the triangles to remove, in [0, 1], as vtkQuadricDecimation. Default 0.9.
  vtkSetClampMacro(TargetReduction, double, 0.0, 1.0);
  vtkGetMacro(TargetReduction, double);
  ///@}

  ///@{
  /**
   * Largest error the simplifier may make, relative to the mesh's extent (meshoptimizer's
   * target_error). Default 1: no limit, the triangle target decides.
   */
  vtkSetClampMacro(TargetError, double, 0.0, 1.0);
  vtkGetMacro(TargetError, double);
  ///@}

  ///@{
  /// Keep the points of open boundaries in place (meshopt_SimplifyLockBorder). Default off.
  vtkSetMacro(LockBorder, bool);
  vtkGetMacro(LockBorder, bool);
  vtkBooleanMacro(LockBorder, bool);
  ///@}

  ///@{
  /// What the last execution reached: the triangles kept, and the error the simplifier
  /// reported (relative to the extent).
  vtkGetMacro(NumberOfTriangles, vtkIdType);
  vtkGetMacro(ResultError, double);
  ///@}

protected:
  vtkMeshoptimizerDecimation();
  ~vtkMeshoptimizerDecimation() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkIdType TargetNumberOfTriangles;
  double TargetReduction;
  double TargetError;
  bool LockBorder;
  vtkIdType NumberOfTriangles;
  double ResultError;

private:
  vtkMeshoptimizerDecimation(const vtkMeshoptimizerDecimation&) = delete;
  void operator=(const vtkMeshoptimizerDecimation&) = delete;
};

#endif
