// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkPerceptualLODSelector and its kernel: exact small cases for every formula (SRCC
// eq. 7 and its one-line form, the specular term, contour classes, TMM on contour and
// brightness, IPV/DPV, Wang & Sato, Cheng), invariants over random views, extremes, bad input.
#include "plodCut.h"
#include "plodOctree.h"
#include "plodPatches.h"
#include "plodScanGenerator.h"
#include "plodSelector.h"
#include "plodTestUtilities.h"
#include "plodTinyOctree.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkSMPTools.h"
#include "vtkTransform.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <unistd.h>

namespace
{
constexpr double Pi = 3.14159265358979323846;

using plodtest::Tiny;
using plodtest::Viewer;

double Direct(double a, double t, double k)
{
  auto c = [k](double x) { return std::pow(std::max(0.0, std::cos(x)), k); };
  return c(std::max(0.0, a - t)) - c(std::min(Pi, a + t));
}

double Spread(double a, double t, double k = 1)
{
  return plod::ConeCosineSpread(std::cos(a), std::sin(a), std::cos(t), std::sin(t), k);
}
} // namespace

// ---- SRCC eq. (7), its one-line form, the specular term ----------------------------------------

TEST(PerceptualLODSelector, EquationSevenFourCases)
{
  // (a) the light inside the cone: 1 - cos(a + t)
  EXPECT_NEAR(Spread(0.1, 0.3), 1 - std::cos(0.4), 1e-12);
  // (b) the cone wholly lit: cos(a - t) - cos(a + t)
  EXPECT_NEAR(Spread(0.6, 0.2), std::cos(0.4) - std::cos(0.8), 1e-12);
  // (c) the cone crosses the terminator: cos(a - t)
  EXPECT_NEAR(Spread(1.3, 0.5), std::cos(0.8), 1e-12);
  // (d) the cone wholly unlit: 0
  EXPECT_NEAR(Spread(2.0, 0.2), 0.0, 1e-12);
  // a cone of angle 0 has no spread; a cone of angle pi spans the full range
  EXPECT_NEAR(Spread(0.7, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(Spread(0.7, Pi), 1.0, 1e-12);
}

TEST(PerceptualLODSelector, OneLineFormMatchesTheDefinition)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(0, Pi), power(0, 200);
  for (int i = 0; i < 20000; ++i)
  {
    const double a = angle(rng), t = angle(rng), k = i % 3 ? power(rng) : 1.0;
    ASSERT_NEAR(Spread(a, t, k), Direct(a, t, k), 1e-9) << a << " " << t << " " << k;
  }
}

TEST(PerceptualLODSelector, SpecularTermUsesTheHalfVector)
{
  // cos^k: the half vector on the axis, cone 0.3: 1 - cos(0.3)^k
  EXPECT_NEAR(Spread(0.0, 0.3, 10), 1 - std::pow(std::cos(0.3), 10), 1e-12);
  // specular powers 0 (constant: no spread) and 10,000 (a needle: spread 1 if the half vector
  // is in the cone, ~0 if it is 0.1 rad outside)
  EXPECT_NEAR(Spread(0.5, 0.3, 0), 0.0, 1e-12);
  EXPECT_NEAR(Spread(0.1, 0.3, 10000), 1.0, 1e-12);
  EXPECT_NEAR(Spread(0.4, 0.3, 10000), 0.0, 1e-12);
  EXPECT_TRUE(std::isfinite(Spread(0.4, 0.3, 1e300)));

  // In a selection: a light at 45 degrees from the axis, the eye opposite: the half vector is
  // on the axis; with a shiny material the root is refined, with a matte one it is accepted.
  Tiny t;
  t.Angle[0] = 0.05f;
  auto in = Viewer(0.5 - 100, 0.5, 0.5 + 100, 1e5);
  in.Lights.push_back({ false, { 1 / std::sqrt(2.0), 0, 1 / std::sqrt(2.0) }, 0, 1 });
  in.Diffuse = 0;
  in.Specular = 1;
  in.SpecularPower = 1000;
  in.BrightnessTolerance = 1;
  int child = 0;
  EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone);
  EXPECT_NE(child, plod::ReasonNone) << "the child (cone angle 0) takes the root's place";
  in.Lights[0].Position[0] = -1 / std::sqrt(2.0); // half vector 90 degrees off: no highlight
  EXPECT_EQ(t.RootReason(in), plod::AcceptedBrightness);
}

// ---- contour classes (a), (b), (c) and TMM ---------------------------------------------------

TEST(PerceptualLODSelector, ContourClassification)
{
  Tiny t; // axis +z, theta 0.2, shape error 0.01
  // (a) front-facing (eye above), no light: brightness accepts at once
  EXPECT_EQ(t.RootReason(Viewer(0.5, 0.5, 100)), plod::AcceptedBrightness);
  // (b) back-facing (eye below): hidden, not refined
  int child = -1;
  EXPECT_EQ(t.RootReason(Viewer(0.5, 0.5, -100), &child), plod::BackFacing);
  EXPECT_EQ(child, plod::ReasonNone);
  // (c) on the contour (eye to the side): error 0.01 * 1000 / 100 = 0.1 px <= 1: accepted
  EXPECT_EQ(t.RootReason(Viewer(100.5, 0.5, 0.5)), plod::AcceptedContour);
  // (c) with error 0.01 * 1e5 / 100 = 10 px > 1: refined to the finest child
  EXPECT_EQ(t.RootReason(Viewer(100.5, 0.5, 0.5, 1e5), &child), plod::ReasonNone);
  EXPECT_NE(child, plod::ReasonNone);
  // just inside (a) and (b): gamma = pi/2 -/+ (theta + 0.01)
  const double g1 = Pi / 2 - 0.21, g2 = Pi / 2 + 0.21;
  EXPECT_EQ(t.RootReason(Viewer(0.5 + 100 * std::sin(g1), 0.5, 0.5 + 100 * std::cos(g1), 1e5)),
    plod::AcceptedBrightness);
  EXPECT_EQ(t.RootReason(Viewer(0.5 + 100 * std::sin(g2), 0.5, 0.5 + 100 * std::cos(g2), 1e5)),
    plod::BackFacing);
  // an open surface (HideBackFaces off): the back-facing root is drawn, not hidden, and still
  // not refined
  {
    auto open = Viewer(0.5, 0.5, -100);
    open.HideBackFaces = false;
    plod::Selector sel;
    sel.SetOctree(t.View());
    uint8_t state[2] = { 0, 0 }, reason[2] = { 0, 0 };
    plod::SelectionStats stats;
    sel.Select(open, state, reason, nullptr, stats);
    EXPECT_EQ(state[0], plod::CutDrawn);
    EXPECT_EQ(reason[0], plod::BackFacing);
    EXPECT_EQ(state[1], plod::NotInCut);
    EXPECT_EQ(stats.Drawn, 1);
  }
  // a cone of angle >= pi/2 is never front- or back-facing
  t.Angle[0] = 2.0f;
  EXPECT_EQ(t.RootReason(Viewer(0.5, 0.5, -100)), plod::AcceptedContour);
}

TEST(PerceptualLODSelector, MicroMotionOnTheContour)
{
  // TMM eq. (6)-(7): tan psi_s = max(0, tan phi - |n.v_f| / d_o). The root's error 10 px is
  // refined still; a motion along n of 0.009 (90% of dE) leaves 1 px: accepted; 0.008 leaves
  // 2 px: refined.
  Tiny t;
  auto in = Viewer(100.5, 0.5, 0.5, 1e5);
  in.Motion = plod::MotionModel::MicroMotion;
  in.MotionB[2] = 0.009;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
  in.MotionB[2] = -0.009; // |n.v_f|: the sign does not matter
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
  in.MotionB[2] = 0.008;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // motion across n does not help the contour
  in.MotionB[2] = 0;
  in.MotionB[1] = 0.5;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // the same displacement written as A v: v_f = A v with A = 0.018 e_z e_x^T at x = 0.5
  in.MotionB[1] = 0;
  in.MotionA[2][0] = 0.018;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
}

TEST(PerceptualLODSelector, MicroMotionOnBrightness)
{
  // Front-facing root, a light at 60 degrees: dB = cos(pi/3 - t) - cos(pi/3 + t) = 0.3973 for
  // t = 0.2. Projected size l_p (n.v_e) k: viewer tilted 30 degrees, k = 1e4 / 100.
  Tiny t;
  const double tilt = Pi / 6;
  auto in = Viewer(0.5 + 100 * std::sin(tilt), 0.5, 0.5 + 100 * std::cos(tilt), 1e4);
  in.Lights.push_back({ false, { std::sin(Pi / 3), 0, std::cos(Pi / 3) }, 1, 0 });
  const double dB = Spread(Pi / 3, 0.2);
  const double size = 1.0 * std::cos(tilt);
  const double k = 1e4 / 100;
  in.BrightnessTolerance = 0.5 * dB * size * k; // half of what is needed
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  in.BrightnessTolerance = 1.001 * dB * size * k;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedBrightness);
  // TMM eq. (11)-(13): v_d = n projected on the plane normal to v_e: (cos tilt, 0, -sin tilt);
  // a motion of size/2 along it halves the size: accepted at the half tolerance
  in.BrightnessTolerance = 0.51 * dB * size * k;
  in.Motion = plod::MotionModel::MicroMotion;
  in.MotionB[0] = 0.5 * size * std::cos(tilt);
  in.MotionB[2] = -0.5 * size * std::sin(tilt);
  EXPECT_EQ(t.RootReason(in), plod::AcceptedBrightness);
  in.MotionB[0] = 0.4 * size * std::cos(tilt);
  in.MotionB[2] = -0.4 * size * std::sin(tilt);
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // n parallel to v_e: v_d is undefined (zero), the motion gives no reduction and no NaN
  auto top = Viewer(0.5, 0.5, 100.5, 1e4);
  top.Lights = in.Lights;
  top.Motion = plod::MotionModel::MicroMotion;
  top.MotionB[0] = 1e3;
  top.BrightnessTolerance = 0.5 * dB * 1.0 * k;
  EXPECT_EQ(t.RootReason(top), plod::ReasonNone);
  top.BrightnessTolerance = 1.001 * dB * 1.0 * k;
  EXPECT_EQ(t.RootReason(top), plod::AcceptedBrightness);
}

TEST(PerceptualLODSelector, BrightnessSpreadSaturatesAtOne)
{
  // A rendered pixel cannot vary by more than 1: dB = min(1, M_d sum L_d dC + ...). The root of
  // the tiny octree, seen from above (size 1, k = 1e4 / 100), a light at 60 degrees: one light
  // of intensity 1 gives dB = 0.3973 (unsaturated); intensity 10, or three lights of intensity
  // 1 (dB 3.97 and 1.19), give 1.
  Tiny t;
  auto in = Viewer(0.5, 0.5, 100.5, 1e4);
  const double k = 1e4 / 100;
  const double one = Spread(Pi / 3, 0.2);
  ASSERT_LT(one, 1.0);
  const plod::SelectorLight light{ false, { std::sin(Pi / 3), 0, std::cos(Pi / 3) }, 1, 0 };
  in.Lights = { light };
  in.BrightnessTolerance = 1.001 * one * k;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedBrightness);
  in.BrightnessTolerance = 0.999 * one * k;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  for (int variant = 0; variant < 2; ++variant)
  {
    if (variant == 0)
    {
      in.Lights = { light };
      in.Lights[0].Diffuse = 10;
    }
    else
    {
      in.Lights = { light, light, light };
    }
    ASSERT_GT(in.Lights.size() * in.Lights[0].Diffuse * one, 1.0) << "saturated";
    in.BrightnessTolerance = 1.001 * k; // accepts dB = 1, not more
    EXPECT_EQ(t.RootReason(in), plod::AcceptedBrightness) << variant;
    in.BrightnessTolerance = 0.999 * k;
    EXPECT_EQ(t.RootReason(in), plod::ReasonNone) << variant;
  }
}

TEST(PerceptualLODSelector, WangSatoLevelRule)
{
  // limit = 2 n0 sin(theta/2) D / N = 2 * 1 * sin(30 deg) * 10 / 1000 = 0.01: the coarsest
  // level with 2^-L <= 0.01 is 7 (0.0078125)
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, Pi / 3, 10.0, 1000), 7);
  // twice as far: one level coarser; finer than a finest level of 5: every leaf opened (6)
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, Pi / 3, 20.0, 1000), 6);
  EXPECT_EQ(plod::DistanceLevel(1.0, 5, 1.0, Pi / 3, 10.0, 1000), 6);
  // very far: the root; at distance 0: the input (every leaf opened)
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, Pi / 3, 1e9, 1000), 0);
  EXPECT_EQ(plod::DistanceLevel(1.0, 10, 1.0, Pi / 3, 0.0, 1000), 11);
}

TEST(PerceptualLODSelector, ChengFoveationThreshold)
{
  // contour error 10 px at T_s = 1: refined; with K = 3 and D = 1, the tolerance is e^3 = 20:
  // accepted. D = w_h beta / pi + w_v |Y - F_y| / H.
  Tiny t;
  auto in = Viewer(100.5, 0.5, 0.5, 1e5);
  in.Foveation = plod::FoveationMode::Object;
  in.FoveationRate = 3;
  in.FoveationUp[0] = 0;
  in.FoveationUp[1] = 0;
  in.FoveationUp[2] = 1; // vertical axis z through the centre (0.5, 0.5, 0.5)
  in.FoveationCentre[0] = in.FoveationCentre[1] = 0.5;
  in.FoveationHeight = 1;
  // the root's vertex is on the axis: beta = 0; fovea at the same height: D = 0
  in.FoveationPoint[0] = 0.9;
  in.FoveationPoint[1] = 0.5;
  in.FoveationPoint[2] = 0.5;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // fovea one height above: D = w_v * 1 = 1: e^3 = 20 > 10: accepted
  in.FoveationPoint[2] = 1.5;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
  // w_v = 0.5: e^1.5 = 4.5 < 10: refined
  in.FoveationWeights[1] = 0.5;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  // screen mode: gaze away from the vertex by pi/2: D = 1/2, e^(3/2) = 4.5: refined; by pi:
  // e^3: accepted
  in.Foveation = plod::FoveationMode::Screen;
  in.GazeDirection[0] = 0;
  in.GazeDirection[1] = 1;
  in.GazeDirection[2] = 0;
  EXPECT_EQ(t.RootReason(in), plod::ReasonNone);
  in.GazeDirection[0] = 1; // the view ray goes towards -x; gaze +x is opposite
  in.GazeDirection[1] = 0;
  EXPECT_EQ(t.RootReason(in), plod::AcceptedContour);
}

// ---- through the VTK class -------------------------------------------------------------------

namespace
{
struct Pipeline
{
  vtkSmartPointer<vtkPolyData> Model;
  vtkNew<vtkMultiscaleOctreeBuilder> Builder;
  vtkNew<vtkPerceptualLODSelector> Selector;
  vtkNew<vtkMultiscalePatchGenerator> Patches;
  explicit Pipeline(vtkPolyData* model, int level = 6)
  {
    this->Model = model;
    this->Builder->SetInputData(model);
    this->Builder->SetFinestLevel(level);
    this->Selector->SetInputConnection(this->Builder->GetOutputPort());
    this->Patches->SetInputConnection(this->Selector->GetOutputPort());
  }
  /// Eye at `eye` looking at `focus`, frustum planes from a vtkCamera.
  void Look(const double eye[3], const double focus[3], double angle = 30)
  {
    vtkNew<vtkCamera> camera;
    camera->SetPosition(eye);
    camera->SetFocalPoint(focus);
    camera->SetViewAngle(angle);
    double planes[24];
    camera->GetFrustumPlanes(16.0 / 9.0, planes);
    this->Selector->SetEyePosition(eye[0], eye[1], eye[2]);
    this->Selector->SetViewAngle(angle);
    this->Selector->SetFrustumPlanes(planes);
  }
  /// The object moved by `shift` along x since the previous frame (identity view now).
  void MovedBy(double shift)
  {
    const double prev[16] = { 1, 0, 0, -shift, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    this->Selector->SetPreviousObjectToViewMatrix(prev);
  }
  vtkMultiscaleOctree* Cut()
  {
    this->Selector->Update();
    return this->Selector->GetOutput();
  }
  std::vector<uint8_t> Array(const char* name)
  {
    auto* a = vtkUnsignedCharArray::SafeDownCast(this->Cut()->GetNodeData()->GetArray(name));
    return std::vector<uint8_t>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfTuples());
  }
};

/// Level of the cut ancestor-or-self of every finest node (-1 when it is hidden).
std::vector<int> CutLevels(vtkMultiscaleOctree* cut)
{
  plod::OctreeView v;
  cut->GetView(v);
  auto* state = vtkUnsignedCharArray::SafeDownCast(
    cut->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  std::vector<int> levels;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (v.Level[n] != v.FinestLevel)
      continue;
    int64_t a = n;
    while (state->GetValue(a) == 0)
      a = v.Parent[a];
    levels.push_back(state->GetValue(a) == 1 ? v.Level[a] : -1);
  }
  return levels;
}
} // namespace

