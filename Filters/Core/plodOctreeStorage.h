// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeStorage.h
 * @brief VTK-free storage of an octree in std::vectors: the Allocator plod::BuildOctree fills
 * when no VTK data object receives the octree (tests, fuzzers and programs that use the kernels
 * alone), and the OctreeView of what was built.
 *
 * @code
 * plod::OctreeStorage storage;
 * const plod::BuildResult r = plod::BuildOctree(input, parameters, storage.MakeAllocator());
 * if (r.Ok) { const plod::OctreeView v = storage.View(r); ... }
 * @endcode
 */
#ifndef plodOctreeStorage_h
#define plodOctreeStorage_h

#include "plodOctree.h"
#include "plodOctreeBuilder.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace plod
{

struct OctreeStorage
{
  std::vector<uint8_t> Level, ChildMask, Flags, PointGhost; // PointGhost: empty without ghosts
  std::vector<int32_t> Parent, FirstChild, FirstPoint, FirstCluster, ClusterNode, ClusterParent,
    PointLeaf, PointCluster, Triangles;
  std::vector<float> Vertex, ConeAxis, ConeAngle, ShapeError, Diffuse, Specular, Thickness,
    ClusterVertex, ClusterNormal, Points, Normals;
  std::vector<int64_t> FirstTriangle, InputPointId;
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
    this->Make(this->Level, nodes);
    this->Make(this->Parent, nodes);
    this->Make(this->FirstChild, nodes);
    this->Make(this->ChildMask, nodes);
    this->Make(this->Vertex, 3 * nodes);
    this->Make(this->ConeAxis, 3 * nodes);
    this->Make(this->ConeAngle, nodes);
    this->Make(this->ShapeError, nodes);
    this->Make(this->Diffuse, 2 * nodes);
    this->Make(this->Specular, 2 * nodes);
    this->Make(this->Flags, nodes);
    this->Make(this->Thickness, nodes);
    this->Make(this->FirstPoint, nodes);
    this->Make(this->FirstTriangle, nodes);
    this->Make(this->FirstCluster, nodes);
    this->Make(this->Points, 3 * points);
    this->Make(this->Normals, 3 * points);
    this->Make(this->PointLeaf, points);
    this->Make(this->PointCluster, points);
    this->Make(this->InputPointId, points);
    this->Make(this->Triangles, 3 * triangles);
    this->PointGhost.clear();
    OctreeArrays o;
    o.Level = this->Level.data();
    o.Parent = this->Parent.data();
    o.FirstChild = this->FirstChild.data();
    o.ChildMask = this->ChildMask.data();
    o.Vertex = this->Vertex.data();
    o.ConeAxis = this->ConeAxis.data();
    o.ConeAngle = this->ConeAngle.data();
    o.ShapeError = this->ShapeError.data();
    o.Diffuse = this->Diffuse.data();
    o.Specular = this->Specular.data();
    o.Flags = this->Flags.data();
    o.Thickness = this->Thickness.data();
    o.FirstPoint = this->FirstPoint.data();
    o.FirstTriangle = this->FirstTriangle.data();
    o.FirstCluster = this->FirstCluster.data();
    o.Points = this->Points.data();
    o.Normals = this->Normals.data();
    o.PointLeaf = this->PointLeaf.data();
    o.PointCluster = this->PointCluster.data();
    o.InputPointId = this->InputPointId.data();
    o.Triangles = this->Triangles.data();
    return o;
  }

  /// The cluster arrays, set into `o`.
  void AllocateClusters(int64_t clusters, OctreeArrays& o)
  {
    this->Clusters = clusters;
    this->Make(this->ClusterNode, clusters);
    this->Make(this->ClusterParent, clusters);
    this->Make(this->ClusterVertex, 3 * clusters);
    this->Make(this->ClusterNormal, 3 * clusters);
    o.ClusterNode = this->ClusterNode.data();
    o.ClusterParent = this->ClusterParent.data();
    o.ClusterVertex = this->ClusterVertex.data();
    o.ClusterNormal = this->ClusterNormal.data();
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
    v.Level = this->Level.data();
    v.Parent = this->Parent.data();
    v.FirstChild = this->FirstChild.data();
    v.ChildMask = this->ChildMask.data();
    v.Vertex = this->Vertex.data();
    v.ConeAxis = this->ConeAxis.data();
    v.ConeAngle = this->ConeAngle.data();
    v.ShapeError = this->ShapeError.data();
    v.Diffuse = this->Diffuse.data();
    v.Specular = this->Specular.data();
    v.Flags = this->Flags.data();
    v.Thickness = this->Thickness.data();
    v.FirstPoint = this->FirstPoint.data();
    v.FirstTriangle = this->FirstTriangle.data();
    v.FirstCluster = this->FirstCluster.data();
    v.NumberOfClusters = this->Clusters;
    v.ClusterNode = this->ClusterNode.data();
    v.ClusterParent = this->ClusterParent.data();
    v.ClusterVertex = this->ClusterVertex.data();
    v.ClusterNormal = this->ClusterNormal.data();
    v.NumberOfPoints = this->NumberOfPoints;
    v.Points = this->Points.data();
    v.Normals = this->Normals.data();
    v.PointLeaf = this->PointLeaf.data();
    v.PointCluster = this->PointCluster.data();
    v.InputPointId = this->InputPointId.data();
    v.PointGhost = this->PointGhost.empty() ? nullptr : this->PointGhost.data();
    v.NumberOfTriangles = this->NumberOfTriangles;
    v.Triangles = this->Triangles.data();
    return v;
  }

private:
  template <typename T>
  void Make(std::vector<T>& v, int64_t n)
  {
    T value;
    std::memset(&value, this->Fill, sizeof value);
    v.assign(static_cast<size_t>(std::max<int64_t>(n, 0)), value);
  }
};

} // namespace plod

#endif
