#include "validate_gtso/specular_methods.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <utility>

#include "common/error.h"
#include "gtso/cone_intersection.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {

namespace {

constexpr double kDegreesPerRadian = 57.295779513082320876;
constexpr std::size_t kProgressStride = 4096;  // samples per progress step

}  // namespace

void setConeAngles(SpecularSample* s, double beta) {
  s->alpha_v = std::acos(std::sqrt(std::clamp(1.0 - static_cast<double>(s->A), 0.0, 1.0)));
  s->beta = beta;
  s->cos_beta = static_cast<float>(std::cos(beta));
  s->cos_av = std::cos(s->alpha_v);
  s->sin_av = std::sin(s->alpha_v);
  s->cos_b = std::cos(beta);
  s->sin_b = std::sin(beta);
}

std::vector<SpecularSample> gatherSamples(const SpecularSweep& sweep) {
  // Scenes in parallel, each writing its own range (unmasked pixels × roughness values, in scene
  // order): the order of a serial pass.
  const std::size_t R = sweep.roughness.size();
  std::vector<std::size_t> begin(sweep.scenes.size() + 1, 0);
  for (std::size_t si = 0; si < sweep.scenes.size(); ++si) {
    const std::vector<std::uint8_t>& mask = sweep.scenes[si].mask;
    begin[si + 1] =
        begin[si] + R * static_cast<std::size_t>(std::count_if(
                            mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; }));
  }
  std::vector<SpecularSample> samples(begin.back());
  tbb::parallel_for(std::size_t{0}, sweep.scenes.size(), [&](std::size_t si) {
    std::size_t next = begin[si];
    const SpecularScene& scene = sweep.scenes[si];
    for (std::size_t p = 0; p < scene.mask.size(); ++p) {
      if (scene.mask[p] == 0) continue;
      const double n[3] = {scene.normal[3 * p], scene.normal[3 * p + 1], scene.normal[3 * p + 2]};
      const double v[3] = {scene.view[3 * p], scene.view[3 * p + 1], scene.view[3 * p + 2]};
      const double b[3] = {scene.bent[3 * p], scene.bent[3 * p + 1], scene.bent[3 * p + 2]};
      const double nv = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
      const double r[3] = {2 * nv * n[0] - v[0], 2 * nv * n[1] - v[1], 2 * nv * n[2] - v[2]};
      const double rlen = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      const double cos_beta =
          std::clamp((b[0] * r[0] + b[1] * r[1] + b[2] * r[2]) / rlen, -1.0, 1.0);
      // Plane of n and ωr: normal m = n × ωr; undefined when ωr ∥ n (then every b lies in a plane
      // through both).
      const double m[3] = {n[1] * r[2] - n[2] * r[1], n[2] * r[0] - n[0] * r[2],
                           n[0] * r[1] - n[1] * r[0]};
      const double mlen = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      const double off =
          mlen > 1e-9
              ? std::asin(std::min(1.0, std::abs(b[0] * m[0] + b[1] * m[1] + b[2] * m[2]) / mlen)) *
                    kDegreesPerRadian
              : 0.0;
      // Everything but the roughness, truth and noise is the pixel's: computed once, copied to
      // each roughness (the same calls on the same values, so the same bits).
      SpecularSample s;
      s.scene = static_cast<int>(si);
      s.pixel = p;
      s.A = scene.A[p];
      s.n_dot_v = static_cast<float>(nv);
      s.n_dot_b = static_cast<float>(n[0] * b[0] + n[1] * b[1] + n[2] * b[2]);
      setConeAngles(&s, std::acos(cos_beta));
      s.cos_beta = static_cast<float>(cos_beta);
      s.out_of_plane = off;
      for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
        s.roughness = static_cast<int>(j);
        s.r_p = static_cast<float>(sweep.roughness[j]);
        s.truth = scene.S[j][p];
        const double d = static_cast<double>(scene.H0[j][p]) - scene.H1[j][p];
        s.noise_var = 0.25 * d * d;
        samples[next++] = s;
      }
    }
  });
  if (samples.empty()) throw Error("sweep " + sweep.dir.string() + " has no unmasked pixels");
  return samples;
}

