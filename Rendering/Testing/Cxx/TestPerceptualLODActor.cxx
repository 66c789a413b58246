// SPDX-License-Identifier: BSD-3-Clause
// vtkPerceptualLODActor: ResetCamera() fits the whole model (mesh, cloud, octree, moved actor);
// the image is the three-filter pipeline's with a binding, pixel for pixel; an octree input
// skips the build; two renderers each get their own cut; a foreign mapper is refused; a
// deleted renderer takes its binding away; while pages are read in the background, the actor
// asks the interactor for renders until the cut is whole.
#include "plodPageLoader.h"
#include "plodTestUtilities.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkMultiscaleOctreeWriter.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPerceptualLODActor.h"
#include "vtkPerceptualLODMapper.h"
#include "vtkPerceptualLODRenderBinding.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWeakPointer.h"
#include "vtkWindowToImageFilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
struct Scene
{
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderer> Renderer;
  explicit Scene(int w = 320, int h = 240)
  {
    this->Window->SetOffScreenRendering(1);
    this->Window->SetSize(w, h);
    this->Window->AddRenderer(this->Renderer);
    this->Renderer->SetBackground(0, 0, 0);
  }
  std::vector<unsigned char> Image()
  {
    this->Window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(this->Window);
    grab->ReadFrontBufferOff();
    grab->Update();
    auto* px = vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
    return std::vector<unsigned char>(
      px->GetPointer(0), px->GetPointer(0) + px->GetNumberOfValues());
  }
};

/// The same camera to float precision (the octree keeps its points in single precision).
void ExpectSameCamera(vtkCamera* a, vtkCamera* b, double scale)
{
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_NEAR(a->GetPosition()[k], b->GetPosition()[k], 1e-6 * scale);
    EXPECT_NEAR(a->GetFocalPoint()[k], b->GetFocalPoint()[k], 1e-6 * scale);
  }
}

double Size(const double b[6])
{
  return std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
}

/// An interactor whose timers never fire by themselves: it records the one-shot timers asked
/// of it, and the test fires them (TimerEvent with the timer's id, as a platform's loop does).
class RecordingInteractor : public vtkRenderWindowInteractor
{
public:
  static RecordingInteractor* New();
  vtkTypeMacro(RecordingInteractor, vtkRenderWindowInteractor);
  std::vector<int> OneShots;

protected:
  int InternalCreateTimer(int timerId, int timerType, unsigned long) override
  {
    if (timerType == vtkRenderWindowInteractor::OneShotTimer)
      this->OneShots.push_back(timerId);
    return timerId;
  }
  int InternalDestroyTimer(int) override { return 1; }
};
vtkStandardNewMacro(RecordingInteractor);

/// Builds the octree of `mesh` and saves it as `path`.
bool SaveOctree(vtkPolyData* mesh, const std::string& path)
{
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(mesh);
  vtkNew<vtkMultiscaleOctreeWriter> writer;
  writer->SetInputConnection(builder->GetOutputPort());
  writer->SetFileName(path.c_str());
  return writer->Write() == 1;
}

int Lit(const std::vector<unsigned char>& image)
{
  int n = 0;
  for (size_t i = 0; i + 2 < image.size(); i += 3)
    n += (image[i] | image[i + 1] | image[i + 2]) ? 1 : 0;
  return n;
}
}

TEST(PerceptualLODActor, ResetCameraFitsTheWholeModel)
{
  auto blob = plodtest::MakeBlob(3, 60, 0.3);
  double model[6];
  blob->GetBounds(model);
  for (int moved = 0; moved < 2; ++moved)
  {
    Scene withActor, reference;
    vtkNew<vtkPerceptualLODActor> actor;
    actor->SetInputData(blob);
    if (moved)
    {
      actor->SetOrientation(20, 35, 0);
      actor->SetPosition(3, -1, 2);
    }
    withActor.Renderer->AddActor(actor);
    // close up, the cut draws part of the model: the actor's bounds must still be the model's
    withActor.Renderer->ResetCamera();
    withActor.Window->Render();
    withActor.Renderer->GetActiveCamera()->Dolly(3.0);
    withActor.Window->Render();
    withActor.Renderer->ResetCamera();
    // the reference: the model's bounds through the same matrix, by a plain actor
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(blob);
    vtkNew<vtkActor> plain;
    plain->SetMapper(mapper);
    plain->SetUserMatrix(actor->GetMatrix());
    reference.Renderer->AddActor(plain);
    reference.Renderer->ResetCamera(plain->GetBounds());
    ExpectSameCamera(
      withActor.Renderer->GetActiveCamera(), reference.Renderer->GetActiveCamera(), Size(model));
    double b[6];
    actor->GetBounds(b);
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(b[k], plain->GetBounds()[k], 1e-6 * Size(model)) << moved << " " << k;
  }
}

