// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODRepresentation
 * @brief   ParaView representation that draws a surface or a point cloud with the perceptual LOD
 *
 * The ParaView form of vtkPerceptualLODActor. In the GUI it is the "Perceptual LOD" entry of a
 * surface's or point cloud's Representation list (and the default representation of the
 * octrees the "Multiscale Octree" filters make). On every render it reads the camera, viewport,
 * lights and material that ParaView renders with, selects a cut of the multiscale octree and
 * draws its triangles; the octree is built once per input change.
 *
 * - **Input**: a vtkPolyData (triangles, or vertices only: a point cloud), any other vtkDataSet
 *   (its outer surface, vtkDataSetSurfaceFilter), or a vtkMultiscaleOctree (from the "Multiscale
 *   Octree Builder" or "Multiscale Octree Reader" filters; nothing is built then, so an octree
 *   built once is reused by every representation and every session that reads it). Composite
 *   datasets are refused with an error that says to apply Merge Blocks first.
 * - **Follows the rendered camera** on every render, on every rank: the selector is fed from
 *   the renderer ParaView draws in (vtkPerceptualLODActor does it in RenderOpaqueGeometry). A
 *   render whose camera, lights and viewport did not change re-executes nothing (the selector
 *   and the patch generator only run when an input they use changed).
 * - **Reset Camera** fits the whole model: the bounds reported to the view are the model's,
 *   whatever the cut draws.
 * - **ParaView's own LOD is off** for it: it never hands ParaView a decimated piece and draws
 *   its own cut in interactive and still renders alike (ParaView's LOD threshold does not
 *   apply to it).
 * - **Distributed** (pvbatch or pvserver over MPI, each rank holding a piece): the ranks agree
 *   on one root cube from the global bounds and on one finest level, so the octree levels
 *   align; vtkPerceptualLODRedistribution gives each rank the triangles of its own octree cells
 *   and complete copies of the neighbouring cells they touch, and marks the points another rank
 *   owns as ghosts, so each triangle is drawn by exactly one rank with the same corners as in a
 *   single-process build: no crack along piece borders (see that class). The selector then
 *   always refines the cells above the ownership level (MinimumLevel), whose content no rank
 *   holds whole, and the automatic back-face rule follows the whole mesh (closed or not), not
 *   each rank's octree, whose halo has a rim. It renders where the data is (it asks the view for
 * distributed rendering): IceT composites the ranks' images.
 * - **Budget and frame-time target with several ranks.** TriangleBudget is the view's total: the
 *   triangles all ranks' selectors count together (vtkPerceptualLODSelector::
 *   GetNumberOfBudgetTriangles: what each rank draws, not the halo triangles another rank
 *   draws). TargetFrameTime holds the composited frame, which is as slow as
 *   the slowest rank. Once per render, at the view's REQUEST_RENDER pass (which every rank makes
 *   before IceT renders, whether its actor is culled, empty or not; not in the actor's render,
 *   which the renderer skips on a rank whose piece lies outside the view), the ranks gather their
 *   figures in one collective (vtkMultiProcessController::AllGather of 4 numbers per rank): the
 *   cost of each rank's last frame (vtkPerceptualLODRenderBinding measures it), the triangles its
 *   selector counted, whether its budget bound, and its demand in the cut's count (the tolerance
 *   cut's when its budget did not bind, else the cut's plus the refinements left waiting:
 *   vtkPerceptualLODSelector::GetNumberOfCutTriangles, GetNumberOfWaitingTriangles). Every rank
 *   then computes the same
 *   figures from the same table: the steering frame cost is the maximum over ranks, the triangles
 *   drawn the sum, and one step of the binding's controller with them gives the same total budget
 *   on every rank (vtkPerceptualLODRenderBinding::StepBudget, ExternalSteering). The total is split
 *   in proportion to the demands: rank r gets 1 + floor((total - ranks) * share_r), so the parts
 *   never add up to more than the total. The shares follow the demands halfway, and only when they
 *   would move more than 5 % of the budget in all, so that a still view settles and nothing
 *   re-executes. The tolerances and the ownership level stay floors: a total below what they need
 *   is exceeded. With a target, the steered total replaces TriangleBudget, as on one process. When
 *   the view does not render distributed (another representation asked for local rendering), the
 *   ranks exchange nothing: each steers from its own frames and a fixed budget is split evenly.
 * - **Selections** (ParaView's Select Cells/Points On, hovering) do not select from this
 *   representation: it is not pickable, because the triangles drawn are those of the current
 *   cut, whose ids change with every view and do not name cells of the input. Select on a
 *   Surface representation of the same source; the selection then applies to the input and
 *   shows in every view.
 *
 * Properties forward to the inner vtkPerceptualLODSelector (error and motion models,
 * tolerances, foveation, back faces), vtkMultiscaleOctreeBuilder (finest level) and the actor's
 * vtkProperty (colour, diffuse, specular, which also drive the brightness criterion). Setting
 * a selector property does not make ParaView re-execute the representation: the next render
 * selects again.
 *
 * Counters (GetNumberOfBuilds, GetNumberOfSelections, GetNumberOfPatchUpdates) count the inner
 * filters' executions, for tests and for users who check that a still view costs nothing.
 *
 * @sa vtkPerceptualLODActor vtkPerceptualLODRedistribution vtkPerceptualLODSelector
 */
#ifndef vtkPerceptualLODRepresentation_h
#define vtkPerceptualLODRepresentation_h

#include "PerceptualLODParaViewRepresentationModule.h" // for export macro
#include "vtkPVDataRepresentation.h"

#include <vector> // for the shares of the budget

class vtkDataObject;
class vtkMultiProcessController;
class vtkPerceptualLODActor;
class vtkPerceptualLODRedistribution;
class vtkPerceptualLODRenderBinding;
class vtkPVRenderView;

class PERCEPTUALLODPARAVIEWREPRESENTATION_EXPORT vtkPerceptualLODRepresentation
  : public vtkPVDataRepresentation
{
public:
  static vtkPerceptualLODRepresentation* New();
  vtkTypeMacro(vtkPerceptualLODRepresentation, vtkPVDataRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int ProcessViewRequest(
    vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) override;
  void SetVisibility(bool visible) override;

  ///@{
  /// Selector settings (vtkPerceptualLODSelector; the same defaults).
  void SetErrorModel(int model);
  int GetErrorModel();
  void SetMotionModel(int model);
  int GetMotionModel();
  void SetVelocityCriterion(int criterion);
  void SetFoveationMode(int mode);
  void SetFoveationRate(double rate);
  void SetFoveationPoint(double x, double y, double z);
  void SetGazeDirection(double x, double y, double z);
  void SetBackFaceMode(int mode);
  void SetContourTolerance(double pixels);
  double GetContourTolerance();
  void SetBrightnessTolerance(double tolerance);
  void SetTopologyTolerance(double pixels);
  /// At most this many triangles in the view (0, the default: no budget; the tolerances stay a
  /// floor). With several ranks, the total over ranks, split between them (see the class
  /// documentation).
  void SetTriangleBudget(vtkIdType triangles);
  vtkGetMacro(TriangleBudget, vtkIdType);
  /// Count the drawn triangles exactly, so that no more than the budget are drawn (off, the
  /// default: the count is estimated, within a few percent; see
  /// vtkPerceptualLODSelector::SetExactTriangleBudget). With several ranks, each rank's part.
  void SetExactTriangleBudget(int exact);
  int GetExactTriangleBudget();
  /// Hold frames near this many seconds by steering the budget (0, the default: off). With
  /// several ranks, the composited frame: the slowest rank's frame steers every rank's budget.
  void SetTargetFrameTime(double seconds);
  ///@}

  ///@{
  /**
   * For tests: seconds added to the measured frame cost of rank TestingSlowRank (-1, the
   * default: every rank) before the ranks share it (default 0 s). It makes one rank look slow
   * without slowing it. Set it alike on every rank: in ParaView a property changed on one rank
   * only makes that rank alone update the view, whose collectives then wait for the others.
   */
  vtkSetMacro(TestingExtraFrameCost, double);
  vtkGetMacro(TestingExtraFrameCost, double);
  vtkSetMacro(TestingSlowRank, int);
  vtkGetMacro(TestingSlowRank, int);
  ///@}

  ///@{
  /**
   * The frame-time target's figures, for tests and for users who check what is held:
   * - SharedFrameCost: the frame cost (s) the budget was last steered with. With several
   *   ranks, the maximum over ranks of their measured costs at the last exchange, the same on
   *   every rank (0: nothing was measured); on one rank, the binding's last measured cost;
   * - LocalFrameCost: this rank's own last measured frame cost (s; 0 before one);
   * - TotalTriangleBudget: the budget in force for the whole view at the last render (the
   *   steered one with a target, else TriangleBudget; 0: none), the same on every rank;
   * - RankTriangleBudget: this rank's part of it, its selector's budget (0: none);
   * - NumberOfBudgetTriangles: the triangles this rank's selector counted at its last cut;
   * - NumberOfFrameReductions: the collectives this representation made to share frames (one
   *   per render with several ranks rendering distributed; 0 on one rank).
   */
  double GetSharedFrameCost();
  double GetLocalFrameCost();
  vtkIdType GetTotalTriangleBudget();
  vtkIdType GetRankTriangleBudget();
  vtkIdType GetNumberOfBudgetTriangles();
  vtkGetMacro(NumberOfFrameReductions, int);
  ///@}

  ///@{
  /// Builder settings (vtkMultiscaleOctreeBuilder): finest level (-1, the default: chosen
  /// from the input; in parallel the same level on every rank).
  void SetFinestLevel(int level);
  vtkGetMacro(FinestLevel, int);
  ///@}

  ///@{
  /// Appearance (the actor's vtkProperty; the diffuse and specular coefficients and the
  /// specular power also drive the brightness criterion).
  void SetDiffuseColor(double r, double g, double b);
  void SetDiffuse(double diffuse);
  void SetSpecular(double specular);
  void SetSpecularPower(double power);
  void SetAmbient(double ambient);
  void SetOpacity(double opacity);
  ///@}

  ///@{
  /**
   * Distributed builds: the octree level whose cells the ranks own (default 3, at most 8^3
   * cells to share out; clamped to [1, 6]). Cells coarser than it are refined on every rank.
   */
  void SetOwnershipLevel(int level);
  vtkGetMacro(OwnershipLevel, int);
  ///@}

  ///@{
  /**
   * Distributed builds: share the mesh out between ranks (default on). Off, each rank builds
   * the octree of its own piece as it is: cracks open along piece borders (kept for
   * comparison, and for pieces that are already whole octree cells).
   */
  void SetRedistribute(bool redistribute);
  vtkGetMacro(Redistribute, bool);
  ///@}

  ///@{
  /// The controller of the ranks (default: the global one).
  void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  ///@{
  /// Figures: executions of the inner filters since construction, the triangles and cut nodes
  /// drawn by this rank at the last render, and the eye position the selector last used.
  vtkGetMacro(NumberOfBuilds, int);
  vtkGetMacro(NumberOfSelections, int);
  vtkGetMacro(NumberOfPatchUpdates, int);
  vtkIdType GetNumberOfTriangles();
  vtkIdType GetNumberOfCutNodes();
  /// Cells of the last cut drawn coarser while their pages are read (an octree file read with
  /// the reader's BackgroundLoading; vtkPerceptualLODSelector::GetNumberOfAwaitingCells). The
  /// view refines at the next renders as they arrive: in the GUI the actor asks its interactor
  /// for them; a script or a server without an interactor renders again itself.
  vtkIdType GetNumberOfAwaitingCells();
  void GetSelectorEyePosition(double eye[3]);
  /// The same, as a pointer (for ParaView's information properties); valid until the next call.
  double* GetSelectorEye() VTK_SIZEHINT(3);
  /// Octree cells of the ownership level this rank owns (0 on one rank).
  int GetNumberOfOwnedCells();
  /// This rank's octree: its finest level, nodes and surface triangles (-1, 0, 0 before the
  /// first build).
  int GetOctreeFinestLevel();
  vtkIdType GetNumberOfOctreeNodes();
  vtkIdType GetNumberOfOctreeTriangles();
  /// Distributed: the whole mesh's boundary edges (0: closed), which decide the automatic
  /// back-face rule; -1 when the mesh was not shared out.
  vtkGetMacro(GlobalBoundaryEdges, vtkIdType);
  /// This rank's number among the controller's processes and their number.
  int GetRank();
  int GetNumberOfRanks();
  ///@}

  /// The inner actor (its builder, selector and patch generator), for settings not exposed.
  vtkPerceptualLODActor* GetActor() { return this->Actor; }

  /// The redistribution of the last distributed build (null on one rank).
  vtkPerceptualLODRedistribution* GetRedistribution() { return this->Redistribution; }

protected:
  vtkPerceptualLODRepresentation();
  ~vtkPerceptualLODRepresentation() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;

  /// The surface or cloud to build from, or the octree, for `input` (null and an error for what
  /// cannot be drawn).
  vtkDataObject* PrepareInput(vtkDataObject* input);
  /// The selector's back-face mode: BackFaceMode, with AUTOMATIC decided by the whole mesh
  /// (closed: hidden) when the mesh was shared out between ranks.
  void ApplyBackFaceMode();
  /**
   * At REQUEST_RENDER, on every rank: with several ranks rendering distributed, gathers the
   * ranks' frame figures (one collective), steers the total budget with the slowest rank's
   * frame cost and gives this rank's selector its part (see the class documentation).
   */
  void ShareFrame(vtkPVRenderView* view);
  /// Moves the shares of the total budget towards `demands` (one per rank; the same on every
  /// rank), with the dead band and the halfway step of the class documentation.
  void UpdateShares(const std::vector<double>& demands);
  /// This rank's part of `total` with the current shares (0 for a total of 0).
  vtkIdType PartOfBudget(vtkIdType total);

  vtkPerceptualLODActor* Actor = nullptr;
  vtkPerceptualLODRedistribution* Redistribution = nullptr;
  vtkMultiProcessController* Controller = nullptr;
  vtkDataObject* Prepared = nullptr;
  vtkMTimeType PreparedFrom = 0; // the input's MTime when Prepared was made
  vtkDataObject* PreparedInput = nullptr;
  int OwnershipLevel = 3;
  int FinestLevel = -1;
  bool Redistribute = true;
  int BackFaceMode = 0;               // as set (vtkPerceptualLODSelector's modes)
  vtkIdType GlobalBoundaryEdges = -1; // of the whole mesh when shared out, else -1
  double ModelBounds[6];
  double SelectorEye[3] = { 0, 0, 0 };
  int NumberOfBuilds = 0;
  int NumberOfSelections = 0;
  int NumberOfPatchUpdates = 0;
  // budget and frame-time target over several ranks (ShareFrame)
  vtkIdType TriangleBudget = 0;
  double TestingExtraFrameCost = 0;
  int TestingSlowRank = -1;
  double SharedFrameCost = 0;
  vtkIdType TotalTriangleBudget = 0;
  int NumberOfFrameReductions = 0;
  bool Sharing = false;          // the last render shared its frame between ranks
  std::vector<double> Shares;    // each rank's share of the total budget (sum 1)
  bool SharesFromDemand = false; // the shares follow measured demands (not an even start)
  vtkPerceptualLODRenderBinding* Binding = nullptr; // the actor's, for the view's renderer

private:
  vtkPerceptualLODRepresentation(const vtkPerceptualLODRepresentation&) = delete;
  void operator=(const vtkPerceptualLODRepresentation&) = delete;
};

#endif
