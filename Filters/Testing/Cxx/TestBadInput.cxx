// SPDX-License-Identifier: BSD-3-Clause
// The bad-input suite (issue 10): one case per class of failure found when the project was tried
// with 180 bad inputs. Each runs the whole pipeline (builder -> selector -> patch generator) and
// asserts a clear error or warning, a valid (possibly empty) output, and no crash or hang (CTest's
// timeout catches a hang; each case takes well under a second).
#include "plodTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkMultiscalePatchGenerator.h"
#include "vtkNew.h"
#include "vtkPerceptualLODSelector.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace
{
/// The whole pipeline on `input`, with every message recorded; a view from +z at `distance`
/// times the model's size.
struct Pipeline
{
  vtkNew<vtkMultiscaleOctreeBuilder> Builder;
  vtkNew<vtkPerceptualLODSelector> Selector;
  vtkNew<vtkMultiscalePatchGenerator> Patches;
  vtkNew<plodtest::ErrorRecorder> Messages;

  explicit Pipeline(vtkPolyData* input, double distance = 3.0)
  {
    this->Builder->SetInputData(input);
    this->Selector->SetInputConnection(this->Builder->GetOutputPort());
    this->Patches->SetInputConnection(this->Selector->GetOutputPort());
    for (vtkObject* o :
      { static_cast<vtkObject*>(this->Builder.Get()), static_cast<vtkObject*>(this->Selector.Get()),
        static_cast<vtkObject*>(this->Patches.Get()) })
    {
      o->AddObserver(vtkCommand::ErrorEvent, this->Messages);
      o->AddObserver(vtkCommand::WarningEvent, this->Messages);
    }
    double b[6];
    input->GetBounds(b);
    const double size = std::max({ b[1] - b[0], b[3] - b[2], b[5] - b[4], 1e-300 });
    const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
    if (std::isfinite(size) && std::isfinite(c[0] + c[1] + c[2]))
    {
      this->Selector->SetEyePosition(c[0], c[1], c[2] + distance * size);
    }
    this->Selector->SetViewportSize(640, 480);
  }
  vtkPolyData* Run()
  {
    this->Patches->Update();
    return this->Patches->GetOutput();
  }
  bool Said(const std::string& part) const
  {
    for (const auto* list : { &this->Messages->Errors, &this->Messages->Warnings })
      for (const auto& m : *list)
        if (m.find(part) != std::string::npos)
          return true;
    return false;
  }
};
}

TEST(BadInput, ALongSliverDoesNotHang)
{
  // 2,000 tiny triangles and one sliver across the model, at the deepest levels
  auto mesh = plodtest::MakeSliverSoup();
  for (int level : { -1, 17, 21 })
  {
    Pipeline p(mesh);
    p.Builder->SetFinestLevel(level);
    vtkPolyData* out = p.Run();
    EXPECT_EQ(p.Builder->GetOutput()->GetNumberOfSurfaceTriangles(), 2001);
    EXPECT_GT(out->GetNumberOfPolys(), 0) << level;
  }
}

TEST(BadInput, APiledPointCloudDoesNotHang)
{
  // a scanned cloud with a pile of duplicates: half of 262,144 points on one spot. The PCA
  // normals visited every point of the 27 cells around each point, k^2 for a cell of k points
  // (65,536 points took 26.6 s; this one would take about 7 minutes). They now take at most
  // 512 evenly spread candidates a point.
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 1);
  const int n = 262144;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (int i = 0; i < n; ++i)
  {
    double x[3] = { g(rng), g(rng), g(rng) };
    const double l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (double& c : x)
      c = (i % 2) ? 0.5 : c / l;
    pts->InsertNextPoint(x);
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(pts);
  Pipeline p(cloud);
  vtkPolyData* out = p.Run();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  ASSERT_GT(o->GetNumberOfNodes(), 1) << p.Messages->Errors.size();
  EXPECT_GT(out->GetNumberOfPolys(), 0);
  // the sphere is still there: the drawn surface spans it
  double b[6];
  out->GetBounds(b);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(b[2 * a + 1] - b[2 * a], 2.0, 0.15) << a;
}