TEST(PerceptualLODActor, ImageIsTheThreeFilterPipelines)
{
  auto blob = plodtest::MakeBlob(4, 80, 0.3);
  // the actor
  Scene a;
  vtkNew<vtkPerceptualLODActor> actor;
  actor->SetInputData(blob);
  actor->GetProperty()->SetSpecular(0.3);
  actor->GetProperty()->SetSpecularPower(20);
  a.Renderer->AddActor(actor);
  a.Renderer->ResetCamera();
  a.Renderer->GetActiveCamera()->Azimuth(30);
  a.Renderer->GetActiveCamera()->Dolly(1.4);
  a.Renderer->ResetCameraClippingRange();
  // builder -> selector -> patches -> mapper, with a binding
  Scene b;
  vtkNew<vtkMultiscaleOctreeBuilder> builder;
  builder->SetInputData(blob);
  vtkNew<vtkPerceptualLODSelector> selector;
  selector->SetInputConnection(builder->GetOutputPort());
  vtkNew<vtkMultiscalePatchGenerator> patches;
  patches->SetInputConnection(selector->GetOutputPort());
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(patches->GetOutputPort());
  vtkNew<vtkActor> plain;
  plain->SetMapper(mapper);
  plain->GetProperty()->SetSpecular(0.3);
  plain->GetProperty()->SetSpecularPower(20);
  b.Renderer->AddActor(plain);
  b.Renderer->SetActiveCamera(a.Renderer->GetActiveCamera());
  vtkNew<vtkPerceptualLODRenderBinding> binding;
  binding->SetRenderer(b.Renderer);
  binding->SetSelector(selector);
  binding->SetProp3D(plain);
  const auto imageA = a.Image();
  const auto imageB = b.Image();
  ASSERT_EQ(imageA.size(), imageB.size());
  EXPECT_GT(Lit(imageA), 2000);
  EXPECT_EQ(actor->GetPatchGenerator()->GetNumberOfTriangles(), patches->GetNumberOfTriangles());
  EXPECT_LT(actor->GetPatchGenerator()->GetNumberOfTriangles(), blob->GetNumberOfPolys());
  int differ = 0;
  for (size_t i = 0; i < imageA.size(); ++i)
    differ += imageA[i] != imageB[i] ? 1 : 0;
  EXPECT_EQ(differ, 0) << "bytes that differ";
}

TEST(PerceptualLODActor, OctreeInputSkipsTheBuildAndDrawsTheSame)
{
  auto blob = plodtest::MakeBlob(5, 50, 0.3);
  const std::string path = "/tmp/plod_actor_" + std::to_string(::getpid()) + ".plod";
  ASSERT_TRUE(SaveOctree(blob, path));
  vtkNew<vtkMultiscaleOctreeReader> reader;
  reader->SetFileName(path.c_str());

  Scene fromFile, fromMesh;
  vtkNew<vtkPerceptualLODActor> a1, a2;
  a1->SetInputConnection(reader->GetOutputPort());
  a2->SetInputData(blob);
  EXPECT_TRUE(a1->GetInputIsOctree());
  EXPECT_FALSE(a2->GetInputIsOctree());
  fromFile.Renderer->AddActor(a1);
  fromMesh.Renderer->AddActor(a2);
  fromFile.Renderer->ResetCamera();
  fromMesh.Renderer->ResetCamera();
  const auto i1 = fromFile.Image();
  const auto i2 = fromMesh.Image();
  EXPECT_EQ(a1->GetBuilder()->GetOutput()->GetNumberOfNodes(), 0) << "nothing built";
  EXPECT_EQ(a1->GetPatchGenerator()->GetNumberOfTriangles(),
    a2->GetPatchGenerator()->GetNumberOfTriangles());
  EXPECT_EQ(i1, i2);
  std::remove(path.c_str());
}

