// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodOctreeFile.h
 * @brief VTK-free reading and writing of octree files (`.plod`), versions 1 and 2.
 *
 * The file holds every array of a vtkMultiscaleOctree and its root cube, so that a large scan
 * is built once and opened in milliseconds afterwards. Layout, all integers and floats
 * little-endian whatever the machine:
 *
 * | offset | size | field |
 * | ---: | ---: | --- |
 * | 0 | 8 | magic `P L O D O C T \n` |
 * | 8 | 4 | format version (1: every array stored as it is; 2: some arrays compressed) |
 * | 12 | 4 | byte-order mark 0x01020304 (bytes 04 03 02 01) |
 * | 16 | 4 | header size in bytes (128 + 64 per array) |
 * | 20 | 4 | number of arrays |
 * | 24 | 24 | origin (3 doubles) |
 * | 48 | 8 | root edge (double) |
 * | 56 | 4 | finest level (int32) |
 * | 60 | 4 | flags (bit 0: material ranges come from input arrays; bits 8-15: the coarsest level
 * drawn, 0 in files before) | | 64 | 48 | nodes, points, triangles, clusters, boundary edges,
 * non-manifold edges (int64) | | 112 | 8 | file size in bytes | | 120 | 4 | checksum of the header
 * and directory (this field counted as 0) | | 124 | 4 | misoriented edges (uint32, saturated at
 * 2^32 - 1; 0 in files that predate it) | | 128 | 64 each | directory: name (32 bytes, NUL-padded),
 * group (1: 0 node, 1 cluster, 2 surface point, 3 surface triangle), type (1: uint8, 2: int32, 3:
 * float32, 4: int64), components (uint16), encoding (1: 0 stored as it is, 1 compressed blocks;
 * always 0 in version 1), reserved (3), tuples (int64), offset (uint64), checksum of the data
 * (uint64) |
 *
 * A compressed array (version 2, FileLayout::Compact) holds its tuples in blocks of a fixed
 * number of tuples (the last one shorter), each decodable on its own: at the array's offset the
 * tuples per block (uint32) and the number of blocks (uint32), then each block's stored bytes
 * (uint32 each), then the blocks back to back. A block is its tuples' values, little-endian,
 * transformed and then compressed with zstd: each value becomes its difference from the same
 * component of the previous tuple of the block (the first tuple's from zero), taken as an
 * unsigned integer of the value's size (a float by its bits, so nothing is lost) and
 * zigzag-mapped (small differences of either sign become small numbers); the values' bytes are
 * then grouped by significance (byte 0 of every value, then byte 1, and so on). The checksum of a
 * compressed array runs over its blocks, then over its table (tuples per block, count, sizes).
 *
 * An array stored as it is starts at a multiple of 4096 bytes (so that it can be mapped in place)
 * and holds tuples x components values; a compressed array starts at a multiple of 8 bytes. The
 * checksums are 64-bit FNV-1a over 8-byte words (the tail byte by byte); the header's is folded to
 * 32 bits.
 *
 * Writing never rewrites a file in place (see WriteOctreeFile). Reading opens only regular files
 * (a FIFO or a device is refused without being opened), maps the file (copy-on-write: edits of
 * the arrays never reach the file), records the file's identity (device, inode, size,
 * modification time: CompareFileIdentity tells later whether it changed underneath) and checks
 * everything that does not need the data: magic, version, byte order, header checksum, sizes,
 * offsets inside the file, counts that agree with each group. The data's checksums are checked
 * only when asked (it reads every byte), except a compressed array's, which is checked whenever
 * it is decoded (on every open: its bytes are read anyway); the octree's consistency is checked by
 * the filters that use it (vtkMultiscaleOctree::IsConsistent).
 */
#ifndef plodOctreeFile_h
#define plodOctreeFile_h

