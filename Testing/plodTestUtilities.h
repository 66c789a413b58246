// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file plodTestUtilities.h
 * @brief Inputs the tests and benchmarks generate, model readers that check the file first (so
 * that a corrupt file gives a message, not a crash), and an observer that captures VTK errors.
 * Header-only, used by tests, benchmarks and examples.
 */
#ifndef plodTestUtilities_h
#define plodTestUtilities_h

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkPLYFileCheck.h"
#include "vtkPLYReader.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSTLReader.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkTransform.h"
#include "vtkXMLPolyDataReader.h"

#include "../Filters/Core/plodMeshFileCheck.h" // (the programs' include path lacks Filters/Core)

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace plodtest
{

/// Records the error and warning messages sent to it.
class ErrorRecorder : public vtkCommand
{
public:
  static ErrorRecorder* New() { return new ErrorRecorder; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string text = data ? static_cast<const char*>(data) : "";
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings).push_back(text);
  }
  bool HasError(const std::string& part = "") const
  {
    for (const auto& e : this->Errors)
    {
      if (e.find(part) != std::string::npos)
      {
        return true;
      }
    }
    return false;
  }
  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;
};

/// Folder of the Stanford scans (PLOD_DATA_DIR, else ../shared/data beside the source tree), or
/// "" when it is absent.
inline std::string DataDir()
{
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("PLOD_DATA_DIR"))
  {
    candidates.emplace_back(env);
  }
#ifdef PLOD_SOURCE_DIR
  candidates.emplace_back(std::string(PLOD_SOURCE_DIR) + "/../shared/data");
#endif
  for (const auto& c : candidates)
  {
    struct stat st;
    if (stat((c + "/bun_zipper.ply").c_str(), &st) == 0)
    {
      return c;
    }
  }
  return "";
}

/// Triangle mesh from flat coordinate and index lists.
inline vtkSmartPointer<vtkPolyData> MakeMesh(
  const std::vector<double>& xyz, const std::vector<vtkIdType>& tri)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (size_t i = 0; i + 2 < xyz.size(); i += 3)
  {
    pts->InsertNextPoint(xyz[i], xyz[i + 1], xyz[i + 2]);
  }
  vtkNew<vtkCellArray> polys;
  for (size_t i = 0; i + 2 < tri.size(); i += 3)
  {
    const vtkIdType ids[3] = { tri[i], tri[i + 1], tri[i + 2] };
    polys->InsertNextCell(3, ids);
  }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

/// The same triangles with three points of their own each (an unwelded mesh: every point
/// repeated as often as triangles share it).
inline vtkSmartPointer<vtkPolyData> Unweld(vtkPolyData* mesh)
{
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  auto it = vtk::TakeSmartPointer(mesh->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (int k = 0; k < 3; ++k)
    {
      double x[3];
      mesh->GetPoint(ids[k], x);
      tri.push_back(static_cast<vtkIdType>(xyz.size() / 3));
      xyz.insert(xyz.end(), x, x + 3);
    }
  }
  return MakeMesh(xyz, tri);
}

/// Axis-aligned box [lo, hi]^3 as 12 outward-oriented triangles.
inline vtkSmartPointer<vtkPolyData> MakeCube(double lo, double hi)
{
  std::vector<double> xyz;
  for (int k = 0; k < 8; ++k)
  {
    xyz.push_back(k & 1 ? hi : lo);
    xyz.push_back(k & 2 ? hi : lo);
    xyz.push_back(k & 4 ? hi : lo);
  }
  // quads listed counter-clockwise seen from outside
  const int quads[6][4] = { { 0, 4, 6, 2 }, { 1, 3, 7, 5 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 },
    { 0, 2, 3, 1 }, { 4, 5, 7, 6 } };
  std::vector<vtkIdType> tri;
  for (auto& q : quads)
  {
    tri.insert(tri.end(), { q[0], q[1], q[2], q[0], q[2], q[3] });
  }
  return MakeMesh(xyz, tri);
}

/// Regular tetrahedron with outward triangles, centred at the origin.
inline vtkSmartPointer<vtkPolyData> MakeTetrahedron()
{
  return MakeMesh(
    { 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1 }, { 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2 });
}

/// Unit square [0,1]^2 at height z, normal +z (two triangles sharing the diagonal).
inline vtkSmartPointer<vtkPolyData> MakePlane(double z)
{
  return MakeMesh({ 0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z }, { 0, 1, 2, 0, 2, 3 });
}