TEST(PerceptualLODActor, RendersAgainWhilePagesAreRead)
{
  // A mapped octree read in the background: after a render that leaves cells awaiting their
  // pages, the actor asks the window's interactor for one more render (one timer at a time);
  // each such render refines further, until the actor's cut is a plain reader's.
  const std::string path = "/tmp/plod_actor_bg_" + std::to_string(::getpid()) + ".plod";
  ASSERT_TRUE(SaveOctree(plodtest::MakeBlob(5, 80, 0.3), path));
  vtkNew<vtkMultiscaleOctreeReader> plainReader, reader;
  plainReader->SetFileName(path.c_str());
  reader->SetFileName(path.c_str());
  reader->SetBackgroundLoading(true);

  Scene plain, streamed;
  vtkNew<vtkPerceptualLODActor> plainActor, actor;
  plainActor->SetInputConnection(plainReader->GetOutputPort());
  actor->SetInputConnection(reader->GetOutputPort());
  plain.Renderer->AddActor(plainActor);
  streamed.Renderer->AddActor(actor);
  vtkNew<RecordingInteractor> interactor;
  interactor->SetRenderWindow(streamed.Window);
  plain.Renderer->ResetCamera();
  streamed.Renderer->ResetCamera();
  streamed.Window->Render(); // the first view: read whole, nothing waits
  EXPECT_TRUE(interactor->OneShots.empty());
  plod::PageLoader* loader = reader->GetOutput()->GetPageLoader();
  ASSERT_NE(loader, nullptr);
  loader->SetPaused(true);
  for (Scene* s : { &plain, &streamed })
    s->Renderer->GetActiveCamera()->Dolly(4.0);
  streamed.Renderer->ResetCameraClippingRange();
  plain.Renderer->ResetCameraClippingRange();
  streamed.Window->Render();
  EXPECT_GT(reader->GetOutput()->GetNumberOfWaitingLoads(), 0);
  ASSERT_EQ(interactor->OneShots.size(), 1u);
  streamed.Window->Render(); // its timer has not fired: no second one
  EXPECT_EQ(interactor->OneShots.size(), 1u);
  plain.Window->Render();
  EXPECT_LT(actor->GetPatchGenerator()->GetNumberOfTriangles(),
    plainActor->GetPatchGenerator()->GetNumberOfTriangles());
  loader->SetPaused(false);
  size_t fired = 0;
  for (; fired < interactor->OneShots.size() && fired < 50; ++fired)
  {
    reader->GetOutput()->WaitForLoads();
    int id = interactor->OneShots[fired];
    interactor->InvokeEvent(vtkCommand::TimerEvent, &id); // renders the window
  }
  EXPECT_GT(fired, 1u);
  EXPECT_EQ(fired, interactor->OneShots.size()) << "the renders asked for stop";
  EXPECT_EQ(reader->GetOutput()->GetNumberOfWaitingLoads(), 0);
  EXPECT_TRUE(plodtest::SameDrawing(
    actor->GetPatchGenerator()->GetOutput(), plainActor->GetPatchGenerator()->GetOutput()));
  // another timer's event is not the actor's
  int other = 12345;
  interactor->InvokeEvent(vtkCommand::TimerEvent, &other);
  EXPECT_EQ(interactor->OneShots.size(), fired);
  std::remove(path.c_str());
}

TEST(PerceptualLODActor, TwoRenderersEachGetTheirOwnCut)
{
  auto blob = plodtest::MakeBlob(6, 80, 0.3);
  vtkNew<vtkPerceptualLODActor> actor;
  actor->SetInputData(blob);
  // alone: near and far
  std::vector<vtkIdType> alone;
  std::vector<std::vector<unsigned char>> aloneImages;
  for (double dolly : { 2.5, 0.3 })
  {
    Scene s(160, 120);
    s.Renderer->AddActor(actor);
    s.Renderer->ResetCamera();
    s.Renderer->GetActiveCamera()->Dolly(dolly);
    s.Renderer->ResetCameraClippingRange();
    aloneImages.push_back(s.Image());
    alone.push_back(actor->GetPatchGenerator()->GetNumberOfTriangles());
    s.Renderer->RemoveActor(actor);
  }
  EXPECT_GT(alone[0], alone[1]) << "near draws more than far";
  // together, side by side in one window
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(320, 120);
  vtkNew<vtkRenderer> left, right;
  left->SetViewport(0, 0, 0.5, 1);
  right->SetViewport(0.5, 0, 1, 1);
  for (vtkRenderer* r : { left.Get(), right.Get() })
  {
    window->AddRenderer(r);
    r->AddActor(actor);
    r->ResetCamera();
  }
  left->GetActiveCamera()->Dolly(2.5);
  right->GetActiveCamera()->Dolly(0.3);
  left->ResetCameraClippingRange();
  right->ResetCameraClippingRange();
  window->Render();
  window->Render();
  EXPECT_EQ(actor->GetPatchGenerator()->GetNumberOfTriangles(), alone[1]) << "the last one drawn";
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto* px = vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
  // each half is the image its camera gave alone
  for (int half = 0; half < 2; ++half)
  {
    int differ = 0;
    for (int y = 0; y < 120; ++y)
      for (int x = 0; x < 160; ++x)
        for (int c = 0; c < 3; ++c)
          differ += px->GetValue(3 * (y * 320 + x + 160 * half) + c) !=
              aloneImages[half][3 * (y * 160 + x) + c]
            ? 1
            : 0;
    EXPECT_EQ(differ, 0) << "half " << half;
  }
}