TEST(PerceptualLODSelector, InvariantsOverRandomViews)
{
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> U(-1, 1);
  for (unsigned seed = 1; seed <= 3; ++seed)
  {
    Pipeline p(plodtest::MakeBlob(seed, 60, 0.3), 6);
    p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
    p.Selector->SetBrightnessTolerance(2);
    for (int view = 0; view < 12; ++view)
    {
      double dir[3] = { U(rng), U(rng), U(rng) };
      vtkMath::Normalize(dir);
      const double dist = 2.5 + 4 * (U(rng) + 1);
      const double eye[3] = { dist * dir[0], dist * dir[1], dist * dir[2] };
      const double focus[3] = { 0.3 * U(rng), 0.3 * U(rng), 0.3 * U(rng) };
      p.Look(eye, focus, 20 + 20 * (U(rng) + 1));
      // a valid cut
      ASSERT_TRUE(p.Cut()->HasValidCut());
      // hidden cells are culled or back-facing, and really are
      plod::OctreeView v;
      p.Cut()->GetView(v);
      const auto state = p.Array(vtkMultiscaleOctree::CutStateArrayName());
      const auto reason = p.Array(vtkPerceptualLODSelector::CutReasonArrayName());
      double planes[24];
      p.Selector->GetFrustumPlanes(planes);
      for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      {
        if (state[n] != 2)
          continue;
        ASSERT_TRUE(reason[n] == plod::Culled || reason[n] == plod::BackFacing);
        double b[6];
        p.Cut()->GetNodeBounds(n, b);
        if (reason[n] == plod::Culled)
        {
          bool outside = false;
          for (int k = 0; k < 6; ++k)
          {
            const double* pl = planes + 4 * k;
            double best = pl[3];
            for (int a = 0; a < 3; ++a)
              best += pl[a] * (pl[a] > 0 ? b[2 * a + 1] : b[2 * a]);
            outside = outside || best < 0;
          }
          ASSERT_TRUE(outside) << "culled node " << n << " is not outside the frustum";
        }
        else
        {
          double x[3], ve[3];
          p.Cut()->GetNodeVertex(n, x);
          vtkMath::Subtract(eye, x, ve);
          vtkMath::Normalize(ve);
          const double c = v.ConeAxis[3 * n] * ve[0] + v.ConeAxis[3 * n + 1] * ve[1] +
            v.ConeAxis[3 * n + 2] * ve[2];
          ASSERT_LT(c, -std::sin(v.ConeAngle[n]) + 1e-6) << "back-facing node " << n;
        }
      }
      // lowering a tolerance never makes a drawn cell coarser
      const auto base = CutLevels(p.Cut());
      p.Selector->SetContourTolerance(0.5);
      p.Selector->SetBrightnessTolerance(1);
      const auto finer = CutLevels(p.Cut());
      int coarser = 0;
      for (size_t i = 0; i < base.size(); ++i)
        coarser += (base[i] >= 0 && finer[i] >= 0 && finer[i] < base[i]);
      EXPECT_EQ(coarser, 0) << "view " << view;
      p.Selector->SetContourTolerance(1);
      p.Selector->SetBrightnessTolerance(2);
    }
  }
}

TEST(PerceptualLODSelector, MovingAwayNeverRefinesAndFasterMotionNeverRefines)
{
  Pipeline p(plodtest::MakeBlob(4, 80, 0.3), 7);
  p.Selector->AddLight(false, 0.2, 0.4, 1.0, 1.0, 0.5);
  const double focus[3] = { 0, 0, 0 };
  // (without the frustum: coming closer would otherwise push parts of the object out of view)
  // Per cell: a cell drawn at both distances is never finer farther away. (The number of
  // drawn cells may grow: from farther away more of the surface faces the eye.) Close up
  // (within about 2 object sizes here) this does not hold for every cell: v_e turns as the eye
  // moves, and a front-facing cell near the silhouette can become a contour cell, which the
  // shape test refines. Measured on this model: 264 cells finer from 2.0 to 2.6 units, 69 from
  // 2.6 to 3.4, 3 from 3.4 to 4.4, none beyond. The invariant is asserted from 5 units (about
  // 4 object radii), where v_e hardly turns.
  std::vector<int> nearLevels;
  vtkIdType drawn = 0;
  for (double dist = 5.0; dist < 300; dist *= 1.3)
  {
    const double eye[3] = { 0.3 * dist, 0.2 * dist, dist };
    p.Look(eye, focus);
    p.Selector->UseFrustumOff();
    const auto levels = CutLevels(p.Cut());
    drawn = p.Selector->GetNumberOfDrawnNodes();
    int finer = 0;
    for (size_t i = 0; i < nearLevels.size(); ++i)
      finer += nearLevels[i] >= 0 && levels[i] >= 0 && levels[i] > nearLevels[i];
    EXPECT_EQ(finer, 0) << "at distance " << dist;
    nearLevels = levels;
  }
  EXPECT_LT(drawn, 1000) << "far away, a few hundred cells";
  vtkIdType last;
  // micro motion: the object translates across the view, faster and faster
  const double eye[3] = { 0, 0, 4 };
  p.Look(eye, focus);
  p.Selector->SetMotionModelToMicroMotion();
  p.Selector->HasPreviousFrameOn();
  p.Selector->SetPreviousFrameTime(1.0 / 60);
  last = std::numeric_limits<vtkIdType>::max();
  for (double speed : { 0.0, 0.001, 0.003, 0.01, 0.03, 0.1 })
  {
    double prev[16] = { 1, 0, 0, -speed, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    p.Selector->SetPreviousObjectToViewMatrix(prev);
    p.Cut();
    EXPECT_LE(p.Selector->GetNumberOfDrawnNodes(), last) << "speed " << speed;
    last = p.Selector->GetNumberOfDrawnNodes();
  }
}

TEST(PerceptualLODSelector, InverseAndDirectVelocityLaws)
{
  Pipeline p(plodtest::MakeBlob(2, 60, 0.3), 6);
  const double focus[3] = { 0, 0, 0 };
  double eye[3] = { 0, 0, 4 };
  p.Selector->SetViewportSize(1000, 1000);
  const double ds = p.Selector->GetScreenDistance();
  p.Selector->HasPreviousFrameOn();
  p.Selector->SetPreviousFrameTime(1.0 / 60);
  p.Selector->SetFrameInterval(1.0 / 60);
  p.Selector->SetInverseVelocitySpeed(10);
  p.Selector->SetDirectVelocitySpeed(40);
  auto at = [&](double pixels) {
    // a translation of `pixels` per frame at the centre of the root (distance ~4)
    vtkMultiscaleOctree* o = p.Builder->GetOutput();
    p.Builder->Update();
    const double* org = o->GetOrigin();
    const double c[3] = { org[0] + o->GetRootEdge() / 2, org[1] + o->GetRootEdge() / 2,
      org[2] + o->GetRootEdge() / 2 };
    const double dist = std::sqrt(vtkMath::Distance2BetweenPoints(eye, c));
    const double shift = pixels * dist / ds;
    p.MovedBy(shift);
    p.Cut();
    EXPECT_NEAR(p.Selector->GetObjectSpeed(), pixels, 1e-6 * std::max(1.0, pixels));
    return p.Selector->GetNumberOfDrawnNodes();
  };
  for (int criterion : { vtkPerceptualLODSelector::VELOCITY_ALONE,
         vtkPerceptualLODSelector::VELOCITY_SCALES_ERROR_MODEL })
  {
    SCOPED_TRACE(criterion);
    // velocity alone sets one screen-space cell size: seen from 20 units, level 6's cells
    // project to about 6.5 pixels, so tolerances of 8, 16 and 64 pixels give levels 6, 5 and 3
    const bool alone = criterion == vtkPerceptualLODSelector::VELOCITY_ALONE;
    const double ts = alone ? 8 : 1;
    eye[2] = alone ? 20 : 4;
    p.Look(eye, focus);
    p.Selector->SetContourTolerance(ts);
    p.Selector->SetVelocityCriterion(criterion);
    p.Selector->SetMotionModelToInverseVelocity();
    const vtkIdType still = at(0);
    // IPV: full detail below 10 px, then tolerances x speed/10
    EXPECT_EQ(at(5), still);
    EXPECT_EQ(at(10), still);
    const vtkIdType ipv20 = at(20), ipv80 = at(80);
    EXPECT_LT(ipv20, still);
    EXPECT_LT(ipv80, ipv20);
    // ... the same as a still view with the tolerances times speed/10
    p.Selector->SetContourTolerance(2 * ts);
    p.Selector->SetBrightnessTolerance(8);
    EXPECT_EQ(at(0), ipv20);
    p.Selector->SetContourTolerance(ts);
    p.Selector->SetBrightnessTolerance(4);
    // DPV: tolerances / (1 - s/40): at 20 px doubled; at 40 px and beyond the root alone
    p.Selector->SetMotionModelToDirectVelocity();
    EXPECT_EQ(at(0), still);
    EXPECT_EQ(at(20), ipv20);
    at(40);
    EXPECT_EQ(p.Selector->GetNumberOfCutNodes(), 1);
    at(400);
    EXPECT_EQ(p.Selector->GetNumberOfCutNodes(), 1);
  }
  // velocity alone ignores shading and contours: the brightness tolerance and the lights change
  // nothing, back faces are drawn, and the still cut differs from the error model's
  p.Selector->SetVelocityCriterionToAlone();
  p.Selector->SetMotionModelToInverseVelocity();
  const vtkIdType alone = at(20);
  p.Selector->SetBrightnessTolerance(0.01);
  p.Selector->AddLight(false, 0, 0, 1, 1, 1);
  EXPECT_EQ(at(20), alone);
  p.Selector->RemoveAllLights();
  p.Selector->SetBrightnessTolerance(4);
  vtkUnsignedCharArray* reason = vtkUnsignedCharArray::SafeDownCast(
    p.Selector->GetOutput()->GetNodeData()->GetArray("CutReason"));
  ASSERT_NE(reason, nullptr);
  vtkIdType back = 0;
  for (vtkIdType n = 0; n < reason->GetNumberOfValues(); ++n)
    back += reason->GetValue(n) == plod::BackFacing ? 1 : 0;
  EXPECT_EQ(back, 0);
  p.Selector->SetVelocityCriterionToScalesErrorModel();
  EXPECT_NE(at(20), alone);
}

TEST(PerceptualLODSelector, MicroMotionScalesByFrameIntervalOverFrameTime)
{
  // v_f = v_m dt / t_m (TMM §3): a shift s measured over t_m = 2 dt is the shift s / 2 over dt
  Pipeline p(plodtest::MakeBlob(3, 60, 0.3), 6);
  const double focus[3] = { 0, 0, 0 }, eye[3] = { 0, 0, 4 };
  p.Look(eye, focus);
  p.Selector->SetViewportSize(1000, 1000);
  p.Selector->SetMotionModelToMicroMotion();
  p.Selector->HasPreviousFrameOn();
  auto cut = [&](double shift, double tm, double dt) {
    p.MovedBy(shift);
    p.Selector->SetPreviousFrameTime(tm);
    p.Selector->SetFrameInterval(dt);
    auto state = p.Array(vtkMultiscaleOctree::CutStateArrayName());
    return std::make_pair(state, p.Selector->GetObjectSpeed());
  };
  const double dt = 1.0 / 60;
  const auto slow = cut(0.02, 2 * dt, dt), half = cut(0.01, dt, dt);
  EXPECT_EQ(slow.first, half.first);
  EXPECT_NEAR(slow.second, half.second, 1e-9 * half.second);
  const auto fast = cut(0.02, dt / 2, dt), twice = cut(0.04, dt, dt);
  EXPECT_EQ(fast.first, twice.first);
  EXPECT_NEAR(fast.second, twice.second, 1e-9 * twice.second);
  EXPECT_NEAR(fast.second, 4 * slow.second, 1e-9 * fast.second);
  // the cases differ from each other: the ratio matters
  EXPECT_NE(slow.first, fast.first);
  // a longer frame interval at the same frame time: more motion
  const auto longer = cut(0.01, dt, 2 * dt);
  EXPECT_EQ(longer.first, twice.first == half.first ? half.first : cut(0.02, dt, dt).first);
  // t_m = 0: no motion (the still cut)
  const auto none = cut(0.04, 0, dt);
  p.Selector->SetMotionModelToNone();
  EXPECT_EQ(none.first, p.Array(vtkMultiscaleOctree::CutStateArrayName()));
}

TEST(PerceptualLODSelector, ObjectSpeedFromTheMotionMatricesByHand)
{
  // v_m = M_p^-1 M_c v - v (M_c, M_p object->view now and before), v_f = v_m dt / t_m; the
  // object's speed is the RMS |v_f| over the root's corners times d_s / d_o. A rotation and a
  // translation together, so that the order of the matrices matters.
  Pipeline p(plodtest::MakeBlob(3, 40, 0.3), 5);
  const double focus[3] = { 0, 0, 0 }, eye[3] = { 0.3, 0.2, 4 };
  p.Look(eye, focus);
  p.Selector->SetViewportSize(800, 600);
  p.Selector->SetMotionModelToMicroMotion();
  vtkNew<vtkTransform> now, before;
  now->RotateY(20);
  now->Translate(0.1, -0.2, -3);
  before->RotateX(-15);
  before->Translate(-0.3, 0.1, -2.5);
  double mc[16], mp[16];
  vtkMatrix4x4::DeepCopy(mc, now->GetMatrix());
  vtkMatrix4x4::DeepCopy(mp, before->GetMatrix());
  p.Selector->SetObjectToViewMatrix(mc);
  p.Selector->SetPreviousObjectToViewMatrix(mp);
  p.Selector->HasPreviousFrameOn();
  p.Selector->SetPreviousFrameTime(0.05);
  p.Selector->SetFrameInterval(0.02);
  p.Cut();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  const double* org = o->GetOrigin();
  const double edge = o->GetRootEdge();
  vtkNew<vtkMatrix4x4> inverse, product;
  inverse->DeepCopy(mp);
  inverse->Invert();
  vtkMatrix4x4::Multiply4x4(inverse, now->GetMatrix(), product);
  double sum = 0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const double v[4] = { org[0] + ((corner & 1) ? edge : 0), org[1] + ((corner & 2) ? edge : 0),
      org[2] + ((corner & 4) ? edge : 0), 1 };
    double w[4];
    product->MultiplyPoint(v, w);
    for (int a = 0; a < 3; ++a)
      sum += std::pow((w[a] - v[a]) * 0.02 / 0.05, 2);
  }
  const double centre[3] = { org[0] + edge / 2, org[1] + edge / 2, org[2] + edge / 2 };
  const double k =
    p.Selector->GetScreenDistance() / std::sqrt(vtkMath::Distance2BetweenPoints(eye, centre));
  EXPECT_NEAR(p.Selector->GetObjectSpeed(), std::sqrt(sum / 8) * k, 1e-9 * k);
}

