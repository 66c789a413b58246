// SPDX-License-Identifier: BSD-3-Clause
// The frame-time target's control law (plodBudgetController.h) against simulated renderers
// whose frame time grows with the triangles drawn: converges, holds, does not oscillate, does
// not run away while the tolerances keep the cut small, survives bad numbers.
#include "plodBudgetController.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{

/// A renderer: fixed cost plus a cost per triangle, with deterministic noise of +-`noise`.
struct Plant
{
  double Fixed = 0.004;
  double PerTriangle = 2e-7; // 5M triangles per second, as llvmpipe on a mid-size model
  double Noise = 0.0;
  uint32_t Seed = 12345;
  double Time(int64_t triangles)
  {
    this->Seed = this->Seed * 1664525u + 1013904223u;
    const double u = double(this->Seed >> 8) / double(1u << 24) * 2 - 1; // [-1, 1)
    return (this->Fixed + this->PerTriangle * double(triangles)) * (1 + this->Noise * u);
  }
};

struct Trace
{
  std::vector<int64_t> Budgets;
  std::vector<int64_t> Drawn;
  std::vector<double> Times;
};

/// Frames of a view whose tolerance cut has `wanted[f]` triangles at frame f.
Trace Simulate(
  const plod::FrameTimeTarget& settings, Plant plant, const std::vector<int64_t>& wanted)
{
  plod::BudgetController controller;
  Trace run;
  int64_t budget = 0;
  for (int64_t want : wanted)
  {
    const bool binding = budget > 0 && want > budget;
    const int64_t drawn = binding ? budget : want;
    const double t = plant.Time(drawn);
    budget = controller.Update(settings, t, drawn, binding);
    run.Budgets.push_back(budget);
    run.Drawn.push_back(drawn);
    run.Times.push_back(t);
  }
  return run;
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Frame-to-frame reversals of the budget's direction (up then down, or down then up).
int Reversals(const std::vector<int64_t>& b, size_t from)
{
  int reversals = 0, last = 0;
  for (size_t i = from + 1; i < b.size(); ++i)
  {
    const int dir = b[i] > b[i - 1] ? 1 : (b[i] < b[i - 1] ? -1 : 0);
    if (dir != 0)
    {
      reversals += last != 0 && dir != last;
      last = dir;
    }
  }
  return reversals;
}

plod::FrameTimeTarget Target(double seconds)
{
  plod::FrameTimeTarget t;
  t.Target = seconds;
  return t;
}

} // namespace

// A full cut of 2M triangles takes 0.404 s; the target is 50 ms (about 230k triangles).
TEST(BudgetController, ConvergesToTheTargetAndHoldsIt)
{
  const std::vector<int64_t> wanted(120, 2000000);
  const Trace run = Simulate(Target(0.05), Plant(), wanted);
  // from 2M down by at most 1.25 per frame: ln(2e6 / 2.3e5) / ln(1.25) ~ 10 frames, then the
  // damped approach
  for (size_t f = 30; f < run.Times.size(); ++f)
  {
    EXPECT_NEAR(run.Times[f], 0.05, 0.05 * 0.10) << "frame " << f;
  }
  // the median of three lags a frame behind the steps down: one small overshoot at most, then
  // rest (measured: 8 % under the target, back within 3 frames, then no change at all)
  EXPECT_LE(Reversals(run.Budgets, 0), 1);
  for (size_t f = 0; f < run.Times.size(); ++f)
  {
    EXPECT_GE(run.Times[f], 0.05 * 0.9) << "frame " << f;
  }
  for (size_t f = 30; f < run.Budgets.size(); ++f)
  {
    EXPECT_EQ(run.Budgets[f], run.Budgets[29]) << "at rest from frame 30";
  }
}

TEST(BudgetController, NoisyFramesHoldTheMedianWithoutOscillating)
{
  Plant noisy;
  noisy.Noise = 0.15; // +-15 % per frame
  const Trace run = Simulate(Target(0.05), noisy, std::vector<int64_t>(300, 2000000));
  const std::vector<double> settled(run.Times.begin() + 40, run.Times.end());
  EXPECT_NEAR(Median(settled), 0.05, 0.05 * 0.10);
  // no oscillation: the budget stays within 20 % of its settled median (frames +-15 % apart
  // make it wander: measured at most 15.6 %), and no frame changes
  // the triangles drawn by more than the largest step
  std::vector<double> budgets(run.Budgets.begin() + 40, run.Budgets.end());
  const double middle = Median(budgets);
  for (size_t f = 40; f < run.Budgets.size(); ++f)
  {
    EXPECT_NEAR(double(run.Budgets[f]), middle, 0.20 * middle) << "frame " << f;
    EXPECT_LE(double(run.Drawn[f]), 1.25 * double(run.Drawn[f - 1]) + 1);
    EXPECT_GE(double(run.Drawn[f]) * 1.25 + 1, double(run.Drawn[f - 1]));
  }
}

