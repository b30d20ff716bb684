#include "screen_ao/visibility_bitmask.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "common/error.h"
#include "screen_ao/estimator.h"
#include "screen_ao/sample_image.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

namespace {

// Sectors (1e-4 rad for uniform ones): the float32 G-buffer puts a sample on the tangent plane up
// to ~Z·1e-7/|D| rad off it, which must not set the sector at the hemisphere's end.
constexpr double kSectorSlack = 1e-3;

// Far past a hemisphere end: beyond it by this much (rad), against a computed back angle off by
// well under 1e-7 (the worst is near θ = ±π, where acos turns an error of ~1e-15 in the cosine
// into √(2e-15) ≈ 4.5e-8).
constexpr double kEndMargin = 1e-6;

// How far below a farPastEnd bound's cosine a cosine must be for the shortcut (SectorMap::pastCos).
constexpr double kPastCosSlack = 1e-9;

// A sample whose front angle lies within this much (rad) of its side's hemisphere end, or past it,
// sets no sector (SectorMap::bandCos): half of kSectorSlack's 1e-4 rad.
constexpr double kEndBand = 5e-5;

// kEndMargin and −kEndBand with their sines and cosines (SectorMap::cosBeyondEnd).
const Angle kEndMarginAngle = angleOf(kEndMargin);
const Angle kEndBandAngle = angleOf(-kEndBand);

// Sector weightings one pass can serve: uniform and cosine.
constexpr std::size_t kMaxSectorMaps = 2;

// What every sector map of one slice shares: n with its sine and cosine and, for cosine sectors,
// the cosine-weighted mass below V (θ ∈ [n − π/2, 0]) and of the whole open hemisphere. One
// slice's maps compute these once (uniform sectors read neither mass, so without a cosine map
// they are left 0 and their trigonometry skipped). The masses' ends, angleOf(n ∓ π/2), are kept:
// the clear runs' bent-normal integrals read the same angles at the hemisphere's ends.
struct SliceHemisphere {
  SliceHemisphere(double n, bool with_mass) : n(n), sin_n(std::sin(n)), cos_n(std::cos(n)) {
    if (!with_mass) return;
    has_ends = true;
    lo_end = angleOf(n - 0.5 * kPi);
    hi_end = angleOf(n + 0.5 * kPi);
    below = arcIntegral(lo_end, sin_n, cos_n);  // = arcIntegral(n − π/2, n)
    open = below + arcIntegral(hi_end, sin_n, cos_n);
  }
  double n, sin_n, cos_n;
  bool has_ends = false;
  Angle lo_end, hi_end;
  double below = 0.0;
  double open = 0.0;
};

// Whether two doubles have the same bits (not NaN): equal, and the same sign for zeros.
bool sameBits(double a, double b) {
  return a == b && std::signbit(a) == std::signbit(b);
}

// The map between slice angles and sector coordinates of one slice (n fixed).
class SectorMap {
 public:
  SectorMap(const SliceHemisphere& h, SectorWeights weights)
      : n_(h.n),
        sin_n_(h.sin_n),
        cos_n_(h.cos_n),
        weights_(weights),
        has_ends_(h.has_ends),
        lo_end_(h.lo_end),
        hi_end_(h.hi_end),
        below_(h.below),
        open_(h.open) {}
  double coordinate(double theta) const { return coordinate(angleOf(theta)); }
  // The same for an angle with its sine and cosine (clamped to the hemisphere, where
  // sin(n ∓ π/2) = ∓cos n and cos(n ∓ π/2) = ±sin n).
  double coordinate(const Angle& theta) const {
    Angle t = theta;
    if (t.a < n_ - 0.5 * kPi) t = {n_ - 0.5 * kPi, -cos_n_, sin_n_};
    if (t.a > n_ + 0.5 * kPi) t = {n_ + 0.5 * kPi, cos_n_, -sin_n_};
    if (weights_ == SectorWeights::kUniform) return (t.a - n_ + 0.5 * kPi) / kPi;
    return cosineCoordinate(t);
  }
  // The inverse, with its sine and cosine: Newton on C from the uniform guess, kept inside a
  // shrinking bracket (bisection when a step leaves it), to 1e-10 in u.
  Angle angle(double u) const {
    double lo = n_ - 0.5 * kPi;
    double hi = n_ + 0.5 * kPi;
    double t = lo + kPi * u;
    if (weights_ == SectorWeights::kUniform) return angleAt(t);
    for (int k = 0; k < 32; ++k) {
      const Angle a = angleAt(t);
      const double f = cosineCoordinate(a) - u;
      if (std::abs(f) < 1e-10) return a;
      (f < 0.0 ? lo : hi) = t;
      const double slope = (a.c * cos_n_ + a.s * sin_n_) * std::abs(a.s) / open_;
      const double next = slope > 0.0 ? t - f / slope : lo - 1.0;
      t = next > lo && next < hi ? next : 0.5 * (lo + hi);
    }
    return angleAt(t);
  }
  double openMass() const { return open_; }
  // Whether an angle on side `sign` (θ = sign·acos c) lies past that side's hemisphere end,
  // n + sign·π/2, by more than kEndMargin.
  bool farPastEnd(double theta, double sign) const {
    return sign > 0.0 ? theta > n_ + 0.5 * kPi + kEndMargin : theta < n_ - 0.5 * kPi - kEndMargin;
  }
  // A cosine below which the angle sign·acos c is farPastEnd, found without the acos (−∞ where
  // no such bound is used). farPastEnd is acos c > e with e = n + π/2 + kEndMargin on side + and
  // −(n − π/2 − kEndMargin) on side − (the same rounded values); for e in [0, π), c < cos e −
  // kPastCosSlack puts acos c past e by at least that slack (|acos′| ≥ 1), far beyond the
  // rounding of cos e (cosBeyondEnd) and of acos (an ulp, ~4e-16).
  double pastCos(double sign) const { return cosBeyondEnd(sign, kEndMargin, kEndMarginAngle); }
  // A cosine below which the angle sign·acos c lies within kEndBand of side `sign`'s end or past
  // it (as pastCos, with e the end moved kEndBand inwards; −∞ where no such bound is used). A
  // sample whose front angle does sets no sector under either weighting: its back angles lie
  // further out (sampleBits; rounded the wrong way by under 1e-7 rad) and clamp to the end, so
  // both coordinates are within 32·(kEndBand/π + 1e-7) ≈ 5.1e-4 sectors of the end's uniform one,
  // less than kSectorSlack, and within far less of the cosine one, whose weight cos(θ − n)|sin θ|
  // is at most |θ − (n ± π/2)| there over an open mass of at least 1.
  double bandCos(double sign) const { return cosBeyondEnd(sign, -kEndBand, kEndBandAngle); }
  // The coordinate every angle past side `sign`'s end has (coordinate clamps it to this angle).
  double endCoordinate(double sign) const {
    return sign > 0.0 ? coordinate(Angle{n_ + 0.5 * kPi, cos_n_, -sin_n_})
                      : coordinate(Angle{n_ - 0.5 * kPi, -cos_n_, sin_n_});
  }