TEST(PerceptualLODSelector, TheViewReachesTheKernelAsComputedByHand)
{
  // The VTK class's cut equals the kernel's cut for a SelectionInput written by hand from the
  // same view: world coordinates with a scaled, rotated, moved object; frustum planes; parallel
  // projection; a physical display; the Distance model's level.
  Pipeline p(plodtest::MakeBlob(5, 40, 0.3), 6);
  p.Builder->Update();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  plod::OctreeView view;
  ASSERT_TRUE(o->GetView(view));
  const double* org = view.Origin;
  const double half = 0.5 * view.RootEdge;
  vtkNew<vtkTransform> place;
  place->Translate(0.4, -0.3, 0.2);
  place->RotateZ(25);
  place->Scale(2, 2, 2);
  double m[16], inverse[16];
  vtkMatrix4x4::DeepCopy(m, place->GetMatrix());
  vtkMatrix4x4::Invert(m, inverse);
  const double eye[3] = { 1.0, 2.5, 9.0 }, focus[3] = { 0.4, -0.3, 0.2 };
  vtkNew<vtkCamera> camera;
  camera->SetPosition(eye);
  camera->SetFocalPoint(focus);
  camera->SetViewAngle(25);
  double planes[24];
  camera->GetFrustumPlanes(800.0 / 600.0, planes);
  vtkPerceptualLODSelector* sel = p.Selector;
  sel->CoordinatesAreWorldOn();
  sel->SetObjectToWorldMatrix(m);
  sel->SetEyePosition(eye[0], eye[1], eye[2]);
  sel->SetFrustumPlanes(planes);
  sel->SetViewAngle(25);
  sel->SetViewportSize(800, 600);
  sel->SetContourTolerance(0.5);

  // the hand-made input: eye and planes in the octree's local coordinates
  plod::SelectionInput in;
  double e4[4] = { eye[0], eye[1], eye[2], 1 }, local[4];
  vtkMatrix4x4::MultiplyPoint(inverse, e4, local);
  for (int a = 0; a < 3; ++a)
    in.Eye[a] = local[a] - org[a];
  in.UseFrustum = true;
  for (int q = 0; q < 6; ++q)
  {
    const double* w = planes + 4 * q;
    double obj[4];
    for (int c = 0; c < 4; ++c) // the plane (a row) times M
      obj[c] = w[0] * m[c] + w[1] * m[4 + c] + w[2] * m[8 + c] + w[3] * m[12 + c];
    for (int a = 0; a < 3; ++a)
      in.Planes[q][a] = obj[a];
    in.Planes[q][3] = obj[3] + obj[0] * org[0] + obj[1] * org[1] + obj[2] * org[2];
  }
  in.HideBackFaces = o->GetNumberOfBoundaryEdges() == 0;
  in.ContourTolerance = 0.5;
  in.PixelScale = 300.0 / std::tan(12.5 * vtkMath::Pi() / 180.0);
  auto kernelCut = [&](const plod::SelectionInput& input) {
    plod::Selector s;
    s.SetOctree(view);
    std::vector<uint8_t> state(view.NumberOfNodes, 0), reason(view.NumberOfNodes, 0);
    plod::SelectionStats stats;
    s.Select(input, state.data(), reason.data(), nullptr, stats);
    return state;
  };
  const auto perspective = kernelCut(in);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), perspective);
  EXPECT_GT(std::count(perspective.begin(), perspective.end(), plod::CutHidden), 0)
    << "the frustum hides part of the model";

  // a physical display: d_s = viewing distance / pixel pitch
  sel->UsePhysicalDisplayOn();
  sel->SetViewingDistance(600);
  sel->SetPixelPitch(0.25);
  EXPECT_DOUBLE_EQ(sel->GetScreenDistance(), 2400);
  in.PixelScale = 2400;
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), kernelCut(in));
  sel->UsePhysicalDisplayOff();

  // parallel projection: pixels per object unit = (height / 2) / parallel scale x the object's
  // scale (2); v_e against the direction of projection, in object coordinates
  sel->ParallelProjectionOn();
  sel->SetParallelScale(1.25);
  const double dop[3] = { focus[0] - eye[0], focus[1] - eye[1], focus[2] - eye[2] };
  sel->SetProjectionDirection(dop[0], dop[1], dop[2]);
  in.Parallel = true;
  in.PixelScale = 300.0 / 1.25 * 2.0;
  for (int a = 0; a < 3; ++a)
    in.ProjectionDirection[a] =
      inverse[4 * a] * dop[0] + inverse[4 * a + 1] * dop[1] + inverse[4 * a + 2] * dop[2];
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), kernelCut(in));
  sel->ParallelProjectionOff();
  in.Parallel = false;

  // Distance: Wang & Sato's level from the distance between the eye and the root's centre
  sel->SetErrorModelToDistance();
  p.Cut();
  const double d = std::sqrt(
    std::pow(in.Eye[0] - half, 2) + std::pow(in.Eye[1] - half, 2) + std::pow(in.Eye[2] - half, 2));
  EXPECT_EQ(sel->GetDistanceLevel(),
    plod::DistanceLevel(view.RootEdge, view.FinestLevel, 1.0, 25 * vtkMath::Pi() / 180, d, 600));
  in.Error = plod::ErrorModel::Distance;
  in.DistanceLevel = sel->GetDistanceLevel();
  in.PixelScale = 300.0 / std::tan(12.5 * vtkMath::Pi() / 180.0);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), kernelCut(in));
}

namespace
{
/// The kernel's cut states for `in` on `view`.
std::vector<uint8_t> KernelCut(const plod::OctreeView& view, const plod::SelectionInput& in)
{
  plod::Selector s;
  s.SetOctree(view);
  std::vector<uint8_t> state(view.NumberOfNodes, 0), reason(view.NumberOfNodes, 0);
  plod::SelectionStats stats;
  s.Select(in, state.data(), reason.data(), nullptr, stats);
  return state;
}

/// How many nodes have another state in `a` than in `b` (all of them for different sizes).
int64_t StatesThatDiffer(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b)
{
  if (a.size() != b.size())
    return static_cast<int64_t>(std::max(a.size(), b.size()));
  int64_t n = 0;
  for (size_t i = 0; i < a.size(); ++i)
    n += a[i] != b[i];
  return n;
}
} // namespace

TEST(PerceptualLODSelector, ChengObjectFoveationHeightIsTheRootEdge)
{
  // Cheng's object mode normalises the vertical distance |Y - F_y| by a height H; the filter
  // passes the root cell's edge. Its cut is the kernel's for H = RootEdge, node for node, on a
  // scene whose cut changes with H (H = 2 RootEdge gives another cut).
  Pipeline p(plodtest::MakeBlob(5, 40, 0.3), 6);
  p.Builder->Update();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  plod::OctreeView view;
  ASSERT_TRUE(o->GetView(view));
  const double* org = view.Origin;
  const double half = 0.5 * view.RootEdge;
  // the eye beside the model, the point of interest above the root cell's top, z vertical
  const double eye[3] = { org[0] + half, org[1] + half - 6, org[2] + half };
  const double fovea[3] = { org[0] + half + 0.2, org[1] + half, org[2] + view.RootEdge };
  vtkPerceptualLODSelector* sel = p.Selector;
  sel->SetErrorModelToCheng();
  sel->SetFoveationModeToObject();
  sel->SetFoveationRate(3);
  sel->SetFoveationUp(0, 0, 1);
  sel->SetFoveationPoint(fovea[0], fovea[1], fovea[2]);
  sel->SetEyePosition(eye[0], eye[1], eye[2]);
  sel->SetViewportSize(800, 600);

  plod::SelectionInput in;
  in.Error = plod::ErrorModel::Cheng;
  in.Foveation = plod::FoveationMode::Object;
  in.FoveationRate = 3;
  in.FoveationUp[0] = 0;
  in.FoveationUp[1] = 0;
  in.FoveationUp[2] = 1;
  for (int a = 0; a < 3; ++a)
  {
    in.Eye[a] = eye[a] - org[a];
    in.FoveationPoint[a] = fovea[a] - org[a];
    in.FoveationCentre[a] = half; // the vertical axis through the root cell's centre
  }
  in.HideBackFaces = o->GetNumberOfBoundaryEdges() == 0;
  in.PixelScale = 300.0 / std::tan(15.0 * vtkMath::Pi() / 180.0);
  in.FoveationHeight = view.RootEdge;
  const auto expected = KernelCut(view, in);
  EXPECT_EQ(StatesThatDiffer(p.Array(vtkMultiscaleOctree::CutStateArrayName()), expected), 0)
    << "nodes whose state is not the kernel's for H = RootEdge";
  in.FoveationHeight = 2 * view.RootEdge;
  EXPECT_GT(StatesThatDiffer(KernelCut(view, in), expected), 0)
    << "the scene must be one where H matters";
}

TEST(PerceptualLODSelector, WangSatoAngleUnderAParallelProjection)
{
  // Distance model with a parallel projection: the view angle is the one the parallel view's
  // height subtends at the root centre's distance, 2 atan(ParallelScale / d). Root cube of edge 4
  // centred at the origin, eye at d = 100 on +z, parallel scale 100, 600 pixels high: angle
  // 2 atan(1) = 90 degrees, cell edge limit 2 sin(45 deg) 100 / 600 = 0.2357: level 5 (edge
  // 0.125; level 4's 0.25 is larger). (A perspective camera's 30 degrees would give 0.0863:
  // level 6.)
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(plodtest::MakeBlob(5, 40, 0.3));
  builder->SetFinestLevel(6);
  builder->UseGivenRootCubeOn();
  builder->SetRootCubeOrigin(-2, -2, -2);
  builder->SetRootCubeEdge(4);
  vtkNew<vtkPerceptualLODSelector> sel;
  sel->SetInputConnection(builder->GetOutputPort());
  builder->Update();
  plod::OctreeView view;
  ASSERT_TRUE(builder->GetOutput()->GetView(view));
  ASSERT_EQ(view.RootEdge, 4.0);
  sel->SetErrorModelToDistance();
  sel->ParallelProjectionOn();
  sel->SetParallelScale(100);
  sel->SetProjectionDirection(0, 0, -1);
  sel->SetEyePosition(0, 0, 100);
  sel->SetViewAngle(30); // read by a perspective camera only
  sel->SetViewportSize(800, 600);
  sel->Update();
  EXPECT_NEAR(2 * std::sin(0.5 * 2 * std::atan(100.0 / 100.0)) * 100 / 600, 0.2357, 1e-4);
  EXPECT_EQ(sel->GetDistanceLevel(), 5);

  // the cut is the kernel's at that level: no drawn cell coarser than level 5, some at 5
  plod::SelectionInput in;
  in.Error = plod::ErrorModel::Distance;
  in.DistanceLevel = 5;
  in.Parallel = true;
  in.PixelScale = 0.5 * 600 / 100.0;
  in.ProjectionDirection[0] = in.ProjectionDirection[1] = 0;
  in.ProjectionDirection[2] = -1;
  in.Eye[0] = in.Eye[1] = 2;
  in.Eye[2] = 102;
  const auto expected = KernelCut(view, in);
  auto* state = vtkUnsignedCharArray::SafeDownCast(
    sel->GetOutput()->GetNodeData()->GetArray(vtkMultiscaleOctree::CutStateArrayName()));
  ASSERT_TRUE(state);
  EXPECT_EQ(StatesThatDiffer(std::vector<uint8_t>(state->GetPointer(0),
                               state->GetPointer(0) + state->GetNumberOfTuples()),
              expected),
    0)
    << "nodes whose state is not the kernel's at level 5";
  int atFive = 0;
  for (int64_t n = 0; n < view.NumberOfNodes; ++n)
  {
    if (state->GetValue(n) == plod::CutDrawn)
    {
      EXPECT_GE(int(view.Level[n]), 5) << n;
      atFive += view.Level[n] == 5;
    }
  }
  EXPECT_GT(atFive, 0);
}

// ---- extremes
// ------------------------------------------------------------------------------------

TEST(PerceptualLODSelector, Extremes)
{
  Pipeline p(plodtest::MakeBlob(5, 40, 0.3), 5);
  p.Selector->AddLight(false, 0, 0, 1, 1, 1);
  p.Builder->Update();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  const double focus[3] = { 0, 0, 0 };
  // the eye on a representative vertex and inside the root cell: valid cut, the cells around
  // the eye at the finest level
  double x[3];
  o->GetNodeVertex(o->FindNode(focus, 3) >= 0 ? o->FindNode(focus, 3) : 10, x);
  for (const double* eye : { static_cast<const double*>(x), focus })
  {
    p.Selector->SetEyePosition(eye[0], eye[1], eye[2]);
    p.Selector->UseFrustumOff();
    ASSERT_TRUE(p.Cut()->HasValidCut());
    const vtkIdType home = o->FindNode(eye, 5);
    if (home >= 0)
    {
      const auto reason = p.Array(vtkPerceptualLODSelector::CutReasonArrayName());
      EXPECT_EQ(reason[home], plod::OpenedLeaf);
    }
  }
  // 1e9 units away: the root alone
  const double far[3] = { 0, 0, 1e9 };
  p.Look(far, focus);
  p.Cut();
  EXPECT_EQ(p.Selector->GetNumberOfCutNodes(), 1);
  // a light at a vertex
  p.Selector->SetNumberOfLights(1);
  p.Selector->SetLight(0, true, x[0], x[1], x[2], 1, 1);
  const double eye[3] = { 0, 0, 3 };
  p.Look(eye, focus);
  ASSERT_TRUE(p.Cut()->HasValidCut());
  // specular powers 0 and 10,000
  for (double power : { 0.0, 1e4 })
  {
    p.Selector->SetSpecularPower(power);
    ASSERT_TRUE(p.Cut()->HasValidCut()) << power;
  }
  // tolerance 0: the finest level wherever visible; huge: the root alone
  p.Selector->UseFrustumOff();
  p.Selector->SetContourTolerance(0);
  p.Selector->SetBrightnessTolerance(0);
  p.Cut();
  plod::OctreeView v;
  p.Cut()->GetView(v);
  const auto state = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (state[n] == 1)
    {
      ASSERT_EQ(v.Level[n], v.FinestLevel);
    }
  }
  p.Selector->SetContourTolerance(1e300);
  p.Selector->SetBrightnessTolerance(HUGE_VAL);
  p.Cut();
  EXPECT_GT(p.Selector->GetNumberOfCutNodes(), 1) << "the closed surface's root is no disc";
  p.Selector->SetTopologyTolerance(HUGE_VAL);
  p.Cut();
  EXPECT_EQ(p.Selector->GetNumberOfCutNodes(), 1);
  EXPECT_NE(std::string(p.Selector->GetEmptyCutReason()).find("root alone"), std::string::npos);
  p.Selector->SetTopologyTolerance(1);
  // t_m = 0 with micro motion: no motion, no division by zero
  p.Selector->SetContourTolerance(1);
  p.Selector->SetBrightnessTolerance(4);
  p.Selector->SetMotionModelToMicroMotion();
  p.Selector->HasPreviousFrameOn();
  p.Selector->SetPreviousFrameTime(0);
  const vtkIdType before = (p.Cut(), p.Selector->GetNumberOfDrawnNodes());
  p.Selector->SetMotionModelToNone();
  EXPECT_EQ((p.Cut(), p.Selector->GetNumberOfDrawnNodes()), before);
  // parallel projection and a physical display give valid cuts
  p.Selector->ParallelProjectionOn();
  p.Selector->SetParallelScale(1.5);
  ASSERT_TRUE(p.Cut()->HasValidCut());
  p.Selector->ParallelProjectionOff();
  p.Selector->UsePhysicalDisplayOn();
  ASSERT_TRUE(p.Cut()->HasValidCut());
}

// Found by Testing/Fuzz/FuzzOctreeBuild (corpus: seed-regression-psec-factor): with a PSEC
// factor of 0, a zero contour tolerance accepted flat cells on the contour (the factor turned
// the 'accept nothing' tolerance into 0); the kernel's check now refuses what the VTK class does.
TEST(PerceptualLODSelector, PSECFactorMustBePositiveAndZeroToleranceAcceptsNothing)
{
  plod::SelectionInput in = Viewer(5, 0.5, 0.5); // on the root's contour
  in.Error = plod::ErrorModel::PSEC;
  in.ContourTolerance = 0;
  std::string why;
  for (double bad : { 0.0, -1.0, std::nan(""), HUGE_VAL })
  {
    in.PSECFactor = bad;
    EXPECT_FALSE(plod::ValidateSelectionInput(in, &why)) << bad;
  }
  Tiny t;
  t.Shape[0] = 0; // flat: an error of exactly 0
  for (double good : { 0.25, 1e-300 })
  {
    in.PSECFactor = good;
    ASSERT_TRUE(plod::ValidateSelectionInput(in, &why)) << why;
    int child = -1;
    EXPECT_EQ(t.RootReason(in, &child), plod::ReasonNone) << "tolerance 0 accepts nothing";
    EXPECT_EQ(child, plod::OpenedLeaf);
  }
}

TEST(PerceptualLODSelector, BadInputKeepsThePreviousCut)
{
  Pipeline p(plodtest::MakeBlob(6, 40, 0.3), 5);
  const double focus[3] = { 0, 0, 0 }, eye[3] = { 0.5, 0.5, 3 };
  p.Look(eye, focus);
  const auto good = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  auto expectKept = [&](const char* what) {
    vtkNew<plodtest::ErrorRecorder> errors;
    const unsigned long tag = p.Selector->AddObserver(vtkCommand::ErrorEvent, errors);
    const auto after = p.Array(vtkMultiscaleOctree::CutStateArrayName());
    EXPECT_TRUE(errors->HasError("Invalid input")) << what;
    EXPECT_EQ(after, good) << what;
    p.Selector->RemoveObserver(tag);
  };
  p.Selector->SetEyePosition(std::nan(""), 0, 3);
  expectKept("NaN eye");
  p.Selector->SetEyePosition(0.5, 0.5, 3);
  p.Selector->SetViewAngle(HUGE_VAL);
  expectKept("infinite view angle");
  p.Selector->SetViewAngle(30);
  p.Selector->SetViewportSize(0, 100);
  expectKept("empty viewport");
  p.Selector->SetViewportSize(1920, 1080);
  p.Selector->AddLight(true, HUGE_VAL, 0, 0, 1, 1);
  expectKept("infinite light");
  p.Selector->RemoveAllLights();
  double planes[24];
  p.Selector->GetFrustumPlanes(planes);
  planes[5] = std::nan("");
  p.Selector->SetFrustumPlanes(planes);
  expectKept("NaN plane");
}

