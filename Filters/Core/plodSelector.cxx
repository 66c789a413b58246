// SPDX-License-Identifier: BSD-3-Clause
#include "plodSelector.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

namespace plod
{

namespace
{
constexpr double Pi = 3.14159265358979323846;

inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline bool Finite(const double* x, int n)
{
  for (int i = 0; i < n; ++i)
  {
    if (!std::isfinite(x[i]))
    {
      return false;
    }
  }
  return true;
}

/// The integer exponent PositivePower raises to by repeated squaring, or -1 when `power` is
/// not one (std::pow then).
inline int IntegerPower(double power)
{
  return power >= 0 && power <= 65536 && power == std::floor(power) ? int(power) : -1;
}

/// max(0, x1)^e and max(0, x2)^e (at most 1) for an integer exponent `e` (IntegerPower), by
/// repeated squaring, exact and fast, with 0^0 = 1. Two numbers at once: the walks raise both
/// ends of a cone range, and the two chains interleave (measured: the specular powers were the
/// SRCC walk's most expensive line before).
inline void PositivePowers(double x1, double x2, int e, double& r1, double& r2)
{
  double b1 = std::min(1.0, std::max(0.0, x1)), b2 = std::min(1.0, std::max(0.0, x2));
  r1 = 1.0;
  r2 = 1.0;
  for (unsigned bits = unsigned(e); bits; bits >>= 1)
  {
    if (bits & 1u)
    {
      r1 *= b1;
      r2 *= b2;
    }
    b1 *= b1;
    b2 *= b2;
  }
}

/// max(0, x)^power, with 0^0 = 1 so that power 0 makes every cosine term constant. Integer
/// powers up to 2^16 (the usual specular powers) by repeated squaring (PositivePowers).
inline double PositivePower(double x, double power)
{
  x = std::min(1.0, std::max(0.0, x));
  if (power == 1.0)
  {
    return x;
  }
  const int e = IntegerPower(power);
  if (e >= 0)
  {
    double result, same;
    PositivePowers(x, x, e, result, same);
    return result;
  }
  return std::pow(x, power);
}

/// ConeCosineRange with `integerPower` = IntegerPower(power) known to the caller (the walks
/// compute it once a frame).
inline void ConeRange(double cosA, double sinA, double cosT, double sinT, double power,
  double& high, double& low, int integerPower)
{
  // highest: the smallest angle max(0, a - theta); lowest: the largest angle min(pi, a + theta)
  const double cLo = cosA >= cosT ? 1.0 : cosA * cosT + sinA * sinT;
  const double cHi = cosA <= -cosT ? -1.0 : cosA * cosT - sinA * sinT;
  if (integerPower >= 0)
  {
    PositivePowers(cLo, cHi, integerPower, high, low);
    return;
  }
  high = PositivePower(cLo, power);
  low = PositivePower(cHi, power);
}

} // namespace

double ConeCosineSpread(double cosA, double sinA, double cosT, double sinT, double power)
{
  double high, low;
  ConeCosineRange(cosA, sinA, cosT, sinT, power, high, low);
  return std::max(0.0, high - low);
}

void ConeCosineRange(
  double cosA, double sinA, double cosT, double sinT, double power, double& high, double& low)
{
  ConeRange(cosA, sinA, cosT, sinT, power, high, low, -1);
}

bool ChengAccepts(double cosT, double sinT, double rate, double D)
{
  // cos(min(pi, 2 theta)): cos 2theta = cos^2 - sin^2 while theta <= pi/2, else -1
  const double cos2 = cosT > 0 ? cosT * cosT - sinT * sinT : -1.0;
  return cos2 > std::exp(-rate * D);
}

int DistanceLevel(double rootEdge, int finestLevel, double pixelThreshold, double viewAngle,
  double distance, double pixels)
{
  // Wang & Sato: the coarsest level whose cell edge l_L = S / 2^L is at most
  // 2 n0 sin(theta / 2) D / N.
  const double limit = 2.0 * pixelThreshold * std::sin(0.5 * viewAngle) * distance / pixels;
  if (!(limit > 0))
  {
    return finestLevel + 1;
  }
  for (int level = 0; level <= finestLevel; ++level)
  {
    if (std::ldexp(rootEdge, -level) <= limit)
    {
      return level;
    }
  }
  return finestLevel + 1;
}

bool ValidateSelectionInput(const SelectionInput& in, std::string* why)
{
  auto fail = [why](const std::string& text) {
    if (why)
    {
      *why = text;
    }
    return false;
  };
  auto number = [](double x) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", x);
    return std::string(text);
  };
  if (!Finite(in.Eye, 3))
  {
    return fail("the eye position is not finite");
  }
  if (in.UseFrustum && !Finite(&in.Planes[0][0], 24))
  {
    return fail("a frustum plane is not finite");
  }
  if (!(in.PixelScale > 0) || !std::isfinite(in.PixelScale))
  {
    return fail("the screen distance (or pixels per unit) must be positive and finite");
  }
  if (in.Parallel &&
    !(Dot(in.ProjectionDirection, in.ProjectionDirection) > 0 && Finite(in.ProjectionDirection, 3)))
  {
    return fail("the projection direction is not a finite non-zero vector");
  }
  if (!(in.ContourTolerance >= 0) || !(in.BrightnessTolerance >= 0) || !(in.TopologyTolerance >= 0))
  {
    return fail("tolerances must be non-negative numbers");
  }
  if (!(in.SpecularPower >= 0) || !std::isfinite(in.SpecularPower) || !std::isfinite(in.Diffuse) ||
    !std::isfinite(in.Specular))
  {
    return fail("material values must be finite (specular power >= 0)");
  }
  // reflectances are fractions of the light: a negative one would make a brightness change
  // negative, and the criterion would accept what it must refine
  if (!(in.Diffuse >= 0 && in.Diffuse <= 1) || !(in.Specular >= 0 && in.Specular <= 1))
  {
    return fail("the diffuse and specular reflectances must be in [0, 1] (got diffuse " +
      number(in.Diffuse) + ", specular " + number(in.Specular) + ")");
  }
  for (size_t i = 0; i < in.Lights.size(); ++i)
  {
    const SelectorLight& l = in.Lights[i];
    if (!Finite(l.Position, 3) || !std::isfinite(l.Diffuse) || !std::isfinite(l.Specular))
    {
      return fail("a light has a non-finite position, direction or intensity");
    }
    if (l.Diffuse < 0 || l.Specular < 0)
    {
      return fail("light " + std::to_string(i) + " has a negative intensity (diffuse " +
        number(l.Diffuse) + ", specular " + number(l.Specular) + "); intensities must be >= 0");
    }
  }
  if (!Finite(&in.MotionA[0][0], 9) || !Finite(in.MotionB, 3))
  {
    return fail("the motion is not finite");
  }
  if (std::isnan(in.VelocityFactor) || in.VelocityFactor < 1)
  {
    return fail("the velocity factor must be >= 1");
  }
  // a zero or negative factor would turn the 'accept nothing' of a zero tolerance (-1) into 0 or
  // a positive tolerance on features
  if (!(in.PSECFactor > 0) || !std::isfinite(in.PSECFactor))
  {
    return fail("the PSEC factor must be positive and finite");
  }
  if (!std::isfinite(in.FoveationRate) || !Finite(in.FoveationPoint, 3) ||
    !Finite(in.FoveationUp, 3) || !Finite(in.GazeDirection, 3) || !Finite(in.FoveationCentre, 3) ||
    !(in.FoveationHeight > 0))
  {
    return fail("foveation parameters must be finite (height > 0)");
  }
  if (in.MinimumLevel < 0 || in.MinimumLevel > MaxFinestLevel)
  {
    return fail("the minimum level must be in [0, 21]");
  }
  return true;
}

