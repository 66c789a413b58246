// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctreeBuilder.h"
#include "vtkPerceptualLODSMP.h"

#include "plodBuildUtil.h"
#include "plodOctreeBuilder.h"
#include "plodPLYRead.h"
#include "plodPieceAssembly.h"
#include "plodPieces.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiscaleOctree.h"
#include "vtkMultiscaleOctreeReader.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkUnsignedCharArray.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkMultiscaleOctreeBuilder);

namespace
{
/// Share of the progress of a build from a file that its reading takes.
constexpr double ReadShare = 0.25;
}

namespace
{
/// Triangles of the polygons and strips of a vtkPolyData, with the cell id of each.
void CollectTriangles(
  vtkPolyData* pd, plod::LargeVector<int64_t>& tris, plod::LargeVector<vtkIdType>& cellOf)
{
  const vtkIdType base = pd->GetNumberOfVerts() + pd->GetNumberOfLines();
  vtkIdType cellId = base;
  auto polys = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cellId)
  {
    vtkIdType n;
    const vtkIdType* ids;
    polys->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      tris.push_back(ids[0]);
      tris.push_back(ids[k]);
      tris.push_back(ids[k + 1]);
      cellOf.push_back(cellId);
    }
  }
  auto strips = vtk::TakeSmartPointer(pd->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k + 2 < n; ++k)
    {
      // every other triangle of a strip is reversed to keep a consistent orientation
      const bool odd = (k & 1) != 0;
      tris.push_back(ids[k]);
      tris.push_back(odd ? ids[k + 2] : ids[k + 1]);
      tris.push_back(odd ? ids[k + 1] : ids[k + 2]);
      cellOf.push_back(cellId);
    }
  }
}

}

/// The input arrays the builder copies (those it cannot use in place), which back the pointers
/// of a plod::BuildInput until the build ends, and how triangles map to cells.
struct vtkMultiscaleOctreeBuilder::InputCopies
{
  plod::LargeVector<double> Points;
  plod::LargeVector<int64_t> Triangles;        ///< split polygons and strips
  plod::LargeVector<vtkIdType> CellOfTriangle; ///< the cell of each split triangle
  vtkIdType FirstPolygonCell = 0; ///< cell id of the first polygon (in-place triangles)
  bool TrianglesInPlace = false;
  plod::LargeVector<float> Normals;
  plod::LargeVector<double> Viewpoints;
  plod::LargeVector<uint8_t> Ghosts;
  std::vector<float> PointDiffuse, PointSpecular, TriangleDiffuse, TriangleSpecular;
  bool HasMaterial = false;
};

//------------------------------------------------------------------------------
vtkMultiscaleOctreeBuilder::vtkMultiscaleOctreeBuilder()
  : FileName(nullptr)
  , FinestLevel(-1)
  , EstimatedMemory(0.0)
  , VertexRule(VERTEX_QEF)
  , DiffuseArrayName(nullptr)
  , SpecularArrayName(nullptr)
  , UniformDiffuse(1.0)
  , UniformSpecular(0.0)
  , ViewpointArrayName(nullptr)
  , UseViewpoint(false)
  , MemoryLimit(0.0)
  , MultiThreaded(true)
  , UseGivenRootCube(false)
  , RootCubeEdge(0.0)
  , NumberOfSkippedTriangles(0)
  , NumberOfInvalidTriangles(0)
  , NumberOfDegenerateTriangles(0)
  , NumberOfInputTriangles(0)
  , NumberOfUnsafeNodes(0)
  , NumberOfGhostPoints(0)
  , BuildTime(0.0)
  , ReadTime(0.0)
{
  this->Viewpoint[0] = this->Viewpoint[1] = this->Viewpoint[2] = 0.0;
  this->RootCubeOrigin[0] = this->RootCubeOrigin[1] = this->RootCubeOrigin[2] = 0.0;
}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeBuilder::~vtkMultiscaleOctreeBuilder()
{
  this->SetFileName(nullptr);
  this->SetOctreeFileName(nullptr);
  this->SetDiffuseArrayName(nullptr);
  this->SetSpecularArrayName(nullptr);
  this->SetViewpointArrayName(nullptr);
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::GetMaximumFinestLevel()
{
  return plod::MaxFinestLevel;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctreeBuilder::ComputeRootCube(
  const double bounds[6], double origin[3], double* edge)
{
  if (!bounds || !origin || !edge)
  {
    return false;
  }
  const double lo[3] = { bounds[0], bounds[2], bounds[4] };
  const double hi[3] = { bounds[1], bounds[3], bounds[5] };
  for (int a = 0; a < 3; ++a)
  {
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]) || lo[a] > hi[a])
    {
      return false;
    }
  }
  double o[3], e = 0.0;
  if (!plod::build::PlaceRootCube(lo, hi, o, e, nullptr))
  {
    return false;
  }
  std::copy(o, o + 3, origin);
  *edge = e;
  return true;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(
  const long long cellsPerLevel[22], long long numberOfPoints, bool cloud)
{
  static_assert(plod::MaxFinestLevel + 1 == 22, "one count per level 0..21");
  if (!cellsPerLevel)
  {
    return -1;
  }
  int64_t cells[plod::MaxFinestLevel + 1];
  for (int l = 0; l <= plod::MaxFinestLevel; ++l)
  {
    cells[l] = static_cast<int64_t>(cellsPerLevel[l]);
  }
  return plod::ChooseFinestLevelFromCounts(cells, static_cast<int64_t>(numberOfPoints), cloud);
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1); // FileName instead
  return 1;
}

