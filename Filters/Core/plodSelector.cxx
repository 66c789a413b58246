// SPDX-License-Identifier: BSD-3-Clause
#include "plodSelector.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

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

/// max(0, x)^power, with 0^0 = 1 so that power 0 makes every cosine term constant. Integer
/// powers up to 2^16 (the usual specular powers) by repeated squaring, exact and fast.
inline double PositivePower(double x, double power)
{
  x = std::min(1.0, std::max(0.0, x));
  if (power == 1.0)
  {
    return x;
  }
  if (power >= 0 && power <= 65536 && power == std::floor(power))
  {
    double result = 1.0, base = x;
    for (unsigned e = static_cast<unsigned>(power); e; e >>= 1)
    {
      if (e & 1u)
        result *= base;
      base *= base;
    }
    return result;
  }
  return std::pow(x, power);
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
  // highest: the smallest angle max(0, a - theta); lowest: the largest angle min(pi, a + theta)
  const double cLo = cosA >= cosT ? 1.0 : cosA * cosT + sinA * sinT;
  const double cHi = cosA <= -cosT ? -1.0 : cosA * cosT - sinA * sinT;
  high = PositivePower(cLo, power);
  low = PositivePower(cHi, power);
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
  auto fail = [why](const char* text) {
    if (why)
    {
      *why = text;
    }
    return false;
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
  for (const SelectorLight& l : in.Lights)
  {
    if (!Finite(l.Position, 3) || !std::isfinite(l.Diffuse) || !std::isfinite(l.Specular))
    {
      return fail("a light has a non-finite position, direction or intensity");
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

void Selector::SetOctree(const OctreeView& view)
{
  this->View = view;
  this->SinTheta.resize(view.NumberOfNodes);
  this->CosTheta.resize(view.NumberOfNodes);
  for (int64_t n = 0; n < view.NumberOfNodes; ++n)
  {
    this->SinTheta[n] = std::sin(view.ConeAngle[n]);
    this->CosTheta[n] = std::cos(view.ConeAngle[n]);
  }
  this->Previous.clear();
}

void Selector::Select(const SelectionInput& in, uint8_t* state, uint8_t* reason, uint8_t* cullMask,
  SelectionStats& stats)
{
  const OctreeView& v = this->View;
  stats = SelectionStats();
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
  if (v.NumberOfNodes == 0)
  {
    return;
  }

  const bool srcc = in.Error == ErrorModel::SRCC;
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
  double dop[3] = { 0, 0, -1 };
  if (in.Parallel)
  {
    const double l = std::sqrt(Dot(in.ProjectionDirection, in.ProjectionDirection));
    for (int a = 0; a < 3; ++a)
      dop[a] = in.ProjectionDirection[a] / l;
  }
  const bool anySpecular = [&] {
    for (const SelectorLight& l : in.Lights)
      if (l.Specular > 0)
        return true;
    return false;
  }();

  auto hide = [&](int64_t n, CutReason r) {
    state[n] = CutHidden;
    reason[n] = r;
    this->Previous.push_back(static_cast<int32_t>(n));
    ++stats.InCut;
  };
  auto draw = [&](int64_t n, CutReason r) {
    state[n] = CutDrawn;
    reason[n] = r;
    this->Previous.push_back(static_cast<int32_t>(n));
    ++stats.InCut;
    ++stats.Drawn;
  };
  auto open = [&](int64_t n) {
    state[n] = CutOpen;
    reason[n] = OpenedLeaf;
    this->Previous.push_back(static_cast<int32_t>(n));
    ++stats.InCut;
    ++stats.Drawn;
    ++stats.Opened;
  };

  // the walk's stack is a member: its capacity is kept from frame to frame
  std::vector<Entry>& stack = this->Stack;
  stack.clear();
  stack.push_back({ 0, { 0, 0, 0 }, false });
  // refine: the children go on (a leaf is opened); a child index that does not follow its
  // parent (corrupt arrays) is never followed, so the walk always ends
  auto refine = [&](const Entry& e, bool brightnessOnly) {
    const unsigned mask = v.ChildMask[e.Node];
    if (mask == 0)
    {
      open(e.Node);
      return;
    }
    const int32_t first = v.FirstChild[e.Node];
    if (first <= e.Node || first + __builtin_popcount(mask) > v.NumberOfNodes ||
      v.Level[e.Node] >= MaxFinestLevel)
    {
      draw(e.Node, AcceptedError);
      return;
    }
    for (int c = 7, r = __builtin_popcount(mask) - 1; c >= 0; --c)
    {
      if (mask & (1u << c))
      {
        stack.push_back({ first + r--,
          { 2 * e.C[0] + (c & 1), 2 * e.C[1] + ((c >> 1) & 1), 2 * e.C[2] + ((c >> 2) & 1) },
          brightnessOnly });
      }
    }
  };

  while (!stack.empty())
  {
    const Entry e = stack.back();
    stack.pop_back();
    const int32_t n = e.Node;
    ++stats.Visited;
    const int level = std::min<int>(v.Level[n], MaxFinestLevel);
    const double h = v.CellEdge(level);
    const double lo[3] = { e.C[0] * h, e.C[1] * h, e.C[2] * h };

    // 1. frustum
    if (!e.BrightnessOnly && in.UseFrustum)
    {
      uint8_t outside = 0;
      for (int p = 0; p < 6; ++p)
      {
        const double* pl = in.Planes[p];
        double far = pl[3];
        for (int a = 0; a < 3; ++a)
          far += pl[a] * (pl[a] > 0 ? lo[a] + h : lo[a]);
        outside |= far < 0 ? uint8_t(1u << p) : uint8_t(0);
      }
      if (outside)
      {
        hide(n, Culled);
        if (cullMask)
        {
          cullMask[n] = outside;
        }
        continue;
      }
    }
    // a cell coarser than the minimum level (incomplete on each process of a distributed
    // rendering) is refined without any other test
    if (level < in.MinimumLevel)
    {
      refine(e, false);
      continue;
    }
    // a cell holding the eye has an unbounded error: refine it
    const bool eyeInside = in.Eye[0] >= lo[0] && in.Eye[0] <= lo[0] + h && in.Eye[1] >= lo[1] &&
      in.Eye[1] <= lo[1] + h && in.Eye[2] >= lo[2] && in.Eye[2] <= lo[2] + h;
    if (eyeInside && !in.Parallel)
    {
      refine(e, e.BrightnessOnly);
      continue;
    }

    const float* vf = &v.Vertex[3 * n];
    const double x[3] = { vf[0], vf[1], vf[2] };
    const float* nf = &v.ConeAxis[3 * n];
    const double axis[3] = { nf[0], nf[1], nf[2] };
    double ve[3], k;
    if (in.Parallel)
    {
      for (int a = 0; a < 3; ++a)
        ve[a] = -dop[a];
      k = in.PixelScale;
    }
    else
    {
      const double d[3] = { in.Eye[0] - x[0], in.Eye[1] - x[1], in.Eye[2] - x[2] };
      const double dist = std::sqrt(Dot(d, d));
      if (!(dist > 0))
      {
        // the eye on the vertex (outside the cell only through rounding): refine
        refine(e, e.BrightnessOnly);
        continue;
      }
      for (int a = 0; a < 3; ++a)
        ve[a] = d[a] / dist;
      k = in.PixelScale / dist;
    }

    // tolerance factor: velocity (IPV/DPV) and foveation
    double factor = velocity;
    double D = 0; // Cheng's normalised distance from the point of interest
    if (in.Foveation != FoveationMode::Off)
    {
      if (in.Foveation == FoveationMode::Object)
      {
        const double* up = in.FoveationUp;
        double r[3], f[3];
        for (int a = 0; a < 3; ++a)
        {
          r[a] = x[a] - in.FoveationCentre[a];
          f[a] = in.FoveationPoint[a] - in.FoveationCentre[a];
        }
        const double y = Dot(r, up), fy = Dot(f, up);
        for (int a = 0; a < 3; ++a)
        {
          r[a] -= y * up[a];
          f[a] -= fy * up[a];
        }
        const double c[3] = { r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2],
          r[0] * f[1] - r[1] * f[0] };
        const double beta =
          (Dot(r, r) > 0 && Dot(f, f) > 0) ? std::atan2(std::sqrt(Dot(c, c)), Dot(r, f)) : 0.0;
        D = in.FoveationWeights[0] * beta / Pi +
          in.FoveationWeights[1] * std::abs(y - fy) / in.FoveationHeight;
      }
      else
      {
        const double* g = in.GazeDirection;
        const double ray[3] = { -ve[0], -ve[1], -ve[2] };
        const double c[3] = { ray[1] * g[2] - ray[2] * g[1], ray[2] * g[0] - ray[0] * g[2],
          ray[0] * g[1] - ray[1] * g[0] };
        D = std::atan2(std::sqrt(Dot(c, c)), Dot(ray, g)) / Pi;
      }
      if (!cheng)
        factor *= std::exp(in.FoveationRate * D);
    }
    if (cheng)
    {
      // Cheng §2 alone: curvature against the foveated threshold exp(-K D)
      if (ChengAccepts(this->CosTheta[n], this->SinTheta[n], in.FoveationRate, D))
        draw(n, AcceptedError);
      else
        refine(e, false);
      continue;
    }
    // a tolerance of 0 accepts nothing (even an error of exactly 0)
    const double Ts = in.ContourTolerance > 0 ? in.ContourTolerance * factor : -1.0;
    const double Tb = in.BrightnessTolerance > 0 ? in.BrightnessTolerance * factor : -1.0;

    const double dE = v.ShapeError[n];
    const double cosT = this->CosTheta[n], sinT = this->SinTheta[n];
    const double c = Dot(axis, ve);
    // v_f = A v + b (micro motion)
    double vfm[3] = { 0, 0, 0 };
    if (micro)
    {
      for (int a = 0; a < 3; ++a)
        vfm[a] = in.MotionA[a][0] * x[0] + in.MotionA[a][1] * x[1] + in.MotionA[a][2] * x[2] +
          in.MotionB[a];
    }

    // a cell that is not a union of discs is refined while the part it could make vanish is
    // thicker than a pixel (its tolerance follows motion and foveation like the others: DPV's
    // infinite factor still accepts the root alone)
    const bool unsafe = !(v.Flags[n] & NodeTopologySafe) &&
      double(v.Thickness[n]) * k > in.TopologyTolerance * factor;
    // a cell whose edge projects within the contour tolerance cannot show more than it: its
    // points lie within that many pixels of its vertex (the size floor of every mode)
    const bool small = Ts >= 0 && h * k <= Ts && !unsafe;

    if (velocityAlone)
    {
      if (small)
        draw(n, AcceptedSize);
      else
      {
        stats.TopologyRefined += (Ts >= 0 && h * k <= Ts) ? 1 : 0;
        refine(e, false);
      }
      continue;
    }

    if (!srcc)
    {
      if (small && in.Error != ErrorModel::Distance)
      {
        draw(n, AcceptedSize);
        continue;
      }
      if (in.Error == ErrorModel::Distance)
      {
        if (level >= in.DistanceLevel && !unsafe)
          draw(n, AcceptedError);
        else
          refine(e, false);
        continue;
      }
      double tol = Ts;
      if (in.Error == ErrorModel::PSEC)
      {
        bool feature = !(cosT > 0 && (c > sinT || c < -sinT)); // on the contour
        for (size_t i = 0; i < in.Lights.size() && !feature && anySpecular; ++i)
        {
          const SelectorLight& l = in.Lights[i];
          if (l.Specular <= 0)
            continue;
          double vl[3];
          for (int a = 0; a < 3; ++a)
            vl[a] = l.Positional ? l.Position[a] - x[a] : l.Position[a];
          const double ll = std::sqrt(Dot(vl, vl));
          if (!(ll > 0))
          {
            feature = true;
            break;
          }
          double hv[3];
          for (int a = 0; a < 3; ++a)
            hv[a] = vl[a] / ll + ve[a];
          const double hl = std::sqrt(Dot(hv, hv));
          feature = hl > 0 && Dot(axis, hv) / hl >= cosT;
        }
        if (feature)
          tol *= in.PSECFactor;
      }
      const double err = std::max(0.0, dE - std::abs(Dot(axis, vfm))) * k;
      if (err <= tol && !unsafe)
        draw(n, AcceptedError);
      else
      {
        stats.TopologyRefined += err <= tol ? 1 : 0;
        refine(e, false);
      }
      continue;
    }

    // 2. contour (SRCC eq. 4-5, TMM eq. 6-7)
    CutReason accepted = AcceptedBrightness;
    if (!e.BrightnessOnly)
    {
      if (cosT > 0 && c < -sinT)
      {
        if (in.HideBackFaces)
          hide(n, BackFacing);
        else
          draw(n, BackFacing); // an open surface: seen from behind, drawn but not refined
        continue;
      }
      if (small)
      {
        draw(n, AcceptedSize);
        continue;
      }
      // an open surface's rim is a silhouette from every side: refined like the contour
      if (v.Flags[n] & NodeBoundary)
      {
        refine(e, false);
        continue;
      }
      if (!(cosT > 0 && c > sinT))
      {
        const double err = std::max(0.0, dE - std::abs(Dot(axis, vfm))) * k;
        if (err > Ts)
        {
          refine(e, false);
          continue;
        }
        accepted = AcceptedContour;
      }
    }
    if (unsafe)
    {
      ++stats.TopologyRefined;
      refine(e, e.BrightnessOnly);
      continue;
    }

    // 3. brightness (SRCC eq. 7-10, TMM eq. 11-13)
    double dB = 0;
    if (!in.Lights.empty())
    {
      // TMM eq. (9): the octree's (min, max) reflectances; one material: min = max
      const double MdMin = in.UseOctreeMaterial ? v.Diffuse[2 * n] : in.Diffuse;
      const double MdMax = in.UseOctreeMaterial ? v.Diffuse[2 * n + 1] : in.Diffuse;
      const double MsMin = in.UseOctreeMaterial ? v.Specular[2 * n] : in.Specular;
      const double MsMax = in.UseOctreeMaterial ? v.Specular[2 * n + 1] : in.Specular;
      for (const SelectorLight& l : in.Lights)
      {
        if (dB >= 1.0)
        {
          break; // a rendered pixel saturates at 1: no cell can vary by more (see below)
        }
        double vl[3];
        for (int a = 0; a < 3; ++a)
          vl[a] = l.Positional ? l.Position[a] - x[a] : l.Position[a];
        const double ll = std::sqrt(Dot(vl, vl));
        if (!(ll > 0))
        {
          // a light on the vertex lights every direction: the largest variation
          dB += MdMax * l.Diffuse + MsMax * l.Specular;
          continue;
        }
        for (int a = 0; a < 3; ++a)
          vl[a] /= ll;
        double high, low;
        if (MdMax > 0 && l.Diffuse > 0)
        {
          const double ca = Dot(axis, vl);
          ConeCosineRange(ca, std::sqrt(std::max(0.0, 1 - ca * ca)), cosT, sinT, 1.0, high, low);
          dB += BrightnessChange(MdMin, MdMax, l.Diffuse, high, low);
        }
        if (MsMax > 0 && l.Specular > 0)
        {
          double hv[3];
          for (int a = 0; a < 3; ++a)
            hv[a] = vl[a] + ve[a];
          const double hl = std::sqrt(Dot(hv, hv));
          high = 1.0; // light opposite the eye: no defined half vector
          low = 0.0;
          if (hl > 0)
          {
            const double cb = Dot(axis, hv) / hl;
            ConeCosineRange(
              cb, std::sqrt(std::max(0.0, 1 - cb * cb)), cosT, sinT, in.SpecularPower, high, low);
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
    double size = h * std::max(0.0, c);
    if (micro)
    {
      double vd[3];
      for (int a = 0; a < 3; ++a)
        vd[a] = axis[a] - c * ve[a];
      const double vdl = std::sqrt(Dot(vd, vd));
      if (vdl > 1e-12)
        size = std::max(0.0, size - std::abs(Dot(vd, vfm)) / vdl);
    }
    if (dB * size * k <= Tb)
      draw(n, accepted);
    else
      refine(e, true);
  }
  // internal invariants (debug builds): on a valid octree the walk writes a valid cut, and the
  // figures count it
  assert(stats.Drawn <= stats.InCut && stats.InCut == int64_t(this->Previous.size()));
  assert(!ValidateOctree(v) || ValidateCut(v, state));
}

} // namespace plod
