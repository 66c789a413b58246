// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscalePatchGenerator.h"

#include "plodPatches.h"

#include "vtkCellArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiscaleOctree.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkTimerLog.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

vtkStandardNewMacro(vtkMultiscalePatchGenerator);

struct vtkMultiscalePatchGenerator::Internals
{
  plod::PatchWorkspace Workspace;
  plod::PatchResult Result;
  std::vector<uint8_t> FullCut; // used when the input carries no cut
};

//------------------------------------------------------------------------------
vtkMultiscalePatchGenerator::vtkMultiscalePatchGenerator()
  : GenerateNormals(true)
  , GenerateColors(false)
  , GenerateNodeIds(false)
  , GenerateInputPointIds(false)
  , FoldHandling(FOLDS_REVERSE_NORMALS)
  , CullBackFaces(true)
  , NumberOfFolds(0)
  , NumberOfCulledBackFaces(0)
  , NumberOfGhostTriangles(0)
  , NumberOfTriangles(0)
  , NumberOfOutputPoints(0)
  , NodesVisited(0)
  , GenerateTime(0)
  , Internal(new Internals)
{
}

//------------------------------------------------------------------------------
vtkMultiscalePatchGenerator::~vtkMultiscalePatchGenerator() = default;

//------------------------------------------------------------------------------
int vtkMultiscalePatchGenerator::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiscaleOctree");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscalePatchGenerator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiscaleOctree* input = vtkMultiscaleOctree::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  this->NumberOfTriangles = this->NodesVisited = this->NumberOfOutputPoints = 0;
  this->NumberOfFolds = 0;
  this->NumberOfCulledBackFaces = 0;
  this->NumberOfGhostTriangles = 0;
  this->GenerateTime = 0;
  if (!input || input->GetNumberOfNodes() == 0)
  {
    return 1;
  }
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  std::string why;
  plod::OctreeView v;
  if (!input->GetCheckedView(v, nullptr, &why))
  {
    vtkErrorMacro("The input octree is invalid (" << why << "): empty output.");
    return 1;
  }
  const uint8_t* state = nullptr;
  auto* cut = vtkUnsignedCharArray::SafeDownCast(
    input->GetNodeData()->GetAbstractArray(vtkMultiscaleOctree::CutStateArrayName()));
  if (cut && cut->GetNumberOfComponents() == 1 && cut->GetNumberOfTuples() == v.NumberOfNodes)
  {
    state = cut->GetPointer(0);
  }
  else
  {
    if (cut)
    {
      vtkWarningMacro("CutState array has the wrong size or type: drawing full resolution.");
    }
    this->Internal->FullCut.resize(v.NumberOfNodes);
    plod::UniformCut(v, -1, this->Internal->FullCut.data());
    state = this->Internal->FullCut.data();
  }
  const uint8_t* cullMask = nullptr;
  auto* mask = vtkUnsignedCharArray::SafeDownCast(
    input->GetNodeData()->GetAbstractArray(vtkMultiscaleOctree::CullMaskArrayName()));
  if (mask && mask->GetNumberOfComponents() == 1 && mask->GetNumberOfTuples() == v.NumberOfNodes)
  {
    cullMask = mask->GetPointer(0);
  }

  plod::PatchResult& r = this->Internal->Result;
  plod::PatchOptions options;
  options.Folds = static_cast<plod::FoldHandling>(this->FoldHandling);
  if (this->CullBackFaces && input->GetFieldData())
  {
    vtkDataArray* view = input->GetFieldData()->GetArray(vtkMultiscaleOctree::CutViewArrayName());
    if (view && view->GetNumberOfValues() == 8 && view->GetComponent(7, 0) != 0)
    {
      options.CullBackFaces = true;
      for (int a = 0; a < 3; ++a)
      {
        options.Eye[a] = view->GetComponent(a, 0);
        options.ProjectionDirection[a] = view->GetComponent(4 + a, 0);
      }
      options.Parallel = view->GetComponent(3, 0) != 0;
    }
  }
  if (this->MultiThreaded && vtkSMPTools::GetEstimatedNumberOfThreads() > 1)
  {
    options.For = [](int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body) {
      vtkSMPTools::For(0, static_cast<vtkIdType>(n), static_cast<vtkIdType>(grain),
        [&body](vtkIdType b, vtkIdType e) { body(b, e); });
    };
  }
  if (!plod::GeneratePatches(v, state, cullMask, r, &why, &this->Internal->Workspace, options))
  {
    vtkErrorMacro("Invalid cut: " << why << ". Empty output.");
    return 1;
  }
  this->UpdateProgress(0.5);

  const vtkIdType np = static_cast<vtkIdType>(r.PointSource.size());
  const vtkIdType nt = static_cast<vtkIdType>(r.Triangles.size() / 3);
  // far from the origin relative to its size: keep double precision
  const double far =
    std::max({ std::abs(v.Origin[0]), std::abs(v.Origin[1]), std::abs(v.Origin[2]) });
  auto position = [&v](int64_t source) {
    return source >= 0 ? &v.ClusterVertex[3 * source] : &v.Points[3 * (-1 - source)];
  };
  // ranges of output points, filled in parallel (each value depends on its source alone)
  auto forPoints = [this, np](const std::function<void(vtkIdType, vtkIdType)>& fill) {
    if (this->MultiThreaded)
    {
      vtkSMPTools::For(0, np, 65536, fill);
    }
    else
    {
      fill(0, np);
    }
  };
  vtkNew<vtkPoints> points;
  const bool doublePoints = far > 100.0 * v.RootEdge;
  points->SetDataType(doublePoints ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(np);
  void* xyz = np > 0 ? points->GetData()->GetVoidPointer(0) : nullptr;
  forPoints([&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const float* x = position(r.PointSource[i]);
      for (int a = 0; a < 3; ++a)
      {
        // as vtkPoints::SetPoint stores it: the double sum, then the array's type
        const double w = v.Origin[a] + x[a];
        if (doublePoints)
          static_cast<double*>(xyz)[3 * i + a] = w;
        else
          static_cast<float*>(xyz)[3 * i + a] = static_cast<float>(w);
      }
    }
  });
  output->SetPoints(points);

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(nt + 1);
  connectivity->SetNumberOfValues(3 * nt);
  vtkIdType* off = offsets->GetPointer(0);
  for (vtkIdType t = 0; t <= nt; ++t)
  {
    off[t] = 3 * t;
  }
  std::copy(r.Triangles.begin(), r.Triangles.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  output->SetPolys(polys);

  // the node of an output point: its cluster's cell, or the leaf of an opened leaf's point
  auto nodeOf = [&v](int64_t source) {
    return source >= 0 ? int64_t(v.ClusterNode[source]) : int64_t(v.PointLeaf[-1 - source]);
  };
  if (this->GenerateNormals)
  {
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(np);
    float* n = normals->GetPointer(0);
    forPoints([&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
      {
        const int64_t s = r.PointSource[i];
        std::copy_n(s >= 0 ? &v.ClusterNormal[3 * s] : &v.Normals[3 * (-1 - s)], 3, n + 3 * i);
      }
    });
    for (const int32_t i : r.ReversedNormals)
    {
      for (int a = 0; a < 3; ++a)
      {
        n[3 * i + a] = -n[3 * i + a];
      }
    }
    output->GetPointData()->SetNormals(normals);
  }
  if (this->GenerateColors)
  {
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(3);
    colors->SetNumberOfTuples(np);
    for (vtkIdType i = 0; i < np; ++i)
    {
      const float* d = &v.DiffuseRange[2 * nodeOf(r.PointSource[i])];
      const double kd = std::min(1.0, std::max(0.0, 0.5 * (double(d[0]) + d[1])));
      const unsigned char g = static_cast<unsigned char>(std::lround(255.0 * kd));
      colors->SetTypedTuple(i, std::array<unsigned char, 3>{ g, g, g }.data());
    }
    output->GetPointData()->SetScalars(colors);
  }
  if (this->GenerateNodeIds)
  {
    vtkNew<vtkIdTypeArray> ids;
    ids->SetName("OctreeNode");
    ids->SetNumberOfTuples(np);
    for (vtkIdType i = 0; i < np; ++i)
    {
      ids->SetValue(i, nodeOf(r.PointSource[i]));
    }
    output->GetPointData()->AddArray(ids);
  }
  if (this->GenerateInputPointIds)
  {
    vtkNew<vtkIdTypeArray> ids;
    ids->SetName("InputPointId");
    ids->SetNumberOfTuples(np);
    for (vtkIdType i = 0; i < np; ++i)
    {
      const int64_t s = r.PointSource[i];
      ids->SetValue(i, s >= 0 ? -1 : v.InputPointId[-1 - s]);
    }
    output->GetPointData()->AddArray(ids);
  }
  timer->StopTimer();
  this->GenerateTime = timer->GetElapsedTime();
  this->NumberOfTriangles = nt;
  this->NumberOfOutputPoints = np;
  this->NodesVisited = r.NodesVisited;
  this->NumberOfFolds = r.Folds;
  this->NumberOfCulledBackFaces = r.BackFacesCulled;
  this->NumberOfGhostTriangles = r.GhostSkipped;
  return 1;
}

