// bench_bc4: gtbake's exact BC4 encoder beside stb_dxt, libsquish and NVTT on the GTSO tables.
//
// Usage: bench_bc4 [GTSO_DIR] [--threads T]   (default GTSO_DIR: the source tree's luts/gtso, then
// out/gtso) Reads GTSO_DIR/gtso3d.f32 (32×32×32) and gtso4d.f32 (32×32×1024); if they are missing
// it uses a synthetic smooth table of the same size and says so. Peers get the table quantised to
// UNORM8 (round(clamp(v)·255), the same byte in R, G, B and A); gtbake gets the floats. Every error
// is measured against the float table after decoding with the D3D float decode (bc4_block.h).
#include <nvtt/nvtt.h>
#include <squish.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "common/threads.h"
#include "texture/bc4_block.h"
#include "texture/bc4_encoder.h"

#define STB_DXT_IMPLEMENTATION
#include <stb_dxt.h>

namespace {

using Clock = std::chrono::steady_clock;

struct Table {
  std::string name;
  int width = 32, height = 32, depth = 32;
  std::vector<float> values;
};

std::vector<float> readFloats(const std::filesystem::path& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  std::vector<float> v(count);
  if (!in.read(reinterpret_cast<char*>(v.data()), count * sizeof(float))) return {};
  return v;
}

// A smooth stand-in for S(A, β, r_p[, θo]) when no baked table exists: saturating in x, falling in
// y, with a sharp visibility edge that moves with z.
std::vector<float> syntheticTable(int w, int h, int d) {
  std::vector<float> v(static_cast<std::size_t>(w) * h * d);
  for (int z = 0; z < d; ++z) {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double a = x / (w - 1.0), c = y / (h - 1.0), r = (z % 32) / 31.0;
        const double edge = 1.0 / (1.0 + std::exp(-(a - (1.0 - c)) / (0.03 + 0.3 * r)));
        v[(static_cast<std::size_t>(z) * h + y) * w + x] =
            static_cast<float>(std::pow(a, 0.3 + r) * edge);
      }
    }
  }
  return v;
}

struct Score {
  double rmse = 0.0, max_abs = 0.0, seconds = 0.0;
};

Score score(const Table& t, const std::vector<std::uint8_t>& bytes, double seconds) {
  const std::vector<float> back = gtbake::decodeBc4Volume(bytes.data(), t.width, t.height, t.depth);
  double sse = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < back.size(); ++i) {
    const double d = static_cast<double>(back[i]) - t.values[i];
    sse += d * d;
    worst = std::max(worst, std::fabs(d));
  }
  return {std::sqrt(sse / back.size()), worst, seconds};
}

std::uint8_t unorm8(float v) {
  return static_cast<std::uint8_t>(std::lround(std::fmin(std::fmax(v, 0.0f), 1.0f) * 255.0f));
}

// Runs `encode(block index, 16 UNORM8 texels, 8 output bytes)` over all blocks with TBB.
Score perBlockPeer(const Table& t,
                   const std::function<void(const std::uint8_t*, std::uint8_t*)>& encode) {
  const int bx = t.width / 4, by = t.height / 4;
  const std::size_t blocks = static_cast<std::size_t>(bx) * by * t.depth;
  std::vector<std::uint8_t> bytes(blocks * 8);
  const auto start = Clock::now();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      const std::size_t z = b / (bx * by);
      const int row = static_cast<int>(b / bx % by), col = static_cast<int>(b % bx);
      std::uint8_t texels[16];
      for (int j = 0; j < 16; ++j) {
        texels[j] = unorm8(t.values[(z * t.height + 4 * row + j / 4) * t.width + 4 * col + j % 4]);
      }
      encode(texels, &bytes[b * 8]);
    }
  });
  return score(t, bytes, std::chrono::duration<double>(Clock::now() - start).count());
}

struct Collect : nvtt::OutputHandler {
  std::vector<std::uint8_t> bytes;
  void beginImage(int, int, int, int, int, int) override {}
  bool writeData(const void* data, int size) override {
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + size);
    return true;
  }
};