// Issue 24: a light of negative intensity or a reflectance below 0 made a brightness change
// negative, and the selector accepted cells it must refine; both are refused like non-finite
// values, with a message naming the values, and the previous cut stays.
TEST(PerceptualLODSelector, NegativeLightsAndReflectancesOutsideZeroOneAreRefused)
{
  Pipeline p(plodtest::MakeBlob(6, 40, 0.3), 5);
  const double focus[3] = { 0, 0, 0 }, eye[3] = { 0.5, 0.5, 3 };
  p.Look(eye, focus);
  p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
  const auto good = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  auto expectRefused = [&](const std::string& message) {
    vtkNew<plodtest::ErrorRecorder> errors;
    const unsigned long tag = p.Selector->AddObserver(vtkCommand::ErrorEvent, errors);
    const auto after = p.Array(vtkMultiscaleOctree::CutStateArrayName());
    p.Selector->RemoveObserver(tag);
    ASSERT_EQ(errors->Errors.size(), 1u) << message;
    EXPECT_NE(errors->Errors[0].find("Invalid input: "), std::string::npos) << errors->Errors[0];
    EXPECT_NE(errors->Errors[0].find(message), std::string::npos) << errors->Errors[0];
    EXPECT_NE(errors->Errors[0].find("the previous cut is kept"), std::string::npos);
    EXPECT_EQ(after, good) << message;
    EXPECT_TRUE(p.Cut()->HasValidCut()) << message;
  };
  p.Selector->SetDiffuseReflectance(-0.5);
  expectRefused(
    "the diffuse and specular reflectances must be in [0, 1] (got diffuse -0.5, specular 0.3)");
  p.Selector->SetDiffuseReflectance(1.5);
  expectRefused("(got diffuse 1.5, specular 0.3)");
  p.Selector->SetDiffuseReflectance(1);
  p.Selector->SetSpecularReflectance(-1e-9);
  expectRefused("(got diffuse 1, specular -1e-09)");
  p.Selector->SetSpecularReflectance(0.3);
  p.Selector->SetLight(0, false, 0.3, 0.6, 1.0, -0.8, 0.5);
  expectRefused("light 0 has a negative intensity (diffuse -0.8, specular 0.5); intensities must "
                "be >= 0");
  p.Selector->SetLight(0, false, 0.3, 0.6, 1.0, 0.8, 0.5);
  p.Selector->AddLight(true, 0, 0, 5, 1, -2);
  expectRefused("light 1 has a negative intensity (diffuse 1, specular -2)");

  // the bounds themselves are valid: reflectances 0 and 1, lights of intensity 0 (or above 1)
  p.Selector->SetLight(1, true, 0, 0, 5, 0, 0);
  for (const double m : { 0.0, 1.0 })
  {
    p.Selector->SetDiffuseReflectance(m);
    p.Selector->SetSpecularReflectance(1 - m);
    vtkNew<plodtest::ErrorRecorder> errors;
    const unsigned long tag = p.Selector->AddObserver(vtkCommand::ErrorEvent, errors);
    EXPECT_TRUE(p.Cut()->HasValidCut());
    p.Selector->RemoveObserver(tag);
    EXPECT_TRUE(errors->Errors.empty()) << errors->Errors[0];
  }

  // the kernel says the same to a caller without the VTK class
  plod::SelectionInput in = Viewer(5, 0.5, 0.5);
  in.Lights.push_back({ false, { 0, 0, 1 }, 10, 0 });
  std::string why;
  EXPECT_TRUE(plod::ValidateSelectionInput(in, &why)) << why;
  in.Lights[0].Diffuse = -1;
  EXPECT_FALSE(plod::ValidateSelectionInput(in, &why));
  EXPECT_NE(why.find("light 0 has a negative intensity"), std::string::npos) << why;
  in.Lights[0].Diffuse = 1;
  in.Specular = -0.25;
  EXPECT_FALSE(plod::ValidateSelectionInput(in, &why));
  EXPECT_NE(why.find("specular -0.25"), std::string::npos) << why;

  // before any valid frame there is no cut to keep: the output is empty, and empty is drawn
  Pipeline fresh(p.Model, 5);
  fresh.Look(eye, focus);
  fresh.Selector->AddLight(false, 0, 0, 1, -1, 1);
  vtkNew<plodtest::ErrorRecorder> errors;
  fresh.Selector->AddObserver(vtkCommand::ErrorEvent, errors);
  fresh.Patches->Update();
  EXPECT_TRUE(errors->HasError("light 0 has a negative intensity"));
  EXPECT_EQ(fresh.Selector->GetOutput()->GetNumberOfNodes(), 0);
  EXPECT_EQ(fresh.Patches->GetNumberOfTriangles(), 0);
}

// Issue 24: a zero-size viewport (a hidden or collapsed window) gets its own message, with the
// size, and blames nothing else (not the view angle).
TEST(PerceptualLODSelector, ZeroSizeViewportIsNamedInItsMessage)
{
  Pipeline p(plodtest::MakeBlob(6, 40, 0.3), 5);
  const double focus[3] = { 0, 0, 0 }, eye[3] = { 0.5, 0.5, 3 };
  p.Look(eye, focus);
  const auto good = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  const int sizes[4][2] = { { 0, 100 }, { 640, 0 }, { 0, 0 }, { -5, 480 } };
  for (const auto& size : sizes)
  {
    for (const bool parallel : { false, true })
    {
      p.Selector->SetParallelProjection(parallel);
      p.Selector->SetViewportSize(size[0], size[1]);
      vtkNew<plodtest::ErrorRecorder> errors;
      const unsigned long tag = p.Selector->AddObserver(vtkCommand::ErrorEvent, errors);
      const auto after = p.Array(vtkMultiscaleOctree::CutStateArrayName());
      p.Selector->RemoveObserver(tag);
      ASSERT_EQ(errors->Errors.size(), 1u);
      const std::string& e = errors->Errors[0];
      EXPECT_NE(e.find("Invalid input: the viewport size is " + std::to_string(size[0]) + " x " +
                  std::to_string(size[1]) + " pixels; width and height must be positive"),
        std::string::npos)
        << e;
      EXPECT_EQ(e.find("view angle"), std::string::npos) << e;
      EXPECT_EQ(e.find("screen distance"), std::string::npos) << e;
      EXPECT_EQ(after, good);
    }
  }
  // the camera's own problems keep their message
  p.Selector->SetParallelProjection(false);
  p.Selector->SetViewportSize(1920, 1080);
  p.Selector->SetViewAngle(0);
  vtkNew<plodtest::ErrorRecorder> errors;
  p.Selector->AddObserver(vtkCommand::ErrorEvent, errors);
  p.Cut();
  EXPECT_TRUE(errors->HasError("the view angle must be in (0, 180) degrees"));
  EXPECT_FALSE(errors->HasError("viewport"));
}

TEST(PerceptualLODSelector, ReExecutesOnlyOnChangeAndNeverRebuilds)
{
  Pipeline p(plodtest::MakeBlob(7, 40, 0.3), 5);
  int builds = 0, selections = 0;
  vtkNew<vtkCallbackCommand> b, s;
  b->SetClientData(&builds);
  b->SetCallback([](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
  s->SetClientData(&selections);
  s->SetCallback([](vtkObject*, unsigned long, void* c, void*) { ++*static_cast<int*>(c); });
  p.Builder->AddObserver(vtkCommand::EndEvent, b);
  p.Selector->AddObserver(vtkCommand::EndEvent, s);
  const double focus[3] = { 0, 0, 0 };
  for (int frame = 0; frame < 10; ++frame)
  {
    const double eye[3] = { std::sin(0.1 * frame) * 3, 0, std::cos(0.1 * frame) * 3 };
    p.Look(eye, focus);
    p.Patches->Update();
  }
  EXPECT_EQ(builds, 1);
  EXPECT_EQ(selections, 10);
  // the same values again: nothing re-executes
  const double eye[3] = { std::sin(0.9) * 3, 0, std::cos(0.9) * 3 };
  p.Look(eye, focus);
  p.Selector->SetContourTolerance(p.Selector->GetContourTolerance());
  p.Patches->Update();
  EXPECT_EQ(selections, 10);
  EXPECT_GT(p.Selector->GetNumberOfVisitedNodes(), 0);
  EXPECT_GE(p.Selector->GetSelectTime(), 0.0);
}

TEST(PerceptualLODSelector, FollowsArraysReplacedBetweenFrames)
{
  // The selector keeps its output and its caches from frame to frame (GetCheckedView, the
  // prepared output): an array replaced in the input, or another input object with the same
  // arrays, must still reach the next cut and the output.
  Pipeline p(plodtest::MakeBlob(7, 40, 0.3), 5);
  p.Builder->Update();
  vtkNew<vtkMultiscaleOctree> octree;
  octree->ShallowCopy(p.Builder->GetOutput());
  p.Selector->SetInputData(octree);
  // made before the first frame: older than every array the selector sees
  vtkNew<vtkFloatArray> flat;
  flat->DeepCopy(octree->GetNodeData()->GetArray(vtkMultiscaleOctree::ConeAngleArrayName()));
  for (vtkIdType n = 0; n < flat->GetNumberOfTuples(); ++n)
    flat->SetValue(n, 0.0f); // every cell flat: no contour but at the rim of the view
  const double focus[3] = { 0, 0, 0 }, eye[3] = { 0.4, 0.3, 3 };
  p.Look(eye, focus);
  const auto before = p.Array(vtkMultiscaleOctree::CutStateArrayName());

  octree->GetNodeData()->AddArray(flat); // replaces the array of that name
  const double eye2[3] = { 0.41, 0.3, 3 };
  p.Look(eye2, focus);
  const auto after = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  Pipeline q(p.Model, 5); // a selector that has seen only the replaced array
  q.Selector->SetInputData(octree);
  q.Look(eye2, focus);
  EXPECT_EQ(after, q.Array(vtkMultiscaleOctree::CutStateArrayName()))
    << "the cut follows the replaced cone angles";
  EXPECT_NE(after, before) << "flat cones change the cut (else this test shows nothing)";
  EXPECT_EQ(p.Cut()->GetNodeData()->GetArray(vtkMultiscaleOctree::ConeAngleArrayName()), flat.Get())
    << "the output carries the replaced array";

  // another input object, the same arrays, its own field data: the output follows it
  vtkNew<vtkMultiscaleOctree> other;
  other->ShallowCopy(octree);
  vtkNew<vtkIntArray> tag;
  tag->SetName("Tag");
  tag->InsertNextValue(7);
  vtkNew<vtkFieldData> fd;
  fd->AddArray(tag);
  other->SetFieldData(fd);
  p.Selector->SetInputData(other);
  vtkMultiscaleOctree* out = p.Cut();
  ASSERT_NE(out->GetFieldData(), nullptr);
  EXPECT_NE(out->GetFieldData()->GetArray("Tag"), nullptr);
  EXPECT_NE(out->GetFieldData()->GetArray(vtkMultiscaleOctree::CutViewArrayName()), nullptr);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), after) << "same arrays, same view";
}

TEST(PerceptualLODSelector, MinimumLevelRefinesEveryCoarserCellButCulledOnes)
{
  // Distributed rendering: with MinimumLevel m no cut cell is coarser than m unless it is
  // culled; a cell outside the frustum is still culled whatever its level; MinimumLevel 0 gives
  // the previous cut exactly.
  Pipeline p(plodtest::MakeBlob(8, 40, 0.3), 6);
  p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
  p.Selector->SetContourTolerance(4); // coarse cells accepted without the minimum
  const double focus[3] = { 0.6, 0.2, 0 };
  const std::vector<std::array<double, 3>> eyes = { { 0.8, 0.3, 2.5 }, { -4, 1, 6 }, { 9, -2, 1 } };
  int culledBelow = 0; // cut cells coarser than the minimum: all culled, and some exist
  for (const auto& eye : eyes)
  {
    p.Look(eye.data(), focus);
    p.Selector->SetMinimumLevel(0);
    const auto state0 = p.Array(vtkMultiscaleOctree::CutStateArrayName());
    const auto reason0 = p.Array(vtkPerceptualLODSelector::CutReasonArrayName());
    plod::OctreeView v;
    ASSERT_TRUE(p.Cut()->GetView(v));
    int coarsest = 99;
    for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      if (state0[n] != plod::NotInCut && reason0[n] != plod::Culled)
        coarsest = std::min<int>(coarsest, v.Level[n]);
    for (int m : { 1, 3, 5, 6 })
    {
      p.Selector->SetMinimumLevel(m);
      ASSERT_TRUE(p.Cut()->HasValidCut()) << m;
      const auto state = p.Array(vtkMultiscaleOctree::CutStateArrayName());
      const auto reason = p.Array(vtkPerceptualLODSelector::CutReasonArrayName());
      int atMinimum = 0;
      for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      {
        if (state[n] == plod::NotInCut)
          continue;
        if (v.Level[n] < m)
        {
          ASSERT_EQ(reason[n], plod::Culled) << "eye " << eye[0] << " level " << int(v.Level[n]);
          ++culledBelow;
        }
        atMinimum += v.Level[n] == m && reason[n] != plod::Culled;
      }
      if (m > coarsest)
      {
        EXPECT_GT(atMinimum, 0) << m; // cells the view would accept coarser stop at m
      }
      // the frustum still culls: the cells the walk without the minimum culls at levels up to m
      // are culled with it (the walk reaches them: their ancestors are coarser than m)
      for (int64_t n = 0; n < v.NumberOfNodes; ++n)
      {
        if (state0[n] != plod::NotInCut && reason0[n] == plod::Culled && v.Level[n] <= m)
        {
          EXPECT_EQ(reason[n], plod::Culled) << "a culled cell of level " << int(v.Level[n]);
        }
      }
    }
    // the previous cut exactly
    p.Selector->SetMinimumLevel(0);
    EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), state0);
    EXPECT_EQ(p.Array(vtkPerceptualLODSelector::CutReasonArrayName()), reason0);
    EXPECT_LT(coarsest, 3) << "the view without the minimum accepts coarse cells";
  }
  EXPECT_GT(culledBelow, 0);
  // a view that sees none of the object: the root is culled whatever the minimum
  const double away[3] = { 0, 0, 5 }, sky[3] = { 0, 0, 10 };
  p.Look(away, sky);
  p.Selector->SetMinimumLevel(4);
  p.Cut();
  EXPECT_EQ(p.Selector->GetNumberOfCutNodes(), 1);
  EXPECT_EQ(p.Array(vtkPerceptualLODSelector::CutReasonArrayName())[0], plod::Culled);
  // clamped to [0, 21], printed
  p.Selector->SetMinimumLevel(-3);
  EXPECT_EQ(p.Selector->GetMinimumLevel(), 0);
  p.Selector->SetMinimumLevel(40);
  EXPECT_EQ(p.Selector->GetMinimumLevel(), 21);
  std::ostringstream text;
  p.Selector->PrintSelf(text, vtkIndent());
  EXPECT_NE(text.str().find("MinimumLevel: 21"), std::string::npos);
}

TEST(PerceptualLODSelector, OctreesCoarsestDrawnLevelActsAsTheMinimumLevel)
{
  // An octree assembled from pieces whose levels above the pieces could not be built holds
  // only structure above its coarsest drawn level: the selector refines those levels as
  // MinimumLevel does, and the larger of the two applies.
  Pipeline p(plodtest::MakeBlob(8, 40, 0.3), 6);
  p.Selector->SetContourTolerance(4);
  const double eye[3] = { -4, 1, 6 }, focus[3] = { 0.6, 0.2, 0 };
  p.Look(eye, focus);
  std::map<int, std::vector<uint8_t>> byMinimum;
  for (int m : { 0, 3, 5 })
  {
    p.Selector->SetMinimumLevel(m);
    byMinimum[m] = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  }
  ASSERT_NE(byMinimum[0], byMinimum[3]);
  ASSERT_NE(byMinimum[3], byMinimum[5]);
  vtkNew<vtkMultiscaleOctree> assembled;
  assembled->ShallowCopy(p.Builder->GetOutput());
  assembled->SetCoarsestDrawnLevel(3);
  p.Selector->SetInputData(assembled);
  p.Selector->SetMinimumLevel(0);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), byMinimum[3]);
  p.Selector->SetMinimumLevel(5); // the larger applies
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), byMinimum[5]);
  p.Selector->SetMinimumLevel(1);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), byMinimum[3]);
  // copies keep it; clamped to [0, 21]
  vtkNew<vtkMultiscaleOctree> copy;
  copy->DeepCopy(assembled);
  EXPECT_EQ(copy->GetCoarsestDrawnLevel(), 3);
  copy->SetCoarsestDrawnLevel(30);
  EXPECT_EQ(copy->GetCoarsestDrawnLevel(), 21);
}

// ---- triangle budget on real octrees -----------------------------------------------------------

namespace
{
/// The kernel on a built octree: selections in octree-local coordinates, their cuts and patches.
struct BudgetScene
{
  vtkNew<vtkMultiscaleOctreeBuilder> Builder;
  plod::OctreeView View;
  plod::Selector Kernel;
  std::vector<uint8_t> State, Reason, Mask;
  plod::PatchResult Patches;
  bool Closed = true;

