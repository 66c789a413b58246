// SPDX-License-Identifier: BSD-3-Clause
// Exact small cases of every mode of plod::Selector (VTK-free): each test puts a decision on
// the boundary its formula predicts and checks both sides, so that a changed constant, factor or
// term moves the boundary and fails. The octree is plodtest::Tiny: a unit root cell (vertex
// (0.5, 0.5, 0.5), axis +z, cone angle 0.2, shape error 0.01) with one finest child (vertex
// (0.25, 0.25, 0.25), axis +z, cone angle 0). Screen distance 1000 pixels unless said otherwise,
// so a length L at distance d projects to 1000 L / d pixels.
#include "plodSelector.h"
#include "plodTinyOctree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace
{
constexpr double Pi = 3.14159265358979323846;
using plodtest::Tiny;
using plodtest::Viewer;

/// The eye on the root vertex's axis (+z) at distance d.
plod::SelectionInput Above(double d)
{
  return Viewer(0.5, 0.5, 0.5 + d);
}
} // namespace

// ---- SCVC: dE d_s / d_o <= T_s everywhere, nothing else ------------------------------------

TEST(SelectorExact, SCVCProjectedShapeError)
{
  Tiny t;
  // error 0.01 * 1000 / d = 10 / d pixels: accepted from d = 10 on
  auto in = Above(9.99);
  in.Error = plod::ErrorModel::SCVC;
  int child = -1;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::AcceptedError); // the child's error is 0
  in = Above(10.01);
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  // the tolerance scales the boundary: T_s = 2 accepts from d = 5
  in = Above(5.01);
  in.Error = plod::ErrorModel::SCVC;
  in.ContourTolerance = 2;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  in.ContourTolerance = 1.99;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
}

TEST(SelectorExact, SCVCHasNoContourBackFaceOrLightingTerm)
{
  Tiny t;
  // behind the surface (the cone faces away): SCVC still draws it by its error alone
  auto in = Viewer(0.5, 0.5, 0.5 - 10.01);
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  // on the contour (eye along +x): the same boundary as front-facing
  in = Viewer(0.5 + 10.01, 0.5, 0.5);
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  in = Viewer(0.5 + 9.99, 0.5, 0.5);
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // a bright light and a tiny brightness tolerance change nothing
  in = Above(10.01);
  in.Error = plod::ErrorModel::SCVC;
  in.Lights.push_back(plod::SelectorLight{ false, { 1, 0, 0 }, 1, 1 });
  in.BrightnessTolerance = 1e-6;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
}

// ---- PSEC: SCVC with the tolerance times PSECFactor on contours and highlights ----------------

TEST(SelectorExact, PSECOnTheContourAndUnderAHighlight)
{
  Tiny t;
  auto psec = [](plod::SelectionInput in) {
    in.Error = plod::ErrorModel::PSEC;
    return in;
  };
  // front-facing, no light: SCVC's boundary (d = 10)
  EXPECT_EQ(t.RootReason(psec(Above(10.01))), plod::AcceptedError);
  EXPECT_EQ(t.RootReason(psec(Above(9.99))), plod::ReasonNone);
  // on the contour: tolerance 0.25: accepted from d = 40
  EXPECT_EQ(t.RootReason(psec(Viewer(0.5 + 39.9, 0.5, 0.5))), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(psec(Viewer(0.5 + 40.1, 0.5, 0.5))), plod::AcceptedError);
  // the factor is a parameter: 0.5 on the contour accepts from d = 20
  auto half = psec(Viewer(0.5 + 20.1, 0.5, 0.5));
  half.PSECFactor = 0.5;
  EXPECT_EQ(t.RootReason(half), plod::AcceptedError);
  half = psec(Viewer(0.5 + 19.9, 0.5, 0.5));
  half.PSECFactor = 0.5;
  EXPECT_EQ(t.RootReason(half), plod::ReasonNone);
  // a light behind the eye: the half vector is the axis, inside the cone: a highlight
  auto lit = psec(Above(39.9));
  lit.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 0, 1 });
  EXPECT_EQ(t.RootReason(lit), plod::ReasonNone);
  lit = psec(Above(40.1));
  lit.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 0, 1 });
  EXPECT_EQ(t.RootReason(lit), plod::AcceptedError);
  // light 1 radian off the axis: the half vector is 0.5 radian off, outside the 0.2 cone
  lit = psec(Above(10.01));
  lit.Lights.push_back(plod::SelectorLight{ false, { std::sin(1.0), 0, std::cos(1.0) }, 0, 1 });
  EXPECT_EQ(t.RootReason(lit), plod::AcceptedError);
  // half vector 0.19 radian off (light 0.38 off): inside: a highlight
  lit = psec(Above(10.01));
  lit.Lights.push_back(plod::SelectorLight{ false, { std::sin(0.38), 0, std::cos(0.38) }, 0, 1 });
  EXPECT_EQ(t.RootReason(lit), plod::ReasonNone);
  // no diffuse term: a diffuse-only light on the axis is no highlight
  lit = psec(Above(10.01));
  lit.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
  EXPECT_EQ(t.RootReason(lit), plod::AcceptedError);
}

// ---- Distance (Wang & Sato): one level, whatever the errors -----------------------------------

TEST(SelectorExact, DistanceLevelIsTheOnlyCriterion)
{
  Tiny t;
  auto in = Above(10);
  in.Error = plod::ErrorModel::Distance;
  in.ContourTolerance = 1e9; // no size floor in this mode
  in.DistanceLevel = 0;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  in.DistanceLevel = 1;
  int child = -1;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::AcceptedError);
  in.DistanceLevel = 2; // finer than the finest level: the leaves are opened
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::OpenedLeaf);
  // behind the surface: still drawn (no back-face test)
  in = Viewer(0.5, 0.5, -10);
  in.Error = plod::ErrorModel::Distance;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
}

TEST(SelectorExact, WangSatoBoundaries)
{
  // limit = 2 n0 sin(theta / 2) D / N. theta = 90 degrees, N = 1000, n0 = 1: the limit is 0.25
  // (level 2 of a unit root) at D = 250 / sin(45 deg) = 176.777
  const double angle = Pi / 2;
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, angle, 176.8, 1000), 2);
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, angle, 176.7, 1000), 3);
  // n0 = 2 doubles the limit: one level coarser at the same distance
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 2.0, angle, 176.8, 1000), 1);
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 2.0, angle, 176.7, 1000), 2);
  // twice the pixels halve it
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, angle, 176.8, 2000), 3);
  // a root of edge 2 needs one more level for the same cell size
  EXPECT_EQ(plod::DistanceLevel(2.0, 10, 1.0, angle, 176.8, 1000), 3);
  // theta = 60 degrees: sin 30 = 0.5: limit 0.125 (level 3) at D = 125
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, Pi / 3, 125.1, 1000), 3);
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, Pi / 3, 124.9, 1000), 4);
}

// ---- IPV and DPV: one speed factor ----------------------------------------------------------

