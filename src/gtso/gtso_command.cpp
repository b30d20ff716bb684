// `gtbake gtso`: bakes S3 and S4 (SPEC §1.4), picks the axis mapping and the BC4 block axes by
// measurement, fits the cone-aperture constant u, and writes gtso3d.f32, gtso4d.f32, gtso.json
// and PNG previews. See docs/gtso.md for every definition and the measured numbers.
#include "gtso/gtso_command.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <set>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "common/progress.h"
#include "common/threads.h"
#include "gtso/cone_fit.h"
#include "gtso/gtso_integrator.h"
#include "gtso/gtso_tables.h"

namespace gtbake {

namespace {

using gtso::ErrorStats;
using gtso::Mapping;
using gtso::Table;
using Json = nlohmann::json;

constexpr int kMappingCells = 16;  // integrator cells while comparing mappings: the same
                                   // discretisation for table and direct values, 16x cheaper
constexpr int kInterpolationPoints = 1024;  // random off-grid points per interpolation measurement
constexpr std::uint64_t kSeed = 0x67'74'73'6f;  // "gtso": seed of the off-grid points
constexpr double kRoughRp = 0.3;                // the "rough lobes" subset of the cone errors
constexpr double kPaperU = 0.01;                // paper Appendix B
constexpr double kUludagU = 0.244;              // Uludag 2014, quoted in Appendix B
constexpr int kPreviewScale = 8;                // PNG pixels per texel

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Json axesJson(const Table& t, const std::array<int, 4>& layout) {
  static const char* names[4] = {"x", "y", "z", "w"};
  Json axes = Json::array();
  for (int d = 0; d < t.dims; ++d) {
    const gtso::Axis& a = t.mapping.axes[layout[d]];
    axes.push_back({{"axis", names[d]}, {"quantity", a.quantity}, {"min", a.min}, {"max", a.max}});
  }
  return axes;
}

// Measures the default mapping and each single-axis alternative (and the combination of the
// improving ones) and returns the one with the smallest RMS interpolation error.
Mapping chooseMapping(int dims, int size, Json& report, bool showProgress) {
  const Mapping base = Mapping::defaults(dims);
  std::vector<Mapping> candidates = {base};
  for (int a = 0; a < dims; ++a) candidates.push_back(base.withAlternative(a));
  std::vector<ErrorStats> errors;
  Progress progress("gtso: comparing " + std::to_string(dims) + "D axis mappings",
                    static_cast<std::uint64_t>(dims + 2), showProgress);
  auto measure = [&](const Mapping& m) {
    const Table t = gtso::bakeTable(dims, m, size, kMappingCells, nullptr);
    errors.push_back(gtso::interpolationError(t, kInterpolationPoints, kMappingCells, kSeed));
    progress.add(1);
  };
  for (const Mapping& m : candidates) measure(m);
  Mapping combined = base;
  int improving = 0;
  for (int a = 0; a < dims; ++a) {
    if (errors[a + 1].rms < errors[0].rms) {
      combined = combined.withAlternative(a);
      ++improving;
    }
  }
  if (improving > 1) {
    candidates.push_back(combined);
    measure(combined);
  }
  std::size_t best = 0;
  for (std::size_t c = 1; c < candidates.size(); ++c)
    if (errors[c].rms < errors[best].rms) best = c;
  report = Json::array();
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    report.push_back({{"mapping", candidates[c].name()},
                      {"max", errors[c].max},
                      {"rms", errors[c].rms},
                      {"integrator_cells", kMappingCells},
                      {"chosen", c == best}});
  }
  return candidates[best];
}

// Tries every unordered pair of logical axes as the BC4 block plane (x, y); the rest follow in
// logical order. Returns the layout with the smallest proxy RMS error.
std::array<int, 4> chooseLayout(const Table& t, Json& report) {
  report = Json::array();
  std::array<int, 4> best = {0, 1, 2, 3};
  double bestRms = HUGE_VAL;
  for (int p = 0; p < t.dims; ++p) {
    for (int q = p + 1; q < t.dims; ++q) {
      std::array<int, 4> layout = {p, q, 0, 0};
      int d = 2;
      for (int r = 0; r < t.dims; ++r)
        if (r != p && r != q) layout[d++] = r;
      const ErrorStats e = gtso::bc4ProxyError(gtso::toLayout(t, layout), t.dims, t.size);
      report.push_back({{"x", t.mapping.axes[p].quantity},
                        {"y", t.mapping.axes[q].quantity},
                        {"rms", e.rms},
                        {"max", e.max}});
      if (e.rms < bestRms) {
        bestRms = e.rms;
        best = layout;
      }
    }
  }
  return best;
}

std::string floatBytes(const std::vector<float>& v) {
  static_assert(sizeof(float) == 4, "float32 files");
  std::string bytes(v.size() * 4, '\0');
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::uint32_t u;
    std::memcpy(&u, &v[i], 4);
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<char>((u >> (8 * k)) & 0xff);
  }
  return bytes;
}

