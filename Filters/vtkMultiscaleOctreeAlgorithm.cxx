// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctreeAlgorithm.h"

#include "vtkDemandDrivenPipeline.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiscaleOctree.h"
#include "vtkObjectFactory.h"
#include "vtkStreamingDemandDrivenPipeline.h"

vtkStandardNewMacro(vtkMultiscaleOctreeAlgorithm);

//------------------------------------------------------------------------------
vtkMultiscaleOctreeAlgorithm::vtkMultiscaleOctreeAlgorithm()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeAlgorithm::~vtkMultiscaleOctreeAlgorithm() = default;

//------------------------------------------------------------------------------
vtkMultiscaleOctree* vtkMultiscaleOctreeAlgorithm::GetOutput()
{
  return this->GetOutput(0);
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree* vtkMultiscaleOctreeAlgorithm::GetOutput(int port)
{
  return vtkMultiscaleOctree::SafeDownCast(this->GetOutputDataObject(port));
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeAlgorithm::SetInputData(vtkDataObject* input)
{
  this->SetInputData(0, input);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeAlgorithm::SetInputData(int index, vtkDataObject* input)
{
  this->SetInputDataInternal(index, input);
}

//------------------------------------------------------------------------------
vtkTypeBool vtkMultiscaleOctreeAlgorithm::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inInfo, vtkInformationVector* outInfo)
{
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_OBJECT()))
  {
    return this->RequestDataObject(request, inInfo, outInfo);
  }
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_INFORMATION()))
  {
    return this->RequestInformation(request, inInfo, outInfo);
  }
  if (request->Has(vtkStreamingDemandDrivenPipeline::REQUEST_UPDATE_EXTENT()))
  {
    return this->RequestUpdateExtent(request, inInfo, outInfo);
  }
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA()))
  {
    return this->RequestData(request, inInfo, outInfo);
  }
  return this->Superclass::ProcessRequest(request, inInfo, outInfo);
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeAlgorithm::RequestDataObject(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outInfo)
{
  for (int i = 0; i < this->GetNumberOfOutputPorts(); ++i)
  {
    vtkInformation* info = outInfo->GetInformationObject(i);
    if (!vtkMultiscaleOctree::SafeDownCast(info->Get(vtkDataObject::DATA_OBJECT())))
    {
      vtkMultiscaleOctree* output = vtkMultiscaleOctree::New();
      info->Set(vtkDataObject::DATA_OBJECT(), output);
      output->Delete();
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeAlgorithm::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector*)
{
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeAlgorithm::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector**, vtkInformationVector*)
{
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeAlgorithm::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outInfo)
{
  if (vtkMultiscaleOctree* output = vtkMultiscaleOctree::GetData(outInfo))
  {
    output->Initialize();
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeAlgorithm::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkMultiscaleOctree");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeAlgorithm::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiscaleOctree");
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
