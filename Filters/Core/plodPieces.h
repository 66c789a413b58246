// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPieces.h
 * @brief VTK-free partition of a PLY file into pieces by space, in bounded memory, for a build
 *        one piece after the other.
 *
 * A PLY file too large to hold is split into pieces with the rules of the distributed build
 * (plodPartition.h, one copy of them in plodPartitionSteps.h): one root cube, the level-k cells
 * shared out in Morton runs of about equal triangle counts, each piece given the triangles of
 * its cells and their halo, its points merged and put in canonical order, ghosts flagged, one
 * finest level and one open-edge count for all. Piece p equals the share PartitionMesh gives
 * rank p when the same mesh is split over as many processes, so each piece's octree draws its
 * cells exactly as the octree of the whole mesh does (levels k and finer).
 *
 * The file is read once (StreamPLYMesh), forward; nothing of the whole mesh is held in memory:
 * 1. points to a temporary file (single or double precision as in the file, normals as
 *    floats), triangles to another (32-bit indices): 12 to 48 bytes per point, 12 per triangle;
 * 2. two passes over the triangle file, with the point file mapped: the bounds of the usable
 *    triangles (a non-finite corner is skipped and counted) and the root cube; then the
 *    triangles per level-k cell and per box of cells, from which the owners, the cells each
 *    piece needs whole and the pieces' sizes follow for any number of pieces;
 * 3. each triangle's indices appended to the file of every piece that needs it;
 * 4. each piece merged (plod::partition::MergePoints over the points it uses; two pieces at a
 *    time over PiecesParameters::Parallel) and kept in its own file, its owned cells and open
 *    edges counted, so that all pieces agree on the finest level and on whether the whole is
 *    closed before any is built.
 * Where two points of the file have the same position to the last bit, the merge keeps the
 * normal of the one first in the file, a process the one it received first: only then can a
 * piece's normal differ from a rank's.
 * The point file's mapped pages are let go after each pass, so the resident memory stays that
 * of one piece however large the file; the point and triangle files are removed once the pieces
 * are made, and a piece's file by RemovePiece. Temporary files live in a directory of their own,
 * removed with the object (and when Open fails).
 *
 * @sa plodPartition.h plodPLYRead.h
 */
#ifndef plodPieces_h
#define plodPieces_h

#include "plodParallel.h"
#include "plodPartition.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plod
{

/// The split's steps, in order, by the names PiecesParameters::Progress receives (a step may
/// come again when more pieces are needed).
namespace split_step
{
constexpr const char* Reading = "reading the file";
constexpr const char* Bounds = "bounds";
constexpr const char* Cells = "cells";
constexpr const char* Distributing = "pieces";
constexpr const char* Merging = "merging the pieces";
} // namespace split_step
constexpr const char* SplitSteps[] = { split_step::Reading, split_step::Bounds, split_step::Cells,
  split_step::Distributing, split_step::Merging };

struct PiecesParameters
{
  /// k, the level whose cells are shared out, 1 to 6. The halo is one level-k cell wide around
  /// each piece, so a deeper level sends fewer triangles to more than one piece.
  int OwnershipLevel = 6;
  /// Negative: the builder's automatic level of the whole mesh.
  int RequestedFinestLevel = -1;
  /// Pieces wanted; 0: as few as let each piece's partition and build fit MemoryLimit.
  int NumberOfPieces = 0;
  /// Bytes one piece may take (its merge, then its build); used when NumberOfPieces is 0.
  double MemoryLimit = 4.0e9;
  /// Where the temporary directory goes; empty: $TMPDIR, else /tmp.
  std::string TemporaryDirectory;
  /// Called with the fraction done of the current step, in [0, 1], and the step's name (one of
  /// SplitSteps); return false to abort.
  std::function<bool(double, const char*)> Progress;
  /// How pieces are merged two at a time (each on a range of its own); SerialFor: one after
  /// the other.
  ParallelFor Parallel = SerialFor;
};

/// Bytes per triangle a piece's merge (MergePoints, two pieces at once) and build take, the
/// larger of the two; pieces are sized with it.
double PieceBytesPerTriangle(bool normals);

/// A PLY file split into pieces (see the file's documentation).
class PLYPieces
{
public:
  PLYPieces();
  ~PLYPieces(); ///< removes the temporary files
  PLYPieces(const PLYPieces&) = delete;
  PLYPieces& operator=(const PLYPieces&) = delete;

  /**
   * Reads `path` and splits it. False with the reason in `why` (may be null) on a file that
   * cannot be read or does not match its header, a temporary file that cannot be written (a
   * full disk, an unwritable folder), bad parameters or an abort; its temporary files are then
   * removed. A model whose finest level is coarser than the ownership level is split again with
   * its finest level as the ownership level (GetOwnershipLevel gives the one used). Never throws.
   */
  bool Open(const std::string& path, const PiecesParameters& parameters, std::string* why);

  int GetNumberOfPieces() const;
  /// k, the level whose cells the pieces own.
  int GetOwnershipLevel() const;

  /// What every piece shares: root cube, finest level, open-edge count of the whole, normals,
  /// NoTriangles, and in NumberOfSkippedTriangles the file's unusable triangles.
  const PartitionResult& GetAgreement() const;

  /// Piece p (0 <= p < GetNumberOfPieces()), as PartitionMesh gives rank p. False with the
  /// reason when its temporary file cannot be read back.
  bool GetPiece(int p, PartitionResult* piece, std::string* why) const;

  /// Triangles of the file that every piece's build shares out (the file's, less the unusable).
  int64_t GetNumberOfUsableTriangles() const;

  /// The most bytes the temporary files held at once, and what they hold now.
  int64_t GetPeakTemporaryBytes() const;
  int64_t GetTemporaryBytes() const;

  /// Removes piece p's temporary file (a build that has read it needs it no more); GetPiece(p)
  /// then fails, saying so. Nothing for a piece out of range or removed already.
  void RemovePiece(int p);
  /// The temporary directory (empty before Open and after a failed one).
  const std::string& GetTemporaryDirectory() const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace plod

#endif
