// SPDX-License-Identifier: BSD-3-Clause
// Exact tests of the selector's view model (plodViewModel.h), each formula on a case worked out
// by hand: the screen distance, the object's scale, the micro motion (its factor, identity,
// matrix order and origin), the object's speed over the root's corners, IPV and DPV, Wang &
// Sato's angle, and the whole frame in local coordinates (eye, planes, lights, foveation centre
// and Cheng's H, pixel scales, the motion fallback, the distance level, a singular matrix).
#include "plodViewModel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace
{
constexpr double Pi = 3.14159265358979323846;

TEST(ViewModel, ScreenDistance)
{
  EXPECT_NEAR(plod::ScreenDistance(false, 0, 0, 600, 90), 300.0, 1e-12);
  EXPECT_NEAR(plod::ScreenDistance(false, 0, 0, 600, 60), 300.0 / std::tan(Pi / 6), 1e-9);
  EXPECT_DOUBLE_EQ(plod::ScreenDistance(true, 0.25, 500, 600, 30), 2000.0);
  EXPECT_EQ(plod::ScreenDistance(true, 0, 500, 600, 30), 0.0);
}

TEST(ViewModel, ObjectScaleIsTheCubeRootOfTheDeterminant)
{
  const double m[16] = { 2, 0, 0, 5, 0, 3, 0, 6, 0, 0, 4, 7, 0, 0, 0, 1 };
  EXPECT_NEAR(plod::ObjectScale(m), std::cbrt(24.0), 1e-15);
  const double mirror[16] = { -2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1 };
  EXPECT_NEAR(plod::ObjectScale(mirror), 2.0, 1e-15);
}

TEST(ViewModel, MicroMotion)
{
  const double identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  const double origin[3] = { 10, 20, 30 };
  double A[3][3], b[3];
  // a translation by (1, 2, 3) over a frame of t_m = 0.04 s, predicted for dt = 0.02 s
  const double shift[16] = { 1, 0, 0, 1, 0, 1, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1 };
  plod::ObjectMotion(identity, shift, 0.02, 0.04, origin, A, b);
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(A[r][c], 0.0);
    EXPECT_DOUBLE_EQ(b[r], 0.5 * (r + 1));
  }
  // a uniform scale by 2: A = f (2 - 1) I, b = A origin (local coordinates)
  const double grow[16] = { 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1 };
  plod::ObjectMotion(identity, grow, 0.03, 0.01, origin, A, b);
  for (int r = 0; r < 3; ++r)
  {
    EXPECT_DOUBLE_EQ(A[r][r], 3.0);
    EXPECT_DOUBLE_EQ(b[r], 3.0 * origin[r]);
  }
  // the previous frame's view-to-object matrix first: T = P V
  const double previous[16] = { 1, 0, 0, -1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  const double turn[16] = { 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  const double zero[3] = { 0, 0, 0 };
  plod::ObjectMotion(previous, turn, 1, 1, zero, A, b);
  const double wantA[3][3] = { { -1, -1, 0 }, { 1, -1, 0 }, { 0, 0, 0 } };
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(A[r][c], wantA[r][c]) << r << c;
  EXPECT_EQ(b[0], -1.0);
  EXPECT_EQ(b[1], 0.0);
  EXPECT_EQ(b[2], 0.0);
}

TEST(ViewModel, ObjectSpeedOverTheRootsCorners)
{
  const double none[3][3] = {};
  const double b[3] = { 3, 4, 0 };
  EXPECT_DOUBLE_EQ(plod::ObjectSpeed(none, b, 7, 2), 10.0);
  // an expansion about the root's lower corner: |c|^2 over the corners of the unit cube sum to 12
  const double grow[3][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  const double still[3] = { 0, 0, 0 };
  EXPECT_DOUBLE_EQ(plod::ObjectSpeed(grow, still, 1, 1), std::sqrt(1.5));
}

TEST(ViewModel, VelocityFactors)
{
  using M = plod::MotionModel;
  EXPECT_DOUBLE_EQ(plod::VelocityFactor(M::InverseVelocity, 30, 10, 100), 3.0);
  EXPECT_DOUBLE_EQ(plod::VelocityFactor(M::InverseVelocity, 5, 10, 100), 1.0);
  EXPECT_DOUBLE_EQ(plod::VelocityFactor(M::DirectVelocity, 5, 1, 10), 2.0);
  EXPECT_EQ(
    plod::VelocityFactor(M::DirectVelocity, 10, 1, 10), std::numeric_limits<double>::infinity());
  EXPECT_EQ(plod::VelocityFactor(M::MicroMotion, 50, 1, 10), 1.0);
  EXPECT_EQ(plod::VelocityFactor(M::None, 50, 1, 10), 1.0);
}

TEST(ViewModel, WangSatoAngle)
{
  EXPECT_DOUBLE_EQ(plod::WangSatoAngle(true, 1, 1, 30), Pi / 2);
  EXPECT_DOUBLE_EQ(plod::WangSatoAngle(false, 1, 1, 30), Pi / 6);
  EXPECT_DOUBLE_EQ(plod::WangSatoAngle(true, 1, 0, 30), Pi); // eye at the centre
}

TEST(ViewModel, FrameInLocalCoordinates)
{
  const double origin[3] = { 1, 2, 3 };
  plod::FrameView f;
  f.Eye[0] = 1;
  f.Eye[1] = 2;
  f.Eye[2] = 13;
  f.UseFrustum = true;
  for (int p = 0; p < 6; ++p)
    f.FrustumPlanes[4 * p] = 1; // x >= 0
  f.ScreenDistance = 500;
  f.ViewportHeight = 600;
  std::vector<plod::SelectorLight> lights(2);
  lights[0].Positional = true;
  lights[0].Position[0] = 1;
  lights[0].Position[1] = 2;
  lights[0].Position[2] = 3;
  lights[1].Position[2] = 2;
  f.Lights = lights.data();
  f.NumberOfLights = lights.size();
  f.FoveationPoint[0] = 3;
  f.FoveationPoint[1] = 2;
  f.FoveationPoint[2] = 3;
  plod::SelectionInput in;
  in.Motion = plod::MotionModel::MicroMotion;
  const plod::FrameViewResult r = plod::MakeFrameView(f, origin, 4, 6, in);
  ASSERT_TRUE(r.Ok) << r.Error;
  EXPECT_EQ(in.Eye[0], 0.0);
  EXPECT_EQ(in.Eye[1], 0.0);
  EXPECT_EQ(in.Eye[2], 10.0);
  EXPECT_EQ(in.Planes[0][0], 1.0);
  EXPECT_EQ(in.Planes[0][3], 1.0); // x_world = x_local + 1 >= 0
  EXPECT_EQ(in.PixelScale, 500.0);
  ASSERT_EQ(in.Lights.size(), 2u);
  EXPECT_EQ(in.Lights[0].Position[2], 0.0);
  EXPECT_EQ(in.Lights[1].Position[2], 1.0); // a direction, normalised
  EXPECT_EQ(in.FoveationPoint[0], 2.0);
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(in.FoveationCentre[a], 2.0);
  EXPECT_EQ(in.FoveationHeight, 4.0); // Cheng's H: the root's edge
  EXPECT_EQ(in.Motion, plod::MotionModel::None) << "micro motion without a previous frame";
  EXPECT_EQ(r.ObjectSpeed, 0.0);
  EXPECT_EQ(
    r.DistanceLevel, plod::DistanceLevel(4, 6, 1, 30 * Pi / 180, std::sqrt(4.0 + 4 + 64), 600));
  EXPECT_EQ(in.DistanceLevel, r.DistanceLevel);

  // parallel, world coordinates scaled by 2: pixels per object length double
  plod::FrameView p = f;
  p.Parallel = true;
  p.ParallelScale = 3;
  const double two[16] = { 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1 };
  const double half[16] = { 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1 };
  std::copy(two, two + 16, p.ObjectToWorld);
  std::copy(half, half + 16, p.WorldToObject);
  const plod::FrameViewResult rp = plod::MakeFrameView(p, origin, 4, 6, in);
  ASSERT_TRUE(rp.Ok);
  EXPECT_DOUBLE_EQ(in.PixelScale, 0.5 * 600 / 3 * 2);
  EXPECT_DOUBLE_EQ(in.Eye[2], 6.5 - 3); // 13 / 2 - origin
  const double dist = std::sqrt(1.5 * 1.5 + 1 + 1.5 * 1.5);
  EXPECT_EQ(rp.DistanceLevel, plod::DistanceLevel(4, 6, 1, 2 * std::atan(3 / dist), dist, 600));

  // moving: IPV's factor from the speed in pixels at the root centre's distance
  plod::FrameView m = f;
  m.HasPreviousFrame = true;
  m.PreviousFrameTime = 0.04;
  m.FrameInterval = 0.04;
  const double shift[16] = { 1, 0, 0, 0.3, 0, 1, 0, 0.4, 0, 0, 1, 0, 0, 0, 0, 1 };
  std::copy(shift, shift + 16, m.ObjectToView);
  m.InverseVelocitySpeed = 0.5;
  in.Motion = plod::MotionModel::InverseVelocity;
  const plod::FrameViewResult rm = plod::MakeFrameView(m, origin, 4, 6, in);
  ASSERT_TRUE(rm.Ok);
  const double pixels = 500 / std::sqrt(72.0); // screen distance over the eye's distance
  EXPECT_NEAR(rm.ObjectSpeed, 0.5 * pixels, 1e-12);
  EXPECT_NEAR(in.VelocityFactor, rm.ObjectSpeed / 0.5, 1e-12);
  EXPECT_NEAR(in.MotionB[0], 0.3, 1e-15);
  EXPECT_NEAR(in.MotionB[1], 0.4, 1e-15);

  // a singular object-to-world matrix is refused
  plod::FrameView s = f;
  for (double& v : s.ObjectToWorld)
    v = 0;
  EXPECT_FALSE(plod::MakeFrameView(s, origin, 4, 6, in).Ok);
}

} // namespace
