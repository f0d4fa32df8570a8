#include "apps/workloads.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <numbers>

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
  return engine::report::jsonLine(j);
}

std::string WorkloadResult::line() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%-10s %-3s %-10s threads=%-3d median %8.2f ms (min %.2f, max %.2f) %7.1f Mtri/s  "
                "[vertex %.2f, setup+bin %.2f, raster %.2f ms]",
                name.c_str(), workload.c_str(), res.c_str(), threads, medianMs, minMs, maxMs, mtrisPerS, stats.msVertex,
                stats.msSetupBin, stats.msRaster);
  return buf;
}

WorkloadResult runWorkload(const std::string& workload, const std::string& meshName, const engine::Mesh& mesh,
                           int threads, int minFrames, double minSeconds, raster::ImageRgba8* colorOut,
                           raster::DepthTarget* depthOut, raster::RasterConfig config) {
  using Clock = std::chrono::steady_clock;
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
            const glm::vec3 n(f.varyings[0], f.varyings[1], f.varyings[2]);
            const float ndl = std::max(glm::dot(n, light) / std::sqrt(glm::dot(n, n)), 0.0f);
            const float k = 0.15f + 0.85f * ndl;
            auto q = [](float x) { return static_cast<uint8_t>(std::min(x, 1.0f) * 255.0f + 0.5f); };
            color.at(f.x, f.y) = raster::Rgba8{q(0.85f * k), q(0.75f * k), q(0.6f * k), 255};
          });
    }
  };
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
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  WorkloadResult r;
  r.name = meshName;
  r.workload = workload;
  r.res = std::to_string(width) + "x" + std::to_string(height);
  r.tris = mesh.indices.size() / 3;
  r.threads = rast.threads();
  r.frames = static_cast<int>(times.size());
  const size_t n = sorted.size();
  r.medianMs = (n % 2) ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  r.minMs = sorted.front();
  r.maxMs = sorted.back();
  r.mtrisPerS = static_cast<double>(r.tris) / (r.medianMs * 1e-3) / 1e6;
  r.stats = last;
  if (colorOut && !w1) *colorOut = color;
  if (depthOut) *depthOut = depth;
  return r;
}

}  // namespace penumbra::apps
