#include "encode/bc4_layout.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/progress.h"
#include "gtso/gtso_integrator.h"
#include "gtso/gtso_tables.h"
#include "texture/bc4_block.h"

namespace gtbake {

namespace {

using gtso::kPointsPerLobe;
constexpr int kStressDivisor = 4;

const char* axisName(int dims, int axis) {
  return gtso::axisName(gtso::tableAxis(dims, axis));
}

bool isIdentity(const GtsoLayout& l) {
  return l.axis[0] == 0 && l.axis[1] == 1 && l.axis[2] == 2;
}

nlohmann::json layoutJson(int dims, const GtsoLayout& l) {
  return {{"x", axisName(dims, l.axis[0])},
          {"y", axisName(dims, l.axis[1])},
          {"z", axisName(dims, l.axis[2])},
          {"axis", {l.axis[0], l.axis[1], l.axis[2]}},
          {"swizzle", layoutSwizzle(l)}};
}

}  // namespace

std::vector<GtsoLayout> layoutCandidates(const GtsoTable& t) {
  const bool three = t.dims.size() == 3;
  const std::vector<GtsoLayout> all =
      three ? std::vector<GtsoLayout>{{{0, 1, 2}}, {{1, 0, 2}}, {{0, 2, 1}},
                                      {{2, 0, 1}}, {{1, 2, 0}}, {{2, 1, 0}}}
            : std::vector<GtsoLayout>{{{0, 1, 2}}, {{0, 2, 1}}, {{1, 2, 0}}};
  std::vector<GtsoLayout> valid;
  for (const GtsoLayout& l : all) {
    if (t.dims[l.axis[0]] % 4 == 0 && t.dims[l.axis[1]] % 4 == 0) valid.push_back(l);
  }
  return valid;  // never empty: gtso.json's x and y extents are multiples of 4 (identity)
}

std::array<int, 3> layoutVolume(const GtsoTable& t, const GtsoLayout& l) {
  const int nw = t.dims.size() == 4 ? t.dims[3] : 1;
  const int down = (nw + l.tilesX - 1) / l.tilesX;
  return {t.dims[l.axis[0]] * l.tilesX, t.dims[l.axis[1]], t.dims[l.axis[2]] * down};
}

std::array<int, 3> tiledTexel(const GtsoLayout& l, const int* n, const std::array<int, 4>& i) {
  return {i[0] + n[0] * (i[3] % l.tilesX), i[1], i[2] + n[2] * (i[3] / l.tilesX)};
}

std::array<int, 4> tableTexel(const GtsoLayout& l, const int* n, const std::array<int, 3>& v) {
  return {v[0] % n[0], v[1], v[2] % n[2], v[2] / n[2] * l.tilesX + v[0] / n[0]};
}

std::vector<float> permuteToLayout(const GtsoTable& t, const GtsoLayout& l) {
  const std::array<int, 3> v = layoutVolume(t, l);
  const int n[3] = {t.dims[l.axis[0]], t.dims[l.axis[1]], t.dims[l.axis[2]]};
  const int nw = t.dims.size() == 4 ? t.dims[3] : 1;
  std::vector<float> out(static_cast<std::size_t>(v[0]) * v[1] * v[2], 0.0f);
  std::size_t at = 0;
  for (int z = 0; z < v[2]; ++z) {
    for (int y = 0; y < v[1]; ++y) {
      for (int x = 0; x < v[0]; ++x, ++at) {
        const std::array<int, 4> i = tableTexel(l, n, {x, y, z});
        if (i[3] >= nw) continue;  // a tile past the last slice
        int a[3];
        for (int k = 0; k < 3; ++k) a[l.axis[k]] = i[k];
        const std::size_t src =
            ((static_cast<std::size_t>(i[3]) * t.dims[2] + a[2]) * t.dims[1] + a[1]) * t.dims[0] +
            a[0];
        out[at] = t.values[src];
      }
    }
  }
  return out;
}

const char* layout4DName(Layout4D packing) {
  return packing == Layout4D::kAtlas ? "atlas" : "fold";
}

Layout4D parseLayout4D(const std::string& name) {
  if (name == "atlas") return Layout4D::kAtlas;
  if (name == "fold") return Layout4D::kFold;
  throw Error("encode: --4d-layout takes atlas or fold, not '" + name + "'");
}

int tilesAcrossX(const GtsoTable& t, const GtsoLayout& l, Layout4D packing, int max_extent) {
  if (t.dims.size() != 4 || packing == Layout4D::kFold) return 1;
  const int nx = t.dims[l.axis[0]], ny = t.dims[l.axis[1]], nz = t.dims[l.axis[2]];
  const int nw = t.dims[3];
  const int down = std::min(nw, max_extent / nz);
  const int across = down > 0 ? (nw + down - 1) / down : 0;
  if (down == 0 || nx * across > max_extent || ny > max_extent) {
    throw Error("encode: the 4D table " + t.file + " (" + std::to_string(nx) + "x" +
                std::to_string(ny) + "x" + std::to_string(nz) + " tiles x " + std::to_string(nw) +
                " theta_o slices) does not fit an atlas of at most " + std::to_string(max_extent) +
                " texels per dimension; use --4d-layout fold");
  }
  return across;
}

void packLayoutChoice(const GtsoTable& t, Layout4D packing, int max_extent, LayoutChoice* c) {
  GtsoLayout l = c->layout;
  l.tilesX = tilesAcrossX(t, l, packing, max_extent);
  const int n[3] = {t.dims[l.axis[0]], t.dims[l.axis[1]], t.dims[l.axis[2]]};
  const int nw = t.dims[3];
  const std::array<int, 3> v = layoutVolume(t, l);
  // Block (bx, by) of slice z of the tiled volume is the fold's block holding its first texel.
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(v[0] / 4) * (v[1] / 4) * v[2] *
                                  kBc4BlockBytes);
  std::size_t at = 0;
  for (int z = 0; z < v[2]; ++z) {
    for (int by = 0; by < v[1] / 4; ++by) {
      for (int bx = 0; bx < v[0] / 4; ++bx, at += kBc4BlockBytes) {
        const std::array<int, 4> i = tableTexel(l, n, {4 * bx, 4 * by, z});
        if (i[3] >= nw) continue;  // zero texels: key 0, codes 0
        const std::size_t src =
            ((static_cast<std::size_t>(i[3]) * n[2] + i[2]) * (n[1] / 4) + by) * (n[0] / 4) +
            i[0] / 4;
        std::copy_n(c->bc4.bytes.begin() + static_cast<std::ptrdiff_t>(src * kBc4BlockBytes),
                    kBc4BlockBytes, bytes.begin() + static_cast<std::ptrdiff_t>(at));
      }
    }
  }
  const int down = v[2] / n[2];
  c->layout = l;
  c->volume = v;
  c->texels = permuteToLayout(t, l);
  c->bc4.bytes = std::move(bytes);
  c->json["volume"] = {v[0], v[1], v[2]};
  c->json["packing"] = {
      {"name", layout4DName(packing)},
      {"tiles_x", l.tilesX},
      {"tiles_z", down},
      {"tile", {n[0], n[1], n[2]}},
      {"empty_tiles", l.tilesX * down - nw},
      {"max_extent", packing == Layout4D::kAtlas ? nlohmann::json(max_extent) : nlohmann::json()},
      {"rule",
       "theta_o slice w is the tile at texel (N_x (w mod tiles_x), 0, N_z floor(w / tiles_x)); "
       "atlas: at most floor(max_extent / N_z) tiles down z, the fewest columns across x; fold: "
       "one column (tiles_x = 1)"}};
}