TEST(BudgetController, DoesNotRunAwayWhileTheTolerancesDrawLess)
{
  // 60 frames where the tolerances (motion, distance) want only 20k triangles, far under the
  // target's 230k, then the view comes to rest and wants 2M
  std::vector<int64_t> wanted(60, 20000);
  wanted.resize(140, 2000000);
  const Trace run = Simulate(Target(0.05), Plant(), wanted);
  for (size_t f = 1; f < 60; ++f)
  {
    EXPECT_LE(run.Budgets[f], int64_t(1.25 * 20000) + 1) << "frame " << f;
  }
  // back at rest: detail returns by at most the largest step per frame (no popping) and
  // reaches the target
  for (size_t f = 60; f < 140; ++f)
  {
    EXPECT_LE(double(run.Drawn[f]), 1.25 * double(run.Drawn[f - 1]) + 1) << "frame " << f;
  }
  EXPECT_NEAR(run.Times.back(), 0.05, 0.05 * 0.10);
}

TEST(BudgetController, TheStepFollowsTheLaw)
{
  plod::BudgetController c;
  const plod::FrameTimeTarget t = Target(0.1);
  // first frame: starts from what was drawn; 0.4 s is 4x the target: sqrt(1/4) = 0.5, limited
  // to 1 / 1.25
  EXPECT_EQ(c.Update(t, 0.4, 100000, true), 80000);
  // median of (0.4, 0.025) is 0.025... of two the lower: (n - 1) / 2 = 0 -> 0.025: ratio 4,
  // sqrt 2, limited to 1.25
  EXPECT_EQ(c.Update(t, 0.025, 80000, true), 100000);
  EXPECT_DOUBLE_EQ(c.GetMeasuredTime(), 0.025);
  // three frames: median 0.09 -> ratio 1.111, gain 0.5 -> 1.0541
  EXPECT_EQ(c.Update(t, 0.09, 100000, true),
    static_cast<int64_t>(std::round(100000 * std::sqrt(0.1 / 0.09))));
  // inside the dead band (median 0.098): unchanged
  plod::BudgetController d;
  d.Update(t, 0.098, 5000, true);
  EXPECT_EQ(d.Update(t, 0.098, 5000, true), 5000);
  // not binding: scaled from what was drawn, not from the budget
  plod::BudgetController e;
  EXPECT_EQ(e.Update(t, 0.1, 50000, true), 50000);
  EXPECT_EQ(e.Update(t, 0.01, 2000, false), 2500);
}

TEST(BudgetController, BadNumbersChangeNothingOrTurnItOff)
{
  plod::BudgetController c;
  plod::FrameTimeTarget t = Target(0.05);
  EXPECT_EQ(c.Update(t, 0.05, 10000, true), 10000);
  // zero, negative, NaN and infinite frame times: no change
  for (double bad : { 0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
         std::numeric_limits<double>::infinity() })
  {
    EXPECT_EQ(c.Update(t, bad, 10000, true), 10000);
  }
  // huge frame times (two of the last three): one limited step down, never below the minimum
  t.MinimumBudget = 9000;
  EXPECT_EQ(c.Update(t, 1e300, 10000, true), 10000); // median of (0.05, 1e300): 0.05
  EXPECT_EQ(c.Update(t, 1e300, 10000, true), 9000);
  // the maximum holds
  plod::BudgetController m;
  t.MinimumBudget = 1;
  t.MaximumBudget = 12000;
  m.Update(t, 0.05, 10000, true);
  EXPECT_EQ(m.Update(t, 1e-9, 10000, true), 12000);
  // off, or absurd settings: 0 (no budget)
  EXPECT_EQ(c.Update(Target(0), 0.05, 10000, true), 0);
  for (auto change :
    { +[](plod::FrameTimeTarget& s) { s.Gain = 0; }, +[](plod::FrameTimeTarget& s) { s.Gain = 2; },
      +[](plod::FrameTimeTarget& s) { s.MaxStep = 1; },
      +[](plod::FrameTimeTarget& s) { s.DeadBand = 0.5; },
      +[](plod::FrameTimeTarget& s) { s.MinimumBudget = 0; },
      +[](plod::FrameTimeTarget& s) {
        s.MaximumBudget = 5;
        s.MinimumBudget = 10;
      },
      +[](plod::FrameTimeTarget& s) { s.Target = std::numeric_limits<double>::infinity(); } })
  {
    plod::FrameTimeTarget s = Target(0.05);
    change(s);
    std::string why;
    EXPECT_FALSE(plod::ValidateFrameTimeTarget(s, &why));
    EXPECT_FALSE(why.empty());
    plod::BudgetController b;
    EXPECT_EQ(b.Update(s, 0.05, 10000, true), 0);
  }
}
