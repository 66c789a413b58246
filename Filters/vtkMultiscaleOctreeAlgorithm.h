// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctreeAlgorithm
 * @brief   superclass for algorithms that produce a vtkMultiscaleOctree
 *
 * Plays for vtkMultiscaleOctree the role vtkPolyDataAlgorithm plays for vtkPolyData: it creates
 * the output data object, routes the pipeline requests to RequestInformation(),
 * RequestUpdateExtent() and RequestData(), and offers GetOutput()/SetInputData(). By default it
 * has one input port that takes a vtkMultiscaleOctree and one output port; subclasses change
 * FillInputPortInformation() for other inputs.
 *
 * @sa vtkMultiscaleOctree vtkMultiscaleOctreeBuilder
 */
#ifndef vtkMultiscaleOctreeAlgorithm_h
#define vtkMultiscaleOctreeAlgorithm_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkAlgorithm.h"

class vtkMultiscaleOctree;

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctreeAlgorithm : public vtkAlgorithm
{
public:
  static vtkMultiscaleOctreeAlgorithm* New();
  vtkTypeMacro(vtkMultiscaleOctreeAlgorithm, vtkAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The output octree of a port.
  vtkMultiscaleOctree* GetOutput();
  vtkMultiscaleOctree* GetOutput(int port);
  ///@}

  ///@{
  /// Assigns a data object as input (no pipeline connection).
  void SetInputData(vtkDataObject* input);
  void SetInputData(int index, vtkDataObject* input);
  ///@}

  /// Dispatches the pipeline passes to the Request* methods.
  vtkTypeBool ProcessRequest(
    vtkInformation* request, vtkInformationVector** inInfo, vtkInformationVector* outInfo) override;

protected:
  vtkMultiscaleOctreeAlgorithm();
  ~vtkMultiscaleOctreeAlgorithm() override;

  /// Creates a vtkMultiscaleOctree on each output port that lacks one.
  virtual int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*);
  virtual int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*);
  virtual int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*);
  /// Does the work; the default makes an empty output.
  virtual int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

private:
  vtkMultiscaleOctreeAlgorithm(const vtkMultiscaleOctreeAlgorithm&) = delete;
  void operator=(const vtkMultiscaleOctreeAlgorithm&) = delete;
};

#endif
