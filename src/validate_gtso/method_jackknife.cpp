#include "validate_gtso/method_jackknife.h"

#include <cmath>

#include "validate_gtso/scene_statistics.h"

namespace gtbake {

nlohmann::ordered_json methodJackknifeJson(
    const SpecularSweep& sweep, const std::string& unit, const std::vector<std::string>& names,
    const std::vector<std::vector<std::vector<ErrorStats>>>& cells) {
  std::vector<int> of;
  const std::size_t G = sceneClusters(sweep, of, unit == "type").size();
  nlohmann::ordered_json out;
  out["method"] = "delete-one-" + unit +
                  " jackknife of each method's RMSE over every unmasked pixel and roughness: SE = "
                  "sqrt((n-1)/n sum_g (rmse_(g) - mean)^2), rmse_(g) without " +
                  unit + " g's views";
  out["unit"] = unit;
  out["n"] = G;
  out["available"] = G >= 3;
  if (G < 3) return out;
  nlohmann::ordered_json methods = nlohmann::ordered_json::object();
  for (std::size_t m = 0; m < names.size(); ++m) {
    std::vector<double> sum2(G, 0.0), count(G, 0.0);
    for (std::size_t v = 0; v < cells[m].size(); ++v) {
      for (const ErrorStats& e : cells[m][v]) {
        const auto g = static_cast<std::size_t>(of[v]);
        sum2[g] += e.sum2;
        count[g] += static_cast<double>(e.count);
      }
    }
    double total2 = 0.0, total = 0.0;
    for (std::size_t g = 0; g < G; ++g) {
      total2 += sum2[g];
      total += count[g];
    }
    std::vector<double> replicate(G);
    double mean = 0.0;
    for (std::size_t g = 0; g < G; ++g) {
      const double rest = total - count[g];
      replicate[g] = rest > 0.0 ? std::sqrt((total2 - sum2[g]) / rest) : 0.0;
      mean += replicate[g] / static_cast<double>(G);
    }
    double spread = 0.0;
    for (double r : replicate) spread += (r - mean) * (r - mean);
    const double se = std::sqrt((G - 1.0) / static_cast<double>(G) * spread);
    methods[names[m]] = {{"rmse", total > 0.0 ? std::sqrt(total2 / total) : 0.0}, {"se", se}};
  }
  out["rmse"] = methods;
  return out;
}

}  // namespace gtbake
