// SPDX-License-Identifier: BSD-3-Clause
// Validation of STL (3D Systems 1989) and OBJ (Wavefront) files before a reader trusts them.
// See plodMeshFileCheck.h.
#include "plodMeshFileCheck.h"
#include "plodFileInput.h"

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <memory>
#include <new>
#include <sys/stat.h>
#include <system_error>
#include <unistd.h>

namespace plod
{
namespace
{
using Input = fileio::FileInput;

// ---- words and numbers ---------------------------------------------------------------------

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

std::string Lower(std::string word)
{
  std::transform(word.begin(), word.end(), word.begin(),
    [](unsigned char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c + 32 : c); });
  return word;
}

/// Word separators within a line (isspace in the C locale, less the newline).
bool IsBlank(int c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// A text byte as vtksys's DetectFileType counts them (vtkSTLReader decides ASCII or binary by
/// the share of other bytes among the first 256).
bool IsDetectedAsText(unsigned char c)
{
  return (c >= 0x20 && c <= 0x7f) || c == '\n' || c == '\r' || c == '\t';
}

/// A control byte that no text file holds (tab, newline, vertical tab, form feed and carriage
/// return are text; bytes from 0x80 are allowed, as UTF-8 in names).
bool IsControl(unsigned char c)
{
  return c < 0x20 && !(c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r');
}

/// For a decimal number that std::from_chars found out of the double range: true when it is too
/// large, false when it is too small (a value that rounds to zero).
bool Overflows(const char* begin, const char* end)
{
  const char* p = begin;
  if (p != end && (*p == '-' || *p == '+'))
  {
    ++p;
  }
  // the power of ten of the first non-zero digit
  int64_t intDigits = 0;
  int64_t lead = 0;
  bool found = false;
  for (; p != end && *p >= '0' && *p <= '9'; ++p)
  {
    if (!found && *p != '0')
    {
      found = true;
      lead = intDigits;
    }
    ++intDigits;
  }
  int64_t magnitude = found ? intDigits - lead - 1 : 0;
  if (p != end && *p == '.')
  {
    ++p;
    for (int64_t k = 1; p != end && *p >= '0' && *p <= '9'; ++p, ++k)
    {
      if (!found && *p != '0')
      {
        found = true;
        magnitude = -k;
      }
    }
  }
  int64_t exponent = 0;
  if (p != end && (*p == 'e' || *p == 'E'))
  {
    ++p;
    const bool negative = p != end && *p == '-';
    if (p != end && (*p == '-' || *p == '+'))
    {
      ++p;
    }
    for (; p != end && *p >= '0' && *p <= '9'; ++p)
    {
      exponent = std::min<int64_t>(exponent * 10 + (*p - '0'), int64_t(1) << 40);
    }
    exponent = negative ? -exponent : exponent;
  }
  return magnitude + exponent > 0;
}

enum class Number
{
  None,     ///< not a number
  Finite,   ///< a number a float holds
  NotFinite ///< nan, an infinity, or beyond the range of float
};

/// A decimal number in the form of C's strtod (sign, digits, point, exponent; nan, inf and
/// infinity in any case), hexadecimal excepted; whether it is finite as a float.
Number ParseNumber(const std::string& word, double* value)
{
  const char* begin = word.data();
  const char* end = begin + word.size();
  if (begin != end && *begin == '+')
  {
    ++begin;
    if (begin != end && *begin == '-')
    {
      return Number::None;
    }
  }
  if (begin == end)
  {
    return Number::None;
  }
  double v = 0.0;
  const auto r = std::from_chars(begin, end, v, std::chars_format::general);
  if (r.ptr != end)
  {
    return Number::None;
  }
  if (r.ec == std::errc::result_out_of_range)
  {
    v = Overflows(begin, end) ? HUGE_VAL : 0.0;
  }
  else if (r.ec != std::errc())
  {
    return Number::None;
  }
  *value = v;
  return std::isfinite(v) && std::fabs(v) <= FLT_MAX ? Number::Finite : Number::NotFinite;
}

/// "nan", "inf" or "-inf" for a float that is not finite.
std::string NonFiniteName(float v)
{
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}

/// "line N: ", the start of a message about line N.
std::string AtLine(int64_t line)
{
  return "line " + std::to_string(line) + ": ";
}

/// Splits a text file into lines and words, holding at most MaxWordBytes of a word: memory
/// stays small whatever the length of a line.
class TextScanner
{
public:
  enum class Token
  {
    Word,      ///< in Word (cut to MaxWordBytes; WordTooLong says so)
    EndOfLine, ///< the newline is consumed; Line is still the ended line's number
    EndOfFile,
    Error ///< in Why: a zero byte, a line longer than the limit, a read error
  };

  static constexpr size_t MaxWordBytes = 64;

  /// `hashComments`: a `#` starts a comment that runs to the end of the line (OBJ).
  TextScanner(Input& in, int64_t maxLineBytes, const std::string& readerName, bool hashComments)
    : In(in)
    , MaxLineBytes(maxLineBytes)
    , ReaderName(readerName)
    , HashComments(hashComments)
  {
  }

  /// The next word of the current line, the end of the line, or the end of the file.
  Token Next()
  {
    this->StartLine();
    this->Word.clear();
    this->WordTooLong = false;
    int c = 0;
    do
    {
      c = this->GetByte();
    } while (c >= 0 && IsBlank(c));
    if (c == Failed)
    {
      return Token::Error;
    }
    if (c == '#' && this->HashComments)
    {
      this->CommentOnLine = true;
      return this->SkipLine();
    }
    if (c < 0)
    {
      return Token::EndOfFile;
    }
    if (c == '\n')
    {
      this->NewLine = true;
      return Token::EndOfLine;
    }
    while (c >= 0 && c != '\n' && !IsBlank(c) && !(c == '#' && this->HashComments))
    {
      if (this->Word.size() < MaxWordBytes)
      {
        this->Word.push_back(static_cast<char>(c));
      }
      else
      {
        this->WordTooLong = true;
      }
      c = this->GetByte();
    }
    if (c == Failed)
    {
      return Token::Error;
    }
    this->Pushed = c; // the separator (or the end) is read again by the next call
    return Token::Word;
  }

  /// Skips the rest of the line, its newline included.
  Token SkipLine()
  {
    for (;;)
    {
      const int c = this->GetByte();
      if (c == Failed)
      {
        return Token::Error;
      }
      if (c < 0)
      {
        return Token::EndOfFile;
      }
      if (c == '\n')
      {
        this->NewLine = true;
        return Token::EndOfLine;
      }
    }
  }

  /// The lines seen (the last one counts without a newline when it holds a byte).
  int64_t Lines() const { return this->Line - (this->LineBytes == 0 && !this->NewLine ? 1 : 0); }

  std::string At() const { return AtLine(this->Line); }

  int64_t Line = 1;
  std::string Word;
  bool WordTooLong = false;
  bool CommentOnLine = false; ///< a `#` comment on the current line
  std::string Why;

private:
  static constexpr int EndOfData = -1;
  static constexpr int Failed = -2;

  void StartLine()
  {
    if (this->NewLine)
    {
      this->NewLine = false;
      ++this->Line;
      this->LineBytes = 0;
      this->CommentOnLine = false;
    }
  }

  int GetByte()
  {
    if (this->Pushed != NoByte)
    {
      const int c = this->Pushed;
      this->Pushed = NoByte;
      return c;
    }
    const int c = this->In.Get();
    if (c < 0)
    {
      if (this->In.ReadError())
      {
        this->Why = this->At() + "cannot read the file at byte " +
          std::to_string(this->In.Offset()) + ": " + std::strerror(errno);
        return Failed;
      }
      return EndOfData;
    }
    if (c == '\n')
    {
      return c;
    }
    if (c == 0)
    {
      this->Why = this->At() + "a zero byte (byte " + std::to_string(this->In.Offset() - 1) +
        "): not a text file";
      return Failed;
    }
    if (++this->LineBytes > this->MaxLineBytes && this->MaxLineBytes > 0)
    {
      this->Why = this->At() + "the line is longer than " + std::to_string(this->MaxLineBytes) +
        " bytes, the most " + this->ReaderName + " reads whole";
      return Failed;
    }
    return c;
  }

  static constexpr int NoByte = -3;

  Input& In;
  int64_t MaxLineBytes;
  std::string ReaderName;
  bool HashComments;
  int Pushed = NoByte;
  bool NewLine = false;  ///< the last byte read was a newline: the next word is on a new line
  int64_t LineBytes = 0; ///< bytes of the current line so far, without its newline
};

// ---- STL -----------------------------------------------------------------------------------

/// A little-endian float32 or uint32 from the file's bytes.
uint32_t LittleEndian32(const unsigned char* b)
{
  return static_cast<uint32_t>(b[0]) | static_cast<uint32_t>(b[1]) << 8 |
    static_cast<uint32_t>(b[2]) << 16 | static_cast<uint32_t>(b[3]) << 24;
}

float LittleEndianFloat(const unsigned char* b)
{
  const uint32_t bits = LittleEndian32(b);
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

class STLChecker
{
public:
  STLChecker(std::string* why, STLSummary* summary, const STLReaderLimits& limits)
    : Why(why)
    , Summary(summary)
    , Limits(limits)
  {
  }

  bool Run(const std::string& path)
  {
    if (!this->In.Open(path, "an STL file", this->Why))
    {
      return false;
    }
    const int64_t size = this->In.Size();
    this->Summary->FileBytes = size;
    if (size == 0)
    {
      return this->Fail("the file is empty");
    }
    // the first bytes decide the format: the count, the first word, control bytes
    unsigned char prefix[1024];
    const size_t length = this->In.Read(prefix, static_cast<size_t>(std::min<int64_t>(size, 1024)));
    if (length < static_cast<size_t>(std::min<int64_t>(size, 1024)))
    {
      return this->Fail("cannot read the file's first bytes: " + std::string(std::strerror(errno)));
    }
    size_t first = 0;
    while (first < length && (IsBlank(prefix[first]) || prefix[first] == '\n'))
    {
      ++first;
    }
    size_t last = first;
    while (last < length && !IsBlank(prefix[last]) && prefix[last] != '\n')
    {
      ++last;
    }
    const bool solid =
      Lower(std::string(reinterpret_cast<const char*>(prefix) + first, last - first)) == "solid";
    const bool text =
      std::none_of(prefix, prefix + length, [](unsigned char c) { return IsControl(c); });
    const int64_t count = size >= 84 ? static_cast<int64_t>(LittleEndian32(prefix + 80)) : -1;
    const bool sizeMatches = count >= 0 && size - 84 == 50 * count;
    // bytes vtkSTLReader counts as text among the first 256
    const int64_t detected = std::min<int64_t>(length, 256);
    this->DetectedNonText = std::count_if(
      prefix, prefix + detected, [](unsigned char c) { return !IsDetectedAsText(c); });
    this->DetectedBytes = detected;
    if (!this->In.Rewind())
    {
      return this->Fail("cannot read the file again from its start");
    }
    if (!sizeMatches && solid && text)
    {
      this->Summary->Format = STLFormat::ASCII;
      return this->CheckASCII() && this->Finish();
    }
    this->Summary->Format = STLFormat::Binary;
    if (!sizeMatches && text && !solid)
    {
      return this->Fail("not an STL file: it is text that does not start with 'solid' (ASCII "
                        "STL), and its size is not 84 + 50 n bytes for a count n in bytes 80 to "
                        "83 (binary STL)");
    }
    return this->CheckBinary(count, solid) && this->Finish();
  }

private:
  bool Fail(const std::string& message)
  {
    *this->Why = message;
    return false;
  }

  std::string ReaderName() const
  {
    return this->Limits.ReaderName ? this->Limits.ReaderName : "the reader";
  }

  /// Non-finite and degenerate triangles, at the end of a file that is otherwise sound.
  bool Finish()
  {
    STLSummary& s = *this->Summary;
    if (s.NumberOfTriangles == 0)
    {
      return this->Fail(s.Format == STLFormat::Binary ? "no triangle: the header's count is 0"
                                                      : "no triangle: the file holds no facet");
    }
    if (s.NumberOfNonFiniteTriangles > 0)
    {
      return this->Fail(this->FirstNonFinite + "; " + std::to_string(s.NumberOfNonFiniteTriangles) +
        " of " + std::to_string(s.NumberOfTriangles) +
        " triangles have a NaN or infinite coordinate");
    }
    if (s.NumberOfDegenerateTriangles > 0)
    {
      s.Warning = std::to_string(s.NumberOfDegenerateTriangles) + " of " +
        std::to_string(s.NumberOfTriangles) +
        " triangles have two equal corners (the first: " + "triangle " +
        std::to_string(s.FirstDegenerateTriangle) +
        "); readers that merge points (vtkSTLReader) drop them";
    }
    return true;
  }

  /// Counts a triangle's corners (9 coordinates) as non-finite or degenerate; `place` is its
  /// byte offset (binary) or its facet's line (ASCII).
  void Triangle(const float* x, int64_t place)
  {
    STLSummary& s = *this->Summary;
    const int64_t t = s.NumberOfTriangles++;
    for (int k = 0; k < 9; ++k)
    {
      if (!std::isfinite(x[k]))
      {
        if (s.NumberOfNonFiniteTriangles++ == 0)
        {
          s.FirstNonFiniteTriangle = t;
          this->FirstNonFinite = "triangle " + std::to_string(t) +
            (s.Format == STLFormat::Binary ? " (byte " : " (facet at line ") +
            std::to_string(place) + ") has a non-finite vertex coordinate (" + NonFiniteName(x[k]) +
            ")";
        }
        return;
      }
    }
    auto same = [x](int a, int b) {
      return x[3 * a] == x[3 * b] && x[3 * a + 1] == x[3 * b + 1] && x[3 * a + 2] == x[3 * b + 2];
    };
    if (same(0, 1) || same(1, 2) || same(0, 2))
    {
      if (s.NumberOfDegenerateTriangles++ == 0)
      {
        s.FirstDegenerateTriangle = t;
      }
    }
  }

  // ---- binary ------------------------------------------------------------------------------

  /// `solid`: the file starts with the word solid (but is not ASCII STL).
  bool CheckBinary(int64_t count, bool solid)
  {
    const int64_t size = this->In.Size();
    if (size < 84)
    {
      return this->Fail("the file has " + std::to_string(size) +
        " bytes: too short for a binary STL file, whose header and triangle count take 84" +
        (solid ? " (it starts with 'solid' but holds control bytes: not ASCII STL either)" : ""));
    }
    const int64_t expected = 84 + 50 * count;
    const std::string says = "the header's count of " + std::to_string(count) +
      " triangles needs 84 + 50 * " + std::to_string(count) + " = " + std::to_string(expected) +
      " bytes, the file has " + std::to_string(size);
    if (size < expected)
    {
      const int64_t body = size - 84;
      const int64_t whole = body / 50;
      const int64_t part = body % 50;
      const int64_t missing = expected - size;
      if (part > 0)
      {
        return this->Fail("the file is cut inside triangle " + std::to_string(whole) + " of " +
          std::to_string(count) + " (triangles count from 0; " + std::to_string(part) +
          " of its 50 bytes are there, from byte " + std::to_string(84 + 50 * whole) +
          "): " + says + "; " + std::to_string(missing) + " bytes are missing");
      }
      return this->Fail((whole == 0 ? std::string("the file ends after its header")
                                    : "the file ends after triangle " + std::to_string(whole - 1) +
                              " of " + std::to_string(count) + " (triangles count from 0)") +
        ": " + says + "; " + std::to_string(missing) + " bytes (" + std::to_string(count - whole) +
        " triangles) are missing");
    }
    if (size > expected)
    {
      const int64_t extra = size - expected;
      return this->Fail(says + ": " + std::to_string(extra) + " bytes more than the count needs" +
        (extra % 50 == 0 ? " (" + std::to_string(extra / 50) + " more triangles than it says?)"
                         : ""));
    }
    if (this->Limits.MaxTriangles > 0 && count > this->Limits.MaxTriangles)
    {
      return this->Fail(std::to_string(count) + " triangles: " + this->ReaderName() +
        " reads at most " + std::to_string(this->Limits.MaxTriangles));
    }
    if (this->Limits.DetectsTypeFromFirstBytes && this->DetectedNonText * 20 < this->DetectedBytes)
    {
      return this->Fail(this->ReaderName() + " would read this binary file as ASCII: only " +
        std::to_string(this->DetectedNonText) + " of its first " +
        std::to_string(this->DetectedBytes) +
        " bytes are not text (it takes a file for binary from 5%)");
    }
    unsigned char header[84];
    if (this->In.Read(header, 84) != 84)
    {
      return this->Fail("cannot read the header: the file changed or cannot be read");
    }
    unsigned char record[50];
    for (int64_t t = 0; t < count; ++t)
    {
      if (this->In.Read(record, 50) != 50)
      {
        return this->Fail("cannot read triangle " + std::to_string(t) + " at byte " +
          std::to_string(84 + 50 * t) + ": the file changed or cannot be read");
      }
      float x[9];
      for (int k = 0; k < 9; ++k)
      {
        x[k] = LittleEndianFloat(record + 12 + 4 * k); // after the normal
      }
      this->Triangle(x, 84 + 50 * t);
    }
    return true;
  }

  // ---- ASCII -------------------------------------------------------------------------------

  enum class State
  {
    Solid,   ///< `solid`, or the end of the file after a solid
    Facet,   ///< `facet`, `color` or `endsolid`
    Loop,    ///< `outer loop`
    Vertex,  ///< `vertex` (Corners say how many were read)
    EndLoop, ///< `endloop`
    EndFacet ///< `endfacet`
  };

  /// Nothing more on the line after a keyword.
  bool EndOfStatement(const std::string& keyword)
  {
    const TextScanner::Token t = this->Text->Next();
    if (t == TextScanner::Token::Word)
    {
      return this->Fail(this->Text->At() + Quote(this->Text->Word) + " after '" + keyword +
        "', which takes nothing after it");
    }
    return t != TextScanner::Token::Error || this->Fail(this->Text->Why);
  }

  bool CheckASCII()
  {
    if (this->Limits.DetectsTypeFromFirstBytes && this->DetectedNonText * 20 >= this->DetectedBytes)
    {
      return this->Fail(this->ReaderName() +
        " would read this ASCII file as binary: " + std::to_string(this->DetectedNonText) +
        " of its first " + std::to_string(this->DetectedBytes) +
        " bytes are not ASCII text (it takes a file for binary from 5%; a solid's name in UTF-8?)");
    }
    STLSummary& s = *this->Summary;
    TextScanner text(this->In, this->Limits.MaxLineBytes, this->ReaderName(), false);
    this->Text = &text;
    State state = State::Solid;
    int64_t solidLine = 0;
    int64_t facetLine = 0;
    int corners = 0;
    float x[9] = {};
    for (;;)
    {
      TextScanner::Token t = text.Next();
      if (t == TextScanner::Token::Error)
      {
        return this->Fail(text.Why);
      }
      if (t == TextScanner::Token::EndOfLine)
      {
        continue; // a blank line
      }
      if (t == TextScanner::Token::EndOfFile)
      {
        break;
      }
      const std::string word = Lower(text.Word);
      const int64_t line = text.Line;
      const std::string at = AtLine(line);
      auto facet = [&]() {
        return "facet " + std::to_string(s.NumberOfTriangles) + " (line " +
          std::to_string(facetLine) + ")";
      };
      switch (state)
      {
        case State::Solid:
          if (word != "solid")
          {
            return this->Fail(at + "expected 'solid'" +
              (s.NumberOfSolids > 0 ? std::string(" or the end of the file") : "") + ", found " +
              Quote(text.Word));
          }
          ++s.NumberOfSolids;
          solidLine = text.Line;
          t = text.SkipLine(); // the name
          state = State::Facet;
          break;
        case State::Facet:
          if (word == "facet")
          {
            facetLine = text.Line;
            t = text.SkipLine(); // the normal is not read
            state = State::Loop;
          }
          else if (word == "endsolid")
          {
            t = text.SkipLine(); // the name
            state = State::Solid;
          }
          else if (word == "color")
          {
            t = text.SkipLine();
          }
          else
          {
            return this->Fail(at + "expected 'facet' or 'endsolid', found " + Quote(text.Word));
          }
          break;
        case State::Loop:
          if (word != "outer" || text.Next() != TextScanner::Token::Word ||
            Lower(text.Word) != "loop")
          {
            return this->Fail(at + "expected 'outer loop' in " + facet() + ", found " +
              Quote(word == "outer" ? "outer " + text.Word : text.Word));
          }
          if (!this->EndOfStatement("outer loop"))
          {
            return false;
          }
          state = State::Vertex;
          corners = 0;
          continue;
        case State::Vertex:
          if (word != "vertex")
          {
            return this->Fail(at +
              (word == "endloop"
                  ? facet() + " has " + std::to_string(corners) + " vertices; a facet needs 3"
                  : "expected 'vertex' in " + facet() + ", found " + Quote(text.Word)));
          }
          if (!this->Vertex(x + 3 * corners, facetLine))
          {
            return false;
          }
          state = ++corners == 3 ? State::EndLoop : State::Vertex;
          continue;
        case State::EndLoop:
          if (word != "endloop")
          {
            return this->Fail(at +
              (word == "vertex"
                  ? facet() + " has more than 3 vertices"
                  : "expected 'endloop' in " + facet() + ", found " + Quote(text.Word)));
          }
          if (!this->EndOfStatement("endloop"))
          {
            return false;
          }
          state = State::EndFacet;
          continue;
        case State::EndFacet:
          if (word != "endfacet")
          {
            return this->Fail(
              at + "expected 'endfacet' in " + facet() + ", found " + Quote(text.Word));
          }
          if (!this->EndOfStatement("endfacet"))
          {
            return false;
          }
          this->Triangle(x, facetLine);
          state = State::Facet;
          continue;
      }
      if (t == TextScanner::Token::Error)
      {
        return this->Fail(text.Why);
      }
      if (t == TextScanner::Token::EndOfFile)
      {
        break;
      }
    }
    const std::string end = "the file ends at line " + std::to_string(text.Lines());
    const std::string facet = "facet " + std::to_string(s.NumberOfTriangles) + " (opened at line " +
      std::to_string(facetLine) + ")";
    switch (state)
    {
      case State::Solid:
        return true;
      case State::Facet:
        return this->Fail(end + " without 'endsolid' (the solid opened at line " +
          std::to_string(solidLine) + "): is it cut?");
      case State::Loop:
        return this->Fail("the file is cut inside " + facet + ": " + end + " before 'outer loop'");
      case State::Vertex:
        return this->Fail("the file is cut inside " + facet + ": " + end + " after " +
          std::to_string(corners) + " of its 3 vertices");
      case State::EndLoop:
        return this->Fail("the file is cut inside " + facet + ": " + end + " before 'endloop'");
      case State::EndFacet:
        return this->Fail("the file is cut inside " + facet + ": " + end + " before 'endfacet'");
    }
    return true;
  }

  /// The three numbers after `vertex`, as floats in x[0..2], in the facet of line `facetLine`.
  bool Vertex(float* x, int64_t facetLine)
  {
    TextScanner& text = *this->Text;
    const std::string at = text.At();
    auto facet = [&]() {
      return "facet " + std::to_string(this->Summary->NumberOfTriangles) + " (line " +
        std::to_string(facetLine) + ")";
    };
    for (int k = 0; k < 4; ++k)
    {
      const TextScanner::Token t = text.Next();
      if (t == TextScanner::Token::Error)
      {
        return this->Fail(text.Why);
      }
      if (t != TextScanner::Token::Word)
      {
        if (k == 3)
        {
          return true;
        }
        if (t == TextScanner::Token::EndOfFile)
        {
          return this->Fail("the file is cut inside facet " +
            std::to_string(this->Summary->NumberOfTriangles) + " (opened at line " +
            std::to_string(facetLine) + "): the file ends at line " + std::to_string(text.Lines()) +
            " inside a vertex");
        }
        return this->Fail(
          at + "a vertex of " + facet() + " has " + std::to_string(k) + " numbers; it needs 3");
      }
      if (k == 3)
      {
        return this->Fail(
          at + "a vertex of " + facet() + " has more than 3 numbers (" + Quote(text.Word) + ")");
      }
      double v = 0.0;
      const Number kind = text.WordTooLong ? Number::None : ParseNumber(text.Word, &v);
      if (kind == Number::None)
      {
        return this->Fail(
          at + Quote(text.Word) + " is not a number (a vertex coordinate of " + facet() + ")");
      }
      x[k] = kind == Number::Finite ? static_cast<float>(v)
                                    : (std::isnan(v) ? NAN : (v > 0 ? HUGE_VALF : -HUGE_VALF));
    }
    return true;
  }

  std::string* Why;
  STLSummary* Summary;
  STLReaderLimits Limits;
  Input In;
  TextScanner* Text = nullptr;
  int64_t DetectedNonText = 0; ///< bytes vtksys would not count as text among DetectedBytes
  int64_t DetectedBytes = 0;   ///< the first 256 bytes, or fewer in a shorter file
  std::string FirstNonFinite;  ///< the first triangle with a non-finite coordinate, and where
};

// ---- OBJ -----------------------------------------------------------------------------------

/// The forms of an OBJ reference.
enum class Form
{
  V = 1,   ///< i
  VT = 2,  ///< i/t
  VTN = 3, ///< i/t/n
  VN = 4   ///< i//n
};

const char* FormName(Form f)
{
  switch (f)
  {
    case Form::V:
      return "i";
    case Form::VT:
      return "i/t";
    case Form::VTN:
      return "i/t/n";
    case Form::VN:
      return "i//n";
  }
  return "?";
}

class OBJChecker
{
public:
  OBJChecker(std::string* why, OBJSummary* summary, const OBJReaderLimits& limits)
    : Why(why)
    , Summary(summary)
    , Limits(limits)
  {
  }

  bool Run(const std::string& path)
  {
    if (!this->In.Open(path, "an OBJ file", this->Why))
    {
      return false;
    }
    OBJSummary& s = *this->Summary;
    s.FileBytes = this->In.Size();
    if (s.FileBytes == 0)
    {
      return this->Fail("the file is empty");
    }
    TextScanner text(this->In, 0, this->ReaderName(), true);
    this->Text = &text;
    bool ok = true;
    for (;;)
    {
      const TextScanner::Token t = text.Next();
      if (t == TextScanner::Token::Error)
      {
        ok = this->Fail(text.Why);
        break;
      }
      if (t == TextScanner::Token::EndOfFile)
      {
        break;
      }
      if (t == TextScanner::Token::EndOfLine)
      {
        continue;
      }
      const std::string& w = text.Word;
      TextScanner::Token end = TextScanner::Token::EndOfLine;
      if (w == "v")
      {
        ok = this->Vertex(&end);
      }
      else if (w == "vt")
      {
        ok = this->Numbers("texture coordinate", 1, 3, &end);
        s.NumberOfTextureCoordinates += ok ? 1 : 0;
      }
      else if (w == "vn")
      {
        ok = this->Numbers("normal", 3, 3, &end);
        s.NumberOfNormals += ok ? 1 : 0;
      }
      else if (w == "f" || w == "l" || w == "p")
      {
        ok = this->Element(w[0], &end);
      }
      else
      {
        end = text.SkipLine(); // a statement that draws nothing here
      }
      if (!ok)
      {
        break;
      }
      if (end == TextScanner::Token::Error)
      {
        ok = this->Fail(text.Why);
        break;
      }
      if (end == TextScanner::Token::EndOfFile)
      {
        break;
      }
    }
    s.NumberOfLines = text.Lines();
    return ok && this->Finish();
  }

private:
  bool Fail(const std::string& message)
  {
    // a non-finite vertex found before the problem is said too
    *this->Why = message +
      (this->Summary->NumberOfNonFiniteVertices > 0
          ? " (and before it, " + this->FirstNonFinite + ")"
          : "");
    return false;
  }

  std::string ReaderName() const
  {
    return this->Limits.ReaderName ? this->Limits.ReaderName : "the reader";
  }

  bool Finish()
  {
    OBJSummary& s = *this->Summary;
    if (s.NumberOfVertices == 0)
    {
      *this->Why = "no vertex: the file holds no 'v' line";
      return false;
    }
    if (s.NumberOfNonFiniteVertices > 0)
    {
      *this->Why = this->FirstNonFinite + "; " + std::to_string(s.NumberOfNonFiniteVertices) +
        " of " + std::to_string(s.NumberOfVertices) +
        " vertices have a NaN, infinite or out-of-range coordinate";
      return false;
    }
    std::string& w = s.Warning;
    auto add = [&w](const std::string& part) { w += (w.empty() ? "" : "; ") + part; };
    if (s.NumberOfFaces == 0)
    {
      add("no face ('f' line): the " + std::to_string(s.NumberOfVertices) +
        " vertices are read as a point cloud");
    }
    if (s.NumberOfPolylines > 0)
    {
      add(std::to_string(s.NumberOfPolylines) + " 'l' polylines (the first at line " +
        std::to_string(s.FirstPolylineLine) + ") are ignored: only faces are drawn");
    }
    if (s.NumberOfPointElements > 0)
    {
      add(std::to_string(s.NumberOfPointElements) + " 'p' point elements (the first at line " +
        std::to_string(s.FirstPointElementLine) + ") are ignored: only faces are drawn");
    }
    if (this->Limits.SkipsFacesWithoutNormals && this->FacesWithNormals > 0 &&
      this->FacesWithoutNormals > 0)
    {
      s.NumberOfFacesWithoutNormals = this->FacesWithoutNormals;
      s.FirstFaceWithoutNormalsLine = this->FirstFaceWithoutNormalsLine;
      add(std::to_string(this->FacesWithoutNormals) + " of " + std::to_string(s.NumberOfFaces) +
        " faces have no normal reference while others have one (the first: line " +
        std::to_string(this->FirstFaceWithoutNormalsLine) + "); " + this->ReaderName() +
        " skips them");
    }
    return true;
  }

  /// `v x y z [w]` or `v x y z r g b [a]`.
  bool Vertex(TextScanner::Token* end)
  {
    TextScanner& text = *this->Text;
    OBJSummary& s = *this->Summary;
    const std::string at = text.At();
    int n = 0;
    bool finite = true;
    std::string bad;
    for (;;)
    {
      *end = text.Next();
      if (*end != TextScanner::Token::Word)
      {
        break;
      }
      double v = 0.0;
      const Number kind = text.WordTooLong ? Number::None : ParseNumber(text.Word, &v);
      if (kind == Number::None)
      {
        return this->Fail(at + Quote(text.Word) + " is not a number (in a vertex)");
      }
      if (++n > 7)
      {
        return this->Fail(at + "a vertex has more than 7 numbers (x y z, then w or r g b [a])");
      }
      if (n <= 3 && kind == Number::NotFinite && finite)
      {
        finite = false;
        bad = text.Word;
      }
    }
    if (*end == TextScanner::Token::Error)
    {
      return this->Fail(text.Why);
    }
    if (n < 3)
    {
      return this->Fail(at + "a vertex has " + std::to_string(n) + " coordinates; it needs 3");
    }
    ++s.NumberOfVertices;
    if (!finite && s.NumberOfNonFiniteVertices++ == 0)
    {
      s.FirstNonFiniteVertexLine = text.Line;
      this->FirstNonFinite = at + "vertex " + std::to_string(s.NumberOfVertices) +
        " (OBJ counts from 1) has the coordinate " + Quote(bad) + ", which is not a finite float";
    }
    return true;
  }

  /// `vt` or `vn`: from `least` to `most` numbers of any value.
  bool Numbers(const char* what, int least, int most, TextScanner::Token* end)
  {
    TextScanner& text = *this->Text;
    const std::string at = text.At();
    int n = 0;
    for (;;)
    {
      *end = text.Next();
      if (*end != TextScanner::Token::Word)
      {
        break;
      }
      double v = 0.0;
      if (text.WordTooLong || ParseNumber(text.Word, &v) == Number::None)
      {
        return this->Fail(at + Quote(text.Word) + " is not a number (in a " + what + ")");
      }
      if (++n > most)
      {
        return this->Fail(at + "a " + what + " has more than " + std::to_string(most) + " numbers");
      }
    }
    if (*end == TextScanner::Token::Error)
    {
      return this->Fail(text.Why);
    }
    if (n < least)
    {
      return this->Fail(at + "a " + what + " has " + std::to_string(n) + " numbers; it needs " +
        std::to_string(least));
    }
    return true;
  }

  /// An OBJ index (a non-zero integer) that names one of `count` items defined so far.
  bool Index(const char* begin, const char* end, int64_t count, const char* what,
    const std::string& reference)
  {
    const int64_t line = this->Text->Line;
    const char* p = begin;
    if (p != end && *p == '+')
    {
      ++p;
    }
    int64_t i = 0;
    const auto r = std::from_chars(p, end, i, 10);
    if (p == end || r.ptr != end || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
    {
      return this->Fail(AtLine(line) + Quote(reference) +
        " is not a reference (i, i/t, i/t/n or i//n, with integer indices)");
    }
    if (r.ec == std::errc::result_out_of_range || i > count || i < -count)
    {
      const bool relative = *p == '-';
      return this->Fail(AtLine(line) + (relative ? "relative " : "") + what + " index " +
        std::string(begin, end) + " in " + Quote(reference) +
        " is out of range: " + std::to_string(count) + " are defined before this line" +
        (relative ? " (-1 is the last of them)" : ""));
    }
    if (i == 0)
    {
      return this->Fail(AtLine(line) + what + " index 0 in " + Quote(reference) +
        " (OBJ indices count from 1; -1 is the last one defined)");
    }
    return true;
  }

  /// One reference of `f`, `l` or `p`: its form, and its indices in range.
  bool Reference(const std::string& word, Form* form)
  {
    const OBJSummary& s = *this->Summary;
    const char* b = word.data();
    const char* e = b + word.size();
    const char* s1 = std::find(b, e, '/');
    const char* s2 = s1 == e ? e : std::find(s1 + 1, e, '/');
    if (s2 != e && std::find(s2 + 1, e, '/') != e)
    {
      return this->Fail(this->Text->At() + Quote(word) +
        " is not a reference (i, i/t, i/t/n or i//n): too many '/'");
    }
    if (!this->Index(b, s1, s.NumberOfVertices, "vertex", word))
    {
      return false;
    }
    if (s1 == e)
    {
      *form = Form::V;
      return true;
    }
    if (s2 == e)
    {
      *form = Form::VT;
      return this->Index(s1 + 1, e, s.NumberOfTextureCoordinates, "texture coordinate", word);
    }
    if (s2 == s1 + 1)
    {
      *form = Form::VN;
      return this->Index(s2 + 1, e, s.NumberOfNormals, "normal", word);
    }
    *form = Form::VTN;
    return this->Index(s1 + 1, s2, s.NumberOfTextureCoordinates, "texture coordinate", word) &&
      this->Index(s2 + 1, e, s.NumberOfNormals, "normal", word);
  }

  /// `f`, `l` or `p` and their references.
  bool Element(char kind, TextScanner::Token* end)
  {
    TextScanner& text = *this->Text;
    OBJSummary& s = *this->Summary;
    const std::string at = text.At();
    const int64_t line = text.Line;
    const char* name = kind == 'f' ? "face" : (kind == 'l' ? "polyline" : "point element");
    const int least = kind == 'f' ? 3 : (kind == 'l' ? 2 : 1);
    int64_t n = 0;
    Form form = Form::V;
    std::string firstWord;
    for (;;)
    {
      *end = text.Next();
      if (*end != TextScanner::Token::Word)
      {
        break;
      }
      if (text.WordTooLong)
      {
        return this->Fail(at + Quote(text.Word) + " is not a reference (too long)");
      }
      Form f = Form::V;
      if (!this->Reference(text.Word, &f))
      {
        return false;
      }
      if (n == 0)
      {
        form = f;
        firstWord = text.Word;
      }
      else if (f != form)
      {
        return this->Fail(at + "references of different forms in one " + name + " (" +
          Quote(firstWord) + " is " + FormName(form) + ", " + Quote(text.Word) + " is " +
          FormName(f) + "): the form must be the same throughout");
      }
      ++n;
    }
    if (*end == TextScanner::Token::Error)
    {
      return this->Fail(text.Why);
    }
    if (n < least)
    {
      return this->Fail(at + "a " + name + " of " + std::to_string(n) + " references; it needs " +
        std::to_string(least) + " or more" +
        (kind == 'f' ? " (" + this->ReaderName() + " reads nothing from such a file)" : ""));
    }
    if (text.CommentOnLine && this->Limits.NoCommentAfterReferences)
    {
      return this->Fail(at + "a comment after the references of '" + std::string(1, kind) + "': " +
        this->ReaderName() + " reads nothing from such a file (put it on a line of its own)");
    }
    if (kind == 'f')
    {
      ++s.NumberOfFaces;
      s.MaxFaceSize = std::max(s.MaxFaceSize, n);
      if (form == Form::VTN || form == Form::VN)
      {
        ++this->FacesWithNormals;
      }
      else if (this->FacesWithoutNormals++ == 0)
      {
        this->FirstFaceWithoutNormalsLine = line;
      }
    }
    else if (kind == 'l' && s.NumberOfPolylines++ == 0)
    {
      s.FirstPolylineLine = line;
    }
    else if (kind == 'p' && s.NumberOfPointElements++ == 0)
    {
      s.FirstPointElementLine = line;
    }
    return true;
  }

  std::string* Why;
  OBJSummary* Summary;
  OBJReaderLimits Limits;
  Input In;
  TextScanner* Text = nullptr;
  std::string FirstNonFinite; ///< the first non-finite vertex: line, number, coordinate
  int64_t FacesWithNormals = 0;
  int64_t FacesWithoutNormals = 0;
  int64_t FirstFaceWithoutNormalsLine = -1;
};

/// Runs a checker with its outputs made safe (plodFileInput.h).
template <typename Checker, typename Summary, typename Limits>
bool RunCheck(const std::string& path, std::string* why, Summary* summary, const Limits& limits)
{
  return fileio::RunCheckSafely(why, summary, [&](std::string* message, Summary* s) {
    Checker checker(message, s, limits);
    return checker.Run(path);
  });
}

} // namespace

//------------------------------------------------------------------------------
bool CheckSTLFile(
  const std::string& path, std::string* why, STLSummary* summary, const STLReaderLimits& limits)
{
  return RunCheck<STLChecker>(path, why, summary, limits);
}

//------------------------------------------------------------------------------
STLReaderLimits VTKSTLReaderLimits()
{
  STLReaderLimits limits;
  limits.ReaderName = "vtkSTLReader (VTK 9.1)";
  limits.DetectsTypeFromFirstBytes = true;
  limits.MaxLineBytes = MaxVTKSTLLineBytes;
  limits.MaxTriangles = MaxVTKSTLTriangles;
  return limits;
}

//------------------------------------------------------------------------------
bool CheckOBJFile(
  const std::string& path, std::string* why, OBJSummary* summary, const OBJReaderLimits& limits)
{
  return RunCheck<OBJChecker>(path, why, summary, limits);
}

//------------------------------------------------------------------------------
OBJReaderLimits VTKOBJReaderLimits()
{
  OBJReaderLimits limits;
  limits.ReaderName = "vtkOBJReader (VTK 9.1)";
  limits.NoCommentAfterReferences = true;
  limits.SkipsFacesWithoutNormals = true;
  return limits;
}

} // namespace plod
