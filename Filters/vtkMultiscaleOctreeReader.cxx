// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctreeReader.h"
#include "vtkPerceptualLODSMP.h"

#include "plodOctreeFile.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkObjectFactory.h"
#include "vtkTimerLog.h"
#include "vtkUnsignedCharArray.h"

#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <unordered_map>

vtkStandardNewMacro(vtkMultiscaleOctreeReader);

namespace
{
/// The arrays' views into mapped files: each array's pointer keeps its file's memory alive
/// until VTK frees the array (ReleaseMapped).
std::mutex RegistryMutex;
std::unordered_map<void*, std::shared_ptr<void>>& Registry()
{
  static std::unordered_map<void*, std::shared_ptr<void>> registry;
  return registry;
}

void ReleaseMapped(void* data)
{
  std::shared_ptr<void> keep; // released outside the lock
  {
    std::lock_guard<std::mutex> lock(RegistryMutex);
    auto it = Registry().find(data);
    if (it != Registry().end())
    {
      keep = std::move(it->second);
      Registry().erase(it);
    }
  }
}

}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeReader::vtkMultiscaleOctreeReader()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkMultiscaleOctreeReader::~vtkMultiscaleOctreeReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctreeReader::CanReadFile(const char* path)
{
  if (!path || !plod::IsRegularFile(path, nullptr))
  {
    return false; // never opened: a FIFO would block
  }
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in.gcount() == 8 && std::memcmp(magic, "PLODOCT\n", 8) == 0;
}

//------------------------------------------------------------------------------
int vtkMultiscaleOctreeReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkMultiscaleOctree* output = vtkMultiscaleOctree::GetData(outputVector);
  if (!output)
  {
    vtkErrorMacro("No output octree.");
    return 0;
  }
  output->Initialize();
  this->ErrorMessage.clear();
  this->Mapped = false;
  this->Compact = false;
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  if (!this->FileName || !*this->FileName)
  {
    this->ErrorMessage = "No file name to read.";
    vtkErrorMacro(<< this->ErrorMessage);
    return 1;
  }
  plod::OctreeFile file;
  std::string why;
  if (!plod::OpenOctreeFile(
        this->FileName, this->VerifyChecksums, this->MemoryMap, file, &why, plodvtk::SMPRanges()))
  {
    this->ErrorMessage = why;
    vtkErrorMacro(<< "Cannot read the octree: " << why << ". Empty octree.");
    return 1;
  }
  const plod::OctreeFileHeader& h = file.Header;
  if (h.Nodes > 0)
  {
    // every array of the schema, with its type and size
    std::vector<const plod::FileArray*> found;
    if (!plod::MatchSchema(file, found, &why))
    {
      this->ErrorMessage = std::string(this->FileName) + ": " + why;
      vtkErrorMacro(<< "Cannot read the octree: " << this->ErrorMessage << ". Empty octree.");
      return 1;
    }
    size_t k = 0;
    for (const plod::ArraySpec& spec : plod::OctreeFileSchema())
    {
      const plod::FileArray& f = *found[k++];
      vtkDataArray* a = vtkMultiscaleOctree::NewArray(f.Type);
      a->SetName(f.Name.c_str());
      a->SetNumberOfComponents(f.Components);
      const vtkIdType values = static_cast<vtkIdType>(f.Tuples) * f.Components;
      if (values > 0)
      {
        void* data = const_cast<void*>(f.Data);
        {
          std::lock_guard<std::mutex> lock(RegistryMutex);
          Registry()[data] = file.Memory;
        }
        a->SetVoidArray(data, values, 0, vtkAbstractArray::VTK_DATA_ARRAY_USER_DEFINED);
        a->SetArrayFreeFunction(ReleaseMapped);
      }
      output->GetFieldDataOf(spec.Group)->AddArray(a);
      a->Delete();
    }
  }
  output->SetGeometry(h.Origin, h.RootEdge, h.FinestLevel);
  output->SetHasMaterialArrays(h.HasMaterialArrays);
  output->SetCoarsestDrawnLevel(h.CoarsestDrawnLevel);
  output->SetNumberOfBoundaryEdges(h.BoundaryEdges);
  output->SetNumberOfNonManifoldEdges(h.NonManifoldEdges);
  output->SetNumberOfMisorientedEdges(h.MisorientedEdges);
  if (file.Mapped)
  {
    // the filters compare the file on disk with the one mapped (only a map can be hurt)
    output->SetSourceFile(std::make_shared<const plod::FileIdentity>(file.Identity));
    output->SetMappedPages(
      file.Memory, file.MapStart, file.Identity.Size, uint64_t(this->CacheLimit) << 20);
    output->SetBackgroundLoading(this->BackgroundLoading);
  }
  output->Modified();
  this->Mapped = file.Mapped;
  this->Compact = file.Compact;
  timer->StopTimer();
  this->ReadTime = timer->GetElapsedTime();
  return 1;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctreeReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "VerifyChecksums: " << this->VerifyChecksums << "\n";
  os << indent << "MemoryMap: " << this->MemoryMap << "\n";
  os << indent << "CacheLimit: " << this->CacheLimit << " MiB\n";
  os << indent << "BackgroundLoading: " << this->BackgroundLoading << "\n";
  os << indent << "Mapped: " << this->Mapped << "\n";
  os << indent << "Compact: " << this->Compact << "\n";
  os << indent << "ReadTime: " << this->ReadTime << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
}
