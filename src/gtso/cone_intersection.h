// The cone-to-cone specular occlusion of the paper (Eq. 19, Appendix B).
//
// clang-format off
// Omega_cap(a)            = 2 pi (1 - cos a)             solid angle of a spherical cap, 0 <= a <= pi
// Omega_i(a1, a2, beta)   = solid angle of the intersection of two caps with half-angles a1, a2
//                           whose axes are beta apart (0 <= beta <= pi); four cases:
//   disjoint               beta >= a1 + a2                          -> 0
//   nested                 beta <= |a1 - a2|                        -> Omega_cap(min(a1, a2))
//   complements disjoint   a1 + a2 + beta >= 2 pi (union = sphere)  -> Omega_cap(a1) + Omega_cap(a2) - 4 pi
//   partial overlap        otherwise (Tovchigrechko & Vakser 2001; Mazonka 2012, Eq. 12):
//     Omega_i = 2 [ pi - acos((cos b - cos a1 cos a2) / (sin a1 sin a2))
//                      - cos a1 acos((cos a2 - cos b cos a1) / (sin b sin a1))
//                      - cos a2 acos((cos a1 - cos b cos a2) / (sin b sin a2)) ]
//   (Gauss-Bonnet on the lens: 2 pi minus the turning of its two circle arcs and two corners.)
// clang-format on
//
// S_cone(alpha_v, alpha_s, beta) = Omega_i(alpha_v, alpha_s, beta) / Omega_cap(alpha_s)  (Eq. 19),
// with cos(alpha_v) = sqrt(1 - A) (Eq. 18) and cos(alpha_s) = u^(alpha^2 / 2), alpha = r_p^2 the
// GGX width (docs/gtso.md §1; the paper's Eq. 26 writes 0.01^(0.5 r^2)).
#pragma once

namespace gtbake::gtso {

// 2 pi (1 - cos a), written as 4 pi sin^2(a/2) to keep precision for small a.
double capSolidAngle(double a);

// Omega_i(a1, a2, beta); half-angles in [0, pi], beta in [0, pi] (radians).
double capIntersectionSolidAngle(double a1, double a2, double beta);

// S_cone of Eq. 19. For alpha_s = 0 (mirror) the limit: 1 inside the visibility cone, 0 outside,
// 1/2 on its boundary.
double coneSpecularOcclusion(double alpha_v, double alpha_s, double beta);

// The published aperture constants (docs/gtso.md §1): the paper's u = 0.01 (Eq. 26, Appendix B)
// and Uludag 2014's u = 0.244 as the paper's Appendix B quotes it.
inline constexpr double kPaperU = 0.01;
inline constexpr double kUludagU = 0.244;

// The specular cone aperture alpha_s for the aperture constant u and exponent width w:
// cos(alpha_s) = u^(w^2 / 2). The convention of docs/gtso.md §1 passes w = alpha = r_p^2; the
// alternative convention studied in docs/gtso.md passes w = r_p.
double specularConeAperture(double u, double w);

}  // namespace gtbake::gtso