#include "plodOctree.h"
#include "plodOctreeSchema.h"
#include "plodParallel.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plod
{

/// The file-level facts of an octree.
struct OctreeFileHeader
{
  double Origin[3] = { 0, 0, 0 };
  double RootEdge = 1;
  int32_t FinestLevel = 0;
  bool HasMaterialArrays = false;
  int64_t Nodes = 0, Points = 0, Triangles = 0, Clusters = 0;
  int64_t BoundaryEdges = 0, NonManifoldEdges = 0;
  int64_t MisorientedEdges = 0; // stored as a 32-bit count, saturated (files before: 0)
  /// Levels coarser than this hold the tree's structure only, not surfaces to draw (an octree
  /// assembled from pieces whose levels above them could not be built, plodPieceAssembly.h):
  /// a selector refines them at once. 0: every level is drawn (files before: 0).
  int32_t CoarsestDrawnLevel = 0;
};

/// The value types and groups of the file's arrays are the schema's (plodOctreeSchema.h).
using FileArrayType = ArrayType;
using FileArrayGroup = ArrayGroup;

/// Size in bytes of one value of a type (0 for an unknown type).
int FileTypeSize(FileArrayType type);

/// One array to write, or one array read (then Data points into the mapped file).
struct FileArray
{
  std::string Name; // at most 31 bytes
  FileArrayGroup Group = FileArrayGroup::Node;
  FileArrayType Type = FileArrayType::UInt8;
  int Components = 1;
  int64_t Tuples = 0;
  const void* Data = nullptr; // host byte order
  uint64_t Checksum = 0;      // when read: the stored one
  /// To write an array that is not in memory (Data null): fills `out` with `count` values
  /// (tuples x components) from value `first` on, in host byte order; false with the reason.
  /// Called once over the array, in order, with at most 1 MiB at a time.
  std::function<bool(int64_t first, int64_t count, void* out, std::string* why)> Values;
};

/// How an octree file stores its arrays.
enum class FileLayout
{
  /// Version 1: every array as it is in memory, on a page boundary, so that the file is mapped
  /// in place and opens in a millisecond at any size; nothing is read before it is used.
  Mapped,
  /// Version 2: every array compressed in blocks (see the layout above), a third of the bytes or
  /// less; the file is read and decoded into memory when it is opened.
  Compact
};

/// How WriteOctreeFile writes.
struct FileWriteOptions
{
  FileLayout Layout = FileLayout::Mapped;
  /// How a compact file's blocks are compressed (in parallel or not; the bytes are the same).
  ParallelFor Parallel = SerialFor;
};

/// The arrays an octree file holds, in file order: the required arrays of
/// plodOctreeSchema.h (the optional ones are not stored).
const std::vector<ArraySpec>& OctreeFileSchema();

/**
 * Writes `arrays` and `header` to `path` without ever losing what was there: the file is
 * written to a new temporary file beside the target (`.<name>.<random>.tmp`, in the target's
 * directory), flushed and synced, opened again and checked (structure and every checksum; a
 * compact file's blocks by their checksums, without decoding them, so that the check's memory
 * stays bounded), and only then renamed over the target, whose directory is synced. On any failure
 * (a full disk, a write error, a failed check) only the temporary file is removed: an existing
 * target is left byte for byte as it was. Because the target is replaced by a rename and never
 * rewritten in place, a program that has the old file mapped keeps reading the old file's bytes.
 *
 * `path` may name a new file, an existing regular file (its permissions are kept), or a symbolic
 * link to either (the link stays and its target is replaced). Anything else (a directory, a
 * FIFO, a device, a socket, a link to one of them) is refused before anything is written. False
 * with `error` set (what failed, and for which file) on failure.
 */
bool WriteOctreeFile(const std::string& path, const OctreeFileHeader& header,
  const std::vector<FileArray>& arrays, const FileWriteOptions& options, std::string* error);

/// WriteOctreeFile with the default options (FileLayout::Mapped).
bool WriteOctreeFile(const std::string& path, const OctreeFileHeader& header,
  const std::vector<FileArray>& arrays, std::string* error);

/**
 * Writes the octree file `from` again as `to` in `options.Layout` (a compact file to the mapped
 * layout, or back) without decoding it whole: a compressed array is decoded one block at a
 * time as the writer asks for its values, so that the memory it takes stays bounded whatever
 * the file's size. Every checksum of `from` is verified first; `to` is written as
 * WriteOctreeFile writes (never over a file in place; `from` and `to` may be the same file).
 * False with `error` set on failure.
 */
bool ConvertOctreeFile(const std::string& from, const std::string& to,
  const FileWriteOptions& options, std::string* error);

/**
 * True when `path` names a regular file (following symbolic links), decided without opening it,
 * so that a FIFO, whose opening would block until a writer comes, is never opened. False with
 * `why` ("does not exist", "is a directory", "is a FIFO", "is a device", "is a socket") otherwise.
 */
bool IsRegularFile(const std::string& path, std::string* why);

/// What identifies the file an octree was opened from, to notice a change underneath.
struct FileIdentity
{
  std::string Path;
  uint64_t Device = 0;
  uint64_t Inode = 0;
  int64_t Size = 0;
  int64_t ModifiedNs = 0; // modification time, nanoseconds since the epoch
};

/// How the file at an identity's path compares with the file that was opened.
enum class FileChange
{
  Same,           // the same file, same size and modification time
  Replaced,       // another file now has the path (a rename over it): the opened one is intact
  ChangedInPlace, // the opened file itself was rewritten or truncated: a map of it is unsafe
  Gone            // nothing has the path any more (the opened file lives while it is mapped)
};

/// Compares the file now at `opened.Path` with `opened`; `why` says what changed (not Same).
FileChange CompareFileIdentity(const FileIdentity& opened, std::string* why);

/**
 * An octree file opened for reading. Open maps it (or, where mapping fails or the machine is
 * big-endian, reads it into memory) and checks its structure; the arrays' Data point into that
 * memory, which lives as long as the longest-lived holder of the shared pointer `Memory`.
 */
struct OctreeFile
{
  OctreeFileHeader Header;
  std::vector<FileArray> Arrays;
  std::shared_ptr<void> Memory; // keeps the mapping (or buffer) alive
  bool Mapped = false;          // true when Data point into a memory map of the file
  void* MapStart = nullptr;     // the map's first byte (the file's), when Mapped
  bool Compact = false;         // true when arrays were compressed (decoded into memory)
  FileIdentity Identity;        // the file that was opened, as it was then
};

/**
 * Opens `path`. `verifyChecksums` also reads every array and compares its checksum (slower: it
 * touches the whole file). `mapFile` false reads the file into memory instead of mapping it. The
 * compressed arrays of a compact file are decoded into memory (their blocks run through
 * `parallel`, serially when it is empty) and their checksums are always verified; an array
 * stored as it is stays in the map. A compact file whose decoded arrays would take more than
 * three quarters of the machine's memory is refused (ConvertOctreeFile makes a mapped copy in
 * bounded memory). False with `error` set (what is wrong, and where) on a missing, truncated,
 * corrupt or foreign file.
 */
bool OpenOctreeFile(const std::string& path, bool verifyChecksums, bool mapFile, OctreeFile& out,
  std::string* error, const ParallelFor& parallel = ParallelFor());

/// The schema's arrays of an octree, in OctreeFileSchema() order, pointing into `v` (to write).
std::vector<FileArray> FileArraysOf(const OctreeView& v);

/**
 * The view of the octree in `file`: its counts and root cube, and every schema array (see
 * MatchSchema); false (and `why`) when an array is missing or of the wrong type. The view is
 * not validated (plod::ValidateOctree does that).
 */
bool ViewOfFile(const OctreeFile& file, OctreeView& v, std::string* why);

/**
 * The arrays of `file` in OctreeFileSchema() order, each found by group and name with the
 * schema's type and components; false (and `why`: which array is missing or wrong) otherwise.
 */
bool MatchSchema(const OctreeFile& file, std::vector<const FileArray*>& arrays, std::string* why);

/// 64-bit FNV-1a over 8-byte little-endian words, then the tail bytes.
uint64_t FileChecksum(const void* data, size_t bytes);

} // namespace plod

#endif
