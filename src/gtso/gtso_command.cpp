// `gtbake gtso`: bakes S3 and S4 (docs/gtso.md §1) on the warped axes of runtime/gtso_runtime.h,
// measures what the runtime reads (float32, BC4, R16, R8 through the shipped lookup code) against
// direct integration at random and stress points over several seeds, fits the cone-aperture
// constant u, and writes gtso3d.f32, gtso4d.f32, gtso.json and PNG previews. See docs/gtso.md.
#include "gtso/gtso_command.h"

#include <tbb/parallel_invoke.h>
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
#include "gtso/cone_intersection.h"
#include "gtso/gtso_end_to_end.h"
#include "gtso/gtso_integrator.h"
#include "gtso/gtso_tables.h"
#include "gtso/s3_closed_form.h"
#include "gtso/texel_check.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {

namespace {

using gtso::ErrorStats;
using gtso::Table;

using Json = nlohmann::json;

constexpr double kRoughRp = 0.3;              // the "rough lobes" subset of the cone errors
constexpr int kPreviewScale = 8;              // PNG pixels per texel
constexpr std::uint64_t kTexelCheckSeed = 1;  // the sampled lines of the texel check

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void validateOptions(const GtsoOptions& o) {
  if (o.out.empty()) throw Error("gtso: --out DIR is required");
  try {
    gtso::validateTableSize(o.size);
  } catch (const Error& e) {
    throw Error(std::string("gtso: ") + e.what());
  }
  if (o.lobe_cells != 0 && (o.lobe_cells < 4 || o.lobe_cells > 1024)) {
    throw Error("gtso: --lobe-cells must be 0 (default) or in [4, 1024]");
  }
  if (o.error_lobes < 1 || o.error_lobes > 1 << 20) {
    throw Error("gtso: --error-lobes must be in [1, 1048576]");
  }
  if (o.error_seeds < 1 || o.error_seeds > 64)
    throw Error("gtso: --error-seeds must be in [1, 64]");
  if (o.reference_factor < 0 || o.reference_factor > 8) {
    throw Error("gtso: --reference-factor must be in [0, 8]");
  }
  if (o.closed_form_lobes != 0 && (o.closed_form_lobes < 16 || o.closed_form_lobes > 1 << 16)) {
    throw Error("gtso: --closed-form-lobes must be 0 (default) or in [16, 65536]");
  }
  if (o.texel_check_lines_3d < 1 || o.texel_check_lines_4d < 1) {
    throw Error("gtso: the texel check needs at least one line per table");
  }
}

Json axesJson(int dims) {
  static const char* names[4] = {"x", "y", "z", "w"};
  Json axes = Json::array();
  const auto& defs = gtso::axisDefinitions(dims);
  for (int d = 0; d < dims; ++d) {
    axes.push_back({{"axis", names[d]},
                    {"quantity", defs[d].quantity},
                    {"forward", defs[d].forward},
                    {"alu", defs[d].alu}});
  }
  return axes;
}

// Optional converged reference: every texel's error.
std::optional<std::pair<ErrorStats, ErrorStats>> referenceErrors(const Table& s3, const Table& s4,
                                                                 const GtsoOptions& o, int cells) {
  if (o.reference_factor == 0) return std::nullopt;
  const int refCells = cells * o.reference_factor;
  Progress progress("gtso: reference tables", 2ull * o.size * o.size, o.progress);
  auto compare = [&](const Table& t) {
    const Table r = gtso::bakeTable(t.dims, t.size, refCells, &progress);
    ErrorStats e;
    for (std::size_t i = 0; i < t.values.size(); ++i) {
      const double d = std::abs(t.values[i] - r.values[i]);
      e.max = std::max(e.max, d);
      e.rms += d * d;
    }
    e.rms = std::sqrt(e.rms / static_cast<double>(t.values.size()));
    return e;
  };
  return std::pair{compare(s3), compare(s4)};
}

// The sampled texel check of every run: random lines of each table re-integrated at 16x.
std::pair<gtso::TexelCheck, gtso::TexelCheck> sampledTexelCheck(const Table& s3, const Table& s4,
                                                                const GtsoOptions& o, int cells) {
  const int total = o.size * o.size;
  const int lines3 = std::min(o.texel_check_lines_3d, total);
  const int lines4 = std::min(o.texel_check_lines_4d, total);
  Progress progress("gtso: texel check", static_cast<std::uint64_t>(lines3 + lines4), o.progress);
  auto check = [&](const Table& t, int lines) {
    return gtso::checkTexels(t, cells, gtso::kTexelCheckFactor,
                             gtso::sampleStratifiedLines(t.dims, t.size, lines, kTexelCheckSeed),
                             kTexelCheckSeed, &progress);
  };
  std::pair<gtso::TexelCheck, gtso::TexelCheck> out{check(s3, lines3), check(s4, lines4)};
  progress.finish();
  return out;
}

Json texelCheckJson(const gtso::TexelCheck& c, int size, int cells) {
  Json lines = Json::array();
  for (std::size_t l : c.lines) lines.push_back(l);
  const auto& w = c.worst_index;
  const std::string k = std::to_string(gtso::kTexelCheckEdgeColumns);
  auto stratum = [](const gtso::TexelStratum& st, const std::string& lines) {
    return Json{{"lines_from", lines},
                {"lines", st.lines},
                {"texels", st.texels},
                {"max_abs", st.max},
                {"rms", st.rms}};
  };
  return {
      {"method",
       "seeded random lines (one integrator lobe each: r_p texel, theta_o texel), half from the "
       "edge stratum and half from the interior, re-integrated with factor x the lobe cells "
       "per side; every texel of each line compared"},
      {"strata",
       {{"edge", stratum(c.strata[0],
                         "theta_o texel < " + k + " or >= N - " + k + " (normal view, grazing)")},
        {"interior", stratum(c.strata[1], "the other theta_o texels")}}},
      {"factor", c.factor},
      {"reference_lobe_grid_rectangles", 2 * cells * cells * c.factor * c.factor},
      {"seed", c.seed},
      {"lines", c.lines.size()},
      {"lines_total", size * size},
      {"line_indices", lines},
      {"texels", c.texels},
      {"max_abs", c.max},
      {"rms", c.rms},
      {"worst",
       {{"index", {w[0], w[1], w[2], w[3]}},
        {"A", c.worst.A},
        {"beta", c.worst.beta},
        {"r_p", c.worst.r_p},
        {"theta_o", c.worst.theta_o},
        {"value", c.worst_value},
        {"reference", c.worst_reference}}},
      {"seconds", c.seconds}};
}

Json coneErrorsJson(const gtso::ConeErrors& e) {
  return {{"rmse", e.rmse}, {"max_abs", e.max_abs}, {"samples", e.count}};
}

Json coneFitJson(const gtso::ConeFit& f) {
  return {{"u", f.u},
          {"u_se", f.u_se},
          {"rmse", f.errors.rmse},
          {"max_abs", f.errors.max_abs},
          {"samples", f.errors.count}};
}

// The four cone fits (two conventions, all r_p and r_p >= 0.3), two at a time.
Json fitCone(const gtso::S3Samples& samples, gtso::ConeFit& fit) {
  using gtso::RoughnessConvention;
  gtso::ConeFit rough, alt, altRough;
  tbb::parallel_invoke(
      [&] { fit = gtso::fitConeU(samples, RoughnessConvention::kAlpha); },
      [&] { rough = gtso::fitConeU(samples, RoughnessConvention::kAlpha, kRoughRp); },
      [&] { alt = gtso::fitConeU(samples, RoughnessConvention::kPerceptual); },
      [&] { altRough = gtso::fitConeU(samples, RoughnessConvention::kPerceptual, kRoughRp); });
  auto fixedU = [&](double u, RoughnessConvention c) {
    return Json{{"all", coneErrorsJson(gtso::coneErrors(samples, u, c))},
                {"r_p_ge_0.3", coneErrorsJson(gtso::coneErrors(samples, u, c, kRoughRp))}};
  };
  return {{"u", fit.u},
          {"u_se", fit.u_se},
          {"convention", "cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2 (GGX width)"},
          {"fit_samples", "the first seed's uniform random S3 points (exact S), r_p > 0"},
          {"errors",
           {{"fitted", coneErrorsJson(fit.errors)},
            {"fitted_r_p_ge_0.3", coneErrorsJson(gtso::coneErrors(
                                      samples, fit.u, RoughnessConvention::kAlpha, kRoughRp))},
            {"u_0.01", fixedU(gtso::kPaperU, RoughnessConvention::kAlpha)},
            {"u_0.244", fixedU(gtso::kUludagU, RoughnessConvention::kAlpha)}}},
          {"fit_r_p_ge_0.3", coneFitJson(rough)},
          {"alternative_convention",
           {{"convention", "cos(alpha_s) = u^(r_p^2/2) (paper's r read as perceptual roughness)"},
            {"fit", coneFitJson(alt)},
            {"fit_r_p_ge_0.3", coneFitJson(altRough)},
            {"u_0.01", fixedU(gtso::kPaperU, RoughnessConvention::kPerceptual)},
            {"u_0.244", fixedU(gtso::kUludagU, RoughnessConvention::kPerceptual)}}}};
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

// One x-y slice of a texture-order table as an upscaled viridis PNG (row 0 = largest y).
void writeSlice(OutputSet& output, const std::string& name, const std::vector<float>& v, int size,
                std::size_t sliceOffset) {
  const int w = size * kPreviewScale;
  std::vector<float> img(static_cast<std::size_t>(w) * w);
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x)
      img[static_cast<std::size_t>(y) * w + x] =
          v[sliceOffset + static_cast<std::size_t>(size - 1 - y / kPreviewScale) * size +
            x / kPreviewScale];
  output.add(name, encodePng(w, w, 3, toViridis8(img, 0.f, 1.f)));
}

// Bounds on a run's cost (docs/limits.md "Bounded work and memory"), in seconds of one core, each
// term measured and scaled by cells^2 (96 cells = 1): the bake (8.8 s at size 32, scaled by
// size^4 and the reference factor), the end-to-end error (0.012 s per lobe and seed at size 4,
// the costliest size per lobe), the closed-form fit (0.0025 s per training lobe) and the texel
// check (7 s at size 4).
constexpr double kDefaultBakeSeconds = 8.8;
constexpr double kErrorLobeSeconds = 0.012;
constexpr double kClosedFormLobeSeconds = 0.0025;
constexpr double kFixedSeconds = 7.0;
inline constexpr Limit kMaxGtsoSeconds{"GTBAKE_MAX_GTSO_SECONDS", 3600, "estimated seconds"};
// 8 GB (written without digit separators: an odd count of them derails pmccabe's parser).
inline constexpr Limit kMaxGtsoBytes{"GTBAKE_MAX_GTSO_BYTES", 8ull * 1000 * 1000 * 1000,
                                     "estimated bytes"};
// One 3D and four 4D bent normals per end-to-end lobe (gtso_tables.cpp).
constexpr int kEndToEndNormals = 5;

void checkGtsoSeconds(const GtsoOptions& o, int cells) {
  const int size = o.size;
  const double c2 = std::pow(cells / 96.0, 2);
  const int closed_form_lobes =
      o.closed_form_lobes != 0 ? o.closed_form_lobes : gtso::kClosedFormTrainLobes;
  const double seconds = c2 * (kDefaultBakeSeconds * std::pow(size / 32.0, 4) *
                                   (1.0 + o.reference_factor * o.reference_factor) +
                               kErrorLobeSeconds * o.error_lobes * o.error_seeds +
                               kClosedFormLobeSeconds * closed_form_lobes + kFixedSeconds);
  const std::string what = "gtso --size " + std::to_string(size) + " with " +
                           std::to_string(cells) + " cells per lobe and " +
                           std::to_string(o.error_lobes) + " x " + std::to_string(o.error_seeds) +
                           " error lobes";
  checkLimit(kMaxGtsoSeconds, static_cast<std::uint64_t>(seconds), what);
}

// Peak memory, checked before any work against GTBAKE_MAX_GTSO_BYTES and what the process may
// have (memoryBound): the tables (three float copies of the 4D table), each worker's lobe grid at
// the finest cells of the run (the texel check's 4x or the reference's factor) and the
// end-to-end points every seed keeps (both tables' and the cone fit's copy of the 3D ones). The
// error names the options of the largest term.
void checkGtsoMemory(const GtsoOptions& o, int cells, int threads) {
  const std::uint64_t size = static_cast<std::uint64_t>(o.size);
  const std::uint64_t tables = 12 * size * size * size * size;
  const int finest = cells * std::max(gtso::kTexelCheckFactor, o.reference_factor);
  const std::uint64_t grid =
      std::max(gtso::lobeGridBytes(finest, o.size), gtso::lobeGridBytes(cells, kEndToEndNormals));
  const std::uint64_t grids = static_cast<std::uint64_t>(threads) * grid;
  const std::uint64_t lobes = static_cast<std::uint64_t>(o.error_lobes) +
                              std::max(1, o.error_lobes / gtso::kStressLobeDivisor);
  const std::uint64_t points = 3 * (sizeof(gtso::GtsoPoint) + sizeof(double)) *
                               gtso::kPointsPerLobe * lobes *
                               static_cast<std::uint64_t>(o.error_seeds);
  std::string what = "gtso --size " + std::to_string(o.size) + " (the tables)";
  if (grids >= std::max(tables, points)) {
    what = "gtso --lobe-cells " + std::to_string(cells) +
           (o.reference_factor > gtso::kTexelCheckFactor
                ? " --reference-factor " + std::to_string(o.reference_factor)
                : "") +
           " on " + std::to_string(threads) + " threads (each worker holds a " +
           std::to_string(grid / 1000000) + " MB lobe grid at " + std::to_string(finest) +
           " cells; fewer cells or --threads need less)";
  } else if (points >= tables) {
    what = "gtso --error-lobes " + std::to_string(o.error_lobes) + " --error-seeds " +
           std::to_string(o.error_seeds) + " (the end-to-end points)";
  }
  checkMemoryEstimate(tables + grids + points, what, &kMaxGtsoBytes);
}

Json tableJson(const Table& t, const std::string& file, int cells, int referenceFactor,
               const std::optional<ErrorStats>& ref) {
  const int n = t.size;
  Json tj = {{"file", file},
             {"dims", t.dims == 3 ? Json{n, n, n} : Json{n, n, n, n}},
             {"axes", axesJson(t.dims)},
             {"lobe_grid_rectangles", 2 * cells * cells},
             {"reference_lobe_grid_rectangles",
              ref ? Json(2 * cells * cells * referenceFactor * referenceFactor) : Json(nullptr)},
             {"max_abs_error_vs_reference", ref ? Json(ref->max) : Json(nullptr)},
             {"rms_error_vs_reference", ref ? Json(ref->rms) : Json(nullptr)},
             {"error_vs_reference_note",
              "null unless reference_factor > 0; bench_gtso measures the same (docs/gtso.md)"}};
  if (t.dims == 4) tj["folded"] = "texture z = w*size + z";
  return tj;
}

// Everything `gtso` computes (runGtso formats it: gtso.json, previews, the printed summary).
struct GtsoRun {
  int size = 0;
  int cells = 0;
  int threads = 0;
  Table s3, s4;
  std::optional<std::pair<ErrorStats, ErrorStats>> ref;  // against the reference bake, if asked
  std::pair<gtso::TexelCheck, gtso::TexelCheck> texel_check;
  gtso::EndToEnd e2e;
  gtso::ConeFit fit;
  Json cone;
  gtso::ClosedFormStage closed_form;
  double bake_s = 0.0, ref_s = 0.0, check_s = 0.0, error_s = 0.0, fit_s = 0.0;
};

// Bakes both tables and measures them: the reference and texel checks, the error end to end, the
// cone fit and the closed-form S3 (tested on the 3D end-to-end points).
GtsoRun computeGtso(const GtsoOptions& options, int cells, int threads) {
  GtsoRun r;
  r.size = options.size;
  r.cells = cells;
  r.threads = threads;
  auto t0 = std::chrono::steady_clock::now();
  {
    Progress progress("gtso: baking S3 and S4", 2ull * r.size * r.size, options.progress);
    r.s3 = gtso::bakeTable(3, r.size, cells, &progress);
    r.s4 = gtso::bakeTable(4, r.size, cells, &progress);
  }
  r.bake_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  r.ref = referenceErrors(r.s3, r.s4, options, cells);
  r.ref_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  r.texel_check = sampledTexelCheck(r.s3, r.s4, options, cells);
  r.check_s = seconds(t0);
  char exact[256];
  std::snprintf(exact, sizeof(exact),
                "the integrator at the bake's cells (texel error vs 16x reference, measured on "
                "sampled lines: 3D max %.2g, 4D max %.2g; tables.*.texel_check)",
                r.texel_check.first.max, r.texel_check.second.max);
  t0 = std::chrono::steady_clock::now();
  r.e2e = gtso::measureEndToEnd(r.s3, r.s4, options, cells, exact);
  r.error_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  r.cone = fitCone(r.e2e.coneSamples, r.fit);
  r.fit_s = seconds(t0);
  std::vector<const gtso::ErrorPoints*> closed_form_tests;
  for (const gtso::ErrorPoints& p : r.e2e.s3Points) closed_form_tests.push_back(&p);
  r.closed_form = gtso::runClosedFormStage(
      closed_form_tests, r.e2e.seeds, cells,
      options.closed_form_lobes != 0 ? options.closed_form_lobes : gtso::kClosedFormTrainLobes);
  return r;
}

// gtso.json (docs/gtso.md lists its keys).
Json gtsoJson(const GtsoRun& r, const GtsoOptions& options, double total_s) {
  Json j;
  j["version"] = 2;
  j["size"] = r.size;
  j["roughness_convention"] = "perceptual roughness r_p; GGX alpha = r_p^2";
  j["texel_rule"] = "texel i holds the value at the inverse axis map of i/(N-1)";
  for (const GtsoAxisConstant& c : kGtsoAxisConstants) j["axis_constants"][c.key] = c.value;
  j["integrator"] = {{"method",
                      "piecewise-linear quadrature over the stretched visible-normal "
                      "hemisphere, cone step clipped exactly per triangle"},
                     {"cells", r.cells},
                     {"cells_psi_by_phi", {2 * r.cells, r.cells}}};
  j["tables"] = {{"3d", tableJson(r.s3, "gtso3d.f32", r.cells, options.reference_factor,
                                  r.ref ? std::optional(r.ref->first) : std::nullopt)},
                 {"4d", tableJson(r.s4, "gtso4d.f32", r.cells, options.reference_factor,
                                  r.ref ? std::optional(r.ref->second) : std::nullopt)}};
  j["tables"]["3d"]["texel_check"] = texelCheckJson(r.texel_check.first, r.size, r.cells);
  j["tables"]["4d"]["texel_check"] = texelCheckJson(r.texel_check.second, r.size, r.cells);
  j["end_to_end"] = r.e2e.json;
  j["cone"] = r.cone;
  j["closed_form"] = r.closed_form.json;
  j["timings"] = {
      {"threads", r.threads},  {"bake_s", r.bake_s},     {"end_to_end_error_s", r.error_s},
      {"cone_fit_s", r.fit_s}, {"reference_s", r.ref_s}, {"texel_check_s", r.check_s},
      {"total_s", total_s}};
  return j;
}

void printGtsoSummary(const GtsoRun& r, const GtsoOptions& options) {
  std::FILE* out = options.summary;
  if (out == nullptr) return;
  std::fprintf(
      out, "gtso: S3 and S4 (%d^3, %d^4) baked in %.1f s (%d threads, %d x %d cells per lobe)\n",
      r.size, r.size, r.bake_s, r.threads, 2 * r.cells, r.cells);
  for (const char* key : {"3d", "4d"}) {
    const Json& u = r.e2e.json[key]["formats"]["float32"]["uniform"];
    std::fprintf(out,
                 "gtso: %s float32 end to end (max over %d seeds / mean RMS): %.4f/%.5f (encoded "
                 "formats: gtbake encode)\n",
                 key, options.error_seeds, u["max"].get<double>(), u["rms"].get<double>());
  }
  for (const gtso::TexelCheck* c : {&r.texel_check.first, &r.texel_check.second}) {
    std::fprintf(out,
                 "gtso: %s texel check vs %dx reference, %zu random lines (%zu texels): max %.3g "
                 "rms %.3g (%.1f s)\n",
                 c == &r.texel_check.first ? "3d" : "4d", c->factor * c->factor, c->lines.size(),
                 c->texels, c->max, c->rms, c->seconds);
  }
  std::fprintf(out, "gtso: u = %.5g +- %.2g (alpha = r_p^2): rmse %.4f max %.4f\n", r.fit.u,
               r.fit.u_se, r.fit.errors.rmse, r.fit.errors.max_abs);
  const Json& cf = r.closed_form.json["test"]["errors"];
  std::fprintf(out,
               "gtso: closed-form S3 (test points): r_p >= 0.1 max %.4f rms %.5f; r_p < 0.1 max "
               "%.4f rms %.5f (%.1f s)\n",
               cf["r_p_ge_0.1"]["max"].get<double>(), cf["r_p_ge_0.1"]["rms"].get<double>(),
               cf["r_p_lt_0.1"]["max"].get<double>(), cf["r_p_lt_0.1"]["rms"].get<double>(),
               r.closed_form.json["fit_s"].get<double>());
}

}  // namespace