 private:
  // A cosine below which the angle sign·acos c lies past e, side `sign`'s end moved `beyond`
  // outwards (b: angleOf(beyond)): e = n + π/2 + β on side + and −(n − π/2 − β) on side −, as
  // acos c > e. cos e = ∓sin(n ± β) comes from n's sine and cosine and β's, without a cos call:
  // a few ulps off (~1e-15, with the rounding of e itself), far inside kPastCosSlack.
  double cosBeyondEnd(double sign, double beyond, const Angle& b) const {
    const double e = sign > 0.0 ? n_ + 0.5 * kPi + beyond : -(n_ - 0.5 * kPi - beyond);
    if (!(e >= 0.0 && e < kPi)) return -std::numeric_limits<double>::infinity();
    const double cos_e = sign > 0.0 ? -(sin_n_ * b.c + cos_n_ * b.s) : sin_n_ * b.c - cos_n_ * b.s;
    return cos_e - kPastCosSlack;
  }

  // angleOf(t), taken from the hemisphere's ends where t has the bits of one of them.
  Angle angleAt(double t) const {
    if (has_ends_ && sameBits(t, lo_end_.a)) return lo_end_;
    if (has_ends_ && sameBits(t, hi_end_.a)) return hi_end_;
    return angleOf(t);
  }

