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

#include "plodOctree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <tuple>
#include <vector>

vtkStandardNewMacro(vtkPerceptualLODRedistribution);
vtkCxxSetObjectMacro(vtkPerceptualLODRedistribution, Controller, vtkMultiProcessController);

namespace
{
/// Doubles sent per triangle: 3 corners x 3 coordinates, then 3 x 3 normal components.
constexpr int CoordinatesPerTriangle = 9;

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

/// Integer cell coordinates at level 21 as the builder computes them (plodOctreeBuilder.cxx,
/// SortPoints): the same arithmetic, so that a point is in the same cell here and there.
struct CellGrid
{
  double Origin[3];
  double Scale;
  uint32_t Cell21(double x, int a) const
  {
    constexpr uint32_t cells = 1u << plod::MaxFinestLevel;
    const double u = (x - this->Origin[a]) * this->Scale;
    if (!(u >= 0))
    {
      return 0u;
    }
    return u >= double(cells) ? cells - 1 : static_cast<uint32_t>(u);
  }
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
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  const int rank = controller ? controller->GetLocalProcessId() : 0;
  const int k = this->OwnershipLevel;
  const int cellCount = 1 << (3 * k);

  // --- this rank's triangles, with their corners' coordinates (and normals)
  std::vector<vtkIdType> local;
  vtkPoints* inPoints = input ? input->GetPoints() : nullptr;
  if (input && inPoints)
  {
    CollectTriangles(input, local);
  }
  const vtkIdType localTriangles = static_cast<vtkIdType>(local.size() / 3);
  vtkDataArray* inNormals = input ? input->GetPointData()->GetNormals() : nullptr;
  int haveNormals = (inNormals || localTriangles == 0) ? 1 : 0;
  int allHaveNormals = haveNormals;
  double lo[3] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  double hi[3] = { -lo[0], -lo[1], -lo[2] };
  vtkIdType skipped = 0;
  std::vector<uint8_t> usable(localTriangles, 1);
  for (vtkIdType t = 0; t < localTriangles; ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      const vtkIdType id = local[3 * t + c];
      double x[3];
      if (id < 0 || id >= inPoints->GetNumberOfPoints())
      {
        usable[t] = 0;
        break;
      }
      inPoints->GetPoint(id, x);
      if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      {
        usable[t] = 0;
        break;
      }
    }
    if (!usable[t])
    {
      ++skipped;
      continue;
    }
    for (int c = 0; c < 3; ++c)
    {
      double x[3];
      inPoints->GetPoint(local[3 * t + c], x);
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = std::min(lo[a], x[a]);
        hi[a] = std::max(hi[a], x[a]);
      }
    }
  }
  if (skipped > 0)
  {
    vtkWarningMacro(<< skipped << " triangles of rank " << rank
                    << " have a point id out of range or a non-finite corner: left out");
  }

  // --- 1. the global bounds and the root cube
  double globalLo[3], globalHi[3];
  long long count = localTriangles - skipped, globalCount = 0;
  if (controller && ranks > 1)
  {
    controller->AllReduce(lo, globalLo, 3, vtkCommunicator::MIN_OP);
    controller->AllReduce(hi, globalHi, 3, vtkCommunicator::MAX_OP);
    controller->AllReduce(&count, &globalCount, 1, vtkCommunicator::SUM_OP);
    controller->AllReduce(&haveNormals, &allHaveNormals, 1, vtkCommunicator::MIN_OP);
  }
  else
  {
    std::copy(lo, lo + 3, globalLo);
    std::copy(hi, hi + 3, globalHi);
    globalCount = count;
  }
  if (globalCount == 0)
  {
    vtkWarningMacro("No rank holds a triangle: nothing to share out (point clouds are not "
                    "redistributed)");
    output->ShallowCopy(input);
    this->FinestLevel = std::max(0, this->RequestedFinestLevel);
    this->NumberOfBoundaryEdges = 0;
    return 1;
  }
  const double globalBounds[6] = { globalLo[0], globalHi[0], globalLo[1], globalHi[1], globalLo[2],
    globalHi[2] };
  if (!vtkMultiscaleOctreeBuilder::ComputeRootCube(globalBounds, this->RootOrigin, &this->RootEdge))
  {
    vtkErrorMacro("No root cube for the whole mesh: its bounds ("
      << globalLo[0] << " " << globalHi[0] << ", " << globalLo[1] << " " << globalHi[1] << ", "
      << globalLo[2] << " " << globalHi[2]
      << ") are not finite or their extent is outside [1e-30, 1e30]");
    return 0;
  }
  CellGrid grid;
  std::copy(this->RootOrigin, this->RootOrigin + 3, grid.Origin);
  grid.Scale = std::ldexp(1.0, plod::MaxFinestLevel) / this->RootEdge;
  const int shift = plod::MaxFinestLevel - k;

  // each usable triangle's box of level-k cells, one level-21 cell wider on each side (the
  // builder's triangle-box tests count a triangle that touches a cell's face)
  struct Box
  {
    uint32_t Lo[3], Hi[3];
  };
  std::vector<Box> boxes(localTriangles);
  std::vector<long long> perCell(cellCount, 0);
  for (vtkIdType t = 0; t < localTriangles; ++t)
  {
    if (!usable[t])
    {
      continue;
    }
    Box& b = boxes[t];
    uint32_t first[3] = { 0, 0, 0 };
    for (int a = 0; a < 3; ++a)
    {
      b.Lo[a] = std::numeric_limits<uint32_t>::max();
      b.Hi[a] = 0;
    }
    for (int c = 0; c < 3; ++c)
    {
      double x[3];
      inPoints->GetPoint(local[3 * t + c], x);
      for (int a = 0; a < 3; ++a)
      {
        const uint32_t u = grid.Cell21(x[a], a);
        if (c == 0)
        {
          first[a] = u >> shift;
        }
        b.Lo[a] = std::min(b.Lo[a], u > 0 ? u - 1 : 0u);
        b.Hi[a] = std::max(b.Hi[a], std::min(u + 1, (1u << plod::MaxFinestLevel) - 1));
      }
    }
    for (int a = 0; a < 3; ++a)
    {
      b.Lo[a] >>= shift;
      b.Hi[a] >>= shift;
    }
    ++perCell[plod::MortonEncode(first[0], first[1], first[2])];
  }

  // --- 2. owned cells: Morton-ordered runs of about equal triangle counts
  std::vector<long long> globalPerCell(cellCount, 0);
  if (controller && ranks > 1)
  {
    controller->AllReduce(perCell.data(), globalPerCell.data(), cellCount, vtkCommunicator::SUM_OP);
  }
  else
  {
    globalPerCell = perCell;
  }
  const long long total = std::accumulate(globalPerCell.begin(), globalPerCell.end(), 0LL);
  std::vector<int> owner(cellCount, 0);
  long long before = 0;
  this->NumberOfOwnedCells = 0;
  for (int cell = 0; cell < cellCount; ++cell)
  {
    const double middle = double(before) + 0.5 * double(globalPerCell[cell]);
    owner[cell] = std::min(ranks - 1, static_cast<int>(double(ranks) * middle / double(total)));
    before += globalPerCell[cell];
    if (owner[cell] == rank && globalPerCell[cell] > 0)
    {
      ++this->NumberOfOwnedCells;
    }
  }
  auto forEachCell = [&](const Box& b, auto&& body) {
    for (uint32_t z = b.Lo[2]; z <= b.Hi[2]; ++z)
    {
      for (uint32_t y = b.Lo[1]; y <= b.Hi[1]; ++y)
      {
        for (uint32_t x = b.Lo[0]; x <= b.Hi[0]; ++x)
        {
          body(static_cast<int>(plod::MortonEncode(x, y, z)));
        }
      }
    }
  };

  // --- 3. the cells each rank needs whole: its own, and every cell a triangle meeting its own
  // meets (rank-major masks, OR-ed over the ranks)
  std::vector<unsigned char> needs(static_cast<size_t>(ranks) * cellCount, 0);
  std::vector<int> touched;
  for (vtkIdType t = 0; t < localTriangles; ++t)
  {
    if (!usable[t])
    {
      continue;
    }
    touched.clear();
    forEachCell(boxes[t], [&](int cell) { touched.push_back(cell); });
    for (int cell : touched)
    {
      unsigned char* mask = needs.data() + static_cast<size_t>(owner[cell]) * cellCount;
      for (int other : touched)
      {
        mask[other] = 1;
      }
    }
  }
  std::vector<unsigned char> globalNeeds(needs.size(), 0);
  if (controller && ranks > 1)
  {
    controller->AllReduce(needs.data(), globalNeeds.data(), static_cast<vtkIdType>(needs.size()),
      vtkCommunicator::MAX_OP);
  }
  else
  {
    globalNeeds = needs;
  }

  // --- the exchange: one GatherV per destination rank
  const int stride = CoordinatesPerTriangle * (allHaveNormals ? 2 : 1);
  std::vector<double> received;
  for (int destination = 0; destination < ranks; ++destination)
  {
    const unsigned char* mask = globalNeeds.data() + static_cast<size_t>(destination) * cellCount;
    vtkNew<vtkDoubleArray> send;
    send->SetNumberOfComponents(1);
    for (vtkIdType t = 0; t < localTriangles; ++t)
    {
      if (!usable[t])
      {
        continue;
      }
      bool meets = false;
      forEachCell(boxes[t], [&](int cell) { meets = meets || mask[cell]; });
      if (!meets)
      {
        continue;
      }
      double x[3];
      for (int c = 0; c < 3; ++c)
      {
        inPoints->GetPoint(local[3 * t + c], x);
        send->InsertNextTuple1(x[0]);
        send->InsertNextTuple1(x[1]);
        send->InsertNextTuple1(x[2]);
      }
      if (allHaveNormals)
      {
        for (int c = 0; c < 3; ++c)
        {
          inNormals->GetTuple(local[3 * t + c], x);
          send->InsertNextTuple1(x[0]);
          send->InsertNextTuple1(x[1]);
          send->InsertNextTuple1(x[2]);
        }
      }
    }
    vtkNew<vtkDoubleArray> gathered;
    if (controller && ranks > 1)
    {
      controller->GatherV(send, gathered, destination);
    }
    else
    {
      gathered->DeepCopy(send);
    }
    if (destination == rank)
    {
      const double* data = gathered->GetPointer(0);
      received.assign(data, data + gathered->GetNumberOfValues());
    }
  }

  // --- merge coincident points, canonical order. Pieces duplicate the points along their
  // borders, and not always to the last bit (a source that computes each piece's border from
  // its own start angle): points closer than RootEdge / 2^32 on every axis, far below the
  // single precision in which the octree keeps points, are one point. Sorted by that key, then
  // by exact coordinates, so that every rank picks the same representative.
  const vtkIdType n = static_cast<vtkIdType>(received.size()) / stride;
  std::vector<int64_t> corner(3 * n);
  std::iota(corner.begin(), corner.end(), 0);
  auto position = [&](int64_t c) { return received.data() + (c / 3) * stride + (c % 3) * 3; };
  const double quantum = std::ldexp(this->RootEdge, -32);
  std::vector<std::array<int64_t, 3>> key(3 * n);
  for (int64_t c = 0; c < 3 * n; ++c)
  {
    const double* p = position(c);
    for (int a = 0; a < 3; ++a)
    {
      key[c][a] = std::llround((p[a] - this->RootOrigin[a]) / quantum);
    }
  }
  std::sort(corner.begin(), corner.end(), [&](int64_t a, int64_t b) {
    if (key[a] != key[b])
    {
      return key[a] < key[b];
    }
    const double* p = position(a);
    const double* q = position(b);
    return std::lexicographical_compare(p, p + 3, q, q + 3) || (std::equal(p, p + 3, q) && a < b);
  });
  std::vector<vtkIdType> pointOf(3 * n);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  vtkIdType ghostPoints = 0;
  for (size_t i = 0; i < corner.size(); ++i)
  {
    const double* p = position(corner[i]);
    if (i == 0 || key[corner[i]] != key[corner[i - 1]])
    {
      points->InsertNextPoint(p);
      if (allHaveNormals)
      {
        normals->InsertNextTuple(p + CoordinatesPerTriangle);
      }
      const int cell = static_cast<int>(plod::MortonEncode(grid.Cell21(p[0], 0) >> shift,
        grid.Cell21(p[1], 1) >> shift, grid.Cell21(p[2], 2) >> shift));
      const bool ghost = owner[cell] != rank;
      ghosts->InsertNextValue(ghost ? vtkDataSetAttributes::DUPLICATEPOINT : 0);
      ghostPoints += ghost;
    }
    pointOf[corner[i]] = points->GetNumberOfPoints() - 1;
  }
  // triangles in a canonical order too (by their point ids, orientation kept)
  std::vector<std::array<vtkIdType, 3>> triangles(n);
  for (vtkIdType t = 0; t < n; ++t)
  {
    triangles[t] = { pointOf[3 * t], pointOf[3 * t + 1], pointOf[3 * t + 2] };
  }
  std::sort(triangles.begin(), triangles.end());
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(n, 3 * n);
  vtkIdType halo = 0;
  for (const auto& t : triangles)
  {
    polys->InsertNextCell({ t[0], t[1], t[2] });
    halo += ghosts->GetValue(t[0]) && ghosts->GetValue(t[1]) && ghosts->GetValue(t[2]);
  }
  this->NumberOfHaloTriangles = halo;

  // --- edges that forbid hiding back faces, over the whole mesh: boundary edges (used by one
  // triangle) and misoriented ones (used by two triangles in the same direction). An edge with
  // an end this rank owns has all its triangles here (they all hold that end), so its uses are
  // exact; summed over the ranks (an edge two ranks see is counted twice: only zero matters).
  // The halo's own rim is never counted: its edges have both ends on other ranks.
  {
    // (lower end, higher end, 1 when used from the higher end down)
    std::vector<std::tuple<vtkIdType, vtkIdType, int>> edges;
    edges.reserve(3 * triangles.size());
    for (const auto& t : triangles)
    {
      for (int e = 0; e < 3; ++e)
      {
        const vtkIdType a = t[e], b = t[(e + 1) % 3];
        if (!ghosts->GetValue(a) || !ghosts->GetValue(b))
        {
          edges.emplace_back(std::min(a, b), std::max(a, b), a > b ? 1 : 0);
        }
      }
    }
    std::sort(edges.begin(), edges.end());
    long long boundary = 0;
    for (size_t i = 0; i < edges.size();)
    {
      size_t j = i + 1;
      while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
        std::get<1>(edges[j]) == std::get<1>(edges[i]))
      {
        ++j;
      }
      boundary +=
        (j - i == 1) || (j - i == 2 && std::get<2>(edges[i]) == std::get<2>(edges[i + 1]));
      i = j;
    }
    long long globalBoundary = boundary;
    if (controller && ranks > 1)
    {
      controller->AllReduce(&boundary, &globalBoundary, 1, vtkCommunicator::SUM_OP);
    }
    this->NumberOfBoundaryEdges = globalBoundary;
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetPointData()->AddArray(ghosts);
  if (allHaveNormals)
  {
    output->GetPointData()->SetNormals(normals);
  }

  // --- 5. one finest level: occupied cells per level, owned points counted once over the ranks
  if (this->RequestedFinestLevel >= 0)
  {
    this->FinestLevel = std::min(this->RequestedFinestLevel, plod::MaxFinestLevel);
    return 1;
  }
  std::vector<uint64_t> keys;
  keys.reserve(points->GetNumberOfPoints());
  for (vtkIdType p = 0; p < points->GetNumberOfPoints(); ++p)
  {
    if (!ghosts->GetValue(p))
    {
      double x[3];
      points->GetPoint(p, x);
      keys.push_back(
        plod::MortonEncode(grid.Cell21(x[0], 0), grid.Cell21(x[1], 1), grid.Cell21(x[2], 2)));
    }
  }
  std::sort(keys.begin(), keys.end());
  long long cells[plod::MaxFinestLevel + 1] = {};
  for (int l = k; l <= plod::MaxFinestLevel; ++l)
  {
    const int drop = 3 * (plod::MaxFinestLevel - l);
    for (size_t i = 0; i < keys.size(); ++i)
    {
      cells[l] += (i == 0 || (keys[i] >> drop) != (keys[i - 1] >> drop));
    }
  }
  long long globalCells[plod::MaxFinestLevel + 1] = {};
  long long pointCount = static_cast<long long>(keys.size()), globalPoints = pointCount;
  if (controller && ranks > 1)
  {
    controller->AllReduce(cells, globalCells, plod::MaxFinestLevel + 1, vtkCommunicator::SUM_OP);
    controller->AllReduce(&pointCount, &globalPoints, 1, vtkCommunicator::SUM_OP);
  }
  else
  {
    std::copy(cells, cells + plod::MaxFinestLevel + 1, globalCells);
  }
  // levels above k: from the shared histogram of level-k cells
  for (int l = 0; l < k; ++l)
  {
    std::vector<char> seen(size_t(1) << (3 * l), 0);
    for (int cell = 0; cell < cellCount; ++cell)
    {
      if (globalPerCell[cell] > 0 && !seen[cell >> (3 * (k - l))])
      {
        seen[cell >> (3 * (k - l))] = 1;
        ++globalCells[l];
      }
    }
  }
  // the builder's rule, without its memory lowering (the limit is each rank's: a rank whose
  // share would not fit fails its build with a message)
  this->FinestLevel =
    vtkMultiscaleOctreeBuilder::ChooseFinestLevelFromCounts(globalCells, globalPoints, false);
  if (this->FinestLevel < 0)
  {
    vtkErrorMacro("Inconsistent occupied-cell counts over the ranks: no common finest level");
    return 0;
  }
  return 1;
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
