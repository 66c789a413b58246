// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file FuzzOctreeBuild.cxx
 * @brief libFuzzer target for the VTK-free kernels: plod::BuildOctree, then cuts, patches and
 * the selector on what it built (issue 10, "Robust at any size").
 *
 * Build and run: docs/fuzzing.md (`bash scripts/run-fuzz.sh [seconds]`). Replay one input:
 * `build-fuzz/bin/FuzzOctreeBuild file` (prints why a check failed, then traps).
 *
 * INPUT FORMAT. The input is `FRONT | CONTROL | n`: the last byte `n` is the length of CONTROL
 * (clamped to what is there). FRONT describes the model, CONTROL the build's environment, the
 * cuts and the views. Each part is read in order; once a part is used up, its further bytes
 * come from a generator seeded by a hash of the whole input, so a short input can still make a
 * 4096-point model and every mutation of it changes something. Testing/Fuzz/make_seeds.py
 * writes inputs in this format.
 *
 * FRONT:
 * - [0] kind: bit 0 point cloud (no triangles), 1 double points (else float), 2 int64 triangles
 *   (else int32), 3 point normals, 4 point diffuse, 5 point specular, 6 mesh: triangle diffuse /
 *   cloud: per-point viewpoints, 7 mesh: triangle specular / cloud: one common viewpoint.
 * - [1] finest level: b % 24 - 2, and -2 means -1 (automatic): [-1, 21].
 * - [2] bit 0 vertex rule QEF (else mean), bits 1-4 memory limit (MemoryLimits), bits 5-7
 *   uniform diffuse and specular (Materials).
 * - [3-4] points (u16 % 4097), [5-6] triangles (u16 % 8193); both little-endian.
 * - [7] bits 0-1 coordinates: 0 fixed point (s16 / 256 times a scale, plus an offset; the 16
 *   lowest values are Specials: NaN, +-inf, 0, -0, denormals, 1e-30, 1e30, +-1e300, DBL_MAX,
 *   +-FLT_MAX), 1 raw float32 bits, 2 raw float64 bits, 3 a generated shape (below); bits 2-5
 *   the scale (Scales: 1 to 1e-310 and 1e300); bits 6-7 which axes get the offset (none, x,
 *   all, all with mixed signs).
 * - [8] bits 0-3 the offset (Offsets: 0 to +-1e300, 2^24, 2^53), bits 4-5 triangle indices: 0
 *   u16 % (points + 2) (the two last are out of range), 1 s8 steps from the previous index
 *   (modulo the point count), 2 raw s32, 3 raw s64 (truncated to 32 bits for int32 triangles);
 *   in 0 and 1 escape values pick SpecialIndices (-1, INT32_MIN, INT64_MAX, 2^32 + 1, ...).
 * - shape mode only, [9] shape (sphere, torus, nested spheres with a thin wall, open height
 *   field, rounded box, thin tube), [10-11] resolutions, [12] bits 0-2 noise, bit 3 duplicate
 *   triangles reversed (non-manifold edges), bits 6-7 wall gap or tube radius, [13]
 *   corruptions (b % 8 when b >= 192, else none), then 3 s8 of noise per point and the
 *   corruptions (u16 slot, u8 special index).
 * - then, each present only when asked for: the coordinates, the triangles, normals (3 s8 each:
 *   / 64, -128 NaN, 127 +inf, -127 a float denormal), point diffuse and specular, triangle
 *   diffuse and specular (one byte each, Materials: [0, 1], NaN, +-inf, -1, 1e30, ...),
 *   viewpoints (fixed point like coordinates). Every optional array has exactly one entry per
 *   point or triangle (three for vectors), as the kernel's contract requires.
 *
 * CONTROL:
 * - [0] bits 0-1 how ParallelFor splits ranges (serial; reversed; ranges of grain / 7 reversed;
 *   random sizes in random order), bit 2 build a second time serially and compare every array
 *   bit for bit, bits 3-7 abort from the progress callback at that call (0: never).
 * - [1] bits 0-1 fill of the allocated arrays before the build (0x00, 0xff: NaN floats, 0xa5,
 *   0x5a), bit 2 use no PatchWorkspace, bit 3 no cull mask for the selector, bits 4-7 patch
 *   options for the uniform cuts.
 * - [2-7] eye or projection for back-face culling of the cuts (one byte mode, s8 triples).
 * - [8] random cuts (b % 4), each: seed, refine probability, hidden probability, options.
 * - then corrupted cuts (b % 3), each: seed, number of nodes changed.
 * - then views (b % 5), each decoded by DecodeView (about 40 bytes).
 *
 * WHAT IS CHECKED (a failed check prints its reason and calls __builtin_trap(); ASan, UBSan
 * and LeakSanitizer catch memory errors, undefined behaviour and leaks; libFuzzer's -timeout
 * catches hangs):
 * 1. The build: the allocator's counts are sane and called once each; a failed build has an
 *    error message; an aborted build says so; an input without a usable triangle fails.
 * 2. plod::ValidateOctree; the result's counts, level, origin and edge agree with the arrays;
 *    the level and its reason are the user's when set; EstimatedBytes is within the memory
 *    limit.
 * 3. Meshes: the invalid, degenerate and non-finite counts match a recount of the input; the
 *    surface has one triangle per kept input triangle, the same corners in the same cyclic
 *    order (through InputPointId, a bijection onto the input points that kept triangles use);
 *    points are the input relative to the origin; normals are unit and are the given normals
 *    where those are usable. Clouds: every InputPointId is -1.
 * 4. Geometry: every point lies in its leaf's cell, every node and cluster vertex in its node's
 *    cell (up to float rounding); cone axes and cluster normals are unit; shape errors and
 *    thickness are finite; every triangle with a corner in a cell has its normal in the cell's
 *    cone.
 * 5. Ownership: every triangle is owned by the deepest node holding two of its corners.
 * 6. Clusters and flags, level by level: a node's clusters are exactly the connected components
 *    of its sub-mesh; NodeTopologySafe iff V - E + F equals their number; NodeBoundary iff the
 *    cell holds an end of an edge used once; the boundary, non-manifold and unsafe counts agree.
 * 7. Determinism (when asked): a serial build gives the same arrays bit for bit as one whose
 *    ParallelFor splits and orders the ranges differently.
 * 8. Patches of the full cut, of every uniform level and of random predicate cuts with hidden
 *    cells and random cull masks (every FoldHandling, CullBackFaces on and off):
 *    GeneratePatches returns true; output indices and point sources are in range and distinct
 *    except for the folds' own corners; the triangles are exactly those a model of
 *    plodPatches.h predicts (each corner at its cluster in the cut cell, or itself in an opened
 *    leaf; collapsed ones dropped; the rules for hidden cells), minus only the dropped folds
 *    (which always have a representative corner) and back faces the counters report; folds
 *    given reversed normals are drawn on three corners of their own with the same sources. The
 *    full cut gives the input's own triangles.
 * 9. Corrupted cuts: ValidateCut and GeneratePatches never crash; GeneratePatches accepts every
 *    cut ValidateCut accepts, and what it returns for the others is in range.
 * 10. The selector, for views decoded from the bytes that ValidateSelectionInput accepts: the
 *    cut passes ValidateCut and the patch checks of 8 with the selector's cull mask and eye;
 *    reasons, cull masks and statistics agree with the states; culled cells are wholly outside
 *    the planes their mask names; a cell holding the eye (or whose vertex is the eye) is
 *    refined in perspective; zero tolerances in SCVC and PSEC open every leaf that is not
 *    culled, and in SRCC leave only opened, culled or back-facing cells; the Distance model
 *    draws nothing above its level; IPV/DPV with an infinite factor keep the root; a second
 *    Selector given the same view writes the same cut. DistanceLevel and ConeCosineSpread
 *    stay in range.
 */
