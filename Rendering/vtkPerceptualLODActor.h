// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODActor
 * @brief   one actor that draws a mesh, a point cloud or an octree with the perceptual LOD
 *
 * The drop-in form of the whole pipeline, as vtkLODActor or vtkQuadricLODActor are used:
 *
 * @code{.py}
 * actor = vtkPerceptualLODActor()
 * actor.SetInputConnection(reader.GetOutputPort())   # a mesh, a point cloud or a .plod octree
 * renderer.AddActor(actor)
 * renderer.ResetCamera()                             # fits the whole model
 * window.Render()
 * @endcode
 *
 * Inside, it holds a vtkMultiscaleOctreeBuilder (skipped when the input already is a
 * vtkMultiscaleOctree, from vtkMultiscaleOctreeReader say), a vtkPerceptualLODSelector, a
 * vtkMultiscalePatchGenerator and a vtkPolyDataMapper. Every time it renders, it reads the
 * renderer it is drawn in — the camera, the viewport, the lights, its own matrix and its
 * property's material — and feeds the selector, as vtkPerceptualLODRenderBinding does for a
 * hand-made pipeline (no binding object is needed). So it follows the view in every renderer
 * it is added to: with several renderers, the cut is selected again for each one, and each
 * renderer keeps its own motion history (for TMM).
 *
 * - **Bounds are the model's**, whatever the current cut draws, transformed by the actor's
 *   matrix: `ResetCamera()` and the clipping range fit the whole model (the same camera as
 *   `ResetCamera(model bounds)`, to the single precision in which the octree keeps points).
 * - **The selector is reachable** (GetSelector()) for its modes and tolerances, the builder
 *   (GetBuilder()) for the finest level, vertex rule and material arrays, the patch generator
 *   (GetPatchGenerator()) for folds and back faces.
 * - **Material:** the property's diffuse and specular coefficients and specular power drive
 *   the brightness criterion when the octree has no material arrays.
 * - **Picking** hits the surface as currently drawn: a picked position lies on the LOD
 *   surface of the last render, and a cell id is an index into the mapper's current input
 *   (GetMapper()->GetInput()), not into the original mesh. Pick with the same renderer's
 *   view as the last render for a consistent answer.
 * - **Frame-time target**: SetTargetFrameTime(seconds) holds frames near that time by a
 *   triangle budget (vtkPerceptualLODRenderBinding).
 * - **Two draw paths.** The CPU path (the default) makes the cut's triangles with the patch
 *   generator and draws them with a vtkPolyDataMapper. The GPU path (SetDrawPathToGPU())
 *   keeps the octree's surface on the device and sends each frame only the cut's changes
 *   (vtkPerceptualLODMapper); where the context lacks a feature it needs, the actor draws through
 *   the CPU path and warns once, naming the feature.
 * - **Background loading** (vtkMultiscaleOctreeReader::SetBackgroundLoading): while pages of
 *   the cut are being read, or were read since the last cut, the actor asks the render
 *   window's interactor for another render shortly after each render (a one-shot timer of
 *   RefreshInterval milliseconds), so that the view refines as the pages arrive without the
 *   application rendering again. Without an interactor (offscreen scripts) the application
 *   renders when it likes; vtkMultiscaleOctree::GetNumberOfWaitingLoads() tells whether to.
 * - SetMapper() is ignored with a warning: the actor's mapper is its own.
 *
 * @sa vtkPerceptualLODRenderBinding vtkPerceptualLODSelector vtkMultiscaleOctreeReader
 */
#ifndef vtkPerceptualLODActor_h
#define vtkPerceptualLODActor_h

#include "PerceptualLODRenderingModule.h" // for export macro
#include "vtkActor.h"
#include "vtkWeakPointer.h" // for the interactor asked to render again

#include <functional> // for the clock
#include <map>        // for the per-renderer state
#include <memory>     // for the per-renderer state

class vtkAlgorithmOutput;
class vtkCallbackCommand;
class vtkMatrix4x4;
class vtkDataObject;
class vtkMultiscaleOctreeBuilder;
class vtkMultiscalePatchGenerator;
class vtkPerceptualLODMapper;
class vtkPerceptualLODRenderBinding;
class vtkRenderer;
class vtkRenderWindow;
class vtkRenderWindowInteractor;
class vtkPerceptualLODSelector;
class vtkPolyDataMapper;
class vtkTrivialProducer;