TEST(PerceptualLODActor, ForeignMapperIsRefusedAndEmptyInputDrawsNothing)
{
  vtkNew<vtkPerceptualLODActor> actor;
  vtkNew<plodtest::ErrorRecorder> messages;
  actor->AddObserver(vtkCommand::WarningEvent, messages);
  vtkMapper* own = actor->GetMapper();
  vtkNew<vtkPolyDataMapper> other;
  actor->SetMapper(other);
  EXPECT_EQ(actor->GetMapper(), own);
  ASSERT_FALSE(messages->Warnings.empty());
  EXPECT_NE(messages->Warnings[0].find("SetMapper is ignored"), std::string::npos);
  Scene s;
  s.Renderer->AddActor(actor); // no input
  s.Renderer->ResetCamera();
  EXPECT_EQ(Lit(s.Image()), 0);
  double b[6];
  actor->GetBounds(b);
  EXPECT_FALSE(b[0] <= b[1]) << "uninitialized bounds";
}

TEST(PerceptualLODActor, ADeletedRendererTakesItsBindingAway)
{
  // issue 24: each renderer the actor drew in stayed in its binding table after the renderer was
  // gone. The binding (a renderer's motion history) now goes with its renderer, and the actor
  // never keeps a renderer alive.
  auto blob = plodtest::MakeBlob(5, 40, 0.3);
  vtkNew<vtkPerceptualLODActor> actor;
  actor->SetInputData(blob);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(160, 120);
  EXPECT_EQ(actor->GetNumberOfBindings(), 0);
  vtkNew<vtkRenderer> kept; // drawn in and alive to the end: its binding stays
  window->AddRenderer(kept);
  kept->AddActor(actor);
  kept->ResetCamera();
  kept->SetViewport(0, 0, 0.5, 1);
  for (int i = 0; i < 3; ++i)
  {
    auto renderer = vtkSmartPointer<vtkRenderer>::New();
    renderer->SetViewport(0.5, 0, 1, 1);
    window->AddRenderer(renderer);
    renderer->AddActor(actor);
    renderer->ResetCamera();
    window->Render();
    EXPECT_EQ(actor->GetNumberOfBindings(), 2) << "one per renderer drawn in";
    EXPECT_NE(actor->GetBinding(renderer), nullptr);
    vtkWeakPointer<vtkRenderer> weak = renderer.Get();
    window->RemoveRenderer(renderer);
    renderer->RemoveActor(actor);
    renderer = nullptr; // the last reference
    EXPECT_EQ(weak.Get(), nullptr) << "the actor does not keep the renderer alive";
    EXPECT_EQ(actor->GetNumberOfBindings(), 1) << "the deleted renderer's binding went with it";
  }
  EXPECT_NE(actor->GetBinding(kept), nullptr);
  window->Render();
  EXPECT_EQ(actor->GetNumberOfBindings(), 1);
  EXPECT_GT(actor->GetPatchGenerator()->GetNumberOfTriangles(), 0) << "it still draws";

  // MakeBinding without a render is dropped the same way
  {
    vtkNew<vtkRenderer> unused;
    EXPECT_NE(actor->MakeBinding(unused), nullptr);
    EXPECT_EQ(actor->GetNumberOfBindings(), 2);
  }
  EXPECT_EQ(actor->GetNumberOfBindings(), 1);

  // an actor deleted before its renderer takes its observer away: the renderer's deletion
  // later calls into nothing that is gone
  vtkNew<vtkRenderer> outliving;
  {
    vtkNew<vtkPerceptualLODActor> brief;
    brief->SetInputData(blob);
    EXPECT_NE(brief->MakeBinding(outliving), nullptr);
    EXPECT_TRUE(outliving->HasObserver(vtkCommand::DeleteEvent));
  }
  EXPECT_FALSE(outliving->HasObserver(vtkCommand::DeleteEvent));
}

