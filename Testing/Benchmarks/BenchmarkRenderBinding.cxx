// SPDX-License-Identifier: BSD-3-Clause
// Overhead of vtkPerceptualLODRenderBinding on a frame where nothing changed: the time of one
// push (what the renderer's StartEvent runs) against a still camera, still lights and a still
// prop, after which the selector does not re-execute. Also one push while the camera moves.
//
//   build/bin/BenchmarkRenderBinding --benchmark_repetitions=5
//     --benchmark_report_aggregates_only=true
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkLightKit.h"
#include "vtkNew.h"
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

#include <benchmark/benchmark.h>

namespace
{
void Setup(vtkRenderWindow* window, vtkRenderer* renderer, vtkActor* actor,
  vtkPerceptualLODSelector* selector, vtkPerceptualLODRenderBinding* binding, bool kit)
{
  window->SetSize(1920, 1080);
  window->AddRenderer(renderer); // never rendered: the push reads the renderer's numbers only
  renderer->AddActor(actor);
  if (kit)
  {
    vtkNew<vtkLightKit> lights;
    lights->AddLightsToRenderer(renderer);
  }
  actor->SetPosition(0.1, 0.2, 0.3);
  actor->RotateY(20);
  renderer->GetActiveCamera()->SetPosition(0, 0, 5);
  binding->SetRenderer(renderer);
  binding->SetSelector(selector);
  binding->SetProp3D(actor);
}

void BM_StillFrame(benchmark::State& state)
{
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkActor> actor;
  vtkNew<vtkPerceptualLODSelector> selector;
  vtkNew<vtkPerceptualLODRenderBinding> binding;
  Setup(window, renderer, actor, selector, binding, state.range(0) != 0);
  binding->Update();
  binding->Update();
  const vtkMTimeType settled = selector->GetMTime();
  for (auto _ : state)
  {
    binding->Update();
  }
  if (selector->GetMTime() != settled)
  {
    state.SkipWithError("a still frame modified the selector");
  }
  state.SetLabel(state.range(0) ? "light kit (4 lights)" : "automatic headlight");
}

void BM_MovingFrame(benchmark::State& state)
{
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkActor> actor;
  vtkNew<vtkPerceptualLODSelector> selector;
  vtkNew<vtkPerceptualLODRenderBinding> binding;
  Setup(window, renderer, actor, selector, binding, true);
  for (auto _ : state)
  {
    renderer->GetActiveCamera()->Azimuth(0.1);
    binding->Update();
  }
}
}

BENCHMARK(BM_StillFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MovingFrame)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
