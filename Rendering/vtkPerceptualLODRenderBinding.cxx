// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPerceptualLODRenderBinding.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkProp3D.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"

#include "plodBudgetController.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkPerceptualLODRenderBinding);

class vtkPerceptualLODRenderBinding::vtkInternals
{
public:
  plod::BudgetController Controller;
  unsigned long DeleteTag = 0; // the window's DeleteEvent observer
  /// The renderer's lights as the selector takes them, kept between frames (no allocation).
  struct Light
  {
    bool Positional;
    double X[3];
    double Diffuse, Specular;
  };
  std::vector<Light> Lights;
};

namespace
{
double Luminance(const double c[3])
{
  return vtkPerceptualLODSelector::Luminance(c[0], c[1], c[2]);
}

void Apply(vtkMatrix4x4* m, const double in[3], double out[3])
{
  const double p[4] = { in[0], in[1], in[2], 1.0 };
  double r[4];
  m->MultiplyPoint(p, r);
  for (int a = 0; a < 3; ++a)
  {
    out[a] = r[3] != 0 ? r[a] / r[3] : r[a];
  }
}
}

//------------------------------------------------------------------------------
vtkPerceptualLODRenderBinding::vtkPerceptualLODRenderBinding()
  : Renderer(nullptr)
  , Selector(nullptr)
  , Prop3D(nullptr)
  , Enabled(true)
  , Observer(vtkCallbackCommand::New())
  , ObserverTag(0)
  , HasPrevious(false)
  , PreviousStart(0)
  , NumberOfUpdates(0)
  , MeasuredFrameTime(0)
  , LastUpdateTime(0)
{
  this->Observer->SetCallback(&vtkPerceptualLODRenderBinding::OnStart);
  this->Observer->SetClientData(this); // a raw pointer: no reference cycle
  std::fill(this->PreviousObjectToView, this->PreviousObjectToView + 16, 0.0);
  this->WindowObserver = vtkCallbackCommand::New();
  this->WindowObserver->SetCallback(&vtkPerceptualLODRenderBinding::OnWindowEnd);
  this->WindowObserver->SetClientData(this);
  this->Internals = new vtkInternals;
  this->MinimumTriangleBudget = 1000;
  this->MaximumTriangleBudget = VTK_ID_MAX;
}

