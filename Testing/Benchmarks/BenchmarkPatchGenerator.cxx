// SPDX-License-Identifier: BSD-3-Clause
// Output triangles per second of vtkMultiscalePatchGenerator (one thread, and every core) for cuts
// of 10k to 1M triangles on a generated model of 1,005,360 triangles, beside vtkQuadricClustering
// making a mesh of about the same triangle count from the full input in the same run.
//
//   build/bin/BenchmarkPatchGenerator --benchmark_repetitions=5
//     --benchmark_report_aggregates_only=true
#include "plodTestUtilities.h"

#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscalePatchGenerator.h"
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
  const double tris = static_cast<double>(gen->GetNumberOfTriangles());
  state.counters["triangles"] = tris;
  state.counters["Mtri/s"] =
    benchmark::Counter(tris * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
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
// Case 9 (about 1.2M triangles) is left out: vtkQuadricClustering needs about 600^3 bins for it
// and throws std::bad_alloc on this 24 GB machine (measured).
BENCHMARK(BM_QuadricClusteringSameCount)
  ->DenseRange(5, 8)
  ->Unit(benchmark::kMillisecond)
  ->Iterations(2);

BENCHMARK_MAIN();
