// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeStorage.h
 * @brief VTK-free storage of an octree in vectors (LargeVector: huge pages where the kernel has
 * them): the Allocator plod::BuildOctree fills when no VTK data object receives the octree (tests,
 * fuzzers and programs that use the kernels alone), and the OctreeView of what was built.
 *
 * @code
 * plod::OctreeStorage storage;
 * const plod::BuildResult r = plod::BuildOctree(input, parameters, storage.MakeAllocator());
 * if (r.Ok) { const plod::OctreeView v = storage.View(r); ... }
 * @endcode
 */
#ifndef plodOctreeStorage_h
#define plodOctreeStorage_h

#include "plodLargeArrays.h"
#include "plodOctree.h"
#include "plodOctreeBuilder.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <vector>

namespace plod
{

struct OctreeStorage
{
  // one vector per array of plodOctreeSchema.h (PointGhost empty without ghosts)
#define PLOD_STORAGE_MEMBER(member, group, type, comps, meaning) LargeVector<type> member;
  PLOD_OCTREE_ALL_ARRAYS(PLOD_STORAGE_MEMBER)
#undef PLOD_STORAGE_MEMBER
  int64_t Nodes = -1, NumberOfPoints = -1, NumberOfTriangles = -1, Clusters = -1;
  /// The byte every value is made of before the build writes it (a poison for tests of reads
  /// the build should never make; 0 by default).
  uint8_t Fill = 0;

  /// The node, point and triangle arrays, each exactly as long as asked.
  OctreeArrays AllocateNodes(int64_t nodes, int64_t points, int64_t triangles)
  {
    this->Nodes = nodes;
    this->NumberOfPoints = points;
    this->NumberOfTriangles = triangles;
    OctreeArrays o;
    this->AllocateGroups(o, { ArrayGroup::Node, ArrayGroup::Point, ArrayGroup::Triangle });
    this->PointGhost.clear();
    return o;
  }

  /// The cluster arrays, set into `o`.
  void AllocateClusters(int64_t clusters, OctreeArrays& o)
  {
    this->Clusters = clusters;
    this->AllocateGroups(o, { ArrayGroup::Cluster });
  }

  /// The ghost flags, set into `o` (only for inputs with ghost flags).
  void AllocatePointGhosts(int64_t points, OctreeArrays& o)
  {
    this->Make(this->PointGhost, points);
    o.PointGhost = this->PointGhost.data();
  }

  /// An Allocator for plod::BuildOctree writing into this storage (which must outlive it).
  Allocator MakeAllocator()
  {
    Allocator a;
    a.Nodes = [this](int64_t nodes, int64_t points, int64_t triangles) {
      return this->AllocateNodes(nodes, points, triangles);
    };
    a.Clusters = [this](int64_t clusters, OctreeArrays& o) { this->AllocateClusters(clusters, o); };
    a.PointGhost = [this](
                     int64_t points, OctreeArrays& o) { this->AllocatePointGhosts(points, o); };
    return a;
  }

  /// The view of the octree built into this storage (`r` the build's result).
  OctreeView View(const BuildResult& r) const
  {
    OctreeView v;
    v.NumberOfNodes = this->Nodes;
    v.FinestLevel = r.FinestLevel;
    std::copy(r.Origin, r.Origin + 3, v.Origin);
    v.RootEdge = r.RootEdge;
    v.NumberOfClusters = this->Clusters;
    v.NumberOfPoints = this->NumberOfPoints;
    v.NumberOfTriangles = this->NumberOfTriangles;
#define PLOD_STORAGE_VIEW(member, group, type, comps, meaning) v.member = this->member.data();
    PLOD_OCTREE_ARRAYS(PLOD_STORAGE_VIEW)
#undef PLOD_STORAGE_VIEW
#define PLOD_STORAGE_VIEW(member, group, type, comps, meaning)                                     \
  v.member = this->member.empty() ? nullptr : this->member.data();
    PLOD_OCTREE_OPTIONAL_ARRAYS(PLOD_STORAGE_VIEW)
#undef PLOD_STORAGE_VIEW
    return v;
  }

private:
  /// Makes the arrays of `groups` (sized by the counts set above) and points `o` at them.
  void AllocateGroups(OctreeArrays& o, std::initializer_list<ArrayGroup> groups)
  {
    const int64_t tuples[4] = { this->Nodes, this->Clusters, this->NumberOfPoints,
      this->NumberOfTriangles };
#define PLOD_STORAGE_ALLOCATE(member, group, type, comps, meaning)                                 \
  if (std::find(groups.begin(), groups.end(), ArrayGroup::group) != groups.end())                  \
  {                                                                                                \
    this->Make(this->member, comps* tuples[static_cast<int>(ArrayGroup::group)]);                  \
    o.member = this->member.data();                                                                \
  }
    PLOD_OCTREE_ARRAYS(PLOD_STORAGE_ALLOCATE)
#undef PLOD_STORAGE_ALLOCATE
  }

  template <typename T>
  void Make(LargeVector<T>& v, int64_t n)
  {
    T value;
    std::memset(&value, this->Fill, sizeof value);
    v.assign(static_cast<size_t>(std::max<int64_t>(n, 0)), value);
  }
};

} // namespace plod

#endif
