// Grid widening towards each setting's limits, bounds and clipped intervals (docs/tune.md §3, §6)
// on synthetic objectives with known optima: every cluster's squared error a quadratic in the
// search axis, so the pooled RMSE's minimiser is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "tune/tune_analysis.h"
#include "tune/tune_outputs.h"

namespace gtbake {
namespace {

constexpr std::size_t kAlbedos = 2;

// Cluster c has points[c] points and SSE_c(z) = points[c] · M · (σ² + (z − minima[c])²) under
// both objectives (the profile's replica drops cluster s as the paper's does), z the search axis.
struct Synthetic {
  std::vector<double> minima;
  std::vector<std::size_t> points;
  double sigma2 = 1.0;

  // Σ n_c m_c / Σ n_c: where the pooled RMSE, √(const + (z − m̄)²), is smallest.
  double pooledMinimiser() const {
    double num = 0.0, den = 0.0;
    for (std::size_t c = 0; c < minima.size(); ++c) {
      num += points[c] * minima[c];
      den += points[c];
    }
    return num / den;
  }

  GridValueScore score(const SettingGrid& grid, double value) const {
    const double z = axisValue(grid, value);
    GridValueScore g;
    g.value = value;
    double total = 0.0, n = 0.0;
    for (std::size_t c = 0; c < minima.size(); ++c) {
      const double d = z - minima[c];
      g.paper_sse.push_back(points[c] * kAlbedos * (sigma2 + d * d));
      total += g.paper_sse.back();
      n += points[c];
    }
    for (double sse : g.paper_sse) g.profile_replica_sse.push_back(total - sse);
    g.profile_sse = g.held_out_sse = g.paper_sse;
    g.paper_rmse = g.profile_rmse = g.held_out_rmse = std::sqrt(total / (n * kAlbedos));
    return g;
  }

  TuneAnalysis analysis() const {
    TuneAnalysis a;
    a.cluster_points = points;
    a.albedos.assign(kAlbedos, 0.5);
    for (std::size_t c = 0; c < minima.size(); ++c) a.clusters.push_back("s" + std::to_string(c));
    return a;
  }

