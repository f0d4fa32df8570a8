// penumbra_microbench: Google Benchmark timings of the pipeline's inner loops and of the standard
// workloads (shared/WORKLOADS.md) at several thread counts. Links raster/ and engine_core only, so
// it can be copied to another machine with three shared libraries (TBB, Highway, benchmark).
//
//   penumbra_microbench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "apps/workloads.h"
#include "engine/synth.h"
#include "raster/kernels.h"
#include "raster/pipeline.h"
#include "raster/setup.h"
#include "raster/splat.h"

namespace {

using namespace penumbra;

// Setup of small random screen-space triangles (the front end's per-triangle cost).
void BM_SetupTriangle(benchmark::State& state) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const raster::Viewport vp{2048, 2048};
  const raster::GuardPlanes guard = raster::guardPlanes(vp);
  std::vector<raster::ScreenVert> v;
  for (int i = 0; i < 3 * 4096; ++i) {
    const float cx = u(rng) * 2048.0f, cy = u(rng) * 2048.0f;
    v.push_back(raster::projectVertex((cx / 1024.0f - 1.0f), (1.0f - cy / 1024.0f), 0.5f, 1.0f, vp, guard));
  }
  for (size_t i = 0; i < v.size(); i += 3) {  // small triangles: move vertices 1 and 2 near vertex 0
    v[i + 1].x = v[i].x + 700, v[i + 1].y = v[i].y + 90;
    v[i + 2].x = v[i].x + 200, v[i + 2].y = v[i].y + 650;
  }
  raster::SetupTri t;
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(raster::setupTriangle(v[i], v[i + 1], v[i + 2], raster::CullMode::None, vp, t, nullptr, nullptr));
    benchmark::DoNotOptimize(t);
    i = (i + 3) % v.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SetupTriangle);

// Image kernels on a 2048^2 float image (shadow-map sized): the pre-filtering building blocks.
raster::ImageFloat noiseImage() {
  raster::ImageFloat img(2048, 2048);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) img.at(x, y) = u(rng);
  return img;
}

void BM_GaussianBlur2048(benchmark::State& state) {
  const raster::ImageFloat src = noiseImage();
  raster::ImageFloat dst;
  for (auto _ : state) raster::gaussianBlur(src, dst, static_cast<float>(state.range(0)));
}
BENCHMARK(BM_GaussianBlur2048)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SummedAreaTable2048(benchmark::State& state) {
  const raster::ImageFloat src = noiseImage();
  for (auto _ : state) benchmark::DoNotOptimize(raster::buildSat(src));
}
BENCHMARK(BM_SummedAreaTable2048)->Unit(benchmark::kMillisecond)->UseRealTime();

const engine::Mesh& synth(long n) {
  static engine::Mesh m1 = engine::makeSynthMesh(1000000);
  static engine::Mesh m4;
  if (n == 1000000) return m1;
  if (m4.positions.empty()) m4 = engine::makeSynthMesh(4000000);
  return m4;
}

// Whole frames of W1/W2 (clear + draw + wait); args: triangles, threads.
// Pipeline configuration from the environment, for tuning runs: PENUMBRA_TILE_LOG2,
// PENUMBRA_CHUNK, PENUMBRA_BATCH_CHUNKS.
raster::RasterConfig configFromEnv() {
  raster::RasterConfig c;
  if (const char* v = std::getenv("PENUMBRA_TILE_LOG2")) c.tileLog2 = std::atoi(v);
  if (const char* v = std::getenv("PENUMBRA_CHUNK")) c.chunkTriangles = std::atoi(v);
  if (const char* v = std::getenv("PENUMBRA_BATCH_CHUNKS")) c.batchChunks = std::atoi(v);
  return c;
}

template <bool kW1>
void BM_Workload(benchmark::State& state) {
  const long tris = state.range(0);
  const int threads = static_cast<int>(state.range(1));
  const raster::RasterConfig config = configFromEnv();
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  const engine::Mesh& mesh = synth(tris);
  for (auto _ : state) {
    // One iteration = runWorkload's 3 warm-up frames and 5 timed frames; its median is the time.
    const apps::WorkloadResult r = apps::runWorkload(kW1 ? "W1" : "W2", "synth", mesh, threads, 5, 0.0, nullptr, nullptr, config);
    state.SetIterationTime(r.medianMs * 1e-3);
    state.counters["mtris_per_s"] = r.mtrisPerS;
  }
}
BENCHMARK(BM_Workload<true>)->Name("W1")->ArgsProduct({{1000000, 4000000}, {1, 2, 4, 8, 16}})->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Workload<false>)->Name("W2")->ArgsProduct({{1000000, 4000000}, {1, 2, 4, 8, 16}})->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);

// Point splatting (raster/splat.h), the paper's fully parallel mode (K = M): 1M points of a wavy
// 1000 x 1000 height field over [-1, 1]^2, in scan order as a rasterizer would emit them, into M
// 512 x 512 views from sample points of a 0.5 x 0.5 area light 2 above it, looking down. Targets
// are cleared outside the timed region. args: views, threads (0 = all). Items = point-view pairs.
void BM_SplatPoints(benchmark::State& state) {
  const int views = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  constexpr int kGrid = 1000, kSize = 512;
  std::vector<glm::vec3> points;
  points.reserve(kGrid * kGrid);
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const float x = -1.0f + 2.0f * (static_cast<float>(i) + 0.5f) / kGrid;
      const float y = -1.0f + 2.0f * (static_cast<float>(j) + 0.5f) / kGrid;
      points.emplace_back(x, y, 0.1f * std::sin(7.0f * x) * std::cos(5.0f * y));
    }
  std::vector<raster::Image<uint64_t>> targets(static_cast<size_t>(views));
  std::vector<raster::SplatView> splatViews;
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-0.25f, 0.25f);
  for (int v = 0; v < views; ++v) {
    const glm::vec3 eye(u(rng), u(rng), 2.0f);
    const glm::mat4 vp = glm::perspectiveRH_ZO(glm::radians(70.0f), 1.0f, 0.5f, 4.0f) *
                         glm::lookAtRH(eye, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    targets[static_cast<size_t>(v)].resize(kSize, kSize);
    splatViews.push_back({vp, &targets[static_cast<size_t>(v)]});
  }
  tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic : threads);
  raster::SplatStats st;
  for (auto _ : state) {
    state.PauseTiming();
    arena.execute([&] {
      for (auto& t : targets) raster::clearKeys(t);
    });
    state.ResumeTiming();
    arena.execute([&] { st = raster::splatPoints(points, {}, splatViews, raster::DepthKey::ZOverW, 0); });
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(points.size()) * views);
  state.counters["written_frac"] = static_cast<double>(st.written) / static_cast<double>(st.points * st.views);
}
BENCHMARK(BM_SplatPoints)->ArgsProduct({{1, 8, 32, 128}, {1, 0}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
