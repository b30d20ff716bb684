// `gtbake tune` end to end on a tiny sweep: its RMSEs at the default settings against `gtbake fit
// --estimator`, the same bytes on one and two threads, and one-line errors with nothing written
// (docs/tune.md §6).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/output_set.h"
#include "fit/fit_command.h"
#include "screen_ao/screen_ao_command.h"
#include "support/temp_dir.h"
#include "synthetic_sweep.h"
#include "tiny_sweep.h"
#include "tune/tune_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<Estimator> kEstimators = {Estimator::kGtaoRuntime, Estimator::kBitmaskCosine};
// Small grids (every one holds its default) so a run stays within seconds.
const std::vector<std::string> kGrids = {"gtao-runtime.radius=0.5,1", "gtao-runtime.intensity=1,2",
                                         "gtao-runtime.thin_compensation=0,1",
                                         "bitmask-cosine.thickness=0.25,0.5,1"};

// Four scenes and their screen-ao set in <sweep>/screen_ao.
const fs::path& sweepDir() {
  static const fs::path dir = [] {
    const fs::path d = test::tinySweep(test::freshDir("tune_sweep") / "sweep",
                                       {"cavity", "clutter", "corner", "spheres"});
    ScreenAoOptions s;
    s.sweep = d;
    s.out = d / "screen_ao";
    s.estimators = kEstimators;
    s.progress = false;
    runScreenAo(s);
    return d;
  }();
  return dir;
}

TuneOptions tuneOptions(const fs::path& out) {
  TuneOptions o;
  o.sweep = sweepDir();
  o.out = out;
  o.estimators = kEstimators;
  o.grids = kGrids;
  o.progress = false;
  return o;
}

json readJson(const fs::path& file) {
  return json::parse(test::readBytes(file));
}

double relativeGap(double a, double b) {
  return std::abs(a - b) / std::abs(b);
}

TEST(TuneCommand, DefaultSettingMatchesTheProfileFit) {
  const fs::path out = test::freshDir("tune_match");
  runTune(tuneOptions(out / "tune"));
  const json tune = readJson(out / "tune" / "tune.json");
  for (const Estimator id : kEstimators) {
    const std::string e = describe(id).name;
    FitOptions f;
    f.sweep = sweepDir();
    f.out = out / (e + ".json");
    f.write_report = false;
    f.print_summary = false;
    f.progress = false;
    f.input = {e, sweepDir() / "screen_ao"};  // near-field truth at 1 m, as tune scores
    runFit(f);
    const json fit = readJson(f.out);
    const std::string key = e == "gtao-runtime" ? "radius" : "thickness";
    const json& setting = tune["results"][e][key];
    const double default_value = setting["default"];
    for (const json& g : setting["grid"]) {
      if (g["value"].get<double>() != default_value) continue;
      EXPECT_LT(relativeGap(g["rmse"]["paper"], fit["errors"]["shipped"]["rmse"]), 1e-9) << e;
      EXPECT_LT(relativeGap(g["rmse"]["profile"], fit["errors"]["refit"]["rmse"]), 1e-9) << e;
      EXPECT_LT(
          relativeGap(g["rmse"]["profile_held_out"], fit["errors"]["held_out_by_scene"]["rmse"]),
          1e-9)
          << e;
      for (const char* c : {"a1", "a0", "b1", "b0", "c1", "c0"}) {
        EXPECT_LT(relativeGap(g["refit"][c], fit["linear"][c]), 1e-9) << e << " " << c;
      }
    }
  }
  EXPECT_EQ(tune["sweep"]["clusters"].size(), 4u);
}

TEST(TuneCommand, SameBytesOnOneAndTwoThreads) {
  const fs::path out = test::freshDir("tune_threads");
  std::vector<json> docs;
  std::vector<std::string> reports;
  for (int threads : {1, 2}) {
    TuneOptions o = tuneOptions(out / std::to_string(threads));
    o.threads = threads;
    runTune(o);
    const OutputManifest m = readOutputSet(o.out, "tune");
    json doc = json::parse(m.readVerified("tune.json"));
    doc["provenance"].erase("seconds");  // wall time, the only fields that differ
    doc["provenance"].erase("total_seconds");
    docs.push_back(doc);
    reports.push_back(m.readVerified("report/tune.html"));
  }
  EXPECT_EQ(docs[0].dump(), docs[1].dump());
  EXPECT_EQ(reports[0], reports[1]);
}

// Reading the defaults' runs from screen-ao (docs/tune.md §7) gives the bytes of running them.
TEST(TuneCommand, ScreenAoDefaultsGiveTheSameResults) {
  const fs::path out = test::freshDir("tune_reuse");
  std::vector<json> docs;
  std::vector<std::size_t> runs;
  for (const bool reuse : {false, true}) {
    TuneOptions o = tuneOptions(out / (reuse ? "reuse" : "run"));
    if (reuse) o.screen_ao = sweepDir() / "screen_ao";
    runTune(o);
    json doc = readJson(o.out / "tune.json");
    docs.push_back(doc["results"]);
    runs.push_back(doc["provenance"]["estimator_runs"]);
  }
  EXPECT_EQ(docs[0].dump(), docs[1].dump());
  EXPECT_EQ(runs[1] + kEstimators.size(), runs[0]);  // one default run fewer per estimator
}

