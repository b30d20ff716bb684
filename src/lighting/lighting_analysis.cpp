#include "lighting/lighting_analysis.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/error.h"
#include "common/image_io.h"
#include "common/progress.h"
#include "fit/multibounce_fit.h"
#include "fit/sweep_data.h"
#include "sweep/sweep_set.h"

namespace gtbake {

void LightingErrors::add(double error, double open) {
  ++pixels;
  sum += error;
  sum_squares += error * error;
  if (error > kGlowShare * open) ++glowing;
}

double LightingErrors::rmse() const {
  return pixels == 0 ? 0.0 : std::sqrt(sum_squares / pixels);
}
double LightingErrors::bias() const {
  return pixels == 0 ? 0.0 : sum / pixels;
}
double LightingErrors::glowShare() const {
  return pixels == 0 ? 0.0 : static_cast<double>(glowing) / pixels;
}

namespace {

namespace fs = std::filesystem;

// The channels of one view that the analysis reads (docs/sweep.md §4 and "Transfer").
struct ViewChannels {
  std::size_t pixels = 0;
  const std::vector<float>* mask = nullptr;
  const std::vector<float>* a[3] = {};                      // A, H0.A, H1.A
  const std::vector<float>* n[3] = {};                      // NX, NY, NZ
  std::vector<const std::vector<float>*> g;                 // per albedo, the white-sky G
  std::vector<const std::vector<float>*> half[2];           // per bounce, H<h>.A, H<h>.P1 …
  std::vector<std::array<const std::vector<float>*, 9>> t;  // per bounce, T<k>_SH0..8
};

ViewChannels viewChannels(const ExrImage& image, const std::string& file, const SweepSet& set) {
  ViewChannels c;
  c.pixels = static_cast<std::size_t>(image.width) * image.height;
  c.mask = &image.channel("mask", file);
  const char* a[3] = {"A", "H0.A", "H1.A"};
  const char* n[3] = {"NX", "NY", "NZ"};
  for (int i = 0; i < 3; ++i) {
    c.a[i] = &image.channel(a[i], file);
    c.n[i] = &image.channel(n[i], file);
  }
  for (double rho : set.settings.albedos) c.g.push_back(&image.channel(albedoChannel(rho), file));
  for (int k = 0; k <= set.settings.bounces; ++k) {
    for (int h = 0; h < 2; ++h) {
      const std::string p = k == 0 ? "A" : "P" + std::to_string(k);
      c.half[h].push_back(&image.channel("H" + std::to_string(h) + "." + p, file));
    }
    std::array<const std::vector<float>*, 9> bounce{};
    for (int i = 0; i < kShCoefficients; ++i) {
      bounce[i] = &image.channel("T" + std::to_string(k) + "_SH" + std::to_string(i), file);
    }
    c.t.push_back(bounce);
  }
  return c;
}

// Everything one environment accumulates over the views.
struct Accumulator {
  const LightingAnalysis* analysis = nullptr;
  const Environment* env = nullptr;
  std::vector<ModelErrors> models;  // paper, [fit,] white_sky_exact
  SweepData refit;                  // pixels with open ≥ kRefitMinOpen, G/open
  std::vector<double> refit_open;
  double open_sum = 0.0;
  std::size_t pixels = 0;
};

ModelErrors emptyModel(const std::string& name, const LightingAnalysis& a) {
  ModelErrors m;
  m.model = name;
  m.albedo.resize(a.albedos.size());
  m.a_bins.resize(kLightingABins);
  m.types.resize(a.types.size());
  return m;
}

void addError(ModelErrors* m, std::size_t albedo, bool reference, int bin, std::size_t type,
              double error, double open) {
  m->albedo[albedo].add(error, open);
  if (!reference) return;
  m->a_bins[bin].add(error, open);
  m->types[type].add(error, open);
}

// Albedo j's point of the refit: G/O, and as its halves G/O plus the white sky's half-sample
// deviations Σ ρ^k H<h>.P_k − G (docs/lighting.md §3): the transfer has no halves, and under the
// uniform sky this gives exactly the points `gtbake fit` reads.
void addRefitPoint(Accumulator* acc, const ViewChannels& c, std::size_t p, std::size_t j,
                   double g) {
  const double rho = acc->analysis->albedos[j];
  acc->refit.full.G[j].push_back(g);
  for (int h = 0; h < 2; ++h) {
    double half = 0.0;
    for (std::size_t k = c.half[h].size(); k-- > 0;) half = half * rho + (*c.half[h][k])[p];
    acc->refit.half[h].G[j].push_back(g + (half - (*c.g[j])[p]));
  }
}

// One pixel p of a view: the truth Σ_k ρ^k ⟨T_k, L⟩ and the models per albedo; returns the error
// of the paper's model at the reference albedo (the heatmaps).
double addPixel(Accumulator* acc, const ViewChannels& c, std::size_t p, std::size_t type) {
  const LightingAnalysis& a = *acc->analysis;
  const ShVector& sh = acc->env->sh;
  const double open = openIrradiance(sh, (*c.n[0])[p], (*c.n[1])[p], (*c.n[2])[p]);
  std::vector<double> bounce(c.t.size());
  for (std::size_t k = 0; k < c.t.size(); ++k) {
    for (int i = 0; i < kShCoefficients; ++i) bounce[k] += (*c.t[k][i])[p] * sh[i];
  }
  const double A = (*c.a[0])[p];
  const int bin = std::min(kLightingABins - 1, static_cast<int>(A * kLightingABins));
  const bool refit = open >= kRefitMinOpen;
  double reference_error = 0.0;
  for (std::size_t j = 0; j < a.albedos.size(); ++j) {
    const double rho = a.albedos[j];
    double truth = 0.0;
    for (std::size_t k = c.t.size(); k-- > 0;) truth = truth * rho + bounce[k];
    const bool ref = j == a.reference;
    std::size_t m = 0;
    const double paper = open * evalMultiBounce(kPaperCoeffs, A, rho) - truth;
    addError(&acc->models[m++], j, ref, bin, type, paper, open);
    if (a.fit) {
      addError(&acc->models[m++], j, ref, bin, type, open * evalMultiBounce(*a.fit, A, rho) - truth,
               open);
    }
    addError(&acc->models[m], j, ref, bin, type, open * (*c.g[j])[p] - truth, open);
    if (ref) reference_error = paper;
    if (refit) addRefitPoint(acc, c, p, j, truth / open);
  }
  if (refit) {
    for (int h = 0; h < 3; ++h)
      (h == 0 ? acc->refit.full : acc->refit.half[h - 1]).A.push_back((*c.a[h])[p]);
    acc->refit_open.push_back(open);
  }
  acc->open_sum += open;
  ++acc->pixels;
  return reference_error;
}

// One decoded view into an environment's sums; the paper's error map at the reference albedo
// (masked pixels 0) when `image_name` is not empty.
void analyzeView(Accumulator* acc, const ExrImage& image, const ViewChannels& c,
                 const SweepView& view, std::size_t type, const std::string& image_name,
                 EnvironmentResult* result) {
  SweepScene scene{view.name, acc->refit.full.A.size(), 0, view.scene, view.type};
  std::vector<float> errors(c.pixels, 0.0f);
  for (std::size_t p = 0; p < c.pixels; ++p) {
    if ((*c.mask)[p] == 0.0f) continue;
    errors[p] = static_cast<float>(addPixel(acc, c, p, type));
  }
  scene.end = acc->refit.full.A.size();
  acc->refit.scenes.push_back(scene);
  if (image_name.empty()) return;
  result->images.emplace_back(
      image_name, encodePng(image.width, image.height, 3, toViridis8(errors, -0.5f, 0.5f)));
}

// The Equation 10 refit of G/open over the pixels with enough light, its scene-level band, and
// the scores of the paper's constants (and gtbake's white-sky refit) against it.
EnvironmentRefit refitEnvironment(const Accumulator& acc) {
  EnvironmentRefit r;
  r.points = acc.refit.points();
  try {
    const MultiBounceFit fit = fitMultiBounce(acc.refit);
    r.coeffs = fit.linear.coeffs;
    r.se = fit.linear.se;
    r.available = true;
    const SceneJackknife jk = sceneJackknife(acc.refit, fit, kPaperCoeffs);
    if (!jk.available) {
      r.message = jk.message;
      return r;
    }
    r.band = true;
    r.band_max = jk.band_max.value;
    r.paper = scoreAgainstBand(jk, r.coeffs, kPaperCoeffs);
    if (acc.analysis->fit) r.fit = scoreAgainstBand(jk, r.coeffs, *acc.analysis->fit);
  } catch (const Error& e) {
    r.message = e.what();
  }
  return r;
}

// The refit's own errors (per albedo, over the refit's pixels): model open·G_refit − truth.
ModelErrors refitErrors(const Accumulator& acc, const EnvironmentRefit& refit) {
  ModelErrors m = emptyModel("refit", *acc.analysis);
  if (!refit.available) return m;
  const PointSet& full = acc.refit.full;
  for (std::size_t j = 0; j < acc.analysis->albedos.size(); ++j) {
    const double rho = acc.analysis->albedos[j];
    for (std::size_t i = 0; i < full.A.size(); ++i) {
      const double open = acc.refit_open[i];
      m.albedo[j].add(open * (evalMultiBounce(refit.coeffs, full.A[i], rho) - full.G[j][i]), open);
    }
  }
  return m;
}

// An environment's empty sums.
Accumulator startEnvironment(const SweepSet& set, const LightingAnalysis& a,
                             const Environment& env) {
  Accumulator acc;
  acc.analysis = &a;
  acc.env = &env;
  acc.models.push_back(emptyModel("paper", a));
  if (a.fit) acc.models.push_back(emptyModel("fit", a));
  acc.models.push_back(emptyModel("white_sky_exact", a));
  acc.refit.dir = set.dir;
  acc.refit.spp = set.settings.spp;
  acc.refit.bounces = set.settings.bounces;
  acc.refit.albedos = a.albedos;
  for (PointSet* p : {&acc.refit.full, &acc.refit.half[0], &acc.refit.half[1]})
    p->G.resize(a.albedos.size());
  return acc;
}

// The environment's result from its sums over every view: the mean open irradiance, the refit
// and every model's errors.
void finishEnvironment(const Accumulator& acc, EnvironmentResult* result) {
  result->mean_open = acc.pixels == 0 ? 0.0 : acc.open_sum / acc.pixels;
  result->refit = refitEnvironment(acc);
  result->models = acc.models;
  result->models.push_back(refitErrors(acc, result->refit));
}

// Every environment over every view: each view is read and decoded once, then added to every
// environment's sums side by side (each environment sums in view order, so the bytes are those
// of one environment at a time); the first view of each scene type is pictured.
void analyzeEnvironments(const SweepSet& set, const std::vector<Environment>& environments,
                         bool progress, LightingAnalysis* a) {
  Progress bar("lighting", set.views.size() + 1, progress);  // the views, then the refits
  std::vector<Accumulator> sums;
  a->environments.resize(environments.size());
  for (std::size_t e = 0; e < environments.size(); ++e) {
    sums.push_back(startEnvironment(set, *a, environments[e]));
    a->environments[e].environment = environments[e];
  }
  std::vector<bool> pictured(a->types.size(), false);
  for (const SweepView& view : set.views) {
    const std::size_t type =
        std::find(a->types.begin(), a->types.end(), view.type) - a->types.begin();
    const bool picture = !pictured[type];
    pictured[type] = true;
    const std::string file = (set.dir / view.file).string();
    const std::shared_ptr<const ExrImage> shared = readVerifiedExr(
        set.manifest, view.file, file, ExrExpect{view.width, view.height, "sweep.json"});
    const ExrImage& image = *shared;
    const ViewChannels c = viewChannels(image, file, set);
    tbb::parallel_for(std::size_t{0}, environments.size(), [&](std::size_t e) {
      const std::string name =
          picture ? "images/" + environments[e].name + "_" + view.name + ".png" : "";
      analyzeView(&sums[e], image, c, view, type, name, &a->environments[e]);
    });
    bar.add(1);
  }
  tbb::parallel_for(std::size_t{0}, environments.size(),
                    [&](std::size_t e) { finishEnvironment(sums[e], &a->environments[e]); });
  bar.add(1);
  bar.finish();
}

}  // namespace

LightingAnalysis analyzeLighting(const fs::path& sweep,
                                 const std::vector<Environment>& environments,
                                 const std::optional<MultiBounceCoeffs>& fit, bool progress) {
  const SweepSet set = readSweepSet(sweep);
  if (!set.settings.transfer) {
    throw Error(set.where +
                ": the sweep has no transfer channels; rerun gtbake sweep with "
                "--transfer on (docs/sweep.md, \"Transfer\")");
  }
  LightingAnalysis a;
  a.albedos = set.settings.albedos;
  a.fit = fit;
  for (std::size_t j = 0; j < a.albedos.size(); ++j) {
    if (std::abs(a.albedos[j] - 0.5) < std::abs(a.albedos[a.reference] - 0.5)) a.reference = j;
  }
  for (const SweepView& view : set.views) {
    if (std::find(a.types.begin(), a.types.end(), view.type) == a.types.end())
      a.types.push_back(view.type);
  }
  analyzeEnvironments(set, environments, progress, &a);
  a.pixels =
      a.environments.empty() ? 0 : a.environments.front().models.front().albedo.front().pixels;
  return a;
}

}  // namespace gtbake