gtso::ErrorStats layoutLookupError(const GtsoTable& t, const GtsoVolume& v,
                                   const GtsoLayout& layout, const gtso::ErrorPoints& pts) {
  const int rank = static_cast<int>(t.dims.size());
  std::vector<double> err(pts.points.size());
  tbb::parallel_for(std::size_t{0}, err.size(), [&](std::size_t i) {
    const gtso::GtsoPoint& p = pts.points[i];
    const float A = static_cast<float>(p.A), cb = static_cast<float>(std::cos(p.beta));
    const float rp = static_cast<float>(p.r_p);
    const float s = rank == 3 ? gtso3DLookup(v, t.dims.data(), A, cb, rp, layout)
                              : gtso4DLookup(v, t.dims.data(), A, cb, rp,
                                             static_cast<float>(std::cos(p.theta_o)), layout);
    err[i] = std::abs(s - pts.exact[i]);
  });
  return gtso::errorStats(err, pts);
}

std::string layoutSwizzle(const GtsoLayout& l) {
  const char* xyz = "xyz";
  return {xyz[l.axis[0]], xyz[l.axis[1]], xyz[l.axis[2]]};
}

namespace {

// The integrator cells of the exact S: the option, else gtso.json's, else the default.
int exactCells(const GtsoInput& gtso, const LayoutOptions& o) {
  if (o.cells != 0) return o.cells;
  const auto& j = gtso.json;
  return j.contains("integrator") && j["integrator"].contains("cells")
             ? j["integrator"]["cells"].get<int>()
             : gtso::kDefaultLobeCells;
}

// The candidates of the choice: every BC4 layout of the table, or the forced one.
std::vector<GtsoLayout> chosenCandidates(const GtsoTable& t, const LayoutOptions& o) {
  std::vector<GtsoLayout> candidates = layoutCandidates(t);
  if (!o.forced) return candidates;
  const GtsoLayout f = *o.forced;
  if (std::find_if(candidates.begin(), candidates.end(), [&](const GtsoLayout& l) {
        return l.axis[0] == f.axis[0] && l.axis[1] == f.axis[1] && l.axis[2] == f.axis[2];
      }) == candidates.end()) {
    throw Error("encode: layout " + layoutSwizzle(f) + " is not a BC4 layout of " + t.file);
  }
  return {f};
}

// The four point sets every candidate is scored on: the choice's seed and the report seed.
struct LayoutPoints {
  gtso::ErrorPoints uniform, stress, report_uniform, report_stress;
  int stress_lobes = 0;
};

LayoutPoints makeLayoutPoints(int dims, const LayoutOptions& o, int cells) {
  LayoutPoints p;
  p.stress_lobes = std::max(1, o.lobes / kStressDivisor);
  const std::string label = o.progress_label ? o.progress_label : "";
  Progress progress(label + ": exact S at the points", 2 * (o.lobes + p.stress_lobes),
                    o.progress_label != nullptr);
  auto make = [&](gtso::PointSet set, int lobes, std::uint64_t seed) {
    return gtso::makeErrorPoints(dims, set, lobes, kPointsPerLobe, seed, cells, &progress);
  };
  p.uniform = make(gtso::PointSet::kUniform, o.lobes, o.seed);
  p.stress = make(gtso::PointSet::kStress, p.stress_lobes, o.seed);
  p.report_uniform = make(gtso::PointSet::kUniform, o.lobes, o.report_seed);
  p.report_stress = make(gtso::PointSet::kStress, p.stress_lobes, o.report_seed);
  return p;
}

// One candidate's BC4 volume: an x/y swap of a candidate already encoded holds the same blocks
// transposed; any other is encoded.
LayoutChoice encodeCandidate(const Bc4Encoder& encoder, const GtsoTable& t, const GtsoLayout& l,
                             const std::vector<LayoutChoice>& encoded, Progress* progress) {
  LayoutChoice c;
  c.layout = l;
  c.volume = layoutVolume(t, l);
  c.texels = permuteToLayout(t, l);
  const LayoutChoice* swap = nullptr;
  for (const LayoutChoice& e : encoded) {
    if (e.layout.axis[0] == l.axis[1] && e.layout.axis[1] == l.axis[0] &&
        e.layout.axis[2] == l.axis[2]) {
      swap = &e;
    }
  }
  if (swap) {
    c.bc4 = swapBc4VolumeXY(swap->bc4, c.texels.data(), c.volume[0], c.volume[1], c.volume[2]);
    if (progress) progress->add(c.texels.size() / kBc4BlockTexels);
  } else {
    c.bc4 =
        encodeBc4Volume(encoder, c.texels.data(), c.volume[0], c.volume[1], c.volume[2], progress);
  }
  return c;
}

// The end-to-end errors of one encoded candidate on the four point sets.
LayoutCandidate scoreCandidate(const GtsoTable& t, const LayoutChoice& c, const LayoutPoints& p) {
  const std::vector<std::uint64_t> blocks = bc4BlockWords(c.bc4.bytes);
  const GtsoLayout& l = c.layout;
  LayoutCandidate k;
  k.layout = l;
  const GtsoVolume v{GtsoTexelFormat::kBc4, blocks.data(), c.volume[0], c.volume[1], c.volume[2]};
  auto score = [&](const gtso::ErrorPoints& points, double* rms, double* max) {
    const gtso::ErrorStats e = layoutLookupError(t, v, l, points);
    *rms = e.rms;
    *max = e.max;
  };
  score(p.uniform, &k.uniform_rms, &k.uniform_max);
  score(p.stress, &k.stress_rms, &k.stress_max);
  score(p.report_uniform, &k.report_uniform_rms, &k.report_uniform_max);
  score(p.report_stress, &k.report_stress_rms, &k.report_stress_max);
  k.texel_rms = c.bc4.rmse;
  k.texel_max = c.bc4.max_abs;
  k.encode_seconds = c.bc4.seconds;
  return k;
}

// The lowest uniform RMS; within kLayoutRmsTie of it the lowest uniform max; then the order.
int pickLayout(const std::vector<LayoutCandidate>& scores) {
  double lowest = HUGE_VAL;
  for (const LayoutCandidate& k : scores) lowest = std::min(lowest, k.uniform_rms);
  int chosen = -1;
  for (int i = 0; i < static_cast<int>(scores.size()); ++i) {
    const LayoutCandidate& k = scores[i];
    if (k.uniform_rms > lowest * (1.0 + kLayoutRmsTie)) continue;
    if (chosen < 0 || k.uniform_max < scores[chosen].uniform_max) chosen = i;
  }
  return chosen;
}

// encode.json layouts/<3d|4d>: the choice, the rule, every candidate and the points.
nlohmann::json choiceJson(int dims, const LayoutChoice& out, const LayoutOptions& o,
                          const LayoutPoints& p, int cells) {
  const std::vector<LayoutCandidate>& scores = out.candidates;
  const int chosen = out.chosen;
  const int stressLobes = p.stress_lobes;
  nlohmann::json list = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(scores.size()); ++i) {
    const LayoutCandidate& k = scores[i];
    list.push_back({{"layout", layoutJson(dims, k.layout)},
                    {"uniform", {{"rms", k.uniform_rms}, {"max", k.uniform_max}}},
                    {"stress", {{"rms", k.stress_rms}, {"max", k.stress_max}}},
                    {"report",
                     {{"uniform", {{"rms", k.report_uniform_rms}, {"max", k.report_uniform_max}}},
                      {"stress", {{"rms", k.report_stress_rms}, {"max", k.report_stress_max}}}}},
                    {"texel_rms", k.texel_rms},
                    {"texel_max", k.texel_max},
                    {"encode_s", k.encode_seconds},
                    {"chosen", i == chosen}});
  }
  const LayoutCandidate& c = out.candidates[chosen];
  // The table-order layout, when it is a candidate: the baseline the choice is compared with.
  const LayoutCandidate* identity = nullptr;
  for (const LayoutCandidate& k : out.candidates) {
    if (isIdentity(k.layout)) identity = &k;
  }
  auto ofIdentity = [&](double LayoutCandidate::*field) {
    return identity ? nlohmann::json(identity->*field) : nlohmann::json(nullptr);
  };
  return {{"chosen", layoutJson(dims, out.layout)},
          {"rule",
           "lowest uniform RMS of |runtime BC4 lookup - exact S|; candidates within 1% of it "
           "tie and the tie goes to the lowest uniform max, then to the earlier candidate"},
          {"volume", {out.volume[0], out.volume[1], out.volume[2]}},
          {"forced", o.forced != nullptr},
          {"uniform_rms", c.uniform_rms},
          {"uniform_max", c.uniform_max},
          {"stress_rms", c.stress_rms},
          {"stress_max", c.stress_max},
          {"report_uniform_rms", c.report_uniform_rms},
          {"report_uniform_max", c.report_uniform_max},
          {"report_stress_rms", c.report_stress_rms},
          {"report_stress_max", c.report_stress_max},
          {"identity_uniform_rms", ofIdentity(&LayoutCandidate::uniform_rms)},
          {"identity_uniform_max", ofIdentity(&LayoutCandidate::uniform_max)},
          {"identity_report_uniform_rms", ofIdentity(&LayoutCandidate::report_uniform_rms)},
          {"identity_report_uniform_max", ofIdentity(&LayoutCandidate::report_uniform_max)},
          {"identity_report_stress_max", ofIdentity(&LayoutCandidate::report_stress_max)},
          {"candidates", list},
          {"points",
           {{"uniform", o.lobes * kPointsPerLobe},
            {"stress", stressLobes * kPointsPerLobe},
            {"seed", o.seed},
            {"report_seed", o.report_seed},
            {"exact_cells", cells},
            {"generator", "gtso::makeErrorPoints (the distributions of gtso.json end_to_end)"}}}};
}

}  // namespace