//------------------------------------------------------------------------------
double vtkMultiscaleOctreeBuilder::GetEffectiveMemoryLimit()
{
  if (this->MemoryLimit > 0)
  {
    return this->MemoryLimit;
  }
  // GetHostMemoryTotal queries the system itself (GetTotalPhysicalMemory reads a value that
  // only RunMemoryCheck fills in, and was 0 here, which gave the 4 GiB fallback everywhere)
  vtksys::SystemInformation info;
  const double totalKiB = static_cast<double>(info.GetHostMemoryTotal());
  return totalKiB > 0 ? 0.75 * totalKiB / 1024.0 : 4096.0;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkMultiscaleOctreeBuilder::TakeSurfaceCells(vtkPointSet* input)
{
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->SetPoints(input->GetPoints());
  surface->GetPointData()->ShallowCopy(input->GetPointData());
  vtkNew<vtkCellArray> polys, strips;
  vtkNew<vtkIdList> kept, stripCells;
  vtkNew<vtkIdList> ids;
  vtkNew<vtkGenericCell> cell;
  vtkIdType volume = 0, other = 0;
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    const int type = input->GetCellType(c);
    input->GetCellPoints(c, ids);
    if (type == VTK_TRIANGLE || type == VTK_QUAD || type == VTK_POLYGON)
    {
      polys->InsertNextCell(ids);
      kept->InsertNextId(c);
    }
    else if (type == VTK_PIXEL && ids->GetNumberOfIds() == 4)
    {
      // a pixel's points are in raster order: as a polygon, 0 1 3 2
      polys->InsertNextCell({ ids->GetId(0), ids->GetId(1), ids->GetId(3), ids->GetId(2) });
      kept->InsertNextId(c);
    }
    else if (type == VTK_TRIANGLE_STRIP)
    {
      strips->InsertNextCell(ids);
      stripCells->InsertNextId(c);
    }
    else if ((input->GetCell(c, cell), cell->GetCellDimension() == 3))
    {
      ++volume;
    }
    else
    {
      ++other;
    }
  }
  surface->SetPolys(polys);
  surface->SetStrips(strips);
  // cell data in vtkPolyData's order: polygons, then strips
  vtkCellData* in = input->GetCellData();
  vtkCellData* out = surface->GetCellData();
  out->CopyAllocate(in, kept->GetNumberOfIds() + stripCells->GetNumberOfIds());
  vtkIdType next = 0;
  for (vtkIdList* list : { kept.GetPointer(), stripCells.GetPointer() })
  {
    for (vtkIdType k = 0; k < list->GetNumberOfIds(); ++k)
    {
      out->CopyData(in, list->GetId(k), next++);
    }
  }
  vtkWarningMacro(<< "The input is a " << input->GetClassName() << ", not a vtkPolyData: its "
                  << polys->GetNumberOfCells() + strips->GetNumberOfCells()
                  << " surface cells (triangles, quads, polygons, strips) are built"
                  << (volume > 0 ? "; " + std::to_string(volume) +
                           " volume cells are ignored (extract their boundary with "
                           "vtkGeometryFilter to build it)"
                                 : std::string())
                  << (other > 0
                         ? "; " + std::to_string(other) + " vertex and line cells are ignored"
                         : std::string())
                  << (polys->GetNumberOfCells() + strips->GetNumberOfCells() == 0
                         ? "; without surface cells its points are built as a point cloud"
                         : "")
                  << ".");
  return surface;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeBuilder::ReportIgnoredCells(vtkPolyData* input)
{
  if (input && input->GetNumberOfPolys() + input->GetNumberOfStrips() > 0 &&
    input->GetNumberOfVerts() + input->GetNumberOfLines() > 0)
  {
    vtkWarningMacro(<< "The input's " << input->GetNumberOfVerts() << " vertex and "
                    << input->GetNumberOfLines()
                    << " line cells are ignored: only its polygons and strips are built.");
  }
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctreeBuilder::CheckParameters()
{
  if (this->FinestLevel < -1 || this->FinestLevel > plod::MaxFinestLevel)
  {
    vtkErrorMacro("FinestLevel " << this->FinestLevel << " is outside [-1, " << plod::MaxFinestLevel
                                 << "] (-1 chooses it from the input).");
    return false;
  }
  if (!(this->MemoryLimit >= 0) || !std::isfinite(this->MemoryLimit))
  {
    vtkErrorMacro(
      "MemoryLimit must be a non-negative number of MiB (0: automatic), not " << this->MemoryLimit);
    return false;
  }
  if (!std::isfinite(this->UniformDiffuse) || !std::isfinite(this->UniformSpecular))
  {
    vtkErrorMacro("UniformDiffuse and UniformSpecular must be finite.");
    return false;
  }
  std::string cubeProblem;
  if (this->UseGivenRootCube &&
    !plod::build::ValidateRootCube(this->RootCubeOrigin, this->RootCubeEdge, &cubeProblem))
  {
    vtkErrorMacro("UseGivenRootCube: " << cubeProblem << ".");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = inputVector[0]->GetNumberOfInformationObjects() > 0
    ? vtkPointSet::GetData(inputVector[0])
    : nullptr;
  vtkMultiscaleOctree* output = vtkMultiscaleOctree::GetData(outputVector);
  if (!output)
  {
    vtkErrorMacro("No output octree.");
    return 0;
  }
  output->Initialize();
  this->NumberOfSkippedTriangles = 0;
  this->NumberOfInvalidTriangles = 0;
  this->NumberOfDegenerateTriangles = 0;
  this->NumberOfInputTriangles = 0;
  this->NumberOfUnsafeNodes = 0;
  this->NumberOfGhostPoints = 0;
  this->FinestLevelReason.clear();
  this->BuildTime = 0.0;
  this->ReadTime = 0.0;
  this->EstimatedMemory = 0.0;
  if (!this->CheckParameters())
  {
    return 0;
  }
  if (this->FileName && *this->FileName)
  {
    if (input)
    {
      vtkErrorMacro("Both an input and a FileName ('"
        << this->FileName << "') are set: remove the input connection or set FileName to "
        << "nullptr. Empty octree.");
      return 1;
    }
    return this->BuildFromFile(output);
  }
  if (!input || input->GetNumberOfPoints() == 0)
  {
    vtkDebugMacro("Empty input: empty octree.");
    return 1;
  }
  // a point set whose cells are not a vtkPolyData's (an unstructured grid of triangles, say):
  // its surface cells are what is built, not a cloud of its points
  vtkSmartPointer<vtkPolyData> surfaceCells;
  if (!vtkPolyData::SafeDownCast(input) && input->GetNumberOfCells() > 0)
  {
    surfaceCells = this->TakeSurfaceCells(input);
    input = surfaceCells;
  }
  this->ReportIgnoredCells(vtkPolyData::SafeDownCast(input));

  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  plod::BuildInput in;
  InputCopies copies;
  this->TakePoints(input, in, copies);
  this->TakeTriangles(input, in, copies);
  this->NumberOfInputTriangles = in.NumberOfTriangles;
  if (!this->TakeNormals(input, in, copies) || !this->TakeViewpoints(input, in, copies) ||
    !this->TakeGhosts(input, in, copies) || !this->TakeMaterial(input, in, copies))
  {
    return 1;
  }
  in.UniformDiffuse = static_cast<float>(this->UniformDiffuse);
  in.UniformSpecular = static_cast<float>(this->UniformSpecular);
  timer->StopTimer();
  this->ReadTime = timer->GetElapsedTime();
  auto progress = [this](double f) {
    this->UpdateProgress(f);
    return !this->GetAbortExecute();
  };
  return this->RunBuild(
    in, copies.HasMaterial, this->GetEffectiveMemoryLimit() * 1024.0 * 1024.0, progress, output);
}

//------------------------------------------------------------------------------
// The input's arrays, each checked against what it describes before the kernel reads it. Arrays
// of the types the kernel takes are used in place; the others are copied into `copies`.

void vtkMultiscaleOctreeBuilder::ReportLengthError(const char* what, const char* name,
  vtkIdType has, int components, vtkIdType needs, const char* per)
{
  vtkErrorMacro(<< what << " array '" << (name ? name : "") << "' has " << has << " tuple(s) of "
                << components << " component(s); it needs " << needs << " (one per " << per
                << "). Empty octree.");
}

void vtkMultiscaleOctreeBuilder::TakePoints(
  vtkPointSet* input, plod::BuildInput& in, InputCopies& copies)
{
  const vtkIdType np = input->GetNumberOfPoints();
  in.NumberOfPoints = np;
  vtkDataArray* pts = input->GetPoints()->GetData();
  if (pts->GetNumberOfComponents() == 3 && pts->GetDataType() == VTK_DOUBLE)
  {
    in.Points = static_cast<const double*>(pts->GetVoidPointer(0));
  }
  else if (pts->GetNumberOfComponents() == 3 && pts->GetDataType() == VTK_FLOAT)
  {
    in.PointsFloat = static_cast<const float*>(pts->GetVoidPointer(0));
  }
  else
  {
    copies.Points.resize(3 * np);
    for (vtkIdType i = 0; i < np; ++i)
    {
      pts->GetTuple(i, &copies.Points[3 * i]);
    }
    in.Points = copies.Points.data();
  }
}

void vtkMultiscaleOctreeBuilder::TakeTriangles(
  vtkPointSet* input, plod::BuildInput& in, InputCopies& copies)
{
  // a triangle-only polygon array is used in place; other polygons and strips are split
  vtkPolyData* pd = vtkPolyData::SafeDownCast(input);
  if (!pd)
  {
    return;
  }
  copies.FirstPolygonCell = pd->GetNumberOfVerts() + pd->GetNumberOfLines();
  vtkCellArray* polys = pd->GetPolys();
  if (pd->GetNumberOfStrips() == 0 && polys->GetNumberOfCells() > 0 && polys->IsHomogeneous() == 3)
  {
    copies.TrianglesInPlace = true;
    in.NumberOfTriangles = polys->GetNumberOfCells();
    if (polys->IsStorage64Bit())
    {
      in.Triangles =
        reinterpret_cast<const int64_t*>(polys->GetConnectivityArray64()->GetPointer(0));
    }
    else
    {
      in.Triangles32 =
        reinterpret_cast<const int32_t*>(polys->GetConnectivityArray32()->GetPointer(0));
    }
    return;
  }
  CollectTriangles(pd, copies.Triangles, copies.CellOfTriangle);
  in.NumberOfTriangles = static_cast<int64_t>(copies.Triangles.size() / 3);
  in.Triangles = copies.Triangles.empty() ? nullptr : copies.Triangles.data();
}

bool vtkMultiscaleOctreeBuilder::TakeNormals(
  vtkPointSet* input, plod::BuildInput& in, InputCopies& copies)
{
  // a mesh's shading normals, or a cloud's orientation
  vtkDataArray* n = input->GetPointData()->GetNormals();
  if (!n)
  {
    return true;
  }
  const vtkIdType np = input->GetNumberOfPoints();
  if (n->GetNumberOfComponents() != 3 || n->GetNumberOfTuples() != np)
  {
    this->ReportLengthError(
      "Normals", n->GetName(), n->GetNumberOfTuples(), n->GetNumberOfComponents(), np, "point");
    return false;
  }
  copies.Normals.resize(3 * np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    double t[3];
    n->GetTuple(i, t);
    for (int a = 0; a < 3; ++a)
    {
      copies.Normals[3 * i + a] = static_cast<float>(t[a]);
    }
  }
  in.PointNormals = copies.Normals.data();
  return true;
}

bool vtkMultiscaleOctreeBuilder::TakeViewpoints(
  vtkPointSet* input, plod::BuildInput& in, InputCopies& copies)
{
  if (in.NumberOfTriangles > 0) // meshes: no orientation to estimate
  {
    return true;
  }
  in.HasViewpoint = this->UseViewpoint;
  std::copy(this->Viewpoint, this->Viewpoint + 3, in.Viewpoint);
  if (!this->ViewpointArrayName)
  {
    return true;
  }
  vtkDataArray* v = input->GetPointData()->GetArray(this->ViewpointArrayName);
  const vtkIdType np = input->GetNumberOfPoints();
  if (!v)
  {
    vtkWarningMacro("Viewpoint array '" << this->ViewpointArrayName
                                        << "' not found: normals oriented without it.");
    return true;
  }
  if (v->GetNumberOfComponents() != 3 || v->GetNumberOfTuples() != np)
  {
    this->ReportLengthError("Viewpoint", this->ViewpointArrayName, v->GetNumberOfTuples(),
      v->GetNumberOfComponents(), np, "point");
    return false;
  }
  copies.Viewpoints.resize(3 * np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    v->GetTuple(i, &copies.Viewpoints[3 * i]);
  }
  in.PointViewpoints = copies.Viewpoints.data();
  return true;
}

bool vtkMultiscaleOctreeBuilder::TakeGhosts(
  vtkPointSet* input, plod::BuildInput& in, InputCopies& copies)
{
  // distributed rendering: VTK's point ghost array, bit DUPLICATEPOINT
  vtkAbstractArray* g =
    input->GetPointData()->GetAbstractArray(vtkDataSetAttributes::GhostArrayName());
  if (!g)
  {
    return true;
  }
  const vtkIdType np = input->GetNumberOfPoints();
  auto* flags = vtkUnsignedCharArray::SafeDownCast(g);
  if (!flags || flags->GetNumberOfComponents() != 1 || flags->GetNumberOfTuples() != np)
  {
    vtkErrorMacro("Ghost array '" << vtkDataSetAttributes::GhostArrayName() << "' has "
                                  << g->GetNumberOfTuples() << " tuple(s) of "
                                  << g->GetNumberOfComponents() << " component(s) of type "
                                  << g->GetDataTypeAsString() << "; it needs " << np
                                  << " unsigned char values (one per point). Empty octree.");
    return false;
  }
  copies.Ghosts.resize(np);
  const unsigned char* f = flags->GetPointer(0);
  for (vtkIdType i = 0; i < np; ++i)
  {
    copies.Ghosts[i] = (f[i] & vtkDataSetAttributes::DUPLICATEPOINT) ? 1 : 0;
  }
  in.PointGhost = copies.Ghosts.data();
  return true;
}

bool vtkMultiscaleOctreeBuilder::TakeMaterial(
  vtkPointSet* input, plod::BuildInput& in, InputCopies& copies)
{
  return this->TakeMaterialArray(input, this->DiffuseArrayName, copies.PointDiffuse,
           copies.TriangleDiffuse, in.PointDiffuse, in.TriangleDiffuse, in, copies) &&
    this->TakeMaterialArray(input, this->SpecularArrayName, copies.PointSpecular,
      copies.TriangleSpecular, in.PointSpecular, in.TriangleSpecular, in, copies);
}

bool vtkMultiscaleOctreeBuilder::TakeMaterialArray(vtkPointSet* input, const char* name,
  std::vector<float>& pointValues, std::vector<float>& triangleValues, const float*& pointOut,
  const float*& triangleOut, const plod::BuildInput& in, InputCopies& copies)
{
  if (!name)
  {
    return true;
  }
  const vtkIdType np = input->GetNumberOfPoints();
  if (vtkDataArray* a = input->GetPointData()->GetArray(name))
  {
    if (a->GetNumberOfTuples() != np || a->GetNumberOfComponents() < 1)
    {
      this->ReportLengthError(
        "Point material", name, a->GetNumberOfTuples(), a->GetNumberOfComponents(), np, "point");
      return false;
    }
    pointValues.resize(np);
    for (vtkIdType i = 0; i < np; ++i)
    {
      pointValues[i] = static_cast<float>(a->GetComponent(i, 0));
    }
    pointOut = pointValues.data();
    copies.HasMaterial = true;
    return true;
  }
  vtkDataArray* c = in.NumberOfTriangles == 0 ? nullptr : input->GetCellData()->GetArray(name);
  if (!c)
  {
    vtkWarningMacro("Material array '" << name << "' not found: uniform value used.");
    return true;
  }
  const vtkIdType cells = input->GetNumberOfCells();
  if (c->GetNumberOfTuples() != cells || c->GetNumberOfComponents() < 1)
  {
    this->ReportLengthError(
      "Cell material", name, c->GetNumberOfTuples(), c->GetNumberOfComponents(), cells, "cell");
    return false;
  }
  triangleValues.resize(in.NumberOfTriangles);
  for (vtkIdType t = 0; t < in.NumberOfTriangles; ++t)
  {
    const vtkIdType cell =
      copies.TrianglesInPlace ? copies.FirstPolygonCell + t : copies.CellOfTriangle[t];
    triangleValues[t] = static_cast<float>(c->GetComponent(cell, 0));
  }
  triangleOut = triangleValues.data();
  copies.HasMaterial = true;
  return true;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::BuildFromFile(vtkMultiscaleOctree* output)
{
  constexpr double MiB = 1024.0 * 1024.0;
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  const std::string file = this->FileName;
  std::string why;
  plod::PLYSummary header;
  if (!plod::ReadPLYHeader(file, &why, &header))
  {
    vtkErrorMacro("Cannot build from '" << file << "' (FileName takes a PLY file): " << why
                                        << ". Empty octree.");
    return 1;
  }
  // what the build needs at the least (its coarsest levels), the mesh's arrays included
  const double limit = this->GetEffectiveMemoryLimit() * MiB;
  const double meshBytes = plod::EstimatePLYMeshBytes(header);
  const bool cloud = header.NumberOfFaces == 0;
  const double least =
    meshBytes + plod::LeastBuildMemory(header.NumberOfVertices, header.NumberOfFaces, cloud);
  const bool octreeFile = this->OctreeFileName && *this->OctreeFileName;
  if (octreeFile && !cloud && (least > limit || this->BuildInPieces))
  {
    return this->BuildFromFileInPieces(output);
  }
  if (least > limit)
  {
    const double perItem =
      least / double(std::max<int64_t>(1, cloud ? header.NumberOfVertices : header.NumberOfFaces));
    vtkErrorMacro(<< "'" << file << "' holds " << header.NumberOfVertices << " points and "
                  << header.NumberOfFaces << " faces: building it in memory needs at least "
                  << std::llround(least / MiB) << " MiB (the mesh " << std::llround(meshBytes / MiB)
                  << " MiB, the build the rest), "
                  << "more than the memory limit of " << std::llround(limit / MiB)
                  << " MiB. At about " << static_cast<long long>(perItem) << " bytes per "
                  << (cloud ? "point" : "face") << ", at most "
                  << static_cast<long long>(limit / perItem) << (cloud ? " points" : " faces")
                  << " fit; raise MemoryLimit on a machine with more memory, or set "
                  << "OctreeFileName to build it in pieces into that file. Nothing was read. "
                  << "Empty octree.");
    return 1;
  }
  plod::PLYMesh mesh;
  auto readProgress = [this](double f) {
    this->UpdateProgress(ReadShare * f);
    return !this->GetAbortExecute();
  };
  // the triangles may outgrow the header's one per face (polygons): bounded by what is left
  // once the build's least share is set aside
  const double buildLeast = least - meshBytes;
  if (!plod::ReadPLYMesh(file, &mesh, &why, readProgress, limit - buildLeast))
  {
    if (this->GetAbortExecute())
    {
      vtkWarningMacro("Build aborted while reading '" << file << "': empty octree.");
      return 1;
    }
    vtkErrorMacro("Cannot read '" << file << "': " << why << ". Empty octree.");
    return 1;
  }
  if (mesh.NumberOfPoints != header.NumberOfVertices || mesh.NumberOfFaces != header.NumberOfFaces)
  {
    vtkErrorMacro("'" << file << "' changed while it was read (its counts are no longer those of "
                      << "the header the memory estimate used). Empty octree.");
    return 1;
  }
  if (mesh.NumberOfShortFaces > 0)
  {
    vtkWarningMacro(<< "'" << file << "': " << mesh.NumberOfShortFaces << " of "
                    << mesh.NumberOfFaces
                    << " faces have fewer than 3 vertex indices and are not polygons; dropped.");
  }
  plod::BuildInput in;
  in.NumberOfPoints = mesh.NumberOfPoints;
  in.Points = mesh.PointsDouble.empty() ? nullptr : mesh.PointsDouble.data();
  in.PointsFloat = mesh.PointsFloat.empty() ? nullptr : mesh.PointsFloat.data();
  in.NumberOfTriangles = mesh.NumberOfTriangles();
  in.Triangles32 = mesh.Triangles.empty() ? nullptr : mesh.Triangles.data();
  in.PointNormals = mesh.Normals.empty() ? nullptr : mesh.Normals.data();
  in.UniformDiffuse = static_cast<float>(this->UniformDiffuse);
  in.UniformSpecular = static_cast<float>(this->UniformSpecular);
  in.HasViewpoint = this->UseViewpoint;
  std::copy(this->Viewpoint, this->Viewpoint + 3, in.Viewpoint);
  this->NumberOfInputTriangles = in.NumberOfTriangles;
  timer->StopTimer();
  this->ReadTime = timer->GetElapsedTime();
  if (in.NumberOfPoints == 0)
  {
    vtkDebugMacro("Empty file: empty octree.");
    return 1;
  }
  const double held = double(mesh.PointsFloat.capacity()) * sizeof(float) +
    double(mesh.PointsDouble.capacity()) * sizeof(double) +
    double(mesh.Normals.capacity()) * sizeof(float) +
    double(mesh.Triangles.capacity()) * sizeof(int32_t);
  auto buildProgress = [this](double f) {
    this->UpdateProgress(ReadShare + (1.0 - ReadShare) * f);
    return !this->GetAbortExecute();
  };
  if (held >= limit)
  {
    vtkErrorMacro(<< "'" << file << "': its arrays take " << std::llround(held / MiB)
                  << " MiB, the whole memory limit of " << std::llround(limit / MiB)
                  << " MiB, leaving nothing for the build. Empty octree.");
    return 1;
  }
  return this->RunBuild(in, false, limit - held, buildProgress, output);
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::BuildFromFileInPieces(vtkMultiscaleOctree* output)
{
  constexpr double MiB = 1024.0 * 1024.0;
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  const std::string file = this->FileName, octreeFile = this->OctreeFileName;
  // progress: the split's steps (reading the file, its passes, the merge) a third, the builds
  // most of the rest, the write the end; never backwards (a step may come again)
  double shown = 0;
  auto progress = [this, &shown](double f, const char* step) {
    constexpr int n = sizeof(plod::SplitSteps) / sizeof(plod::SplitSteps[0]);
    const std::string s = step;
    double at = 0.9, share = 0.1; // writing the file
    if (s == "building the pieces")
    {
      at = 1.0 / 3.0;
      share = 0.9 - at;
    }
    for (int k = 0; k < n; ++k)
    {
      if (s == plod::SplitSteps[k])
      {
        at = k / (3.0 * n);
        share = 1.0 / (3.0 * n);
      }
    }
    shown = std::max(shown, at + share * f);
    this->UpdateProgress(shown);
    return !this->GetAbortExecute();
  };
  plod::PiecesParameters split;
  split.MemoryLimit = this->GetEffectiveMemoryLimit() * MiB;
  const size_t slash = octreeFile.find_last_of('/');
  split.TemporaryDirectory = slash == std::string::npos
    ? std::string(".")
    : octreeFile.substr(0, std::max<size_t>(slash, 1));
  split.Progress = progress;
  split.Parallel = plodvtk::SMPRanges(this->MultiThreaded);
  plod::PLYPieces pieces;
  std::string why;
  if (!pieces.Open(file, split, &why))
  {
    if (this->GetAbortExecute())
    {
      vtkWarningMacro("Build aborted while splitting '" << file << "': empty octree.");
      return 1;
    }
    vtkErrorMacro("Cannot build '" << file << "' in pieces: " << why << ". Empty octree.");
    return 1;
  }
  timer->StopTimer();
  this->ReadTime = timer->GetElapsedTime(); // the split: the file read and put in pieces
  timer->StartTimer();
  if (this->FinestLevel >= 0 && this->FinestLevel != pieces.GetAgreement().FinestLevel)
  {
    vtkWarningMacro("Built in pieces at the file's own finest level "
      << pieces.GetAgreement().FinestLevel << ", not " << this->FinestLevel << ".");
  }
  plod::AssemblyParameters assembly;
  assembly.Rule = this->VertexRule == VERTEX_QEF ? plod::VertexRule::QEF : plod::VertexRule::Mean;
  assembly.MemoryLimit = split.MemoryLimit;
  assembly.Progress = progress;
  assembly.Parallel = split.Parallel;
  assembly.Layout = this->CompactOctreeFile ? plod::FileLayout::Compact : plod::FileLayout::Mapped;
  assembly.RemovePiecesAsBuilt = true; // the pieces are built once
  plod::AssemblyReport report;
  if (!plod::WriteOctreeFileFromPieces(pieces, octreeFile, assembly, &report, &why))
  {
    if (this->GetAbortExecute())
    {
      vtkWarningMacro("Build aborted while building '" << file << "' in pieces: empty octree.");
      return 1;
    }
    vtkErrorMacro("Cannot build '" << file << "' in pieces into '" << octreeFile << "': " << why
                                   << ". Empty octree.");
    return 1;
  }
  if (!report.StructureOnly.empty())
  {
    vtkWarningMacro("The levels above "
      << pieces.GetOwnershipLevel() << " of '" << octreeFile
      << "' hold structure only (a cut stops there): " << report.StructureOnly << ".");
  }
  vtkNew<vtkMultiscaleOctreeReader> reader;
  reader->SetFileName(octreeFile.c_str());
  reader->Update();
  if (reader->GetOutput()->GetNumberOfNodes() == 0)
  {
    vtkErrorMacro("The octree file '" << octreeFile << "' built in pieces does not read back: "
                                      << reader->GetErrorMessage() << ". Empty octree.");
    return 1;
  }
  output->ShallowCopy(reader->GetOutput());
  this->NumberOfInputTriangles = pieces.GetNumberOfUsableTriangles();
  this->NumberOfSkippedTriangles = pieces.GetAgreement().NumberOfSkippedTriangles;
  this->FinestLevelReason = "built in " + std::to_string(pieces.GetNumberOfPieces()) +
    " pieces of level " + std::to_string(pieces.GetOwnershipLevel()) +
    ", at the level the pieces agreed on";
  timer->StopTimer();
  this->BuildTime = timer->GetElapsedTime(); // the pieces' builds and the file
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeBuilder::RunBuild(const plod::BuildInput& in, bool hasMaterial,
  double memoryLimit, const std::function<bool(double)>& progress, vtkMultiscaleOctree* output)
{
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  plod::BuildParameters params;
  params.FinestLevel = this->FinestLevel;
  params.Rule = this->VertexRule == VERTEX_QEF ? plod::VertexRule::QEF : plod::VertexRule::Mean;
  params.MemoryLimit = memoryLimit;
  params.HasRootCube = this->UseGivenRootCube;
  std::copy(this->RootCubeOrigin, this->RootCubeOrigin + 3, params.RootOrigin);
  params.RootEdge = this->RootCubeEdge;

  const plod::ParallelFor pfor = plodvtk::SMPRanges(this->MultiThreaded);
  plod::Allocator allocate;
  allocate.Nodes = [output](int64_t nodes, int64_t points, int64_t triangles) {
    output->Allocate(static_cast<vtkIdType>(nodes), static_cast<vtkIdType>(points),
      static_cast<vtkIdType>(triangles));
    plod::OctreeArrays arrays;
    output->GetArrays(arrays);
    return arrays;
  };
  allocate.Clusters = [output](int64_t clusters, plod::OctreeArrays& arrays) {
    output->AllocateClusters(static_cast<vtkIdType>(clusters));
    output->GetArrays(arrays);
  };
  allocate.PointGhost = [output](int64_t, plod::OctreeArrays& arrays) {
    output->AllocatePointGhosts();
    output->GetArrays(arrays);
  };

  const plod::BuildResult result = plod::BuildOctree(in, params, allocate, pfor, progress);
  timer->StopTimer();
  this->BuildTime = timer->GetElapsedTime();
  this->NumberOfInvalidTriangles = result.NumberOfInvalidTriangles;
  this->NumberOfDegenerateTriangles = result.NumberOfDegenerateTriangles;
  this->NumberOfSkippedTriangles =
    result.NumberOfInvalidTriangles + result.NumberOfDegenerateTriangles;
  this->NumberOfUnsafeNodes = result.NumberOfUnsafeNodes;
  this->NumberOfGhostPoints = result.NumberOfGhostPoints;
  this->EstimatedMemory = result.EstimatedBytes;
  this->FinestLevelReason = result.LevelReason;
  for (const std::string& w : result.Warnings)
  {
    vtkWarningMacro(<< w << ".");
  }
  if (!result.Ok)
  {
    output->Initialize();
    if (result.Aborted)
    {
      vtkWarningMacro("Build aborted: empty octree.");
      return 1;
    }
    vtkErrorMacro("Cannot build the octree: " << result.Error << ". Empty octree.");
    return 1;
  }
  output->SetGeometry(result.Origin, result.RootEdge, result.FinestLevel);
  output->SetHasMaterialArrays(hasMaterial);
  output->SetNumberOfBoundaryEdges(result.NumberOfBoundaryEdges);
  output->SetNumberOfNonManifoldEdges(result.NumberOfNonManifoldEdges);
  output->SetNumberOfMisorientedEdges(result.NumberOfMisorientedEdges);
  if (result.NumberOfMisorientedEdges > 0)
  {
    vtkWarningMacro(<< "The input's triangles are not consistently oriented: "
                    << result.NumberOfMisorientedEdges
                    << " edges are used by two triangles in the same direction. Back faces "
                       "will be drawn (hiding them would open see-through holes); orient the "
                       "mesh consistently (vtkPolyDataNormals with ConsistencyOn) to hide them.");
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeBuilder::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "OctreeFileName: " << (this->OctreeFileName ? this->OctreeFileName : "(none)")
     << "\n";
  os << indent << "BuildInPieces: " << (this->BuildInPieces ? "On" : "Off") << "\n";
  os << indent << "FinestLevel: " << this->FinestLevel << "\n";
  os << indent << "VertexRule: " << (this->VertexRule == VERTEX_QEF ? "QEF" : "Mean") << "\n";
  os << indent
     << "DiffuseArrayName: " << (this->DiffuseArrayName ? this->DiffuseArrayName : "(none)")
     << "\n";
  os << indent
     << "SpecularArrayName: " << (this->SpecularArrayName ? this->SpecularArrayName : "(none)")
     << "\n";
  os << indent << "UniformDiffuse: " << this->UniformDiffuse << "\n";
  os << indent << "UniformSpecular: " << this->UniformSpecular << "\n";
  os << indent
     << "ViewpointArrayName: " << (this->ViewpointArrayName ? this->ViewpointArrayName : "(none)")
     << "\n";
  os << indent << "Viewpoint: (" << this->Viewpoint[0] << ", " << this->Viewpoint[1] << ", "
     << this->Viewpoint[2] << ")\n";
  os << indent << "UseViewpoint: " << (this->UseViewpoint ? "On" : "Off") << "\n";
  os << indent << "MemoryLimit: " << this->MemoryLimit << " MiB (0: automatic, now "
     << this->GetEffectiveMemoryLimit() << " MiB)\n";
  os << indent << "MultiThreaded: " << (this->MultiThreaded ? "On" : "Off") << "\n";
  os << indent << "UseGivenRootCube: " << (this->UseGivenRootCube ? "On" : "Off") << "\n";
  os << indent << "RootCubeOrigin: (" << this->RootCubeOrigin[0] << ", " << this->RootCubeOrigin[1]
     << ", " << this->RootCubeOrigin[2] << ")\n";
  os << indent << "RootCubeEdge: " << this->RootCubeEdge << "\n";
  os << indent << "NumberOfInputTriangles: " << this->NumberOfInputTriangles << "\n";
  os << indent << "NumberOfSkippedTriangles: " << this->NumberOfSkippedTriangles << "\n";
  os << indent << "NumberOfInvalidTriangles: " << this->NumberOfInvalidTriangles << "\n";
  os << indent << "NumberOfDegenerateTriangles: " << this->NumberOfDegenerateTriangles << "\n";
  os << indent << "NumberOfUnsafeNodes: " << this->NumberOfUnsafeNodes << "\n";
  os << indent << "NumberOfGhostPoints: " << this->NumberOfGhostPoints << "\n";
  os << indent << "FinestLevelReason: " << this->FinestLevelReason << "\n";
  os << indent << "BuildTime: " << this->BuildTime << " s\n";
  os << indent << "EstimatedMemory: " << this->EstimatedMemory / 1e6 << " MB\n";
}
