// `penumbra bench points`: throughput of the point splatter (raster/splat.h) against a memory
// bandwidth bound measured in the same run.
//
// Workload: N points sampled from the surfaces of the built-in scene 'complex' (apps/point_cloud.h:
// in random order, so consecutive points land in unrelated pixels), splatted into M views of
// size x size pixels in one traversal (fully parallel, K = M), DepthKey::ZOverW, no payloads (the
// point index). The views are perspective views from M stratified points (a Hammersley set) on a
// horizontal 2 x 2 square above the scene's bounds (by half their larger horizontal extent), looking
// at the centre of the bounds; each view's field of view is the smallest that holds the corners of
// every instance's bounding box (plus 1%), so every point lands in every view (written_fraction
// reports it). Targets are
// cleared before each run, outside the timing; one untimed warm-up run; medians over --runs runs.
//
// Bandwidth model (a lower bound on memory traffic, hence an upper bound on throughput), in bytes
// per point-view, K = M views per traversal, w = written / (N M):
//   bytes = 12 / K                 the point (3 floats), streamed once per traversal
//         + w * 8                  when the targets (M size^2 8 bytes) fit the last-level cache: the
//                                  key read (its write hits the same cached line);
//         + w * 64                 when they do not: the key's 64-byte cache line, fetched for the
//                                  atomic min (points in random order: no reuse between points).
//                                  Write-backs of the modified lines are not counted.
// The streaming bandwidth B is a parallel memcpy of 256 MiB at the same thread count (read + write
// counted, 2 x 256 MiB per copy; median of 3), and bound = B / bytes point-views per second. While
// the targets fit the cache the keys are served by the cache, which is faster than B: the bound
// then says how far the run is from "every byte touched at streaming bandwidth", and the fraction
// may exceed 1.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <memory>

#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/point_cloud.h"
#include "engine/report.h"
#include "engine/builtin_scenes.h"
#include "raster/splat.h"

namespace penumbra::apps {

namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kCopyBytes = size_t{256} << 20;         // the bandwidth probe's buffer
constexpr uint64_t kMaxTargetBytes = uint64_t{4} << 30;  // M size^2 8 bytes of keys at most
constexpr double kPointBytes = 12.0;                     // glm::vec3
constexpr double kKeyBytes = 8.0, kLineBytes = 64.0;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Streaming bandwidth in bytes per second: a parallel memcpy of kCopyBytes in 1 MiB blocks, read +
// write counted, median of 3 after the buffers were first touched (in parallel, as the copy is).
double copyBandwidth(tbb::task_arena& arena) {
  constexpr size_t kBlock = size_t{1} << 20, kBlocks = kCopyBytes / kBlock;
  const auto src = std::make_unique_for_overwrite<unsigned char[]>(kCopyBytes);
  const auto dst = std::make_unique_for_overwrite<unsigned char[]>(kCopyBytes);
  std::vector<double> seconds;
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, kBlocks, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t b = r.begin(); b != r.end(); ++b) {
        std::memset(src.get() + b * kBlock, static_cast<int>(b & 0xff), kBlock);
        std::memset(dst.get() + b * kBlock, 0, kBlock);
      }
    });
    for (int run = 0; run < 3; ++run) {
      const auto t0 = Clock::now();
      tbb::parallel_for(tbb::blocked_range<size_t>(0, kBlocks, 1), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t b = r.begin(); b != r.end(); ++b)
          std::memcpy(dst.get() + b * kBlock, src.get() + b * kBlock, kBlock);
      });
      seconds.push_back(msSince(t0) * 1e-3);
    }
  });
  return 2.0 * static_cast<double>(kCopyBytes) / median(seconds);
}

