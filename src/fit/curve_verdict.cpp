#include "fit/curve_verdict.h"

#include <algorithm>
#include <cmath>

#include "common/text_format.h"

namespace gtbake {

namespace {

std::string at(const GridPoint& p) {
  return "A = " + formatNumber(p.A, "%.3f") + ", rho = " + formatNumber(p.rho, "%.2f");
}

// The grid points of range `r` scored in one pass: max |ΔG|, max ratio, power, median band.
void scanRange(const SceneJackknife& jk, const MultiBounceCoeffs& refit,
               const MultiBounceCoeffs& given, std::size_t r, RangeScore& out) {
  std::vector<double> bands;
  std::size_t j = 0;
  forEachBandPoint(jk.rule, [&](double A, double rho) {
    const bool scored = jk.scored[j++] != 0;
    if (rangeOf(jk.rule, A) != r) return;
    const double diff = evalMultiBounce(given, A, rho) - evalMultiBounce(refit, A, rho);
    if (std::abs(diff) > out.max_difference.value) {
      out.max_difference = {std::abs(diff), A, rho};
      out.signed_difference = diff;
    }
    if (!scored) return;
    ++out.scored_points;
    const double band = jackknifeBand(jk, A, rho);
    bands.push_back(band);
    if (A < kOpenLimitA && std::abs(diff) / band > out.max_ratio_away.value) {
      out.max_ratio_away = {std::abs(diff) / band, A, rho};
    }
    if (std::abs(diff) / band > out.max_ratio.value) {
      out.max_ratio = {std::abs(diff) / band, A, rho};
      out.ratio_difference = diff;
      out.ratio_band = band;
    }
    if (out.threshold * band > out.detectable.value) {
      out.detectable = {out.threshold * band, A, rho};
    }
  });
  if (bands.empty()) return;
  std::nth_element(bands.begin(), bands.begin() + bands.size() / 2, bands.end());
  out.median_band = bands[bands.size() / 2];
}

std::string rangeText(const RangeScore& r, const VerdictRule& rule) {
  const std::string largest =
      "max |dG| " + formatNumber(r.max_difference.value, "%.4f") + " at " + at(r.max_difference);
  const std::string power =
      "detects " + formatNumber(r.detectable.value, "%.4f") + " anywhere in the range";
  switch (r.verdict) {
    case Verdict::kOutside: {
      std::string text = "outside: " + formatNumber(r.max_ratio.value, "%.2f") + " band widths > " +
                         formatNumber(r.threshold, "%.2f") + " at " + at(r.max_ratio) + " (dG " +
                         formatNumber(r.ratio_difference, "%+.5f") + ", band " +
                         formatNumber(r.ratio_band, "%.2g") + "); " + largest;
      if (r.near_open) {
        text += "; set at A >= " + formatNumber(kOpenLimitA, "%.2f") +
                ", where open pixels pin G(1, rho) = 1 (below it: " +
                formatNumber(r.max_ratio_away.value, "%.2f") + " band widths at " +
                at(r.max_ratio_away) + ")";
      }
      if (!r.fails) {
        text += "; within the tolerance " + formatNumber(*rule.fail_above, "%.4g");
      }
      return text;
    }
    case Verdict::kTooFewScenes:
      if (r.scored_points == 0) return "too few scenes to judge: no point of the range is scored";
      return "too few scenes to judge: only a difference above " +
             formatNumber(r.detectable.value, "%.3f") +
             " is detected everywhere here (needs <= " + formatNumber(rule.powerNeeded(), "%.3g") +
             "); " + largest;
    case Verdict::kConsistent:
      break;
  }
  return "consistent: " + formatNumber(r.max_ratio.value, "%.2f") +
         " band widths <= " + formatNumber(r.threshold, "%.2f") + "; " + largest + "; " + power;
}

std::string headline(const CurveVerdict& v) {
  std::string where;
  bool only_open = true;
  double largest = 0.0;
  for (std::size_t r = 0; r < v.ranges.size(); ++r) {
    const RangeScore& s = v.ranges[r];
    const bool counts = v.verdict == Verdict::kOutside ? s.fails : s.verdict == v.verdict;
    if (!counts) continue;
    where += (where.empty() ? "" : ", ") + rangeLabel(v, r);
    only_open = only_open && s.near_open && s.max_ratio_away.value <= s.threshold;
    largest = std::max(largest, s.max_difference.value);
  }
  switch (v.verdict) {
    case Verdict::kOutside:
      return "outside for A in " + where + ", by up to " + formatNumber(largest, "%.4f") + " in G" +
             (only_open ? " (only at A >= 0.95, where open pixels pin the band)" : "");
    case Verdict::kTooFewScenes:
      return "too few scenes to judge for A in " + where +
             " (the detectable difference there exceeds " +
             formatNumber(v.rule.powerNeeded(), "%.3g") + ")";
    case Verdict::kConsistent:
      break;
  }
  return "consistent in every range of A" +
         std::string(v.rule.fail_above ? " (outside the band nowhere beyond the tolerance " +
                                             formatNumber(*v.rule.fail_above, "%.4g") + ")"
                                       : "");
}

}  // namespace

std::string rangeLabel(const CurveVerdict& v, std::size_t r) {
  const RangeScore& s = v.ranges[r];
  return "[" + formatNumber(s.lo, "%.1f") + ", " + formatNumber(s.hi, "%.1f") +
         (r + 1 == v.ranges.size() ? "]" : ")");
}

const char* verdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kConsistent:
      return "consistent";
    case Verdict::kOutside:
      return "outside";
    case Verdict::kTooFewScenes:
      break;
  }
  return "too few scenes to judge";
}

CurveVerdict judgeCurve(const SceneJackknife& jk, const MultiBounceCoeffs& refit,
                        const MultiBounceCoeffs& given, const VerdictRule& rule) {
  CurveVerdict v;
  v.rule = rule;
  v.available = jk.available;
  v.message = jk.message;
  v.overall = scoreAgainstBand(jk, refit, given);
  const std::vector<double>& edges = jk.rule.ranges;
  for (std::size_t r = 0; r + 1 < edges.size(); ++r) {
    RangeScore s;
    s.lo = edges[r];
    s.hi = edges[r + 1];
    if (jk.available && r < jk.range_thresholds.size()) {
      s.threshold = jk.range_thresholds[r];
      scanRange(jk, refit, given, r, s);
    }
    s.detected = s.scored_points > 0 && s.max_ratio.value > s.threshold;
    s.fails = s.detected && (!rule.fail_above || s.max_difference.value > *rule.fail_above);
    s.near_open = s.detected && s.max_ratio.A >= kOpenLimitA;
    if (s.detected) {
      s.verdict = Verdict::kOutside;
    } else if (s.scored_points == 0 || s.detectable.value > rule.powerNeeded()) {
      s.verdict = Verdict::kTooFewScenes;
    } else {
      s.verdict = Verdict::kConsistent;
    }
    s.text = rangeText(s, rule);
    v.ranges.push_back(s);
  }
  const auto any = [&](auto pred) { return std::any_of(v.ranges.begin(), v.ranges.end(), pred); };
  if (any([](const RangeScore& s) { return s.fails; })) {
    v.verdict = Verdict::kOutside;
  } else if (any([](const RangeScore& s) { return s.verdict == Verdict::kTooFewScenes; })) {
    v.verdict = Verdict::kTooFewScenes;
  } else {
    v.verdict = Verdict::kConsistent;
  }
  v.headline = v.available ? headline(v) : std::string("too few scenes to judge: ") + jk.message;
  return v;
}

}  // namespace gtbake