namespace {

struct MethodText {
  const char* name;
  const char* description;
};

// A method's name (the key in validate_gtso.json) and its one-line description.
MethodText methodText(Method m) {
  switch (m) {
    case Method::kS3Bc4:
      return {"S3_bc4", "3D table, shipped BC4 texture, shader lookup (cos beta = b.wr)"};
    case Method::kS4Bc4:
      return {"S4_bc4", "4D table, shipped BC4 texture, shader lookup (two fetches + lerp)"};
    case Method::kS3Float:
      return {"S3_float", "3D table, float texels, same lookup"};
    case Method::kS4Float:
      return {"S4_float", "4D table, float texels, same lookup"};
    case Method::kS3R16:
      return {"S3_r16", "3D table, shipped R16_UNORM texture, same lookup"};
    case Method::kS4R16:
      return {"S4_r16", "4D table, shipped R16_UNORM texture, same lookup"};
    case Method::kS3R8:
      return {"S3_r8", "3D table, shipped R8_UNORM texture, same lookup"};
    case Method::kS4R8:
      return {"S4_r8", "4D table, shipped R8_UNORM texture, same lookup"};
    case Method::kS3ClosedForm:
      return {"S3_closed_form",
              "closed-form S3 fit (gtsoS3ClosedForm, no texture; cos beta = b.wr)"};
    case Method::kConeTableFitU:
      return {"cone_u_table_fit", "cone-to-cone, u fitted to the 3D table (gtso.json)"};
    case Method::kConePaperU:
      return {"cone_u_0.01", "cone-to-cone, u = 0.01 (paper), cos as = u^(alpha^2/2)"};
    case Method::kConeUludagU:
      return {"cone_u_0.244", "cone-to-cone, u = 0.244 (Uludag), cos as = u^(alpha^2/2)"};
    case Method::kConeFittedU:
      return {"cone_u_fitted", "cone-to-cone, u fitted to path-traced S, u^(alpha^2/2)"};
    case Method::kConeFittedPerceptual:
      return {"cone_u_fitted_perceptual",
              "cone-to-cone, u fitted to path-traced S, perceptual u^(r_p^2/2)"};
    case Method::kNone:
      return {"S_1", "no specular occlusion, S = 1"};
    case Method::kAo:
      return {"S_A", "S = A"};
    case Method::kLagarde:
      return {"lagarde", "Lagarde 2014 with r = alpha = r_p^2 (Filament, HDRP)"};
    case Method::kConeAo2PaperU:
      return {"cone_ao2_u_0.01", "runtime pass's GTSO mode: max(cone-to-cone with u = 0.01, A^2)"};
    case Method::kConeAo2FittedU:
      return {"cone_ao2_u_fitted", "max(cone-to-cone with the fitted u, A^2)"};
    case Method::kConeUserU:
      return {"cone_u_user", "cone-to-cone, u given by --u, cos as = u^(alpha^2/2)"};
  }
  return {"", ""};
}

}  // namespace

const char* methodName(Method m) {
  return methodText(m).name;
}

const char* methodDescription(Method m) {
  return methodText(m).description;
}

ConeAperture coneAperture(double u, double w) {
  ConeAperture a;
  a.a = gtso::specularConeAperture(u, w);
  a.c = std::cos(a.a);
  a.s = std::sin(a.a);
  a.cap = gtso::capSolidAngle(a.a);
  return a;
}

ConeInput coneInput(const SpecularSample& s) {
  return {s.alpha_v, s.beta, s.cos_av, s.sin_av, s.cos_b, s.sin_b, gtso::capSolidAngle(s.alpha_v),
          s.truth};
}

double coneAt(const SpecularSample& x, const ConeAperture& s) {
  return coneAt(coneInput(x), s);
}

double coneAt(const SpecularSample& s, double u, bool perceptual) {
  const double w = perceptual ? s.r_p : static_cast<double>(s.r_p) * s.r_p;
  return coneAt(s, coneAperture(u, w));
}

