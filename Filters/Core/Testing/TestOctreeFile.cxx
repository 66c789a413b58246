// SPDX-License-Identifier: BSD-3-Clause
// The compact layout of octree files (plodOctreeFile, version 2), on arrays large enough to span
// several blocks: every value of every type comes back bit for bit (NaN payloads, extremes, the
// last short block), from arrays in memory and from arrays made by Values (called once, in
// order), the bytes do not depend on how the blocks were compressed, a damaged block or table is
// refused on every open with the array and the block named, and a version-1 file still opens.
#include "plodOctreeFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
std::string TempPath(const std::string& name)
{
  return ::testing::TempDir() + "plod_file_" + std::to_string(::getpid()) + "_" + name;
}

std::vector<char> ReadBytes(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteBytes(const std::string& path, const std::vector<char>& bytes)
{
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Arrays of every type, with values that stress the transform: smooth runs, noise, extremes,
/// NaNs with payloads, negative zeros; tuple counts that leave the last block short.
struct Arrays
{
  static constexpr int64_t Nodes = 200003;   // three blocks of 65536 and a short one
  static constexpr int64_t Points = 70001;   // one block and a short one
  static constexpr int64_t Triangles = 5;    // one short block
  static constexpr int64_t Clusters = 65536; // exactly one block
  std::vector<uint8_t> Level;
  std::vector<int32_t> Parent;
  std::vector<float> Vertex;
  std::vector<int64_t> First;
  std::vector<float> Normal;
  std::vector<int32_t> Triangle;
  std::vector<int32_t> ClusterNode;

  Arrays()
  {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> byte(0, 255);
    std::normal_distribution<float> noise(0.0f, 1.0f);
    for (int64_t i = 0; i < Nodes; ++i)
    {
      Level.push_back(static_cast<uint8_t>(i % 3 == 0 ? byte(rng) : i / 10000));
      Parent.push_back(i % 1000 == 0 ? std::numeric_limits<int32_t>::min()
          : i % 1001 == 0            ? std::numeric_limits<int32_t>::max()
                                     : static_cast<int32_t>(i / 8) - 1);
      First.push_back(i % 777 == 0 ? std::numeric_limits<int64_t>::min()
          : i % 778 == 0           ? std::numeric_limits<int64_t>::max()
                                   : int64_t(i) * 3 + (i % 5));
    }
    uint32_t nanBits = 0x7fc00123u, negativeZero = 0x80000000u;
    float nan, zero;
    std::memcpy(&nan, &nanBits, 4);
    std::memcpy(&zero, &negativeZero, 4);
    for (int64_t i = 0; i < Points * 3; ++i)
    {
      Vertex.push_back(i % 997 == 0 ? nan
          : i % 991 == 0            ? zero
          : i % 983 == 0            ? std::numeric_limits<float>::infinity()
                                    : 0.001f * float(i / 3) + 1e-4f * noise(rng));
      Normal.push_back(noise(rng));
    }
    for (int64_t i = 0; i < Triangles * 3; ++i)
    {
      Triangle.push_back(static_cast<int32_t>((i * 7919) % Points));
    }
    for (int64_t i = 0; i < Clusters; ++i)
    {
      ClusterNode.push_back(static_cast<int32_t>(i / 2));
    }
  }

  plod::OctreeFileHeader Header() const
  {
    plod::OctreeFileHeader h;
    h.Origin[0] = -1.5;
    h.RootEdge = 3;
    h.FinestLevel = 9;
    h.Nodes = Nodes;
    h.Points = Points;
    h.Triangles = Triangles;
    h.Clusters = Clusters;
    return h;
  }

  /// The arrays to write; `made` gives some of them through Values instead of Data, counting
  /// the values each call asks for in `calls` (first, count).
  std::vector<plod::FileArray> Files(
    bool made, std::vector<std::pair<int64_t, int64_t>>* calls = nullptr) const
  {
    std::vector<plod::FileArray> files;
    auto add = [&](const char* name, plod::FileArrayGroup group, plod::FileArrayType type,
                 int components, int64_t tuples, const void* data) {
      plod::FileArray f;
      f.Name = name;
      f.Group = group;
      f.Type = type;
      f.Components = components;
      f.Tuples = tuples;
      f.Data = data;
      files.push_back(f);
    };
    add("Level", plod::FileArrayGroup::Node, plod::FileArrayType::UInt8, 1, Nodes, Level.data());
    add("Parent", plod::FileArrayGroup::Node, plod::FileArrayType::Int32, 1, Nodes, Parent.data());
    add("First", plod::FileArrayGroup::Node, plod::FileArrayType::Int64, 1, Nodes, First.data());
    add("Points", plod::FileArrayGroup::Point, plod::FileArrayType::Float32, 3, Points,
      Vertex.data());
    add("Normals", plod::FileArrayGroup::Point, plod::FileArrayType::Float32, 3, Points,
      Normal.data());
    add("Triangles", plod::FileArrayGroup::Triangle, plod::FileArrayType::Int32, 3, Triangles,
      Triangle.data());
    add("Node", plod::FileArrayGroup::Cluster, plod::FileArrayType::Int32, 1, Clusters,
      ClusterNode.data());
    if (made)
    {
      for (plod::FileArray* f : { &files[2], &files[3] })
      {
        const auto* data = static_cast<const unsigned char*>(f->Data);
        const int size = plod::FileTypeSize(f->Type);
        f->Data = nullptr;
        f->Values = [data, size, calls](int64_t first, int64_t count, void* out, std::string*) {
          if (calls)
          {
            calls->push_back({ first, count });
          }
          EXPECT_LE(count * size, int64_t(1) << 20) << "at most 1 MiB at a time";
          std::memcpy(out, data + first * size, size_t(count) * size_t(size));
          return true;
        };
      }
    }
    return files;
  }
};

/// Every array of `file` equals `expected` byte for byte.
void ExpectSameValues(const std::vector<plod::FileArray>& expected, const plod::OctreeFile& file)
{
  ASSERT_EQ(file.Arrays.size(), expected.size());
  for (size_t a = 0; a < expected.size(); ++a)
  {
    const plod::FileArray& f = file.Arrays[a];
    EXPECT_EQ(f.Name, expected[a].Name);
    ASSERT_EQ(f.Tuples, expected[a].Tuples) << f.Name;
    ASSERT_EQ(f.Components, expected[a].Components) << f.Name;
    const size_t bytes = size_t(f.Tuples) * size_t(f.Components) * size_t(FileTypeSize(f.Type));
    if (bytes > 0)
    {
      EXPECT_EQ(std::memcmp(f.Data, expected[a].Data, bytes), 0) << f.Name;
    }
  }
}

/// Makes the header checksum of a file of `arrays` arrays agree with its bytes again (FNV-1a
/// over the header and directory, the checksum field counted as 0, folded to 32 bits), so that
/// damage made on purpose gets past the header.
void ResumHeader(std::vector<char>& b, size_t arrays)
{
  std::vector<unsigned char> head(b.begin(), b.begin() + 128 + 64 * arrays);
  std::fill(head.begin() + 120, head.begin() + 124, 0);
  uint64_t h = 14695981039346656037ull;
  for (unsigned char c : head)
  {
    h = (h ^ c) * 1099511628211ull;
  }
  const uint32_t sum = static_cast<uint32_t>(h ^ (h >> 32));
  std::memcpy(&b[120], &sum, 4);
}

/// Runs the ranges last to first, one value at a time (as threads might finish).
void BackwardsFor(int64_t n, int64_t, const std::function<void(int64_t, int64_t)>& body)
{
  for (int64_t b = n - 1; b >= 0; --b)
  {
    body(b, b + 1);
  }
}
}

TEST(OctreeFile, CompactLayoutKeepsEveryValueBitForBit)
{
  const Arrays data;
  const std::vector<plod::FileArray> expected = data.Files(false);
  const std::string mapped = TempPath("mapped.plod"), compact = TempPath("compact.plod");
  std::string why;
  ASSERT_TRUE(plod::WriteOctreeFile(mapped, data.Header(), expected, &why)) << why;
  plod::FileWriteOptions options;
  options.Layout = plod::FileLayout::Compact;
  ASSERT_TRUE(plod::WriteOctreeFile(compact, data.Header(), expected, options, &why)) << why;
  for (const std::string& path : { mapped, compact })
  {
    const bool isCompact = path == compact;
    for (bool map : { true, false })
      for (bool verify : { false, true })
      {
        SCOPED_TRACE(path + (map ? " mapped" : " read") + (verify ? " verified" : ""));
        plod::OctreeFile file;
        ASSERT_TRUE(plod::OpenOctreeFile(path, verify, map, file, &why)) << why;
        EXPECT_EQ(file.Compact, isCompact);
        EXPECT_EQ(file.Mapped, map && !isCompact) << "a compact file's arrays are decoded";
        ExpectSameValues(expected, file);
        EXPECT_EQ(file.Header.Nodes, Arrays::Nodes);
        EXPECT_EQ(file.Header.RootEdge, 3);
      }
  }
  const std::vector<char> m = ReadBytes(mapped), c = ReadBytes(compact);
  EXPECT_EQ(m[8], 1) << "the mapped layout is version 1";
  EXPECT_EQ(c[8], 2) << "the compact layout is version 2";
  // the smooth arrays shrink: the compact file is well under the mapped one
  EXPECT_LT(c.size(), m.size() * 6 / 10) << c.size() << " of " << m.size();
  std::remove(mapped.c_str());
  std::remove(compact.c_str());
}

TEST(OctreeFile, CompactBytesDoNotDependOnHowTheBlocksWereCompressed)
{
  const Arrays data;
  std::vector<std::pair<int64_t, int64_t>> calls;
  const std::string serial = TempPath("serial.plod"), backwards = TempPath("backwards.plod");
  plod::FileWriteOptions options;
  options.Layout = plod::FileLayout::Compact;
  std::string why;
  ASSERT_TRUE(plod::WriteOctreeFile(serial, data.Header(), data.Files(false), options, &why))
    << why;
  options.Parallel = BackwardsFor;
  ASSERT_TRUE(
    plod::WriteOctreeFile(backwards, data.Header(), data.Files(true, &calls), options, &why))
    << why;
  EXPECT_EQ(ReadBytes(serial), ReadBytes(backwards))
    << "arrays made by Values, blocks compressed in another order: the same file";
  // Values are called once over each array, in order
  int64_t expectedFirst = 0;
  int64_t values = 0;
  for (const auto& call : calls)
  {
    if (call.first == 0)
    {
      expectedFirst = 0; // the next array
    }
    EXPECT_EQ(call.first, expectedFirst);
    expectedFirst = call.first + call.second;
    values += call.second;
  }
  EXPECT_EQ(values, Arrays::Nodes + Arrays::Points * 3) << "each value made once";
  plod::OctreeFile file;
  ASSERT_TRUE(plod::OpenOctreeFile(backwards, false, true, file, &why, BackwardsFor)) << why;
  ExpectSameValues(data.Files(false), file);
  std::remove(serial.c_str());
  std::remove(backwards.c_str());
}

TEST(OctreeFile, DamagedCompactArraysAreRefusedOnEveryOpen)
{
  const Arrays data;
  const std::string path = TempPath("damaged.plod");
  plod::FileWriteOptions options;
  options.Layout = plod::FileLayout::Compact;
  std::string why;
  ASSERT_TRUE(plod::WriteOctreeFile(path, data.Header(), data.Files(false), options, &why)) << why;
  const std::vector<char> bytes = ReadBytes(path);
  // the directory: each array's offset (entries of 64 bytes from 128; offset at 48)
  auto offsetOf = [&](int a) {
    uint64_t offset;
    std::memcpy(&offset, &bytes[128 + 64 * a + 48], 8);
    return offset;
  };
  auto refused = [&](const std::vector<char>& b, const std::string& phrase) {
    WriteBytes(path, b);
    for (bool map : { true, false })
    {
      plod::OctreeFile file;
      std::string error;
      EXPECT_FALSE(plod::OpenOctreeFile(path, false, map, file, &error)) << phrase;
      EXPECT_NE(error.find(phrase), std::string::npos) << error;
      EXPECT_TRUE(file.Arrays.empty() && !file.Memory) << "nothing handed out";
    }
  };
  // a byte of the third block of "Parent" (array 1): its table is 8 + 4 x 4 bytes
  {
    std::vector<char> b = bytes;
    uint32_t sizes[4];
    std::memcpy(sizes, &b[offsetOf(1) + 8], 16);
    b[offsetOf(1) + 24 + sizes[0] + sizes[1] + 5] ^= 0x10;
    refused(b, "'Parent' is corrupt (checksum mismatch)");
  }
  // the tuples per block, a block's size, the number of blocks
  for (int at : { 0, 4, 8, 12 })
  {
    std::vector<char> b = bytes;
    b[offsetOf(2) + at] ^= 0x01;
    refused(b, "'First'");
  }
  // a block whose bytes are intact but say another length: the checksum made to agree (a
  // forged file), the decoder refuses the block
  {
    std::vector<char> b = bytes;
    const uint64_t at = offsetOf(6); // "Node": one block
    uint32_t size;
    std::memcpy(&size, &b[at + 8], 4);
    // the block's frame declares its content size; change one byte of the frame header
    b[at + 12 + 4 + 1] ^= 0x01;
    // recompute the array's checksum (blocks, then table) and the header's
    std::vector<unsigned char> stream(b.begin() + at + 12, b.begin() + at + 12 + size);
    stream.insert(stream.end(), b.begin() + at, b.begin() + at + 12);
    const uint64_t sum = plod::FileChecksum(stream.data(), stream.size());
    std::memcpy(&b[128 + 64 * 6 + 56], &sum, 8);
    ResumHeader(b, 7);
    refused(b, "'Node' is corrupt (block 0");
  }
  // an unknown encoding (the header's checksum made to agree)
  {
    std::vector<char> b = bytes;
    b[128 + 64 * 3 + 36] = 7;
    ResumHeader(b, 7);
    refused(b, "unknown encoding");
  }
  // truncated inside the last array
  {
    std::vector<char> b(bytes.begin(), bytes.end() - 3);
    refused(b, "truncated");
  }
  std::remove(path.c_str());
}

TEST(OctreeFile, ConversionBetweenLayoutsGivesTheFileWrittenDirectly)
{
  const Arrays data;
  const std::vector<plod::FileArray> arrays = data.Files(false);
  const std::string mapped = TempPath("direct-mapped.plod");
  const std::string compact = TempPath("direct-compact.plod");
  const std::string converted = TempPath("converted.plod");
  plod::FileWriteOptions toMapped, toCompact;
  toCompact.Layout = plod::FileLayout::Compact;
  std::string why;
  ASSERT_TRUE(plod::WriteOctreeFile(mapped, data.Header(), arrays, toMapped, &why)) << why;
  ASSERT_TRUE(plod::WriteOctreeFile(compact, data.Header(), arrays, toCompact, &why)) << why;
  // compact to mapped, block by block, and back
  ASSERT_TRUE(plod::ConvertOctreeFile(compact, converted, toMapped, &why)) << why;
  EXPECT_EQ(ReadBytes(converted), ReadBytes(mapped));
  ASSERT_TRUE(plod::ConvertOctreeFile(converted, converted, toCompact, &why)) << why;
  EXPECT_EQ(ReadBytes(converted), ReadBytes(compact)) << "converted in place, by a rename";
  // a damaged source is refused and the target left as it was
  std::vector<char> bytes = ReadBytes(compact);
  bytes[bytes.size() / 2] ^= 0x40; // inside the noisy normals
  WriteBytes(compact, bytes);
  const std::vector<char> before = ReadBytes(converted);
  EXPECT_FALSE(plod::ConvertOctreeFile(compact, converted, toMapped, &why));
  EXPECT_NE(why.find("corrupt"), std::string::npos) << why;
  EXPECT_EQ(ReadBytes(converted), before);
  for (const std::string& p : { mapped, compact, converted })
  {
    std::remove(p.c_str());
  }
}
