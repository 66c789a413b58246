// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPerceptualLODSelector.h"
#include "vtkPerceptualLODSMP.h"

#include "plodPatches.h"
#include "plodSelector.h"
#include "plodViewModel.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiscaleOctree.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkPerceptualLODSelector);

namespace
{
void Identity(double m[16])
{
  for (int i = 0; i < 16; ++i)
  {
    m[i] = (i % 5 == 0) ? 1.0 : 0.0;
  }
}

bool Finite(const double* x, int n)
{
  for (int i = 0; i < n; ++i)
  {
    if (!std::isfinite(x[i]))
    {
      return false;
    }
  }
  return true;
}

}

struct vtkPerceptualLODSelector::Internals
{
  plod::Selector Kernel;
  std::vector<plod::SelectorLight> Lights;
  vtkSmartPointer<vtkUnsignedCharArray> State;
  vtkSmartPointer<vtkUnsignedCharArray> Reason;
  vtkSmartPointer<vtkUnsignedCharArray> CullMask;
  vtkSmartPointer<vtkDoubleArray> CutView;
  // the cut arrays' bytes (a byte a node each), counted against the reader's CacheLimit; made
  // with the arrays
  std::shared_ptr<std::atomic<uint64_t>> Held;
  // The output between frames: the input's arrays, the three cut arrays and the cut's view. It
  // is made when the input changes; each frame writes the cut arrays and the view in place and
  // the output shallow-copies it (the pipeline clears the output before each execution). Made
  // anew every frame, the output cost more than a small cut's walk (measured: docs/benchmarks.md).
  // It is also the last good output, which an invalid input restores instead of losing the
  // previous cut (RestoreLastCut): null before the first cut and after an empty or invalid octree.
  vtkSmartPointer<vtkMultiscaleOctree> Prepared;
  // what the caches were made for: the octree's checked view (its stamp: the kernel and the cut
  // arrays follow the arrays), and the input object and its modification time (Prepared)
  vtkMTimeType ViewStamp = 0;
  vtkMultiscaleOctree* Input = nullptr;
  vtkMTimeType InputTime = 0;
  // the input's background loads (vtkMultiscaleOctree::SetBackgroundLoading) as of the last cut
  vtkIdType LoadsSeen = 0;

  /// The output of the last cut, or an empty one (an invalid input keeps the previous cut).
  void RestoreLastCut(vtkMultiscaleOctree* output)
  {
    if (this->Prepared)
      output->ShallowCopy(this->Prepared);
    else
      output->Initialize();
  }

  /// Forgets the caches (after an empty or invalid octree).
  void Reset()
  {
    this->Prepared = nullptr;
    this->State = nullptr;
    this->ViewStamp = 0;
    this->Input = nullptr;
  }
};

