// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPLYCheck.h
 * @brief VTK-free validation of a PLY file before a reader trusts it.
 *
 * Format: Greg Turk's PLY polygon file format (1994), as read by the reader VTK ships
 * (vtkPLY, Turk's code): a text header, then the rows of each element in header order, in
 * ASCII (one row per line) or binary (little or big endian, no padding).
 *
 * The check trusts nothing in the file:
 * 1. File: a regular, non-empty, readable file (not a directory).
 * 2. Header (at most MaxPLYHeaderBytes): first line `ply`; exactly one
 *    `format ascii|binary_little_endian|binary_big_endian 1.0`; `comment` and `obj_info` lines;
 *    `element <name> <count>` with 0 <= count <= 2^31 - 1 (Turk's reader keeps counts in an
 *    int); `property <type> <name>` and `property list <count type> <item type> <name>` with the
 *    types char/int8, uchar/uint8, short/int16, ushort/uint16, int/int32, uint/uint32,
 *    float/float32, double/float64 (a list count must have an integer type); unique element
 *    names and unique property names in an element; a line `end_header`. Unknown keywords are
 *    errors.
 * 3. Geometry: an element `vertex` with scalar properties x, y and z; an element `face` with
 *    rows has a list vertex_indices or vertex_index. The properties every
 *    reader gives a fixed shape must have it: in `vertex`, u v texture_u texture_v nx ny nz red
 *    green blue diffuse_red diffuse_green diffuse_blue alpha are scalars; in `face`,
 *    vertex_indices, vertex_index and texcoord are lists and intensity red green blue alpha are
 *    scalars. (A reader that finds a list where it expects a scalar, or the reverse, writes a
 *    pointer over a number or follows a number as a pointer.)
 * 4. Body, streamed through a fixed buffer, in time linear in the file size:
 *    - binary: rows of fixed size are counted by arithmetic against the bytes left; rows with
 *      lists are walked one by one, each list count read and checked (not negative, and its
 *      items fit in the bytes left) before its items are skipped or read;
 *    - ASCII: each row is one line with exactly the tokens its properties need (a list's count
 *      says how many follow), separated by spaces, tabs or carriage returns; integer types take
 * integers in their type's range, floating types take decimal numbers (nan and inf included); blank
 * lines inside the body are errors;
 *    - every item of a list named vertex_indices or vertex_index (in any element but `vertex`)
 *      is an integer in [0, vertex count); in an element `tristrips`, -1 (the strip separator)
 *      is allowed too.
 *    Bytes after the last row are allowed (summary's TrailingBytes; for ASCII, whitespace does
 *    not count).
 * 5. Warnings (the check passes; summary's Warning says it): rows of `face` with fewer than 3
 *    vertex indices. The format allows them and vtkPLYReader reads them as polygons of 0, 1 or 2
 *    points, but they bound no surface, and filters that expect polygons (vtkPolyDataNormals)
 *    crash on them: consumers drop them (summary's NumberOfShortFaces and FirstShortFace).
 *
 * Reader limits (PLYReaderLimits, optional): what a particular reader cannot take although
 * the format allows it. VTKPLYReaderLimits() gives those of vtkPLYReader in VTK 9.1 (Turk's
 * code): lines read into 4096-byte buffers, a face's vertex count kept in an unsigned char,
 * elements read in file order with only `vertex` and `face` consumed, every header line's
 * first "vertex_index" overwritten with "vertex_indices", and a last ASCII line without a
 * newline dropped.
 *
 * Messages name the problem and where it is: the element and its row (rows count from 0), the
 * property, and the byte offset (binary) or line number (ASCII, lines count from 1).
 *
 * Not checked: the values themselves (NaN coordinates are valid PLY; consumers decide).
 */
#ifndef plodPLYCheck_h
#define plodPLYCheck_h

#include <cstdint>
#include <string>
#include <vector>

namespace plod
{

enum class PLYFormat
{
  ASCII = 0,
  BinaryLittleEndian = 1,
  BinaryBigEndian = 2
};

/// The scalar types of PLY; each has two names (e.g. uchar and uint8).
enum class PLYType
{
  Int8 = 0,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

struct PLYProperty
{
  std::string Name;
  bool IsList = false;
  PLYType Type = PLYType::Float32;    ///< the value's type, or a list item's
  PLYType CountType = PLYType::UInt8; ///< a list's count type (unused for scalars)
};

struct PLYElement
{
  std::string Name;
  int64_t Count = 0;
  std::vector<PLYProperty> Properties;
};

/// What the check read. Complete when the check passes; after a failure it holds what was read
/// before the problem was found.
struct PLYSummary
{
  PLYFormat Format = PLYFormat::ASCII;
  std::vector<PLYElement> Elements; ///< in file order
  int64_t NumberOfVertices = 0;     ///< count of element `vertex`
  int64_t NumberOfFaces = 0;        ///< count of element `face` (0 when there is none)
  int64_t MaxFaceSize = 0;          ///< longest vertex index list in `face`
  /// Rows of `face` with fewer than 3 vertex indices (valid PLY, but not polygons), and the
  /// first of them (-1 when there is none).
  int64_t NumberOfShortFaces = 0;
  int64_t FirstShortFace = -1;
  int64_t FileBytes = 0;
  int64_t HeaderBytes = 0;   ///< offset of the body
  int64_t TrailingBytes = 0; ///< bytes after the last row (ASCII: non-whitespace bytes only)
  /// After a passing check, what a reader takes but a consumer must know, in one line: faces of
  /// fewer than 3 vertex indices (how many, and the first one's row, size and place), and
  /// a `tristrips` element (a surface a reader of `vertex` and `face` drops). "" when there is
  /// nothing to say.
  std::string Warning;
};

/// What a particular reader cannot take although the format allows it. Zero or false: no limit.
struct PLYReaderLimits
{
  const char* ReaderName = "the reader"; ///< for messages
  int64_t MaxLineBytes = 0;    ///< longest header line or ASCII body line, without its newline
  int64_t MaxFaceSize = 0;     ///< most vertex indices in one row of `face`
  bool VertexThenFace = false; ///< `vertex` comes first, and `face` (if any) right after it
  /// A header word containing "vertex_index" must be the property name vertex_index or
  /// vertex_indices at the end of its line (comments excepted): Turk's reader replaces the first
  /// "vertex_index" of every line by "vertex_indices" and drops the rest of the line.
  bool VertexIndexAtLineEnd = false;
  /// The last row of an ASCII body ends with a newline: Turk's reader reads lines with
  /// std::getline and drops a last line that reaches the end of the file.
  bool FinalNewline = false;
};

/// The limits of vtkPLYReader in VTK 9.1: lines of at most 4000 bytes (it reads 4096-byte
/// buffers and writes past the replaced word), faces of at most 255 vertices (the count is kept
/// in an unsigned char), `vertex` then `face` first (it reads only those two elements, in file
/// order, without skipping others), "vertex_index" only at the end of header lines, and a
/// newline after the last ASCII row.
PLYReaderLimits VTKPLYReaderLimits();

/// Longest header the check reads before deciding that `end_header` is missing.
constexpr int64_t MaxPLYHeaderBytes = 1 << 20;

/// Largest element count: Turk's reader (and VTK's) keeps counts in an int.
constexpr int64_t MaxPLYElementCount = 2147483647;

/**
 * Checks that the file at `path` is a well-formed PLY file whose body matches its header (see
 * the file's documentation) and that a reader with the given limits can take. Returns true when
 * it is (with summary's Warning set when faces of fewer than 3 indices must be dropped);
 * otherwise false with the reason in `why` (one line). `why` and `summary` may be null.
 * Never throws; memory stays within a small buffer plus the header's description.
 */
bool CheckPLYFile(const std::string& path, std::string* why, PLYSummary* summary = nullptr,
  const PLYReaderLimits& limits = PLYReaderLimits());

/**
 * Reads only the header of the PLY file at `path` (steps 1 to 3 above, without the body), in
 * time independent of the file's size: what a caller needs to decide before reading the rows
 * (counts, types, whether normals are there). A body shorter than the header's rows at their
 * smallest (every list empty; in ASCII, every value one character and a separator) fails here
 * already. `summary` gets everything but the
 * body's findings (MaxFaceSize, short faces, TrailingBytes and Warning stay empty).
 */
bool ReadPLYHeader(const std::string& path, std::string* why, PLYSummary* summary);

/// "ascii", "binary_little_endian" or "binary_big_endian".
const char* PLYFormatName(PLYFormat format);

/// The type's first PLY name: "char", "uchar", "short", "ushort", "int", "uint", "float",
/// "double".
const char* PLYTypeName(PLYType type);

/// Size in bytes of a binary value of the type.
int PLYTypeSize(PLYType type);

/// The element named `name`, or null.
const PLYElement* FindPLYElement(const PLYSummary& summary, const std::string& name);

} // namespace plod

#endif