// NVTT 2.0.8 takes BGRA8 2D images: the volume goes in as one 32 × (32·depth) image, whose blocks
// are exactly the volume's blocks in the same memory order.
Score nvttPeer(const Table& t) {
  const int w = t.width, h = t.height * t.depth;
  std::vector<std::uint8_t> bgra(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < t.values.size(); ++i)
    std::memset(&bgra[4 * i], unorm8(t.values[i]), 4);
  const auto start = Clock::now();
  nvtt::InputOptions in;
  in.setTextureLayout(nvtt::TextureType_2D, w, h);
  in.setMipmapData(bgra.data(), w, h);
  in.setMipmapGeneration(false);
  nvtt::CompressionOptions options;
  options.setFormat(nvtt::Format_BC4);
  options.setQuality(nvtt::Quality_Highest);
  Collect collect;
  nvtt::OutputOptions out;
  out.setOutputHandler(&collect);
  out.setOutputHeader(false);
  nvtt::Compressor().process(in, options, out);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  collect.bytes.resize(t.values.size() / 2);
  return score(t, collect.bytes, seconds);
}

void row(const char* table, const char* codec, const char* input, const Score& s) {
  std::printf("| %-3s | %-22s | %-6s | %.4e | %.4e | %8.3f |\n", table, codec, input, s.rmse,
              s.max_abs, s.seconds);
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path dir;
  int threads = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      dir = argv[i];
    }
  }
  if (dir.empty()) {
    const std::filesystem::path shipped =
        std::filesystem::path(GTBAKE_SOURCE_DIR) / "luts" / "gtso";
    dir = std::filesystem::exists(shipped / "gtso3d.f32") ? shipped : "out/gtso";
  }
  const gtbake::ThreadLimit limit(threads);
  Table t3{"3D", 32, 32, 32, readFloats(dir / "gtso3d.f32", 32 * 32 * 32)};
  Table t4{"4D", 32, 32, 1024, readFloats(dir / "gtso4d.f32", 32 * 32 * 1024)};
  for (Table* t : {&t3, &t4}) {
    const bool synthetic = t->values.empty();
    if (synthetic) t->values = syntheticTable(t->width, t->height, t->depth);
    std::printf("%s table: %s\n", t->name.c_str(),
                synthetic
                    ? "SYNTHETIC smooth stand-in (no baked file found)"
                    : (dir / (t->name == "3D" ? "gtso3d.f32" : "gtso4d.f32")).string().c_str());
  }
  std::printf("threads: %d\n", limit.threads());
  std::printf("| tbl | codec                  | input  | RMSE       | max abs    | time (s) |\n");
  std::printf("|-----|------------------------|--------|------------|------------|----------|\n");
  const auto start = Clock::now();
  const gtbake::Bc4Encoder encoder;
  const double setup = std::chrono::duration<double>(Clock::now() - start).count();
  for (const Table* t : {&t3, &t4}) {
    const gtbake::Bc4Volume ours =
        gtbake::encodeBc4Volume(encoder, t->values.data(), t->width, t->height, t->depth, nullptr);
    row(t->name.c_str(), "gtbake (exact)", "float", {ours.rmse, ours.max_abs, ours.seconds});
    row(t->name.c_str(), "stb_dxt 1.12", "unorm8",
        perBlockPeer(*t, [](const std::uint8_t* texels, std::uint8_t* out) {
          stb_compress_bc4_block(out, texels);
        }));
    row(t->name.c_str(), "libsquish 1.15 kBc4", "unorm8",
        perBlockPeer(*t, [](const std::uint8_t* texels, std::uint8_t* out) {
          std::uint8_t rgba[64];
          for (int i = 0; i < 16; ++i) std::memset(&rgba[4 * i], texels[i], 4);
          squish::Compress(rgba, out, squish::kBc4);
        }));
    row(t->name.c_str(), "NVTT 2.0.8 Highest", "unorm8", nvttPeer(*t));
  }
  std::printf("gtbake palette table setup: %.3f s (once per run)\n", setup);
  return 0;
}
