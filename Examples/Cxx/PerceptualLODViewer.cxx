// SPDX-License-Identifier: BSD-3-Clause
// PerceptualLOD's viewer: renders a model with the perceptual LOD, frame by frame.
//
//   PerceptualLODViewer [model.ply|.stl|.obj|.vtp|.plod] [--offscreen] [--frames N] [--out DIR]
//                       [--size W H] [--level L] [--mode srcc|tmm|scvc|psec|distance|ipv|dpv|fovea]
//                       [--cache-limit MiB] [--background-loading]
//
// Without a file it uses a generated detailed model (a displaced sphere, about 250k triangles).
// An octree file is mapped; --cache-limit bounds how much of it the viewer keeps resident
// between frames (vtkMultiscaleOctreeReader::SetCacheLimit; 0: no limit; default 2048), and
// --background-loading reads its pages off the frame (SetBackgroundLoading): what is not read
// yet is drawn coarser, and the viewer renders again as the pages arrive.
// Interactive keys:
//   1 SRCC   2 SRCC+TMM   3 SCVC   4 PSEC   5 Distance   6 IPV   7 DPV   8 foveated
//   0 full resolution    + / - tolerances x1.5 / /1.5    h help
// With --offscreen it follows a scripted path: the object translates, the camera zooms in, the
// object rotates. Each frame is also drawn at full resolution, for the PSNR and for the frame
// time the LOD saves: it prints both frame times and, at the end, their medians and the
// speed-up (render_ms is the renderer's whole frame, select and patch included). It writes
// per-frame figures to DIR/frames.csv, every 10th frame as
// DIR/frame_NNNN.png, and DIR/compare_*.png images with full resolution (left) beside the LOD
// (right) at the same instant.
#include "plodTestUtilities.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkImageAppend.h"
#include "vtkImageData.h"
#include "vtkInteractorStyleTrackballCamera.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeCutter.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataNormals.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTimerLog.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace
{
const char* ModeNames[] = { "full resolution", "SRCC", "SRCC+TMM", "SCVC", "PSEC",
  "Distance (Wang & Sato)", "SRCC+IPV", "SRCC+DPV", "SRCC+foveated" };

/// The pipeline and the figures shown on screen.
struct Viewer
{
  vtkNew<vtkMultiscaleOctreeBuilder> Builder;
  vtkNew<vtkPerceptualLODSelector> Selector;
  vtkNew<vtkMultiscalePatchGenerator> Patches;
  vtkNew<vtkPolyDataMapper> LODMapper, FullMapper;
  vtkNew<vtkActor> LODActor, FullActor;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkPerceptualLODRenderBinding> Binding;
  vtkNew<vtkTextActor> Text;
  int Mode = 1;
  double Scale = 1.0; // tolerance scale
  double RenderStart = 0, RenderTime = 0;
  vtkIdType LoadsRendered = 0; // background loads as of the last render asked for them

  void SetMode(int mode)
  {
    this->Mode = mode;
    const bool full = mode == 0;
    this->FullActor->SetVisibility(full);
    this->LODActor->SetVisibility(!full);
    this->Binding->SetEnabled(!full);
    vtkPerceptualLODSelector* s = this->Selector;
    s->SetErrorModelToSRCC();
    s->SetMotionModelToNone();
    s->SetFoveationModeToOff();
    switch (mode)
    {
      case 2:
        s->SetMotionModelToMicroMotion();
        break;
      case 3:
        s->SetErrorModelToSCVC();
        break;
      case 4:
        s->SetErrorModelToPSEC();
        break;
      case 5:
        s->SetErrorModelToDistance();
        break;
      case 6:
        s->SetMotionModelToInverseVelocity();
        break;
      case 7:
        s->SetMotionModelToDirectVelocity();
        break;
      case 8:
        s->SetFoveationModeToScreen();
        break;
      default:
        break;
    }
  }

  void SetScale(double scale)
  {
    this->Scale = scale;
    this->Selector->ScaleTolerances(scale);
  }

  vtkIdType Triangles()
  {
    return this->Mode == 0 ? this->FullMapper->GetInput()->GetNumberOfPolys()
                           : this->Patches->GetNumberOfTriangles();
  }

  std::string Status()
  {
    std::ostringstream os;
    os.precision(3);
    os << ModeNames[this->Mode] << "   T_s " << this->Selector->GetContourTolerance() << " px, T_b "
       << this->Selector->GetBrightnessTolerance() << "\n"
       << this->Triangles() << " triangles";
    if (this->Mode != 0)
    {
      os << "   select " << this->Selector->GetSelectTime() * 1e3 << " ms   patch "
         << this->Patches->GetGenerateTime() * 1e3 << " ms";
    }
    os << "   render " << this->RenderTime * 1e3
       << " ms\nkeys: 1-8 modes, 0 full, +/- tolerance, h help";
    return os.str();
  }
};

void OnKey(vtkObject* caller, unsigned long, void* client, void*)
{
  auto* viewer = static_cast<Viewer*>(client);
  auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
  const std::string key = interactor->GetKeySym() ? interactor->GetKeySym() : "";
  if (key.size() == 1 && key[0] >= '0' && key[0] <= '8')
    viewer->SetMode(key[0] - '0');
  else if (key == "plus" || key == "equal" || key == "KP_Add")
    viewer->SetScale(viewer->Scale * 1.5);
  else if (key == "minus" || key == "KP_Subtract")
    viewer->SetScale(viewer->Scale / 1.5);
  else if (key == "h")
    std::printf("1 SRCC, 2 SRCC+TMM, 3 SCVC, 4 PSEC, 5 Distance, 6 IPV, 7 DPV, 8 foveated, "
                "0 full resolution, +/- tolerances\n");
  else
    return;
  interactor->Render();
}

void OnStart(vtkObject*, unsigned long, void* client, void*)
{
  static_cast<Viewer*>(client)->RenderStart = vtkTimerLog::GetUniversalTime();
}

void OnEnd(vtkObject*, unsigned long, void* client, void*)
{
  auto* v = static_cast<Viewer*>(client);
  v->RenderTime = vtkTimerLog::GetUniversalTime() - v->RenderStart;
}

vtkSmartPointer<vtkImageData> Grab(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

double PSNR(vtkImageData* a, vtkImageData* b)
{
  vtkDataArray* x = a->GetPointData()->GetScalars();
  vtkDataArray* y = b->GetPointData()->GetScalars();
  double sum = 0;
  const vtkIdType n = x->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n; ++i)
  {
    double lx = 0, ly = 0;
    const double w[3] = { 0.2126, 0.7152, 0.0722 };
    for (int c = 0; c < 3; ++c)
    {
      lx += w[c] * x->GetComponent(i, c);
      ly += w[c] * y->GetComponent(i, c);
    }
    sum += (lx - ly) * (lx - ly);
  }
  const double mse = sum / std::max<vtkIdType>(n, 1);
  return mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
}

/**
 * The model without its polygons of fewer than three points, which vtkPolyDataNormals crashes
 * on (a PLY face of one or two indices is valid PLY, and OBJ and VTP files may hold such cells
 * too); their cell data go with them. The model itself when it has none; otherwise a warning on
 * stderr says how many were dropped and which was the first.
 */
vtkSmartPointer<vtkPolyData> DropShortPolys(vtkPolyData* model, const std::string& file)
{
  vtkCellArray* polys = model->GetPolys();
  vtkIdType dropped = 0, first = -1, index = 0, n;
  const vtkIdType* ids;
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++index)
  {
    it->GetCurrentCell(n, ids);
    if (n < 3)
    {
      first = dropped++ == 0 ? index : first;
    }
  }
  if (dropped == 0)
  {
    return model;
  }
  // cells are numbered verts, lines, polys, strips: the cell data follow that order
  const vtkIdType base = model->GetNumberOfVerts() + model->GetNumberOfLines();
  const vtkIdType cells = model->GetNumberOfCells();
  vtkNew<vtkCellArray> kept;
  kept->AllocateEstimate(polys->GetNumberOfCells() - dropped, 3);
  vtkNew<vtkCellData> cellData;
  cellData->CopyAllocate(model->GetCellData(), cells - dropped);
  vtkIdType next = 0;
  for (vtkIdType c = 0; c < base; ++c)
  {
    cellData->CopyData(model->GetCellData(), c, next++);
  }
  index = base;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++index)
  {
    it->GetCurrentCell(n, ids);
    if (n >= 3)
    {
      kept->InsertNextCell(n, ids);
      cellData->CopyData(model->GetCellData(), index, next++);
    }
  }
  for (vtkIdType c = index; c < cells; ++c)
  {
    cellData->CopyData(model->GetCellData(), c, next++);
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(model);
  out->SetPolys(kept);
  out->GetCellData()->ShallowCopy(cellData);
  std::fprintf(stderr,
    "warning: %s: dropped %lld of %lld polygons with fewer than 3 points (the first: polygon "
    "%lld), which are not surfaces and crash vtkPolyDataNormals\n",
    file.empty() ? "the model" : file.c_str(), static_cast<long long>(dropped),
    static_cast<long long>(polys->GetNumberOfCells()), static_cast<long long>(first));
  return out;
}

