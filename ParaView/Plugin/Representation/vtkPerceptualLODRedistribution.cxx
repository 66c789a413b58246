// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPerceptualLODRedistribution.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "plodPartition.h"

#include <algorithm>
#include <cstdint>
#include <vector>

vtkStandardNewMacro(vtkPerceptualLODRedistribution);
vtkCxxSetObjectMacro(vtkPerceptualLODRedistribution, Controller, vtkMultiProcessController);

namespace
{
/// The triangles of a vtkPolyData's polygons (fans) and strips, as point ids. Ghost cells (the
/// cell array vtkGhostType: a copy of another rank's cell, or a hidden cell) are left out: the
/// rank that owns a cell sends it.
void CollectTriangles(vtkPolyData* input, std::vector<vtkIdType>& triangles)
{
  vtkUnsignedCharArray* ghostCells = input->GetCellData()->GetGhostArray();
  const unsigned char skip = vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL;
  // cell ids run over vertices, lines, polygons and strips, in that order
  vtkIdType cellId = input->GetNumberOfVerts() + input->GetNumberOfLines();
  auto isGhost = [&](vtkIdType id) {
    return ghostCells && id < ghostCells->GetNumberOfValues() &&
      (ghostCells->GetValue(id) & skip) != 0;
  };
  vtkIdType n;
  const vtkIdType* ids;
  auto polys = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cellId)
  {
    polys->GetCurrentCell(n, ids);
    if (isGhost(cellId))
    {
      continue;
    }
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      triangles.insert(triangles.end(), { ids[0], ids[k], ids[k + 1] });
    }
  }
  auto strips = vtk::TakeSmartPointer(input->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
  {
    strips->GetCurrentCell(n, ids);
    if (isGhost(cellId))
    {
      continue;
    }
    for (vtkIdType k = 0; k + 2 < n; ++k)
    {
      if (k & 1)
      {
        triangles.insert(triangles.end(), { ids[k + 1], ids[k], ids[k + 2] });
      }
      else
      {
        triangles.insert(triangles.end(), { ids[k], ids[k + 1], ids[k + 2] });
      }
    }
  }
}

/// The partition's collective calls on a VTK controller (MPI ranks in ParaView).
class ControllerCollective : public plod::Collective
{
public:
  explicit ControllerCollective(vtkMultiProcessController* controller)
    : Controller(controller)
  {
  }
  int Rank() const override { return this->Controller->GetLocalProcessId(); }
  int Ranks() const override { return this->Controller->GetNumberOfProcesses(); }
  void Sum(int64_t* values, int64_t n) override
  {
    std::vector<long long> in(values, values + n), out(n, 0);
    this->Controller->AllReduce(in.data(), out.data(), n, vtkCommunicator::SUM_OP);
    std::copy(out.begin(), out.end(), values);
  }
  void Min(double* values, int n) override { this->Reduce(values, n, vtkCommunicator::MIN_OP); }
  void Max(double* values, int n) override { this->Reduce(values, n, vtkCommunicator::MAX_OP); }
  void Max(uint8_t* values, int64_t n) override
  {
    std::vector<unsigned char> out(n, 0);
    this->Controller->AllReduce(values, out.data(), n, vtkCommunicator::MAX_OP);
    std::copy(out.begin(), out.end(), values);
  }
  void Gather(const std::vector<double>& send, int root, std::vector<double>* received) override
  {
    vtkNew<vtkDoubleArray> out, in;
    out->SetNumberOfValues(static_cast<vtkIdType>(send.size()));
    std::copy(send.begin(), send.end(), out->GetPointer(0));
    this->Controller->GatherV(out, in, root);
    if (this->Rank() == root)
    {
      const double* data = in->GetPointer(0);
      received->assign(data, data + in->GetNumberOfValues());
    }
  }

private:
  void Reduce(double* values, int n, int operation)
  {
    std::vector<double> out(n, 0.0);
    this->Controller->AllReduce(values, out.data(), n, operation);
    std::copy(out.begin(), out.end(), values);
  }
  vtkMultiProcessController* Controller;
};
}

