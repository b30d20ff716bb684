// Fit of the cone-aperture constant u of the cone-to-cone model (paper Eq. 19, 25-26) to S3.
//
// Model, per 3D texel (A, beta = theta_o, r_p):
//   S_cone = Omega_i(alpha_v, alpha_s, beta) / (2 pi (1 - cos alpha_s)),
//   cos(alpha_v) = sqrt(1 - A),  cos(alpha_s) = u^(w^2 / 2),
// with w = alpha = r_p^2 (SPEC convention, GGX width) or w = r_p (alternative: the paper's r read
// as perceptual roughness). Least squares over the texels with r_p > 0 (at r_p = 0 both sides are
// the mirror limit and do not depend on u), by Ceres with u = 1 / (1 + exp(-z)) so 0 < u < 1.
// Standard error: Ceres covariance of z, (J^T J)^-1, scaled by the residual variance
// sum(r^2) / (m - 1), mapped to u by du/dz = u (1 - u).
#pragma once

#include "gtso/gtso_tables.h"

namespace gtbake::gtso {

enum class RoughnessConvention { kAlpha, kPerceptual };  // w = r_p^2 (SPEC) or w = r_p

struct ConeErrors {
  double rmse = 0.0, max_abs = 0.0;
  int count = 0;
};

struct ConeFit {
  double u = 0.0, u_se = 0.0;
  ConeErrors errors;
};

// S_cone at one texel's physical parameters (3D: beta = theta_o).
double coneModel(const GtsoPoint& p, double u, RoughnessConvention convention);

// Errors of S_cone(u) against the 3D table over texels with r_p > 0 and r_p >= rpMin.
ConeErrors coneErrors(const Table& s3, double u, RoughnessConvention convention,
                      double rpMin = 0.0);

// Least-squares u over the texels with r_p > 0 and r_p >= rpMin. Throws gtbake::Error if Ceres
// does not converge.
ConeFit fitConeU(const Table& s3, RoughnessConvention convention, double rpMin = 0.0);

}  // namespace gtbake::gtso