TEST(SelectorExact, VelocityAloneSetsOneScreenResolution)
{
  for (auto motion : { plod::MotionModel::InverseVelocity, plod::MotionModel::DirectVelocity })
  {
    Tiny t;
    t.Shape[0] = 1000; // the shape error is not consulted
    // the root's edge at distance 100 is 10 pixels: accepted once T_s times the factor reaches 10
    auto in = Above(100);
    in.Motion = motion;
    in.VelocityFactor = 9.99;
    int child = -1;
    EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
    // the child's edge is 0.5 at distance ~100.25: 4.99 pixels
    EXPECT_EQ(child, plod::AcceptedSize);
    in.VelocityFactor = 10.01;
    EXPECT_EQ(t.RootReason(in), plod::AcceptedSize);
    in.ContourTolerance = 2;
    in.VelocityFactor = 5.01;
    EXPECT_EQ(t.RootReason(in), plod::AcceptedSize);
    in.VelocityFactor = 4.99;
    EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
    // no contour, back-face or brightness test: behind the surface, under a light, accepted
    in = Viewer(0.5, 0.5, 0.5 - 100);
    in.Motion = motion;
    in.VelocityFactor = 10.01;
    in.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 1 });
    in.BrightnessTolerance = 1e-9;
    EXPECT_EQ(t.RootReason(in), plod::AcceptedSize);
    // at rest (factor 1): every cell larger than T_s is refined: the leaf is opened
    in = Above(100);
    in.Motion = motion;
    EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
    EXPECT_EQ(child, plod::OpenedLeaf);
    // an infinite factor (DPV beyond its speed): the root alone
    in.VelocityFactor = std::numeric_limits<double>::infinity();
    EXPECT_EQ(t.RootReason(in), plod::AcceptedSize);
  }
}

TEST(SelectorExact, VelocityScalingTheErrorModel)
{
  Tiny t;
  t.Shape[0] = 0.5f; // SCVC error at distance 100: 5 pixels; the root's edge: 10 pixels
  for (auto motion : { plod::MotionModel::InverseVelocity, plod::MotionModel::DirectVelocity })
  {
    auto in = Above(100);
    in.Error = plod::ErrorModel::SCVC;
    in.Motion = motion;
    in.Velocity = plod::VelocityCriterion::ScalesErrorModel;
    in.VelocityFactor = 4.99;
    EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
    in.VelocityFactor = 5.01;
    EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
    // the factor is ignored without a velocity model
    in.Motion = plod::MotionModel::None;
    EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  }
  // SRCC's brightness tolerance is scaled too: a light along the axis, Tb = 4: the root's
  // brightness change 1 - cos 0.2 = 0.01993 over 1000 / d pixels: accepted from d = 4.983
  // (rounded to the float cone angle); with a factor 2, from d = 2.49
  Tiny lit;
  lit.Shape[0] = 0;
  auto in = Above(2.6);
  in.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
  in.Motion = plod::MotionModel::InverseVelocity;
  in.Velocity = plod::VelocityCriterion::ScalesErrorModel;
  in.VelocityFactor = 2;
  EXPECT_EQ(lit.RootReason(in), plod::AcceptedBrightness);
  in.VelocityFactor = 1.9;
  EXPECT_EQ(lit.RootReason(in), plod::ReasonNone);
}

// ---- Cheng §2: cos(2 theta) > exp(-K D) ------------------------------------------------------

namespace
{
/// Object mode with the vertical axis z through the origin, H = 2, weights (1, 0.5), K = 1 and
/// the fovea at (0.5, -0.5, 0.1): from the root's vertex, beta = pi/2 and |Y - F_y| = 0.4, so
/// D = 0.5 + 0.5 * 0.2 = 0.6, T = exp(-0.6) = 0.5488 and cos(2 theta) > T for theta < 0.49494.
plod::SelectionInput ChengObject(plod::SelectionInput in)
{
  in.Foveation = plod::FoveationMode::Object;
  in.FoveationRate = 1;
  in.FoveationCentre[0] = in.FoveationCentre[1] = in.FoveationCentre[2] = 0;
  in.FoveationUp[0] = in.FoveationUp[1] = 0;
  in.FoveationUp[2] = 1;
  in.FoveationHeight = 2;
  in.FoveationWeights[0] = 1;
  in.FoveationWeights[1] = 0.5;
  in.FoveationPoint[0] = 0.5;
  in.FoveationPoint[1] = -0.5;
  in.FoveationPoint[2] = 0.1;
  return in;
}

/// Screen mode: the eye on the axis at distance 10, the gaze 60 degrees off the ray to the root's
/// vertex: D = 1/3; K = 3: T = exp(-1) = 0.3679 and cos(2 theta) > T for theta < 0.59698.
plod::SelectionInput ChengScreen(plod::SelectionInput in)
{
  in.Foveation = plod::FoveationMode::Screen;
  in.FoveationRate = 3;
  in.GazeDirection[0] = std::sin(Pi / 3);
  in.GazeDirection[1] = 0;
  in.GazeDirection[2] = -std::cos(Pi / 3);
  return in;
}
} // namespace

TEST(SelectorExact, ChengThresholdObjectMode)
{
  Tiny t;
  auto in = ChengObject(Above(10));
  in.Error = plod::ErrorModel::Cheng;
  t.Angle[0] = 0.49f;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  t.Angle[0] = 0.50f;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // no tolerance, no distance: the same far away and with huge tolerances
  in = ChengObject(Above(1e6));
  in.Error = plod::ErrorModel::Cheng;
  in.ContourTolerance = in.BrightnessTolerance = 1e9;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // at the fovea (D = 0, T = 1): nothing is simplified, even a flat cell: full detail (with
  // w_v = 0 both vertices, on the same vertical half-plane as the fovea, have D = 0)
  in.FoveationPoint[0] = in.FoveationPoint[1] = in.FoveationPoint[2] = 0.5;
  in.FoveationWeights[1] = 0;
  t.Angle[0] = 0;
  int child = -1;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::OpenedLeaf);
  // without foveation D = 0 too
  in = Above(10);
  in.Error = plod::ErrorModel::Cheng;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::OpenedLeaf);
}

TEST(SelectorExact, ChengThresholdScreenMode)
{
  Tiny t;
  auto in = ChengScreen(Above(10));
  in.Error = plod::ErrorModel::Cheng;
  t.Angle[0] = 0.59f;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  t.Angle[0] = 0.60f;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // the gaze on the vertex: D = 0, T = 1: even a flat cell is refined
  in.GazeDirection[0] = 0;
  in.GazeDirection[2] = -1;
  t.Angle[0] = 0;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // a cone wider than pi/2 never passes (its normals can be opposite)
  EXPECT_FALSE(plod::ChengAccepts(std::cos(1.6), std::sin(1.6), 100, 1));
  EXPECT_FALSE(plod::ChengAccepts(std::cos(3.0), std::sin(3.0), 100, 1)); // 2 theta > pi
  EXPECT_TRUE(plod::ChengAccepts(1, 0, 100, 1));
}

TEST(SelectorExact, FoveationMultipliesTheTolerancesOfTheOtherModes)
{
  Tiny t;
  // object mode, D = 0.6, K = 1: T_s x exp(0.6) = 1.8221; SCVC's 10 / d accepted from d = 5.488
  auto in = ChengObject(Above(5.45));
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  in = ChengObject(Above(5.53));
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  // screen mode, D = 1/3, K = 3: x e: accepted from d = 3.679
  in = ChengScreen(Above(3.64));
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  in = ChengScreen(Above(3.72));
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
}

// ---- TMM eq. (8)-(9): brightest minus darkest, each with its own reflectance -------------------