float lagarde(float n_dot_v, float A, float r_p) {
  const float r = r_p * r_p;
  const float v = std::pow(n_dot_v + A, std::exp2(-16.0f * r - 1.0f)) - 1.0f + A;
  return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

double coneAo2(double cone, double A) {
  return std::max(cone, A * A);
}

std::vector<std::vector<float>> evaluateMethods(const std::vector<SpecularSample>& samples,
                                                const TablesLookups& tables,
                                                const ConeConstants& cones,
                                                const std::vector<Method>& methods,
                                                Progress* progress) {
  std::array<bool, kMethodCount> want{};
  std::vector<std::vector<float>> values(kMethodCount);
  for (Method m : methods) {
    want[static_cast<int>(m)] = true;
    values[static_cast<int>(m)].resize(samples.size());
  }
  // The apertures of the cone methods, once per roughness (coneAperture is what coneAt(s, u,
  // perceptual) computes per call). The floored cones reuse the plain cones' values.
  const std::pair<Method, double> cone_methods[] = {
      {Method::kConeTableFitU, cones.table_fit},
      {Method::kConePaperU, gtso::kPaperU},
      {Method::kConeUludagU, gtso::kUludagU},
      {Method::kConeFittedU, cones.fitted},
      {Method::kConeFittedPerceptual, cones.fitted_perceptual},
      {Method::kConeUserU, cones.user}};
  std::vector<std::array<ConeAperture, std::size(cone_methods)>> apertures;
  for (const SpecularSample& s : samples) {
    if (static_cast<std::size_t>(s.roughness) < apertures.size()) continue;
    apertures.resize(static_cast<std::size_t>(s.roughness) + 1);
    for (std::size_t m = 0; m < std::size(cone_methods); ++m) {
      const bool perceptual = cone_methods[m].first == Method::kConeFittedPerceptual;
      const double w = perceptual ? s.r_p : static_cast<double>(s.r_p) * s.r_p;
      apertures[s.roughness][m] = coneAperture(cone_methods[m].second, w);
    }
  }
  const auto wanted = [&](Method m) { return want[static_cast<int>(m)]; };
  const bool paper_cone = wanted(Method::kConePaperU) || wanted(Method::kConeAo2PaperU);
  const bool fitted_cone = wanted(Method::kConeFittedU) || wanted(Method::kConeAo2FittedU);
  const bool any3 = wanted(Method::kS3Bc4) || wanted(Method::kS3Float) || wanted(Method::kS3R16) ||
                    wanted(Method::kS3R8);
  const bool any4 = wanted(Method::kS4Bc4) || wanted(Method::kS4Float) || wanted(Method::kS4R16) ||
                    wanted(Method::kS4R8);
  tbb::parallel_for(std::size_t{0}, samples.size(), [&](std::size_t i) {
    if (progress && i % kProgressStride == 0) progress->add(kProgressStride);
    const SpecularSample& s = samples[i];
    const ConeInput x = coneInput(s);
    auto set = [&](Method m, double v) {
      if (wanted(m)) values[static_cast<int>(m)][i] = static_cast<float>(v);
    };
    // The axis warps once for every table read (all of one size: GtsoLookup::s3At).
    GtsoAxisT<float> axes3{}, axes4{};
    if (any3) axes3 = tables.bc4->axes3(s.A, s.cos_beta, s.r_p);
    if (any4) axes4 = tables.bc4->axes4(s.A, s.cos_beta, s.r_p, s.n_dot_v);
    const auto table = [&](Method m3, Method m4, const GtsoLookup* lookup) {
      if (wanted(m3)) set(m3, lookup->s3At(axes3));
      if (wanted(m4)) set(m4, lookup->s4At(axes4));
    };
    table(Method::kS3Bc4, Method::kS4Bc4, tables.bc4.get());
    table(Method::kS3Float, Method::kS4Float, tables.floats.get());
    table(Method::kS3R16, Method::kS4R16, tables.r16.get());
    table(Method::kS3R8, Method::kS4R8, tables.r8.get());
    if (wanted(Method::kS3ClosedForm)) {
      set(Method::kS3ClosedForm,
          gtsoS3ClosedForm(tables.info.s3_closed_form.data(), s.A, s.cos_beta, s.r_p));
    }
    for (std::size_t m = 0; m < std::size(cone_methods); ++m) {
      const Method method = cone_methods[m].first;
      const bool needed = wanted(method) || (method == Method::kConePaperU && paper_cone) ||
                          (method == Method::kConeFittedU && fitted_cone);
      if (!needed) continue;
      const bool unused = method == Method::kConeUserU && !(cones.user > 0.0);
      const double cone = unused ? 0.0 : coneAt(x, apertures[s.roughness][m]);
      set(method, cone);
      if (method == Method::kConePaperU) set(Method::kConeAo2PaperU, coneAo2(cone, s.A));
      if (method == Method::kConeFittedU) set(Method::kConeAo2FittedU, coneAo2(cone, s.A));
    }
    set(Method::kNone, 1.0);
    set(Method::kAo, s.A);
    set(Method::kLagarde, lagarde(s.n_dot_v, s.A, s.r_p));
  });
  return values;
}

void ErrorStats::add(double error, double noise_var) {
  ++count;
  sum += error;
  sum2 += error * error;
  max_abs = std::max(max_abs, std::abs(error));
  noise += noise_var;
}

void ErrorStats::merge(const ErrorStats& o) {
  count += o.count;
  sum += o.sum;
  sum2 += o.sum2;
  max_abs = std::max(max_abs, o.max_abs);
  noise += o.noise;
}

double ErrorStats::rmse() const {
  return count > 0 ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0;
}

double ErrorStats::meanSigned() const {
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

double ErrorStats::rmseNoiseCorrected() const {
  if (count == 0) return 0.0;
  return std::sqrt(std::max(0.0, (sum2 - noise) / static_cast<double>(count)));
}

}  // namespace gtbake
