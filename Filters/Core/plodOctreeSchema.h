// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeSchema.h
 * @brief The octree's arrays, listed once: name, group, type, components and meaning of each.
 *
 * Everything that names the octree's arrays is made from the lists below: the members of
 * plod::OctreeView and plod::OctreeArrays, the vectors of plod::OctreeStorage, the arrays of an
 * octree file (plodOctreeFile.h), the vtkFieldData arrays of vtkMultiscaleOctree and their
 * `...ArrayName()` functions, and the documentation's table (`docs/octree-schema.md`, written
 * by the program `plodSchemaTable` and compared with it by a test). A new array is one new line
 * here; the compiler then asks for it wherever an array is handled one by one.
 *
 * Each entry is `X(Member, Group, Type, Components, Meaning)`:
 * - `Member`: the C++ member name, which is also the array's name in vtkMultiscaleOctree
 *   (`Member` + `ArrayName()`) once the group's prefix is dropped (see ArrayName());
 * - `Group`: what the array has one tuple per: `Node`, `Cluster`, `Point` (surface point) or
 *   `Triangle` (surface triangle);
 * - `Type`: `uint8_t`, `int32_t`, `float` or `int64_t`;
 * - `Components`: values per tuple;
 * - `Meaning`: one line for the documentation.
 *
 * The structural rules that tie the arrays together (node order, ranges, ownership of
 * triangles, clusters) are plodOctree.h's.
 */
#ifndef plodOctreeSchema_h
#define plodOctreeSchema_h

#include <cstdint>
#include <string>

// clang-format off
/// The arrays every octree has, in file order.
#define PLOD_OCTREE_ARRAYS(X)                                                                      \
  X(Level, Node, uint8_t, 1, "level of the node, 0 for the root")                                  \
  X(Parent, Node, int32_t, 1, "parent node, -1 for the root")                                      \
  X(FirstChild, Node, int32_t, 1, "first child node (children are contiguous), -1 for a leaf")     \
  X(ChildMask, Node, uint8_t, 1, "bit c set when child c = x + 2y + 4z exists")                    \
  X(Vertex, Node, float, 3, "representative vertex, relative to the root origin")                  \
  X(ConeAxis, Node, float, 3, "normal cone axis (unit): the area-weighted mean normal")            \
  X(ConeAngle, Node, float, 1, "normal cone half angle in radians, in [0, pi]")                    \
  X(ShapeError, Node, float, 1, "shape error of SRCC eq. (3) over the points inside, world units") \
  X(DiffuseRange, Node, float, 2, "(min, max) diffuse reflectance in the cell")                    \
  X(SpecularRange, Node, float, 2, "(min, max) specular reflectance in the cell")                  \
  X(Flags, Node, uint8_t, 1, "bit 0: the sub-mesh is a union of discs; bit 1: boundary point")     \
  X(Thickness, Node, float, 1, "how thick a part collapsing an unsafe cell could lose, world units") \
  X(FirstPoint, Node, int32_t, 1, "first of the cell's points (to the next node of its level)")    \
  X(FirstTriangle, Node, int64_t, 1, "first of the triangles the node owns")                       \
  X(FirstCluster, Node, int32_t, 1, "first of the node's clusters (to the next node's)")           \
  X(ClusterNode, Cluster, int32_t, 1, "the cluster's node")                                        \
  X(ClusterParent, Cluster, int32_t, 1, "cluster of the parent node holding its points, -1 at the root") \
  X(ClusterVertex, Cluster, float, 3, "representative vertex, relative to the root origin")        \
  X(ClusterNormal, Cluster, float, 3, "shading normal (unit)")                                     \
  X(Points, Point, float, 3, "input points used by a triangle, in Morton order, relative to the root origin") \
  X(Normals, Point, float, 3, "unit shading normals (the input's, or as vtkPolyDataNormals computes)") \
  X(PointLeaf, Point, int32_t, 1, "the leaf holding each point")                                   \
  X(PointCluster, Point, int32_t, 1, "the leaf cluster holding each point")                        \
  X(InputPointId, Point, int64_t, 1, "each point's index in the builder's input, -1 if contoured") \
  X(Triangles, Triangle, int32_t, 3, "point indices, oriented as in the input, sorted by owner node")

/// The arrays an octree may lack (null in a view; not stored in octree files).
#define PLOD_OCTREE_OPTIONAL_ARRAYS(X)                                                             \
  X(PointGhost, Point, uint8_t, 1, "non-zero for a point owned by another process (a ghost)")
// clang-format on

/// Every array, the required ones first.
#define PLOD_OCTREE_ALL_ARRAYS(X) PLOD_OCTREE_ARRAYS(X) PLOD_OCTREE_OPTIONAL_ARRAYS(X)