  BudgetScene(vtkPolyData* model, int level)
  {
    this->Builder->SetInputData(model);
    this->Builder->SetFinestLevel(level);
    this->Builder->Update();
    this->Builder->GetOutput()->GetView(this->View);
    this->Closed = this->Builder->GetOutput()->GetNumberOfBoundaryEdges() == 0;
    this->Kernel.SetOctree(this->View);
    this->State.assign(this->View.NumberOfNodes, 0);
    this->Reason.assign(this->View.NumberOfNodes, 0);
    this->Mask.assign(this->View.NumberOfNodes, 0);
  }
  /// A view from `eye` towards `focus` (world coordinates), frustum from a vtkCamera, one light.
  plod::SelectionInput Look(const double eye[3], const double focus[3], double angle = 30) const
  {
    vtkNew<vtkCamera> camera;
    camera->SetPosition(eye);
    camera->SetFocalPoint(focus);
    camera->SetViewAngle(angle);
    double planes[24];
    camera->GetFrustumPlanes(16.0 / 9.0, planes);
    plod::SelectionInput in;
    const double* o = this->View.Origin;
    for (int a = 0; a < 3; ++a)
      in.Eye[a] = eye[a] - o[a];
    in.UseFrustum = true;
    for (int p = 0; p < 6; ++p)
    {
      const double* w = planes + 4 * p;
      for (int a = 0; a < 3; ++a)
        in.Planes[p][a] = w[a];
      in.Planes[p][3] = w[3] + w[0] * o[0] + w[1] * o[1] + w[2] * o[2];
    }
    in.PixelScale = 540 / std::tan(0.5 * angle * Pi / 180);
    in.HideBackFaces = this->Closed;
    double light[3] = { 0.3, 0.6, 1.0 };
    vtkMath::Normalize(light);
    in.Lights.push_back({ false, { light[0], light[1], light[2] }, 0.8, 0.5 });
    in.Specular = 0.3;
    in.SpecularPower = 20;
    return in;
  }
  plod::SelectionStats Select(const plod::SelectionInput& in)
  {
    plod::SelectionStats stats;
    this->Kernel.Select(in, this->State.data(), this->Reason.data(), this->Mask.data(), stats);
    return stats;
  }
  /// Triangles GeneratePatches draws for the current cut (every triangle it may draw: no
  /// back-face culling).
  int64_t PatchTriangles()
  {
    std::string why;
    EXPECT_TRUE(
      plod::GeneratePatches(this->View, this->State.data(), this->Mask.data(), this->Patches, &why))
      << why;
    return static_cast<int64_t>(this->Patches.Triangles.size() / 3);
  }
  /// 1 for the refined nodes of the current cut: strictly above it, or opened leaves.
  std::vector<uint8_t> Refined() const
  {
    std::vector<uint8_t> above(this->View.NumberOfNodes, 0), refined(this->View.NumberOfNodes, 0);
    for (int64_t n = 0; n < this->View.NumberOfNodes; ++n)
    {
      const int32_t p = this->View.Parent[n];
      above[n] = this->State[n] == plod::NotInCut && (p < 0 || above[p]);
      refined[n] = above[n] || this->State[n] == plod::CutOpen;
    }
    return refined;
  }
  /// The triangles the cells left unrefined by the budget (BudgetLimited) own.
  int64_t Limited() const
  {
    int64_t sum = 0;
    for (int64_t n = 0; n < this->View.NumberOfNodes; ++n)
      if (this->State[n] != plod::NotInCut && this->Reason[n] == plod::BudgetLimited)
        sum += this->View.TriangleEnd(n) - this->View.FirstTriangle[n];
    return sum;
  }
  /// The triangles the refined nodes own, counted here from the octree's arrays.
  int64_t Owned(const std::vector<uint8_t>& refined) const
  {
    int64_t sum = 0;
    for (int64_t n = 0; n < this->View.NumberOfNodes; ++n)
      if (refined[n])
        sum += this->View.TriangleEnd(n) - this->View.FirstTriangle[n];
    return sum;
  }
  /// Whether input triangle t faces away from the eye of `in` (or along its projection).
  bool FacesAway(const plod::SelectionInput& in, int64_t t) const
  {
    const int32_t* c = &this->View.Triangles[3 * t];
    const float* x0 = &this->View.Points[3 * c[0]];
    const float* x1 = &this->View.Points[3 * c[1]];
    const float* x2 = &this->View.Points[3 * c[2]];
    double e1[3], e2[3], d[3], f[3];
    for (int a = 0; a < 3; ++a)
    {
      e1[a] = double(x1[a]) - x0[a];
      e2[a] = double(x2[a]) - x0[a];
      d[a] = in.Parallel ? -in.ProjectionDirection[a] : in.Eye[a] - x0[a];
    }
    vtkMath::Cross(e1, e2, f);
    return vtkMath::Dot(f, d) < 0;
  }
  /// What a budget counts of the triangles the refined nodes own, counted here triangle by
  /// triangle: when back faces are hidden those facing the eye, else all.
  int64_t Counted(const std::vector<uint8_t>& refined, const plod::SelectionInput& in) const
  {
    int64_t sum = 0;
    for (int64_t n = 0; n < this->View.NumberOfNodes; ++n)
      for (int64_t t = this->View.FirstTriangle[n]; refined[n] && t < this->View.TriangleEnd(n);
           ++t)
        sum += in.HideBackFaces && this->FacesAway(in, t) ? 0 : 1;
    return sum;
  }
  /// Triangles GeneratePatches draws for the current cut, back faces culled as the patch
  /// generator culls them after the selector hid them.
  int64_t DrawnTriangles(const plod::SelectionInput& in)
  {
    plod::PatchOptions o;
    o.CullBackFaces = in.HideBackFaces;
    o.Parallel = in.Parallel;
    for (int a = 0; a < 3; ++a)
    {
      o.Eye[a] = in.Eye[a];
      o.ProjectionDirection[a] = in.ProjectionDirection[a];
    }
    std::string why;
    EXPECT_TRUE(plod::GeneratePatches(
      this->View, this->State.data(), this->Mask.data(), this->Patches, &why, nullptr, o))
      << why;
    return static_cast<int64_t>(this->Patches.Triangles.size() / 3);
  }
};

/// The gaze from the eye towards the origin (the models' centre).
void GazeAtTheOrigin(plod::SelectionInput& in)
{
  for (int a = 0; a < 3; ++a)
    in.GazeDirection[a] = -in.Eye[a];
  vtkMath::Normalize(in.GazeDirection);
}

/// The modes the budget is tested in: every error model, motion, foveation, velocity.
const std::vector<std::pair<const char*, std::function<void(plod::SelectionInput&)>>>& BudgetModes()
{
  static const std::vector<std::pair<const char*, std::function<void(plod::SelectionInput&)>>>
    modes = {
      { "SRCC", [](plod::SelectionInput&) {} },
      { "SRCC+TMM",
        [](plod::SelectionInput& in) {
          in.Motion = plod::MotionModel::MicroMotion;
          in.MotionA[0][1] = 0.01; // a slow turn about z and a shift
          in.MotionA[1][0] = -0.01;
          in.MotionB[0] = 0.004;
        } },
      { "SRCC+foveation",
        [](plod::SelectionInput& in) {
          in.Foveation = plod::FoveationMode::Screen;
          in.FoveationRate = 3;
          GazeAtTheOrigin(in);
        } },
      { "SCVC", [](plod::SelectionInput& in) { in.Error = plod::ErrorModel::SCVC; } },
      { "PSEC", [](plod::SelectionInput& in) { in.Error = plod::ErrorModel::PSEC; } },
      { "Distance",
        [](plod::SelectionInput& in) {
          in.Error = plod::ErrorModel::Distance;
          in.DistanceLevel = 4;
        } },
      { "Cheng",
        [](plod::SelectionInput& in) {
          in.Error = plod::ErrorModel::Cheng;
          in.Foveation = plod::FoveationMode::Screen;
          in.FoveationRate = 2;
          GazeAtTheOrigin(in);
        } },
      { "IPV",
        [](plod::SelectionInput& in) {
          in.Motion = plod::MotionModel::InverseVelocity;
          in.VelocityFactor = 2;
        } },
      { "SRCC x IPV",
        [](plod::SelectionInput& in) {
          in.Motion = plod::MotionModel::InverseVelocity;
          in.Velocity = plod::VelocityCriterion::ScalesErrorModel;
          in.VelocityFactor = 1.5;
        } },
    };
  return modes;
}

/// Generated models: a noisy closed blob, a thin ring (cells that are not topologically safe),
/// an open soup (rims, back faces drawn).
std::vector<std::pair<const char*, vtkSmartPointer<vtkPolyData>>> BudgetModels()
{
  return { { "blob", plodtest::MakeBlob(5, 60, 0.3) },
    { "ring", plodtest::MakeRing(1.0, 0.04, 90, 10) },
    { "soup", plodtest::MakeSoup(7, 500, 0.12) } };
}
/// Calls `visit(scene, model name, eye offset, eye, focus)` for each of BudgetModels (an octree
/// of level 7, the soup 6) and each eye offset from the model's centre, the focus.
template <class Visit>
void ForEachBudgetView(const std::vector<std::array<double, 3>>& eyes, Visit&& visit)
{
  for (auto& model : BudgetModels())
  {
    BudgetScene scene(model.second, model.first == std::string("soup") ? 6 : 7);
    const double* o = scene.View.Origin;
    const double focus[3] = { o[0] + 0.5 * scene.View.RootEdge, o[1] + 0.5 * scene.View.RootEdge,
      o[2] + 0.5 * scene.View.RootEdge };
    for (const auto& eyeArray : eyes)
    {
      double eye[3] = { focus[0] + eyeArray[0], focus[1] + eyeArray[1], focus[2] + eyeArray[2] };
      visit(scene, std::string(model.first), eyeArray, eye, focus);
    }
  }
}
} // namespace

TEST(PerceptualLODSelector, ScreenFoveationTableGivesTheExactCut)
{
  // The tolerance walk bounds screen foveation's factor from a table and computes it only where
  // a test falls within the bounds; the budget walk (a budget that does not bind) computes it at
  // every cell. Over models, views (perspective and parallel), rates (negative, 0, large, beyond
  // the table's 512), gazes (at the model, aside, away from it, none) and the modes that
  // multiply tolerances by it,
  // both give the same cut, node for node. The table spares most factors, yet the exact
  // fallback is reached (the bounds are tight, not vacuous, and the test exercises both paths).
  const std::vector<std::array<double, 3>> eyes = { { 0.4, 0.9, 3.2 }, { -1.2, 0.3, 1.9 } };
  const double rates[] = { -4, 0, 0.7, 3, 40, 512, 600 };
  int64_t tableVisited = 0, tableFactors = 0, cases = 0;
  ForEachBudgetView(eyes,
    [&](BudgetScene& scene, const std::string& modelName, const std::array<double, 3>& eyeArray,
      double eye[3], const double focus[3]) {
      for (int gaze = 0; gaze < 8; ++gaze) // 4 to 7: the same gazes, parallel projection
      {
        for (const double rate : rates)
        {
          for (const auto& mode : BudgetModes())
          {
            // the budget test's modes that multiply tolerances by the factor (Cheng compares
            // curvature with exp(-K D) at every cell; its foveation is set here)
            if (mode.first == std::string("Cheng") || mode.first == std::string("SRCC+foveation"))
              continue;
            const std::string what = modelName + " " + mode.first + " eye " +
              std::to_string(eyeArray[0]) + " gaze " + std::to_string(gaze) + " rate " +
              std::to_string(rate);
            plod::SelectionInput in = scene.Look(eye, focus);
            if (gaze >= 4)
            {
              // every view ray along the projection direction: one angle to the gaze
              in.Parallel = true;
              for (int a = 0; a < 3; ++a)
                in.ProjectionDirection[a] = focus[a] - eye[a];
              in.PixelScale = 400; // pixels per unit: the model about 800 pixels across
            }
            mode.second(in);
            in.Foveation = plod::FoveationMode::Screen;
            in.FoveationRate = rate;
            GazeAtTheOrigin(in);
            if (gaze % 4 == 1)
            {
              in.GazeDirection[0] += 0.3; // aside: the fovea on the model's edge
              vtkMath::Normalize(in.GazeDirection);
            }
            else if (gaze % 4 == 2)
            {
              for (int a = 0; a < 3; ++a) // away: D near 1 everywhere
                in.GazeDirection[a] = -in.GazeDirection[a];
            }
            else if (gaze % 4 == 3)
            {
              in.GazeDirection[0] = in.GazeDirection[1] = in.GazeDirection[2] = 0;
            }
            const plod::SelectionStats fast = scene.Select(in);
            const auto state = scene.State, reason = scene.Reason, mask = scene.Mask;
            in.TriangleBudget = std::numeric_limits<int64_t>::max();
            in.ToleranceCutFirst = false; // the queue walk, which computes every factor
            const plod::SelectionStats exact = scene.Select(in);
            ASSERT_FALSE(exact.BudgetBinding) << what;
            ASSERT_TRUE(scene.State == state && scene.Reason == reason && scene.Mask == mask)
              << what << ": the table's cut is not the exact one";
            EXPECT_EQ(fast.Visited, exact.Visited) << what;
            EXPECT_EQ(fast.CutTriangles, exact.CutTriangles) << what;
            if (std::abs(rate) <= 512 && gaze % 4 != 3)
            {
              tableVisited += fast.Visited;
              tableFactors += fast.FoveationFactors;
              ++cases;
            }
            else
            {
              // no table: every cell that reaches a tolerance computes its factor
              EXPECT_EQ(fast.FoveationFactors, exact.FoveationFactors) << what;
            }
          }
        }
      }
    });
  std::cout << cases << " cases with the table: " << tableFactors << " factors computed for "
            << tableVisited << " cells visited\n";
  EXPECT_GT(tableFactors, 0) << "the exact fallback was never reached";
  EXPECT_LT(tableFactors * 20, tableVisited) << "the table spared fewer than 95 % of the factors";
}

