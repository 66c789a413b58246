// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodPLYSamples.h
 * @brief Valid and corrupt PLY files for the tests of the PLY check, made by the tests
 * themselves: a tetrahedron (4 vertices, 4 triangles) in ASCII and both binary byte orders,
 * files that use every type and alias, extra elements and lists, and corrupt variants (cut
 * bodies, counts that lie, indices out of range, broken headers, garbage), each with a part of
 * the message the check must give. Header-only and VTK-free.
 */
#ifndef plodPLYSamples_h
#define plodPLYSamples_h

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace plodtest
{

enum class PLYEncoding
{
  ASCII,
  Little,
  Big
};

/// One sample: a file's bytes, or a path that is not a regular file (Bytes unused).
struct PLYSample
{
  std::string Name;   ///< the file is Name + ".ply"
  std::string Bytes;  ///< the file's content
  std::string Expect; ///< corrupt: a part of the check's message; valid: ""
  int64_t Vertices = 0;
  int64_t Faces = 0;     ///< valid samples: counts the check reports
  bool NotAFile = false; ///< the path must not be written (missing file, directory)
  std::string Path;      ///< set by WritePLYSamples
};

/// A value of the PLY type `type` (any name or alias) in the encoding, appended to `out`.
inline void PutPLYValue(std::string& out, const std::string& type, double value, PLYEncoding enc)
{
  if (enc == PLYEncoding::ASCII)
  {
    char text[64];
    const bool real = type == "float" || type == "float32" || type == "double" || type == "float64";
    if (real)
    {
      std::snprintf(text, sizeof(text), "%.9g", value);
    }
    else
    {
      std::snprintf(text, sizeof(text), "%lld", static_cast<long long>(value));
    }
    if (!out.empty() && out.back() != '\n')
    {
      out += ' ';
    }
    out += text;
    return;
  }
  unsigned char bytes[8];
  int size = 0;
  auto store = [&](auto v) {
    size = static_cast<int>(sizeof(v));
    std::memcpy(bytes, &v, sizeof(v));
  };
  if (type == "char" || type == "int8")
    store(static_cast<int8_t>(value));
  else if (type == "uchar" || type == "uint8")
    store(static_cast<uint8_t>(value));
  else if (type == "short" || type == "int16")
    store(static_cast<int16_t>(value));
  else if (type == "ushort" || type == "uint16")
    store(static_cast<uint16_t>(value));
  else if (type == "int" || type == "int32")
    store(static_cast<int32_t>(value));
  else if (type == "uint" || type == "uint32")
    store(static_cast<uint32_t>(value));
  else if (type == "float" || type == "float32")
    store(static_cast<float>(value));
  else
    store(static_cast<double>(value));
  const uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  const bool hostLittle = first == 1;
  const bool swap = hostLittle != (enc == PLYEncoding::Little);
  for (int i = 0; i < size; ++i)
  {
    out += static_cast<char>(bytes[swap ? size - 1 - i : i]);
  }
}

/// Ends an ASCII row (nothing in binary).
inline void EndPLYRow(std::string& out, PLYEncoding enc)
{
  if (enc == PLYEncoding::ASCII)
  {
    out += '\n';
  }
}

inline const char* PLYFormatWord(PLYEncoding enc)
{
  return enc == PLYEncoding::ASCII ? "ascii"
    : enc == PLYEncoding::Little   ? "binary_little_endian"
                                   : "binary_big_endian";
}

/// The tetrahedron and the ways a test may change it.
struct TetraPLY
{
  PLYEncoding Encoding = PLYEncoding::ASCII;
  std::string CoordType = "float";
  std::string CountType = "uchar";
  std::string IndexType = "int";
  int64_t DeclaredVertices = 4; ///< the header's counts (the body always has 4 and 4)
  int64_t DeclaredFaces = 4;
  std::vector<std::vector<int64_t>> Faces = { { 0, 1, 2 }, { 0, 3, 1 }, { 0, 2, 3 }, { 1, 3, 2 } };
  std::vector<int64_t> ListCounts; ///< counts written instead of the lists' sizes, when set
  std::string ExtraHeader;         ///< lines added after the format line
  bool WithFaces = true;
  std::string Newline = "\n";

  std::string Header() const
  {
    std::string h = "ply" + this->Newline + "format " + PLYFormatWord(this->Encoding) + " 1.0" +
      this->Newline + this->ExtraHeader;
    h += "element vertex " + std::to_string(this->DeclaredVertices) + this->Newline;
    for (const char* axis : { "x", "y", "z" })
    {
      h += "property " + this->CoordType + " " + axis + this->Newline;
    }
    if (this->WithFaces)
    {
      h += "element face " + std::to_string(this->DeclaredFaces) + this->Newline;
      h += "property list " + this->CountType + " " + this->IndexType + " vertex_indices" +
        this->Newline;
    }
    return h + "end_header" + this->Newline;
  }

  std::string VertexRows() const
  {
    const double xyz[4][3] = { { 1, 1, 1 }, { 1, -1, -1 }, { -1, 1, -1 }, { -1, -1, 1 } };
    std::string b;
    for (const auto& p : xyz)
    {
      for (double c : p)
      {
        PutPLYValue(b, this->CoordType, c, this->Encoding);
      }
      this->EndRow(b);
    }
    return b;
  }

  std::string FaceRows() const
  {
    std::string b;
    for (size_t f = 0; f < this->Faces.size(); ++f)
    {
      const double n = f < this->ListCounts.size() ? static_cast<double>(this->ListCounts[f])
                                                   : static_cast<double>(this->Faces[f].size());
      PutPLYValue(b, this->CountType, n, this->Encoding);
      for (int64_t i : this->Faces[f])
      {
        PutPLYValue(b, this->IndexType, static_cast<double>(i), this->Encoding);
      }
      this->EndRow(b);
    }
    return b;
  }

  std::string Bytes() const
  {
    return this->Header() + this->VertexRows() + (this->WithFaces ? this->FaceRows() : "");
  }

  void EndRow(std::string& b) const
  {
    if (this->Encoding == PLYEncoding::ASCII)
    {
      b += this->Newline;
    }
  }
};

inline PLYSample MakeValidSample(
  const std::string& name, const std::string& bytes, int64_t vertices, int64_t faces)
{
  PLYSample s;
  s.Name = name;
  s.Bytes = bytes;
  s.Vertices = vertices;
  s.Faces = faces;
  return s;
}

inline PLYSample MakeCorruptSample(
  const std::string& name, const std::string& bytes, const std::string& expect)
{
  PLYSample s;
  s.Name = name;
  s.Bytes = bytes;
  s.Expect = expect;
  return s;
}

/// Files every PLY reader should take.
inline std::vector<PLYSample> ValidPLYSamples()
{
  std::vector<PLYSample> v;
  const PLYEncoding encodings[3] = { PLYEncoding::ASCII, PLYEncoding::Little, PLYEncoding::Big };
  const char* names[3] = { "ascii", "binary_le", "binary_be" };
  for (int k = 0; k < 3; ++k)
  {
    TetraPLY t;
    t.Encoding = encodings[k];
    t.ExtraHeader = "comment made by plodPLYSamples.h\nobj_info a tetrahedron\n";
    v.push_back(MakeValidSample(std::string("tetra_") + names[k], t.Bytes(), 4, 4));

    // every type, by its first name and by its alias
    std::string h = std::string("ply\nformat ") + PLYFormatWord(encodings[k]) + " 1.0\n";
    const char* types[16] = { "char", "int8", "uchar", "uint8", "short", "int16", "ushort",
      "uint16", "int", "int32", "uint", "uint32", "float", "float32", "double", "float64" };
    h += "element vertex 2\nproperty float32 x\nproperty float64 y\nproperty double z\n";
    for (int i = 0; i < 16; ++i)
    {
      h += std::string("property ") + types[i] + " p" + std::to_string(i) + "\n";
    }
    h += "element face 1\nproperty list uint8 uint32 vertex_indices\n";
    h += "element material 2\nproperty list uint16 float64 values\nproperty int16 id\n";
    h += "end_header\n";
    std::string b;
    for (int row = 0; row < 2; ++row)
    {
      PutPLYValue(b, "float32", 0.5 * row, encodings[k]);
      PutPLYValue(b, "float64", -0.25, encodings[k]);
      PutPLYValue(b, "double", 1e-3, encodings[k]);
      const double values[8] = { -128, 255, -32768, 65535, -2147483648.0, 4294967295.0, 1.5,
        -2.5e100 };
      for (int i = 0; i < 16; ++i)
      {
        PutPLYValue(b, types[i], values[i / 2], encodings[k]);
      }
      EndPLYRow(b, encodings[k]);
    }
    PutPLYValue(b, "uint8", 3, encodings[k]);
    for (int i : { 0, 1, 1 })
    {
      PutPLYValue(b, "uint32", i, encodings[k]);
    }
    EndPLYRow(b, encodings[k]);
    for (int row = 0; row < 2; ++row)
    {
      PutPLYValue(b, "uint16", row * 2, encodings[k]);
      for (int i = 0; i < row * 2; ++i)
      {
        PutPLYValue(b, "float64", i, encodings[k]);
      }
      PutPLYValue(b, "int16", -row, encodings[k]);
      EndPLYRow(b, encodings[k]);
    }
    v.push_back(MakeValidSample(std::string("all_types_") + names[k], h + b, 2, 1));

    // a range scan: vertices and a range grid (one optional index per cell), no faces
    std::string scan = std::string("ply\nformat ") + PLYFormatWord(encodings[k]) +
      " 1.0\nobj_info num_cols 2\nobj_info num_rows 2\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement range_grid 4\n"
      "property list uchar int vertex_indices\nend_header\n";
    TetraPLY points;
    points.Encoding = encodings[k];
    scan += points.VertexRows();
    for (int cell = 0; cell < 4; ++cell)
    {
      PutPLYValue(scan, "uchar", cell == 2 ? 0 : 1, encodings[k]);
      if (cell != 2)
      {
        PutPLYValue(scan, "int", cell == 3 ? 2 : cell, encodings[k]);
      }
      EndPLYRow(scan, encodings[k]);
    }
    v.push_back(MakeValidSample(std::string("range_scan_") + names[k], scan, 4, 0));

    // faces with other list and count types, a quad, strips with their -1 separators, and
    // bytes after the last row
    TetraPLY t2;
    t2.Encoding = encodings[k];
    t2.CountType = "ushort";
    t2.IndexType = "uint";
    t2.Faces = { { 0, 1, 2, 3 }, { 0, 3, 1 }, { 0, 2, 3 }, { 1, 3, 2 } };
    std::string strips = t2.Header();
    strips.replace(strips.find("end_header"), 10,
      "element tristrips 1\nproperty list int int vertex_indices\nend_header");
    strips += t2.VertexRows() + t2.FaceRows();
    PutPLYValue(strips, "int", 7, encodings[k]);
    for (int i : { 0, 1, 2, -1, 1, 2, 3 })
    {
      PutPLYValue(strips, "int", i, encodings[k]);
    }
    EndPLYRow(strips, encodings[k]);
    strips += encodings[k] == PLYEncoding::ASCII ? "\n\n" : "xyz";
    v.push_back(MakeValidSample(std::string("strips_quads_") + names[k], strips, 4, 4));
  }
  TetraPLY crlf;
  crlf.Newline = "\r\n";
  v.push_back(MakeValidSample("tetra_ascii_crlf", crlf.Bytes(), 4, 4));
  TetraPLY cloud;
  cloud.Encoding = PLYEncoding::Little;
  cloud.WithFaces = false;
  v.push_back(MakeValidSample("point_cloud_binary_le", cloud.Bytes(), 4, 0));
  TetraPLY alias;
  alias.Encoding = PLYEncoding::Big;
  alias.CoordType = "float64";
  alias.CountType = "uint8";
  alias.IndexType = "int32";
  alias.Faces[0] = { 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3 };
  v.push_back(MakeValidSample("aliases_binary_be", alias.Bytes(), 4, 4));
  TetraPLY index;
  index.Encoding = PLYEncoding::Little;
  std::string vi = index.Bytes();
  vi.replace(vi.find("vertex_indices"), 14, "vertex_index");
  v.push_back(MakeValidSample("vertex_index_binary_le", vi, 4, 4));
  return v;
}

/// Files that are valid PLY but that VTK 9.1's vtkPLYReader cannot take (it crashes or misreads).
inline std::vector<PLYSample> ReaderLimitPLYSamples()
{
  std::vector<PLYSample> v;
  {
    TetraPLY t;
    std::string h = t.Header();
    const size_t vertex = h.find("element vertex");
    const size_t face = h.find("element face");
    const size_t end = h.find("end_header");
    std::string swapped = h.substr(0, vertex) + h.substr(face, end - face) +
      h.substr(vertex, face - vertex) + h.substr(end);
    v.push_back(MakeCorruptSample(
      "face_before_vertex", swapped + t.FaceRows() + t.VertexRows(), "needs 'vertex' first"));
  }
  {
    TetraPLY t;
    std::string h = t.Header();
    h.insert(
      h.find("element face"), "element edge 1\nproperty int vertex1\nproperty int vertex2\n");
    v.push_back(MakeCorruptSample("element_between_vertex_and_face",
      h + t.VertexRows() + "0 1\n" + t.FaceRows(), "needs 'face' right after 'vertex'"));
  }
  {
    TetraPLY t;
    t.Encoding = PLYEncoding::Little;
    t.CountType = "ushort";
    t.Faces[1].assign(300, 1);
    v.push_back(MakeCorruptSample("face_of_300_vertices", t.Bytes(), "reads at most 255"));
  }
  {
    TetraPLY t;
    t.ExtraHeader = "comment " + std::string(5000, 'x') + "\n";
    v.push_back(MakeCorruptSample("header_line_of_5000_bytes", t.Bytes(), "reads at most 4000"));
  }
  {
    TetraPLY t;
    std::string b = t.Bytes();
    b.insert(b.find("0 1 2\n"), std::string(4100, ' ')); // a face row of 4100 + bytes
    v.push_back(MakeCorruptSample("ascii_line_of_4100_bytes", b, "longer than 4000 bytes"));
  }
  {
    TetraPLY t;
    std::string h = t.Header();
    h.insert(h.find("end_header"), "element vertex_index_sets 0\nproperty int id\n");
    v.push_back(MakeCorruptSample(
      "element_named_vertex_index_sets", h + t.VertexRows() + t.FaceRows(), "'vertex_index'"));
  }
  {
    TetraPLY t;
    std::string b = t.Bytes();
    b.pop_back(); // the last face row's newline
    v.push_back(MakeCorruptSample(
      "ascii_without_final_newline", b, "the last line (line 17) does not end with a newline"));
  }
  return v;
}

/// Files that are not valid PLY, or whose body does not match the header.
inline std::vector<PLYSample> CorruptPLYSamples()
{
  std::vector<PLYSample> v;
  TetraPLY le;
  le.Encoding = PLYEncoding::Little;
  const std::string leHeader = le.Header();
  const std::string leBody = le.VertexRows() + le.FaceRows(); // 48 + 52 bytes
  TetraPLY be = le;
  be.Encoding = PLYEncoding::Big;
  const std::string beHeader = be.Header();
  const std::string beBody = be.VertexRows() + be.FaceRows();
  TetraPLY ascii;
  const std::string asciiHeader = ascii.Header();
  const std::string asciiBody = ascii.VertexRows() + ascii.FaceRows();

  // cut bodies: inside a vertex row, at a row boundary, before a face's count, inside a list,
  // one byte short
  v.push_back(MakeCorruptSample("cut_binary_le_inside_vertex_row", leHeader + leBody.substr(0, 18),
    "ends inside element 'vertex' row 1 of 4"));
  v.push_back(MakeCorruptSample("cut_binary_le_at_vertex_row", leHeader + leBody.substr(0, 24),
    "ends inside element 'vertex' row 2 of 4"));
  v.push_back(MakeCorruptSample("cut_binary_le_before_faces", leHeader + leBody.substr(0, 48),
    "ends inside element 'face' row 0 of 4"));
  v.push_back(
    MakeCorruptSample("cut_binary_le_inside_list", leHeader + leBody.substr(0, 48 + 13 + 7),
      "row 1 list 'vertex_indices': count 3 needs 12 bytes but only 6"));
  v.push_back(MakeCorruptSample("cut_binary_le_last_byte", leHeader + leBody.substr(0, 99),
    "row 3 list 'vertex_indices': count 3 needs 12 bytes but only 11"));
  v.push_back(MakeCorruptSample("cut_binary_be_inside_vertex_row", beHeader + beBody.substr(0, 47),
    "ends inside element 'vertex' row 3 of 4"));
  v.push_back(MakeCorruptSample("cut_binary_be_inside_list", beHeader + beBody.substr(0, 48 + 3),
    "row 0 list 'vertex_indices': count 3 needs 12 bytes but only 2"));
  v.push_back(MakeCorruptSample("cut_ascii_inside_line",
    asciiHeader + asciiBody.substr(0, asciiBody.find("1 -1 -1") + 4),
    "ends inside element 'vertex' row 1 of 4"));
  v.push_back(MakeCorruptSample("cut_ascii_inside_list",
    asciiHeader + asciiBody.substr(0, asciiBody.find("3 0 3 1") + 4),
    "row 1 list 'vertex_indices': count 3 needs at least 6 more bytes but only 3"));
  v.push_back(MakeCorruptSample("cut_ascii_at_line",
    asciiHeader + asciiBody.substr(0, asciiBody.find("3 0 2 3")),
    "ends inside element 'face' row 2 of 4"));

  // counts that lie
  {
    TetraPLY t = le;
    t.WithFaces = false;
    t.DeclaredVertices = 6;
    v.push_back(MakeCorruptSample(
      "vertex_count_too_large_binary", t.Bytes(), "ends inside element 'vertex' row 4 of 6"));
    t.Encoding = PLYEncoding::ASCII;
    v.push_back(MakeCorruptSample(
      "vertex_count_too_large_ascii", t.Bytes(), "ends inside element 'vertex' row 4 of 6"));
    TetraPLY mesh;
    mesh.DeclaredVertices = 6; // rows 4 and 5 are then the first faces' lines
    v.push_back(MakeCorruptSample(
      "vertex_count_too_large_ascii_mesh", mesh.Bytes(), "element 'vertex' row 4 has more values"));
  }
  {
    TetraPLY t = le;
    t.DeclaredFaces = 6;
    v.push_back(MakeCorruptSample(
      "face_count_too_large_binary", t.Bytes(), "ends inside element 'face' row 4 of 6"));
    t.Encoding = PLYEncoding::ASCII;
    v.push_back(MakeCorruptSample(
      "face_count_too_large_ascii", t.Bytes(), "ends inside element 'face' row 4 of 6"));
  }
  v.push_back(
    MakeCorruptSample("header_only_binary", leHeader, "ends inside element 'vertex' row 0 of 4"));
  v.push_back(
    MakeCorruptSample("header_only_ascii", asciiHeader, "ends inside element 'vertex' row 0 of 4"));

  // indices out of range, negative indices
  for (PLYEncoding enc : { PLYEncoding::ASCII, PLYEncoding::Little, PLYEncoding::Big })
  {
    const std::string suffix = enc == PLYEncoding::ASCII ? "ascii"
      : enc == PLYEncoding::Little                       ? "binary_le"
                                                         : "binary_be";
    TetraPLY t;
    t.Encoding = enc;
    t.Faces[2][1] = 9;
    v.push_back(MakeCorruptSample("index_out_of_range_" + suffix, t.Bytes(),
      "element 'face' row 2 list 'vertex_indices': vertex index 9 is not in [0, 4)"));
    t.Faces[2][1] = 4;
    v.push_back(MakeCorruptSample(
      "index_equal_to_vertex_count_" + suffix, t.Bytes(), "vertex index 4 is not in [0, 4)"));
    t.Faces[2][1] = -1;
    v.push_back(MakeCorruptSample("negative_index_" + suffix, t.Bytes(),
      "element 'face' row 2 list 'vertex_indices': vertex index -1 is not in [0, 4)"));
  }

  // list counts
  {
    TetraPLY t = le;
    t.ListCounts = { 3, 3, 3, 255 };
    v.push_back(MakeCorruptSample("list_count_255_binary", t.Bytes(),
      "row 3 list 'vertex_indices': count 255 needs 1020 bytes but only 12"));
    t.CountType = "int";
    t.ListCounts = { 2147483647 };
    v.push_back(MakeCorruptSample("list_count_int_huge_binary", t.Bytes(),
      "row 0 list 'vertex_indices': count 2147483647 needs"));
    t.ListCounts = { 3, -5 };
    v.push_back(MakeCorruptSample("list_count_int_negative_binary", t.Bytes(),
      "row 1 list 'vertex_indices': negative count -5"));
    t.CountType = "uint";
    t.ListCounts = { 4294967295LL };
    v.push_back(MakeCorruptSample(
      "list_count_uint_max_binary", t.Bytes(), "count 4294967295 needs 17179869180 bytes"));
    TetraPLY a;
    a.CountType = "int";
    a.ListCounts = { 3, 3, -3 };
    v.push_back(MakeCorruptSample(
      "list_count_negative_ascii", a.Bytes(), "row 2 list 'vertex_indices': negative count -3"));
    a.ListCounts = { 3, 3, 3, 2147483647 };
    v.push_back(MakeCorruptSample(
      "list_count_huge_ascii", a.Bytes(), "count 2147483647 needs at least 4294967294 more bytes"));
    a.CountType = "uchar";
    a.ListCounts = { 256 };
    v.push_back(MakeCorruptSample(
      "list_count_256_for_uchar_ascii", a.Bytes(), "'256' is not an integer of type uchar"));
    a.ListCounts = { 4 };
    v.push_back(MakeCorruptSample("list_count_larger_than_row_ascii", a.Bytes(),
      "element 'face' row 0 ends early: no list item"));
    a.ListCounts = { 2 };
    v.push_back(MakeCorruptSample(
      "list_count_smaller_than_row_ascii", a.Bytes(), "element 'face' row 0 has more values"));
  }

  // headers
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const std::string asciiFile = asciiHeader + asciiBody;
  v.push_back(MakeCorruptSample("missing_end_header_ascii", replace(asciiFile, "end_header\n", ""),
    "unknown header keyword '1' (is end_header missing?)"));
  v.push_back(MakeCorruptSample("missing_end_header_header_only",
    replace(asciiHeader, "end_header\n", ""), "no end_header line"));
  v.push_back(MakeCorruptSample("missing_end_header_binary",
    replace(leHeader + leBody, "end_header\n", ""), "no end_header line"));
  v.push_back(MakeCorruptSample("end_header_after_a_blank_line",
    replace(asciiFile, "end_header", "\nend_header"), "blank line in the header"));
  v.push_back(MakeCorruptSample("unknown_format",
    replace(asciiFile, "format ascii", "format binary_middle_endian"),
    "unknown format 'binary_middle_endian'"));
  v.push_back(MakeCorruptSample("no_format_line", replace(asciiFile, "format ascii 1.0\n", ""),
    "element before the format line"));
  v.push_back(MakeCorruptSample("unsupported_version", replace(asciiFile, "ascii 1.0", "ascii 2.0"),
    "unsupported PLY version '2.0'"));
  v.push_back(MakeCorruptSample("unknown_property_type",
    replace(asciiFile, "property float y", "property float3 y"), "unknown property type 'float3'"));
  v.push_back(MakeCorruptSample("unknown_list_item_type",
    replace(asciiFile, "uchar int vertex", "uchar integer vertex"),
    "unknown property type 'integer'"));
  v.push_back(
    MakeCorruptSample("float_list_count_type", replace(asciiFile, "list uchar", "list float"),
      "list count type 'float' is not an integer type"));
  v.push_back(MakeCorruptSample("vertex_count_2_to_the_63",
    replace(asciiFile, "vertex 4", "vertex 9223372036854775808"),
    "count '9223372036854775808' is not an integer in [0, 2147483647]"));
  v.push_back(MakeCorruptSample("vertex_count_negative",
    replace(asciiFile, "vertex 4", "vertex -4"), "count '-4' is not an integer"));
  v.push_back(MakeCorruptSample("face_count_not_a_number",
    replace(asciiFile, "face 4", "face four"), "count 'four' is not an integer"));
  v.push_back(MakeCorruptSample("element_declared_twice",
    replace(asciiFile, "end_header", "element face 0\nend_header"),
    "element 'face' declared twice"));
  v.push_back(MakeCorruptSample("property_declared_twice",
    replace(asciiFile, "property float z", "property float y"), "property 'y' declared twice"));
  v.push_back(MakeCorruptSample("property_before_element",
    replace(asciiFile, "format ascii 1.0\n", "format ascii 1.0\nproperty float w\n"),
    "property before any element"));
  v.push_back(MakeCorruptSample("no_vertex_element",
    replace(asciiFile, "element vertex 4", "element point 4"), "no 'vertex' element"));
  v.push_back(MakeCorruptSample("vertex_without_z",
    replace(asciiFile, "property float z", "property float w"), "has no property 'z'"));
  v.push_back(MakeCorruptSample("vertex_x_is_a_list",
    replace(asciiFile, "property float x", "property list uchar float x"), "'x' must be a scalar"));
  v.push_back(MakeCorruptSample("face_indices_not_a_list",
    replace(asciiFile, "property list uchar int vertex_indices", "property int vertex_indices"),
    "'vertex_indices' must be a list"));
  v.push_back(MakeCorruptSample("face_without_indices",
    replace(asciiFile, "vertex_indices", "corners"), "no list 'vertex_indices'"));
  v.push_back(MakeCorruptSample("element_without_properties",
    replace(asciiFile, "end_header", "element nothing 3\nend_header"),
    "element 'nothing' has 3 rows but no properties"));
  v.push_back(MakeCorruptSample("first_line_not_ply", "plyx\n" + asciiFile.substr(4),
    "not a PLY file: the first line is not 'ply'"));
  v.push_back(MakeCorruptSample("starts_with_obj", "# OBJ file\nv 0 0 0\n", "not a PLY file"));
  v.push_back(MakeCorruptSample("only_ply", "ply\n", "no end_header line"));
  v.push_back(MakeCorruptSample("only_pl", "pl", "not a PLY file"));
  v.push_back(MakeCorruptSample("ply_without_newline", "ply", "the file ends after 'ply'"));
  v.push_back(MakeCorruptSample("vertical_tab_in_header",
    replace(asciiFile, "element vertex", "\velement vertex"), "unknown header keyword"));

  // ASCII rows
  v.push_back(MakeCorruptSample("ascii_extra_value", replace(asciiFile, "1 -1 -1", "1 -1 -1 7"),
    "element 'vertex' row 1 has more values than its properties, starting with '7' (line 11)"));
  v.push_back(MakeCorruptSample("ascii_missing_value", replace(asciiFile, "1 -1 -1", "1 -1"),
    "element 'vertex' row 1 ends early: no value for property 'z' (line 11)"));
  v.push_back(MakeCorruptSample("ascii_blank_line", replace(asciiFile, "1 -1 -1\n", "1 -1 -1\n\n"),
    "blank line where element 'vertex' row 2 should be (line 12)"));
  v.push_back(MakeCorruptSample("ascii_not_a_number", replace(asciiFile, "1 -1 -1", "1 -1 abc"),
    "property 'z': 'abc' is not a number (line 11)"));
  v.push_back(MakeCorruptSample("ascii_decimal_index", replace(asciiFile, "3 0 2 3", "3 0 2.5 3"),
    "'2.5' is not an integer of type int (line 16)"));
  v.push_back(MakeCorruptSample("ascii_nul_byte",
    replace(asciiFile, "1 -1 -1", std::string("1 -1\0-1", 7)), "is not a number (line 11)"));

  // garbage
  {
    std::mt19937 rng(7);
    std::string noise;
    for (int i = 0; i < 4096; ++i)
    {
      noise += static_cast<char>(rng() & 0xff);
    }
    v.push_back(MakeCorruptSample("garbage", noise, "not a PLY file"));
    v.push_back(
      MakeCorruptSample("binary_header_then_garbage", leHeader + noise, "element 'face' row"));
    v.push_back(MakeCorruptSample(
      "ascii_header_then_garbage", asciiHeader + noise, "element 'vertex' row 0"));
  }
  v.push_back(MakeCorruptSample("empty", "", "the file is empty"));
  PLYSample missing;
  missing.Name = "does_not_exist";
  missing.Expect = "cannot open: No such file or directory";
  missing.NotAFile = true;
  v.push_back(missing);
  PLYSample folder;
  folder.Name = "a_directory";
  folder.Expect = "is a directory";
  folder.NotAFile = true;
  v.push_back(folder);
  return v;
}

/// Writes the samples into `dir` (created if needed) and sets their Path. The directory sample
/// becomes a directory named like a PLY file; the missing one is made sure not to exist.
inline bool WritePLYSamples(std::vector<PLYSample>& samples, const std::string& dir)
{
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  for (PLYSample& s : samples)
  {
    s.Path = dir + "/" + s.Name + ".ply";
    std::filesystem::remove_all(s.Path, error);
    if (s.NotAFile)
    {
      if (s.Name == "a_directory" && !std::filesystem::create_directory(s.Path, error))
      {
        return false;
      }
      continue;
    }
    std::ofstream out(s.Path, std::ios::binary | std::ios::trunc);
    out.write(s.Bytes.data(), static_cast<std::streamsize>(s.Bytes.size()));
    if (!out)
    {
      return false;
    }
  }
  return true;
}

} // namespace plodtest

#endif
