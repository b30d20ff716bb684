#include "screen_ao/gtao_reference.h"

#include <tbb/parallel_for.h>

#include <string>
#include <vector>

#include "common/error.h"
#include "screen_ao/horizon_search.h"

namespace gtbake {

void validate(const GtaoReferenceSettings& s) {
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error("gtao-reference: radius must be a positive finite distance in metres");
  }
  if (s.slices < 1 || s.slices > 1024) throw Error("gtao-reference: slices must be in [1, 1024]");
  if (!(s.refine_tolerance > 0.0) || !std::isfinite(s.refine_tolerance)) {
    throw Error("gtao-reference: refine_tolerance must be a positive finite number");
  }
  if (s.refine_levels < 0 || s.refine_levels > 16) {
    throw Error("gtao-reference: refine_levels must be in [0, 16]");
  }
}

namespace {

// One direction's terms: its side's visibility |N'|·arc(h) and bent-normal part |N'|(t0 o + t1 V).
struct DirectionTerms {
  double visibility = 0.0;
  Eigen::Vector3d bent = Eigen::Vector3d::Zero();
};

// The slice angle ψ (with its sine and cosine) of each base direction φ_k = step·(k + ½), the
// same for every pixel of a run: ψ = φ on side 1 (φ < π), φ − π on side 0.
std::vector<Angle> baseSliceAngles(const GtaoReferenceSettings& s) {
  const int count = 2 * s.slices;
  const double step = 2.0 * kPi / count;
  std::vector<Angle> out(count);
  for (int k = 0; k < count; ++k) {
    const double phi = step * (k + 0.5);
    out[k] = angleOf(phi < kPi ? phi : phi - kPi);
  }
  return out;
}

class ReferencePixel {
 public:
  ReferencePixel(const GBuffer& g, int i, int j, const GtaoReferenceSettings& s,
                 const std::vector<Angle>& base_psi)
      : g_(g),
        s_(s),
        base_psi_(base_psi),
        f_(pixelFrame(g, static_cast<std::size_t>(j) * g.width + i)),
        basis_(viewSliceBasis(g, f_.x, f_.v)),
        pixel_(g, i, j, f_.x, f_.v, s.radius) {}

  // ∫ over φ ∈ [0, 2π) of the direction terms: the trapezoid rule on the base grid, each interval
  // bisected while its jump is large (docs/screen_ao.md, "gtao-reference").
  DirectionTerms integrate() const {
    const int count = 2 * s_.slices;
    const double step = 2.0 * kPi / count;
    std::vector<DirectionTerms> base(count);
    for (int k = 0; k < count; ++k) base[k] = at(step * (k + 0.5), base_psi_[k]);
    DirectionTerms sum;
    for (int k = 0; k < count; ++k) {
      refine(step * (k + 0.5), step, base[k], base[(k + 1) % count], s_.refine_levels, &sum);
    }
    return sum;
  }

 private:
  // Direction φ: side 1 of the slice at ψ = φ for φ < π, side 0 of the slice at ψ = φ − π.
  DirectionTerms at(double phi) const { return at(phi, angleOf(phi < kPi ? phi : phi - kPi)); }
  // The same with ψ and its sine and cosine given.
  DirectionTerms at(double phi, const Angle& psi) const {
    const int side = phi < kPi ? 1 : 0;
    const Slice slice = viewSliceWithoutAngle(g_, basis_, f_.x, f_.v, f_.normal, psi);
    // The hemisphere's end, cos(n ∓ π/2): horizonOf clamps any lower horizon to it.
    const double floor_cos = side == 0 ? slice.sin_n : -slice.sin_n;
    const double c = exactHorizonCos(g_, pixel_, slice, side, floor_cos);
    const Angle h = horizonUnclamped(c, floor_cos, slice) ? unclampedHorizon(c, side)
                                                          : horizonOf(c, side, withAngle(slice));
    DirectionTerms d;
    d.visibility = slice.projected_length * arcIntegral(h, slice.sin_n, slice.cos_n);
    double t0 = 0.0;
    double t1 = 0.0;
    addBentSide(h, slice.sin_n, slice.cos_n, &t0, &t1);
    d.bent = slice.projected_length * (t0 * slice.o + t1 * f_.v);
    return d;
  }
  void refine(double a, double width, const DirectionTerms& fa, const DirectionTerms& fb,
              int levels, DirectionTerms* sum) const {
    if (levels == 0 || width * std::abs(fb.visibility - fa.visibility) <= s_.refine_tolerance) {
      sum->visibility += 0.5 * width * (fa.visibility + fb.visibility);
      sum->bent += 0.5 * width * (fa.bent + fb.bent);
      return;
    }
    const DirectionTerms mid = at(a + 0.5 * width);
    refine(a, 0.5 * width, fa, mid, levels - 1, sum);
    refine(a + 0.5 * width, 0.5 * width, mid, fb, levels - 1, sum);
  }

