// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file FuzzOctreeFile.cxx
 * @brief libFuzzer target for octree files (plodOctreeFile) and for the octree validation a
 * file's arrays then meet (plod::ValidateOctree), with the cut, patches and selector run on
 * whatever the validation accepts.
 *
 * Each input builds a small valid octree (a noisy closed UV sphere or an open sheet whose size,
 * noise and level come from the first bytes), writes it as a `.plod` file, damages the file as
 * the rest of the input says, and opens it:
 *
 *   byte 0: shape (bit 0: open sheet), resolution 3 + (byte >> 1) % 14
 *   byte 1: finest level: -1 (automatic) or 1 + byte % 7
 *   byte 2: flags. bit 0: recompute the header checksum and size after the damage (so that
 *           the damage reaches the arrays and the validation); bit 1: verify the arrays'
 *           checksums; bit 2: read into memory instead of mapping; bit 3: truncate at the
 *           position of the first edit; bit 4: once opened, save the undamaged octree over
 *           the open file (plod::WriteOctreeFile); bit 5: once opened, truncate the open file
 *           in place to half its size; bit 6: write the compact layout (FileLayout::Compact:
 *           compressed blocks, decoded on opening, their checksums always verified)
 *   then edits of 5 bytes: a position (uint32 little-endian, modulo the file size) and a byte
 *           to XOR there (0 sets the byte to 0xff)
 *
 * Checked: OpenOctreeFile never crashes, and when it accepts the file every array lies inside
 * its memory (every byte is read); when the arrays make a view that ValidateOctree accepts,
 * uniform cuts and the full cut pass ValidateCut and GeneratePatches returns in-range output,
 * and the selector's cut passes ValidateCut. The undamaged file reads back bit for bit. A save
 * over the open file leaves what it mapped byte for byte as it was and is reported as a
 * replacement (CompareFileIdentity); a truncation in place is reported as a change in place
 * (after which the arrays are not read: their pages may be gone).
 * PLOD_FUZZ_VERBOSE=1 names the array and value each edit damages.
 */
#include "plodCut.h"
#include "plodFuzzCheck.h"
#include "plodOctree.h"
#include "plodOctreeBuilder.h"
#include "plodOctreeFile.h"
#include "plodOctreeStorage.h"
#include "plodPatches.h"
#include "plodSelector.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
#define CHECK(cond, what) PLOD_FUZZ_CHECK("FuzzOctreeFile", cond, what)

