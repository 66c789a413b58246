// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodSelector.h
 * @brief VTK-free perceptual level-of-detail selection (SRCC §3.3-3.5, TMM §3-4, Wang & Sato
 * eq. 1-2, Cheng §2): walks the octree from the root and writes a cut.
 *
 * Every test is expressed in pixels through one scale `k` (pixels per unit length at the
 * cell's representative vertex v): `k = d_s / d_o` in perspective (d_s = screen distance in
 * pixels, d_o = |eye - v|), `k = viewport height / (2 parallel scale)` in parallel projection.
 * So SRCC eq. (5) `tan psi_s <= T_s / d_s` becomes `(dE - |n.v_f|) k <= T_s`, and eq. (10)
 * `dB d_s tan psi_b <= T_b` becomes `dB (l_p (n.v_e) - |v_d.v_f|) k <= T_b`.
 *
 * Walk (SRCC §3.5), from the root:
 * 1. Frustum: a cell whose box is wholly outside one plane is hidden (in the cut, not drawn)
 *    and not refined.
 * 2. Contour, with `c = n.v_e` and `s = sin(theta)` (no trigonometry per node):
 *    (a) `cos(theta) > 0` and `c > s` (gamma < pi/2 - theta): front-facing: go to 3;
 *    (b) `cos(theta) > 0` and `c < -s` (gamma > pi/2 + theta): back-facing: hidden, not
 *        refined;
 *    (c) otherwise on the contour (a cone wider than pi/2 always is): accept if
 *        `max(0, dE - |n.v_f|) k <= T_s`, then go to 3; else refine, each child through 1-3.
 * 3. Brightness: `dB = M_d sum L_d dC_alpha + M_s sum L_s dC_beta` (eq. 8) with
 *    `dC = c(max(0, a - theta)) - c(min(pi, a + theta))`, `c(x) = max(0, cos x)` (raised to the
 *    specular power for dC_beta, with the half vector), at most 1 (a rendered pixel saturates:
 *    summing stops there, so many bright lights cost no more than a few); accept if
 *    `dB max(0, l_p max(0, n.v_e) - |v_d.v_f|) k <= T_b`; else each child through 3 only.
 * 4. A leaf that is reached and fails a test is opened: it is drawn at full resolution, its
 *    own input points and triangles (a leaf that passes is drawn at its representative vertex).
 * A tolerance of 0 accepts nothing, even a cell whose error is exactly 0 (an unlit or flat
 * cell), so that zero tolerances give the full-resolution cut: the input itself.
 * Size floor (every mode but Distance and Cheng's test, after the frustum and back-face tests;
 * in SRCC not for the cells tested for brightness only, whose parent passed its contour test): a
 * cell whose edge projects to at most T_s pixels is accepted. Its points lie within about that many
 * pixels of its vertex, so refining it cannot change the image by more than the tolerance. Without
 * it, wide cones (noisy scans) put almost every cell "on the contour", where a shape error that
 * spans up to the cell's diagonal drove cells below a pixel: 3.4 triangles per covered pixel
 * on Lucy seen from afar.
 * Topology: a cell whose sub-mesh is not a union of discs (no NodeTopologySafe flag: a tube, a
 * handle) is refined, whatever its errors, while its Thickness (the part collapsing it could
 * make vanish) projects to more than TopologyTolerance pixels (times the motion and foveation
 * factor, like the other tolerances): collapsing a tube drops its triangles. Judging by the
 * thickness and not the cell's size matters for thin features seen from afar: a ring 0.6 pixel
 * thick was refined to sub-pixel cells at 10 triangles per covered pixel.
 * Back-facing and culled cells are hidden first: they are not refined.
 * Boundaries (SRCC mode): a cell holding a rim of an open surface (NodeBoundary) is refined until
 * it passes the size floor, as a contour cell would: a rim is a silhouette from every side, and
 * its flat neighbourhood would otherwise pass the brightness test with large cells and pull the
 * rim inwards.
 * A cell containing the eye is always refined (its error is unbounded); the eye on a vertex
 * counts as inside.
 *
 * Brightness with a material that varies inside the cell (TMM eq. 8-9): each light's term is
 * `L (M_max c_max - M_min c_min)`, the brightest shading the cell can show (largest reflectance,
 * largest cosine) minus the darkest (smallest reflectance, smallest cosine). With one material,
 * M_min = M_max and it is SRCC's `M L dC`.
 *
 * Baselines, as modes of the same walk: SCVC (`dE k <= T_s` everywhere), PSEC (the same with
 * the tolerance multiplied by PSECFactor on the contour and where the cone contains a light's
 * half vector; no diffuse term; the factor 0.25 is this project's choice, the seeds give none),
 * Distance (one level for the whole object, chosen by the caller with Wang & Sato eq. 1-2),
 * Cheng (the paper's test alone: a cell is simplified when the cosine of its largest normal
 * deviation exceeds `exp(-K D)`, so the fovea keeps full detail). Motion: micro motion (TMM eq.
 * 6-7, 11-13) reduces the errors by the per-vertex displacement `v_f = A v + b`; IPV and DPV
 * take one factor of the object's speed: by default (VelocityCriterion::Alone, TMM §5.3: "only
 * incorporates the criterion of velocity and thereby ignores contours and shading") every cell
 * is refined until its edge projects within `T_s` times the factor; ScalesErrorModel multiplies
 * both tolerances of the error model instead. Foveation with the other modes multiplies the
 * tolerances by `exp(K D)` (this project's combination of Cheng's D with SRCC); IPV and DPV by
 * velocity alone replace every error model, Cheng's included, so there the size test's
 * tolerance is multiplied too.
 * Frustum culling and the eye-inside rule apply in every mode; the topology rule (tubes) in every
 * mode but Cheng's.
 * Minimum level (distributed rendering): a cell coarser than SelectionInput::MinimumLevel is
 * refined without any test but the frustum's (step 1), in every mode: its content is
 * incomplete in each process's piece, so its errors, cone and vertex say nothing about the
 * whole surface. A leaf coarser than it is opened.
 *
 * One decision per cell: the tests above are one function (Judge in the .cxx) that every walk
 * below calls, so that they cannot drift apart. It answers hide, draw (with the reason) or
 * refine (with what the children are tested for) and, for the budget walk, the priority. The
 * error model is chosen once per frame (SRCC, the baselines, velocity alone or Cheng's test)
 * and each walk is compiled for each, so a walk tests only what its model needs.
 *
 * Triangle budget (SelectionInput::TriangleBudget > 0): priority-queue refinement from the root
 * (Luebke & Erikson 1997's budget-based simplification; Hoppe 1997 and Duchaineau et al. 1997,
 * ROAM, refine the same way), with the tolerances as a floor:
 * - A cell the walk would accept, hide or cull is handled exactly as above: the budget never
 *   refines a cell the tolerances accept. A cell the walk would refine waits in a max-heap,
 *   keyed by its priority, how far its error exceeds its tolerance: SRCC, for a cell refined
 *   for its contour (or its rim), the larger of contour error / T_s and brightness error / T_b,
 *   for a cell refined for its brightness, brightness error / T_b (TMM's motion reductions in the
 * errors, IPV/DPV's and foveation's factors in T_s and T_b, as in the walk; a rim's contour error
 * is its projected edge, h k); SCVC and PSEC, the shape error over their (PSEC: feature) tolerance;
 * Distance, the cell's edge over the chosen level's, 2^(level chosen - level); velocity alone, the
 * projected edge over T_s; Cheng, the normal deviation 1 - cos(min(pi, 2 theta)) (2 sin^2(theta) up
 * to theta = pi/2, then 2) over the allowed one, 1 - exp(-K D) (infinite at the fovea). A cell that
 * is not topologically safe (refined for its topology), or under a zero tolerance, is infinitely
 *   over: it goes first among the keys it can have (below).
 * - Monotone keys: a cell's key is its priority, but at most the key of the refinement that
 *   reached it (ROAM's monotone priorities). The queue then yields keys in non-increasing order.
 *   Without it, a larger budget could leave a larger key in the cut in the foveated modes, Cheng's
 * above all: a child nearer the gaze exceeds its tolerance by more than its parent. Equal keys go
 * to the larger own priority, then to the smaller node index (the coarser cell: nodes are stored
 * level by level). Keys are compared in single precision.
 * - Stop rule (SelectionInput::BudgetStop): the top refinement is made if the triangles it adds
 *   fit. When it does not fit (a misfit):
 *   StopAtFirstMisfit ends the walk there. The pops are then the same for every budget up to
 *   the stop, so a larger budget refines a superset of what a smaller one refines.
 *   SkipMisfits (default) leaves the misfit unrefined and goes on with the next refinements in key
 * order, skipping each that does not fit, until the queue is empty. Cut-off: the walk counts
 *   the queued refinements by the triangles they own (from 1 to 63; they count at most that);
 *   once the room left is below 64 and none of them surely fits it, only refinements owning no
 *   triangle (a cell whose triangles all lie within its children) are still made, and in any
 *   order, since the room no longer changes. One linear pass over the queue then makes those and
 * draws the others, instead of a heap pop each (which cost +45 % of the walk's time on the
 * benchmark scene at 25 % of its tolerance cut, where the queue held 2,300 cells and 161
 * refinements adding nothing were made after the first misfit); the walk goes on in key order with
 * what they queue. With the cut's count (below) the cut is the one popping the whole queue would
 * give; with the drawn one, a refinement owning more triangles than the room but counting no more
 * is drawn rather than refined (at most 63 triangles of the budget left unused). When the walk
 * ends, no cell left unrefined by the budget owns few enough triangles to fit in the room left.
 *   Cuts no longer nest, but both rules make
 *   the same pops up to the first misfit, so SkipMisfits refines a superset of what
 *   StopAtFirstMisfit refines at the same budget, and its first misfit is the stop rule's.
 *   Either way the first misfit's key is the largest key left in the cut (keys leave the queue in
 *   non-increasing order: whatever is pushed after it is reached from a smaller key), and it is
 *   non-increasing as the budget grows (SelectionStats::BudgetRefusedPriority). The cells left
 *   unrefined are drawn at their vertex, reason BudgetLimited.
 *   SkipMisfits is the default because at equal budget it is never measurably worse and often
 *   better (the refinements that add no triangle, made after the room is spent, refine
 *   vertices for free), fills the budget more fully and costs little more CPU; the nesting it
 *   gives up changes very few cells (docs/results/budget.md, docs/benchmarks.md).
 * - The count, of what is drawn: a cut draws the triangles owned by its refined nodes and
 *   opened leaves (plodOctree.h, plodPatches.h), so refining node n can add TriangleEnd(n) -
 *   FirstTriangle[n], opening a leaf its own (SelectionStats::CutTriangles sums them; the root
 *   alone counts 0, it is one point). Of those the budget counts the ones GeneratePatches
 *   draws (SelectionStats::BudgetTriangles): not a triangle whose lead corner is a ghost
 *   (another process draws it) and, with HideBackFaces, not one whose face turns away from the
 *   eye. The walk decides the facing on the input triangle's corners (for a whole cell at once
 *   where its normal cone faces the eye, or away from it, across the cell's angular size; else
 *   triangle by triangle), when the refinement leaves the queue. That is exact for an opened
 *   leaf, whose triangles are drawn on their input points, and an estimate for a refined
 *   node's, drawn on representative vertices that can turn a face near the contour: measured,
 *   the drawn count strays a few percent above the budget at most (13 % at budgets of about a
 *   hundred triangles) and falls up to 22 % below it close up, where the triangles among cells
 *   outside the frustum are counted (docs/results/budget.md). SelectionInput::ExactBudget
 *   removes the excess: after the walk the drawn triangles are counted as GeneratePatches
 *   decides them (CountDrawnTriangles: every corner's representative, about the cost of making
 *   the patches), and the walk runs again with the budget scaled by budget / drawn, down (by at
 *   least the excess, doubled at each walk still over) while they exceed the budget and up (at
 *   least one more) while they fill less than 95 % of it; the largest budget found that fits
 *   is kept. Without back faces hidden or ghosts the walk's count is the cut's, which bounds
 *   the drawn count from above: a cut that did not bind then draws no more than the budget,
 *   and it is not counted (BudgetTriangles stays the cut's count: counting would cost a patch
 *   generation to tell how far below the budget the drawn count lies). Counting the back faces
 * reads the corners of every counted triangle, which the walk otherwise never touches: the budget
 * walk takes two to three times as long on a closed scan (docs/benchmarks.md).
 * - Floors: the cells holding the eye and those coarser than MinimumLevel are refined at once,
 *   whatever the budget: the first because its error is unbounded, the second because the
 *   distributed pieces must agree. When they alone exceed the budget, the count exceeds it and
 *   BudgetBinding says so. The topology rule is not a floor: it waits for the budget, first.
 * - When the tolerance cut fits (its count is at most the budget), the budget walk refines the
 *   same cells, so its cut is the tolerance cut, node for node, states, reasons and cull masks.
 *
 * Cost: the queue walk visits fewer nodes per second than the depth-first walk (the heap's pops
 * and the lost memory locality) and runs on one thread; a binding budget visits far fewer nodes
 * than the tolerance walk. A budget that does not bind would cost more than the tolerance walk,
 * so the tolerance cut is tried first (SelectionInput::ToleranceCutFirst) when the last budget
 * walk on the octree did not bind: the tolerance walk (in parallel with SetParallelFor) counts
 * what the budget counts, refinement by refinement, and gives up as soon as the count exceeds
 * the budget. When its cut fits, it is the budget walk's cut (above), node for node, with the
 * same figures but Visited and FoveationFactors, and it is kept
 * (SelectionStats::BudgetToleranceCut); otherwise its cells are cleared and the queue walk runs.
 * A frame where the budget starts to bind thus pays for a tolerance walk cut short near the
 * budget's count, and the next frame goes straight to the queue walk. The queue walk itself is
 * one heap, but most of its time goes into judging cells and counting their triangles, and
 * those depend only on the cell and on what its parent passes down (its key too: its priority
 * and its parent's key). So with SetParallelFor, after a binding walk, a first pass judges
 * ahead, in parallel subtrees, the cells below every refinement whose key is at least the last
 * walk's first misfit (the refinements the walk makes, give or take the camera's motion), and
 * counts those refinements' triangles (SelectionStats::BudgetJudgedAhead). The walk then
 * replays those decisions where it meets them, in the order in which it would have made them,
 * and judges the cells it reaches beyond them itself: its queue holds the same refinements in
 * the same places, so the cut and every figure but Visited and FoveationFactors are the serial
 * walk's, on any number of threads. The alternative, scaling both
 * tolerances by one factor found by bisection (a full walk per step), costs more as soon as it
 * needs more than about one and a half walks a frame, and its cut follows one scale for every
 * tolerance rather than the order of the errors (docs/benchmarks.md, "Triangle budget").
 *
 * Incremental selection (SelectionInput::Incremental, after Hoppe 1997 and Luebke & Erikson
 * 1997, who update the previous frame's front instead of walking from the root):
 * 1. Every cell of the previous cut is judged again, with every test: no "brightness only"
 *    from a parent whose contour decision is not judged again this frame, and no frustum plane
 *    known inside (the frustum moved). Kept, it stays (its state and reason rewritten); refined,
 *    the walk goes on below it, every cell judged with every test.
 * 2. Coarsening, pass after pass while a parent collapses: a parent whose children are all in
 *    the cut and kept (drawn or hidden, none opened) is judged, and replaces them when it is
 *    no longer refined.
 * So every cell of the cut passes its tests at the current view (Refines() is false for it,
 * true for an opened leaf) and every parent of kept cells would still be refined. What it does
 * not find is a coarser ancestor further up that would now pass: the full walk's cut may be
 * coarser, and it can also be finer, since the full walk tests a cell below a contour-accepted
 * parent for brightness only. The count (BudgetTriangles) is kept exactly. Without a previous
 * tolerance cut (first frame, new octree, a budget) the full walk runs, and records its cut as
 * the front. On this project's octrees it is slower than the full walk per frame
 * (docs/benchmarks.md, "Selection speed and incremental selection"): a full walk judges the cut
 * and the refined cells above it, about a third as many with four children per refined cell,
 * while the incremental walk judges every cell of the cut and most parents of kept cells again,
 * so it saves few judgements and pays for its bookkeeping (parent and mark lookups, all six
 * frustum planes at every cell of the front). It stays an option, off by default.
 */
#ifndef plodSelector_h
#define plodSelector_h

#include "plodCut.h"
#include "plodOctree.h"
#include "plodPageLoader.h"
#include "plodParallel.h"
#include "plodPatches.h"
#include "plodResidentPages.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace plod
{

enum class ErrorModel
{
  SRCC = 0,
  SCVC = 1,
  PSEC = 2,
  Distance = 3,
  Cheng = 4 // Cheng's curvature test against the foveated threshold, nothing else
};

enum class MotionModel
{
  None = 0,
  MicroMotion = 1,
  InverseVelocity = 2,
  DirectVelocity = 3
};

/// What IPV and DPV scale by the object's speed.
enum class VelocityCriterion
{
  /// TMM §5.3: velocity alone, ignoring contours and shading. Cells are refined until their edge
  /// projects within T_s times the speed factor (a uniform screen-space resolution); the error
  /// model is not consulted.
  Alone = 0,
  /// Both tolerances of the chosen error model times the speed factor (a stronger baseline).
  ScalesErrorModel = 1
};

enum class FoveationMode
{
  Off = 0,
  Object = 1, // Cheng: D = w_h beta/pi + w_v |Y - F_y| / H about a vertical axis
  Screen = 2  // D = angle between the view ray through v and the gaze ray, over pi
};

/// Why a node is in the cut (node array "CutReason").
enum CutReason : uint8_t
{
  ReasonNone = 0,         // not in the cut
  AcceptedContour = 1,    // on the contour: contour and brightness tests passed
  AcceptedBrightness = 2, // front-facing: brightness test passed
  OpenedLeaf = 3,         // a leaf that failed a test: drawn at full resolution (CutOpen)
  Culled = 4,             // outside the view frustum (hidden)
  BackFacing = 5,         // whole cone facing away (hidden)
  AcceptedError = 6,      // SCVC, PSEC or Distance test passed
  AcceptedSize = 7,       // its edge projects within the contour tolerance
  BudgetLimited = 8,      // the tolerances would refine it; the triangle budget did not let it
  AwaitingPages = 9       // the tolerances would refine it; its pages are being read (PageLoader)
};

/// What the budget walk does with a refinement that does not fit in the room left (see
/// "Triangle budget" in the file documentation).
enum class BudgetStopRule
{
  /// The walk ends at it: a larger budget refines a superset of what a smaller one refines, but
  /// one costly refinement at the top of the queue can leave much of the budget unused.
  StopAtFirstMisfit = 0,
  /// It stays unrefined and the walk goes on with the next refinements, skipping each that does
  /// not fit: the budget fills, cuts of different budgets no longer nest.
  SkipMisfits = 1
};

/// A light in the octree's local coordinates (relative to its origin).
struct SelectorLight
{
  bool Positional = false;
  double Position[3] = { 0, 0, 1 }; // positional: position; directional: unit vector to light
  double Diffuse = 1;               // luminance-weighted diffuse intensity L_d
  double Specular = 1;              // luminance-weighted specular intensity L_s
};

/// Everything one frame's selection uses, in the octree's local coordinates.
struct SelectionInput
{
  ErrorModel Error = ErrorModel::SRCC;
  MotionModel Motion = MotionModel::None;
  FoveationMode Foveation = FoveationMode::Off;

  double Eye[3] = { 0, 0, 0 };
  bool UseFrustum = false;
  double Planes[6][4] = {}; // a x + b y + c z + d >= 0 inside
  bool Parallel = false;
  double ProjectionDirection[3] = { 0, 0, -1 }; // parallel projection: v_e = -direction
  /// Perspective: screen distance d_s in pixels. Parallel: pixels per unit length.
  double PixelScale = 1000;

  /// SRCC: back-facing cells are hidden (closed surfaces). Off: they are drawn (not refined),
  /// for open surfaces such as range scans, whose back faces can be seen.
  bool HideBackFaces = true;
  double ContourTolerance = 1;    // T_s, pixels
  double BrightnessTolerance = 4; // T_b, brightness x pixels
  double TopologyTolerance = 1;   // pixels; unsafe cells larger than this are refined

  std::vector<SelectorLight> Lights;
  bool UseOctreeMaterial = false; // take M_d, M_s from the octree's ranges (their maxima)
  double Diffuse = 1;             // M_d when the octree has no material
  double Specular = 0;            // M_s when the octree has no material
  double SpecularPower = 1;       // k

  /// Micro motion (TMM): v_f = A v + b, already scaled by dt / t_m.
  double MotionA[3][3] = {};
  double MotionB[3] = {};
  /// IPV / DPV: tolerance factor (>= 1; infinity: root alone), from the object's speed.
  double VelocityFactor = 1;
  VelocityCriterion Velocity = VelocityCriterion::Alone;

  double PSECFactor = 0.25;
  int DistanceLevel = 0;

  double FoveationRate = 0;                // K
  double FoveationPoint[3] = { 0, 0, 0 };  // object mode: point of interest
  double FoveationUp[3] = { 0, 1, 0 };     // object mode: unit vertical axis
  double FoveationCentre[3] = { 0, 0, 0 }; // object mode: a point of the vertical axis
  double FoveationHeight = 1;              // object mode: H
  double FoveationWeights[2] = { 1, 1 };   // w_h, w_v
  double GazeDirection[3] = { 0, 0, -1 };  // screen mode: unit gaze ray from the eye

  /// Cells of a level below this one are always refined unless culled by the frustum (see the
  /// file documentation); 0 (default) changes nothing. In [0, MaxFinestLevel].
  int MinimumLevel = 0;

  /// At most this many triangles (see "Triangle budget" in the file documentation): the cut
  /// refines, in order of priority, the cells the tolerances would refine while their
  /// triangles fit. 0 or negative (default): no budget, the depth-first walk.
  int64_t TriangleBudget = 0;
  /// What the budget walk does with a refinement that does not fit (default SkipMisfits).
  BudgetStopRule BudgetStop = BudgetStopRule::SkipMisfits;
  /// With a budget: count the triangles drawn exactly, as GeneratePatches decides them, and walk
  /// again with a smaller budget while they exceed it, a larger one while they fill less than
  /// 95 % of it (see "The count" in the file documentation). Off (default): the walk's count,
  /// which estimates the back faces.
  bool ExactBudget = false;
  /// With a budget: when the last budget walk on this octree did not bind, try the tolerance
  /// walk's cut first and keep it when it fits (see "Cost" in the file documentation); the cut
  /// is the same either way. Off: the queue walk alone.
  bool ToleranceCutFirst = true;

  /// Start from the previous frame's cut instead of the root (see "Incremental selection" in
  /// the file documentation). Used only when the previous frame was a tolerance walk (no
  /// budget) on the same octree; otherwise the full walk runs and seeds the next frame.
  bool Incremental = false;
};

struct SelectionStats
{
  int64_t Visited = 0;
  int64_t InCut = 0;
  int64_t Drawn = 0;
  int64_t Opened = 0;          // leaves drawn at full resolution
  int64_t TopologyRefined = 0; // cells refined only because they are not topologically safe
  int64_t AwaitingPages = 0;   // cells drawn coarser while their pages are read (PageLoader)
  /// Cells whose foveation factor exp(K D) was computed (angle and exponential). Screen
  /// foveation's table bounds it first in the tolerance and incremental walks, and only cells
  /// whose tests fall within the bounds compute it (plodSelector.cxx, FoveaTable).
  int64_t FoveationFactors = 0;
  /// Triangles owned by the refined nodes and the opened leaves: what the cut draws at most
  /// (GeneratePatches may draw fewer: hidden cells, back faces, ghosts). Counted by every walk.
  int64_t CutTriangles = 0;
  /// What the budget counts (see "The count" in the file documentation): with a budget, the
  /// triangles of the cut GeneratePatches can draw, not the back faces or the ghosts'; without
  /// one, CutTriangles (counting the drawn ones costs a test per triangle, which nothing needs
  /// then).
  int64_t BudgetTriangles = 0;
  /// The budget stopped refinement before the tolerances were met, or the floors (eye inside,
  /// minimum level) alone exceed it.
  bool BudgetBinding = false;
  /// When the budget stopped refinement: the queue priority of the first refinement that did not
  /// fit (the largest left in the cut, with either stop rule) and the triangles it would have
  /// added to BudgetTriangles; else 0.
  double BudgetRefusedPriority = 0;
  int64_t BudgetRefusedTriangles = 0;
  /// The triangles that the refinements the budget left waiting own, each made one level (the
  /// refused one included, and with SkipMisfits every one skipped: the cells drawn as
  /// BudgetLimited); 0 when the budget did not stop refinement. In the cut's count (counting
  /// what they would draw would cost as much as refining them): CutTriangles plus this is the
  /// tolerance cut's CutTriangles when the budget does not bind, and a lower bound of it when
  /// it does: what a process asks for when several share one budget.
  int64_t BudgetWaitingTriangles = 0;
  /// With a budget: the tolerance walk's cut fitted and was kept, the queue walk did not run
  /// (SelectionInput::ToleranceCutFirst).
  bool BudgetToleranceCut = false;
  /// With a budget and Selector::SetParallelFor: the cells the queue walk's parallel first pass
  /// judged (in Visited; see "Cost" in the file documentation).
  int64_t BudgetJudgedAhead = 0;
};

namespace detail
{
/// A light as the walks read it, prepared once a frame (Selector keeps the storage): a
/// directional light's direction made a unit vector, with the length it was given (0: no
/// direction, it lights every direction).
struct PreparedLight
{
  bool Positional;
  double P[3];   // positional: position; directional: unit direction
  double Length; // directional: the given direction's length
  double Diffuse, Specular;
};

/// Screen foveation's factor tabulated for one rate (plodSelector.cxx, FoveaTable), kept from
/// frame to frame and rebuilt when the rate changes.
struct DrawnTally; // the budget's count of a tolerance walk tried first (plodSelector.cxx)

struct FoveaTable
{
  std::vector<double> Values; ///< empty until built
  double Rate = 0;
};
} // namespace detail

/// The difference of c(x) = max(0, cos x)^power over a cone: SRCC eq. (7) in one formula.
/// `cosA`, `sinA`: the angle between the light (or half) vector and the axis; cone angle theta.
double ConeCosineSpread(double cosA, double sinA, double cosT, double sinT, double power);

/// The largest and the smallest of c(x) = max(0, cos x)^power over the cone (the two terms of
/// ConeCosineSpread), for TMM eq. (9), which weighs them by different reflectances.
void ConeCosineRange(
  double cosA, double sinA, double cosT, double sinT, double power, double& high, double& low);

/// TMM eq. (8)-(9) for one light term: I_max - I_min = M_max L c_max - M_min L c_min, at least 0.
inline double BrightnessChange(double mMin, double mMax, double light, double high, double low)
{
  const double d = light * (mMax * high - mMin * low);
  return d > 0 ? d : 0.0;
}

/// Cheng §2 on a normal cone: the largest angle between two normals of the cell is at most
/// min(pi, 2 theta); the cell may be simplified when the cosine of that angle exceeds the
/// threshold T = exp(-K D). At the fovea (D = 0) T = 1 and nothing is simplified.
bool ChengAccepts(double cosT, double sinT, double rate, double D);

/// Wang & Sato eq. (1)-(2): coarsest level whose cell edge is at most 2 n0 sin(angle/2) D / N;
/// finestLevel + 1 (every leaf opened) when even the finest cells are larger.
int DistanceLevel(double rootEdge, int finestLevel, double pixelThreshold, double viewAngle,
  double distance, double pixels);

/// Checks an input: finite numbers, positive scales and PSEC factor, unit-ish vectors, material
/// reflectances in [0, 1], light intensities >= 0, a minimum level in [0, MaxFinestLevel].
/// Explains in `why` (one line, naming the values refused).
bool ValidateSelectionInput(const SelectionInput& in, std::string* why);

/**
 * The selector keeps per-octree caches (sin and cos of the cone angles) and the previous cut,
 * so that a frame touches only what it visits.
 */
class Selector
{
public:
  /// Call when the octree changes (recomputes the caches).
  void SetOctree(const OctreeView& view);
  /**
   * The exact count's remembered corner walks (SelectionInput::ExactBudget): `memo`, shared
   * with the patch generator that draws the same octree, under `stamp` (non-zero, unique to the
   * octree: see PatchOptions::OctreeStamp). Call after SetOctree(), which goes back to a memo of
   * the selector's own under a stamp of its own.
   */
  void SetCornerMemo(std::shared_ptr<CornerMemo> memo, uint64_t stamp)
  {
    this->CountSpace.Memo = std::move(memo);
    this->CountOptions.OctreeStamp = stamp;
  }
  /// Writes the cut into `state`, `reason` and `cullMask` (arrays of NumberOfNodes, kept
  /// between calls: only the previous cut's entries are cleared). `cullMask` (may be null)
  /// receives, for culled cells, the frustum planes their cell lies wholly outside (bit i:
  /// plane i), for the patch generator.
  void Select(const SelectionInput& in, uint8_t* state, uint8_t* reason, uint8_t* cullMask,
    SelectionStats& stats);

  /**
   * When set, the tolerance walk (no triangle budget, not incremental) judges the top of the
   * tree breadth first until enough subtrees wait, then walks the subtrees through `parallelFor`
   * (vtkSMPTools in the VTK layer), each with its own stack, list and figures, merged in order.
   * The cut, the reasons, the cull masks and the figures are the serial walk's; only the order of
   * the internal list of cut nodes differs. The budget walk's first pass (see "Cost" in the file
   * documentation) and the tolerance walk it may try first run through it too. Unset (default):
   * serial.
   */
  void SetParallelFor(const ParallelFor& parallelFor)
  {
    this->For = parallelFor;
    this->CountOptions.For = parallelFor;
  }

  /**
   * Reads of a mapped octree's pages off the frame (plodPageLoader.h), or null (default): every
   * refinement the walks make is read when made. With a loader, a cell the tolerances refine
   * whose refinement was not read yet is drawn as it is, with reason AwaitingPages (the
   * coarser cell stands in for its children), and asked of the loader; a later frame refines it
   * once read. The first selection after the loader is set makes every refinement and reads it
   * in the frame (the first view is drawn whole); its refinements are then marked read and read
   * again in the background (PageLoader::Preload: the frame skips what it culls, which a later
   * view may show). Each selection drops the requests the last one left waiting
   * (PageLoader::ForgetRequests) and asks again for what it still needs; the requests of other
   * selectors sharing the loader stay (each is a requester of its own,
   * PageLoader::AddRequester). Under a triangle
   * budget, a cell waits for its pages even when the budget would not refine it, so the loader
   * reads one level beyond the budget's cut: what a zoom needs next.
   */
  void SetPageLoader(PageLoader* loader);

  /// Whether the tolerances refine (a leaf: open) the cell `node` judged with every test and no
  /// context from its parent, as the incremental walk judges the cells of the previous cut and
  /// the parents it may coarsen to. For tests and diagnostics; false for an index out of range.
  bool Refines(const SelectionInput& in, int64_t node) const;

private:
  /// A node to visit: its cell coordinates and whether only brightness is still tested.
  struct Entry
  {
    int32_t Node;
    uint32_t C[3];
    bool BrightnessOnly;
    uint8_t Inside; // the frustum planes its parent lies wholly inside (bit i: plane i)
  };
  /// A refinement waiting in the budget walk's queue (a 4-ary max-heap of 16-byte items; the
  /// rest of the cell is in Waiting[Slot]). Order: its key (its priority, at most the key of
  /// the refinement that reached it) in the high 32 bits, its own priority in the low 32 bits,
  /// both as the bits of non-negative floats, which order as the numbers do. Equal orders go to
  /// the smaller node index. Single precision: which of two priorities within 1e-7 of each
  /// other goes first does not matter, only that it is deterministic.
  struct Candidate
  {
    uint64_t Order;
    int32_t Node;
    uint32_t Slot;
  };
  /// What refining a waiting cell needs, read when it is judged (with its siblings, whose
  /// entries share cache lines) rather than when it leaves the queue.
  struct AheadCell;
  struct WaitingCell
  {
    int64_t Owned; // the triangles refining it adds
    uint32_t C[3];
    int32_t FirstChild;
    uint8_t ChildMask;
    uint8_t Level;
    uint8_t Inside;              // the frustum planes it lies wholly inside
    bool ChildrenBrightnessOnly; // what its children are tested for
    bool Topology;               // refined only for its topology (TopologyRefined)
    const AheadCell* Ahead;      // its cell as judged ahead, or null
  };
  /// A cell the budget walk's parallel first pass judged (plodSelector.cxx, BudgetWalk::
  /// JudgeAhead): the decision the walk makes when it meets the cell, and for a refinement the
  /// first pass went below, what refining it adds to the budget's count and where its
  /// children's cells are (ChildList, ChildIndex: contiguous, in child order, in
  /// AheadLists[ChildList]; ChildList NotAhead: not judged ahead).
  struct AheadCell
  {
    int32_t Node;
    uint32_t C[3];
    int64_t Owned; // a refinement: the triangles refining it adds (as WaitingCell)
    int64_t Count; // a refinement gone below: CountDrawable of them; else -1
    uint32_t ChildList, ChildIndex;
    int32_t FirstChild;
    float Priority;
    uint8_t What, Reason, Outside, Inside, ChildMask, Level;
    bool BrightnessOnly, Floor, Topology, Factor;
  };

  void ClearPrevious(uint8_t* state, uint8_t* reason, uint8_t* cullMask);
  /// The tolerance walk; with `tally`, counting what the budget counts and giving up once the
  /// count exceeds its budget (WalkToleranceCutWithinBudget).
  void SelectDepthFirst(const SelectionInput& in, uint8_t* state, uint8_t* reason,
    uint8_t* cullMask, SelectionStats& stats, detail::DrawnTally* tally = nullptr);
  void SelectIncremental(const SelectionInput& in, uint8_t* state, uint8_t* reason,
    uint8_t* cullMask, SelectionStats& stats);
  /// The budget walk with a budget of `budget` triangles (in.TriangleBudget, or the exact
  /// budget's next try).
  void SelectWithinBudget(const SelectionInput& in, int64_t budget, uint8_t* state, uint8_t* reason,
    uint8_t* cullMask, SelectionStats& stats);
  void FitDrawnTriangles(const SelectionInput& in, uint8_t* state, uint8_t* reason,
    uint8_t* cullMask, SelectionStats& stats);
  /// With a budget: the tolerance walk, counting what the budget counts; true when its cut fits
  /// the budget (then it is the cut), false when it was given up (its cells are then in
  /// Previous, to be cleared).
  bool WalkToleranceCutWithinBudget(const SelectionInput& in, uint8_t* state, uint8_t* reason,
    uint8_t* cullMask, SelectionStats& stats);
  struct BudgetWalk; // SelectWithinBudget's state and steps (plodSelector.cxx)

  OctreeView View;
  std::vector<Entry> Stack;
  std::vector<Candidate> Queue;     // the budget walk's max-heap
  PatchWorkspace CountSpace;        // ExactBudget's count of the drawn triangles
  PatchOptions CountOptions;        // its rules (For, octree stamp kept; the view's set each frame)
  std::vector<Candidate> QueueRest; // SkipMisfits' last pass: the queue it reads
  std::vector<WaitingCell> Waiting;
  // per node, its cone angle's sine and cosine once judged (see ConeSinCos in the source): zero
  // pages, so that they take memory where the views judge, not in proportion to the octree
  mutable ZeroPages<uint64_t> Cones;
  std::vector<detail::PreparedLight> FrameLights; // the frame's lights (capacity kept)
  detail::FoveaTable Fovea;      // screen foveation's factor table (the walks' first bound)
  std::vector<int32_t> Previous; // nodes of the previous cut
  /// Incremental selection: the previous cut's cells (a tolerance walk's, else empty), the
  /// triangles it counted, and per-node marks of the coarsening pass.
  std::vector<Entry> Front, NextFront;
  int64_t FrontTriangles = 0;
  std::vector<uint32_t> Mark;
  uint32_t MarkValue = 0;
  /// The last budget walk on this octree bound (SelectionInput::ToleranceCutFirst then waits
  /// for one that does not).
  bool BudgetBound = false;
  /// The budget walk's parallel first pass: the key down to which it judges ahead (the last
  /// binding walk's first misfit; infinite: no first pass), its lists of cells (one for the
  /// top of the tree, one per subtree), and the top's refinements waiting to be gone below.
  float AheadKey = std::numeric_limits<float>::infinity();
  std::vector<std::vector<AheadCell>> AheadLists;
  std::vector<std::pair<uint32_t, float>> AheadOpen;
  std::vector<std::vector<std::pair<uint32_t, float>>> AheadStacks;
  /// SetPageLoader's loader, and whether a selection with it was made (the first view read)
  PageLoader* Pages = nullptr;
  uint64_t PagesSerial = 0; // PageLoader::GetSerial (a new loader may take a freed address)
  int PageRequester = 0;
  bool FirstViewRead = false;
  /// After the first view: its refinements (the cut in `state`) marked read, and preloaded.
  void PreloadRefinements(const uint8_t* state);
  /// The parallel tolerance walk: the function, and each subtree's stack, cut list, figures and
  /// triangles (capacities kept between frames).
  ParallelFor For;
  std::vector<std::vector<Entry>> TaskStacks;
  std::vector<std::vector<int32_t>> TaskPrevious;
  std::vector<SelectionStats> TaskStats;
  std::vector<int64_t> TaskTriangles;
};

} // namespace plod

#endif
