// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODRenderBinding
 * @brief   feeds a vtkPerceptualLODSelector from a vtkRenderer on every render
 *
 * The only PerceptualLOD class that reads a renderer. It observes the renderer's StartEvent,
 * which fires before the props render, and pushes to the selector, so that the pipeline
 * builder -> selector -> patch generator -> mapper adapts itself in the same frame:
 * - the view: camera position and frustum planes in world coordinates with the prop's matrix
 *   (user transform included) as the selector's object-to-world matrix; view angle, or
 *   parallel projection with its scale and direction; the renderer's size in pixels (its tile
 *   of a tiled display, its part of a multi-viewport window);
 * - every light that is switched on: scene lights (their transform matrix applied),
 *   headlights (at the camera, towards its focal point), camera lights (placed by the camera's
 *   light transform) and light kits (made of those). Positional lights and spotlights are
 *   positional; the others directional. Diffuse and specular intensities are the light's
 *   intensity times the luminance of its colours. When the renderer has no light yet and
 *   creates lights automatically, the headlight it is about to create is assumed;
 * - the prop's material (for octrees without material arrays): diffuse and specular
 *   coefficients times the luminance of their colours, and the specular power;
 * - motion: the object->view matrix (view transform times prop matrix) of this frame and of
 *   the previous one, and the measured time between the previous frame's start and this one's.
 *   The measured time is only pushed when the object->view matrix moved, so a still scene
 *   changes nothing and nothing re-executes. Motion is pushed only when the selector's motion
 *   model is not None.
 *
 * - the **frame-time target** (off by default): with SetTargetFrameTime(seconds), the binding
 *   measures what each frame costs, from this push to the end of the render window's frame
 *   (selection, patches, rendering and the buffer swap, where a software renderer finishes
 *   drawing), and steers the selector's triangle budget (vtkPerceptualLODSelector::
 *   SetTriangleBudget) so that frames take about that long: plod::BudgetController's law
 *   (plodBudgetController.h: median of three frames, a 5 % dead band, a damped step of at most
 *   1.25x per frame, scaled from what was drawn when the tolerances drew less). The
 *   tolerances stay a floor, so a view that needs fewer triangles than the target allows is
 *   drawn as without a budget, and motion models keep lowering detail during motion. Turning
 *   the target off sets the budget back to 0 (off). A budget you set yourself is left alone
 *   while the target is off.
 * - **steering by the owner** (ExternalSteering, off by default): for processes that draw one
 *   image together (vtkPerceptualLODRepresentation under MPI, where the composited frame is as
 *   slow as the slowest process). A push then still measures the frame, but neither steers nor
 *   sets the selector's budget. Once per frame, on every process, the owner takes the measured
 *   cost (TakeFrameCost), combines it with the other processes' figures, makes the controller's
 *   step with the combined figures (StepBudget) and gives the selector its part of the budget
 *   returned. The controller is this one, with the same law: only its inputs change.
 *
 * @warning The LOD output holds only what the current view draws, so its bounds change with the
 * view. Reset cameras and clipping ranges with the model's bounds
 * (vtkRenderer::ResetCamera(bounds), ResetCameraClippingRange(bounds)), not from the LOD
 * actor, or the clipping planes fit a partial surface.
 *
 * The binding holds its renderer, selector and prop; the renderer's observer holds only a raw
 * pointer back, so there is no reference cycle. The observer is removed when the binding is
 * destroyed, disabled, or bound to another renderer.
 *
 * @sa vtkPerceptualLODSelector vtkMultiscalePatchGenerator
 */
#ifndef vtkPerceptualLODRenderBinding_h
#define vtkPerceptualLODRenderBinding_h

#include "PerceptualLODRenderingModule.h" // for export macro
#include "vtkObject.h"

#include <functional> // for the clock

