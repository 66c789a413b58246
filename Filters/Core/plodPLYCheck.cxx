// SPDX-License-Identifier: BSD-3-Clause
// Validation of PLY files (Turk 1994) before a reader trusts them. See plodPLYCheck.h.
#include "plodPLYCheck.h"
#include "plodPLYIO.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <new>
#include <sys/stat.h>
#include <system_error>

namespace plod
{
namespace
{
using namespace plyio;

bool ParseType(const std::string& word, PLYType* type)
{
  for (int t = 0; t < 8; ++t)
  {
    if (word == Types[t].Name || word == Types[t].Alias)
    {
      *type = static_cast<PLYType>(t);
      return true;
    }
  }
  return false;
}

/// A word from the file made safe to print: printable ASCII, at most 40 characters, quoted.
std::string Quote(const std::string& word)
{
  std::string s = "'";
  for (size_t i = 0; i < word.size() && i < 40; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(word[i]);
    s += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  }
  if (word.size() > 40)
  {
    s += "...";
  }
  return s + "'";
}

/// Splits a header line into words separated by blanks.
std::vector<std::string> Words(const std::string& line)
{
  std::vector<std::string> words;
  size_t i = 0;
  while (i < line.size())
  {
    while (i < line.size() && IsBlank(line[i]))
    {
      ++i;
    }
    size_t j = i;
    while (j < line.size() && !IsBlank(line[j]))
    {
      ++j;
    }
    if (j > i)
    {
      words.emplace_back(line, i, j - i);
    }
    i = j;
  }
  return words;
}

/// What a list property is checked for.
enum class ListRole
{
  None,
  Indices,        ///< items in [0, vertex count)
  IndicesOrStrip, ///< the same, or -1 (tristrips)
};

class Checker
{
public:
  Checker(std::string* why, PLYSummary* summary, const PLYReaderLimits& limits)
    : Why(why)
    , Summary(summary)
    , Limits(limits)
  {
  }

  /// Checks the file; with `headerOnly`, only its header (and its size against the header's
  /// rows of fixed size), not the body.
  bool Run(const std::string& path, bool headerOnly = false)
  {
    if (!this->In.Open(path, "a PLY file", this->Why))
    {
      return false;
    }
    this->Summary->FileBytes = this->In.Size();
    if (this->In.Size() == 0)
    {
      return this->Fail("the file is empty");
    }
    if (!this->ReadHeader() || !this->CheckGeometry() || !this->CheckElementOrder())
    {
      return false;
    }
    this->Summary->HeaderBytes = this->In.Offset();
    if (headerOnly)
    {
      return this->CheckBodyAtLeastFixedRows();
    }
    const bool ok =
      this->Summary->Format == PLYFormat::ASCII ? this->CheckASCIIBody() : this->CheckBinaryBody();
    if (ok && this->Summary->NumberOfShortFaces > 0)
    {
      this->Summary->Warning = std::to_string(this->Summary->NumberOfShortFaces) + " of " +
        std::to_string(this->Summary->NumberOfFaces) +
        " faces have fewer than 3 vertex indices (the first: " + this->FirstShortFaceText +
        "); they are not polygons and must be dropped (vtkPolyDataNormals crashes on them)";
    }
    if (ok)
    {
      this->WarnOfIgnoredElements();
    }
    return ok;
  }

private:
  /// Elements that describe a surface VTK's reader drops (it reads `vertex` and `face` only):
  /// triangle strips. Without faces, the points would be taken for a point cloud. (A range
  /// scan's `range_grid` is left out: such scans are read as the point clouds they are.)
  void WarnOfIgnoredElements()
  {
    for (const PLYElement& e : this->Summary->Elements)
    {
      if (e.Count == 0 || e.Name != "tristrips")
      {
        continue;
      }
      std::string& w = this->Summary->Warning;
      w += (w.empty() ? "" : "; ") + std::string("element '") + e.Name + "' (" +
        std::to_string(e.Count) + " rows) describes a surface that is not read (only 'vertex' " +
        "and 'face' are)";
      if (this->Summary->NumberOfFaces == 0)
      {
        w += ": without faces the points are taken for a point cloud; convert it to faces";
      }
    }
  }

  bool Fail(const std::string& message)
  {
    *this->Why = message;
    return false;
  }

