#include "validate_gtso/out_of_plane.h"

namespace gtbake {

std::vector<OutOfPlaneBin> outOfPlaneOccluded(const std::vector<SpecularSample>& samples,
                                              const std::vector<float>& s4,
                                              const std::vector<float>& s3) {
  std::vector<OutOfPlaneBin> bins(kOutOfPlaneEdges.size() - 1);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    bins[b].min_deg = kOutOfPlaneEdges[b];
    bins[b].max_deg = kOutOfPlaneEdges[b + 1];
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const SpecularSample& s = samples[i];
    std::size_t b = 0;
    while (b + 1 < bins.size() && s.out_of_plane >= kOutOfPlaneEdges[b + 1]) ++b;
    if (s.A > kOpenA) {
      ++bins[b].open_excluded;
      continue;
    }
    bins[b].s4.add(s4[i] - s.truth, s.noise_var);
    bins[b].s3.add(s3[i] - s.truth, s.noise_var);
  }
  return bins;
}

}  // namespace gtbake
