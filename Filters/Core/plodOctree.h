// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctree.h
 * @brief VTK-free description of the multiscale octree layout shared by the builder, the
 * selector and the patch generator.
 *
 * Layout (structure of arrays, one entry per node):
 * - Nodes are stored level by level (level 0, the root, first), and inside one level in Morton
 *   order of their integer cell coordinates. The children of a node are therefore contiguous,
 *   start at `FirstChild[n]` and appear in increasing child index; `ChildMask[n]` has bit `c`
 *   set when child `c` exists. A leaf has `FirstChild == -1` and `ChildMask == 0`.
 * - Child index `c = xbit | ybit << 1 | zbit << 2`: bit set means the upper half on that axis.
 * - Cell edges: edge `e = 4 * a + pbit + 2 * qbit` runs along axis `a`; `(p, q)` are the two
 *   other axes in cyclic order (`a = x: (y, z)`, `a = y: (z, x)`, `a = z: (x, y)`) and
 *   `pbit`, `qbit` tell which side of the cell the edge lies on along `p` and `q`.
 * - Edge-crossing word (32 bits): bit `e` (0..11) is set when the surface crosses edge `e` an
 *   odd number of times, counted with orientation (net crossing != 0); bit `12 + e` is set when
 *   that net crossing is negative, i.e. the surface normal points towards `-a` where it cuts the
 *   edge. A coarse edge is the union of the finer edges it contains: its net crossing is the sum
 *   of theirs, so a cell and its children always agree.
 * - Vertices are stored in single precision *relative to the root origin*: the root cube can
 *   sit 1e6 units from the world origin while the cells are 1e-3 units wide without losing
 *   precision. Add the origin (kept in double) to get world coordinates.
 */
#ifndef plodOctree_h
#define plodOctree_h

#include <cstdint>

namespace plod
{

/// Deepest level the Morton keys (3 x 21 bits) can address.
constexpr int MaxFinestLevel = 21;

/// Edge index of the edge along `axis` lying on side `pbit` of axis p and `qbit` of axis q.
inline constexpr int EdgeIndex(int axis, int pbit, int qbit)
{
  return 4 * axis + pbit + 2 * qbit;
}

/// Bit mask of an edge in the edge-crossing word.
inline constexpr uint32_t EdgeCrossedBit(int edge)
{
  return 1u << edge;
}

/// Bit telling that the crossing on `edge` is oriented towards the negative axis.
inline constexpr uint32_t EdgeNegativeBit(int edge)
{
  return 1u << (12 + edge);
}

/// Net orientation of the crossing on `edge`: +1, -1, or 0 when not crossed.
inline constexpr int EdgeSign(uint32_t word, int edge)
{
  return (word & EdgeCrossedBit(edge)) ? ((word & EdgeNegativeBit(edge)) ? -1 : 1) : 0;
}

/// Encodes a net crossing count into the word (only its sign is kept).
inline constexpr uint32_t EncodeEdge(int edge, int net)
{
  return net == 0 ? 0u : (EdgeCrossedBit(edge) | (net < 0 ? EdgeNegativeBit(edge) : 0u));
}

/// Read-only view of the node arrays. Pointers are owned elsewhere (the vtkMultiscaleOctree).
struct OctreeView
{
  int64_t NumberOfNodes = 0;
  int FinestLevel = 0;
  double Origin[3] = { 0, 0, 0 };
  double RootEdge = 1;

  const uint8_t* Level = nullptr;
  const int32_t* Parent = nullptr;
  const int32_t* FirstChild = nullptr;
  const uint8_t* ChildMask = nullptr;
  const float* Vertex = nullptr;     // 3 per node, relative to Origin
  const float* ConeAxis = nullptr;   // 3 per node, unit
  const float* ConeAngle = nullptr;  // radians in [0, pi]
  const float* ShapeError = nullptr; // world units
  const float* Diffuse = nullptr;    // (min, max) per node
  const float* Specular = nullptr;   // (min, max) per node
  const uint32_t* Edges = nullptr;   // edge-crossing word

  /// Index of child `c` of `node`, or -1 when that child does not exist.
  int32_t Child(int64_t node, int c) const
  {
    const unsigned mask = this->ChildMask[node];
    if (!(mask & (1u << c)))
    {
      return -1;
    }
    return this->FirstChild[node] + __builtin_popcount(mask & ((1u << c) - 1u));
  }

  /// Child index (0..7) of `node` inside its parent; -1 for the root.
  int ChildIndexInParent(int64_t node) const
  {
    const int32_t p = this->Parent[node];
    if (p < 0)
    {
      return -1;
    }
    const int rank = static_cast<int>(node - this->FirstChild[p]);
    unsigned mask = this->ChildMask[p];
    for (int c = 0, seen = 0; c < 8; ++c)
    {
      if (mask & (1u << c))
      {
        if (seen == rank)
        {
          return c;
        }
        ++seen;
      }
    }
    return -1;
  }

  /// Integer coordinates of `node`'s cell at its own level (walks up to the root).
  void CellCoordinates(int64_t node, int xyz[3]) const
  {
    xyz[0] = xyz[1] = xyz[2] = 0;
    int shift = 0;
    for (int64_t n = node; this->Parent[n] >= 0; n = this->Parent[n], ++shift)
    {
      const int c = this->ChildIndexInParent(n);
      for (int a = 0; a < 3; ++a)
      {
        xyz[a] |= ((c >> a) & 1) << shift;
      }
    }
  }

  /// Edge length of a cell at `level`.
  double CellEdge(int level) const { return this->RootEdge / static_cast<double>(1u << level); }
};

/// Writable node arrays, filled by the builder after it has counted the nodes.
struct OctreeArrays
{
  uint8_t* Level = nullptr;
  int32_t* Parent = nullptr;
  int32_t* FirstChild = nullptr;
  uint8_t* ChildMask = nullptr;
  float* Vertex = nullptr;
  float* ConeAxis = nullptr;
  float* ConeAngle = nullptr;
  float* ShapeError = nullptr;
  float* Diffuse = nullptr;
  float* Specular = nullptr;
  uint32_t* Edges = nullptr;
};

/// Morton key of integer cell coordinates (x in bit 0, y in bit 1, z in bit 2 of each triple).
inline uint64_t MortonEncode(uint32_t x, uint32_t y, uint32_t z)
{
  auto spread = [](uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

/// Inverse of MortonEncode.
inline void MortonDecode(uint64_t key, uint32_t xyz[3])
{
  auto compact = [](uint64_t v) {
    v &= 0x1249249249249249ULL;
    v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3ULL;
    v = (v ^ (v >> 4)) & 0x100f00f00f00f00fULL;
    v = (v ^ (v >> 8)) & 0x1f0000ff0000ffULL;
    v = (v ^ (v >> 16)) & 0x1f00000000ffffULL;
    v = (v ^ (v >> 32)) & 0x1fffff;
    return static_cast<uint32_t>(v);
  };
  xyz[0] = compact(key);
  xyz[1] = compact(key >> 1);
  xyz[2] = compact(key >> 2);
}

} // namespace plod

#endif