  static std::string Row(const PLYElement& e, int64_t row)
  {
    return "element " + Quote(e.Name) + " row " + std::to_string(row);
  }

  std::string ReaderName() const
  {
    return this->Limits.ReaderName ? this->Limits.ReaderName : "the reader";
  }

  // ---- header ------------------------------------------------------------------------------

  static std::string HeaderLine(int64_t line)
  {
    return "header line " + std::to_string(line) + ": ";
  }

  /// Reads one header line without its newline. False at the end of the file (`atEnd`, with
  /// `line` holding what was read) or past MaxPLYHeaderBytes.
  bool ReadLine(std::string* line, bool* atEnd)
  {
    line->clear();
    *atEnd = false;
    for (;;)
    {
      if (this->In.Offset() >= MaxPLYHeaderBytes)
      {
        return false;
      }
      const int c = this->In.Get();
      if (c < 0)
      {
        *atEnd = true;
        return false;
      }
      if (c == '\n')
      {
        return true;
      }
      line->push_back(static_cast<char>(c));
    }
  }

  bool ReadHeader()
  {
    // the magic word, decided from the first bytes so that a binary file is not scanned
    unsigned char magic[3] = { 0, 0, 0 };
    for (unsigned char& m : magic)
    {
      const int c = this->In.Get();
      if (c < 0)
      {
        break;
      }
      m = static_cast<unsigned char>(c);
    }
    if (std::memcmp(magic, "ply", 3) != 0)
    {
      return this->Fail("not a PLY file: it does not start with 'ply'");
    }
    std::string line;
    bool atEnd = false;
    const bool complete = this->ReadLine(&line, &atEnd);
    if (!Words(line).empty())
    {
      return this->Fail("not a PLY file: the first line is not 'ply'");
    }
    if (!complete)
    {
      return this->Fail(atEnd
          ? "header line 1: the file ends after 'ply' (no format, no end_header)"
          : "no end_header line in the first " + std::to_string(MaxPLYHeaderBytes) + " bytes");
    }
    if (this->Limits.MaxLineBytes > 0 &&
      static_cast<int64_t>(line.size()) + 3 > this->Limits.MaxLineBytes)
    {
      return this->Fail("header line 1: the line has " + std::to_string(line.size() + 3) +
        " bytes; " + this->ReaderName() + " reads at most " +
        std::to_string(this->Limits.MaxLineBytes));
    }
    bool haveFormat = false;
    int64_t number = 1;
    for (;;)
    {
      ++number;
      if (!this->ReadLine(&line, &atEnd))
      {
        const bool endHeader = atEnd && Words(line).size() == 1 && Words(line)[0] == "end_header";
        if (!endHeader)
        {
          return this->Fail(atEnd ? "no end_header line: the header runs to the end of the file (" +
                std::to_string(number) + " lines, " + std::to_string(this->In.Size()) + " bytes)"
                                  : "no end_header line in the first " +
                std::to_string(MaxPLYHeaderBytes) + " bytes (line " + std::to_string(number) + ")");
        }
      }
      if (this->Limits.MaxLineBytes > 0 &&
        static_cast<int64_t>(line.size()) > this->Limits.MaxLineBytes)
      {
        return this->Fail(HeaderLine(number) + "the line has " + std::to_string(line.size()) +
          " bytes; " + this->ReaderName() + " reads at most " +
          std::to_string(this->Limits.MaxLineBytes));
      }
      const std::vector<std::string> w = Words(line);
      if (w.empty())
      {
        return this->Fail(HeaderLine(number) + "blank line in the header");
      }
      if (w[0] == "comment" || w[0] == "obj_info")
      {
        continue;
      }
      if (!this->CheckVertexIndexWords(w, number))
      {
        return false;
      }
      if (w[0] == "end_header")
      {
        if (w.size() != 1)
        {
          return this->Fail(HeaderLine(number) + "words after end_header");
        }
        break;
      }
      bool ok = false;
      if (w[0] == "format")
      {
        ok = this->ParseFormat(w, number, &haveFormat);
      }
      else if (w[0] == "element")
      {
        ok = haveFormat ? this->ParseElement(w, number)
                        : this->Fail(HeaderLine(number) + "element before the format line");
      }
      else if (w[0] == "property")
      {
        ok = this->ParseProperty(w, number);
      }
      else
      {
        ok = this->Fail(HeaderLine(number) + "unknown header keyword " + Quote(w[0]) +
          " (is end_header missing?)");
      }
      if (!ok)
      {
        return false;
      }
    }
    if (!haveFormat)
    {
      return this->Fail("the header has no format line");
    }
    this->HeaderLines = number;
    return true;
  }