// One x-y slice of a file-order table as an upscaled viridis PNG (row 0 = largest y).
void writeSlice(OutputSet& output, const std::string& name, const std::vector<float>& v, int size,
                std::size_t sliceOffset, float lo, float hi) {
  const int w = size * kPreviewScale;
  std::vector<float> img(static_cast<std::size_t>(w) * w);
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x)
      img[static_cast<std::size_t>(y) * w + x] =
          v[sliceOffset + static_cast<std::size_t>(size - 1 - y / kPreviewScale) * size +
            x / kPreviewScale];
  output.add(name, encodePng(w, w, 3, toViridis8(img, lo, hi)));
}

// Bounds on a bake's cost (issue 9: --samples and --size were unbounded). Samples per lobe
// line beyond 2^20 only add rounding noise; the time estimate scales the measured default bake
// (size 32, 96 cells: 9.1 s on 2 cores, docs/gtso.md) by size^4 and cells^2, and the memory
// estimate is three float copies of the 4D table.
constexpr int kMaxSamples = 1 << 20;
constexpr double kDefaultBakeSeconds = 9.1;
inline constexpr Limit kMaxGtsoSeconds{"GTBAKE_MAX_GTSO_SECONDS", 3600, "estimated seconds"};
inline constexpr Limit kMaxGtsoBytes{"GTBAKE_MAX_GTSO_BYTES", 8'000'000'000, "estimated bytes"};

void checkGtsoCost(int size, int cells, int reference_factor) {
  const double scale = std::pow(size / 32.0, 4) * std::pow(cells / 96.0, 2) *
                       (1.0 + reference_factor * reference_factor);
  const std::string what =
      "gtso --size " + std::to_string(size) + " with " + std::to_string(cells) + " cells per lobe";
  checkLimit(kMaxGtsoSeconds, static_cast<std::uint64_t>(kDefaultBakeSeconds * scale), what);
  checkLimit(kMaxGtsoBytes, 12ull * size * size * size * size, what);
}

Json coneFitJson(const gtso::ConeFit& f) {
  return {{"u", f.u},
          {"u_se", f.u_se},
          {"rmse", f.errors.rmse},
          {"max_abs", f.errors.max_abs},
          {"texels", f.errors.count}};
}

Json coneErrorsJson(const gtso::ConeErrors& e) {
  return {{"rmse", e.rmse}, {"max_abs", e.max_abs}, {"texels", e.count}};
}

}  // namespace