TEST(SelectorExact, BrightnessChangeUsesMinimumAndMaximumReflectance)
{
  Tiny t;
  t.Shape[0] = 0;
  t.Diffuse[0] = 0.5f; // the root's diffuse reflectance lies in [0.5, 1]
  t.Diffuse[1] = 1.0f;
  const double c = std::cos(double(0.2f));
  // one light along the axis, the eye on it: c_max = 1, c_min = cos 0.2; dB = 1 - 0.5 cos 0.2 =
  // 0.50997 over 1000 / d pixels: accepted (T_b = 4) from d = 127.49
  const double dB = 1.0 - 0.5 * c;
  const double boundary = dB * 1000 / 4;
  auto lit = [](double d) {
    auto in = Above(d);
    in.UseOctreeMaterial = true;
    in.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
    return in;
  };
  EXPECT_EQ(t.RootReason(lit(boundary - 0.2)), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(lit(boundary + 0.2)), plod::AcceptedBrightness);
  // a specular range [0.2, 0.6] with power 10 adds 0.6 - 0.2 cos^10 0.2
  t.Specular[0] = 0.2f;
  t.Specular[1] = 0.6f;
  const double both = dB + double(0.6f) - double(0.2f) * std::pow(c, 10);
  auto shiny = [&](double d) {
    auto in = lit(d);
    in.Lights[0].Specular = 1;
    in.SpecularPower = 10;
    return in;
  };
  EXPECT_EQ(t.RootReason(shiny(both * 250 - 0.2)), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(shiny(both * 250 + 0.2)), plod::AcceptedBrightness);
  // the helper itself
  EXPECT_DOUBLE_EQ(plod::BrightnessChange(0.5, 1, 2, 1, 0.25), 2 * (1 - 0.125));
  EXPECT_EQ(plod::BrightnessChange(1, 1, 1, 0.3, 0.3), 0);
  // one material (min = max, the selector's constants): SRCC's M L (c_max - c_min)
  Tiny one;
  one.Shape[0] = 0;
  auto plain = Above(0);
  const double spread = 1 - c; // 0.01993: accepted from d = 4.983
  plain = Above(spread * 250 + 0.01);
  plain.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
  EXPECT_EQ(one.RootReason(plain), plod::AcceptedBrightness);
  plain.Eye[2] = 0.5 + spread * 250 - 0.01;
  EXPECT_EQ(one.RootReason(plain), plod::ReasonNone);
}

TEST(SelectorExact, DiffuseTermWithAZeroMinimumReflectanceIsTheBrightestPart)
{
  // A cell holding an unlit-black part (minimum diffuse reflectance 0) and a part of reflectance
  // 0.6 varies by M_max L c_max - 0 = 0.6, the brightest part alone: the term is kept, not
  // skipped for its zero minimum nor read from the maximum alone.
  Tiny t;
  t.Shape[0] = 0;
  t.Diffuse[0] = 0.0f; // the root's diffuse reflectance lies in [0, 0.6]
  t.Diffuse[1] = 0.6f;
  // one light along the axis, the eye on it: c_max = 1; dB = 0.6 over 1000 / d pixels against
  // T_b = 4: accepted from d = 0.6 x 250 = 150 on
  const double boundary = double(0.6f) * 1000 / 4;
  auto lit = [](double d) {
    auto in = Above(d);
    in.UseOctreeMaterial = true;
    in.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
    return in;
  };
  EXPECT_EQ(t.RootReason(lit(boundary - 0.2)), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(lit(boundary + 0.2)), plod::AcceptedBrightness);
  // a light of diffuse intensity 0.5 halves the variation: the boundary moves to d = 75
  auto dim = [&](double d) {
    auto in = lit(d);
    in.Lights[0].Diffuse = 0.5;
    return in;
  };
  EXPECT_EQ(t.RootReason(dim(boundary / 2 - 0.2)), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(dim(boundary / 2 + 0.2)), plod::AcceptedBrightness);
}

// ---- SRCC §3.5 step 3: children of a brightness failure are tested for brightness only -------

TEST(SelectorExact, BrightnessRefinementSkipsTheContourTests)
{
  Tiny t;
  t.Shape[0] = 0;
  t.Axis[5] = -1; // the child faces away: a contour test would hide it as back-facing
  // eye at distance 3: the root fails brightness (0.01993 x 333 px > T_b = 4)
  auto in = Above(3);
  in.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
  int child = -1;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::AcceptedBrightness);
  // the same child reached through a contour failure is tested for the contour: hidden
  t.Shape[0] = 0.01f;
  auto contour = Viewer(0.5 + 3, 0.5, 0.5); // on the root's contour, error 3.3 px
  EXPECT_EQ(t.RootReason(contour, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::BackFacing);
}

// ---- SRCC eq. (4)-(5), (10) with micro motion (TMM eq. 6-7, 12-13) ---------------------------

TEST(SelectorExact, MicroMotionReducesBothErrorsByItsComponents)
{
  Tiny t;
  // on the contour (eye along +x, 5 units): error 0.01 x 200 = 2 px > 1: refined. A motion along
  // the axis (n.v_f = 0.006) leaves 0.004 x 200 = 0.8 px: accepted; along x it does nothing.
  auto in = Viewer(5.5, 0.5, 0.5);
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  in.Motion = plod::MotionModel::MicroMotion;
  in.MotionB[2] = 0.006;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
  in.MotionB[2] = 0.004; // 0.006 x 200 = 1.2 px left
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  in.MotionB[2] = 0;
  in.MotionB[0] = 0.006;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // v_f = A v + b: the same displacement through A (v_z = 0.5: A_zz = 0.012)
  in.MotionB[0] = 0;
  in.MotionA[2][2] = 0.012;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
  // brightness: front-facing at distance 3 (0.01993 x 333 = 6.6 > 4); a motion across the view
  // in the axis' tilt direction shrinks the projected size. The axis tilted by 0.3 about y:
  // c = cos 0.3, v_d = (1, 0, 0) x sin 0.3 / |sin 0.3|; size = h c - |v_d . v_f|
  Tiny b;
  b.Shape[0] = 0;
  b.Axis[0] = float(std::sin(0.3));
  b.Axis[2] = float(std::cos(0.3));
  auto lit = Above(3);
  lit.Lights.push_back(plod::SelectorLight{ false, { b.Axis[0], 0, b.Axis[2] }, 1, 0 });
  EXPECT_EQ(b.RootReason(lit), plod::ReasonNone);
  // dB = 1 - cos 0.2 = 0.019933, k = 1000 / |eye - v| = 333.33: accepted when size <= 0.60201
  const double k = 1000.0 / 3.0, dB = 1 - std::cos(double(0.2f));
  const double c = double(b.Axis[2]);
  const double need = c - 4.0 / (dB * k); // the motion across the view that suffices
  lit.Motion = plod::MotionModel::MicroMotion;
  lit.MotionB[0] = need + 0.01;
  EXPECT_EQ(b.RootReason(lit), plod::AcceptedBrightness);
  lit.MotionB[0] = need - 0.01;
  EXPECT_EQ(b.RootReason(lit), plod::ReasonNone);
  // a motion along the view direction (v_d . v_f = 0) does nothing
  lit.MotionB[0] = 0;
  lit.MotionB[1] = need + 0.01;
  EXPECT_EQ(b.RootReason(lit), plod::ReasonNone);
}

// ---- SRCC eq. (5) and (10) on their boundaries ------------------------------------------------

