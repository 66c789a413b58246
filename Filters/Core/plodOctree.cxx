// SPDX-License-Identifier: BSD-3-Clause
#include "plodOctree.h"

#include <cmath>
#include <vector>

namespace plod
{

namespace
{
/// The counts, the arrays a non-empty octree needs, the root cube and the root. "" or what is
/// wrong.
std::string CheckOverall(const OctreeView& v)
{
  const int64_t n = v.NumberOfNodes;
  if (n < 0 || n > MaxIndex || v.NumberOfPoints < 0 || v.NumberOfPoints > MaxIndex ||
    v.NumberOfTriangles < 0 || v.NumberOfTriangles > MaxIndex || v.NumberOfClusters < n ||
    v.NumberOfClusters > MaxIndex)
  {
    return "node, point or triangle count out of range";
  }
  const char* missing = nullptr;
  ForEachArray(v, [&](const ArraySpec& spec, const auto* pointer) {
    if (!missing && !spec.Optional && v.TupleCount(spec.Group) > 0 && !pointer)
    {
      missing = spec.Member;
    }
  });
  if (missing)
  {
    return std::string("the octree array ") + missing + " is missing";
  }
  if (!(v.RootEdge > 0) || !std::isfinite(v.RootEdge) || v.FinestLevel < 0 ||
    v.FinestLevel > MaxFinestLevel || !std::isfinite(v.Origin[0]) || !std::isfinite(v.Origin[1]) ||
    !std::isfinite(v.Origin[2]))
  {
    return "invalid root cube or finest level";
  }
  if (v.Parent[0] != -1 || v.Level[0] != 0)
  {
    return "node 0 is not a root (parent -1, level 0)";
  }
  if (v.FirstPoint[0] != 0 || v.FirstTriangle[0] != 0 || v.FirstCluster[0] != 0)
  {
    return "the root's point, triangle and cluster ranges do not start at 0";
  }
  return std::string();
}

/// Node i against its parent and predecessor (order, levels, ranges), its children (which
/// must point back; `listedChildren` counts them) and its own values. "" or what is wrong.
std::string CheckNode(const OctreeView& v, int64_t i, int64_t& listedChildren)
{
  const int64_t n = v.NumberOfNodes;
  const std::string node = "node " + std::to_string(i);
  if (i > 0)
  {
    const int64_t p = v.Parent[i];
    if (p < 0 || p >= i)
    {
      return node + " has parent " + std::to_string(p) + " (must be a node before it)";
    }
    if (v.Level[p] + 1 != v.Level[i])
    {
      return node + " is not one level below its parent";
    }
    if (v.Level[i] < v.Level[i - 1])
    {
      return node + " breaks the level-by-level order";
    }
    if (v.FirstTriangle[i] < v.FirstTriangle[i - 1])
    {
      return node + " has a triangle range before its predecessor's";
    }
    if (v.FirstCluster[i] <= v.FirstCluster[i - 1])
    {
      return node + " has no cluster of its own or a cluster range out of order";
    }
    if (v.Level[i] == v.Level[i - 1] && v.FirstPoint[i] < v.FirstPoint[i - 1])
    {
      return node + " has a point range before its predecessor's";
    }
    if (v.Level[i] != v.Level[i - 1] && v.FirstPoint[i] != 0)
    {
      return node + " starts its level but not at point 0";
    }
  }
  if (v.Level[i] > v.FinestLevel)
  {
    return node + " is below the finest level";
  }
  if (v.FirstPoint[i] < 0 || v.FirstPoint[i] > v.NumberOfPoints || v.FirstTriangle[i] < 0 ||
    v.FirstTriangle[i] > v.NumberOfTriangles || v.FirstCluster[i] < 0 ||
    v.FirstCluster[i] >= v.NumberOfClusters)
  {
    return node + " has a point or triangle range outside the arrays";
  }
  const unsigned mask = v.ChildMask[i];
  if (mask == 0)
  {
    if (v.FirstChild[i] != -1)
    {
      return "leaf " + std::to_string(i) + " has a first child";
    }
    if (v.Level[i] != v.FinestLevel)
    {
      return "leaf " + std::to_string(i) + " is not at the finest level";
    }
  }
  else
  {
    const int count = __builtin_popcount(mask);
    listedChildren += count;
    const int64_t first = v.FirstChild[i];
    if (first <= i || first + count > n)
    {
      return node + " has children outside the node arrays";
    }
    for (int c = 0; c < count; ++c)
    {
      if (v.Parent[first + c] != i)
      {
        return "child " + std::to_string(first + c) + " does not point back to " +
          std::to_string(i);
      }
    }
    if (v.FirstPoint[first] != v.FirstPoint[i])
    {
      return node + " and its first child start at different points";
    }
  }
  if (!(v.ConeAngle[i] >= 0.0f && v.ConeAngle[i] <= 3.1416f) || !std::isfinite(v.Vertex[3 * i]) ||
    !std::isfinite(v.Vertex[3 * i + 1]) || !std::isfinite(v.Vertex[3 * i + 2]) ||
    !std::isfinite(v.ConeAxis[3 * i]) || !std::isfinite(v.ConeAxis[3 * i + 1]) ||
    !std::isfinite(v.ConeAxis[3 * i + 2]) || !(v.ShapeError[i] >= 0.0f) ||
    !(v.Thickness[i] >= 0.0f))
  {
    return node +
      " has a non-finite vertex or axis, a cone angle outside [0, pi] or a negative shape error "
      "or thickness";
  }
  return std::string();
}

/// The clusters of node i: each in its node's range, its parent a cluster of the parent node,
/// its vertex and normal finite. "" or what is wrong.
std::string CheckClusters(const OctreeView& v, int64_t i)
{
  for (int64_t c = v.FirstCluster[i], end = v.ClusterEnd(i); c < end; ++c)
  {
    const int64_t parent = v.ClusterParent[c];
    if (v.ClusterNode[c] != i)
    {
      return "cluster " + std::to_string(c) + " is in node " + std::to_string(i) +
        "'s range but names node " + std::to_string(v.ClusterNode[c]);
    }
    if (i == 0
        ? parent != -1
        : (parent < 0 || parent >= v.NumberOfClusters || v.ClusterNode[parent] != v.Parent[i]))
    {
      return "cluster " + std::to_string(c) + " has parent " + std::to_string(parent) +
        ", not a cluster of its node's parent";
    }
    if (!std::isfinite(v.ClusterVertex[3 * c]) || !std::isfinite(v.ClusterVertex[3 * c + 1]) ||
      !std::isfinite(v.ClusterVertex[3 * c + 2]) || !std::isfinite(v.ClusterNormal[3 * c]) ||
      !std::isfinite(v.ClusterNormal[3 * c + 1]) || !std::isfinite(v.ClusterNormal[3 * c + 2]))
    {
      return "cluster " + std::to_string(c) + " has a non-finite vertex or normal";
    }
  }
  return std::string();
}

/// Surface point p: its leaf holds it, its cluster is one of its leaf's. "" or what is wrong.
std::string CheckPoint(const OctreeView& v, int64_t p)
{
  const int64_t leaf = v.PointLeaf[p];
  if (leaf < 0 || leaf >= v.NumberOfNodes || v.ChildMask[leaf] != 0 || p < v.FirstPoint[leaf] ||
    p >= v.PointEnd(leaf))
  {
    return "point " + std::to_string(p) + " has leaf " + std::to_string(leaf) +
      ", which does not hold it";
  }
  const int64_t c = v.PointCluster[p];
  if (c < v.FirstCluster[leaf] || c >= v.ClusterEnd(leaf))
  {
    return "point " + std::to_string(p) + " has cluster " + std::to_string(c) +
      ", which is not a cluster of its leaf";
  }
  return std::string();
}
}

bool ValidateOctree(const OctreeView& v, std::string* why)
{
  auto fail = [why](const std::string& text) {
    if (why)
    {
      *why = text;
    }
    return false;
  };
  const int64_t n = v.NumberOfNodes;
  if (n == 0)
  {
    return true;
  }
  std::string problem = CheckOverall(v);
  int64_t listedChildren = 0; // children named by the masks (each points back: checked)
  for (int64_t i = 0; i < n && problem.empty(); ++i)
  {
    problem = CheckNode(v, i, listedChildren);
  }
  if (!problem.empty())
  {
    return fail(problem);
  }
  // every node but the root is some node's child: the listed children point back to their
  // parents, so they are distinct, and there must be n - 1 of them (a child mask that lost a
  // bit leaves a node that names a parent which does not list it; found by fuzzing)
  if (listedChildren != n - 1)
  {
    return fail("the child masks list " + std::to_string(listedChildren) + " children for " +
      std::to_string(n - 1) + " non-root nodes");
  }
  // a node's points end where the next node of its level starts: a child range must end
  // within its parent's (ranges are in Morton order, so nesting follows from the starts)
  for (int64_t i = 1; i < n; ++i)
  {
    const int64_t p = v.Parent[i];
    if (v.PointEnd(i) > v.PointEnd(p) || v.FirstPoint[i] < v.FirstPoint[p])
    {
      return fail("node " + std::to_string(i) + "'s points are not inside its parent's");
    }
  }
  for (int64_t i = 0; i < n && problem.empty(); ++i)
  {
    problem = CheckClusters(v, i);
  }
  for (int64_t p = 0; p < v.NumberOfPoints && problem.empty(); ++p)
  {
    problem = CheckPoint(v, p);
  }
  if (!problem.empty())
  {
    return fail(problem);
  }
  for (int64_t t = 0; t < 3 * v.NumberOfTriangles; ++t)
  {
    if (v.Triangles[t] < 0 || v.Triangles[t] >= v.NumberOfPoints)
    {
      return fail("triangle " + std::to_string(t / 3) + " refers to point " +
        std::to_string(v.Triangles[t]) + ", outside [0, " + std::to_string(v.NumberOfPoints) + ")");
    }
  }
  return true;
}

} // namespace plod