TEST(BadInput, AHubOfBoundarySpokesDoesNotHang)
{
  // 32,000 triangles around one hub point, every spoke a boundary edge: finding each boundary
  // edge's triangle among the hub's triangles cost 32,000^2 / 2 tests (1.1 s; a million spokes
  // would take about 20 minutes). It now searches the end with fewer triangles (0.18 s, most of
  // it sorting). The rest of this build (2 s) is the cells these large triangles cross.
  const int n = 32000;
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<double> xyz(3 * (2 * n + 1), 0.0);
  for (size_t i = 3; i < xyz.size(); ++i)
    xyz[i] = U(rng);
  std::vector<vtkIdType> tri;
  for (int i = 0; i < n; ++i)
    tri.insert(tri.end(), { 0, 2 * vtkIdType(i) + 1, 2 * vtkIdType(i) + 2 });
  auto mesh = plodtest::MakeMesh(xyz, tri);
  Pipeline p(mesh);
  p.Run();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  ASSERT_EQ(o->GetNumberOfSurfaceTriangles(), n);
  EXPECT_EQ(o->GetNumberOfBoundaryEdges(), 3 * n);
}

TEST(BadInput, ShortOrLongArraysAreErrorsNamingThem)
{
  auto blob = plodtest::MakeBlob(1, 16, 0.2);
  const vtkIdType np = blob->GetNumberOfPoints();
  struct Case
  {
    const char* Name;
    bool Cell;
    int Comps;
    vtkIdType Tuples;
    const char* Setting; // "normals", "diffuse", "specular"
  };
  const Case cases[] = { { "Kd", false, 1, np - 1, "diffuse" },
    { "Ks", true, 1, blob->GetNumberOfCells() / 2, "specular" },
    { "N", false, 3, np + 5, "normals" } };
  for (const Case& c : cases)
  {
    vtkNew<vtkPolyData> pd;
    pd->DeepCopy(blob);
    vtkNew<vtkFloatArray> a;
    a->SetName(c.Name);
    a->SetNumberOfComponents(c.Comps);
    a->SetNumberOfTuples(c.Tuples);
    a->Fill(0.5);
    if (std::string(c.Setting) == "normals")
      pd->GetPointData()->SetNormals(a);
    else if (c.Cell)
      pd->GetCellData()->AddArray(a);
    else
      pd->GetPointData()->AddArray(a);
    Pipeline p(pd);
    if (std::string(c.Setting) == "diffuse")
      p.Builder->SetDiffuseArrayName(c.Name);
    if (std::string(c.Setting) == "specular")
      p.Builder->SetSpecularArrayName(c.Name);
    vtkPolyData* out = p.Run();
    EXPECT_TRUE(p.Said(std::string("array '") + c.Name + "'")) << c.Name;
    EXPECT_EQ(p.Builder->GetOutput()->GetNumberOfNodes(), 0) << c.Name;
    EXPECT_EQ(out->GetNumberOfPolys(), 0) << c.Name;
  }
}

