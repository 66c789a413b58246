// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctree.h"

#include "plodOctree.h"
#include "plodPatches.h"

#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkTypeUInt32Array.h"
#include "vtkUnsignedCharArray.h"

#include <cmath>
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
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::Initialize()
{
  this->Superclass::Initialize();
  this->NodeData->Initialize();
  this->Origin[0] = this->Origin[1] = this->Origin[2] = 0.0;
  this->RootEdge = 1.0;
  this->FinestLevel = 0;
  this->HasMaterialArrays = false;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::ShallowCopy(vtkDataObject* src)
{
  if (auto* o = vtkMultiscaleOctree::SafeDownCast(src))
  {
    this->NodeData->ShallowCopy(o->NodeData);
    std::copy(o->Origin, o->Origin + 3, this->Origin);
    this->RootEdge = o->RootEdge;
    this->FinestLevel = o->FinestLevel;
    this->HasMaterialArrays = o->HasMaterialArrays;
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
    std::copy(o->Origin, o->Origin + 3, this->Origin);
    this->RootEdge = o->RootEdge;
    this->FinestLevel = o->FinestLevel;
    this->HasMaterialArrays = o->HasMaterialArrays;
  }
  this->Superclass::DeepCopy(src);
  this->Modified();
}

//------------------------------------------------------------------------------
unsigned long vtkMultiscaleOctree::GetActualMemorySize()
{
  return this->Superclass::GetActualMemorySize() + this->NodeData->GetActualMemorySize();
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfNodes()
{
  vtkAbstractArray* a = this->NodeData->GetAbstractArray(LevelArrayName());
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
void vtkMultiscaleOctree::AllocateNodes(vtkIdType n)
{
  this->NodeData->Initialize();
  auto add = [this, n](vtkDataArray* a, const char* name, int comps) {
    a->SetName(name);
    a->SetNumberOfComponents(comps);
    a->SetNumberOfTuples(n);
    this->NodeData->AddArray(a);
    a->Delete();
  };
  add(vtkUnsignedCharArray::New(), LevelArrayName(), 1);
  add(vtkIntArray::New(), ParentArrayName(), 1);
  add(vtkIntArray::New(), FirstChildArrayName(), 1);
  add(vtkUnsignedCharArray::New(), ChildMaskArrayName(), 1);
  add(vtkFloatArray::New(), VertexArrayName(), 3);
  add(vtkFloatArray::New(), ConeAxisArrayName(), 3);
  add(vtkFloatArray::New(), ConeAngleArrayName(), 1);
  add(vtkFloatArray::New(), ShapeErrorArrayName(), 1);
  add(vtkFloatArray::New(), DiffuseRangeArrayName(), 2);
  add(vtkFloatArray::New(), SpecularRangeArrayName(), 2);
  add(vtkTypeUInt32Array::New(), EdgeCrossingsArrayName(), 1);
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetArrays(plod::OctreeArrays& out)
{
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
  auto* edges = FetchArray<vtkTypeUInt32Array>(fd, EdgeCrossingsArrayName(), 1, n);
  if (!level || !parent || !first || !mask || !vertex || !axis || !angle || !shape ||
    !diffuse || !specular || !edges)
  {
    out = plod::OctreeArrays();
    return false;
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
  out.Edges = edges->GetPointer(0);
  return true;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetView(plod::OctreeView& view)
{
  view = plod::OctreeView();
  plod::OctreeArrays a;
  const vtkIdType n = this->GetNumberOfNodes();
  if (n == 0 || !this->GetArrays(a))
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
  view.Edges = a.Edges;
  return true;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::CheckConsistency(std::string* why)
{
  std::ostringstream msg;
  plod::OctreeView v;
  const vtkIdType n = this->GetNumberOfNodes();
  bool ok = true;
  if (n == 0)
  {
    ok = true; // an empty octree is valid
  }
  else if (!this->GetView(v))
  {
    msg << "node arrays missing or of the wrong type/size";
    ok = false;
  }
  else if (!(this->RootEdge > 0) || !std::isfinite(this->RootEdge) || this->FinestLevel < 0 ||
    this->FinestLevel > plod::MaxFinestLevel)
  {
    msg << "invalid root edge or finest level";
    ok = false;
  }
  else if (v.Parent[0] != -1 || v.Level[0] != 0)
  {
    msg << "node 0 is not a root";
    ok = false;
  }
  else
  {
    for (vtkIdType i = 0; i < n && ok; ++i)
    {
      if (v.Level[i] > this->FinestLevel)
      {
        msg << "node " << i << " is below the finest level";
        ok = false;
      }
      else if (i > 0 && (v.Parent[i] < 0 || v.Parent[i] >= i || v.Level[v.Parent[i]] + 1 != v.Level[i]))
      {
        msg << "node " << i << " has an invalid parent";
        ok = false;
      }
      else if (v.ChildMask[i] != 0)
      {
        const int count = __builtin_popcount(v.ChildMask[i]);
        if (v.FirstChild[i] <= i || v.FirstChild[i] + count > n)
        {
          msg << "node " << i << " has invalid children";
          ok = false;
        }
        for (int c = 0; c < count && ok; ++c)
        {
          if (v.Parent[v.FirstChild[i] + c] != i)
          {
            msg << "child " << v.FirstChild[i] + c << " does not point back to " << i;
            ok = false;
          }
        }
      }
      else if (v.FirstChild[i] != -1)
      {
        msg << "leaf " << i << " has a first child";
        ok = false;
      }
    }
  }
  if (why)
  {
    *why = msg.str();
  }
  return ok;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::HasValidCut()
{
  plod::OctreeView v;
  auto* cut = FetchArray<vtkUnsignedCharArray>(
    this->NodeData, CutStateArrayName(), 1, this->GetNumberOfNodes());
  if (!cut || !this->GetView(v))
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
  if (!this->GetView(v) || node < 0 || node >= v.NumberOfNodes || childIndex < 0 ||
    childIndex > 7)
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
  if (this->GetView(v) && node >= 0 && node < v.NumberOfNodes)
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
  if (!this->GetView(v) || level < 0 || level > this->FinestLevel)
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
  os << indent << "NumberOfNodes: " << this->GetNumberOfNodes() << "\n";
  os << indent << "NodeData:\n";
  this->NodeData->PrintSelf(os, indent.GetNextIndent());
}