namespace
{
/// A triangulated sphere with every other triangle's orientation reversed (a closed mesh whose
/// triangles disagree on which side is the front, as scans often arrive).
vtkSmartPointer<vtkPolyData> FlippedSphere(bool flip)
{
  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(48);
  source->SetPhiResolution(48);
  source->Update();
  auto sphere = vtkSmartPointer<vtkPolyData>::New();
  sphere->DeepCopy(source->GetOutput());
  sphere->GetPointData()->SetNormals(nullptr); // the normals must come from the triangles
  vtkNew<vtkCellArray> polys;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  vtkCellArray* input = sphere->GetPolys();
  input->InitTraversal();
  for (vtkIdType k = 0; input->GetNextCell(n, ids); ++k)
  {
    if (flip && k % 2 == 1 && n == 3)
      polys->InsertNextCell({ ids[2], ids[1], ids[0] });
    else
      polys->InsertNextCell(n, ids);
  }
  sphere->SetPolys(polys);
  return sphere;
}

/// Pixels covered by `sphere` (those not of the background's colour), drawn by an actor seen
/// from a fixed camera with the selector's back-face mode `mode`; whether it hid back faces.
int CoveredPixelsOf(vtkPolyData* sphere, int mode, bool* hid, plodtest::ErrorRecorder* warnings)
{
  Scene s;
  vtkNew<vtkPerceptualLODActor> actor;
  actor->SetInputData(sphere);
  actor->GetBuilder()->AddObserver(vtkCommand::WarningEvent, warnings);
  if (mode >= 0)
    actor->GetSelector()->SetBackFaceMode(mode);
  s.Renderer->AddActor(actor);
  s.Renderer->SetBackground(0.1, 0.6, 0.9); // a colour no shading of the sphere takes
  s.Renderer->ResetCamera();
  s.Renderer->GetActiveCamera()->Azimuth(20);
  s.Renderer->GetActiveCamera()->Elevation(15);
  s.Renderer->ResetCameraClippingRange();
  const std::vector<unsigned char> image = s.Image();
  int covered = 0;
  for (size_t i = 0; i + 2 < image.size(); i += 3)
    covered += (image[i] != image[0] || image[i + 1] != image[1] || image[i + 2] != image[2]);
  *hid = actor->GetSelector()->GetHidBackFaces();
  return covered;
}
}

TEST(PerceptualLODActor, InconsistentlyOrientedClosedMeshHasNoSeeThroughHoles)
{
  vtkNew<plodtest::ErrorRecorder> warnings;
  bool hid = true;
  // the flipped sphere: the builder notices, and back faces are drawn
  const auto flipped = FlippedSphere(true);
  const int automatic =
    CoveredPixelsOf(flipped, vtkPerceptualLODSelector::BACK_FACES_AUTOMATIC, &hid, warnings);
  EXPECT_FALSE(hid) << "back faces hidden on an inconsistently oriented mesh";
  bool warned = false;
  for (const std::string& w : warnings->Warnings)
    warned = warned || w.find("not consistently oriented") != std::string::npos;
  EXPECT_TRUE(warned) << "no warning about the orientation";
  const int drawn =
    CoveredPixelsOf(flipped, vtkPerceptualLODSelector::BACK_FACES_DRAWN, &hid, warnings);
  EXPECT_GT(drawn, 5000);
  EXPECT_EQ(automatic, drawn) << "see-through holes: pixels missing against back faces drawn";
  // hiding them would have opened holes (the case the automatic rule avoids)
  const int hidden =
    CoveredPixelsOf(flipped, vtkPerceptualLODSelector::BACK_FACES_HIDDEN, &hid, warnings);
  EXPECT_LT(hidden, drawn);
  // the consistent sphere still hides its back faces, with no warning
  vtkNew<plodtest::ErrorRecorder> quiet;
  CoveredPixelsOf(
    FlippedSphere(false), vtkPerceptualLODSelector::BACK_FACES_AUTOMATIC, &hid, quiet);
  EXPECT_TRUE(hid);
  EXPECT_TRUE(quiet->Warnings.empty()) << quiet->Warnings.front();
}