TEST(BadInput, CorruptOctreeArraysAreRefusedByEveryFilter)
{
  // arrays edited after the build: the selector and the patch generator refuse the octree with
  // an error naming the problem, and never follow a bad index or loop on a cycle
  auto blob = plodtest::MakeBlob(2, 24, 0.2);
  Pipeline p(blob);
  p.Run();
  vtkMultiscaleOctree* o = p.Builder->GetOutput();
  auto* first = vtkIntArray::SafeDownCast(o->GetNodeData()->GetArray("FirstChild"));
  auto* parent = vtkIntArray::SafeDownCast(o->GetNodeData()->GetArray("Parent"));
  const vtkIdType last = o->GetNumberOfNodes() - 1;
  for (int edit = 0; edit < 3; ++edit)
  {
    vtkIntArray* a = edit == 0 ? first : parent;
    const vtkIdType i = edit == 0 ? 0 : (edit == 1 ? last : 1);
    const int old = a->GetValue(i);
    a->SetValue(i, edit == 0 ? 1 << 30 : (edit == 1 ? static_cast<int>(last) : 1)); // cycles
    a->Modified();
    p.Messages->Errors.clear();
    p.Selector->Modified();
    vtkPolyData* out = p.Run();
    EXPECT_TRUE(p.Said("invalid")) << edit;
    EXPECT_EQ(out->GetNumberOfPolys(), 0) << edit;
    a->SetValue(i, old);
    a->Modified();
  }
  p.Selector->Modified();
  p.Messages->Errors.clear();
  EXPECT_GT(p.Run()->GetNumberOfPolys(), 0) << "mended, it draws again";
  EXPECT_TRUE(p.Messages->Errors.empty());
}

TEST(BadInput, TinyMeshesDraw)
{
  // a cube, a tetrahedron, one triangle: a level that separates the corners, and a picture
  for (auto mesh : { plodtest::MakeCube(0, 1), plodtest::MakeTetrahedron(),
         plodtest::MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0 }, { 0, 1, 2 }) })
  {
    Pipeline p(mesh);
    p.Selector->HideBackFacesOff(); // the single triangle is seen from its back as well
    vtkPolyData* out = p.Run();
    EXPECT_GE(p.Builder->GetOutput()->GetFinestLevel(), 1);
    EXPECT_GT(out->GetNumberOfPolys(), 0);
    EXPECT_STREQ(p.Selector->GetEmptyCutReason(), "");
  }
}

TEST(BadInput, ExtremeCoordinatesAreAClearErrorOrWork)
{
  // 1e-300 and 1e300 extents: beyond single precision, an error that says so; 1e-20 and 1e20
  // with a far origin: built and drawn
  for (double scale : { 1e-300, 1e300 })
  {
    Pipeline p(plodtest::MakeBlob(3, 12, 0.2, scale));
    vtkPolyData* out = p.Run();
    EXPECT_TRUE(p.Said("single-precision")) << scale;
    EXPECT_EQ(out->GetNumberOfPolys(), 0);
  }
  for (double scale : { 1e-20, 1e20 })
  {
    const double centre[3] = { 1e3 * scale, 0, 0 };
    Pipeline p(plodtest::MakeBlob(3, 12, 0.2, scale, centre));
    EXPECT_GT(p.Run()->GetNumberOfPolys(), 0) << scale;
    EXPECT_TRUE(p.Messages->Errors.empty()) << scale;
  }
}

TEST(BadInput, NonFinitePointsAndBadIndicesAreSkippedWithAWarning)
{
  auto blob = plodtest::MakeBlob(4, 16, 0.2);
  vtkNew<vtkPolyData> bad;
  bad->DeepCopy(blob);
  const vtkIdType inf = bad->GetPoints()->InsertNextPoint(HUGE_VAL, 0, 0);
  const vtkIdType t1[3] = { 0, 1, inf }, t2[3] = { 0, 1, 1 << 30 };
  bad->GetPolys()->InsertNextCell(3, t1);
  bad->GetPolys()->InsertNextCell(3, t2);
  Pipeline p(bad);
  vtkPolyData* out = p.Run();
  EXPECT_TRUE(p.Said("2 triangle(s) skipped"));
  EXPECT_GT(out->GetNumberOfPolys(), 0);
}

TEST(BadInput, MemoryLimitLowersTheLevelWithAWarning)
{
  auto blob = plodtest::MakeBlob(5, 150, 0.2);
  Pipeline free(blob);
  free.Run();
  const int wanted = free.Builder->GetOutput()->GetFinestLevel();
  const double need = 1.0 * free.Builder->GetOutput()->GetActualMemorySize() / 1024.0;
  Pipeline tight(blob);
  tight.Builder->SetMemoryLimit(need); // below what the build itself needs at that level
  vtkPolyData* out = tight.Run();
  EXPECT_LT(tight.Builder->GetOutput()->GetFinestLevel(), wanted);
  EXPECT_TRUE(tight.Said("lowered from"));
  EXPECT_GT(out->GetNumberOfPolys(), 0) << "coarser, still drawn";
}