// Bytes of the largest data or unified cache of CPU 0 as Linux lists it (sysfs, what lscpu reads;
// glibc's sysconf reports the sum over all cache slices on some virtual machines); 0 when unknown
// (the model then takes the targets as beyond the cache).
uint64_t lastLevelCacheBytes() {
  uint64_t best = 0;
  for (int index = 0; index < 8; ++index) {
    const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/";
    std::ifstream type(dir + "type"), size(dir + "size");
    std::string t, s;
    if (!(type >> t) || !(size >> s) || t == "Instruction") continue;
    uint64_t v = 0;
    const auto [end, err] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (err != std::errc()) continue;
    const std::string_view unit(end, static_cast<size_t>(s.data() + s.size() - end));
    v <<= unit == "K" ? 10 : unit == "M" ? 20 : unit == "G" ? 30 : 0;
    best = std::max(best, v);
  }
  return best;
}

// k-th point of the 2D Hammersley set of n points: ((k + 0.5) / n, radical inverse of k in base 2).
glm::vec2 hammersley(uint32_t k, uint32_t n) {
  uint32_t bits = k;
  bits = (bits << 16) | (bits >> 16);
  bits = ((bits & 0x55555555u) << 1) | ((bits & 0xAAAAAAAAu) >> 1);
  bits = ((bits & 0x33333333u) << 2) | ((bits & 0xCCCCCCCCu) >> 2);
  bits = ((bits & 0x0F0F0F0Fu) << 4) | ((bits & 0xF0F0F0F0u) >> 4);
  bits = ((bits & 0x00FF00FFu) << 8) | ((bits & 0xFF00FF00u) >> 8);
  return {(static_cast<float>(k) + 0.5f) / static_cast<float>(n), static_cast<float>(bits) * 0x1p-32f};
}

// The M view matrices described in the header.
std::vector<glm::mat4> benchViews(const engine::Scene& scene, int m) {
  std::vector<glm::vec3> corners;
  for (const engine::Instance& inst : scene.instances) {
    const engine::Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 p((c & 1) ? mesh.boundsMax.x : mesh.boundsMin.x,
                        (c & 2) ? mesh.boundsMax.y : mesh.boundsMin.y,
                        (c & 4) ? mesh.boundsMax.z : mesh.boundsMin.z);
      corners.emplace_back(inst.transform * glm::vec4(p, 1.0f));
    }
  }
  glm::vec3 lo, hi;
  scene.worldBounds(lo, hi);
  const glm::vec3 centre = 0.5f * (lo + hi);
  // Above the top of the bounds by half their larger horizontal extent: every instance is in front.
  const glm::vec3 square(centre.x, hi.y + 0.5f * std::max(hi.x - lo.x, hi.z - lo.z), centre.z);
  std::vector<glm::mat4> views;
  for (int k = 0; k < m; ++k) {
    const glm::vec2 st = hammersley(static_cast<uint32_t>(k), static_cast<uint32_t>(m));
    const glm::vec3 eye = square + glm::vec3(2.0f * st.x - 1.0f, 0.0f, 2.0f * st.y - 1.0f);
    // Up is -z: the view looks down (the eye is above the scene), never along -z.
    const glm::mat4 view = glm::lookAtRH(eye, centre, glm::vec3(0.0f, 0.0f, -1.0f));
    float spread = 0.0f, nearest = 1e30f, farthest = 0.0f;  // tan(fov / 2) and depths holding every corner
    for (const glm::vec3& c : corners) {
      const glm::vec3 v(view * glm::vec4(c, 1.0f));
      const float depth = std::max(-v.z, 1e-3f);
      spread = std::max({spread, std::abs(v.x) / depth, std::abs(v.y) / depth});
      nearest = std::min(nearest, depth);
      farthest = std::max(farthest, depth);
    }
    const float fovy = 2.0f * std::atan(std::min(spread * 1.01f, 11.4f));  // at most 170 degrees
    views.push_back(
        glm::perspectiveRH_ZO(fovy, 1.0f, std::max(0.5f * nearest, 1e-4f * farthest), 1.01f * farthest) *
        view);
  }
  return views;
}