/// 2,000 tiny separate triangles in the unit cube and one sliver across it, from (0,0,0) to
/// (1,1,1): fine detail forces deep levels, and the sliver crosses the whole grid (2,001
/// triangles).
inline vtkSmartPointer<vtkPolyData> MakeSliverSoup()
{
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  for (int t = 0; t < 2000; ++t)
  {
    const double c[3] = { U(rng), U(rng), U(rng) };
    for (int k = 0; k < 3; ++k)
    {
      tri.push_back(static_cast<vtkIdType>(xyz.size() / 3));
      for (int a = 0; a < 3; ++a)
        xyz.push_back(c[a] + 1e-4 * U(rng));
    }
  }
  const vtkIdType s = static_cast<vtkIdType>(xyz.size() / 3);
  xyz.insert(xyz.end(), { 0, 0, 0, 1, 1, 1, 1, 1, 1.0001 });
  tri.insert(tri.end(), { s, s + 1, s + 2 });
  return MakeMesh(xyz, tri);
}

/**
 * Closed sphere-like surface: a UV sphere of radius `radius` at `centre`, displaced radially by
 * a random sum of low-frequency waves of relative amplitude `noise` (star-shaped, so it never
 * self-intersects for noise < 0.5). About 2 * res * res triangles.
 */
inline vtkSmartPointer<vtkPolyData> MakeBlob(unsigned seed, int res, double noise,
  double radius = 1.0, const double centre[3] = nullptr, bool floatPoints = false)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(res);
  sphere->SetPhiResolution(res);
  sphere->SetRadius(1.0);
  sphere->SetOutputPointsPrecision(
    floatPoints ? vtkAlgorithm::SINGLE_PRECISION : vtkAlgorithm::DOUBLE_PRECISION);
  sphere->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->ShallowCopy(sphere->GetOutput());
  sphere->GetOutput()->Initialize(); // no second copy of a large model
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  double waves[6][4];
  for (auto& w : waves)
  {
    for (double& c : w)
    {
      c = U(rng);
    }
  }
  vtkPoints* pts = pd->GetPoints();
  for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pts->GetPoint(i, x);
    double r = 1.0;
    for (int k = 0; k < 6; ++k)
    {
      const double f = 1.0 + 2.0 * k;
      r += noise / 6.0 *
        std::sin(
          f * (waves[k][0] * x[0] + waves[k][1] * x[1] + waves[k][2] * x[2]) + 3 * waves[k][3]);
    }
    for (int a = 0; a < 3; ++a)
    {
      x[a] = x[a] * r * radius + (centre ? centre[a] : 0.0);
    }
    pts->SetPoint(i, x);
  }
  pd->GetPointData()->Initialize();
  return pd;
}

/**
 * Closed box surface [0,1]^3 subdivided nx x ny x nz, with outward triangles and welded
 * points, each point then moved by `map` (which must keep orientation: a positive Jacobian).
 * The building block of the thin-part models below.
 */
inline vtkSmartPointer<vtkPolyData> MakeDeformedBox(
  int nx, int ny, int nz, const std::function<void(const double in[3], double out[3])>& map)
{
  const int n[3] = { nx, ny, nz };
  std::map<std::array<int, 3>, vtkIdType> ids;
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  auto id = [&](const std::array<int, 3>& g) {
    auto it = ids.find(g);
    if (it != ids.end())
    {
      return it->second;
    }
    const double in[3] = { double(g[0]) / n[0], double(g[1]) / n[1], double(g[2]) / n[2] };
    double out[3];
    map(in, out);
    xyz.insert(xyz.end(), out, out + 3);
    const vtkIdType i = static_cast<vtkIdType>(ids.size());
    ids[g] = i;
    return i;
  };
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side)
    {
      for (int i = 0; i < n[b]; ++i)
      {
        for (int j = 0; j < n[c]; ++j)
        {
          vtkIdType q[4];
          const int di[4] = { 0, 1, 1, 0 }, dj[4] = { 0, 0, 1, 1 };
          for (int k = 0; k < 4; ++k)
          {
            std::array<int, 3> g;
            g[a] = side * n[a];
            g[b] = i + di[k];
            g[c] = j + dj[k];
            q[k] = id(g);
          }
          if (side == 0)
          {
            std::swap(q[1], q[3]);
          }
          tri.insert(tri.end(), { q[0], q[1], q[2], q[0], q[2], q[3] });
        }
      }
    }
  }
  return MakeMesh(xyz, tri);
}

