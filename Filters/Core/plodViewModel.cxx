// SPDX-License-Identifier: BSD-3-Clause
// The selector's view model. See plodViewModel.h.
#include "plodViewModel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plod
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

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

/// m p for a point (w = 1), divided by the result's w when it is not 0.
void TransformPoint(const double m[16], const double in[3], double out[3])
{
  const double p[4] = { in[0], in[1], in[2], 1.0 };
  double r[4];
  for (int i = 0; i < 4; ++i)
  {
    r[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
  }
  const double w = r[3] != 0 ? r[3] : 1.0;
  for (int a = 0; a < 3; ++a)
  {
    out[a] = r[a] / w;
  }
}

/// The linear part applied to a direction, normalised (zero stays zero).
void TransformDirection(const double m[16], const double in[3], double out[3])
{
  for (int a = 0; a < 3; ++a)
  {
    out[a] = m[4 * a] * in[0] + m[4 * a + 1] * in[1] + m[4 * a + 2] * in[2];
  }
  const double l = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
  if (l > 0)
  {
    for (int a = 0; a < 3; ++a)
    {
      out[a] /= l;
    }
  }
}

/// c = a b for row-major 4 x 4 matrices.
void Multiply(const double a[16], const double b[16], double c[16])
{
  double t[16];
  for (int r = 0; r < 4; ++r)
  {
    for (int col = 0; col < 4; ++col)
    {
      t[4 * r + col] = a[4 * r] * b[col] + a[4 * r + 1] * b[4 + col] + a[4 * r + 2] * b[8 + col] +
        a[4 * r + 3] * b[12 + col];
    }
  }
  std::copy(t, t + 16, c);
}

double Distance(const double a[3], double centre)
{
  const double d[3] = { a[0] - centre, a[1] - centre, a[2] - centre };
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}
} // namespace

//------------------------------------------------------------------------------
double ScreenDistance(bool physicalDisplay, double pixelPitch, double viewingDistance,
  int viewportHeight, double viewAngle)
{
  if (physicalDisplay)
  {
    return pixelPitch > 0 ? viewingDistance / pixelPitch : 0.0;
  }
  return 0.5 * viewportHeight / std::tan(0.5 * viewAngle * Pi / 180.0);
}

//------------------------------------------------------------------------------
double ObjectScale(const double m[16])
{
  const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
    m[2] * (m[4] * m[9] - m[5] * m[8]);
  return std::cbrt(std::abs(det));
}

//------------------------------------------------------------------------------
void ObjectMotion(const double previousViewToObject[16], const double objectToView[16],
  double frameInterval, double previousFrameTime, const double origin[3], double A[3][3],
  double b[3])
{
  double t[16];
  Multiply(previousViewToObject, objectToView, t);
  const double f = frameInterval / previousFrameTime;
  double bo[3];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      A[r][c] = f * (t[4 * r + c] - (r == c ? 1.0 : 0.0));
    }
    bo[r] = f * t[4 * r + 3];
  }
  // local coordinates: v_object = v_local + origin
  for (int r = 0; r < 3; ++r)
  {
    b[r] = bo[r] + A[r][0] * origin[0] + A[r][1] * origin[1] + A[r][2] * origin[2];
  }
}

//------------------------------------------------------------------------------
double ObjectSpeed(const double A[3][3], const double b[3], double rootEdge, double pixelsPerLength)
{
  double sum = 0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const double c[3] = { (corner & 1) ? rootEdge : 0.0, (corner & 2) ? rootEdge : 0.0,
      (corner & 4) ? rootEdge : 0.0 };
    for (int r = 0; r < 3; ++r)
    {
      const double vf = A[r][0] * c[0] + A[r][1] * c[1] + A[r][2] * c[2] + b[r];
      sum += vf * vf;
    }
  }
  return std::sqrt(sum / 8) * pixelsPerLength;
}

//------------------------------------------------------------------------------
double VelocityFactor(
  MotionModel model, double speed, double inverseVelocitySpeed, double directVelocitySpeed)
{
  if (model == MotionModel::InverseVelocity)
  {
    return std::max(1.0, speed / inverseVelocitySpeed);
  }
  if (model == MotionModel::DirectVelocity)
  {
    const double left = 1.0 - speed / directVelocitySpeed;
    return left > 0 ? 1.0 / left : std::numeric_limits<double>::infinity();
  }
  return 1.0;
}