TEST(SelectorExact, SRCCContourAndBrightnessBoundaries)
{
  Tiny t;
  // contour (eye along +x at d): error 10 / d: accepted from d = 10 (T_s = 1)
  int child = -1;
  EXPECT_EQ(t.RootReason(Viewer(0.5 + 9.99, 0.5, 0.5), &child), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(Viewer(0.5 + 10.01, 0.5, 0.5)), plod::AcceptedContour);
  // the contour band is |c| <= sin(theta): 0.2 rad either side of the tangent plane
  auto tilted = [](double a) { // eye at distance 100, angle a above the tangent plane
    return Viewer(0.5 + 100 * std::cos(a), 0.5, 0.5 + 100 * std::sin(a));
  };
  t.Shape[0] = 1; // 10 px on the contour: refined there, accepted front-facing
  EXPECT_EQ(t.RootReason(tilted(0.19)), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(tilted(0.21)), plod::AcceptedBrightness);
  EXPECT_EQ(t.RootReason(tilted(-0.21)), plod::BackFacing);
  // brightness, front-facing: dB h (n.v_e) k <= T_b; light along the axis, eye 60 degrees off
  // it at distance d: size h cos 60 = 0.5; dB = 1 - cos 0.2: accepted from d = 2.49
  Tiny b;
  b.Shape[0] = 0;
  const double dB = 1 - std::cos(double(0.2f)), boundary = dB * 0.5 * 1000 / 4;
  auto at = [&](double d) {
    auto in = Viewer(0.5 + d * std::sin(Pi / 3), 0.5, 0.5 + d * std::cos(Pi / 3));
    in.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
    return in;
  };
  EXPECT_EQ(b.RootReason(at(boundary - 0.01)), plod::ReasonNone);
  EXPECT_EQ(b.RootReason(at(boundary + 0.01)), plod::AcceptedBrightness);
}

// ---- parallel projection: k is pixels per unit length, v_e is against the projection --------

TEST(SelectorExact, ParallelProjection)
{
  Tiny t;
  auto parallel = [](double pixelsPerUnit, double dz) {
    auto in = Viewer(0.5, 0.5, 50); // the eye position plays no part in parallel projection
    in.Parallel = true;
    in.ProjectionDirection[0] = in.ProjectionDirection[1] = 0;
    in.ProjectionDirection[2] = dz;
    in.PixelScale = pixelsPerUnit;
    return in;
  };
  // SCVC: error 0.01 x pixels per unit: accepted up to 100 pixels per unit
  auto in = parallel(99.9, -1);
  in.Error = plod::ErrorModel::SCVC;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedError);
  in.PixelScale = 100.1;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // SRCC: looking down -z, the +z cone faces the viewer; looking up +z it faces away
  EXPECT_EQ(t.RootReason(parallel(99.9, -1)), plod::AcceptedBrightness);
  EXPECT_EQ(t.RootReason(parallel(99.9, +1)), plod::BackFacing);
  // looking along x the root is on the contour: its 0.01 error decides at 100 pixels per unit
  auto side = parallel(99.9, 0);
  side.ProjectionDirection[0] = -1;
  EXPECT_EQ(t.RootReason(side), plod::AcceptedContour);
  side.PixelScale = 100.1;
  EXPECT_EQ(t.RootReason(side), plod::ReasonNone);
}

// ---- lights, topology and the eye inside a cell ----------------------------------------------

TEST(SelectorExact, PositionalLightPointsFromTheVertexToTheLight)
{
  Tiny t;
  t.Shape[0] = 0;
  // a positional light straight above the vertex is the directional light (0, 0, 1): the same
  // brightness boundary (d = 4.98); below the vertex it lights the cone from behind: dB = 0
  const double boundary = (1 - std::cos(double(0.2f))) * 250;
  auto lit = [](double d, double lightZ) {
    auto in = Above(d);
    in.Lights.push_back(plod::SelectorLight{ true, { 0.5, 0.5, lightZ }, 1, 0 });
    return in;
  };
  EXPECT_EQ(t.RootReason(lit(boundary - 0.01, 100)), plod::ReasonNone);
  EXPECT_EQ(t.RootReason(lit(boundary + 0.01, 100)), plod::AcceptedBrightness);
  EXPECT_EQ(t.RootReason(lit(boundary - 0.01, -100)), plod::AcceptedBrightness);
}

TEST(SelectorExact, UnsafeCellsRefinedWhileTheirThicknessShows)
{
  Tiny t;
  t.Flags[0] = 0; // the root is not a union of discs (a tube)
  t.Thickness[0] = 0.01f;
  // huge tolerances: only the topology rule refines; 0.01 x 1000 / d pixels against 1 pixel
  auto at = [](double d) {
    auto in = Above(d);
    in.ContourTolerance = in.BrightnessTolerance = 1e9;
    return in;
  };
  EXPECT_EQ(t.RootReason(at(9.9)), plod::ReasonNone);
  EXPECT_NE(t.RootReason(at(10.1)), plod::ReasonNone);
  auto loose = at(4.9);
  loose.TopologyTolerance = 2; // 2 pixels: accepted from d = 5
  EXPECT_EQ(t.RootReason(loose), plod::ReasonNone);
  loose = at(5.1);
  loose.TopologyTolerance = 2;
  EXPECT_NE(t.RootReason(loose), plod::ReasonNone);
  t.Flags[0] = plod::NodeTopologySafe; // safe: no refinement
  EXPECT_NE(t.RootReason(at(1.5)), plod::ReasonNone);
}

TEST(SelectorExact, EyeInsideACellRefinesIt)
{
  Tiny t;
  // the eye inside the root cell, 0.35 from its vertex: refined however large the tolerances;
  // on the cell's face it counts as inside too; just outside it is judged by the tests
  for (const double z : { 0.85, 1.0 })
  {
    auto in = Viewer(0.5, 0.5, z);
    in.ContourTolerance = in.BrightnessTolerance = 1e9;
    int child = -1;
    EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone) << z;
    EXPECT_NE(child, plod::ReasonNone) << z;
  }
  auto out = Viewer(0.5, 0.5, 1.01);
  out.ContourTolerance = out.BrightnessTolerance = 1e9;
  EXPECT_NE(t.RootReason(out), plod::ReasonNone);
}

// ---- minimum level (distributed rendering) ----------------------------------------------------

TEST(SelectorExact, MinimumLevelRefinesCoarserCellsWithoutAnyOtherTest)
{
  // Huge tolerances accept the root; with MinimumLevel 1 the root (level 0) is refined and its
  // child (level 1, not below the minimum) is judged as usual: accepted by its size, not opened.
  Tiny t;
  auto in = Above(10);
  in.ContourTolerance = in.BrightnessTolerance = 1e9;
  EXPECT_NE(t.RootReason(in), plod::ReasonNone);
  in.MinimumLevel = 1;
  int child = -1;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::AcceptedSize);
  // not hidden as back-facing: the eye behind the surface (the root's cone faces away)
  auto behind = Viewer(0.5, 0.5, 0.5 - 10);
  EXPECT_EQ(t.RootReason(behind), plod::BackFacing);
  behind.MinimumLevel = 1;
  EXPECT_EQ(t.RootReason(behind, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::BackFacing); // the child is judged: it faces away too
  // every mode: SCVC, Distance and Cheng accept the root at these settings, not with the minimum
  for (plod::ErrorModel model :
    { plod::ErrorModel::SCVC, plod::ErrorModel::Distance, plod::ErrorModel::Cheng })
  {
    auto m = Above(10);
    m.Error = model;
    m.ContourTolerance = 1e9;
    m.FoveationRate = 100; // Cheng: a threshold near 0 at D > 0 (no fovea: D = 0, T = 1)
    m.Foveation = plod::FoveationMode::Screen;
    m.GazeDirection[0] = 1;
    m.GazeDirection[2] = 0;
    if (model != plod::ErrorModel::Cheng)
      m.Foveation = plod::FoveationMode::Off;
    EXPECT_NE(t.RootReason(m), plod::ReasonNone) << int(model);
    m.MinimumLevel = 1;
    EXPECT_EQ(t.RootReason(m), plod::ReasonNone) << int(model);
  }
  // above the finest level: the leaf is opened (drawn at full resolution)
  in.MinimumLevel = 2;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::OpenedLeaf);
  // the frustum still culls: the root wholly outside a plane is culled whatever the minimum
  in.UseFrustum = true;
  for (auto& plane : in.Planes)
  {
    plane[0] = plane[1] = 0;
    plane[2] = 1;
    plane[3] = 0; // z >= 0: the whole octree is inside
  }
  in.Planes[5][2] = -1;
  in.Planes[5][3] = -2; // z <= -2: the root lies outside
  EXPECT_EQ(t.RootReason(in), plod::Culled);
  // the child alone outside a plane (x >= 0.6): culled at level 1 after the refinement
  in.Planes[5][0] = 1;
  in.Planes[5][2] = 0;
  in.Planes[5][3] = -0.6;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_EQ(child, plod::Culled);
}

