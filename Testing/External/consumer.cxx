// SPDX-License-Identifier: BSD-3-Clause
// An external program using the installed PerceptualLOD: builds an octree, saves and opens it,
// and draws it offscreen with vtkPerceptualLODActor.
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODActor.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSphereSource.h"

#include <cstdio>
#include <string>

int main(int argc, char* argv[])
{
  const std::string path = argc > 1 ? argv[1] : "consumer.plod";
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(120);
  sphere->SetPhiResolution(120);
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputConnection(sphere->GetOutputPort());
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->SetInputConnection(builder->GetOutputPort());
  writer->SetFileName(path.c_str());
  if (!writer->Write())
  {
    std::fprintf(stderr, "write failed: %s\n", writer->GetErrorMessage());
    return 1;
  }
  vtkNew<vtkMultiscaleOctreeReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkPerceptualLODActor> actor;
  actor->SetInputConnection(reader->GetOutputPort());
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(320, 240);
  window->AddRenderer(renderer);
  window->Render();
  const long long drawn = actor->GetPatchGenerator()->GetNumberOfTriangles();
  std::printf("consumer: octree of %lld nodes, %lld triangles drawn\n",
    static_cast<long long>(reader->GetOutput()->GetNumberOfNodes()), drawn);
  return drawn > 0 ? 0 : 1;
}