void WritePNG(vtkImageData* image, const std::string& file)
{
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputData(image);
  writer->Write();
}
} // namespace

int main(int argc, char* argv[])
{
  std::string file, out = "perceptual_lod_output", modeName = "srcc";
  bool offscreen = false;
  int frames = 90, width = 960, height = 720, level = -1, cacheLimit = -1;
  bool background = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--offscreen")
      offscreen = true;
    else if (a == "--frames" && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc)
      out = argv[++i];
    else if (a == "--level" && i + 1 < argc)
      level = std::atoi(argv[++i]);
    else if (a == "--mode" && i + 1 < argc)
      modeName = argv[++i];
    else if (a == "--cache-limit" && i + 1 < argc)
      cacheLimit = std::max(0, std::atoi(argv[++i]));
    else if (a == "--background-loading")
      background = true;
    else if (a == "--size" && i + 2 < argc)
    {
      width = std::atoi(argv[++i]);
      height = std::atoi(argv[++i]);
    }
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: %s [model] [--offscreen] [--frames N] [--out DIR] [--size W H] "
                  "[--level L] [--mode srcc|tmm|scvc|psec|distance|ipv|dpv|fovea] "
                  "[--cache-limit MiB] [--background-loading]\n",
        argv[0]);
      return 0;
    }
    else
      file = a;
  }
  // an octree file (PerceptualLODMain --save) opens without a build; its full-resolution
  // reference is the octree's finest cut, which is the input surface
  const bool octreeFile = !file.empty() && vtkMultiscaleOctreeReader::CanReadFile(file.c_str());
  vtkNew<vtkMultiscaleOctreeReader> reader;
  vtkSmartPointer<vtkPolyData> model;
  if (octreeFile)
  {
    reader->SetFileName(file.c_str());
    if (cacheLimit >= 0)
    {
      reader->SetCacheLimit(cacheLimit);
    }
    reader->SetBackgroundLoading(background);
    reader->Update();
    if (reader->GetOutput()->GetNumberOfNodes() == 0)
    {
      std::fprintf(stderr, "%s\ncannot read a model from '%s' (an octree file)\n",
        reader->GetErrorMessage(), file.c_str());
      return 1;
    }
    vtkNew<vtkMultiscaleOctreeCutter> fullCut;
    fullCut->SetInputConnection(reader->GetOutputPort());
    fullCut->SetLevel(-1);
    vtkNew<vtkMultiscalePatchGenerator> fullPatches;
    fullPatches->SetInputConnection(fullCut->GetOutputPort());
    fullPatches->Update();
    model = vtkSmartPointer<vtkPolyData>::New();
    model->DeepCopy(fullPatches->GetOutput());
  }
  else
  {
    model = file.empty() ? plodtest::MakeBlob(11, 350, 0.2) : plodtest::ReadModel(file);
  }
  if (!model)
  {
    std::fprintf(
      stderr, "cannot read a model from '%s' (PLY, STL, OBJ, VTP or .plod)\n", file.c_str());
    return 1;
  }
  // the builder skips such polygons, but the full-resolution reference's normals would not
  model = DropShortPolys(model, file);

  Viewer v;
  v.Builder->SetInputData(model);
  v.Builder->SetFinestLevel(level);
  v.Selector->SetInputConnection(octreeFile ? reader->GetOutputPort() : v.Builder->GetOutputPort());
  v.Patches->SetInputConnection(v.Selector->GetOutputPort());
  v.LODMapper->SetInputConnection(v.Patches->GetOutputPort());
  // the full-resolution reference, smooth-shaded like the LOD (whose normals are area-weighted mean
  // normals)
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(model);
  normals->SplittingOff();
  normals->Update();
  v.FullMapper->SetInputConnection(normals->GetOutputPort());
  for (vtkActor* actor : { v.LODActor.Get(), v.FullActor.Get() })
  {
    actor->GetProperty()->SetColor(0.85, 0.82, 0.75);
    actor->GetProperty()->SetSpecular(0.3);
    actor->GetProperty()->SetSpecularPower(20);
  }
  v.LODActor->SetMapper(v.LODMapper);
  v.FullActor->SetMapper(v.FullMapper);
  v.Renderer->AddActor(v.LODActor);
  v.Renderer->AddActor(v.FullActor);
  v.Renderer->SetBackground(0.1, 0.1, 0.15);
  v.Text->GetTextProperty()->SetFontSize(16);
  v.Text->SetPosition(10, 10);
  v.Renderer->AddActor2D(v.Text);
  v.Window->AddRenderer(v.Renderer);
  v.Window->SetSize(width, height);
  v.Window->SetWindowName("PerceptualLOD");
  v.Binding->SetRenderer(v.Renderer);
  v.Binding->SetSelector(v.Selector);
  v.Binding->SetProp3D(v.LODActor);
  vtkNew<vtkCallbackCommand> start, end;
  start->SetCallback(OnStart);
  start->SetClientData(&v);
  end->SetCallback(OnEnd);
  end->SetClientData(&v);
  v.Renderer->AddObserver(vtkCommand::StartEvent, start);
  v.Renderer->AddObserver(vtkCommand::EndEvent, end);
  const std::string modes[] = { "full", "srcc", "tmm", "scvc", "psec", "distance", "ipv", "dpv",
    "fovea" };
  for (int m = 0; m < 9; ++m)
    if (modeName == modes[m])
      v.SetMode(m);
  // the model's bounds: the LOD output only holds what the view draws
  double modelBounds[6];
  model->GetBounds(modelBounds);
  v.Renderer->ResetCamera(modelBounds);
  if (octreeFile)
  {
    std::printf("model: %lld triangles; octree: %lld nodes, level %d, opened from %s in %.1f ms "
                "(%s)\n",
      static_cast<long long>(model->GetNumberOfPolys()),
      static_cast<long long>(reader->GetOutput()->GetNumberOfNodes()),
      reader->GetOutput()->GetFinestLevel(), file.c_str(), reader->GetReadTime() * 1e3,
      reader->GetMapped() ? "mapped" : "read");
  }
  else
  {
    v.Builder->Update();
    std::printf("model: %lld triangles; octree: %lld nodes, level %d, built in %.0f ms\n",
      static_cast<long long>(model->GetNumberOfPolys()),
      static_cast<long long>(v.Builder->GetOutput()->GetNumberOfNodes()),
      v.Builder->GetOutput()->GetFinestLevel(), v.Builder->GetBuildTime() * 1e3);
  }

  if (!offscreen)
  {
    vtkNew<vtkRenderWindowInteractor> interactor;
    vtkNew<vtkInteractorStyleTrackballCamera> style;
    interactor->SetInteractorStyle(style);
    interactor->SetRenderWindow(v.Window);
    vtkNew<vtkCallbackCommand> key;
    key->SetCallback(OnKey);
    key->SetClientData(&v);
    interactor->AddObserver(vtkCommand::KeyPressEvent, key);
    vtkNew<vtkCallbackCommand> status;
    status->SetClientData(&v);
    status->SetCallback([](vtkObject*, unsigned long, void* c, void*) {
      auto* viewer = static_cast<Viewer*>(c);
      viewer->Text->SetInput(viewer->Status().c_str());
    });
    v.Window->AddObserver(vtkCommand::EndEvent, status);
    // background loading: render again while pages are read, so the view refines
    vtkNew<vtkCallbackCommand> refresh;
    refresh->SetClientData(&v);
    refresh->SetCallback([](vtkObject*, unsigned long, void* c, void*) {
      auto* viewer = static_cast<Viewer*>(c);
      auto* octree = vtkMultiscaleOctree::SafeDownCast(viewer->Selector->GetInputDataObject(0, 0));
      if (octree && octree->GetBackgroundLoading() &&
        (octree->GetNumberOfWaitingLoads() > 0 ||
          octree->GetNumberOfBackgroundLoads() != viewer->LoadsRendered))
      {
        viewer->LoadsRendered = octree->GetNumberOfBackgroundLoads();
        viewer->Window->Render();
      }
    });
    interactor->AddObserver(vtkCommand::TimerEvent, refresh);
    interactor->Initialize();
    if (background)
    {
      interactor->CreateRepeatingTimer(50);
    }
    v.Window->Render();
    interactor->Start();
    return 0;
  }

  // ---- scripted offscreen run -----------------------------------------------------------------
  v.Window->SetOffScreenRendering(1);
  mkdir(out.c_str(), 0755);
  std::ofstream csv(out + "/frames.csv");
  csv << "frame,phase,mode,triangles,select_ms,patch_ms,render_ms,binding_us,visited,drawn,"
         "psnr_db,full_render_ms,speedup\n";
  std::vector<double> lodTimes, fullTimes;
  vtkCamera* camera = v.Renderer->GetActiveCamera();
  const double startDistance = camera->GetDistance();
  double bounds[6];
  model->GetBounds(bounds);
  const double size =
    std::max({ bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4] });
  const int lodMode = v.Mode == 0 ? 1 : v.Mode;
  v.SetMode(lodMode);
  for (int f = 0; f < frames; ++f)
  {
    // three phases: translation, zoom, rotation
    const double t = double(f) / std::max(1, frames - 1);
    const char* phase = t < 1.0 / 3 ? "translate" : (t < 2.0 / 3 ? "zoom" : "rotate");
    if (t < 1.0 / 3)
    {
      const double x = 0.3 * size * std::sin(2 * 3.14159265 * t * 3);
      v.LODActor->SetPosition(x, 0, 0);
    }
    else if (t < 2.0 / 3)
    {
      const double s = (t - 1.0 / 3) * 3;
      camera->SetPosition(camera->GetFocalPoint()[0], camera->GetFocalPoint()[1],
        camera->GetFocalPoint()[2] + startDistance * (1.0 - 0.35 * s));
      v.Renderer->ResetCameraClippingRange(modelBounds);
    }
    else
    {
      v.LODActor->RotateY(3.0);
    }
    v.FullActor->SetUserMatrix(nullptr);
    v.FullActor->SetPosition(v.LODActor->GetPosition());
    v.FullActor->SetOrientation(v.LODActor->GetOrientation());
    // LOD frame
    v.SetMode(lodMode);
    v.Text->SetInput("");
    v.Window->Render();
    auto lod = Grab(v.Window);
    const double renderMs = v.RenderTime * 1e3;
    const vtkIdType triangles = v.Triangles();
    // full resolution at the same instant, for the PSNR
    v.SetMode(0);
    v.Window->Render();
    auto full = Grab(v.Window);
    const double fullMs = v.RenderTime * 1e3; // the whole full-resolution frame
    const double psnr = PSNR(full, lod);
    lodTimes.push_back(renderMs);
    fullTimes.push_back(fullMs);
    v.SetMode(lodMode);
    csv << f << "," << phase << "," << ModeNames[lodMode] << "," << triangles << ","
        << v.Selector->GetSelectTime() * 1e3 << "," << v.Patches->GetGenerateTime() * 1e3 << ","
        << renderMs << "," << v.Binding->GetLastUpdateTime() * 1e6 << ","
        << v.Selector->GetNumberOfVisitedNodes() << "," << v.Selector->GetNumberOfDrawnNodes()
        << "," << psnr << "," << fullMs << "," << (renderMs > 0 ? fullMs / renderMs : 0.0) << "\n";
    char name[64];
    if (f % 10 == 0)
    {
      std::snprintf(name, sizeof(name), "/frame_%04d.png", f);
      WritePNG(lod, out + name);
    }
    if (f == frames / 6 || f == frames / 2 || f == (5 * frames) / 6)
    {
      vtkNew<vtkImageAppend> side;
      side->SetAppendAxis(0);
      side->AddInputData(full);
      side->AddInputData(lod);
      side->Update();
      std::snprintf(name, sizeof(name), "/compare_%s.png", phase);
      WritePNG(side->GetOutput(), out + name);
    }
    std::printf("frame %3d %-9s %8lld triangles  select %6.2f ms  patch %6.2f ms  render %7.1f ms"
                "  PSNR %5.2f dB  full resolution %7.1f ms\n",
      f, phase, static_cast<long long>(triangles), v.Selector->GetSelectTime() * 1e3,
      v.Patches->GetGenerateTime() * 1e3, renderMs, psnr, fullMs);
  }
  auto median = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x.empty() ? 0.0 : x[x.size() / 2];
  };
  if (!lodTimes.empty())
  {
    // the LOD frame (select + patch + render) against the full-resolution frame, same views
    std::printf("frame time, medians: LOD %.1f ms, full resolution %.1f ms (%.1fx faster)\n",
      median(lodTimes), median(fullTimes),
      median(lodTimes) > 0 ? median(fullTimes) / median(lodTimes) : 0.0);
  }
  if (octreeFile && reader->GetMapped())
  {
    vtkMultiscaleOctree* octree = reader->GetOutput();
    std::printf("mapped octree: cache limit %d MiB, %.1f MiB resident at the end, dropped %lld "
                "times\n",
      reader->GetCacheLimit(), double(octree->GetMappedResidentBytes()) / 1048576.0,
      static_cast<long long>(octree->GetNumberOfResidentReleases()));
    if (octree->GetBackgroundLoading())
    {
      std::printf("background loading: %lld refinements read by the thread, %lld waiting\n",
        static_cast<long long>(octree->GetNumberOfBackgroundLoads()),
        static_cast<long long>(octree->GetNumberOfWaitingLoads()));
    }
  }
  std::printf("wrote %s/frames.csv and PNG frames\n", out.c_str());
  return 0;
}