class vtkCallbackCommand;
class vtkCamera;
class vtkPerceptualLODSelector;
class vtkProp3D;
class vtkProperty;
class vtkRenderWindow;
class vtkRenderer;

class PERCEPTUALLODRENDERING_EXPORT vtkPerceptualLODRenderBinding : public vtkObject
{
public:
  static vtkPerceptualLODRenderBinding* New();
  vtkTypeMacro(vtkPerceptualLODRenderBinding, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The renderer observed. Setting another removes the observer from the previous one.
  void SetRenderer(vtkRenderer* renderer);
  vtkGetObjectMacro(Renderer, vtkRenderer);
  ///@}

  ///@{
  /// The selector fed.
  void SetSelector(vtkPerceptualLODSelector* selector);
  vtkGetObjectMacro(Selector, vtkPerceptualLODSelector);
  ///@}

  ///@{
  /// The prop whose matrix maps the octree (object) to the world, and whose property gives the
  /// material. Without a prop the octree is in world coordinates.
  void SetProp3D(vtkProp3D* prop);
  vtkGetObjectMacro(Prop3D, vtkProp3D);
  ///@}

  ///@{
  /// Enabled (default) or not. Disabling removes the observer; enabling adds it back.
  void SetEnabled(bool enabled);
  vtkGetMacro(Enabled, bool);
  void EnabledOn() { this->SetEnabled(true); }
  void EnabledOff() { this->SetEnabled(false); }
  ///@}

  ///@{
  /**
   * Frame-time target in seconds (default 0: off). Negative and non-finite values are errors
   * (the target stays off). See the class documentation.
   */
  void SetTargetFrameTime(double seconds);
  vtkGetMacro(TargetFrameTime, double);
  /// Limits of the budget the target sets (defaults 1000 and VTK_ID_MAX).
  vtkSetClampMacro(MinimumTriangleBudget, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MinimumTriangleBudget, vtkIdType);
  vtkSetClampMacro(MaximumTriangleBudget, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MaximumTriangleBudget, vtkIdType);
  /// The cost of the last complete frame (s; 0 before one was measured): from the push to the
  /// end of the render window's frame.
  vtkGetMacro(LastFrameCost, double);
  /// The budget the target set at the last push (0: none).
  vtkGetMacro(TargetBudget, vtkIdType);
  ///@}

  ///@{
  /**
   * Steering by the owner (default off; see the class documentation). On, a push measures the
   * frame but does not steer; the owner calls TakeFrameCost() and StepBudget() once per frame
   * and sets the selector's budget. It must set the target here too (SetTargetFrameTime), so
   * that all processes reset their controllers at the same frame.
   */
  vtkSetMacro(ExternalSteering, bool);
  vtkGetMacro(ExternalSteering, bool);
  vtkBooleanMacro(ExternalSteering, bool);
  ///@}

#ifndef __VTK_WRAP__
  /**
   * The clock the binding reads (seconds; default: the wall clock, vtkTimerLog's universal
   * time). Frame costs, the frame interval the motion models use and the push's own time are
   * measured on it, so that a test drives the frame-time target and the motion models on a
   * simulated clock. An empty function restores the wall clock.
   */
  void SetClock(std::function<double()> clock);
#endif

  /**
   * The clock of SetClock for scripts (Python has no std::function): from now on the binding
   * reads `seconds` as the time, until the next call or UseWallClock(). A script that renders
   * on its own schedule (a measurement of moving views at a simulated frame rate) sets the time
   * of each frame before the binding's push, and the binding measures the frame times and the
   * motion on that schedule.
   */
  void SetSimulatedTime(double seconds);
  /// Back to the wall clock (after SetSimulatedTime or SetClock).
  void UseWallClock();

  /// The cost of the last frame measured and not yet steered with (s), which is then forgotten;
  /// 0 when there is none (the first frame, a frame that did not finish, or one already used).
  double TakeFrameCost();

  /**
   * One step of the frame-time target's controller (plod::BudgetController), as a push makes
   * with this binding's own figures: `seconds`, the frame's cost (0: nothing new measured; the
   * budget stays), `drawn`, the triangles the selector counted (vtkPerceptualLODSelector::
   * GetNumberOfBudgetTriangles) and `binding`, whether the budget stopped the cut. Returns the
   * budget for the next frame, also TargetBudget (0 when the target is off). Does not set the
   * selector's budget: that is the caller's (with ExternalSteering on).
   */
  vtkIdType StepBudget(double seconds, vtkIdType drawn, bool binding);

  /// Pushes the renderer's current state to the selector now (what StartEvent does).
  void Update();

  /**
   * Pushes the state of `renderer` with `prop`'s matrix and material to the selector now,
   * without holding either (whatever SetRenderer, SetProp3D and Enabled say). For a prop that
   * feeds its own selector while it renders (vtkPerceptualLODActor), where holding the
   * renderer or the prop would make a reference cycle. Motion is measured between successive
   * pushes of this binding.
   */
  void UpdateFrom(vtkRenderer* renderer, vtkProp3D* prop);

  ///@{
  /// Figures: frames pushed, the last measured frame interval (s) and the time the last push
  /// took (s).
  vtkGetMacro(NumberOfUpdates, vtkIdType);
  vtkGetMacro(MeasuredFrameTime, double);
  vtkGetMacro(LastUpdateTime, double);
  ///@}

protected:
  vtkPerceptualLODRenderBinding();
  ~vtkPerceptualLODRenderBinding() override;

  void AddObserver();
  void RemoveObserver();
  static void OnStart(vtkObject* caller, unsigned long event, void* client, void* data);
  static void OnWindowEnd(vtkObject* caller, unsigned long event, void* client, void* data);
  /// Observes `window`'s EndEvent (once per window), to measure the frame's cost.
  void WatchWindow(vtkRenderWindow* window);
  /// The frame-time target's step: the next budget from the last frame's cost.
  void SteerBudget();
  ///@{
  /// The steps of UpdateFrom: the camera and viewport (with the prop's matrix), the lights,
  /// the actor's material, and the motion since the last push (only for a selector with a
  /// motion model, measured on the clock from `start`, this push's time).
  void PushView(vtkRenderer* ren, const double objectToWorld[16]);
  void PushLights(vtkRenderer* ren);
  void PushMaterial(vtkProperty* property);
  void PushMotion(vtkCamera* camera, const double objectToWorld[16], double start);
  ///@}

  vtkRenderer* Renderer;
  vtkPerceptualLODSelector* Selector;
  vtkProp3D* Prop3D;
  bool Enabled;
  vtkCallbackCommand* Observer;
  unsigned long ObserverTag;

  bool HasPrevious;
  double PreviousObjectToView[16];
  double PreviousStart;
  vtkIdType NumberOfUpdates;
  double MeasuredFrameTime;
  double LastUpdateTime;

  double TargetFrameTime = 0;
  vtkIdType MinimumTriangleBudget; // 1000
  vtkIdType MaximumTriangleBudget; // VTK_ID_MAX
  double LastFrameCost = 0;
#ifndef __VTK_WRAP__
  std::function<double()> Clock;
  /// The clock's time now (SetClock).
  double Now() const;
#endif
  bool FrameCostPending = false;
  bool FrameStarted = false;
  vtkIdType TargetBudget = 0;
  bool ExternalSteering = false;
  vtkCallbackCommand* WindowObserver = nullptr;
  vtkRenderWindow* Window = nullptr; // observed, not held (see WatchWindow)
  unsigned long WindowTag = 0;
  class vtkInternals;
  vtkInternals* Internals = nullptr;

private:
  vtkPerceptualLODRenderBinding(const vtkPerceptualLODRenderBinding&) = delete;
  void operator=(const vtkPerceptualLODRenderBinding&) = delete;
};

#endif
