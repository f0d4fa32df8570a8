#include "apps/workloads.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <numbers>
#include <span>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/report.h"

namespace penumbra::apps {

namespace {
constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;
}

ViewFit fitView(const engine::Mesh& mesh) {
  ViewFit f;
  if (mesh.positions.empty()) return f;
  glm::vec3 lo = mesh.positions[0], hi = lo;
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  f.centre = (lo + hi) * 0.5f;
  float r2 = 0.0f;
  for (const glm::vec3& p : mesh.positions) r2 = std::max(r2, glm::dot(p - f.centre, p - f.centre));
  f.radius = std::sqrt(r2);
  return f;
}

glm::mat4 w1LightMatrix(const ViewFit& fit) {
  const float el = 60.0f * kDeg, az = 45.0f * kDeg;
  const glm::vec3 l(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
  const float r = fit.radius;
  const glm::vec3 eye = fit.centre + l * (2.0f * r);
  return glm::orthoRH_ZO(-r, r, -r, r, 0.99f * r, 3.01f * r) * glm::lookAtRH(eye, fit.centre, glm::vec3(0, 1, 0));
}

glm::mat4 w2CameraMatrix(const ViewFit& fit, glm::vec3* lightDir) {
  const float fovy = 40.0f * kDeg, el = 25.0f * kDeg, az = 30.0f * kDeg;
  const glm::vec3 d(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  const float r = fit.radius, dist = r / std::sin(fovy * 0.5f);
  const glm::vec3 eye = fit.centre + d * dist;
  const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0, 1, 0), d));
  if (lightDir) *lightDir = glm::normalize(d + glm::vec3(0, 0.6f, 0) - 0.4f * right);
  return glm::perspectiveRH_ZO(fovy, 1920.0f / 1080.0f, std::max(dist - 1.01f * r, 0.01f * dist), dist + 1.01f * r) *
         glm::lookAtRH(eye, fit.centre, glm::vec3(0, 1, 0));
}

std::string WorkloadResult::json() const {
  engine::report::Json j;
  j["name"] = name;
  j["tris"] = tris;
  j["workload"] = workload;
  j["res"] = res;
  j["threads"] = threads;
  j["frames"] = frames;
  j["median_ms"] = engine::report::jsonNumber(medianMs);
  j["min_ms"] = engine::report::jsonNumber(minMs);
  j["max_ms"] = engine::report::jsonNumber(maxMs);
  j["mtris_per_s"] = engine::report::jsonNumber(mtrisPerS);
  j["ms_vertex"] = engine::report::jsonNumber(stats.msVertex);
  j["ms_setup_bin"] = engine::report::jsonNumber(stats.msSetupBin);
  j["ms_raster"] = engine::report::jsonNumber(stats.msRaster);
  j["samples"] = samples;
  if (edgeRmse >= 0) {
    j["edge_rmse"] = engine::report::jsonNumber(edgeRmse);
    j["edge_pixels"] = edgePixels;
  }
  return engine::report::jsonLine(j);
}

std::string WorkloadResult::line() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%-10s %-3s %-10s threads=%-3d median %8.2f ms (min %.2f, max %.2f) %7.1f Mtri/s  "
                "[vertex %.2f, setup+bin %.2f, raster %.2f ms]",
                name.c_str(), workload.c_str(), res.c_str(), threads, medianMs, minMs, maxMs, mtrisPerS, stats.msVertex,
                stats.msSetupBin, stats.msRaster);
  std::string s = buf;
  if (edgeRmse >= 0) {
    std::snprintf(buf, sizeof buf, "  edge RMSE %.4f over %zu silhouette pixels (240x135 against 16x16 supersampling)",
                  edgeRmse, edgePixels);
    s += buf;
  }
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;

// W2's shading: a headlight-free Lambert term of the interpolated normal towards `light`.
glm::vec3 shadeW2(const glm::vec3& n, const glm::vec3& light) {
  const float ndl = std::max(glm::dot(n, light) / std::sqrt(glm::dot(n, n)), 0.0f);
  const float k = 0.15f + 0.85f * ndl;
  return {0.85f * k, 0.75f * k, 0.6f * k};
}
uint8_t quantize(float x) { return static_cast<uint8_t>(std::min(x, 1.0f) * 255.0f + 0.5f); }
constexpr glm::vec3 kW2Clear{0.1f, 0.1f, 0.12f};

// 3 warm-up frames, then at least minFrames frames and minSeconds; the summary of their times.
template <class F>
WorkloadResult timeFrames(F&& frame, int minFrames, double minSeconds) {
  for (int i = 0; i < 3; ++i) frame();
  std::vector<double> times;
  const auto start = Clock::now();
  while (static_cast<int>(times.size()) < minFrames ||
         std::chrono::duration<double>(Clock::now() - start).count() < minSeconds) {
    const auto t0 = Clock::now();
    frame();
    times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (times.size() > 10000) break;
  }
  std::sort(times.begin(), times.end());
  WorkloadResult r;
  r.frames = static_cast<int>(times.size());
  const size_t n = times.size();
  r.medianMs = (n % 2) ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
  r.minMs = times.front();
  r.maxMs = times.back();
  return r;
}

