// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPerceptualLODRepresentation.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPVRenderView.h"
#include "vtkPVView.h"
#include "vtkPerceptualLODActor.h"
#include "vtkPerceptualLODRedistribution.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"

#include <algorithm>

vtkStandardNewMacro(vtkPerceptualLODRepresentation);

namespace
{
/// Counts the executions of an inner filter (its EndEvent).
void CountExecution(vtkObject*, unsigned long, void* counter, void*)
{
  ++*static_cast<int*>(counter);
}
}

//------------------------------------------------------------------------------
vtkPerceptualLODRepresentation::vtkPerceptualLODRepresentation()
{
  this->Actor = vtkPerceptualLODActor::New();
  // the cut's triangles change with every view: their ids name nothing a selection could use
  this->Actor->PickableOff();
  // nothing to draw until the first RequestData (a client in client-server mode never gets
  // the data: its actor stays empty and the server ranks render)
  vtkNew<vtkPolyData> nothing;
  this->Actor->SetInputData(nothing);
  this->SetController(vtkMultiProcessController::GetGlobalController());
  vtkMath::UninitializeBounds(this->ModelBounds);
  auto observe = [](vtkObject* filter, int* counter) {
    vtkNew<vtkCallbackCommand> command;
    command->SetCallback(CountExecution);
    command->SetClientData(counter);
    filter->AddObserver(vtkCommand::EndEvent, command);
  };
  observe(this->Actor->GetBuilder(), &this->NumberOfBuilds);
  observe(this->Actor->GetSelector(), &this->NumberOfSelections);
  observe(this->Actor->GetPatchGenerator(), &this->NumberOfPatchUpdates);
}

