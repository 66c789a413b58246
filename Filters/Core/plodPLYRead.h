// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPLYRead.h
 * @brief VTK-free streaming reader of a PLY triangle mesh into compact arrays.
 *
 * Reads the file once, forward, through a fixed buffer (plodPLYIO.h), straight into the arrays
 * a build takes (plod::BuildInput): single-precision points when the file's coordinates are
 * single precision (double when any coordinate is), 32-bit triangle indices, and unit-free point
 * normals when the vertex element has nx, ny and nz. Nothing else of the file is kept: other
 * vertex properties (colours, confidence, texture coordinates) and elements other than `vertex`
 * and `face` are skipped. Faces of more than 3 vertices are split into a fan of triangles;
 * faces of fewer than 3 are dropped and counted.
 *
 * The header is read with ReadPLYHeader (plodPLYCheck.h). The body is not trusted: a row that
 * runs past the end of the file, a negative list count, a vertex index outside [0, vertex
 * count) or an ASCII token that is not a number of its type stops the read with a message that
 * names the element, the row and the place, and leaves the output empty.
 *
 * Memory: the output arrays only (EstimatePLYMeshBytes gives it from the header before any row
 * is read), never a second copy of the mesh; a vtkPLYReader holds about twice as much.
 *
 * @sa plodPLYCheck.h plodOctreeBuilder.h vtkMultiscaleOctreeBuilder::SetFileName
 */
#ifndef plodPLYRead_h
#define plodPLYRead_h

#include "plodPLYCheck.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace plod
{

/// A triangle mesh read from a PLY file.
struct PLYMesh
{
  int64_t NumberOfPoints = 0;
  std::vector<float> PointsFloat;   ///< 3 per point, when every coordinate is float
  std::vector<double> PointsDouble; ///< 3 per point, when a coordinate is double
  std::vector<float> Normals;       ///< 3 per point, or empty (no nx ny nz)
  std::vector<int32_t> Triangles;   ///< 3 point indices per triangle
  int64_t NumberOfFaces = 0;        ///< rows of `face`
  int64_t NumberOfShortFaces = 0;   ///< rows of fewer than 3 indices, dropped
  int64_t NumberOfSplitFaces = 0;   ///< rows of more than 3 indices, split into fans

  int64_t NumberOfTriangles() const { return static_cast<int64_t>(this->Triangles.size() / 3); }
};

/// Whether the header's vertex element has a double coordinate (the points are then read as
/// double), and whether it has nx, ny and nz (read as normals).
bool PLYHasDoubleCoordinates(const PLYSummary& header);
bool PLYHasNormals(const PLYSummary& header);

/// Bytes ReadPLYMesh holds for a file with this header: the points, the normals and one
/// triangle per face (a face of n > 3 vertices adds n - 3 triangles, which the header cannot
/// tell).
double EstimatePLYMeshBytes(const PLYSummary& header);

/// Called with the fraction of the file read, in [0, 1]; return false to abort.
using PLYProgress = std::function<bool(double)>;

/**
 * Receives a PLY mesh's rows as StreamPLYMesh reads them, in file order. Each function returns
 * false to stop the read, with the reason in `why` (the reader adds where in the file it was).
 */
class PLYMeshSink
{
public:
  virtual ~PLYMeshSink() = default;
  /// Before the first vertex row: the rows to come, whether a coordinate is double and whether
  /// normals (nx, ny, nz) are read.
  virtual bool BeginVertices(int64_t count, bool doubles, bool normals, std::string* why) = 0;
  /// One vertex row: its coordinates and, when normals are read, its normal (else null).
  virtual bool Vertex(
    int64_t row, const double xyz[3], const double normal[3], std::string* why) = 0;
  /// Before a face's corners are read: how many it has (a sink may refuse what it cannot hold).
  virtual bool BeginFace(int64_t corners, std::string* why) = 0;
  /// One triangle of a face's fan, corner indices in [0, vertex count).
  virtual bool Triangle(int64_t a, int64_t b, int64_t c, std::string* why) = 0;
};

/// What a streamed read saw of the faces.
struct PLYStreamCounts
{
  int64_t NumberOfFaces = 0;      ///< rows of `face`
  int64_t NumberOfShortFaces = 0; ///< rows of fewer than 3 indices, dropped
  int64_t NumberOfSplitFaces = 0; ///< rows of more than 3 indices, split into fans
};

/**
 * Reads the PLY mesh at `path` forward once, through a fixed buffer, handing each vertex row
 * and each triangle to `sink`; holds nothing of the mesh itself. The same checks as ReadPLYMesh;
 * false with the reason in `why` (one line, may be null) when the file or the sink stops it.
 * Rows already handed over stay with the sink: a sink that keeps them must drop them on false.
 * Never throws.
 */
bool StreamPLYMesh(const std::string& path, PLYMeshSink* sink, std::string* why,
  const PLYProgress& progress = nullptr, PLYStreamCounts* counts = nullptr);

/**
 * Reads the PLY mesh at `path` into `mesh` (replacing what it held). Returns false with the
 * reason in `why` (one line, may be null) on a file that cannot be read, a header without a
 * vertex element, a body that does not match its header, an abort from `progress`, or too
 * little memory; `mesh` is then empty. `maxBytes` > 0 bounds the arrays: a file whose faces
 * split into more triangles than that holds (one face of many corners can) is refused before
 * they are made. Never throws.
 */
bool ReadPLYMesh(const std::string& path, PLYMesh* mesh, std::string* why,
  const PLYProgress& progress = nullptr, double maxBytes = 0);

} // namespace plod

#endif
