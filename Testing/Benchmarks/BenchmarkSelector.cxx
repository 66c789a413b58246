// SPDX-License-Identifier: BSD-3-Clause
// Visited nodes per second and milliseconds per frame of vtkPerceptualLODSelector (the walk is
// single-threaded) for each mode, on the generated 1,005,360-triangle model (octree level 9)
// filling a 1920 x 1080 viewport, one directional light. Each iteration moves the eye a little
// (a slow orbit), so every frame really selects. BM_SelectBudget: the triangle budget's
// priority-queue walk; BM_SelectBisection: the alternative it was chosen against (tolerances
// scaled by a factor found by bisection, several walks a frame).
//
//   build/bin/BenchmarkSelector --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "plodTestUtilities.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkPerceptualLODSelector.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <string>

namespace
{
vtkMultiscaleOctree* GetOctree()
{
  static vtkSmartPointer<vtkMultiscaleOctree> octree;
  if (!octree)
  {
    auto model = plodtest::MakeBlob(11, 710, 0.2);
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(model);
    builder->SetFinestLevel(9);
    builder->Update();
    octree = builder->GetOutput();
  }
  return octree;
}

enum Mode
{
  SRCC,
  SRCC_TMM,
  SCVC,
  PSEC,
  DISTANCE,
  IPV,
  DPV,
  FOVEATED
};
const char* Names[] = { "SRCC", "SRCC+TMM", "SCVC", "PSEC", "Distance", "SRCC+IPV", "SRCC+DPV",
  "SRCC+foveation" };

/// A selector on the benchmark's octree in one of the modes, tolerances T_s and 4 T_s.
vtkSmartPointer<vtkPerceptualLODSelector> MakeSelector(int mode, double tolerance)
{
  auto selector = vtkSmartPointer<vtkPerceptualLODSelector>::New();
  selector->ScaleTolerances(tolerance);
  selector->SetInputData(GetOctree());
  selector->SetViewportSize(1920, 1080);
  selector->SetViewAngle(30);
  selector->AddLight(false, 0.3, 0.5, 1.0, 0.8, 0.5);
  switch (mode)
  {
    case SCVC:
      selector->SetErrorModelToSCVC();
      break;
    case PSEC:
      selector->SetErrorModelToPSEC();
      break;
    case DISTANCE:
      selector->SetErrorModelToDistance();
      break;
    case SRCC_TMM:
      selector->SetMotionModelToMicroMotion();
      break;
    case IPV:
      selector->SetMotionModelToInverseVelocity();
      break;
    case DPV:
      selector->SetMotionModelToDirectVelocity();
      break;
    case FOVEATED:
      selector->SetFoveationModeToScreen();
      break;
    default:
      break;
  }
  return selector;
}

/// The slow orbit: sets frame `frame`'s view (and the previous frame's matrix for motion).
class Orbit
{
public:
  /// zoom: the eye moves in and out along the view axis instead (distance 4.5 to 2.25 and back,
  /// at most 0.5 % a frame), the model growing past the viewport
  explicit Orbit(bool zoom = false)
    : Zoom(zoom)
  {
  }