TEST(SelectorExact, MinimumLevelMustBeALevel)
{
  auto in = Above(10);
  std::string why;
  for (int level : { 0, 5, plod::MaxFinestLevel })
  {
    in.MinimumLevel = level;
    EXPECT_TRUE(plod::ValidateSelectionInput(in, &why)) << level << ": " << why;
  }
  for (int level : { -1, plod::MaxFinestLevel + 1, 1000 })
  {
    in.MinimumLevel = level;
    EXPECT_FALSE(plod::ValidateSelectionInput(in, &why)) << level;
    EXPECT_NE(why.find("minimum level"), std::string::npos) << why;
  }
}

// ---- triangle budget: priority-queue refinement from the root --------------------------------
//
// plodtest::Fork: a root (vertex (0.5, 0.5, 0.5)) with two leaves, A (node 1, vertex (0.25,
// 0.25, 0.25)) and B (node 2, vertex (0.75, 0.25, 0.25)). The eye is 10 above B, one light
// along +z, T_s = 1, T_b = 4 (screen distance 1000 px):
// - the root (axis +x, cone 1.0: on the contour) fails its contour test by 0.1 k_R = 10.3
//   (its brightness error over T_b, 0.56, is smaller), so its children get every test;
// - B (cone 0.8, eye on its axis: c = 1, k = 100, edge 0.5) fails brightness by
//   rB = (1 - cos 0.8) 0.5 x 100 / 4 = 3.79;
// - A's axis is +x: seen from 10 above it is on the contour (c = 0.05 < sin 0.2), where its
//   shape error dE fails by dE k_A / T_s, k_A = 1000 / |(0.5, 0, 10)| (its brightness error
//   over T_b, 0.12, is smaller).

namespace
{
struct ForkScene
{
  plodtest::Fork T;
  plod::SelectionInput In = Viewer(0.75, 0.25, 10.25);
  ForkScene()
  {
    this->T.Angle[0] = 1.0f;
    this->T.Angle[2] = 0.8f;
    this->T.Axis[0] = 1; // the root: +x
    this->T.Axis[2] = 0;
    this->T.Shape[0] = 0.1f;
    this->T.Axis[3] = 1; // A: +x
    this->T.Axis[5] = 0;
    this->In.Lights.push_back(plod::SelectorLight{ false, { 0, 0, 1 }, 1, 0 });
  }
  /// B's brightness error over T_b (the float cosine the selector caches).
  double B() const
  {
    return (1.0 - double(std::cos(0.8f))) * 0.5 * 100 / this->In.BrightnessTolerance;
  }
  /// The root's contour error over T_s.
  double Root() const
  {
    const double l = std::sqrt(0.25 * 0.25 * 2 + 9.75 * 9.75);
    return double(this->T.Shape[0]) * (1000 / l) / this->In.ContourTolerance;
  }
  static double KA() { return 1000 / std::sqrt(0.25 + 100); }
  /// The triangles the root, A and B own.
  void Own(int64_t root, int64_t a, int64_t b)
  {
    this->T.Owned[0] = root;
    this->T.Owned[1] = a;
    this->T.Owned[2] = b;
  }
  /// Gives A a contour error of `ratio` times its contour tolerance.
  void SetA(double ratio) { this->T.Shape[1] = float(ratio * this->In.ContourTolerance / KA()); }
  plodtest::Fork::Result Select(int64_t budget)
  {
    this->In.TriangleBudget = budget;
    return this->T.Select(this->In);
  }
};
} // namespace

TEST(SelectorExact, BudgetRefinesTheHigherErrorOverToleranceFirst)
{
  // Room for the root (0 triangles) and one leaf (10): the leaf whose error exceeds its
  // tolerance by more is opened, the other drawn at its vertex. A boundary test: A's contour
  // ratio 1 % either side of B's brightness ratio.
  ForkScene s;
  s.SetA(1.01 * s.B());
  auto r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutDrawn);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_TRUE(r.Stats.BudgetBinding);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  // the refused refinement is B's, at its error over tolerance exactly
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, s.B(), 1e-5 * s.B());
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 10);
  s.SetA(0.99 * s.B());
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.State[1], plod::CutDrawn);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 0.99 * s.B(), 1e-5 * s.B());

  // each error is over its own tolerance: T_b = 8 halves B's ratio, T_s = 2 halves A's
  s.In.BrightnessTolerance = 8;
  s.SetA(0.99 * 2 * s.B()); // 0.99 of B's ratio at T_b = 4: now above B's
  EXPECT_EQ(s.Select(10).State[1], plod::CutOpen);
  s.In.BrightnessTolerance = 4;
  s.SetA(1.01 * s.B());
  s.In.ContourTolerance = 2; // A's ratio halves
  EXPECT_EQ(s.Select(10).State[2], plod::CutOpen);
  s.In.ContourTolerance = 1;

  // micro motion along A's axis lowers its contour error as in the walk (TMM eq. 7): |n.v_f|
  // of 0.02 rB / k_A takes A from 1.01 rB to 0.99 rB (B, seen along its axis, is unchanged)
  s.In.Motion = plod::MotionModel::MicroMotion;
  s.In.MotionB[0] = 0.02 * s.B() / ForkScene::KA();
  EXPECT_EQ(s.Select(10).State[2], plod::CutOpen);
  s.In.MotionB[0] = 0;
  EXPECT_EQ(s.Select(10).State[1], plod::CutOpen);
  s.In.Motion = plod::MotionModel::None;

  // foveation multiplies each cell's tolerances by exp(K D): the gaze on B (D = 0), A's view ray
  // atan(0.05) off it: with K = 10 A's tolerance grows by 1.1725, so a contour ratio 1.1 rB
  // drops to 0.94 rB
  s.SetA(1.1 * s.B());
  EXPECT_EQ(s.Select(10).State[1], plod::CutOpen);
  s.In.Foveation = plod::FoveationMode::Screen;
  s.In.FoveationRate = 10;
  EXPECT_EQ(s.Select(10).State[2], plod::CutOpen);
  s.In.FoveationRate = 1; // factor 1.016: A still first
  EXPECT_EQ(s.Select(10).State[1], plod::CutOpen);
}

TEST(SelectorExact, BudgetRanksAContourCellByTheLargerOfItsTwoRatios)
{
  // A on the contour with a small contour error (2 x T_s) but a large shading error: its axis
  // 70 degrees from its view direction (c = cos 70 = 0.342 < sin 1.2), cone 1.2, the light 72.9
  // degrees off the axis: dB = cos(72.9 deg - 1.2) = 0.997 over 0.5 c k_A / T_b = 4.26 x T_b.
  // It outranks B (3.79) by its brightness, not by its contour error.
  ForkScene s;
  const double phi = 70 * Pi / 180 + std::atan(0.05);
  s.T.Axis[3] = float(std::sin(phi));
  s.T.Axis[5] = float(std::cos(phi));
  s.T.Angle[1] = 1.2f;
  s.SetA(2);
  auto r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, s.B(), 1e-5 * s.B());
  // T_b doubled halves both shading ratios (2.13 and 1.90) while A's contour ratio stays 2:
  // A still goes first, by its shading
  s.In.BrightnessTolerance = 8;
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
}

