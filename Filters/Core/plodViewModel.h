// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodViewModel.h
 * @brief VTK-free view model of the selector: from a frame's camera, lights and motion to the
 *        view part of plod::SelectionInput, in the octree's local coordinates.
 *
 * A frame is described as a renderer gives it (vtkPerceptualLODSelector forwards its settings
 * here unchanged): the eye, the frustum planes, the projection and the lights in world
 * coordinates (or object coordinates), the object-to-world matrix of the prop and its inverse,
 * and the object-to-view matrices of this frame and the previous one. MakeFrameView turns that
 * into what the selection kernel reads:
 * - **local coordinates**: a point p of the world becomes W^-1 p - origin (W the object-to-world
 *   matrix, origin the octree's lower corner); a direction d becomes the normalised linear part
 *   of W^-1 applied to d; a plane (a, b, c, d) of the world becomes (a, b, c, d) W, its constant
 *   then shifted by the origin. World lengths per object length: s = cbrt |det W|.
 * - **pixels per length**: perspective, the screen distance D = (h / 2) / tan(angle / 2) (h the
 *   viewport's height in pixels), or ViewingDistance / PixelPitch for a physical display;
 *   parallel, (h / 2) / ParallelScale * s.
 * - **micro motion (TMM §3)**: with T = V_prev^-1 V (the previous frame's view-to-object
 *   matrix times this frame's object-to-view matrix) and f = FrameInterval / PreviousFrameTime,
 *   the displacement of a local point v over the next frame is A v + b with
 *   A = f (T_3x3 - I) and b = f T_translation + A origin. No previous frame, or a previous frame
 *   time of 0, means no motion (micro motion falls back to none).
 * - **the object's speed** for IPV and DPV, in pixels per frame interval: the root-mean-square
 *   displacement of the root cell's eight corners times the pixels per length at the distance
 *   from the eye to the root's centre (parallel: the parallel pixel scale). The centre alone
 *   does not move when the camera orbits about it.
 * - **velocity factors**: IPV, max(1, speed / InverseVelocitySpeed); DPV,
 *   1 / (1 - speed / DirectVelocitySpeed), infinite from DirectVelocitySpeed on.
 * - **Wang & Sato's level** (plod::DistanceLevel) from the distance to the root's centre and the
 *   view angle; under a parallel projection the angle is 2 atan(ParallelScale / distance).
 * - **Cheng's object-centred foveation**: the vertical axis through the root's centre, and the
 *   height H = the root's edge.
 *
 * @sa plodSelector.h vtkPerceptualLODSelector
 */
#ifndef plodViewModel_h
#define plodViewModel_h

#include "plodSelector.h"

#include <string>
#include <vector>

namespace plod
{

/// One frame's view as a renderer gives it (see the file's documentation).
struct FrameView
{
  /// True: the points, directions and planes below are in world coordinates; false: in the
  /// object's (the octree's input) coordinates, and ObjectToWorld is ignored.
  bool CoordinatesAreWorld = true;
  double ObjectToWorld[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  /// The inverse of ObjectToWorld, computed by the caller.
  double WorldToObject[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  /// This frame's object-to-view matrix, and the inverse of the previous frame's (read only
  /// when there is motion: HasPreviousFrame and PreviousFrameTime > 0).
  double ObjectToView[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double PreviousViewToObject[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  bool HasPreviousFrame = false;
  double PreviousFrameTime = 0; ///< t_m, seconds
  double FrameInterval = 0;     ///< dt, seconds

  double Eye[3] = { 0, 0, 1 };
  bool UseFrustum = false;
  double FrustumPlanes[24] = {}; ///< six planes (a, b, c, d), a x + b y + c z + d >= 0 inside
  bool Parallel = false;
  double ParallelScale = 1;
  double ViewAngle = 30; ///< degrees
  double ProjectionDirection[3] = { 0, 0, -1 };
  /// Pixels per length at unit distance (perspective); see ScreenDistance.
  double ScreenDistance = 1000;
  int ViewportHeight = 1;

  /// The lights (borrowed, not copied: the view is made every frame).
  const SelectorLight* Lights = nullptr;
  size_t NumberOfLights = 0;
  double FoveationPoint[3] = { 0, 0, 0 };
  double FoveationUp[3] = { 0, 1, 0 };
  double GazeDirection[3] = { 0, 0, -1 };

  double InverseVelocitySpeed = 1;
  double DirectVelocitySpeed = 1;
  double DistancePixelThreshold = 1;
};

/// What MakeFrameView found besides the selection input.
struct FrameViewResult
{
  bool Ok = false;
  std::string Error;
  double ObjectSpeed = 0; ///< pixels per frame interval (0 without motion)
  int DistanceLevel = 0;
};

/// The screen distance in pixels: ViewingDistance / PixelPitch on a physical display, else
/// (height / 2) / tan(viewAngle / 2) with the angle in degrees.
double ScreenDistance(bool physicalDisplay, double pixelPitch, double viewingDistance,
  int viewportHeight, double viewAngle);

/// World lengths per object length of an object-to-world matrix: cbrt |det| of its 3 x 3 part.
double ObjectScale(const double objectToWorld[16]);

/// The micro motion A v + b of local points (see the file's documentation).
void ObjectMotion(const double previousViewToObject[16], const double objectToView[16],
  double frameInterval, double previousFrameTime, const double origin[3], double A[3][3],
  double b[3]);

/// The object's speed in pixels: the root-mean-square of |A c + b| over the root cell's eight
/// corners c (local coordinates, edge `rootEdge`), times `pixelsPerLength`.
double ObjectSpeed(
  const double A[3][3], const double b[3], double rootEdge, double pixelsPerLength);

/// IPV's and DPV's factor for a motion model (1 for the others).
double VelocityFactor(
  MotionModel model, double speed, double inverseVelocitySpeed, double directVelocitySpeed);

/// The view angle Wang & Sato's level uses, in radians: the view angle under a perspective
/// projection, 2 atan(parallelScale / distance) under a parallel one.
double WangSatoAngle(bool parallel, double parallelScale, double distance, double viewAngle);

/**
 * Fills the view part of `in` for an octree with lower corner `origin`, root edge `rootEdge` and
 * finest level `finestLevel`: Eye, UseFrustum, Planes, Parallel, ProjectionDirection,
 * PixelScale, Lights, the foveation point, up, gaze, centre and height, MotionA, MotionB,
 * VelocityFactor and DistanceLevel. `in.Motion` must be set first; micro motion without a
 * previous frame becomes MotionModel::None. Fails (Ok false, `in` partly filled) on a singular
 * object-to-world matrix.
 */
FrameViewResult MakeFrameView(const FrameView& frame, const double origin[3], double rootEdge,
  int finestLevel, SelectionInput& in);

} // namespace plod

#endif
