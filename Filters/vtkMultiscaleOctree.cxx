// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctree.h"

#include "plodCut.h"
#include "plodOctree.h"

#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkMultiscaleOctree);

namespace
{
template <typename ArrayT>
ArrayT* FetchArray(vtkFieldData* fd, const char* name, int comps, vtkIdType n)
{
  ArrayT* a = ArrayT::SafeDownCast(fd->GetAbstractArray(name));
  if (!a || a->GetNumberOfComponents() != comps || a->GetNumberOfTuples() != n)
  {
    return nullptr;
  }
  return a;
}
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree::vtkMultiscaleOctree()
  : NodeData(vtkFieldData::New())
  , SurfaceData(vtkFieldData::New())
  , ClusterData(vtkFieldData::New())
  , RootEdge(1.0)
  , FinestLevel(0)
  , HasMaterialArrays(false)
{
  this->Origin[0] = this->Origin[1] = this->Origin[2] = 0.0;
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree::~vtkMultiscaleOctree()
{
  this->NodeData->Delete();
  this->SurfaceData->Delete();
  this->ClusterData->Delete();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::Initialize()
{
  this->Superclass::Initialize();
  this->NodeData->Initialize();
  this->SurfaceData->Initialize();
  this->ClusterData->Initialize();
  this->Origin[0] = this->Origin[1] = this->Origin[2] = 0.0;
  this->RootEdge = 1.0;
  this->FinestLevel = 0;
  this->HasMaterialArrays = false;
  this->NumberOfBoundaryEdges = 0;
  this->NumberOfNonManifoldEdges = 0;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::ShallowCopy(vtkDataObject* src)
{
  if (auto* o = vtkMultiscaleOctree::SafeDownCast(src))
  {
    this->NodeData->ShallowCopy(o->NodeData);
    this->SurfaceData->ShallowCopy(o->SurfaceData);
    this->ClusterData->ShallowCopy(o->ClusterData);
    std::copy(o->Origin, o->Origin + 3, this->Origin);
    this->RootEdge = o->RootEdge;
    this->FinestLevel = o->FinestLevel;
    this->HasMaterialArrays = o->HasMaterialArrays;
    this->NumberOfBoundaryEdges = o->NumberOfBoundaryEdges;
    this->NumberOfNonManifoldEdges = o->NumberOfNonManifoldEdges;
    // the same arrays: the source's check holds for the copy
    this->CheckedKey = o->CheckedKey;
    this->CheckedValid = o->CheckedValid;
    this->CheckedResult = o->CheckedResult;
    this->CheckedWhy = o->CheckedWhy;
    this->CheckedView = o->CheckedView;
    this->CheckedStamp = o->CheckedStamp;
  }
  this->Superclass::ShallowCopy(src);
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::DeepCopy(vtkDataObject* src)
{
  if (auto* o = vtkMultiscaleOctree::SafeDownCast(src))
  {
    this->NodeData->DeepCopy(o->NodeData);
    this->SurfaceData->DeepCopy(o->SurfaceData);
    this->ClusterData->DeepCopy(o->ClusterData);
    std::copy(o->Origin, o->Origin + 3, this->Origin);
    this->RootEdge = o->RootEdge;
    this->FinestLevel = o->FinestLevel;
    this->HasMaterialArrays = o->HasMaterialArrays;
    this->NumberOfBoundaryEdges = o->NumberOfBoundaryEdges;
    this->NumberOfNonManifoldEdges = o->NumberOfNonManifoldEdges;
  }
  this->Superclass::DeepCopy(src);
  this->Modified();
}

//------------------------------------------------------------------------------
unsigned long vtkMultiscaleOctree::GetActualMemorySize()
{
  return this->Superclass::GetActualMemorySize() + this->NodeData->GetActualMemorySize() +
    this->SurfaceData->GetActualMemorySize() + this->ClusterData->GetActualMemorySize();
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfNodes()
{
  vtkAbstractArray* a = this->NodeData->GetAbstractArray(LevelArrayName());
  return a ? a->GetNumberOfTuples() : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfSurfacePoints()
{
  vtkAbstractArray* a = this->SurfaceData->GetAbstractArray(PointsArrayName());
  return a ? a->GetNumberOfTuples() : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfClusters()
{
  vtkAbstractArray* a = this->ClusterData->GetAbstractArray(ClusterNodeArrayName());
  return a ? a->GetNumberOfTuples() : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfSurfaceTriangles()
{
  vtkAbstractArray* a = this->SurfaceData->GetAbstractArray(TrianglesArrayName());
  return a ? a->GetNumberOfTuples() : 0;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::SetGeometry(const double origin[3], double rootEdge, int finestLevel)
{
  std::copy(origin, origin + 3, this->Origin);
  this->RootEdge = rootEdge;
  this->FinestLevel = finestLevel;
  this->Modified();
}

//------------------------------------------------------------------------------
double vtkMultiscaleOctree::GetCellEdge(int level) const
{
  return std::ldexp(this->RootEdge, -level);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::Allocate(vtkIdType nodes, vtkIdType points, vtkIdType triangles)
{
  this->NodeData->Initialize();
  this->SurfaceData->Initialize();
  this->ClusterData->Initialize();
  auto add = [](vtkFieldData* fd, vtkDataArray* a, const char* name, int comps, vtkIdType n) {
    a->SetName(name);
    a->SetNumberOfComponents(comps);
    a->SetNumberOfTuples(n);
    fd->AddArray(a);
    a->Delete();
  };
  vtkFieldData* fd = this->NodeData;
  add(fd, vtkUnsignedCharArray::New(), LevelArrayName(), 1, nodes);
  add(fd, vtkIntArray::New(), ParentArrayName(), 1, nodes);
  add(fd, vtkIntArray::New(), FirstChildArrayName(), 1, nodes);
  add(fd, vtkUnsignedCharArray::New(), ChildMaskArrayName(), 1, nodes);
  add(fd, vtkFloatArray::New(), VertexArrayName(), 3, nodes);
  add(fd, vtkFloatArray::New(), ConeAxisArrayName(), 3, nodes);
  add(fd, vtkFloatArray::New(), ConeAngleArrayName(), 1, nodes);
  add(fd, vtkFloatArray::New(), ShapeErrorArrayName(), 1, nodes);
  add(fd, vtkFloatArray::New(), DiffuseRangeArrayName(), 2, nodes);
  add(fd, vtkFloatArray::New(), SpecularRangeArrayName(), 2, nodes);
  add(fd, vtkUnsignedCharArray::New(), FlagsArrayName(), 1, nodes);
  add(fd, vtkFloatArray::New(), ThicknessArrayName(), 1, nodes);
  add(fd, vtkIntArray::New(), FirstPointArrayName(), 1, nodes);
  add(fd, vtkIdTypeArray::New(), FirstTriangleArrayName(), 1, nodes);
  add(fd, vtkIntArray::New(), FirstClusterArrayName(), 1, nodes);
  fd = this->SurfaceData;
  add(fd, vtkFloatArray::New(), PointsArrayName(), 3, points);
  add(fd, vtkFloatArray::New(), NormalsArrayName(), 3, points);
  add(fd, vtkIntArray::New(), PointLeafArrayName(), 1, points);
  add(fd, vtkIntArray::New(), PointClusterArrayName(), 1, points);
  add(fd, vtkIdTypeArray::New(), InputPointIdArrayName(), 1, points);
  add(fd, vtkIntArray::New(), TrianglesArrayName(), 3, triangles);
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::AllocateClusters(vtkIdType clusters)
{
  this->ClusterData->Initialize();
  auto add = [this, clusters](vtkDataArray* a, const char* name, int comps) {
    a->SetName(name);
    a->SetNumberOfComponents(comps);
    a->SetNumberOfTuples(clusters);
    this->ClusterData->AddArray(a);
    a->Delete();
  };
  add(vtkIntArray::New(), ClusterNodeArrayName(), 1);
  add(vtkIntArray::New(), ClusterParentArrayName(), 1);
  add(vtkFloatArray::New(), ClusterVertexArrayName(), 3);
  add(vtkFloatArray::New(), ClusterNormalArrayName(), 3);
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::AllocatePointGhosts()
{
  vtkNew<vtkUnsignedCharArray> a;
  a->SetName(PointGhostArrayName());
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(this->GetNumberOfSurfacePoints());
  this->SurfaceData->AddArray(a);
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::HasPointGhosts()
{
  return FetchArray<vtkUnsignedCharArray>(this->SurfaceData, PointGhostArrayName(), 1,
           this->GetNumberOfSurfacePoints()) != nullptr;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfGhostPoints()
{
  auto* a = FetchArray<vtkUnsignedCharArray>(
    this->SurfaceData, PointGhostArrayName(), 1, this->GetNumberOfSurfacePoints());
  if (!a)
  {
    return 0;
  }
  const unsigned char* g = a->GetPointer(0);
  return static_cast<vtkIdType>(
    std::count_if(g, g + a->GetNumberOfTuples(), [](unsigned char x) { return x != 0; }));
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetArrays(plod::OctreeArrays& out)
{
  static_assert(sizeof(vtkIdType) == sizeof(int64_t), "vtkIdType must be 64-bit");
  out = plod::OctreeArrays();
  vtkFieldData* fd = this->NodeData;
  const vtkIdType n = this->GetNumberOfNodes();
  auto* level = FetchArray<vtkUnsignedCharArray>(fd, LevelArrayName(), 1, n);
  auto* parent = FetchArray<vtkIntArray>(fd, ParentArrayName(), 1, n);
  auto* first = FetchArray<vtkIntArray>(fd, FirstChildArrayName(), 1, n);
  auto* mask = FetchArray<vtkUnsignedCharArray>(fd, ChildMaskArrayName(), 1, n);
  auto* vertex = FetchArray<vtkFloatArray>(fd, VertexArrayName(), 3, n);
  auto* axis = FetchArray<vtkFloatArray>(fd, ConeAxisArrayName(), 3, n);
  auto* angle = FetchArray<vtkFloatArray>(fd, ConeAngleArrayName(), 1, n);
  auto* shape = FetchArray<vtkFloatArray>(fd, ShapeErrorArrayName(), 1, n);
  auto* diffuse = FetchArray<vtkFloatArray>(fd, DiffuseRangeArrayName(), 2, n);
  auto* specular = FetchArray<vtkFloatArray>(fd, SpecularRangeArrayName(), 2, n);
  auto* flags = FetchArray<vtkUnsignedCharArray>(fd, FlagsArrayName(), 1, n);
  auto* thickness = FetchArray<vtkFloatArray>(fd, ThicknessArrayName(), 1, n);
  auto* firstPoint = FetchArray<vtkIntArray>(fd, FirstPointArrayName(), 1, n);
  auto* firstTriangle = FetchArray<vtkIdTypeArray>(fd, FirstTriangleArrayName(), 1, n);
  auto* firstCluster = FetchArray<vtkIntArray>(fd, FirstClusterArrayName(), 1, n);
  const vtkIdType np = this->GetNumberOfSurfacePoints();
  const vtkIdType nt = this->GetNumberOfSurfaceTriangles();
  fd = this->SurfaceData;
  auto* points = FetchArray<vtkFloatArray>(fd, PointsArrayName(), 3, np);
  auto* normals = FetchArray<vtkFloatArray>(fd, NormalsArrayName(), 3, np);
  auto* leaf = FetchArray<vtkIntArray>(fd, PointLeafArrayName(), 1, np);
  auto* pointCluster = FetchArray<vtkIntArray>(fd, PointClusterArrayName(), 1, np);
  auto* ids = FetchArray<vtkIdTypeArray>(fd, InputPointIdArrayName(), 1, np);
  auto* triangles = FetchArray<vtkIntArray>(fd, TrianglesArrayName(), 3, nt);
  if (!level || !parent || !first || !mask || !vertex || !axis || !angle || !shape || !diffuse ||
    !specular || !flags || !thickness || !firstPoint || !firstTriangle || !firstCluster ||
    !points || !normals || !leaf || !pointCluster || !ids || !triangles)
  {
    return false;
  }
  // optional: absent, no ghosts; present with another type or size, the octree is malformed
  // (ignoring it would make every process draw every triangle)
  auto* ghost = FetchArray<vtkUnsignedCharArray>(fd, PointGhostArrayName(), 1, np);
  if (!ghost && fd->GetAbstractArray(PointGhostArrayName()))
  {
    return false;
  }
  out.PointGhost = ghost ? ghost->GetPointer(0) : nullptr;
  // the cluster arrays come later in a build: absent, their pointers stay null
  const vtkIdType nc = this->GetNumberOfClusters();
  auto* cnode = FetchArray<vtkIntArray>(this->ClusterData, ClusterNodeArrayName(), 1, nc);
  auto* cparent = FetchArray<vtkIntArray>(this->ClusterData, ClusterParentArrayName(), 1, nc);
  auto* cvertex = FetchArray<vtkFloatArray>(this->ClusterData, ClusterVertexArrayName(), 3, nc);
  auto* cnormal = FetchArray<vtkFloatArray>(this->ClusterData, ClusterNormalArrayName(), 3, nc);
  if (cnode && cparent && cvertex && cnormal)
  {
    out.ClusterNode = cnode->GetPointer(0);
    out.ClusterParent = cparent->GetPointer(0);
    out.ClusterVertex = cvertex->GetPointer(0);
    out.ClusterNormal = cnormal->GetPointer(0);
  }
  out.Level = level->GetPointer(0);
  out.Parent = parent->GetPointer(0);
  out.FirstChild = first->GetPointer(0);
  out.ChildMask = mask->GetPointer(0);
  out.Vertex = vertex->GetPointer(0);
  out.ConeAxis = axis->GetPointer(0);
  out.ConeAngle = angle->GetPointer(0);
  out.ShapeError = shape->GetPointer(0);
  out.Diffuse = diffuse->GetPointer(0);
  out.Specular = specular->GetPointer(0);
  out.Flags = flags->GetPointer(0);
  out.Thickness = thickness->GetPointer(0);
  out.FirstPoint = firstPoint->GetPointer(0);
  out.FirstTriangle = reinterpret_cast<int64_t*>(firstTriangle->GetPointer(0));
  out.FirstCluster = firstCluster->GetPointer(0);
  out.PointCluster = pointCluster->GetPointer(0);
  out.Points = points->GetPointer(0);
  out.Normals = normals->GetPointer(0);
  out.PointLeaf = leaf->GetPointer(0);
  out.InputPointId = reinterpret_cast<int64_t*>(ids->GetPointer(0));
  out.Triangles = triangles->GetPointer(0);
  return true;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetView(plod::OctreeView& view)
{
  view = plod::OctreeView();
  plod::OctreeArrays a;
  const vtkIdType n = this->GetNumberOfNodes();
  if (n == 0 || !this->GetArrays(a) || !a.ClusterNode)
  {
    return false;
  }
  view.NumberOfNodes = n;
  view.FinestLevel = this->FinestLevel;
  std::copy(this->Origin, this->Origin + 3, view.Origin);
  view.RootEdge = this->RootEdge;
  view.Level = a.Level;
  view.Parent = a.Parent;
  view.FirstChild = a.FirstChild;
  view.ChildMask = a.ChildMask;
  view.Vertex = a.Vertex;
  view.ConeAxis = a.ConeAxis;
  view.ConeAngle = a.ConeAngle;
  view.ShapeError = a.ShapeError;
  view.Diffuse = a.Diffuse;
  view.Specular = a.Specular;
  view.Flags = a.Flags;
  view.Thickness = a.Thickness;
  view.FirstPoint = a.FirstPoint;
  view.FirstTriangle = a.FirstTriangle;
  view.FirstCluster = a.FirstCluster;
  view.NumberOfClusters = this->GetNumberOfClusters();
  view.ClusterNode = a.ClusterNode;
  view.ClusterParent = a.ClusterParent;
  view.ClusterVertex = a.ClusterVertex;
  view.ClusterNormal = a.ClusterNormal;
  view.NumberOfPoints = this->GetNumberOfSurfacePoints();
  view.Points = a.Points;
  view.Normals = a.Normals;
  view.PointLeaf = a.PointLeaf;
  view.PointCluster = a.PointCluster;
  view.InputPointId = a.InputPointId;
  view.PointGhost = a.PointGhost;
  view.NumberOfTriangles = this->GetNumberOfSurfaceTriangles();
  view.Triangles = a.Triangles;
  return true;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::CheckKey::operator==(const CheckKey& o) const
{
  return this->Arrays == o.Arrays && this->Finest == o.Finest && this->Origin[0] == o.Origin[0] &&
    this->Origin[1] == o.Origin[1] && this->Origin[2] == o.Origin[2] && this->Edge == o.Edge;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::MakeCheckKey(CheckKey& k)
{
  k.Arrays.clear();
  k.Finest = this->FinestLevel;
  std::copy(this->Origin, this->Origin + 3, k.Origin);
  k.Edge = this->RootEdge;
  for (vtkFieldData* fd : { this->NodeData, this->SurfaceData, this->ClusterData })
  {
    for (int i = 0; i < fd->GetNumberOfArrays(); ++i)
    {
      vtkAbstractArray* a = fd->GetAbstractArray(i);
      const char* name = a ? a->GetName() : nullptr;
      if (!a ||
        (fd == this->NodeData && name && name[0] == 'C' &&
          (!strcmp(name, CutStateArrayName()) || !strcmp(name, CullMaskArrayName()) ||
            !strcmp(name, "CutReason"))))
      {
        continue; // the cut changes every frame; it is checked by the filters that read it
      }
      const vtkIdType values = a->GetNumberOfValues();
      k.Arrays.push_back({ a, values > 0 ? a->GetVoidPointer(0) : nullptr, values, a->GetMTime() });
    }
  }
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::CheckConsistency(std::string* why)
{
  this->MakeCheckKey(this->ScratchKey);
  if (!this->CheckedValid || !(this->ScratchKey == this->CheckedKey))
  {
    std::string text;
    plod::OctreeView v;
    bool ok = true;
    if (this->GetNumberOfNodes() == 0)
    {
      ok = true; // an empty octree is valid
    }
    else if (!this->GetView(v))
    {
      text = "octree arrays missing or of the wrong type or size";
      ok = false;
    }
    else
    {
      ok = plod::ValidateOctree(v, &text);
    }
    std::swap(this->CheckedKey, this->ScratchKey);
    this->CheckedValid = true;
    this->CheckedResult = ok;
    this->CheckedWhy = text;
    this->CheckedView =
      ok && v.NumberOfNodes > 0 ? std::make_shared<const plod::OctreeView>(v) : nullptr;
    vtkTimeStamp stamp; // a new value of VTK's global clock
    stamp.Modified();
    this->CheckedStamp = stamp.GetMTime();
  }
  if (why)
  {
    *why = this->CheckedWhy;
  }
  return this->CheckedResult;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetCheckedView(
  plod::OctreeView& view, vtkMTimeType* time, std::string* why)
{
  const bool ok = this->CheckConsistency(why);
  if (time)
  {
    *time = this->CheckedStamp;
  }
  if (!ok || !this->CheckedView)
  {
    view = plod::OctreeView();
    return false;
  }
  view = *this->CheckedView;
  return true;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::HasValidCut()
{
  plod::OctreeView v;
  auto* cut = FetchArray<vtkUnsignedCharArray>(
    this->NodeData, CutStateArrayName(), 1, this->GetNumberOfNodes());
  if (!cut || !this->IsConsistent() || !this->GetView(v))
  {
    return false;
  }
  return plod::ValidateCut(v, cut->GetPointer(0));
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctree::GetNodeLevel(vtkIdType node)
{
  plod::OctreeView v;
  if (!this->GetView(v) || node < 0 || node >= v.NumberOfNodes)
  {
    return -1;
  }
  return v.Level[node];
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetParent(vtkIdType node)
{
  plod::OctreeView v;
  if (!this->GetView(v) || node < 0 || node >= v.NumberOfNodes)
  {
    return -1;
  }
  return v.Parent[node];
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctree::GetNumberOfChildren(vtkIdType node)
{
  plod::OctreeView v;
  if (!this->GetView(v) || node < 0 || node >= v.NumberOfNodes)
  {
    return 0;
  }
  return __builtin_popcount(v.ChildMask[node]);
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetChild(vtkIdType node, int childIndex)
{
  plod::OctreeView v;
  if (!this->IsConsistent() || !this->GetView(v) || node < 0 || node >= v.NumberOfNodes ||
    childIndex < 0 || childIndex > 7)
  {
    return -1;
  }
  return v.Child(node, childIndex);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::GetNodeCellCoordinates(vtkIdType node, int ijk[3])
{
  plod::OctreeView v;
  ijk[0] = ijk[1] = ijk[2] = -1;
  if (this->IsConsistent() && this->GetView(v) && node >= 0 && node < v.NumberOfNodes)
  {
    v.CellCoordinates(node, ijk);
  }
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::GetNodeBounds(vtkIdType node, double bounds[6])
{
  int ijk[3];
  this->GetNodeCellCoordinates(node, ijk);
  const int level = this->GetNodeLevel(node);
  if (level < 0)
  {
    bounds[0] = bounds[2] = bounds[4] = 1.0;
    bounds[1] = bounds[3] = bounds[5] = -1.0; // VTK's uninitialized bounds
    return;
  }
  const double h = this->GetCellEdge(level);
  for (int a = 0; a < 3; ++a)
  {
    bounds[2 * a] = this->Origin[a] + ijk[a] * h;
    bounds[2 * a + 1] = this->Origin[a] + (ijk[a] + 1) * h;
  }
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::GetNodeVertex(vtkIdType node, double x[3])
{
  plod::OctreeView v;
  if (!this->GetView(v) || node < 0 || node >= v.NumberOfNodes)
  {
    x[0] = x[1] = x[2] = 0.0;
    return;
  }
  for (int a = 0; a < 3; ++a)
  {
    x[a] = this->Origin[a] + static_cast<double>(v.Vertex[3 * node + a]);
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::FindNode(const double x[3], int level)
{
  plod::OctreeView v;
  if (!this->IsConsistent() || !this->GetView(v) || level < 0 || level > this->FinestLevel)
  {
    return -1;
  }
  double u[3];
  const double cells = std::ldexp(1.0, this->FinestLevel);
  for (int a = 0; a < 3; ++a)
  {
    u[a] = (x[a] - this->Origin[a]) / this->RootEdge * cells;
    if (!(u[a] >= 0 && u[a] < cells))
    {
      return -1;
    }
  }
  const uint32_t ijk[3] = { static_cast<uint32_t>(u[0]), static_cast<uint32_t>(u[1]),
    static_cast<uint32_t>(u[2]) };
  vtkIdType node = 0;
  for (int l = 1; l <= level && node >= 0; ++l)
  {
    const int shift = this->FinestLevel - l;
    const int c =
      ((ijk[0] >> shift) & 1) | (((ijk[1] >> shift) & 1) << 1) | (((ijk[2] >> shift) & 1) << 2);
    node = v.Child(node, c);
  }
  return node;
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree* vtkMultiscaleOctree::GetData(vtkInformation* info)
{
  return info ? vtkMultiscaleOctree::SafeDownCast(info->Get(DATA_OBJECT())) : nullptr;
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree* vtkMultiscaleOctree::GetData(vtkInformationVector* v, int i)
{
  return vtkMultiscaleOctree::GetData(v->GetInformationObject(i));
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Origin: (" << this->Origin[0] << ", " << this->Origin[1] << ", "
     << this->Origin[2] << ")\n";
  os << indent << "RootEdge: " << this->RootEdge << "\n";
  os << indent << "FinestLevel: " << this->FinestLevel << "\n";
  os << indent << "HasMaterialArrays: " << (this->HasMaterialArrays ? "On" : "Off") << "\n";
  os << indent << "NumberOfBoundaryEdges: " << this->NumberOfBoundaryEdges << "\n";
  os << indent << "NumberOfNonManifoldEdges: " << this->NumberOfNonManifoldEdges << "\n";
  os << indent << "NumberOfNodes: " << this->GetNumberOfNodes() << "\n";
  os << indent << "NumberOfSurfacePoints: " << this->GetNumberOfSurfacePoints() << "\n";
  os << indent << "NumberOfSurfaceTriangles: " << this->GetNumberOfSurfaceTriangles() << "\n";
  os << indent << "PointGhosts: "
     << (this->HasPointGhosts() ? std::to_string(this->GetNumberOfGhostPoints()) + " ghost points"
                                : std::string("none"))
     << "\n";
  os << indent << "NodeData:\n";
  this->NodeData->PrintSelf(os, indent.GetNextIndent());
  os << indent << "SurfaceData:\n";
  this->SurfaceData->PrintSelf(os, indent.GetNextIndent());
  os << indent << "NumberOfClusters: " << this->GetNumberOfClusters() << "\n";
  os << indent << "ClusterData:\n";
  this->ClusterData->PrintSelf(os, indent.GetNextIndent());
}