//------------------------------------------------------------------------------
vtkPerceptualLODRenderBinding::~vtkPerceptualLODRenderBinding()
{
  this->RemoveObserver();
  this->Observer->Delete();
  if (this->Window)
  {
    this->Window->RemoveObserver(this->WindowTag);
    this->Window->RemoveObserver(this->Internals->DeleteTag);
  }
  this->WindowObserver->Delete();
  delete this->Internals;
  if (this->Renderer)
    this->Renderer->UnRegister(this);
  if (this->Selector)
    this->Selector->UnRegister(this);
  if (this->Prop3D)
    this->Prop3D->UnRegister(this);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::AddObserver()
{
  if (this->Renderer && this->Enabled && !this->ObserverTag)
  {
    this->ObserverTag = this->Renderer->AddObserver(vtkCommand::StartEvent, this->Observer);
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::RemoveObserver()
{
  if (this->Renderer && this->ObserverTag)
  {
    this->Renderer->RemoveObserver(this->ObserverTag);
  }
  this->ObserverTag = 0;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetRenderer(vtkRenderer* renderer)
{
  if (renderer == this->Renderer)
  {
    return;
  }
  this->RemoveObserver();
  if (this->Renderer)
    this->Renderer->UnRegister(this);
  this->Renderer = renderer;
  if (this->Renderer)
    this->Renderer->Register(this);
  this->HasPrevious = false;
  this->AddObserver();
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetSelector(vtkPerceptualLODSelector* selector)
{
  if (selector == this->Selector)
  {
    return;
  }
  if (this->Selector)
    this->Selector->UnRegister(this);
  this->Selector = selector;
  if (this->Selector)
    this->Selector->Register(this);
  this->HasPrevious = false;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetProp3D(vtkProp3D* prop)
{
  if (prop == this->Prop3D)
  {
    return;
  }
  if (this->Prop3D)
    this->Prop3D->UnRegister(this);
  this->Prop3D = prop;
  if (this->Prop3D)
    this->Prop3D->Register(this);
  this->HasPrevious = false;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetEnabled(bool enabled)
{
  if (enabled == this->Enabled)
  {
    return;
  }
  this->Enabled = enabled;
  if (enabled)
    this->AddObserver();
  else
    this->RemoveObserver();
  this->HasPrevious = false;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::OnStart(vtkObject*, unsigned long, void* client, void*)
{
  static_cast<vtkPerceptualLODRenderBinding*>(client)->Update();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::OnWindowEnd(
  vtkObject* caller, unsigned long event, void* client, void*)
{
  auto* self = static_cast<vtkPerceptualLODRenderBinding*>(client);
  if (event == vtkCommand::DeleteEvent)
  {
    // the window goes first: forget it (its observers go with it)
    if (caller == self->Window)
    {
      self->Window = nullptr;
      self->WindowTag = 0;
      self->Internals->DeleteTag = 0;
    }
    return;
  }
  if (self->FrameStarted)
  {
    self->LastFrameCost = self->Now() - self->PreviousStart;
    self->FrameCostPending = true;
    self->FrameStarted = false;
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::WatchWindow(vtkRenderWindow* window)
{
  if (window == this->Window)
  {
    return;
  }
  if (this->Window)
  {
    this->Window->RemoveObserver(this->WindowTag);
    this->Window->RemoveObserver(this->Internals->DeleteTag);
  }
  this->Window = window;
  this->WindowTag = 0;
  this->Internals->DeleteTag = 0;
  if (window)
  {
    this->WindowTag = window->AddObserver(vtkCommand::EndEvent, this->WindowObserver);
    this->Internals->DeleteTag = window->AddObserver(vtkCommand::DeleteEvent, this->WindowObserver);
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetTargetFrameTime(double seconds)
{
  if (!std::isfinite(seconds) || seconds < 0)
  {
    vtkErrorMacro("The target frame time must be a finite number of seconds, 0 for off; got "
      << seconds << ": the target stays " << (this->TargetFrameTime > 0 ? "as it was" : "off"));
    return;
  }
  if (seconds != this->TargetFrameTime)
  {
    this->TargetFrameTime = seconds;
    this->Internals->Controller.Reset();
    if (!(seconds > 0))
    {
      this->WatchWindow(nullptr); // no frame to time: no observer on the window's every render
      this->FrameStarted = false;
    }
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetClock(std::function<double()> clock)
{
  this->Clock = std::move(clock);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SetSimulatedTime(double seconds)
{
  auto time = std::make_shared<double>(seconds);
  this->Clock = [time]() { return *time; };
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::UseWallClock()
{
  this->Clock = nullptr;
}

//------------------------------------------------------------------------------
double vtkPerceptualLODRenderBinding::Now() const
{
  return this->Clock ? this->Clock() : vtkTimerLog::GetUniversalTime();
}

//------------------------------------------------------------------------------
double vtkPerceptualLODRenderBinding::TakeFrameCost()
{
  const double cost = this->FrameCostPending ? this->LastFrameCost : 0.0;
  this->FrameCostPending = false;
  return cost;
}

//------------------------------------------------------------------------------
vtkIdType vtkPerceptualLODRenderBinding::StepBudget(double seconds, vtkIdType drawn, bool binding)
{
  if (!(this->TargetFrameTime > 0))
  {
    this->TargetBudget = 0;
    return 0;
  }
  if (!(seconds > 0) && this->TargetBudget > 0)
  {
    return this->TargetBudget; // nothing new measured: the budget stays
  }
  plod::FrameTimeTarget target;
  target.Target = this->TargetFrameTime;
  target.MinimumBudget = this->MinimumTriangleBudget;
  target.MaximumBudget = std::max(this->MinimumTriangleBudget, this->MaximumTriangleBudget);
  this->TargetBudget = this->Internals->Controller.Update(
    target, seconds > 0 ? seconds : 0.0, std::max<vtkIdType>(drawn, 0), binding);
  return this->TargetBudget;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::SteerBudget()
{
  vtkPerceptualLODSelector* sel = this->Selector;
  if (!(this->TargetFrameTime > 0))
  {
    if (this->TargetBudget > 0)
    {
      sel->SetTriangleBudget(0); // the target was turned off: no budget
      this->TargetBudget = 0;
    }
    return;
  }
  if (!this->FrameCostPending && this->TargetBudget > 0)
  {
    return; // no new measurement (the first frame, or a frame that did not finish)
  }
  const vtkIdType budget = this->StepBudget(
    this->TakeFrameCost(), sel->GetNumberOfBudgetTriangles(), sel->GetBudgetWasBinding());
  // Modified() only on a change: a settled budget re-executes nothing
  sel->SetTriangleBudget(budget);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::Update()
{
  if (this->Enabled)
  {
    this->UpdateFrom(this->Renderer, this->Prop3D);
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::UpdateFrom(vtkRenderer* ren, vtkProp3D* prop)
{
  vtkPerceptualLODSelector* sel = this->Selector;
  if (!ren || !sel)
  {
    return;
  }
  const double start = this->Now();
  double objectToWorld[16];
  if (prop)
  {
    vtkMatrix4x4::DeepCopy(objectToWorld, prop->GetMatrix());
  }
  else
  {
    vtkMatrix4x4::Identity(objectToWorld);
  }
  this->PushView(ren, objectToWorld);
  this->PushLights(ren);
  if (vtkActor* actor = vtkActor::SafeDownCast(prop))
  {
    this->PushMaterial(actor->GetProperty());
  }
  this->PushMotion(ren->GetActiveCamera(), objectToWorld, start);
  // the frame-time target
  if (!this->ExternalSteering)
  {
    this->SteerBudget();
  }
  if (this->TargetFrameTime > 0)
  {
    this->WatchWindow(ren->GetRenderWindow()); // the frame ends there (PreviousStart: its start)
    this->FrameStarted = true;
  }
  ++this->NumberOfUpdates;
  this->LastUpdateTime = this->Now() - start;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::PushView(vtkRenderer* ren, const double objectToWorld[16])
{
  // in world coordinates, with the prop's matrix as object -> world
  vtkPerceptualLODSelector* sel = this->Selector;
  vtkCamera* camera = ren->GetActiveCamera();
  sel->CoordinatesAreWorldOn();
  sel->SetObjectToWorldMatrix(objectToWorld);
  int width = 0, height = 0, x0 = 0, y0 = 0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  if (width > 0 && height > 0)
  {
    sel->SetViewportSize(width, height);
  }
  const double aspect = height > 0 ? double(width) / double(height) : 1.0;
  double planes[24];
  camera->GetFrustumPlanes(aspect, planes);
  sel->SetFrustumPlanes(planes);
  sel->SetEyePosition(camera->GetPosition());
  sel->SetViewAngle(camera->GetViewAngle());
  sel->SetParallelProjection(camera->GetParallelProjection() != 0);
  sel->SetParallelScale(camera->GetParallelScale());
  sel->SetProjectionDirection(camera->GetDirectionOfProjection());
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::PushLights(vtkRenderer* ren)
{
  vtkPerceptualLODSelector* sel = this->Selector;
  vtkCamera* camera = ren->GetActiveCamera();
  using L = vtkInternals::Light;
  std::vector<L>& lights = this->Internals->Lights;
  lights.clear();
  vtkLightCollection* collection = ren->GetLights();
  if (collection->GetNumberOfItems() == 0 && ren->GetAutomaticLightCreation())
  {
    // the renderer is about to create a white headlight of intensity 1
    double d[3];
    for (int a = 0; a < 3; ++a)
      d[a] = camera->GetPosition()[a] - camera->GetFocalPoint()[a];
    lights.push_back({ false, { d[0], d[1], d[2] }, 1.0, 1.0 });
  }
  vtkCollectionSimpleIterator it;
  collection->InitTraversal(it);
  while (vtkLight* light = collection->GetNextLight(it))
  {
    if (!light->GetSwitch() || light->GetIntensity() <= 0)
    {
      continue;
    }
    double position[3], focal[3];
    if (light->LightTypeIsHeadlight())
    {
      camera->GetPosition(position);
      camera->GetFocalPoint(focal);
    }
    else if (light->LightTypeIsCameraLight())
    {
      vtkMatrix4x4* m = camera->GetCameraLightTransformMatrix();
      Apply(m, light->GetPosition(), position);
      Apply(m, light->GetFocalPoint(), focal);
    }
    else
    {
      light->GetTransformedPosition(position);
      light->GetTransformedFocalPoint(focal);
    }
    L l;
    l.Positional = light->GetPositional() != 0;
    for (int a = 0; a < 3; ++a)
      l.X[a] = l.Positional ? position[a] : position[a] - focal[a];
    l.Diffuse = light->GetIntensity() * Luminance(light->GetDiffuseColor());
    l.Specular = light->GetIntensity() * Luminance(light->GetSpecularColor());
    lights.push_back(l);
  }
  sel->SetNumberOfLights(static_cast<int>(lights.size()));
  for (size_t i = 0; i < lights.size(); ++i)
  {
    const L& l = lights[i];
    sel->SetLight(static_cast<int>(i), l.Positional, l.X[0], l.X[1], l.X[2], l.Diffuse, l.Specular);
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::PushMaterial(vtkProperty* p)
{
  vtkPerceptualLODSelector* sel = this->Selector;
  sel->SetDiffuseReflectance(p->GetDiffuse() * Luminance(p->GetDiffuseColor()));
  sel->SetSpecularReflectance(p->GetSpecular() * Luminance(p->GetSpecularColor()));
  sel->SetSpecularPower(p->GetSpecularPower());
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::PushMotion(
  vtkCamera* camera, const double objectToWorld[16], double start)
{
  vtkPerceptualLODSelector* sel = this->Selector;
  // Pushed only when the selector's motion model uses it, so that a camera coming to rest does
  // not re-execute a selector that ignores motion.
  double view[16], objectToView[16];
  vtkMatrix4x4::DeepCopy(view, camera->GetViewTransformMatrix());
  vtkMatrix4x4::Multiply4x4(view, objectToWorld, objectToView);
  const bool motion = sel->GetMotionModel() != vtkPerceptualLODSelector::MOTION_NONE;
  if (this->HasPrevious)
  {
    this->MeasuredFrameTime = start - this->PreviousStart;
  }
  if (motion)
  {
    sel->SetObjectToViewMatrix(objectToView);
    if (!this->HasPrevious)
    {
      // first frame: the previous frame is this one (no motion), so that the second frame of
      // a still scene changes nothing
      sel->SetPreviousObjectToViewMatrix(objectToView);
      sel->HasPreviousFrameOn();
    }
    else
    {
      const bool moved = !std::equal(objectToView, objectToView + 16, this->PreviousObjectToView);
      sel->SetPreviousObjectToViewMatrix(this->PreviousObjectToView);
      sel->HasPreviousFrameOn();
      if (moved)
      {
        // only a moving scene needs the frame time; a still one keeps the old value, so that
        // nothing changes and nothing re-executes
        sel->SetPreviousFrameTime(this->MeasuredFrameTime);
      }
    }
  }
  std::copy(objectToView, objectToView + 16, this->PreviousObjectToView);
  this->PreviousStart = start;
  this->HasPrevious = true;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRenderBinding::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Renderer: " << this->Renderer << "\n";
  os << indent << "Selector: " << this->Selector << "\n";
  os << indent << "Prop3D: " << this->Prop3D << "\n";
  os << indent << "Enabled: " << (this->Enabled ? "On" : "Off") << "\n";
  os << indent << "NumberOfUpdates: " << this->NumberOfUpdates << "\n";
  os << indent << "MeasuredFrameTime: " << this->MeasuredFrameTime << " s\n";
  os << indent << "LastUpdateTime: " << this->LastUpdateTime << " s\n";
  os << indent << "TargetFrameTime: " << this->TargetFrameTime << " s\n";
  os << indent << "MinimumTriangleBudget: " << this->MinimumTriangleBudget << "\n";
  os << indent << "MaximumTriangleBudget: " << this->MaximumTriangleBudget << "\n";
  os << indent << "LastFrameCost: " << this->LastFrameCost << " s\n";
  os << indent << "TargetBudget: " << this->TargetBudget << "\n";
  os << indent << "ExternalSteering: " << (this->ExternalSteering ? "On" : "Off") << "\n";
}
