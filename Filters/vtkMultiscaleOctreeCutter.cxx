// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctreeCutter.h"

#include <algorithm>

#include "plodCut.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiscaleOctree.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkUnsignedCharArray.h"

vtkStandardNewMacro(vtkMultiscaleOctreeCutter);

//------------------------------------------------------------------------------
vtkMultiscaleOctreeCutter::vtkMultiscaleOctreeCutter()
  : Mode(CUT_UNIFORM)
  , Level(-1)
  , RefineArrayName(nullptr)
{
  this->SetRefineArrayName("Refine");
}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeCutter::~vtkMultiscaleOctreeCutter()
{
  this->SetRefineArrayName(nullptr);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeCutter::SetRefineCallback(std::function<bool(vtkIdType)> refine)
{
  this->RefineCallback = std::move(refine);
  this->Modified();
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeCutter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiscaleOctree* input = vtkMultiscaleOctree::GetData(inputVector[0]);
  vtkMultiscaleOctree* output = vtkMultiscaleOctree::GetData(outputVector);
  output->Initialize();
  if (!input || input->GetNumberOfNodes() == 0)
  {
    return 1;
  }
  plod::OctreeView v;
  std::string why;
  if (!input->GetCheckedView(v, nullptr, &why))
  {
    vtkErrorMacro("The input octree is invalid (" << why << "): empty output.");
    return 1;
  }
  output->ShallowCopy(input);
  vtkNew<vtkUnsignedCharArray> cut;
  cut->SetName(vtkMultiscaleOctree::CutStateArrayName());
  cut->SetNumberOfTuples(v.NumberOfNodes);
  uint8_t* state = cut->GetPointer(0);
  switch (this->Mode)
  {
    case CUT_REFINE_ARRAY:
    {
      vtkDataArray* refine = input->GetNodeData()->GetArray(this->RefineArrayName);
      if (!refine || refine->GetNumberOfTuples() != v.NumberOfNodes)
      {
        vtkErrorMacro("Refine array '" << (this->RefineArrayName ? this->RefineArrayName : "")
                                       << "' is missing or does not have one value per node.");
        output->Initialize();
        return 1;
      }
      plod::PredicateCut(
        v, [refine](int64_t n) { return refine->GetComponent(n, 0) != 0; }, state);
      break;
    }
    case CUT_CALLBACK:
      if (!this->RefineCallback)
      {
        vtkErrorMacro("CUT_CALLBACK mode without a refine callback.");
        output->Initialize();
        return 1;
      }
      plod::PredicateCut(
        v, [this](int64_t n) { return this->RefineCallback(static_cast<vtkIdType>(n)); }, state);
      break;
    default:
      // an octree built in pieces draws nothing above its coarsest drawn level
      plod::UniformCut(v,
        this->Level < 0 ? this->Level : std::max(this->Level, input->GetCoarsestDrawnLevel()),
        state);
  }
  output->GetNodeData()->AddArray(cut);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeCutter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: "
     << (this->Mode == CUT_UNIFORM           ? "Uniform"
            : this->Mode == CUT_REFINE_ARRAY ? "RefineArray"
                                             : "Callback")
     << "\n";
  os << indent << "Level: " << this->Level << "\n";
  os << indent << "RefineArrayName: " << (this->RefineArrayName ? this->RefineArrayName : "(none)")
     << "\n";
}
