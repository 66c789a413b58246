// SPDX-License-Identifier: BSD-3-Clause
// Scale benchmark (issue 10): one generated closed model of about N triangles per process, so
// that each size's peak memory is its own.
//
//   xvfb-run -a build/bin/PerceptualLODScale --triangles 4000000 [--frames 20] [--no-render]
//       [--full-render-limit 16000000] [--level L] [--csv out.csv] [--octree-file f.plod]
//
// It generates a displaced UV sphere (plodtest::MakeBlob, float points, 64-bit cells: what a
// VTK reader gives), builds its octree, and reports:
// - build seconds, the process's peak resident memory (VmHWM) during the build, the build's own
//   peak (peak minus the resident memory before it: the input is already there), both per input
//   triangle; octree bytes per node and per triangle;
// - per frame, along a 20-frame orbit at mid distance (640x480, Mesa llvmpipe under Xvfb):
//   select, patch and render milliseconds (medians) with the binding feeding the selector, and
//   the full-resolution render of the same view (median of 3 frames), up to a size limit.
// With --octree-file it also saves the octree there, opens it with vtkMultiscaleOctreeReader
// (mapped) and times the open and the first filter's consistency check (then removes it).
// scripts/run-scale.sh runs the sizes and writes docs/results/scale.csv.
#include "plodTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace
{
/// A field of /proc/self/status in kB ("VmHWM", "VmRSS"), or -1.
long StatusKB(const char* field)
{
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(field);
  while (std::getline(in, line))
  {
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':')
    {
      return std::atol(line.c_str() + n + 1);
    }
  }
  return -1;
}

/// Resets the peak resident size to the current one (Linux >= 4.0).
void ResetPeak()
{
  std::ofstream("/proc/self/clear_refs") << "5";
}

double Median(std::vector<double> v)
{
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}