//------------------------------------------------------------------------------
vtkPerceptualLODRepresentation::~vtkPerceptualLODRepresentation()
{
  this->Actor->Delete();
  if (this->Redistribution)
  {
    this->Redistribution->Delete();
  }
  if (this->Prepared)
  {
    this->Prepared->Delete();
  }
  this->SetController(nullptr);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRepresentation::SetController(vtkMultiProcessController* controller)
{
  vtkSetObjectBodyMacro(Controller, vtkMultiProcessController, controller);
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
vtkDataObject* vtkPerceptualLODRepresentation::PrepareInput(vtkDataObject* input)
{
  if (auto octree = vtkMultiscaleOctree::SafeDownCast(input))
  {
    return octree;
  }
  if (vtkCompositeDataSet::SafeDownCast(input))
  {
    vtkErrorMacro("Perceptual LOD draws one surface or point cloud: this input is a composite "
                  "dataset ("
      << input->GetClassName() << "); apply Merge Blocks first");
    return nullptr;
  }
  if (auto polyData = vtkPolyData::SafeDownCast(input))
  {
    return polyData;
  }
  if (auto dataSet = vtkDataSet::SafeDownCast(input))
  {
    vtkNew<vtkDataSetSurfaceFilter> surface;
    surface->SetInputData(dataSet);
    surface->Update();
    return surface->GetOutput();
  }
  vtkErrorMacro("Perceptual LOD cannot draw a " << (input ? input->GetClassName() : "null input")
                                                << ": it takes a surface, a point cloud or a "
                                                   "multiscale octree");
  return nullptr;
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = inputVector[0]->GetNumberOfInformationObjects() > 0
    ? vtkDataObject::GetData(inputVector[0], 0)
    : nullptr;
  const int ranks = this->GetNumberOfRanks();
  // Only a new input (or a new ownership level) is prepared again: representation properties
  // that ParaView sets mark the representation modified, and the redistribution is collective
  // and costs a pass over the data.
  const vtkMTimeType inputTime = input ? input->GetMTime() : 0;
  const bool redistributionChanged =
    this->Redistribution && this->Redistribution->GetOwnershipLevel() != this->OwnershipLevel;
  if (input != this->PreparedInput || inputTime != this->PreparedFrom || redistributionChanged)
  {
    this->PreparedInput = input;
    this->PreparedFrom = inputTime;
    vtkDataObject* prepared = input ? this->PrepareInput(input) : nullptr;
    auto surface = vtkPolyData::SafeDownCast(prepared);
    vtkPerceptualLODSelector* selector = this->Actor->GetSelector();
    vtkMultiscaleOctreeBuilder* builder = this->Actor->GetBuilder();
    if (ranks > 1 && this->Redistribute && (surface || !input || !prepared))
    {
      // every rank takes part, with or without a piece
      if (!this->Redistribution)
      {
        this->Redistribution = vtkPerceptualLODRedistribution::New();
      }
      this->Redistribution->SetController(this->Controller);
      this->Redistribution->SetOwnershipLevel(this->OwnershipLevel);
      this->Redistribution->SetRequestedFinestLevel(this->FinestLevel);
      vtkNew<vtkPolyData> empty;
      this->Redistribution->SetInputData(surface ? surface : empty.Get());
      this->Redistribution->Update();
      vtkNew<vtkPolyData> piece;
      piece->ShallowCopy(this->Redistribution->GetOutput());
      prepared = piece;
      prepared->Register(this);
      if (this->Prepared)
      {
        this->Prepared->Delete();
      }
      this->Prepared = prepared;
      this->Redistribution->ConfigureBuilder(builder);
      selector->SetMinimumLevel(this->Redistribution->GetOwnershipLevel());
      this->GlobalBoundaryEdges = this->Redistribution->GetNumberOfBoundaryEdges();
    }
    else
    {
      if (prepared)
      {
        prepared->Register(this);
      }
      if (this->Prepared)
      {
        this->Prepared->Delete();
      }
      this->Prepared = prepared;
      if (ranks > 1 && vtkMultiscaleOctree::SafeDownCast(prepared))
      {
        vtkWarningMacro("An octree read or built per rank is drawn as it is: its cells are not "
                        "shared out between ranks, so cracks can open along piece borders. "
                        "Give this representation the surface instead.");
      }
      builder->SetUseGivenRootCube(false);
      builder->SetFinestLevel(this->FinestLevel);
      selector->SetMinimumLevel(0);
      this->GlobalBoundaryEdges = -1;
    }
    this->ApplyBackFaceMode();
    if (this->Prepared)
    {
      this->Actor->SetInputData(this->Prepared);
    }
    else
    {
      vtkNew<vtkPolyData> nothing;
      this->Actor->SetInputData(nothing);
    }
  }
  // Builds here (not in the first render), so that the build reports progress as data
  // processing does, and the view gets the model's bounds.
  double* bounds = this->Actor->GetBounds();
  std::copy(bounds, bounds + 6, this->ModelBounds);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0; // invisible
  }
  if (request == vtkPVView::REQUEST_UPDATE())
  {
    if (vtkMath::AreBoundsInitialized(this->ModelBounds))
    {
      vtkPVRenderView::SetGeometryBounds(inInfo, this, this->ModelBounds);
    }
    // The cut is selected and drawn where the data is: every rank renders its own piece and
    // IceT composites (in client-server, on the server).
    vtkPVRenderView::SetRequiresDistributedRendering(inInfo, this, true);
    vtkPVRenderView::SetRequiresDistributedRenderingLOD(inInfo, this, true);
  }
  return 1;
}

//------------------------------------------------------------------------------
bool vtkPerceptualLODRepresentation::AddToView(vtkView* view)
{
  if (auto renderView = vtkPVRenderView::SafeDownCast(view))
  {
    renderView->GetRenderer()->AddActor(this->Actor);
    return this->Superclass::AddToView(view);
  }
  return false;
}

//------------------------------------------------------------------------------
bool vtkPerceptualLODRepresentation::RemoveFromView(vtkView* view)
{
  if (auto renderView = vtkPVRenderView::SafeDownCast(view))
  {
    renderView->GetRenderer()->RemoveActor(this->Actor);
    return this->Superclass::RemoveFromView(view);
  }
  return false;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRepresentation::SetVisibility(bool visible)
{
  this->Superclass::SetVisibility(visible);
  this->Actor->SetVisibility(visible);
}

//------------------------------------------------------------------------------
// Selector, builder and property settings: forwarded, without marking the representation
// modified (the next render selects again).
void vtkPerceptualLODRepresentation::SetErrorModel(int model)
{
  this->Actor->GetSelector()->SetErrorModel(model);
}
int vtkPerceptualLODRepresentation::GetErrorModel()
{
  return this->Actor->GetSelector()->GetErrorModel();
}
void vtkPerceptualLODRepresentation::SetMotionModel(int model)
{
  this->Actor->GetSelector()->SetMotionModel(model);
}
int vtkPerceptualLODRepresentation::GetMotionModel()
{
  return this->Actor->GetSelector()->GetMotionModel();
}
void vtkPerceptualLODRepresentation::SetVelocityCriterion(int criterion)
{
  this->Actor->GetSelector()->SetVelocityCriterion(criterion);
}
void vtkPerceptualLODRepresentation::SetFoveationMode(int mode)
{
  this->Actor->GetSelector()->SetFoveationMode(mode);
}
void vtkPerceptualLODRepresentation::SetFoveationRate(double rate)
{
  this->Actor->GetSelector()->SetFoveationRate(rate);
}
void vtkPerceptualLODRepresentation::SetFoveationPoint(double x, double y, double z)
{
  this->Actor->GetSelector()->SetFoveationPoint(x, y, z);
}
void vtkPerceptualLODRepresentation::SetGazeDirection(double x, double y, double z)
{
  this->Actor->GetSelector()->SetGazeDirection(x, y, z);
}
void vtkPerceptualLODRepresentation::SetBackFaceMode(int mode)
{
  this->BackFaceMode = mode;
  this->ApplyBackFaceMode();
}
void vtkPerceptualLODRepresentation::ApplyBackFaceMode()
{
  vtkPerceptualLODSelector* selector = this->Actor->GetSelector();
  if (this->BackFaceMode == vtkPerceptualLODSelector::BACK_FACES_AUTOMATIC &&
    this->GlobalBoundaryEdges >= 0)
  {
    // distributed: the whole mesh decides, not this rank's octree (whose halo has a rim)
    selector->SetBackFaceMode(this->GlobalBoundaryEdges == 0
        ? vtkPerceptualLODSelector::BACK_FACES_HIDDEN
        : vtkPerceptualLODSelector::BACK_FACES_DRAWN);
  }
  else
  {
    selector->SetBackFaceMode(this->BackFaceMode);
  }
}
void vtkPerceptualLODRepresentation::SetContourTolerance(double pixels)
{
  this->Actor->GetSelector()->SetContourTolerance(pixels);
}
double vtkPerceptualLODRepresentation::GetContourTolerance()
{
  return this->Actor->GetSelector()->GetContourTolerance();
}
void vtkPerceptualLODRepresentation::SetBrightnessTolerance(double tolerance)
{
  this->Actor->GetSelector()->SetBrightnessTolerance(tolerance);
}
void vtkPerceptualLODRepresentation::SetTopologyTolerance(double pixels)
{
  this->Actor->GetSelector()->SetTopologyTolerance(pixels);
}
void vtkPerceptualLODRepresentation::SetTriangleBudget(vtkIdType triangles)
{
  this->Actor->GetSelector()->SetTriangleBudget(triangles);
}
void vtkPerceptualLODRepresentation::SetTargetFrameTime(double seconds)
{
  this->Actor->SetTargetFrameTime(seconds);
}
void vtkPerceptualLODRepresentation::SetFinestLevel(int level)
{
  if (level != this->FinestLevel)
  {
    this->FinestLevel = level;
    // prepared again: in parallel the redistribution chooses the level all ranks build at
    this->PreparedFrom = 0;
    this->MarkModified();
  }
}
void vtkPerceptualLODRepresentation::SetOwnershipLevel(int level)
{
  level = std::min(6, std::max(1, level));
  if (level != this->OwnershipLevel)
  {
    this->OwnershipLevel = level;
    this->MarkModified();
  }
}
void vtkPerceptualLODRepresentation::SetRedistribute(bool redistribute)
{
  if (redistribute != this->Redistribute)
  {
    this->Redistribute = redistribute;
    this->PreparedFrom = 0; // prepared again
    this->MarkModified();   // ParaView's executive runs RequestData only after this
  }
}
void vtkPerceptualLODRepresentation::SetDiffuseColor(double r, double g, double b)
{
  this->Actor->GetProperty()->SetDiffuseColor(r, g, b);
}
void vtkPerceptualLODRepresentation::SetDiffuse(double diffuse)
{
  this->Actor->GetProperty()->SetDiffuse(diffuse);
}
void vtkPerceptualLODRepresentation::SetSpecular(double specular)
{
  this->Actor->GetProperty()->SetSpecular(specular);
}
void vtkPerceptualLODRepresentation::SetSpecularPower(double power)
{
  this->Actor->GetProperty()->SetSpecularPower(power);
}
void vtkPerceptualLODRepresentation::SetAmbient(double ambient)
{
  this->Actor->GetProperty()->SetAmbient(ambient);
}
void vtkPerceptualLODRepresentation::SetOpacity(double opacity)
{
  this->Actor->GetProperty()->SetOpacity(opacity);
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetNumberOfTriangles()
{
  auto output = vtkPolyData::SafeDownCast(this->Actor->GetPatchGenerator()->GetOutputDataObject(0));
  return output ? output->GetNumberOfPolys() : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetNumberOfCutNodes()
{
  return this->Actor->GetSelector()->GetNumberOfCutNodes();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRepresentation::GetSelectorEyePosition(double eye[3])
{
  this->Actor->GetSelector()->GetEyePosition(eye);
}

//------------------------------------------------------------------------------
double* vtkPerceptualLODRepresentation::GetSelectorEye()
{
  this->Actor->GetSelector()->GetEyePosition(this->SelectorEye);
  return this->SelectorEye;
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRepresentation::GetNumberOfOwnedCells()
{
  return this->Redistribution ? this->Redistribution->GetNumberOfOwnedCells() : 0;
}

//------------------------------------------------------------------------------
namespace
{
vtkMultiscaleOctree* DrawnOctree(vtkPerceptualLODActor* actor)
{
  return vtkMultiscaleOctree::SafeDownCast(actor->GetSelector()->GetInputDataObject(0, 0));
}
}

int vtkPerceptualLODRepresentation::GetOctreeFinestLevel()
{
  vtkMultiscaleOctree* octree = DrawnOctree(this->Actor);
  return octree && octree->GetNumberOfNodes() > 0 ? octree->GetFinestLevel() : -1;
}

vtkIdType vtkPerceptualLODRepresentation::GetNumberOfOctreeNodes()
{
  vtkMultiscaleOctree* octree = DrawnOctree(this->Actor);
  return octree ? octree->GetNumberOfNodes() : 0;
}

vtkIdType vtkPerceptualLODRepresentation::GetNumberOfOctreeTriangles()
{
  vtkMultiscaleOctree* octree = DrawnOctree(this->Actor);
  return octree ? octree->GetNumberOfSurfaceTriangles() : 0;
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRepresentation::GetRank()
{
  return this->Controller ? this->Controller->GetLocalProcessId() : 0;
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRepresentation::GetNumberOfRanks()
{
  return this->Controller ? this->Controller->GetNumberOfProcesses() : 1;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FinestLevel: " << this->FinestLevel << "\n";
  os << indent << "OwnershipLevel: " << this->OwnershipLevel << "\n";
  os << indent << "Redistribute: " << this->Redistribute << "\n";
  os << indent << "BackFaceMode: " << this->BackFaceMode << "\n";
  os << indent << "GlobalBoundaryEdges: " << this->GlobalBoundaryEdges << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "Ranks: " << this->GetNumberOfRanks() << "\n";
  os << indent << "NumberOfBuilds: " << this->NumberOfBuilds << "\n";
  os << indent << "NumberOfSelections: " << this->NumberOfSelections << "\n";
  os << indent << "NumberOfPatchUpdates: " << this->NumberOfPatchUpdates << "\n";
  os << indent << "Actor:\n";
  this->Actor->PrintSelf(os, indent.GetNextIndent());
}
