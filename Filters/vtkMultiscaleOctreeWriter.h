// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMultiscaleOctreeWriter
 * @brief   writes a vtkMultiscaleOctree to an octree file (`.plod`)
 *
 * A built octree is saved once and opened in milliseconds afterwards by
 * vtkMultiscaleOctreeReader, instead of being built again at every launch:
 *
 * @code{.py}
 * writer = vtkMultiscaleOctreeWriter()
 * writer.SetInputConnection(builder.GetOutputPort())
 * writer.SetFileName("model.plod")
 * if not writer.Write():
 *     raise IOError(writer.GetErrorMessage())
 * @endcode
 *
 * The file holds every documented node, cluster and surface array, the root cube, the finest
 * level and the edge counts, in a versioned little-endian layout with checksums (see
 * plodOctreeFile.h in Filters/Core). The cut ("CutState", "CullMask") and any other array are
 * not saved: a cut belongs to a view. Nor are ghost flags (the optional PointGhost array of a
 * distributed build; the format is unchanged): writing an octree that flags ghost points warns,
 * and the octree read back draws every triangle. An octree that fails
 * vtkMultiscaleOctree::IsConsistent() is refused with an error, so a file always holds an octree
 * the filters accept.
 *
 * Saving cannot lose data: the file is written beside the target under a temporary name, synced,
 * read back and checked, and only then renamed over the target (plod::WriteOctreeFile). A failed
 * save (a full disk, say) leaves the old file byte for byte as it was; a program that has the old
 * file open keeps reading it. A target that is not a regular file (a directory, a FIFO, a device)
 * is refused before anything is written; a symbolic link stays a link and its target is replaced.
 *
 * Compact (off by default) writes version 2 of the format: every array compressed in blocks,
 * losslessly (the octree read back is the same bit for bit), in about a third of the bytes (the
 * figures are in docs/benchmarks.md). The price is at opening: a compact file is read and
 * decoded into memory (over every core), where the default layout is mapped in a millisecond and
 * read only where a view needs it. Compact suits files to keep or send; the default suits files
 * to view, above all files larger than memory. A reader older than version 2 refuses a compact
 * file with a message that names its version.
 *
 * @sa vtkMultiscaleOctreeReader vtkMultiscaleOctreeBuilder
 */
#ifndef vtkMultiscaleOctreeWriter_h
#define vtkMultiscaleOctreeWriter_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkWriter.h"

#include <string> // for ErrorMessage

class vtkMultiscaleOctree;

class PERCEPTUALLODFILTERS_EXPORT vtkMultiscaleOctreeWriter : public vtkWriter
{
public:
  static vtkMultiscaleOctreeWriter* New();
  vtkTypeMacro(vtkMultiscaleOctreeWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to write (replaced if it exists). Default none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Write the compact layout (arrays compressed; decoded into memory when read) instead of the
  /// mapped one. Default off.
  vtkSetMacro(Compact, bool);
  vtkGetMacro(Compact, bool);
  vtkBooleanMacro(Compact, bool);
  ///@}

  /// The octree written last.
  vtkMultiscaleOctree* GetInput();

  /// Why the last Write() failed ("" after a success).
  const char* GetErrorMessage() { return this->ErrorMessage.c_str(); }

protected:
  vtkMultiscaleOctreeWriter();
  ~vtkMultiscaleOctreeWriter() override;

  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  char* FileName = nullptr;
  bool Compact = false;
  std::string ErrorMessage;

private:
  vtkMultiscaleOctreeWriter(const vtkMultiscaleOctreeWriter&) = delete;
  void operator=(const vtkMultiscaleOctreeWriter&) = delete;
};

#endif
