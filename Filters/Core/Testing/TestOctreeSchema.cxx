// SPDX-License-Identifier: BSD-3-Clause
// The octree's schema (plodOctreeSchema.h) and what is made from it: the documentation's table,
// the storage's and the file's arrays.
#include "plodOctree.h"
#include "plodOctreeFile.h"
#include "plodOctreeSchema.h"
#include "plodOctreeStorage.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace
{

std::string ReadText(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The documentation's table is the schema's, so that it cannot drift from the code.
TEST(OctreeSchema, DocumentedTableIsTheSchema)
{
  const std::string path = std::string(PLOD_SOURCE_DIR) + "/docs/octree-schema.md";
  EXPECT_EQ(ReadText(path), plod::OctreeSchemaMarkdown())
    << path << " differs from plodOctreeSchema.h: regenerate it with `plodSchemaTable > " << path
    << "` (the program is built beside this test)";
}

// Names are unique within a group (the field data looks them up by name), and the cluster
// arrays drop their prefix.
TEST(OctreeSchema, NamesAreUniquePerGroupAndClusterPrefixesDropped)
{
  std::set<std::pair<int, std::string>> seen;
  std::set<std::string> members;
  for (const plod::ArraySpec& s : plod::OctreeSchema)
  {
    const int field = s.Group == plod::ArrayGroup::Triangle ? int(plod::ArrayGroup::Point)
                                                            : int(s.Group); // one surface data
    EXPECT_TRUE(seen.insert({ field, s.Name }).second) << s.Name;
    EXPECT_TRUE(members.insert(s.Member).second) << s.Member;
    EXPECT_EQ(std::string(s.Member),
      (s.Group == plod::ArrayGroup::Cluster ? std::string("Cluster") : std::string()) + s.Name);
  }
  EXPECT_STREQ(plod::OctreeSchema[0].Name, "Level");
  EXPECT_STREQ(plod::ArrayName("ClusterNormal", plod::ArrayGroup::Cluster), "Normal");
}

// Bytes per tuple, summed by hand from the table's types and components.
TEST(OctreeSchema, BytesPerTuple)
{
  EXPECT_EQ(plod::BytesPer(plod::ArrayGroup::Node),
    1 + 4 + 4 + 1 + 12 + 12 + 4 + 4 + 8 + 8 + 1 + 4 + 4 + 8 + 4);
  EXPECT_EQ(plod::BytesPer(plod::ArrayGroup::Cluster), 4 + 4 + 12 + 12);
  EXPECT_EQ(plod::BytesPer(plod::ArrayGroup::Point), 12 + 12 + 4 + 4 + 8); // no PointGhost
  EXPECT_EQ(plod::BytesPer(plod::ArrayGroup::Triangle), 12);
}

// The file stores the required arrays, in schema order, and no optional one.
TEST(OctreeSchema, FileSchemaIsTheRequiredArrays)
{
  const std::vector<plod::ArraySpec>& file = plod::OctreeFileSchema();
  ASSERT_EQ(static_cast<int>(file.size()), plod::OctreeRequiredArrays);
  for (size_t k = 0; k < file.size(); ++k)
  {
    EXPECT_STREQ(file[k].Member, plod::OctreeSchema[k].Member);
    EXPECT_FALSE(file[k].Optional);
  }
  int optional = 0;
  for (const plod::ArraySpec& s : plod::OctreeSchema)
  {
    optional += s.Optional ? 1 : 0;
  }
  EXPECT_EQ(optional, plod::OctreeSchemaSize - plod::OctreeRequiredArrays);
  EXPECT_GE(optional, 1);
}

// The storage makes every required array, sized by its group, and its view points at each; an
// optional array is null until allocated. FileArraysOf names them as the schema does.
TEST(OctreeSchema, StorageViewAndFileArraysFollowTheSchema)
{
  plod::OctreeStorage storage;
  plod::OctreeArrays o = storage.AllocateNodes(5, 7, 3);
  storage.AllocateClusters(6, o);
  plod::BuildResult r;
  r.FinestLevel = 1;
  const plod::OctreeView v = storage.View(r);
  const int64_t tuples[4] = { 5, 6, 7, 3 };
  int visited = 0;
  plod::ForEachArray(storage, [&](const plod::ArraySpec& spec, const auto& vector) {
    const int64_t expected = spec.Optional ? 0 : tuples[int(spec.Group)] * spec.Components;
    EXPECT_EQ(static_cast<int64_t>(vector.size()), expected) << spec.Member;
    EXPECT_EQ(static_cast<int>(sizeof(vector[0])), plod::ArrayTypeSize(spec.Type)) << spec.Member;
    ++visited;
  });
  EXPECT_EQ(visited, plod::OctreeSchemaSize);
  plod::ForEachArray(v, [&](const plod::ArraySpec& spec, const auto* pointer) {
    EXPECT_EQ(pointer == nullptr, spec.Optional) << spec.Member;
  });
  EXPECT_EQ(v.PointGhost, nullptr);
  plod::OctreeArrays withGhosts = o;
  storage.AllocatePointGhosts(7, withGhosts);
  EXPECT_NE(storage.View(r).PointGhost, nullptr);

  const std::vector<plod::FileArray> arrays = plod::FileArraysOf(v);
  ASSERT_EQ(static_cast<int>(arrays.size()), plod::OctreeRequiredArrays);
  for (size_t k = 0; k < arrays.size(); ++k)
  {
    const plod::ArraySpec& spec = plod::OctreeSchema[k];
    EXPECT_EQ(arrays[k].Name, spec.Name);
    EXPECT_EQ(arrays[k].Tuples, tuples[int(spec.Group)]) << spec.Name;
    EXPECT_NE(arrays[k].Data, nullptr) << spec.Name;
  }
  EXPECT_EQ(arrays[0].Data, static_cast<const void*>(v.Level));
}

// A view that lacks a required array is refused, naming it.
TEST(OctreeSchema, ValidationNamesAMissingArray)
{
  plod::OctreeStorage storage;
  plod::OctreeArrays o = storage.AllocateNodes(1, 0, 0);
  storage.AllocateClusters(1, o);
  plod::BuildResult r;
  plod::OctreeView v = storage.View(r);
  v.ConeAngle = nullptr;
  std::string why;
  EXPECT_FALSE(plod::ValidateOctree(v, &why));
  EXPECT_NE(why.find("ConeAngle"), std::string::npos) << why;
}

} // namespace