  // ∫ from n − π/2 to θ of cos(x − n)|sin x| dx over the open mass, θ within the hemisphere
  // (arcIntegral is the signed mass from 0).
  double cosineCoordinate(const Angle& t) const {
    const double arc = arcIntegral(t, sin_n_, cos_n_);
    return std::clamp((t.a <= 0.0 ? below_ - arc : below_ + arc) / open_, 0.0, 1.0);
  }

  double n_, sin_n_, cos_n_;
  SectorWeights weights_;
  bool has_ends_;
  Angle lo_end_, hi_end_;
  double below_;
  double open_;
};

// ∫ over [θa, θb] of cos(θ − n)|sin θ| (sin θ, cos θ) dθ: differences of Alg. 2's one-side terms.
void bentOver(const Angle& a, const Angle& b, const Slice& slice, double* t0, double* t1) {
  double a0 = 0.0, a1 = 0.0, b0 = 0.0, b1 = 0.0;
  addBentSide(a, slice.sin_n, slice.cos_n, &a0, &a1);  // = bentIntegrals(0, a)
  addBentSide(b, slice.sin_n, slice.cos_n, &b0, &b1);
  const double sa = a.a < 0.0 ? -1.0 : 1.0;  // bentIntegrals(0, h): the mass over [h, 0] for h < 0
  const double sb = b.a < 0.0 ? -1.0 : 1.0;
  *t0 = sb * b0 - sa * a0;
  *t1 = sb * b1 - sa * a1;
}

// The slice angle sign·acos(c) on a side, with its sine and cosine.
Angle sliceAngle(double c, double sign) {
  const double cc = std::clamp(c, -1.0, 1.0);
  return {sign * std::acos(cc), sign * std::sqrt(1.0 - cc * cc), cc};
}

// sectorBits's run: lo*32 ∈ [0, 32] so its floor is its truncation, and the count is a ceiling
// only where positive (a NaN bound gives no sectors, as before).
std::uint32_t sectorRun(double ua, double ub) {
  const double lo = std::clamp(std::min(ua, ub), 0.0, 1.0);
  const double hi = std::clamp(std::max(ua, ub), 0.0, 1.0);
  const double span = (hi - lo) * kSectors - kSectorSlack;
  if (!(span > 0.0)) return 0u;
  const int start = std::min(kSectors - 1, static_cast<int>(lo * kSectors));
  int count = static_cast<int>(span);
  if (count < span) ++count;
  const std::uint32_t run = count >= kSectors ? 0xffffffffu : (1u << count) - 1u;
  return run << start;
}

// The sectors of one sample (`front`, the offset from P, on side `sign`) for each sector map and
// thickness, OR-ed into bits[m·T + k] (u_front[m]: the front angle's coordinate under maps[m];
// past_cos and u_end[m]: the side's maps[0].pastCos and maps[m].endCoordinate). Each back angle
// is computed once and read by every map, and not at all where every map's bits already hold all
// the sectors the sample can set (reachableSectors). The slab's back point front − tV moves away
// from V as t grows (cos θ_b = (f·V − t)/|f − tV| falls), so once its angle is far past the
// side's hemisphere end (farPastEnd, which does not depend on the map: further than any rounding
// of it; told by pastCos before any acos where it can), it and every thicker slab's back angle
// clamp to the end's coordinate, whose sectors are computed once; the same bits as computing each.
void sampleBits(const SectorMap* maps, std::size_t map_count, const Eigen::Vector3d& front,
                const Eigen::Vector3d& v, const double* u_front, double sign, double past_cos,
                const double* u_end, const std::vector<double>& thicknesses, std::uint32_t* bits) {
  const std::size_t T = thicknesses.size();
  std::array<std::uint32_t, kMaxSectorMaps> reachable{};
  std::array<std::uint32_t, kMaxSectorMaps> end_bits{};  // set with clamped_from
  for (std::size_t m = 0; m < map_count; ++m) reachable[m] = reachableSectors(u_front[m], sign);
  double clamped_from = std::numeric_limits<double>::infinity();  // the thinnest slab past the end
  for (std::size_t k = 0; k < T; ++k) {
    bool covered = true;
    for (std::size_t m = 0; m < map_count; ++m) {
      covered = covered && (bits[m * T + k] & reachable[m]) == reachable[m];
    }
    if (covered) continue;
    bool past = !(thicknesses[k] < clamped_from);
    Angle theta{};
    if (!past) {
      const Eigen::Vector3d back = front - thicknesses[k] * v;
      const double c = std::clamp(back.normalized().dot(v), -1.0, 1.0);
      past = c < past_cos;
      if (!past) {
        theta = sliceAngle(c, sign);
        past = maps[0].farPastEnd(theta.a, sign);
      }
      if (past) {
        clamped_from = thicknesses[k];
        for (std::size_t m = 0; m < map_count; ++m) end_bits[m] = sectorRun(u_front[m], u_end[m]);
      }
    }
    for (std::size_t m = 0; m < map_count; ++m) {
      bits[m * T + k] |= past ? end_bits[m] : sectorRun(u_front[m], maps[m].coordinate(theta));
    }
  }
}

// What is the same for every pixel of a pass: the slice angles ψ_k = π(k + ½)/slices with their
// sines and cosines, and the samples' offsets ±(step + ½)/steps (side·steps + step; side 0 along
// −ω), which times the projected radius are their distances in pixels.
struct PassTables {
  explicit PassTables(const BitmaskSettings& s) : psi(s.slices), offsets(2 * s.steps) {
    for (int k = 0; k < s.slices; ++k) psi[k] = angleOf(kPi * (k + 0.5) / s.slices);
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? -1.0 : 1.0;
      for (int step = 0; step < s.steps; ++step) {
        offsets[side * s.steps + step] = sign * (step + 0.5) / s.steps;
      }
    }
  }
  std::vector<Angle> psi;
  std::vector<double> offsets;
};

