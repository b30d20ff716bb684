// The exact horizon of one side of a slice over the depth buffer's surface (docs/screen_ao.md,
// "gtao-reference"): no step count, so nothing to converge along the slice.
//
// The surface is the one every estimator samples (texelPlanePoint): each texel's tangent plane
// where the view ray meets it within kPlaneReach footprints of the texel's point and at
// |N·r̂| ≥ 0.05. The slice's image line crosses a texel in a segment; the view rays through that
// segment all lie in the slice plane and meet the texel's plane along one straight line, and seen
// from P the angle of a point moving along a straight line is monotone, so the largest cos on the
// texel is at one end of the part of the segment where the sample is valid. Each of the three
// conditions (reach, graze: |S| ≤ 20|N·T|, radius: |S − P| ≤ R) is a ball, so that part is one
// interval, found in closed form (quadratics in the image parameter). The search visits every
// texel the line crosses (Amanatides–Woo) up to where no point of the radius ball can still rise
// above the horizon found so far: the ray through the ball's point at that horizon angle (or the
// ball's tangent ray), which makes the search exact and shorter in occluded pixels.
#pragma once

#include "screen_ao/slice_geometry.h"

namespace gtbake {

// The largest cos of the angle from V of a surface sample within `radius` of x seen on the
// slice's image line on `side` (0: −ω, 1: +ω), or floor_cos if none is higher. Texels in the
// plane of the pixel's own (that one included) are skipped: their samples lie on P's tangent plane,
// whose horizon is the hemisphere's end, the floor_cos the hemisphere clamp allows.
double exactHorizonCos(const GBuffer& g, int i, int j, const Eigen::Vector3d& x,
                       const Eigen::Vector3d& v, const Slice& slice, int side, double radius,
                       double floor_cos);

// What exactHorizonCos computes of pixel (i, j) at x, V = v, and the radius before it looks at the
// slice: a caller searching many slices of one pixel makes it once.
struct HorizonPixel {
  HorizonPixel(const GBuffer& g, int i, int j, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
               double radius);

  int i, j;
  Eigen::Vector3d x, v;
  double radius;
  double x0, y0;                 // the pixel's centre in the image
  double kx, ky;                 // the view ray's x and y per unit of image x and y
  Eigen::Vector3d r0;            // the view ray (z = −1) through the centre
  double distance;               // |P|
  double tangent_cos;            // R/|P|
  double rv0, rx0, rr0, xv, xx;  // r0·v, r0·x, |r0|², x·v, |x|²
  const Texel* self;             // the pixel's own texel
  double nearest, farthest;      // the depths a texel's slab must reach into to meet the ball
  double slab_reach;             // slabReach(g)
  float plane_tolerance;  // 10⁻⁶|N·T| of the own texel, in float as coplanar compares it
};

// exactHorizonCos for the pixel p.
double exactHorizonCos(const GBuffer& g, const HorizonPixel& p, const Slice& slice, int side,
                       double floor_cos);

}  // namespace gtbake
