// The screen-space estimators gtbake runs, one descriptor each (docs/screen_ao.md, "Command";
// docs/tune.md §1): its name, its settings in ScreenAoSettings (read, written, as JSON), how it
// runs on one image, and the settings tune searches with their grids and limits. Every stage
// that names an estimator goes through this table: names are compared here only.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "screen_ao/gtao_reference.h"
#include "screen_ao/gtao_runtime.h"
#include "screen_ao/hbao.h"
#include "screen_ao/visibility_bitmask.h"

namespace gtbake {

enum class Estimator { kGtaoReference, kGtaoRuntime, kHbao, kBitmaskUniform, kBitmaskCosine };

struct ScreenAoSettings {
  GtaoReferenceSettings reference;
  GtaoRuntimeSettings runtime;
  HbaoSettings hbao;
  BitmaskSettings bitmask_uniform;
  BitmaskSettings bitmask_cosine{1.0, 8, 8, 0.5, SectorWeights::kCosine};
};

// How far a tuned setting's grid may widen at one end (docs/tune.md §1, the limits table): the
// value and why the search stops there.
struct SettingLimit {
  double value = 0.0;
  std::string reason;
};

// A setting tune searches: its key, the setting itself in ScreenAoSettings (tune sets and reads
// it as a number, docs/tune.md §1), its axis, the grid it starts from (holding the default) and
// the limits its widening stops at (docs/tune.md §1, §3). Every tuned setting is a double.
struct TunedKey {
  const char* key;
  double& (*field)(ScreenAoSettings& s);
  bool log_axis;
  std::vector<double> grid;
  SettingLimit lower, upper;
};

struct EstimatorDescriptor {
  Estimator id;
  const char* name;  // as the command line, the JSON files and the EXR channels spell it
  const char* keys;  // its settings' keys, for an error naming them
  // Sets KEY from VALUE ("--setting NAME.KEY=VALUE" is `text`, for the error); throws a one-line
  // gtbake::Error on an unknown key or a value that does not parse.
  void (*apply)(ScreenAoSettings* s, const std::string& key, const std::string& value,
                const std::string& text);
  nlohmann::ordered_json (*settings)(const ScreenAoSettings& s);
  AoEstimate (*run)(const ScreenAoSettings& s, const GBuffer& g);
  // The bitmask settings of a visibility-bitmask estimator (their passes can be shared), else
  // null.
  BitmaskSettings ScreenAoSettings::*bitmask;
  std::vector<TunedKey> tuned;  // empty: tune does not search it
};

// Every estimator, in output order: gtao-reference, gtao-runtime, hbao, bitmask-uniform,
// bitmask-cosine.
const std::array<EstimatorDescriptor, 5>& estimatorDescriptors();
const EstimatorDescriptor& describe(Estimator e);
// The estimator of that name, or nullopt (an imported pass's name, or an unknown word).
std::optional<Estimator> findEstimator(const std::string& name);
// The descriptor of that name; throws a one-line gtbake::Error naming `what` for an unknown one.
const EstimatorDescriptor& describe(const std::string& name, const std::string& what);

}  // namespace gtbake