//------------------------------------------------------------------------------
double WangSatoAngle(bool parallel, double parallelScale, double distance, double viewAngle)
{
  return parallel ? 2.0 * std::atan(parallelScale / std::max(distance, 1e-300))
                  : viewAngle * Pi / 180.0;
}

//------------------------------------------------------------------------------
FrameViewResult MakeFrameView(
  const FrameView& f, const double origin[3], double rootEdge, int finestLevel, SelectionInput& in)
{
  FrameViewResult result;
  // world -> object
  double toObject[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double scale = 1.0; // world length per object length
  if (f.CoordinatesAreWorld)
  {
    std::copy(f.WorldToObject, f.WorldToObject + 16, toObject);
    scale = ObjectScale(f.ObjectToWorld);
    if (!(scale > 0) || !Finite(toObject, 16))
    {
      result.Error = "the object-to-world matrix is singular";
      return result;
    }
  }
  auto toLocalPoint = [&](const double p[3], double out[3]) {
    TransformPoint(toObject, p, out);
    for (int a = 0; a < 3; ++a)
    {
      out[a] -= origin[a];
    }
  };
  toLocalPoint(f.Eye, in.Eye);
  in.UseFrustum = f.UseFrustum;
  if (f.UseFrustum)
  {
    for (int p = 0; p < 6; ++p)
    {
      const double* w = f.FrustumPlanes + 4 * p;
      double obj[4];
      // plane (row) x M: a plane of the world seen in object coordinates
      const double* m = f.CoordinatesAreWorld ? f.ObjectToWorld : toObject;
      for (int c = 0; c < 4; ++c)
      {
        obj[c] = w[0] * m[c] + w[1] * m[4 + c] + w[2] * m[8 + c] + w[3] * m[12 + c];
      }
      for (int a = 0; a < 3; ++a)
      {
        in.Planes[p][a] = obj[a];
      }
      in.Planes[p][3] = obj[3] + obj[0] * origin[0] + obj[1] * origin[1] + obj[2] * origin[2];
    }
  }
  in.Parallel = f.Parallel;
  TransformDirection(toObject, f.ProjectionDirection, in.ProjectionDirection);
  in.PixelScale = f.Parallel ? 0.5 * f.ViewportHeight / f.ParallelScale * scale : f.ScreenDistance;
  in.Lights.clear();
  in.Lights.reserve(f.NumberOfLights);
  for (size_t i = 0; i < f.NumberOfLights; ++i)
  {
    const SelectorLight& l = f.Lights[i];
    SelectorLight t = l;
    if (l.Positional)
    {
      toLocalPoint(l.Position, t.Position);
    }
    else
    {
      TransformDirection(toObject, l.Position, t.Position);
    }
    in.Lights.push_back(t);
  }
  toLocalPoint(f.FoveationPoint, in.FoveationPoint);
  TransformDirection(toObject, f.FoveationUp, in.FoveationUp);
  TransformDirection(toObject, f.GazeDirection, in.GazeDirection);
  const double half = 0.5 * rootEdge;
  in.FoveationCentre[0] = in.FoveationCentre[1] = in.FoveationCentre[2] = half;
  in.FoveationHeight = rootEdge;

  // motion (TMM §3), and the object's speed for IPV and DPV
  const bool moving = f.HasPreviousFrame && f.PreviousFrameTime > 0;
  if (moving)
  {
    ObjectMotion(f.PreviousViewToObject, f.ObjectToView, f.FrameInterval, f.PreviousFrameTime,
      origin, in.MotionA, in.MotionB);
    const double dist = Distance(in.Eye, half);
    const double k = f.Parallel ? in.PixelScale : (dist > 0 ? f.ScreenDistance / dist : 0.0);
    result.ObjectSpeed = ObjectSpeed(in.MotionA, in.MotionB, rootEdge, k);
  }
  in.VelocityFactor =
    VelocityFactor(in.Motion, result.ObjectSpeed, f.InverseVelocitySpeed, f.DirectVelocitySpeed);
  if (in.Motion == MotionModel::MicroMotion && !moving)
  {
    in.Motion = MotionModel::None; // first frame, or t_m = 0: no motion
  }
  // Wang & Sato: one level from the distance to the root's centre
  const double dist = Distance(in.Eye, half);
  result.DistanceLevel = DistanceLevel(rootEdge, finestLevel, f.DistancePixelThreshold,
    WangSatoAngle(f.Parallel, f.ParallelScale, dist, f.ViewAngle), dist, f.ViewportHeight);
  in.DistanceLevel = result.DistanceLevel;
  result.Ok = true;
  return result;
}

} // namespace plod
