#include <cstdio>

#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/stress_raster.h"
#include "apps/stress_shadows.h"
#include "apps/stress_stochastic.h"

namespace penumbra::apps {

int runStress(const StressArgs& a) {
  require(engine::kThreadsOption, a.threads);
  const ThreadLimit threadLimit(a.threads);
  raster::Rasterizer rast({.threads = a.threads});
  Progress progress("stress " + a.suite);
  if (a.suite == "stochastic") {
    progress.step(1, 1, "stochastic cases");
    const std::vector<StochasticStressRow> rows = runStochasticStress(rast);
    progress.done();
    int broken = 0;
    if (!a.json)
      std::printf("%-26s %-24s %-9s %9s %11s %9s %7s %8s %8s  %s\n", "case", "parameter", "method", "ms", "tests", "hits",
                  "STE", "mismatch", "badz", "verdict");
    for (const StochasticStressRow& r : rows) {
      if (!r.ok()) ++broken;
      if (a.json)
        std::printf("%s\n", r.json().c_str());
      else
        std::printf("%-26s %-24s %-9s %9.2f %11llu %9llu %7.3f %8zu %8zu  %s\n", r.name.c_str(), r.param.c_str(),
                    r.method.c_str(), r.ms, static_cast<unsigned long long>(r.tests),
                    static_cast<unsigned long long>(r.hits),
                    r.tests ? static_cast<double>(r.hits) / static_cast<double>(r.tests) : 0.0, r.mismatches, r.badDepth,
                    r.ok() ? "ok" : "BROKEN");
    }
    if (!a.json)
      std::printf("%zu cases, %d broken (mismatch: samples differing from testing every sample; badz: depth NaN or "
                  "outside [0, 1])\n",
                  rows.size(), broken);
    return broken == 0 ? 0 : 1;
  }
  if (a.suite == "shadows") {
    progress.step(1, 1, "shadow cases");
    const std::vector<ShadowStressRow> rows = runShadowStress(rast);
    progress.done();
    int broken = 0;
    if (!a.json)
      std::printf("%-8s %-12s %-28s %9s %7s %7s %9s %9s %8s %8s  %s\n", "technique", "case", "parameter", "receivers",
                  "nonfin", "range", "bleed", "darken", "rmse", "bias", "verdict");
    for (const ShadowStressRow& r : rows) {
      if (!r.ok()) ++broken;
      if (a.json)
        std::printf("%s\n", r.json().c_str());
      else
        std::printf("%-8s %-12s %-28s %9zu %7zu %7zu %9.4f %9.4f %8.4f %+8.4f  %s\n", r.technique.c_str(),
                    r.name.c_str(), r.param.c_str(), r.receivers, r.nonFinite, r.outOfRange, r.bleed, r.darkening,
                    r.rmse, r.bias, r.ok() ? "ok" : "BROKEN");
    }
    if (!a.json)
      std::printf("%zu cases, %d broken (bleed: max V in full umbra; darken: 1 - min V in full light; rmse, bias: "
                  "against the exact V of the terminator, above-caster and contact cases, nan elsewhere)\n",
                  rows.size(), broken);
    const std::vector<SatPrecisionRow> sat = runSatPrecision();
    if (!a.json)
      std::printf("\n%-14s %6s %8s %12s %12s %12s  %s\n", "sat table", "size", "queries", "max error", "relative",
                  "error/bound", "verdict");
    for (const SatPrecisionRow& r : sat) {
      if (!r.ok()) ++broken;
      if (a.json)
        std::printf("%s\n", r.json().c_str());
      else
        std::printf("%-14s %6d %8zu %12.3e %12.3e %12.3e  %s\n", r.table.c_str(), r.size, r.queries, r.maxError,
                    r.maxRelative, r.maxBoundRatio, r.ok() ? "ok" : "BROKEN");
    }
    if (!a.json)
      std::printf("summed-area tables on exp(-80 u) at %d^2: error of box means against the exact sums (relative: "
                  "to the exact mean; error/bound: against the table's stated bound, <= 1)\n",
                  sat.empty() ? 0 : sat.front().size);
    return broken == 0 ? 0 : 1;
  }
  progress.step(1, 1, "raster cases");
  const std::vector<StressRow> rows = runRasterStress(rast);
  progress.done();
  int broken = 0;
  if (a.json) {
    for (const StressRow& r : rows) std::printf("%s\n", r.json().c_str());
  } else {
    std::printf("%-24s %-44s %9s %7s %7s %7s %7s %7s  %s\n", "case", "parameter", "pixels", "cracks", "double", "nonfin",
                "order", "clipped", "verdict");
  }
  for (const StressRow& r : rows) {
    if (!r.ok()) ++broken;
    if (!a.json)
      std::printf("%-24s %-44s %9llu %7llu %7llu %7llu %7llu %7llu  %s%s%s\n", r.name.c_str(), r.param.c_str(),
                  static_cast<unsigned long long>(r.pixels), static_cast<unsigned long long>(r.cracks),
                  static_cast<unsigned long long>(r.doubles), static_cast<unsigned long long>(r.nonFinite),
                  static_cast<unsigned long long>(r.depthErrors), static_cast<unsigned long long>(r.clipped),
                  !r.judged ? "reported" : (r.ok() ? "ok" : "BROKEN"), r.note.empty() ? "" : ": ", r.note.c_str());
  }
  if (!a.json) std::printf("%zu cases, %d broken\n", rows.size(), broken);
  return broken == 0 ? 0 : 1;
}

}  // namespace penumbra::apps