TEST(SelectorExact, BudgetRefinesTopologyFirst)
{
  // B is refined only for its topology (not a union of discs, 1 unit thick: 100 px), its cone
  // too narrow for a brightness error: infinitely over, before A (50 x T_s). The root is a
  // floor (minimum level 1), so the children's keys are their own.
  ForkScene s;
  s.In.MinimumLevel = 1;
  s.T.Angle[2] = 0.01f;
  s.T.Flags[2] = 0;
  s.T.Thickness[2] = 1;
  s.SetA(50);
  auto r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.TopologyRefined, 1);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 50, 1e-3);
  s.T.Flags[2] = plod::NodeTopologySafe; // safe: B is accepted, A refined
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::AcceptedBrightness);
}

TEST(SelectorExact, BudgetPriorityOfTheBaselines)
{
  // SCVC: the shape error over T_s everywhere. A (axis +x) and B (axis +z) at about the same
  // distance: the larger shape error goes first.
  ForkScene s;
  s.In.Error = plod::ErrorModel::SCVC;
  s.In.Lights.clear();
  s.T.Shape[0] = 1;      // the root: far above its tolerance (103 px)
  s.T.Shape[1] = 0.031f; // A: 0.031 x 99.88 = 3.10 px
  s.T.Shape[2] = 0.030f; // B: 0.030 x 100 = 3.00 px
  auto r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 0.030 * 100, 1e-4);
  s.T.Shape[1] = 0.0299f; // 2.986 px
  EXPECT_EQ(s.Select(10).State[2], plod::CutOpen);
  // Distance: every cell coarser than the chosen level, ranked by its edge over that level's:
  // the root (level 0, DistanceLevel 2) first at 4, then A and B at 2 each: the tie goes to the
  // smaller node index, A
  s.In.Error = plod::ErrorModel::Distance;
  s.In.DistanceLevel = 2;
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_DOUBLE_EQ(r.Stats.BudgetRefusedPriority, 2.0);
  r = s.Select(9); // not even A: the root alone is refined
  EXPECT_DOUBLE_EQ(r.Stats.BudgetRefusedPriority, 2.0);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
  // Cheng: 1 - cos 2 theta = 2 sin^2 theta over 1 - exp(-K D). B at the gaze (D = 0) is
  // infinitely over; A (D = atan(0.05) / pi, K = 100: 1 - T = 0.796) by 2 sin^2 0.2 / 0.796
  s.In.Error = plod::ErrorModel::Cheng;
  s.In.Foveation = plod::FoveationMode::Screen;
  s.In.FoveationRate = 100;
  s.T.Angle[1] = 0.7f; // A: 2 sin^2 0.7 = 0.830 > 0.796: refined
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  const double D = std::atan(0.05) / Pi;
  const double sinA = double(std::sin(0.7f));
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 2 * sinA * sinA / (1 - std::exp(-100 * D)), 1e-5);
  // a cone wider than pi/2: its largest deviation is 1 - cos(pi) = 2, not 2 sin^2 theta (which
  // would fall back towards 0 as theta nears pi and make the widest cells wait last)
  s.T.Angle[0] = 2.0f; // the root too, so that its key does not cap A's
  s.T.Angle[1] = 2.0f;
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 2.0 / (1 - std::exp(-100 * D)), 1e-5);
}

TEST(SelectorExact, BudgetPriorityOfVelocityAlonePSECFeaturesAndRims)
{
  // Velocity alone (IPV, TMM §5.3): the projected edge over T_s times the speed factor. A and B
  // are both level-1 cells (edge 0.5); B is nearer (k_B = 100 against k_A = 99.875): B first,
  // and A is refused at 0.5 k_A / (T_s factor). Unprojected edges would tie, and the tie would
  // go to A.
  ForkScene s;
  s.In.Motion = plod::MotionModel::InverseVelocity;
  auto r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 0.5 * ForkScene::KA(), 1e-5 * ForkScene::KA());
  s.In.VelocityFactor = 2; // the tolerance doubles, the ratio halves
  r = s.Select(10);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 0.25 * ForkScene::KA(), 1e-5 * ForkScene::KA());
  s.In.Motion = plod::MotionModel::None;
  s.In.VelocityFactor = 1;

  // PSEC: a feature cell (A, its cone holding the view direction's normal plane: on the
  // contour) is ranked against its reduced tolerance, PSECFactor T_s. A's shape error projects
  // to 1 px (ratio 1 / 0.25 = 4), B's to 3 px (ratio 3): A first, B refused at 3.
  s.In.Error = plod::ErrorModel::PSEC;
  s.T.Shape[1] = float(1.0 / ForkScene::KA());
  s.T.Shape[2] = 0.03f;
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 3.0, 1e-5);
  s.In.PSECFactor = 0.5; // A's ratio 2, now below B's 3
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 2.0, 1e-5);
  s.In.Error = plod::ErrorModel::SRCC;
  s.In.PSECFactor = 0.25;

  // SRCC rim (an open surface's boundary, refined like the contour until its edge passes the
  // size floor): ranked by its projected edge, 0.5 k_A = 49.9 T_s, whatever its shape error
  // (1 px here), and capped by the root's key (its contour ratio, 10.3): still above B's
  // brightness ratio (3.79), so A goes first. Ranked by its shape error it would come after B.
  s.T.Flags[1] |= plod::NodeBoundary;
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, s.B(), 1e-5 * s.B());
  s.T.Flags[1] = plod::NodeTopologySafe; // not a rim: its contour ratio 1 comes after B
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
}

TEST(SelectorExact, BudgetStopsAtTheFirstRefinementThatDoesNotFit)
{
  // A first (its ratio is larger) but it owns 20 triangles: a budget of 10 stops there, and B
  // (5, which would fit) is not refined either: a larger budget must refine a superset
  ForkScene s;
  s.In.BudgetStop = plod::BudgetStopRule::StopAtFirstMisfit;
  s.Own(0, 20, 5);
  s.SetA(1.5 * s.B());
  auto r = s.Select(10);
  EXPECT_EQ(r.State[0], plod::NotInCut); // the root (no triangle of its own) is refined
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 20);
  EXPECT_TRUE(r.Stats.BudgetBinding);
  r = s.Select(24); // A fits, then B does not
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 20);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 5);
  r = s.Select(25); // both: the tolerance cut, not binding
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_FALSE(r.Stats.BudgetBinding);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 0);
  EXPECT_EQ(r.Stats.BudgetRefusedPriority, 0);
}