  void Next(vtkPerceptualLODSelector* selector)
  {
    // the model (radius about 1.2) fills the 1080-pixel height at distance 4.5
    const double distance = this->Zoom ? 4.5 * (0.75 + 0.25 * std::cos(0.02 * this->Frame)) : 4.5;
    const double a = this->Zoom ? 0.3 : 0.002 * this->Frame;
    ++this->Frame;
    vtkNew<vtkCamera> camera;
    camera->SetPosition(distance * std::sin(a), 0.0, distance * std::cos(a));
    camera->SetFocalPoint(0, 0, 0);
    camera->SetViewAngle(30);
    double planes[24];
    camera->GetFrustumPlanes(1920.0 / 1080.0, planes);
    selector->SetEyePosition(camera->GetPosition());
    selector->SetFrustumPlanes(planes);
    double now[16];
    vtkMatrix4x4::DeepCopy(now, camera->GetViewTransformMatrix());
    selector->SetObjectToViewMatrix(now);
    if (!this->First)
    {
      selector->SetPreviousObjectToViewMatrix(this->Previous);
      selector->HasPreviousFrameOn();
      selector->SetPreviousFrameTime(1.0 / 60.0);
      camera->SetPosition(0, 0, 0); // (keeps the compiler from caching the camera)
    }
    std::copy(now, now + 16, this->Previous);
    this->First = false;
  }

private:
  bool Zoom;
  double Previous[16];
  bool First = true;
  int Frame = 0;
};

/// The calling thread's CPU time in seconds: unlike the wall clock, it does not count the time
/// the thread waits for a core (this machine has 2, often shared), so the per-core rate it gives
/// varies less from run to run.
double ThreadSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// The visited nodes and the wall and CPU seconds of the timed selections of one benchmark.
struct SelectTimes
{
  double Visited = 0, Seconds = 0, Cpu = 0;

