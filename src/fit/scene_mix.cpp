#include "fit/scene_mix.h"

#include "fit/multibounce_fit.h"

namespace gtbake {

namespace {

void appendRange(const PointSet& from, std::size_t begin, std::size_t end, PointSet& to) {
  to.A.insert(to.A.end(), from.A.begin() + static_cast<std::ptrdiff_t>(begin),
              from.A.begin() + static_cast<std::ptrdiff_t>(end));
  to.G.resize(from.G.size());
  for (std::size_t j = 0; j < from.G.size(); ++j) {
    to.G[j].insert(to.G[j].end(), from.G[j].begin() + static_cast<std::ptrdiff_t>(begin),
                   from.G[j].begin() + static_cast<std::ptrdiff_t>(end));
  }
}

}  // namespace

SweepData withoutScene(const SweepData& data, std::size_t skip) {
  SweepData out;
  out.dir = data.dir;
  out.spp = data.spp;
  out.bounces = data.bounces;
  out.albedos = data.albedos;
  for (std::size_t s = 0; s < data.scenes.size(); ++s) {
    if (s == skip) continue;
    const SweepScene& scene = data.scenes[s];
    const std::size_t begin = out.full.A.size();
    appendRange(data.full, scene.begin, scene.end, out.full);
    for (int h = 0; h < 2; ++h) appendRange(data.half[h], scene.begin, scene.end, out.half[h]);
    out.scenes.push_back({scene.name, begin, out.full.A.size()});
  }
  return out;
}

std::vector<SceneMixRow> leaveOneSceneOut(const SweepData& data, bool eiv_correction,
                                          const MultiBounceCoeffs& refit,
                                          const MultiBounceCoeffs& shipped) {
  std::vector<SceneMixRow> rows;
  if (data.scenes.size() < 2) return rows;
  for (std::size_t s = 0; s < data.scenes.size(); ++s) {
    const MultiBounceFit fit = fitMultiBounce(withoutScene(data, s), eiv_correction);
    rows.push_back({data.scenes[s].name, fit.linear.coeffs,
                    maxCurveDifference(fit.linear.coeffs, refit),
                    maxCurveDifference(fit.linear.coeffs, shipped)});
  }
  return rows;
}

}  // namespace gtbake