// Computing the first widening step's values in each grid's pass (docs/tune.md §7) changes no
// result: both bitmasks' thickness grids (0.25 to 4 m, sharing a pass) and the runtime pass's
// two-value grids (whose pooled minimum lies at an end, so each widens; computed without) give
// tune.json's bytes without it, apart from the seconds; a value computed ahead that widening does
// not add is not reported.
TEST(TuneCommand, ComputingWideningValuesAheadGivesTheSameResults) {
  const fs::path out = test::freshDir("tune_ahead");
  const std::vector<std::string> grids = {"gtao-runtime.radius=0.5,1", "gtao-runtime.intensity=1,2",
                                          "gtao-runtime.thin_compensation=0,1",
                                          "bitmask-uniform.thickness=0.25,0.5,1,2,4",
                                          "bitmask-cosine.thickness=0.25,0.5,1,2,4"};
  std::vector<json> docs;
  std::vector<std::vector<std::string>> parts;
  for (const bool ahead : {false, true}) {
    TuneOptions o = tuneOptions(out / (ahead ? "ahead" : "plain"));
    o.estimators = {Estimator::kGtaoRuntime, Estimator::kBitmaskUniform, Estimator::kBitmaskCosine};
    o.grids = grids;
    o.compute_ahead = ahead;
    runTune(o);
    json doc = readJson(o.out / "tune.json");
    parts.emplace_back();
    for (const auto& [part, seconds] : doc["provenance"]["seconds"].items()) {
      parts.back().push_back(part);
    }
    doc["provenance"].erase("seconds");
    doc["provenance"].erase("total_seconds");
    docs.push_back(doc);
  }
  EXPECT_EQ(docs[0].dump(), docs[1].dump());
  EXPECT_EQ(parts[0], parts[1]);
  const json& results = docs[1]["results"];
  int ends_not_added = 0;  // ends not at their limit whose value was computed ahead, not added
  for (const auto& [estimator, key] :
       std::vector<std::pair<std::string, std::string>>{{"gtao-runtime", "intensity"},
                                                        {"bitmask-uniform", "thickness"},
                                                        {"bitmask-cosine", "thickness"}}) {
    const json& r = results[estimator][key];
    const int lower = r["widened"]["lower"], upper = r["widened"]["upper"];
    EXPECT_GE(lower + upper, 1) << estimator;  // the test covers a widening step
    const std::vector<double> values = r["values"];
    const bool ahead = key == "thickness";  // the runtime pass computes none ahead
    ASSERT_EQ(values.size(), (ahead ? 5u : 2u) + static_cast<std::size_t>(lower + upper))
        << estimator;
    // An end that did not widen keeps its value: the value beyond it is not reported.
    if (lower == 0) {
      EXPECT_EQ(values.front(), ahead ? 0.25 : 1.0) << estimator;
      ends_not_added += ahead ? 1 : 0;
    }
    if (upper == 0) {
      EXPECT_EQ(values.back(), ahead ? 4.0 : 2.0) << estimator;
      ends_not_added += ahead ? 1 : 0;
    }
  }
  EXPECT_GE(ends_not_added, 1);  // and a value computed ahead went unused
}

// Every failure is one line and leaves nothing in the output directory.
void expectOneLineError(const TuneOptions& o, const std::string& needle) {
  try {
    runTune(o);
    ADD_FAILURE() << "no error; expected " << needle;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(needle), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  EXPECT_FALSE(fs::exists(o.out)) << o.out;
}

TEST(TuneCommand, BadGridsAreOneLineErrors) {
  const fs::path out = test::freshDir("tune_bad") / "out";
  const auto with = [&](std::vector<Estimator> estimators, std::vector<std::string> grids) {
    TuneOptions o = tuneOptions(out);
    o.estimators = std::move(estimators);
    o.grids = std::move(grids);
    return o;
  };
  expectOneLineError(with({Estimator::kHbao}, {}), "does not search 'hbao'");
  expectOneLineError(with(kEstimators, {"bitmask-uniform.thickness=0.5,1"}), "not tuned");
  expectOneLineError(with(kEstimators, {"gtao-runtime.steps=2,4"}), "does not search");
  expectOneLineError(with(kEstimators, {"gtao-runtime.radius=0.5,2"}), "default");
  expectOneLineError(with(kEstimators, {"gtao-runtime.radius=1"}), "two values");
  expectOneLineError(with(kEstimators, {"gtao-runtime.radius=1,1,2"}), "twice");
  expectOneLineError(with(kEstimators, {"gtao-runtime.radius=1,nan"}), "finite");
  expectOneLineError(with(kEstimators, {"gtao-runtime.intensity=1,inf"}), "finite");
  expectOneLineError(with(kEstimators, {"gtao-runtime.intensity=0,1"}), "intensity");
  expectOneLineError(with(kEstimators, {"bitmask-cosine.thickness=-1,0.5"}), "thickness");
  expectOneLineError(with(kEstimators, {"gtao-runtime.radius=1,8"}), "screen-space maximum");
  expectOneLineError(with(kEstimators, {"bitmask-cosine.thickness=0.01,0.5"}), "limits");
  expectOneLineError(with(kEstimators, {"gtao-runtime.radius"}), "ESTIMATOR.KEY=");
  expectOneLineError(with({}, {}), "no estimator");
}

TEST(TuneCommand, SweepsItCannotTuneAreOneLineErrors) {
  const fs::path root = test::freshDir("tune_bad_sweep");
  const fs::path walk = root / "walk";
  test::writeWalkSweep(
      walk, {"a", "b", "c"}, 32, 32, 16, 3, [](double u) { return test::cavityLaw(u, 3); }, 5);
  TuneOptions o = tuneOptions(root / "out_walk");
  o.sweep = walk;
  expectOneLineError(o, "no near-field truth at radius 1 m");  // a synthetic walk sweep has none
  o.unbounded_truth = true;
  expectOneLineError(o, "sweep it again");  // no camera: no G-buffer
  o = tuneOptions(root / "out_two");
  o.sweep = test::tinySweep(root / "two", {"cavity", "corner"});
  expectOneLineError(o, "needs at least 3");
}

}  // namespace
}  // namespace gtbake