  bool CheckVertexIndexWords(const std::vector<std::string>& w, int64_t number)
  {
    if (!this->Limits.VertexIndexAtLineEnd)
    {
      return true;
    }
    for (size_t i = 0; i < w.size(); ++i)
    {
      if (w[i].find("vertex_index") != std::string::npos &&
        ((w[i] != "vertex_index" && w[i] != "vertex_indices") || i + 1 != w.size()))
      {
        return this->Fail(HeaderLine(number) + Quote(w[i]) + " contains 'vertex_index' where " +
          this->ReaderName() +
          " would rewrite the line (it is taken only as the last word, "
          "vertex_index or vertex_indices)");
      }
    }
    return true;
  }

  bool ParseFormat(const std::vector<std::string>& w, int64_t number, bool* haveFormat)
  {
    if (*haveFormat)
    {
      return this->Fail(HeaderLine(number) + "a second format line");
    }
    if (w.size() != 3)
    {
      return this->Fail(HeaderLine(number) +
        "the format line must be 'format ascii|binary_little_endian|binary_big_endian 1.0'");
    }
    PLYFormat& f = this->Summary->Format;
    if (w[1] == "ascii")
    {
      f = PLYFormat::ASCII;
    }
    else if (w[1] == "binary_little_endian")
    {
      f = PLYFormat::BinaryLittleEndian;
    }
    else if (w[1] == "binary_big_endian")
    {
      f = PLYFormat::BinaryBigEndian;
    }
    else
    {
      return this->Fail(HeaderLine(number) + "unknown format " + Quote(w[1]) +
        " (ascii, binary_little_endian or binary_big_endian)");
    }
    double version = 0;
    if (!ParseReal(w[2].data(), w[2].data() + w[2].size(), &version) || version != 1.0)
    {
      return this->Fail(HeaderLine(number) + "unsupported PLY version " + Quote(w[2]) + " (1.0)");
    }
    *haveFormat = true;
    return true;
  }

  bool ParseElement(const std::vector<std::string>& w, int64_t number)
  {
    if (w.size() != 3)
    {
      return this->Fail(HeaderLine(number) + "the element line must be 'element <name> <count>'");
    }
    if (FindPLYElement(*this->Summary, w[1]))
    {
      return this->Fail(HeaderLine(number) + "element " + Quote(w[1]) + " declared twice");
    }
    int64_t count = -1;
    if (!ParseInteger(w[2].data(), w[2].data() + w[2].size(), &count) || count < 0 ||
      count > MaxPLYElementCount)
    {
      return this->Fail(HeaderLine(number) + "element " + Quote(w[1]) + " count " + Quote(w[2]) +
        " is not an integer in [0, " + std::to_string(MaxPLYElementCount) + "]");
    }
    PLYElement e;
    e.Name = w[1];
    e.Count = count;
    this->Summary->Elements.push_back(std::move(e));
    return true;
  }