//------------------------------------------------------------------------------
vtkPerceptualLODRedistribution::vtkPerceptualLODRedistribution()
{
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

//------------------------------------------------------------------------------
vtkPerceptualLODRedistribution::~vtkPerceptualLODRedistribution()
{
  this->SetController(nullptr);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRedistribution::ConfigureBuilder(vtkMultiscaleOctreeBuilder* builder)
{
  builder->SetUseGivenRootCube(true);
  builder->SetRootCubeOrigin(this->RootOrigin);
  builder->SetRootCubeEdge(this->RootEdge);
  builder->SetFinestLevel(this->FinestLevel);
}

//------------------------------------------------------------------------------
int vtkPerceptualLODRedistribution::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  vtkMultiProcessController* controller = this->Controller;
  const bool parallel = controller && controller->GetNumberOfProcesses() > 1;
  const int rank = controller ? controller->GetLocalProcessId() : 0;

  // this rank's triangles, points (as doubles) and normals, for the kernel
  std::vector<vtkIdType> local;
  vtkPoints* inPoints = input ? input->GetPoints() : nullptr;
  if (input && inPoints)
  {
    CollectTriangles(input, local);
  }
  const vtkIdType np = inPoints ? inPoints->GetNumberOfPoints() : 0;
  std::vector<double> xyz(3 * np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    inPoints->GetPoint(i, &xyz[3 * i]);
  }
  std::vector<double> normals;
  vtkDataArray* inNormals = input ? input->GetPointData()->GetNormals() : nullptr;
  if (inNormals &&
    (inNormals->GetNumberOfComponents() != 3 || inNormals->GetNumberOfTuples() != np))
  {
    vtkWarningMacro(<< "Rank " << rank << "'s normals array has " << inNormals->GetNumberOfTuples()
                    << " tuples of " << inNormals->GetNumberOfComponents() << " components for "
                    << np << " points: not carried");
    inNormals = nullptr;
  }
  if (inNormals)
  {
    normals.resize(3 * np);
    for (vtkIdType i = 0; i < np; ++i)
    {
      inNormals->GetTuple(i, &normals[3 * i]);
    }
  }
  std::vector<int64_t> triangles(local.begin(), local.end());
  plod::PartitionInput in;
  in.NumberOfPoints = np;
  in.Points = xyz.data();
  in.Normals = inNormals ? normals.data() : nullptr;
  in.NumberOfTriangles = static_cast<int64_t>(triangles.size() / 3);
  in.Triangles = triangles.data();
  plod::PartitionParameters params;
  params.OwnershipLevel = this->OwnershipLevel;
  params.RequestedFinestLevel = this->RequestedFinestLevel;

  plod::SerialCollective serial;
  ControllerCollective ranks(controller);
  plod::Collective& collective = parallel ? static_cast<plod::Collective&>(ranks) : serial;
  const plod::PartitionResult r = plod::PartitionMesh(in, params, collective);
  if (r.NumberOfSkippedTriangles > 0)
  {
    vtkWarningMacro(<< r.NumberOfSkippedTriangles << " triangles of rank " << rank
                    << " have a point id out of range or a non-finite corner: left out");
  }
  if (!r.Ok)
  {
    vtkErrorMacro("Cannot share the mesh out: " << r.Error);
    return 0;
  }
  std::copy(r.RootOrigin, r.RootOrigin + 3, this->RootOrigin);
  this->RootEdge = r.RootEdge;
  this->FinestLevel = r.FinestLevel;
  this->NumberOfOwnedCells = r.NumberOfOwnedCells;
  this->NumberOfHaloTriangles = r.NumberOfHaloTriangles;
  this->NumberOfBoundaryEdges = r.NumberOfBoundaryEdges;
  if (r.NoTriangles)
  {
    vtkWarningMacro("No rank holds a triangle: nothing to share out (point clouds are not "
                    "redistributed)");
    output->ShallowCopy(input);
    return 1;
  }
  this->MakeOutput(r, output);
  return 1;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRedistribution::MakeOutput(const plod::PartitionResult& r, vtkPolyData* output)
{
  const vtkIdType np = static_cast<vtkIdType>(r.Ghost.size());
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(np);
  std::copy(r.Points.begin(), r.Points.end(), coordinates->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfValues(np);
  for (vtkIdType p = 0; p < np; ++p)
  {
    ghosts->SetValue(p, r.Ghost[p] ? vtkDataSetAttributes::DUPLICATEPOINT : 0);
  }
  const vtkIdType nt = static_cast<vtkIdType>(r.Triangles.size() / 3);
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(nt, 3 * nt);
  for (vtkIdType t = 0; t < nt; ++t)
  {
    polys->InsertNextCell(
      { static_cast<vtkIdType>(r.Triangles[3 * t]), static_cast<vtkIdType>(r.Triangles[3 * t + 1]),
        static_cast<vtkIdType>(r.Triangles[3 * t + 2]) });
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetPointData()->AddArray(ghosts);
  if (r.HasNormals)
  {
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(np);
    for (vtkIdType i = 0; i < 3 * np; ++i)
    {
      normals->SetValue(i, static_cast<float>(r.Normals[i]));
    }
    output->GetPointData()->SetNormals(normals);
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODRedistribution::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "OwnershipLevel: " << this->OwnershipLevel << "\n";
  os << indent << "RequestedFinestLevel: " << this->RequestedFinestLevel << "\n";
  os << indent << "RootOrigin: " << this->RootOrigin[0] << " " << this->RootOrigin[1] << " "
     << this->RootOrigin[2] << "\n";
  os << indent << "RootEdge: " << this->RootEdge << "\n";
  os << indent << "FinestLevel: " << this->FinestLevel << "\n";
  os << indent << "NumberOfOwnedCells: " << this->NumberOfOwnedCells << "\n";
  os << indent << "NumberOfHaloTriangles: " << this->NumberOfHaloTriangles << "\n";
  os << indent << "NumberOfBoundaryEdges: " << this->NumberOfBoundaryEdges << "\n";
}