GtsoResult runGtso(const GtsoOptions& options) {
  if (options.out.empty()) throw Error("gtso: --out DIR is required");
  if (options.size < 4 || options.size > 256 || options.size % 4 != 0) {
    throw Error("gtso: --size must be a multiple of 4 in [4, 256] (export stores BC4 blocks)");
  }
  if (options.samples < 0 || options.samples > kMaxSamples) {
    throw Error("gtso: --samples must be in [0, " + std::to_string(kMaxSamples) +
                "] (0 = default)");
  }
  if (options.reference_factor < 0 || options.reference_factor > 8) {
    throw Error("gtso: --reference-factor must be in [0, 8]");
  }
  const int cells =
      options.samples == 0
          ? gtso::kDefaultLobeCells
          : std::max(4, static_cast<int>(std::lround(std::sqrt(options.samples / 2.0))));
  checkGtsoCost(options.size, cells, options.reference_factor);
  OutputSet output(options.out, "gtso");  // committed whole at the end (output_set.h)
  const ThreadLimit limit(options.threads);
  const auto start = std::chrono::steady_clock::now();
  const int n = options.size;

  Json mapping3, mapping4;
  auto t0 = std::chrono::steady_clock::now();
  const Mapping m3 = chooseMapping(3, n, mapping3, options.progress);
  const Mapping m4 = chooseMapping(4, n, mapping4, options.progress);
  const double mappingSeconds = seconds(t0);

  t0 = std::chrono::steady_clock::now();
  Table s3, s4;
  {
    Progress progress("gtso: baking S3 and S4", 2ull * n * n, options.progress);
    s3 = gtso::bakeTable(3, m3, n, cells, &progress);
    s4 = gtso::bakeTable(4, m4, n, cells, &progress);
  }
  const double bakeSeconds = seconds(t0);

  // Optional converged reference: every texel's error.
  ErrorStats ref3, ref4;
  double refSeconds = 0.0;
  if (options.reference_factor > 0) {
    t0 = std::chrono::steady_clock::now();
    const int refCells = cells * options.reference_factor;
    Progress progress("gtso: reference tables", 2ull * n * n, options.progress);
    auto compare = [&](const Table& t, int dims, const Mapping& m) {
      const Table r = gtso::bakeTable(dims, m, n, refCells, &progress);
      ErrorStats e;
      for (std::size_t i = 0; i < t.values.size(); ++i) {
        const double d = std::abs(t.values[i] - r.values[i]);
        e.max = std::max(e.max, d);
        e.rms += d * d;
      }
      e.rms = std::sqrt(e.rms / static_cast<double>(t.values.size()));
      return e;
    };
    ref3 = compare(s3, 3, m3);
    ref4 = compare(s4, 4, m4);
    refSeconds = seconds(t0);
  }

  t0 = std::chrono::steady_clock::now();
  Progress interpProgress("gtso: interpolation error", 4, options.progress);
  auto interp = [&](const Table& t, double rpMin) {
    const ErrorStats e = gtso::interpolationError(t, kInterpolationPoints, cells, kSeed, rpMin);
    interpProgress.add(1);
    return e;
  };
  const ErrorStats interp3 = interp(s3, 0.0), interp4 = interp(s4, 0.0);
  const ErrorStats interp3r = interp(s3, kRoughRp), interp4r = interp(s4, kRoughRp);
  interpProgress.finish();
  const double interpSeconds = seconds(t0);

  Json bc43, bc44;
  const std::array<int, 4> layout3 = chooseLayout(s3, bc43);
  const std::array<int, 4> layout4 = chooseLayout(s4, bc44);
  const std::vector<float> f3 = gtso::toLayout(s3, layout3), f4 = gtso::toLayout(s4, layout4);

  t0 = std::chrono::steady_clock::now();
  using gtso::RoughnessConvention;
  const gtso::ConeFit fit = gtso::fitConeU(s3, RoughnessConvention::kAlpha);
  const gtso::ConeFit fitRough = gtso::fitConeU(s3, RoughnessConvention::kAlpha, kRoughRp);
  const gtso::ConeFit fitAlt = gtso::fitConeU(s3, RoughnessConvention::kPerceptual);
  const gtso::ConeFit fitAltRough = gtso::fitConeU(s3, RoughnessConvention::kPerceptual, kRoughRp);
  const double fitSeconds = seconds(t0);

  auto fixedU = [&](double u, RoughnessConvention c) {
    return Json{{"all", coneErrorsJson(gtso::coneErrors(s3, u, c))},
                {"r_p_ge_0.3", coneErrorsJson(gtso::coneErrors(s3, u, c, kRoughRp))}};
  };

  // Previews: S3 over (x, y) at a few slices of the third axis; S4 at a few (z, w).
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  for (int z : std::set<int>{0, n / 4, n / 2, 3 * n / 4, n - 1}) {  // distinct at small n
    writeSlice(output, "gtso3d_z" + std::to_string(z) + ".png", f3, n, z * plane, 0.f, 1.f);
    for (int w : std::set<int>{0, n / 2, n - 1}) {
      writeSlice(output, "gtso4d_z" + std::to_string(z) + "_w" + std::to_string(w) + ".png", f4, n,
                 (static_cast<std::size_t>(w) * n + z) * plane, 0.f, 1.f);
    }
  }

  const double total = seconds(start);
  Json j;
  j["version"] = 1;
  j["size"] = n;
  j["roughness_convention"] = "perceptual roughness r_p; GGX alpha = r_p^2";
  j["texel_rule"] = "texel i holds the value at i/(N-1) of the axis range";
  j["integrator"] = {{"method",
                      "piecewise-linear quadrature over the stretched visible-normal "
                      "hemisphere, cone step clipped exactly per triangle"},
                     {"cells", cells},
                     {"cells_psi_by_phi", {2 * cells, cells}}};
  auto refOf = [&](const ErrorStats& e) {
    return options.reference_factor > 0 ? std::optional<ErrorStats>(e) : std::nullopt;
  };
  const Json refSamples =
      options.reference_factor > 0
          ? Json(2 * cells * cells * options.reference_factor * options.reference_factor)
          : Json(nullptr);
  auto tableJson = [&](const Table& t, const std::string& file, const std::array<int, 4>& layout,
                       const ErrorStats& interp, const ErrorStats& interpRough,
                       const Json& alternatives, const Json& bc4, std::optional<ErrorStats> ref) {
    Json tj = {
        {"file", file},
        {"dims", t.dims == 3 ? Json{n, n, n} : Json{n, n, n, n}},
        {"axes", axesJson(t, layout)},
        {"samples", 2 * cells * cells},
        {"reference_samples", refSamples},
        {"max_abs_error_vs_reference", ref ? Json(ref->max) : Json(nullptr)},
        {"rms_error_vs_reference", ref ? Json(ref->rms) : Json(nullptr)},
        {"error_vs_reference_note",
         "null unless reference_factor > 0; bench_gtso measures the same (docs/gtso.md)"},
        {"interpolation_error",
         {{"shipped", {{"mapping", t.mapping.name()}, {"max", interp.max}, {"rms", interp.rms}}},
          {"shipped_r_p_ge_0.3", {{"max", interpRough.max}, {"rms", interpRough.rms}}},
          {"points", kInterpolationPoints},
          {"point_distribution", "uniform in A, cos beta, r_p, cos theta_o"},
          {"alternatives", alternatives}}},
        {"bc4_proxy_by_block_axes", bc4}};
    if (t.dims == 4) tj["folded"] = "texture z = w*size + z";
    return tj;
  };
  j["tables"] = {
      {"3d", tableJson(s3, "gtso3d.f32", layout3, interp3, interp3r, mapping3, bc43, refOf(ref3))},
      {"4d", tableJson(s4, "gtso4d.f32", layout4, interp4, interp4r, mapping4, bc44, refOf(ref4))}};
  j["cone"] = {
      {"u", fit.u},
      {"u_se", fit.u_se},
      {"convention", "cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2 (GGX width)"},
      {"fit_texels", "all S3 texels with r_p > 0"},
      {"errors",
       {{"fitted", coneErrorsJson(fit.errors)},
        {"fitted_r_p_ge_0.3",
         coneErrorsJson(gtso::coneErrors(s3, fit.u, RoughnessConvention::kAlpha, kRoughRp))},
        {"u_0.01", fixedU(kPaperU, RoughnessConvention::kAlpha)},
        {"u_0.244", fixedU(kUludagU, RoughnessConvention::kAlpha)}}},
      {"fit_r_p_ge_0.3", coneFitJson(fitRough)},
      {"alternative_convention",
       {{"convention", "cos(alpha_s) = u^(r_p^2/2) (paper's r read as perceptual roughness)"},
        {"fit", coneFitJson(fitAlt)},
        {"fit_r_p_ge_0.3", coneFitJson(fitAltRough)},
        {"u_0.01", fixedU(kPaperU, RoughnessConvention::kPerceptual)},
        {"u_0.244", fixedU(kUludagU, RoughnessConvention::kPerceptual)}}}};
  j["timings"] = {{"threads", limit.threads()},
                  {"mapping_selection_s", mappingSeconds},
                  {"bake_s", bakeSeconds},
                  {"interpolation_error_s", interpSeconds},
                  {"cone_fit_s", fitSeconds},
                  {"reference_s", refSeconds},
                  {"total_s", total}};

  output.add("gtso3d.f32", floatBytes(f3));
  output.add("gtso4d.f32", floatBytes(f4));
  output.add("gtso.json", j.dump(2) + "\n");
  output.setSettings({{"size", n},
                      {"samples", options.samples},
                      {"cells", cells},
                      {"reference_factor", options.reference_factor}});
  output.commit();

  std::printf("gtso: S3 %s, S4 %s baked in %.1f s (%d threads, %d x %d cells per lobe)\n",
              s3.mapping.name().c_str(), s4.mapping.name().c_str(), bakeSeconds, limit.threads(),
              2 * cells, cells);
  std::printf("gtso: interpolation error S3 max %.2e rms %.2e, S4 max %.2e rms %.2e\n", interp3.max,
              interp3.rms, interp4.max, interp4.rms);
  std::printf("gtso: u = %.5f +- %.5f (alpha = r_p^2): rmse %.4f max %.4f; u = %.5f under r_p\n",
              fit.u, fit.u_se, fit.errors.rmse, fit.errors.max_abs, fitAlt.u);
  return {fit.u, fit.u_se, total};
}

}  // namespace gtbake
