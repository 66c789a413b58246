// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodTinyOctree.h
 * @brief Hand-made octrees for exact selector tests (VTK-free). Tiny: a unit root cell at the
 * origin (level 0) with one finest child (child 0, the cell [0, 0.5]^3, level 1). Fork: a root
 * with two finest children and triangle counts, for the triangle budget. Every quantity the
 * selector reads is a member the test sets.
 */
#ifndef plodTinyOctree_h
#define plodTinyOctree_h

#include "plodCut.h"
#include "plodOctree.h"
#include "plodSelector.h"

#include <cstdint>

namespace plodtest
{

/// The view of a hand-made octree `t` of `nodes` nodes (one level below the root), whose
/// members are named as in Tiny and Fork.
template <class T>
plod::OctreeView ViewOf(T& t, int nodes)
{
  plod::OctreeView v;
  v.NumberOfNodes = nodes;
  v.FinestLevel = 1;
  v.RootEdge = 1;
  v.Level = t.Level;
  v.Parent = t.Parent;
  v.FirstChild = t.FirstChild;
  v.ChildMask = t.Mask;
  v.Vertex = t.Vertex;
  v.ConeAxis = t.Axis;
  v.ConeAngle = t.Angle;
  v.ShapeError = t.Shape;
  v.DiffuseRange = t.Diffuse;
  v.SpecularRange = t.Specular;
  v.Flags = t.Flags;
  v.Thickness = t.Thickness;
  v.FirstPoint = t.FirstPoint;
  v.FirstTriangle = t.FirstTriangle;
  return v;
}

struct Tiny
{
  uint8_t Level[2] = { 0, 1 };
  int32_t Parent[2] = { -1, 0 };
  int32_t FirstChild[2] = { 1, -1 };
  uint8_t Mask[2] = { 1, 0 };
  float Vertex[6] = { 0.5f, 0.5f, 0.5f, 0.25f, 0.25f, 0.25f };
  float Axis[6] = { 0, 0, 1, 0, 0, 1 };
  float Angle[2] = { 0.2f, 0.0f };
  float Shape[2] = { 0.01f, 0.0f };
  float Diffuse[4] = { 1, 1, 1, 1 };  // (min, max) per node
  float Specular[4] = { 0, 0, 0, 0 }; // (min, max) per node
  uint8_t Flags[2] = { plod::NodeTopologySafe, plod::NodeTopologySafe };
  float Thickness[2] = { 0, 0 };
  int32_t FirstPoint[2] = { 0, 0 };
  int64_t FirstTriangle[2] = { 0, 0 };

  plod::OctreeView View() { return ViewOf(*this, 2); }

  /// Reason of the root after one selection (ReasonNone when it was refined); the child's reason
  /// in `childReason` when given.
  int RootReason(const plod::SelectionInput& in, int* childReason = nullptr)
  {
    plod::Selector s;
    s.SetOctree(this->View());
    uint8_t state[2] = { 0, 0 }, reason[2] = { 0, 0 };
    plod::SelectionStats stats;
    s.Select(in, state, reason, nullptr, stats);
    if (childReason)
      *childReason = reason[1];
    return reason[0];
  }
};

/**
 * A hand-made three-node octree for the budget walk: a unit root cell at the origin (level 0,
 * vertex (0.5, 0.5, 0.5)) with two finest children, A = child 0 (the cell [0, 0.5]^3, vertex
 * (0.25, 0.25, 0.25)) and B = child 1 (the cell [0.5, 1] x [0, 0.5]^2, vertex (0.75, 0.25,
 * 0.25)). Node 0 owns Owned[0] triangles, A Owned[1], B Owned[2]: the selector reads only the
 * counts, unless Points and Triangles are set (then the budget tells their faces from their
 * corners; PointGhost, when set, flags ghost points). Every axis +z; every quantity the
 * selector reads is a member.
 */
struct Fork
{
  uint8_t Level[3] = { 0, 1, 1 };
  int32_t Parent[3] = { -1, 0, 0 };
  int32_t FirstChild[3] = { 1, -1, -1 };
  uint8_t Mask[3] = { 3, 0, 0 };
  float Vertex[9] = { 0.5f, 0.5f, 0.5f, 0.25f, 0.25f, 0.25f, 0.75f, 0.25f, 0.25f };
  float Axis[9] = { 0, 0, 1, 0, 0, 1, 0, 0, 1 };
  float Angle[3] = { 0.2f, 0.2f, 0.2f };
  float Shape[3] = { 0, 0, 0 };
  float Diffuse[6] = { 1, 1, 1, 1, 1, 1 };  // (min, max) per node
  float Specular[6] = { 0, 0, 0, 0, 0, 0 }; // (min, max) per node
  uint8_t Flags[3] = { plod::NodeTopologySafe, plod::NodeTopologySafe, plod::NodeTopologySafe };
  float Thickness[3] = { 0, 0, 0 };
  int32_t FirstPoint[3] = { 0, 0, 0 };
  int64_t Owned[3] = { 0, 10, 10 };
  int64_t FirstTriangle[3] = { 0, 0, 0 };
  int64_t NumberOfPoints = 0;
  const float* Points = nullptr;       ///< 3 per point, or null
  const int32_t* Triangles = nullptr;  ///< 3 per owned triangle, in node order, or null
  const uint8_t* PointGhost = nullptr; ///< 1 per point, or null

  plod::OctreeView View()
  {
    this->FirstTriangle[0] = 0;
    this->FirstTriangle[1] = this->Owned[0];
    this->FirstTriangle[2] = this->Owned[0] + this->Owned[1];
    plod::OctreeView v = ViewOf(*this, 3);
    v.NumberOfTriangles = this->Owned[0] + this->Owned[1] + this->Owned[2];
    v.NumberOfPoints = this->NumberOfPoints;
    v.Points = this->Points;
    v.Triangles = this->Triangles;
    v.PointGhost = this->PointGhost;
    return v;
  }

  /// One selection: the three states and reasons, and the figures.
  struct Result
  {
    uint8_t State[3] = { 0, 0, 0 };
    uint8_t Reason[3] = { 0, 0, 0 };
    plod::SelectionStats Stats;
  };
  Result Select(const plod::SelectionInput& in)
  {
    plod::Selector s;
    s.SetOctree(this->View());
    Result r;
    s.Select(in, r.State, r.Reason, nullptr, r.Stats);
    return r;
  }
};

/// A viewer at (x, y, z) with screen distance `ds` pixels, no lights, no frustum.
inline plod::SelectionInput Viewer(double x, double y, double z, double ds = 1000)
{
  plod::SelectionInput in;
  in.Eye[0] = x;
  in.Eye[1] = y;
  in.Eye[2] = z;
  in.PixelScale = ds;
  return in;
}

} // namespace plodtest

#endif
