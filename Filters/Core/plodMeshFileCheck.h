// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodMeshFileCheck.h
 * @brief VTK-free validation of STL and OBJ files before a reader trusts them.
 *
 * Formats: STL as 3D Systems defined it (1989; binary: an 80-byte header, a little-endian
 * uint32 triangle count, then per triangle a normal and three vertices as 12 float32 and a
 * 2-byte attribute; ASCII: `solid [name]`, facets of `facet normal ...`, `outer loop`, three
 * `vertex x y z`, `endloop`, `endfacet`, then `endsolid [name]`), and Wavefront OBJ (the
 * geometry statements of Wavefront's Advanced Visualizer manual, appendix B1).
 *
 * Both checks read the file once, forward, through a fixed buffer: memory stays small for a
 * file of any size, time is linear in its size, and no byte of the file can make them crash or
 * loop. Only a regular file is opened (it is stat'ed first, and opened without blocking, so a
 * FIFO is refused at once: "is not a regular file (a FIFO)"); an empty file is an error.
 *
 * CheckSTLFile:
 * 1. Binary or ASCII: binary when the size is exactly 84 + 50 n for the count n in bytes
 *    80..83 (also when the header starts with "solid", as many binary writers' headers do);
 *    ASCII when it is not, the first word is `solid` and the first 1024 bytes hold no control
 *    byte (binary counts and floats hold zero bytes); anything else is a damaged binary file.
 * 2. Binary: the size must be exactly 84 + 50 n: the message says how many bytes are missing
 *    and in which triangle the file ends (triangles count from 0), or how many are extra. Every
 *    vertex coordinate must be finite (the normal is ignored): the first triangle with a NaN or
 *    infinite coordinate is named and all of them are counted.
 * 3. ASCII, line by line (keywords in any case, blank lines allowed): `solid [name]`, then
 *    facets (`color ...` lines between facets are allowed), each `facet ...` (the normal is
 *    ignored), `outer loop`, exactly three `vertex x y z` with three numbers that are finite as
 *    float32, `endloop`, `endfacet`; then `endsolid [name]`; several solids may follow each
 *    other. A file that ends inside a solid or a facet is cut: the message gives the line.
 * 4. At least one triangle. Warnings (the check passes; summary's Warning says it): triangles
 *    with two equal corners, which readers that merge points (vtkSTLReader) drop.
 *
 * CheckOBJFile, line by line (a `#` starts a comment that runs to the end of the line; keywords
 * are case-sensitive, as in the format):
 * 1. `v x y z [w]` (or `v x y z r g b [a]`): 3 to 7 numbers; x, y and z finite as float32
 *    (the readers keep float coordinates: a value beyond the range of float is not finite). A
 *    non-finite vertex is an error naming its line; all of them are counted.
 * 2. `vt u [v [w]]` (1 to 3 numbers) and `vn x y z` (3 numbers) are counted; their values are not
 *    geometry and may be anything (exporters write `vn nan nan nan` for degenerate faces).
 * 3. `f` with at least 3 references, `l` with at least 2, `p` with at least 1. A reference is
 *    i, i/t, i/t/n or i//n, the same form throughout a statement; each index is a non-zero
 *    integer; a positive one counts from 1, a negative one back from the last defined so far
 *    (-1 is the last), and each must name a vertex, texture coordinate or normal defined
 *    before the statement. A face of fewer than 3 references is an error, not a warning:
 *    the format requires 3, and VTK 9.1's vtkOBJReader refuses the whole file for it.
 * 4. Other statements (g, o, s, usemtl, mtllib, vp, curves and surfaces, ...) are skipped.
 * 5. At least one vertex. Warnings: `l` and `p` statements (not faces, so nothing draws them),
 *    no face at all (the vertices are read as a point cloud), and under VTK's limits faces
 *    without normal references beside faces with them (vtkOBJReader skips them).
 *
 * Reader limits (STLReaderLimits, OBJReaderLimits, optional): what a particular reader cannot
 * take although the format allows it. VTKSTLReaderLimits() and VTKOBJReaderLimits() give those
 * of VTK 9.1's vtkSTLReader and vtkOBJReader.
 *
 * Messages name the problem and where it is: the byte offset or the triangle (binary STL) or
 * the line number (ASCII STL and OBJ; lines count from 1). A byte 0 in a text file is an error.
 */
#ifndef plodMeshFileCheck_h
#define plodMeshFileCheck_h

#include <cstdint>
#include <string>

namespace plod
{

enum class STLFormat
{
  ASCII = 0,
  Binary = 1
};

/// What CheckSTLFile read. Complete when the check passes; after a failure it holds what was
/// read before the problem was found.
struct STLSummary
{
  STLFormat Format = STLFormat::Binary;
  int64_t FileBytes = 0;
  /// Binary: the count in the header; ASCII: the facets read.
  int64_t NumberOfTriangles = 0;
  int64_t NumberOfSolids = 0; ///< ASCII: `solid` ... `endsolid` blocks (binary: 0)
  /// Triangles with a NaN or infinite vertex coordinate, and the first of them (-1: none).
  int64_t NumberOfNonFiniteTriangles = 0;
  int64_t FirstNonFiniteTriangle = -1;
  /// Triangles with two equal corners, and the first of them (-1: none).
  int64_t NumberOfDegenerateTriangles = 0;
  int64_t FirstDegenerateTriangle = -1;
  /// After a passing check, what a reader takes but a consumer must know, in one line
  /// (degenerate triangles); "" when there is nothing to say.
  std::string Warning;
};

/// What a particular STL reader cannot take although the format allows it. Zero or false: no
/// limit.
struct STLReaderLimits
{
  const char* ReaderName = "the reader"; ///< for messages
  /// The reader decides ASCII or binary from the first bytes alone, as vtksys's DetectFileType
  /// does: binary when 5% or more of the first 256 bytes are not text (text: 0x20 to 0x7f, tab,
  /// newline, carriage return). A file whose bytes say otherwise than its structure is refused
  /// (an ASCII solid with a name in UTF-8 would be read as binary triangles of garbage).
  bool DetectsTypeFromFirstBytes = false;
  /// Longest ASCII line, without its newline (a longer one is split by the reader).
  int64_t MaxLineBytes = 0;
  /// Most triangles of a binary file (the reader sizes its arrays in an int).
  int64_t MaxTriangles = 0;
};

/// The limits of vtkSTLReader in VTK 9.1: the file type taken from the first 256 bytes, ASCII
/// lines of at most 254 bytes (read with fgets into 255 bytes), and at most 715827882 binary
/// triangles (it allocates 3 n points with n in an int).
STLReaderLimits VTKSTLReaderLimits();

/**
 * Checks that the file at `path` is a well-formed binary or ASCII STL file of at least one
 * triangle whose vertices are finite (see the file's documentation), and that a reader with the
 * given limits reads it as what it is. Returns true when it is (with summary's Warning set when
 * a consumer must know something); otherwise false with the reason in `why` (one line). `why`
 * and `summary` may be null. Never throws; memory stays within a small buffer.
 */
bool CheckSTLFile(const std::string& path, std::string* why, STLSummary* summary = nullptr,
  const STLReaderLimits& limits = STLReaderLimits());

/// What CheckOBJFile read. Complete when the check passes; after a failure it holds what was
/// read before the problem was found.
struct OBJSummary
{
  int64_t FileBytes = 0;
  int64_t NumberOfLines = 0;    ///< text lines (the last one counts even without a newline)
  int64_t NumberOfVertices = 0; ///< `v`
  int64_t NumberOfTextureCoordinates = 0; ///< `vt`
  int64_t NumberOfNormals = 0;            ///< `vn`
  int64_t NumberOfFaces = 0;              ///< `f`
  int64_t MaxFaceSize = 0;                ///< most references in one face
  int64_t NumberOfPolylines = 0;          ///< `l`, not drawn
  int64_t FirstPolylineLine = -1;
  int64_t NumberOfPointElements = 0; ///< `p`, not drawn
  int64_t FirstPointElementLine = -1;
  /// Vertices with a non-finite x, y or z, and the line of the first (-1: none).
  int64_t NumberOfNonFiniteVertices = 0;
  int64_t FirstNonFiniteVertexLine = -1;
  /// Faces without a normal reference in a file where other faces have one, and the line of the
  /// first (-1: none).
  int64_t NumberOfFacesWithoutNormals = 0;
  int64_t FirstFaceWithoutNormalsLine = -1;
  /// After a passing check, what a reader takes but a consumer must know, in one line: `l` and
  /// `p` statements (not drawn), no face at all (a point cloud), faces a reader skips; "" when
  /// there is nothing to say.
  std::string Warning;
};

/// What a particular OBJ reader cannot take although the format allows it. False: no limit.
struct OBJReaderLimits
{
  const char* ReaderName = "the reader"; ///< for messages
  /// No comment after the references of an `f`, `l` or `p` statement (a reader that parses
  /// every word of the statement as a reference fails on the `#`, and drops the whole file).
  bool NoCommentAfterReferences = false;
  /// Faces without a normal reference are skipped when another face has one: a warning.
  bool SkipsFacesWithoutNormals = false;
};

/// The limits of vtkOBJReader in VTK 9.1: a `#` after the references of `f`, `l` or `p` makes
/// it read nothing, and once a face has normal references it skips every face without them.
OBJReaderLimits VTKOBJReaderLimits();

/**
 * Checks that the file at `path` is a well-formed OBJ file of at least one vertex, whose
 * vertices are finite and whose references name what was defined before them (see the file's
 * documentation), and that a reader with the given limits can take. Returns true when it is
 * (with summary's Warning set when a consumer must know something); otherwise false with the
 * reason in `why` (one line). `why` and `summary` may be null. Never throws; memory stays within
 * a small buffer, whatever the length of a line.
 */
bool CheckOBJFile(const std::string& path, std::string* why, OBJSummary* summary = nullptr,
  const OBJReaderLimits& limits = OBJReaderLimits());

/// Largest binary STL triangle count VTK 9.1's vtkSTLReader takes (3 n fits in an int).
constexpr int64_t MaxVTKSTLTriangles = 715827882;

/// Longest ASCII STL line VTK 9.1's vtkSTLReader takes whole, without its newline.
constexpr int64_t MaxVTKSTLLineBytes = 254;

} // namespace plod

#endif