class PERCEPTUALLODRENDERING_EXPORT vtkPerceptualLODActor : public vtkActor
{
public:
  static vtkPerceptualLODActor* New();
  vtkTypeMacro(vtkPerceptualLODActor, vtkActor);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The model: a pipeline output or a data object holding a mesh or point cloud (any
   * vtkPointSet the builder takes), or a vtkMultiscaleOctree (then nothing is built).
   */
  void SetInputConnection(vtkAlgorithmOutput* input);
  void SetInputData(vtkDataObject* input);
  ///@}

  ///@{
  /// The inner pipeline, for its settings.
  vtkMultiscaleOctreeBuilder* GetBuilder();
  vtkPerceptualLODSelector* GetSelector();
  vtkMultiscalePatchGenerator* GetPatchGenerator();
  ///@}

  ///@{
  /**
   * Frame-time target in seconds (default 0: off): each renderer's binding measures what its
   * frames cost and steers the selector's triangle budget to hold the target
   * (vtkPerceptualLODRenderBinding::SetTargetFrameTime). The tolerances stay a floor.
   */
  void SetTargetFrameTime(double seconds);
  vtkGetMacro(TargetFrameTime, double);
  ///@}

  ///@{
  /**
   * How the cut is drawn:
   * - DRAW_PATH_CPU: the patch generator's triangles through a vtkPolyDataMapper, uploaded
   *   whenever the cut changes;
   * - DRAW_PATH_GPU: vtkPerceptualLODMapper, the surface resident on the GPU and only the
   *   cut's changes sent each frame; the CPU path, with a warning, where the context lacks
   *   what it needs;
   * - DRAW_PATH_AUTOMATIC (default): the GPU path on a hardware renderer, the CPU path on a
   *   software rasterizer (vtkPerceptualLODMapper::IsSoftwareRenderer: there the GPU path's
   *   vertex shader walks the cluster tree on the CPU's own cores for every vertex of every
   *   frame, and still frames cost more than the CPU path's), and the CPU path without a
   *   warning where the context lacks a feature the GPU path needs.
   * Both paths draw the same picture (tests compare them); the patch generator's settings
   * (FoldHandling) are followed by the GPU path too.
   */
  enum DrawPaths
  {
    DRAW_PATH_CPU = 0,
    DRAW_PATH_GPU = 1,
    DRAW_PATH_AUTOMATIC = 2
  };
  void SetDrawPath(int path);
  vtkGetMacro(DrawPath, int);
  void SetDrawPathToCPU() { this->SetDrawPath(DRAW_PATH_CPU); }
  void SetDrawPathToGPU() { this->SetDrawPath(DRAW_PATH_GPU); }
  void SetDrawPathToAutomatic() { this->SetDrawPath(DRAW_PATH_AUTOMATIC); }
  /// The GPU path's mapper (its figures: bytes uploaded, triangles drawn).
  vtkPerceptualLODMapper* GetGPUMapper() { return this->GPUMapper; }
  /// True when the last render drew through the GPU path.
  vtkGetMacro(DrewOnGPU, bool);
  ///@}

#ifndef __VTK_WRAP__
  /**
   * The clock every binding of the actor reads (vtkPerceptualLODRenderBinding::SetClock;
   * default: the wall clock): a test drives the frame-time target and the motion models on a
   * simulated clock with it.
   */
  void SetClock(std::function<double()> clock);
#endif

  ///@{
  /// Milliseconds between the renders the actor asks for while pages are read in the
  /// background (see "Background loading" above). Default 50.
  vtkSetClampMacro(RefreshInterval, int, 1, 10000);
  vtkGetMacro(RefreshInterval, int);
  ///@}

  /// The binding that feeds the selector for `renderer` (null before it first rendered there).
  /// It lives as long as the renderer (see GetNumberOfBindings()).
  vtkPerceptualLODRenderBinding* GetBinding(vtkRenderer* renderer);

  /**
   * How many renderers the actor keeps a binding (a motion history) for: those it has rendered
   * in, or made a binding for, that still exist. A renderer's binding goes when the renderer is
   * deleted (the actor observes its DeleteEvent and never holds it).
   */
  int GetNumberOfBindings();

