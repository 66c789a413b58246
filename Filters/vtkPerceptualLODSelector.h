// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODSelector
 * @brief   picks, every frame, the cut through a multiscale octree that a viewer can perceive
 *
 * Reads a vtkMultiscaleOctree and the view, written as plain numbers (no renderer inside, so it
 * is testable and usable from Python without a window), and outputs the same octree (shallow
 * copy) with three node arrays for vtkMultiscalePatchGenerator: "CutState" (0 not in the cut,
 * 1 drawn at the cell's representative vertex, 2 hidden, 3 a leaf opened: drawn at full
 * resolution), "CutReason" (plod::CutReason: 1 accepted on the contour, 2 accepted by
 * brightness, 3 leaf opened, 4 culled, 5 back-facing, 6 accepted by a baseline's error test,
 * 7 accepted by its projected size, 8 left unrefined by the triangle budget, 9 left unrefined
 * while its pages are read: see vtkMultiscaleOctree::SetBackgroundLoading) and "CullMask"
 * (the frustum planes a culled cell lies outside), and the field array "CutView" (the eye and
 * projection the cut was made for). The cut arrays and "CutView" are the selector's own and are
 * rewritten in place every frame (their modification times change): an output kept from an
 * earlier frame shows the latest cut; DeepCopy it to keep a frame's cut.
 *
 * Method (docs/design.md, "Selection"; SRCC §3.3-3.5 by Wakatsuki et al. 2003; TMM §3-4; Wang &
 * Sato eq. 1-2; Cheng §2), walking from the root:
 * 1. cells wholly outside the view frustum are hidden and not refined;
 * 2. contour: with gamma the angle between v_e (vertex to eye) and the cone axis, cells with
 *    gamma < pi/2 - theta are front-facing, gamma > pi/2 + theta back-facing (hidden, not
 *    refined), otherwise on the contour, accepted when the projected shape error
 *    ShapeError * d_s / d_o (reduced by the micro motion |n.v_f| d_s / d_o) is at most
 *    ContourTolerance pixels;
 * 3. brightness: the spread of Lambert and Phong shading over the normal cone, summed over the
 *    lights (SRCC eq. 7-8), times the projected cell size l_p (n.v_e) d_s / d_o (reduced by the
 *    motion across the view) is at most BrightnessTolerance; else the children are tested for
 *    brightness only;
 * 4. a leaf that is reached and fails a test is opened: its own input points and triangles are
 *    drawn, so zero tolerances give the input itself.
 * Topology: a cell whose sub-mesh is not a union of discs (a tube, a handle: collapsing it
 * would drop its triangles and open a see-through gap) is refined, whatever its errors, while
 * the part it could lose (its Thickness) projects to more than TopologyTolerance pixels.
 * Open rims: a cell holding a boundary point of an open surface is refined until its edge passes
 * the size floor (its shape error is not used), since its outline is seen from every side.
 * Size floor (every mode but Distance and Cheng's; in SRCC not for the cells tested for
 * brightness only, whose parent passed its contour test): a cell whose edge projects to at most
 * ContourTolerance pixels is accepted, since its points then lie within about that many pixels of
 * its vertex on the screen (the vertex is clamped to the cell); without it, brightness and contour
 * tests kept refining sub-pixel cells, so that far views drew several triangles per covered
 * pixel. See plodSelector.h for the formulas as implemented.
 *
 * Units: ContourTolerance in pixels (default 1). BrightnessTolerance in brightness x pixels,
 * brightness being reflectance x luminance-weighted light intensity in [0, 1] (default 4: a
 * cell may span 4 pixels over which its shading could vary by the full range 1, or 16 over
 * which it varies by 0.25). The screen distance d_s is (viewport height / 2) / tan(view angle
 * / 2) pixels, or ViewingDistance / PixelPitch for a physical display.
 *
 * Modes of the same walk, so that they compare on equal terms:
 * - error model: SRCC (default), SCVC (ShapeError d_s / d_o <= ContourTolerance everywhere),
 *   PSEC (the same, with the tolerance times PSECFactor on the contour and where the cone holds
 *   a light's half vector; the factor 0.25 is this project's choice), Distance (Wang & Sato: one
 *   level for the whole object, the coarsest whose cell edge is at most 2 n0 sin(view angle / 2)
 *   D / N, D the distance from the eye to the root's centre, N the viewport height,
 *   n0 = DistancePixelThreshold), Cheng (Cheng §2 as published: a cell is simplified when the
 *   cosine of the largest angle between two of its normals, cos(min(pi, 2 theta)), exceeds
 *   T = exp(-FoveationRate D); D = 0 without foveation or at the point of interest, where T = 1
 *   and every leaf is opened: full detail at the fovea; no tolerance is used);
 * - motion model: None (default); MicroMotion (TMM: v_m = M_p M_c v - v from the current and
 *   previous object->view matrices, v_f = v_m FrameInterval / PreviousFrameTime);
 *   InverseVelocity (IPV: factor max(1, s / InverseVelocitySpeed)); DirectVelocity (DPV: factor
 *   1 / (1 - s / DirectVelocitySpeed), the root alone once s >= DirectVelocitySpeed); s is the
 *   object's speed: the root-mean-square displacement v_f of the root cell's 8 corners, in pixels
 *   per FrameInterval at the distance of the root's centre (the centre alone would not move
 *   when the camera orbits about it); what the factor scales is the
 *   VelocityCriterion (by default velocity alone, as in TMM §5.3);
 * - foveation: in every mode but Cheng's test (IPV and DPV by velocity alone replace every
 *   error model, Cheng's included, and their size tolerance is multiplied too), the tolerances are
 * multiplied by exp(FoveationRate D) (this project's use of Cheng's distance with SRCC: the fovea
 * keeps the base tolerances); Object mode measures D about a vertical axis from FoveationPoint (D =
 * w_h beta / pi + w_v |Y - F_y| / H, H the root edge), Screen mode as the angle between the view
 * ray and GazeDirection, over pi.
 * - material: with the octree's DiffuseRange and SpecularRange, each light adds
 *   L (M_max c_max - M_min c_min) to the brightness change (TMM eq. 8-9), else the constant
 *   DiffuseReflectance and SpecularReflectance.
 * Frustum culling applies in every mode, and so does MinimumLevel (distributed rendering).
 *
 * Triangle budget (TriangleBudget, off by default): the best cut of at most that many triangles
 * under the same criteria, refined from the root in order of perceptual error over tolerance
 * (Luebke & Erikson 1997's budget-based simplification, with the tolerances as a floor).
 *
 * Monotonicity: lowering a tolerance never makes a drawn cell coarser, and faster micro motion
 * never makes one finer. Moving the eye away never makes a drawn cell finer once the eye is a
 * few object sizes away. Closer up, v_e turns as the eye moves, and a front-facing cell near
 * the silhouette can become a contour cell, which the shape test refines; that is SRCC's
 * behaviour, not an error.
 *
 * Coordinates: eye, frustum planes, lights, gaze and fovea are in the octree's (object)
 * coordinates, unless CoordinatesAreWorld is on: then they are in world coordinates and
 * ObjectToWorldMatrix (row-major 4x4, x_world = M x_object) maps the octree to the world.
 * Frustum planes are 6 x (a, b, c, d) with a x + b y + c z + d >= 0 inside, the layout of
 * vtkCamera::GetFrustumPlanes. Without planes (UseFrustum off) nothing is culled.
 *
 * The filter re-executes only when a value it uses changes (every setter compares), and never
 * makes the builder re-execute. Invalid input (NaN or infinite numbers, a viewport of zero or
 * negative width or height, reflectances outside [0, 1], negative light intensities) is
 * reported with vtkErrorMacro, naming the values, and leaves the previous output, cut included,
 * untouched (empty before the first valid frame).
 *
 * @sa vtkMultiscaleOctree vtkMultiscalePatchGenerator vtkPerceptualLODRenderBinding
 */
#ifndef vtkPerceptualLODSelector_h
#define vtkPerceptualLODSelector_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkMultiscaleOctreeAlgorithm.h"

#include <memory> // for the internals
#include <string> // for the empty-cut reason

class vtkMultiscaleOctree;
namespace plod
{
struct FrameView;
struct OctreeView;
struct SelectionInput;
struct SelectionStats;
}

class PERCEPTUALLODFILTERS_EXPORT vtkPerceptualLODSelector : public vtkMultiscaleOctreeAlgorithm
{
public:
  static vtkPerceptualLODSelector* New();
  vtkTypeMacro(vtkPerceptualLODSelector, vtkMultiscaleOctreeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Also newer when the input's pages read in the background have changed since the last cut
  /// (vtkMultiscaleOctree::SetBackgroundLoading): the next cut can then refine further.
  vtkMTimeType GetMTime() override;

  enum ErrorModels
  {
    ERROR_SRCC = 0,
    ERROR_SCVC = 1,
    ERROR_PSEC = 2,
    ERROR_DISTANCE = 3,
    ERROR_CHENG = 4
  };
  enum MotionModels
  {
    MOTION_NONE = 0,
    MOTION_MICRO = 1,
    MOTION_INVERSE_VELOCITY = 2,
    MOTION_DIRECT_VELOCITY = 3
  };
  enum FoveationModes
  {
    FOVEATION_OFF = 0,
    FOVEATION_OBJECT = 1,
    FOVEATION_SCREEN = 2
  };

  ///@{
  /// Error model. Default ERROR_SRCC.
  vtkSetClampMacro(ErrorModel, int, ERROR_SRCC, ERROR_CHENG);
  vtkGetMacro(ErrorModel, int);
  void SetErrorModelToSRCC() { this->SetErrorModel(ERROR_SRCC); }
  void SetErrorModelToSCVC() { this->SetErrorModel(ERROR_SCVC); }
  void SetErrorModelToPSEC() { this->SetErrorModel(ERROR_PSEC); }
  void SetErrorModelToDistance() { this->SetErrorModel(ERROR_DISTANCE); }
  void SetErrorModelToCheng() { this->SetErrorModel(ERROR_CHENG); }
  ///@}

  ///@{
  /// Motion model. Default MOTION_NONE.
  vtkSetClampMacro(MotionModel, int, MOTION_NONE, MOTION_DIRECT_VELOCITY);
  vtkGetMacro(MotionModel, int);
  void SetMotionModelToNone() { this->SetMotionModel(MOTION_NONE); }
  void SetMotionModelToMicroMotion() { this->SetMotionModel(MOTION_MICRO); }
  void SetMotionModelToInverseVelocity() { this->SetMotionModel(MOTION_INVERSE_VELOCITY); }
  void SetMotionModelToDirectVelocity() { this->SetMotionModel(MOTION_DIRECT_VELOCITY); }
  ///@}

  enum VelocityCriteria
  {
    VELOCITY_ALONE = 0,             ///< TMM §5.3: one screen-space resolution set by the speed
    VELOCITY_SCALES_ERROR_MODEL = 1 ///< the error model's tolerances times the speed factor
  };
  ///@{
  /**
   * What IPV and DPV scale by the object's speed. VELOCITY_ALONE (default) is the baseline as
   * TMM §5.3 describes it: "only incorporates the criterion of velocity and thereby ignores
   * contours and shading". Every visible cell is refined until its edge projects within
   * ContourTolerance times the speed factor (no shape, contour, back-face or brightness test;
   * the error model is not consulted), so at rest the object is drawn with cells of at most
   * ContourTolerance pixels: full detail to the eye. VELOCITY_SCALES_ERROR_MODEL multiplies both
   * tolerances of the chosen error model (SRCC by default) by the factor: a stronger baseline,
   * kept as an option because it is what this project measured before.
   */
  vtkSetClampMacro(VelocityCriterion, int, VELOCITY_ALONE, VELOCITY_SCALES_ERROR_MODEL);
  vtkGetMacro(VelocityCriterion, int);
  void SetVelocityCriterionToAlone() { this->SetVelocityCriterion(VELOCITY_ALONE); }
  void SetVelocityCriterionToScalesErrorModel()
  {
    this->SetVelocityCriterion(VELOCITY_SCALES_ERROR_MODEL);
  }
  ///@}

  ///@{
  /// Foveation. Default FOVEATION_OFF.
  vtkSetClampMacro(FoveationMode, int, FOVEATION_OFF, FOVEATION_SCREEN);
  vtkGetMacro(FoveationMode, int);
  void SetFoveationModeToOff() { this->SetFoveationMode(FOVEATION_OFF); }
  void SetFoveationModeToObject() { this->SetFoveationMode(FOVEATION_OBJECT); }
  void SetFoveationModeToScreen() { this->SetFoveationMode(FOVEATION_SCREEN); }
  /// K of exp(K D). Default 2.
  vtkSetMacro(FoveationRate, double);
  vtkGetMacro(FoveationRate, double);
  /// Object mode: point of interest. Default (0, 0, 0).
  vtkSetVector3Macro(FoveationPoint, double);
  vtkGetVector3Macro(FoveationPoint, double);
  /// Object mode: the vertical axis (through the root's centre). Default (0, 1, 0).
  vtkSetVector3Macro(FoveationUp, double);
  vtkGetVector3Macro(FoveationUp, double);
  /// Object mode: w_h, w_v. Default (1, 1).
  vtkSetVector2Macro(FoveationWeights, double);
  vtkGetVector2Macro(FoveationWeights, double);
  /// Screen mode: gaze ray direction from the eye. Default (0, 0, -1).
  vtkSetVector3Macro(GazeDirection, double);
  vtkGetVector3Macro(GazeDirection, double);
  ///@}

  enum BackFaceModes
  {
    BACK_FACES_AUTOMATIC = 0, ///< hidden when the octree's surface is closed, else drawn
    BACK_FACES_HIDDEN = 1,    ///< SRCC: hidden, for closed surfaces
    BACK_FACES_DRAWN = 2      ///< drawn at the level where they are found, not refined
  };

  ///@{
  /**
   * Back-facing cells (gamma > pi/2 + theta). SRCC hides them, which assumes a closed surface
   * whose back faces are occluded. Through a hole of an open surface (a range scan, a mesh with
   * holes like the Stanford bunny's base) VTK draws the back faces and the viewer sees them:
   * hidden, they leave the background showing inside the silhouette. BACK_FACES_AUTOMATIC (the
   * default) hides them only when the octree's surface has no boundary edge
   * and its triangles agree on their orientation (vtkMultiscaleOctree's
   * GetNumberOfBoundaryEdges() and GetNumberOfMisorientedEdges() both 0: through a triangle
   * facing the other way a closed surface would show a hole), else draws them at the level where
   * they are found (still not refined). SetHideBackFaces(bool) chooses HIDDEN or DRAWN.
   * Hiding them on an open or inconsistently oriented surface opens see-through holes; drawing
   * them on a closed one costs triangles for nothing (docs/results/analysis.md).
   */
  vtkSetClampMacro(BackFaceMode, int, BACK_FACES_AUTOMATIC, BACK_FACES_DRAWN);
  vtkGetMacro(BackFaceMode, int);
  void SetBackFaceModeToAutomatic() { this->SetBackFaceMode(BACK_FACES_AUTOMATIC); }
  void SetBackFaceModeToHidden() { this->SetBackFaceMode(BACK_FACES_HIDDEN); }
  void SetBackFaceModeToDrawn() { this->SetBackFaceMode(BACK_FACES_DRAWN); }
  void SetHideBackFaces(bool hide)
  {
    this->SetBackFaceMode(hide ? BACK_FACES_HIDDEN : BACK_FACES_DRAWN);
  }
  void HideBackFacesOn() { this->SetHideBackFaces(true); }
  void HideBackFacesOff() { this->SetHideBackFaces(false); }
  /// Whether the last execution hid back faces (the automatic mode's decision).
  vtkGetMacro(HidBackFaces, bool);
  ///@}

  ///@{
  /// Tolerances: contour T_s in pixels (default 1), brightness T_b (default 4), see above;
  /// topology: cells that are not topologically safe are refined while their thickness (the
  /// part collapsing them could make vanish) projects to more than this many pixels (default 1;
  /// a huge value turns the rule off).
  vtkSetMacro(ContourTolerance, double);
  vtkGetMacro(ContourTolerance, double);
  vtkSetMacro(BrightnessTolerance, double);
  vtkGetMacro(BrightnessTolerance, double);
  vtkSetMacro(TopologyTolerance, double);
  vtkGetMacro(TopologyTolerance, double);
  /// The default contour and brightness tolerances times `scale`: T_s = scale pixels and
  /// T_b = 4 scale (SRCC's preset, T_b = 4 T_s). One knob for coarser or finer cuts; the
  /// topology tolerance is left as it is.
  void ScaleTolerances(double scale);
  ///@}

  ///@{
  /**
   * For distributed rendering: cells coarser than this level are incomplete on each rank (each
   * process holds a piece of the mesh, complete only in cells of this level and finer), so every
   * cell of a level below it is refined without any test but the frustum's: it is never
   * accepted, never hidden as back-facing, and culled only when its box lies wholly outside a
   * frustum plane. A leaf coarser than it is opened. Default 0 (no effect), clamped to [0, 21].
   * The input's vtkMultiscaleOctree::GetCoarsestDrawnLevel (an octree assembled from pieces)
   * raises it for that octree.
   * Every process must also use the whole's back-face mode, set explicitly (BACK_FACES_HIDDEN
   * for a closed whole): the automatic mode looks at each process's piece, which is open, and
   * would draw back faces the whole hides. See vtkMultiscaleOctreeBuilder for the rest of the
   * scheme.
   */
  vtkSetClampMacro(MinimumLevel, int, 0, 21);
  vtkGetMacro(MinimumLevel, int);
  ///@}

  ///@{
  /**
   * Triangle budget: at most this many triangles (default 0: no budget). The cut is then the
   * best one the budget allows under the same criteria: starting from the root, the cells the
   * tolerances would refine are refined in order of priority, how far their error exceeds
   * their tolerance (SRCC: the larger of contour error / ContourTolerance and brightness error /
   * BrightnessTolerance, with the motion and foveation factors; the other models: the ratio of
   * their own test), while their triangles fit (BudgetStopRule says what happens to a refinement
   * that does not). The tolerances stay
   * a floor: a cell they accept is never refined, so a budget larger than the tolerance cut's
   * triangles gives the tolerance cut exactly. Cells left unrefined by the budget are drawn at
   * their vertex with CutReason 8 (plod::BudgetLimited). The budget counts what is drawn
   * (GetNumberOfBudgetTriangles): of the triangles the cut's refined cells own
   * (GetNumberOfCutTriangles), not those another process draws (ghosts) and, when back faces
   * are hidden, not those whose input face turns away from the eye, the rule by which
   * vtkMultiscalePatchGenerator culls them. It is exact for opened leaves (drawn on their input
   * points) and an estimate for the triangles of refined cells, which are drawn on
   * representative vertices that can turn a face near the contour: docs/results/budget.md
   * measures how far the drawn count strays from the budget. Counting costs a test per
   * triangle (the walk reads the triangles' points), so the selection takes longer with a
   * budget on a closed model (docs/benchmarks.md). Floors kept whatever the
   * budget: MinimumLevel and the cells holding the eye are always refined, so a budget smaller
   * than what they need is exceeded (GetBudgetWasBinding() is then true). Negative values are
   * clamped to 0. See plodSelector.h for the rules.
   */
  vtkSetClampMacro(TriangleBudget, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(TriangleBudget, vtkIdType);
  /// Whether the budget stopped refinement in the last execution before the tolerances were
  /// met (or the floors alone exceeded it). False without a budget.
  vtkGetMacro(BudgetWasBinding, bool);
  /// What the budget counted of the last cut: with a budget, the triangles it draws (see
  /// TriangleBudget), at most TriangleBudget unless the floors need more; without one, the
  /// cut's count (GetNumberOfCutTriangles: the drawn ones are not counted, which would cost a
  /// test per triangle).
  vtkGetMacro(NumberOfBudgetTriangles, vtkIdType);
  /// Triangles owned by the refined cells of the last cut (with or without a budget): what it
  /// draws at most.
  vtkGetMacro(NumberOfCutTriangles, vtkIdType);
  /// The triangles the refinements the budget left waiting own, each made one level: the cells
  /// drawn with CutReason 8, skipped ones included (0 when the budget did not bind). In the
  /// cut's count: NumberOfCutTriangles plus this is the tolerance cut's when the budget does
  /// not bind, and a lower bound of it when it does: what this selector asks for when several
  /// share one budget (vtkPerceptualLODRepresentation under MPI).
  vtkGetMacro(NumberOfWaitingTriangles, vtkIdType);
  /// With a budget: whether the last execution kept the tolerance walk's cut (it fitted the
  /// budget: see plodSelector.h, "Cost"), and how many cells the budget walk's parallel first
  /// pass judged (counted in GetNumberOfVisitedNodes; 0 without MultiThreaded or after a budget
  /// that did not bind). Diagnostics: the cut is the same either way.
  vtkGetMacro(BudgetKeptToleranceCut, bool);
  vtkGetMacro(NumberOfCellsJudgedAhead, vtkIdType);
  ///@}

  enum BudgetStopRules
  {
    BUDGET_STOP_AT_FIRST_MISFIT = 0, ///< the first refinement that does not fit ends the walk
    BUDGET_SKIP_MISFITS = 1          ///< refinements that do not fit are skipped (default)
  };
  ///@{
  /**
   * What the triangle budget does with a refinement that does not fit in the room left.
   * BUDGET_SKIP_MISFITS (default) leaves it unrefined and goes on with the next ones, so the
   * budget fills; BUDGET_STOP_AT_FIRST_MISFIT ends the walk there, so that a larger budget always
   * refines a superset of what a smaller one refines. Skipping fills the budget more fully and is
   * never measurably worse at equal budget (docs/results/budget.md). Both are the tolerance cut
   * when it fits. See plodSelector.h.
   */
  vtkSetClampMacro(BudgetStopRule, int, BUDGET_STOP_AT_FIRST_MISFIT, BUDGET_SKIP_MISFITS);
  vtkGetMacro(BudgetStopRule, int);
  void SetBudgetStopRuleToStopAtFirstMisfit()
  {
    this->SetBudgetStopRule(BUDGET_STOP_AT_FIRST_MISFIT);
  }
  void SetBudgetStopRuleToSkipMisfits() { this->SetBudgetStopRule(BUDGET_SKIP_MISFITS); }
  ///@}

  ///@{
  /**
   * Exact triangle budget (on by default). On, the drawn triangles are counted after the walk
   * as the patch generator decides them, and the walk runs again with a smaller budget while
   * they exceed it (a larger one while they fill less than 95 % of it), so that no more than
   * TriangleBudget are drawn (unless the floors need more) with the patch generator's default
   * fold handling; this costs about one patch generation more per frame, and another walk and
   * count when the first misses. GetNumberOfBudgetTriangles is then the exact drawn count,
   * except where nothing needs counting: a budget that does not bind on a surface whose back
   * faces are drawn (and no ghosts) draws at most the cut's count, which it reports.
   * Off, the budget counts the back faces from the input triangles' corners (see
   * TriangleBudget), and vtkMultiscalePatchGenerator can draw a few percent more or fewer
   * triangles than the budget, for a selection 1.6 to 4 times cheaper (docs/benchmarks.md).
   * See plodSelector.h.
   */
  vtkSetMacro(ExactTriangleBudget, bool);
  vtkGetMacro(ExactTriangleBudget, bool);
  vtkBooleanMacro(ExactTriangleBudget, bool);
  ///@}

  ///@{
  /**
   * Incremental selection (off by default): each execution starts from the previous cut
   * instead of the root (Hoppe 1997, Luebke & Erikson 1997). Every cell of the previous cut is
   * judged again and refined where the tolerances now ask for it; a parent whose children are
   * all kept is judged and replaces them when it would no longer be refined. Every cell of the
   * cut then passes the tests at the current view, as in the full walk, but a coarser ancestor
   * that would now pass is found only level by level, so the cut can hold more cells than the
   * full walk's. Only without a triangle budget; the first execution (and the one after the
   * octree or the budget changes) is a full walk. It is compared with the full walk in
   * docs/benchmarks.md ("Selection speed and incremental selection"); see plodSelector.h for the
   * rules.
   */
  vtkSetMacro(IncrementalSelection, bool);
  vtkGetMacro(IncrementalSelection, bool);
  vtkBooleanMacro(IncrementalSelection, bool);
  ///@}

  ///@{
  /**
   * Walk the tolerance cut's subtrees in parallel with vtkSMPTools (default on): the top of the
   * tree is judged breadth first until enough subtrees wait, then each subtree is walked on its
   * own. The cut, reasons, cull masks and figures are the serial walk's, node for node, on any
   * number of threads. The budget walk (a global priority queue) and the incremental walk stay
   * serial.
   */
  vtkSetMacro(MultiThreaded, bool);
  vtkGetMacro(MultiThreaded, bool);
  vtkBooleanMacro(MultiThreaded, bool);
  ///@}

  ///@{
  /// The view. Eye position default (0, 0, 1); view angle in degrees (default 30); viewport
  /// size in pixels (default 1920 x 1080).
  vtkSetVector3Macro(EyePosition, double);
  vtkGetVector3Macro(EyePosition, double);
  vtkSetMacro(ViewAngle, double);
  vtkGetMacro(ViewAngle, double);
  vtkSetVector2Macro(ViewportSize, int);
  vtkGetVector2Macro(ViewportSize, int);
  /// Frustum planes (24 numbers, see above); setting them turns UseFrustum on.
  void SetFrustumPlanes(const double planes[24]);
  void GetFrustumPlanes(double planes[24]);
  vtkSetMacro(UseFrustum, bool);
  vtkGetMacro(UseFrustum, bool);
  vtkBooleanMacro(UseFrustum, bool);
  /// Parallel projection (default off): ParallelScale is half the viewport height in world
  /// units; the projection direction is the direction of projection of the camera.
  vtkSetMacro(ParallelProjection, bool);
  vtkGetMacro(ParallelProjection, bool);
  vtkBooleanMacro(ParallelProjection, bool);
  vtkSetMacro(ParallelScale, double);
  vtkGetMacro(ParallelScale, double);
  vtkSetVector3Macro(ProjectionDirection, double);
  vtkGetVector3Macro(ProjectionDirection, double);
  /// A physical display instead of pixels: d_s = ViewingDistance / PixelPitch (same units).
  vtkSetMacro(UsePhysicalDisplay, bool);
  vtkGetMacro(UsePhysicalDisplay, bool);
  vtkBooleanMacro(UsePhysicalDisplay, bool);
  vtkSetMacro(PixelPitch, double);
  vtkGetMacro(PixelPitch, double);
  vtkSetMacro(ViewingDistance, double);
  vtkGetMacro(ViewingDistance, double);
  /// Screen distance d_s in pixels as used (read-only).
  double GetScreenDistance();
  ///@}

  ///@{
  /// World coordinates: when on, the view, lights, gaze and fovea are in world coordinates and
  /// ObjectToWorldMatrix (row-major, x_world = M x_object) places the octree. Default off.
  vtkSetMacro(CoordinatesAreWorld, bool);
  vtkGetMacro(CoordinatesAreWorld, bool);
  vtkBooleanMacro(CoordinatesAreWorld, bool);
  vtkSetVectorMacro(ObjectToWorldMatrix, double, 16);
  vtkGetVectorMacro(ObjectToWorldMatrix, double, 16);
  ///@}

  ///@{
  /**
   * Lights. Each has a type (positional or directional), a position or a direction towards the
   * light, and luminance-weighted diffuse and specular intensities (intensity x (0.2126 r +
   * 0.7152 g + 0.0722 b) of its colours), finite and >= 0 (a negative one is an error when the
   * filter executes). SetLight and SetNumberOfLights call Modified() only when something
   * changes.
   */
  void SetNumberOfLights(int n);
  int GetNumberOfLights();
  void SetLight(
    int index, bool positional, double x, double y, double z, double diffuse, double specular);
  void AddLight(bool positional, double x, double y, double z, double diffuse, double specular);
  void RemoveAllLights() { this->SetNumberOfLights(0); }
  /// Luminance of an RGB colour (Rec. 709 weights), to fold a light's colour into an intensity.
  static double Luminance(double r, double g, double b)
  {
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
  }
  ///@}

  ///@{
  /// Material used where the octree has no material arrays: diffuse (default 1), specular
  /// (default 0.3) reflectance, each in [0, 1] (another value is an error when the filter
  /// executes), and specular power (default 20).
  vtkSetMacro(DiffuseReflectance, double);
  vtkGetMacro(DiffuseReflectance, double);
  vtkSetMacro(SpecularReflectance, double);
  vtkGetMacro(SpecularReflectance, double);
  vtkSetMacro(SpecularPower, double);
  vtkGetMacro(SpecularPower, double);
  ///@}

  ///@{
  /**
   * Motion: object->view matrices (row-major 4x4) of this frame and of the previous one, the
   * previous frame's time t_m in seconds and the frame interval dt (default 1/60 s). Without a
   * previous matrix, or with t_m = 0, there is no motion.
   */
  vtkSetVectorMacro(ObjectToViewMatrix, double, 16);
  vtkGetVectorMacro(ObjectToViewMatrix, double, 16);
  vtkSetVectorMacro(PreviousObjectToViewMatrix, double, 16);
  vtkGetVectorMacro(PreviousObjectToViewMatrix, double, 16);
  vtkSetMacro(HasPreviousFrame, bool);
  vtkGetMacro(HasPreviousFrame, bool);
  vtkBooleanMacro(HasPreviousFrame, bool);
  vtkSetMacro(PreviousFrameTime, double);
  vtkGetMacro(PreviousFrameTime, double);
  vtkSetMacro(FrameInterval, double);
  vtkGetMacro(FrameInterval, double);
  /// IPV: full detail up to this speed (pixels per frame interval), then 1/speed. Default 4.
  vtkSetMacro(InverseVelocitySpeed, double);
  vtkGetMacro(InverseVelocitySpeed, double);
  /// DPV: detail falls linearly to zero (root alone) at this speed. Default 64.
  vtkSetMacro(DirectVelocitySpeed, double);
  vtkGetMacro(DirectVelocitySpeed, double);
  /// The object's speed used by IPV and DPV in the last execution (pixels per frame interval).
  vtkGetMacro(ObjectSpeed, double);
  ///@}

  ///@{
  /// Baselines' constants: PSEC tolerance factor on features (default 0.25); Wang & Sato's
  /// pixel threshold n0 (default 1).
  vtkSetMacro(PSECFactor, double);
  vtkGetMacro(PSECFactor, double);
  vtkSetMacro(DistancePixelThreshold, double);
  vtkGetMacro(DistancePixelThreshold, double);
  /// Level chosen by the Distance model in the last execution.
  vtkGetMacro(DistanceLevel, int);
  ///@}

  ///@{
  /// Figures of the last execution.
  vtkGetMacro(NumberOfVisitedNodes, vtkIdType);
  vtkGetMacro(NumberOfCutNodes, vtkIdType);
  vtkGetMacro(NumberOfDrawnNodes, vtkIdType);
  /// Leaves drawn at full resolution, and cells refined only for their topology.
  vtkGetMacro(NumberOfOpenedLeaves, vtkIdType);
  vtkGetMacro(NumberOfTopologyRefinedNodes, vtkIdType);
  /// Cells drawn coarser while their pages are read (CutReason 9; background loading, see
  /// vtkMultiscaleOctree::SetBackgroundLoading): the view is still refining.
  vtkGetMacro(NumberOfAwaitingCells, vtkIdType);
  /// Cells whose foveation factor exp(FoveationRate D) was computed. With screen foveation the
  /// walk first bounds it from a table and computes it only where a test falls within the
  /// bounds (a fraction of a percent of the cells; the cut is the same to the bit).
  vtkGetMacro(NumberOfFoveationFactors, vtkIdType);
  /**
   * Why the last cut draws no triangle, or an empty string when it draws some: the model is
   * outside the frustum; every cell faces away; or the root alone was accepted (it is one
   * point: the model covers about a pixel, the tolerances are huge, or DPV's speed limit was
   * reached, where TMM's DPV draws zero polygons by definition).
   */
  const char* GetEmptyCutReason() { return this->EmptyCutReason.c_str(); }
  /// Wall-clock seconds of the last selection.
  vtkGetMacro(SelectTime, double);
  ///@}

  /// Name of the node array holding each cut cell's reason.
  static const char* CutReasonArrayName() { return "CutReason"; }

protected:
  vtkPerceptualLODSelector();
  ~vtkPerceptualLODSelector() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  ///@{
  /// The steps of RequestData.
  /// The input's checked view; false (the output to be emptied) for an empty or invalid octree.
  bool TakeOctree(vtkMultiscaleOctree* input, plod::OctreeView& view, vtkMTimeType& viewStamp);
  /// What is wrong with the parameters ("" when nothing).
  std::string CheckParameters();
  /// The kernel's input from the settings and the view model; what is wrong ("" when nothing).
  std::string MakeSelectionInput(
    vtkMultiscaleOctree* input, const plod::OctreeView& view, plod::SelectionInput& in);
  /// The view model's input (plodViewModel.h) from the camera, lights and motion settings.
  plod::FrameView MakeFrame();
  /// The kernel's walk into the cut arrays (made again when the octree changed); its exact
  /// count remembers corner walks in the input's memo (shared with the patch generator).
  void Select(vtkMultiscaleOctree* input, const plod::OctreeView& view, vtkMTimeType viewStamp,
    const plod::SelectionInput& in, plod::SelectionStats& stats);
  /// The output: the input's arrays, the cut's, and the view the cut was made for.
  void MakeOutput(
    vtkMultiscaleOctree* input, const plod::SelectionInput& in, vtkMultiscaleOctree* output);
  /// EmptyCutReason for a cut that draws no triangle.
  void ExplainEmptyCut(const plod::SelectionInput& in, const plod::SelectionStats& stats);
  /// The figures of the Get...() methods from the walk's.
  void RecordFigures(const plod::SelectionStats& stats);
  ///@}

  int ErrorModel;
  int MotionModel;
  int VelocityCriterion;
  int FoveationMode;
  double FoveationRate;
  double FoveationPoint[3];
  double FoveationUp[3];
  double FoveationWeights[2];
  double GazeDirection[3];
  int BackFaceMode;
  bool HidBackFaces;
  double ContourTolerance;
  double BrightnessTolerance;
  double TopologyTolerance;
  int MinimumLevel;
  vtkIdType TriangleBudget;
  int BudgetStopRule;
  bool ExactTriangleBudget;
  bool IncrementalSelection;
  bool MultiThreaded = true;
  double EyePosition[3];
  double ViewAngle;
  int ViewportSize[2];
  double FrustumPlanes[24];
  bool UseFrustum;
  bool ParallelProjection;
  double ParallelScale;
  double ProjectionDirection[3];
  bool UsePhysicalDisplay;
  double PixelPitch;
  double ViewingDistance;
  bool CoordinatesAreWorld;
  double ObjectToWorldMatrix[16];
  double DiffuseReflectance;
  double SpecularReflectance;
  double SpecularPower;
  double ObjectToViewMatrix[16];
  double PreviousObjectToViewMatrix[16];
  bool HasPreviousFrame;
  double PreviousFrameTime;
  double FrameInterval;
  double InverseVelocitySpeed;
  double DirectVelocitySpeed;
  double PSECFactor;
  double DistancePixelThreshold;

  double ObjectSpeed;
  int DistanceLevel;
  vtkIdType NumberOfVisitedNodes;
  vtkIdType NumberOfCutNodes;
  vtkIdType NumberOfDrawnNodes;
  vtkIdType NumberOfOpenedLeaves;
  vtkIdType NumberOfTopologyRefinedNodes;
  vtkIdType NumberOfAwaitingCells = 0;
  vtkIdType NumberOfFoveationFactors = 0;
  bool BudgetWasBinding;
  vtkIdType NumberOfBudgetTriangles;
  vtkIdType NumberOfCutTriangles;
  vtkIdType NumberOfWaitingTriangles;
  bool BudgetKeptToleranceCut = false;
  vtkIdType NumberOfCellsJudgedAhead = 0;
  std::string EmptyCutReason;
  double SelectTime;

private:
  vtkPerceptualLODSelector(const vtkPerceptualLODSelector&) = delete;
  void operator=(const vtkPerceptualLODSelector&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
