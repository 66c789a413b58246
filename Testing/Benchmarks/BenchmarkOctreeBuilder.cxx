// SPDX-License-Identifier: BSD-3-Clause
// Build time and bytes per node of vtkMultiscaleOctreeBuilder, beside vtkQuadricClustering on
// the same input in the same run.
//
//   build/bin/BenchmarkOctreeBuilder --benchmark_repetitions=5
//     --benchmark_report_aggregates_only=true
//
// Inputs: the Stanford bunny mesh and the ten merged bunny range scans (../shared/data, skipped
// when absent), and a generated closed model of 1,005,360 triangles (a displaced UV sphere).
// Counters: Mtri/s (input triangles, or points for the scans, per second), nodes,
// bytes/node (the octree's arrays over its node count).
#include "plodTestUtilities.h"

#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkQuadricClustering.h"
#include "vtkSMPTools.h"
#include "vtkTimerLog.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>

#include <unistd.h>

namespace
{
enum Model
{
  BUNNY = 0,
  SCANS = 1,
  GENERATED = 2,
  GENERATED_DEFAULT = 3 // the same model at the builder's own level
};

vtkPolyData* GetModel(int model)
{
  static std::map<int, vtkSmartPointer<vtkPolyData>> cache;
  auto it = cache.find(model);
  if (it != cache.end())
  {
    return it->second;
  }
  vtkSmartPointer<vtkPolyData> pd;
  const std::string dir = plodtest::DataDir();
  if (model == GENERATED || model == GENERATED_DEFAULT)
  {
    if (model == GENERATED_DEFAULT)
    {
      return cache[model] = GetModel(GENERATED);
    }
    pd = plodtest::MakeBlob(11, 710, 0.2);
  }
  else if (!dir.empty())
  {
    pd =
      model == BUNNY ? plodtest::ReadPLY(dir + "/bun_zipper.ply") : plodtest::ReadBunnyScans(dir);
  }
  cache[model] = pd;
  return pd;
}

const char* ModelName(int model)
{
  return model == BUNNY  ? "bunny"
    : model == SCANS     ? "scans"
    : model == GENERATED ? "generated1M"
                         : "generated1M default level";
}

/// Finest level used for each model: 9 for the generated model (the reference level),
/// the builder's own choice for the Stanford data (the bunny's is 6, the scans' 7) and for
/// GENERATED_DEFAULT (8).
int LevelFor(int model)
{
  return model == GENERATED ? 9 : -1;
}

void BM_Build(benchmark::State& state)
{
  const int model = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  vtkPolyData* input = GetModel(model);
  if (!input)
  {
    state.SkipWithError("../shared/data not found");
    return;
  }
  vtkSMPTools::Initialize(threads);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(input);
  builder->SetFinestLevel(LevelFor(model));
  builder->SetMultiThreaded(threads > 1);
  if (model == SCANS)
  {
    builder->SetViewpointArrayName("ScannerPosition");
  }
  for (auto _ : state)
  {
    builder->Modified();
    builder->Update();
    state.SetIterationTime(builder->GetBuildTime());
  }
  vtkMultiscaleOctree* o = builder->GetOutput();
  const double elements = model == SCANS
    ? input->GetNumberOfPoints()
    : static_cast<double>(builder->GetNumberOfInputTriangles());
  state.counters["Mtri/s"] =
    benchmark::Counter(elements * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["nodes"] = static_cast<double>(o->GetNumberOfNodes());
  state.counters["level"] = o->GetFinestLevel();
  state.counters["bytes/node"] =
    o->GetActualMemorySize() * 1024.0 / std::max<vtkIdType>(1, o->GetNumberOfNodes());
  state.SetLabel(std::string(ModelName(model)) + (threads > 1 ? " smp" : " serial"));
}

void BM_QuadricClustering(benchmark::State& state)
{
  const int model = static_cast<int>(state.range(0));
  vtkPolyData* input = GetModel(model);
  if (!input || input->GetNumberOfPolys() == 0)
  {
    state.SkipWithError(input ? "point cloud: not a mesh" : "../shared/data not found");
    return;
  }
  // same finest resolution as the octree, capped at 256 divisions (the grid is dense)
  vtkNew<vtkMultiscaleOctreeBuilder> probe;
  probe->SetInputData(input);
  probe->SetFinestLevel(LevelFor(model));
  probe->Update();
  const int divisions = std::min(256, 1 << probe->GetOutput()->GetFinestLevel());
  vtkNew<vtkQuadricClustering> qc;
  qc->SetInputData(input);
  qc->AutoAdjustNumberOfDivisionsOff();
  qc->SetNumberOfDivisions(divisions, divisions, divisions);
  for (auto _ : state)
  {
    qc->Modified();
    qc->Update();
  }
  state.counters["Mtri/s"] = benchmark::Counter(
    input->GetNumberOfPolys() * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["divisions"] = divisions;
  state.counters["out_tris"] = static_cast<double>(qc->GetOutput()->GetNumberOfPolys());
  state.SetLabel(std::string(ModelName(model)) + " vtkQuadricClustering");
}
}

/**
 * Opening a saved octree (vtkMultiscaleOctreeReader) against building it, same model, same
 * run: range(0) the model, range(1) 0 mapped, 1 mapped + checksums, 2 read into memory,
 * 3 mapped + the consistency check the first filter runs (IsConsistent). The file is written
 * once, before the timing, so it is in the page cache, as on a second launch.
 */
void BM_OpenOctreeFile(benchmark::State& state)
{
  const int model = static_cast<int>(state.range(0));
  const int variant = static_cast<int>(state.range(1));
  vtkPolyData* input = GetModel(model);
  if (!input)
  {
    state.SkipWithError("../shared/data not found");
    return;
  }
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(input);
  builder->SetFinestLevel(LevelFor(model));
  builder->Update();
  const std::string path = "/tmp/plod_bench_" + std::to_string(::getpid()) + ".plod";
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->SetInputConnection(builder->GetOutputPort());
  writer->SetFileName(path.c_str());
  if (!writer->Write())
  {
    state.SkipWithError(writer->GetErrorMessage());
    return;
  }
  for (auto _ : state)
  {
    vtkNew<vtkMultiscaleOctreeReader> reader;
    reader->SetFileName(path.c_str());
    reader->SetVerifyChecksums(variant == 1);
    reader->SetMemoryMap(variant != 2);
    vtkNew<vtkTimerLog> timer;
    timer->StartTimer();
    reader->Update();
    if (variant == 3 && !reader->GetOutput()->IsConsistent())
    {
      state.SkipWithError("inconsistent");
      break;
    }
    timer->StopTimer();
    state.SetIterationTime(timer->GetElapsedTime());
  }
  state.counters["build_ms"] = builder->GetBuildTime() * 1e3;
  state.counters["MB"] = static_cast<double>(input->GetNumberOfPolys()) > 0
    ? builder->GetOutput()->GetActualMemorySize() / 1024.0
    : 0;
  const char* names[] = { "mapped", "mapped+checksums", "read into memory", "mapped+IsConsistent" };
  state.SetLabel(std::string(ModelName(model)) + " " + names[variant]);
  std::remove(path.c_str());
}

BENCHMARK(BM_OpenOctreeFile)
  ->ArgsProduct({ { BUNNY, GENERATED, GENERATED_DEFAULT }, { 0, 1, 2, 3 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(5);
BENCHMARK(BM_Build)
  ->ArgsProduct({ { BUNNY, SCANS, GENERATED, GENERATED_DEFAULT }, { 1, 2 } })
  ->UseManualTime()
  ->Unit(benchmark::kMillisecond)
  ->Iterations(3);
BENCHMARK(BM_QuadricClustering)
  ->Args({ BUNNY })
  ->Args({ GENERATED })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(3);

BENCHMARK_MAIN();