#include "plodCut.h"
#include "plodOctree.h"
#include "plodOctreeBuilder.h"
#include "plodOctreeStorage.h"
#include "plodPatches.h"
#include "plodSelector.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace
{

constexpr int64_t MaxPoints = 4096;
constexpr int64_t MaxTriangles = 8192;
/// Clouds are capped lower: the PCA normals of a cloud cost the square of the points per cell
/// (reported in docs/fuzzing.md), and a cloud of 4096 identical points takes 14 s under ASan.
constexpr int64_t MaxCloudPoints = 1024;
constexpr double Pi = 3.14159265358979323846;
constexpr double Inf = std::numeric_limits<double>::infinity();
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

[[noreturn]] void Fail(const std::string& what)
{
  std::fprintf(stderr, "FuzzOctreeBuild: check failed: %s\n", what.c_str());
  std::fflush(stderr);
  __builtin_trap();
}

/// CHECK(condition, message): the message (a std::string expression) is built only on failure.
#define CHECK(condition, message)                                                                  \
  do                                                                                               \
  {                                                                                                \
    if (!(condition))                                                                              \
    {                                                                                              \
      Fail(std::string(#condition) + " -- " + (message));                                          \
    }                                                                                              \
  } while (0)

std::string Str(int64_t x)
{
  return std::to_string(x);
}

// ------------------------------------------------------------------------------------------------
// Bytes

uint64_t SplitMix(uint64_t& state)
{
  state += 0x9e3779b97f4a7c15ULL;
  uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// One part of the input, then bytes from a generator.
class Stream
{
public:
  Stream(const uint8_t* data, size_t size, uint64_t seed)
    : Data(data)
    , Size(size)
    , State(seed)
  {
  }
  uint8_t U8()
  {
    if (this->Pos < this->Size)
    {
      return this->Data[this->Pos++];
    }
    return static_cast<uint8_t>(SplitMix(this->State) >> 56);
  }
  uint16_t U16()
  {
    const uint16_t lo = this->U8();
    return static_cast<uint16_t>(lo | (uint16_t(this->U8()) << 8));
  }
  uint32_t U32()
  {
    const uint32_t lo = this->U16();
    return lo | (uint32_t(this->U16()) << 16);
  }
  uint64_t U64()
  {
    const uint64_t lo = this->U32();
    return lo | (uint64_t(this->U32()) << 32);
  }
  int8_t S8() { return static_cast<int8_t>(this->U8()); }
  int16_t S16() { return static_cast<int16_t>(this->U16()); }
  /// A table entry chosen by one byte.
  template <typename T, size_t N>
  T Pick(const T (&table)[N])
  {
    return table[this->U8() % N];
  }

private:
  const uint8_t* Data;
  size_t Size;
  size_t Pos = 0;
  uint64_t State;
};

/// Double to float without undefined behaviour: out of range gives an infinity.
float ToFloat(double x)
{
  if (std::isnan(x))
  {
    return std::numeric_limits<float>::quiet_NaN();
  }
  if (x > double(FLT_MAX))
  {
    return std::numeric_limits<float>::infinity();
  }
  if (x < -double(FLT_MAX))
  {
    return -std::numeric_limits<float>::infinity();
  }
  return static_cast<float>(x);
}

float FloatBits(uint32_t bits)
{
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

double DoubleBits(uint64_t bits)
{
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

int32_t Truncate32(int64_t x)
{
  const uint32_t low = static_cast<uint32_t>(static_cast<uint64_t>(x));
  int32_t r;
  std::memcpy(&r, &low, sizeof r);
  return r;
}

const double Specials[16] = { NaN, Inf, -Inf, 0.0, -0.0, 4.9406564584124654e-324, 1e-310,
  1.4012984643248171e-45, 1.1754943508222875e-38, 1e-30, 1e30, 1e300, -1e300, DBL_MAX,
  double(FLT_MAX), -double(FLT_MAX) };
const double Scales[16] = { 1.0, 1e-3, 1e3, 1e-7, 1e-12, 1e-20, 1e-28, 1e-30, 1e-33, 1e20, 1e28,
  1e30, 1e33, 1e300, 1e-300, 1e-310 };
const double Offsets[16] = { 0.0, 1.0, 1e6, -1e6, 1e7 + 0.5, 3e8, 1e12, 1e15, 1e20, 1e30, 1e300,
  -1e300, 1e-300, 4294967296.0, 16777216.0, 9007199254740992.0 };
const double MemoryLimits[16] = { 4e9, 1e9, 1e8, 1e7, 1e6, 3e5, 1e5, 1e4, 1000, 1, 1e-300,
  4.9406564584124654e-324, Inf, 1e300, 2e6, 5e7 };
const float Materials[16] = { 1.0f, 0.0f, 0.5f, 0.25f, std::numeric_limits<float>::quiet_NaN(),
  std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), -1.0f, 1e30f,
  1e-40f, -0.0f, 2.0f, 0.75f, 1e-6f, 100.0f, FLT_MAX };

// ------------------------------------------------------------------------------------------------
// The model a fuzz input describes

struct Model
{
  bool Cloud = false;
  bool DoublePoints = false;
  bool Int64Triangles = false;
  int64_t NumberOfPoints = 0;
  int64_t NumberOfTriangles = 0;
  std::vector<double> PointsD;
  std::vector<float> PointsF;
  std::vector<int64_t> Triangles64;
  std::vector<int32_t> Triangles32;
  std::vector<float> Normals, PointDiffuse, PointSpecular, TriangleDiffuse, TriangleSpecular;
  std::vector<double> Viewpoints;
  plod::BuildInput Input;
  plod::BuildParameters Params;

  double X(int64_t i, int a) const
  {
    return this->DoublePoints ? this->PointsD[3 * i + a] : double(this->PointsF[3 * i + a]);
  }
  int64_t T(int64_t t, int k) const
  {
    return this->Int64Triangles ? this->Triangles64[3 * t + k]
                                : int64_t(this->Triangles32[3 * t + k]);
  }
};

/// Coordinates in fixed point: s16 / 256 times the scale plus the offset, or a special value.
struct CoordinateCode
{
  int Encoding = 0;
  double Scale = 1;
  double Offset[3] = { 0, 0, 0 };

  double Decode(Stream& s, int axis) const
  {
    const int16_t v = s.S16();
    if (v < -32768 + 16)
    {
      return Specials[v + 32768];
    }
    return this->Offset[axis] + this->Scale * (double(v) / 256.0);
  }
};

/// A closed or open surface in [-1, 1]^3 with at most 4096 points and 8192 triangles.
void MakeShape(Stream& s, std::vector<double>& p, std::vector<int64_t>& t, int& corruptions)
{
  const int shape = s.U8() % 6;
  int nu = 3 + s.U8() % 62;
  int nv = 2 + s.U8() % 62;
  const uint8_t extra = s.U8();
  const uint8_t corrupt = s.U8();
  corruptions = corrupt >= 192 ? corrupt % 8 : 0;
  const double noise[8] = { 0, 0, 1e-6, 1e-3, 1e-2, 0.05, 0.3, 1.0 };
  const double amplitude = noise[extra & 7];
  const bool nested = shape == 2;
  const int copies = nested ? 2 : 1;
  auto fits = [&] {
    const int64_t points = int64_t(copies) * (int64_t(nu) * nv + 2);
    const int64_t triangles = int64_t(copies) * 2 * int64_t(nu) * nv * ((extra & 8) ? 2 : 1);
    return points <= MaxPoints && triangles <= MaxTriangles;
  };
  while (!fits())
  {
    nu = std::max(3, nu - 1);
    nv = std::max(2, nv - 1);
  }
  auto add = [&p](double x, double y, double z) {
    p.push_back(x);
    p.push_back(y);
    p.push_back(z);
  };
  auto tri = [&t](int64_t a, int64_t b, int64_t c) {
    t.push_back(a);
    t.push_back(b);
    t.push_back(c);
  };
  const double tubeRadius[4] = { 0.3, 0.05, 1e-3, 1e-5 };
  const double gaps[4] = { 1e-2, 1e-3, 1e-5, 1e-7 };
  for (int copy = 0; copy < copies; ++copy)
  {
    const int64_t base = static_cast<int64_t>(p.size() / 3);
    if (shape == 0 || shape == 2 || shape == 4)
    {
      // UV sphere (a rounded box for shape 4): two poles and nv - 1 rings of nu points
      const double r = copy == 0 ? 1.0 : 1.0 - gaps[extra >> 6];
      const int rings = nv - 1 < 1 ? 1 : nv - 1;
      auto put = [&](double x, double y, double z) {
        if (shape == 4)
        {
          const double m = std::max({ std::abs(x), std::abs(y), std::abs(z) });
          x /= m;
          y /= m;
          z /= m;
        }
        add(r * x, r * y, r * z);
      };
      put(0, 0, 1);
      for (int i = 1; i <= rings; ++i)
      {
        const double phi = Pi * i / (rings + 1);
        for (int j = 0; j < nu; ++j)
        {
          const double theta = 2 * Pi * j / nu;
          put(std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta), std::cos(phi));
        }
      }
      put(0, 0, -1);
      const int64_t south = base + 1 + int64_t(rings) * nu;
      const bool inward = copy == 1;
      auto face = [&](int64_t a, int64_t b, int64_t c) {
        if (inward)
          tri(a, c, b);
        else
          tri(a, b, c);
      };
      for (int j = 0; j < nu; ++j)
      {
        const int k = (j + 1) % nu;
        face(base, base + 1 + j, base + 1 + k);
        face(south, base + 1 + int64_t(rings - 1) * nu + k, base + 1 + int64_t(rings - 1) * nu + j);
      }
      for (int i = 0; i + 1 < rings; ++i)
      {
        for (int j = 0; j < nu; ++j)
        {
          const int k = (j + 1) % nu;
          const int64_t a = base + 1 + int64_t(i) * nu + j, b = base + 1 + int64_t(i) * nu + k;
          const int64_t c = a + nu, d = b + nu;
          face(a, c, d);
          face(a, d, b);
        }
      }
    }
    else if (shape == 1 || shape == 5)
    {
      // torus (a thin tube for shape 5): closed, genus one
      const double minor = shape == 1 ? tubeRadius[(extra >> 6) & 1] : tubeRadius[2 + (extra >> 7)];
      for (int i = 0; i < nv; ++i)
      {
        const double phi = 2 * Pi * i / nv;
        for (int j = 0; j < nu; ++j)
        {
          const double theta = 2 * Pi * j / nu;
          const double w = 0.7 + minor * std::cos(phi);
          add(w * std::cos(theta), w * std::sin(theta), minor * std::sin(phi));
        }
      }
      for (int i = 0; i < nv; ++i)
      {
        for (int j = 0; j < nu; ++j)
        {
          const int64_t a = base + int64_t(i) * nu + j;
          const int64_t b = base + int64_t(i) * nu + (j + 1) % nu;
          const int64_t c = base + int64_t((i + 1) % nv) * nu + j;
          const int64_t d = base + int64_t((i + 1) % nv) * nu + (j + 1) % nu;
          tri(a, b, d);
          tri(a, d, c);
        }
      }
    }
    else
    {
      // an open height field (boundary everywhere around)
      for (int i = 0; i < nv; ++i)
      {
        for (int j = 0; j < nu; ++j)
        {
          const double x = -1 + 2.0 * j / (nu - 1), y = -1 + 2.0 * i / (nv - 1);
          add(x, y, 0.25 * std::sin(3 * x) * std::cos(2 * y));
        }
      }
      for (int i = 0; i + 1 < nv; ++i)
      {
        for (int j = 0; j + 1 < nu; ++j)
        {
          const int64_t a = base + int64_t(i) * nu + j;
          tri(a, a + 1, a + 1 + nu);
          tri(a, a + 1 + nu, a + nu);
        }
      }
    }
  }
  if (extra & 8)
  {
    // every triangle again, reversed: each edge used four times (non-manifold)
    const size_t n = t.size();
    for (size_t i = 0; i < n; i += 3)
    {
      tri(t[i], t[i + 2], t[i + 1]);
    }
  }
  for (size_t i = 0; i < p.size(); ++i)
  {
    p[i] += amplitude * (double(s.S8()) / 128.0);
  }
}

int64_t SpecialIndex(int which, int64_t np)
{
  switch (which & 15)
  {
    case 0:
      return -1;
    case 1:
      return -2;
    case 2:
      return np;
    case 3:
      return np + 1;
    case 4:
      return std::numeric_limits<int32_t>::min();
    case 5:
      return std::numeric_limits<int32_t>::max();
    case 6:
      return std::numeric_limits<int64_t>::min();
    case 7:
      return std::numeric_limits<int64_t>::max();
    case 8:
      return int64_t(1) << 32;
    case 9:
      return (int64_t(1) << 32) + 1;
    case 10:
      return -(int64_t(1) << 32);
    case 11:
      return 0;
    case 12:
      return 1;
    case 13:
      return 2;
    case 14:
      return np - 1;
    default:
      return np - 2;
  }
}

void DecodeModel(Stream& s, Model& m)
{
  const uint8_t kind = s.U8();
  m.Cloud = kind & 1;
  m.DoublePoints = kind & 2;
  m.Int64Triangles = kind & 4;
  const int levelByte = s.U8() % 24 - 2;
  m.Params.FinestLevel = std::max(-1, levelByte);
  const uint8_t rule = s.U8();
  m.Params.Rule = (rule & 1) ? plod::VertexRule::QEF : plod::VertexRule::Mean;
  m.Params.MemoryLimit = MemoryLimits[(rule >> 1) & 15];
  m.Input.UniformDiffuse = Materials[(rule >> 5) * 2 % 16];
  m.Input.UniformSpecular = Materials[((rule >> 5) * 2 + 1) % 16];
  int64_t np = s.U16() % (MaxPoints + 1);
  int64_t nt = s.U16() % (MaxTriangles + 1);
  const uint8_t coordinates = s.U8();
  const uint8_t indices = s.U8();
  CoordinateCode code;
  code.Encoding = coordinates & 3;
  code.Scale = Scales[(coordinates >> 2) & 15];
  const double offset = Offsets[indices & 15];
  switch (coordinates >> 6)
  {
    case 1:
      code.Offset[0] = offset;
      break;
    case 2:
      code.Offset[0] = code.Offset[1] = code.Offset[2] = offset;
      break;
    case 3:
      code.Offset[0] = offset;
      code.Offset[1] = -offset;
      code.Offset[2] = 0.5 * offset;
      break;
    default:
      break;
  }
  const int indexEncoding = (indices >> 4) & 3;

  // points (and, for a shape, its triangles)
  std::vector<double> points;
  std::vector<int64_t> triangles;
  if (code.Encoding == 3)
  {
    int corruptions = 0;
    MakeShape(s, points, triangles, corruptions);
    for (size_t i = 0; i < points.size(); ++i)
    {
      points[i] = code.Offset[i % 3] + code.Scale * points[i];
    }
    np = static_cast<int64_t>(points.size() / 3);
    nt = static_cast<int64_t>(triangles.size() / 3);
    for (int i = 0; i < corruptions && nt > 0; ++i)
    {
      const int64_t slot = s.U16() % (3 * nt);
      triangles[slot] = SpecialIndex(s.U8(), np);
    }
  }
  else
  {
    points.resize(3 * np);
    for (int64_t i = 0; i < 3 * np; ++i)
    {
      const int a = static_cast<int>(i % 3);
      if (code.Encoding == 0)
        points[i] = code.Decode(s, a);
      else if (code.Encoding == 1)
        points[i] = double(FloatBits(s.U32()));
      else
        points[i] = DoubleBits(s.U64());
    }
  }
  if (m.Cloud && np > MaxCloudPoints)
  {
    np = MaxCloudPoints;
    points.resize(3 * np);
  }
  m.NumberOfPoints = np;
  if (m.DoublePoints)
  {
    m.PointsD = points;
  }
  else
  {
    m.PointsF.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i)
    {
      m.PointsF[i] = ToFloat(points[i]);
    }
  }

  // triangles
  if (!m.Cloud)
  {
    if (code.Encoding != 3)
    {
      triangles.resize(3 * nt);
      int64_t previous = 0;
      for (int64_t i = 0; i < 3 * nt; ++i)
      {
        int64_t index = 0;
        if (indexEncoding == 0)
        {
          const uint16_t w = s.U16();
          index = w >= 0xfff0 ? SpecialIndex(w - 0xfff0, np) : int64_t(w % (np + 2));
        }
        else if (indexEncoding == 1)
        {
          const int8_t d = s.S8();
          if (d == -128)
          {
            index = SpecialIndex(s.U8(), np);
          }
          else
          {
            index = np > 0 ? ((previous + d) % np + np) % np : 0;
            previous = index;
          }
        }
        else if (indexEncoding == 2)
        {
          index = static_cast<int32_t>(s.U32());
        }
        else
        {
          index = static_cast<int64_t>(s.U64());
        }
        triangles[i] = index;
      }
    }
    m.NumberOfTriangles = nt;
    if (m.Int64Triangles)
    {
      m.Triangles64 = triangles;
    }
    else
    {
      m.Triangles32.resize(triangles.size());
      for (size_t i = 0; i < triangles.size(); ++i)
      {
        m.Triangles32[i] = Truncate32(triangles[i]);
      }
    }
  }

  // optional arrays: exactly one entry per point or triangle
  auto material = [&s](std::vector<float>& out, int64_t n) {
    out.resize(n);
    for (int64_t i = 0; i < n; ++i)
    {
      const uint8_t b = s.U8();
      out[i] = b < 240 ? float(b) / 200.0f : Materials[b - 240];
    }
  };
  if (kind & 8)
  {
    m.Normals.resize(3 * np);
    for (int64_t i = 0; i < 3 * np; ++i)
    {
      const int8_t v = s.S8();
      m.Normals[i] = v == -128 ? std::numeric_limits<float>::quiet_NaN()
        : v == 127             ? std::numeric_limits<float>::infinity()
        : v == -127            ? 1e-40f
                               : float(v) / 64.0f;
    }
  }
  if (kind & 16)
    material(m.PointDiffuse, np);
  if (kind & 32)
    material(m.PointSpecular, np);
  if (!m.Cloud)
  {
    if (kind & 64)
      material(m.TriangleDiffuse, nt);
    if (kind & 128)
      material(m.TriangleSpecular, nt);
  }
  else
  {
    if (kind & 64)
    {
      m.Viewpoints.resize(3 * np);
      for (int64_t i = 0; i < 3 * np; ++i)
      {
        m.Viewpoints[i] = code.Decode(s, static_cast<int>(i % 3));
      }
    }
    if (kind & 128)
    {
      m.Input.HasViewpoint = true;
      for (int a = 0; a < 3; ++a)
      {
        m.Input.Viewpoint[a] = code.Decode(s, a);
      }
    }
  }

  plod::BuildInput& in = m.Input;
  if (nt == 0)
  {
    m.Cloud = true; // a mesh without triangles is a point cloud (plodOctreeBuilder.h)
  }
  in.NumberOfPoints = np;
  in.Points = m.DoublePoints && np > 0 ? m.PointsD.data() : nullptr;
  in.PointsFloat = !m.DoublePoints && np > 0 ? m.PointsF.data() : nullptr;
  in.NumberOfTriangles = m.Cloud ? 0 : nt;
  if (!m.Cloud && nt > 0)
  {
    in.Triangles = m.Int64Triangles ? m.Triangles64.data() : nullptr;
    in.Triangles32 = m.Int64Triangles ? nullptr : m.Triangles32.data();
  }
  in.PointNormals = m.Normals.empty() ? nullptr : m.Normals.data();
  in.PointDiffuse = m.PointDiffuse.empty() ? nullptr : m.PointDiffuse.data();
  in.PointSpecular = m.PointSpecular.empty() ? nullptr : m.PointSpecular.data();
  in.TriangleDiffuse = m.TriangleDiffuse.empty() ? nullptr : m.TriangleDiffuse.data();
  in.TriangleSpecular = m.TriangleSpecular.empty() ? nullptr : m.TriangleSpecular.data();
  in.PointViewpoints = m.Viewpoints.empty() ? nullptr : m.Viewpoints.data();
}

// ------------------------------------------------------------------------------------------------
// The build

/// The arrays an Allocator hands to the builder (plod::OctreeStorage, filled with the poison
/// byte `Fill`), and checks of how the builder calls it.
struct Storage : plod::OctreeStorage
{
  int NodeCalls = 0, ClusterCalls = 0;

  plod::Allocator MakeAllocator(int64_t maxPoints, int64_t maxTriangles)
  {
    plod::Allocator a;
    a.Nodes = [this, maxPoints, maxTriangles](int64_t nodes, int64_t points, int64_t triangles) {
      ++this->NodeCalls;
      CHECK(this->NodeCalls == 1, "Nodes called twice");
      CHECK(nodes >= 1 && points >= 1 && triangles >= 1,
        "counts " + Str(nodes) + " " + Str(points) + " " + Str(triangles));
      CHECK(points <= maxPoints && triangles <= maxTriangles,
        "more points or triangles than the input has: " + Str(points) + " " + Str(triangles));
      CHECK(nodes <= points * (plod::MaxFinestLevel + 1), "nodes " + Str(nodes));
      return this->AllocateNodes(nodes, points, triangles);
    };
    a.Clusters = [this](int64_t clusters, plod::OctreeArrays& o) {
      ++this->ClusterCalls;
      CHECK(this->ClusterCalls == 1 && this->NodeCalls == 1, "Clusters called out of turn");
      CHECK(
        clusters >= this->Nodes && clusters <= (plod::MaxFinestLevel + 1) * this->NumberOfPoints,
        "clusters " + Str(clusters) + " for " + Str(this->Nodes) + " nodes");
      CHECK(o.Level == this->Level.data() && o.Points == this->Points.data(),
        "Clusters received other arrays than Nodes returned");
      this->AllocateClusters(clusters, o);
    };
    return a;
  }
};

/// A ParallelFor that splits and orders the ranges differently from SerialFor (each range still
/// at most `grain` long, as the contract allows), run on the calling thread.
plod::ParallelFor MakeParallelFor(int variant, uint64_t seed)
{
  if (variant == 0)
  {
    return plod::SerialFor;
  }
  auto state = std::make_shared<uint64_t>(seed);
  return
    [variant, state](int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& body) {
      grain = std::max<int64_t>(1, grain);
      std::vector<std::pair<int64_t, int64_t>> ranges;
      int64_t step = variant == 2 ? std::max<int64_t>(1, grain / 7) : grain;
      for (int64_t b = 0; b < n;)
      {
        int64_t size = step;
        if (variant == 3)
        {
          size = 1 + static_cast<int64_t>(SplitMix(*state) % static_cast<uint64_t>(grain));
        }
        const int64_t e = std::min(n, b + size);
        ranges.emplace_back(b, e);
        b = e;
      }
      if (variant == 3)
      {
        for (size_t i = ranges.size(); i > 1; --i)
        {
          std::swap(ranges[i - 1], ranges[SplitMix(*state) % i]);
        }
      }
      else
      {
        std::reverse(ranges.begin(), ranges.end());
      }
      for (const auto& r : ranges)
      {
        body(r.first, r.second);
      }
    };
}

// ------------------------------------------------------------------------------------------------
// Checks of the octree

/// The input's triangles as the kernel documents their fate.
struct InputCounts
{
  int64_t Invalid = 0, Degenerate = 0, Kept = 0, NonFinite = 0;
  std::vector<uint8_t> Finite, Used, KeptTriangle;
};

InputCounts CountInput(const Model& m)
{
  InputCounts c;
  const int64_t np = m.NumberOfPoints;
  c.Finite.assign(np, 0);
  c.Used.assign(np, 0);
  for (int64_t i = 0; i < np; ++i)
  {
    c.Finite[i] = std::isfinite(m.X(i, 0)) && std::isfinite(m.X(i, 1)) && std::isfinite(m.X(i, 2));
    c.NonFinite += c.Finite[i] ? 0 : 1;
  }
  if (m.Cloud)
  {
    return c;
  }
  c.KeptTriangle.assign(m.NumberOfTriangles, 0);
  for (int64_t t = 0; t < m.NumberOfTriangles; ++t)
  {
    const int64_t a = m.T(t, 0), b = m.T(t, 1), d = m.T(t, 2);
    if (a < 0 || b < 0 || d < 0 || a >= np || b >= np || d >= np || !c.Finite[a] || !c.Finite[b] ||
      !c.Finite[d])
    {
      ++c.Invalid;
    }
    else if (a == b || b == d || a == d)
    {
      ++c.Degenerate;
    }
    else
    {
      ++c.Kept;
      c.KeptTriangle[t] = 1;
      c.Used[a] = c.Used[b] = c.Used[d] = 1;
    }
  }
  return c;
}

/// A triangle rotated so that its smallest entry comes first (the cyclic order is kept).
std::array<int64_t, 3> Rotated(int64_t a, int64_t b, int64_t c)
{
  if (b < a && b <= c)
    return { b, c, a };
  if (c < a && c < b)
    return { c, a, b };
  return { a, b, c };
}

/// Cell box of a node, relative to the origin.
void NodeBox(const plod::OctreeView& v, int64_t n, double lo[3], double& h)
{
  int xyz[3];
  v.CellCoordinates(n, xyz);
  h = v.CellEdge(v.Level[n]);
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = xyz[a] * h;
  }
}

bool InBox(const float* x, const double lo[3], double h, double tolerance)
{
  for (int a = 0; a < 3; ++a)
  {
    if (!(double(x[a]) >= lo[a] - tolerance && double(x[a]) <= lo[a] + h + tolerance))
    {
      return false;
    }
  }
  return true;
}

double Length(const float* x)
{
  return std::sqrt(double(x[0]) * x[0] + double(x[1]) * x[1] + double(x[2]) * x[2]);
}

/// Unit normal of a surface triangle, computed as the builder does (root-edge units); false
/// when it has no area.
bool FaceNormal(const plod::OctreeView& v, int64_t t, double n[3])
{
  double p[3][3];
  for (int k = 0; k < 3; ++k)
  {
    for (int a = 0; a < 3; ++a)
    {
      p[k][a] = double(v.Points[3 * v.Triangles[3 * t + k] + a]) / v.RootEdge;
    }
  }
  const double e1[3] = { p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] };
  const double e2[3] = { p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] };
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0) || !std::isfinite(len))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    n[a] /= len;
  }
  return true;
}

