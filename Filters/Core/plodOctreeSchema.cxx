// SPDX-License-Identifier: BSD-3-Clause
#include "plodOctreeSchema.h"

#include <sstream>

namespace plod
{

const char* ArrayGroupName(ArrayGroup group)
{
  switch (group)
  {
    case ArrayGroup::Node:
      return "node";
    case ArrayGroup::Cluster:
      return "cluster";
    case ArrayGroup::Point:
      return "point";
    case ArrayGroup::Triangle:
      return "triangle";
  }
  return "?";
}

const char* ArrayTypeName(ArrayType type)
{
  switch (type)
  {
    case ArrayType::UInt8:
      return "uint8";
    case ArrayType::Int32:
      return "int32";
    case ArrayType::Float32:
      return "float32";
    case ArrayType::Int64:
      return "int64";
  }
  return "?";
}

std::string OctreeSchemaMarkdown()
{
  struct Section
  {
    ArrayGroup Group;
    const char* Title;
    const char* Where;
  };
  const Section sections[] = {
    { ArrayGroup::Node, "Node arrays", "`GetNodeData()`" },
    { ArrayGroup::Cluster, "Cluster arrays", "`GetClusterData()`" },
    { ArrayGroup::Point, "Surface point arrays", "`GetSurfaceData()`" },
    { ArrayGroup::Triangle, "Surface triangle arrays", "`GetSurfaceData()`" },
  };
  std::ostringstream md;
  md << "# The octree's arrays\n\n"
     << "Written by `plodSchemaTable` from `Filters/Core/plodOctreeSchema.h`, the one list of the\n"
     << "octree's arrays (a test compares this page with it). In vtkMultiscaleOctree each array\n"
     << "is a named array of the field data given below, one tuple per node, cluster, surface\n"
     << "point or surface triangle; `vtkMultiscaleOctree::<Member>ArrayName()` returns its name.\n"
     << "The VTK arrays are vtkUnsignedCharArray (uint8), vtkIntArray (int32), vtkFloatArray\n"
     << "(float32) and vtkIdTypeArray (int64). An octree file (`.plod`) stores the required\n"
     << "arrays under the same names.\n"
     << "Vertices and points are single precision relative to the root origin (kept in double).\n";
  for (const Section& s : sections)
  {
    md << "\n## " << s.Title << " (" << s.Where << ", " << BytesPer(s.Group) << " bytes per "
       << ArrayGroupName(s.Group) << ")\n\n"
       << "| name | member | type | components | meaning |\n"
       << "| --- | --- | --- | ---: | --- |\n";
    for (const ArraySpec& a : OctreeSchema)
    {
      if (a.Group == s.Group)
      {
        md << "| `" << a.Name << "` | `" << a.Member << "` | " << ArrayTypeName(a.Type) << " | "
           << a.Components << " | " << (a.Optional ? "optional: " : "") << a.Meaning << " |\n";
      }
    }
  }
  return md.str();
}

} // namespace plod
