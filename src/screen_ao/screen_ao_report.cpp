#include "screen_ao/screen_ao_report.h"

#include <algorithm>
#include <cstdio>

#include "common/image_io.h"
#include "common/text_escape.h"

namespace gtbake {

namespace {

constexpr float kDiffRange = 0.5f;  // |Â − A| shown at full colour

std::string cell(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4f", v);
  return text;
}

std::string summaryTable(const std::vector<EstimatorRun>& runs) {
  std::string html =
      "<table><tr><th>estimator</th><th>bias</th><th>RMSE</th><th>bias at R</th>"
      "<th>RMSE at R</th><th>b&#770; mean&deg;</th><th>b&#770; p95&deg;</th></tr>\n";
  for (const EstimatorRun& run : runs) {
    const ErrorSummary& e = run.errors.back().all;
    html += "<tr><td>" + escapeHtml(run.name) + "</td><td>" + cell(e.bias) + "</td><td>" +
            cell(e.rmse) + "</td><td>" + (e.pixels_at_radius ? cell(e.bias_at_radius) : "-") +
            "</td><td>" + (e.pixels_at_radius ? cell(e.rmse_at_radius) : "-") + "</td><td>" +
            cell(e.bent_mean_deg) + "</td><td>" + cell(e.bent_p95_deg) + "</td></tr>\n";
  }
  return html + "</table>\n";
}

}  // namespace

std::string screenAoExr(const SweepImage& image, const std::vector<std::string>& estimators,
                        const std::vector<AoEstimate>& estimates) {
  const GBuffer& g = image.gbuffer;
  std::vector<ExrChannel> channels;
  for (std::size_t e = 0; e < estimators.size(); ++e) {
    channels.push_back({estimators[e] + ".A", estimates[e].a});
    for (int c = 0; c < 3; ++c) {
      ExrChannel channel{estimators[e] + ".BN" + "XYZ"[c], std::vector<float>(g.pixels())};
      for (std::size_t p = 0; p < g.pixels(); ++p) channel.pixels[p] = estimates[e].bent[3 * p + c];
      channels.push_back(std::move(channel));
    }
  }
  ExrChannel mask{"mask", std::vector<float>(g.pixels())};
  for (std::size_t p = 0; p < g.pixels(); ++p) mask.pixels[p] = g.mask[p];
  channels.push_back(std::move(mask));
  return encodeExr(g.width, g.height, channels, {{"gtbake.image", image.name}});
}

std::vector<std::uint8_t> divergingRgb8(const std::vector<float>& d, float range) {
  std::vector<std::uint8_t> rgb(3 * d.size());
  for (std::size_t p = 0; p < d.size(); ++p) {
    const float t = std::clamp(d[p] / range, -1.0f, 1.0f);
    const float fade = 1.0f - std::abs(t);  // white at 0
    const auto byte = [](float x) { return static_cast<std::uint8_t>(std::lround(255.0f * x)); };
    rgb[3 * p] = byte(t > 0.0f ? 1.0f : fade);
    rgb[3 * p + 1] = byte(fade);
    rgb[3 * p + 2] = byte(t < 0.0f ? 1.0f : fade);
  }
  return rgb;
}

void stageReport(OutputSet* output, const std::vector<SweepImage>& images,
                 const std::vector<EstimatorRun>& runs,
                 const std::vector<std::vector<AoEstimate>>& estimates) {
  std::string html =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>gtbake screen-ao</title>"
      "<style>body{font-family:sans-serif}img{image-rendering:pixelated;width:192px}"
      "td,th{padding:2px 8px;text-align:right}figure{display:inline-block;margin:4px}"
      "</style></head><body>\n<h1>Screen-space AO against ray-traced A</h1>\n"
      "<p>All pixels of all images (docs/screen_ao.md). Differences &Acirc; &minus; A: blue "
      "negative, red positive, full colour at &plusmn;0.5.</p>\n" +
      summaryTable(runs);
  for (std::size_t k = 0; k < images.size(); ++k) {
    const SweepImage& image = images[k];
    const GBuffer& g = image.gbuffer;
    const std::string slug = fileSlug(image.name);  // docs/limits.md §Names in outputs
    const std::string a_png = slug + "_A.png";
    output->add(a_png, encodePng(g.width, g.height, 1, toGray8(image.truth.a, 0.0f, 1.0f)));
    html += "<h2>" + escapeHtml(image.name) + "</h2>\n<div><figure><img src=\"" +
            escapeHtml(a_png) + "\"><figcaption>ray-traced A</figcaption></figure>";
    for (std::size_t e = 0; e < runs.size(); ++e) {
      const std::vector<float>& a = estimates[e][k].a;
      std::vector<float> diff(a.size(), 0.0f);
      for (std::size_t p = 0; p < a.size(); ++p) {
        if (g.mask[p] != 0) diff[p] = a[p] - image.truth.a[p];
      }
      const std::string png = slug + "_" + fileSlug(runs[e].name) + ".png";
      const std::string diff_png = slug + "_" + fileSlug(runs[e].name) + "_diff.png";
      output->add(png, encodePng(g.width, g.height, 1, toGray8(a, 0.0f, 1.0f)));
      output->add(diff_png, encodePng(g.width, g.height, 3, divergingRgb8(diff, kDiffRange)));
      const std::string run = escapeHtml(runs[e].name);
      html += "<figure><img src=\"" + escapeHtml(png) + "\"><figcaption>" + run +
              "</figcaption></figure><figure><img src=\"" + escapeHtml(diff_png) +
              "\"><figcaption>" + run + " &minus; A</figcaption></figure>";
    }
    html += "</div>\n";
  }
  output->add("screen_ao.html", html + "</body></html>\n");
}

}  // namespace gtbake