  /// One frame: the next view of `path`, the selection, its time as the iteration's.
  void Frame(benchmark::State& state, vtkPerceptualLODSelector* selector, Orbit& path)
  {
    path.Next(selector);
    const double start = ThreadSeconds();
    selector->Update();
    this->Cpu += ThreadSeconds() - start;
    state.SetIterationTime(selector->GetSelectTime());
    this->Visited += static_cast<double>(selector->GetNumberOfVisitedNodes());
    this->Seconds += selector->GetSelectTime();
  }
  void Report(benchmark::State& state) const
  {
    state.counters["Mvisited/s"] = this->Visited / this->Seconds * 1e-6;
    // per second of the thread's CPU time (the whole Update: the pipeline's own cost included)
    state.counters["Mvisited/cpu-s"] = this->Visited / this->Cpu * 1e-6;
  }
};

void BM_Select(benchmark::State& state)
{
  const int mode = static_cast<int>(state.range(0));
  const double tolerance = state.range(1) / 100.0; // contour tolerance in pixels
  auto selector = MakeSelector(mode, tolerance);
  Orbit orbit;
  SelectTimes times;
  for (auto _ : state)
  {
    times.Frame(state, selector, orbit);
  }
  times.Report(state);
  state.counters["visited"] = static_cast<double>(selector->GetNumberOfVisitedNodes());
  state.counters["drawn"] = static_cast<double>(selector->GetNumberOfDrawnNodes());
  state.counters["triangles"] = static_cast<double>(selector->GetNumberOfBudgetTriangles());
  if (mode == FOVEATED) // of the last frame: cells whose foveation factor was computed
    state.counters["factors"] = static_cast<double>(selector->GetNumberOfFoveationFactors());
  state.SetLabel(std::string(Names[mode]) + " T_s=" + std::to_string(tolerance).substr(0, 4));
}

/**
 * Incremental selection (each frame starts from the previous cut) against the full walk from
 * the root, over the orbit (range(2) 0) or the zoom (1): range(3) 1 incremental, 0 full. Both
 * report their cells judged a frame (visited), the triangles of the cut and, for the
 * incremental walk, how many more triangles than the full walk's cut of the same view it counts
 * (the full walk is run beside it, outside the timing).
 */
void BM_SelectIncremental(benchmark::State& state)
{
  const int mode = static_cast<int>(state.range(0));
  const double tolerance = state.range(1) / 100.0;
  const bool zoom = state.range(2) != 0;
  const bool incremental = state.range(3) != 0;
  auto selector = MakeSelector(mode, tolerance);
  auto full = MakeSelector(mode, tolerance);
  selector->SetIncrementalSelection(incremental);
  Orbit orbit(zoom), fullOrbit(zoom);
  SelectTimes times;
  double extra = 0, frames = 0;
  for (auto _ : state)
  {
    times.Frame(state, selector, orbit);
    state.PauseTiming();
    fullOrbit.Next(full);
    full->Update();
    extra += double(selector->GetNumberOfBudgetTriangles()) /
        std::max<double>(1.0, double(full->GetNumberOfBudgetTriangles())) -
      1.0;
    ++frames;
    state.ResumeTiming();
  }
  times.Report(state);
  state.counters["visited/frame"] = times.Visited / frames;
  state.counters["triangles"] = static_cast<double>(selector->GetNumberOfBudgetTriangles());
  state.counters["extra triangles"] = extra / frames; // over the full walk's, same view
  state.SetLabel(std::string(Names[mode]) + " T_s=" + std::to_string(tolerance).substr(0, 4) +
    (zoom ? " zoom " : " orbit ") + (incremental ? "incremental" : "full"));
}

/// The triangles of the tolerance cut at the orbit's first view (the budgets are fractions of
/// it).
vtkIdType ToleranceTriangles(int mode, double tolerance)
{
  auto selector = MakeSelector(mode, tolerance);
  Orbit orbit;
  orbit.Next(selector);
  selector->Update();
  return selector->GetNumberOfBudgetTriangles();
}

/// The budget walk (priority-queue refinement from the root) with a budget of range(2) percent
/// of the tolerance cut's triangles (all it owns: the budget counts the drawn ones, about half
/// on this closed model, so 25 % binds and 200 % does not). range(3): the stop rule (0
/// StopAtFirstMisfit, 1 SkipMisfits). `exact`: ExactTriangleBudget.
void SelectBudget(benchmark::State& state, bool exact)
{
  const int mode = static_cast<int>(state.range(0));
  const double tolerance = state.range(1) / 100.0;
  const vtkIdType budget = ToleranceTriangles(mode, tolerance) * state.range(2) / 100;
  const int rule = static_cast<int>(state.range(3));
  auto selector = MakeSelector(mode, tolerance);
  selector->SetTriangleBudget(budget);
  selector->SetBudgetStopRule(rule);
  selector->SetExactTriangleBudget(exact);
  Orbit orbit;
  SelectTimes times;
  double binding = 0, frames = 0, fill = 0;
  for (auto _ : state)
  {
    times.Frame(state, selector, orbit);
    binding += selector->GetBudgetWasBinding() ? 1 : 0;
    fill += double(selector->GetNumberOfBudgetTriangles()) / double(budget);
    ++frames;
  }
  times.Report(state);
  state.counters["visited"] = static_cast<double>(selector->GetNumberOfVisitedNodes());
  state.counters["drawn"] = static_cast<double>(selector->GetNumberOfDrawnNodes());
  state.counters["triangles"] = static_cast<double>(selector->GetNumberOfBudgetTriangles());
  state.counters["cut"] = static_cast<double>(selector->GetNumberOfCutTriangles());
  state.counters["budget"] = static_cast<double>(budget);
  state.counters["binding"] = binding / frames;
  state.counters["fill"] = fill / frames; // the counted triangles over the budget
  state.SetLabel(std::string(Names[mode]) + " T_s=" + std::to_string(tolerance).substr(0, 4) +
    " budget " + std::to_string(state.range(2)) + "%" + (rule ? " skip" : " stop") +
    (exact ? " exact" : ""));
}

void BM_SelectBudget(benchmark::State& state)
{
  SelectBudget(state, false);
}

void BM_SelectBudgetExact(benchmark::State& state)
{
  SelectBudget(state, true);
}

/**
 * The alternative the budget walk was chosen against: scale both tolerances by a factor s and
 * search s by bisection so that the tolerance walk's cut fits the budget, starting from the
 * previous frame's factor. Each frame: one walk at the previous s, then walks bisecting log s
 * in [s / 2, s] or [s, 2 s] (widened while nothing fits) until range(3) walks are done; the
 * finest fitting s is kept. Reported: the select time of all the frame's
 * walks and how close the kept cut comes to the budget.
 */
void BM_SelectBisection(benchmark::State& state)
{
  const int mode = static_cast<int>(state.range(0));
  const double tolerance = state.range(1) / 100.0;
  const vtkIdType budget = ToleranceTriangles(mode, tolerance) * state.range(2) / 100;
  const int walks = static_cast<int>(state.range(3));
  auto selector = MakeSelector(mode, tolerance);
  Orbit orbit;
  double scale = 1, visited = 0, seconds = 0, fill = 0, frames = 0;
  for (auto _ : state)
  {
    orbit.Next(selector);
    double frameSeconds = 0;
    auto walk = [&](double s) {
      selector->ScaleTolerances(tolerance * s);
      selector->Update();
      frameSeconds += selector->GetSelectTime();
      visited += static_cast<double>(selector->GetNumberOfVisitedNodes());
      return selector->GetNumberOfBudgetTriangles();
    };
    // log-scale bisection of the bracket [fine, coarse] (coarse: larger tolerances, fewer
    // triangles); until a factor fits, the coarse end is tried and the bracket widened
    double best = -1, fine = scale / 2, coarse = scale * 2;
    vtkIdType bestCount = 0;
    auto fits = [&](double s) {
      const vtkIdType count = walk(s);
      if (count > budget)
        return false;
      if (best < 0 || s < best)
      {
        best = s;
        bestCount = count;
      }
      return true;
    };
    if (fits(scale))
      coarse = scale;
    else
      fine = scale;
    for (int w = 1; w < walks; ++w)
    {
      const double s = best < 0 ? coarse : std::sqrt(fine * coarse);
      if (fits(s))
        coarse = s;
      else
      {
        fine = s;
        if (best < 0)
          coarse = 2 * s;
      }
    }
    scale = best > 0 ? best : coarse; // the next frame starts here
    state.SetIterationTime(frameSeconds);
    seconds += frameSeconds;
    fill += budget > 0 ? double(bestCount) / double(budget) : 0;
    ++frames;
  }
  state.counters["Mvisited/s"] = visited / seconds * 1e-6;
  state.counters["visited/frame"] = visited / frames;
  state.counters["budget"] = static_cast<double>(budget);
  state.counters["fill"] = fill / frames; // kept cut's triangles over the budget
  state.counters["scale"] = scale;
  state.SetLabel(std::string(Names[mode]) + " T_s=" + std::to_string(tolerance).substr(0, 4) +
    " budget " + std::to_string(state.range(2)) + "%, " + std::to_string(walks) + " walks");
}
}

