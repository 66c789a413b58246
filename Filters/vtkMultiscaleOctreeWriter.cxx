// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctreeWriter.h"

#include "plodOctreeFile.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMultiscaleOctree.h"
#include "vtkObjectFactory.h"

#include <vector>

vtkStandardNewMacro(vtkMultiscaleOctreeWriter);

namespace
{
/// The VTK type of a file array type.
int VTKType(plod::FileArrayType type)
{
  switch (type)
  {
    case plod::FileArrayType::UInt8:
      return VTK_UNSIGNED_CHAR;
    case plod::FileArrayType::Int32:
      return VTK_INT;
    case plod::FileArrayType::Float32:
      return VTK_FLOAT;
    case plod::FileArrayType::Int64:
      return VTK_ID_TYPE;
  }
  return -1;
}
}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeWriter::vtkMultiscaleOctreeWriter() = default;

//------------------------------------------------------------------------------
vtkMultiscaleOctreeWriter::~vtkMultiscaleOctreeWriter()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiscaleOctree");
  return 1;
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree* vtkMultiscaleOctreeWriter::GetInput()
{
  return vtkMultiscaleOctree::SafeDownCast(this->Superclass::GetInput());
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeWriter::WriteData()
{
  this->ErrorMessage.clear();
  auto fail = [this](const std::string& why, unsigned long code) {
    this->ErrorMessage = why;
    vtkErrorMacro(<< why);
    this->SetErrorCode(code);
  };
  vtkMultiscaleOctree* octree = this->GetInput();
  if (!this->FileName || !*this->FileName)
  {
    fail("No file name to write the octree to.", vtkErrorCode::NoFileNameError);
    return;
  }
  if (!octree)
  {
    fail("The input is not a vtkMultiscaleOctree.", vtkErrorCode::UnknownError);
    return;
  }
  if (!octree->IsConsistent())
  {
    fail("The octree is inconsistent (see vtkMultiscaleOctree::IsConsistent); not writing it.",
      vtkErrorCode::UnknownError);
    return;
  }
  plod::OctreeFileHeader header;
  octree->GetOrigin(header.Origin);
  header.RootEdge = octree->GetRootEdge();
  header.FinestLevel = octree->GetFinestLevel();
  header.HasMaterialArrays = octree->GetHasMaterialArrays();
  header.Nodes = octree->GetNumberOfNodes();
  header.Points = octree->GetNumberOfSurfacePoints();
  header.Triangles = octree->GetNumberOfSurfaceTriangles();
  header.Clusters = header.Nodes > 0 ? octree->GetNumberOfClusters() : 0;
  header.BoundaryEdges = octree->GetNumberOfBoundaryEdges();
  header.NonManifoldEdges = octree->GetNumberOfNonManifoldEdges();
  std::vector<plod::FileArray> arrays;
  if (header.Nodes > 0)
  {
    for (const plod::FileArraySpec& spec : plod::OctreeFileSchema())
    {
      vtkFieldData* fd = spec.Group == plod::FileArrayGroup::Node ? octree->GetNodeData()
        : spec.Group == plod::FileArrayGroup::Cluster             ? octree->GetClusterData()
                                                                  : octree->GetSurfaceData();
      vtkDataArray* a = fd->GetArray(spec.Name);
      const int64_t tuples = spec.Group == plod::FileArrayGroup::Node ? header.Nodes
        : spec.Group == plod::FileArrayGroup::Cluster                  ? header.Clusters
        : spec.Group == plod::FileArrayGroup::Point                    ? header.Points
                                                                       : header.Triangles;
      if (!a || a->GetDataType() != VTKType(spec.Type) ||
        a->GetNumberOfComponents() != spec.Components || a->GetNumberOfTuples() != tuples)
      {
        fail(std::string("The octree's array '") + spec.Name +
            "' is missing or has the wrong type or size.",
          vtkErrorCode::UnknownError);
        return;
      }
      plod::FileArray f;
      f.Name = spec.Name;
      f.Group = spec.Group;
      f.Type = spec.Type;
      f.Components = spec.Components;
      f.Tuples = tuples;
      f.Data = a->GetVoidPointer(0);
      arrays.push_back(f);
    }
  }
  std::string why;
  if (!plod::WriteOctreeFile(this->FileName, header, arrays, &why))
  {
    fail(why, vtkErrorCode::CannotOpenFileError);
  }
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
}
