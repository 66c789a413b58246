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
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <cmath>
#include <numeric>

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
  else if (request == vtkPVView::REQUEST_RENDER())
  {
    // Every rendering process makes this pass before the render window renders, for every
    // visible representation, whether its actor then draws or is culled: the place where all
    // ranks can exchange, once per render and in the same order.
    this->ShareFrame(vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW())));
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRepresentation::ShareFrame(vtkPVRenderView* view)
{
  vtkRenderer* renderer = view ? view->GetRenderer() : nullptr;
  vtkPerceptualLODRenderBinding* binding = this->Actor->MakeBinding(renderer);
  this->Binding = binding;
  const int ranks = this->GetNumberOfRanks();
  if (!binding || ranks < 2)
  {
    // one process: the binding steers at each push, as for vtkPerceptualLODActor alone
    if (binding)
    {
      binding->ExternalSteeringOff();
    }
    this->Sharing = false;
    return;
  }
  // The ranks share a frame only when every one of them renders it: distributed rendering for
  // still and interactive renders (this representation asks for both, but another one can ask
  // for local rendering). vtkPVRenderView::Update decides both flags from figures reduced over
  // the ranks, so every rank takes the same branch.
  const bool shared =
    view->GetUseDistributedRenderingForRender() && view->GetUseDistributedRenderingForLODRender();
  const double target = this->Actor->GetTargetFrameTime();
  if (shared && !this->Sharing)
  {
    // start from the same state on every rank: a new controller (a target that changes resets
    // it), an even split
    binding->SetTargetFrameTime(0);
    binding->StepBudget(0, 0, false);
    this->Shares.clear();
  }
  this->Sharing = shared;
  // here rather than at the push, which a rank whose actor is culled does not make: every rank
  // resets its controller at the same frame
  binding->SetTargetFrameTime(target);
  binding->SetExternalSteering(shared);
  vtkPerceptualLODSelector* selector = this->Actor->GetSelector();
  if (!(target > 0))
  {
    binding->StepBudget(0, 0, false); // forgets a steered budget: the push leaves ours alone
  }
  if (!shared)
  {
    // nothing exchanged: each rank steers from its own frames; a fixed budget is split evenly
    this->Shares.assign(ranks, 1.0 / ranks);
    this->SharesFromDemand = false;
    this->TotalTriangleBudget = target > 0 ? 0 : this->TriangleBudget;
    this->SharedFrameCost = binding->GetLastFrameCost();
    if (!(target > 0))
    {
      selector->SetTriangleBudget(this->PartOfBudget(this->TriangleBudget));
    }
    return;
  }

  // One collective per render, on every rank: this rank's figures, gathered in rank order.
  // The figures are small whole numbers and times, and every rank reduces the same table in the
  // same order, so all get the same results, bit for bit.
  double measured = binding->TakeFrameCost();
  if (measured > 0 && (this->TestingSlowRank < 0 || this->TestingSlowRank == this->GetRank()))
  {
    measured += this->TestingExtraFrameCost;
  }
  constexpr int fields = 4;
  const double mine[fields] = { measured,
    double(selector->GetNumberOfCutTriangles() + selector->GetNumberOfWaitingTriangles()),
    double(selector->GetNumberOfBudgetTriangles()), selector->GetBudgetWasBinding() ? 1.0 : 0.0 };
  std::vector<double> all(static_cast<size_t>(fields) * ranks, 0.0);
  this->Controller->AllGather(mine, all.data(), fields);
  ++this->NumberOfFrameReductions;
  double cost = 0, drawn = 0;
  bool bound = false;
  std::vector<double> demands(ranks);
  for (int r = 0; r < ranks; ++r)
  {
    const double* figures = all.data() + static_cast<size_t>(fields) * r;
    cost = std::max(cost, figures[0]);
    demands[r] = figures[1];
    drawn += figures[2];
    bound = bound || figures[3] > 0;
  }
  this->SharedFrameCost = cost;
  // the composited frame steers: the slowest rank's cost, the triangles of all ranks
  const vtkIdType total = target > 0
    ? binding->StepBudget(cost, static_cast<vtkIdType>(drawn), bound)
    : this->TriangleBudget;
  this->TotalTriangleBudget = total;
  this->UpdateShares(demands);
  selector->SetTriangleBudget(this->PartOfBudget(total));
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRepresentation::UpdateShares(const std::vector<double>& demands)
{
  const size_t n = demands.size();
  const double sum = std::accumulate(demands.begin(), demands.end(), 0.0);
  std::vector<double> wanted(n, 1.0 / double(n));
  if (sum > 0)
  {
    for (size_t r = 0; r < n; ++r)
    {
      wanted[r] = demands[r] / sum;
    }
  }
  if (this->Shares.size() != n || (!this->SharesFromDemand && sum > 0))
  {
    // the first demands measured: taken as they are
    this->Shares = wanted;
    this->SharesFromDemand = sum > 0;
    return;
  }
  double moved = 0;
  for (size_t r = 0; r < n; ++r)
  {
    moved += std::abs(wanted[r] - this->Shares[r]);
  }
  if (moved <= 0.05)
  {
    return; // dead band: at most 2.5 % of the budget would change hands
  }
  for (size_t r = 0; r < n; ++r)
  {
    this->Shares[r] = 0.5 * (this->Shares[r] + wanted[r]); // halfway: smoothly
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::PartOfBudget(vtkIdType total)
{
  const int rank = this->GetRank();
  const vtkIdType n = static_cast<vtkIdType>(this->Shares.size());
  if (total <= 0 || n == 0 || rank < 0 || rank >= n)
  {
    return total > 0 ? total : 0;
  }
  if (total <= n)
  {
    return 1; // fewer triangles than ranks: the floors exceed it anyway
  }
  // 1 each (0 would mean no budget), the rest in proportion: the parts add up to at most total
  const long double part = static_cast<long double>(total - n) * this->Shares[rank];
  return 1 +
    static_cast<vtkIdType>(std::floor(std::min(part, static_cast<long double>(total - n))));
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
    this->Binding = nullptr;
    this->Sharing = false;
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
  this->TriangleBudget = std::max<vtkIdType>(triangles, 0);
  if (this->GetNumberOfRanks() < 2)
  {
    this->Actor->GetSelector()->SetTriangleBudget(triangles);
  }
  // with several ranks: split at the next render (ShareFrame)
}
void vtkPerceptualLODRepresentation::SetExactTriangleBudget(int exact)
{
  this->Actor->GetSelector()->SetExactTriangleBudget(exact != 0);
}
int vtkPerceptualLODRepresentation::GetExactTriangleBudget()
{
  return this->Actor->GetSelector()->GetExactTriangleBudget() ? 1 : 0;
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
double vtkPerceptualLODRepresentation::GetLocalFrameCost()
{
  return this->Binding ? this->Binding->GetLastFrameCost() : 0.0;
}

//------------------------------------------------------------------------------
double vtkPerceptualLODRepresentation::GetSharedFrameCost()
{
  return this->GetNumberOfRanks() > 1 ? this->SharedFrameCost : this->GetLocalFrameCost();
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetTotalTriangleBudget()
{
  return this->GetNumberOfRanks() > 1 ? this->TotalTriangleBudget
                                      : this->Actor->GetSelector()->GetTriangleBudget();
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetRankTriangleBudget()
{
  return this->Actor->GetSelector()->GetTriangleBudget();
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetNumberOfBudgetTriangles()
{
  return this->Actor->GetSelector()->GetNumberOfBudgetTriangles();
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetNumberOfCutNodes()
{
  return this->Actor->GetSelector()->GetNumberOfCutNodes();
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRepresentation::GetNumberOfAwaitingCells()
{
  return this->Actor->GetSelector()->GetNumberOfAwaitingCells();
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
  os << indent << "TriangleBudget: " << this->TriangleBudget << " (in the view)\n";
  os << indent << "TotalTriangleBudget: " << this->TotalTriangleBudget << "\n";
  os << indent << "SharedFrameCost: " << this->SharedFrameCost << " s\n";
  os << indent << "NumberOfFrameReductions: " << this->NumberOfFrameReductions << "\n";
  os << indent << "TestingExtraFrameCost: " << this->TestingExtraFrameCost << " s (rank "
     << this->TestingSlowRank << ")\n";
  os << indent << "Actor:\n";
  this->Actor->PrintSelf(os, indent.GetNextIndent());
}