namespace plod
{

/// What an array has one tuple per (the values are those of the file format).
enum class ArrayGroup : uint8_t
{
  Node = 0,
  Cluster = 1,
  Point = 2,
  Triangle = 3
};

/// The type of an array's values (the values are those of the file format).
enum class ArrayType : uint8_t
{
  UInt8 = 1,
  Int32 = 2,
  Float32 = 3,
  Int64 = 4
};

/// The ArrayType of a C++ value type.
template <typename T>
constexpr ArrayType ArrayTypeOf();
template <>
constexpr ArrayType ArrayTypeOf<uint8_t>()
{
  return ArrayType::UInt8;
}
template <>
constexpr ArrayType ArrayTypeOf<int32_t>()
{
  return ArrayType::Int32;
}
template <>
constexpr ArrayType ArrayTypeOf<float>()
{
  return ArrayType::Float32;
}
template <>
constexpr ArrayType ArrayTypeOf<int64_t>()
{
  return ArrayType::Int64;
}

/// Size in bytes of one value of a type (0 for an unknown type).
constexpr int ArrayTypeSize(ArrayType type)
{
  return type == ArrayType::UInt8                              ? 1
    : (type == ArrayType::Int32 || type == ArrayType::Float32) ? 4
    : type == ArrayType::Int64                                 ? 8
                                                               : 0;
}

/// One array of the schema.
struct ArraySpec
{
  const char* Member; // C++ member name
  const char* Name;   // name in vtkMultiscaleOctree and in octree files
  ArrayGroup Group;
  ArrayType Type;
  int Components;
  bool Optional;
  const char* Meaning;
};

/// The array's name: its member name without the group's prefix ("ClusterNode" is the cluster
/// array "Node"), so that each field data of vtkMultiscaleOctree reads naturally.
constexpr const char* ArrayName(const char* member, ArrayGroup group)
{
  return group == ArrayGroup::Cluster ? member + 7 : member; // strlen("Cluster") == 7
}

namespace schema_detail
{
constexpr bool StartsWithCluster(const char* s)
{
  const char prefix[] = "Cluster";
  for (int i = 0; i < 7; ++i)
  {
    if (s[i] != prefix[i])
    {
      return false;
    }
  }
  return true;
}
}

/// The schema, required arrays first, in file order.
inline constexpr ArraySpec OctreeSchema[] = {
#define PLOD_SPEC(member, group, type, comps, meaning)                                             \
  { #member, ArrayName(#member, ArrayGroup::group), ArrayGroup::group, ArrayTypeOf<type>(), comps, \
    false, meaning },
  PLOD_OCTREE_ARRAYS(PLOD_SPEC)
#undef PLOD_SPEC
#define PLOD_SPEC(member, group, type, comps, meaning)                                             \
  { #member, ArrayName(#member, ArrayGroup::group), ArrayGroup::group, ArrayTypeOf<type>(), comps, \
    true, meaning },
    PLOD_OCTREE_OPTIONAL_ARRAYS(PLOD_SPEC)
#undef PLOD_SPEC
};

/// Number of arrays in the schema, and of the required ones.
constexpr int OctreeSchemaSize = static_cast<int>(sizeof(OctreeSchema) / sizeof(OctreeSchema[0]));
constexpr int OctreeRequiredArrays = [] {
  int n = 0;
  for (const ArraySpec& s : OctreeSchema)
  {
    n += s.Optional ? 0 : 1;
  }
  return n;
}();

/// Bytes one tuple of `group` takes in the required arrays (a node, a cluster, a point, a
/// triangle).
constexpr int BytesPer(ArrayGroup group)
{
  int bytes = 0;
  for (const ArraySpec& s : OctreeSchema)
  {
    bytes += (s.Group == group && !s.Optional) ? s.Components * ArrayTypeSize(s.Type) : 0;
  }
  return bytes;
}

/// Every cluster array's member starts with "Cluster" (ArrayName drops it), and no other does.
constexpr bool ClusterPrefixesHold()
{
  for (const ArraySpec& s : OctreeSchema)
  {
    if (schema_detail::StartsWithCluster(s.Member) != (s.Group == ArrayGroup::Cluster))
    {
      return false;
    }
  }
  return true;
}
static_assert(ClusterPrefixesHold(), "cluster arrays are named Cluster<Name>, others are not");

// The documented sizes (docs/octree-schema.md, the builder's memory estimate): a change of the
// schema must change them too.
static_assert(BytesPer(ArrayGroup::Node) == 79, "bytes per node");
static_assert(BytesPer(ArrayGroup::Cluster) == 32, "bytes per cluster");
static_assert(BytesPer(ArrayGroup::Point) == 40, "bytes per surface point");
static_assert(BytesPer(ArrayGroup::Triangle) == 12, "bytes per surface triangle");

/// The group's name as the documentation writes it ("node", "cluster", "point", "triangle").
const char* ArrayGroupName(ArrayGroup group);

/// The type's name as the documentation writes it ("uint8", "int32", "float32", "int64").
const char* ArrayTypeName(ArrayType type);

/// The schema as a Markdown page: one table per group, with bytes per tuple.
std::string OctreeSchemaMarkdown();

} // namespace plod

#endif
