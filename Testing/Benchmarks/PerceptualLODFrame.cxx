// SPDX-License-Identifier: BSD-3-Clause
// Whole frames as a user sees them (issue 25): a plain vtkActor of the full mesh against
// vtkPerceptualLODActor on the same mesh, through each of its draw paths (the CPU path: patches
// through a vtkPolyDataMapper; the GPU path: vtkPerceptualLODMapper), on scan-like models with
// detail at every scale.
//
//   xvfb-run -a -s "-screen 0 1920x1080x24" build/bin/PerceptualLODFrame
//       [--levels 2,3,4] [--frames 20] [--size 1920 1080] [--csv frames.csv] [--busy 0.25 2]
//
// The models: the Stanford bunny (bun_zipper.ply, 69,451 triangles) subdivided k times, each
// triangle into four by its edge midpoints (shared, so the mesh stays closed where it was), each
// new midpoint moved along the local normal by a deterministic noise of +-0.15 x the edge length
// (a hash of the edge's two point ids): new detail at every scale, as in a scan. k = 1..4 gives
// about 0.28M, 1.1M, 4.4M and 17.8M triangles.
//
// Each model is seen from three views, orbiting 2 degrees per frame (every frame a new view):
// far (the model about a tenth of the window's height), mid (the model about fills the window's
// height) and close (the camera a third of the model's size from its surface). Every frame is
// timed whole: the camera move, vtkRenderWindow::Render() and WaitForCompletion() (glFinish in
// VTK 9.1's vtkOpenGLRenderWindow). Each method has its own offscreen window; the three share
// one camera and draw every pose one after the other (rotating which goes first), so that a
// busy machine slows them alike. The first two frames of each view are not counted; the
// figures are medians. The full mesh's buffers are uploaded once, on its first frame. The
// octree is built once per model before timing (its time is printed apart) and given to both
// LOD actors; their frames include the selection, the patches (CPU path) and what is sent to
// the GL. Each pose is drawn by each LOD a second time with the camera still (nothing selected
// or sent), which splits its frame into drawing and the rest. Each view also reports the CPU
// that other processes used meanwhile (in cores, from /proc/stat), since the figures mean
// little on a machine someone else is loading; a view during which they used more than 0.25
// cores is measured again, up to twice (--busy C N).
//
// The table goes to stdout as Markdown and, with --csv, to a CSV file.
#include "plodTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPerceptualLODActor.h"
#include "vtkPerceptualLODMapper.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace
{
double Median(std::vector<double> v)
{
  if (v.empty())
  {
    return 0;
  }
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// A well-mixed 64-bit hash (splitmix64's finalizer).
uint64_t Mix(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Area-weighted point normals of a triangle list (as vtkPolyDataNormals without splitting).
std::vector<float> PointNormals(const std::vector<float>& xyz, const std::vector<int64_t>& tri)
{
  std::vector<float> n(xyz.size(), 0.0f);
  for (size_t t = 0; t + 2 < tri.size(); t += 3)
  {
    const float* a = &xyz[3 * tri[t]];
    const float* b = &xyz[3 * tri[t + 1]];
    const float* c = &xyz[3 * tri[t + 2]];
    const float u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const float v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const float f[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
      u[0] * v[1] - u[1] * v[0] }; // twice the area, along the normal
    for (int k = 0; k < 3; ++k)
    {
      float* p = &n[3 * tri[t + k]];
      p[0] += f[0];
      p[1] += f[1];
      p[2] += f[2];
    }
  }
  for (size_t i = 0; i < n.size(); i += 3)
  {
    const float l = std::sqrt(n[i] * n[i] + n[i + 1] * n[i + 1] + n[i + 2] * n[i + 2]);
    if (l > 0)
    {
      n[i] /= l;
      n[i + 1] /= l;
      n[i + 2] /= l;
    }
  }
  return n;
}

/**
 * One subdivision step: each triangle into four by its edge midpoints, one midpoint per edge
 * (shared by the edge's triangles), moved along the mean of its end points' normals by
 * `amplitude` x the edge length x a value in [-1, 1] hashed from the two point ids. The old
 * points keep their ids; the new ones follow in the order of their edges' keys.
 */
void Subdivide(std::vector<float>& xyz, std::vector<int64_t>& tri, double amplitude)
{
  const std::vector<float> normals = PointNormals(xyz, tri);
  const size_t triangles = tri.size() / 3;
  // every triangle's three edges, keyed by (smaller id, larger id), sorted to find the shared ones
  std::vector<std::pair<uint64_t, uint64_t>> edges(3 * triangles);
  for (size_t t = 0; t < triangles; ++t)
  {
    for (int e = 0; e < 3; ++e)
    {
      const uint64_t a = static_cast<uint64_t>(tri[3 * t + e]);
      const uint64_t b = static_cast<uint64_t>(tri[3 * t + (e + 1) % 3]);
      edges[3 * t + e] = { (std::min(a, b) << 32) | std::max(a, b), 3 * t + e };
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<int64_t> mid(3 * triangles);
  int64_t next = static_cast<int64_t>(xyz.size() / 3);
  uint64_t previous = ~0ULL;
  for (const auto& edge : edges)
  {
    if (edge.first != previous)
    {
      previous = edge.first;
      const uint64_t a = edge.first >> 32, b = edge.first & 0xffffffffULL;
      const float* pa = &xyz[3 * a];
      const float* pb = &xyz[3 * b];
      const float* na = &normals[3 * a];
      const float* nb = &normals[3 * b];
      double m[3], n[3], length = 0, nl = 0;
      for (int k = 0; k < 3; ++k)
      {
        m[k] = 0.5 * (double(pa[k]) + double(pb[k]));
        n[k] = double(na[k]) + double(nb[k]);
        length += (double(pb[k]) - double(pa[k])) * (double(pb[k]) - double(pa[k]));
        nl += n[k] * n[k];
      }
      length = std::sqrt(length);
      nl = std::sqrt(nl);
      const double noise = 2.0 * (double(Mix(edge.first) >> 11) / double(1ULL << 53)) - 1.0;
      const double shift = nl > 0 ? amplitude * length * noise / nl : 0.0;
      for (int k = 0; k < 3; ++k)
      {
        xyz.push_back(static_cast<float>(m[k] + shift * n[k]));
      }
      ++next;
    }
    mid[edge.second] = next - 1;
  }
  std::vector<int64_t> out;
  out.reserve(12 * triangles);
  for (size_t t = 0; t < triangles; ++t)
  {
    const int64_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    const int64_t ab = mid[3 * t], bc = mid[3 * t + 1], ca = mid[3 * t + 2];
    const int64_t four[12] = { a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca };
    out.insert(out.end(), four, four + 12);
  }
  tri.swap(out);
}

/// The bunny subdivided `k` times (see Subdivide), with point normals, float points and
/// 64-bit cells (what a VTK reader gives).
vtkSmartPointer<vtkPolyData> MakeScanLike(vtkPolyData* bunny, int k)
{
  std::vector<float> xyz(3 * bunny->GetNumberOfPoints());
  for (vtkIdType i = 0; i < bunny->GetNumberOfPoints(); ++i)
  {
    double p[3];
    bunny->GetPoint(i, p);
    for (int c = 0; c < 3; ++c)
    {
      xyz[3 * i + c] = static_cast<float>(p[c]);
    }
  }
  std::vector<int64_t> tri;
  tri.reserve(3 * bunny->GetNumberOfPolys());
  auto it = vtk::TakeSmartPointer(bunny->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType j = 1; j + 1 < n; ++j) // fans, though the bunny holds triangles only
    {
      tri.push_back(ids[0]);
      tri.push_back(ids[j]);
      tri.push_back(ids[j + 1]);
    }
  }
  for (int s = 0; s < k; ++s)
  {
    Subdivide(xyz, tri, 0.15);
  }
  const std::vector<float> normals = PointNormals(xyz, tri);

  const vtkIdType np = static_cast<vtkIdType>(xyz.size() / 3);
  const vtkIdType nt = static_cast<vtkIdType>(tri.size() / 3);
  vtkNew<vtkFloatArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(np);
  std::copy(xyz.begin(), xyz.end(), coords->GetPointer(0));
  std::vector<float>().swap(xyz);
  vtkNew<vtkFloatArray> normalArray;
  normalArray->SetName("Normals");
  normalArray->SetNumberOfComponents(3);
  normalArray->SetNumberOfTuples(np);
  std::copy(normals.begin(), normals.end(), normalArray->GetPointer(0));
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nt + 1);
  for (vtkIdType t = 0; t <= nt; ++t)
  {
    offsets->SetValue(t, 3 * t);
  }
  connectivity->SetNumberOfTuples(3 * nt);
  std::copy(tri.begin(), tri.end(), connectivity->GetPointer(0));
  std::vector<int64_t>().swap(tri);
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);

  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  mesh->SetPoints(points);
  mesh->SetPolys(polys);
  mesh->GetPointData()->SetNormals(normalArray);
  return mesh;
}

/// The lines of ReportCapabilities() that name the OpenGL vendor, renderer and version.
std::string RendererLines(vtkRenderWindow* window)
{
  std::istringstream in(window->ReportCapabilities());
  std::string line, out;
  while (std::getline(in, line))
  {
    if (line.rfind("OpenGL ", 0) == 0 &&
      (line.find("vendor string") != std::string::npos ||
        line.find("renderer string") != std::string::npos ||
        line.find("version string") != std::string::npos))
    {
      out += line + "\n";
    }
  }
  return out.empty() ? std::string("(no capabilities reported)\n") : out;
}

/// The renderer string alone ("llvmpipe (LLVM 15.0.6, 256 bits)"), for the table's caption.
std::string RendererName(const std::string& lines)
{
  const std::string key = "renderer string:";
  const size_t at = lines.find(key);
  if (at == std::string::npos)
  {
    return "unknown";
  }
  const size_t begin = lines.find_first_not_of(' ', at + key.size());
  const size_t end = lines.find('\n', at);
  return lines.substr(begin, end - begin);
}

/// The system's load averages (/proc/loadavg), to tell a quiet machine's figures from a busy
/// one's; "" where the file does not exist.
std::string LoadAverage()
{
  std::ifstream in("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  if (!(in >> one >> five >> fifteen))
  {
    return "";
  }
  char text[96];
  std::snprintf(text, sizeof(text), "load average %.2f %.2f %.2f", one, five, fifteen);
  return text;
}

/**
 * The CPU time other processes used over an interval, in cores (busy time of the whole machine
 * from /proc/stat less this process's own), so that figures taken while the shared machine was
 * busy can be told apart. -1 where /proc/stat cannot be read.
 */
class OtherLoad
{
public:
  OtherLoad()
    : Busy(MachineBusySeconds())
    , Own(OwnSeconds())
  {
    this->Clock->StartTimer();
  }
  double Cores()
  {
    this->Clock->StopTimer();
    const double busy = MachineBusySeconds(), wall = this->Clock->GetElapsedTime();
    if (busy < 0 || this->Busy < 0 || wall <= 0)
    {
      return -1;
    }
    return std::max(0.0, ((busy - this->Busy) - (OwnSeconds() - this->Own)) / wall);
  }

private:
  static double MachineBusySeconds()
  {
    std::ifstream in("/proc/stat");
    std::string cpu;
    double user, nice, system, idle, iowait, irq, softirq, steal;
    if (!(in >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal))
    {
      return -1;
    }
    return (user + nice + system + irq + softirq + steal) / double(sysconf(_SC_CLK_TCK));
  }
  static double OwnSeconds()
  {
    rusage use;
    getrusage(RUSAGE_SELF, &use);
    return double(use.ru_utime.tv_sec) + 1e-6 * double(use.ru_utime.tv_usec) +
      double(use.ru_stime.tv_sec) + 1e-6 * double(use.ru_stime.tv_usec);
  }
  double Busy, Own;
  vtkNew<vtkTimerLog> Clock;
};

struct Row
{
  double ModelTriangles = 0;
  std::string View;
  double FullMs = 0;
  // the LOD actor's CPU path (the default): select, patch, whole frame, triangles drawn
  double SelectMs = 0, PatchMs = 0, LODMs = 0, LODTriangles = 0;
  double StillMs = 0;                 // the same pose drawn again, the camera still: drawing alone
  double LODPoints = 0, LODFolds = 0; // the cut's output points and turned-over triangles
  // the LOD actor's GPU path (vtkPerceptualLODMapper)
  double GPUSelectMs = 0, GPUMs = 0, GPUTriangles = 0, GPUStillMs = 0, GPUUploadKB = 0;
  double GPUCPUMs = 0;      // the GPU path's CPU work: select, ranges, state compare and upload
  bool GPUFellBack = false; // the GPU path drew through the CPU path
  double OtherCores = -1;   // CPU used by other processes meanwhile, in cores (-1: unknown)
  int Frames = 0;
  int Attempts = 1; // measured again while other processes loaded the machine
};

/// The three ways of drawing the model, one window each.
enum Method
{
  FULL = 0,
  LOD_CPU = 1,
  LOD_GPU = 2,
  METHODS = 3
};

/**
 * One view: `frames` poses of an orbit (2 degrees apart) from the camera `distance` from the
 * model's centre, each drawn by the three windows (rotating which goes first), then by each LOD
 * window once more with the camera still. Medians of the frames after the first `skipped`.
 */
Row MeasureView(double distance, int frames, int skipped, const double center[3],
  const double bounds[6], vtkCamera* camera, vtkRenderWindow* windows[METHODS],
  vtkRenderer* renderers[METHODS], vtkPerceptualLODActor* cpu, vtkPerceptualLODActor* gpu,
  vtkTimerLog* timer)
{
  camera->SetFocalPoint(center[0], center[1], center[2]);
  camera->SetPosition(center[0], center[1], center[2] + 1.0);
  camera->SetViewUp(0, 1, 0);
  camera->SetViewAngle(30.0);
  renderers[FULL]->ResetCamera(const_cast<double*>(bounds));
  camera->Dolly(camera->GetDistance() / distance);
  vtkMultiscalePatchGenerator* patches = cpu->GetPatchGenerator();
  std::vector<double> ms[METHODS], stillMs[METHODS];
  std::vector<double> selectMs, patchMs, drawn, points, folds, gpuSelectMs, gpuDrawn, gpuKB,
    gpuCPUMs;
  int changedWhileStill = 0;
  bool fellBack = false;
  OtherLoad others;
  for (int f = 0; f < frames; ++f)
  {
    // the camera move, timed once and counted in every method's frame (a few microseconds)
    timer->StartTimer();
    camera->Azimuth(2.0);
    timer->StopTimer();
    const double moveMs = 1e3 * timer->GetElapsedTime();
    double frame[METHODS];
    for (int i = 0; i < METHODS; ++i)
    {
      const int m = (f + i) % METHODS; // rotate which method draws first
      timer->StartTimer();
      renderers[m]->ResetCameraClippingRange(const_cast<double*>(bounds));
      windows[m]->Render();
      windows[m]->WaitForCompletion();
      timer->StopTimer();
      frame[m] = moveMs + 1e3 * timer->GetElapsedTime();
    }
    const double select = cpu->GetSelector()->GetSelectTime();
    const double patch = patches->GetGenerateTime();
    const double gpuSelect = gpu->GetSelector()->GetSelectTime();
    const double gpuUploadKB = double(gpu->GetGPUMapper()->GetLastUploadBytes()) / 1024.0;
    const double gpuCPU = gpuSelect + gpu->GetGPUMapper()->GetLastCPUTime();
    fellBack = fellBack || !gpu->GetDrewOnGPU();
    // Each LOD's pose again: nothing is selected or uploaded, the frame only draws the cut. The
    // moving frame less this, the selection and the patches is what sending the new cut costs.
    double still[METHODS] = { 0, 0, 0 };
    for (const int m : { LOD_CPU, LOD_GPU })
    {
      vtkPerceptualLODActor* lod = m == LOD_CPU ? cpu : gpu;
      const vtkMTimeType cut = lod->GetSelector()->GetOutputDataObject(0)->GetMTime();
      timer->StartTimer();
      windows[m]->Render();
      windows[m]->WaitForCompletion();
      timer->StopTimer();
      still[m] = 1e3 * timer->GetElapsedTime();
      changedWhileStill += lod->GetSelector()->GetOutputDataObject(0)->GetMTime() != cut;
    }
    if (f < skipped)
    {
      continue; // the first upload, shader compilation, the selector's caches
    }
    for (int m = 0; m < METHODS; ++m)
    {
      ms[m].push_back(frame[m]);
      stillMs[m].push_back(still[m]);
    }
    selectMs.push_back(1e3 * select);
    patchMs.push_back(1e3 * patch);
    drawn.push_back(double(patches->GetNumberOfTriangles()));
    points.push_back(double(patches->GetNumberOfOutputPoints()));
    folds.push_back(double(patches->GetNumberOfFolds()));
    gpuSelectMs.push_back(1e3 * gpuSelect);
    gpuDrawn.push_back(double(gpu->GetGPUMapper()->GetNumberOfDrawnTriangles()));
    gpuKB.push_back(gpuUploadKB);
    gpuCPUMs.push_back(1e3 * gpuCPU);
  }
  if (changedWhileStill > 0)
  {
    std::fprintf(
      stderr, "warning: a cut changed %d times while the camera was still\n", changedWhileStill);
  }
  Row row;
  row.OtherCores = others.Cores();
  row.Frames = frames - skipped;
  row.FullMs = Median(ms[FULL]);
  row.LODMs = Median(ms[LOD_CPU]);
  row.StillMs = Median(stillMs[LOD_CPU]);
  row.SelectMs = Median(selectMs);
  row.PatchMs = Median(patchMs);
  row.LODTriangles = Median(drawn);
  row.LODPoints = Median(points);
  row.LODFolds = Median(folds);
  row.GPUMs = Median(ms[LOD_GPU]);
  row.GPUStillMs = Median(stillMs[LOD_GPU]);
  row.GPUSelectMs = Median(gpuSelectMs);
  row.GPUTriangles = Median(gpuDrawn);
  row.GPUUploadKB = Median(gpuKB);
  row.GPUCPUMs = Median(gpuCPUMs);
  row.GPUFellBack = fellBack;
  return row;
}
}

int main(int argc, char* argv[])
{
  std::vector<int> levels = { 2, 3, 4 };
  int frames = 20;
  int width = 1920, height = 1080;
  std::string csv;
  double maxOtherCores = 0.25;
  vtkIdType budget = 0;
  int retries = 2;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--levels" && i + 1 < argc)
    {
      levels.clear();
      std::stringstream list(argv[++i]);
      std::string item;
      while (std::getline(list, item, ','))
      {
        const int k = std::atoi(item.c_str());
        if (k < 0 || k > 4)
        {
          std::fprintf(
            stderr, "--levels: each subdivision count must be in 0..4, got '%s'\n", item.c_str());
          return 2;
        }
        levels.push_back(k);
      }
    }
    else if (a == "--frames" && i + 1 < argc)
    {
      frames = std::atoi(argv[++i]);
    }
    else if (a == "--size" && i + 2 < argc)
    {
      width = std::atoi(argv[++i]);
      height = std::atoi(argv[++i]);
    }
    else if (a == "--csv" && i + 1 < argc)
    {
      csv = argv[++i];
    }
    else if (a == "--budget" && i + 1 < argc)
    {
      budget = std::atoll(argv[++i]);
    }
    else if (a == "--busy" && i + 2 < argc)
    {
      maxOtherCores = std::atof(argv[++i]);
      retries = std::atoi(argv[++i]);
    }
    else
    {
      std::fprintf(stderr,
        "usage: %s [--levels 2,3,4] [--frames 20] [--size 1920 1080] [--csv file.csv]\n"
        "          [--busy 0.25 2] [--budget 0]\n"
        "  levels: how many times the bunny is subdivided (0..4: 69k, about 0.28M, 1.1M, 4.4M "
        "and 17.8M triangles)\n"
        "  busy: a view during which other processes used more than this many cores is measured "
        "again, at most this many times\n"
        "  budget: the LOD actors' triangle budget (0: none, the tolerance cut)\n",
        argv[0]);
      return 2;
    }
  }
  const int skipped = 2;
  if (frames <= skipped || width < 16 || height < 16 || levels.empty())
  {
    std::fprintf(
      stderr, "need --frames above %d, a window of at least 16x16 and a level\n", skipped);
    return 2;
  }

  const std::string dir = plodtest::DataDir();
  if (dir.empty())
  {
    std::fprintf(stderr,
      "the Stanford bunny (bun_zipper.ply) was not found: put it in ../shared/data beside the "
      "source tree, or set PLOD_DATA_DIR to its folder\n");
    return 1;
  }
  auto bunny = plodtest::ReadPLY(dir + "/bun_zipper.ply");
  if (!bunny || bunny->GetNumberOfPolys() == 0)
  {
    std::fprintf(stderr, "could not read %s/bun_zipper.ply\n", dir.c_str());
    return 1;
  }

  // One window per method, all offscreen, sharing one camera: every pose is drawn by each, one
  // after the other, so that a busy machine slows them alike.
  vtkNew<vtkRenderWindow> fullWindow, cpuWindow, gpuWindow;
  vtkNew<vtkRenderer> fullRenderer, cpuRenderer, gpuRenderer;
  vtkNew<vtkCamera> camera;
  vtkRenderWindow* windows[METHODS] = { fullWindow, cpuWindow, gpuWindow };
  vtkRenderer* renderers[METHODS] = { fullRenderer, cpuRenderer, gpuRenderer };
  for (int m = 0; m < METHODS; ++m)
  {
    windows[m]->SetOffScreenRendering(1);
    windows[m]->SetSize(width, height);
    windows[m]->AddRenderer(renderers[m]);
    renderers[m]->SetActiveCamera(camera);
  }
  for (int m = 0; m < METHODS; ++m)
  {
    windows[m]->Render(); // makes the contexts, for the report below
  }
  const std::string gl = RendererLines(fullWindow);
  std::printf("%s", gl.c_str());
  std::printf("%s\n", LoadAverage().c_str());
  std::printf("window %dx%d offscreen; %d frames per view and method, the first %d not counted\n",
    width, height, frames, skipped);

  // the floor: a frame that draws nothing (clear, the renderer's passes, the offscreen frame)
  vtkNew<vtkTimerLog> timer;
  std::vector<double> emptyMs;
  for (int f = 0; f < frames; ++f)
  {
    timer->StartTimer();
    camera->Azimuth(2.0);
    fullWindow->Render();
    fullWindow->WaitForCompletion();
    timer->StopTimer();
    if (f >= skipped)
    {
      emptyMs.push_back(1e3 * timer->GetElapsedTime());
    }
  }
  const double emptyFrameMs = Median(emptyMs);
  std::printf("empty frame (nothing drawn): %.1f ms\n", emptyFrameMs);
  std::fflush(stdout);

  std::vector<Row> rows;
  for (const int k : levels)
  {
    timer->StartTimer();
    vtkSmartPointer<vtkPolyData> model = MakeScanLike(bunny, k);
    timer->StopTimer();
    const double triangles = static_cast<double>(model->GetNumberOfPolys());
    std::printf(
      "\nmodel: bunny subdivided %d times: %.0f triangles, %lld points (made in %.1f s)\n", k,
      triangles, static_cast<long long>(model->GetNumberOfPoints()), timer->GetElapsedTime());
    std::fflush(stdout);

    // the full mesh, as a user would draw it
    vtkNew<vtkPolyDataMapper> fullMapper;
    fullMapper->SetInputData(model);
    vtkNew<vtkActor> full;
    full->SetMapper(fullMapper);

    // The LOD actor on the same mesh, its octree built once before any frame (by the builder the
    // actor would run, with its defaults) and given to both paths' actors, which then build
    // nothing: the CPU path (the default) and the GPU path.
    vtkNew<vtkMultiscaleOctreeBuilder> builder;
    builder->SetInputData(model);
    timer->StartTimer();
    builder->Update();
    timer->StopTimer();
    vtkMultiscaleOctree* octree = builder->GetOutput();
    std::printf("octree: built in %.2f s, level %d (%s), %lld nodes\n", timer->GetElapsedTime(),
      octree->GetFinestLevel(), builder->GetFinestLevelReason(),
      static_cast<long long>(octree->GetNumberOfNodes()));
    std::fflush(stdout);
    if (octree->GetNumberOfNodes() == 0)
    {
      std::fprintf(stderr, "the octree build failed\n");
      return 1;
    }
    vtkNew<vtkPerceptualLODActor> cpu, gpu;
    cpu->SetInputConnection(builder->GetOutputPort());
    cpu->SetDrawPathToCPU();
    gpu->SetInputConnection(builder->GetOutputPort());
    gpu->SetDrawPathToGPU();
    cpu->GetSelector()->SetTriangleBudget(budget);
    gpu->GetSelector()->SetTriangleBudget(budget);

    fullRenderer->AddActor(full);
    cpuRenderer->AddActor(cpu);
    gpuRenderer->AddActor(gpu);

    // the model's size and the camera distances of the three views
    double bounds[6];
    model->GetBounds(bounds);
    const double center[3] = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
      0.5 * (bounds[4] + bounds[5]) };
    const double size =
      std::max({ bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4] });
    const double tanHalf = std::tan(vtkMath::RadiansFromDegrees(0.5 * 30.0)); // view angle 30
    // how far the surface reaches towards the camera (+z, where ResetCamera puts it)
    double front = 0;
    for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
    {
      double p[3];
      model->GetPoint(i, p);
      front = std::max(front, p[2] - center[2]);
    }
    struct View
    {
      const char* Name;
      double Distance; // from the model's centre
    };
    const View views[3] = {
      { "far", size / (0.1 * 2 * tanHalf) }, // the model a tenth of the window's height
      { "mid", size / (2 * tanHalf) },       // the model the window's height
      { "close", front + size / 3.0 },       // a third of the model's size from its surface
    };

    for (const View& view : views)
    {
      Row row;
      for (int attempt = 0;; ++attempt)
      {
        row = MeasureView(view.Distance, frames, skipped, center, bounds, camera, windows,
          renderers, cpu, gpu, timer);
        row.Attempts = attempt + 1;
        if (row.OtherCores <= maxOtherCores || attempt >= retries)
        {
          break;
        }
        std::printf(
          "  %-5s other processes used %.2f cores: measured again\n", view.Name, row.OtherCores);
        std::fflush(stdout);
      }
      row.ModelTriangles = triangles;
      row.View = view.Name;
      std::printf("  %-5s (camera %.3g from the centre): full %.1f ms; LOD %.1f ms (select %.2f, "
                  "patch %.2f), %.0f triangles\n",
        view.Name, view.Distance, row.FullMs, row.LODMs, row.SelectMs, row.PatchMs,
        row.LODTriangles);
      std::printf("        LOD: %.0f points, %.0f turned-over triangles; full mesh: %lld points\n",
        row.LODPoints, row.LODFolds, static_cast<long long>(model->GetNumberOfPoints()));
      std::printf("        LOD with the camera still: %.1f ms\n", row.StillMs);
      std::printf("        GPU path: %.1f ms (select %.2f, CPU in all %.2f), %.0f triangles, "
                  "%.1f KB sent; camera still: %.1f ms%s\n",
        row.GPUMs, row.GPUSelectMs, row.GPUCPUMs, row.GPUTriangles, row.GPUUploadKB, row.GPUStillMs,
        row.GPUFellBack ? "; FELL BACK TO THE CPU PATH" : "");
      std::printf(
        "        other processes used %.2f cores; %s\n", row.OtherCores, LoadAverage().c_str());
      std::fflush(stdout);
      rows.push_back(row);
    }
    // free this model's buffers before the next one is made
    fullRenderer->RemoveActor(full);
    cpuRenderer->RemoveActor(cpu);
    gpuRenderer->RemoveActor(gpu);
    full->ReleaseGraphicsResources(fullWindow);
    cpu->ReleaseGraphicsResources(cpuWindow);
    gpu->ReleaseGraphicsResources(gpuWindow);
  }

  std::printf("%s at the end\n", LoadAverage().c_str());
  std::printf("\nRenderer: %s; %dx%d; medians of %d frames per row; a frame that draws "
              "nothing takes %.1f ms.\n\n",
    RendererName(gl).c_str(), width, height, frames - skipped, emptyFrameMs);
  std::printf("| model triangles | view | full frame ms | LOD select ms | LOD patch ms | "
              "LOD frame ms | LOD triangles | full / LOD | GPU path frame ms | GPU path "
              "triangles | full / GPU path |\n");
  std::printf("| ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (const Row& r : rows)
  {
    std::printf("| %.0f | %s | %.1f | %.2f | %.2f | %.1f | %.0f | %.2f | %.1f%s | %.0f | %.2f |\n",
      r.ModelTriangles, r.View.c_str(), r.FullMs, r.SelectMs, r.PatchMs, r.LODMs, r.LODTriangles,
      r.LODMs > 0 ? r.FullMs / r.LODMs : 0.0, r.GPUMs, r.GPUFellBack ? " (CPU path)" : "",
      r.GPUTriangles, r.GPUMs > 0 ? r.FullMs / r.GPUMs : 0.0);
  }
  std::printf("\nWhere the LOD's moving frames go (ms; still: the same pose drawn again, nothing "
              "selected or sent; rest = frame - select - patch - still):\n\n");
  std::printf("| model triangles | view | CPU path frame | select | patch | rest | still | GPU "
              "path frame | select | rest | still | GPU path CPU | GPU path KB sent | other "
              "processes (cores) |\n");
  std::printf("| ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
              "| ---: | ---: |\n");
  for (const Row& r : rows)
  {
    std::printf("| %.0f | %s | %.1f | %.2f | %.2f | %.1f | %.1f | %.1f | %.2f | %.1f | %.1f | "
                "%.2f | %.1f | %.2f |\n",
      r.ModelTriangles, r.View.c_str(), r.LODMs, r.SelectMs, r.PatchMs,
      r.LODMs - r.SelectMs - r.PatchMs - r.StillMs, r.StillMs, r.GPUMs, r.GPUSelectMs,
      r.GPUMs - r.GPUSelectMs - r.GPUStillMs, r.GPUStillMs, r.GPUCPUMs, r.GPUUploadKB,
      r.OtherCores);
  }
  if (!csv.empty())
  {
    std::ofstream out(csv);
    if (!out)
    {
      std::fprintf(stderr, "cannot write %s\n", csv.c_str());
      return 1;
    }
    out.precision(10);
    out << "model_triangles,view,full_frame_ms,lod_select_ms,lod_patch_ms,lod_frame_ms,"
           "lod_triangles,speedup,gpu_frame_ms,gpu_triangles,gpu_speedup,lod_still_frame_ms,"
           "lod_points,lod_folds,gpu_select_ms,gpu_still_frame_ms,gpu_upload_kb,gpu_fell_back,"
           "other_cpu_cores,attempts,frames,width,height,empty_frame_ms,renderer,gpu_cpu_ms,"
           "budget\n";
    for (const Row& r : rows)
    {
      out << r.ModelTriangles << "," << r.View << "," << r.FullMs << "," << r.SelectMs << ","
          << r.PatchMs << "," << r.LODMs << "," << r.LODTriangles << ","
          << (r.LODMs > 0 ? r.FullMs / r.LODMs : 0.0) << "," << r.GPUMs << "," << r.GPUTriangles
          << "," << (r.GPUMs > 0 ? r.FullMs / r.GPUMs : 0.0) << "," << r.StillMs << ","
          << r.LODPoints << "," << r.LODFolds << "," << r.GPUSelectMs << "," << r.GPUStillMs << ","
          << r.GPUUploadKB << "," << r.GPUFellBack << "," << r.OtherCores << "," << r.Attempts
          << "," << r.Frames << "," << width << "," << height << "," << emptyFrameMs << ",\""
          << RendererName(gl) << "\"," << r.GPUCPUMs << "," << budget << "\n";
    }
  }
  return 0;
}