TEST(SelectorExact, BudgetCountsOnlyTheTrianglesDrawn)
{
  // A (refined first: its ratio is above B's) owns 10 triangles whose faces turn away from the
  // eye, B 10 that face it. With back faces hidden (a closed surface) the budget counts what
  // the patch generator draws: A's refinement counts nothing, so a budget of 10 opens both;
  // with back faces drawn (an open surface) A's 10 fill it and B waits. A triangle whose lead
  // corner is a ghost counts nothing either (another process draws it).
  ForkScene s;
  s.Own(0, 10, 10);
  s.SetA(1.01 * s.B());
  // A's corners in A's cell, B's in B's, all at z = 0.25; the eye is far above (+z)
  const float points[18] = { 0.1f, 0.1f, 0.25f, 0.2f, 0.1f, 0.25f, 0.1f, 0.2f, 0.25f, 0.6f, 0.1f,
    0.25f, 0.7f, 0.1f, 0.25f, 0.6f, 0.2f, 0.25f };
  int32_t triangles[60];
  for (int t = 0; t < 10; ++t)
  {
    const int32_t away[3] = { 0, 2, 1 }, facing[3] = { 3, 4, 5 }; // normals -z and +z
    std::copy(away, away + 3, triangles + 3 * t);
    std::copy(facing, facing + 3, triangles + 30 + 3 * t);
  }
  s.T.NumberOfPoints = 6;
  s.T.Points = points;
  s.T.Triangles = triangles;
  ASSERT_TRUE(s.In.HideBackFaces);
  auto r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  EXPECT_EQ(r.Stats.CutTriangles, 20);
  EXPECT_FALSE(r.Stats.BudgetBinding);
  r = s.Select(9); // A still fits (it counts 0), B does not
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
  EXPECT_EQ(r.Stats.CutTriangles, 10);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 10);
  EXPECT_EQ(r.Stats.BudgetWaitingTriangles, 10);
  // a parallel projection looking down: the same faces turn away
  s.In.Parallel = true;
  s.In.ProjectionDirection[0] = s.In.ProjectionDirection[1] = 0;
  s.In.ProjectionDirection[2] = -2;
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  // looking up instead: A's faces are the drawn ones
  s.In.ProjectionDirection[2] = 2;
  r = s.Select(9);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 10);
  s.In.Parallel = false;
  // an open surface: every owned triangle counts
  s.In.HideBackFaces = false;
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  // B's lead corner (its smallest point index, 3) a ghost: B counts nothing
  const uint8_t ghost[6] = { 0, 0, 0, 1, 0, 0 };
  s.T.PointGhost = ghost;
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  EXPECT_EQ(r.Stats.CutTriangles, 20);
  // without a budget nothing is counted but the cut's triangles
  r = s.Select(0);
  EXPECT_EQ(r.Stats.BudgetTriangles, 20);
  EXPECT_EQ(r.Stats.CutTriangles, 20);
}

TEST(SelectorExact, BudgetDecidesAWholeCellOnlyWhenItsExtentAllowsIt)
{
  // Flat leaves (cones of angle 0 about +z) opened by the distance levels, the eye beside them
  // at z = 0.3: above A's centre (z = 0.25) but below A's triangles (z = 0.4), which therefore
  // face away; B's (z = 0.25) face the eye. Seen from A's centre the cone faces the eye, yet the
  // cell is too near for that to hold at every corner: its triangles are decided one by one, A
  // counts nothing and both leaves fit a budget of 10.
  plodtest::Fork t;
  t.Angle[1] = t.Angle[2] = 0;
  const float points[18] = { 0.1f, 0.1f, 0.4f, 0.2f, 0.1f, 0.4f, 0.1f, 0.2f, 0.4f, 0.6f, 0.1f,
    0.25f, 0.7f, 0.1f, 0.25f, 0.6f, 0.2f, 0.25f };
  int32_t triangles[60];
  for (int k = 0; k < 30; ++k)
    triangles[k] = k % 3; // A: normal +z
  for (int k = 30; k < 60; ++k)
    triangles[k] = 3 + k % 3; // B: normal +z
  t.NumberOfPoints = 6;
  t.Points = points;
  t.Triangles = triangles;
  plod::SelectionInput in = Viewer(-0.4, 0.25, 0.3);
  in.Error = plod::ErrorModel::Distance;
  in.DistanceLevel = 2; // both leaves opened, A first (equal keys: the smaller index)
  in.TriangleBudget = 10;
  auto r = t.Select(in);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  EXPECT_EQ(r.Stats.CutTriangles, 20);
  // the eye above both: A's triangles face it too, and B waits
  in.Eye[2] = 0.6;
  r = t.Select(in);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
}

TEST(SelectorExact, BudgetSkipsARefinementThatDoesNotFitAndMakesCheaperOnes)
{
  // The same tree with SkipMisfits (the default): A (20 triangles) does not fit in 10, is drawn
  // at its vertex, and B (5) is opened. A is still the refused refinement reported: the first
  // misfit, whose key (1.5 rB) is the largest left in the cut.
  ForkScene s;
  ASSERT_EQ(s.In.BudgetStop, plod::BudgetStopRule::SkipMisfits);
  s.Own(0, 20, 5);
  s.SetA(1.5 * s.B());
  auto r = s.Select(10);
  EXPECT_EQ(r.State[0], plod::NotInCut);
  EXPECT_EQ(r.State[1], plod::CutDrawn);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 5);
  EXPECT_TRUE(r.Stats.BudgetBinding); // the queue is empty, but a refinement was refused
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, 1.5 * s.B(), 1e-5 * s.B());
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 20);
  EXPECT_EQ(r.Stats.InCut, 2);
  EXPECT_EQ(r.Stats.Drawn, 2);
  r = s.Select(4); // neither fits
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 20);
  r = s.Select(24); // A fits; then B does not (4 left): as the stop rule
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 20);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 5);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, s.B(), 1e-5 * s.B());
  r = s.Select(25); // both: the tolerance cut
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_FALSE(r.Stats.BudgetBinding);
  EXPECT_EQ(r.Stats.BudgetRefusedPriority, 0);

  // after a misfit, a refinement that fills the room exactly is made (the walk ends only when
  // the room is below every refinement queued): B owning 10, room 10
  s.T.Owned[2] = 10;
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 10);
  r = s.Select(9);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
  // and one that adds no triangle is made even with no room left
  s.T.Owned[2] = 0;
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  // sizes beyond those the walk counts (64 and up): A (200) skipped, B (70) fits in 100
  s.T.Owned[1] = 200;
  s.T.Owned[2] = 70;
  r = s.Select(100);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 70);
  r = s.Select(69);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
}

TEST(SelectorExact, BudgetRulesAgreeUpToTheFirstMisfitAtEveryBudget)
{
  // Budgets 1 to 40 on the root (3 triangles), A (first, 20) and B (5), both rules: the count
  // is within the budget; skipping fills at least as much, and more exactly where the stop rule
  // leaves B out though it fits (below 23 triangles: root + B only); both report the same first
  // misfit, whose priority never rises with the budget (the pops before it are the same).
  ForkScene s;
  s.Own(3, 20, 5);
  s.SetA(1.5 * s.B());
  double previous = std::numeric_limits<double>::infinity();
  for (int64_t budget = 1; budget <= 40; ++budget)
  {
    s.In.BudgetStop = plod::BudgetStopRule::StopAtFirstMisfit;
    const auto stop = s.Select(budget);
    s.In.BudgetStop = plod::BudgetStopRule::SkipMisfits;
    const auto skip = s.Select(budget);
    const int64_t expectStop = budget >= 28 ? 28 : budget >= 23 ? 23 : budget >= 3 ? 3 : 0;
    const int64_t expectSkip = budget >= 28 ? 28
      : budget >= 23                        ? 23
      : budget >= 8                         ? 8
      : budget >= 3                         ? 3
                                            : 0;
    EXPECT_EQ(stop.Stats.BudgetTriangles, expectStop) << budget;
    EXPECT_EQ(skip.Stats.BudgetTriangles, expectSkip) << budget;
    EXPECT_EQ(skip.Stats.BudgetRefusedPriority, stop.Stats.BudgetRefusedPriority) << budget;
    EXPECT_EQ(skip.Stats.BudgetRefusedTriangles, stop.Stats.BudgetRefusedTriangles) << budget;
    EXPECT_EQ(skip.Stats.BudgetBinding, budget < 28) << budget;
    EXPECT_LE(skip.Stats.BudgetRefusedPriority, previous) << budget;
    previous = skip.Stats.BudgetRefusedPriority;
  }
}