  bool ParseProperty(const std::vector<std::string>& w, int64_t number)
  {
    if (this->Summary->Elements.empty())
    {
      return this->Fail(HeaderLine(number) + "property before any element");
    }
    PLYElement& e = this->Summary->Elements.back();
    PLYProperty p;
    if (w.size() >= 2 && w[1] == "list")
    {
      if (w.size() != 5)
      {
        return this->Fail(
          HeaderLine(number) + "the line must be 'property list <count type> <item type> <name>'");
      }
      p.IsList = true;
      if (!ParseType(w[2], &p.CountType))
      {
        return this->Fail(HeaderLine(number) + "unknown property type " + Quote(w[2]));
      }
      if (!Info(p.CountType).Integer)
      {
        return this->Fail(
          HeaderLine(number) + "list count type " + Quote(w[2]) + " is not an integer type");
      }
      if (!ParseType(w[3], &p.Type))
      {
        return this->Fail(HeaderLine(number) + "unknown property type " + Quote(w[3]));
      }
      p.Name = w[4];
    }
    else
    {
      if (w.size() != 3)
      {
        return this->Fail(HeaderLine(number) +
          "the line must be 'property <type> <name>' or 'property list <count type> <item "
          "type> <name>'");
      }
      if (!ParseType(w[1], &p.Type))
      {
        return this->Fail(HeaderLine(number) + "unknown property type " + Quote(w[1]));
      }
      p.Name = w[2];
    }
    for (const PLYProperty& q : e.Properties)
    {
      if (q.Name == p.Name)
      {
        return this->Fail(HeaderLine(number) + "property " + Quote(p.Name) +
          " declared twice in element " + Quote(e.Name));
      }
    }
    e.Properties.push_back(std::move(p));
    return true;
  }

  // ---- geometry, property shapes, element order -------------------------------------------

  static const PLYProperty* FindProperty(const PLYElement& e, const char* name)
  {
    for (const PLYProperty& p : e.Properties)
    {
      if (p.Name == name)
      {
        return &p;
      }
    }
    return nullptr;
  }

  bool CheckShape(const PLYElement& e, std::initializer_list<const char*> names, bool list)
  {
    for (const char* name : names)
    {
      const PLYProperty* p = FindProperty(e, name);
      if (p && p->IsList != list)
      {
        return this->Fail("element " + Quote(e.Name) + " property " + Quote(p->Name) +
          (list ? " must be a list" : " must be a scalar, not a list"));
      }
    }
    return true;
  }

  bool CheckGeometry()
  {
    PLYSummary& s = *this->Summary;
    const PLYElement* vertex = FindPLYElement(s, "vertex");
    if (!vertex)
    {
      return this->Fail("the header declares no 'vertex' element");
    }
    for (const char* axis : { "x", "y", "z" })
    {
      if (!FindProperty(*vertex, axis))
      {
        return this->Fail(std::string("element 'vertex' has no property '") + axis + "'");
      }
    }
    if (!this->CheckShape(*vertex,
          { "x", "y", "z", "u", "v", "texture_u", "texture_v", "nx", "ny", "nz", "red", "green",
            "blue", "diffuse_red", "diffuse_green", "diffuse_blue", "alpha" },
          false))
    {
      return false;
    }
    s.NumberOfVertices = vertex->Count;
    if (const PLYElement* face = FindPLYElement(s, "face"))
    {
      if (!this->CheckShape(*face, { "vertex_indices", "vertex_index", "texcoord" }, true) ||
        !this->CheckShape(*face, { "intensity", "red", "green", "blue", "alpha" }, false))
      {
        return false;
      }
      if (face->Count > 0 && !FindProperty(*face, "vertex_indices") &&
        !FindProperty(*face, "vertex_index"))
      {
        return this->Fail("element 'face' has no list 'vertex_indices' (or 'vertex_index')");
      }
      s.NumberOfFaces = face->Count;
    }
    for (const PLYElement& e : s.Elements)
    {
      if (e.Count > 0 && e.Properties.empty())
      {
        return this->Fail("element " + Quote(e.Name) + " has " + std::to_string(e.Count) +
          " rows but no properties");
      }
    }
    return true;
  }

  bool CheckElementOrder()
  {
    if (!this->Limits.VertexThenFace)
    {
      return true;
    }
    const std::vector<PLYElement>& elements = this->Summary->Elements;
    if (elements[0].Name != "vertex")
    {
      return this->Fail("element " + Quote(elements[0].Name) + " comes before 'vertex'; " +
        this->ReaderName() + " needs 'vertex' first");
    }
    const PLYElement* face = FindPLYElement(*this->Summary, "face");
    if (face && elements[1].Name != "face")
    {
      return this->Fail("element " + Quote(elements[1].Name) + " comes between 'vertex' and " +
        "'face'; " + this->ReaderName() + " needs 'face' right after 'vertex'");
    }
    return true;
  }

  ListRole Role(const PLYElement& e, const PLYProperty& p) const
  {
    if (!p.IsList || e.Name == "vertex" || (p.Name != "vertex_indices" && p.Name != "vertex_index"))
    {
      return ListRole::None;
    }
    return e.Name == "tristrips" ? ListRole::IndicesOrStrip : ListRole::Indices;
  }

