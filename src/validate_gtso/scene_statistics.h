// validate-gtso's scene-level statistics in one call (docs/validate_gtso.md §2, §3, §5): the
// scene clusters, u's scene-level interval and per-roughness optima, the paired scene-level
// ranking tests, the SO floor and the out-of-plane table over occluded pixels; and their JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/progress.h"
#include "validate_gtso/out_of_plane.h"
#include "validate_gtso/scene_paired_test.h"
#include "validate_gtso/so_floor.h"
#include "validate_gtso/specular_sweep.h"
#include "validate_gtso/u_scene_interval.h"

namespace gtbake {

struct SceneStatistics {
  std::vector<std::string> clusters;
  std::vector<int> cluster_of;  // [sweep scene]
  UAnalysis u;
  std::vector<RankingTest> ranking;  // [roughness]
  SoFloor floor;
  std::vector<OutOfPlaneBin> out_of_plane;
};

// The clusters of the sweep's views (SpecularScene::sceneName(), or typeName() with by_type),
// first-seen order, and each view's cluster index in cluster_of.
std::vector<std::string> sceneClusters(const SpecularSweep& sweep, std::vector<int>& cluster_of,
                                       bool by_type = false);

// The paired scene-level ranking test of `methods` at each roughness (scene_paired_test.h), the
// clusters those of cluster_of (numbered from 0), under its own bar in `parts`.
std::vector<RankingTest> rankingTests(const SpecularSweep& sweep,
                                      const std::vector<SpecularSample>& samples,
                                      const std::vector<std::vector<float>>& values,
                                      const std::vector<Method>& methods,
                                      const std::vector<int>& cluster_of, StageParts& parts);

// values[m][i]: method m (Method order) at samples[i]; `methods` are the scored ones; table: the
// cone SSE table of the samples over sceneClusters(sweep). Each part (u's scene-level analysis,
// the ranking tests, the floor) runs under its own bar in `parts`.
SceneStatistics sceneStatistics(const SpecularSweep& sweep,
                                const std::vector<SpecularSample>& samples,
                                const std::vector<std::vector<float>>& values,
                                const std::vector<Method>& methods, const ConeSseTable& table,
                                StageParts& parts);

// validate_gtso.json ranking_tests: per roughness the best method, the tied ones and each other
// method's paired test against the best.
nlohmann::ordered_json rankingTestsJson(const SpecularSweep& sweep,
                                        const std::vector<RankingTest>& tests);

// The keys validate_gtso.json adds: u_scene_interval, u_per_roughness, u_law, ranking_tests,
// so_floor, by_out_of_plane_occluded.
void addSceneStatisticsJson(const SpecularSweep& sweep, const SceneStatistics& s,
                            nlohmann::ordered_json& json);

// The same as an HTML page (report/validate_gtso_scenes.html, beside validate_gtso.html):
// the ranking statements, u's scene-level intervals and per-roughness optima, the floor.
std::string sceneStatisticsHtml(const SpecularSweep& sweep, const SceneStatistics& s);

}  // namespace gtbake
