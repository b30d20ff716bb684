// bench_sweep: the sweep's tracing throughput beside a bare Embree loop over the same rays
// (docs/sweep.md §6: sweep ≥ 0.9× bare), on 1 and 2 threads, and Embree's stream calls
// (rtcIntersect1M / rtcOccluded1M) over the same rays for comparison.
//
// The ray set is recorded by replaying the sweep's walks with the same public pieces
// (cameraRay, WalkSampler, offsetOrigin) in the sweep's order and grouping, and checked to give
// the same escape counts as countEscapes for every pixel, so both sides trace exactly the same
// rays with the same calls: rtcIntersect1 for each camera ray; per pixel and bounce either one
// rtcIntersect1M (rtcOccluded1M for the last segment) over the walks still alive, or one
// rtcIntersect1 (rtcOccluded1) per ray. The bare loop copies each batch into a scratch array
// first (the sweep builds its rays there too) and counts hits, as the sweep must.
//
// The sweep keeps per-walk state in arrays and generates each bounce's directions for all walks
// still alive in vectorized loops (escape_walk.cpp); the bare loop only copies pre-made rays.
//
// Usage: bench_sweep [scene type = cavity] [resolution = 96] [spp = 256] [repeats = 3]
//        bench_sweep defaults SCENES_DIR OUT_DIR [threads = all]   (runSweep, default settings)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "common/threads.h"
#include "scene/procedural_scenes.h"
#include "sweep/escape_image.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

constexpr std::size_t kBatchGrain = 16;  // pixels' batches per TBB task in the bare loops

// Rays in the order and grouping the sweep traces them: one batch per camera ray (rtcIntersect1)
// and, per pixel, one batch per bounce (one stream call, or one single call per ray).
struct Batch {
  std::size_t begin;
  unsigned count;
  bool occlusion;  // rtcOccluded*: the last segment of the walks
  bool camera;     // a camera ray: always rtcIntersect1, as in the sweep
};

struct RaySet {
  std::vector<RTCRayHit> rays;
  std::vector<Batch> batches;
};

// countEscapes' stream traversal for one pixel, recording each bounce's batch; returns the counts.
std::vector<std::uint32_t> recordPixel(const EmbreeTracer& tracer, const SurfaceHit& start,
                                       const WalkSettings& s, std::uint64_t stream, RaySet* set) {
  const WalkSampler sampler(s, stream);
  std::vector<std::uint32_t> counts(2 * (s.bounces + 1), 0);
  std::vector<SurfaceHit> at(s.spp, start);
  std::vector<int> alive(s.spp);
  for (int i = 0; i < s.spp; ++i) alive[i] = i;
  for (int k = 0; k <= s.bounces && !alive.empty(); ++k) {
    const std::size_t begin = set->rays.size();
    const bool last = k == s.bounces;
    set->batches.push_back({begin, static_cast<unsigned>(alive.size()), last, false});
    std::vector<int> next;
    for (int i : alive) {
      const Ray ray{tracer.offsetOrigin(at[i]), sampler.direction(at[i].normal, i, k)};
      set->rays.push_back(makeRayHit(ray, s.radius));
      const int slot = (i & 1) * (s.bounces + 1) + k;
      if (last) {
        if (!tracer.occluded(ray, s.radius)) ++counts[slot];
      } else if (!tracer.intersect(ray, s.radius, &at[i])) {
        ++counts[slot];
      } else {
        next.push_back(i);
      }
    }
    alive.swap(next);
  }
  return counts;
}

RaySet recordRays(const EmbreeTracer& tracer, const Scene& scene, int res, const WalkSettings& s,
                  const EscapeImage& reference) {
  RaySet set;
  for (int j = 0; j < res; ++j) {
    for (int i = 0; i < res; ++i) {
      const Ray camera = cameraRay(scene.camera, i, j, res, res);
      set.batches.push_back({set.rays.size(), 1, false, true});
      set.rays.push_back(makeRayHit(camera, INFINITY));
      SurfaceHit hit;
      if (!tracer.intersect(camera, INFINITY, &hit)) continue;
      const std::size_t p = static_cast<std::size_t>(j) * res + i;
      const auto counts = recordPixel(tracer, hit, s, p, &set);
      for (std::size_t c = 0; c < counts.size(); ++c) {
        if (counts[c] != reference.counts[p * counts.size() + c]) {
          std::fprintf(stderr, "recorded walks differ from countEscapes at pixel %zu\n", p);
          std::exit(1);
        }
      }
    }
  }
  return set;
}

struct Timing {
  double wall = 1e30;  // seconds
  double cpu = 1e30;   // CPU seconds of the whole process
  void keepBest(const Timing& t) {
    wall = std::min(wall, t.wall);
    cpu = std::min(cpu, t.cpu);
  }
};

template <typename Fn>
Timing timed(Fn fn) {
  const std::clock_t cpu0 = std::clock();
  const auto wall0 = std::chrono::steady_clock::now();
  fn();
  Timing t;
  t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  t.cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  return t;
}