//------------------------------------------------------------------------------
const char* vtkMultiscalePatchGenerator::GetFoldHandlingAsString() const
{
  switch (this->FoldHandling)
  {
    case FOLDS_KEEP:
      return "Keep";
    case FOLDS_DROP:
      return "Drop";
    default:
      return "ReverseNormals";
  }
}

void vtkMultiscalePatchGenerator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "GenerateNormals: " << (this->GenerateNormals ? "On" : "Off") << "\n";
  os << indent << "GenerateColors: " << (this->GenerateColors ? "On" : "Off") << "\n";
  os << indent << "GenerateNodeIds: " << (this->GenerateNodeIds ? "On" : "Off") << "\n";
  os << indent << "GenerateInputPointIds: " << (this->GenerateInputPointIds ? "On" : "Off") << "\n";
  os << indent << "NumberOfTriangles: " << this->NumberOfTriangles << "\n";
  os << indent << "NumberOfOutputPoints: " << this->NumberOfOutputPoints << "\n";
  os << indent << "NodesVisited: " << this->NodesVisited << "\n";
  os << indent << "FoldHandling: " << this->GetFoldHandlingAsString() << "\n";
  os << indent << "NumberOfFolds: " << this->NumberOfFolds << "\n";
  os << indent << "CullBackFaces: " << (this->CullBackFaces ? "On" : "Off") << "\n";
  os << indent << "MultiThreaded: " << (this->MultiThreaded ? "On" : "Off") << "\n";
  os << indent << "NumberOfCulledBackFaces: " << this->NumberOfCulledBackFaces << "\n";
  os << indent << "NumberOfGhostTriangles: " << this->NumberOfGhostTriangles << "\n";
  os << indent << "GenerateTime: " << this->GenerateTime << " s\n";
}