struct Row {
  int64_t points = 0;
  int views = 0, size = 0, threads = 0, runs = 0;
  double msMedian = 0, msMin = 0, writtenFraction = 0, bandwidth = 0;  // bandwidth in bytes/s
  bool inCache = false;
  double mpointsPerS() const { return static_cast<double>(points) / (std::max(msMedian, 1e-6) * 1e3); }
  double mpointviewsPerS() const { return mpointsPerS() * views; }
  double bytesPerPointview() const {
    return kPointBytes / views + writtenFraction * (inCache ? kKeyBytes : kLineBytes);
  }
  double boundMpointviewsPerS() const { return bandwidth / bytesPerPointview() * 1e-6; }
  double targetsMiB() const { return static_cast<double>(views) * size * size * 8.0 / (1 << 20); }

  std::string json() const {
    engine::report::Json j;
    j["points"] = points;
    j["views"] = views;
    j["size"] = size;
    j["threads"] = threads;
    j["runs"] = runs;
    j["ms_median"] = engine::report::jsonNumber(msMedian);
    j["ms_min"] = engine::report::jsonNumber(msMin);
    j["mpoints_per_s"] = engine::report::jsonNumber(mpointsPerS());
    j["mpointviews_per_s"] = engine::report::jsonNumber(mpointviewsPerS());
    j["written_fraction"] = engine::report::jsonNumber(writtenFraction);
    j["targets_mib"] = engine::report::jsonNumber(targetsMiB());
    j["targets_in_cache"] = inCache;
    j["bytes_per_pointview"] = engine::report::jsonNumber(bytesPerPointview());
    j["bandwidth_gb_s"] = engine::report::jsonNumber(bandwidth * 1e-9);
    j["bound_mpointviews_per_s"] = engine::report::jsonNumber(boundMpointviewsPerS());
    j["fraction_of_bound"] = engine::report::jsonNumber(mpointviewsPerS() / boundMpointviewsPerS());
    return engine::report::jsonLine(j);
  }
  std::string line() const {
    char buf[512];
    std::snprintf(
        buf, sizeof buf,
        "points %lld views=%-4d threads=%-3d median %9.2f ms (min %.2f) %8.1f Mpoint/s %9.1f Mpoint-view/s  "
        "[written %.1f%%, targets %.0f MiB %s, %.2f B/point-view, bound %.0f Mpoint-view/s, %.0f%% of it]",
        static_cast<long long>(points), views, threads, msMedian, msMin, mpointsPerS(), mpointviewsPerS(),
        100.0 * writtenFraction, targetsMiB(), inCache ? "in cache" : "beyond cache", bytesPerPointview(),
        boundMpointviewsPerS(), 100.0 * mpointviewsPerS() / boundMpointviewsPerS());
    return buf;
  }
};

}  // namespace

