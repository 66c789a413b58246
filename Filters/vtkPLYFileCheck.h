// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPLYFileCheck
 * @brief   checks that a PLY file is sound before vtkPLYReader reads it
 *
 * VTK 9.1's vtkPLYReader (Greg Turk's PLY code) trusts the file: a body cut short, an element
 * count that lies, a face index out of range or a list count the file cannot hold make it read
 * past buffers, crash or abort. vtkPLYFileCheck reads the file first, trusting nothing, and says
 * whether the reader can take it and, if not, why and where (element, row, byte offset or
 * line), in one line:
 *
 * @code{.py}
 * check = vtkPLYFileCheck()
 * check.SetFileName("model.ply")
 * if not check.Check():
 *     raise ValueError(check.GetErrorMessage())
 * @endcode
 *
 * The check streams the file through a small buffer in time linear in its size; it checks the
 * header (formats, types and their aliases, lists, any elements), the body against it (binary
 * rows counted or walked list by list, ASCII rows token by token), every vertex index of faces
 * and the presence of vertex x, y and z. See plodPLYCheck.h (the VTK-free check it runs) for the
 * full list. With ReaderLimits on (the default) it also rejects valid PLY files that VTK 9.1's
 * reader cannot take: `face` before `vertex` or another element between them, faces of more
 * than 255 vertices, lines longer than 4000 bytes, and "vertex_index" inside a header word.
 *
 * Faces of fewer than 3 vertex indices are valid PLY and pass, with a warning
 * (GetWarningMessage(), also sent as a VTK warning): vtkPLYReader reads them as polygons of 0, 1
 * or 2 points, on which vtkPolyDataNormals crashes, so a program drops them before such filters.
 *
 * @warning The check does not look at the values: NaN or infinite coordinates pass (the
 * octree builder skips the triangles that use them, with a warning).
 *
 * @sa vtkPLYReader
 */
#ifndef vtkPLYFileCheck_h
#define vtkPLYFileCheck_h

#include "PerceptualLODFiltersModule.h" // for export macro
#include "vtkObject.h"

class PERCEPTUALLODFILTERS_EXPORT vtkPLYFileCheck : public vtkObject
{
public:
  static vtkPLYFileCheck* New();
  vtkTypeMacro(vtkPLYFileCheck, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Formats
  {
    FORMAT_ASCII = 0,
    FORMAT_BINARY_LITTLE_ENDIAN = 1,
    FORMAT_BINARY_BIG_ENDIAN = 2
  };

  ///@{
  /// The file to check. Default none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Also reject valid PLY files that VTK 9.1's vtkPLYReader cannot take (see the class
  /// documentation). Default on.
  vtkSetMacro(ReaderLimits, bool);
  vtkGetMacro(ReaderLimits, bool);
  vtkBooleanMacro(ReaderLimits, bool);
  ///@}

  /**
   * Checks FileName. Returns true when the file is sound (and, with ReaderLimits, when
   * vtkPLYReader can read it); otherwise false, with the reason in GetErrorMessage(). A sound
   * file with faces of fewer than 3 vertex indices passes with a warning (GetWarningMessage(),
   * also sent with vtkWarningMacro). Reads the file every time it is called.
   */
  bool Check();

  /// Why the last Check() failed, in one line; "" after a success or before any check.
  const char* GetErrorMessage() const { return this->ErrorMessage ? this->ErrorMessage : ""; }

  /**
   * What a consumer of the last checked file must know although the check passed, in one line:
   * how many faces have fewer than 3 vertex indices and where the first one is (they must be
   * dropped before vtkPolyDataNormals and the like). "" when there is nothing to say, after a
   * failure, or before any check.
   */
  const char* GetWarningMessage() const { return this->WarningMessage ? this->WarningMessage : ""; }

  ///@{
  /// What the last Check() read: the counts of elements `vertex` and `face` (0 when there is
  /// none), the most vertices in one face, the faces of fewer than 3 vertices (see
  /// GetWarningMessage()), and the format (FORMAT_ASCII, ...). Meaningful after a successful
  /// check.
  vtkGetMacro(NumberOfVertices, vtkIdType);
  vtkGetMacro(NumberOfFaces, vtkIdType);
  vtkGetMacro(MaxFaceSize, vtkIdType);
  vtkGetMacro(NumberOfShortFaces, vtkIdType);
  vtkGetMacro(Format, int);
  const char* GetFormatAsString() const;
  ///@}

  /**
   * Checks `path` with the reader limits: true when vtkPLYReader can read it. For the reason of
   * a failure, use an instance.
   */
  static bool CheckFile(const char* path);

protected:
  vtkPLYFileCheck();
  ~vtkPLYFileCheck() override;

  vtkSetStringMacro(ErrorMessage);
  vtkSetStringMacro(WarningMessage);

  char* FileName;
  bool ReaderLimits;
  char* ErrorMessage;
  char* WarningMessage;
  vtkIdType NumberOfVertices;
  vtkIdType NumberOfFaces;
  vtkIdType MaxFaceSize;
  vtkIdType NumberOfShortFaces;
  int Format;

private:
  vtkPLYFileCheck(const vtkPLYFileCheck&) = delete;
  void operator=(const vtkPLYFileCheck&) = delete;
};

#endif