/// Lowest common ancestor of two nodes.
int64_t CommonAncestor(const plod::OctreeView& v, int64_t a, int64_t b)
{
  while (a != b)
  {
    if (v.Level[a] >= v.Level[b])
      a = v.Parent[a];
    else
      b = v.Parent[b];
  }
  return a;
}

void CheckResultAndInput(const Model& m, const InputCounts& counts, const plod::BuildResult& r,
  const Storage& s, const plod::OctreeView& v)
{
  CHECK(r.NumberOfNodes == v.NumberOfNodes && r.NumberOfClusters == v.NumberOfClusters &&
      r.NumberOfPoints == v.NumberOfPoints && r.NumberOfTriangles == v.NumberOfTriangles,
    "result counts differ from the allocated arrays");
  CHECK(s.ClusterCalls == 1, "Clusters never called");
  CHECK(r.NumberOfNonFinitePoints == counts.NonFinite,
    "non-finite points " + Str(r.NumberOfNonFinitePoints) + ", expected " + Str(counts.NonFinite));
  if (m.Params.FinestLevel >= 0)
  {
    CHECK(r.FinestLevel == m.Params.FinestLevel && r.LevelReason == "set by the user",
      "finest level " + Str(r.FinestLevel) + " (" + r.LevelReason + ") instead of the user's " +
        Str(m.Params.FinestLevel));
  }
  CHECK(r.EstimatedBytes <= m.Params.MemoryLimit,
    "estimated " + std::to_string(r.EstimatedBytes) + " bytes above the memory limit " +
      std::to_string(m.Params.MemoryLimit));
  const double tolerance = 1e-6 * v.RootEdge;
  if (m.Cloud)
  {
    for (int64_t p = 0; p < v.NumberOfPoints; ++p)
    {
      CHECK(v.InputPointId[p] == -1, "cloud surface point " + Str(p) + " has an input id");
    }
  }
  else
  {
    CHECK(r.NumberOfInvalidTriangles == counts.Invalid,
      "invalid triangles " + Str(r.NumberOfInvalidTriangles) + ", expected " + Str(counts.Invalid));
    CHECK(r.NumberOfDegenerateTriangles == counts.Degenerate,
      "degenerate triangles " + Str(r.NumberOfDegenerateTriangles) + ", expected " +
        Str(counts.Degenerate));
    CHECK(v.NumberOfTriangles == counts.Kept,
      "surface triangles " + Str(v.NumberOfTriangles) + ", kept " + Str(counts.Kept));
    // InputPointId: a bijection onto the used input points
    int64_t used = 0;
    for (uint8_t u : counts.Used)
      used += u;
    CHECK(
      v.NumberOfPoints == used, "surface points " + Str(v.NumberOfPoints) + ", used " + Str(used));
    std::vector<uint8_t> seen(m.NumberOfPoints, 0);
    for (int64_t p = 0; p < v.NumberOfPoints; ++p)
    {
      const int64_t i = v.InputPointId[p];
      CHECK(i >= 0 && i < m.NumberOfPoints && counts.Used[i] && !seen[i],
        "surface point " + Str(p) + " has input id " + Str(i));
      seen[i] = 1;
      for (int a = 0; a < 3; ++a)
      {
        const double expected = m.X(i, a) - v.Origin[a];
        CHECK(std::abs(double(v.Points[3 * p + a]) - expected) <= tolerance,
          "surface point " + Str(p) + " is not input point " + Str(i) + " relative to the origin");
      }
      const float* n = &v.Normals[3 * p];
      CHECK(std::abs(Length(n) - 1.0) <= 1e-4, "normal of point " + Str(p) + " is not unit");
      if (!m.Normals.empty())
      {
        const float* g = &m.Normals[3 * i];
        const double len =
          std::sqrt(double(g[0]) * g[0] + double(g[1]) * g[1] + double(g[2]) * g[2]);
        if (len > 0 && std::isfinite(len))
        {
          for (int a = 0; a < 3; ++a)
          {
            CHECK(std::abs(double(n[a]) - g[a] / len) <= 1e-6,
              "normal of point " + Str(p) + " is not its given normal");
          }
        }
      }
    }
    // the same triangles, corners in the same cyclic order
    std::vector<std::array<int64_t, 3>> a, b;
    a.reserve(counts.Kept);
    b.reserve(v.NumberOfTriangles);
    for (int64_t t = 0; t < m.NumberOfTriangles; ++t)
    {
      if (counts.KeptTriangle[t])
        a.push_back(Rotated(m.T(t, 0), m.T(t, 1), m.T(t, 2)));
    }
    for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    {
      const int32_t* c = &v.Triangles[3 * t];
      b.push_back(Rotated(v.InputPointId[c[0]], v.InputPointId[c[1]], v.InputPointId[c[2]]));
    }
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    CHECK(a == b, "the surface triangles are not the kept input triangles");
  }
  for (int64_t p = 0; p < v.NumberOfPoints; ++p)
  {
    CHECK(std::abs(Length(&v.Normals[3 * p]) - 1.0) <= 1e-4,
      "normal of point " + Str(p) + " is not unit");
  }
}