// The GPU draw path: the same picture as the CPU path (folds kept on both, the GPU path's rule),
// the surface sent once and then only the cut's changes; where the context lacks a feature, the
// CPU path with one warning naming it.
TEST(PerceptualLODActor, GPUPathDrawsTheCPUPathsPicture)
{
  auto blob = plodtest::MakeBlob(4, 90, 0.3);
  auto image = [&blob](int path, const char* missing, int* drawnTriangles,
                 plodtest::ErrorRecorder* warnings, bool* onGPU) {
    Scene s;
    vtkNew<vtkPerceptualLODActor> actor;
    actor->SetInputData(blob);
    actor->GetPatchGenerator()->SetFoldHandling(vtkMultiscalePatchGenerator::FOLDS_KEEP);
    actor->SetDrawPath(path);
    if (missing)
      actor->GetGPUMapper()->SetSimulatedMissingFeature(missing);
    if (warnings)
      actor->AddObserver(vtkCommand::WarningEvent, warnings);
    s.Renderer->AddActor(actor);
    s.Renderer->ResetCamera();
    s.Renderer->GetActiveCamera()->Azimuth(40);
    s.Renderer->GetActiveCamera()->Dolly(1.6);
    s.Renderer->ResetCameraClippingRange();
    const auto pixels = s.Image();
    *drawnTriangles = path == vtkPerceptualLODActor::DRAW_PATH_GPU && !missing
      ? static_cast<int>(actor->GetGPUMapper()->GetNumberOfDrawnTriangles())
      : static_cast<int>(actor->GetPatchGenerator()->GetNumberOfTriangles());
    *onGPU = actor->GetDrewOnGPU();
    return pixels;
  };
  int cpuTriangles = 0, gpuTriangles = 0, fallbackTriangles = 0;
  bool onGPU = false;
  const auto cpu =
    image(vtkPerceptualLODActor::DRAW_PATH_CPU, nullptr, &cpuTriangles, nullptr, &onGPU);
  EXPECT_FALSE(onGPU);
  const auto gpu =
    image(vtkPerceptualLODActor::DRAW_PATH_GPU, nullptr, &gpuTriangles, nullptr, &onGPU);
  EXPECT_TRUE(onGPU);
  ASSERT_EQ(cpu.size(), gpu.size());
  EXPECT_GT(Lit(cpu), 2000);
  // the GPU path sends the triangles the patch generator culls as back faces (OpenGL culls them)
  EXPECT_GE(gpuTriangles, cpuTriangles);
  int differ = 0;
  for (size_t i = 0; i + 2 < cpu.size(); i += 3)
    differ += (std::abs(cpu[i] - gpu[i]) > 8 || std::abs(cpu[i + 1] - gpu[i + 1]) > 8 ||
                std::abs(cpu[i + 2] - gpu[i + 2]) > 8)
      ? 1
      : 0;
  EXPECT_LE(differ, Lit(cpu) / 200 + 5) << "pixels that differ between the two paths";
  // a context without a needed feature: the CPU path, and one warning naming the feature
  vtkNew<plodtest::ErrorRecorder> warnings;
  const auto fallback = image(vtkPerceptualLODActor::DRAW_PATH_GPU, "glMultiDrawElements",
    &fallbackTriangles, warnings, &onGPU);
  EXPECT_FALSE(onGPU);
  ASSERT_EQ(warnings->Warnings.size(), 1u);
  EXPECT_NE(warnings->Warnings[0].find("needs glMultiDrawElements"), std::string::npos)
    << warnings->Warnings[0];
  EXPECT_EQ(fallback, cpu) << "the fallback is the CPU path";
  EXPECT_EQ(fallbackTriangles, cpuTriangles);
}