// Previews: S3 over (x, y) at a few z slices; S4 at a few (z, w).
void writeGtsoPreviews(OutputSet& output, const std::vector<float>& f3,
                       const std::vector<float>& f4, int n) {
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  for (int z : std::set<int>{0, n / 4, n / 2, 3 * n / 4, n - 1}) {  // distinct at small n
    writeSlice(output, "gtso3d_z" + std::to_string(z) + ".png", f3, n, z * plane);
    for (int w : std::set<int>{0, n / 2, n - 1}) {
      writeSlice(output, "gtso4d_z" + std::to_string(z) + "_w" + std::to_string(w) + ".png", f4, n,
                 (static_cast<std::size_t>(w) * n + z) * plane);
    }
  }
}

GtsoResult runGtso(const GtsoOptions& options) {
  validateOptions(options);
  const int cells = options.lobe_cells == 0 ? gtso::kDefaultLobeCells : options.lobe_cells;
  checkGtsoSeconds(options, cells);
  const ThreadLimit limit(options.threads);
  checkGtsoMemory(options, cells, limit.threads());
  OutputSet output(options.out, "gtso");  // committed whole at the end (output_set.h)
  const auto start = std::chrono::steady_clock::now();
  const GtsoRun r = computeGtso(options, cells, limit.threads());
  const std::vector<float> f3 = gtso::toFloats(r.s3), f4 = gtso::toFloats(r.s4);
  writeGtsoPreviews(output, f3, f4, r.size);
  const Json j = gtsoJson(r, options, seconds(start));
  output.add("gtso3d.f32", floatBytes(f3));
  output.add("gtso4d.f32", floatBytes(f4));
  output.add("gtso.json", j.dump(2) + "\n");
  output.setSettings({{"size", r.size},
                      {"lobe_cells", cells},
                      {"error_lobes", options.error_lobes},
                      {"error_seeds", options.error_seeds},
                      {"reference_factor", options.reference_factor}});
  output.commit();
  printGtsoSummary(r, options);
  return {r.fit.u, r.fit.u_se, seconds(start)};
}

}  // namespace gtbake