void CheckGeometry(const plod::OctreeView& v)
{
  const double tolerance = 1e-5 * v.RootEdge;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    double lo[3], h;
    NodeBox(v, n, lo, h);
    CHECK(InBox(&v.Vertex[3 * n], lo, h, tolerance),
      "vertex of node " + Str(n) + " is outside its cell");
    for (int64_t c = v.FirstCluster[n], end = v.ClusterEnd(n); c < end; ++c)
    {
      CHECK(InBox(&v.ClusterVertex[3 * c], lo, h, tolerance),
        "vertex of cluster " + Str(c) + " is outside its node's cell");
      CHECK(std::abs(Length(&v.ClusterNormal[3 * c]) - 1.0) <= 1e-4,
        "normal of cluster " + Str(c) + " is not unit");
    }
    CHECK(std::abs(Length(&v.ConeAxis[3 * n]) - 1.0) <= 1e-4,
      "cone axis of node " + Str(n) + " is not unit");
    CHECK(std::isfinite(v.ShapeError[n]) && std::isfinite(v.Thickness[n]),
      "shape error or thickness of node " + Str(n) + " is not finite");
    if (v.IsLeaf(n))
    {
      for (int64_t p = v.FirstPoint[n], end = v.PointEnd(n); p < end; ++p)
      {
        CHECK(InBox(&v.Points[3 * p], lo, h, tolerance),
          "point " + Str(p) + " lies outside its leaf " + Str(n));
      }
    }
  }
}

/// Per point, the triangles at it.
struct Incidence
{
  std::vector<int64_t> Start;
  std::vector<int32_t> Triangle;
  Incidence(const plod::OctreeView& v)
  {
    this->Start.assign(v.NumberOfPoints + 1, 0);
    for (int64_t i = 0; i < 3 * v.NumberOfTriangles; ++i)
      ++this->Start[v.Triangles[i] + 1];
    for (int64_t p = 0; p < v.NumberOfPoints; ++p)
      this->Start[p + 1] += this->Start[p];
    this->Triangle.resize(3 * v.NumberOfTriangles);
    std::vector<int64_t> cursor(this->Start.begin(), this->Start.end() - 1);
    for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
      for (int k = 0; k < 3; ++k)
        this->Triangle[cursor[v.Triangles[3 * t + k]]++] = static_cast<int32_t>(t);
  }
};

void CheckCones(const plod::OctreeView& v, const Incidence& inc)
{
  std::vector<double> normal(3 * v.NumberOfTriangles);
  std::vector<uint8_t> hasArea(v.NumberOfTriangles);
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
  {
    hasArea[t] = FaceNormal(v, t, &normal[3 * t]);
  }
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const double angle = v.ConeAngle[n];
    if (angle >= Pi - 1e-6)
    {
      continue;
    }
    const float* axis = &v.ConeAxis[3 * n];
    const double least = std::cos(std::min(Pi, angle + 1e-4)) - 1e-6;
    for (int64_t p = v.FirstPoint[n], end = v.PointEnd(n); p < end; ++p)
    {
      for (int64_t j = inc.Start[p]; j < inc.Start[p + 1]; ++j)
      {
        const int32_t t = inc.Triangle[j];
        if (!hasArea[t])
          continue;
        const double* f = &normal[3 * t];
        const double d = axis[0] * f[0] + axis[1] * f[1] + axis[2] * f[2];
        CHECK(d >= least,
          "normal of triangle " + Str(t) + " lies outside the cone of node " + Str(n) + " (cos " +
            std::to_string(d) + ", angle " + std::to_string(angle) + ")");
      }
    }
  }
}

void CheckOwnership(const plod::OctreeView& v)
{
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    for (int64_t t = v.FirstTriangle[n], end = v.TriangleEnd(n); t < end; ++t)
    {
      const int32_t* c = &v.Triangles[3 * t];
      const int64_t la = v.PointLeaf[c[0]], lb = v.PointLeaf[c[1]], lc = v.PointLeaf[c[2]];
      int64_t owner = CommonAncestor(v, la, lb);
      for (int64_t x : { CommonAncestor(v, lb, lc), CommonAncestor(v, la, lc) })
      {
        if (v.Level[x] > v.Level[owner])
          owner = x;
      }
      CHECK(owner == n,
        "triangle " + Str(t) + " is stored at node " + Str(n) + " but owned by " + Str(owner));
    }
  }
}

struct UnionFind
{
  std::vector<int32_t> Root;
  void Reset(int64_t n)
  {
    this->Root.resize(n);
    std::iota(this->Root.begin(), this->Root.end(), 0);
  }
  int32_t Find(int32_t x)
  {
    while (this->Root[x] != x)
    {
      this->Root[x] = this->Root[this->Root[x]];
      x = this->Root[x];
    }
    return x;
  }
  void Unite(int32_t a, int32_t b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a != b)
      this->Root[std::max(a, b)] = std::min(a, b);
  }
};

