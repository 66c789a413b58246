// SPDX-License-Identifier: BSD-3-Clause
// Streaming reader of PLY triangle meshes into compact arrays. See plodPLYRead.h.
#include "plodPLYRead.h"
#include "plodPLYIO.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <new>

namespace plod
{
namespace
{
using namespace plyio;

/// Longest ASCII token kept (a number needs far fewer characters).
constexpr size_t MaxWord = 128;

/// Rows between two progress reports.
constexpr int64_t ProgressRows = int64_t(1) << 20;

bool IsIndexList(const PLYProperty& p)
{
  return p.IsList && (p.Name == "vertex_indices" || p.Name == "vertex_index");
}

int FindProperty(const PLYElement& e, const char* name)
{
  for (size_t i = 0; i < e.Properties.size(); ++i)
  {
    if (e.Properties[i].Name == name && !e.Properties[i].IsList)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

/// Reads the rows of the body in file order and hands the vertex and face data to a sink.
class MeshReader
{
public:
  MeshReader(const PLYSummary& header, PLYMeshSink* sink, PLYStreamCounts* counts, std::string* why,
    const PLYProgress& progress)
    : Header(header)
    , Sink(sink)
    , Counts(counts)
    , Why(why)
    , Progress(progress)
    , Ascii(header.Format == PLYFormat::ASCII)
    , Swap((header.Format == PLYFormat::BinaryLittleEndian) != HostIsLittleEndian())
  {
  }

  bool Run(const std::string& path)
  {
    if (!this->In.Open(path, "a PLY file", this->Why))
    {
      return false;
    }
    if (this->In.Size() != this->Header.FileBytes)
    {
      return this->Fail("the file changed size after its header was read");
    }
    if (!this->In.Skip(this->Header.HeaderBytes))
    {
      return this->Fail("cannot read the file's body");
    }
    for (const PLYElement& e : this->Header.Elements)
    {
      const bool ok = e.Name == "vertex" ? this->ReadVertices(e)
        : e.Name == "face"               ? this->ReadFaces(e)
                                         : this->SkipRows(e);
      if (!ok)
      {
        return false;
      }
    }
    return true;
  }

private:
  bool Fail(const std::string& message)
  {
    *this->Why = message;
    return false;
  }

  std::string Where(const PLYElement& e, int64_t row) const
  {
    return "element '" + e.Name + "' row " + std::to_string(row) + " (byte offset " +
      std::to_string(this->In.Offset()) + ")";
  }

  bool Report()
  {
    if (this->Progress &&
      !this->Progress(double(this->In.Offset()) / double(std::max<int64_t>(1, this->In.Size()))))
    {
      return this->Fail("aborted");
    }
    return true;
  }

  /// The next ASCII token of the current line; false at the end of the line or of the file.
  bool Token()
  {
    int c = this->In.Peek();
    while (c >= 0 && IsBlank(c))
    {
      this->In.Get();
      c = this->In.Peek();
    }
    this->Word.clear();
    this->WordTooLong = false;
    while (c >= 0 && c != '\n' && !IsBlank(c))
    {
      const int k = this->In.Get();
      if (this->Word.size() < MaxWord)
      {
        this->Word.push_back(static_cast<char>(k));
      }
      else
      {
        this->WordTooLong = true; // no number is that long: refused, not read cut
      }
      c = this->In.Peek();
    }
    return !this->Word.empty();
  }

  /// The end of an ASCII row: only blanks, then a newline or the end of the file.
  bool EndRow(const PLYElement& e, int64_t row)
  {
    if (!this->Ascii)
    {
      return true;
    }
    if (this->Token())
    {
      return this->Fail(Where(e, row) + ": more values than its properties");
    }
    this->In.Get(); // the newline, or nothing at the end of the file
    return true;
  }

  /// One value of type `t` of property `p`; false (with the reason set) when there is none.
  bool Value(const PLYElement& e, int64_t row, const PLYProperty& p, PLYType t, double* value)
  {
    if (this->Ascii)
    {
      if (!this->Token())
      {
        return this->Fail(Where(e, row) + ": property '" + p.Name + "' has no value");
      }
      if (this->WordTooLong)
      {
        return this->Fail(Where(e, row) + ": property '" + p.Name + "' has a value longer than " +
          std::to_string(MaxWord) + " characters");
      }
      const char* b = this->Word.data();
      const char* end = b + this->Word.size();
      if (Info(t).Integer)
      {
        int64_t v = 0;
        if (!ParseInteger(b, end, &v) || v < Info(t).Min || v > Info(t).Max)
        {
          return this->Fail(Where(e, row) + ": property '" + p.Name + "' value '" + this->Word +
            "' is not a " + PLYTypeName(t));
        }
        *value = static_cast<double>(v);
        return true;
      }
      if (!ParseReal(b, end, value))
      {
        return this->Fail(
          Where(e, row) + ": property '" + p.Name + "' value '" + this->Word + "' is not a number");
      }
      return true;
    }
    unsigned char bytes[8];
    if (!this->In.ReadExactly(bytes, Info(t).Size))
    {
      return this->Fail("the file ends inside " + Where(e, row) + ", property '" + p.Name + "'");
    }
    *value = Decode(bytes, t, this->Swap);
    return true;
  }

  /// A list's count, checked not negative.
  bool Count(const PLYElement& e, int64_t row, const PLYProperty& p, int64_t* count)
  {
    double v = 0;
    if (!this->Value(e, row, p, p.CountType, &v))
    {
      return false;
    }
    if (v < 0)
    {
      return this->Fail(Where(e, row) + ": list '" + p.Name + "' has a negative count");
    }
    *count = static_cast<int64_t>(v);
    return true;
  }

  /// Skips one property of a row (a scalar, or a list with its items).
  bool SkipProperty(const PLYElement& e, int64_t row, const PLYProperty& p)
  {
    double v = 0;
    if (!p.IsList)
    {
      return this->Value(e, row, p, p.Type, &v);
    }
    int64_t n = 0;
    if (!this->Count(e, row, p, &n))
    {
      return false;
    }
    if (!this->Ascii)
    {
      const int64_t bytes = n * Info(p.Type).Size;
      if (bytes > this->In.Left() || !this->In.Skip(bytes))
      {
        return this->Fail("the file ends inside " + Where(e, row) + ", list '" + p.Name + "'");
      }
      return true;
    }
    for (int64_t i = 0; i < n; ++i)
    {
      if (!this->Value(e, row, p, p.Type, &v))
      {
        return false;
      }
    }
    return true;
  }

  bool SkipRows(const PLYElement& e)
  {
    bool fixed = !this->Ascii;
    int64_t rowSize = 0;
    for (const PLYProperty& p : e.Properties)
    {
      fixed = fixed && !p.IsList;
      rowSize += Info(p.Type).Size;
    }
    if (fixed)
    {
      if (e.Count * rowSize > this->In.Left() || !this->In.Skip(e.Count * rowSize))
      {
        return this->Fail("the file ends inside element '" + e.Name + "'");
      }
      return true;
    }
    return this->WalkRows(
      e, [](size_t) { return false; }, [](int64_t, size_t) { return true; },
      [](int64_t) { return true; });
  }

  /// The rows of `e` in order: progress every ProgressRows rows, `read(row, index)` for each
  /// property `wanted(index)` selects (the others skipped), `done(row)` after the row's
  /// properties, and the end of each ASCII row.
  template <typename Wanted, typename Read, typename Done>
  bool WalkRows(const PLYElement& e, Wanted&& wanted, Read&& read, Done&& done)
  {
    for (int64_t row = 0; row < e.Count; ++row)
    {
      if (row % ProgressRows == 0 && !this->Report())
      {
        return false;
      }
      for (size_t i = 0; i < e.Properties.size(); ++i)
      {
        const PLYProperty& p = e.Properties[i];
        if (!(wanted(i) ? read(row, i) : this->SkipProperty(e, row, p)))
        {
          return false;
        }
      }
      if (!done(row) || !this->EndRow(e, row))
      {
        return false;
      }
    }
    return true;
  }

  bool ReadVertices(const PLYElement& e)
  {
    // slot of each property: 0-2 coordinates, 3-5 normal components, -1 skipped
    const char* names[6] = { "x", "y", "z", "nx", "ny", "nz" };
    std::vector<int> slot(e.Properties.size(), -1);
    bool normals = true;
    for (int k = 0; k < 6; ++k)
    {
      const int i = FindProperty(e, names[k]);
      if (i >= 0)
      {
        slot[i] = k;
      }
      else if (k < 3)
      {
        return this->Fail(
          std::string("element 'vertex' has no scalar property '") + names[k] + "'");
      }
      else
      {
        normals = false;
      }
    }
    if (!normals)
    {
      for (int& s : slot)
      {
        s = s >= 3 ? -1 : s;
      }
    }
    if (!this->Sink->BeginVertices(
          e.Count, PLYHasDoubleCoordinates(this->Header), normals, this->Why))
    {
      return false;
    }
    double values[6] = { 0, 0, 0, 0, 0, 0 };
    return this->WalkRows(
      e, [&](size_t i) { return slot[i] >= 0; },
      [&](int64_t row, size_t i) {
        const PLYProperty& p = e.Properties[i];
        return this->Value(e, row, p, p.Type, &values[slot[i]]);
      },
      [&](int64_t row) {
        return this->Sink->Vertex(row, values, normals ? values + 3 : nullptr, this->Why);
      });
  }

  bool ReadFaces(const PLYElement& e)
  {
    this->Counts->NumberOfFaces = e.Count;
    const int64_t points = this->Header.NumberOfVertices; // `vertex` may come after `face`
    int listIndex = -1;
    for (size_t i = 0; i < e.Properties.size() && listIndex < 0; ++i)
    {
      listIndex = IsIndexList(e.Properties[i]) ? static_cast<int>(i) : -1;
    }
    if (listIndex < 0 && e.Count > 0)
    {
      return this->Fail("element 'face' has no list 'vertex_indices' or 'vertex_index'");
    }
    std::vector<int64_t> corners;
    return this->WalkRows(
      e, [&](size_t i) { return static_cast<int>(i) == listIndex; },
      [&](int64_t row, size_t i) {
        const PLYProperty& p = e.Properties[i];
        double v = 0;
        int64_t n = 0;
        if (!this->Count(e, row, p, &n))
        {
          return false;
        }
        if (!this->Ascii && n * Info(p.Type).Size > this->In.Left())
        {
          return this->Fail("the file ends inside " + Where(e, row) + ": its list of " +
            std::to_string(n) + " indices");
        }
        std::string refusal;
        if (!this->Sink->BeginFace(n, &refusal))
        {
          return this->Fail(Where(e, row) + ": " + refusal);
        }
        corners.clear();
        for (int64_t c = 0; c < n; ++c)
        {
          if (!this->Value(e, row, p, p.Type, &v))
          {
            return false;
          }
          if (!(v >= 0 && v < double(points)) || v != std::floor(v))
          {
            char text[40];
            std::snprintf(text, sizeof(text), "%.17g", v);
            return this->Fail(Where(e, row) + ": vertex index " + text +
              " is not a whole number in [0, " + std::to_string(points) + ")");
          }
          corners.push_back(static_cast<int64_t>(v));
        }
        return this->AddFan(corners);
      },
      [](int64_t) { return true; });
  }

  /// A face as a fan of triangles about its first corner.
  bool AddFan(const std::vector<int64_t>& corners)
  {
    if (corners.size() < 3)
    {
      ++this->Counts->NumberOfShortFaces;
      return true;
    }
    if (corners.size() > 3)
    {
      ++this->Counts->NumberOfSplitFaces;
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k)
    {
      if (!this->Sink->Triangle(corners[0], corners[k], corners[k + 1], this->Why))
      {
        return false;
      }
    }
    return true;
  }

  const PLYSummary& Header;
  PLYMeshSink* Sink;
  PLYStreamCounts* Counts;
  std::string* Why;
  const PLYProgress& Progress;
  const bool Ascii;
  const bool Swap;
  Input In;
  std::string Word;
  bool WordTooLong = false;
};

/// Keeps the rows in the arrays of a PLYMesh, within a memory limit (0: none).
class MeshArraysSink : public PLYMeshSink
{
public:
  MeshArraysSink(PLYMesh* mesh, int64_t faces, double maxBytes)
    : Mesh(*mesh)
    , Faces(faces)
    , MaxBytes(maxBytes)
  {
  }

  bool BeginVertices(int64_t count, bool doubles, bool normals, std::string*) override
  {
    this->Mesh.NumberOfPoints = count;
    if (doubles)
    {
      this->Mesh.PointsDouble.reserve(3 * count);
    }
    else
    {
      this->Mesh.PointsFloat.reserve(3 * count);
    }
    if (normals)
    {
      this->Mesh.Normals.reserve(3 * count);
    }
    this->Mesh.Triangles.reserve(3 * static_cast<size_t>(this->Faces));
    this->Doubles = doubles;
    return true;
  }

  bool Vertex(int64_t, const double xyz[3], const double normal[3], std::string*) override
  {
    PLYMesh& m = this->Mesh;
    for (int a = 0; a < 3; ++a)
    {
      if (this->Doubles)
      {
        m.PointsDouble.push_back(xyz[a]);
      }
      else
      {
        m.PointsFloat.push_back(static_cast<float>(xyz[a]));
      }
    }
    if (normal)
    {
      m.Normals.insert(m.Normals.end(),
        { static_cast<float>(normal[0]), static_cast<float>(normal[1]),
          static_cast<float>(normal[2]) });
    }
    return true;
  }

  /// A face of n corners adds n - 2 triangles: within the memory the caller allows.
  bool BeginFace(int64_t n, std::string* why) override
  {
    const double grows = 12.0 * double(std::max<int64_t>(0, n - 2)) + 4.0 * double(n);
    if (this->MaxBytes > 0 && this->HeldBytes() + grows > this->MaxBytes)
    {
      *why = "its face of " + std::to_string(n) +
        " corners takes the triangles beyond the memory limit of " +
        std::to_string(static_cast<long long>(this->MaxBytes)) + " bytes";
      return false;
    }
    return true;
  }

  bool Triangle(int64_t a, int64_t b, int64_t c, std::string*) override
  {
    this->Mesh.Triangles.insert(this->Mesh.Triangles.end(),
      { static_cast<int32_t>(a), static_cast<int32_t>(b), static_cast<int32_t>(c) });
    return true;
  }

private:
  /// Bytes of the points, the normals and the triangles so far.
  double HeldBytes() const
  {
    const PLYMesh& m = this->Mesh;
    return 4.0 * double(m.PointsFloat.size() + m.Normals.size() + m.Triangles.size()) +
      8.0 * double(m.PointsDouble.size());
  }

  PLYMesh& Mesh;
  const int64_t Faces;
  const double MaxBytes;
  bool Doubles = false;
};

/// The header, checked to have a vertex element, then the rows to `sink`.
bool StreamRows(const std::string& path, PLYMeshSink* sink, PLYStreamCounts* counts,
  std::string* why, const PLYProgress& progress, PLYSummary* header)
{
  if (!ReadPLYHeader(path, why, header))
  {
    return false;
  }
  if (!FindPLYElement(*header, "vertex"))
  {
    *why = "the file has no element 'vertex'";
    return false;
  }
  MeshReader reader(*header, sink, counts, why, progress);
  return reader.Run(path);
}

} // namespace

//------------------------------------------------------------------------------
bool PLYHasDoubleCoordinates(const PLYSummary& header)
{
  const PLYElement* v = FindPLYElement(header, "vertex");
  if (!v)
  {
    return false;
  }
  for (const char* name : { "x", "y", "z" })
  {
    const int i = FindProperty(*v, name);
    if (i >= 0 && v->Properties[i].Type == PLYType::Float64)
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
bool PLYHasNormals(const PLYSummary& header)
{
  const PLYElement* v = FindPLYElement(header, "vertex");
  return v && FindProperty(*v, "nx") >= 0 && FindProperty(*v, "ny") >= 0 &&
    FindProperty(*v, "nz") >= 0;
}

//------------------------------------------------------------------------------
double EstimatePLYMeshBytes(const PLYSummary& header)
{
  const double points = double(header.NumberOfVertices);
  const double coordinate = PLYHasDoubleCoordinates(header) ? 8.0 : 4.0;
  return points * 3.0 * coordinate + (PLYHasNormals(header) ? points * 12.0 : 0.0) +
    double(header.NumberOfFaces) * 12.0;
}

//------------------------------------------------------------------------------
bool StreamPLYMesh(const std::string& path, PLYMeshSink* sink, std::string* why,
  const PLYProgress& progress, PLYStreamCounts* counts)
{
  PLYStreamCounts local;
  return fileio::RunCheckSafely(
    why, counts ? counts : &local,
    [&](std::string* message, PLYStreamCounts* c) {
      PLYSummary header;
      return StreamRows(path, sink, c, message, progress, &header);
    },
    "reading the mesh", false);
}

//------------------------------------------------------------------------------
bool ReadPLYMesh(const std::string& path, PLYMesh* mesh, std::string* why,
  const PLYProgress& progress, double maxBytes)
{
  return fileio::RunCheckSafely(
    why, mesh,
    [&](std::string* message, PLYMesh* m) {
      PLYSummary header;
      if (!ReadPLYHeader(path, message, &header))
      {
        return false;
      }
      MeshArraysSink sink(m, header.NumberOfFaces, maxBytes);
      PLYStreamCounts counts;
      if (!StreamRows(path, &sink, &counts, message, progress, &header))
      {
        return false;
      }
      m->NumberOfFaces = counts.NumberOfFaces;
      m->NumberOfShortFaces = counts.NumberOfShortFaces;
      m->NumberOfSplitFaces = counts.NumberOfSplitFaces;
      return true;
    },
    "reading the mesh", true);
}

} // namespace plod
