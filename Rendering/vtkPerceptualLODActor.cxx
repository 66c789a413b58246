// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPerceptualLODActor.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCallbackCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkObjectFactory.h"
#include "vtkPerceptualLODMapper.h"
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkTrivialProducer.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkPerceptualLODActor);

//------------------------------------------------------------------------------
vtkPerceptualLODActor::vtkPerceptualLODActor()
{
  this->Builder = vtkMultiscaleOctreeBuilder::New();
  this->Selector = vtkPerceptualLODSelector::New();
  this->Patches = vtkMultiscalePatchGenerator::New();
  this->LODMapper = vtkPolyDataMapper::New();
  this->Selector->SetInputConnection(this->Builder->GetOutputPort());
  this->Patches->SetInputConnection(this->Selector->GetOutputPort());
  this->LODMapper->SetInputConnection(this->Patches->GetOutputPort());
  this->GPUMapper = vtkPerceptualLODMapper::New();
  this->GPUMapper->SetOctreeConnection(this->Selector->GetOutputPort());
  this->Superclass::SetMapper(this->GPUMapper); // DRAW_PATH_AUTOMATIC decides per render
  this->Device = vtkActor::New();
  this->DeviceMatrix = vtkMatrix4x4::New();
  this->OnRendererDeleted = vtkCallbackCommand::New();
  this->OnRendererDeleted->SetCallback(&vtkPerceptualLODActor::RendererDeleted);
  this->OnRendererDeleted->SetClientData(this);
  this->OnRefreshTimer = vtkCallbackCommand::New();
  this->OnRefreshTimer->SetCallback(&vtkPerceptualLODActor::RefreshTimerFired);
  this->OnRefreshTimer->SetClientData(this);
  vtkMath::UninitializeBounds(this->ModelBounds);
}

//------------------------------------------------------------------------------
vtkPerceptualLODActor::~vtkPerceptualLODActor()
{
  // every renderer still here is alive: a deleted one has taken its entry away
  for (auto& entry : this->Bindings)
  {
    entry.second.Renderer->RemoveObserver(entry.second.DeleteObserver);
    entry.second.Binding->Delete();
  }
  this->Bindings.clear();
  this->OnRendererDeleted->Delete();
  if (this->RefreshInteractor)
  {
    if (this->RefreshTimer >= 0)
    {
      this->RefreshInteractor->DestroyTimer(this->RefreshTimer);
    }
    this->RefreshInteractor->RemoveObserver(this->OnRefreshTimer);
  }
  this->OnRefreshTimer->Delete();
  this->Superclass::SetMapper(nullptr);
  this->Device->Delete();
  this->DeviceMatrix->Delete();
  this->LODMapper->Delete();
  this->GPUMapper->Delete();
  this->Patches->Delete();
  this->Selector->Delete();
  this->Builder->Delete();
  if (this->Producer)
  {
    this->Producer->Delete();
  }
}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeBuilder* vtkPerceptualLODActor::GetBuilder()
{
  return this->Builder;
}

vtkPerceptualLODSelector* vtkPerceptualLODActor::GetSelector()
{
  return this->Selector;
}

vtkMultiscalePatchGenerator* vtkPerceptualLODActor::GetPatchGenerator()
{
  return this->Patches;
}