void CheckClustersAndFlags(const plod::OctreeView& v, const plod::BuildResult& r)
{
  const int64_t np = v.NumberOfPoints, nn = v.NumberOfNodes;
  // unique edges and their uses
  std::vector<std::pair<int32_t, int32_t>> uses;
  uses.reserve(3 * v.NumberOfTriangles);
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int32_t a = v.Triangles[3 * t + k], b = v.Triangles[3 * t + (k + 1) % 3];
      uses.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(uses.begin(), uses.end());
  std::vector<std::pair<int32_t, int32_t>> edges;
  std::vector<uint8_t> boundaryEnd(np, 0);
  int64_t boundary = 0, nonManifold = 0;
  for (size_t i = 0; i < uses.size();)
  {
    size_t j = i + 1;
    while (j < uses.size() && uses[j] == uses[i])
      ++j;
    edges.push_back(uses[i]);
    if (j - i == 1)
    {
      ++boundary;
      boundaryEnd[uses[i].first] = boundaryEnd[uses[i].second] = 1;
    }
    nonManifold += j - i > 2 ? 1 : 0;
    i = j;
  }
  CHECK(r.NumberOfBoundaryEdges == boundary,
    "boundary edges " + Str(r.NumberOfBoundaryEdges) + ", counted " + Str(boundary));
  CHECK(r.NumberOfNonManifoldEdges == nonManifold,
    "non-manifold edges " + Str(r.NumberOfNonManifoldEdges) + ", counted " + Str(nonManifold));

  std::vector<int32_t> anc(v.PointLeaf, v.PointLeaf + np);
  std::vector<int32_t> cl(v.PointCluster, v.PointCluster + np);
  std::vector<int64_t> V(nn, 0), E(nn, 0), F(nn, 0), components(nn, 0);
  std::vector<uint8_t> boundaryNode(nn, 0);
  std::vector<int32_t> clusterOfRoot(np), rootOfCluster(v.NumberOfClusters, -1);
  UnionFind uf;
  int64_t unsafe = 0;
  for (int level = v.FinestLevel; level >= 0; --level)
  {
    if (level < v.FinestLevel)
    {
      for (int64_t p = 0; p < np; ++p)
      {
        anc[p] = v.Parent[anc[p]];
        cl[p] = v.ClusterParent[cl[p]];
      }
    }
    uf.Reset(np);
    for (const auto& e : edges)
    {
      if (anc[e.first] == anc[e.second])
      {
        ++E[anc[e.first]];
        uf.Unite(e.first, e.second);
      }
    }
    for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
    {
      const int32_t* c = &v.Triangles[3 * t];
      if (anc[c[0]] == anc[c[1]] && anc[c[1]] == anc[c[2]])
        ++F[anc[c[0]]];
    }
    std::fill(clusterOfRoot.begin(), clusterOfRoot.end(), -1);
    for (int64_t p = 0; p < np; ++p)
    {
      const int64_t n = anc[p];
      CHECK(v.Level[n] == level && v.ClusterNode[cl[p]] == n,
        "point " + Str(p) + "'s ancestor cluster is not in its ancestor node at level " +
          Str(level));
      CHECK(p >= v.FirstPoint[n] && p < v.PointEnd(n),
        "point " + Str(p) + " is outside the range of its ancestor " + Str(n));
      ++V[n];
      boundaryNode[n] |= boundaryEnd[p];
      const int32_t root = uf.Find(static_cast<int32_t>(p));
      if (clusterOfRoot[root] < 0 && rootOfCluster[cl[p]] < 0)
      {
        clusterOfRoot[root] = cl[p];
        rootOfCluster[cl[p]] = root;
        ++components[n];
      }
      CHECK(clusterOfRoot[root] == cl[p] && rootOfCluster[cl[p]] == root,
        "at node " + Str(n) + " the clusters are not the connected components (point " + Str(p) +
          ")");
    }
  }
  for (int64_t n = 0; n < nn; ++n)
  {
    const int64_t clusters = v.ClusterEnd(n) - v.FirstCluster[n];
    CHECK(clusters == components[n],
      "node " + Str(n) + " has " + Str(clusters) + " clusters for " + Str(components[n]) +
        " components");
    CHECK(V[n] == v.PointEnd(n) - v.FirstPoint[n], "point count of node " + Str(n));
    const bool safe = V[n] - E[n] + F[n] == components[n];
    CHECK(safe == bool(v.Flags[n] & plod::NodeTopologySafe),
      "node " + Str(n) + " topology flag disagrees with V - E + F = " + Str(V[n] - E[n] + F[n]) +
        " for " + Str(components[n]) + " components");
    CHECK(bool(boundaryNode[n]) == bool(v.Flags[n] & plod::NodeBoundary),
      "node " + Str(n) + " boundary flag disagrees");
    unsafe += safe ? 0 : 1;
  }
  CHECK(r.NumberOfUnsafeNodes == unsafe,
    "unsafe nodes " + Str(r.NumberOfUnsafeNodes) + ", counted " + Str(unsafe));
}

void CheckSameBuild(
  const Storage& a, const plod::BuildResult& ra, const Storage& b, const plod::BuildResult& rb)
{
  CHECK(ra.Ok == rb.Ok && ra.Error == rb.Error && ra.FinestLevel == rb.FinestLevel &&
      ra.NumberOfNodes == rb.NumberOfNodes && ra.NumberOfClusters == rb.NumberOfClusters &&
      std::memcmp(ra.Origin, rb.Origin, sizeof ra.Origin) == 0 && ra.RootEdge == rb.RootEdge &&
      ra.NumberOfUnsafeNodes == rb.NumberOfUnsafeNodes,
    "the result depends on how ParallelFor splits the work: " + ra.Error + " / " + rb.Error);
  // every array of the schema, pairwise (ForEachArray visits both storages in one order)
  std::vector<std::pair<const plod::ArraySpec*, std::pair<const void*, size_t>>> bytesOfB;
  plod::ForEachArray(b, [&](const plod::ArraySpec& spec, const auto& y) {
    bytesOfB.push_back({ &spec, { y.data(), y.size() * sizeof(y[0]) } });
  });
  size_t k = 0;
  plod::ForEachArray(a, [&](const plod::ArraySpec& spec, const auto& x) {
    const auto& y = bytesOfB[k++].second;
    CHECK(x.size() * sizeof(x[0]) == y.second &&
        (x.empty() || std::memcmp(x.data(), y.first, y.second) == 0),
      std::string("array ") + spec.Member + " depends on how ParallelFor splits the work");
  });
}

// ------------------------------------------------------------------------------------------------
// Checks of cuts and patches

using Tri = std::array<int64_t, 3>;

/**
 * What GeneratePatches must draw for a valid cut, from plodPatches.h and plodCut.h: each corner
 * becomes its cluster in the cut cell holding it (key >= 0), or itself in an opened leaf
 * (key -1 - p, PatchResult's PointSource code); triangles whose keys repeat have collapsed;
 * a triangle among hidden cells only is skipped when one of them faces away (no cull mask, or
 * a mask of 0) or all were culled by one common plane.
 */
void ExpectedPatches(const plod::OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
  std::vector<Tri>& expected, int64_t& hiddenSkipped)
{
  expected.clear();
  hiddenSkipped = 0;
  std::vector<int64_t> cutCluster(v.NumberOfClusters, -1);
  for (int64_t c = 0; c < v.NumberOfClusters; ++c)
  {
    const int64_t parent = v.ClusterParent[c];
    cutCluster[c] = state[v.ClusterNode[c]] != plod::NotInCut ? c
      : parent >= 0                                           ? cutCluster[parent]
                                                              : -1;
  }
  std::vector<int64_t> key(v.NumberOfPoints), node(v.NumberOfPoints);
  for (int64_t p = 0; p < v.NumberOfPoints; ++p)
  {
    const int64_t leaf = v.PointLeaf[p];
    if (state[leaf] == plod::CutOpen)
    {
      key[p] = -1 - p;
      node[p] = leaf;
    }
    else
    {
      key[p] = cutCluster[v.PointCluster[p]];
      CHECK(key[p] >= 0, "a valid cut leaves point " + Str(p) + " without a cut cell");
      node[p] = v.ClusterNode[key[p]];
    }
  }
  for (int64_t t = 0; t < v.NumberOfTriangles; ++t)
  {
    const int32_t* c = &v.Triangles[3 * t];
    const int64_t k0 = key[c[0]], k1 = key[c[1]], k2 = key[c[2]];
    if (k0 == k1 || k1 == k2 || k0 == k2)
    {
      continue;
    }
    bool drawn = false, backFacing = false;
    uint8_t masks = 0x3f;
    for (int k = 0; k < 3; ++k)
    {
      const int64_t n = node[c[k]];
      if (plod::IsDrawnState(state[n]))
      {
        drawn = true;
      }
      else
      {
        const uint8_t m = cullMask ? cullMask[n] : 0;
        backFacing = backFacing || m == 0;
        masks &= m;
      }
    }
    if (!drawn && (backFacing || masks != 0))
    {
      ++hiddenSkipped;
      continue;
    }
    expected.push_back(Rotated(k0, k1, k2));
  }
  std::sort(expected.begin(), expected.end());
}

/// Output indices and point sources in range, sources distinct (except the folds' own
/// corners, which repeat their sources), no collapsed triangle.
void CheckPatchOutput(const plod::OctreeView& v, const plod::PatchResult& out)
{
  const int64_t points = static_cast<int64_t>(out.PointSource.size());
  CHECK(out.Triangles.size() % 3 == 0, "triangle array length");
  CHECK(static_cast<int64_t>(out.Triangles.size() / 3) <= v.NumberOfTriangles,
    "more output triangles than the input has");
  for (size_t i = 0; i < out.Triangles.size(); i += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      CHECK(out.Triangles[i + k] >= 0 && out.Triangles[i + k] < points,
        "output triangle corner " + Str(out.Triangles[i + k]) + " outside [0, " + Str(points) +
          ")");
    }
    CHECK(out.Triangles[i] != out.Triangles[i + 1] &&
        out.Triangles[i + 1] != out.Triangles[i + 2] && out.Triangles[i] != out.Triangles[i + 2],
      "output triangle with a repeated corner");
  }
  std::vector<uint8_t> reversed(static_cast<size_t>(points), 0);
  for (int32_t r : out.ReversedNormals)
  {
    CHECK(r >= 0 && r < points, "reversed-normal point " + Str(r) + " out of range");
    CHECK(!reversed[r], "a reversed-normal point listed twice");
    reversed[r] = 1;
  }
  std::vector<int64_t> sources;
  for (int64_t p = 0; p < points; ++p)
  {
    const int64_t s = out.PointSource[p];
    CHECK((s >= 0 && s < v.NumberOfClusters) || (s < 0 && -1 - s < v.NumberOfPoints),
      "point source " + Str(s) + " out of range");
    if (!reversed[p])
    {
      sources.push_back(s);
    }
  }
  std::sort(sources.begin(), sources.end());
  CHECK(std::adjacent_find(sources.begin(), sources.end()) == sources.end(),
    "two output points share a source");
}