void CheckPatches(const plod::OctreeView& v, const uint8_t* state, const std::string& what)
{
  plod::PatchResult out;
  std::string why;
  const bool ok = plod::GeneratePatches(v, state, nullptr, out, &why);
  CHECK(ok, what + ": " + why);
  const int64_t points = static_cast<int64_t>(out.PointSource.size());
  for (int64_t t : out.Triangles)
  {
    CHECK(t >= 0 && t < points, what + ": corner out of range");
  }
  for (int64_t s : out.PointSource)
  {
    CHECK((s >= 0 && s < v.NumberOfClusters) || (s < 0 && -1 - s < v.NumberOfPoints),
      what + ": source out of range");
  }
}
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size < 3)
  {
    return 0;
  }
  // the model: a noisy closed UV sphere or an open sheet
  const bool sheet = data[0] & 1;
  const int res = 3 + (data[0] >> 1) % 14;
  uint32_t seed = 2166136261u;
  for (size_t i = 0; i < size; ++i)
    seed = (seed ^ data[i]) * 16777619u;
  auto noise = [&seed]() {
    seed = seed * 1664525u + 1013904223u;
    return double(seed >> 8) / double(1u << 24) - 0.5;
  };
  std::vector<double> points;
  std::vector<int64_t> triangles;
  const int nu = res, nv = res;
  for (int i = 0; i <= nv; ++i)
    for (int j = 0; j < nu; ++j)
    {
      const double u = 2 * M_PI * j / nu, w = M_PI * i / nv;
      const double r = 1 + 0.2 * noise();
      if (sheet)
        points.insert(points.end(), { double(j), double(i), 0.3 * noise() });
      else
        points.insert(points.end(),
          { r * std::sin(w) * std::cos(u), r * std::sin(w) * std::sin(u), r * std::cos(w) });
    }
  for (int i = 0; i < nv; ++i)
    for (int j = 0; j < nu; ++j)
    {
      if (sheet && j + 1 == nu)
        continue;
      const int64_t a = i * nu + j, b = i * nu + (j + 1) % nu, c = a + nu, d = b + nu;
      triangles.insert(triangles.end(), { a, b, d, a, d, c });
    }
  plod::OctreeStorage storage;
  plod::BuildInput in;
  in.NumberOfPoints = static_cast<int64_t>(points.size() / 3);
  in.Points = points.data();
  in.NumberOfTriangles = static_cast<int64_t>(triangles.size() / 3);
  in.Triangles = triangles.data();
  plod::BuildParameters params;
  params.FinestLevel = data[1] < 64 ? -1 : 1 + data[1] % 7;
  const plod::BuildResult r = plod::BuildOctree(in, params, storage.MakeAllocator());
  if (!r.Ok)
  {
    return 0;
  }
  plod::OctreeFileHeader header;
  for (int k = 0; k < 3; ++k)
    header.Origin[k] = r.Origin[k];
  header.RootEdge = r.RootEdge;
  header.FinestLevel = r.FinestLevel;
  header.Nodes = r.NumberOfNodes;
  header.Points = r.NumberOfPoints;
  header.Triangles = r.NumberOfTriangles;
  header.Clusters = r.NumberOfClusters;
  header.BoundaryEdges = r.NumberOfBoundaryEdges;
  header.NonManifoldEdges = r.NumberOfNonManifoldEdges;
  const std::string path = "/tmp/plod_fuzz_file_" + std::to_string(::getpid()) + ".plod";
  std::string why;
  const std::vector<plod::FileArray> written = plod::FileArraysOf(storage.View(r));
  plod::FileWriteOptions layout;
  layout.Layout = (data[2] & 64) ? plod::FileLayout::Compact : plod::FileLayout::Mapped;
  CHECK(plod::WriteOctreeFile(path, header, written, layout, &why), why);

  // the undamaged file reads back bit for bit
  std::ifstream original(path, std::ios::binary);
  std::vector<char> bytes(
    (std::istreambuf_iterator<char>(original)), std::istreambuf_iterator<char>());
  original.close();
  if (size == 3)
  {
    plod::OctreeFile file;
    CHECK(plod::OpenOctreeFile(path, true, true, file, &why), why);
    for (size_t a = 0; a < written.size(); ++a)
    {
      const size_t n =
        size_t(written[a].Tuples) * written[a].Components * plod::FileTypeSize(written[a].Type);
      CHECK(n == 0 || std::memcmp(written[a].Data, file.Arrays[a].Data, n) == 0, written[a].Name);
    }
  }

  // the damage
  const uint8_t flags = data[2];
  size_t first = bytes.size();
  for (size_t i = 3; i + 5 <= size; i += 5)
  {
    uint32_t at;
    std::memcpy(&at, data + i, 4);
    const size_t pos = at % bytes.size();
    first = std::min(first, pos);
    bytes[pos] = data[i + 4] ? char(bytes[pos] ^ data[i + 4]) : char(0xff);
    if (std::getenv("PLOD_FUZZ_VERBOSE"))
    {
      // which array (and value) the damaged byte belongs to
      uint64_t offset = 0;
      for (const plod::FileArray& f : written)
      {
        const uint64_t n = uint64_t(f.Tuples) * f.Components * plod::FileTypeSize(f.Type);
        if (n == 0)
          continue;
        offset = (offset == 0) ? ((128 + 64 * written.size() + 4095) / 4096 * 4096) : offset;
        if (pos >= offset && pos < offset + n)
        {
          std::fprintf(stderr, "edit at %zu: array %s value %llu (of %lld tuples x %d)\n", pos,
            f.Name.c_str(), (unsigned long long)((pos - offset) / plod::FileTypeSize(f.Type)),
            (long long)f.Tuples, f.Components);
        }
        offset = (offset + n + 4095) / 4096 * 4096;
      }
    }
  }
  if ((flags & 8) && first < bytes.size())
  {
    bytes.resize(first);
  }
  if ((flags & 1) && bytes.size() >= 128)
  {
    // make the header agree with the damage, so that it reaches the arrays
    const uint64_t total = bytes.size();
    std::memcpy(&bytes[112], &total, 8);
    uint32_t headerSize;
    std::memcpy(&headerSize, &bytes[16], 4);
    if (headerSize <= bytes.size())
    {
      uint64_t h = 14695981039346656037ull;
      for (size_t i = 0; i < headerSize; ++i)
      {
        const unsigned char b = (i >= 120 && i < 124) ? 0 : static_cast<unsigned char>(bytes[i]);
        h = (h ^ b) * 1099511628211ull;
      }
      const uint32_t sum = static_cast<uint32_t>(h ^ (h >> 32));
      std::memcpy(&bytes[120], &sum, 4);
    }
  }
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  plod::OctreeFile file;
  const bool opened = plod::OpenOctreeFile(path, flags & 2, !(flags & 4), file, &why);
  if (opened && (flags & 16))
  {
    // a save over the open file replaces it by a rename: the opened bytes stay as they were
    auto arrayBytes = [&file]() {
      std::vector<unsigned char> all;
      for (const plod::FileArray& f : file.Arrays)
      {
        const size_t n = size_t(f.Tuples) * f.Components * plod::FileTypeSize(f.Type);
        const unsigned char* p = static_cast<const unsigned char*>(f.Data);
        all.insert(all.end(), p, p + n);
      }
      return all;
    };
    const std::vector<unsigned char> before = arrayBytes();
    CHECK(plod::WriteOctreeFile(path, header, written, layout, &why), why);
    std::string change;
    CHECK(plod::CompareFileIdentity(file.Identity, &change) == plod::FileChange::Replaced,
      "a save over an open file is not seen as a replacement: " + change);
    CHECK(arrayBytes() == before, "a save changed the bytes of the open file");
  }
  else if (opened && (flags & 32))
  {
    // a program truncates the open file where it lies: noticed before any page is read
    CHECK(::truncate(path.c_str(), static_cast<off_t>(bytes.size() / 2)) == 0, "truncate");
    std::string change;
    CHECK(plod::CompareFileIdentity(file.Identity, &change) == plod::FileChange::ChangedInPlace,
      "a truncation in place is not seen: " + change);
    std::remove(path.c_str());
    return 0;
  }
  std::remove(path.c_str());
  if (!opened)
  {
    CHECK(!why.empty(), "a refused file without a reason");
    return 0;
  }
  // every array lies in the memory: read all of it
  unsigned sum = 0;
  for (const plod::FileArray& f : file.Arrays)
  {
    const size_t n = size_t(f.Tuples) * f.Components * plod::FileTypeSize(f.Type);
    const unsigned char* p = static_cast<const unsigned char*>(f.Data);
    for (size_t i = 0; i < n; ++i)
      sum += p[i];
  }
  (void)sum;
  plod::OctreeView v;
  if (file.Header.Nodes == 0 || !plod::ViewOfFile(file, v, nullptr) ||
    !plod::ValidateOctree(v, &why))
  {
    return 0;
  }
  // the octree passed validation: the filters' kernels must be safe on it
  std::vector<uint8_t> state(static_cast<size_t>(v.NumberOfNodes));
  for (int level = -1; level <= std::min(v.FinestLevel, 4); ++level)
  {
    plod::UniformCut(v, level, state.data());
    CHECK(plod::ValidateCut(v, state.data(), &why), why);
    CheckPatches(v, state.data(), "uniform cut " + std::to_string(level));
  }
  plod::Selector selector;
  selector.SetOctree(v);
  plod::SelectionInput sel;
  sel.Eye[0] = v.RootEdge * 0.5;
  sel.Eye[1] = v.RootEdge * 0.4;
  sel.Eye[2] = v.RootEdge * 3.0;
  sel.Lights.push_back(plod::SelectorLight());
  if (plod::ValidateSelectionInput(sel, &why))
  {
    std::vector<uint8_t> reason(state.size()), cull(state.size());
    std::fill(state.begin(), state.end(), 0);
    plod::SelectionStats stats;
    selector.Select(sel, state.data(), reason.data(), cull.data(), stats);
    CHECK(plod::ValidateCut(v, state.data(), &why), "selector: " + why);
    CheckPatches(v, state.data(), "selector");
  }
  return 0;
}
