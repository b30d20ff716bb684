// The GTSO integral S of docs/gtso.md §1 (paper Eq. 20-21) for one GGX lobe against many cones.
//
//   S(b, alpha_v) = Int_H DeltaV(wi) fr(wo,wi) cos(theta_i) dwi / Int_H fr(wo,wi) cos(theta_i) dwi
//   DeltaV(wi) = [wi.b >= cos(alpha_v)],  wo = (sin theta_o, 0, cos theta_o),  n = +z,
//   fr: GGX of width alpha = r_p^2 (r_p the perceptual roughness), height-correlated G2, F = 1.
//
// pdf and weight: with the visible-normal pdf(wi) = D_wo(wm) / (4 wo.wm) (ggx.h),
// fr cos dwi = W pdf(wi) dwi with W = G2(wo,wi) / G1(wo) (0 below the horizon). Heitz's stretch
// Nh ~ (wm.x/alpha, wm.y/alpha, wm.z) maps the visible normals of width alpha to those of width 1
// seen from Vh = normalize(alpha wo.x, alpha wo.y, wo.z), whose density is the clamped cosine
// max(0, Vh.Nh) on z > 0 (times a constant). With Nh in spherical coordinates (psi, phi):
//
//   numerator(c) = Int Q [wi.b >= c] dzeta dphi,   denominator = Int Q dzeta dphi,
//   Q(zeta, phi) = W(wi) max(0, Vh.Nh) sin(psi) dpsi/dzeta,   wi = reflect(wo, unstretch(Nh)),
//
// and S = numerator / denominator: the constant and G1(wo) cancel, S = 1 exactly where the cone
// holds the whole lobe, and S is monotone in A. Q is smooth for every alpha (the stretch is the
// importance sampling). phi covers [0, pi] only (lobe and every b are symmetric about the xz
// plane); psi = (pi/2)(1 - (1 - zeta)^p), p = 1 + sin^2(theta_o), refines the grid toward
// psi = pi/2 where grazing views put the visible normals.
//
// Estimator (a departure from plain QMC, because DeltaV is a step): the (zeta, phi) rectangle is
// cut into 2 cells x cells rectangles, each split into two triangles. On each triangle Q, t = wi.b
// and z = wi.n are replaced by their linear interpolants from exact vertex values, and the
// integrals of the interpolants are taken exactly: clipped to z >= 0 (Sutherland-Hodgman in
// barycentric coordinates) and to t >= c (closed-form corner triangles). The step is integrated
// analytically to first order: error O(h^2) in the cell size, not the O(N^-3/4) of point samples
// on a discontinuity. The vertex t of a triangle is divided by the mean length of the
// interpolated unit vector, removing the leading O(h^2) shrinking of cones on the curved sphere.
//
// Cumulative-sum trick: for fixed (r_p, theta_o, b), numerator(c) is a cumulative sum over t.
// A triangle entirely inside a cone is inside every wider one, so it is added once, to the bin of
// the narrowest such cone (binary search), and the bins are prefix-summed; only triangles that
// straddle a cone boundary are clipped. All cones of the A axis cost one pass over the triangles.
#pragma once

#include <cstdint>
#include <vector>

#include "gtso/ggx.h"

namespace gtbake::gtso {

constexpr int kDefaultLobeCells = 96;  // phi cells (psi gets 2x): 2*96*192 triangles per lobe;
                                       // the accuracy/time trade-off measured by bench_gtso

// S for one lobe (r_p, theta_o) against every bent normal b[k] and every cone cos(alpha_v)[j];
// returns S[k * cos_alpha_v.size() + j]. r_p = 0 gives the mirror limit S = DeltaV(wr), the cone
// including its boundary; a cone of zero aperture (A = 0) gives 0 for every r_p.
std::vector<double> specularOcclusion(double r_p, double cos_theta_o, const std::vector<Vec3>& b,
                                      const std::vector<double>& cos_alpha_v,
                                      int cells = kDefaultLobeCells);
// The same with cones of their own per bent normal: returns S[k][j] for cos_alpha_v[k][j].
std::vector<std::vector<double>> specularOcclusion(
    double r_p, double cos_theta_o, const std::vector<Vec3>& b,
    const std::vector<std::vector<double>>& cos_alpha_v, int cells = kDefaultLobeCells);

// Bytes one integration of a lobe holds at `cells` for `normals` bent normals: the grid's weight,
// height and direction per vertex and each normal's t per vertex. Each worker holds one at a time
// (docs/limits.md "Bounded work and memory").
std::uint64_t lobeGridBytes(int cells, int normals);

// The view direction of docs/gtso.md §1 and the 4D table's bent normal (beta from wr toward n).
Vec3 viewDirection(double cos_theta_o);
Vec3 bentNormal(double theta_o, double beta);

}  // namespace gtbake::gtso