TEST(SelectorExact, BudgetCountsTheTrianglesOfRefinedNodesAndOpenedLeaves)
{
  ForkScene s;
  s.Own(3, 4, 5);
  s.SetA(1.5 * s.B());
  // without a budget the walk counts too: the root refined (3), both leaves opened (4 + 5)
  auto r = s.Select(0);
  EXPECT_EQ(r.Stats.BudgetTriangles, 12);
  EXPECT_FALSE(r.Stats.BudgetBinding);
  const struct
  {
    int64_t Budget, Triangles;
    uint8_t A, B;
  } cases[] = { { 12, 12, plod::CutOpen, plod::CutOpen },
    { 11, 7, plod::CutOpen, plod::CutDrawn }, // root + A; B's 5 do not fit
    { 7, 7, plod::CutOpen, plod::CutDrawn }, { 6, 3, plod::CutDrawn, plod::CutDrawn },
    { 3, 3, plod::CutDrawn, plod::CutDrawn } };
  for (const auto& c : cases)
  {
    r = s.Select(c.Budget);
    EXPECT_EQ(r.Stats.BudgetTriangles, c.Triangles) << c.Budget;
    EXPECT_EQ(r.State[1], c.A) << c.Budget;
    EXPECT_EQ(r.State[2], c.B) << c.Budget;
    EXPECT_EQ(r.Stats.BudgetBinding, c.Budget < 12) << c.Budget;
  }
  // the root alone counts 0 triangles (it is one point): a budget below its 3 keeps it, and
  // the queue walk visits the root alone (no tolerance walk tried first)
  s.In.ToleranceCutFirst = false;
  r = s.Select(2);
  EXPECT_EQ(r.State[0], plod::CutDrawn);
  EXPECT_EQ(r.Reason[0], plod::BudgetLimited);
  EXPECT_EQ(r.State[1], plod::NotInCut);
  EXPECT_EQ(r.Stats.BudgetTriangles, 0);
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 3);
  EXPECT_EQ(r.Stats.Visited, 1);
  EXPECT_EQ(r.Stats.InCut, 1);
  EXPECT_EQ(r.Stats.Drawn, 1);
}

TEST(SelectorExact, BudgetKeysNeverExceedTheRefinementThatReachedThem)
{
  // A's own ratio (30) exceeds the root's (10.3), whose refinement reached it: A waits with the
  // root's key (monotone keys: the queue yields keys in non-increasing order), so the refused
  // priority is the root's; among equal keys the larger own ratio goes first.
  ForkScene s;
  s.T.Owned[1] = 20;
  s.SetA(30);
  ASSERT_GT(30, s.Root());
  auto r = s.Select(10);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, s.Root(), 1e-5 * s.Root());
  EXPECT_EQ(r.Stats.BudgetRefusedTriangles, 20); // A's
  // B above the root too (T_b small): both keys are the root's; the larger own ratio first
  s.T.Owned[1] = 10;
  s.In.BrightnessTolerance = 4 * s.B() / 20; // B: 20, A: 30: A first
  const double root = s.Root();
  r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, root, 1e-5 * root);
  s.SetA(15); // still above the root's key: B (20) first now
  r = s.Select(10);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_NEAR(r.Stats.BudgetRefusedPriority, root, 1e-5 * root); // A's key, the root's
}

TEST(SelectorExact, BudgetTiesGoToTheSmallerNodeIndex)
{
  // zero tolerances accept nothing: every refinement is infinitely over; A (node 1) before B
  ForkScene s;
  s.In.ContourTolerance = s.In.BrightnessTolerance = 0;
  auto r = s.Select(10);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetRefusedPriority, std::numeric_limits<double>::infinity());
}

TEST(SelectorExact, BudgetFloorsAreRefinedWhateverTheBudget)
{
  ForkScene s;
  s.T.Owned[0] = 5;
  s.SetA(2);
  // the eye inside the root and inside B: both refined with a budget of 1 (B is opened); A,
  // which does not hold the eye, waits and is refused; the floors' 15 triangles exceed the
  // budget, which is reported as binding
  s.In.Eye[0] = 0.75;
  s.In.Eye[1] = 0.25;
  s.In.Eye[2] = 0.4;
  auto r = s.Select(1);
  EXPECT_EQ(r.State[0], plod::NotInCut);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 15);
  EXPECT_TRUE(r.Stats.BudgetBinding);
  // the minimum level (distributed rendering): the root refined with a budget of 1
  s = ForkScene();
  s.T.Owned[0] = 5;
  s.SetA(2);
  s.In.MinimumLevel = 1;
  r = s.Select(1);
  EXPECT_EQ(r.State[0], plod::NotInCut);
  EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
  EXPECT_EQ(r.Reason[2], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetTriangles, 5);
  EXPECT_TRUE(r.Stats.BudgetBinding);
  s.In.MinimumLevel = 2; // the leaves too
  r = s.Select(1);
  EXPECT_EQ(r.State[1], plod::CutOpen);
  EXPECT_EQ(r.State[2], plod::CutOpen);
  EXPECT_EQ(r.Stats.BudgetTriangles, 25);
  // the topology rule is not a floor: an unsafe root (a tube) waits for the budget like any
  // refinement (first, being infinitely over)
  s = ForkScene();
  s.T.Owned[0] = 5;
  s.T.Flags[0] = 0;
  s.T.Thickness[0] = 1;
  r = s.Select(4);
  EXPECT_EQ(r.Reason[0], plod::BudgetLimited);
  EXPECT_EQ(r.Stats.BudgetRefusedPriority, std::numeric_limits<double>::infinity());
  r = s.Select(5);
  EXPECT_EQ(r.State[0], plod::NotInCut);
  EXPECT_EQ(r.Stats.TopologyRefined, 0); // the root also fails brightness
}

TEST(SelectorExact, NoBudgetOrANonBindingOneGivesTheToleranceCut)
{
  ForkScene s;
  s.T.Owned[0] = 3;
  s.SetA(2);
  const auto base = s.Select(0);
  ASSERT_EQ(base.Stats.BudgetTriangles, 23);
  // the queue walk, and the tolerance walk tried first (kept: the cut fits)
  for (const bool first : { false, true })
  {
    s.In.ToleranceCutFirst = first;
    for (int64_t budget : { int64_t(-3), int64_t(23), int64_t(24), int64_t(1) << 40 })
    {
      const auto r = s.Select(budget);
      for (int n = 0; n < 3; ++n)
      {
        EXPECT_EQ(r.State[n], base.State[n]) << budget;
        EXPECT_EQ(r.Reason[n], base.Reason[n]) << budget;
      }
      EXPECT_EQ(r.Stats.BudgetTriangles, 23);
      EXPECT_FALSE(r.Stats.BudgetBinding);
      EXPECT_EQ(r.Stats.Visited, base.Stats.Visited);
      EXPECT_EQ(r.Stats.BudgetToleranceCut, first && budget > 0) << budget;
    }
    // one less: the tolerance walk gives up, the queue walk's cut (B's larger ratio first, A
    // left unrefined)
    const auto r = s.Select(22);
    EXPECT_TRUE(r.Stats.BudgetBinding);
    EXPECT_FALSE(r.Stats.BudgetToleranceCut);
    EXPECT_EQ(r.Reason[1], plod::BudgetLimited);
    EXPECT_EQ(r.State[2], plod::CutOpen);
    EXPECT_EQ(r.Stats.BudgetTriangles, 13);
  }
}