// One multisampled W2 frame into `linear` (w x h RGB) and `covered` (samples that hit, per pixel):
// every sample's triangle and barycentrics, then per pixel one shaded texel per triangle seen (at
// its sample nearest the centre), blended by sample counts -- as the engine's msaa pass resolves.
struct MsaaW2 {
  raster::Rasterizer& rast;
  const engine::Mesh& mesh;
  glm::mat4 mvp;
  glm::vec3 light;
  int width, height, samples;
  std::vector<raster::DepthTarget> depth;
  std::vector<uint32_t> prim;
  std::vector<glm::vec2> bary;  // b1, b2 (b0 = 1 - b1 - b2)

  raster::PassStats draw() {
    if (depth.size() != static_cast<size_t>(samples))  // allocated once, cleared every frame
      depth.assign(static_cast<size_t>(samples), raster::DepthTarget(width, height, 1.0f));
    for (raster::DepthTarget& d : depth) rast.clear(d, 1.0f);
    prim.resize(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(samples));
    bary.resize(prim.size());
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(mesh.positions.size());
    desc.indices = mesh.indices;
    return rast.drawSamples(
        desc, depth, [&](uint32_t i, float*) { return mvp * glm::vec4(mesh.positions[i], 1.0f); },
        [&](const raster::Fragment& f) {
          const size_t k = (static_cast<size_t>(f.y) * static_cast<size_t>(width) + static_cast<size_t>(f.x)) *
                               static_cast<size_t>(samples) + static_cast<size_t>(f.sample);
          prim[k] = f.primitive;
          bary[k] = {f.b1, f.b2};
        });
  }

  // Pixel (x, y): linear color and the share of its samples covered.
  glm::vec4 resolve(int x, int y, const int* order) const {
    const size_t base = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                        static_cast<size_t>(samples);
    uint32_t seen[raster::kMaxSamples];
    int count[raster::kMaxSamples], rep[raster::kMaxSamples], groups = 0, covered = 0;
    for (int k = 0; k < samples; ++k) {
      const int s = order[k];
      if (!(depth[static_cast<size_t>(s)].at(x, y) < 1.0f)) continue;  // cleared to 1: not drawn
      ++covered;
      const uint32_t p = prim[base + static_cast<size_t>(s)];
      int g = 0;
      while (g < groups && seen[g] != p) ++g;
      if (g == groups) seen[groups] = p, count[groups] = 0, rep[groups++] = s;
      ++count[g];
    }
    glm::vec3 c = kW2Clear * static_cast<float>(samples - covered);
    for (int g = 0; g < groups; ++g) {
      const glm::vec2 b = bary[base + static_cast<size_t>(rep[g])];
      glm::vec3 n(0.0f);
      const float w[3] = {1.0f - b.x - b.y, b.x, b.y};
      for (int v = 0; v < 3; ++v) n += w[v] * mesh.normals[mesh.indices[static_cast<size_t>(seen[g]) * 3 + static_cast<size_t>(v)]];
      c += shadeW2(n, light) * static_cast<float>(count[g]);
    }
    return {c / static_cast<float>(samples), static_cast<float>(covered) / static_cast<float>(samples)};
  }
};