TEST(PerceptualLODSelector, BudgetIsNeverExceededAndNestsAndMeetsTheToleranceCut)
{
  // Over models, views and modes, budgets 1, 10, ..., 10^5, random ones below the tolerance
  // cut's count N and N - 1, N, N + 1 (the closed blob and ring count the triangles that face
  // the eye, the open soup every one):
  // - the count is exact (the triangles the refined nodes own, facing the eye on the closed
  //   models, recounted here triangle by triangle), at most the budget; GeneratePatches draws
  //   at most the cut's count (CutTriangles, every triangle the refined nodes own);
  // - a budget of at least N gives the tolerance cut node for node (states, reasons, cull
  //   masks), not binding; a smaller one is binding, refines only cells the tolerances refine,
  //   and stops at a refinement that would not have fitted (BudgetTriangles + its triangles >
  //   budget; with exactly that budget it is made and the count reaches it);
  // - with the stop rule StopAtFirstMisfit, a larger budget refines a superset of what a smaller
  //   one refines, and the refused priority (the largest left in the cut) never rises;
  // - the waiting triangles (the refinements left unrefined, one level each) are 0 without
  //   binding, else at least the refused refinement's and at most N minus the count, and they
  //   are what the BudgetLimited cells own (recounted), with either rule (counted in the cut's
  //   count: with what was refined, at most the tolerance cut's);
  // - with SkipMisfits, at the same budget: the count is exact and within the budget; it refines
  //   a superset of what the stop rule refines (so it fills at least as much), only cells the
  //   tolerances refine, and refuses first the same refinement (same priority and triangles: the
  //   pops before the first misfit are the stop rule's, and every key popped after it was
  //   reached from a smaller key), so its refused priority never rises with the budget either;
  //   and no cell it leaves unrefined (BudgetLimited) owns few enough triangles to fit in the
  //   room left.
  std::mt19937 rng(14);
  const std::vector<std::array<double, 3>> eyes = { { 0.4, 0.9, 3.2 }, { 4.5, -2, 1.5 },
    { -1.2, 0.3, 1.9 } };
  int binding = 0, checked = 0, filledMore = 0;
  ForEachBudgetView(eyes,
    [&](BudgetScene& scene, const std::string& modelName, const std::array<double, 3>& eyeArray,
      double eye[3], const double focus[3]) {
      for (const auto& mode : BudgetModes())
      {
        const std::string what =
          modelName + " " + mode.first + " eye " + std::to_string(eyeArray[0]);
        plod::SelectionInput in = scene.Look(eye, focus);
        mode.second(in);
        in.ToleranceCutFirst = false; // the queue walk at every budget (its shortcut: below)
        const plod::SelectionStats tolerance = scene.Select(in);
        const auto state0 = scene.State, reason0 = scene.Reason, mask0 = scene.Mask;
        const auto refined0 = scene.Refined();
        ASSERT_EQ(scene.Owned(refined0), tolerance.CutTriangles) << what;
        ASSERT_EQ(tolerance.BudgetTriangles, tolerance.CutTriangles) << what; // no budget
        ASSERT_FALSE(tolerance.BudgetBinding) << what;
        // what a budget counts of the tolerance cut
        const int64_t N = scene.Counted(refined0, in);
        ASSERT_LE(N, tolerance.CutTriangles) << what;
        std::vector<int64_t> budgets = { 1, 10, 100, 1000, 10000, 100000, N - 1, N, N + 1 };
        for (int i = 0; i < 4; ++i)
          budgets.push_back(
            std::uniform_int_distribution<int64_t>(1, std::max<int64_t>(1, N))(rng));
        std::sort(budgets.begin(), budgets.end());
        budgets.erase(
          std::remove_if(budgets.begin(), budgets.end(), [](int64_t b) { return b < 1; }),
          budgets.end());
        std::vector<uint8_t> previousRefined;
        double previousRefused = std::numeric_limits<double>::infinity();
        double previousSkipRefused = std::numeric_limits<double>::infinity();
        for (const int64_t budget : budgets)
        {
          in.TriangleBudget = budget;
          in.BudgetStop = plod::BudgetStopRule::StopAtFirstMisfit;
          const plod::SelectionStats stats = scene.Select(in);
          ASSERT_TRUE(plod::ValidateCut(scene.View, scene.State.data())) << what << " " << budget;
          const auto refined = scene.Refined();
          ++checked;
          EXPECT_EQ(scene.Counted(refined, in), stats.BudgetTriangles) << what << " " << budget;
          EXPECT_EQ(scene.Owned(refined), stats.CutTriangles) << what << " " << budget;
          EXPECT_LE(stats.BudgetTriangles, budget) << what;
          EXPECT_LE(scene.PatchTriangles(), stats.CutTriangles) << what;
          if (budget >= N)
          {
            EXPECT_FALSE(stats.BudgetBinding) << what << " " << budget;
            EXPECT_EQ(stats.BudgetTriangles, N) << what;
            EXPECT_TRUE(scene.State == state0 && scene.Reason == reason0 && scene.Mask == mask0)
              << what << ": budget " << budget << " >= " << N << " but not the tolerance cut";
            EXPECT_EQ(stats.Visited, tolerance.Visited) << what;
            EXPECT_EQ(stats.BudgetRefusedPriority, 0) << what;
            EXPECT_EQ(stats.BudgetWaitingTriangles, 0) << what;
          }
          else
          {
            ++binding;
            EXPECT_TRUE(stats.BudgetBinding) << what << " " << budget;
            EXPECT_GT(stats.BudgetTriangles + stats.BudgetRefusedTriangles, budget) << what;
            EXPECT_GT(stats.BudgetRefusedPriority, 0) << what;
            // the waiting refinements, one level each: at least the refused one, and a lower
            // bound of the tolerance cut with what was refined
            EXPECT_GE(stats.BudgetWaitingTriangles, stats.BudgetRefusedTriangles) << what;
            EXPECT_LE(stats.CutTriangles + stats.BudgetWaitingTriangles, tolerance.CutTriangles)
              << what;
            EXPECT_EQ(stats.BudgetWaitingTriangles, scene.Limited()) << what;
            for (int64_t n = 0; n < scene.View.NumberOfNodes; ++n)
            {
              ASSERT_FALSE(refined[n] && !refined0[n])
                << what << ": node " << n << " refined beyond the tolerances";
            }
          }
          if (!previousRefined.empty())
          {
            for (int64_t n = 0; n < scene.View.NumberOfNodes; ++n)
            {
              ASSERT_FALSE(previousRefined[n] && !refined[n])
                << what << ": budget " << budget << " does not refine node " << n
                << ", which a smaller budget refines";
            }
            EXPECT_LE(stats.BudgetRefusedPriority, previousRefused) << what << " " << budget;
          }
          previousRefined = refined;
          previousRefused = stats.BudgetRefusedPriority;
          if (stats.BudgetBinding)
          {
            // the refused refinement is the next one: with room for it exactly, it is made and
            // the count reaches the budget
            const int64_t next = stats.BudgetTriangles + stats.BudgetRefusedTriangles;
            in.TriangleBudget = next;
            const plod::SelectionStats more = scene.Select(in);
            EXPECT_EQ(more.BudgetTriangles, next) << what << " " << budget;
          }

          // the same budget with SkipMisfits
          in.TriangleBudget = budget;
          in.BudgetStop = plod::BudgetStopRule::SkipMisfits;
          const plod::SelectionStats skip = scene.Select(in);
          const std::string at = what + " skip " + std::to_string(budget);
          ASSERT_TRUE(plod::ValidateCut(scene.View, scene.State.data())) << at;
          const auto skipRefined = scene.Refined();
          EXPECT_EQ(scene.Counted(skipRefined, in), skip.BudgetTriangles) << at;
          EXPECT_EQ(scene.Owned(skipRefined), skip.CutTriangles) << at;
          EXPECT_LE(skip.BudgetTriangles, budget) << at;
          EXPECT_LE(scene.PatchTriangles(), skip.CutTriangles) << at;
          EXPECT_GE(skip.BudgetTriangles, stats.BudgetTriangles) << at;
          filledMore += skip.BudgetTriangles > stats.BudgetTriangles;
          EXPECT_EQ(skip.BudgetBinding, stats.BudgetBinding) << at;
          EXPECT_EQ(skip.BudgetRefusedPriority, stats.BudgetRefusedPriority) << at;
          EXPECT_EQ(skip.BudgetRefusedTriangles, stats.BudgetRefusedTriangles) << at;
          EXPECT_LE(skip.BudgetRefusedPriority, previousSkipRefused) << at;
          previousSkipRefused = skip.BudgetRefusedPriority;
          EXPECT_EQ(skip.BudgetWaitingTriangles, scene.Limited()) << at;
          EXPECT_LE(skip.CutTriangles + skip.BudgetWaitingTriangles, tolerance.CutTriangles) << at;
          EXPECT_GE(skip.BudgetWaitingTriangles, skip.BudgetRefusedTriangles) << at;
          if (budget >= N)
          {
            EXPECT_TRUE(scene.State == state0 && scene.Reason == reason0 && scene.Mask == mask0)
              << at << " >= " << N << " but not the tolerance cut";
          }
          const int64_t room = budget - skip.BudgetTriangles;
          for (int64_t n = 0; n < scene.View.NumberOfNodes; ++n)
          {
            ASSERT_FALSE(refined[n] && !skipRefined[n])
              << at << ": node " << n << " refined by the stop rule only";
            ASSERT_FALSE(skipRefined[n] && !refined0[n])
              << at << ": node " << n << " refined beyond the tolerances";
            if (scene.State[n] != plod::NotInCut && scene.Reason[n] == plod::BudgetLimited)
            {
              ASSERT_GT(scene.View.TriangleEnd(n) - scene.View.FirstTriangle[n], room)
                << at << ": node " << n << " left unrefined though it fits in the room left";
            }
          }
        }
      }
    });
  EXPECT_GT(binding, 100);
  EXPECT_GT(checked, 500);
  EXPECT_GT(filledMore, 20); // the rules differ on these models
}

TEST(PerceptualLODSelector, IncrementalSelectionKeepsEveryCellWithinItsTests)
{
  // Over models and modes, a camera path (an orbit step, a zoom in, a jump to the other side, a
  // zoom out, then the same view twice) selected incrementally, each frame from the last cut:
  // - the first frame is the full walk, node for node;
  // - every frame: a valid cut; the count is exact (the refined nodes' triangles, recounted);
  // - every frame after the first: every kept cell passes its tests at the current view
  //   (Refines false), every opened leaf fails them; every parent whose children are all kept
  //   would still be refined (else the coarsening pass has missed it);
  // - with a budget, the incremental flag changes nothing (the budget walk runs);
  // - at the end the cut has no more than 1.5 times the full walk's triangles at the same view
  //   (the front coarsens level by level; measured: within 4 % on the benchmark's paths).
  const std::vector<std::array<double, 3>> path = { { 0.4, 0.9, 3.2 }, { 0.5, 0.9, 3.15 },
    { 0.3, 0.6, 2.0 }, { 0.2, 0.4, 1.3 }, { -3.0, -0.5, -1.0 }, { -6.0, -1.0, -2.0 },
    { -6.0, -1.0, -2.0 }, { -6.0, -1.0, -2.0 } };
  int frames = 0, coarsened = 0;
  for (auto& model : BudgetModels())
  {
    // one octree per model; each mode starts from no previous cut (SetOctree forgets it)
    BudgetScene scene(model.second, model.first == std::string("soup") ? 6 : 7);
    BudgetScene full(model.second, model.first == std::string("soup") ? 6 : 7);
    for (const auto& mode : BudgetModes())
    {
      for (BudgetScene* s : { &scene, &full })
      {
        s->Kernel.SetOctree(s->View);
        std::fill(s->State.begin(), s->State.end(), 0);
        std::fill(s->Reason.begin(), s->Reason.end(), 0);
        std::fill(s->Mask.begin(), s->Mask.end(), 0);
      }
      const double* o = scene.View.Origin;
      const double focus[3] = { o[0] + 0.5 * scene.View.RootEdge, o[1] + 0.5 * scene.View.RootEdge,
        o[2] + 0.5 * scene.View.RootEdge };
      int64_t previousTriangles = -1;
      for (size_t f = 0; f < path.size(); ++f)
      {
        const std::string what =
          std::string(model.first) + " " + mode.first + " frame " + std::to_string(f);
        const double eye[3] = { focus[0] + path[f][0], focus[1] + path[f][1],
          focus[2] + path[f][2] };
        plod::SelectionInput in = scene.Look(eye, focus);
        mode.second(in);
        plod::SelectionInput fullInput = in;
        in.Incremental = true;
        const plod::SelectionStats stats = scene.Select(in);
        const plod::SelectionStats reference = full.Select(fullInput);
        ++frames;
        ASSERT_TRUE(plod::ValidateCut(scene.View, scene.State.data())) << what;
        EXPECT_EQ(scene.Owned(scene.Refined()), stats.BudgetTriangles) << what;
        EXPECT_EQ(stats.InCut,
          std::count_if(
            scene.State.begin(), scene.State.end(), [](uint8_t s) { return s != plod::NotInCut; }))
          << what;
        if (f == 0)
        {
          EXPECT_TRUE(
            scene.State == full.State && scene.Reason == full.Reason && scene.Mask == full.Mask)
            << what << ": the first incremental frame is not the full walk";
        }
        // (the full walk of the first frame judges a cell in its parent's context: a cell whose
        // parent passed the contour test is tested for brightness only)
        for (int64_t n = 0; f > 0 && n < scene.View.NumberOfNodes; ++n)
        {
          const uint8_t s = scene.State[n];
          if (s == plod::CutOpen)
          {
            ASSERT_TRUE(scene.Kernel.Refines(in, n)) << what << ": opened leaf " << n;
          }
          else if (s != plod::NotInCut)
          {
            ASSERT_FALSE(scene.Kernel.Refines(in, n)) << what << ": kept cell " << n;
          }
          else if (!scene.View.IsLeaf(n))
          {
            const int32_t first = scene.View.FirstChild[n];
            const int count = __builtin_popcount(scene.View.ChildMask[n]);
            bool allKept = true;
            for (int k = 0; k < count; ++k)
              allKept = allKept &&
                (scene.State[first + k] == plod::CutDrawn ||
                  scene.State[first + k] == plod::CutHidden);
            if (allKept)
            {
              ASSERT_TRUE(scene.Kernel.Refines(in, n)) << what << ": parent " << n;
            }
          }
        }
        if (previousTriangles >= 0 && stats.BudgetTriangles < previousTriangles)
          ++coarsened;
        previousTriangles = stats.BudgetTriangles;
        if (f + 1 == path.size())
        {
          EXPECT_LE(stats.BudgetTriangles, 1.5 * reference.BudgetTriangles + 10) << what;
        }
        // a budget runs the budget walk whatever the flag
        plod::SelectionInput budget = in;
        budget.TriangleBudget = std::max<int64_t>(1, reference.BudgetTriangles / 2);
        fullInput.TriangleBudget = budget.TriangleBudget;
        const plod::SelectionStats b1 = scene.Select(budget);
        const plod::SelectionStats b2 = full.Select(fullInput);
        EXPECT_TRUE(scene.State == full.State && b1.BudgetTriangles == b2.BudgetTriangles)
          << what << ": the incremental flag changed a budget cut";
        // the next frame starts again from a tolerance cut (the budget walk left no front)
        scene.Select(in);
      }
    }
  }
  EXPECT_EQ(frames, 3 * 9 * 8);
  EXPECT_GT(coarsened, 20); // the zoom out and the jump coarsen the front
}

TEST(PerceptualLODSelector, BudgetFloorsWithTheEyeInsideAndAMinimumLevel)
{
  // With a budget of 1, the cells holding the eye are still refined down to the leaves (or
  // culled), and no cell coarser than the minimum level is left in the cut unless culled; the
  // floors' triangles exceed the budget, reported as binding.
  BudgetScene scene(plodtest::MakeBlob(2, 60, 0.3), 6);
  const double* o = scene.View.Origin;
  const double h = scene.View.RootEdge;
  const double eye[3] = { o[0] + 0.5 * h, o[1] + 0.5 * h, o[2] + 0.5 * h }; // inside the blob
  const double focus[3] = { eye[0] + 1, eye[1], eye[2] };
  plod::SelectionInput in = scene.Look(eye, focus, 60);
  in.TriangleBudget = 1;
  // (from inside a closed surface every face turns away: with back faces hidden nothing is
  // drawn and nothing counts, so the floors bind only with back faces drawn)
  in.HideBackFaces = false;
  auto stats = scene.Select(in);
  EXPECT_TRUE(stats.BudgetBinding);
  int holding = 0;
  for (int64_t n = 0; n < scene.View.NumberOfNodes; ++n)
  {
    int c[3];
    scene.View.CellCoordinates(n, c);
    const double e = scene.View.CellEdge(scene.View.Level[n]);
    bool inside = true;
    for (int a = 0; a < 3; ++a)
      inside = inside && in.Eye[a] >= c[a] * e && in.Eye[a] <= (c[a] + 1) * e;
    if (inside && scene.State[n] != plod::NotInCut)
    {
      ++holding;
      EXPECT_TRUE(scene.State[n] == plod::CutOpen || scene.Reason[n] == plod::Culled)
        << "node " << n << " holds the eye, reason " << int(scene.Reason[n]);
    }
  }
  EXPECT_GT(holding, 0);
  // the minimum level
  const double far[3] = { eye[0], eye[1], eye[2] + 4 };
  in = scene.Look(far, eye);
  in.TriangleBudget = 1;
  in.MinimumLevel = 3;
  stats = scene.Select(in);
  EXPECT_TRUE(stats.BudgetBinding);
  EXPECT_GT(stats.BudgetTriangles, 1);
  int limited = 0;
  for (int64_t n = 0; n < scene.View.NumberOfNodes; ++n)
  {
    if (scene.State[n] == plod::NotInCut)
      continue;
    EXPECT_TRUE(scene.View.Level[n] >= 3 || scene.Reason[n] == plod::Culled) << n;
    limited += scene.Reason[n] == plod::BudgetLimited;
  }
  EXPECT_GT(limited, 0);
}

TEST(PerceptualLODSelector, TriangleBudgetThroughTheFilter)
{
  Pipeline p(plodtest::MakeBlob(6, 80, 0.3), 7);
  p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
  const double eye[3] = { 0.5, 0.8, 3.0 }, focus[3] = { 0, 0, 0 };
  p.Look(eye, focus);
  EXPECT_EQ(p.Selector->GetTriangleBudget(), 0);
  // the walk's own count (estimated), forwarded; the exact count, the default, is held to the
  // drawn triangles in BudgetOfDrawnTrianglesOnClosedModels
  EXPECT_TRUE(p.Selector->GetExactTriangleBudget());
  p.Selector->ExactTriangleBudgetOff();
  p.Selector->SetTriangleBudget(-7); // negative: off (clamped to 0)
  EXPECT_EQ(p.Selector->GetTriangleBudget(), 0);
  p.Patches->Update();
  // without a budget the count is the cut's; a budget that cannot bind counts what is drawn
  const vtkIdType cutTriangles = p.Selector->GetNumberOfCutTriangles();
  EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), cutTriangles);
  EXPECT_FALSE(p.Selector->GetBudgetWasBinding());
  EXPECT_LE(p.Patches->GetNumberOfTriangles(), cutTriangles);
  const auto state0 = p.Array(vtkMultiscaleOctree::CutStateArrayName());
  p.Selector->SetTriangleBudget(VTK_ID_MAX);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), state0);
  const vtkIdType N = p.Selector->GetNumberOfBudgetTriangles();
  EXPECT_EQ(p.Selector->GetNumberOfCutTriangles(), cutTriangles);
  EXPECT_GT(N, 1000);
  EXPECT_LT(N, cutTriangles); // the back faces of the closed blob do not count
  // the budget is forwarded: the filter re-executes, its figures follow
  const vtkMTimeType before = p.Selector->GetMTime();
  for (const vtkIdType budget : { N / 10, N / 3, N - 1 })
  {
    p.Selector->SetTriangleBudget(budget);
    p.Patches->Update();
    EXPECT_TRUE(p.Selector->GetBudgetWasBinding()) << budget;
    EXPECT_LE(p.Selector->GetNumberOfBudgetTriangles(), budget);
    EXPECT_GT(p.Selector->GetNumberOfBudgetTriangles(), budget / 2); // no small step ends it
    EXPECT_LE(p.Patches->GetNumberOfTriangles(), p.Selector->GetNumberOfCutTriangles());
    EXPECT_TRUE(p.Cut()->HasValidCut());
    const auto reason = p.Array(vtkPerceptualLODSelector::CutReasonArrayName());
    EXPECT_NE(std::count(reason.begin(), reason.end(), plod::BudgetLimited), 0);
  }
  EXPECT_GT(p.Selector->GetMTime(), before);
  // not binding: the tolerance cut
  p.Selector->SetTriangleBudget(N);
  EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), state0);
  EXPECT_FALSE(p.Selector->GetBudgetWasBinding());
  EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), N);
  // a budget smaller than the root's own triangles: the root alone, and the filter says why
  p.Selector->SetTriangleBudget(1);
  p.Patches->Update();
  EXPECT_EQ(p.Patches->GetNumberOfTriangles(), 0);
  EXPECT_NE(std::string(p.Selector->GetEmptyCutReason()).find("triangle budget"), std::string::npos)
    << p.Selector->GetEmptyCutReason();
  std::ostringstream text;
  p.Selector->PrintSelf(text, vtkIndent());
  EXPECT_NE(text.str().find("TriangleBudget: 1"), std::string::npos);
  EXPECT_NE(text.str().find("budget was binding"), std::string::npos);
}

