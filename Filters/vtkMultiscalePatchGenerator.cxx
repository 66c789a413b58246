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
#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkMultiscalePatchGenerator);

struct vtkMultiscalePatchGenerator::Internals
{
  plod::PatchWorkspace Workspace;
  plod::PatchResult Result;
  std::vector<uint8_t> FullCut; // used when the input carries no cut
  // what the workspace keeps per cluster, counted against the reader's CacheLimit; a new count
  // for each checked view, so that an octree drawn before stops counting it
  std::shared_ptr<std::atomic<uint64_t>> Held;
  vtkMTimeType HeldView = 0;
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

namespace
{
/// Calls `fill(begin, end)` over [0, n): in ranges on every core, or at once.
void ForPoints(
  bool multiThreaded, vtkIdType n, const std::function<void(vtkIdType, vtkIdType)>& fill)
{
  if (multiThreaded)
  {
    vtkSMPTools::For(0, n, 65536, fill);
  }
  else
  {
    fill(0, n);
  }
}

/// The output points at their world positions: in double far from the origin relative to the
/// model's size, else in float, each as vtkPoints::SetPoint would store the double sum.
void MakePoints(
  const plod::OctreeView& v, const plod::PatchResult& r, bool multiThreaded, vtkPolyData* output)
{
  const vtkIdType np = static_cast<vtkIdType>(r.PointSource.size());
  const double far =
    std::max({ std::abs(v.Origin[0]), std::abs(v.Origin[1]), std::abs(v.Origin[2]) });
  vtkNew<vtkPoints> points;
  const bool doublePoints = far > 100.0 * v.RootEdge;
  points->SetDataType(doublePoints ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(np);
  void* xyz = np > 0 ? points->GetData()->GetVoidPointer(0) : nullptr;
  ForPoints(multiThreaded, np, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const int64_t source = r.PointSource[i];
      const float* x = source >= 0 ? &v.ClusterVertex[3 * source] : &v.Points[3 * (-1 - source)];
      for (int a = 0; a < 3; ++a)
      {
        const double w = v.Origin[a] + x[a];
        if (doublePoints)
          static_cast<double*>(xyz)[3 * i + a] = w;
        else
          static_cast<float*>(xyz)[3 * i + a] = static_cast<float>(w);
      }
    }
  });
  output->SetPoints(points);
}

/// The triangles as the output's polygons.
void MakeTriangles(const plod::PatchResult& r, vtkPolyData* output)
{
  const vtkIdType nt = static_cast<vtkIdType>(r.Triangles.size() / 3);
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
}

/// The node of an output point's source: its cluster's cell, or an opened leaf's point's leaf.
int64_t NodeOf(const plod::OctreeView& v, int64_t source)
{
  return source >= 0 ? int64_t(v.ClusterNode[source]) : int64_t(v.PointLeaf[-1 - source]);
}

/// "Normals": each source's normal, reversed for a fold's own corners.
void AddNormals(
  const plod::OctreeView& v, const plod::PatchResult& r, bool multiThreaded, vtkPolyData* output)
{
  const vtkIdType np = static_cast<vtkIdType>(r.PointSource.size());
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(np);
  float* n = normals->GetPointer(0);
  ForPoints(multiThreaded, np, [&](vtkIdType b, vtkIdType e) {
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

/// "Colors": the grey of the middle of the cell's diffuse reflectance range.
void AddColors(const plod::OctreeView& v, const plod::PatchResult& r, vtkPolyData* output)
{
  const vtkIdType np = static_cast<vtkIdType>(r.PointSource.size());
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    const float* d = &v.DiffuseRange[2 * NodeOf(v, r.PointSource[i])];
    const double kd = std::min(1.0, std::max(0.0, 0.5 * (double(d[0]) + d[1])));
    const unsigned char g = static_cast<unsigned char>(std::lround(255.0 * kd));
    colors->SetTypedTuple(i, std::array<unsigned char, 3>{ g, g, g }.data());
  }
  output->GetPointData()->SetScalars(colors);
}

/// "OctreeNode": the node of each output point.
void AddNodeIds(const plod::OctreeView& v, const plod::PatchResult& r, vtkPolyData* output)
{
  const vtkIdType np = static_cast<vtkIdType>(r.PointSource.size());
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("OctreeNode");
  ids->SetNumberOfTuples(np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    ids->SetValue(i, NodeOf(v, r.PointSource[i]));
  }
  output->GetPointData()->AddArray(ids);
}

/// "InputPointId": an opened leaf's point's input point, -1 for a cluster's vertex.
void AddInputPointIds(const plod::OctreeView& v, const plod::PatchResult& r, vtkPolyData* output)
{
  const vtkIdType np = static_cast<vtkIdType>(r.PointSource.size());
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
}

//------------------------------------------------------------------------------
int vtkMultiscalePatchGenerator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiscaleOctree* input = vtkMultiscaleOctree::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  this->RecordFigures(plod::PatchResult(), 0);
  if (!input || input->GetNumberOfNodes() == 0)
  {
    return 1;
  }
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  std::string why;
  plod::OctreeView v;
  vtkMTimeType checked = 0; // changes whenever the octree's arrays do
  if (!input->GetCheckedView(v, &checked, &why))
  {
    vtkErrorMacro("The input octree is invalid (" << why << "): empty output.");
    return 1;
  }
  const uint8_t* state = this->TakeCut(input, v);
  plod::PatchResult& r = this->Internal->Result; // its vectors keep their capacity
  auto* mask = vtkUnsignedCharArray::SafeDownCast(
    input->GetNodeData()->GetAbstractArray(vtkMultiscaleOctree::CullMaskArrayName()));
  const bool hasMask =
    mask && mask->GetNumberOfComponents() == 1 && mask->GetNumberOfTuples() == v.NumberOfNodes;
  this->Internal->Workspace.Memo = input->GetCornerMemo(); // shared with the selector's count
  if (!plod::GeneratePatches(v, state, hasMask ? mask->GetPointer(0) : nullptr, r, &why,
        &this->Internal->Workspace, this->MakeOptions(input, checked)))
  {
    vtkErrorMacro("Invalid cut: " << why << ". Empty output.");
    return 1;
  }
  this->UpdateProgress(0.5);
  MakePoints(v, r, this->MultiThreaded, output);
  MakeTriangles(r, output);
  if (this->GenerateNormals)
  {
    AddNormals(v, r, this->MultiThreaded, output);
  }
  if (this->GenerateColors)
  {
    AddColors(v, r, output);
  }
  if (this->GenerateNodeIds)
  {
    AddNodeIds(v, r, output);
  }
  if (this->GenerateInputPointIds)
  {
    AddInputPointIds(v, r, output);
  }
  // the pages read here, and the output index per cluster, within the reader's CacheLimit
  Internals& I = *this->Internal;
  if (!I.Held || I.HeldView != checked)
  {
    I.Held = std::make_shared<std::atomic<uint64_t>>(0);
    I.HeldView = checked;
  }
  I.Held->store(I.Workspace.OutputOf.capacity() * sizeof(int32_t), std::memory_order_relaxed);
  input->CountHeldBytes(I.Held);
  input->EnforceResidentLimit();
  timer->StopTimer();
  this->RecordFigures(r, timer->GetElapsedTime());
  return 1;
}

//------------------------------------------------------------------------------
const uint8_t* vtkMultiscalePatchGenerator::TakeCut(
  vtkMultiscaleOctree* input, const plod::OctreeView& v)
{
  auto* cut = vtkUnsignedCharArray::SafeDownCast(
    input->GetNodeData()->GetAbstractArray(vtkMultiscaleOctree::CutStateArrayName()));
  if (cut && cut->GetNumberOfComponents() == 1 && cut->GetNumberOfTuples() == v.NumberOfNodes)
  {
    return cut->GetPointer(0);
  }
  if (cut)
  {
    vtkWarningMacro("CutState array has the wrong size or type: drawing full resolution.");
  }
  this->Internal->FullCut.resize(v.NumberOfNodes);
  plod::UniformCut(v, -1, this->Internal->FullCut.data());
  return this->Internal->FullCut.data();
}

//------------------------------------------------------------------------------
plod::PatchOptions vtkMultiscalePatchGenerator::MakeOptions(
  vtkMultiscaleOctree* input, vtkMTimeType checked)
{
  plod::PatchOptions options;
  // each corner starts from where its walk ended last frame, while the octree is the same
  options.OctreeStamp = checked;
  options.Folds = static_cast<plod::FoldHandling>(this->FoldHandling);
  // back faces culled per triangle when the selector hid back-facing cells (CutView)
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
  return options;
}

//------------------------------------------------------------------------------
void vtkMultiscalePatchGenerator::RecordFigures(const plod::PatchResult& r, double seconds)
{
  this->GenerateTime = seconds;
  this->NumberOfTriangles = static_cast<vtkIdType>(r.Triangles.size() / 3);
  this->NumberOfOutputPoints = static_cast<vtkIdType>(r.PointSource.size());
  this->NodesVisited = r.NodesVisited;
  this->NumberOfFolds = r.Folds;
  this->NumberOfCulledBackFaces = r.BackFacesCulled;
  this->NumberOfGhostTriangles = r.GhostSkipped;
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