// W2's image at width x height with `samples` samples (1: the ordinary pass at pixel centres, as
// runWorkload shades it), linear RGB and coverage per pixel.
std::vector<glm::vec4> w2Linear(const engine::Mesh& mesh, int width, int height, int samples, int threads) {
  const ViewFit fit = fitView(mesh);
  glm::vec3 light(0.0f);
  const glm::mat4 mvp = w2CameraMatrix(fit, &light);
  raster::Rasterizer rast({.threads = threads});
  MsaaW2 m{rast, mesh, mvp, light, width, height, samples, {}, {}, {}};
  m.draw();
  const std::array<int, raster::kMaxSamples> order = raster::samplesNearestFirst(samples);
  std::vector<glm::vec4> out(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      out[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = m.resolve(x, y, order.data());
  return out;
}

}  // namespace

WorkloadResult runW2Multisample(const std::string& meshName, const engine::Mesh& mesh, int threads, int samples,
                                int minFrames, double minSeconds) {
  const ViewFit fit = fitView(mesh);
  glm::vec3 light(0.0f);
  const glm::mat4 mvp = w2CameraMatrix(fit, &light);
  raster::Rasterizer rast({.threads = threads});
  MsaaW2 m{rast, mesh, mvp, light, 1920, 1080, samples, {}, {}, {}};
  raster::ImageRgba8 color(1920, 1080);
  const std::array<int, raster::kMaxSamples> order = raster::samplesNearestFirst(samples);
  raster::PassStats last;
  WorkloadResult r = timeFrames(
      [&] {
        last = m.draw();
        rast.run([&] {
          tbb::parallel_for(tbb::blocked_range<int>(0, 1080, 8), [&](const tbb::blocked_range<int>& rows) {
            for (int y = rows.begin(); y != rows.end(); ++y)
              for (int x = 0; x < 1920; ++x) {
                const glm::vec4 c = m.resolve(x, y, order.data());
                color.at(x, y) = raster::Rgba8{quantize(c.x), quantize(c.y), quantize(c.z), 255};
              }
          });
        });
      },
      minFrames, minSeconds);
  r.name = meshName;
  r.workload = "W2x" + std::to_string(samples);
  r.samples = samples;
  r.res = "1920x1080";
  r.tris = mesh.indices.size() / 3;
  r.threads = rast.threads();
  r.mtrisPerS = static_cast<double>(r.tris) / (r.medianMs * 1e-3) / 1e6;
  r.stats = last;
  return r;
}

EdgeError w2EdgeError(const engine::Mesh& mesh, int samples, int width, int height, int threads) {
  constexpr int kF = 16;
  const std::vector<glm::vec4> img = w2Linear(mesh, width, height, samples, threads);
  const std::vector<glm::vec4> ref = w2Linear(mesh, width * kF, height * kF, 1, threads);
  EdgeError e;
  double sum = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      glm::dvec3 mean(0.0);
      int covered = 0;
      for (int j = 0; j < kF; ++j)
        for (int i = 0; i < kF; ++i) {
          const glm::vec4 c = ref[static_cast<size_t>(y * kF + j) * static_cast<size_t>(width * kF) +
                                  static_cast<size_t>(x * kF + i)];
          mean += glm::dvec3(c);
          covered += c.w > 0.0f ? 1 : 0;
        }
      if (covered == 0 || covered == kF * kF) continue;  // not on a silhouette
      mean /= double{kF * kF};
      const glm::dvec3 d = glm::dvec3(img[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]) - mean;
      sum += glm::dot(d, d) / 3.0;
      ++e.edgePixels;
    }
  e.rmse = e.edgePixels ? std::sqrt(sum / static_cast<double>(e.edgePixels)) : 0.0;
  return e;
}

WorkloadResult runWorkload(const std::string& workload, const std::string& meshName, const engine::Mesh& mesh,
                           int threads, int minFrames, double minSeconds, raster::ImageRgba8* colorOut,
                           raster::DepthTarget* depthOut, raster::RasterConfig config) {
  const ViewFit fit = fitView(mesh);
  const bool w1 = workload == "W1";
  const int width = w1 ? 2048 : 1920, height = w1 ? 2048 : 1080;
  glm::vec3 light(0.0f);
  const glm::mat4 mvp = w1 ? w1LightMatrix(fit) : w2CameraMatrix(fit, &light);

  config.threads = threads;
  raster::Rasterizer rast(config);
  raster::DepthTarget depth(width, height, 1.0f);
  raster::ImageRgba8 color;
  if (!w1) color.resize(width, height);
  const raster::Rgba8 clearColor{26, 26, 31, 255};  // (0.1, 0.1, 0.12)
  raster::DrawDesc desc;
  desc.vertexCount = static_cast<uint32_t>(mesh.positions.size());
  desc.indices = mesh.indices;
  desc.varyings = w1 ? 0 : 3;
  const glm::vec3* pos = mesh.positions.data();
  const glm::vec3* nrm = mesh.normals.data();

  raster::PassStats last;
  auto frame = [&] {
    rast.clear(depth, 1.0f);
    if (w1) {
      last = rast.drawDepth(desc, depth, [&](uint32_t i) { return mvp * glm::vec4(pos[i], 1.0f); });
    } else {
      rast.run([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, color.paddedRows(), 64), [&](const tbb::blocked_range<int>& r) {
          std::fill(color.row(r.begin()), color.row(r.end() - 1) + color.stride(), clearColor);
        });
      });
      last = rast.draw(
          desc, depth,
          [&](uint32_t i, float* v) {
            v[0] = nrm[i].x;
            v[1] = nrm[i].y;
            v[2] = nrm[i].z;
            return mvp * glm::vec4(pos[i], 1.0f);
          },
          [&](const raster::Fragment& f) {
            const glm::vec3 c = shadeW2(glm::vec3(f.varyings[0], f.varyings[1], f.varyings[2]), light);
            color.at(f.x, f.y) = raster::Rgba8{quantize(c.x), quantize(c.y), quantize(c.z), 255};
          });
    }
  };
  WorkloadResult r = timeFrames(frame, minFrames, minSeconds);
  r.name = meshName;
  r.workload = workload;
  r.res = std::to_string(width) + "x" + std::to_string(height);
  r.tris = mesh.indices.size() / 3;
  r.threads = rast.threads();
  r.mtrisPerS = static_cast<double>(r.tris) / (r.medianMs * 1e-3) / 1e6;
  r.stats = last;
  if (colorOut && !w1) *colorOut = color;
  if (depthOut) *depthOut = depth;
  return r;
}

}  // namespace penumbra::apps
