#include "sweep/specular_occlusion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "common/error.h"
#include "common/input_limits.h"
#include "common/text_format.h"

#include "sweep/philox_lanes.h"
#include "sweep/strata.h"

namespace gtbake {

void validateSpecularOptions(const std::vector<double>& roughness, int spp) {
  std::set<long> names;
  for (double r : roughness) {
    if (!(r >= 0.0 && r <= 1.0)) {
      throw Error("--specular-roughness values must be perceptual roughness in [0, 1], got " +
                  specularRoughnessList({r}));
    }
    if (!names.insert(std::lround(r * 100.0)).second) {
      throw Error("--specular-roughness values " + specularRoughnessList(roughness) +
                  " give two channels of the same name (S + r_p x 100 on three digits)");
    }
  }
  if (!roughness.empty() && (spp < 2 || spp > kMaxSweepSpecularSpp || spp % 2 != 0)) {
    throw Error("--specular-spp must be an even number in [2, " +
                std::to_string(kMaxSweepSpecularSpp) + "], got " + std::to_string(spp));
  }
}

std::string specularRoughnessList(const std::vector<double>& roughness) {
  return formatNumberList(roughness);
}

VndfFrame makeVndfFrame(double alpha, const float wo_local[3]) {
  VndfFrame f;
  const double wo[3] = {wo_local[0], wo_local[1], wo_local[2]};
  double vh[3] = {alpha * wo[0], alpha * wo[1], wo[2]};
  const double vlen = std::sqrt(vh[0] * vh[0] + vh[1] * vh[1] + vh[2] * vh[2]);
  for (double& v : vh) v /= vlen;
  const double lensq = vh[0] * vh[0] + vh[1] * vh[1];
  double t1[3] = {1.0, 0.0, 0.0};
  if (lensq > 0.0) {
    const double inv = 1.0 / std::sqrt(lensq);
    t1[0] = -vh[1] * inv;
    t1[1] = vh[0] * inv;
    t1[2] = 0.0;
  }
  const double t2[3] = {vh[1] * t1[2] - vh[2] * t1[1], vh[2] * t1[0] - vh[0] * t1[2],
                        vh[0] * t1[1] - vh[1] * t1[0]};
  const double cos2 = wo[2] * wo[2];
  double inv_lambda = 0.0;  // the horizon: Λ(ωo) = ∞
  if (cos2 > 0.0) {
    const double x = alpha * alpha * std::max(0.0, 1.0 - cos2) / cos2;
    inv_lambda = 1.0 / (1.0 + x / (2.0 * (std::sqrt(1.0 + x) + 1.0)));
  }
  f.alpha = static_cast<float>(alpha);
  f.alpha2 = static_cast<float>(alpha * alpha);
  for (int c = 0; c < 3; ++c) {
    f.wo[c] = wo_local[c];
    f.vh[c] = static_cast<float>(vh[c]);
    f.t1[c] = static_cast<float>(t1[c]);
    f.t2[c] = static_cast<float>(t2[c]);
  }
  f.squash = static_cast<float>(0.5 * (1.0 + vh[2]));
  f.inv_one_plus_lambda_o = static_cast<float>(inv_lambda);
  return f;
}

namespace {

void resizeScratch(SpecularScratch* w, int spp, const StratumGrid& grid) {
  const std::size_t n = static_cast<std::size_t>(spp);
  if (w->sample.size() != n) {
    w->sample.resize(n);
    for (int s = 0; s < spp; ++s) w->sample[s] = s;
    for (auto& v : w->words) v.resize(n);
    for (auto& v : w->u) v.resize(n);
    for (auto& v : w->direction) v.resize(n);
    w->cell[0].resize(n);
    w->cell[1].resize(n);
    for (int s = 0; s < spp; ++s) {
      w->cell[0][s] = grid.column(s);
      w->cell[1][s] = grid.row(s);
    }
    w->weight.resize(n);
    w->traced.resize(n);
    w->again.resize(n);
    w->hit_t.resize(n);
    w->rays.assign(n, makeRayHit(Ray{Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitZ()}, 0.0f));
  }
}

// World directions and weights of m samples: the stratified uniforms through vndfReflect, then
// the local frame (t, s, n) to world space.
GTBAKE_AVX2_CLONES void specularKernel(int m, const VndfFrame& f, const float t[3],
                                       const float s[3], const float n[3],
                                       const float* __restrict u0, const float* __restrict u1,
                                       float* __restrict dx, float* __restrict dy,
                                       float* __restrict dz, float* __restrict weight) {
  for (int i = 0; i < m; ++i) {
    float wi[3];
    vndfReflect(f, u0[i], u1[i], wi, &weight[i]);
    dx[i] = wi[0] * t[0] + wi[1] * s[0] + wi[2] * n[0];
    dy[i] = wi[0] * t[1] + wi[1] * s[1] + wi[2] * n[1];
    dz[i] = wi[0] * t[2] + wi[1] * s[2] + wi[2] * n[2];
  }
}

// Near-field visibility of the m rays of roughness j just traced by occludedStream (slot k: sample
// traced[k], direction w->direction[·][traced[k]], weight w->weight[traced[k]]): the occluded ones
// again up to the largest G-buffer radius (within the sky radius) for their hit distance t, then
// each radius R < t adds the weight to its half's Σ V_R·w (both halves: the mirror's one ray).
// Returns the rays traced again.
std::uint64_t addNearSpecular(const EmbreeTracer& tracer, const WalkSettings& settings,
                              const float origin[3], int m, std::size_t j, bool both_halves,
                              double* near_sums, SpecularScratch* w) {
  RTCRayHit* rays = w->rays.data();
  const float limit = std::min(settings.gbuffer_radii.back(), settings.radius);
  int n = 0;  // slot n ≤ k, so in place
  for (int k = 0; k < m; ++k) {
    w->hit_t[k] = INFINITY;
    if (rays[k].ray.tfar >= 0.0f) continue;
    const int i = w->traced[k];
    w->again[n] = k;
    setRay(&rays[n], origin[0], origin[1], origin[2], w->direction[0][i], w->direction[1][i],
           w->direction[2][i], limit);
    ++n;
  }
  if (n > 0) tracer.intersectStream(rays, static_cast<unsigned>(n));
  for (int a = 0; a < n; ++a) {
    if (rays[a].hit.geomID != RTC_INVALID_GEOMETRY_ID) w->hit_t[w->again[a]] = rays[a].ray.tfar;
  }
  const std::size_t roughness = settings.specular_roughness.size();
  for (std::size_t r = 0; r < settings.gbuffer_radii.size(); ++r) {
    double* sum = near_sums + 2 * (r * roughness + j);
    for (int k = 0; k < m; ++k) {
      if (!(w->hit_t[k] > settings.gbuffer_radii[r])) continue;
      const int i = w->traced[k];
      if (both_halves) {
        sum[0] += w->weight[i];
        sum[1] += w->weight[i];
      } else {
        sum[i & 1] += w->weight[i];
      }
    }
  }
  return static_cast<std::uint64_t>(n);
}

}  // namespace

std::uint64_t traceSpecular(const EmbreeTracer& tracer, const SurfaceHit& start, const float wo[3],
                            const WalkSettings& settings, std::uint64_t stream, double* sums,
                            SpecularScratch* w, double* near_sums) {
  const int spp = settings.specular_spp;
  const StratumGrid grid(std::max(1, spp / 2));
  resizeScratch(w, spp, grid);
  const float p0[3] = {start.position.x(), start.position.y(), start.position.z()};
  const float n[3] = {start.normal.x(), start.normal.y(), start.normal.z()};
  float origin[3];
  offsetAlongNormal(p0, n, start.scale, origin);
  float t[3];
  float s[3];
  tangentBasis(n[0], n[1], n[2], t, s);
  const float wo_local[3] = {wo[0] * t[0] + wo[1] * t[1] + wo[2] * t[2],
                             wo[0] * s[0] + wo[1] * s[1] + wo[2] * s[2],
                             wo[0] * n[0] + wo[1] * n[1] + wo[2] * n[2]};
  const PhiloxLanes philox(settings.seed, stream);
  RTCRayHit* rays = w->rays.data();
  std::uint64_t traced = 0;
  for (std::size_t j = 0; j < settings.specular_roughness.size(); ++j) {
    double* sum = sums + 4 * j;
    const double r = settings.specular_roughness[j];
    if (r == 0.0) {
      // Mirror: ωr = 2(n·ωo)n − ωo, weight 1, the same value in both halves (slot 0: sample 0).
      const float d = 2.0f * wo_local[2];
      for (int c = 0; c < 3; ++c) w->direction[c][0] = d * n[c] - wo[c];
      w->weight[0] = 1.0f;
      w->traced[0] = 0;
      setRay(&rays[0], origin[0], origin[1], origin[2], w->direction[0][0], w->direction[1][0],
             w->direction[2][0], settings.radius);
      tracer.occludedStream(rays, 1);
      ++traced;
      const double v = rays[0].ray.tfar >= 0.0f ? 1.0 : 0.0;
      for (int h = 0; h < 2; ++h) {
        sum[2 * h] += v;
        sum[2 * h + 1] += 1.0;
      }
      if (near_sums != nullptr)
        traced += addNearSpecular(tracer, settings, origin, 1, j, true, near_sums, w);
      continue;
    }
    const VndfFrame frame = makeVndfFrame(r * r, wo_local);
    philox.words(w->sample.data(), spp, kSpecularBlock + static_cast<std::uint32_t>(j),
                 w->words[0].data(), w->words[1].data(), w->words[2].data(), w->words[3].data());
    for (int i = 0; i < spp; ++i) {
      w->u[0][i] = stratum(w->cell[0][i], wordToUniform(w->words[0][i]), grid.columns());
      w->u[1][i] = stratum(w->cell[1][i], wordToUniform(w->words[1][i]), grid.rows());
    }
    specularKernel(spp, frame, t, s, n, w->u[0].data(), w->u[1].data(), w->direction[0].data(),
                   w->direction[1].data(), w->direction[2].data(), w->weight.data());
    int m = 0;
    for (int i = 0; i < spp; ++i) {
      if (!(w->weight[i] > 0.0f)) continue;  // below the horizon: adds 0 to both sums
      setRay(&rays[m], origin[0], origin[1], origin[2], w->direction[0][i], w->direction[1][i],
             w->direction[2][i], settings.radius);
      w->traced[m] = i;
      ++m;
    }
    if (m == 0) continue;
    tracer.occludedStream(rays, static_cast<unsigned>(m));
    traced += static_cast<std::uint64_t>(m);
    for (int k = 0; k < m; ++k) {
      const int i = w->traced[k];
      const double weight = w->weight[i];
      const int h = i & 1;
      if (rays[k].ray.tfar >= 0.0f) sum[2 * h] += weight;
      sum[2 * h + 1] += weight;
    }
    if (near_sums != nullptr)
      traced += addNearSpecular(tracer, settings, origin, m, j, false, near_sums, w);
  }
  return traced;
}

}  // namespace gtbake
