// bench_s3_closed_form: the closed-form S3 fit of `gtbake gtso` (gtso_runtime.h gtsoS3ClosedForm)
// on its own: fit time, training objective, and the error of the shipped float function on the
// validation set (another seed of the training distribution) and on the test sets (gtso's 3D
// end-to-end uniform and stress points), split at r_p = 0.1. Used to choose the form (docs/gtso.md
// §7). --cold fits from closedFormStart() (every polynomial 0) instead of the warm start and prints
// the coefficients as the C++ initializer of the warm start; --dump prints S and the form along
// alpha_v for a few lobes.
//
// usage: bench_s3_closed_form [--cold] [--dump] [--lobes N] [--per-lobe N] [--cells N]
//                             [--test-lobes N] [--threads T]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "common/threads.h"
#include "gtso/gtso_integrator.h"
#include "gtso/s3_closed_form.h"

using namespace gtbake;
using namespace gtbake::gtso;

namespace {

void print(const char* name, const ClosedFormErrors& e) {
  std::printf("  %-22s r_p >= 0.1: max %.4f rms %.5f (%d)   r_p < 0.1: max %.4f rms %.5f (%d)\n",
              name, e.rough.stats.max, e.rough.stats.rms, e.rough.count, e.smooth.stats.max,
              e.smooth.stats.rms, e.smooth.count);
  const GtsoPoint& w = e.rough.stats.worst;
  std::printf("  %-22s worst r_p >= 0.1 at A %.4f cos theta_o %.4f r_p %.4f\n", "", w.A,
              std::cos(w.theta_o), w.r_p);
}

}  // namespace

int main(int argc, char** argv) {
  int lobes = 2048, perLobe = 32, cells = 48, testLobes = 1024, threads = 2;
  bool cold = false, dump = false;
  for (int i = 1; i < argc; ++i) {
    const bool value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--cold")) {
      cold = true;
    } else if (!std::strcmp(argv[i], "--dump")) {
      dump = true;
    } else if (value && !std::strcmp(argv[i], "--lobes")) {
      lobes = std::atoi(argv[++i]);
    } else if (value && !std::strcmp(argv[i], "--per-lobe")) {
      perLobe = std::atoi(argv[++i]);
    } else if (value && !std::strcmp(argv[i], "--cells")) {
      cells = std::atoi(argv[++i]);
    } else if (value && !std::strcmp(argv[i], "--test-lobes")) {
      testLobes = std::atoi(argv[++i]);
    } else if (value && !std::strcmp(argv[i], "--threads")) {
      threads = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "bench_s3_closed_form: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  const ThreadLimit limit(threads);
  auto t0 = std::chrono::steady_clock::now();
  const ErrorPoints train = makeClosedFormPoints(lobes, perLobe, 1000, cells);
  const ErrorPoints val = makeClosedFormPoints(lobes, perLobe, 2000, kDefaultLobeCells);
  const double pointSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t0 = std::chrono::steady_clock::now();
  const S3ClosedFormFit fit =
      fitS3ClosedForm(train, perLobe, cold ? closedFormStart() : closedFormWarmStart());
  const double fitSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "points %.2f s, fit %.2f s: %d points, objective %.6g -> %.6g (rms %.5f), %d "
      "iterations%s, float-k objective %.6g\n",
      pointSeconds, fitSeconds, fit.points, fit.initial_objective, fit.objective, fit.rms,
      fit.iterations, fit.converged ? "" : " (not converged)", fit.objective_float_k);
  print("training", closedFormErrors(fit.k, train));
  print("validation", closedFormErrors(fit.k, val));
  // gtso's uniform and stress distributions at seeds [first, last]: the selection set (seeds
  // 50-52, comparable across training distributions) and gtso's test set (its end-to-end report
  // seeds 10-12).
  auto gtsoSets = [&](std::uint64_t first, std::uint64_t last) {
    ClosedFormErrors e;
    for (std::uint64_t seed = first; seed <= last; ++seed) {
      for (PointSet set : {PointSet::kUniform, PointSet::kStress}) {
        const int lobes = set == PointSet::kUniform ? testLobes : testLobes / 4;
        addClosedFormErrors(fit.k,
                            makeErrorPointPair(set, lobes, 16, seed, kDefaultLobeCells).three, e);
      }
    }
    finishClosedFormErrors(e);
    return e;
  };
  print("selection (seeds 50-52)", gtsoSets(50, 52));
  print("test (seeds 10-12)", gtsoSets(10, 12));
  if (dump) {
    const double lobes[][2] = {{1.0, 0.5},  {0.97, 0.2}, {0.5, 0.3},
                               {0.5, 0.15}, {0.05, 0.3}, {0.01, 0.15}};
    for (const auto& l : lobes) {
      std::vector<double> cones;
      for (int i = 1; i < 40; ++i) cones.push_back(std::cos(i / 40.0 * 1.5707963267948966));
      const auto s = specularOcclusion(l[1], l[0], {Vec3{0, 0, 1}}, cones, kDefaultLobeCells);
      std::printf("lobe mu %.2f rp %.2f\n", l[0], l[1]);
      for (std::size_t i = 0; i < cones.size(); ++i) {
        const double A = 1 - cones[i] * cones[i];
        GtsoPoint p{A, std::acos(l[0]), l[1], std::acos(l[0])};
        std::printf("  av %5.1f u %6.2f S %.4f form %.4f err %+.4f\n",
                    std::acos(cones[i]) * 57.29578, 0.5 * std::log(A / (1 - A)), s[i],
                    closedFormAt(fit.k, p), closedFormAt(fit.k, p) - s[i]);
      }
    }
  }
  std::printf("k (C++):");
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) {
    std::printf("%s%.9g,", i % kGtsoS3ClosedFormBasis == 0 ? "\n   " : " ", fit.k[i]);
  }
  std::printf("\nse:");
  for (double v : fit.standard_errors) std::printf(" %.3g", v);
  std::printf("\n");
  return 0;
}
