#include "screen_ao/gtao_reference.h"

#include <tbb/parallel_for.h>

#include <string>

#include "common/error.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

void validate(const GtaoReferenceSettings& s) {
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error("gtao-reference: radius must be a positive finite distance in metres");
  }
  if (s.slices < 1 || s.slices > 1024) throw Error("gtao-reference: slices must be in [1, 1024]");
  if (s.steps_per_pixel < 1 || s.steps_per_pixel > 64) {
    throw Error("gtao-reference: steps_per_pixel must be in [1, 64]");
  }
}

void gtaoReferencePixel(const GBuffer& g, int i, int j, const GtaoReferenceSettings& s, double* a,
                        Eigen::Vector3d* bent) {
  const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
  const Eigen::Vector3d x = viewPosition(g, p);
  const Eigen::Vector3d v = -x.normalized();
  const Eigen::Vector3d normal = viewNormal(g, p);
  const double radius_px = s.radius * g.pixelsPerMetre(g.depth[p]);
  const double radius2 = s.radius * s.radius;
  double visibility = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < s.slices; ++k) {
    const Slice slice = makeViewSlice(g, x, v, normal, kPi * (k + 0.5) / s.slices);
    double h[2];
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? -1.0 : 1.0;
      double horizon_cos = -1.0;
      forEachCrossedTexel(i + 0.5, j + 0.5, sign * slice.omega.x(), -sign * slice.omega.y(),
                          radius_px, s.steps_per_pixel, [&](double sx, double sy) {
                            Eigen::Vector3d sample;
                            if (!texelPlanePoint(g, sx, sy, &sample)) return;
                            const Eigen::Vector3d d = sample - x;
                            const double length2 = d.squaredNorm();
                            if (length2 > radius2 || !(length2 > 0.0)) return;
                            horizon_cos = std::max(horizon_cos, d.dot(v) / std::sqrt(length2));
                          });
      h[side] = horizonAngle(horizon_cos, side, slice.n);
    }
    accumulateSlice(slice, h, v, &visibility, &sum);
  }
  *a = visibility / s.slices;
  *bent = sum;
}

AoEstimate gtaoReference(const GBuffer& g, const GtaoReferenceSettings& s) {
  validate(s);
  return estimatePerPixel(g, [&](int i, int j, std::size_t, double* a, Eigen::Vector3d* bent) {
    gtaoReferencePixel(g, i, j, s, a, bent);
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
  c.doubled.steps_per_pixel *= 2;
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
        gtaoReferencePixel(*g, i, j, c.settings, &a, &bent);
        gtaoReferencePixel(*g, i, j, c.doubled, &b, &bent);
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
