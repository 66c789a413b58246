// SPDX-License-Identifier: BSD-3-Clause
// Tests of vtkMeshoptimizerDecimation, the second static baseline: it reaches the target on a
// closed blob and keeps it closed and within its own points; it never adds triangles; a far
// from the origin model keeps its double coordinates; bad input gives an error and an empty
// output.
#include "plodTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkMeshoptimizerDecimation.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace
{

vtkSmartPointer<vtkPolyData> Simplify(vtkPolyData* input, vtkIdType target,
  plodtest::ErrorRecorder* errors = nullptr, bool lockBorder = false)
{
  vtkNew<vtkMeshoptimizerDecimation> simplify;
  if (errors)
  {
    simplify->AddObserver(vtkCommand::ErrorEvent, errors);
  }
  simplify->SetInputData(input);
  simplify->SetTargetNumberOfTriangles(target);
  simplify->SetLockBorder(lockBorder);
  simplify->Update();
  EXPECT_EQ(simplify->GetNumberOfTriangles(), simplify->GetOutput()->GetNumberOfPolys());
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(simplify->GetOutput());
  return out;
}

/// Every directed edge matched by its reverse: closed and consistently oriented.
bool ClosedAndOriented(vtkPolyData* pd)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> directed;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      ++directed[{ ids[k], ids[(k + 1) % n] }];
    }
  }
  for (const auto& e : directed)
  {
    auto back = directed.find({ e.first.second, e.first.first });
    if (back == directed.end() || back->second != e.second)
    {
      return false;
    }
  }
  return !directed.empty();
}

TEST(MeshoptimizerDecimation, ReachesTheTargetAndKeepsAClosedSurfaceClosed)
{
  auto blob = plodtest::MakeBlob(3, 60, 0.05);
  const vtkIdType input = blob->GetNumberOfPolys();
  ASSERT_GT(input, 6000);
  auto out = Simplify(blob, 1000);
  EXPECT_LE(out->GetNumberOfPolys(), 1000);
  EXPECT_GE(out->GetNumberOfPolys(), 900);
  EXPECT_TRUE(ClosedAndOriented(out));
  // every output point is an input point
  std::set<std::array<double, 3>> inputPoints;
  for (vtkIdType i = 0; i < blob->GetNumberOfPoints(); ++i)
  {
    double p[3];
    blob->GetPoint(i, p);
    inputPoints.insert({ p[0], p[1], p[2] });
  }
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    EXPECT_TRUE(inputPoints.count({ p[0], p[1], p[2] })) << "point " << i;
  }
}

TEST(MeshoptimizerDecimation, TargetReductionAndNoGrowth)
{
  auto blob = plodtest::MakeBlob(5, 40, 0.02);
  vtkNew<vtkMeshoptimizerDecimation> simplify;
  simplify->SetInputData(blob);
  simplify->SetTargetReduction(0.75);
  simplify->Update();
  const double kept = static_cast<double>(simplify->GetNumberOfTriangles()) /
    static_cast<double>(blob->GetNumberOfPolys());
  EXPECT_LE(kept, 0.25 + 1e-9);
  EXPECT_GT(kept, 0.2);
  // a target above the input keeps the input
  auto same = Simplify(blob, 10 * blob->GetNumberOfPolys());
  EXPECT_EQ(same->GetNumberOfPolys(), blob->GetNumberOfPolys());
}

TEST(MeshoptimizerDecimation, FarFromTheOriginKeepsDoubleCoordinates)
{
  const double centre[3] = { 1e7, -2e7, 3e7 };
  auto blob = plodtest::MakeBlob(7, 40, 0.03, 1.0, centre);
  auto out = Simplify(blob, 400);
  ASSERT_GT(out->GetNumberOfPolys(), 300);
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_DOUBLE);
  double b[6];
  out->GetBounds(b);
  EXPECT_NEAR(0.5 * (b[0] + b[1]), 1e7, 0.2);
  EXPECT_NEAR(0.5 * (b[4] + b[5]), 3e7, 0.2);
  EXPECT_TRUE(ClosedAndOriented(out));
}

/// A 21 x 21 grid on the unit square with a bump in the middle.
vtkSmartPointer<vtkPolyData> MakeBumpyGrid()
{
  const int n = 20;
  std::vector<double> xyz;
  std::vector<vtkIdType> tris;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      const double x = double(i) / n, y = double(j) / n;
      xyz.insert(
        xyz.end(), { x, y, 0.2 * std::exp(-20 * ((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5))) });
    }
  }
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const vtkIdType a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      tris.insert(tris.end(), { a, b, d, a, d, c });
    }
  }
  return plodtest::MakeMesh(xyz, tris);
}

int BorderPoints(vtkPolyData* pd)
{
  int count = 0;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double p[3];
    pd->GetPoint(i, p);
    count += (p[0] == 0 || p[0] == 1 || p[1] == 0 || p[1] == 1) ? 1 : 0;
  }
  return count;
}

TEST(MeshoptimizerDecimation, LockBorderKeepsTheRim)
{
  auto grid = MakeBumpyGrid();
  ASSERT_EQ(BorderPoints(grid), 80);
  EXPECT_EQ(BorderPoints(Simplify(grid, 100, nullptr, true)), 80);
  EXPECT_LT(BorderPoints(Simplify(grid, 100, nullptr, false)), 80);
}

TEST(MeshoptimizerDecimation, BadInputGivesAnErrorAndAnEmptyOutput)
{
  vtkNew<plodtest::ErrorRecorder> errors;
  // empty input: empty output, no error
  vtkNew<vtkPolyData> empty;
  EXPECT_EQ(Simplify(empty, 10, errors)->GetNumberOfPolys(), 0);
  EXPECT_TRUE(errors->Errors.empty());
  // a non-finite coordinate
  auto blob = plodtest::MakeBlob(1, 20, 0.0);
  blob->GetPoints()->SetPoint(5, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  EXPECT_EQ(Simplify(blob, 10, errors)->GetNumberOfPolys(), 0);
  EXPECT_TRUE(errors->HasError("non-finite"));
  // a quad
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1, 0, 0);
  points->InsertNextPoint(1, 1, 0);
  points->InsertNextPoint(0, 1, 0);
  vtkNew<vtkCellArray> polys;
  const vtkIdType quad[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, quad);
  vtkNew<vtkPolyData> quadMesh;
  quadMesh->SetPoints(points);
  quadMesh->SetPolys(polys);
  EXPECT_EQ(Simplify(quadMesh, 1, errors)->GetNumberOfPolys(), 0);
  EXPECT_TRUE(errors->HasError("only triangles"));
  // an index out of range
  vtkNew<vtkCellArray> bad;
  const vtkIdType tri[3] = { 0, 1, 9 };
  bad->InsertNextCell(3, tri);
  quadMesh->SetPolys(bad);
  EXPECT_EQ(Simplify(quadMesh, 1, errors)->GetNumberOfPolys(), 0);
  EXPECT_TRUE(errors->HasError("out of range"));
}

} // namespace
