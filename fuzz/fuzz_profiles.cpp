// Fuzz target: export's reader of engine profiles (readProfiles, export --profiles DIR): DIR holds
// one fit set per estimator, <estimator>/fit.json. The first byte picks the estimator directory
// the rest becomes the fit.json of (the other profile stays valid), sealed into a valid fit set
// so the reader's own checks run:
//   0 gtao-runtime   1 hbao   2 "Bad_Name" (refused by name)   3 a 40-letter name (too long)
// Anything but a gtbake::Error is a bug.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "fit/fit_set.h"
#include "fuzz_target.h"

namespace gtbake::fuzz {

namespace {

const std::string kNames[] = {"gtao-runtime", "hbao", "Bad_Name", std::string(40, 'a')};

// A profile's fit.json with every field export reads.
nlohmann::json profileJson(const std::string& estimator) {
  nlohmann::json doc;
  for (const char* c : {"a1", "a0", "b1", "b0", "c1", "c0"}) {
    doc["linear"][c] = 0.5;
    doc["linear_se"][c] = 0.01;
  }
  doc["input"] = {{"estimator", estimator}};
  doc["errors"] = {{"shipped", {{"rmse", 0.03}}}, {"held_out_by_scene", {{"rmse", 0.04}}}};
  doc["scene_jackknife"] = {{"band_max", {{"value", 0.02}}}};
  return doc;
}

}  // namespace

std::vector<std::string> seeds() {
  return {std::string(1, '\0') + profileJson("gtao-runtime").dump(),
          std::string(1, '\1') + profileJson("hbao").dump()};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  namespace fs = std::filesystem;
  if (size < 1) return 0;
  const std::string dir = fuzz::scratchDir() + "/profiles";
  const std::string& name = fuzz::kNames[data[0] % 4];
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  const std::string other = name == "hbao" ? "gtao-runtime" : "hbao";
  fuzz::writeSet(dir + "/" + other, "fit", {{"fit.json", fuzz::profileJson(other).dump()}});
  fuzz::writeSet(dir + "/" + name, "fit",
                 {{"fit.json", std::string(reinterpret_cast<const char*>(data) + 1, size - 1)}});
  try {
    readProfiles(dir);
  } catch (const Error& e) {
    fuzz::requireOneLine(e);
  }
  return 0;
}
