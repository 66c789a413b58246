// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodTinyOctree.h
 * @brief A hand-made two-node octree for exact selector tests (VTK-free): a unit root cell at the
 * origin (level 0) with one finest child (child 0, the cell [0, 0.5]^3, level 1). Every quantity
 * the selector reads is a member the test sets.
 */
#ifndef plodTinyOctree_h
#define plodTinyOctree_h

#include "plodCut.h"
#include "plodOctree.h"
#include "plodSelector.h"

#include <cstdint>

namespace plodtest
{

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

  plod::OctreeView View()
  {
    plod::OctreeView v;
    v.NumberOfNodes = 2;
    v.FinestLevel = 1;
    v.RootEdge = 1;
    v.Level = Level;
    v.Parent = Parent;
    v.FirstChild = FirstChild;
    v.ChildMask = Mask;
    v.Vertex = Vertex;
    v.ConeAxis = Axis;
    v.ConeAngle = Angle;
    v.ShapeError = Shape;
    v.Diffuse = Diffuse;
    v.Specular = Specular;
    v.Flags = Flags;
    v.Thickness = Thickness;
    v.FirstPoint = FirstPoint;
    v.FirstTriangle = FirstTriangle;
    return v;
  }

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