//------------------------------------------------------------------------------
vtkPerceptualLODSelector::vtkPerceptualLODSelector()
  : ErrorModel(ERROR_SRCC)
  , MotionModel(MOTION_NONE)
  , VelocityCriterion(VELOCITY_ALONE)
  , FoveationMode(FOVEATION_OFF)
  , FoveationRate(2.0)
  , BackFaceMode(BACK_FACES_AUTOMATIC)
  , HidBackFaces(true)
  , ContourTolerance(plod::SelectionInput().ContourTolerance)
  , BrightnessTolerance(plod::SelectionInput().BrightnessTolerance)
  , TopologyTolerance(plod::SelectionInput().TopologyTolerance)
  , MinimumLevel(0)
  , TriangleBudget(0)
  , BudgetStopRule(BUDGET_SKIP_MISFITS)
  , ExactTriangleBudget(true)
  , IncrementalSelection(false)
  , ViewAngle(30.0)
  , UseFrustum(false)
  , ParallelProjection(false)
  , ParallelScale(1.0)
  , UsePhysicalDisplay(false)
  , PixelPitch(0.25)
  , ViewingDistance(600.0)
  , CoordinatesAreWorld(false)
  , DiffuseReflectance(1.0)
  , SpecularReflectance(0.3)
  , SpecularPower(20.0)
  , HasPreviousFrame(false)
  , PreviousFrameTime(0.0)
  , FrameInterval(1.0 / 60.0)
  , InverseVelocitySpeed(4.0)
  , DirectVelocitySpeed(64.0)
  , PSECFactor(0.25)
  , DistancePixelThreshold(1.0)
  , ObjectSpeed(0.0)
  , DistanceLevel(0)
  , NumberOfVisitedNodes(0)
  , NumberOfCutNodes(0)
  , NumberOfDrawnNodes(0)
  , NumberOfOpenedLeaves(0)
  , NumberOfTopologyRefinedNodes(0)
  , BudgetWasBinding(false)
  , NumberOfBudgetTriangles(0)
  , NumberOfCutTriangles(0)
  , NumberOfWaitingTriangles(0)
  , SelectTime(0.0)
  , Internal(new Internals)
{
  this->FoveationPoint[0] = this->FoveationPoint[1] = this->FoveationPoint[2] = 0.0;
  this->FoveationUp[0] = this->FoveationUp[2] = 0.0;
  this->FoveationUp[1] = 1.0;
  this->FoveationWeights[0] = this->FoveationWeights[1] = 1.0;
  this->GazeDirection[0] = this->GazeDirection[1] = 0.0;
  this->GazeDirection[2] = -1.0;
  this->EyePosition[0] = this->EyePosition[1] = 0.0;
  this->EyePosition[2] = 1.0;
  this->ViewportSize[0] = 1920;
  this->ViewportSize[1] = 1080;
  std::fill(this->FrustumPlanes, this->FrustumPlanes + 24, 0.0);
  this->ProjectionDirection[0] = this->ProjectionDirection[1] = 0.0;
  this->ProjectionDirection[2] = -1.0;
  Identity(this->ObjectToWorldMatrix);
  Identity(this->ObjectToViewMatrix);
  Identity(this->PreviousObjectToViewMatrix);
}

