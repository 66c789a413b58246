// SPDX-License-Identifier: BSD-3-Clause
// Output triangles per second of vtkMultiscalePatchGenerator (one thread, and every core) for cuts
// of 10k to 1M triangles on a generated model of 1,005,360 triangles, beside vtkQuadricClustering
// making a mesh of about the same triangle count from the full input in the same run.
// BM_PatchesOrbit: the patches of a selector's cuts as the eye orbits the model (far or mid,
// 2 or 45 degrees a frame), on every core: what a moving camera costs, where the corner walks
// the generator remembers from frame to frame help (small steps) or not (large ones).
//
//   build/bin/BenchmarkPatchGenerator --benchmark_repetitions=5
//     --benchmark_report_aggregates_only=true
#include "plodTestUtilities.h"

#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkQuadricClustering.h"
#include "vtkSMPTools.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

namespace
{
struct Scene
{
  vtkSmartPointer<vtkPolyData> Model;
  vtkSmartPointer<vtkMultiscaleOctree> Octree;
};

Scene& GetScene()
{
  static Scene scene;
  if (!scene.Model)
  {
    scene.Model = plodtest::MakeBlob(11, 710, 0.2);
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(scene.Model);
    builder->SetFinestLevel(9);
    builder->Update();
    scene.Octree = builder->GetOutput();
  }
  return scene;
}

/// The cut of each case: uniform levels 5..8, and level 9 on the upper half (about 1M).
vtkSmartPointer<vtkMultiscaleOctree> MakeCut(int which)
{
  Scene& s = GetScene();
  vtkNew<vtkMultiscaleOctreeCutter> cutter;
  cutter->SetInputData(s.Octree);
  if (which <= 8)
  {
    cutter->SetLevel(which);
  }
  else
  {
    vtkMultiscaleOctree* o = s.Octree;
    cutter->SetModeToCallback();
    cutter->SetRefineCallback([o](vtkIdType n) {
      double x[3];
      o->GetNodeVertex(n, x);
      return o->GetNodeLevel(n) < 8 || x[2] > 0.1;
    });
  }
  cutter->Update();
  return cutter->GetOutput();
}

/// The generator's last triangle count and its rate in million triangles per second.
void ReportTriangles(benchmark::State& state, vtkMultiscalePatchGenerator* gen)
{
  const double tris = static_cast<double>(gen->GetNumberOfTriangles());
  state.counters["triangles"] = tris;
  state.counters["Mtri/s"] =
    benchmark::Counter(tris * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

/// The patches of cut `state.range(0)` on `threads` threads (0: vtkSMPTools' default, every
/// core).
void RunPatches(benchmark::State& state, int threads)
{
  vtkSMPTools::Initialize(threads);
  auto cut = MakeCut(static_cast<int>(state.range(0)));
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputData(cut);
  for (auto _ : state)
  {
    gen->Modified();
    gen->Update();
    state.SetIterationTime(gen->GetGenerateTime());
  }
  ReportTriangles(state, gen);
  vtkSMPTools::Initialize(0);
}

void BM_Patches(benchmark::State& state)
{
  RunPatches(state, 1);
}

void BM_PatchesAllCores(benchmark::State& state)
{
  RunPatches(state, 0);
}

/// The patches of the selector's cut (SRCC, default tolerances, one headlight, 1920 x 1080)
/// as the eye orbits the model at distance range(0) / 10 (3.5: mid, the model about the view's
/// height; 14: far), range(1) degrees a frame, every core. Timed: the patch generator alone.
void BM_PatchesOrbit(benchmark::State& state)
{
  Scene& s = GetScene();
  const double distance = state.range(0) / 10.0;
  const double step = state.range(1) * 3.14159265358979323846 / 180.0;
  vtkNew<vtkPerceptualLODSelector> selector;
  selector->SetInputData(s.Octree);
  selector->SetViewportSize(1920, 1080);
  selector->AddLight(false, 0, 0, 1, 1, 0);
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputConnection(selector->GetOutputPort());
  int frame = 0;
  for (auto _ : state)
  {
    const double a = step * frame++;
    const double eye[3] = { distance * std::sin(a), 0.2 * distance, distance * std::cos(a) };
    selector->SetEyePosition(eye[0], eye[1], eye[2]);
    selector->SetLight(0, false, eye[0], eye[1], eye[2], 1, 0);
    gen->Update();
    state.SetIterationTime(gen->GetGenerateTime());
  }
  ReportTriangles(state, gen);
}

/// vtkQuadricClustering with the divisions that give about the cut's triangle count.
void BM_QuadricClusteringSameCount(benchmark::State& state)
{
  auto cut = MakeCut(static_cast<int>(state.range(0)));
  vtkNew<vtkMultiscalePatchGenerator> gen;
  gen->SetInputData(cut);
  gen->Update();
  const double target = static_cast<double>(gen->GetNumberOfTriangles());
  Scene& s = GetScene();
  vtkNew<vtkQuadricClustering> qc;
  qc->SetInputData(s.Model);
  qc->AutoAdjustNumberOfDivisionsOff();
  // calibrate: the output grows like divisions^2 on a surface
  int d = std::max(4, static_cast<int>(std::sqrt(target / 6.0)));
  for (int k = 0; k < 6; ++k)
  {
    qc->SetNumberOfDivisions(d, d, d);
    qc->Update();
    const double got = static_cast<double>(qc->GetOutput()->GetNumberOfPolys());
    const int next = std::max(4, static_cast<int>(std::lround(d * std::sqrt(target / got))));
    if (std::abs(got - target) < 0.03 * target || next == d)
      break;
    d = next;
  }
  for (auto _ : state)
  {
    qc->Modified();
    qc->Update();
  }
  state.counters["triangles"] = static_cast<double>(qc->GetOutput()->GetNumberOfPolys());
  state.counters["divisions"] = d;
}
}

BENCHMARK(BM_Patches)->DenseRange(5, 9)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PatchesAllCores)->DenseRange(5, 9)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PatchesOrbit)
  ->ArgsProduct({ { 140, 35 }, { 2, 45 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond);
// Case 9 (about 1.2M triangles) is left out: vtkQuadricClustering needs about 600^3 bins for it
// and throws std::bad_alloc on this 24 GB machine (measured).
BENCHMARK(BM_QuadricClusteringSameCount)
  ->DenseRange(5, 8)
  ->Unit(benchmark::kMillisecond)
  ->Iterations(2);

BENCHMARK_MAIN();