  /**
   * The binding for `renderer`, made now if the actor has not rendered there yet (as its first
   * render there would make it). For an owner that configures the binding before the first
   * render, or whether the actor renders at all (vtkPerceptualLODRepresentation under MPI).
   */
  vtkPerceptualLODRenderBinding* MakeBinding(vtkRenderer* renderer);

  /// True when the input is an octree (the builder is not used).
  bool GetInputIsOctree();

  /**
   * The model's bounds (every point of the surface, not only the current cut) in world
   * coordinates, through the actor's matrix. Empty input: uninitialized bounds.
   */
  double* GetBounds() override;
  using vtkActor::GetBounds;

  /// Feeds the selector from `viewport` (a vtkRenderer), then draws.
  int RenderOpaqueGeometry(vtkViewport* viewport) override;

  /// Ignored with a warning: the actor draws through its own mapper.
  void SetMapper(vtkMapper* mapper) override;

  /// Draws through a device actor of the rendering backend (vtkActor itself draws nothing),
  /// with this actor's property, textures and matrix.
  void Render(vtkRenderer* renderer, vtkMapper* mapper) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

protected:
  vtkPerceptualLODActor();
  ~vtkPerceptualLODActor() override;

  /// The mapper that draws: `mapper` (the path's), or the CPU path's where the GPU path cannot
  /// or, automatically, should not draw.
  vtkMapper* ChooseMapper(vtkRenderer* renderer, vtkMapper* mapper);
  /// Connects builder or selector to `input`, by the input's data type.
  void Connect(vtkAlgorithmOutput* input);
  /// Feeds the selector for `renderer` (its own binding, made on first use).
  void Feed(vtkViewport* viewport);
  /// After a render in `renderer`: while the cut's pages are read in the background, asks the
  /// window's interactor for another render (a one-shot timer; one at a time).
  void RenderAgainWhileLoading(vtkRenderer* renderer);
  /// TimerEvent of the interactor: renders the window again when the timer is the actor's.
  static void RefreshTimerFired(vtkObject* caller, unsigned long, void* client, void* callData);
  /// DeleteEvent of a renderer with a binding: drops the binding.
  static void RendererDeleted(vtkObject* caller, unsigned long, void* client, void*);

  vtkTrivialProducer* Producer = nullptr;
  vtkActor* Device = nullptr; // the backend's actor (vtkOpenGLActor), as in vtkLODActor
  vtkMatrix4x4* DeviceMatrix = nullptr;
  vtkMultiscaleOctreeBuilder* Builder = nullptr;
  vtkPerceptualLODSelector* Selector = nullptr;
  vtkMultiscalePatchGenerator* Patches = nullptr;
  vtkPolyDataMapper* LODMapper = nullptr;
  vtkPerceptualLODMapper* GPUMapper = nullptr;
  int DrawPath = DRAW_PATH_AUTOMATIC;
  bool DrewOnGPU = false;
  bool WarnedFallback = false;
#ifndef __VTK_WRAP__
  std::function<double()> Clock;
#endif
  bool InputIsOctree = false;
  double TargetFrameTime = 0;
  double ModelBounds[6];
  vtkMTimeType ModelBoundsTime = 0;
  /// One binding per renderer (by address): its motion history, and the tag of the observer of
  /// the renderer's DeleteEvent that drops it. Never holds the renderer.
  struct RendererBinding
  {
    vtkPerceptualLODRenderBinding* Binding = nullptr;
    vtkRenderer* Renderer = nullptr;
    unsigned long DeleteObserver = 0;
  };
  std::map<const void*, RendererBinding> Bindings;
  vtkCallbackCommand* OnRendererDeleted = nullptr;
  // the render asked for while loading: its interactor (observed, never held), timer and window
  int RefreshInterval = 50;
  vtkCallbackCommand* OnRefreshTimer = nullptr;
  vtkWeakPointer<vtkRenderWindowInteractor> RefreshInteractor;
  vtkWeakPointer<vtkRenderWindow> RefreshWindow;
  int RefreshTimer = -1;
  vtkIdType LoadsRendered = 0;

private:
  vtkPerceptualLODActor(const vtkPerceptualLODActor&) = delete;
  void operator=(const vtkPerceptualLODActor&) = delete;
};

#endif
