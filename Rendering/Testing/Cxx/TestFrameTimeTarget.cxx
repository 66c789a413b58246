// SPDX-License-Identifier: BSD-3-Clause
// The frame-time target (issue 14), rendered for real on a simulated clock: a generated model
// whose full-resolution frame costs several times the target, a scripted camera path (orbit and
// dolly), and vtkPerceptualLODActor::SetTargetFrameTime. The actor's clock (SetClock) advances,
// while each frame is made, by a cost that grows with the triangles drawn (as a renderer's
// does), so the verdict does not depend on this machine's speed or load. The median frame holds
// the target within 10 %, the budget does not oscillate and no frame pops (the triangles drawn
// change by at most the controller's step). The budget steered is a count of what is drawn: on
// the closed model, whose back faces the patch generator culls, the triangles drawn follow the
// budget (a count of the cut's triangles would draw about half of it).
#include "plodTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODActor.h"
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace
{
double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Frames
{
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkPerceptualLODActor> Actor;
  vtkNew<vtkCallbackCommand> Cost;
  double Clock = 1000.0; // simulated seconds
  /// The simulated cost of a frame that draws `triangles`: a fixed part and a part per triangle.
  static double FrameCost(double triangles) { return 2e-3 + 200e-9 * triangles; }
  Frames()
  {
    this->Window->SetOffScreenRendering(1);
    this->Window->SetSize(480, 480);
    this->Window->AddRenderer(this->Renderer);
    this->Renderer->AddActor(this->Actor);
    this->Actor->SetClock([this]() { return this->Clock; });
    // each frame costs what it draws: the clock advances once the patches are made
    this->Cost->SetClientData(this);
    this->Cost->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
      auto* self = static_cast<Frames*>(client);
      self->Clock += FrameCost(double(self->Actor->GetPatchGenerator()->GetNumberOfTriangles()));
    });
    this->Actor->GetPatchGenerator()->AddObserver(vtkCommand::EndEvent, this->Cost);
  }
  /// Simulated time of one frame (select, patches, render, swap).
  double Render()
  {
    const double t0 = this->Clock;
    this->Window->Render();
    return this->Clock - t0;
  }
  /// Median time of `n` frames of an unchanged view, each selected again (a toggled setting
  /// makes the selector re-execute, as a moving view would).
  double MedianFrame(int n)
  {
    std::vector<double> t;
    for (int i = 0; i < n; ++i)
    {
      this->Renderer->GetActiveCamera()->Azimuth(i % 2 ? 0.5 : -0.5);
      t.push_back(this->Render());
    }
    return Median(t);
  }
};
}

TEST(FrameTimeTarget, HeldWithinTenPercentOnAScriptedPath)
{
  Frames f;
  // about 320k triangles: the tolerance cut below is most of them
  f.Actor->SetInputData(plodtest::MakeBlob(7, 400, 0.2));
  vtkPerceptualLODSelector* selector = f.Actor->GetSelector();
  // tolerances a hundred times finer than the defaults (this smooth blob passes the default
  // ones with a few thousand triangles): the tolerance cut is heavy, so the budget decides every
  // frame, and the queue still orders cells by their errors (a zero tolerance would put every
  // cell first, in index order)
  selector->SetContourTolerance(0.01);
  selector->SetBrightnessTolerance(0.04);
  f.Renderer->ResetCamera();
  f.Render(); // the build
  const double full = f.MedianFrame(5);
  selector->SetTriangleBudget(2000);
  const double coarse = f.MedianFrame(5);
  selector->SetTriangleBudget(0);
  const double target = coarse + 0.1 * (full - coarse);
  std::printf("full frame %.1f ms, coarsest %.1f ms, target %.1f ms\n", 1e3 * full, 1e3 * coarse,
    1e3 * target);
  ASSERT_GT(full, 3 * target) << "the model must be far above the target";

  f.Actor->SetTargetFrameTime(target);
  std::vector<double> times, triangles, budgets, drawn;
  vtkCamera* camera = f.Renderer->GetActiveCamera();
  const int frames = 90;
  for (int i = 0; i < frames; ++i)
  {
    camera->Azimuth(2.0);
    camera->Dolly(i < frames / 2 ? 1.004 : 1 / 1.004); // in, then out
    f.Renderer->ResetCameraClippingRange(f.Actor->GetBounds());
    times.push_back(f.Render());
    triangles.push_back(double(selector->GetNumberOfBudgetTriangles()));
    budgets.push_back(double(f.Actor->GetBinding(f.Renderer)->GetTargetBudget()));
    drawn.push_back(double(f.Actor->GetPatchGenerator()->GetNumberOfTriangles()));
  }
  // settled after 30 frames (from the full model, 1.25x per frame)
  const std::vector<double> settled(times.begin() + 30, times.end());
  const double median = Median(settled);
  std::printf("median frame over frames 30-%d: %.1f ms (target %.1f ms)\n", frames, 1e3 * median,
    1e3 * target);
  EXPECT_NEAR(median, target, 0.10 * target);
  // the budget is what is drawn: every settled frame binds, and draws its budget within a few
  // percent (the walk estimates the back faces from the input triangles)
  std::vector<double> fill;
  for (int i = 30; i < frames; ++i)
  {
    EXPECT_LE(triangles[i], budgets[i]) << "frame " << i;
    EXPECT_GT(triangles[i], 0.9 * budgets[i]) << "frame " << i << ": the budget is not binding";
    fill.push_back(drawn[i] / budgets[i]);
  }
  std::printf("triangles drawn / budget over frames 30-%d: median %.3f, %.3f to %.3f\n", frames,
    Median(fill), *std::min_element(fill.begin(), fill.end()),
    *std::max_element(fill.begin(), fill.end()));
  EXPECT_NEAR(Median(fill), 1.0, 0.05);
  EXPECT_GT(*std::min_element(fill.begin(), fill.end()), 0.85);
  EXPECT_LT(*std::max_element(fill.begin(), fill.end()), 1.05);
  // no popping: the budget never changes by more than the controller's step (1.25) and the
  // triangles drawn by no more than that step and the fill slack of the budget's stop rule
  // (with BUDGET_STOP_AT_FIRST_MISFIT the walk stops a little under the budget: measured, one
  // frame in a clean-clone run dropped by 1.2507; the default, BUDGET_SKIP_MISFITS, fills it)
  int reversals = 0, last = 0;
  for (int i = 31; i < frames; ++i)
  {
    EXPECT_LE(budgets[i], 1.25 * budgets[i - 1] + 1) << "frame " << i;
    EXPECT_GE(1.25 * budgets[i] + 1, budgets[i - 1]) << "frame " << i;
    EXPECT_LE(triangles[i], 1.35 * triangles[i - 1] + 1) << "frame " << i;
    EXPECT_GE(1.35 * triangles[i] + 1, triangles[i - 1]) << "frame " << i;
    const int dir = budgets[i] > budgets[i - 1] ? 1 : (budgets[i] < budgets[i - 1] ? -1 : 0);
    if (dir)
    {
      reversals += last && dir != last;
      last = dir;
    }
  }
  // no oscillation: the budget does not swing up and down frame after frame
  std::printf("budget direction reversals over frames 31-%d: %d\n", frames, reversals);
  EXPECT_LE(reversals, 20);

  // off again: the budget is released
  f.Actor->SetTargetFrameTime(0);
  f.Render();
  EXPECT_EQ(selector->GetTriangleBudget(), 0);
}