  // Scores the grid, widens it (counting the values run) and returns the result.
  SettingResult tune(const SettingGrid& grid, std::size_t* runs) const {
    std::vector<SettingResult> group(1);
    group[0].grid = grid;
    for (double v : grid.values) group[0].scores.push_back(score(grid, v));
    widenGroup(&group, analysis(),
               [&](std::size_t first, std::size_t count, const std::vector<double>& values) {
                 EXPECT_EQ(first, 0u);
                 EXPECT_EQ(count, 1u);
                 std::vector<GridValueScore> scores;
                 for (double v : values) scores.push_back(score(grid, v));
                 *runs += values.size();
                 return std::vector<std::vector<GridValueScore>>{scores};
               });
    return group[0];
  }
};

// Eight clusters with minima scattered (deterministically) about `centre` on the axis.
Synthetic scattered(double centre, double spread) {
  Synthetic s;
  const double offsets[] = {-0.9, 0.4, -0.2, 1.0, 0.1, -0.6, 0.7, -0.5};
  for (std::size_t c = 0; c < 8; ++c) {
    s.minima.push_back(centre + spread * offsets[c]);
    s.points.push_back(100 + 37 * c);
  }
  return s;
}

SettingGrid radiusLike() {
  SettingGrid g;
  g.estimator = Estimator::kGtaoRuntime;
  g.key = "radius";
  g.log_axis = true;
  g.default_value = 1.0;
  g.values = {0.5, 1.0, 2.0, 4.0};
  g.lower = {0.0625, "floor"};
  g.upper = {64.0, "ceiling"};
  return g;
}

TEST(TuneWiden, WidenedEndStepsGeometricallyOrArithmeticallyAndStopsAtTheLimit) {
  SettingGrid g = radiusLike();
  EXPECT_EQ(*widenedEnd(g, true), 8.0);    // 4 · (4 / 2)
  EXPECT_EQ(*widenedEnd(g, false), 0.25);  // 0.5 / (1 / 0.5)
  g.upper.value = 6.0;
  EXPECT_EQ(*widenedEnd(g, true), 6.0);  // clipped to the limit
  g.values.push_back(6.0);
  EXPECT_FALSE(widenedEnd(g, true).has_value());  // the end is the limit
  SettingGrid linear = g;
  linear.log_axis = false;
  linear.values = {0.0, 0.5, 1.0};
  linear.lower.value = 0.0;
  linear.upper.value = 10.0;
  EXPECT_EQ(*widenedEnd(linear, true), 1.5);
  EXPECT_FALSE(widenedEnd(linear, false).has_value());
}

// The vertex of the parabola through (x0, f0), (x1, f1), (x2, f2), in Lagrange's closed form
// (independent of curveArgmin's Newton form).
double parabolaVertex(double x0, double x1, double x2, double f0, double f1, double f2) {
  const double num = (x1 - x0) * (x1 - x0) * (f1 - f2) - (x1 - x2) * (x1 - x2) * (f1 - f0);
  const double den = (x1 - x0) * (f1 - f2) - (x1 - x2) * (f1 - f0);
  return x1 - 0.5 * num / den;
}

TEST(TuneWiden, AnInteriorOptimumBeyondTheGridIsFound) {
  // Minima about log10(10) = 1, past the grid's 4 m end: two steps (8, 16) bracket it, the
  // smallest sample at 8 m.
  const Synthetic s = scattered(1.0, 0.1);
  std::size_t runs = 0;
  const SettingResult r = s.tune(radiusLike(), &runs);
  EXPECT_EQ(r.grid.values, (std::vector<double>{0.5, 1.0, 2.0, 4.0, 8.0, 16.0}));
  EXPECT_EQ(runs, 2u);
  EXPECT_EQ(r.widened_upper, 2);
  EXPECT_EQ(r.widened_lower, 0);
  const SettingGrid& g = r.grid;
  const double x0 = std::log10(4.0), x1 = std::log10(8.0), x2 = std::log10(16.0);
  const double expected = parabolaVertex(x0, x1, x2, s.score(g, 4.0).paper_rmse,
                                         s.score(g, 8.0).paper_rmse, s.score(g, 16.0).paper_rmse);
  for (const SceneInterval* o : {&r.paper, &r.profile}) {
    EXPECT_EQ(optimumPlace(r, *o).status, OptimumStatus::kInterior);
    EXPECT_EQ(o->replicates_at_bound, 0u);
    EXPECT_NEAR(o->z, expected, 1e-12);
    // The RMSE is √(c + (z − m̄)²), a parabola only near m̄: the vertex within a tenth of the
    // 0.3-wide cell of the exact minimiser.
    EXPECT_NEAR(o->z, s.pooledMinimiser(), 0.03);
    EXPECT_LT(o->low, s.pooledMinimiser());
    EXPECT_GT(o->high, s.pooledMinimiser());
  }
}

TEST(TuneWiden, AnOptimumPastAPhysicalLimitIsAnUpperBoundNamingIt) {
  const Synthetic s = scattered(3.0, 0.1);  // minima near 1000, far past the limit of 16
  SettingGrid g = radiusLike();
  g.upper = {16.0, "the pass's range"};
  std::size_t runs = 0;
  const SettingResult r = s.tune(g, &runs);
  EXPECT_EQ(r.grid.values.back(), 16.0);
  EXPECT_EQ(r.widened_upper, 2);  // 8, then 16 = the limit, where it stops
  const OptimumPlace p = optimumPlace(r, r.paper);
  EXPECT_EQ(p.status, OptimumStatus::kUpperBound);
  EXPECT_EQ(p.limit.value, 16.0);
  EXPECT_EQ(p.limit.reason, "the pass's range");
  EXPECT_EQ(r.paper.replicates_at_bound, 8u);
  EXPECT_EQ(optimumSummary(r, r.paper), ">= 16 bound (8/8 replicas)");
}

TEST(TuneWiden, AnOptimumBelowALimitThatIsTheGridStartIsALowerBoundWithoutWidening) {
  const Synthetic s = scattered(-2.0, 0.1);
  SettingGrid g = radiusLike();
  g.key = "thin_compensation";
  g.log_axis = false;
  g.default_value = 0.0;
  g.values = {0.0, 0.5, 1.0};
  g.lower = {0.0, "physical"};
  std::size_t runs = 0;
  const SettingResult r = s.tune(g, &runs);
  EXPECT_EQ(runs, 0u);
  EXPECT_EQ(r.widened_lower, 0);
  const OptimumPlace p = optimumPlace(r, r.profile);
  EXPECT_EQ(p.status, OptimumStatus::kLowerBound);
  EXPECT_EQ(p.limit.reason, "physical");
  EXPECT_EQ(optimumSummary(r, r.profile), "<= 0 bound (8/8 replicas)");
}

TEST(TuneWiden, WideningStopsAfterItsBudgetAndSaysSo) {
  const Synthetic s = scattered(40.0, 0.1);  // linear axis, far beyond 1 + 4 steps of 0.5
  SettingGrid g = radiusLike();
  g.log_axis = false;
  g.values = {0.0, 0.5, 1.0};
  g.lower = {0.0, "physical"};
  g.upper = {100.0, "ceiling"};
  std::size_t runs = 0;
  const SettingResult r = s.tune(g, &runs);
  EXPECT_EQ(r.widened_upper, kMaxWidenings);
  EXPECT_EQ(r.grid.values.back(), 1.0 + 0.5 * kMaxWidenings);
  const OptimumPlace p = optimumPlace(r, r.paper);
  EXPECT_EQ(p.status, OptimumStatus::kUpperBound);
  EXPECT_EQ(p.limit.value, 3.0);
  EXPECT_NE(p.limit.reason.find("widening steps used"), std::string::npos) << p.limit.reason;
}

TEST(TuneWiden, IntervalsAreClippedToTheSearchedGrid) {
  // Replicas' argmins spread over the whole grid, the pooled one interior near the top: z + t·SE
  // reaches past the last node and is clipped there.
  const std::vector<double> x = {0.0, 1.0, 2.0, 3.0};
  const auto bowl = [&](double m) {
    std::vector<double> y;
    for (double v : x) y.push_back(1.0 + (v - m) * (v - m));
    return y;
  };
  const std::vector<std::vector<double>> replicas = {bowl(0.2), bowl(2.8), bowl(2.6), bowl(1.0)};
  const SceneInterval o = sceneInterval(x, bowl(2.4), replicas);
  EXPECT_FALSE(o.at_bound);
  EXPECT_NEAR(o.z, 2.4, 1e-12);  // the parabola through a parabola's nodes
  ASSERT_GT(o.z + o.t * o.se, 3.0);
  EXPECT_TRUE(o.interval_clipped);
  EXPECT_EQ(o.high, 3.0);
  EXPECT_GE(o.low, 0.0);
  EXPECT_EQ(o.low, std::max(0.0, o.z - o.t * o.se));
  // An unclipped one says so too.
  const SceneInterval narrow = sceneInterval(x, bowl(1.5), {bowl(1.4), bowl(1.6), bowl(1.5)});
  EXPECT_FALSE(narrow.interval_clipped);
  EXPECT_NEAR(narrow.low, narrow.z - narrow.t * narrow.se, 1e-15);
}

TEST(TuneWiden, TuneJsonSaysBoundNotBestAndNamesTheLimit) {
  const Synthetic s = scattered(3.0, 0.1);
  SettingGrid g = radiusLike();
  g.upper = {16.0, "the pass's range"};
  std::size_t runs = 0;
  TuneAnalysis a = s.analysis();
  a.settings.push_back(s.tune(g, &runs));
  const Synthetic inside = scattered(std::log10(1.5), 0.05);
  SettingGrid g2 = radiusLike();
  g2.key = "intensity";
  a.settings.push_back(inside.tune(g2, &runs));
  const nlohmann::ordered_json j = tuneJson(a, {g, g2}, {"..", 1.0});
  const auto& bound = j["results"]["gtao-runtime"]["radius"];
  EXPECT_EQ(bound["optimum"]["paper"]["status"], "upper_bound");
  EXPECT_EQ(bound["optimum"]["paper"]["limit"]["value"], 16.0);
  EXPECT_EQ(bound["optimum"]["paper"]["limit"]["reason"], "the pass's range");
  EXPECT_EQ(bound["widened"]["upper"], 2);
  EXPECT_EQ(bound["values"].back(), 16.0);
  const auto& interior = j["results"]["gtao-runtime"]["intensity"]["optimum"]["profile"];
  EXPECT_EQ(interior["status"], "interior");
  EXPECT_TRUE(interior["limit"].is_null());
  EXPECT_EQ(j["settings"]["grids"][0]["limits"]["upper"]["value"], 16.0);
  EXPECT_EQ(j["settings"]["grids"][0]["values"].size(), 4u);  // the grid as given, before widening
  EXPECT_EQ(j["settings"]["max_widenings"], kMaxWidenings);
}

}  // namespace
}  // namespace gtbake
