// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctreeReader
 * @brief   reads an octree file (`.plod`) written by vtkMultiscaleOctreeWriter
 *
 * The reader maps the file into memory (copy-on-write: editing an array never changes the
 * file) and hands the mapped bytes to the octree's arrays without copying, so opening costs
 * about the same for any size: the pages are read when a filter first touches them. The
 * mapping is released when the last array using it is deleted.
 *
 * @code{.py}
 * reader = vtkMultiscaleOctreeReader()
 * reader.SetFileName("model.plod")
 * selector.SetInputConnection(reader.GetOutputPort())
 * @endcode
 *
 * Everything about the file is checked before any array is made: the magic, the format
 * version, the byte order, a checksum of the header and directory, the stated size against the
 * real one (a truncated copy), every array's name, type, size and place in the file. A missing,
 * truncated, corrupt or foreign file gives an error saying what is wrong and an empty octree,
 * never a crash. VerifyChecksums also compares every array's data with its checksum (this
 * reads the whole file). Without it, damage inside the data is caught when a filter first uses
 * the octree (vtkMultiscaleOctree::IsConsistent: an error and an empty output), except values
 * that stay plausible, such as a vertex moved inside its cell.
 *
 * Only regular files are opened: a FIFO, a device or a directory is refused at once (opening a
 * FIFO would wait for a writer). The octree remembers the mapped file's identity (device,
 * inode, size, modification time); every filter that reads the octree compares it with the file
 * on disk (vtkMultiscaleOctree::GetCheckedView). A file replaced by a rename, as
 * vtkMultiscaleOctreeWriter saves, leaves the mapped old file intact: the filters go on with
 * it and warn once. A file rewritten in place, whose mapped pages can no longer be trusted, makes
 * every filter refuse the octree with an error instead of crashing on a page past the new end.
 * The file is read again only when the reader is asked to (Modified(), or a new FileName).
 *
 * The pages of a mapped file that the process holds are kept within CacheLimit (2048 MiB by
 * default), less the arrays the filters keep for the octree, which count against the same
 * limit: when the views have mapped more, the selector and the patch generator drop them
 * after their execution (vtkMultiscaleOctree::EnforceResidentLimit, plodResidentPages.h), and the
 * next views map again what they read, from the kernel's page cache while memory allows. A file
 * smaller than the limit is never trimmed.
 *
 * With BackgroundLoading on, a mapped file's pages are read off the frame: a refinement whose
 * pages have not been read waits, drawn at the coarser cell, while a thread reads them, and a
 * later frame refines (vtkMultiscaleOctree::SetBackgroundLoading). Frames then never wait on
 * the disk; the view refines over a few frames after a move into unread parts of the model.
 *
 * A compact file (vtkMultiscaleOctreeWriter::SetCompact) is not mapped: its arrays are read and
 * decoded into memory when the file is opened, over every core, their checksums always verified
 * (the bytes are read anyway); GetCompact() tells. It then takes the memory of the whole octree
 * at once, and the file can change underneath without harm.
 *
 * @sa vtkMultiscaleOctreeWriter vtkMultiscaleOctree
 */
#ifndef vtkMultiscaleOctreeReader_h
#define vtkMultiscaleOctreeReader_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkMultiscaleOctreeAlgorithm.h"

#include <string> // for ErrorMessage

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctreeReader : public vtkMultiscaleOctreeAlgorithm
{
public:
  static vtkMultiscaleOctreeReader* New();
  vtkTypeMacro(vtkMultiscaleOctreeReader, vtkMultiscaleOctreeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read. Default none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Compare every array with its checksum (reads the whole file). Default off.
  vtkSetMacro(VerifyChecksums, bool);
  vtkGetMacro(VerifyChecksums, bool);
  vtkBooleanMacro(VerifyChecksums, bool);
  ///@}

  ///@{
  /// Map the file (default on); off reads it into memory instead.
  vtkSetMacro(MemoryMap, bool);
  vtkGetMacro(MemoryMap, bool);
  vtkBooleanMacro(MemoryMap, bool);
  ///@}

  ///@{
  /**
   * The most memory, in MiB, that viewing a mapped file keeps between frames (0: no limit):
   * the file's pages the process holds, and the arrays the filters keep for the octree, which
   * grow with it (the selector's cut arrays, a byte a node each; the remembered corner walks,
   * four bytes a point; the patch generator's output index, four bytes a cluster:
   * vtkMultiscaleOctree::CountHeldBytes). The pages are kept within the limit less those
   * arrays, and at least an eighth of it. Default 2048. It should exceed what one view reads
   * plus the arrays, or every frame maps its pages again (a triangle budget bounds what a view
   * reads); the octree warns once when most frames do. With BackgroundLoading, the loading thread
   * keeps it too, after each refinement it reads.
   */
  vtkSetClampMacro(CacheLimit, int, 0, VTK_INT_MAX);
  vtkGetMacro(CacheLimit, int);
  ///@}

  ///@{
  /**
   * Read a mapped file's pages in the background, off the frame (default off: each frame reads
   * what it refines, and a view always draws the same cut). See
   * vtkMultiscaleOctree::SetBackgroundLoading. Nothing changes for a file read into memory.
   */
  vtkSetMacro(BackgroundLoading, bool);
  vtkGetMacro(BackgroundLoading, bool);
  vtkBooleanMacro(BackgroundLoading, bool);
  ///@}

  /// True when the last read mapped the file (false: it was read into memory).
  vtkGetMacro(Mapped, bool);

  /// True when the last read decoded a compact file (vtkMultiscaleOctreeWriter::SetCompact).
  vtkGetMacro(Compact, bool);

  /// Why the last read failed ("" after a success).
  const char* GetErrorMessage() { return this->ErrorMessage.c_str(); }

  /// Seconds the last read took (opening and checking the file, making the arrays).
  vtkGetMacro(ReadTime, double);

  /// True when `path` is a regular file that starts like an octree file (the magic), for
  /// programs choosing a reader; a FIFO, a device or a directory gives false without waiting.
  static bool CanReadFile(const char* path);

protected:
  vtkMultiscaleOctreeReader();
  ~vtkMultiscaleOctreeReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  bool VerifyChecksums = false;
  bool MemoryMap = true;
  int CacheLimit = 2048;
  bool BackgroundLoading = false;
  bool Mapped = false;
  bool Compact = false;
  double ReadTime = 0;
  std::string ErrorMessage;

private:
  vtkMultiscaleOctreeReader(const vtkMultiscaleOctreeReader&) = delete;
  void operator=(const vtkMultiscaleOctreeReader&) = delete;
};

#endif
