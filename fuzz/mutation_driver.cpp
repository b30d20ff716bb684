// A bounded, deterministic mutation loop around a fuzz target, built with the normal compiler so
// CTest (and CI) exercise every target on every build; libFuzzer builds (GTBAKE_FUZZ=ON, clang)
// explore far more.
//
//   <driver> [ITERATIONS] [SEED]   mutate the target's seeds ITERATIONS times (default 2000)
//   <driver> --write-corpus DIR    write the seeds as a starting corpus for libFuzzer
//   <driver> FILE...               run the given inputs (reproduce a libFuzzer crash)
//
// Mutations (xorshift64*, so a run is reproducible from its seed): bit flips, byte overwrites
// with boundary values, inserted and deleted runs, duplicated runs, digit strings replaced by
// huge or negative numbers, and splices of two seeds.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_target.h"

namespace {

struct Rng {
  std::uint64_t state;
  std::uint64_t next() {
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return state * 0x2545F4914F6CDD1Dull;
  }
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(next() % n); }
};

void mutate(std::string& s, Rng& rng, const std::vector<std::string>& seeds) {
  static const char* kNumbers[] = {"-1",
                                   "0",
                                   "4294967296",
                                   "18446744073709551615",
                                   "18446744073709551616",
                                   "9223372036854775807",
                                   "1e308",
                                   "-2147483648",
                                   "65535",
                                   "3"};
  static const unsigned char kBytes[] = {0x00, 0xFF, 0x7F, 0x80, 0x01, '[', '{', '"', '.', '/'};
  const int rounds = 1 + static_cast<int>(rng.below(4));
  for (int r = 0; r < rounds; ++r) {
    switch (rng.below(7)) {
      case 0:
        if (!s.empty()) s[rng.below(s.size())] ^= static_cast<char>(1u << rng.below(8));
        break;
      case 1:
        if (!s.empty()) s[rng.below(s.size())] = static_cast<char>(kBytes[rng.below(10)]);
        break;
      case 2: {
        const std::size_t at = rng.below(s.size() + 1);
        s.insert(at, std::string(1 + rng.below(8), static_cast<char>(rng.next())));
        break;
      }
      case 3:
        if (!s.empty()) {
          const std::size_t at = rng.below(s.size());
          s.erase(at, 1 + rng.below(std::min<std::size_t>(64, s.size() - at)));
        }
        break;
      case 4:
        if (!s.empty() && s.size() < (1u << 20)) {
          const std::size_t at = rng.below(s.size());
          const std::size_t len = 1 + rng.below(std::min<std::size_t>(256, s.size() - at));
          s.insert(rng.below(s.size()), s.substr(at, len));
        }
        break;
      case 5: {  // a number in the text replaced by a boundary value
        std::vector<std::size_t> starts;
        for (std::size_t i = 0; i < s.size(); ++i) {
          if (s[i] >= '0' && s[i] <= '9' && (i == 0 || s[i - 1] < '0' || s[i - 1] > '9')) {
            starts.push_back(i);
          }
        }
        if (starts.empty()) break;
        const std::size_t at = starts[rng.below(starts.size())];
        std::size_t end = at;
        while (end < s.size() && ((s[end] >= '0' && s[end] <= '9') || s[end] == '.')) ++end;
        s.replace(at, end - at, kNumbers[rng.below(10)]);
        break;
      }
      default: {  // splice with another seed
        const std::string& other = seeds[rng.below(seeds.size())];
        const std::size_t cut = rng.below(s.size() + 1);
        const std::size_t from = rng.below(other.size() + 1);
        s = s.substr(0, cut) + other.substr(from);
        break;
      }
    }
  }
}

int runInput(const std::string& bytes) {
  return LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> seeds = gtbake::fuzz::seeds();
  if (argc == 3 && std::strcmp(argv[1], "--write-corpus") == 0) {
    std::filesystem::create_directories(argv[2]);
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      std::ofstream(std::filesystem::path(argv[2]) / ("seed" + std::to_string(i)), std::ios::binary)
          << seeds[i];
    }
    return 0;
  }
  if (argc >= 2 && !std::isdigit(static_cast<unsigned char>(argv[1][0]))) {
    for (int i = 1; i < argc; ++i) {
      std::ifstream in(argv[i], std::ios::binary);
      std::ostringstream buffer;
      buffer << in.rdbuf();
      runInput(buffer.str());
    }
    return 0;
  }
  const long iterations = argc >= 2 ? std::strtol(argv[1], nullptr, 10) : 2000;
  Rng rng{argc >= 3 ? std::strtoull(argv[2], nullptr, 10) | 1 : 0x9E3779B97F4A7C15ull};
  for (const std::string& seed : seeds) runInput(seed);
  for (long i = 0; i < iterations; ++i) {
    std::string input = seeds[rng.below(seeds.size())];
    mutate(input, rng, seeds);
    runInput(input);
  }
  std::printf("%s: %ld mutated inputs, no crash\n", argv[0], iterations);
  return 0;
}