LayoutChoice chooseLayout(const Bc4Encoder& encoder, const GtsoTable& t, const GtsoInput& gtso,
                          const LayoutOptions& o) {
  const int dims = static_cast<int>(t.dims.size());
  const int cells = exactCells(gtso, o);
  const LayoutPoints points = makeLayoutPoints(dims, o, cells);
  const std::vector<GtsoLayout> candidates = chosenCandidates(t, o);
  const auto& v = t.volume;
  const std::string label = o.progress_label ? o.progress_label : "";
  Progress progress(label + ": encoding", candidates.size() * (v[0] / 4) * (v[1] / 4) * v[2],
                    o.progress_label != nullptr);
  std::vector<LayoutCandidate> scores;
  std::vector<LayoutChoice> encoded;
  for (const GtsoLayout& l : candidates) {
    encoded.push_back(encodeCandidate(encoder, t, l, encoded, &progress));
    scores.push_back(scoreCandidate(t, encoded.back(), points));
  }
  progress.finish();
  const int chosen = pickLayout(scores);
  LayoutChoice out = std::move(encoded[chosen]);
  out.candidates = std::move(scores);
  out.chosen = chosen;
  out.json = choiceJson(dims, out, o, points, cells);
  out.report_uniform = points.report_uniform;
  out.report_stress = points.report_stress;
  out.lobes = o.lobes;
  out.stress_lobes = points.stress_lobes;
  out.exact_cells = cells;
  return out;
}

GtsoLayouts chooseLayouts(const GtsoInput& gtso, int lobes, const GtsoLayout* forced3,
                          const GtsoLayout* forced4, bool progress) {
  const Bc4Encoder encoder;
  auto one = [&](const GtsoTable& t, const GtsoLayout* forced, const char* label) {
    LayoutOptions o;
    o.lobes = lobes;
    o.forced = forced;
    o.progress_label = progress ? label : nullptr;
    return chooseLayout(encoder, t, gtso, o);
  };
  return {one(gtso.table3d, forced3, "BC4 3D layouts"),
          one(gtso.table4d, forced4, "BC4 4D layouts")};
}

}  // namespace gtbake