// The recorded rays through bare Embree calls, batches in parallel: `streams` = one
// rtcIntersect1M / rtcOccluded1M per batch, else one rtcIntersect1 / rtcOccluded1 per ray.
void bareLoop(RTCScene scene, const RaySet& set, bool streams) {
  std::atomic<std::uint64_t> hits{0};
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, set.batches.size(), kBatchGrain),
      [&](const tbb::blocked_range<std::size_t>& r) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        std::vector<RTCRayHit> rays;
        std::uint64_t local_hits = 0;
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
          const Batch& batch = set.batches[b];
          rays.assign(set.rays.begin() + batch.begin, set.rays.begin() + batch.begin + batch.count);
          if (streams && !batch.camera) {
            if (batch.occlusion) {
              rtcOccluded1M(scene, &context, &rays[0].ray, batch.count, sizeof(RTCRayHit));
            } else {
              rtcIntersect1M(scene, &context, rays.data(), batch.count, sizeof(RTCRayHit));
            }
          } else {
            for (RTCRayHit& rh : rays) {
              if (batch.occlusion) {
                rtcOccluded1(scene, &context, &rh.ray);
              } else {
                rtcIntersect1(scene, &context, &rh);
              }
            }
          }
          for (const RTCRayHit& rh : rays) {
            local_hits +=
                batch.occlusion ? rh.ray.tfar < 0.0f : rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
          }
        }
        hits += local_hits;
      });
  if (hits.load() == 0) std::puts("(no ray hit anything)");
}

// The default sweep (SweepOptions' defaults, all cores) over a scene directory, timed.
int runDefaults(const char* scenes, const char* out, int threads) {
  SweepOptions options;
  options.threads = threads;
  options.scenes = {scenes};
  options.out = out;
  options.progress = false;
  const Timing t = timed([&] { runSweep(options); });
  std::printf("default sweep: %.2f s wall, %.2f CPU-seconds\n", t.wall, t.cpu);
  return 0;
}

int run(int argc, char** argv) {
  if ((argc == 4 || argc == 5) && std::string(argv[1]) == "defaults") {
    return runDefaults(argv[2], argv[3], argc == 5 ? std::atoi(argv[4]) : 0);
  }
  const std::string type = argc > 1 ? argv[1] : "cavity";
  const int res = argc > 2 ? std::atoi(argv[2]) : 96;
  WalkSettings settings;
  settings.spp = argc > 3 ? std::atoi(argv[3]) : 256;
  const int repeats = argc > 4 ? std::atoi(argv[4]) : 3;
  const Scene scene = makeSceneType(type, 1);
  const EmbreeTracer tracer(scene);
  std::printf(
      "scene %s: %zu triangles, BVH build %.3f s (quality HIGH, robust), %dx%d px, spp %d,"
      " K %d\n",
      type.c_str(), scene.triangles.size(), tracer.buildSeconds(), res, res, settings.spp,
      settings.bounces);

  const EscapeImage reference =
      traceEscapeImage(tracer, scene.camera, res, res, settings, "", false);
  WalkSettings single = settings;
  single.streams = false;
  const EscapeImage single_image =
      traceEscapeImage(tracer, scene.camera, res, res, single, "", false);
  if (single_image.counts != reference.counts) {
    std::fprintf(stderr, "single-ray and stream traversals disagree\n");
    return 1;
  }
  const RaySet set = recordRays(tracer, scene, res, settings, reference);
  if (set.rays.size() != reference.rays) {
    std::fprintf(stderr, "ray count mismatch: %zu recorded, %llu traced\n", set.rays.size(),
                 static_cast<unsigned long long>(reference.rays));
    return 1;
  }
  std::printf(
      "%zu rays (%.2f per walk); single-ray and stream sweeps and the recording give "
      "identical escape counts\n\n",
      set.rays.size(),
      static_cast<double>(set.rays.size()) / (reference.unmaskedPixels() * settings.spp));
  std::printf(
      "Wall clock: Mrays per second. CPU: Mrays per CPU-second of this process (robust to\n"
      "load from other processes; on 2 threads it measures work per core, not scaling).\n");
  std::printf("%-8s %-18s %11s %11s %8s %11s %11s %8s\n", "threads", "calls", "sweep wall",
              "bare wall", "ratio", "sweep CPU", "bare CPU", "ratio");
  const double mrays = 1e-6 * static_cast<double>(set.rays.size());
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    for (bool streams : {false, true}) {
      WalkSettings mode = settings;
      mode.streams = streams;
      Timing sweep;
      Timing bare;
      // Best of `repeats`, alternating, so a burst of load from elsewhere hits both alike.
      for (int r = 0; r < repeats; ++r) {
        sweep.keepBest(
            timed([&] { traceEscapeImage(tracer, scene.camera, res, res, mode, "", false); }));
        bare.keepBest(timed([&] { bareLoop(tracer.handle(), set, streams); }));
      }
      std::printf("%-8d %-18s %11.2f %11.2f %8.3f %11.2f %11.2f %8.3f\n", threads,
                  streams ? "Intersect1M/Occ1M" : "Intersect1/Occ1", mrays / sweep.wall,
                  mrays / bare.wall, bare.wall / sweep.wall, mrays / sweep.cpu, mrays / bare.cpu,
                  bare.cpu / sweep.cpu);
    }
  }
  return 0;
}

}  // namespace
}  // namespace gtbake

int main(int argc, char** argv) {
  return gtbake::run(argc, argv);
}