// default tolerances (T_s = 1 px, T_b = 4) for every mode; and SRCC and SRCC+TMM with
// tolerances 4x smaller, which visit many more nodes (the per-node rate without the
// per-frame fixed costs)
BENCHMARK(BM_Select)
  ->ArgsProduct({ benchmark::CreateDenseRange(SRCC, FOVEATED, 1), { 100 } })
  ->Args({ SRCC, 25 })
  ->Args({ SRCC_TMM, 25 })
  ->Args({ FOVEATED, 25 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);

// incremental against full selection over the orbit and the zoom, SRCC and SRCC+TMM
BENCHMARK(BM_SelectIncremental)
  ->ArgsProduct({ { SRCC, SRCC_TMM }, { 25, 100 }, { 0, 1 }, { 0, 1 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);

// the triangle budget beside the tolerance walk above: SRCC and SRCC+TMM at T_s = 0.25 and 1,
// budgets of 25 % (binding) and 200 % (not binding) of the tolerance cut's triangles, both stop
// rules
BENCHMARK(BM_SelectBudget)
  ->ArgsProduct({ { SRCC, SRCC_TMM }, { 25, 100 }, { 25, 200 }, { 0, 1 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);

// the exact budget (the drawn triangles counted as the patch generator decides them, walks
// repeated while they exceed it): SRCC, binding budgets, the default stop rule
BENCHMARK(BM_SelectBudgetExact)
  ->ArgsProduct({ { SRCC }, { 25, 100 }, { 25 }, { 1 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);

// the alternative: bisection of a tolerance scale factor, 5 and 7 walks a frame, same budgets
BENCHMARK(BM_SelectBisection)
  ->ArgsProduct({ { SRCC, SRCC_TMM }, { 25, 100 }, { 25 }, { 5, 7 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
