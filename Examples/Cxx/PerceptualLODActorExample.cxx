// SPDX-License-Identifier: BSD-3-Clause
// The perceptual LOD as one actor. Usage:
//
//   PerceptualLODActorExample [model.ply | octree.plod] [--offscreen]
//
// vtkPerceptualLODActor holds the builder, the selector, the patch generator and the mapper,
// and reads the camera and lights of the renderer it is drawn in: nothing else to wire.
#include "vtkCamera.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPLYFileCheck.h"
#include "vtkPLYReader.h"
#include "vtkPerceptualLODActor.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSphereSource.h"

#include <cstdio>
#include <cstring>
#include <string>

#include <sys/stat.h>

int main(int argc, char* argv[])
{
  std::string file;
  bool offscreen = false;
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], "--offscreen") == 0)
      offscreen = true;
    else
      file = argv[i];
  }
  vtkNew<vtkPerceptualLODActor> actor;
  vtkNew<vtkMultiscaleOctreeReader> octreeFile;
  vtkNew<vtkPLYReader> ply;
  vtkNew<vtkSphereSource> sphere;
  struct stat st;
  if (!file.empty() && (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)))
  {
    // checked before any reader opens it: a FIFO would make it wait forever
    std::fprintf(stderr,
      "cannot read '%s': missing, or not a regular file (a directory, a FIFO "
      "or a device)\n",
      file.c_str());
    return 1;
  }
  vtkNew<vtkPLYFileCheck> check; // VTK's PLY reader crashes on some damaged files
  if (!file.empty() && vtkMultiscaleOctreeReader::CanReadFile(file.c_str()))
  {
    octreeFile->SetFileName(file.c_str()); // a saved octree: nothing to build
    actor->SetInputConnection(octreeFile->GetOutputPort());
  }
  else if (!file.empty())
  {
    check->SetFileName(file.c_str());
    if (!check->Check())
    {
      std::fprintf(stderr, "cannot read '%s': %s\n", file.c_str(), check->GetErrorMessage());
      return 1;
    }
    ply->SetFileName(file.c_str());
    actor->SetInputConnection(ply->GetOutputPort());
  }
  else
  {
    sphere->SetThetaResolution(300);
    sphere->SetPhiResolution(300);
    actor->SetInputConnection(sphere->GetOutputPort());
  }
  actor->GetProperty()->SetSpecular(0.3);
  actor->GetProperty()->SetSpecularPower(20);

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->ResetCamera(); // the actor's bounds are the whole model's
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetSize(640, 480);
  if (offscreen)
  {
    window->SetOffScreenRendering(1);
    for (int frame = 0; frame < 30; ++frame)
    {
      renderer->GetActiveCamera()->Azimuth(6);
      renderer->ResetCameraClippingRange();
      window->Render();
      std::printf("frame %2d: %lld triangles (select %.2f ms)\n", frame,
        static_cast<long long>(actor->GetPatchGenerator()->GetNumberOfTriangles()),
        actor->GetSelector()->GetSelectTime() * 1e3);
    }
    return actor->GetPatchGenerator()->GetNumberOfTriangles() > 0 ? 0 : 1;
  }
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(window);
  window->Render();
  interactor->Start();
  return 0;
}