int runBenchPoints(const BenchPointsArgs& a) {
  // Validate everything before any work.
  if (a.points < 1 || a.points > kMaxCloudPoints)
    fail("option --points",
         "must be in [1, " + std::to_string(kMaxCloudPoints) + "], got " + std::to_string(a.points));
  const std::vector<int> viewCounts = a.views.empty() ? std::vector<int>{1, 8, 32, 128} : a.views;
  for (int m : viewCounts)
    if (m < 1 || m > 1024)
      fail("option --views", "view counts must be in [1, 1024], got " + std::to_string(m));
  if (a.size < 1 || a.size > 4096)
    fail("option --size", "must be in [1, 4096], got " + std::to_string(a.size));
  const std::vector<int> threads = a.threads.empty() ? std::vector<int>{1, 2} : a.threads;
  for (int t : threads)
    if (t < 1 || t > 1024)
      fail("option --threads", "thread counts must be in [1, 1024], got " + std::to_string(t));
  if (a.runs < 1 || a.runs > 1000)
    fail("option --runs", "must be in [1, 1000], got " + std::to_string(a.runs));
  const int maxViews = *std::max_element(viewCounts.begin(), viewCounts.end());
  const uint64_t targetBytes = static_cast<uint64_t>(maxViews) * static_cast<uint64_t>(a.size) *
                               static_cast<uint64_t>(a.size) * sizeof(uint64_t);
  if (targetBytes > kMaxTargetBytes)
    fail("option --views/--size", std::to_string(maxViews) + " views of " + std::to_string(a.size) +
                                      "^2 keys take " + std::to_string(targetBytes >> 20) +
                                      " MiB, more than the limit of " +
                                      std::to_string(kMaxTargetBytes >> 20) + " MiB");
  const int maxThreads = *std::max_element(threads.begin(), threads.end());
  const ThreadLimit threadLimit(maxThreads);

  engine::Result<engine::Scene> scene = engine::makeBuiltinScene("complex");
  if (!scene) fail(scene.error());
  tbb::task_arena all(maxThreads);
  engine::Result<SurfacePoints> sampled = all.execute([&] { return sampleSurface(*scene, a.points, false); });
  if (!sampled) fail(sampled.error());
  const std::vector<glm::vec3> points = std::move(sampled->positions);
  const std::vector<glm::mat4> matrices = benchViews(*scene, maxViews);
  std::vector<raster::Image<uint64_t>> targets(static_cast<size_t>(maxViews));
  std::vector<raster::SplatView> views;
  for (int k = 0; k < maxViews; ++k) {
    targets[static_cast<size_t>(k)].resize(a.size, a.size);
    views.push_back({matrices[static_cast<size_t>(k)], &targets[static_cast<size_t>(k)]});
  }
  const uint64_t cacheBytes = lastLevelCacheBytes();

  Progress progress("bench points", 2.0);
  const int total = static_cast<int>(threads.size() * viewCounts.size());
  int index = 0;
  for (int t : threads) {
    tbb::task_arena arena(t);
    const double bandwidth = copyBandwidth(arena);
    if (!a.json)
      std::printf(
          "threads=%d: streaming bandwidth %.2f GB/s (parallel copy of 256 MiB, read + write, median of 3); "
          "last-level cache %llu MiB\n",
          t, bandwidth * 1e-9, static_cast<unsigned long long>(cacheBytes >> 20));
    for (int m : viewCounts) {
      progress.step(++index, total, "views=" + std::to_string(m) + " threads=" + std::to_string(t));
      const std::span<const raster::SplatView> pass(views.data(), static_cast<size_t>(m));
      std::vector<double> ms;
      raster::SplatStats stats;
      arena.execute([&] {
        for (int run = -1; run < a.runs; ++run) {  // run -1: warm-up
          for (const raster::SplatView& v : pass) raster::clearKeys(*v.target);
          const auto t0 = Clock::now();
          stats = raster::splatPoints(points, {}, pass, raster::DepthKey::ZOverW, m);
          if (run >= 0) ms.push_back(msSince(t0));
        }
      });
      Row row;
      row.points = a.points;
      row.views = m;
      row.size = a.size;
      row.threads = t;
      row.runs = a.runs;
      row.msMedian = median(ms);
      row.msMin = *std::min_element(ms.begin(), ms.end());
      row.writtenFraction = static_cast<double>(stats.written) / (static_cast<double>(stats.points) * m);
      row.bandwidth = bandwidth;
      row.inCache = cacheBytes > 0 && static_cast<uint64_t>(m) * static_cast<uint64_t>(a.size) *
                                              static_cast<uint64_t>(a.size) * sizeof(uint64_t) <=
                                          cacheBytes;
      std::printf("%s\n", a.json ? row.json().c_str() : row.line().c_str());
      std::fflush(stdout);
    }
  }
  progress.done();
  return 0;
}

}  // namespace penumbra::apps
