// bench_gtso_axes: the end-to-end error of the table axes on the selection seeds, the tool that
// chose the axis constants of src/runtime/gtso_runtime.h (docs/gtso.md §3).
//
// Bakes the 3D or 4D table with the compiled-in axes, reads it back through the runtime lookup
// (float32 and BC4, half-texel remap, trilinear, 4D fold) at the uniform and stress point sets of
// the selection seeds (1-3 by default; `gtbake gtso` reports on fresh seeds from 10), and prints
// max / RMS error per seed, the worst point, and where the squared error lives (r_p quarter x
// theta_o band). A candidate constant is compiled in and measured with this program; the one
// kept is the one with the lowest float32 uniform RMS whose maxima meet the bars.
//
// usage: bench_gtso_axes 3|4 [--size N] [--seeds K] [--lobes L] [--cells C]
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "gtso/gtso_integrator.h"
#include "gtso/gtso_tables.h"
#include "texture/bc4_encoder.h"

using namespace gtbake::gtso;
using gtbake::TexelFormat;
using gtbake::texelFormatName;

namespace {

struct Options {
  int dims = 3, size = 32, seeds = 3, lobes = 1024, cells = kDefaultLobeCells;
};

// Share of the squared error per r_p quarter (rows) and theta_o band (< 0.5, < 1.3, >= 1.3 rad).
void printBands(const Table& t, const EncodedTable& e, const ErrorPoints& p) {
  double band[4][3] = {};
  double total = 0.0;
  for (std::size_t i = 0; i < p.points.size(); ++i) {
    const double d = runtimeLookup(t, e, p.points[i]) - p.exact[i];
    const int r = std::min(3, static_cast<int>(p.points[i].r_p * 4));
    const double th = p.points[i].theta_o;
    band[r][th < 0.5 ? 0 : (th < 1.3 ? 1 : 2)] += d * d;
    total += d * d;
  }
  std::printf("    squared error by r_p quarter [theta_o < 0.5, < 1.3, >= 1.3]:");
  for (const auto& row : band)
    std::printf(" [%.2f %.2f %.2f]", row[0] / total, row[1] / total, row[2] / total);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (argc < 2 || (std::strcmp(argv[1], "3") != 0 && std::strcmp(argv[1], "4") != 0)) {
    std::fprintf(stderr,
                 "usage: bench_gtso_axes 3|4 [--size N] [--seeds K] [--lobes L] [--cells C]\n");
    return 2;
  }
  o.dims = std::atoi(argv[1]);
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const int v = std::atoi(argv[i + 1]);
    if (k == "--size")
      o.size = v;
    else if (k == "--seeds")
      o.seeds = v;
    else if (k == "--lobes")
      o.lobes = v;
    else if (k == "--cells")
      o.cells = v;
    else {
      std::fprintf(stderr, "bench_gtso_axes: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Table t = bakeTable(o.dims, o.size, o.cells, nullptr);
  std::printf("%dD table %d per axis baked in %.1f s\n", o.dims, o.size,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  // BC4 in table order, as the axes were chosen (gtso itself writes only float32).
  EncodedTable bc4;
  bc4.format = TexelFormat::kBc4;
  const std::vector<float> texels = toFloats(t);
  const std::array<int, 3> v = t.volume();
  bc4.bytes =
      gtbake::encodeBc4Volume(gtbake::Bc4Encoder(), texels.data(), v[0], v[1], v[2], nullptr).bytes;
  for (const EncodedTable& e : {floatTable(t), bc4}) {
    const TexelFormat f = e.format;
    for (PointSet set : {PointSet::kUniform, PointSet::kStress}) {
      for (int s = 1; s <= o.seeds; ++s) {
        const int lobes = set == PointSet::kUniform ? o.lobes : std::max(1, o.lobes / 4);
        const ErrorPoints p = makeErrorPoints(o.dims, set, lobes, 16, s, o.cells);
        const ErrorStats st = lookupError(t, e, p);
        std::printf(
            "%-7s %-7s seed %d: max %.4f rms %.5f  worst A %.5f beta %.4f r_p %.4f "
            "theta_o %.4f\n",
            texelFormatName(f), pointSetName(set), s, st.max, st.rms, st.worst.A, st.worst.beta,
            st.worst.r_p, st.worst.theta_o);
        if (f == TexelFormat::kFloat32) printBands(t, e, p);
      }
    }
  }
  return 0;
}