/// A closed thin box 2 x 2 x `thickness` centred at the origin, about `n` quads per unit.
inline vtkSmartPointer<vtkPolyData> MakeThinBox(double thickness, int n)
{
  return MakeDeformedBox(2 * n, 2 * n, 1, [thickness](const double p[3], double x[3]) {
    x[0] = 2 * p[0] - 1;
    x[1] = 2 * p[1] - 1;
    x[2] = (p[2] - 0.5) * thickness;
  });
}

/// A closed thin disc of radius 1 and the given thickness (a square plate mapped to a disc).
inline vtkSmartPointer<vtkPolyData> MakeThinDisc(double thickness, int n)
{
  return MakeDeformedBox(2 * n, 2 * n, 1, [thickness](const double p[3], double x[3]) {
    const double u = 2 * p[0] - 1, v = 2 * p[1] - 1;
    x[0] = u * std::sqrt(1 - 0.5 * v * v);
    x[1] = v * std::sqrt(1 - 0.5 * u * u);
    x[2] = (p[2] - 0.5) * thickness;
  });
}

/**
 * A closed sheet of the given thickness, 2 long, folded over by 180 degrees around a fold of
 * radius `bend` (mid-surface), so that its two halves lie parallel at 2 * bend apart: a gap of
 * 2 * bend - thickness between them.
 */
inline vtkSmartPointer<vtkPolyData> MakeFoldedSheet(double thickness, double bend, int n)
{
  const double flat = 1.0, arc = 3.14159265358979 * bend, length = 2 * flat + arc;
  const int nl = std::max(4, static_cast<int>(std::ceil(length * n)));
  return MakeDeformedBox(nl, n, 1, [=](const double p[3], double x[3]) {
    const double s = p[0] * length, z = (p[2] - 0.5) * thickness;
    double c[2], nn[2]; // mid-curve and its normal in the xz plane
    if (s <= flat)
    {
      c[0] = s;
      c[1] = 0;
      nn[0] = 0;
      nn[1] = 1;
    }
    else if (s <= flat + arc)
    {
      const double t = (s - flat) / bend;
      c[0] = flat + bend * std::sin(t);
      c[1] = bend - bend * std::cos(t);
      nn[0] = -std::sin(t);
      nn[1] = std::cos(t);
    }
    else
    {
      c[0] = flat - (s - flat - arc);
      c[1] = 2 * bend;
      nn[0] = 0;
      nn[1] = -1;
    }
    x[0] = c[0] + z * nn[0];
    x[1] = p[1];
    x[2] = c[1] + z * nn[1];
  });
}

