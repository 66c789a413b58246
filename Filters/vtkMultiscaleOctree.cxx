// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMultiscaleOctree.h"

#include "plodCut.h"
#include "plodLargeArrays.h"
#include "plodOctree.h"
#include "plodOctreeFile.h"
#include "plodOctreeSchema.h"
#include "plodPageLoader.h"
#include "plodPatches.h"
#include "plodResidentPages.h"

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
#include <type_traits>

vtkStandardNewMacro(vtkMultiscaleOctree);

// the names of the schema's arrays (plodOctreeSchema.h)
#define PLOD_NAME_FUNCTION(member, group, type, comps, meaning)                                    \
  const char* vtkMultiscaleOctree::member##ArrayName()                                             \
  {                                                                                                \
    return plod::ArrayName(#member, plod::ArrayGroup::group);                                      \
  }
PLOD_OCTREE_ALL_ARRAYS(PLOD_NAME_FUNCTION)
#undef PLOD_NAME_FUNCTION

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

/// Whether `a` holds values of the schema's `type` (vtkIdType for int64).
bool HoldsSchemaType(vtkDataArray* a, plod::ArrayType type)
{
  switch (type)
  {
    case plod::ArrayType::UInt8:
      return a->GetDataType() == VTK_UNSIGNED_CHAR;
    case plod::ArrayType::Int32:
      return a->GetDataType() == VTK_INT;
    case plod::ArrayType::Float32:
      return a->GetDataType() == VTK_FLOAT;
    case plod::ArrayType::Int64:
      return a->GetDataType() == VTK_ID_TYPE;
  }
  return false;
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
  this->CoarsestDrawnLevel = 0;
  this->NumberOfBoundaryEdges = 0;
  this->NumberOfNonManifoldEdges = 0;
  this->NumberOfMisorientedEdges = 0;
  this->SourceFile = nullptr;
  this->CornerMemo = nullptr;
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
    this->CoarsestDrawnLevel = o->CoarsestDrawnLevel;
    this->NumberOfBoundaryEdges = o->NumberOfBoundaryEdges;
    this->NumberOfNonManifoldEdges = o->NumberOfNonManifoldEdges;
    this->NumberOfMisorientedEdges = o->NumberOfMisorientedEdges;
    // the same arrays: the source's check holds for the copy
    this->CheckedKey = o->CheckedKey;
    this->CheckedValid = o->CheckedValid;
    this->CheckedResult = o->CheckedResult;
    this->CheckedWhy = o->CheckedWhy;
    this->CheckedView = o->CheckedView;
    this->CheckedStamp = o->CheckedStamp;
    this->SourceFile = o->SourceFile;      // the same mapped bytes
    this->CornerMemo = o->GetCornerMemo(); // the same points: one memo for both
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
    this->CoarsestDrawnLevel = o->CoarsestDrawnLevel;
    this->NumberOfBoundaryEdges = o->NumberOfBoundaryEdges;
    this->NumberOfNonManifoldEdges = o->NumberOfNonManifoldEdges;
    this->NumberOfMisorientedEdges = o->NumberOfMisorientedEdges;
    this->SourceFile = nullptr; // copied into memory
    this->CornerMemo = nullptr;
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
vtkFieldData* vtkMultiscaleOctree::GetFieldDataOf(plod::ArrayGroup group)
{
  return group == plod::ArrayGroup::Node ? this->NodeData
    : group == plod::ArrayGroup::Cluster ? this->ClusterData
                                         : this->SurfaceData;
}

//------------------------------------------------------------------------------
vtkDataArray* vtkMultiscaleOctree::NewArray(plod::ArrayType type)
{
  switch (type)
  {
    case plod::ArrayType::UInt8:
      return vtkUnsignedCharArray::New();
    case plod::ArrayType::Int32:
      return vtkIntArray::New();
    case plod::ArrayType::Float32:
      return vtkFloatArray::New();
    case plod::ArrayType::Int64:
      return vtkIdTypeArray::New();
  }
  return nullptr;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::AddSchemaArray(const plod::ArraySpec& spec, vtkIdType tuples)
{
  vtkDataArray* a = NewArray(spec.Type);
  a->SetName(spec.Name);
  a->SetNumberOfComponents(spec.Components);
  a->SetNumberOfTuples(tuples);
  // written whole by the build or the decoder: huge pages where the kernel gives them
  plod::AdviseHugePages(
    a->GetVoidPointer(0), static_cast<size_t>(a->GetDataSize()) * size_t(a->GetDataTypeSize()));
  this->GetFieldDataOf(spec.Group)->AddArray(a);
  a->Delete();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::Allocate(vtkIdType nodes, vtkIdType points, vtkIdType triangles)
{
  this->NodeData->Initialize();
  this->SurfaceData->Initialize();
  this->ClusterData->Initialize();
  for (const plod::ArraySpec& spec : plod::OctreeSchema)
  {
    if (!spec.Optional && spec.Group != plod::ArrayGroup::Cluster)
    {
      const vtkIdType tuples = spec.Group == plod::ArrayGroup::Node ? nodes
        : spec.Group == plod::ArrayGroup::Point                     ? points
                                                                    : triangles;
      this->AddSchemaArray(spec, tuples);
    }
  }
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::AllocateClusters(vtkIdType clusters)
{
  this->ClusterData->Initialize();
  for (const plod::ArraySpec& spec : plod::OctreeSchema)
  {
    if (spec.Group == plod::ArrayGroup::Cluster)
    {
      this->AddSchemaArray(spec, clusters);
    }
  }
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::AllocatePointGhosts()
{
  for (const plod::ArraySpec& spec : plod::OctreeSchema)
  {
    if (!std::strcmp(spec.Member, "PointGhost"))
    {
      this->AddSchemaArray(spec, this->GetNumberOfSurfacePoints());
    }
  }
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
  const vtkIdType tuples[4] = { this->GetNumberOfNodes(), this->GetNumberOfClusters(),
    this->GetNumberOfSurfacePoints(), this->GetNumberOfSurfaceTriangles() };
  bool ok = true;
  bool clusters = true;
  plod::ForEachArray(out, [&](const plod::ArraySpec& spec, auto& pointer) {
    using T = std::remove_pointer_t<std::remove_reference_t<decltype(pointer)>>;
    vtkFieldData* fd = this->GetFieldDataOf(spec.Group);
    vtkDataArray* a = FetchArray<vtkDataArray>(
      fd, spec.Name, spec.Components, tuples[static_cast<int>(spec.Group)]);
    // the array's type must be the schema's (vtkIdType stands for int64)
    if (a && a->HasStandardMemoryLayout() && HoldsSchemaType(a, spec.Type))
    {
      pointer = static_cast<T*>(a->GetVoidPointer(0));
    }
    else if (spec.Optional)
    {
      // absent, no ghosts; present with another type or size, the octree is malformed
      // (ignoring it would make every process draw every triangle)
      ok = ok && !fd->GetAbstractArray(spec.Name);
    }
    else if (spec.Group == plod::ArrayGroup::Cluster)
    {
      clusters = false; // the cluster arrays come later in a build
    }
    else
    {
      ok = false;
    }
  });
  if (!clusters)
  {
    out.ClusterNode = out.ClusterParent = nullptr;
    out.ClusterVertex = out.ClusterNormal = nullptr;
  }
  if (!ok)
  {
    out = plod::OctreeArrays();
  }
  return ok;
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
  view.NumberOfClusters = this->GetNumberOfClusters();
  view.NumberOfPoints = this->GetNumberOfSurfacePoints();
  view.NumberOfTriangles = this->GetNumberOfSurfaceTriangles();
#define PLOD_VIEW_OF_ARRAYS(member, group, type, comps, meaning) view.member = a.member;
  PLOD_OCTREE_ALL_ARRAYS(PLOD_VIEW_OF_ARRAYS)
#undef PLOD_VIEW_OF_ARRAYS
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
struct vtkMultiscaleOctree::SourceFileState
{
  std::shared_ptr<const plod::FileIdentity> File;
  bool WarnedReplaced = false;
  // the mapped bytes and the limit on their resident pages (SetMappedPages)
  std::shared_ptr<void> Memory;
  plod::ResidentLimit Resident;
  bool WarnedResident = false;
  // the filters' counts of what they keep for the octree (CountHeldBytes)
  std::vector<std::weak_ptr<const std::atomic<uint64_t>>> Held;
  // how many of the last executions dropped the pages (WarnIfDroppedMostFrames)
  uint64_t Executions = 0;
  uint64_t DroppingExecutions = 0;
  uint64_t LastReleases = 0;
  bool WarnedDropping = false;
  // background reads of the pages (SetBackgroundLoading), made at the first GetPageLoader()
  bool BackgroundLoading = false;
  std::unique_ptr<plod::PageLoader> Loader;
};

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::SetMappedPages(
  std::shared_ptr<void> memory, void* start, uint64_t bytes, uint64_t limit)
{
  if (!this->SourceFile)
  {
    vtkErrorMacro("SetMappedPages needs the source file first (SetSourceFile).");
    return;
  }
  this->SourceFile->Loader = nullptr; // (joins its thread: it reads the old map and limit)
  this->SourceFile->Memory = std::move(memory);
  this->SourceFile->Resident.Attach(start, bytes);
  this->SourceFile->Resident.SetLimit(limit);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::EnforceResidentLimit()
{
  if (!this->SourceFile || !this->SourceFile->Memory)
  {
    return;
  }
  // what the filters keep for the octree counts against the limit too
  SourceFileState& file = *this->SourceFile;
  uint64_t held = this->CornerMemo ? this->CornerMemo->CutCluster.capacity() * sizeof(int32_t) : 0;
  file.Held.erase(std::remove_if(file.Held.begin(), file.Held.end(),
                    [&held](const std::weak_ptr<const std::atomic<uint64_t>>& w) {
                      const auto bytes = w.lock();
                      held += bytes ? bytes->load(std::memory_order_relaxed) : 0;
                      return !bytes;
                    }),
    file.Held.end());
  file.Resident.SetHeld(held);
  std::string why;
  if (!this->SourceFile->Resident.Enforce(&why) && !this->SourceFile->WarnedResident)
  {
    this->SourceFile->WarnedResident = true;
    vtkWarningMacro(<< "The octree file's cache limit is not kept: " << why << ".");
  }
  this->WarnIfDroppedMostFrames();
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::WarnIfDroppedMostFrames()
{
  // a limit below what the views read plus the arrays: the pages are dropped after most
  // executions and every frame maps them again (once per file, judged over a window)
  constexpr uint64_t Window = 64;
  SourceFileState& file = *this->SourceFile;
  const uint64_t releases = file.Resident.GetReleases();
  file.DroppingExecutions += releases != file.LastReleases ? 1 : 0;
  file.LastReleases = releases;
  if (++file.Executions < Window)
  {
    return;
  }
  if (file.DroppingExecutions >= Window / 4 && !file.WarnedDropping)
  {
    file.WarnedDropping = true;
    vtkWarningMacro(<< "The octree file's pages were dropped after " << file.DroppingExecutions
                    << " of the last " << Window << " executions: the cache limit ("
                    << (file.Resident.GetLimit() >> 20) << " MiB, of which "
                    << (file.Resident.GetHeld() >> 20)
                    << " MiB hold the filters' arrays) is below what the views read, so the "
                       "frames map their pages again. Raise the reader's CacheLimit for faster "
                       "frames.");
  }
  file.Executions = 0;
  file.DroppingExecutions = 0;
}

//------------------------------------------------------------------------------
std::shared_ptr<plod::CornerMemo> vtkMultiscaleOctree::GetCornerMemo()
{
  if (!this->CornerMemo)
  {
    this->CornerMemo = std::make_shared<plod::CornerMemo>();
  }
  return this->CornerMemo;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::ReleaseMappedPages()
{
  return this->SourceFile && this->SourceFile->Memory &&
    this->SourceFile->Resident.Release(nullptr);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::SetBackgroundLoading(bool on)
{
  if (!this->SourceFile || this->SourceFile->BackgroundLoading == on)
  {
    return;
  }
  this->SourceFile->BackgroundLoading = on;
  if (!on)
  {
    this->SourceFile->Loader = nullptr; // (joins its thread)
  }
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetBackgroundLoading()
{
  return this->SourceFile && this->SourceFile->BackgroundLoading;
}

//------------------------------------------------------------------------------
plod::PageLoader* vtkMultiscaleOctree::GetPageLoader()
{
  SourceFileState* file = this->SourceFile.get();
  if (!file || !file->BackgroundLoading || !file->Memory)
  {
    return nullptr;
  }
  if (!file->Loader)
  {
    plod::OctreeView view;
    if (!this->GetCheckedView(view, nullptr, nullptr))
    {
      return nullptr;
    }
    file->Loader = std::make_unique<plod::PageLoader>();
    file->Loader->SetOctree(view, file->Memory);
    file->Loader->SetResidentLimit(&file->Resident); // (declared before the loader: outlives it)
  }
  return file->Loader.get();
}

//------------------------------------------------------------------------------
plod::PageLoader* vtkMultiscaleOctree::CurrentPageLoader()
{
  return this->SourceFile ? this->SourceFile->Loader.get() : nullptr;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfBackgroundLoads()
{
  plod::PageLoader* loader = this->CurrentPageLoader();
  return loader ? static_cast<vtkIdType>(loader->GetLoaded()) : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfBackgroundMajorFaults()
{
  plod::PageLoader* loader = this->CurrentPageLoader();
  return loader ? static_cast<vtkIdType>(loader->GetMajorFaults()) : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfWaitingLoads()
{
  plod::PageLoader* loader = this->CurrentPageLoader();
  return loader ? static_cast<vtkIdType>(loader->GetWaiting()) : 0;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::WaitForLoads()
{
  if (plod::PageLoader* loader = this->CurrentPageLoader())
  {
    loader->WaitUntilIdle();
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetMappedResidentBytes()
{
  plod::MappingResidency r;
  if (!this->SourceFile || !this->SourceFile->Resident.Measure(r, nullptr))
  {
    return -1;
  }
  return static_cast<vtkIdType>(r.FileBytes + r.PrivateBytes);
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::CountHeldBytes(const std::shared_ptr<const std::atomic<uint64_t>>& bytes)
{
  if (!this->SourceFile || !bytes)
  {
    return;
  }
  for (const auto& w : this->SourceFile->Held)
  {
    if (w.lock() == bytes)
    {
      return;
    }
  }
  this->SourceFile->Held.push_back(bytes);
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetHeldBytes()
{
  return this->SourceFile ? static_cast<vtkIdType>(this->SourceFile->Resident.GetHeld()) : 0;
}

//------------------------------------------------------------------------------
vtkIdType vtkMultiscaleOctree::GetNumberOfResidentReleases()
{
  return this->SourceFile ? static_cast<vtkIdType>(this->SourceFile->Resident.GetReleases()) : 0;
}

//------------------------------------------------------------------------------
void vtkMultiscaleOctree::SetSourceFile(std::shared_ptr<const plod::FileIdentity> file)
{
  this->SourceFile = nullptr;
  if (file)
  {
    this->SourceFile = std::make_shared<SourceFileState>();
    this->SourceFile->File = std::move(file);
  }
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::IsSourceFileIntact(std::string* why)
{
  if (!this->SourceFile)
  {
    return true;
  }
  std::string what;
  switch (plod::CompareFileIdentity(*this->SourceFile->File, &what))
  {
    case plod::FileChange::Same:
      return true;
    case plod::FileChange::Replaced:
    case plod::FileChange::Gone:
      if (!this->SourceFile->WarnedReplaced)
      {
        this->SourceFile->WarnedReplaced = true;
        vtkWarningMacro(<< "The octree file " << what
                        << ": the octree goes on with the file it mapped; call Modified() on "
                           "the reader to read the new one.");
      }
      return true;
    case plod::FileChange::ChangedInPlace:
      break;
  }
  if (why)
  {
    *why = "the octree file " + what +
      ": its mapped pages can no longer be read safely; call Modified() on the reader to read "
      "it again";
  }
  return false;
}

//------------------------------------------------------------------------------
bool vtkMultiscaleOctree::GetCheckedView(
  plod::OctreeView& view, vtkMTimeType* time, std::string* why)
{
  if (!this->IsSourceFileIntact(why))
  {
    view = plod::OctreeView();
    return false;
  }
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
  os << indent << "CoarsestDrawnLevel: " << this->CoarsestDrawnLevel << "\n";
  os << indent << "NumberOfBoundaryEdges: " << this->NumberOfBoundaryEdges << "\n";
  os << indent << "NumberOfNonManifoldEdges: " << this->NumberOfNonManifoldEdges << "\n";
  os << indent << "NumberOfMisorientedEdges: " << this->NumberOfMisorientedEdges << "\n";
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
