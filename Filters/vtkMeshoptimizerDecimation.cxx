// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMeshoptimizerDecimation.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <meshoptimizer.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMeshoptimizerDecimation);

vtkMeshoptimizerDecimation::vtkMeshoptimizerDecimation()
  : TargetNumberOfTriangles(0)
  , TargetReduction(0.9)
  , TargetError(1.0)
  , LockBorder(false)
  , NumberOfTriangles(0)
  , ResultError(0.0)
{
}

void vtkMeshoptimizerDecimation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetNumberOfTriangles: " << this->TargetNumberOfTriangles << "\n";
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "TargetError: " << this->TargetError << "\n";
  os << indent << "LockBorder: " << (this->LockBorder ? "on" : "off") << "\n";
  os << indent << "NumberOfTriangles: " << this->NumberOfTriangles << "\n";
  os << indent << "ResultError: " << this->ResultError << "\n";
}

namespace
{
/// The points relative to the centre of their bounds, in single precision, into `positions`;
/// false (and `why`) at a non-finite coordinate.
bool CenteredPositions(vtkPoints* points, std::vector<float>& positions, std::string& why)
{
  const vtkIdType numPoints = points->GetNumberOfPoints();
  double bounds[6];
  points->GetBounds(bounds);
  const double centre[3] = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
    0.5 * (bounds[4] + bounds[5]) };
  positions.resize(3 * static_cast<size_t>(numPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    double p[3];
    points->GetPoint(i, p);
    for (int a = 0; a < 3; ++a)
    {
      if (!std::isfinite(p[a]))
      {
        why = "point " + std::to_string(i) + " has a non-finite coordinate: nothing is simplified";
        return false;
      }
      positions[3 * i + a] = static_cast<float>(p[a] - centre[a]);
    }
  }
  return true;
}

/// The triangles' point ids into `indices`; false (and `why`) at a cell that is not a triangle
/// or a point id outside [0, numPoints).
bool TriangleIndices(
  vtkCellArray* polys, vtkIdType numPoints, std::vector<unsigned int>& indices, std::string& why)
{
  indices.clear();
  indices.reserve(3 * static_cast<size_t>(polys->GetNumberOfCells()));
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    if (n != 3)
    {
      why = "cell " + std::to_string(it->GetCurrentCellId()) + " has " + std::to_string(n) +
        " points: only triangles are simplified (run vtkTriangleFilter)";
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      if (ids[k] < 0 || ids[k] >= numPoints)
      {
        why = "cell " + std::to_string(it->GetCurrentCellId()) + " refers to point " +
          std::to_string(ids[k]) + ", out of range [0, " + std::to_string(numPoints) + ")";
        return false;
      }
      indices.push_back(static_cast<unsigned int>(ids[k]));
    }
  }
  return true;
}

/// `output` made of the `kept` triangles (3 input point ids each) and the points they use, in
/// their input order.
void CompactOutput(vtkPoints* inPoints, const std::vector<unsigned int>& kept, vtkPolyData* output)
{
  const vtkIdType numPoints = inPoints->GetNumberOfPoints();
  std::vector<char> usedPoint(static_cast<size_t>(numPoints), 0);
  for (unsigned int i : kept)
  {
    usedPoint[i] = 1;
  }
  std::vector<vtkIdType> newId(static_cast<size_t>(numPoints), -1);
  auto outPoints = vtkSmartPointer<vtkPoints>::New();
  outPoints->SetDataType(inPoints->GetDataType());
  vtkIdType used = 0;
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    if (usedPoint[i])
    {
      newId[i] = used++;
    }
  }
  outPoints->SetNumberOfPoints(used);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    if (newId[i] >= 0)
    {
      outPoints->SetPoint(newId[i], inPoints->GetPoint(i));
    }
  }
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  const size_t count = kept.size();
  polys->AllocateExact(static_cast<vtkIdType>(count / 3), static_cast<vtkIdType>(count));
  for (size_t t = 0; t < count; t += 3)
  {
    const vtkIdType tri[3] = { newId[kept[t]], newId[kept[t + 1]], newId[kept[t + 2]] };
    polys->InsertNextCell(3, tri);
  }
  output->SetPoints(outPoints);
  output->SetPolys(polys);
}
}

int vtkMeshoptimizerDecimation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->NumberOfTriangles = 0;
  this->ResultError = 0.0;
  output->Initialize();
  if (!input || !input->GetPoints() || !input->GetPolys() ||
    input->GetPolys()->GetNumberOfCells() == 0)
  {
    return 1; // nothing to simplify: an empty output
  }
  if (input->GetNumberOfStrips() > 0)
  {
    vtkErrorMacro("the input has triangle strips: run vtkTriangleFilter first");
    return 1;
  }
  vtkPoints* inPoints = input->GetPoints();
  const vtkIdType numPoints = inPoints->GetNumberOfPoints();
  if (static_cast<uint64_t>(numPoints) >= std::numeric_limits<unsigned int>::max())
  {
    vtkErrorMacro(
      "meshoptimizer indexes points with 32 bits: " << numPoints << " points are too many");
    return 1;
  }
  std::vector<float> positions;
  std::vector<unsigned int> indices;
  std::string why;
  if (!CenteredPositions(inPoints, positions, why) ||
    !TriangleIndices(input->GetPolys(), numPoints, indices, why))
  {
    vtkErrorMacro(<< why);
    return 1;
  }

  const size_t triangles = indices.size() / 3;
  size_t target = this->TargetNumberOfTriangles > 0
    ? static_cast<size_t>(this->TargetNumberOfTriangles)
    : static_cast<size_t>(std::llround((1.0 - this->TargetReduction) * triangles));
  target = std::min(target, triangles);
  std::vector<unsigned int> kept(indices.size());
  float error = 0.0f;
  this->UpdateProgress(0.1);
  const size_t count = meshopt_simplify(kept.data(), indices.data(), indices.size(),
    positions.data(), static_cast<size_t>(numPoints), 3 * sizeof(float), 3 * target,
    static_cast<float>(this->TargetError), this->LockBorder ? meshopt_SimplifyLockBorder : 0,
    &error);
  this->UpdateProgress(0.9);
  kept.resize(count);
  this->ResultError = error;
  CompactOutput(inPoints, kept, output);
  this->NumberOfTriangles = static_cast<vtkIdType>(count / 3);
  return 1;
}