  const GBuffer& g_;
  const GtaoReferenceSettings& s_;
  const std::vector<Angle>& base_psi_;
  PixelFrame f_;
  ViewSliceBasis basis_;
  HorizonPixel pixel_;  // what every slice's horizon search shares
};

}  // namespace

namespace {

// One pixel with the run's base slice angles (baseSliceAngles(s)).
void referencePixel(const GBuffer& g, int i, int j, const GtaoReferenceSettings& s,
                    const std::vector<Angle>& base_psi, double* a, Eigen::Vector3d* bent) {
  const DirectionTerms sum = ReferencePixel(g, i, j, s, base_psi).integrate();
  *a = sum.visibility / kPi;  // A = (1/π) ∫_0^π |N'| â dψ = (1/π) ∫_0^2π (one side's term) dφ
  *bent = sum.bent;
}

}  // namespace

void gtaoReferencePixel(const GBuffer& g, int i, int j, const GtaoReferenceSettings& s, double* a,
                        Eigen::Vector3d* bent) {
  referencePixel(g, i, j, s, baseSliceAngles(s), a, bent);
}

AoEstimate gtaoReference(const GBuffer& g, const GtaoReferenceSettings& s) {
  validate(s);
  const std::vector<Angle> base_psi = baseSliceAngles(s);
  return estimatePerPixel(g, [&](int i, int j, std::size_t, double* a, Eigen::Vector3d* bent) {
    referencePixel(g, i, j, s, base_psi, a, bent);
  });
}

}  // namespace gtbake

namespace gtbake {

ReferenceConvergence referenceConvergence(const std::vector<const GBuffer*>& images,
                                          const GtaoReferenceSettings& s) {
  ReferenceConvergence c;
  c.settings = s;
  c.doubled = s;
  c.doubled.slices *= 2;
  c.doubled.refine_tolerance *= 0.5;
  c.doubled.refine_levels += 1;
  const std::vector<Angle> base_psi = baseSliceAngles(c.settings);
  const std::vector<Angle> doubled_psi = baseSliceAngles(c.doubled);
  double sum = 0.0;
  for (const GBuffer* g : images) {
    const int rows = (g->height + kConvergenceStride - 1) / kConvergenceStride;
    const int columns = (g->width + kConvergenceStride - 1) / kConvergenceStride;
    std::vector<double> change(static_cast<std::size_t>(rows) * columns, -1.0);
    tbb::parallel_for(0, rows, [&](int r) {
      for (int q = 0; q < columns; ++q) {
        const int i = q * kConvergenceStride;
        const int j = r * kConvergenceStride;
        if (g->mask[static_cast<std::size_t>(j) * g->width + i] == 0) continue;
        double a = 0.0;
        double b = 0.0;
        Eigen::Vector3d bent;
        referencePixel(*g, i, j, c.settings, base_psi, &a, &bent);
        referencePixel(*g, i, j, c.doubled, doubled_psi, &b, &bent);
        change[static_cast<std::size_t>(r) * columns + q] = std::abs(b - a);
      }
    });
    for (double d : change) {
      if (d < 0.0) continue;
      ++c.pixels;
      sum += d * d;
      c.max_change = std::max(c.max_change, d);
    }
  }
  c.rms_change = c.pixels > 0 ? std::sqrt(sum / c.pixels) : 0.0;
  return c;
}

}  // namespace gtbake