  /// Checks one vertex index; `where` ends the message.
  bool CheckIndex(double value, ListRole role, const PLYElement& e, const PLYProperty& p,
    int64_t row, const std::string& where)
  {
    const double n = static_cast<double>(this->Summary->NumberOfVertices);
    if ((value >= 0 && value < n && value == std::floor(value)) ||
      (role == ListRole::IndicesOrStrip && value == -1))
    {
      return true;
    }
    char text[64];
    std::snprintf(text, sizeof(text), "%.17g", value);
    return this->Fail(Row(e, row) + " list " + Quote(p.Name) + ": vertex index " + text +
      " is not in [0, " + std::to_string(this->Summary->NumberOfVertices) + ")" + where);
  }

  /// Records a list's length; false when it breaks the reader's face size limit.
  bool CheckListLength(const PLYElement& e, const PLYProperty& p, ListRole role, int64_t row,
    int64_t count, const std::string& where)
  {
    if (role == ListRole::None || e.Name != "face")
    {
      return true;
    }
    this->Summary->MaxFaceSize = std::max(this->Summary->MaxFaceSize, count);
    if (count < 3 && row != this->LastShortFace)
    {
      // valid PLY, not a polygon: counted for the warning, the first one described
      this->LastShortFace = row;
      if (this->Summary->NumberOfShortFaces++ == 0)
      {
        this->Summary->FirstShortFace = row;
        this->FirstShortFaceText = Row(e, row) + " with " + std::to_string(count) +
          (count == 1 ? " index" : " indices") + where;
      }
    }
    if (this->Limits.MaxFaceSize > 0 && count > this->Limits.MaxFaceSize)
    {
      return this->Fail(Row(e, row) + " list " + Quote(p.Name) + ": a face of " +
        std::to_string(count) + " vertices; " + this->ReaderName() + " reads at most " +
        std::to_string(this->Limits.MaxFaceSize) + where);
    }
    return true;
  }

  // ---- binary body -------------------------------------------------------------------------

  static std::string At(int64_t offset) { return " (byte offset " + std::to_string(offset) + ")"; }

  bool Truncated(const PLYElement& e, int64_t row, const std::string& what, int64_t offset)
  {
    return this->Fail("the file ends inside element " + Quote(e.Name) + " row " +
      std::to_string(row) + " of " + std::to_string(e.Count) + " at byte offset " +
      std::to_string(offset) + ": " + what + " (the file has " + std::to_string(this->In.Size()) +
      " bytes)");
  }

  /// Header only: the body must hold at least the header's rows at their smallest (each list
  /// empty; in ASCII each value one character and a separator), so a header that claims more
  /// rows than the file can hold fails at once.
  bool CheckBodyAtLeastFixedRows()
  {
    // binary: each value its type's size, a list its count; ASCII: each value (a list, its
    // count) at least one character and a separator or newline
    const bool ascii = this->Summary->Format == PLYFormat::ASCII;
    int64_t least = 0;
    for (const PLYElement& e : this->Summary->Elements)
    {
      int64_t row = 0;
      for (const PLYProperty& p : e.Properties)
      {
        row += ascii ? 2 : Info(p.IsList ? p.CountType : p.Type).Size;
      }
      least += e.Count * row;
    }
    if (ascii && least > 0)
    {
      --least; // the last row may end the file without a newline
    }
    if (least > this->In.Left())
    {
      return this->Fail("the header describes rows of at least " + std::to_string(least) +
        " bytes, but the file has " + std::to_string(this->In.Left()) +
        " bytes after its header: it is truncated or its counts are wrong");
    }
    return true;
  }

  bool CheckBinaryBody()
  {
    const bool little = this->Summary->Format == PLYFormat::BinaryLittleEndian;
    const bool swap = little != HostIsLittleEndian();
    for (const PLYElement& e : this->Summary->Elements)
    {
      bool fixed = true;
      int64_t rowSize = 0;
      for (const PLYProperty& p : e.Properties)
      {
        fixed = fixed && !p.IsList;
        rowSize += Info(p.Type).Size;
      }
      const bool ok = fixed ? this->SkipFixedRows(e, rowSize) : this->WalkRows(e, swap);
      if (!ok)
      {
        return false;
      }
    }
    this->Summary->TrailingBytes = this->In.Left();
    return true;
  }

