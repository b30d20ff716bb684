// Fit of the cone-aperture constant u of the cone-to-cone model (paper Eq. 19, 25-26) to S3.
//
// Model, per sample of S3 (A, beta = theta_o, r_p):
//   S_cone = Omega_i(alpha_v, alpha_s, beta) / (2 pi (1 - cos alpha_s)),
//   cos(alpha_v) = sqrt(1 - A),  cos(alpha_s) = u^(w^2 / 2),
// with w = alpha = r_p^2 (docs/gtso.md §1 convention, GGX width) or w = r_p (alternative: the
// paper's r read as perceptual roughness). Least squares over samples of S3 with r_p > 0 (gtbake
// gtso passes the exactly integrated uniform random points of its error measurement, so the fit
// weights the domain uniformly rather than by the warped texel density), by Ceres with u = 1 / (1 +
// exp(-z)). Standard error: Ceres covariance of z, (J^T J)^-1, scaled by the residual variance
// sum(r^2) / (m - 1), mapped to u by du/dz = u (1 - u).
#pragma once

#include <vector>

#include "gtso/gtso_tables.h"

namespace gtbake::gtso {

enum class RoughnessConvention { kAlpha, kPerceptual };  // w = r_p^2 (docs/gtso.md §1) or w = r_p

struct ConeErrors {
  double rmse = 0.0, max_abs = 0.0;
  int count = 0;
};

struct ConeFit {
  double u = 0.0, u_se = 0.0;
  ConeErrors errors;
};

// S_cone at one point's physical parameters (3D: beta = theta_o).
double coneModel(const GtsoPoint& p, double u, RoughnessConvention convention);

// Samples of S3: physical parameters and exact values.
struct S3Samples {
  std::vector<GtsoPoint> points;
  std::vector<double> values;
};

// Errors of S_cone(u) against the samples with r_p > 0 and r_p >= rp_min.
ConeErrors coneErrors(const S3Samples& s3, double u, RoughnessConvention convention,
                      double rp_min = 0.0);

// Least-squares u over the samples with r_p > 0 and r_p >= rp_min. Throws gtbake::Error if Ceres
// does not converge.
ConeFit fitConeU(const S3Samples& s3, RoughnessConvention convention, double rp_min = 0.0);

}  // namespace gtbake::gtso
