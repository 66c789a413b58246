// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodScanGenerator.h
 * @brief Scan-like test models of any size written to a binary PLY file in bounded memory.
 *
 * A base mesh (the Stanford bunny, or a closed octahedral sphere when no base is given) has each
 * triangle split into n x n triangles on a regular barycentric grid. Every new point is moved
 * along the smooth normal (the base's point normals interpolated) by a sum of value-noise
 * octaves of its undisplaced position, from the scale of the base's edges down to the scale of
 * the new triangles, each octave's amplitude 0.15 x its scale: detail at every scale, as in a
 * scan, and the base's own shape, holes and thin parts above. Points on a base edge are
 * generated once for the edge and shared by its triangles, so the model is as closed as its
 * base and has no duplicated points.
 *
 * The file is written in one forward pass: the base's points, then the points inside each
 * base edge, then those inside each base triangle, then the faces. Memory holds the base mesh,
 * its edge table and a fixed write buffer, whatever n is. The counts are
 *   points    = V + E (n - 1) + T (n - 1)(n - 2) / 2,
 *   triangles = T n^2,
 * for a base of V points, E edges and T triangles. The file is written under a temporary name
 * and renamed when complete.
 *
 * VTK-free: used by the benchmark program plodGenerateScan and by the kernels' tests.
 */
#ifndef plodScanGenerator_h
#define plodScanGenerator_h

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace plodtest
{

/// A triangle mesh: 3 coordinates per point, 3 point ids per triangle.
struct BaseMesh
{
  std::vector<double> Points;
  std::vector<int64_t> Triangles;
};

/// A closed sphere of 8 * 4^k triangles (an octahedron subdivided k times, projected).
inline BaseMesh OctahedralSphere(int k)
{
  BaseMesh m;
  m.Points = { 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1 };
  m.Triangles = { 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5 };
  for (int s = 0; s < k; ++s)
  {
    std::vector<std::pair<uint64_t, int64_t>> mids; // edge key -> new point
    auto mid = [&](int64_t a, int64_t b) {
      const uint64_t key = (uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b));
      for (const auto& e : mids)
      {
        if (e.first == key)
        {
          return e.second;
        }
      }
      double p[3], l = 0;
      for (int c = 0; c < 3; ++c)
      {
        p[c] = 0.5 * (m.Points[3 * a + c] + m.Points[3 * b + c]);
        l += p[c] * p[c];
      }
      l = std::sqrt(l);
      const int64_t id = static_cast<int64_t>(m.Points.size() / 3);
      for (double c : p)
      {
        m.Points.push_back(c / l);
      }
      mids.emplace_back(key, id);
      return id;
    };
    std::vector<int64_t> out;
    for (size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      const int64_t a = m.Triangles[t], b = m.Triangles[t + 1], c = m.Triangles[t + 2];
      const int64_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      const int64_t four[12] = { a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca };
      out.insert(out.end(), four, four + 12);
    }
    m.Triangles.swap(out);
  }
  return m;
}

/// What GenerateScanPLY wrote.
struct ScanCounts
{
  int64_t Points = 0;
  int64_t Triangles = 0;
  int64_t Bytes = 0;
};

/// The largest n: a base triangle's inner points and its grid of ids are held at once.
constexpr int MaxScanSplit = 4096;

namespace scan
{
inline uint64_t Mix(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// A value in [-1, 1] at an integer lattice point of an octave.
inline double Lattice(int64_t x, int64_t y, int64_t z, uint64_t octave)
{
  const uint64_t h = Mix(Mix(Mix(Mix(octave) ^ uint64_t(x)) ^ uint64_t(y)) ^ uint64_t(z));
  return 2.0 * (double(h >> 11) / double(1ULL << 53)) - 1.0;
}

/// Value noise in [-1, 1] of frequency 1 at p (smoothstep-weighted trilinear).
inline double ValueNoise(const double p[3], uint64_t octave)
{
  int64_t i[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    const double fl = std::floor(p[a]);
    i[a] = static_cast<int64_t>(fl);
    const double t = p[a] - fl;
    f[a] = t * t * (3.0 - 2.0 * t);
  }
  double v = 0;
  for (int c = 0; c < 8; ++c)
  {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? f[0] : 1 - f[0]) * (dy ? f[1] : 1 - f[1]) * (dz ? f[2] : 1 - f[2]);
    v += w * Lattice(i[0] + dx, i[1] + dy, i[2] + dz, octave);
  }
  return v;
}
} // namespace scan

/**
 * Writes the base mesh with each triangle split n x n and displaced (see the file's
 * documentation) to `path` as a binary little-endian PLY (float x y z; uchar int
 * vertex_indices). `seed` changes the noise. Returns false with `why` set when the file cannot
 * be written (the temporary file is removed) or the counts exceed PLY's 2^31 - 1.
 * `progress`, when set, is called with the fraction written.
 */
inline bool GenerateScanPLY(const BaseMesh& base, int n, uint64_t seed, const std::string& path,
  ScanCounts* counts, std::string* why, const std::function<void(double)>& progress = nullptr)
{
  const uint16_t one = 1;
  if (*reinterpret_cast<const unsigned char*>(&one) != 1)
  {
    *why = "the generator writes little-endian rows from memory: this host is big-endian";
    return false;
  }
  const int64_t V = static_cast<int64_t>(base.Points.size() / 3);
  const int64_t T = static_cast<int64_t>(base.Triangles.size() / 3);
  n = std::max(1, n);
  if (n > MaxScanSplit)
  {
    *why = "a split of " + std::to_string(n) + " x " + std::to_string(n) + " per triangle is " +
      "more than " + std::to_string(MaxScanSplit) + " (a base triangle's points are held at once)";
    return false;
  }

  // edges: (min id, max id) sorted; a triangle's edge is found by binary search
  std::vector<uint64_t> edges;
  edges.reserve(3 * T);
  for (int64_t t = 0; t < T; ++t)
  {
    for (int e = 0; e < 3; ++e)
    {
      const uint64_t a = uint64_t(base.Triangles[3 * t + e]);
      const uint64_t b = uint64_t(base.Triangles[3 * t + (e + 1) % 3]);
      edges.push_back((std::min(a, b) << 32) | std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const int64_t E = static_cast<int64_t>(edges.size());
  const int64_t inner = int64_t(n - 1) * (n - 2) / 2;
  const int64_t points = V + E * (n - 1) + T * inner;
  const int64_t triangles = T * int64_t(n) * n;
  if (points > 2147483647LL || triangles > 2147483647LL)
  {
    *why = "more than 2^31 - 1 points or triangles, beyond PLY readers";
    return false;
  }

  // smooth normals: area-weighted sums of the base's triangle normals; the mean edge length
  std::vector<double> normals(3 * V, 0.0);
  double edgeSum = 0;
  for (int64_t t = 0; t < T; ++t)
  {
    const double* p[3];
    for (int k = 0; k < 3; ++k)
    {
      p[k] = &base.Points[3 * base.Triangles[3 * t + k]];
    }
    const double u[3] = { p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] };
    const double v[3] = { p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] };
    const double c[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
      u[0] * v[1] - u[1] * v[0] };
    for (int k = 0; k < 3; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        normals[3 * base.Triangles[3 * t + k] + a] += c[a];
      }
    }
    edgeSum += std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  }
  for (int64_t i = 0; i < V; ++i)
  {
    double* q = &normals[3 * i];
    const double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    for (int a = 0; a < 3 && l > 0; ++a)
    {
      q[a] /= l;
    }
  }
  const double scale0 = T > 0 ? edgeSum / double(T) : 1.0;
  int octaves = 1;
  while ((1 << (octaves - 1)) < n)
  {
    ++octaves;
  }

  // a point from a base point's barycentric weights: position and normal interpolated, then
  // moved along the normal by the noise octaves of the undisplaced position
  auto place = [&](const int64_t ids[3], const double w[3], float out[3]) {
    double x[3] = { 0, 0, 0 }, nn[3] = { 0, 0, 0 };
    for (int k = 0; k < 3; ++k)
    {
      if (w[k] == 0.0)
      {
        continue;
      }
      for (int a = 0; a < 3; ++a)
      {
        x[a] += w[k] * base.Points[3 * ids[k] + a];
        nn[a] += w[k] * normals[3 * ids[k] + a];
      }
    }
    const double l = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
    double shift = 0;
    if (l > 0)
    {
      double s = scale0;
      for (int o = 0; o < octaves; ++o, s *= 0.5)
      {
        const double q[3] = { x[0] / s, x[1] / s, x[2] / s };
        shift += 0.15 * s * scan::ValueNoise(q, seed * 64 + uint64_t(o));
      }
      shift /= l;
    }
    for (int a = 0; a < 3; ++a)
    {
      out[a] = static_cast<float>(x[a] + shift * nn[a]);
    }
  };

  const std::string temporary = path + ".partial";
  std::FILE* file = std::fopen(temporary.c_str(), "wb");
  if (!file)
  {
    *why = "cannot write " + temporary + ": " + std::strerror(errno);
    return false;
  }
  std::vector<unsigned char> buffer;
  buffer.reserve(1 << 23);
  bool ok = true;
  auto flush = [&]() {
    if (!buffer.empty() && std::fwrite(buffer.data(), 1, buffer.size(), file) != buffer.size())
    {
      ok = false;
    }
    buffer.clear();
  };
  auto put = [&](const void* bytes, size_t size) {
    const auto* b = static_cast<const unsigned char*>(bytes);
    buffer.insert(buffer.end(), b, b + size);
    if (buffer.size() >= (1u << 23))
    {
      flush();
    }
  };
  const std::string header = "ply\nformat binary_little_endian 1.0\n"
                             "comment plodScanGenerator: base of " +
    std::to_string(T) + " triangles split " + std::to_string(n) + " x " + std::to_string(n) +
    ", seed " + std::to_string(seed) + "\nelement vertex " + std::to_string(points) +
    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
    std::to_string(triangles) + "\nproperty list uchar int vertex_indices\nend_header\n";
  put(header.data(), header.size());
  const double total = double(points) + double(triangles);
  double done = 0;
  auto report = [&](double more) {
    done += more;
    if (progress)
    {
      progress(done / total);
    }
  };

  // points, in blocks computed on the machine's threads and written in order
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  auto emitBlocks = [&](int64_t count, int64_t pointsPerItem,
                      const std::function<void(int64_t item, float* out)>& make) {
    if (pointsPerItem <= 0)
    {
      return; // nothing to place (edges when n = 1, inner points when n <= 2)
    }
    const int64_t block =
      std::max<int64_t>(1, (int64_t(1) << 20) / std::max<int64_t>(1, pointsPerItem));
    std::vector<float> xyz;
    for (int64_t first = 0; first < count && ok; first += block)
    {
      const int64_t last = std::min(count, first + block);
      xyz.assign(size_t(3 * pointsPerItem * (last - first)), 0.0f);
      std::vector<std::thread> pool;
      for (unsigned w = 0; w < threads; ++w)
      {
        pool.emplace_back([&, w]() {
          for (int64_t item = first + w; item < last; item += threads)
          {
            make(item, &xyz[size_t(3 * pointsPerItem * (item - first))]);
          }
        });
      }
      for (auto& th : pool)
      {
        th.join();
      }
      put(xyz.data(), xyz.size() * sizeof(float));
      report(double(pointsPerItem * (last - first)));
    }
  };
  emitBlocks(V, 1, [&](int64_t i, float* out) {
    const int64_t ids[3] = { i, i, i };
    const double w[3] = { 1, 0, 0 };
    place(ids, w, out);
  });
  emitBlocks(E, n - 1, [&](int64_t e, float* out) {
    const int64_t ids[3] = { int64_t(edges[e] >> 32), int64_t(edges[e] & 0xffffffffULL), 0 };
    for (int k = 1; k < n; ++k)
    {
      const double w[3] = { double(n - k) / n, double(k) / n, 0 };
      place(ids, w, out + 3 * (k - 1));
    }
  });
  emitBlocks(T, inner, [&](int64_t t, float* out) {
    const int64_t ids[3] = { base.Triangles[3 * t], base.Triangles[3 * t + 1],
      base.Triangles[3 * t + 2] };
    int64_t next = 0;
    for (int j = 1; j <= n - 2; ++j)
    {
      for (int i = 1; i + j <= n - 1; ++i)
      {
        const double w[3] = { double(n - i - j) / n, double(i) / n, double(j) / n };
        place(ids, w, out + 3 * next++);
      }
    }
  });

  // faces: each base triangle's grid, with its corner, edge and inner points' global ids
  const int64_t edgeStart = V, innerStart = V + E * (n - 1);
  auto edgePoint = [&](int64_t u, int64_t v, int k) { // k/n of the way from u to v
    const uint64_t key = (uint64_t(std::min(u, v)) << 32) | uint64_t(std::max(u, v));
    const int64_t e = std::lower_bound(edges.begin(), edges.end(), key) - edges.begin();
    return edgeStart + e * (n - 1) + (u < v ? k - 1 : n - 1 - k);
  };
  std::vector<int64_t> grid;
  for (int64_t t = 0; t < T && ok; ++t)
  {
    const int64_t a = base.Triangles[3 * t], b = base.Triangles[3 * t + 1],
                  c = base.Triangles[3 * t + 2];
    // P(i, j) = a + i/n (b - a) + j/n (c - a), stored at row j, column i
    grid.assign(size_t(n + 1) * (n + 1), -1);
    auto at = [&](int i, int j) -> int64_t& { return grid[size_t(j) * (n + 1) + i]; };
    at(0, 0) = a;
    at(n, 0) = b;
    at(0, n) = c;
    for (int k = 1; k < n; ++k)
    {
      at(k, 0) = edgePoint(a, b, k);
      at(0, k) = edgePoint(a, c, k);
      at(n - k, k) = edgePoint(b, c, k);
    }
    int64_t next = innerStart + t * inner;
    for (int j = 1; j <= n - 2; ++j)
    {
      for (int i = 1; i + j <= n - 1; ++i)
      {
        at(i, j) = next++;
      }
    }
    unsigned char row[13];
    row[0] = 3;
    auto face = [&](int64_t p, int64_t q, int64_t r) {
      const int32_t ids[3] = { int32_t(p), int32_t(q), int32_t(r) };
      std::memcpy(row + 1, ids, 12);
      put(row, 13);
    };
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i + j < n; ++i)
      {
        face(at(i, j), at(i + 1, j), at(i, j + 1));
        if (i + j + 1 < n)
        {
          face(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
      }
    }
    report(double(n) * n);
  }
  flush();
  ok = std::fflush(file) == 0 && ok;
  const long end = std::ftell(file);
  ok = std::fclose(file) == 0 && ok;
  if (!ok || std::rename(temporary.c_str(), path.c_str()) != 0)
  {
    *why = "cannot write " + path + ": " + std::strerror(errno);
    std::remove(temporary.c_str());
    return false;
  }
  if (counts)
  {
    counts->Points = points;
    counts->Triangles = triangles;
    counts->Bytes = static_cast<int64_t>(end);
  }
  return true;
}

} // namespace plodtest

#endif
