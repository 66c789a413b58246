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

class vtkCallbackCommand;
class vtkPerceptualLODSelector;
class vtkProp3D;
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

private:
  vtkPerceptualLODRenderBinding(const vtkPerceptualLODRenderBinding&) = delete;
  void operator=(const vtkPerceptualLODRenderBinding&) = delete;
};

#endif