TEST(PerceptualLODSelector, BudgetStopRuleThroughTheFilter)
{
  Pipeline p(plodtest::MakeBlob(6, 80, 0.3), 7);
  p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
  const double eye[3] = { 0.5, 0.8, 3.0 }, focus[3] = { 0, 0, 0 };
  p.Look(eye, focus);
  p.Selector->ExactTriangleBudgetOff(); // the walk's own count (the rule is the walk's)
  EXPECT_EQ(p.Selector->GetBudgetStopRule(), vtkPerceptualLODSelector::BUDGET_SKIP_MISFITS);
  p.Selector->SetBudgetStopRule(7); // clamped
  EXPECT_EQ(p.Selector->GetBudgetStopRule(), vtkPerceptualLODSelector::BUDGET_SKIP_MISFITS);
  p.Selector->SetBudgetStopRule(-1);
  EXPECT_EQ(p.Selector->GetBudgetStopRule(), vtkPerceptualLODSelector::BUDGET_STOP_AT_FIRST_MISFIT);
  p.Patches->Update();
  const vtkIdType N = p.Selector->GetNumberOfBudgetTriangles();
  // the rule is forwarded: at the same budget, skipping fills at least as much, within it, and
  // more at one budget at least
  int more = 0;
  for (const vtkIdType budget : { N / 10, N / 4, N / 3, N / 2 })
  {
    p.Selector->SetTriangleBudget(budget);
    p.Selector->SetBudgetStopRuleToStopAtFirstMisfit();
    p.Patches->Update();
    const vtkIdType stop = p.Selector->GetNumberOfBudgetTriangles();
    const vtkMTimeType before = p.Selector->GetMTime();
    p.Selector->SetBudgetStopRuleToSkipMisfits();
    EXPECT_GT(p.Selector->GetMTime(), before);
    p.Patches->Update();
    const vtkIdType skip = p.Selector->GetNumberOfBudgetTriangles();
    EXPECT_GE(skip, stop) << budget;
    EXPECT_LE(skip, budget);
    EXPECT_LE(p.Patches->GetNumberOfTriangles(), p.Selector->GetNumberOfCutTriangles());
    more += skip > stop;
  }
  EXPECT_GT(more, 0);
  std::ostringstream text;
  p.Selector->PrintSelf(text, vtkIndent());
  EXPECT_NE(text.str().find("stop rule SkipMisfits"), std::string::npos) << text.str();
}

namespace
{
/// A ParallelFor that runs the ranges one after the other, the last first.
void Backwards(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body)
{
  grain = std::max<int64_t>(1, grain);
  for (int64_t b = ((n - 1) / grain) * grain; b >= 0; b -= grain)
    body(b, std::min(n, b + grain));
}

/// A ParallelFor over vtkSMPTools (as the VTK filter's).
void SMPFor(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body)
{
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), static_cast<vtkIdType>(grain),
    [&body](vtkIdType b, vtkIdType e) { body(b, e); });
}
} // namespace

// The tolerance walk in parallel (Selector::SetParallelFor): over the models, views and every
// mode, the cut, reasons, cull masks and figures of the serial walk, node for node, whether the
// subtrees run in order, backwards, or on 1, 2 and 8 vtkSMPTools threads.
TEST(PerceptualLODSelector, ParallelWalkGivesTheSerialCut)
{
  const std::vector<std::array<double, 3>> eyes = { { 0.4, 0.9, 3.2 }, { -1.2, 0.3, 1.9 },
    { 0.05, 0.02, 0.3 } };
  int cases = 0;
  ForEachBudgetView(eyes,
    [&](BudgetScene& scene, const std::string& modelName, const std::array<double, 3>& eyeArray,
      double eye[3], const double focus[3]) {
      for (const auto& mode : BudgetModes())
      {
        plod::SelectionInput in = scene.Look(eye, focus);
        mode.second(in);
        const std::string what =
          modelName + " " + mode.first + " eye " + std::to_string(eyeArray[0]);
        plod::SelectionStats serialStats;
        scene.Kernel.SetParallelFor(nullptr);
        scene.Kernel.Select(
          in, scene.State.data(), scene.Reason.data(), scene.Mask.data(), serialStats);
        const std::vector<uint8_t> state = scene.State, reason = scene.Reason, mask = scene.Mask;
        for (int run = 0; run < 5; ++run)
        {
          plod::Selector parallel;
          parallel.SetOctree(scene.View);
          if (run == 0)
            parallel.SetParallelFor(plod::SerialFor);
          else if (run == 1)
            parallel.SetParallelFor(Backwards);
          else
          {
            vtkSMPTools::Initialize(run == 2 ? 1 : run == 3 ? 2 : 8);
            parallel.SetParallelFor(SMPFor);
          }
          std::vector<uint8_t> s(state.size(), 0), r(state.size(), 0), m(state.size(), 0);
          plod::SelectionStats stats;
          parallel.Select(in, s.data(), r.data(), m.data(), stats);
          ASSERT_EQ(s, state) << what << " run " << run;
          ASSERT_EQ(r, reason) << what << " run " << run;
          ASSERT_EQ(m, mask) << what << " run " << run;
          EXPECT_EQ(stats.Visited, serialStats.Visited) << what;
          EXPECT_EQ(stats.InCut, serialStats.InCut) << what;
          EXPECT_EQ(stats.Drawn, serialStats.Drawn) << what;
          EXPECT_EQ(stats.Opened, serialStats.Opened) << what;
          EXPECT_EQ(stats.TopologyRefined, serialStats.TopologyRefined) << what;
          EXPECT_EQ(stats.FoveationFactors, serialStats.FoveationFactors) << what;
          EXPECT_EQ(stats.BudgetTriangles, serialStats.BudgetTriangles) << what;
          // the next frame clears exactly this cut (its list of cut nodes is complete)
          in.Eye[0] += 0.01;
          plod::SelectionStats next;
          parallel.SetParallelFor(nullptr);
          parallel.Select(in, s.data(), r.data(), m.data(), next);
          std::string why;
          EXPECT_TRUE(plod::ValidateCut(scene.View, s.data(), &why)) << what << ": " << why;
          in.Eye[0] -= 0.01;
          ++cases;
        }
      }
    });
  vtkSMPTools::Initialize(0);
  EXPECT_GT(cases, 300);
}

// A budget's tolerance walk tried first (SelectionInput::ToleranceCutFirst): over the models,
// views and every mode, serial and on 2 and 8 vtkSMPTools threads, the cut, reasons, cull masks
// and figures (all but the visits) of the queue walk alone, node for node, at budgets the
// tolerance cut fits (its count N, and far more: kept) and does not fit (N - 1 and N / 3: given
// up, then the queue walk). After a binding budget the next frame goes to the queue walk first,
// and the one after tries the tolerance cut again.
TEST(PerceptualLODSelector, ToleranceCutFirstGivesTheQueueWalksCut)
{
  const std::vector<std::array<double, 3>> eyes = { { 0.4, 0.9, 3.2 }, { -1.2, 0.3, 1.9 },
    { 0.05, 0.02, 0.3 } };
  int kept = 0, givenUp = 0;
  ForEachBudgetView(eyes,
    [&](BudgetScene& scene, const std::string& modelName, const std::array<double, 3>& eyeArray,
      double eye[3], const double focus[3]) {
      for (const auto& mode : BudgetModes())
      {
        plod::SelectionInput in = scene.Look(eye, focus);
        mode.second(in);
        const std::string what =
          modelName + " " + mode.first + " eye " + std::to_string(eyeArray[0]);
        struct Run
        {
          std::vector<uint8_t> State, Reason, Mask;
          plod::SelectionStats Stats;
        };
        const auto select = [&](plod::Selector& kernel, int64_t budget, bool first) {
          Run r{ std::vector<uint8_t>(scene.State.size(), 0),
            std::vector<uint8_t>(scene.State.size(), 0),
            std::vector<uint8_t>(scene.State.size(), 0), {} };
          in.TriangleBudget = budget;
          in.ToleranceCutFirst = first;
          kernel.Select(in, r.State.data(), r.Reason.data(), r.Mask.data(), r.Stats);
          return r;
        };
        const auto expectSame = [&](const Run& a, const Run& b, const std::string& where) {
          ASSERT_EQ(a.State, b.State) << where;
          ASSERT_EQ(a.Reason, b.Reason) << where;
          ASSERT_EQ(a.Mask, b.Mask) << where;
          EXPECT_EQ(a.Stats.InCut, b.Stats.InCut) << where;
          EXPECT_EQ(a.Stats.Drawn, b.Stats.Drawn) << where;
          EXPECT_EQ(a.Stats.Opened, b.Stats.Opened) << where;
          EXPECT_EQ(a.Stats.TopologyRefined, b.Stats.TopologyRefined) << where;
          EXPECT_EQ(a.Stats.CutTriangles, b.Stats.CutTriangles) << where;
          EXPECT_EQ(a.Stats.BudgetTriangles, b.Stats.BudgetTriangles) << where;
          EXPECT_EQ(a.Stats.BudgetBinding, b.Stats.BudgetBinding) << where;
          EXPECT_EQ(a.Stats.BudgetRefusedPriority, b.Stats.BudgetRefusedPriority) << where;
          EXPECT_EQ(a.Stats.BudgetRefusedTriangles, b.Stats.BudgetRefusedTriangles) << where;
          EXPECT_EQ(a.Stats.BudgetWaitingTriangles, b.Stats.BudgetWaitingTriangles) << where;
        };
        plod::Selector queue;
        queue.SetOctree(scene.View);
        const int64_t N = select(queue, std::numeric_limits<int64_t>::max(), false)
                            .Stats.BudgetTriangles; // what the budget counts of the tolerance cut
        if (N < 3)
          continue;
        for (const int threads : { 0, 2, 8 })
        {
          const std::string where = what + " threads " + std::to_string(threads);
          plod::Selector first;
          first.SetOctree(scene.View);
          if (threads > 0)
          {
            vtkSMPTools::Initialize(threads);
            first.SetParallelFor(SMPFor);
          }
          for (const int64_t budget : { std::numeric_limits<int64_t>::max(), N, N - 1, N / 3 })
          {
            const Run a = select(queue, budget, false);
            EXPECT_FALSE(a.Stats.BudgetToleranceCut) << where;
            // a fresh selector for each budget: the tolerance cut is tried on the first frame
            plod::Selector fresh;
            fresh.SetOctree(scene.View);
            if (threads > 0)
              fresh.SetParallelFor(SMPFor);
            const Run b = select(fresh, budget, true);
            expectSame(a, b, where + " budget " + std::to_string(budget));
            EXPECT_EQ(b.Stats.BudgetToleranceCut, budget >= N) << where << " budget " << budget;
            (budget >= N ? kept : givenUp) += 1;
          }
          // a binding budget, then the tolerance cut's count twice: the queue walk, then kept
          const Run bound = select(first, N - 1, true);
          EXPECT_TRUE(bound.Stats.BudgetBinding) << where;
          const Run a = select(queue, N, false);
          const Run next = select(first, N, true);
          expectSame(a, next, where + " after a binding budget");
          EXPECT_FALSE(next.Stats.BudgetToleranceCut) << where;
          const Run after = select(first, N, true);
          expectSame(a, after, where + " two frames after");
          EXPECT_TRUE(after.Stats.BudgetToleranceCut) << where;
        }
      }
    });
  vtkSMPTools::Initialize(0);
  std::cout << kept << " cuts kept from the tolerance walk, " << givenUp << " given up\n";
  EXPECT_GT(kept, 200);
  EXPECT_GT(givenUp, 200);
}

// The budget walk with its parallel first pass (Selector::SetParallelFor): over the models,
// views and every mode, both stop rules and the exact count, on a sequence of frames whose
// budgets rise and fall and whose eye moves (so that the first pass goes below more cells than
// the walk refines, and fewer), run serially, backwards and on 2 and 8 vtkSMPTools threads:
// every frame's cut, reasons, cull masks and figures (all but the visits) are the serial walk's,
// and so is the tolerance walk's that follows (it shares the selector's task vectors).
TEST(PerceptualLODSelector, ParallelBudgetWalkGivesTheSerialCut)
{
  const std::vector<std::array<double, 3>> eyes = { { 0.4, 0.9, 3.2 }, { -1.2, 0.3, 1.9 },
    { 0.05, 0.02, 0.3 } };
  const double fractions[] = { 0.5, 0.3, 0.3, 0.1, 0.7, 0.45, 0 }; // 0: no budget, last
  int frames = 0, ahead = 0;
  ForEachBudgetView(eyes,
    [&](BudgetScene& scene, const std::string& modelName, const std::array<double, 3>& eyeArray,
      double eye[3], const double focus[3]) {
      for (const auto& mode : BudgetModes())
      {
        for (int variant = 0; variant < 3; ++variant) // skip misfits, stop at the first, exact
        {
          plod::SelectionInput in = scene.Look(eye, focus);
          mode.second(in);
          in.ToleranceCutFirst = false;
          in.BudgetStop = variant == 1 ? plod::BudgetStopRule::StopAtFirstMisfit
                                       : plod::BudgetStopRule::SkipMisfits;
          in.ExactBudget = variant == 2;
          in.TriangleBudget = std::numeric_limits<int64_t>::max();
          const int64_t N = scene.Select(in).BudgetTriangles;
          if (N < 20)
            continue;
          const std::string what = modelName + " " + mode.first + " eye " +
            std::to_string(eyeArray[0]) + " variant " + std::to_string(variant);
          for (int run = 0; run < 4; ++run)
          {
            plod::Selector parallel;
            parallel.SetOctree(scene.View);
            if (run == 0)
              parallel.SetParallelFor(plod::SerialFor);
            else if (run == 1)
              parallel.SetParallelFor(Backwards);
            else
            {
              vtkSMPTools::Initialize(run == 2 ? 2 : 8);
              parallel.SetParallelFor(SMPFor);
            }
            std::vector<uint8_t> s(scene.State.size(), 0), r(s.size(), 0), m(s.size(), 0);
            plod::SelectionInput moving = in;
            for (const double fraction : fractions)
            {
              moving.TriangleBudget =
                fraction > 0 ? std::max<int64_t>(1, int64_t(fraction * double(N))) : 0;
              moving.Eye[0] += 0.01;
              const std::string where = what + " run " + std::to_string(run) + " budget " +
                std::to_string(moving.TriangleBudget);
              plod::SelectionStats stats;
              parallel.Select(moving, s.data(), r.data(), m.data(), stats);
              // a fresh serial selector, into arrays of its own
              plod::Selector serial;
              serial.SetOctree(scene.View);
              std::vector<uint8_t> s1(s.size(), 0), r1(s.size(), 0), m1(s.size(), 0);
              plod::SelectionStats expected;
              serial.Select(moving, s1.data(), r1.data(), m1.data(), expected);
              ASSERT_EQ(s, s1) << where;
              ASSERT_EQ(r, r1) << where;
              ASSERT_EQ(m, m1) << where;
              EXPECT_EQ(stats.InCut, expected.InCut) << where;
              EXPECT_EQ(stats.Drawn, expected.Drawn) << where;
              EXPECT_EQ(stats.Opened, expected.Opened) << where;
              EXPECT_EQ(stats.TopologyRefined, expected.TopologyRefined) << where;
              EXPECT_EQ(stats.CutTriangles, expected.CutTriangles) << where;
              EXPECT_EQ(stats.BudgetTriangles, expected.BudgetTriangles) << where;
              EXPECT_EQ(stats.BudgetBinding, expected.BudgetBinding) << where;
              EXPECT_EQ(stats.BudgetRefusedPriority, expected.BudgetRefusedPriority) << where;
              EXPECT_EQ(stats.BudgetRefusedTriangles, expected.BudgetRefusedTriangles) << where;
              EXPECT_EQ(stats.BudgetWaitingTriangles, expected.BudgetWaitingTriangles) << where;
              EXPECT_EQ(expected.BudgetJudgedAhead, 0) << where; // serial: no first pass
              ahead += stats.BudgetJudgedAhead > 0 ? 1 : 0;
              ++frames;
            }
          }
        }
      }
    });
  vtkSMPTools::Initialize(0);
  std::cout << frames << " frames, " << ahead << " with a first pass\n";
  EXPECT_GT(frames, 1000);
  EXPECT_GT(ahead * 2, frames); // every frame after a binding one
}

