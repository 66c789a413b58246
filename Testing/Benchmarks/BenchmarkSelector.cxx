// SPDX-License-Identifier: BSD-3-Clause
// Visited nodes per second and milliseconds per frame of vtkPerceptualLODSelector (the walk is
// single-threaded) for each mode, on the generated 1,005,360-triangle model (octree level 9)
// filling a 1920 x 1080 viewport, one directional light. Each iteration moves the eye a little
// (a slow orbit), so every frame really selects.
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

#include <cmath>
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

void BM_Select(benchmark::State& state)
{
  const int mode = static_cast<int>(state.range(0));
  const double tolerance = state.range(1) / 100.0; // contour tolerance in pixels
  vtkNew<vtkPerceptualLODSelector> selector;
  selector->SetContourTolerance(tolerance);
  selector->SetBrightnessTolerance(4 * tolerance);
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
  // the model (radius about 1.2) fills the 1080-pixel height at distance 4.5
  const double distance = 4.5;
  double previous[16];
  bool first = true;
  int frame = 0;
  double visited = 0, seconds = 0;
  for (auto _ : state)
  {
    const double a = 0.002 * frame++;
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
    if (!first)
    {
      selector->SetPreviousObjectToViewMatrix(previous);
      selector->HasPreviousFrameOn();
      selector->SetPreviousFrameTime(1.0 / 60.0);
      camera->SetPosition(0, 0, 0); // (keeps the compiler from caching the camera)
    }
    std::copy(now, now + 16, previous);
    first = false;
    selector->Update();
    state.SetIterationTime(selector->GetSelectTime());
    visited += static_cast<double>(selector->GetNumberOfVisitedNodes());
    seconds += selector->GetSelectTime();
  }
  state.counters["Mvisited/s"] = visited / seconds * 1e-6;
  state.counters["visited"] = static_cast<double>(selector->GetNumberOfVisitedNodes());
  state.counters["drawn"] = static_cast<double>(selector->GetNumberOfDrawnNodes());
  state.SetLabel(std::string(Names[mode]) + " T_s=" + std::to_string(tolerance).substr(0, 4));
}
}

// default tolerances (T_s = 1 px, T_b = 4) for every mode; and SRCC and SRCC+TMM with
// tolerances 4x smaller, which visit many more nodes (the per-node rate without the
// per-frame fixed costs)
BENCHMARK(BM_Select)
  ->ArgsProduct({ benchmark::CreateDenseRange(SRCC, FOVEATED, 1), { 100 } })
  ->Args({ SRCC, 25 })
  ->Args({ SRCC_TMM, 25 })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