bool vtkPerceptualLODActor::GetInputIsOctree()
{
  return this->InputIsOctree;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::SetMapper(vtkMapper* mapper)
{
  if (mapper != this->LODMapper && mapper != this->GPUMapper)
  {
    vtkWarningMacro("SetMapper is ignored: vtkPerceptualLODActor draws through its own mapper "
                    "(set its input with SetInputConnection or SetInputData).");
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::SetDrawPath(int path)
{
  path = std::min(std::max(path, int(DRAW_PATH_CPU)), int(DRAW_PATH_AUTOMATIC));
  if (path != this->DrawPath)
  {
    this->DrawPath = path;
    this->Superclass::SetMapper(path == DRAW_PATH_CPU ? static_cast<vtkMapper*>(this->LODMapper)
                                                      : static_cast<vtkMapper*>(this->GPUMapper));
    this->WarnedFallback = false;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::SetInputData(vtkDataObject* input)
{
  if (!input)
  {
    this->Connect(nullptr);
    return;
  }
  if (!this->Producer)
  {
    this->Producer = vtkTrivialProducer::New();
  }
  this->Producer->SetOutput(input);
  this->Connect(this->Producer->GetOutputPort());
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::SetInputConnection(vtkAlgorithmOutput* input)
{
  this->Connect(input);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::Connect(vtkAlgorithmOutput* input)
{
  bool octree = false;
  if (input && input->GetProducer())
  {
    vtkAlgorithm* producer = input->GetProducer();
    producer->UpdateDataObject();
    octree = vtkMultiscaleOctree::SafeDownCast(producer->GetOutputDataObject(input->GetIndex())) !=
      nullptr;
  }
  this->InputIsOctree = octree;
  if (octree)
  {
    this->Builder->SetInputConnection(nullptr);
    this->Selector->SetInputConnection(input);
  }
  else
  {
    this->Builder->SetInputConnection(input);
    this->Selector->SetInputConnection(this->Builder->GetOutputPort());
  }
  this->ModelBoundsTime = 0;
  this->Modified();
}

//------------------------------------------------------------------------------
double* vtkPerceptualLODActor::GetBounds()
{
  vtkMath::UninitializeBounds(this->Bounds);
  vtkAlgorithmOutput* source = this->Selector->GetInputConnection(0, 0);
  if (!source || !source->GetProducer())
  {
    return this->Bounds;
  }
  source->GetProducer()->Update(source->GetIndex());
  vtkMultiscaleOctree* octree = vtkMultiscaleOctree::SafeDownCast(
    source->GetProducer()->GetOutputDataObject(source->GetIndex()));
  if (!octree || octree->GetNumberOfNodes() == 0)
  {
    return this->Bounds;
  }
  // the surface's bounds, once per octree modification
  if (octree->GetMTime() > this->ModelBoundsTime)
  {
    vtkDataArray* points =
      octree->GetSurfaceData()->GetArray(vtkMultiscaleOctree::PointsArrayName());
    const double* origin = octree->GetOrigin();
    if (points && points->GetNumberOfTuples() > 0 && points->GetNumberOfComponents() == 3)
    {
      for (int a = 0; a < 3; ++a)
      {
        double range[2];
        points->GetRange(range, a);
        this->ModelBounds[2 * a] = origin[a] + range[0];
        this->ModelBounds[2 * a + 1] = origin[a] + range[1];
      }
    }
    else
    {
      // no surface points (cannot happen for a consistent non-empty octree): the root cube
      for (int a = 0; a < 3; ++a)
      {
        this->ModelBounds[2 * a] = origin[a];
        this->ModelBounds[2 * a + 1] = origin[a] + octree->GetRootEdge();
      }
    }
    this->ModelBoundsTime = octree->GetMTime();
  }
  // through the actor's matrix: the box of the eight transformed corners
  vtkMatrix4x4* m = this->GetMatrix();
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (int k = 0; k < 8; ++k)
  {
    const double p[4] = { this->ModelBounds[(k & 1) ? 1 : 0], this->ModelBounds[(k & 2) ? 3 : 2],
      this->ModelBounds[(k & 4) ? 5 : 4], 1.0 };
    double q[4];
    m->MultiplyPoint(p, q);
    for (int a = 0; a < 3; ++a)
    {
      const double x = q[3] != 0 ? q[a] / q[3] : q[a];
      lo[a] = std::min(lo[a], x);
      hi[a] = std::max(hi[a], x);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    this->Bounds[2 * a] = lo[a];
    this->Bounds[2 * a + 1] = hi[a];
  }
  return this->Bounds;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::Feed(vtkViewport* viewport)
{
  vtkRenderer* renderer = vtkRenderer::SafeDownCast(viewport);
  if (!renderer)
  {
    return;
  }
  vtkPerceptualLODRenderBinding* binding = this->MakeBinding(renderer);
  binding->SetTargetFrameTime(this->TargetFrameTime);
  binding->UpdateFrom(renderer, this);
}

//------------------------------------------------------------------------------
vtkPerceptualLODRenderBinding* vtkPerceptualLODActor::MakeBinding(vtkRenderer* renderer)
{
  if (!renderer)
  {
    return nullptr;
  }
  RendererBinding& entry = this->Bindings[renderer];
  if (!entry.Binding)
  {
    entry.Binding = vtkPerceptualLODRenderBinding::New();
    entry.Binding->EnabledOff(); // no observer: the actor pushes while it renders
    entry.Binding->SetSelector(this->Selector);
    entry.Binding->SetClock(this->Clock);
    // the binding goes with the renderer: no stale entry, none found again by a new renderer
    // at the same address
    entry.Renderer = renderer;
    entry.DeleteObserver = renderer->AddObserver(vtkCommand::DeleteEvent, this->OnRendererDeleted);
  }
  return entry.Binding;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::RendererDeleted(vtkObject* caller, unsigned long, void* client, void*)
{
  auto* self = static_cast<vtkPerceptualLODActor*>(client);
  // the renderer is whole while its DeleteEvent runs (before its destructor)
  auto it = self->Bindings.find(vtkRenderer::SafeDownCast(caller));
  if (it != self->Bindings.end())
  {
    it->second.Binding->Delete();
    self->Bindings.erase(it);
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::SetClock(std::function<double()> clock)
{
  this->Clock = std::move(clock);
  for (auto& entry : this->Bindings)
  {
    entry.second.Binding->SetClock(this->Clock);
  }
}

//------------------------------------------------------------------------------
int vtkPerceptualLODActor::GetNumberOfBindings()
{
  return static_cast<int>(this->Bindings.size());
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::SetTargetFrameTime(double seconds)
{
  if (!std::isfinite(seconds) || seconds < 0)
  {
    vtkErrorMacro(
      "The target frame time must be a finite number of seconds, 0 for off; got " << seconds);
    return;
  }
  if (seconds != this->TargetFrameTime)
  {
    this->TargetFrameTime = seconds;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkPerceptualLODRenderBinding* vtkPerceptualLODActor::GetBinding(vtkRenderer* renderer)
{
  auto it = this->Bindings.find(renderer);
  return it == this->Bindings.end() ? nullptr : it->second.Binding;
}

//------------------------------------------------------------------------------
int vtkPerceptualLODActor::RenderOpaqueGeometry(vtkViewport* viewport)
{
  this->Feed(viewport);
  return this->Superclass::RenderOpaqueGeometry(viewport);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::Render(vtkRenderer* renderer, vtkMapper* mapper)
{
  this->Device->SetProperty(this->GetProperty());
  if (this->BackfaceProperty)
  {
    this->Device->SetBackfaceProperty(this->BackfaceProperty);
  }
  this->Device->SetTexture(this->GetTexture());
  this->GetMatrix(this->DeviceMatrix);
  this->Device->SetUserMatrix(this->DeviceMatrix);
  this->Device->SetForceOpaque(this->GetForceOpaque());
  this->Device->SetForceTranslucent(this->GetForceTranslucent());
  mapper = this->ChooseMapper(renderer, mapper);
  this->DrewOnGPU = mapper == this->GPUMapper;
  this->Device->Render(renderer, mapper);
  this->EstimatedRenderTime = mapper->GetTimeToDraw();
  this->RenderAgainWhileLoading(renderer);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::RenderAgainWhileLoading(vtkRenderer* renderer)
{
  auto* octree = this->Selector->GetNumberOfInputConnections(0) > 0
    ? vtkMultiscaleOctree::SafeDownCast(this->Selector->GetInputDataObject(0, 0))
    : nullptr;
  if (!octree || !octree->GetBackgroundLoading())
  {
    return;
  }
  // loads waiting, or read since this render's cut was selected (the selector's next cut
  // refines)
  const vtkIdType loads = octree->GetNumberOfBackgroundLoads();
  const bool refine = octree->GetNumberOfWaitingLoads() > 0 || loads != this->LoadsRendered;
  this->LoadsRendered = loads;
  vtkRenderWindow* window = renderer->GetRenderWindow();
  vtkRenderWindowInteractor* interactor = window ? window->GetInteractor() : nullptr;
  if (!refine || !interactor || this->RefreshTimer >= 0)
  {
    return;
  }
  if (this->RefreshInteractor != interactor)
  {
    if (this->RefreshInteractor)
    {
      this->RefreshInteractor->RemoveObserver(this->OnRefreshTimer);
    }
    this->RefreshInteractor = interactor;
    interactor->AddObserver(vtkCommand::TimerEvent, this->OnRefreshTimer);
  }
  this->RefreshWindow = window;
  const int timer =
    interactor->CreateOneShotTimer(static_cast<unsigned long>(this->RefreshInterval));
  this->RefreshTimer = timer > 0 ? timer : -1; // (0: the interactor has no timers)
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::RefreshTimerFired(vtkObject*, unsigned long, void* client, void* data)
{
  auto* self = static_cast<vtkPerceptualLODActor*>(client);
  if (!data || self->RefreshTimer < 0 || *static_cast<int*>(data) != self->RefreshTimer)
  {
    return;
  }
  self->RefreshTimer = -1;
  if (self->RefreshWindow)
  {
    self->RefreshWindow->Render();
  }
}

//------------------------------------------------------------------------------
vtkMapper* vtkPerceptualLODActor::ChooseMapper(vtkRenderer* renderer, vtkMapper* mapper)
{
  if (mapper != this->GPUMapper)
  {
    return mapper;
  }
  vtkRenderWindow* window = renderer->GetRenderWindow();
  if (!this->GPUMapper->IsSupported(window))
  {
    if (this->DrawPath == DRAW_PATH_GPU && !this->WarnedFallback)
    {
      this->WarnedFallback = true;
      vtkWarningMacro(<< "The GPU draw path needs " << this->GPUMapper->GetUnsupportedReason()
                      << ", which this OpenGL context lacks: drawing through the CPU path.");
    }
    return this->LODMapper;
  }
  if (this->DrawPath == DRAW_PATH_AUTOMATIC && this->GPUMapper->IsSoftwareRenderer(window))
  {
    return this->LODMapper;
  }
  // the GPU path follows the patch generator's fold rule
  this->GPUMapper->SetFoldHandling(this->Patches->GetFoldHandling());
  return this->GPUMapper;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Device->ReleaseGraphicsResources(window);
  this->LODMapper->ReleaseGraphicsResources(window);
  this->GPUMapper->ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODActor::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "InputIsOctree: " << this->InputIsOctree << "\n";
  os << indent << "Renderers fed: " << this->Bindings.size() << "\n";
  os << indent << "TargetFrameTime: " << this->TargetFrameTime << " s\n";
  const char* paths[] = { "CPU", "GPU", "automatic" };
  os << indent << "DrawPath: " << paths[this->DrawPath] << "\n";
  os << indent << "Selector:\n";
  this->Selector->PrintSelf(os, indent.GetNextIndent());
}