// The default draw path: the GPU path on a hardware renderer, the CPU path on a software
// rasterizer and, without a warning, where the context lacks a feature the GPU path needs;
// either way the picture of the CPU path with the patch generator's fold rule.
TEST(PerceptualLODActor, AutomaticDrawPathChoosesByRenderer)
{
  auto blob = plodtest::MakeBlob(4, 90, 0.3);
  struct Drawn
  {
    std::vector<unsigned char> Pixels;
    bool OnGPU = false;
    size_t Warnings = 0;
    std::string Renderer;
    bool Software = false;
    int Folds = -1;
  };
  auto draw = [&blob](int path, const char* renderer, const char* missing, int folds = -1) {
    Scene s;
    vtkNew<vtkPerceptualLODActor> actor;
    actor->SetInputData(blob);
    if (folds >= 0)
      actor->GetPatchGenerator()->SetFoldHandling(folds);
    if (path >= 0)
      actor->SetDrawPath(path);
    if (renderer)
      actor->GetGPUMapper()->SetSimulatedRendererName(renderer);
    if (missing)
      actor->GetGPUMapper()->SetSimulatedMissingFeature(missing);
    vtkNew<plodtest::ErrorRecorder> warnings;
    actor->AddObserver(vtkCommand::WarningEvent, warnings);
    s.Renderer->AddActor(actor);
    s.Renderer->ResetCamera();
    s.Renderer->GetActiveCamera()->Azimuth(40);
    s.Renderer->GetActiveCamera()->Dolly(1.6);
    s.Renderer->ResetCameraClippingRange();
    Drawn d;
    d.Pixels = s.Image();
    d.OnGPU = actor->GetDrewOnGPU();
    d.Warnings = warnings->Warnings.size();
    d.Software = actor->GetGPUMapper()->IsSoftwareRenderer(s.Window);
    d.Folds = actor->GetGPUMapper()->GetFoldHandling();
    d.Renderer = actor->GetGPUMapper()->GetRendererName();
    return d;
  };
  vtkNew<vtkPerceptualLODActor> fresh;
  EXPECT_EQ(fresh->GetDrawPath(), vtkPerceptualLODActor::DRAW_PATH_AUTOMATIC);
  const Drawn cpu = draw(vtkPerceptualLODActor::DRAW_PATH_CPU, nullptr, nullptr);
  EXPECT_FALSE(cpu.OnGPU);
  EXPECT_GT(Lit(cpu.Pixels), 2000);
  // this machine's renderer, as it is
  const Drawn automatic = draw(-1, nullptr, nullptr);
  std::printf("renderer: %s\n", automatic.Renderer.c_str());
  EXPECT_FALSE(automatic.Renderer.empty());
  EXPECT_EQ(automatic.OnGPU, !automatic.Software) << automatic.Renderer;
  EXPECT_EQ(automatic.Warnings, 0u);
  // a hardware renderer's name: the GPU path, with the CPU path's picture (folds reversed)
  const Drawn hardware = draw(-1, "NVIDIA H100 PCIe/PCIe/SSE2", nullptr);
  EXPECT_TRUE(hardware.OnGPU);
  int differ = 0;
  for (size_t i = 0; i + 2 < cpu.Pixels.size(); i += 3)
    for (int k = 0; k < 3; ++k)
      if (std::abs(cpu.Pixels[i + k] - hardware.Pixels[i + k]) > 8)
      {
        ++differ;
        break;
      }
  EXPECT_LE(differ, Lit(cpu.Pixels) / 200 + 5) << "pixels that differ from the CPU path";
  // the GPU path follows the patch generator's fold rule (the mapper's test shows that the
  // two paths then draw the same picture)
  const Drawn hardwareDrop =
    draw(-1, "NVIDIA H100 PCIe/PCIe/SSE2", nullptr, vtkMultiscalePatchGenerator::FOLDS_DROP);
  EXPECT_TRUE(hardwareDrop.OnGPU);
  EXPECT_EQ(hardwareDrop.Folds, vtkMultiscalePatchGenerator::FOLDS_DROP);
  // software rasterizers' names: the CPU path
  for (const char* name : { "llvmpipe (LLVM 15.0.6, 256 bits)", "softpipe", "SwiftShader Device",
         "Microsoft Basic Render Driver", "GDI Generic" })
  {
    const Drawn soft = draw(-1, name, nullptr);
    EXPECT_FALSE(soft.OnGPU) << name;
    EXPECT_EQ(soft.Pixels, cpu.Pixels) << name;
  }
  // a missing feature: the CPU path, without a warning (the GPU path asked for warns)
  const Drawn lacking = draw(-1, "NVIDIA H100 PCIe/PCIe/SSE2", "glMultiDrawElements");
  EXPECT_FALSE(lacking.OnGPU);
  EXPECT_EQ(lacking.Warnings, 0u);
  EXPECT_EQ(lacking.Pixels, cpu.Pixels);
}
