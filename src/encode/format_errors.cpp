#include "encode/format_errors.h"

#include <cmath>
#include <string>
#include <vector>

#include "common/progress.h"
#include "gtso/gtso_end_to_end.h"
#include "texture/bc4_block.h"
#include "texture/texture_containers.h"

namespace gtbake {

namespace {

using Json = nlohmann::json;

// The bars of docs/gtso.md §3a on what the runtime reads: uniform max, stress max (3D, 4D).
constexpr double kUniformBar[2] = {0.03, 0.06};
constexpr double kStressBar[2] = {0.05, 0.10};
constexpr double kRecommendRatio = 1.5;  // a format's error vs float32's for the recommendation
constexpr TexelFormat kFormats[] = {TexelFormat::kFloat32, TexelFormat::kBc4, TexelFormat::kR16,
                                    TexelFormat::kR8};

// One format of a table in its layout: the texels as the runtime reads them.
struct FormatVolume {
  TexelFormat format;
  std::vector<std::uint8_t> bytes;   // float32, R16, R8: the texels; BC4: the blocks
  std::vector<std::uint64_t> words;  // BC4 blocks as the lookup reads them
  double texel_max = 0.0, texel_rms = 0.0;
  const void* texels() const {
    return format == TexelFormat::kBc4 ? static_cast<const void*>(words.data())
                                       : static_cast<const void*>(bytes.data());
  }
};

// Decoded texels against the layout's float texels: max and RMS.
void texelErrors(const std::vector<float>& decoded, const std::vector<float>& texels,
                 FormatVolume* v) {
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const double d = std::abs(static_cast<double>(decoded[i]) - texels[i]);
    v->texel_max = std::max(v->texel_max, d);
    v->texel_rms += d * d;
  }
  v->texel_rms = std::sqrt(v->texel_rms / static_cast<double>(texels.size()));
}

FormatVolume formatVolume(const LayoutChoice& c, TexelFormat format) {
  FormatVolume v{format, {}, {}};
  const std::vector<float>& f = c.texels;
  if (format == TexelFormat::kFloat32) {
    v.bytes.resize(f.size() * sizeof(float));
    std::copy(reinterpret_cast<const std::uint8_t*>(f.data()),
              reinterpret_cast<const std::uint8_t*>(f.data()) + v.bytes.size(), v.bytes.begin());
  } else if (format == TexelFormat::kBc4) {
    v.bytes = c.bc4.bytes;
    v.words = bc4BlockWords(v.bytes);
    v.texel_max = c.bc4.max_abs;
    v.texel_rms = c.bc4.rmse;
  } else {
    v.bytes = quantizeUnorm(f.data(), f.size(), format);
    texelErrors(dequantizeUnorm(v.bytes, format), f, &v);
  }
  return v;
}

}  // namespace

Json formatErrorsJson(const GtsoTable& t, const LayoutChoice& c, const char* progress) {
  const int dims = static_cast<int>(t.dims.size());
  Progress bar(std::string(progress ? progress : "") + ": exact S at the second seed",
               static_cast<std::size_t>(c.lobes + c.stress_lobes), progress != nullptr);
  const gtso::ErrorPoints second[2] = {
      gtso::makeErrorPoints(dims, gtso::PointSet::kUniform, c.lobes, gtso::kPointsPerLobe,
                            kFormatSecondSeed, c.exact_cells, &bar),
      gtso::makeErrorPoints(dims, gtso::PointSet::kStress, c.stress_lobes, gtso::kPointsPerLobe,
                            kFormatSecondSeed, c.exact_cells, &bar)};
  bar.finish();
  const gtso::ErrorPoints* sets[2][2] = {{&c.report_uniform, &second[0]},
                                         {&c.report_stress, &second[1]}};
  Json formats = Json::object();
  Json summaries[std::size(kFormats)][2];
  for (std::size_t f = 0; f < std::size(kFormats); ++f) {
    const FormatVolume v = formatVolume(c, kFormats[f]);
    const GtsoVolume volume{v.format, v.texels(), c.volume[0], c.volume[1], c.volume[2]};
    for (int set = 0; set < 2; ++set) {
      std::vector<gtso::ErrorStats> per_seed;
      for (const gtso::ErrorPoints* points : sets[set]) {
        per_seed.push_back(layoutLookupError(t, volume, c.layout, *points));
      }
      summaries[f][set] = gtso::seedSummary(per_seed, kLayoutReportSeed);
    }
    formats[texelFormatName(v.format)] = {{"bytes", v.bytes.size()},
                                          {"texel_max_error", v.texel_max},
                                          {"texel_rms_error", v.texel_rms},
                                          {"uniform", summaries[f][0]},
                                          {"stress", summaries[f][1]}};
  }
  // The smallest format whose uniform max, uniform RMS and stress max are each within 1.5x those
  // of float32 in the same layout: quantisation does not dominate the interpolation error.
  std::size_t best = 0;
  for (std::size_t f = 1; f < std::size(kFormats); ++f) {
    auto within = [&](int set, const char* k) {
      return summaries[f][set][k].get<double>() <=
             kRecommendRatio * summaries[0][set][k].get<double>();
    };
    const std::size_t size = formats[texelFormatName(kFormats[f])]["bytes"].get<std::size_t>();
    const std::size_t best_size =
        formats[texelFormatName(kFormats[best])]["bytes"].get<std::size_t>();
    if (within(0, "max") && within(0, "rms") && within(1, "max") && size < best_size) best = f;
  }
  const int k = dims == 3 ? 0 : 1;
  return {{"formats", formats},
          {"recommended", texelFormatName(kFormats[best])},
          {"bars", {{"uniform_max", kUniformBar[k]}, {"stress_max", kStressBar[k]}}}};
}

Json endToEndJson(const GtsoInput& gtso, const GtsoLayouts& layouts, bool progress) {
  const LayoutChoice& c = layouts.t3;
  return {{"points",
           {{"uniform", c.lobes * gtso::kPointsPerLobe},
            {"stress", c.stress_lobes * gtso::kPointsPerLobe},
            {"seeds", {kLayoutReportSeed, kFormatSecondSeed}},
            {"exact_cells", c.exact_cells},
            {"layout", "each table's chosen layout (layouts/<3d|4d>/chosen), the files as written"},
            {"note",
             "seed 1002 is the layout choice's report seed and 1003 the next: both fresh, the "
             "choice used 1001; the distributions of gtso.json end_to_end"}}},
          {"3d", formatErrorsJson(gtso.table3d, layouts.t3, progress ? "end to end 3D" : nullptr)},
          {"4d", formatErrorsJson(gtso.table4d, layouts.t4, progress ? "end to end 4D" : nullptr)},
          {"recommendation_rule",
           "smallest format whose uniform max, uniform RMS and stress max are each within 1.5x "
           "those of float32 in the same layout (quantisation does not dominate the "
           "interpolation error)"}};
}

}  // namespace gtbake