/// GeneratePatches on a valid cut against the model; returns the number of output triangles.
int64_t CheckPatches(const plod::OctreeView& v, const uint8_t* state, const uint8_t* cullMask,
  const plod::PatchOptions& options, plod::PatchWorkspace* workspace, const char* what)
{
  plod::PatchResult out;
  std::string why;
  const bool ok = plod::GeneratePatches(v, state, cullMask, out, &why, workspace, options);
  CHECK(ok, std::string(what) + ": GeneratePatches refused a valid cut: " + why);
  CheckPatchOutput(v, out);
  std::vector<Tri> expected, got;
  int64_t hidden = 0;
  ExpectedPatches(v, state, cullMask, expected, hidden);
  // a fold given reversed normals: three own corners, in a row, each with its source
  std::vector<uint8_t> reversed(out.PointSource.size(), 0);
  for (int32_t r : out.ReversedNormals)
  {
    reversed[r] = 1;
  }
  int64_t ownCornerTriangles = 0;
  for (size_t i = 0; i < out.Triangles.size(); i += 3)
  {
    const int64_t a = out.Triangles[i], b = out.Triangles[i + 1], c = out.Triangles[i + 2];
    const int own = reversed[a] + reversed[b] + reversed[c];
    CHECK(own == 0 || own == 3, std::string(what) + ": a triangle mixes own and shared corners");
    if (own == 3)
    {
      ++ownCornerTriangles;
      CHECK(out.PointSource[a] >= 0 || out.PointSource[b] >= 0 || out.PointSource[c] >= 0,
        std::string(what) + ": an input triangle was drawn as a fold");
    }
    got.push_back(Rotated(out.PointSource[a], out.PointSource[b], out.PointSource[c]));
  }
  std::sort(got.begin(), got.end());
  CHECK(out.HiddenSkipped == hidden,
    std::string(what) + ": hidden skipped " + Str(out.HiddenSkipped) + ", expected " + Str(hidden));
  const bool keep = options.Folds == plod::FoldHandling::Keep;
  const bool drop = options.Folds == plod::FoldHandling::Drop;
  CHECK(!keep || out.Folds == 0, std::string(what) + ": folds counted with FoldHandling::Keep");
  CHECK(options.Folds == plod::FoldHandling::ReverseNormals || out.ReversedNormals.empty(),
    std::string(what) + ": reversed normals without FoldHandling::ReverseNormals");
  if (options.Folds == plod::FoldHandling::ReverseNormals)
  {
    CHECK(static_cast<int64_t>(out.ReversedNormals.size()) == 3 * out.Folds &&
        ownCornerTriangles == out.Folds,
      std::string(what) + ": " + Str(out.Folds) + " folds, " + Str(out.ReversedNormals.size()) +
        " reversed points, " + Str(ownCornerTriangles) + " triangles on own corners");
  }
  if (!drop && !options.CullBackFaces)
  {
    CHECK(got == expected,
      std::string(what) + ": " + Str(got.size()) + " triangles, expected " + Str(expected.size()));
    CHECK(out.BackFacesCulled == 0, "back faces culled without the option");
    return static_cast<int64_t>(got.size());
  }
  CHECK(std::includes(expected.begin(), expected.end(), got.begin(), got.end()),
    std::string(what) + ": a triangle the model does not draw");
  const int64_t dropped = drop ? out.Folds : 0;
  CHECK(static_cast<int64_t>(got.size()) + dropped + out.BackFacesCulled ==
      static_cast<int64_t>(expected.size()),
    std::string(what) + ": " + Str(got.size()) + " drawn + " + Str(dropped) + " folds + " +
      Str(out.BackFacesCulled) + " back faces != " + Str(expected.size()));
  CHECK(options.CullBackFaces || out.BackFacesCulled == 0, "back faces culled without the option");
  if (!options.CullBackFaces)
  {
    // only dropped folds are missing: each has a representative vertex (input triangles stay)
    std::vector<Tri> missing;
    std::set_difference(
      expected.begin(), expected.end(), got.begin(), got.end(), std::back_inserter(missing));
    for (const Tri& t : missing)
    {
      CHECK(t[0] >= 0 || t[1] >= 0 || t[2] >= 0, "an input triangle was dropped as a fold");
    }
  }
  return static_cast<int64_t>(got.size());
}

/// Fold handling from two bits of a byte: Drop, Keep or ReverseNormals.
plod::FoldHandling DecodeFolds(uint8_t bits)
{
  return (bits & 1) ? plod::FoldHandling::Drop
                    : ((bits & 2) ? plod::FoldHandling::Keep : plod::FoldHandling::ReverseNormals);
}

plod::PatchOptions DecodeOptions(uint8_t b, const plod::PatchOptions& view)
{
  plod::PatchOptions o = view;
  o.Folds = DecodeFolds(static_cast<uint8_t>((b & 1) | ((b >> 1) & 2)));
  o.CullBackFaces = b & 2;
  return o;
}

/// Eye or projection for back-face culling: inside, outside or far from the model.
plod::PatchOptions DecodeCullView(Stream& s, const plod::OctreeView& v)
{
  plod::PatchOptions o;
  const uint8_t mode = s.U8();
  double d[3];
  for (double& x : d)
    x = double(s.S8()) / 32.0;
  const double far[4] = { 1, 10, 1e6, 1e30 };
  o.Parallel = mode & 1;
  for (int a = 0; a < 3; ++a)
  {
    o.Eye[a] = v.RootEdge * (0.5 + d[a] * far[(mode >> 1) & 3]);
    o.ProjectionDirection[a] = d[a];
  }
  if (d[0] == 0 && d[1] == 0 && d[2] == 0)
  {
    o.ProjectionDirection[2] = -1;
  }
  s.U8(); // reserved
  s.U8();
  return o;
}

