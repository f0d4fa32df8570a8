// Wall-clock timing of stages and the median of repeated measurements: the one helper every pass,
// bench and report uses (times go into stats and reports, never into asserting tests).
//
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace penumbra::raster {

using Clock = std::chrono::steady_clock;

// Milliseconds from a to b, and since t.
inline double msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
inline double msSince(Clock::time_point t) { return msBetween(t, Clock::now()); }

// The median (the mean of the middle two for an even count; 0 for none).
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

}  // namespace penumbra::raster