  /// Rows without lists: counted by arithmetic. Counts below 2^31 and rows of a 1 MiB header
  /// keep the product far below 2^63.
  bool SkipFixedRows(const PLYElement& e, int64_t rowSize)
  {
    const int64_t need = e.Count * rowSize;
    if (this->In.Left() < need)
    {
      const int64_t row = this->In.Left() / rowSize;
      return this->Truncated(e, row,
        "the row needs " + std::to_string(rowSize) + " bytes, " +
          std::to_string(this->In.Left() - row * rowSize) + " are left",
        this->In.Offset() + row * rowSize);
    }
    return this->In.Skip(need) || this->Fail("cannot read the file" + At(this->In.Offset()));
  }

  /// Rows with lists: each count is read and checked before its items.
  bool WalkRows(const PLYElement& e, bool swap)
  {
    unsigned char bytes[8];
    for (int64_t row = 0; row < e.Count; ++row)
    {
      for (const PLYProperty& p : e.Properties)
      {
        const int64_t offset = this->In.Offset();
        if (!p.IsList)
        {
          const int size = Info(p.Type).Size;
          if (this->In.Left() < size || !this->In.Skip(size))
          {
            return this->Truncated(e, row,
              "property " + Quote(p.Name) + " needs " + std::to_string(size) + " bytes", offset);
          }
          continue;
        }
        const int countSize = Info(p.CountType).Size;
        if (this->In.Left() < countSize || !this->In.ReadExactly(bytes, countSize))
        {
          return this->Truncated(e, row, "no room for the count of list " + Quote(p.Name), offset);
        }
        const double value = Decode(bytes, p.CountType, swap);
        if (value < 0)
        {
          return this->Fail(Row(e, row) + " list " + Quote(p.Name) + ": negative count " +
            std::to_string(static_cast<int64_t>(value)) + At(offset));
        }
        const int64_t count = static_cast<int64_t>(value);
        const int itemSize = Info(p.Type).Size;
        if (count * itemSize > this->In.Left())
        {
          return this->Fail(Row(e, row) + " list " + Quote(p.Name) + ": count " +
            std::to_string(count) + " needs " + std::to_string(count * itemSize) +
            " bytes but only " + std::to_string(this->In.Left()) + " are left in the file" +
            At(offset));
        }
        const ListRole role = this->Role(e, p);
        if (!this->CheckListLength(e, p, role, row, count, At(offset)))
        {
          return false;
        }
        if (role == ListRole::None)
        {
          if (!this->In.Skip(count * itemSize))
          {
            return this->Fail("cannot read the file" + At(this->In.Offset()));
          }
          continue;
        }
        for (int64_t k = 0; k < count; ++k)
        {
          const int64_t itemOffset = this->In.Offset();
          if (!this->In.ReadExactly(bytes, itemSize))
          {
            return this->Truncated(e, row,
              "list " + Quote(p.Name) + " item " + std::to_string(k) + " is missing", itemOffset);
          }
          if (!this->CheckIndex(Decode(bytes, p.Type, swap), role, e, p, row, At(itemOffset)))
          {
            return false;
          }
        }
      }
    }
    return true;
  }

  // ---- ASCII body --------------------------------------------------------------------------

  enum class Token
  {
    Word,
    EndOfLine, ///< the newline is consumed: Line is the next line's number
    EndOfFile,
    TooLong, ///< a word of more than 64 bytes
    LongLine ///< a line longer than the reader's limit
  };

  bool LineTooLong()
  {
    const int64_t end = this->In.Offset();
    const int64_t length = end - this->LineStart;
    this->LineStart = end + 1;
    return this->Limits.MaxLineBytes > 0 && length > this->Limits.MaxLineBytes;
  }