// One slice's 32 sectors from both sides' samples, for each sector map and thickness (bits[m·T +
// k] for maps[m] at thicknesses[k]): the samples and their front angles are shared, each
// thickness adds its own back angles and each map its own coordinates of them.
void sliceBits(const SampleImage& image, int i, int j, const Eigen::Vector3d& x,
               const Eigen::Vector3d& v, const Slice& slice, const SectorMap* maps,
               std::size_t map_count, double radius_px, const BitmaskSettings& s,
               const std::vector<double>& offsets, const std::vector<double>& thicknesses,
               std::uint32_t* bits) {
  std::fill(bits, bits + map_count * thicknesses.size(), 0u);
  std::array<double, kMaxSectorMaps> u_front{};
  std::array<double, kMaxSectorMaps> u_end{};
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    const double past_cos = maps[0].pastCos(sign);
    const double band_cos = std::max(past_cos, maps[0].bandCos(sign));
    for (std::size_t m = 0; m < map_count; ++m) u_end[m] = maps[m].endCoordinate(sign);
    for (int step = 0; step < s.steps; ++step) {
      const double t = offsets[side * s.steps + step] * radius_px;
      Eigen::Vector3d sample;
      if (!image.point(i + 0.5 + t * slice.omega.x(), j + 0.5 - t * slice.omega.y(), &sample)) {
        continue;
      }
      const Eigen::Vector3d front = sample - x;
      const double length = front.norm();
      if (length > s.radius || !(length > 0.0)) continue;
      // Every back angle lies further past the end than a front one far past it (sampleBits), so
      // every coordinate is the end's and the sample sets no sector; nor does one whose front
      // angle lies within kEndBand of the end (bandCos).
      const double c = std::clamp(front.dot(v) / length, -1.0, 1.0);
      if (c < band_cos) continue;
      const Angle theta = sliceAngle(c, sign);
      if (maps[0].farPastEnd(theta.a, sign)) continue;
      for (std::size_t m = 0; m < map_count; ++m) u_front[m] = maps[m].coordinate(theta);
      sampleBits(maps, map_count, front, v, u_front.data(), sign, past_cos, u_end.data(),
                 thicknesses, bits);
    }
  }
}

// The number of set bits (std::bitset's count, without its library call).
int setSectors(std::uint32_t bits) {
  bits = bits - ((bits >> 1) & 0x55555555u);
  bits = (bits & 0x33333333u) + ((bits >> 2) & 0x33333333u);
  bits = (bits + (bits >> 4)) & 0x0f0f0f0fu;
  return static_cast<int>((bits * 0x01010101u) >> 24);
}