namespace
{
constexpr double Infinite = std::numeric_limits<double>::infinity();
constexpr uint8_t AllPlanes = 0x3f;

/// How far an error exceeds its tolerance: error / tolerance. A tolerance of 0 (written -1 by
/// the walk: it accepts nothing) is exceeded infinitely.
inline double Over(double error, double tolerance)
{
  return tolerance > 0 ? error / tolerance : Infinite;
}

/// Cheng §2 as an error over a tolerance: the cell's largest normal deviation 1 - cos(min(pi,
/// 2 theta)) = 2 sin^2 theta (2 for a cone wider than pi/2) over the deviation the threshold
/// allows, 1 - exp(-K D). At least 1 where ChengAccepts refuses; infinite at the fovea.
inline double ChengExcess(double cosT, double sinT, double rate, double D)
{
  const double deviation = cosT > 0 ? 2.0 * sinT * sinT : 2.0;
  const double allowed = -std::expm1(-rate * D);
  return allowed > 0 ? deviation / allowed : Infinite;
}

/// What the per-cell tests (steps 1-4 and the rules of the file documentation) decide for one
/// cell. Both walks follow it, so they cannot decide differently.
enum class Verdict : uint8_t
{
  Hide,  ///< in the cut, not drawn (culled or back-facing)
  Draw,  ///< in the cut, drawn at its representative vertex
  Refine ///< the tolerances refine it (a leaf is opened)
};

/// 12 bytes, the priority in single precision (as the budget's queue keeps it). At 24 bytes
/// (a double priority), the copy of a decision out of the interval path of screen foveation was
/// the foveated walk's hottest instruction: a 16-byte load of fields just stored a byte at a
/// time. Measured: the foveated walk 5 % faster at 12 bytes, the others unchanged
/// (docs/benchmarks.md).
struct Decision
{
  Verdict What;
  uint8_t Reason;      ///< Hide, Draw: the CutReason
  uint8_t Outside;     ///< Hide by the frustum: the planes the cell lies wholly outside
  bool BrightnessOnly; ///< Refine: its children are tested for brightness only
  bool Floor;          ///< Refine: minimum level or eye inside: refined whatever the budget
  bool Topology;       ///< Refine: only because it is not topologically safe
  bool Factor;         ///< the foveation factor was computed (SelectionStats::FoveationFactors)
  float Priority;      ///< Refine, when asked for: how far its error exceeds its tolerance
};
static_assert(sizeof(Decision) == 12, "a decision is 12 bytes (see above)");

/// A priority in single precision, as the budget's queue orders it: a non-negative number
/// (whose bits order as it does); NaN or beyond float's range: infinite.
inline float QueuePriority(double priority)
{
  return !(priority < std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity()
    : priority > 0                                       ? static_cast<float>(priority)
                                                         : 0.0f;
}

inline Decision Hide(CutReason reason, uint8_t outside)
{
  return { Verdict::Hide, uint8_t(reason), outside, false, false, false, false, 0.0f };
}

inline Decision Draw(CutReason reason)
{
  return { Verdict::Draw, uint8_t(reason), 0, false, false, false, false, 0.0f };
}

inline Decision Refine(bool brightnessOnly, double priority, bool topology = false)
{
  return { Verdict::Refine, ReasonNone, 0, brightnessOnly, false, topology, false,
    QueuePriority(priority) };
}

inline Decision Floor(bool brightnessOnly)
{
  return { Verdict::Refine, ReasonNone, 0, brightnessOnly, true, false, false,
    std::numeric_limits<float>::infinity() };
}

/**
 * The error model a frame's walk decides with, chosen once per frame (MakeFrame) from the
 * selection's modes: each walk is instantiated for each policy (WithPolicy), so the per-cell
 * decision holds only its own model's tests.
 * - SRCC: contour and brightness (with TMM's micro motion, the velocity factor or foveation);
 * - Baseline: SCVC, PSEC or distance levels;
 * - VelocityAlone: IPV and DPV as TMM §5.3 defines them (whatever the error model);
 * - Cheng: Cheng's own foveated curvature test (not under velocity alone).
 */
enum class Policy : uint8_t
{
  SRCC,
  Baseline,
  VelocityAlone,
  Cheng
};

template <Policy P>
using PolicyTag = std::integral_constant<Policy, P>;

/// Calls `walk` with the tag of `policy` (a std::integral_constant): the one place the
/// per-frame choice becomes a type.
template <class Walk>
inline auto WithPolicy(Policy policy, Walk&& walk)
{
  switch (policy)
  {
    case Policy::Baseline:
      return walk(PolicyTag<Policy::Baseline>());
    case Policy::VelocityAlone:
      return walk(PolicyTag<Policy::VelocityAlone>());
    case Policy::Cheng:
      return walk(PolicyTag<Policy::Cheng>());
    case Policy::SRCC:
    default:
      return walk(PolicyTag<Policy::SRCC>());
  }
}

/// What one frame's walk needs besides the cell: the input and the modes derived from it.
struct Frame
{
  const OctreeView& V;
  const SelectionInput& In;
  const ZeroPages<uint64_t>* Cones; // Selector::Cones (see ConeSinCos)
  Policy Model;
  bool Micro;
  double Velocity;
  double Dop[3];
  bool AnySpecular;
  /// IntegerPower(specular power): the exponent's checks made once a frame
  int SpecularExponent;
  /// Cell edge per level (RootEdge / 2^level, exact).
  double Edge[MaxFinestLevel + 1];
  /// Per frustum plane and axis: 1 where the normal's component is positive, else 0. The corner
  /// of a cell [lo, lo + h]^3 farthest along the normal is lo + h PlaneUp, the nearest
  /// lo + h (1 - PlaneUp) (exact: h times 0 or 1).
  double PlaneUp[6][3];
  /// The lights, prepared once a frame (the selector's storage, kept from frame to frame).
  using Light = detail::PreparedLight;
  const std::vector<Light>& Lights;
  /// Screen foveation's table (FoveaTable), or null: the factor is computed at every cell.
  const double* Fovea = nullptr;
  /// The gaze direction as a unit vector (with Fovea).
  double Gaze[3] = { 0, 0, 0 };
  /// The budget walk counts only the owned triangles the patch generator can draw
  /// (CountDrawable): back faces are culled (HideBackFaces) or points are ghosts.
  bool CountDrawn = false;
  /// The reads of refinements (Selector::SetPageLoader), or null: every refinement is made.
  PageLoader* Pages = nullptr;
  int PageRequester = 0; // who asks (PageLoader::AddRequester)
  /// With Pages: every refinement is made and read in the frame (the first view), none asked
  /// for.
  bool WaitForPages = false;
};

/**
 * Screen foveation multiplies a cell's tolerances by exp(K D), D = theta / pi, theta the angle
 * between its view ray and the gaze: an arctangent and an exponential at every cell, a third
 * of the foveated walk's time (perf). Yet a decision compares errors against those tolerances, and
 * most errors are far from them. So the walk first bounds the factor: with w = sin(theta / 2) =
 * sqrt((1 - cos theta) / 2) (one square root of the cosine it has), exp(K 2 asin(w) / pi) is
 * monotone in w, and FoveaSize + 1 values of it at w = j / FoveaSize bound it on each interval.
 * The cell's index is widened by one interval on each side (w's rounding is far smaller), and
 * the bounds by a relative 1e-12 (the exponential's and the arctangent's own rounding). Each
 * test is made at both ends of the range; only when they disagree is the factor computed, and
 * the decision made again with it: the cut is the exact one, to the bit. Measured on the
 * benchmark scene (docs/benchmarks.md). Built for one rate at a time; |K| <= FoveaMaxRate (the
 * table's values stay finite), a finite velocity factor and a non-zero gaze, else every cell
 * computes its factor.
 */
constexpr int FoveaSize = 1024;
constexpr double FoveaMaxRate = 512;

/// Fills `table` for the rate `rate`: for each interval j of w, the bounds of the factor over
/// the intervals j - 1 to j + 1 (the index widened by one on each side), widened by a relative
/// 1e-12, as the pair (low, high) at 2 j (one load a cell, nothing else to compute).
void FillFoveaTable(double rate, std::vector<double>& table)
{
  std::vector<double> at(FoveaSize + 1); // the factor at w = i / FoveaSize
  for (int i = 0; i <= FoveaSize; ++i)
    at[i] = std::exp(rate * 2.0 * std::asin(double(i) / FoveaSize) / Pi);
  table.resize(2 * FoveaSize);
  for (int j = 0; j < FoveaSize; ++j)
  {
    const double a = at[std::max(0, j - 1)], b = at[std::min(FoveaSize, j + 2)];
    table[2 * j] = std::min(a, b) * (1.0 - 1e-12);
    table[2 * j + 1] = std::max(a, b) * (1.0 + 1e-12);
  }
}

/// The range [range[0], range[1]] of the foveation factor exp(K D) of a cell whose view ray
/// makes the angle theta with the gaze, cos theta = `u` (the factor foveate() computes lies
/// within it).
inline void FoveaRange(const Frame& f, double u, double range[2])
{
  // w = sqrt((1 - u) / 2); w above 1 by rounding: the last interval
  const double w = std::sqrt(std::max(0.0, 0.5 * (1.0 - u)));
  const int j = std::min(FoveaSize - 1, static_cast<int>(w * FoveaSize));
  range[0] = f.Fovea[2 * j];
  range[1] = f.Fovea[2 * j + 1];
}

/// The unit vector from `x` to the light `l` in `vl`; returns the distance (directional: the
/// given direction's length). 0: the light is on `x` (or has no direction), `vl` is not a unit
/// vector.
inline double ToLight(const Frame::Light& l, const double x[3], double vl[3])
{
  for (int a = 0; a < 3; ++a)
    vl[a] = l.P[a]; // directional: already a unit vector
  if (!l.Positional)
    return l.Length;
  for (int a = 0; a < 3; ++a)
    vl[a] -= x[a];
  const double ll = std::sqrt(Dot(vl, vl));
  for (int a = 0; a < 3 && ll > 0; ++a)
    vl[a] /= ll;
  return ll;
}

/**
 * The sine and cosine of node n's cone angle (as std::sin and std::cos of the float give them),
 * computed when the node is first judged and kept in frame.Cones: both floats' bits in one
 * 64-bit word, 0 until computed (never 0 once computed: the sine and cosine of an angle are
 * never both zero). Walks judging in parallel may compute the same node twice: they store the
 * same word, atomically.
 */
inline void ConeSinCos(const Frame& f, int64_t n, float& sinT, float& cosT)
{
  uint64_t& slot = (*f.Cones)[n];
  uint64_t packed = __atomic_load_n(&slot, __ATOMIC_RELAXED);
  uint32_t sinBits = uint32_t(packed), cosBits = uint32_t(packed >> 32);
  if (packed == 0)
  {
    sinT = std::sin(f.V.ConeAngle[n]);
    cosT = std::cos(f.V.ConeAngle[n]);
    std::memcpy(&sinBits, &sinT, sizeof(float));
    std::memcpy(&cosBits, &cosT, sizeof(float));
    __atomic_store_n(&slot, uint64_t(sinBits) | uint64_t(cosBits) << 32, __ATOMIC_RELAXED);
    return;
  }
  std::memcpy(&sinT, &sinBits, sizeof(float));
  std::memcpy(&cosT, &cosBits, sizeof(float));
}

/// The frame's constants; `lights` receives the prepared lights (its capacity is kept).
Frame MakeFrame(const OctreeView& v, const SelectionInput& in, const ZeroPages<uint64_t>* cones,
  std::vector<detail::PreparedLight>& lights, detail::FoveaTable* fovea = nullptr)
{
  const bool micro = in.Motion == MotionModel::MicroMotion;
  const double velocity =
    (in.Motion == MotionModel::InverseVelocity || in.Motion == MotionModel::DirectVelocity)
    ? in.VelocityFactor
    : 1.0;
  // IPV and DPV as TMM §5.3 defines them: velocity alone sets one screen-space resolution
  const bool velocityAlone =
    (in.Motion == MotionModel::InverseVelocity || in.Motion == MotionModel::DirectVelocity) &&
    in.Velocity == VelocityCriterion::Alone;
  const bool cheng = in.Error == ErrorModel::Cheng && !velocityAlone;
  const Policy model = cheng       ? Policy::Cheng
    : velocityAlone                ? Policy::VelocityAlone
    : in.Error == ErrorModel::SRCC ? Policy::SRCC
                                   : Policy::Baseline;
  Frame f{ v, in, cones, model, micro, velocity, { 0, 0, -1 }, false,
    IntegerPower(in.SpecularPower), {}, {}, lights };
  lights.clear();
  if (in.Parallel)
  {
    const double l = std::sqrt(Dot(in.ProjectionDirection, in.ProjectionDirection));
    for (int a = 0; a < 3; ++a)
      f.Dop[a] = in.ProjectionDirection[a] / l;
  }
  for (const SelectorLight& l : in.Lights)
  {
    f.AnySpecular = f.AnySpecular || l.Specular > 0;
    detail::PreparedLight p{ l.Positional, { l.Position[0], l.Position[1], l.Position[2] }, 1.0,
      l.Diffuse, l.Specular };
    if (!l.Positional)
    {
      p.Length = std::sqrt(Dot(l.Position, l.Position));
      for (int a = 0; a < 3 && p.Length > 0; ++a)
        p.P[a] /= p.Length;
    }
    lights.push_back(p);
  }
  for (int level = 0; level <= MaxFinestLevel; ++level)
    f.Edge[level] = v.CellEdge(level);
  f.CountDrawn = in.TriangleBudget > 0 && (in.HideBackFaces || v.PointGhost != nullptr);
  for (int p = 0; p < 6; ++p)
    for (int a = 0; a < 3; ++a)
      f.PlaneUp[p][a] = in.Planes[p][a] > 0 ? 1.0 : 0.0;
  // screen foveation's table (FoveaTable), where it bounds the factor
  const bool table = fovea && in.Foveation == FoveationMode::Screen && !cheng &&
    std::isfinite(velocity) && std::abs(in.FoveationRate) <= FoveaMaxRate;
  const double gaze = table ? std::sqrt(Dot(in.GazeDirection, in.GazeDirection)) : 0.0;
  if (table && gaze > 0 && std::isfinite(gaze))
  {
    if (fovea->Values.empty() || fovea->Rate != in.FoveationRate)
    {
      FillFoveaTable(in.FoveationRate, fovea->Values);
      fovea->Rate = in.FoveationRate;
    }
    f.Fovea = fovea->Values.data();
    for (int a = 0; a < 3; ++a)
      f.Gaze[a] = in.GazeDirection[a] / gaze;
  }
  return f;
}

/// A tolerance at the two ends of the factor's range (equal when the factor is known exactly).
struct Bounds
{
  double Lo, Hi;
  Bounds Scaled(double s) const { return { this->Lo * s, this->Hi * s }; }
};

/**
 * The factor of a cell's tolerances (velocity and foveation), known exactly or known to lie in
 * [Lo, Hi] (screen foveation's table, FoveaTable). A test `x <= T` or `x > T` decides at the low
 * end; over an interval, Ambiguous records that the high end would decide otherwise (both
 * tests are monotone in T), and the walk then computes the factor and judges the cell again.
 */
template <bool IsInterval>
struct ToleranceFactor
{
  double Lo, Hi;
  bool Ambiguous = false;

  /// Tolerance `t` times the factor; a tolerance of 0 accepts nothing (not even an error of
  /// exactly 0): -1.
  Bounds Of(double t) const
  {
    return t > 0 ? Bounds{ t * this->Lo, t * this->Hi } : Bounds{ -1.0, -1.0 };
  }
  /// `t` times the factor, whatever its sign.
  Bounds Times(double t) const { return { t * this->Lo, t * this->Hi }; }
  bool AtMost(double x, const Bounds& t)
  {
    const bool r = x <= t.Lo;
    if constexpr (IsInterval)
      this->Ambiguous = this->Ambiguous || r != (x <= t.Hi);
    return r;
  }
  bool Above(double x, const Bounds& t)
  {
    const bool r = x > t.Lo;
    if constexpr (IsInterval)
      this->Ambiguous = this->Ambiguous || r != (x > t.Hi);
    return r;
  }
};

/// What the decisions read of one cell seen from the eye.
struct CellView
{
  int32_t N;
  int Level;
  double H;            // edge
  double X[3];         // vertex
  double Axis[3];      // cone axis
  double Ve[3];        // unit vector from the vertex to the eye (parallel: -direction)
  double ToEye[3];     // perspective: eye - vertex
  double Inverse;      // perspective: 1 / |eye - vertex|
  double K;            // pixels per unit length at the vertex
  double C;            // axis . ve
  double CosT, SinT;   // the cone's half angle
  double Motion[3];    // v_f = A v + b at the vertex (micro motion), else 0
  bool BrightnessOnly; // the parent's contour decision holds for it
};

/// D, the cell's normalised distance from the point of interest (Cheng's object mode) or from
/// the gaze (screen mode); 0 with foveation off.
inline double FoveationDistance(const Frame& f, const CellView& cell)
{
  const SelectionInput& in = f.In;
  if (in.Foveation == FoveationMode::Off)
    return 0.0;
  if (in.Foveation == FoveationMode::Object)
  {
    const double* up = in.FoveationUp;
    double r[3], fp[3];
    for (int a = 0; a < 3; ++a)
    {
      r[a] = cell.X[a] - in.FoveationCentre[a];
      fp[a] = in.FoveationPoint[a] - in.FoveationCentre[a];
    }
    const double y = Dot(r, up), fy = Dot(fp, up);
    for (int a = 0; a < 3; ++a)
    {
      r[a] -= y * up[a];
      fp[a] -= fy * up[a];
    }
    const double c[3] = { r[1] * fp[2] - r[2] * fp[1], r[2] * fp[0] - r[0] * fp[2],
      r[0] * fp[1] - r[1] * fp[0] };
    const double beta =
      (Dot(r, r) > 0 && Dot(fp, fp) > 0) ? std::atan2(std::sqrt(Dot(c, c)), Dot(r, fp)) : 0.0;
    return in.FoveationWeights[0] * beta / Pi +
      in.FoveationWeights[1] * std::abs(y - fy) / in.FoveationHeight;
  }
  const double* g = in.GazeDirection;
  const double ray[3] = { -cell.Ve[0], -cell.Ve[1], -cell.Ve[2] };
  const double c[3] = { ray[1] * g[2] - ray[2] * g[1], ray[2] * g[0] - ray[0] * g[2],
    ray[0] * g[1] - ray[1] * g[0] };
  return std::atan2(std::sqrt(Dot(c, c)), Dot(ray, g)) / Pi;
}

/// The shape error in pixels: the shape error less the motion along the axis, projected.
inline double ContourError(const Frame& f, const CellView& cell)
{
  return std::max(0.0, double(f.V.ShapeError[cell.N]) - std::abs(Dot(cell.Axis, cell.Motion))) *
    cell.K;
}

/// The cosine between the cell's cone axis and the half vector of the unit directions to the
/// light `vl` and to the eye (Blinn's H, of the specular term and of PSEC's highlight test);
/// false where the two directions are opposite (no half vector).
inline bool AxisHalfVectorCosine(const CellView& cell, const double vl[3], double& cosine)
{
  double hv[3];
  for (int a = 0; a < 3; ++a)
    hv[a] = vl[a] + cell.Ve[a];
  const double hl = std::sqrt(Dot(hv, hv));
  if (!(hl > 0))
    return false;
  cosine = Dot(cell.Axis, hv) / hl;
  return true;
}

/**
 * The shading error (SRCC eq. 7-10, TMM eq. 11-13) in brightness x pixels: the brightness range
 * dB of the cell's cone under the lights (at most 1, a rendered pixel's range), times its
 * projected size, reduced by the motion across the view.
 */
inline double ShadingError(const Frame& f, const CellView& cell)
{
  const OctreeView& v = f.V;
  const SelectionInput& in = f.In;
  const int32_t n = cell.N;
  double dB = 0;
  if (!in.Lights.empty())
  {
    // TMM eq. (9): the octree's (min, max) reflectances; one material: min = max
    const double MdMin = in.UseOctreeMaterial ? v.DiffuseRange[2 * n] : in.Diffuse;
    const double MdMax = in.UseOctreeMaterial ? v.DiffuseRange[2 * n + 1] : in.Diffuse;
    const double MsMin = in.UseOctreeMaterial ? v.SpecularRange[2 * n] : in.Specular;
    const double MsMax = in.UseOctreeMaterial ? v.SpecularRange[2 * n + 1] : in.Specular;
    for (const Frame::Light& l : f.Lights)
    {
      if (dB >= 1.0)
      {
        break; // a rendered pixel saturates at 1: no cell can vary by more (see below)
      }
      double vl[3];
      const double ll = ToLight(l, cell.X, vl);
      if (!(ll > 0))
      {
        // a light on the vertex lights every direction: the largest variation
        dB += MdMax * l.Diffuse + MsMax * l.Specular;
        continue;
      }
      double high, low;
      if (MdMax > 0 && l.Diffuse > 0)
      {
        const double ca = Dot(cell.Axis, vl);
        ConeRange(
          ca, std::sqrt(std::max(0.0, 1 - ca * ca)), cell.CosT, cell.SinT, 1.0, high, low, -1);
        dB += BrightnessChange(MdMin, MdMax, l.Diffuse, high, low);
      }
      if (MsMax > 0 && l.Specular > 0)
      {
        high = 1.0; // light opposite the eye: no defined half vector
        low = 0.0;
        double cb;
        if (AxisHalfVectorCosine(cell, vl, cb))
        {
          ConeRange(cb, std::sqrt(std::max(0.0, 1 - cb * cb)), cell.CosT, cell.SinT,
            in.SpecularPower, high, low, f.SpecularExponent);
        }
        dB += BrightnessChange(MsMin, MsMax, l.Specular, high, low);
      }
    }
  }
  // The rendered brightness saturates at 1, so a cell's visible variation is at most 1 however
  // many bright lights add up (1,000 lights of intensity 1 took 26 s a selection: every cell
  // refined to the finest level, every light summed at every node).
  dB = std::min(dB, 1.0);
  // projected cell size, reduced by the motion across the view (v_d: n projected on the
  // plane normal to v_e; zero when n is parallel to v_e)
  double size = cell.H * std::max(0.0, cell.C);
  if (f.Micro)
  {
    double vd[3];
    for (int a = 0; a < 3; ++a)
      vd[a] = cell.Axis[a] - cell.C * cell.Ve[a];
    const double vdl = std::sqrt(Dot(vd, vd));
    if (vdl > 1e-12)
      size = std::max(0.0, size - std::abs(Dot(vd, cell.Motion)) / vdl);
  }
  return dB * size * cell.K;
}

/// PSEC's feature test: the cell is on the contour, or a specular highlight may lie in it.
inline bool PSECFeature(const Frame& f, const CellView& cell)
{
  bool feature = !(cell.CosT > 0 && (cell.C > cell.SinT || cell.C < -cell.SinT));
  for (size_t i = 0; i < f.Lights.size() && !feature && f.AnySpecular; ++i)
  {
    const Frame::Light& l = f.Lights[i];
    if (l.Specular <= 0)
      continue;
    double vl[3];
    const double ll = ToLight(l, cell.X, vl);
    if (!(ll > 0))
      return true;
    double cb;
    feature = AxisHalfVectorCosine(cell, vl, cb) && cb >= cell.CosT;
  }
  return feature;
}

/// The floors every tolerance model shares: whether a cell that is not a union of discs is
/// thicker than its tolerance (it is then refined: the part it could make vanish shows), and
/// whether its edge projects within the contour tolerance (it cannot show more than that).
struct Floors
{
  bool Unsafe;
  bool SizeWithin;
  bool Small; // within the size floor and safe
};

template <bool IsInterval>
inline Floors JudgeFloors(
  const Frame& f, const CellView& cell, ToleranceFactor<IsInterval>& factor, const Bounds& Ts)
{
  const OctreeView& v = f.V;
  // its tolerance follows motion and foveation like the others: DPV's infinite factor still
  // accepts the root alone
  const bool unsafe = !(v.Flags[cell.N] & NodeTopologySafe) &&
    factor.Above(double(v.Thickness[cell.N]) * cell.K, factor.Times(f.In.TopologyTolerance));
  const bool sizeWithin = Ts.Lo >= 0 && factor.AtMost(cell.H * cell.K, Ts);
  return { unsafe, sizeWithin, sizeWithin && !unsafe };
}

/// IPV and DPV as TMM §5.3 defines them: velocity alone sets the resolution, through the size
/// floor.
template <bool WithPriority>
inline Decision JudgeVelocityAlone(const CellView& cell, const Floors& floors, const Bounds& Ts)
{
  if (floors.Small)
    return Draw(AcceptedSize);
  return Refine(false,
    WithPriority ? (floors.Unsafe ? Infinite : Over(cell.H * cell.K, Ts.Lo)) : 0.0,
    floors.SizeWithin);
}

/// The baselines: SCVC (the shape error against the contour tolerance everywhere), PSEC (a
/// tighter tolerance on features), distance levels (Wang & Sato).
template <bool WithPriority, bool IsInterval>
inline Decision JudgeBaseline(const Frame& f, const CellView& cell,
  ToleranceFactor<IsInterval>& factor, const Floors& floors, const Bounds& Ts)
{
  const SelectionInput& in = f.In;
  if (in.Error == ErrorModel::Distance)
  {
    if (cell.Level >= in.DistanceLevel && !floors.Unsafe)
      return Draw(AcceptedError);
    // the cell's edge over the edge of the level Wang & Sato chose
    return Refine(false,
      WithPriority ? (floors.Unsafe ? Infinite : std::ldexp(1.0, in.DistanceLevel - cell.Level))
                   : 0.0);
  }
  if (floors.Small)
    return Draw(AcceptedSize);
  const Bounds tol =
    in.Error == ErrorModel::PSEC && PSECFeature(f, cell) ? Ts.Scaled(in.PSECFactor) : Ts;
  const double err = ContourError(f, cell);
  const bool within = factor.AtMost(err, tol);
  if (within && !floors.Unsafe)
    return Draw(AcceptedError);
  return Refine(false, WithPriority ? (floors.Unsafe ? Infinite : Over(err, tol.Lo)) : 0.0, within);
}

/// SRCC (with TMM's motion): the contour (eq. 4-5, TMM eq. 6-7), then the brightness (eq. 7-10,
/// TMM eq. 11-13). Back faces were decided before (Judge, step 2a).
template <bool WithPriority, bool IsInterval>
inline Decision JudgeSRCC(const Frame& f, const CellView& cell, ToleranceFactor<IsInterval>& factor,
  const Floors& floors, const Bounds& Ts)
{
  const OctreeView& v = f.V;
  const Bounds Tb = factor.Of(f.In.BrightnessTolerance);
  // a refinement for the contour (or a rim) is ranked by the larger of its errors over their
  // tolerances: the contour's and the brightness'. The brightness error is at most
  // h max(0, c) k (dB <= 1, motion only shrinks the size): when that bound cannot exceed the
  // contour's ratio, the shading is not computed (measured: 30 % more ConeCosineRange calls)
  auto contourPriority = [&](double overContour) {
    if (floors.Unsafe || !(Tb.Lo > 0))
      return Infinite;
    if (cell.H * std::max(0.0, cell.C) * cell.K <= overContour * Tb.Lo)
      return overContour;
    return std::max(overContour, Over(ShadingError(f, cell), Tb.Lo));
  };
  CutReason accepted = AcceptedBrightness;
  if (!cell.BrightnessOnly)
  {
    if (floors.Small)
    {
      return Draw(AcceptedSize);
    }
    // an open surface's rim is a silhouette from every side: refined like the contour, until
    // its edge passes the size floor
    if (v.Flags[cell.N] & NodeBoundary)
    {
      return Refine(false, WithPriority ? contourPriority(Over(cell.H * cell.K, Ts.Lo)) : 0.0);
    }
    if (!(cell.CosT > 0 && cell.C > cell.SinT))
    {
      const double err = ContourError(f, cell);
      if (factor.Above(err, Ts))
      {
        return Refine(false, WithPriority ? contourPriority(Over(err, Ts.Lo)) : 0.0);
      }
      accepted = AcceptedContour;
    }
  }
  if (floors.Unsafe)
  {
    return Refine(cell.BrightnessOnly, Infinite, true);
  }
  const double shadingError = ShadingError(f, cell);
  if (factor.AtMost(shadingError, Tb))
    return Draw(accepted);
  return Refine(true, WithPriority ? Over(shadingError, Tb.Lo) : 0.0);
}

/// The decisions that read the tolerances, by error model, for the factor `factor`.
template <Policy P, bool WithPriority, bool IsInterval>
[[gnu::always_inline]] inline Decision JudgeTolerances(
  const Frame& f, const CellView& cell, ToleranceFactor<IsInterval>& factor)
{
  const Bounds Ts = factor.Of(f.In.ContourTolerance);
  const Floors floors = JudgeFloors(f, cell, factor, Ts);
  if constexpr (P == Policy::VelocityAlone)
    return JudgeVelocityAlone<WithPriority>(cell, floors, Ts);
  else if constexpr (P == Policy::Baseline)
    return JudgeBaseline<WithPriority>(f, cell, factor, floors, Ts);
  else
    return JudgeSRCC<WithPriority>(f, cell, factor, floors, Ts);
}

/// Cheng §2 alone: curvature against the foveated threshold exp(-K D).
template <bool WithPriority>
inline Decision JudgeCheng(const Frame& f, const CellView& cell)
{
  const SelectionInput& in = f.In;
  const double D = FoveationDistance(f, cell);
  Decision d = ChengAccepts(cell.CosT, cell.SinT, in.FoveationRate, D)
    ? Draw(AcceptedError)
    : Refine(false, WithPriority ? ChengExcess(cell.CosT, cell.SinT, in.FoveationRate, D) : 0.0);
  d.Factor = in.Foveation != FoveationMode::Off;
  return d;
}

/// The tolerance models (SRCC, the baselines, velocity alone) with the cell's motion and its
/// tolerance factor (velocity times foveation): bounded by screen foveation's table where it
/// decides, else computed.
template <Policy P, bool WithPriority>
[[gnu::always_inline]] inline Decision JudgeWithFactor(const Frame& f, CellView& cell)
{
  const SelectionInput& in = f.In;
  // v_f = A v + b (micro motion)
  for (int a = 0; a < 3; ++a)
    cell.Motion[a] = f.Micro ? in.MotionA[a][0] * cell.X[0] + in.MotionA[a][1] * cell.X[1] +
        in.MotionA[a][2] * cell.X[2] + in.MotionB[a]
                             : 0.0;
  if (!WithPriority && f.Fovea)
  {
    // screen foveation: the factor's range from the table, without the angle and exponential;
    // exact only when some test falls inside the range (rare: see FoveaTable). cos theta
    // between the view ray (-ve) and the gaze; in perspective from toEye, not ve: the dot
    // product does not wait for the division (the index only needs to be within one interval)
    const double gazeCos =
      in.Parallel ? Dot(f.Dop, f.Gaze) : -Dot(cell.ToEye, f.Gaze) * cell.Inverse;
    double range[2];
    FoveaRange(f, gazeCos, range);
    ToleranceFactor<true> bounded{ f.Velocity * range[0], f.Velocity * range[1] };
    const Decision d = JudgeTolerances<P, WithPriority>(f, cell, bounded);
    if (!bounded.Ambiguous)
      return d;
  }
  // the factor computed: velocity (IPV/DPV) times foveation
  double factor = f.Velocity;
  if (in.Foveation != FoveationMode::Off)
    factor *= std::exp(in.FoveationRate * FoveationDistance(f, cell));
  ToleranceFactor<false> exact{ factor, factor };
  Decision d = JudgeTolerances<P, WithPriority>(f, cell, exact);
  d.Factor = in.Foveation != FoveationMode::Off;
  return d;
}

/**
 * The per-cell decision of the walk (SRCC §3.5 steps 1-4, the floors and the baselines; see the
 * file documentation) for node `n` with cell coordinates `C`, tested for brightness only when
 * `brightnessOnly`. With `WithPriority`, a refined cell also gets its priority (how far its
 * error exceeds its tolerance); without it, none is computed.
 */
template <Policy P, bool WithPriority>
[[gnu::always_inline]] inline Decision JudgeCell(
  const Frame& f, int32_t n, const uint32_t C[3], bool brightnessOnly, uint8_t& inside)
{
  const OctreeView& v = f.V;
  const SelectionInput& in = f.In;
  const int level = std::min<int>(v.Level[n], MaxFinestLevel);
  const double h = f.Edge[level];
  const double lo[3] = { C[0] * h, C[1] * h, C[2] * h };

  // 1. frustum. `inside` holds the planes the parent lies wholly inside (bit i: plane i): its
  // children do too, and are not tested against them. The walks pass it on to the children.
  if (!brightnessOnly && in.UseFrustum && inside != AllPlanes)
  {
    uint8_t outside = 0;
    for (int p = 0; p < 6; ++p)
    {
      if (inside & (1u << p))
        continue;
      // the corners farthest along and against the plane's normal, summed in the same order as
      // the frustum check of the tests (Testing/Fuzz), so that they agree to the last bit
      const double* pl = in.Planes[p];
      const double* up = f.PlaneUp[p];
      double far = pl[3], near = pl[3];
      for (int a = 0; a < 3; ++a)
      {
        far += pl[a] * (lo[a] + h * up[a]);
        near += pl[a] * (lo[a] + h * (1.0 - up[a]));
      }
      outside |= far < 0 ? uint8_t(1u << p) : uint8_t(0);
      inside |= near >= 0 ? uint8_t(1u << p) : uint8_t(0);
    }
    if (outside)
    {
      return Hide(Culled, outside);
    }
  }
  // a cell coarser than the minimum level (incomplete on each process of a distributed
  // rendering) is refined without any other test
  if (level < in.MinimumLevel)
  {
    return Floor(false);
  }
  // a cell holding the eye has an unbounded error: refine it
  const bool eyeInside = in.Eye[0] >= lo[0] && in.Eye[0] <= lo[0] + h && in.Eye[1] >= lo[1] &&
    in.Eye[1] <= lo[1] + h && in.Eye[2] >= lo[2] && in.Eye[2] <= lo[2] + h;
  if (eyeInside && !in.Parallel)
  {
    return Floor(brightnessOnly);
  }

  // the cell seen from the eye
  CellView cell;
  cell.N = n;
  cell.Level = level;
  cell.H = h;
  cell.BrightnessOnly = brightnessOnly;
  const float* vf = &v.Vertex[3 * n];
  const float* nf = &v.ConeAxis[3 * n];
  for (int a = 0; a < 3; ++a)
  {
    cell.X[a] = vf[a];
    cell.Axis[a] = nf[a];
    cell.ToEye[a] = 0.0;
  }
  cell.Inverse = 1.0;
  if (in.Parallel)
  {
    for (int a = 0; a < 3; ++a)
      cell.Ve[a] = -f.Dop[a];
    cell.K = in.PixelScale;
  }
  else
  {
    for (int a = 0; a < 3; ++a)
      cell.ToEye[a] = in.Eye[a] - cell.X[a];
    const double dist = std::sqrt(Dot(cell.ToEye, cell.ToEye));
    if (!(dist > 0))
    {
      // the eye on the vertex (outside the cell only through rounding): refine
      return Floor(brightnessOnly);
    }
    cell.Inverse = 1.0 / dist;
    for (int a = 0; a < 3; ++a)
      cell.Ve[a] = cell.ToEye[a] * cell.Inverse;
    cell.K = in.PixelScale * cell.Inverse;
  }
  float sinT = 0, cosT = 0;
  ConeSinCos(f, n, sinT, cosT);
  cell.CosT = cosT;
  cell.SinT = sinT;
  cell.C = Dot(cell.Axis, cell.Ve);

  // 2a. SRCC's back faces (the contour test's first case) need no tolerance: decided before the
  // foveation's factor is bounded or computed (measured: +9 % on the foveated benchmark, when
  // every cell computed it)
  if (P == Policy::SRCC && !brightnessOnly && cell.CosT > 0 && cell.C < -cell.SinT)
  {
    if (in.HideBackFaces)
      return Hide(BackFacing, 0);
    return Draw(BackFacing); // an open surface: seen from behind, drawn but not refined
  }
  if constexpr (P == Policy::Cheng)
    return JudgeCheng<WithPriority>(f, cell);
  else
    return JudgeWithFactor<P, WithPriority>(f, cell);
}

/**
 * JudgeCell, with the pages a refinement reads (Frame::Pages): a refinement whose pages were
 * not read yet is asked of the loader and the cell is drawn as it is (AwaitingPages), so that
 * the frame never waits on the disk; for the first view (Frame::WaitForPages) it is made, read
 * in the frame (Selector::PreloadRefinements then marks it read).
 * Every walk judges through here, so a cell is never gone below before its pages are read.
 */
template <Policy P, bool WithPriority>
[[gnu::always_inline]] inline Decision Judge(
  const Frame& f, int32_t n, const uint32_t C[3], bool brightnessOnly, uint8_t& inside)
{
  const Decision d = JudgeCell<P, WithPriority>(f, n, C, brightnessOnly, inside);
  if (d.What != Verdict::Refine || !f.Pages || f.WaitForPages || f.Pages->IsReady(n))
    return d;
  f.Pages->Request(n, f.PageRequester);
  return Draw(AwaitingPages);
}

/// `f` with the selector's page loader (Frame::Pages).
inline Frame WithPages(Frame f, PageLoader* pages, int requester, bool wait)
{
  f.Pages = pages;
  f.PageRequester = requester;
  f.WaitForPages = wait;
  return f;
}

/// Writes cut entries and counts them (both walks).
struct CutWriter
{
  uint8_t* State;
  uint8_t* Reason;
  uint8_t* CullMask;
  std::vector<int32_t>& Previous;
  SelectionStats& Stats;

  void Add(int64_t n, uint8_t state, uint8_t reason)
  {
    this->State[n] = state;
    this->Reason[n] = reason;
    this->Previous.push_back(static_cast<int32_t>(n));
    ++this->Stats.InCut;
    this->Stats.Drawn += IsDrawnState(state) ? 1 : 0;
    this->Stats.AwaitingPages += reason == AwaitingPages ? 1 : 0;
  }
  /// A decision that puts the cell in the cut (Hide or Draw).
  void Keep(int64_t n, const Decision& d)
  {
    if (d.What == Verdict::Hide)
    {
      this->Add(n, CutHidden, d.Reason);
      if (this->CullMask && d.Outside)
      {
        this->CullMask[n] = d.Outside;
      }
    }
    else
    {
      this->Add(n, CutDrawn, d.Reason);
    }
  }
};

/// What refining a node reads of it.
struct Refinement
{
  unsigned Mask;
  int32_t First;
  int Level;
  int64_t Owned; // the triangles refining it adds to the cut: those it owns (plodOctree.h)
};

inline Refinement Refinable(const OctreeView& v, int64_t n)
{
  return { v.ChildMask[n], v.FirstChild[n], v.Level[n], v.TriangleEnd(n) - v.FirstTriangle[n] };
}

/// Whether input triangle `c` faces away from the eye (or along the projection direction): the
/// patch generator's back-face rule on the input corners.
inline bool InputFacesAway(const Frame& f, const int32_t* c)
{
  const float* x[3] = { &f.V.Points[3 * c[0]], &f.V.Points[3 * c[1]], &f.V.Points[3 * c[2]] };
  double n[3];
  FaceNormal(x[0], x[1], x[2], n);
  return FacesAway(n, x[0], f.In.Eye, f.In.Parallel, f.In.ProjectionDirection);
}

/**
 * Whether every triangle meeting node `n`'s cell (coordinates `c` at level `level`) faces the
 * eye (+1) or faces away from it (-1) by InputFacesAway, or neither is certain (0). The node's
 * cone holds the face normal of every triangle meeting the cell (plodOctreeBuilder.cxx,
 * TightenCones) and every corner of one it owns lies in the cell, so the angle between such a
 * face's normal and the direction from its corner to the eye is within theta + alpha of the
 * angle phi between the cone's axis and the direction from the cell's centre to the eye, alpha
 * the angle the cell's bounding sphere subtends from the eye (0 under a parallel projection):
 * all face the eye when phi + theta + alpha < pi/2, all face away when phi - theta - alpha >
 * pi/2. A margin of 1e-5 on the cosines leaves the float cones' rounding to the per-triangle
 * test.
 */
inline int ConeFacing(const Frame& f, int64_t n, const uint32_t c[3], int level)
{
  const double h = f.Edge[level];
  double u[3], sinA = 0, cosA = 1;
  if (f.In.Parallel)
  {
    for (int a = 0; a < 3; ++a)
      u[a] = -f.Dop[a];
  }
  else
  {
    for (int a = 0; a < 3; ++a)
      u[a] = f.In.Eye[a] - (double(c[a]) + 0.5) * h;
    const double dist = std::sqrt(Dot(u, u));
    const double radius = 0.8660254037844386 * h; // half the cell's diagonal
    if (!(dist > radius))
      return 0;
    for (int a = 0; a < 3; ++a)
      u[a] /= dist;
    sinA = radius / dist;
    cosA = std::sqrt(1.0 - sinA * sinA);
  }
  float sinTheta = 0, cosTheta = 0;
  ConeSinCos(f, n, sinTheta, cosTheta);
  const double sinT = sinTheta, cosT = cosTheta;
  if (!(cosT * cosA - sinT * sinA > 0))
    return 0;                                            // theta + alpha >= pi/2
  const double bound = sinT * cosA + cosT * sinA + 1e-5; // sin(theta + alpha), widened
  const float* axis = &f.V.ConeAxis[3 * n];
  const double along = axis[0] * u[0] + axis[1] * u[1] + axis[2] * u[2];
  return along > bound ? 1 : along < -bound ? -1 : 0;
}

/**
 * Of the `owned` triangles of node `n` (cell coordinates `c`, level `level`), those the budget
 * counts (Frame::CountDrawn; see "The count" in plodSelector.h), or `limit` + 1 as soon as they
 * are more than `limit`: not those whose lead corner is a ghost (another process draws them),
 * and with back faces hidden not those whose input face turns away from the eye
 * (InputFacesAway, decided for the whole cell by ConeFacing where it can). Those outside the
 * frustum count: the patch generator skips a triangle only when its corners' cut cells are
 * culled, which input corners outside a plane do not tell (counting them out was measured to
 * overshoot close views by up to 75 %). A corner out of range counts (the patch generator
 * reports it).
 */
inline int64_t CountDrawable(const Frame& f, int64_t n, int64_t owned, const uint32_t c[3],
  int level, int64_t limit = std::numeric_limits<int64_t>::max() - 1)
{
  const OctreeView& v = f.V;
  if (!f.CountDrawn || owned <= 0 || !v.Triangles || !v.Points)
    return owned; // (a hand-made octree may hold the counts alone)
  const int facing = f.In.HideBackFaces ? ConeFacing(f, n, c, level) : 1;
  if (facing < 0)
    return 0;
  if (facing > 0 && !v.PointGhost)
    return owned;
  int64_t count = 0;
  for (int64_t t = v.FirstTriangle[n], end = t + owned; t < end && count <= limit; ++t)
  {
    const int32_t* p = &v.Triangles[3 * t];
    const int32_t lead = std::min({ p[0], p[1], p[2] });
    if (lead < 0 || std::max({ p[0], p[1], p[2] }) >= v.NumberOfPoints)
    {
      ++count;
      continue;
    }
    if (v.PointGhost && v.PointGhost[lead] != 0)
      continue;
    count += facing == 0 && InputFacesAway(f, p) ? 0 : 1;
  }
  return count;
}

/**
 * Refines the cell `e`: its children go on `stack`, tested for brightness only when
 * `brightnessOnly`; a leaf is opened (it adds its own triangles). Returns the triangles the cut
 * gains (Refinement::Owned). A child index that does not follow its parent (corrupt arrays) is
 * never followed, so the walk always ends: the cell is drawn instead and nothing is gained.
 */
/// Whether the children of inner node `n` (refinement `r`) follow it, as a valid octree's do.
inline bool ChildrenFollow(const OctreeView& v, int64_t n, const Refinement& r)
{
  return !(r.First <= n || r.First + __builtin_popcount(r.Mask) > v.NumberOfNodes ||
    r.Level >= MaxFinestLevel);
}

/// Pushes the children of inner cell `e` (refinement `r`) on `stack`, from the last (highest
/// octant) to the first, so that the first is walked first: over the set bits only (a test of
/// each of the 8 bits mispredicts with the masks).
template <class EntryType>
[[gnu::always_inline]] inline void PushChildren(const EntryType& e, const Refinement& r,
  bool brightnessOnly, uint8_t inside, std::vector<EntryType>& stack)
{
  for (unsigned m = r.Mask, k = __builtin_popcount(r.Mask); m;)
  {
    const unsigned c = 31u - unsigned(__builtin_clz(m));
    m ^= 1u << c;
    stack.push_back({ r.First + int32_t(--k),
      { 2 * e.C[0] + (c & 1), 2 * e.C[1] + ((c >> 1) & 1), 2 * e.C[2] + ((c >> 2) & 1) },
      brightnessOnly, inside });
  }
}

template <class EntryType>
[[gnu::always_inline]] inline int64_t RefineCell(const OctreeView& v, const EntryType& e,
  const Refinement& r, bool brightnessOnly, uint8_t inside, std::vector<EntryType>& stack,
  CutWriter& cut)
{
  if (r.Mask == 0)
  {
    cut.Add(e.Node, CutOpen, OpenedLeaf);
    ++cut.Stats.Opened;
    return r.Owned;
  }
  if (!ChildrenFollow(v, e.Node, r))
  {
    cut.Add(e.Node, CutDrawn, AcceptedError);
    return 0;
  }
  PushChildren(e, r, brightnessOnly, inside, stack);
  return r.Owned;
}

/// The bits of a non-negative float (or +infinity), which order as the numbers do.
inline uint32_t OrderBits(float x)
{
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

inline float FromOrderBits(uint32_t bits)
{
  float x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

/// Push and pop of a 4-ary max-heap under `less` (half the depth of std::push_heap's binary
/// heap: measured, its pops cost less). `less` must be a strict total order on the items, so
/// the order of the pops does not depend on the heap's shape.
template <class T, class Less>
void HeapPush(std::vector<T>& heap, const T& item, Less less)
{
  size_t i = heap.size();
  heap.push_back(item);
  while (i > 0)
  {
    const size_t parent = (i - 1) / 4;
    if (!less(heap[parent], item))
      break;
    heap[i] = heap[parent];
    i = parent;
  }
  heap[i] = item;
}

template <class T, class Less>
void HeapPop(std::vector<T>& heap, Less less)
{
  const T last = heap.back();
  heap.pop_back();
  const size_t n = heap.size();
  if (n == 0)
    return;
  size_t i = 0;
  for (;;)
  {
    const size_t first = 4 * i + 1;
    if (first >= n)
      break;
    size_t best = first;
    const size_t end = std::min(first + 4, n);
    for (size_t c = first + 1; c < end; ++c)
      best = less(heap[best], heap[c]) ? c : best;
    if (!less(last, heap[best]))
      break;
    heap[i] = heap[best];
    i = best;
  }
  heap[i] = last;
}
} // namespace

void Selector::SetOctree(const OctreeView& view)
{
  // a new identity for the exact budget's remembered corner walks (PatchOptions::OctreeStamp)
  static std::atomic<uint64_t> stamps{ 0 };
  this->CountOptions.OctreeStamp = ++stamps;
  this->CountSpace.Memo = nullptr; // a memo of its own, made at the first count
  this->View = view;
  this->Cones.Assign(size_t(view.NumberOfNodes)); // each computed when first judged
  this->Previous.clear();
  this->Front.clear();
  this->BudgetBound = false;
  this->AheadKey = std::numeric_limits<float>::infinity();
}

void Selector::SetPageLoader(PageLoader* loader)
{
  const uint64_t serial = loader ? loader->GetSerial() : 0;
  if (serial != this->PagesSerial) // (not the address: a new loader may take a freed one's)
  {
    this->Pages = loader;
    this->PagesSerial = serial;
    this->PageRequester = loader ? loader->AddRequester() : 0;
    this->FirstViewRead = false;
  }
}

bool Selector::Refines(const SelectionInput& in, int64_t node) const
{
  if (node < 0 || node >= this->View.NumberOfNodes ||
    this->Cones.size() != size_t(this->View.NumberOfNodes))
  {
    return false;
  }
  int xyz[3];
  this->View.CellCoordinates(node, xyz);
  const uint32_t C[3] = { uint32_t(xyz[0]), uint32_t(xyz[1]), uint32_t(xyz[2]) };
  std::vector<detail::PreparedLight> lights; // (a diagnostic: its own storage, the walks' kept)
  const Frame frame = MakeFrame(this->View, in, &this->Cones, lights);
  return WithPolicy(frame.Model, [&](auto policy) {
    uint8_t inside = 0;
    return Judge<decltype(policy)::value, false>(
             frame, static_cast<int32_t>(node), C, false, inside)
             .What == Verdict::Refine;
  });
}

void Selector::PreloadRefinements(const uint8_t* state)
{
  // the refined nodes: the opened leaves and every ancestor of a cut node, each marked once
  for (const int32_t n : this->Previous)
  {
    if (state[n] == CutOpen)
      this->Pages->Preload(n);
    for (int64_t p = this->View.Parent[n]; p >= 0 && !this->Pages->IsReady(p);
         p = this->View.Parent[p])
      this->Pages->Preload(p);
  }
}

void Selector::ClearPrevious(uint8_t* state, uint8_t* reason, uint8_t* cullMask)
{
  for (int32_t n : this->Previous)
  {
    state[n] = NotInCut;
    reason[n] = ReasonNone;
    if (cullMask)
    {
      cullMask[n] = 0;
    }
  }
  this->Previous.clear();
}

void Selector::Select(const SelectionInput& in, uint8_t* state, uint8_t* reason, uint8_t* cullMask,
  SelectionStats& stats)
{
  stats = SelectionStats();
  // the incremental walk starts from the previous cut, left in the arrays
  const bool incremental = in.Incremental && in.TriangleBudget <= 0 && !this->Front.empty();
  if (!incremental)
  {
    this->ClearPrevious(state, reason, cullMask);
  }
  if (this->View.NumberOfNodes == 0)
  {
    return;
  }
  if (this->Pages)
  {
    this->Pages->ForgetRequests(this->PageRequester); // this frame asks again for what it needs
  }
  if (in.TriangleBudget > 0)
  {
    this->Front.clear();
    const bool kept = in.ToleranceCutFirst && !this->BudgetBound &&
      this->WalkToleranceCutWithinBudget(in, state, reason, cullMask, stats);
    if (!kept)
    {
      const int64_t visited = stats.Visited; // (a tolerance walk given up)
      this->ClearPrevious(state, reason, cullMask);
      stats = SelectionStats();
      this->SelectWithinBudget(in, in.TriangleBudget, state, reason, cullMask, stats);
      stats.Visited += visited;
    }
    this->BudgetBound = stats.BudgetBinding;
    if (in.ExactBudget)
    {
      this->FitDrawnTriangles(in, state, reason, cullMask, stats);
    }
  }
  else if (incremental)
  {
    this->SelectIncremental(in, state, reason, cullMask, stats);
  }
  else
  {
    this->SelectDepthFirst(in, state, reason, cullMask, stats);
  }
  if (this->Pages && !this->FirstViewRead)
  {
    this->PreloadRefinements(state);
    this->FirstViewRead = true;
  }
  // internal invariants (debug builds): on a valid octree the walk writes a valid cut, and the
  // figures count it
  assert(stats.Drawn <= stats.InCut && stats.InCut == int64_t(this->Previous.size()));
  assert(!ValidateOctree(this->View) || ValidateCut(this->View, state));
}

void Selector::FitDrawnTriangles(const SelectionInput& in, uint8_t* state, uint8_t* reason,
  uint8_t* cullMask, SelectionStats& stats)
{
  // the patch generator's rules: back faces culled when hidden, folds drawn (with
  // FoldHandling::Drop it draws fewer)
  PatchOptions& options = this->CountOptions;
  options.CullBackFaces = in.HideBackFaces;
  options.Parallel = in.Parallel;
  for (int a = 0; a < 3; ++a)
  {
    options.Eye[a] = in.Eye[a];
    options.ProjectionDirection[a] = in.ProjectionDirection[a];
  }
  const auto count = [&]() {
    return CountDrawnTriangles(this->View, state, cullMask, options, this->CountSpace);
  };
  int64_t walked = in.TriangleBudget; // the budget of the last walk
  const auto rewalk = [&](int64_t budget) {
    walked = budget;
    const int64_t visited = stats.Visited;
    this->ClearPrevious(state, reason, cullMask);
    stats = SelectionStats();
    this->SelectWithinBudget(in, budget, state, reason, cullMask, stats);
    stats.Visited += visited;
  };
  const int64_t B = in.TriangleBudget;
  // the cut's count bounds the drawn one without back faces hidden or ghosts: a walk that did
  // not bind draws no more than B, and no fill is asked of it
  if (!stats.BudgetBinding && !in.HideBackFaces && !this->View.PointGhost)
    return;
  int64_t drawn = count();
  if (drawn < 0)
    return; // an invalid octree's cut cannot be counted: the walk's count stays
  // The walk's count follows the drawn one closely: down by the excess while more than the
  // budget are drawn, up by the ratio of the budget to the drawn count while less than LowFill
  // of it are drawn and the budget bound (at least one more). The drawn count is not monotone
  // in the budget walked with (the representative vertices turn other faces), so each walk
  // that still draws too many doubles the next step down: walks that each drew a few over a
  // budget a few triangles lower every time, until the walks ran out, were measured on Lucy in
  // motion. The largest budget found drawing no more than B is kept, and walked again last when
  // the last walk drew too many.
  constexpr double LowFill = 0.95;
  constexpr int MaxWalks = 6;
  int64_t best = drawn <= B ? B : -1, bestDrawn = drawn;
  int64_t shrink = 1; // how many times the excess the next step down takes, at least
  for (int walks = 1; walks < MaxWalks; ++walks)
  {
    const bool over = drawn > B;
    if (!over && (drawn >= LowFill * double(B) || !stats.BudgetBinding))
      break;
    const int64_t now = walked;
    const double scaled = std::floor(double(now) * double(B) / double(std::max<int64_t>(1, drawn)));
    const int64_t next = over
      ? std::max<int64_t>(1, now - shrink * (drawn - B))
      : std::max<int64_t>(now + 1, int64_t(std::min(scaled, 4.0 * double(B))));
    shrink = over ? 2 * shrink : 1;
    if ((over && now <= 1) || (best >= 0 && over && next <= best) || (!over && next <= best))
      break;
    rewalk(next);
    drawn = count();
    if (drawn <= B && next > best)
    {
      best = next;
      bestDrawn = drawn;
    }
  }
  if (drawn > B && best >= 0 && best != walked)
  {
    rewalk(best);
    drawn = bestDrawn;
  }
  stats.BudgetBinding = stats.BudgetBinding || drawn > B;
  stats.BudgetTriangles = drawn;
}

namespace detail
{
/**
 * The budget's count kept by a tolerance walk tried as a budget's cut
 * (SelectionInput::ToleranceCutFirst): what CountDrawable counts of every refinement, summed
 * over the walkers, and the budget above which they give up. Each walker adds its count in
 * batches of about Batch triangles, so that the shared total is rarely written; the total is
 * exact once every walker has added its last batch.
 */
struct DrawnTally
{
  static constexpr int64_t Batch = 4096;
  explicit DrawnTally(int64_t budget)
    : Budget(budget)
  {
  }
  const int64_t Budget;
  std::atomic<int64_t> Total{ 0 };

  /// Whether the total exceeds the budget (the walkers give up; the queue walk makes the cut).
  bool Over() const { return this->Total.load(std::memory_order_relaxed) > this->Budget; }
  /// Adds a walker's batch; false once the total exceeds the budget.
  bool Add(int64_t count)
  {
    this->Total.fetch_add(count, std::memory_order_relaxed);
    return !this->Over();
  }
};
} // namespace detail

namespace
{
using detail::DrawnTally;

/// A walker's share of a DrawnTally (or nothing, without one: the walk then compiles as it
/// would without counting).
template <bool Tally>
struct TallyBatch
{
  DrawnTally* Shared;
  int64_t Count = 0;

  /// Counts the refinement of cell `e` (the `owned` triangles it adds); false when the walk
  /// is to give up.
  template <class EntryType>
  bool Refined(const Frame& f, const EntryType& e, int64_t owned, int level)
  {
    if (!Tally || owned <= 0)
      return true;
    this->Count += CountDrawable(f, e.Node, owned, e.C, level);
    if (this->Count < DrawnTally::Batch)
      return true;
    return this->Flush();
  }
  bool Flush()
  {
    const int64_t count = this->Count;
    this->Count = 0;
    return !Tally || this->Shared->Add(count);
  }
};

/**
 * The depth-first walk (SRCC §3.5) of the cells on `stack` and everything below them that the
 * tolerances refine. Returns the triangles the refinements add. With `record`, every cell put in
 * the cut is also appended to it (the front the incremental selection starts from next frame).
 * With `Tally`, the budget's count of the refinements is added to `*tally`, and the walk gives
 * up (returns with cells left on the stack) once its total exceeds the budget.
 */
template <Policy P, bool EveryTest, class EntryType, bool Tally = false>
[[gnu::always_inline]] inline int64_t WalkDepthFirst(const Frame& frame,
  std::vector<EntryType>& stack, CutWriter& cut, std::vector<EntryType>* record,
  DrawnTally* tally = nullptr)
{
  const OctreeView& v = frame.V;
  int64_t triangles = 0;
  TallyBatch<Tally> batch{ tally };
  while (!stack.empty())
  {
    const EntryType e = stack.back();
    stack.pop_back();
    ++cut.Stats.Visited;
    uint8_t inside = e.Inside;
    const Decision d = Judge<P, false>(frame, e.Node, e.C, e.BrightnessOnly, inside);
    cut.Stats.FoveationFactors += d.Factor ? 1 : 0;
    if (d.What != Verdict::Refine)
    {
      cut.Keep(e.Node, d);
      if (record)
        record->push_back(e);
      continue;
    }
    cut.Stats.TopologyRefined += d.Topology ? 1 : 0;
    const Refinement r = Refinable(v, e.Node);
    const int64_t owned = RefineCell(v, e, r, d.BrightnessOnly && !EveryTest, inside, stack, cut);
    triangles += owned;
    if (record && cut.State[e.Node] != NotInCut)
      record->push_back(e); // an opened leaf
    if (!batch.Refined(frame, e, owned, r.Level))
      return triangles;
  }
  batch.Flush();
  return triangles;
}
} // namespace

namespace
{
/// `a` += `b`: the figures of a tolerance walk (all counts).
void AddFigures(SelectionStats& a, const SelectionStats& b)
{
  a.Visited += b.Visited;
  a.InCut += b.InCut;
  a.Drawn += b.Drawn;
  a.Opened += b.Opened;
  a.TopologyRefined += b.TopologyRefined;
  a.AwaitingPages += b.AwaitingPages;
  a.FoveationFactors += b.FoveationFactors;
}
}

namespace
{
/**
 * The tolerance walk's parallel form (Selector::SetParallelFor): the top of the tree breadth
 * first until enough subtrees wait, then the subtrees through `pfor`, each with its own stack,
 * cut list and figures (in the task vectors, whose capacities are kept), merged in order.
 * Returns the triangles the refinements add. With `Tally`, as WalkDepthFirst: each subtree gives
 * up (or is not walked) once the total exceeds the budget; the cells written are still merged
 * into the cut list, to be cleared.
 */
template <Policy P, class EntryType, bool Tally = false>
int64_t WalkInParallel(const Frame& frame, std::vector<EntryType>& stack, CutWriter& cut,
  const ParallelFor& pfor, std::vector<std::vector<EntryType>>& taskStacks,
  std::vector<std::vector<int32_t>>& taskPrevious, std::vector<SelectionStats>& taskStats,
  std::vector<int64_t>& taskTriangles, DrawnTally* tally = nullptr)
{
  const OctreeView& v = frame.V;
  // 1. the top of the tree breadth first, until enough subtrees wait (each cell is judged as
  // the depth-first walk judges it: its entry holds all it depends on)
  constexpr size_t Subtrees = 64;
  int64_t triangles = 0;
  TallyBatch<Tally> batch{ tally };
  size_t next = 0;
  while (next < stack.size() && stack.size() - next < Subtrees)
  {
    const EntryType e = stack[next++];
    ++cut.Stats.Visited;
    uint8_t inside = e.Inside;
    const Decision d = Judge<P, false>(frame, e.Node, e.C, e.BrightnessOnly, inside);
    cut.Stats.FoveationFactors += d.Factor ? 1 : 0;
    if (d.What != Verdict::Refine)
    {
      cut.Keep(e.Node, d);
      continue;
    }
    cut.Stats.TopologyRefined += d.Topology ? 1 : 0;
    const Refinement r = Refinable(v, e.Node);
    const int64_t owned = RefineCell(v, e, r, d.BrightnessOnly, inside, stack, cut);
    triangles += owned;
    batch.Refined(frame, e, owned, r.Level); // (the subtrees see the total)
  }
  batch.Flush();
  // 2. the waiting subtrees, each walked depth first with its own stack, list and figures
  // (disjoint subtrees: no two write the same node)
  const size_t waiting = stack.size() - next;
  if (taskStacks.size() < waiting) // (the budget walk's first pass uses the stacks too)
    taskStacks.resize(waiting);
  if (taskPrevious.size() < waiting)
    taskPrevious.resize(waiting);
  taskStats.assign(waiting, SelectionStats());
  taskTriangles.assign(waiting, 0);
  pfor(static_cast<int64_t>(waiting), 1, [&](int64_t begin, int64_t end) {
    for (int64_t k = begin; k < end; ++k)
    {
      std::vector<EntryType>& own = taskStacks[k];
      own.assign(1, stack[next + k]);
      taskPrevious[k].clear();
      if (Tally && tally->Over())
        continue;
      CutWriter local{ cut.State, cut.Reason, cut.CullMask, taskPrevious[k], taskStats[k] };
      taskTriangles[k] =
        WalkDepthFirst<P, false, EntryType, Tally>(frame, own, local, nullptr, tally);
    }
  });
  // 3. merged in subtree order
  for (size_t k = 0; k < waiting; ++k)
  {
    cut.Previous.insert(cut.Previous.end(), taskPrevious[k].begin(), taskPrevious[k].end());
    AddFigures(cut.Stats, taskStats[k]);
    triangles += taskTriangles[k];
  }
  return triangles;
}
} // namespace

// flatten: the decision, the refinement and the cone spreads inlined into the loop (measured on
// the benchmark scene: 61 ns per visited node, against 67 ns with calls; 63 ns before the walks
// shared Judge)
[[gnu::flatten]] void Selector::SelectDepthFirst(const SelectionInput& in, uint8_t* state,
  uint8_t* reason, uint8_t* cullMask, SelectionStats& stats, DrawnTally* tally)
{
  const Frame frame =
    WithPages(MakeFrame(this->View, in, &this->Cones, this->FrameLights, &this->Fovea), this->Pages,
      this->PageRequester, !this->FirstViewRead);
  CutWriter cut{ state, reason, cullMask, this->Previous, stats };
  // the walk's stack is a member: its capacity is kept from frame to frame
  std::vector<Entry>& stack = this->Stack;
  stack.clear();
  stack.push_back({ 0, { 0, 0, 0 }, false, 0 });
  this->Front.clear();
  stats.BudgetTriangles = WithPolicy(frame.Model, [&](auto policy) {
    constexpr Policy P = decltype(policy)::value;
    if (tally && this->For)
      return WalkInParallel<P, Entry, true>(frame, stack, cut, this->For, this->TaskStacks,
        this->TaskPrevious, this->TaskStats, this->TaskTriangles, tally);
    if (tally)
      return WalkDepthFirst<P, false, Entry, true>(frame, stack, cut, nullptr, tally);
    if (this->For && !in.Incremental)
      return WalkInParallel<P>(frame, stack, cut, this->For, this->TaskStacks, this->TaskPrevious,
        this->TaskStats, this->TaskTriangles);
    return WalkDepthFirst<P, false>(frame, stack, cut, in.Incremental ? &this->Front : nullptr);
  });
  this->FrontTriangles = stats.BudgetTriangles;
  stats.CutTriangles = stats.BudgetTriangles;
}

bool Selector::WalkToleranceCutWithinBudget(const SelectionInput& in, uint8_t* state,
  uint8_t* reason, uint8_t* cullMask, SelectionStats& stats)
{
  DrawnTally tally(in.TriangleBudget);
  this->SelectDepthFirst(in, state, reason, cullMask, stats, &tally);
  if (tally.Over())
    return false;
  stats.BudgetTriangles = tally.Total.load();
  stats.BudgetToleranceCut = true;
  return true;
}

namespace
{
/// Takes node `n` out of the cut.
inline void LeaveCut(CutWriter& cut, int32_t n)
{
  cut.State[n] = NotInCut;
  cut.Reason[n] = ReasonNone;
  if (cut.CullMask)
    cut.CullMask[n] = 0;
}

/**
 * The incremental selection's refinement: every cell of the previous cut (`front`) is judged
 * again, with every test (its parent's contour decision is not judged again, so a "brightness
 * only" would be stale) and no plane known inside (the frustum moved). Kept, it stays; refined,
 * the walk goes on below it, every cell judged with every test. The cells put in the cut are
 * appended to `next`. Returns the cut's triangles, from the previous cut's `triangles`.
 */
template <Policy P, class EntryType>
int64_t RefineFront(const Frame& frame, const std::vector<EntryType>& front,
  std::vector<EntryType>& stack, std::vector<EntryType>& next, CutWriter& cut, int64_t triangles)
{
  for (const EntryType& old : front)
  {
    if (cut.State[old.Node] == CutOpen)
      triangles -= Refinable(frame.V, old.Node).Owned; // opened again below if still refined
    LeaveCut(cut, old.Node);
    stack.push_back({ old.Node, { old.C[0], old.C[1], old.C[2] }, false, 0 });
    triangles += WalkDepthFirst<P, true>(frame, stack, cut, &next);
  }
  return triangles;
}

/**
 * The incremental selection's coarsening: a parent whose children are all in the cut and kept
 * (drawn or hidden, none opened) is judged; when it is no longer refined, it replaces them
 * (appended to `next`). Pass after pass, one level up each, while some parent collapses.
 * `mark` (one per node, `markValue` the current pass's) remembers the parents judged in a
 * pass. Returns the cut's triangles, from `triangles`.
 */
template <Policy P, class EntryType>
int64_t CoarsenFront(const Frame& frame, std::vector<EntryType>& next, std::vector<uint32_t>& mark,
  uint32_t& markValue, CutWriter& cut, int64_t triangles)
{
  const OctreeView& v = frame.V;
  const uint8_t* state = cut.State;
  if (mark.size() != size_t(v.NumberOfNodes))
  {
    mark.assign(v.NumberOfNodes, 0);
    markValue = 0;
  }
  for (size_t begin = 0, end = next.size(); begin < end; begin = end, end = next.size())
  {
    if (++markValue == 0)
    {
      std::fill(mark.begin(), mark.end(), 0u);
      markValue = 1;
    }
    for (size_t i = begin; i < end; ++i)
    {
      const EntryType e = next[i];
      const int32_t p = e.Node > 0 ? v.Parent[e.Node] : -1;
      if (state[e.Node] == NotInCut || p < 0 || p >= e.Node || mark[p] == markValue)
        continue;
      mark[p] = markValue;
      const Refinement r = Refinable(v, p);
      bool allKept = r.First > p && r.First + __builtin_popcount(r.Mask) <= v.NumberOfNodes;
      for (int k = 0; allKept && k < __builtin_popcount(r.Mask); ++k)
        allKept = state[r.First + k] == CutDrawn || state[r.First + k] == CutHidden;
      if (!allKept)
        continue;
      const EntryType pe{ p, { e.C[0] >> 1, e.C[1] >> 1, e.C[2] >> 1 }, false, 0 };
      ++cut.Stats.Visited;
      uint8_t inside = 0;
      const Decision d = Judge<P, false>(frame, p, pe.C, false, inside);
      if (d.What == Verdict::Refine)
        continue;
      for (int k = 0; k < __builtin_popcount(r.Mask); ++k)
      {
        --cut.Stats.InCut;
        cut.Stats.Drawn -= IsDrawnState(state[r.First + k]) ? 1 : 0;
        cut.Stats.AwaitingPages -= cut.Reason[r.First + k] == AwaitingPages ? 1 : 0;
        LeaveCut(cut, r.First + k);
      }
      triangles -= r.Owned;
      cut.Keep(p, d);
      next.push_back(pe);
    }
  }
  return triangles;
}
} // namespace

// flatten: as SelectDepthFirst
[[gnu::flatten]] void Selector::SelectIncremental(const SelectionInput& in, uint8_t* state,
  uint8_t* reason, uint8_t* cullMask, SelectionStats& stats)
{
  const Frame frame =
    WithPages(MakeFrame(this->View, in, &this->Cones, this->FrameLights, &this->Fovea), this->Pages,
      this->PageRequester, !this->FirstViewRead);
  this->Previous.clear(); // rebuilt below from the new front
  CutWriter cut{ state, reason, cullMask, this->Previous, stats };
  this->Stack.clear();
  this->NextFront.clear();
  const int64_t triangles = WithPolicy(frame.Model, [&](auto policy) {
    const int64_t refined = RefineFront<decltype(policy)::value>(
      frame, this->Front, this->Stack, this->NextFront, cut, this->FrontTriangles);
    return CoarsenFront<decltype(policy)::value>(
      frame, this->NextFront, this->Mark, this->MarkValue, cut, refined);
  });
  // the new front: the cells still in the cut
  this->Previous.clear();
  this->Front.clear();
  for (const Entry& e : this->NextFront)
  {
    if (state[e.Node] != NotInCut)
    {
      this->Previous.push_back(e.Node);
      this->Front.push_back(e);
    }
  }
  this->FrontTriangles = triangles;
  stats.CutTriangles = triangles;
  stats.BudgetTriangles = triangles;
}

/**
 * The budget walk's state and steps (SelectWithinBudget; "Triangle budget" in plodSelector.h):
 * the cells judged off a stack, the refinements waiting in the max-heap, and the two counts,
 * what the budget counts (CountDrawable, when a refinement leaves the queue) and the cut's.
 */
namespace
{
/// AheadCell::ChildList of a cell whose children were not judged ahead.
constexpr uint32_t NotAhead = ~0u;
}

struct Selector::BudgetWalk
{
  Selector& S;
  const Frame& F;
  const SelectionInput& In;
  const int64_t Budget; ///< what the walk may count (In.TriangleBudget, or an exact budget's try)
  CutWriter& Cut;
  SelectionStats& Stats;
  int64_t Triangles = 0;
  int64_t CutTriangles = 0;
  bool Refused = false;
  /// How many queued refinements own k triangles, for 0 < k < Few: whether one of them surely
  /// fits a small room left (SkipMisfits; it counts at most what it owns).
  static constexpr int64_t Few = 64;
  int32_t FewOwning[Few] = {};

  /// Max-heap order: the larger key, then the larger own priority (Candidate::Order), then the
  /// smaller node index (the coarser cell: nodes are stored level by level).
  static bool Below(const Candidate& a, const Candidate& b)
  {
    return a.Order != b.Order ? a.Order < b.Order : a.Node > b.Node;
  }

  void CountOwning(int64_t owned, int32_t change)
  {
    if (owned > 0 && owned < Few)
      this->FewOwning[owned] += change;
  }

  /// Judges the cells on the stack, children of a refinement of priority `bound`: cut cells are
  /// written, floors refined at once, the other refinements queued with a key of at most
  /// `bound` (monotone keys: the queue then yields refinements in non-increasing key order).
  /// (Out of line, its decision inlined: inlined into Run it measured 6 % slower.)
  template <Policy P>
  [[gnu::flatten, gnu::noinline]] void JudgeStack(float bound)
  {
    const OctreeView& v = this->F.V;
    std::vector<Entry>& stack = this->S.Stack;
    while (!stack.empty())
    {
      const Entry e = stack.back();
      stack.pop_back();
      ++this->Stats.Visited;
      uint8_t inside = e.Inside;
      const Decision d = Judge<P, true>(this->F, e.Node, e.C, e.BrightnessOnly, inside);
      this->Stats.FoveationFactors += d.Factor ? 1 : 0;
      if (d.What != Verdict::Refine)
      {
        this->Cut.Keep(e.Node, d);
        continue;
      }
      const Refinement r = Refinable(v, e.Node);
      if (d.Floor)
      {
        const int64_t owned = RefineCell(v, e, r, d.BrightnessOnly, inside, stack, this->Cut);
        this->CutTriangles += owned;
        this->Triangles += owned > 0 ? CountDrawable(this->F, e.Node, owned, e.C, r.Level) : 0;
        continue;
      }
      const float priority = d.Priority; // single precision, non-negative (QueuePriority)
      const uint64_t order =
        uint64_t(OrderBits(std::min(priority, bound))) << 32 | OrderBits(priority);
      HeapPush(
        this->S.Queue, { order, e.Node, static_cast<uint32_t>(this->S.Waiting.size()) }, Below);
      this->CountOwning(r.Owned, 1);
      this->S.Waiting.push_back(
        { r.Owned, { e.C[0], e.C[1], e.C[2] }, r.First, static_cast<uint8_t>(r.Mask),
          static_cast<uint8_t>(r.Level), inside, d.BrightnessOnly, d.Topology, nullptr });
    }
  }

  // ---- the parallel first pass (Selector::SetParallelFor; see "Cost" in plodSelector.h) ----
  // Every cell's decision depends only on the cell and on what its parent passes down, and the
  // key of a refinement only on its priority and its parent's key, so the cells the walk will
  // meet can be judged before it meets them, in parallel subtrees: each refinement whose key
  // is at least AheadKey (the last binding walk's first misfit: the walk makes nearly all of
  // them) has its children judged and its count made ahead. The walk then replays those
  // decisions in the order it would have made them (so the queue holds the same refinements
  // in the same places) and judges the rest itself: the cut is the serial walk's.

  /// Cell `e` judged as JudgeStack judges it.
  template <Policy P>
  AheadCell JudgeAheadCell(const Entry& e, int64_t& factors) const
  {
    uint8_t inside = e.Inside;
    const Decision d = Judge<P, true>(this->F, e.Node, e.C, e.BrightnessOnly, inside);
    factors += d.Factor ? 1 : 0;
    AheadCell a{ e.Node, { e.C[0], e.C[1], e.C[2] }, 0, -1, NotAhead, 0, -1, d.Priority,
      static_cast<uint8_t>(d.What), d.Reason, d.Outside, inside, 0, 0, d.BrightnessOnly, d.Floor,
      d.Topology, d.Factor };
    if (d.What == Verdict::Refine)
    {
      const Refinement r = Refinable(this->F.V, e.Node);
      a.Owned = r.Owned;
      a.FirstChild = r.First;
      a.ChildMask = static_cast<uint8_t>(r.Mask);
      a.Level = static_cast<uint8_t>(r.Level);
    }
    return a;
  }

  static Refinement RefinementOf(const AheadCell& a)
  {
    return { a.ChildMask, a.FirstChild, a.Level, a.Owned };
  }

  /// The key under which a refinement judged under `bound` leaves its children: a floor passes
  /// `bound` on (its children are judged with its siblings), a queued refinement its own key.
  static float ChildBound(const AheadCell& a, float bound)
  {
    return a.Floor ? bound : std::min(a.Priority, bound);
  }

  /// Whether the first pass goes below refinement `a`, judged under `bound`.
  bool GoesBelow(const AheadCell& a, float bound) const
  {
    return a.What == uint8_t(Verdict::Refine) &&
      (a.Floor || std::min(a.Priority, bound) >= this->S.AheadKey);
  }

  /// Goes below refinement `list[index]`: its count, and its children judged, in child order,
  /// at the end of `out` (list number `outId`). Returns the number of children judged.
  template <Policy P>
  int JudgeChildren(std::vector<AheadCell>& list, size_t index, std::vector<AheadCell>& out,
    uint32_t outId, std::vector<Entry>& scratch, int64_t& visited, int64_t& factors) const
  {
    AheadCell& a = list[index];
    a.Count = CountDrawable(this->F, a.Node, a.Owned, a.C, a.Level);
    const Refinement r = RefinementOf(a);
    if (r.Mask == 0 || !ChildrenFollow(this->F.V, a.Node, r))
      return 0;
    scratch.clear();
    const Entry e{ a.Node, { a.C[0], a.C[1], a.C[2] }, false, a.Inside };
    PushChildren(e, r, a.BrightnessOnly, a.Inside, scratch);
    const int k = static_cast<int>(scratch.size());
    const size_t first = out.size();
    for (int i = k - 1; i >= 0; --i) // (pushed last to first)
      out.push_back(this->JudgeAheadCell<P>(scratch[i], factors));
    visited += k;
    list[index].ChildList = outId; // (`a` may have moved when `list` is `out`)
    list[index].ChildIndex = static_cast<uint32_t>(first);
    return k;
  }

  /**
   * The first pass: the root judged, the top of the tree gone below breadth first until enough
   * refinements wait, then each of them depth first in its own list through the selector's
   * ParallelFor.
   */
  template <Policy P>
  void JudgeAhead()
  {
    constexpr size_t Subtrees = 64;
    std::vector<std::vector<AheadCell>>& lists = this->S.AheadLists;
    std::vector<std::pair<uint32_t, float>>& open = this->S.AheadOpen;
    if (lists.empty())
      lists.resize(1);
    std::vector<AheadCell>& top = lists[0];
    top.clear();
    open.clear();
    int64_t visited = 1, factors = 0;
    top.push_back(this->JudgeAheadCell<P>({ 0, { 0, 0, 0 }, false, 0 }, factors));
    constexpr float Unbounded = std::numeric_limits<float>::infinity();
    if (this->GoesBelow(top[0], Unbounded))
      open.emplace_back(0, Unbounded);
    size_t next = 0;
    while (next < open.size() && open.size() - next < Subtrees)
    {
      const auto [index, bound] = open[next++];
      const float below = ChildBound(top[index], bound);
      const size_t first = top.size();
      const int k = this->JudgeChildren<P>(top, index, top, 0, this->S.Stack, visited, factors);
      for (int i = 0; i < k; ++i)
        if (this->GoesBelow(top[first + i], below))
          open.emplace_back(static_cast<uint32_t>(first + i), below);
    }
    // (each subtree's lists and figures in the selector's task vectors, capacities kept)
    const size_t waiting = open.size() - next;
    if (lists.size() < waiting + 1)
      lists.resize(waiting + 1);
    std::vector<AheadCell>& topNow = lists[0]; // (`top` moved if `lists` grew)
    if (this->S.TaskStacks.size() < waiting)
      this->S.TaskStacks.resize(waiting);
    if (this->S.AheadStacks.size() < waiting)
      this->S.AheadStacks.resize(waiting);
    this->S.TaskStats.assign(waiting, SelectionStats());
    this->S.For(static_cast<int64_t>(waiting), 1, [&](int64_t begin, int64_t end) {
      for (int64_t t = begin; t < end; ++t)
      {
        std::vector<Entry>& scratch = this->S.TaskStacks[t];
        std::vector<std::pair<uint32_t, float>>& stack = this->S.AheadStacks[t];
        int64_t& taskVisited = this->S.TaskStats[t].Visited;
        int64_t& taskFactors = this->S.TaskStats[t].FoveationFactors;
        std::vector<AheadCell>& own = lists[t + 1];
        own.clear();
        const auto [index, bound] = open[next + t];
        const float below = ChildBound(topNow[index], bound);
        int k = this->JudgeChildren<P>(
          topNow, index, own, uint32_t(t + 1), scratch, taskVisited, taskFactors);
        stack.clear();
        for (int i = k - 1; i >= 0; --i)
          stack.emplace_back(static_cast<uint32_t>(i), below);
        while (!stack.empty())
        {
          const auto [at, under] = stack.back();
          stack.pop_back();
          if (!this->GoesBelow(own[at], under))
            continue;
          const float deeper = ChildBound(own[at], under);
          const size_t first = own.size();
          k = this->JudgeChildren<P>(
            own, at, own, uint32_t(t + 1), scratch, taskVisited, taskFactors);
          for (int i = k - 1; i >= 0; --i)
            stack.emplace_back(static_cast<uint32_t>(first + i), deeper);
        }
      }
    });
    for (size_t t = 0; t < waiting; ++t)
    {
      visited += this->S.TaskStats[t].Visited;
      factors += this->S.TaskStats[t].FoveationFactors;
    }
    this->Stats.Visited += visited;
    this->Stats.FoveationFactors += factors;
    this->Stats.BudgetJudgedAhead = visited;
  }

  /// Cell `a`, judged ahead, met by the walk under key `bound`: what JudgeStack does with it,
  /// its decision read instead of made (a floor's children replayed before its siblings, as
  /// JudgeStack's stack takes them).
  template <Policy P>
  void Replay(const AheadCell& a, float bound)
  {
    if (a.What != uint8_t(Verdict::Refine))
    {
      this->Cut.Keep(
        a.Node, { Verdict(a.What), a.Reason, a.Outside, false, false, false, false, 0 });
      return;
    }
    const Entry e{ a.Node, { a.C[0], a.C[1], a.C[2] }, false, a.Inside };
    if (a.Floor)
    {
      const int64_t owned = RefineCell(
        this->F.V, e, RefinementOf(a), a.BrightnessOnly, a.Inside, this->S.Stack, this->Cut);
      this->CutTriangles += owned;
      this->Triangles += owned > 0 ? a.Count : 0;
      this->ReplayChildren<P>(a, bound);
      return;
    }
    const float priority = a.Priority;
    const uint64_t order =
      uint64_t(OrderBits(std::min(priority, bound))) << 32 | OrderBits(priority);
    HeapPush(
      this->S.Queue, { order, a.Node, static_cast<uint32_t>(this->S.Waiting.size()) }, Below);
    this->CountOwning(a.Owned, 1);
    this->S.Waiting.push_back({ a.Owned, { a.C[0], a.C[1], a.C[2] }, a.FirstChild, a.ChildMask,
      a.Level, a.Inside, a.BrightnessOnly, a.Topology, &a });
  }

  /// The children of refinement `a` (just refined: RefineCell pushed them on the stack): their
  /// decisions replayed when the first pass judged them, else judged now.
  template <Policy P>
  void ReplayChildren(const AheadCell& a, float bound)
  {
    if (a.ChildList == NotAhead)
    {
      this->JudgeStack<P>(bound);
      return;
    }
    this->S.Stack.clear();
    const AheadCell* child = this->S.AheadLists[a.ChildList].data() + a.ChildIndex;
    for (int k = __builtin_popcount(a.ChildMask); k > 0; --k, ++child)
      this->Replay<P>(*child, bound);
  }

  /// What refining waiting cell `c` adds to the budget's count, or more than `limit` (its
  /// count judged ahead, when it was: then the whole count).
  int64_t Counted(const Candidate& c, int64_t limit) const
  {
    const WaitingCell& w = this->S.Waiting[c.Slot];
    if (w.Ahead && w.Ahead->Count >= 0)
      return w.Ahead->Count;
    return CountDrawable(this->F, c.Node, w.Owned, w.C, w.Level, limit);
  }

  /// Refines a cell that left the queue (adding `add` to the budget's count), and judges its
  /// children under its key.
  template <Policy P>
  void RefineWaiting(const Candidate& c, int64_t add)
  {
    const WaitingCell w = this->S.Waiting[c.Slot]; // (a copy: judging children grows Waiting)
    this->Stats.TopologyRefined += w.Topology ? 1 : 0;
    const Entry e{ c.Node, { w.C[0], w.C[1], w.C[2] }, false, w.Inside };
    const int64_t owned = RefineCell(this->F.V, e, { w.ChildMask, w.FirstChild, w.Level, w.Owned },
      w.ChildrenBrightnessOnly, w.Inside, this->S.Stack, this->Cut);
    this->CutTriangles += owned;
    this->Triangles += owned > 0 ? add : 0;
    const float key = FromOrderBits(static_cast<uint32_t>(c.Order >> 32));
    if (w.Ahead)
      this->ReplayChildren<P>(*w.Ahead, key);
    else
      this->JudgeStack<P>(key);
  }

  /// Draws waiting cell `c` at its vertex, unrefined by the budget.
  void LeaveWaiting(const Candidate& c)
  {
    this->Cut.Add(c.Node, CutDrawn, BudgetLimited);
    this->Stats.BudgetWaitingTriangles += this->S.Waiting[c.Slot].Owned;
  }

  /// A misfit at the top of the queue: the first one is reported (it has the largest key of
  /// any left in the cut: keys leave the queue in non-increasing order).
  void ReportMisfit(const Candidate& top)
  {
    if (!this->Refused)
    {
      this->Refused = true;
      this->Stats.BudgetRefusedPriority = FromOrderBits(static_cast<uint32_t>(top.Order >> 32));
      this->Stats.BudgetRefusedTriangles =
        this->Counted(top, std::numeric_limits<int64_t>::max() - 1);
    }
  }

  /// Whether a queued refinement owning triangles surely fits in `room`.
  bool SomeSurelyFits(int64_t room) const
  {
    bool fits = room >= Few;
    for (int64_t k = 1; k <= room && k < Few && !fits; ++k)
      fits = this->FewOwning[k] > 0;
    return fits;
  }

  /**
   * No queued refinement owning triangles surely fits any more, and the room will not change
   * until the walk reaches new cells: only refinements owning none are made, and in any order.
   * One pass over the queue makes them and draws the others, instead of a heap pop for each;
   * the walk goes on with the refinements they queue, whose keys order them as before. With
   * the cut's count, the cut is the one that popping the whole queue in order would give; with
   * the drawn one, a refinement owning more than the room but counting no more than it is drawn
   * too (at most Few - 1 triangles of room left unused). (The pass reads a copy of the queue,
   * which the refinements refill: a member, so that its capacity is kept from frame to frame.)
   */
  template <Policy P>
  void MakeTheFreeRefinements()
  {
    std::vector<Candidate>& rest = this->S.QueueRest;
    rest.assign(this->S.Queue.begin(), this->S.Queue.end());
    this->S.Queue.clear();
    for (const Candidate& c : rest)
    {
      const int64_t owned = this->S.Waiting[c.Slot].Owned;
      this->CountOwning(owned, -1);
      if (owned > 0 || this->Triangles > this->Budget)
        this->LeaveWaiting(c);
      else
        this->RefineWaiting<P>(c, 0);
    }
  }

  /// The walk: from the root, the top refinement made while it fits; a misfit ends the walk
  /// (StopAtFirstMisfit, so that a larger budget refines a superset of what a smaller one
  /// refines) or is drawn and the walk goes on (SkipMisfits). What is left waiting is drawn.
  template <Policy P>
  [[gnu::flatten]] void Run()
  {
    std::vector<Candidate>& queue = this->S.Queue;
    constexpr float Unbounded = std::numeric_limits<float>::infinity();
    if (this->S.For && this->S.AheadKey < Unbounded)
    {
      this->JudgeAhead<P>();
      this->Replay<P>(this->S.AheadLists[0][0], Unbounded);
    }
    else
    {
      this->S.Stack.push_back({ 0, { 0, 0, 0 }, false, 0 });
      this->JudgeStack<P>(Unbounded);
    }
    const bool skip = this->In.BudgetStop == BudgetStopRule::SkipMisfits;
    while (!queue.empty())
    {
      const Candidate top = queue.front();
      const int64_t room = this->Budget - this->Triangles;
      const int64_t add = this->Counted(top, room);
      if (add <= room)
      {
        HeapPop(queue, Below);
        this->CountOwning(this->S.Waiting[top.Slot].Owned, -1);
        this->RefineWaiting<P>(top, add);
        continue;
      }
      this->ReportMisfit(top);
      if (!skip)
        break;
      HeapPop(queue, Below);
      this->CountOwning(this->S.Waiting[top.Slot].Owned, -1);
      this->LeaveWaiting(top);
      if (!this->SomeSurelyFits(room))
        this->MakeTheFreeRefinements<P>();
    }
    for (const Candidate& c : queue)
      this->LeaveWaiting(c);
  }
};

// flatten: as SelectDepthFirst (84 ns per visited node against 88 ns)
void Selector::SelectWithinBudget(const SelectionInput& in, int64_t budget, uint8_t* state,
  uint8_t* reason, uint8_t* cullMask, SelectionStats& stats)
{
  // (no foveation table: the budget's priorities need the exact factor)
  const Frame frame = WithPages(MakeFrame(this->View, in, &this->Cones, this->FrameLights),
    this->Pages, this->PageRequester, !this->FirstViewRead);
  CutWriter cut{ state, reason, cullMask, this->Previous, stats };
  this->Stack.clear();
  this->Queue.clear();
  this->Waiting.clear();
  BudgetWalk walk{ *this, frame, in, budget, cut, stats };
  WithPolicy(frame.Model, [&](auto policy) { walk.Run<decltype(policy)::value>(); });
  stats.CutTriangles = walk.CutTriangles;
  stats.BudgetTriangles = walk.Triangles;
  stats.BudgetBinding = walk.Refused || walk.Triangles > budget;
  // the next walk's first pass goes down to this one's first misfit (a finite positive key)
  const float misfit = static_cast<float>(stats.BudgetRefusedPriority);
  this->AheadKey = walk.Refused && misfit > 0 ? misfit : std::numeric_limits<float>::infinity();
}

} // namespace plod
