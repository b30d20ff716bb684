#include "screen_ao/screen_ao_import.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <system_error>

#include "common/error.h"
#include "common/image_io.h"
#include "common/input_limits.h"
#include "common/text_escape.h"
#include "common/text_format.h"
#include "screen_ao/screen_ao_set.h"
#include "screen_ao/screen_ao_settings.h"
#include "sweep/sweep_set.h"

namespace gtbake {

namespace {

constexpr std::size_t kMaxNameLength = 64;

// The bent normal channels the file holds: "BN" (world), "VBN" (view) or "" (none).
std::string bentPrefix(const ExrImage& exr, const std::string& file) {
  const auto has = [&](const std::string& prefix) {
    int count = 0;
    for (const char* c : {"X", "Y", "Z"}) count += static_cast<int>(exr.channels.count(prefix + c));
    if (count != 0 && count != 3) {
      throw Error(file + ": has some of the channels " + prefix + "X " + prefix + "Y " + prefix +
                  "Z but not all three");
    }
    return count == 3;
  };
  const bool world = has("BN");
  const bool view = has("VBN");
  if (world && view) throw Error(file + ": has both BNX/BNY/BNZ and VBNX/VBNY/VBNZ; keep one");
  return world ? "BN" : (view ? "VBN" : "");
}

// b̂ of unmasked pixel p in world space, from the file's channels (or the G-buffer's normal).
Eigen::Vector3d bentAt(const ExrImage& exr, const std::string& prefix, const GBuffer& g,
                       std::size_t p) {
  if (prefix.empty()) return {g.normal[3 * p], g.normal[3 * p + 1], g.normal[3 * p + 2]};
  const Eigen::Vector3d b(exr.channels.at(prefix + "X")[p], exr.channels.at(prefix + "Y")[p],
                          exr.channels.at(prefix + "Z")[p]);
  return prefix == "VBN" ? g.viewToWorld(b) : b;
}

// 1 to 64 of [a-z0-9_-], starting with a letter or digit.
bool nameSyntax(const std::string& name) {
  const auto allowed = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  };
  return !name.empty() && name.size() <= kMaxNameLength && name[0] != '-' && name[0] != '_' &&
         std::all_of(name.begin(), name.end(), allowed);
}

bool isBuiltin(const std::string& name) {
  const auto& builtin = screenAoEstimatorNames();
  return std::find(builtin.begin(), builtin.end(), name) != builtin.end();
}

}  // namespace

void checkImportedName(const std::string& name, const std::string& option) {
  if (!nameSyntax(name)) {
    throw Error(option + ": estimator name '" + name +
                "' must be 1 to 64 of a-z 0-9 - _, starting with a letter or digit");
  }
  if (isBuiltin(name) || name == "all" || name == "none") {
    throw Error(option + ": '" + name + "' is a built-in estimator's name or a keyword; " +
                "name the imported pass differently");
  }
}

bool isEstimatorName(const std::string& name) {
  return isBuiltin(name) || (nameSyntax(name) && name != "all" && name != "none");
}

ImportedEstimator parseImport(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos) {
    throw Error("--import must look like NAME=DIR or NAME=DIR:radius=R, got '" + text + "'");
  }
  ImportedEstimator e;
  e.name = text.substr(0, eq);
  checkImportedName(e.name, "--import");
  std::string dir = text.substr(eq + 1);
  const std::size_t suffix = dir.rfind(":radius=");
  if (suffix != std::string::npos) {
    const std::string value = dir.substr(suffix + 8);
    char* stop = nullptr;
    e.radius = std::strtod(value.c_str(), &stop);
    if (value.empty() || stop != value.c_str() + value.size() || !std::isfinite(e.radius) ||
        !(e.radius > 0.0)) {
      throw Error("--import " + e.name + ": radius '" + value + "' is not a positive number");
    }
    dir.resize(suffix);
  }
  if (dir.empty()) throw Error("--import " + e.name + ": no directory given");
  e.dir = dir;
  return e;
}

void checkImportRadius(const ImportedEstimator& e, const std::vector<SweepImage>& images) {
  if (e.radius == 0.0) return;
  const std::string channel = gbufferRadiusChannelName(e.radius);
  for (const SweepImage& image : images) {
    if (image.truth.a_at_radius.count(channel) == 0) {
      throw Error("--import " + e.name + ": the sweep's image '" + image.name + "' has no " +
                  channel + " (radius " + formatNumber(e.radius, "%g") +
                  " m is not in the sweep's --gbuffer-radius list)");
    }
  }
}

AoEstimate decodeImportedEstimate(const std::string& bytes, const std::string& file,
                                  const SweepImage& image) {
  const GBuffer& g = image.gbuffer;
  const ExrImage exr = decodeExr(bytes, file, {g.width, g.height, "the sweep's image"});
  const std::vector<float>& a = exr.channel("A", file);
  const std::string prefix = bentPrefix(exr, file);
  AoEstimate e = makeEstimate(g);
  for (std::size_t p = 0; p < g.pixels(); ++p) {
    if (g.mask[p] == 0) continue;
    if (!(a[p] >= 0.0f && a[p] <= 1.0f)) {
      throw Error(file + ": A = " + formatNumber(a[p], "%.9g") +
                  " is not in [0, 1] at the unmasked pixel " + pixelText(p, g.width));
    }
    const Eigen::Vector3d b = bentAt(exr, prefix, g, p);
    if (!b.allFinite() || !(std::abs(b.norm() - 1.0) <= kBentUnitTolerance)) {
      throw Error(file + ": the bent normal is not a finite unit vector at the unmasked pixel " +
                  pixelText(p, g.width));
    }
    e.a[p] = a[p];
    for (int c = 0; c < 3; ++c) e.bent[3 * p + c] = static_cast<float>(b[c]);
  }
  return e;
}

AoEstimate readImportedEstimate(const ImportedEstimator& e, const SweepImage& image) {
  const std::filesystem::path file = e.dir / (fileSlug(image.name) + ".exr");
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) {
    throw Error("--import " + e.name + ": no image " + file.string() + " for the sweep's image '" +
                image.name + "'");
  }
  return decodeImportedEstimate(readRegularFile(file), file.string(), image);
}

}  // namespace gtbake