TEST(FrameTimeTarget, AbsurdTargetsAreErrors)
{
  vtkNew<vtkPerceptualLODRenderBinding> binding;
  binding->SetTargetFrameTime(0.05);
  for (double bad : { -1.0, std::nan(""), HUGE_VAL })
  {
    binding->SetTargetFrameTime(bad);
    EXPECT_EQ(binding->GetTargetFrameTime(), 0.05) << bad;
  }
  vtkNew<vtkPerceptualLODActor> actor;
  actor->SetTargetFrameTime(-3);
  EXPECT_EQ(actor->GetTargetFrameTime(), 0);
}

TEST(FrameTimeTarget, SteeredByTheOwner)
{
  // ExternalSteering, the hook of vtkPerceptualLODRepresentation under MPI: the push measures
  // but does not steer; the owner takes the cost, steers with its own figures and sets the
  // selector's budget
  Frames f;
  f.Actor->SetInputData(plodtest::MakeBlob(3, 120, 0.2));
  f.Renderer->ResetCamera();
  EXPECT_EQ(f.Actor->GetBinding(f.Renderer), nullptr);
  vtkPerceptualLODRenderBinding* binding = f.Actor->MakeBinding(f.Renderer);
  ASSERT_NE(binding, nullptr);
  binding->ExternalSteeringOn();
  f.Actor->SetTargetFrameTime(0.05);
  vtkPerceptualLODSelector* selector = f.Actor->GetSelector();
  f.Render();
  EXPECT_EQ(f.Actor->GetBinding(f.Renderer), binding) << "the first render uses the binding made";
  EXPECT_EQ(selector->GetTriangleBudget(), 0) << "the push did not steer";
  EXPECT_EQ(binding->GetTargetBudget(), 0);
  // the measured cost, once
  const double cost = binding->TakeFrameCost();
  EXPECT_GT(cost, 0);
  EXPECT_EQ(cost, binding->GetLastFrameCost());
  EXPECT_EQ(binding->TakeFrameCost(), 0) << "a cost is taken once";
  // the controller's steps with the owner's figures: the first starts from what was drawn, a
  // frame four times the target steps down by the largest step (1.25)
  const vtkIdType start = binding->StepBudget(0, 40000, false);
  EXPECT_EQ(start, 40000);
  EXPECT_EQ(binding->StepBudget(0.2, 40000, true), 32000);
  EXPECT_EQ(binding->StepBudget(0, 40000, true), 32000) << "nothing measured: the budget stays";
  EXPECT_EQ(binding->GetTargetBudget(), 32000);
  EXPECT_EQ(selector->GetTriangleBudget(), 0) << "StepBudget leaves the selector to the owner";
  // the owner's budget is left alone by the pushes
  selector->SetTriangleBudget(1234);
  f.Render();
  f.Render();
  EXPECT_EQ(selector->GetTriangleBudget(), 1234);
  // steering by the push again: the next push sets the binding's budget
  binding->ExternalSteeringOff();
  f.Render();
  EXPECT_EQ(selector->GetTriangleBudget(), binding->GetTargetBudget());
  // the target off: no budget
  f.Actor->SetTargetFrameTime(0);
  f.Render();
  EXPECT_EQ(selector->GetTriangleBudget(), 0);
  EXPECT_EQ(binding->StepBudget(0.2, 100, true), 0);
}