// The exact count's search for a budget that draws at most B (Selector::FitDrawnTriangles):
// over the models, views from far to inside the model, every mode and budgets from 2 % to 95 %
// of the unbounded cut, whenever the plain walk with budget B draws at most B (so a fitting
// budget exists), the exact cut draws at most B, counted here by the patch generator, and its
// reported count is that drawn one. About half the searches walk again (counted by their
// visits), and some of those end on a walk that drew too many, which the search must not keep.
TEST(PerceptualLODSelector, ExactBudgetKeepsTheBestWalkThatFits)
{
  const std::vector<std::array<double, 3>> eyes = { { 0.4, 0.9, 3.2 }, { -1.2, 0.3, 1.9 },
    { 0.05, 0.02, 0.3 }, { 0.9, -0.6, 0.7 }, { 2.5, 1.5, -4.0 } };
  const double fractions[] = { 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.95 };
  int cases = 0, fitted = 0, searched = 0;
  ForEachBudgetView(eyes,
    [&](BudgetScene& scene, const std::string& modelName, const std::array<double, 3>& eyeArray,
      double eye[3], const double focus[3]) {
      for (const auto& mode : BudgetModes())
      {
        plod::SelectionInput in = scene.Look(eye, focus);
        mode.second(in);
        in.ToleranceCutFirst = false;
        in.TriangleBudget = std::numeric_limits<int64_t>::max();
        const int64_t N = scene.Select(in).BudgetTriangles;
        if (N < 50)
          continue;
        // the scene's selector remembers its cut in these arrays: given back after the budgets
        const std::vector<uint8_t> state = scene.State, reason = scene.Reason, mask = scene.Mask;
        for (const double fraction : fractions)
        {
          in.TriangleBudget = std::max<int64_t>(1, int64_t(fraction * double(N)));
          const std::string what = modelName + " " + mode.first + " eye " +
            std::to_string(eyeArray[0]) + " budget " + std::to_string(in.TriangleBudget);
          // fresh selectors, each from an empty cut
          const auto clear = [&scene]() {
            std::fill(scene.State.begin(), scene.State.end(), 0);
            std::fill(scene.Reason.begin(), scene.Reason.end(), 0);
            std::fill(scene.Mask.begin(), scene.Mask.end(), 0);
          };
          plod::Selector plain;
          plain.SetOctree(scene.View);
          in.ExactBudget = false;
          clear();
          plod::SelectionStats plainStats;
          plain.Select(in, scene.State.data(), scene.Reason.data(), scene.Mask.data(), plainStats);
          const int64_t plainDrawn = scene.DrawnTriangles(in);
          plod::Selector exact;
          exact.SetOctree(scene.View);
          in.ExactBudget = true;
          clear();
          plod::SelectionStats stats;
          exact.Select(in, scene.State.data(), scene.Reason.data(), scene.Mask.data(), stats);
          const int64_t drawn = scene.DrawnTriangles(in);
          ++cases;
          EXPECT_EQ(stats.BudgetTriangles, drawn) << what;
          if (plainDrawn > in.TriangleBudget)
            continue;
          ++fitted;
          EXPECT_LE(drawn, in.TriangleBudget) << what;
          searched += stats.Visited > 2 * plainStats.Visited ? 1 : 0;
        }
        scene.State = state;
        scene.Reason = reason;
        scene.Mask = mask;
      }
    });
  std::cout << cases << " budgets, " << fitted << " with a fitting plain walk, " << searched
            << " searched further\n";
  EXPECT_GT(fitted, 200);
  EXPECT_GT(searched, 100);
}

// One knob for SRCC's preset: the default tolerances, and T_b = 4 T_s scaled together.
TEST(PerceptualLODSelector, ScaleTolerancesKeepsBrightnessFourTimesContour)
{
  vtkNew<vtkPerceptualLODSelector> selector;
  EXPECT_EQ(selector->GetContourTolerance(), 1.0);
  EXPECT_EQ(selector->GetBrightnessTolerance(), 4.0);
  selector->SetTopologyTolerance(3);
  selector->ScaleTolerances(2.5);
  EXPECT_EQ(selector->GetContourTolerance(), 2.5);
  EXPECT_EQ(selector->GetBrightnessTolerance(), 10.0);
  EXPECT_EQ(selector->GetTopologyTolerance(), 3.0);
}

TEST(PerceptualLODSelector, ExactBudgetNeverExceededOnLucy)
{
  // Lucy from ../shared/data (closed: back faces hidden), SRCC with the tolerances 1/16 of the
  // papers' as the floor (the quality studies' FLOOR), a headlight, eyes on a circle and a
  // small translation as the TMM examination moves it, and its budgets (B = 3058 and B/2):
  // with the exact count, the default, no frame draws more than its budget, every binding one
  // at least 90 % of it, and the count reported is the drawn one (Rendering/Testing/Python/
  // TestExactBudgetInMotion.py holds the same through the render binding in motion, where the
  // exact count's steps down once ran out a few triangles over).
  const std::string dir = plodtest::DataDir();
  if (dir.empty())
    GTEST_SKIP() << "../shared/data (Stanford scans) not found: set PLOD_DATA_DIR";
  auto lucy = plodtest::ReadPLY(dir + "/lucy.ply");
  ASSERT_GT(lucy->GetNumberOfPolys(), 10000);
  Pipeline p(lucy, 8);
  p.Selector->SetContourTolerance(1.0 / 16);
  p.Selector->SetBrightnessTolerance(4.0 / 16);
  p.Selector->AddLight(true, 0, 0, 0, 1.0, 0.3);
  double b[6];
  lucy->GetBounds(b);
  const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  const double r =
    0.5 * std::sqrt(std::pow(b[1] - b[0], 2) + std::pow(b[3] - b[2], 2) + std::pow(b[5] - b[4], 2));
  const double d = 1.5 * r / std::sin(15.0 * Pi / 180);
  int frames = 0, binding = 0;
  for (int k = 0; k < 90; ++k)
  {
    const double a = 2 * Pi * k / 90, shift = 0.6 * r * std::sin(0.37 * k);
    const double eye[3] = { c[0] + d * std::sin(a) + shift, c[1], c[2] + d * std::cos(a) };
    const double focus[3] = { c[0] + shift, c[1], c[2] };
    p.Look(eye, focus);
    p.Selector->SetLight(0, true, eye[0], eye[1], eye[2], 1.0, 0.3);
    for (const vtkIdType B : { 1529, 3058 })
    {
      p.Selector->SetTriangleBudget(B);
      p.Patches->Update();
      const vtkIdType drawn = p.Patches->GetNumberOfTriangles();
      const std::string what = "view " + std::to_string(k) + " budget " + std::to_string(B);
      EXPECT_LE(drawn, B) << what;
      EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), drawn) << what;
      if (p.Selector->GetBudgetWasBinding())
      {
        EXPECT_GE(double(drawn), 0.9 * double(B)) << what;
        ++binding;
      }
      ++frames;
    }
  }
  EXPECT_GT(binding, frames / 2);
}

TEST(PerceptualLODSelector, ExactCountAndPatchesShareOneCornerMemo)
{
  // The selector's exact count and the patch generator remember corner walks in one memo per
  // octree (vtkMultiscaleOctree::GetCornerMemo, shared by the selector's output): over an orbit
  // whose budget binds, the memo is made once (both pass the same stamp: neither empties it for
  // the other), holds one entry per surface point, and every frame draws what a fresh pipeline
  // on a copy of the octree draws (its memo empty), point for point.
  auto blob = plodtest::MakeBlob(3, 120, 0.25);
  Pipeline p(blob, 7);
  p.Selector->SetTriangleBudget(800);
  p.Selector->ScaleTolerances(0.25);
  ASSERT_TRUE(p.Selector->GetExactTriangleBudget());
  const double focus[3] = { 0, 0, 0 };
  int binding = 0;
  for (int k = 0; k < 12; ++k)
  {
    const double a = 0.3 * k;
    const double eye[3] = { 2.6 * std::sin(a), 0.4, 2.6 * std::cos(a) };
    p.Look(eye, focus);
    p.Patches->Update();
    binding += p.Selector->GetBudgetWasBinding() ? 1 : 0;
    vtkPolyData* drawn = p.Patches->GetOutput();
    // a fresh pipeline on a deep copy (a memo of its own, empty)
    vtkNew<vtkMultiscaleOctree> copy;
    copy->DeepCopy(p.Builder->GetOutput());
    vtkNew<vtkPerceptualLODSelector> selector;
    vtkNew<vtkMultiscalePatchGenerator> patches;
    selector->SetInputData(copy);
    patches->SetInputConnection(selector->GetOutputPort());
    selector->SetTriangleBudget(800);
    selector->ScaleTolerances(0.25);
    selector->SetEyePosition(eye[0], eye[1], eye[2]);
    selector->SetViewAngle(30);
    double planes[24];
    p.Selector->GetFrustumPlanes(planes);
    selector->SetFrustumPlanes(planes);
    patches->Update();
    ASSERT_GT(drawn->GetNumberOfPolys(), 0) << "frame " << k;
    EXPECT_TRUE(plodtest::SameDrawing(drawn, patches->GetOutput())) << "frame " << k;
  }
  EXPECT_GT(binding, 6);
  const auto memo = p.Builder->GetOutput()->GetCornerMemo();
  EXPECT_EQ(p.Selector->GetOutput()->GetCornerMemo(), memo);
  EXPECT_EQ(memo->Resets, 1);
  EXPECT_EQ(static_cast<vtkIdType>(memo->CutCluster.size()),
    p.Builder->GetOutput()->GetNumberOfSurfacePoints());
  EXPECT_NE(memo->Stamp, 0u);
}

TEST(PerceptualLODSelector, ExactBudgetOnAnOpenModel)
{
  // An open soup (back faces drawn, no ghosts), seen close so that the frustum culls much of it:
  // the patch generator draws fewer triangles than the cut owns. The exact count (the default)
  // counts them only where the budget binds: there the count is the drawn one, at most the
  // budget and at least 90 % of it; a budget that does not bind keeps the cut's count, which
  // bounds the drawn one, uncounted.
  Pipeline p(plodtest::MakeSoup(7, 500, 0.12), 6);
  p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
  const double eye[3] = { 0.1, 0.2, 0.9 }, focus[3] = { 0, 0, 0 };
  p.Look(eye, focus);
  ASSERT_TRUE(p.Selector->GetExactTriangleBudget());
  p.Selector->SetTriangleBudget(VTK_ID_MAX);
  p.Patches->Update();
  ASSERT_FALSE(p.Selector->GetHidBackFaces());
  ASSERT_FALSE(p.Selector->GetBudgetWasBinding());
  const vtkIdType cut = p.Selector->GetNumberOfCutTriangles();
  const vtkIdType drawn = p.Patches->GetNumberOfTriangles();
  ASSERT_LT(drawn, cut * 9 / 10) << "the frustum must cull much of the soup";
  EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), cut); // not counted
  for (const double fraction : { 0.3, 0.6, 0.9 })
  {
    const vtkIdType B = vtkIdType(fraction * double(drawn));
    p.Selector->SetTriangleBudget(B);
    p.Patches->Update();
    EXPECT_TRUE(p.Selector->GetBudgetWasBinding()) << B;
    EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), p.Patches->GetNumberOfTriangles()) << B;
    EXPECT_LE(p.Patches->GetNumberOfTriangles(), B);
    EXPECT_GE(p.Patches->GetNumberOfTriangles(), 0.9 * double(B));
  }
}

TEST(PerceptualLODSelector, BudgetOfDrawnTrianglesOnClosedModels)
{
  // On closed models (a noisy blob and a generated scan), from far, mid and close views on two
  // sides, with budgets from 5 % to 90 % of what the tolerance cut draws: the budget counts
  // what vtkMultiscalePatchGenerator draws (back faces culled). Estimated (the default), the
  // triangles drawn stay within 15 % of the budget (measured: 0.86 to 1.13, the excess at
  // budgets of about a hundred triangles, where representative vertices turn many faces);
  // exact, at most the budget and at least 90 % of it, with GetNumberOfBudgetTriangles the
  // drawn count itself. A budget that the tolerance cut fits in gives the tolerance cut.
  std::vector<std::pair<std::string, vtkSmartPointer<vtkPolyData>>> models;
  models.emplace_back("blob", plodtest::MakeBlob(6, 80, 0.3));
  const std::string path = (std::filesystem::temp_directory_path() /
    ("plod_selector_" + std::to_string(::getpid()) + "_closed_scan.ply"))
                             .string();
  plodtest::ScanCounts counts;
  std::string why;
  ASSERT_TRUE(plodtest::GenerateScanPLY(plodtest::OctahedralSphere(3), 16, 3, path, &counts, &why))
    << why;
  models.emplace_back("scan", plodtest::ReadPLY(path));
  std::remove(path.c_str());
  double lowest = 2, highest = 0;
  int cases = 0;
  for (auto& model : models)
  {
    Pipeline p(model.second, 8);
    p.Selector->AddLight(false, 0.3, 0.6, 1.0, 0.8, 0.5);
    for (const double distance : { 2.0, 3.5, 8.0 })
    {
      for (const double side : { 1.0, -1.0 })
      {
        const double eye[3] = { 0.3 * distance * side, 0.4 * distance, distance * side };
        const double focus[3] = { 0, 0, 0 };
        p.Look(eye, focus);
        p.Selector->SetTriangleBudget(0);
        p.Selector->ExactTriangleBudgetOff();
        p.Patches->Update();
        ASSERT_TRUE(p.Selector->GetHidBackFaces());
        const auto tolerance = p.Array(vtkMultiscaleOctree::CutStateArrayName());
        const vtkIdType D = p.Patches->GetNumberOfTriangles();
        for (const bool exact : { false, true })
        {
          // a budget that the tolerance cut fits in gives it: its count estimated (the walk
          // aims with that count in both modes), and drawn too when exact
          p.Selector->SetExactTriangleBudget(false);
          p.Selector->SetTriangleBudget(VTK_ID_MAX);
          EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), tolerance);
          const vtkIdType N = p.Selector->GetNumberOfBudgetTriangles();
          p.Selector->SetExactTriangleBudget(exact);
          p.Selector->SetTriangleBudget(exact ? std::max(N, D) : N);
          p.Patches->Update();
          EXPECT_EQ(p.Array(vtkMultiscaleOctree::CutStateArrayName()), tolerance);
          EXPECT_FALSE(p.Selector->GetBudgetWasBinding());
          EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), exact ? D : N);
          for (const double fraction : { 0.05, 0.1, 0.25, 0.5, 0.9 })
          {
            const vtkIdType B = std::max<vtkIdType>(100, vtkIdType(fraction * D));
            p.Selector->SetTriangleBudget(B);
            p.Patches->Update();
            const std::string what = model.first + " distance " + std::to_string(distance) +
              " side " + std::to_string(side) + " budget " + std::to_string(B) +
              (exact ? " exact" : " estimated");
            const double fill = double(p.Patches->GetNumberOfTriangles()) / double(B);
            ++cases;
            if (exact)
            {
              EXPECT_LE(p.Patches->GetNumberOfTriangles(), B) << what;
              EXPECT_GE(fill, 0.9) << what;
              EXPECT_EQ(p.Selector->GetNumberOfBudgetTriangles(), p.Patches->GetNumberOfTriangles())
                << what;
            }
            else
            {
              lowest = std::min(lowest, fill);
              highest = std::max(highest, fill);
              EXPECT_LE(p.Selector->GetNumberOfBudgetTriangles(), B) << what;
              EXPECT_GE(fill, 0.85) << what;
              EXPECT_LE(fill, 1.15) << what;
            }
          }
        }
      }
    }
  }
  std::printf(
    "estimated budget: triangles drawn from %.3f to %.3f of the budget\n", lowest, highest);
  EXPECT_EQ(cases, 2 * 3 * 2 * 2 * 5);
}