//------------------------------------------------------------------------------
vtkPerceptualLODSelector::~vtkPerceptualLODSelector() = default;

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::ScaleTolerances(double scale)
{
  const plod::SelectionInput defaults;
  this->SetContourTolerance(scale * defaults.ContourTolerance);
  this->SetBrightnessTolerance(scale * defaults.BrightnessTolerance);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::SetFrustumPlanes(const double planes[24])
{
  if (!std::equal(planes, planes + 24, this->FrustumPlanes) || !this->UseFrustum)
  {
    std::copy(planes, planes + 24, this->FrustumPlanes);
    this->UseFrustum = true;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::GetFrustumPlanes(double planes[24])
{
  std::copy(this->FrustumPlanes, this->FrustumPlanes + 24, planes);
}

//------------------------------------------------------------------------------
double vtkPerceptualLODSelector::GetScreenDistance()
{
  return plod::ScreenDistance(this->UsePhysicalDisplay, this->PixelPitch, this->ViewingDistance,
    this->ViewportSize[1], this->ViewAngle);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::SetNumberOfLights(int n)
{
  n = std::max(0, n);
  if (static_cast<int>(this->Internal->Lights.size()) != n)
  {
    this->Internal->Lights.resize(n);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkPerceptualLODSelector::GetNumberOfLights()
{
  return static_cast<int>(this->Internal->Lights.size());
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::SetLight(
  int index, bool positional, double x, double y, double z, double diffuse, double specular)
{
  if (index < 0 || index >= this->GetNumberOfLights())
  {
    vtkErrorMacro(
      "SetLight: index " << index << " outside [0, " << this->GetNumberOfLights() << ").");
    return;
  }
  plod::SelectorLight& l = this->Internal->Lights[index];
  if (l.Positional != positional || l.Position[0] != x || l.Position[1] != y ||
    l.Position[2] != z || l.Diffuse != diffuse || l.Specular != specular)
  {
    l.Positional = positional;
    l.Position[0] = x;
    l.Position[1] = y;
    l.Position[2] = z;
    l.Diffuse = diffuse;
    l.Specular = specular;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::AddLight(
  bool positional, double x, double y, double z, double diffuse, double specular)
{
  this->SetNumberOfLights(this->GetNumberOfLights() + 1);
  this->SetLight(this->GetNumberOfLights() - 1, positional, x, y, z, diffuse, specular);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkPerceptualLODSelector::GetMTime()
{
  // pages read in the background since the last cut: the next one can refine further
  auto* input = this->GetNumberOfInputConnections(0) > 0
    ? vtkMultiscaleOctree::SafeDownCast(this->GetInputDataObject(0, 0))
    : nullptr;
  if (input && input->GetNumberOfBackgroundLoads() != this->Internal->LoadsSeen)
  {
    this->Modified();
  }
  return this->Superclass::GetMTime();
}

//------------------------------------------------------------------------------
int vtkPerceptualLODSelector::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiscaleOctree* input = vtkMultiscaleOctree::GetData(inputVector[0]);
  vtkMultiscaleOctree* output = vtkMultiscaleOctree::GetData(outputVector);
  this->EmptyCutReason.clear();
  plod::OctreeView view;
  vtkMTimeType viewStamp = 0;
  if (!this->TakeOctree(input, view, viewStamp))
  {
    output->Initialize();
    return 1;
  }
  const auto start = std::chrono::steady_clock::now();
  this->Internal->LoadsSeen = input->GetNumberOfBackgroundLoads();
  // the parameters checked before anything is touched: a bad one keeps the previous cut
  plod::SelectionInput in;
  std::string problem = this->CheckParameters();
  if (problem.empty())
  {
    problem = this->MakeSelectionInput(input, view, in);
  }
  if (!problem.empty())
  {
    vtkErrorMacro("Invalid input: " << problem << "; the previous cut is kept.");
    this->Internal->RestoreLastCut(output);
    return 1;
  }
  plod::SelectionStats stats;
  this->Select(input, view, viewStamp, in, stats);
  this->MakeOutput(input, in, output);
  this->ExplainEmptyCut(in, stats);
  // the pages this walk mapped, and the cut arrays, within the reader's CacheLimit
  input->CountHeldBytes(this->Internal->Held);
  input->EnforceResidentLimit();
  this->SelectTime =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  this->RecordFigures(stats);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkPerceptualLODSelector::TakeOctree(
  vtkMultiscaleOctree* input, plod::OctreeView& view, vtkMTimeType& viewStamp)
{
  if (!input || input->GetNumberOfNodes() == 0)
  {
    this->Internal->Reset();
    this->RecordFigures(plod::SelectionStats());
    this->EmptyCutReason = "the octree is empty";
    return false;
  }
  std::string why;
  if (!input->GetCheckedView(view, &viewStamp, &why))
  {
    vtkErrorMacro("The input octree is invalid (" << why << "): empty output.");
    this->Internal->Reset();
    this->EmptyCutReason = "the input octree is invalid";
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
std::string vtkPerceptualLODSelector::CheckParameters()
{
  if (!(this->ViewportSize[0] > 0 && this->ViewportSize[1] > 0))
  {
    // its own message: a zero-size viewport (a hidden or collapsed window) is no camera problem
    return "the viewport size is " + std::to_string(this->ViewportSize[0]) + " x " +
      std::to_string(this->ViewportSize[1]) + " pixels; width and height must be positive";
  }
  if (!this->ParallelProjection && !this->UsePhysicalDisplay &&
    !(this->ViewAngle > 0 && this->ViewAngle < 180))
    return "the view angle must be in (0, 180) degrees";
  if (this->ParallelProjection && !(this->ParallelScale > 0 && std::isfinite(this->ParallelScale)))
    return "the parallel scale must be positive and finite";
  if (this->UsePhysicalDisplay &&
    !(this->PixelPitch > 0 && this->ViewingDistance > 0 && std::isfinite(this->ViewingDistance)))
    return "pixel pitch and viewing distance must be positive and finite";
  if (!Finite(this->ObjectToWorldMatrix, 16) || !Finite(this->ObjectToViewMatrix, 16) ||
    !Finite(this->PreviousObjectToViewMatrix, 16))
    return "a matrix has a NaN or infinite entry";
  if (!std::isfinite(this->PreviousFrameTime) || this->PreviousFrameTime < 0 ||
    !std::isfinite(this->FrameInterval) || this->FrameInterval < 0)
    return "frame times must be finite and non-negative";
  if (!(this->InverseVelocitySpeed > 0) || !(this->DirectVelocitySpeed > 0) ||
    !std::isfinite(this->PSECFactor) || !(this->PSECFactor > 0) ||
    !(this->DistancePixelThreshold > 0))
    return "IPV/DPV speeds, the PSEC factor and the pixel threshold must be positive";
  return std::string();
}

//------------------------------------------------------------------------------
std::string vtkPerceptualLODSelector::MakeSelectionInput(
  vtkMultiscaleOctree* input, const plod::OctreeView& view, plod::SelectionInput& in)
{
  in.Error = static_cast<plod::ErrorModel>(this->ErrorModel);
  in.Motion = static_cast<plod::MotionModel>(this->MotionModel);
  in.Velocity = static_cast<plod::VelocityCriterion>(this->VelocityCriterion);
  in.Foveation = static_cast<plod::FoveationMode>(this->FoveationMode);
  in.HideBackFaces = this->BackFaceMode == BACK_FACES_HIDDEN ||
    (this->BackFaceMode == BACK_FACES_AUTOMATIC && input->GetNumberOfBoundaryEdges() == 0 &&
      input->GetNumberOfMisorientedEdges() == 0);
  this->HidBackFaces = in.HideBackFaces;
  in.ContourTolerance = this->ContourTolerance;
  in.BrightnessTolerance = this->BrightnessTolerance;
  in.TopologyTolerance = this->TopologyTolerance;
  in.MinimumLevel = std::max(this->MinimumLevel, input->GetCoarsestDrawnLevel());
  in.TriangleBudget = this->TriangleBudget;
  in.BudgetStop = static_cast<plod::BudgetStopRule>(this->BudgetStopRule);
  in.ExactBudget = this->ExactTriangleBudget;
  in.Incremental = this->IncrementalSelection;
  in.UseOctreeMaterial = input->GetHasMaterialArrays();
  in.Diffuse = this->DiffuseReflectance;
  in.Specular = this->SpecularReflectance;
  in.SpecularPower = this->SpecularPower;
  in.PSECFactor = this->PSECFactor;
  in.FoveationRate = this->FoveationRate;
  in.FoveationWeights[0] = this->FoveationWeights[0];
  in.FoveationWeights[1] = this->FoveationWeights[1];
  // the view model (plodViewModel.h): camera, lights and motion into octree-local terms
  const plod::FrameViewResult framed =
    plod::MakeFrameView(this->MakeFrame(), view.Origin, view.RootEdge, view.FinestLevel, in);
  if (!framed.Ok)
  {
    return framed.Error;
  }
  this->ObjectSpeed = framed.ObjectSpeed;
  this->DistanceLevel = framed.DistanceLevel;
  std::string why;
  return plod::ValidateSelectionInput(in, &why) ? std::string() : why;
}

//------------------------------------------------------------------------------
plod::FrameView vtkPerceptualLODSelector::MakeFrame()
{
  plod::FrameView frame;
  frame.CoordinatesAreWorld = this->CoordinatesAreWorld;
  std::copy(this->ObjectToWorldMatrix, this->ObjectToWorldMatrix + 16, frame.ObjectToWorld);
  if (this->CoordinatesAreWorld)
  {
    vtkMatrix4x4::Invert(this->ObjectToWorldMatrix, frame.WorldToObject);
  }
  std::copy(this->ObjectToViewMatrix, this->ObjectToViewMatrix + 16, frame.ObjectToView);
  if (this->HasPreviousFrame && this->PreviousFrameTime > 0) // read only with motion
  {
    vtkMatrix4x4::Invert(this->PreviousObjectToViewMatrix, frame.PreviousViewToObject);
  }
  frame.HasPreviousFrame = this->HasPreviousFrame;
  frame.PreviousFrameTime = this->PreviousFrameTime;
  frame.FrameInterval = this->FrameInterval;
  std::copy(this->EyePosition, this->EyePosition + 3, frame.Eye);
  frame.UseFrustum = this->UseFrustum;
  std::copy(this->FrustumPlanes, this->FrustumPlanes + 24, frame.FrustumPlanes);
  frame.Parallel = this->ParallelProjection;
  frame.ParallelScale = this->ParallelScale;
  frame.ViewAngle = this->ViewAngle;
  std::copy(this->ProjectionDirection, this->ProjectionDirection + 3, frame.ProjectionDirection);
  frame.ScreenDistance = this->GetScreenDistance();
  frame.ViewportHeight = this->ViewportSize[1];
  frame.Lights = this->Internal->Lights.data();
  frame.NumberOfLights = this->Internal->Lights.size();
  std::copy(this->FoveationPoint, this->FoveationPoint + 3, frame.FoveationPoint);
  std::copy(this->FoveationUp, this->FoveationUp + 3, frame.FoveationUp);
  std::copy(this->GazeDirection, this->GazeDirection + 3, frame.GazeDirection);
  frame.InverseVelocitySpeed = this->InverseVelocitySpeed;
  frame.DirectVelocitySpeed = this->DirectVelocitySpeed;
  frame.DistancePixelThreshold = this->DistancePixelThreshold;
  return frame;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::Select(vtkMultiscaleOctree* input, const plod::OctreeView& view,
  vtkMTimeType viewStamp, const plod::SelectionInput& in, plod::SelectionStats& stats)
{
  // the kernel and the cut arrays follow the octree
  Internals& I = *this->Internal;
  if (I.ViewStamp != viewStamp || !I.State)
  {
    I.Kernel.SetOctree(view);
    auto cutArray = [&](const char* name) {
      auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
      a->SetName(name);
      a->SetNumberOfTuples(view.NumberOfNodes);
      a->FillValue(0);
      return a;
    };
    I.State = cutArray(vtkMultiscaleOctree::CutStateArrayName());
    I.Reason = cutArray(CutReasonArrayName());
    I.CullMask = cutArray(vtkMultiscaleOctree::CullMaskArrayName());
    // a new count: an octree this selector drew before stops counting these arrays
    I.Held = std::make_shared<std::atomic<uint64_t>>(3 * uint64_t(view.NumberOfNodes));
    I.ViewStamp = viewStamp;
    I.Prepared = nullptr;
  }
  // one memo of corner walks for the exact count and the patch generator, under the stamp the
  // patch generator passes too (the view's, which the output's shallow copy keeps)
  I.Kernel.SetCornerMemo(input->GetCornerMemo(), viewStamp);
  // a mapped file's pages read off the frame, when the reader asked for it
  I.Kernel.SetPageLoader(input->GetPageLoader());
  if (this->MultiThreaded && vtkSMPTools::GetEstimatedNumberOfThreads() > 1)
  {
    I.Kernel.SetParallelFor(plodvtk::SMPRanges());
  }
  else
  {
    I.Kernel.SetParallelFor(nullptr);
  }
  I.Kernel.Select(
    in, I.State->GetPointer(0), I.Reason->GetPointer(0), I.CullMask->GetPointer(0), stats);
  I.State->Modified();
  I.Reason->Modified();
  I.CullMask->Modified();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::MakeOutput(
  vtkMultiscaleOctree* input, const plod::SelectionInput& in, vtkMultiscaleOctree* output)
{
  // the input's arrays with the cut's, made once per input
  Internals& I = *this->Internal;
  if (!I.Prepared || I.Input != input || I.InputTime != input->GetMTime())
  {
    I.Prepared = vtkSmartPointer<vtkMultiscaleOctree>::New();
    I.Prepared->ShallowCopy(input);
    vtkFieldData* nodes = I.Prepared->GetNodeData();
    for (vtkUnsignedCharArray* a : { I.State.Get(), I.Reason.Get(), I.CullMask.Get() })
    {
      nodes->RemoveArray(a->GetName());
      nodes->AddArray(a);
    }
    I.CutView = vtkSmartPointer<vtkDoubleArray>::New();
    I.CutView->SetName(vtkMultiscaleOctree::CutViewArrayName());
    I.CutView->SetNumberOfValues(8);
    if (!I.Prepared->GetFieldData())
    {
      vtkNew<vtkFieldData> fd;
      I.Prepared->SetFieldData(fd);
    }
    I.Prepared->GetFieldData()->RemoveArray(vtkMultiscaleOctree::CutViewArrayName());
    I.Prepared->GetFieldData()->AddArray(I.CutView);
    I.Input = input;
    I.InputTime = input->GetMTime();
  }
  // the view the cut was made for, in octree-local coordinates, for the patch generator's
  // per-triangle back-face culling (only when back faces are hidden)
  double* cutView = I.CutView->GetPointer(0);
  for (int a = 0; a < 3; ++a)
  {
    cutView[a] = in.Eye[a];
    cutView[4 + a] = in.ProjectionDirection[a];
  }
  cutView[3] = in.Parallel ? 1.0 : 0.0;
  cutView[7] = in.HideBackFaces ? 1.0 : 0.0;
  I.CutView->Modified();
  output->ShallowCopy(I.Prepared);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::ExplainEmptyCut(
  const plod::SelectionInput& in, const plod::SelectionStats& stats)
{
  // a cut that draws nothing says why (the root alone is one point: no triangle)
  Internals& I = *this->Internal;
  const uint8_t rootState = I.State->GetValue(0);
  if (stats.Drawn == 0)
  {
    this->EmptyCutReason = stats.InCut > 0 && I.Reason->GetValue(0) == plod::Culled
      ? "the model is outside the view frustum"
      : "no cell is drawn: every cell in the view faces away from the eye (back faces hidden)";
  }
  else if (rootState != plod::NotInCut && I.Reason->GetValue(0) == plod::BudgetLimited)
  {
    this->EmptyCutReason = "the triangle budget is smaller than the triangles refining the root "
                           "would add: the root alone is drawn, which is one point and no triangle";
  }
  else if (rootState != plod::NotInCut && rootState != plod::CutOpen)
  {
    this->EmptyCutReason = in.VelocityFactor == std::numeric_limits<double>::infinity()
      ? "DPV: the object's speed reached DirectVelocitySpeed, so the root alone is drawn, which "
        "is one point and no triangle"
      : "the whole model projects within the tolerances: the root alone is accepted, which is "
        "one point and no triangle (the model covers about a pixel, or the tolerances are huge)";
  }
  if (!this->EmptyCutReason.empty())
  {
    vtkDebugMacro("The cut draws nothing: " << this->EmptyCutReason << ".");
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::RecordFigures(const plod::SelectionStats& stats)
{
  this->NumberOfVisitedNodes = stats.Visited;
  this->NumberOfCutNodes = stats.InCut;
  this->NumberOfDrawnNodes = stats.Drawn;
  this->NumberOfOpenedLeaves = stats.Opened;
  this->NumberOfFoveationFactors = stats.FoveationFactors;
  this->NumberOfTopologyRefinedNodes = stats.TopologyRefined;
  this->NumberOfAwaitingCells = stats.AwaitingPages;
  this->BudgetWasBinding = stats.BudgetBinding;
  this->NumberOfBudgetTriangles = stats.BudgetTriangles;
  this->NumberOfCutTriangles = stats.CutTriangles;
  this->NumberOfWaitingTriangles = stats.BudgetWaitingTriangles;
  this->BudgetKeptToleranceCut = stats.BudgetToleranceCut;
  this->NumberOfCellsJudgedAhead = stats.BudgetJudgedAhead;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODSelector::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  static const char* errors[] = { "SRCC", "SCVC", "PSEC", "Distance", "Cheng" };
  static const char* motions[] = { "None", "MicroMotion", "InverseVelocity", "DirectVelocity" };
  static const char* foveations[] = { "Off", "Object", "Screen" };
  os << indent << "ErrorModel: " << errors[this->ErrorModel] << "\n";
  os << indent << "MotionModel: " << motions[this->MotionModel] << "\n";
  os << indent << "VelocityCriterion: "
     << (this->VelocityCriterion == VELOCITY_ALONE ? "Alone" : "ScalesErrorModel") << "\n";
  os << indent << "FoveationMode: " << foveations[this->FoveationMode] << "\n";
  os << indent << "FoveationRate: " << this->FoveationRate << "\n";
  os << indent << "BackFaceMode: "
     << (this->BackFaceMode == BACK_FACES_AUTOMATIC   ? "Automatic"
            : this->BackFaceMode == BACK_FACES_HIDDEN ? "Hidden"
                                                      : "Drawn")
     << " (last: " << (this->HidBackFaces ? "hidden" : "drawn") << ")\n";
  os << indent << "ContourTolerance: " << this->ContourTolerance << " px\n";
  os << indent << "TopologyTolerance: " << this->TopologyTolerance << " px\n";
  os << indent << "BrightnessTolerance: " << this->BrightnessTolerance << "\n";
  os << indent << "MinimumLevel: " << this->MinimumLevel << "\n";
  os << indent << "IncrementalSelection: " << (this->IncrementalSelection ? "on" : "off") << "\n";
  os << indent << "TriangleBudget: " << this->TriangleBudget
     << (this->TriangleBudget > 0 ? "" : " (off)") << ", stop rule "
     << (this->BudgetStopRule == BUDGET_STOP_AT_FIRST_MISFIT ? "StopAtFirstMisfit" : "SkipMisfits")
     << (this->ExactTriangleBudget ? ", exact" : ", estimated back faces") << "\n";
  os << indent << "EyePosition: (" << this->EyePosition[0] << ", " << this->EyePosition[1] << ", "
     << this->EyePosition[2] << ")\n";
  os << indent << "ViewAngle: " << this->ViewAngle << " deg\n";
  os << indent << "ViewportSize: " << this->ViewportSize[0] << " x " << this->ViewportSize[1]
     << "\n";
  os << indent << "UseFrustum: " << (this->UseFrustum ? "On" : "Off") << "\n";
  os << indent << "ParallelProjection: " << (this->ParallelProjection ? "On" : "Off") << ", scale "
     << this->ParallelScale << "\n";
  os << indent << "UsePhysicalDisplay: " << (this->UsePhysicalDisplay ? "On" : "Off")
     << ", pixel pitch " << this->PixelPitch << ", viewing distance " << this->ViewingDistance
     << "\n";
  os << indent << "CoordinatesAreWorld: " << (this->CoordinatesAreWorld ? "On" : "Off") << "\n";
  os << indent << "NumberOfLights: " << this->Internal->Lights.size() << "\n";
  os << indent << "Material: diffuse " << this->DiffuseReflectance << ", specular "
     << this->SpecularReflectance << ", power " << this->SpecularPower << "\n";
  os << indent << "HasPreviousFrame: " << (this->HasPreviousFrame ? "On" : "Off")
     << ", previous frame time " << this->PreviousFrameTime << " s, frame interval "
     << this->FrameInterval << " s\n";
  os << indent << "InverseVelocitySpeed: " << this->InverseVelocitySpeed << "\n";
  os << indent << "DirectVelocitySpeed: " << this->DirectVelocitySpeed << "\n";
  os << indent << "PSECFactor: " << this->PSECFactor << "\n";
  os << indent << "DistancePixelThreshold: " << this->DistancePixelThreshold << "\n";
  os << indent << "Last: " << this->NumberOfVisitedNodes << " visited, " << this->NumberOfCutNodes
     << " in the cut, " << this->NumberOfDrawnNodes << " drawn, " << this->SelectTime * 1e3
     << " ms, object speed " << this->ObjectSpeed << " px, distance level " << this->DistanceLevel
     << ", " << this->NumberOfBudgetTriangles << " triangles counted of "
     << this->NumberOfCutTriangles << " in the cut, " << this->NumberOfFoveationFactors
     << " foveation factors computed" << (this->BudgetWasBinding ? " (the budget was binding)" : "")
     << ", " << this->NumberOfWaitingTriangles << " waiting"
     << (this->BudgetKeptToleranceCut ? ", the tolerance cut kept" : "") << ", "
     << this->NumberOfCellsJudgedAhead << " judged ahead\n";
}