// One slice's visibility and, unless sum is null, bent-normal terms from its sectors.
void addSlice(std::uint32_t bits, const Slice& slice, const SectorMap& map,
              const Eigen::Vector3d& v, SectorWeights weights, double* visibility,
              Eigen::Vector3d* sum) {
  const double clear = 1.0 - static_cast<double>(setSectors(bits)) / kSectors;
  *visibility +=
      weights == SectorWeights::kUniform ? clear : slice.projected_length * map.openMass() * clear;
  if (sum == nullptr) return;
  for (int run = 0; run < kSectors;) {  // each run of clear sectors [run, end)
    const std::uint32_t clear_from = ~bits >> run;
    if (clear_from == 0u) break;
    run += __builtin_ctz(clear_from);
    const std::uint32_t set_from = bits >> run;
    const int end = set_from == 0u ? kSectors : run + __builtin_ctz(set_from);
    double t0 = 0.0;
    double t1 = 0.0;
    bentOver(map.angle(static_cast<double>(run) / kSectors),
             map.angle(static_cast<double>(end) / kSectors), slice, &t0, &t1);
    *sum += slice.projected_length * (t0 * slice.o + t1 * v);
    run = end;
  }
}

// Pixel p for each sector weighting and thickness: Â and the view-space bent normal into
// a[w·T + k], bent[w·T + k] for weights[w] at thicknesses[k] (Â alone when bent is null). tables
// is PassTables(s) and image SampleImage(g), both made once per pass; bits holds
// weights.size()·T words of scratch.
void bitmaskPixel(const GBuffer& g, const SampleImage& image, int i, int j, std::size_t p,
                  const BitmaskSettings& s, const PassTables& tables,
                  const std::vector<SectorWeights>& weights, const std::vector<double>& thicknesses,
                  std::uint32_t* bits, double* a, Eigen::Vector3d* bent) {
  const auto [x, v, normal] = pixelFrame(g, p);
  const double radius_px = s.radius * g.pixelsPerMetre(g.depth[p]);
  const std::size_t T = thicknesses.size();
  const std::size_t n = weights.size() * T;
  const bool with_mass =
      std::find(weights.begin(), weights.end(), SectorWeights::kCosine) != weights.end();
  std::fill(a, a + n, 0.0);
  if (bent != nullptr) std::fill(bent, bent + n, Eigen::Vector3d::Zero());
  const ViewSliceBasis basis = viewSliceBasis(g, x, v);
  for (int k = 0; k < s.slices; ++k) {
    // makeViewSlice's bits, from the pixel's basis made once.
    const Slice slice = withAngle(viewSliceWithoutAngle(g, basis, x, v, normal, tables.psi[k]));
    const SliceHemisphere hemisphere(slice.n, with_mass);
    const std::array<SectorMap, kMaxSectorMaps> maps = {SectorMap(hemisphere, weights.front()),
                                                        SectorMap(hemisphere, weights.back())};
    sliceBits(image, i, j, x, v, slice, maps.data(), weights.size(), radius_px, s, tables.offsets,
              thicknesses, bits);
    for (std::size_t t = 0; t < n; ++t) {
      addSlice(bits[t], slice, maps[t / T], v, weights[t / T], &a[t],
               bent == nullptr ? nullptr : &bent[t]);
    }
  }
  for (std::size_t t = 0; t < n; ++t) a[t] /= s.slices;
}

}  // namespace

double sectorCoordinate(double theta, double n, SectorWeights weights) {
  return SectorMap(SliceHemisphere(n, weights == SectorWeights::kCosine), weights)
      .coordinate(theta);
}

std::uint32_t sectorBits(double ua, double ub) {
  return sectorRun(ua, ub);
}