/// Cut from a refinement predicate drawn from a seed, then some cells hidden with random masks.
void RandomCut(const plod::OctreeView& v, uint64_t seed, int refineProbability,
  int hiddenProbability, std::vector<uint8_t>& state, std::vector<uint8_t>& mask)
{
  auto hash = [seed](int64_t n, uint64_t salt) {
    uint64_t s = seed ^ (uint64_t(n) * 0x9e3779b97f4a7c15ULL) ^ salt;
    return SplitMix(s);
  };
  plod::PredicateCut(
    v, [&](int64_t n) { return int(hash(n, 1) % 256) < refineProbability || n == 0; },
    state.data());
  std::fill(mask.begin(), mask.end(), 0);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (state[n] == plod::CutDrawn && int(hash(n, 2) % 256) < hiddenProbability)
    {
      state[n] = plod::CutHidden;
      const uint64_t h = hash(n, 3);
      mask[n] = (h & 3) == 0 ? 0 : static_cast<uint8_t>((h >> 8) & 0x3f);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// The selector

const double Tolerances[16] = { 0, 1e-300, 0.1, 0.5, 1, 2, 4, 16, 100, 1e6, 1e30, 1e300, Inf,
  4.9406564584124654e-324, 1e-12, 3 };
const double PixelScales[8] = { 1000, 1, 1e-300, 1e300, 0.5, 4000, 1e6, 1e-6 };
const double Intensities[8] = { 0, 0.5, 1, 10, 1e300, -1, 1e-300, 0.8 };
const double Powers[8] = { 0, 1, 2, 5, 64, 65536, 65537, 0.5 };
const double MotionScales[8] = { 0, 1e-3, 1, 1e6, 1e300, 1e-300, 0.1, 10 };
const double Velocities[8] = { 1, 1.5, 10, 1e30, Inf, 1e300, 1, 2 };
const double PSECFactors[8] = { 0.25, 0, 1, 1e30, -1, NaN, 1e-300, 0.1 };
const double FoveationRates[8] = { 0, 1, 10, -10, 1e3, 1e300, -1e300, 0.5 };
const double Heights[4] = { 1, 1e-300, 1e300, 0.5 };
const double Distances[8] = { 2, 10, 1e3, 1e6, 1e15, 1e30, 1e300, 0.6 };
const double ViewAngles[4] = { 30, 1, 170, 1e-3 };

void UnitOrDefault(double d[3], double fallback2)
{
  const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (l > 0 && std::isfinite(l))
  {
    for (int a = 0; a < 3; ++a)
      d[a] /= l;
  }
  else
  {
    d[0] = d[1] = 0;
    d[2] = fallback2;
  }
}

void ReadTriple(Stream& s, double d[3], double scale)
{
  for (int a = 0; a < 3; ++a)
    d[a] = scale * (double(s.S8()) / 64.0);
}

/// A view in the octree's local coordinates.
plod::SelectionInput DecodeView(Stream& s, const plod::OctreeView& v)
{
  plod::SelectionInput in;
  const double E = v.RootEdge;
  const double centre[3] = { 0.5 * E, 0.5 * E, 0.5 * E };
  const uint8_t b0 = s.U8();
  in.Error = static_cast<plod::ErrorModel>(b0 & 3);
  in.Motion = static_cast<plod::MotionModel>((b0 >> 2) & 3);
  in.Foveation = static_cast<plod::FoveationMode>(((b0 >> 4) & 3) % 3);
  in.Parallel = b0 & 64;
  in.HideBackFaces = b0 & 128;
  const uint8_t b1 = s.U8();
  // Cheng's own test in place of Distance on some inputs; IPV/DPV by velocity alone or scaling
  // the error model
  if (in.Error == plod::ErrorModel::Distance && (b1 & 64))
    in.Error = plod::ErrorModel::Cheng;
  in.Velocity =
    (b1 & 32) ? plod::VelocityCriterion::ScalesErrorModel : plod::VelocityCriterion::Alone;
  // eye
  double d[3];
  ReadTriple(s, d, 1.0);
  switch (b1 & 7)
  {
    case 0: // anywhere within two root edges of the model
    case 1:
      for (int a = 0; a < 3; ++a)
        in.Eye[a] = centre[a] + 2 * E * d[a];
      break;
    case 2: // on a node's vertex
    {
      const int64_t n = s.U16() % v.NumberOfNodes;
      for (int a = 0; a < 3; ++a)
        in.Eye[a] = v.Vertex[3 * n + a];
      break;
    }
    case 3: // on a surface point
    {
      const int64_t p = s.U16() % v.NumberOfPoints;
      for (int a = 0; a < 3; ++a)
        in.Eye[a] = v.Points[3 * p + a];
      break;
    }
    case 4: // far away
    {
      UnitOrDefault(d, 1);
      const double dist = s.Pick(Distances) * E;
      for (int a = 0; a < 3; ++a)
        in.Eye[a] = centre[a] + dist * d[a];
      break;
    }
    case 5: // on a corner or face of the root cell, or of a cell of some level
    {
      const int level = s.U8() % 22;
      for (int a = 0; a < 3; ++a)
        in.Eye[a] = std::ldexp(E, -level) * std::round(d[a] * 4);
      break;
    }
    case 6:
      std::copy(centre, centre + 3, in.Eye);
      break;
    default: // fixed-point coordinates with special values, unscaled
      for (int a = 0; a < 3; ++a)
      {
        const int16_t x = s.S16();
        in.Eye[a] = x < -32768 + 16 ? Specials[x + 32768] : double(x) / 256.0;
      }
      break;
  }
  // frustum
  const int frustum = (b1 >> 3) & 3;
  in.UseFrustum = frustum != 0;
  if (frustum == 1)
  {
    // a camera at the eye looking at the centre
    double dir[3] = { centre[0] - in.Eye[0], centre[1] - in.Eye[1], centre[2] - in.Eye[2] };
    UnitOrDefault(dir, -1);
    double up[3] = { 0, 1, 0 };
    if (std::abs(dir[1]) > 0.9)
    {
      up[0] = 1;
      up[1] = 0;
    }
    double right[3] = { dir[1] * up[2] - dir[2] * up[1], dir[2] * up[0] - dir[0] * up[2],
      dir[0] * up[1] - dir[1] * up[0] };
    UnitOrDefault(right, 1);
    const double u[3] = { right[1] * dir[2] - right[2] * dir[1],
      right[2] * dir[0] - right[0] * dir[2], right[0] * dir[1] - right[1] * dir[0] };
    const double half = 0.5 * s.Pick(ViewAngles) * Pi / 180;
    const double aspect[4] = { 1, 16.0 / 9.0, 1e-3, 4 };
    const double halfH = std::atan(std::tan(half) * aspect[s.U8() % 4]);
    const double nearFar[4] = { 1e-3, 0.1, 1, 1e6 };
    const double nearD = nearFar[s.U8() % 4] * E, farD = nearD + nearFar[s.U8() % 4] * 10 * E;
    auto plane = [&](int i, const double n[3], const double at[3]) {
      for (int a = 0; a < 3; ++a)
        in.Planes[i][a] = n[a];
      in.Planes[i][3] = -(n[0] * at[0] + n[1] * at[1] + n[2] * at[2]);
    };
    double n[3];
    for (int a = 0; a < 3; ++a)
      n[a] = dir[a] * std::sin(halfH) + right[a] * std::cos(halfH);
    plane(0, n, in.Eye);
    for (int a = 0; a < 3; ++a)
      n[a] = dir[a] * std::sin(halfH) - right[a] * std::cos(halfH);
    plane(1, n, in.Eye);
    for (int a = 0; a < 3; ++a)
      n[a] = dir[a] * std::sin(half) + u[a] * std::cos(half);
    plane(2, n, in.Eye);
    for (int a = 0; a < 3; ++a)
      n[a] = dir[a] * std::sin(half) - u[a] * std::cos(half);
    plane(3, n, in.Eye);
    double at[3];
    for (int a = 0; a < 3; ++a)
      at[a] = in.Eye[a] + nearD * dir[a];
    plane(4, dir, at);
    for (int a = 0; a < 3; ++a)
    {
      at[a] = in.Eye[a] + farD * dir[a];
      n[a] = -dir[a];
    }
    plane(5, n, at);
  }
  else if (frustum == 2)
  {
    // random planes
    for (int i = 0; i < 6; ++i)
    {
      ReadTriple(s, in.Planes[i], 1.0);
      in.Planes[i][3] = E * double(s.S8()) / 32.0;
    }
  }
  else if (frustum == 3)
  {
    // degenerate planes: zero normals, a constant sign
    const double constant[4] = { 1, 0, -1, -1e-300 };
    for (int i = 0; i < 6; ++i)
    {
      in.Planes[i][0] = in.Planes[i][1] = in.Planes[i][2] = 0;
      in.Planes[i][3] = constant[s.U8() % 4];
    }
  }
  // projection
  ReadTriple(s, in.ProjectionDirection, 1.0);
  in.PixelScale = s.Pick(PixelScales);
  // tolerances
  const uint8_t t = s.U8();
  in.ContourTolerance = Tolerances[t & 15];
  in.BrightnessTolerance = Tolerances[t >> 4];
  const uint8_t t2 = s.U8();
  in.TopologyTolerance = Tolerances[t2 & 15];
  in.UseOctreeMaterial = t2 & 16;
  in.Diffuse = s.Pick(Intensities);
  in.Specular = s.Pick(Intensities);
  in.SpecularPower = s.Pick(Powers);
  // lights
  const int lights = (b1 >> 5) & 3;
  for (int i = 0; i < lights; ++i)
  {
    plod::SelectorLight l;
    const uint8_t f = s.U8();
    l.Positional = f & 1;
    ReadTriple(s, l.Position, l.Positional ? 2 * E : 1.0);
    if (l.Positional)
    {
      for (int a = 0; a < 3; ++a)
        l.Position[a] += centre[a];
      if (f & 2) // the light on a vertex
      {
        const int64_t n = s.U16() % v.NumberOfNodes;
        for (int a = 0; a < 3; ++a)
          l.Position[a] = v.Vertex[3 * n + a];
      }
    }
    l.Diffuse = Intensities[(f >> 2) & 7];
    l.Specular = Intensities[(f >> 5) & 7];
    in.Lights.push_back(l);
  }
  if ((b1 >> 7) & 1)
  {
    plod::SelectorLight l; // directional, along the view (a headlight)
    l.Position[0] = in.Eye[0] - centre[0];
    l.Position[1] = in.Eye[1] - centre[1];
    l.Position[2] = in.Eye[2] - centre[2];
    in.Lights.push_back(l);
  }
  // motion
  const double motionScale = s.Pick(MotionScales);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      in.MotionA[i][j] = motionScale * double(s.S8()) / 64.0;
  for (int a = 0; a < 3; ++a)
    in.MotionB[a] = motionScale * E * double(s.S8()) / 64.0;
  in.VelocityFactor = s.Pick(Velocities);
  in.PSECFactor = s.Pick(PSECFactors);
  in.DistanceLevel = s.S8() / 4;
  // foveation
  in.FoveationRate = s.Pick(FoveationRates);
  ReadTriple(s, in.FoveationPoint, E);
  ReadTriple(s, in.FoveationUp, 1.0);
  UnitOrDefault(in.FoveationUp, 1);
  ReadTriple(s, in.FoveationCentre, E);
  in.FoveationHeight = Heights[s.U8() % 4] * E;
  in.FoveationWeights[0] = double(s.U8()) / 64.0;
  in.FoveationWeights[1] = double(s.U8()) / 64.0;
  ReadTriple(s, in.GazeDirection, 1.0);
  UnitOrDefault(in.GazeDirection, -1);
  return in;
}

bool EyeInBox(const double eye[3], const double lo[3], double h)
{
  return eye[0] >= lo[0] && eye[0] <= lo[0] + h && eye[1] >= lo[1] && eye[1] <= lo[1] + h &&
    eye[2] >= lo[2] && eye[2] <= lo[2] + h;
}

void CheckSelection(const plod::OctreeView& v, const plod::SelectionInput& in, const uint8_t* state,
  const uint8_t* reason, const uint8_t* cullMask, const plod::SelectionStats& stats)
{
  std::string why;
  CHECK(plod::ValidateCut(v, state, &why), "the selector wrote an invalid cut: " + why);
  const bool velocityAlone = (in.Motion == plod::MotionModel::InverseVelocity ||
                               in.Motion == plod::MotionModel::DirectVelocity) &&
    in.Velocity == plod::VelocityCriterion::Alone;
  const bool cheng = in.Error == plod::ErrorModel::Cheng && !velocityAlone;
  int64_t inCut = 0, drawn = 0, opened = 0, leaves = 0;
  const bool zero = in.ContourTolerance == 0 && in.BrightnessTolerance == 0;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const uint8_t s = state[n], r = reason[n];
    leaves += v.IsLeaf(n) ? 1 : 0;
    CHECK((s == plod::NotInCut) == (r == plod::ReasonNone),
      "node " + Str(n) + " state " + Str(s) + " with reason " + Str(r));
    if (s == plod::NotInCut)
    {
      CHECK(!cullMask || cullMask[n] == 0, "a cull mask left on node " + Str(n));
      continue;
    }
    ++inCut;
    drawn += plod::IsDrawnState(s) ? 1 : 0;
    opened += s == plod::CutOpen ? 1 : 0;
    CHECK((s == plod::CutOpen) == (r == plod::OpenedLeaf),
      "node " + Str(n) + " state " + Str(s) + " with reason " + Str(r));
    CHECK(s != plod::CutHidden || r == plod::Culled || r == plod::BackFacing,
      "hidden node " + Str(n) + " with reason " + Str(r));
    CHECK(r != plod::Culled || (s == plod::CutHidden && in.UseFrustum),
      "culled node " + Str(n) + " in state " + Str(s));
    CHECK(r != plod::BackFacing || (in.Error == plod::ErrorModel::SRCC && !velocityAlone),
      "back-facing node " + Str(n) + " outside SRCC");
    CHECK(r != plod::BackFacing || (s == plod::CutHidden) == in.HideBackFaces,
      "back-facing node " + Str(n) + " in state " + Str(s));
    double lo[3], h;
    NodeBox(v, n, lo, h);
    if (r == plod::Culled)
    {
      if (cullMask)
      {
        CHECK(cullMask[n] != 0 && cullMask[n] < 64, "culled node " + Str(n) + " without a mask");
        for (int p = 0; p < 6; ++p)
        {
          if (!(cullMask[n] & (1u << p)))
            continue;
          const double* pl = in.Planes[p];
          double far = pl[3];
          for (int a = 0; a < 3; ++a)
            far += pl[a] * (pl[a] > 0 ? lo[a] + h : lo[a]);
          CHECK(far < 0, "node " + Str(n) + " is not wholly outside plane " + Str(p));
        }
      }
      continue;
    }
    if (cullMask)
    {
      CHECK(cullMask[n] == 0, "node " + Str(n) + " has a cull mask but was not culled");
    }
    if (!in.Parallel)
    {
      const float* x = &v.Vertex[3 * n];
      const bool onVertex =
        in.Eye[0] == double(x[0]) && in.Eye[1] == double(x[1]) && in.Eye[2] == double(x[2]);
      CHECK(s == plod::CutOpen || (!EyeInBox(in.Eye, lo, h) && !onVertex),
        "node " + Str(n) + " holds the eye but was not refined (reason " + Str(r) + ")");
    }
    if (velocityAlone)
    {
      // velocity alone: a cell is drawn at its vertex only by its projected size
      CHECK(s == plod::CutOpen || r == plod::AcceptedSize,
        "velocity alone drew node " + Str(n) + " for reason " + Str(r));
      CHECK(s == plod::CutOpen || in.ContourTolerance > 0,
        "zero tolerance, yet velocity alone accepted node " + Str(n));
    }
    if (cheng && in.Foveation == plod::FoveationMode::Off)
    {
      // D = 0 everywhere: the threshold is 1 and nothing is simplified
      CHECK(s == plod::CutOpen, "Cheng without foveation accepted node " + Str(n));
    }
    if (zero && in.Error == plod::ErrorModel::SRCC && !velocityAlone)
    {
      CHECK(s == plod::CutOpen || r == plod::BackFacing,
        "zero tolerances, yet node " + Str(n) + " was accepted (reason " + Str(r) + ")");
    }
    if (in.ContourTolerance == 0 &&
      (in.Error == plod::ErrorModel::SCVC || in.Error == plod::ErrorModel::PSEC))
    {
      CHECK(s == plod::CutOpen,
        "zero tolerance, yet node " + Str(n) + " was accepted (reason " + Str(r) + ")");
    }
    if (in.Error == plod::ErrorModel::Distance && !velocityAlone)
    {
      CHECK(s == plod::CutOpen || v.Level[n] >= in.DistanceLevel,
        "Distance model drew node " + Str(n) + " above level " + Str(in.DistanceLevel));
    }
  }
  CHECK(stats.InCut == inCut && stats.Drawn == drawn && stats.Opened == opened,
    "statistics " + Str(stats.InCut) + "/" + Str(stats.Drawn) + "/" + Str(stats.Opened) +
      " for a cut of " + Str(inCut) + "/" + Str(drawn) + "/" + Str(opened));
  if (in.ContourTolerance == 0 && !in.UseFrustum &&
    (in.Error == plod::ErrorModel::SCVC || in.Error == plod::ErrorModel::PSEC))
  {
    CHECK(opened == leaves, "zero tolerance opened " + Str(opened) + " of " + Str(leaves));
  }
  // IPV and DPV with an infinite factor: the root alone (unless the eye forces refinement)
  if ((in.Motion == plod::MotionModel::InverseVelocity ||
        in.Motion == plod::MotionModel::DirectVelocity) &&
    std::isinf(in.VelocityFactor) && in.Foveation == plod::FoveationMode::Off &&
    in.ContourTolerance > 0 &&
    (velocityAlone ||
      (in.Error != plod::ErrorModel::Distance && in.Error != plod::ErrorModel::Cheng)))
  {
    const float* x = &v.Vertex[0];
    const bool eyeRefines = !in.Parallel &&
      (EyeInBox(in.Eye, std::array<double, 3>{ 0, 0, 0 }.data(), v.RootEdge) ||
        (in.Eye[0] == double(x[0]) && in.Eye[1] == double(x[1]) && in.Eye[2] == double(x[2])));
    if (!eyeRefines)
    {
      CHECK(state[0] != plod::NotInCut, "an infinite velocity factor refined the root");
    }
  }
}

/// Cuts that may be invalid: GeneratePatches must not crash, must accept what ValidateCut
/// accepts, and must return something in range.
void CheckCorruptCut(const plod::OctreeView& v, std::vector<uint8_t>& state,
  const std::vector<uint8_t>& mask, plod::PatchWorkspace* workspace)
{
  std::string why;
  const bool valid = plod::ValidateCut(v, state.data(), &why);
  plod::PatchResult out;
  std::string patchWhy;
  const bool ok = plod::GeneratePatches(v, state.data(), mask.data(), out, &patchWhy, workspace);
  if (valid)
  {
    CHECK(ok, "GeneratePatches refused a cut ValidateCut accepts: " + patchWhy);
  }
  if (ok)
  {
    CheckPatchOutput(v, out);
  }
  else
  {
    CHECK(!patchWhy.empty() && out.Triangles.empty() && out.PointSource.empty(),
      "a refused cut left output or no reason");
  }
}

uint64_t Hash(const uint8_t* data, size_t size)
{
  uint64_t h = 1469598103934665603ULL;
  for (size_t i = 0; i < size; ++i)
  {
    h = (h ^ data[i]) * 1099511628211ULL;
  }
  return h;
}

void Run(const uint8_t* data, size_t size)
{
  const uint64_t seed = Hash(data, size);
  size_t control = size > 0 ? std::min<size_t>(data[size - 1], size - 1) : 0;
  const size_t front = size > 0 ? size - 1 - control : 0;
  Stream model(data, front, seed);
  Stream ctl(data + front, control, seed ^ 0x5bd1e995ULL);

  Model m;
  DecodeModel(model, m);

  const uint8_t c0 = ctl.U8();
  const uint8_t c1 = ctl.U8();
  const int forVariant = c0 & 3;
  const bool compare = c0 & 4;
  const int abortAt = c0 >> 3;

  Storage storage;
  storage.Fill = std::array<uint8_t, 4>{ 0x00, 0xff, 0xa5, 0x5a }[c1 & 3];
  int calls = 0;
  bool aborted = false;
  plod::ProgressCallback progress = [&](double f) {
    CHECK(f >= 0 && f <= 1, "progress " + std::to_string(f) + " outside [0, 1]");
    if (abortAt > 0 && ++calls >= abortAt)
    {
      aborted = true;
      return false;
    }
    return true;
  };
  // a cloud's mesh: at most 3 crossed edges per grid corner, 8 corners per occupied cell, a
  // vertex per cell around each crossed edge and two triangles per crossed edge
  const int64_t maxPoints = m.Cloud ? 96 * m.NumberOfPoints : m.NumberOfPoints;
  const int64_t maxTriangles = m.Cloud ? 48 * m.NumberOfPoints : m.NumberOfTriangles;
  const plod::Allocator allocate = storage.MakeAllocator(maxPoints, maxTriangles);
  const plod::BuildResult r =
    plod::BuildOctree(m.Input, m.Params, allocate, MakeParallelFor(forVariant, seed), progress);
  const InputCounts counts = CountInput(m);
  const bool verbose = std::getenv("PLOD_FUZZ_VERBOSE") != nullptr;
  if (verbose)
  {
    std::fprintf(stderr,
      "model: %s, %lld points (%s), %lld triangles (%s), level %d, memory %g, normals %d\n"
      "input: %lld kept, %lld invalid, %lld degenerate, %lld non-finite points\n"
      "build: %s%s; level %d (%s); %lld nodes, %lld clusters, %lld points, %lld triangles; "
      "non-finite %lld, invalid %lld, degenerate %lld; origin %g %g %g, edge %g\n",
      m.Cloud ? "cloud" : "mesh", (long long)m.NumberOfPoints, m.DoublePoints ? "double" : "float",
      (long long)m.NumberOfTriangles, m.Int64Triangles ? "int64" : "int32", m.Params.FinestLevel,
      m.Params.MemoryLimit, int(!m.Normals.empty()), (long long)counts.Kept,
      (long long)counts.Invalid, (long long)counts.Degenerate, (long long)counts.NonFinite,
      r.Ok ? "ok" : "failed: ", r.Error.c_str(), r.FinestLevel, r.LevelReason.c_str(),
      (long long)r.NumberOfNodes, (long long)r.NumberOfClusters, (long long)r.NumberOfPoints,
      (long long)r.NumberOfTriangles, (long long)r.NumberOfNonFinitePoints,
      (long long)r.NumberOfInvalidTriangles, (long long)r.NumberOfDegenerateTriangles, r.Origin[0],
      r.Origin[1], r.Origin[2], r.RootEdge);
  }
  if (!r.Ok)
  {
    CHECK(!r.Error.empty(), "a failed build without an error message");
    CHECK(r.Aborted == aborted, "Aborted " + Str(r.Aborted) + " after an abort " + Str(aborted));
    CHECK(!r.Aborted || r.Error == "build aborted", "an aborted build says " + r.Error);
    return;
  }
  CHECK(!aborted && !r.Aborted, "an aborted build returned Ok");
  CHECK(m.Cloud || counts.Kept > 0, "a mesh without a usable triangle was built");
  CHECK(storage.NodeCalls == 1, "Ok without allocating");
  const plod::OctreeView v = storage.View(r);
  std::string why;
  CHECK(plod::ValidateOctree(v, &why), "ValidateOctree: " + why);
  CHECK(v.NumberOfNodes > 0, "an Ok build without nodes");

  CheckResultAndInput(m, counts, r, storage, v);
  CheckGeometry(v);
  CheckOwnership(v);
  CheckClustersAndFlags(v, r);
  {
    const Incidence inc(v);
    CheckCones(v, inc);
  }
  if (compare)
  {
    Storage serial;
    serial.Fill = storage.Fill ^ 0xff;
    const plod::BuildResult rs = plod::BuildOctree(
      m.Input, m.Params, serial.MakeAllocator(maxPoints, maxTriangles), plod::SerialFor);
    CheckSameBuild(storage, r, serial, rs);
  }

  // cuts and patches
  plod::PatchWorkspace workspaceStorage;
  plod::PatchWorkspace* workspace = (c1 & 4) ? nullptr : &workspaceStorage;
  const plod::PatchOptions cullView = DecodeCullView(ctl, v);
  const int64_t nn = v.NumberOfNodes;
  std::vector<uint8_t> state(nn), mask(nn, 0);
  plod::UniformCut(v, -1, state.data());
  CHECK(plod::ValidateCut(v, state.data(), &why), "the full cut is invalid: " + why);
  for (int options = 0; options < 4; ++options)
  {
    const int64_t drawn = CheckPatches(v, state.data(), nullptr,
      DecodeOptions(static_cast<uint8_t>(options), cullView), workspace, "full cut");
    CHECK((options & 2) || drawn == v.NumberOfTriangles,
      "the full cut drew " + Str(drawn) + " of " + Str(v.NumberOfTriangles) + " triangles");
  }
  for (int level = 0; level <= v.FinestLevel + 1; ++level)
  {
    plod::UniformCut(v, level, state.data());
    CHECK(plod::ValidateCut(v, state.data(), &why),
      "uniform cut " + Str(level) + " is invalid: " + why);
    const uint8_t options = static_cast<uint8_t>((c1 >> 4) + level);
    CheckPatches(
      v, state.data(), nullptr, DecodeOptions(options, cullView), workspace, "uniform cut");
  }
  const int cuts = ctl.U8() % 4;
  for (int i = 0; i < cuts; ++i)
  {
    const uint64_t cutSeed = seed ^ (uint64_t(ctl.U8()) << 32) ^ uint64_t(i);
    const int refine = ctl.U8();
    const int hidden = ctl.U8();
    const uint8_t options = ctl.U8();
    RandomCut(v, cutSeed, refine, hidden, state, mask);
    CHECK(plod::ValidateCut(v, state.data(), &why), "a predicate cut is invalid: " + why);
    CheckPatches(v, state.data(), (options & 4) ? nullptr : mask.data(),
      DecodeOptions(options, cullView), workspace, "random cut");
  }
  const int corrupt = ctl.U8() % 3;
  for (int i = 0; i < corrupt; ++i)
  {
    uint64_t cutSeed = seed ^ (uint64_t(ctl.U8()) << 40) ^ uint64_t(i);
    const int changes = 1 + ctl.U8() % 4;
    RandomCut(v, cutSeed, 128, 32, state, mask);
    for (int k = 0; k < changes; ++k)
    {
      const uint64_t h = SplitMix(cutSeed);
      const uint8_t value = static_cast<uint8_t>(h >> 32);
      state[h % nn] = (value & 0xc0) ? (value & 3) : value;
    }
    CheckCorruptCut(v, state, mask, workspace);
  }

  // the selector
  const int views = ctl.U8() % 5;
  const bool useMask = !(c1 & 8);
  plod::Selector selector;
  selector.SetOctree(v);
  std::vector<uint8_t> reason(nn, 0), cull(nn, 0);
  std::fill(state.begin(), state.end(), 0);
  bool compared = false;
  for (int i = 0; i < views; ++i)
  {
    const plod::SelectionInput in = DecodeView(ctl, v);
    {
      // the helpers stay in range for any view
      const int level =
        plod::DistanceLevel(v.RootEdge, v.FinestLevel, in.ContourTolerance, in.PixelScale * 1e-3,
          std::sqrt(in.Eye[0] * in.Eye[0] + in.Eye[1] * in.Eye[1]), in.PixelScale);
      CHECK(level >= 0 && level <= v.FinestLevel + 1, "DistanceLevel " + Str(level));
      const double a = double(in.DistanceLevel) / 16.0, b = v.ConeAngle[0];
      const double spread = plod::ConeCosineSpread(
        std::cos(a), std::sin(a), std::cos(b), std::sin(b), in.SpecularPower);
      CHECK(spread >= 0 && spread <= 1, "ConeCosineSpread " + std::to_string(spread));
    }
    const bool valid = plod::ValidateSelectionInput(in, &why);
    if (verbose)
    {
      std::fprintf(stderr, "view %d: model %d, motion %d, fovea %d, %s, eye %g %g %g, %s\n", i,
        int(in.Error), int(in.Motion), int(in.Foveation), in.Parallel ? "parallel" : "perspective",
        in.Eye[0], in.Eye[1], in.Eye[2], valid ? "valid" : why.c_str());
    }
    if (!valid)
    {
      continue;
    }
    plod::SelectionStats stats;
    selector.Select(in, state.data(), reason.data(), useMask ? cull.data() : nullptr, stats);
    if (verbose)
    {
      std::fprintf(stderr, "  visited %lld, in cut %lld, drawn %lld, opened %lld\n",
        (long long)stats.Visited, (long long)stats.InCut, (long long)stats.Drawn,
        (long long)stats.Opened);
    }
    CheckSelection(v, in, state.data(), reason.data(), useMask ? cull.data() : nullptr, stats);
    plod::PatchOptions options;
    options.CullBackFaces = in.HideBackFaces && (i & 1);
    options.Folds = DecodeFolds(static_cast<uint8_t>(i >> 1));
    std::copy(in.Eye, in.Eye + 3, options.Eye);
    options.Parallel = in.Parallel;
    std::copy(in.ProjectionDirection, in.ProjectionDirection + 3, options.ProjectionDirection);
    CheckPatches(v, state.data(), useMask ? cull.data() : nullptr, options, workspace, "selection");
    if (!compared)
    {
      compared = true;
      plod::Selector fresh;
      fresh.SetOctree(v);
      std::vector<uint8_t> s2(nn, 0), r2(nn, 0), m2(nn, 0);
      plod::SelectionStats stats2;
      fresh.Select(in, s2.data(), r2.data(), useMask ? m2.data() : nullptr, stats2);
      CHECK(s2 == state && r2 == reason && (!useMask || m2 == cull),
        "a fresh selector wrote another cut for the same view");
    }
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  Run(data, size);
  return 0;
}