int main(int argc, char* argv[])
{
  double target = 1e6;
  int frames = 20;
  bool render = true;
  double fullLimit = 16e6;
  std::string csv, octreeFile;
  int level = -1;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--triangles" && i + 1 < argc)
      target = std::atof(argv[++i]);
    else if (a == "--frames" && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (a == "--no-render")
      render = false;
    else if (a == "--full-render-limit" && i + 1 < argc)
      fullLimit = std::atof(argv[++i]);
    else if (a == "--level" && i + 1 < argc)
      level = std::atoi(argv[++i]);
    else if (a == "--csv" && i + 1 < argc)
      csv = argv[++i];
    else if (a == "--octree-file" && i + 1 < argc)
      octreeFile = argv[++i];
    else
    {
      std::fprintf(stderr,
        "usage: %s --triangles N [--frames F] [--no-render] [--full-render-limit N] "
        "[--level L] [--csv file] [--octree-file path.plod]\n",
        argv[0]);
      return 2;
    }
  }
  // a UV sphere of resolution r has about 2 r^2 triangles
  const int res = std::max(8, static_cast<int>(std::lround(std::sqrt(target / 2.0))));
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  auto model = plodtest::MakeBlob(11, res, 0.2, 1.0, nullptr, /*floatPoints=*/true);
  timer->StopTimer();
  const double triangles = static_cast<double>(model->GetNumberOfPolys());
  std::printf("model: %.0f triangles, %lld points (generated in %.1f s)\n", triangles,
    static_cast<long long>(model->GetNumberOfPoints()), timer->GetElapsedTime());
  std::fflush(stdout);

  const long before = StatusKB("VmRSS");
  ResetPeak();
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(model);
  builder->SetFinestLevel(level);
  timer->StartTimer();
  builder->Update();
  timer->StopTimer();
  const double buildSeconds = timer->GetElapsedTime();
  const long peak = StatusKB("VmHWM");
  vtkMultiscaleOctree* octree = builder->GetOutput();
  const double octreeBytes = 1024.0 * octree->GetActualMemorySize();
  const double nodes = static_cast<double>(octree->GetNumberOfNodes());
  std::printf("build: %.2f s, level %d, %.0f nodes, %lld clusters\n", buildSeconds,
    octree->GetFinestLevel(), nodes, static_cast<long long>(octree->GetNumberOfClusters()));
  std::printf("memory: process peak %.0f MB (%.1f B/triangle), build's own peak %.0f MB "
              "(%.1f B/triangle), octree %.0f MB (%.1f B/node, %.1f B/triangle)\n",
    peak / 1024.0, peak * 1024.0 / triangles, (peak - before) / 1024.0,
    (peak - before) * 1024.0 / triangles, octreeBytes / 1e6, octreeBytes / nodes,
    octreeBytes / triangles);
  std::printf("estimate of the build's own peak: %.0f MB (measured/estimate %.2f)\n",
    builder->GetEstimatedMemory() / 1e6,
    (peak - before) * 1024.0 / std::max(1.0, builder->GetEstimatedMemory()));
  std::fflush(stdout);
  if (octree->GetNumberOfNodes() == 0)
  {
    std::fprintf(stderr, "the build failed\n");
    return 1;
  }

  if (!octreeFile.empty())
  {
    // save the octree, then open it (mapped) and run the check the first filter runs
    vtkNew<vtkMultiscaleOctreeWriter> writer;
    writer->SetInputData(octree);
    writer->SetFileName(octreeFile.c_str());
    timer->StartTimer();
    const bool written = writer->Write() == 1;
    timer->StopTimer();
    const double writeSeconds = timer->GetElapsedTime();
    vtkNew<vtkMultiscaleOctreeReader> reader;
    reader->SetFileName(octreeFile.c_str());
    reader->Update();
    timer->StartTimer();
    const bool consistent = reader->GetOutput()->IsConsistent();
    timer->StopTimer();
    std::printf("octree file: %s, written in %.2f s; opened in %.3f ms (%s, %lld nodes); "
                "first filter's check %.0f ms (%s)\n",
      written ? "ok" : writer->GetErrorMessage(), writeSeconds, reader->GetReadTime() * 1e3,
      reader->GetMapped() ? "mapped" : "read",
      static_cast<long long>(reader->GetOutput()->GetNumberOfNodes()),
      timer->GetElapsedTime() * 1e3, consistent ? "consistent" : "INCONSISTENT");
    std::remove(octreeFile.c_str());
  }

  double selectMs = 0, patchMs = 0, renderMs = 0, fullMs = -1, lodTriangles = 0;
  if (render)
  {
    vtkNew<vtkPerceptualLODSelector> selector;
    selector->SetInputConnection(builder->GetOutputPort());
    vtkNew<vtkMultiscalePatchGenerator> patches;
    patches->SetInputConnection(selector->GetOutputPort());
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(patches->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetSpecular(0.3);
    vtkNew<vtkRenderer> renderer;
    renderer->AddActor(actor);
    vtkNew<vtkRenderWindow> window;
    window->SetOffScreenRendering(1);
    window->SetSize(640, 480);
    window->AddRenderer(renderer);
    vtkNew<vtkPerceptualLODRenderBinding> binding;
    binding->SetRenderer(renderer);
    binding->SetSelector(selector);
    binding->SetProp3D(actor);
    double bounds[6];
    model->GetBounds(bounds);
    vtkCamera* camera = renderer->GetActiveCamera();
    std::vector<double> sel, pat, ren, full, tri;
    for (int f = 0; f < frames; ++f)
    {
      camera->SetPosition(0, 0, 1);
      camera->SetFocalPoint(0, 0, 0);
      camera->SetViewUp(0, 1, 0);
      renderer->ResetCamera(bounds);
      camera->Azimuth(360.0 * f / frames);
      renderer->ResetCameraClippingRange(bounds);
      timer->StartTimer();
      window->Render();
      timer->StopTimer();
      const double total = 1e3 * timer->GetElapsedTime();
      const double s = 1e3 * selector->GetSelectTime(), p = 1e3 * patches->GetGenerateTime();
      if (f > 0) // the first frame includes the caches' set-up
      {
        sel.push_back(s);
        pat.push_back(p);
        ren.push_back(total - s - p);
        tri.push_back(double(patches->GetNumberOfTriangles()));
      }
    }
    binding->EnabledOff();
    selectMs = Median(sel);
    patchMs = Median(pat);
    renderMs = Median(ren);
    lodTriangles = Median(tri);
    if (triangles <= fullLimit)
    {
      vtkNew<vtkPolyDataMapper> fullMapper;
      fullMapper->SetInputData(model);
      actor->SetMapper(fullMapper);
      for (int f = 0; f < 4; ++f)
      {
        timer->StartTimer();
        window->Render();
        timer->StopTimer();
        if (f > 0) // the first upload is not a frame
          full.push_back(1e3 * timer->GetElapsedTime());
      }
      fullMs = Median(full);
    }
    std::printf("frames (medians of %d): %.0f triangles drawn; select %.2f ms, patch %.2f ms, "
                "render %.1f ms; full resolution render %s\n",
      frames - 1, lodTriangles, selectMs, patchMs, renderMs,
      fullMs < 0 ? "not measured (above the limit)" : (std::to_string(fullMs) + " ms").c_str());
  }
  if (!csv.empty())
  {
    const bool header = !std::ifstream(csv).good();
    std::ofstream out(csv, std::ios::app);
    out.precision(10); // counts in full, not as 1.996e+06
    if (header)
    {
      out << "triangles,points,build_s,level,nodes,clusters,peak_mb,peak_b_per_tri,"
             "build_peak_mb,build_b_per_tri,octree_mb,b_per_node,octree_b_per_tri,"
             "lod_triangles,select_ms,patch_ms,render_ms,full_render_ms\n";
    }
    out << triangles << "," << model->GetNumberOfPoints() << "," << buildSeconds << ","
        << octree->GetFinestLevel() << "," << nodes << "," << octree->GetNumberOfClusters() << ","
        << peak / 1024.0 << "," << peak * 1024.0 / triangles << "," << (peak - before) / 1024.0
        << "," << (peak - before) * 1024.0 / triangles << "," << octreeBytes / 1e6 << ","
        << octreeBytes / nodes << "," << octreeBytes / triangles << "," << lodTriangles << ","
        << selectMs << "," << patchMs << "," << renderMs << "," << fullMs << "\n";
  }
  return 0;
}