  /// The next word of the current line, in Word.
  Token Next()
  {
    this->Word.clear();
    int c = this->In.Peek();
    while (c >= 0 && IsBlank(c))
    {
      this->In.Get();
      c = this->In.Peek();
    }
    if (c < 0)
    {
      return this->LineTooLong() ? Token::LongLine : Token::EndOfFile;
    }
    if (c == '\n')
    {
      if (this->LineTooLong())
      {
        return Token::LongLine;
      }
      this->In.Get();
      ++this->Line;
      return Token::EndOfLine;
    }
    while (c >= 0 && c != '\n' && !IsBlank(c))
    {
      if (this->Word.size() >= 64)
      {
        return Token::TooLong;
      }
      this->Word.push_back(static_cast<char>(c));
      this->In.Get();
      c = this->In.Peek();
    }
    return Token::Word;
  }

  std::string OnLine() const { return " (line " + std::to_string(this->Line) + ")"; }

  bool LongLineError()
  {
    return this->Fail("line " + std::to_string(this->Line) + " is longer than " +
      std::to_string(this->Limits.MaxLineBytes) + " bytes, the most " + this->ReaderName() +
      " reads");
  }

  /// Reads the value of a property, list count or list item of type `t`; `rowStart` when it is
  /// the row's first value.
  bool Value(const PLYElement& e, int64_t row, const PLYProperty& p, PLYType t, const char* what,
    bool rowStart, double* value)
  {
    switch (this->Next())
    {
      case Token::Word:
        break;
      case Token::EndOfFile:
        return this->Fail("the file ends inside element " + Quote(e.Name) + " row " +
          std::to_string(row) + " of " + std::to_string(e.Count) + ": no " + what +
          " for property " + Quote(p.Name) + OnLine());
      case Token::EndOfLine:
        --this->Line; // the line that ended
        return this->Fail(rowStart ? "blank line where " + Row(e, row) + " should be" + OnLine()
                                   : Row(e, row) + " ends early: no " + what + " for property " +
              Quote(p.Name) + OnLine() + " (each row is one line)");
      case Token::LongLine:
        return this->LongLineError();
      case Token::TooLong:
        return this->Fail(Row(e, row) + " property " + Quote(p.Name) + ": " + Quote(this->Word) +
          " is not a number" + OnLine());
    }
    const char* b = this->Word.data();
    const char* end = b + this->Word.size();
    const TypeInfo& info = Info(t);
    if (info.Integer)
    {
      int64_t v = 0;
      if (!ParseInteger(b, end, &v) || v < info.Min || v > info.Max)
      {
        return this->Fail(Row(e, row) + " property " + Quote(p.Name) + ": " + Quote(this->Word) +
          " is not an integer of type " + info.Name + OnLine());
      }
      *value = static_cast<double>(v);
      return true;
    }
    return ParseReal(b, end, value) ||
      this->Fail(Row(e, row) + " property " + Quote(p.Name) + ": " + Quote(this->Word) +
        " is not a number" + OnLine());
  }

  bool CheckASCIIRow(const PLYElement& e, int64_t row)
  {
    bool rowStart = true;
    for (const PLYProperty& p : e.Properties)
    {
      double value = 0;
      if (!p.IsList)
      {
        if (!this->Value(e, row, p, p.Type, "value", rowStart, &value))
        {
          return false;
        }
        rowStart = false;
        continue;
      }
      if (!this->Value(e, row, p, p.CountType, "list count", rowStart, &value))
      {
        return false;
      }
      rowStart = false;
      if (value < 0)
      {
        return this->Fail(Row(e, row) + " list " + Quote(p.Name) + ": negative count " +
          std::to_string(static_cast<int64_t>(value)) + OnLine());
      }
      const int64_t count = static_cast<int64_t>(value);
      // an item takes at least two bytes (a separator and a digit), so a count that cannot fit
      // in the rest of the file fails here rather than after walking it
      if (count * 2 > this->In.Left())
      {
        return this->Fail(Row(e, row) + " list " + Quote(p.Name) + ": count " +
          std::to_string(count) + " needs at least " + std::to_string(count * 2) +
          " more bytes but only " + std::to_string(this->In.Left()) + " are left in the file" +
          OnLine());
      }
      const ListRole role = this->Role(e, p);
      if (!this->CheckListLength(e, p, role, row, count, OnLine()))
      {
        return false;
      }
      for (int64_t k = 0; k < count; ++k)
      {
        if (!this->Value(e, row, p, p.Type, "list item", false, &value) ||
          (role != ListRole::None && !this->CheckIndex(value, role, e, p, row, OnLine())))
        {
          return false;
        }
      }
    }
    switch (this->Next())
    {
      case Token::Word:
      case Token::TooLong:
        return this->Fail(Row(e, row) + " has more values than its properties, starting with " +
          Quote(this->Word) + OnLine() + " (each row is one line)");
      case Token::LongLine:
        return this->LongLineError();
      case Token::EndOfFile:
        this->EndsWithoutNewline = true;
        return true;
      default:
        return true;
    }
  }