/// A closed torus (ring) of radius R whose tube has radius r, nu x nv quads, outward.
inline vtkSmartPointer<vtkPolyData> MakeRing(double R, double r, int nu, int nv)
{
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  const double pi2 = 2 * 3.14159265358979;
  for (int i = 0; i < nu; ++i)
  {
    for (int j = 0; j < nv; ++j)
    {
      const double u = pi2 * i / nu, v = pi2 * j / nv;
      xyz.insert(xyz.end(),
        { (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
          r * std::sin(v) });
    }
  }
  auto id = [nu, nv](int i, int j) { return vtkIdType((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
  {
    for (int j = 0; j < nv; ++j)
    {
      const vtkIdType a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      tri.insert(tri.end(), { a, b, c, a, c, d });
    }
  }
  return MakeMesh(xyz, tri);
}

/// Random open triangle soup in the unit cube (for invariants that do not need closure).
inline vtkSmartPointer<vtkPolyData> MakeSoup(unsigned seed, int triangles, double size)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> xyz;
  std::vector<vtkIdType> tri;
  for (int t = 0; t < triangles; ++t)
  {
    const double c[3] = { U(rng), U(rng), U(rng) };
    for (int k = 0; k < 3; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        xyz.push_back(c[a] + size * (U(rng) - 0.5));
      }
      tri.push_back(3 * t + k);
    }
  }
  return MakeMesh(xyz, tri);
}

/// Says why `file` cannot be read: one line on stderr, "<file>: <why>".
inline void ReportUnreadable(const std::string& file, const std::string& why)
{
  std::fprintf(stderr, "%s: %s\n", file.c_str(), why.c_str());
}

/// True when `file` is a regular, non-empty file that can be opened; otherwise reports why.
inline bool CheckModelFile(const std::string& file)
{
  struct stat st;
  if (file.empty() || stat(file.c_str(), &st) != 0)
  {
    ReportUnreadable(
      file, std::string("cannot open: ") + std::strerror(file.empty() ? ENOENT : errno));
    return false;
  }
  if (S_ISDIR(st.st_mode))
  {
    ReportUnreadable(file, "is a directory, not a model file");
    return false;
  }
  if (!S_ISREG(st.st_mode))
  {
    ReportUnreadable(file, "is not a regular file");
    return false;
  }
  if (st.st_size == 0)
  {
    ReportUnreadable(file, "the file is empty");
    return false;
  }
  if (std::FILE* f = std::fopen(file.c_str(), "rb"))
  {
    std::fclose(f);
    return true;
  }
  ReportUnreadable(file, std::string("cannot open: ") + std::strerror(errno));
  return false;
}

/// Runs a reader; false (and a report) when it throws, e.g. std::bad_alloc for a binary STL
/// whose triangle count lies.
inline bool UpdateReader(vtkAlgorithm* reader, const std::string& file)
{
  try
  {
    reader->Update();
    return true;
  }
  catch (const std::exception& e)
  {
    ReportUnreadable(file, std::string("the reader failed: ") + e.what());
  }
  return false;
}

/**
 * Reads a PLY file (mesh or range scan). vtkPLYFileCheck reads it first: a corrupt file (cut
 * short, counts that lie, indices out of range, ...) or one that VTK 9.1's vtkPLYReader cannot
 * take gives nullptr and one line on stderr, "<file>: <what is wrong and where>", instead of a
 * crash in the reader. nullptr with a line too when the file holds no points.
 */
inline vtkSmartPointer<vtkPolyData> ReadPLY(const std::string& file)
{
  vtkNew<vtkPLYFileCheck> check;
  check->SetFileName(file.c_str());
  if (!check->Check())
  {
    ReportUnreadable(file, check->GetErrorMessage());
    return nullptr;
  }
  if (check->GetNumberOfVertices() == 0)
  {
    ReportUnreadable(file, "the file holds no vertices");
    return nullptr;
  }
  vtkNew<vtkPLYReader> reader;
  reader->SetFileName(file.c_str());
  if (!UpdateReader(reader, file))
  {
    return nullptr;
  }
  if (reader->GetOutput()->GetNumberOfPoints() == 0)
  {
    ReportUnreadable(file, "vtkPLYReader read no points");
    return nullptr;
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->ShallowCopy(reader->GetOutput());
  return pd;
}

/**
 * Reads a model by extension: PLY (checked first, see ReadPLY), STL, OBJ or VTP. STL and OBJ
 * files are checked first too, by plod::CheckSTLFile and plod::CheckOBJFile under the limits of
 * VTK 9.1's readers: a cut, non-finite or out-of-range file gives nullptr and one line,
 * "<file>: <what is wrong and where>", and a warning of the check (faces that are not drawn,
 * ...) one line "warning: <file>: <warning>". nullptr when it cannot be read, with one line on
 * stderr saying why for a missing, empty or unreadable file, a directory, an unknown extension,
 * a reader that throws, or a model without points (VTK's XML reader may print its own errors
 * before it).
 */
inline vtkSmartPointer<vtkPolyData> ReadModel(const std::string& file)
{
  const size_t slash = file.find_last_of('/');
  const size_t dot = file.find_last_of('.');
  std::string ext =
    dot == std::string::npos || (slash != std::string::npos && dot < slash) ? "" : file.substr(dot);
  std::transform(
    ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (!CheckModelFile(file)) // before any reader opens it: a FIFO would block
  {
    return nullptr;
  }
  if (ext == ".ply")
  {
    return ReadPLY(file);
  }
  if (ext == ".stl" || ext == ".obj")
  {
    std::string why;
    std::string warning;
    bool ok = false;
    if (ext == ".stl")
    {
      plod::STLSummary summary;
      ok = plod::CheckSTLFile(file, &why, &summary, plod::VTKSTLReaderLimits());
      warning = summary.Warning;
    }
    else
    {
      plod::OBJSummary summary;
      ok = plod::CheckOBJFile(file, &why, &summary, plod::VTKOBJReaderLimits());
      warning = summary.Warning;
    }
    if (!ok)
    {
      ReportUnreadable(file, why);
      return nullptr;
    }
    if (!warning.empty())
    {
      std::fprintf(stderr, "warning: %s: %s\n", file.c_str(), warning.c_str());
    }
  }
  vtkSmartPointer<vtkAlgorithm> reader;
  if (ext == ".stl")
  {
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(file.c_str());
    reader = r;
  }
  else if (ext == ".obj")
  {
    auto r = vtkSmartPointer<vtkOBJReader>::New();
    r->SetFileName(file.c_str());
    reader = r;
  }
  else if (ext == ".vtp")
  {
    auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    r->SetFileName(file.c_str());
    reader = r;
  }
  else
  {
    ReportUnreadable(file,
      (ext.empty() ? std::string("no file extension") : "unknown model type '" + ext + "'") +
        " (PLY, STL, OBJ or VTP)");
    return nullptr;
  }
  if (!UpdateReader(reader, file))
  {
    return nullptr;
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->ShallowCopy(reader->GetOutputDataObject(0));
  if (pd->GetNumberOfPoints() == 0)
  {
    ReportUnreadable(file, std::string(reader->GetClassName()) + " read no points");
    return nullptr;
  }
  return pd;
}

/**
 * The Stanford bunny range scans listed in `dir`/bun.conf, merged into one point cloud in the
 * common frame (each `bmesh file tx ty tz qx qy qz qw` maps scan points by p' = R(q)^T p + t:
 * the rotation of the conjugate quaternion; with R(q) itself the scans miss the zippered mesh
 * by 16 to 130 mm, with its transpose every scan lies within 0.6 mm of it, median),
 * with a 3-component point array "ScannerPosition": each scan's scanner, taken at (0, 0, 1) m
 * in its own frame (the Cyberware scanner looks down -z at the object near the origin) and
 * moved by the same transform. nullptr when the folder or a scan is missing.
 */
inline vtkSmartPointer<vtkPolyData> ReadBunnyScans(const std::string& dir, int* scans = nullptr)
{
  std::ifstream conf(dir + "/bun.conf");
  if (!conf)
  {
    return nullptr;
  }
  vtkNew<vtkPoints> merged;
  merged->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> scanner;
  scanner->SetName("ScannerPosition");
  scanner->SetNumberOfComponents(3);
  std::string line;
  int count = 0;
  while (std::getline(conf, line))
  {
    std::istringstream is(line);
    std::string kind, file;
    double t[3], q[4];
    if (!(is >> kind) || kind != "bmesh" ||
      !(is >> file >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3]))
    {
      continue;
    }
    auto scan = ReadPLY(dir + "/" + file);
    if (!scan)
    {
      return nullptr;
    }
    // quaternion (x, y, z, w) to rotation matrix
    const double w = q[3], x = q[0], y = q[1], z = q[2];
    const double R[3][3] = { { 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w) },
      { 2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w) },
      { 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y) } };
    auto apply = [&](const double p[3], double out[3]) {
      for (int a = 0; a < 3; ++a)
      {
        out[a] = R[0][a] * p[0] + R[1][a] * p[1] + R[2][a] * p[2] + t[a];
      }
    };
    const double eye[3] = { 0, 0, 1 };
    double eyeWorld[3];
    apply(eye, eyeWorld);
    for (vtkIdType i = 0; i < scan->GetNumberOfPoints(); ++i)
    {
      double p[3], o[3];
      scan->GetPoint(i, p);
      apply(p, o);
      merged->InsertNextPoint(o);
      scanner->InsertNextTuple(eyeWorld);
    }
    ++count;
  }
  if (scans)
  {
    *scans = count;
  }
  if (count == 0)
  {
    return nullptr;
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(merged);
  pd->GetPointData()->AddArray(scanner);
  return pd;
}

/// True when two drawn surfaces hold the same triangle and point counts and the same points,
/// bit for bit (float points, as the patch generator makes them).
inline bool SameDrawing(vtkPolyData* a, vtkPolyData* b)
{
  if (a->GetNumberOfPolys() != b->GetNumberOfPolys() ||
    a->GetNumberOfPoints() != b->GetNumberOfPoints())
  {
    return false;
  }
  auto* pa = a->GetPoints() ? vtkFloatArray::SafeDownCast(a->GetPoints()->GetData()) : nullptr;
  auto* pb = b->GetPoints() ? vtkFloatArray::SafeDownCast(b->GetPoints()->GetData()) : nullptr;
  if (!pa || !pb)
  {
    return !pa && !pb && a->GetNumberOfPoints() == 0;
  }
  return std::memcmp(pa->GetPointer(0), pb->GetPointer(0),
           size_t(3 * a->GetNumberOfPoints()) * sizeof(float)) == 0;
}

} // namespace plodtest

#endif