TEST(BadInput, RootAloneSaysWhyItDrawsNothing)
{
  // an eye at 1e300, DPV past its speed, a view angle of 179.9999 degrees: the root alone is the
  // cut (the model is below a pixel, or DPV draws zero polygons by definition), and the selector
  // says so instead of drawing nothing silently
  auto blob = plodtest::MakeBlob(6, 24, 0.2);
  {
    Pipeline p(blob);
    p.Selector->SetEyePosition(0, 0, 1e300);
    EXPECT_EQ(p.Run()->GetNumberOfPolys(), 0);
    EXPECT_NE(std::string(p.Selector->GetEmptyCutReason()).find("root alone"), std::string::npos);
  }
  {
    Pipeline p(blob);
    p.Selector->SetViewAngle(179.9999);
    p.Run();
    EXPECT_NE(std::string(p.Selector->GetEmptyCutReason()).find("root alone"), std::string::npos);
  }
  {
    Pipeline p(blob);
    p.Selector->SetMotionModelToDirectVelocity();
    p.Selector->SetDirectVelocitySpeed(1e-9);
    p.Selector->HasPreviousFrameOn();
    p.Selector->SetPreviousFrameTime(1.0 / 60);
    double m[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -3, 0, 0, 0, 1 };
    p.Selector->SetPreviousObjectToViewMatrix(m);
    m[3] = 0.5; // moved
    p.Selector->SetObjectToViewMatrix(m);
    EXPECT_EQ(p.Run()->GetNumberOfPolys(), 0);
    EXPECT_NE(std::string(p.Selector->GetEmptyCutReason()).find("DPV"), std::string::npos);
  }
}

TEST(BadInput, ManyBrightLightsCostLittle)
{
  // 1,000 lights of intensity 1 took 26 s a selection: the brightness spread saturates at 1 (a
  // rendered pixel cannot vary more), so they give the cut of one light 1,000 times as bright
  auto blob = plodtest::MakeBlob(7, 60, 0.3);
  Pipeline many(blob), one(blob);
  many.Selector->SetNumberOfLights(1000);
  for (int i = 0; i < 1000; ++i)
    many.Selector->SetLight(i, false, 0.3, 0.4, 1.0, 1.0, 1.0);
  one.Selector->SetNumberOfLights(1);
  one.Selector->SetLight(0, false, 0.3, 0.4, 1.0, 1000.0, 1000.0);
  many.Run();
  one.Run();
  EXPECT_EQ(many.Selector->GetNumberOfCutNodes(), one.Selector->GetNumberOfCutNodes());
  EXPECT_EQ(many.Patches->GetNumberOfTriangles(), one.Patches->GetNumberOfTriangles());
}

TEST(BadInput, AbsurdParametersAreErrors)
{
  auto blob = plodtest::MakeBlob(8, 16, 0.2);
  {
    Pipeline p(blob);
    p.Builder->SetFinestLevel(99);
    p.Builder->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, p.Messages);
    EXPECT_EQ(p.Run()->GetNumberOfPolys(), 0);
    EXPECT_TRUE(p.Said("FinestLevel 99"));
  }
  for (double bad : { -1.0, std::nan("") })
  {
    Pipeline p(blob);
    p.Selector->SetContourTolerance(bad);
    p.Run();
    EXPECT_TRUE(p.Said("Invalid input")) << bad;
  }
  {
    Pipeline p(blob);
    p.Selector->SetViewportSize(0, 480);
    p.Run();
    EXPECT_TRUE(p.Said("viewport"));
  }
}