  bool CheckASCIIBody()
  {
    this->Line = this->HeaderLines + 1;
    this->LineStart = this->In.Offset();
    for (const PLYElement& e : this->Summary->Elements)
    {
      for (int64_t row = 0; row < e.Count; ++row)
      {
        if (!this->CheckASCIIRow(e, row))
        {
          return false;
        }
      }
    }
    if (this->EndsWithoutNewline && this->Limits.FinalNewline)
    {
      return this->Fail("the last line (line " + std::to_string(this->Line) +
        ") does not end with a newline; " + this->ReaderName() + " loses such a line");
    }
    // after the last row: whitespace does not count
    int64_t trailing = 0;
    for (int c = this->In.Get(); c >= 0; c = this->In.Get())
    {
      trailing += (c != '\n' && !IsBlank(c)) ? 1 : 0;
    }
    this->Summary->TrailingBytes = trailing;
    return true;
  }

  std::string* Why;
  PLYSummary* Summary;
  PLYReaderLimits Limits;
  Input In;
  int64_t HeaderLines = 0;
  int64_t Line = 0;      ///< ASCII body: number of the current line
  int64_t LineStart = 0; ///< ASCII body: offset of the current line's first byte
  std::string Word;
  bool EndsWithoutNewline = false; ///< ASCII body: the last row reaches the end of the file
  int64_t LastShortFace = -1;      ///< the last `face` row counted as short (one per row)
  std::string FirstShortFaceText;  ///< the first short face: row, list, size and place
};

} // namespace

//------------------------------------------------------------------------------
namespace
{
bool RunChecker(const std::string& path, std::string* why, PLYSummary* summary,
  const PLYReaderLimits& limits, bool headerOnly)
{
  return fileio::RunCheckSafely(why, summary, [&](std::string* message, PLYSummary* s) {
    Checker checker(message, s, limits);
    return checker.Run(path, headerOnly);
  });
}

} // namespace

//------------------------------------------------------------------------------
bool CheckPLYFile(
  const std::string& path, std::string* why, PLYSummary* summary, const PLYReaderLimits& limits)
{
  return RunChecker(path, why, summary, limits, false);
}

//------------------------------------------------------------------------------
bool ReadPLYHeader(const std::string& path, std::string* why, PLYSummary* summary)
{
  return RunChecker(path, why, summary, PLYReaderLimits(), true);
}

//------------------------------------------------------------------------------
PLYReaderLimits VTKPLYReaderLimits()
{
  PLYReaderLimits limits;
  limits.ReaderName = "vtkPLYReader (VTK 9.1)";
  limits.MaxLineBytes = 4000;
  limits.MaxFaceSize = 255;
  limits.VertexThenFace = true;
  limits.VertexIndexAtLineEnd = true;
  limits.FinalNewline = true;
  return limits;
}

//------------------------------------------------------------------------------
const char* PLYFormatName(PLYFormat format)
{
  switch (format)
  {
    case PLYFormat::ASCII:
      return "ascii";
    case PLYFormat::BinaryLittleEndian:
      return "binary_little_endian";
    case PLYFormat::BinaryBigEndian:
      return "binary_big_endian";
  }
  return "unknown";
}

//------------------------------------------------------------------------------
const char* PLYTypeName(PLYType type)
{
  return Info(type).Name;
}

//------------------------------------------------------------------------------
int PLYTypeSize(PLYType type)
{
  return Info(type).Size;
}

//------------------------------------------------------------------------------
const PLYElement* FindPLYElement(const PLYSummary& summary, const std::string& name)
{
  for (const PLYElement& e : summary.Elements)
  {
    if (e.Name == name)
    {
      return &e;
    }
  }
  return nullptr;
}

} // namespace plod
