// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctreeWriter.h"

#include "plodOctreeFile.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkMultiscaleOctree.h"
#include "vtkObjectFactory.h"
#include "vtkPerceptualLODSMP.h"

#include <vector>

vtkStandardNewMacro(vtkMultiscaleOctreeWriter);

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
  std::string changed;
  if (!octree->IsSourceFileIntact(&changed))
  {
    fail("Cannot write the octree: " + changed + ".", vtkErrorCode::UnknownError);
    return;
  }
  if (!octree->IsConsistent())
  {
    fail("The octree is inconsistent (see vtkMultiscaleOctree::IsConsistent); not writing it.",
      vtkErrorCode::UnknownError);
    return;
  }
  if (octree->GetNumberOfGhostPoints() > 0)
  {
    // the file format has no place for them: a process reading the file back draws every
    // triangle of its piece
    vtkWarningMacro("The octree flags " << octree->GetNumberOfGhostPoints()
                                        << " ghost point(s) (distributed rendering); the file "
                                           "does not store ghost flags.");
  }
  plod::OctreeFileHeader header;
  octree->GetOrigin(header.Origin);
  header.RootEdge = octree->GetRootEdge();
  header.FinestLevel = octree->GetFinestLevel();
  header.HasMaterialArrays = octree->GetHasMaterialArrays();
  header.CoarsestDrawnLevel = octree->GetCoarsestDrawnLevel();
  header.BoundaryEdges = octree->GetNumberOfBoundaryEdges();
  header.NonManifoldEdges = octree->GetNumberOfNonManifoldEdges();
  header.MisorientedEdges = octree->GetNumberOfMisorientedEdges();
  std::vector<plod::FileArray> arrays;
  plod::OctreeView v;
  if (octree->GetNumberOfNodes() > 0 && octree->GetView(v)) // consistent: the view exists
  {
    header.Nodes = v.NumberOfNodes;
    header.Points = v.NumberOfPoints;
    header.Triangles = v.NumberOfTriangles;
    header.Clusters = v.NumberOfClusters;
    arrays = plod::FileArraysOf(v);
  }
  plod::FileWriteOptions options;
  options.Layout = this->Compact ? plod::FileLayout::Compact : plod::FileLayout::Mapped;
  options.Parallel = plodvtk::SMPRanges();
  std::string why;
  if (!plod::WriteOctreeFile(this->FileName, header, arrays, options, &why))
  {
    fail(why, vtkErrorCode::CannotOpenFileError);
  }
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Compact: " << this->Compact << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
}