// The back angle lies past the front one, away from V (cos θ_b = (f·V − t)/|f − tV| falls as t
// grows), so on side + its coordinate is ≥ u and sectorRun starts at ⌊32u⌋; on side − it is ≤ u and
// the run ends at or before ⌊32u⌋ (its count, ⌈32(u − u_b) − slack⌉ up to rounding of ~1e-14, is at
// most ⌈32u⌉ − ⌊32u_b⌋). Rounding can put the back angle past the front one the wrong way only by
// far less than the slack (1e-7 rad against 1e-3 of a sector), which sets no sector at all.
std::uint32_t reachableSectors(double u, double sign) {
  const int k = std::min(kSectors - 1, static_cast<int>(std::clamp(u, 0.0, 1.0) * kSectors));
  if (sign > 0.0) return 0xffffffffu << k;
  return k == kSectors - 1 ? 0xffffffffu : (1u << (k + 1)) - 1u;
}

double pastEndCos(double n, double sign) {
  return SectorMap(SliceHemisphere(n, false), SectorWeights::kUniform).pastCos(sign);
}

double endBandCos(double n, double sign) {
  return SectorMap(SliceHemisphere(n, false), SectorWeights::kUniform).bandCos(sign);
}

void validate(const BitmaskSettings& s) {
  const std::string name =
      describe(s.weights == SectorWeights::kUniform ? Estimator::kBitmaskUniform
                                                    : Estimator::kBitmaskCosine)
          .name;
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error(name + ": radius must be a positive finite distance in metres");
  }
  if (s.slices < 1 || s.slices > 1024) throw Error(name + ": slices must be in [1, 1024]");
  if (s.steps < 1 || s.steps > 4096) throw Error(name + ": steps must be in [1, 4096]");
  if (!(s.thickness > 0.0) || !std::isfinite(s.thickness)) {
    throw Error(name + ": thickness must be a positive finite distance in metres");
  }
}

AoEstimate visibilityBitmask(const GBuffer& g, const BitmaskSettings& s) {
  validate(s);
  const std::vector<SectorWeights> weights = {s.weights};
  const std::vector<double> thickness = {s.thickness};
  const PassTables tables(s);
  const SampleImage image(g);
  return estimatePerPixel(g, [&](int i, int j, std::size_t p, double* a, Eigen::Vector3d* bent) {
    std::uint32_t bits = 0;
    bitmaskPixel(g, image, i, j, p, s, tables, weights, thickness, &bits, a, bent);
  });
}

std::vector<AoEstimate> visibilityBitmasks(const GBuffer& g, const BitmaskSettings& s,
                                           const std::vector<double>& thicknesses,
                                           EstimateParts parts) {
  return std::move(visibilityBitmasks(g, s, {s.weights}, thicknesses, parts).front());
}

std::vector<std::vector<AoEstimate>> visibilityBitmasks(const GBuffer& g, const BitmaskSettings& s,
                                                        const std::vector<SectorWeights>& weights,
                                                        const std::vector<double>& thicknesses,
                                                        EstimateParts parts) {
  if (weights.empty() || weights.size() > kMaxSectorMaps) {
    throw Error("internal: a bitmask pass serves one or two sector weightings");
  }
  std::vector<std::vector<AoEstimate>> out(weights.size());
  for (std::size_t w = 0; w < weights.size(); ++w) {
    for (double t : thicknesses) {
      BitmaskSettings at = s;
      at.weights = weights[w];
      at.thickness = t;
      validate(at);
      out[w].push_back(makeEstimate(g, parts));
    }
  }
  const bool with_bent = parts == EstimateParts::kAoAndBent;
  const std::size_t T = thicknesses.size();
  const PassTables tables(s);
  const SampleImage image(g);
  forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
    // Per-thread scratch, sized once per thread rather than allocated per pixel.
    thread_local std::vector<std::uint32_t> bits;
    thread_local std::vector<double> a;
    thread_local std::vector<Eigen::Vector3d> bent;
    bits.resize(weights.size() * T);
    a.resize(weights.size() * T);
    bent.resize(with_bent ? a.size() : 0);
    bitmaskPixel(g, image, i, j, p, s, tables, weights, thicknesses, bits.data(), a.data(),
                 with_bent ? bent.data() : nullptr);
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (with_bent) {
        storePixel(g, p, a[k], bent[k], &out[k / T][k % T]);
      } else {
        storeAo(p, a[k], &out[k / T][k % T]);
      }
    }
  });
  return out;
}

}  // namespace gtbake
