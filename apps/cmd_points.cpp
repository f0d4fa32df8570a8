// `penumbra render --points`: draws a point cloud with the point splatter (raster/splat.h) instead
// of rasterizing triangles, for a visual check of the splatter. The points are sampled from the
// scene's surfaces (apps/point_cloud.h), colored by their material and a headlight term, or read
// from an .xyz file with their own colors. One view: the camera render would use (scene, options,
// or fitted to the bounds), except that for a points file with no scene named the camera is fitted
// to the points' bounds. Each point lands in one pixel (no footprint), nearest wins (z / w keys);
// pixels no point reached take the scene's background. PNG only.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <glm/geometric.hpp>
#include <optional>

#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/point_cloud.h"
#include "engine/image_io.h"
#include "engine/memory.h"
#include "engine/renderer.h"
#include "engine/texture.h"
#include "raster/splat.h"

namespace penumbra::apps {

namespace {

constexpr int64_t kDefaultPointCount = 2000000;

// A scene that holds only a bounding box: chooseCamera and viewProjection then fit the view to
// the box exactly as they fit a scene. The box is padded so that one point still has a depth range.
engine::Scene boundsScene(const std::vector<glm::vec3>& points) {
  glm::vec3 lo = points[0], hi = points[0];
  for (const glm::vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float scale = std::max({1.0f, glm::length(lo), glm::length(hi)});
  const glm::vec3 pad(std::max(1e-3f * scale, 1e-3f * glm::length(hi - lo)));
  engine::Mesh box;
  box.positions = {lo - pad, hi + pad};
  box.boundsMin = lo - pad;
  box.boundsMax = hi + pad;
  engine::Scene s;
  s.name = "points";
  s.meshes.push_back(std::move(box));
  s.instances.push_back({"points", 0, glm::mat4(1.0f)});
  return s;
}

}  // namespace

void checkPointOptions(const RenderArgs& a) {
  if (!a.points) {
    if (a.pointCount) fail("option --point-count", "needs --points");
    if (!a.pointsFile.empty()) fail("option --points-file", "needs --points");
    return;
  }
  if (a.pointCount && !a.pointsFile.empty())
    fail("option --point-count", "give --point-count or --points-file, not both (the file holds the points)");
  if (a.pointCount && (*a.pointCount < 1 || *a.pointCount > kMaxCloudPoints))
    fail("option --point-count",
         "must be in [1, " + std::to_string(kMaxCloudPoints) + "], got " + std::to_string(*a.pointCount));
  if (!a.exr.empty())
    fail("option --exr", "--points writes a PNG only (the splatter resolves to 8-bit color)");
  if (!a.params.empty()) fail("option --param", "--points draws no shadows");
  if (!a.cache.empty()) fail("option --cache", "--points draws no shadows");
}

int renderPoints(const RenderArgs& a, const engine::Scene& scene, std::optional<glm::vec3> eye,
                 std::optional<glm::vec3> target, const std::string& path, uint64_t memoryLimit,
                 const std::string& limitSource) {
  {
    // Per point: position, color, and while sampling normal and material; per pixel a 64-bit key
    // and the color. A points file's size bounds its points (a line per point, at least 6 bytes).
    std::error_code ec;
    const uint64_t points = a.pointsFile.empty() ? static_cast<uint64_t>(a.pointCount.value_or(kDefaultPointCount))
                                                 : std::filesystem::file_size(a.pointsFile, ec) / 6 + 1;
    engine::MemoryEstimate e;
    e.parts = {{"points", points * (12 + 4 + 12 + 4)},
               {"targets", static_cast<uint64_t>(a.width) * static_cast<uint64_t>(a.height) * (8 + 4)}};
    for (const auto& [what, bytes] : e.parts) e.bytes += bytes;
    require(engine::checkMemory(e, memoryLimit, "render --points", limitSource));
  }
  raster::RasterConfig config;
  config.threads = a.threads;
  raster::Rasterizer rast(config);
  const auto t0 = std::chrono::steady_clock::now();
  // The points and, for a file with no scene named, the bounds the camera is fitted to.
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> colors;
  std::optional<engine::Scene> pointBounds;
  SurfacePoints surface;
  if (!a.pointsFile.empty()) {
    engine::Result<XyzCloud> cloud = readXyz(a.pointsFile);
    if (!cloud) fail(cloud.error());
    positions = std::move(cloud->positions);
    colors = std::move(cloud->colors);
    if (a.scene.empty() && a.builtin.empty()) pointBounds = boundsScene(positions);
  } else {
    const int64_t count = a.pointCount.value_or(kDefaultPointCount);
    engine::Result<SurfacePoints> s = rast.run([&] { return sampleSurface(scene, count, true); });
    if (!s) fail(s.error());
    surface = std::move(*s);
  }
  const engine::Scene& viewScene = pointBounds ? *pointBounds : scene;

  engine::RenderOptions options;
  options.width = a.width;
  options.height = a.height;
  std::string cameraSource;
  engine::Camera cam = engine::chooseCamera(viewScene, options, &cameraSource);
  if (eye) cam.eye = *eye;
  if (target) cam.target = *target;
  if (a.fov) cam.fovYDegrees = static_cast<float>(*a.fov);
  if (eye || target || a.fov) cameraSource = "options";
  if (cam.eye == cam.target) fail("option --eye", "camera eye and target coincide");
  const glm::mat4 viewProj = engine::viewProjection(cam, viewScene, static_cast<double>(a.width) / a.height);
  if (a.pointsFile.empty()) {
    colors = rast.run([&] { return headlightColors(scene, surface, cam.eye); });
    positions = std::move(surface.positions);
    surface = {};
  }
  const double msPoints =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  raster::Image<uint64_t> keys(a.width, a.height);
  raster::ImageRgba8 color;
  const raster::SplatView view{viewProj, &keys};
  const glm::vec3 bg = scene.background;
  const raster::Rgba8 background{engine::linearToSrgb(bg.x), engine::linearToSrgb(bg.y),
                                 engine::linearToSrgb(bg.z), 255};
  const auto t1 = std::chrono::steady_clock::now();
  const raster::SplatStats stats = rast.run([&] {
    raster::clearKeys(keys);
    const raster::SplatStats st =
        raster::splatPoints(positions, colors, {&view, 1}, raster::DepthKey::ZOverW);
    raster::resolveColor(keys, color, background);
    return st;
  });
  const double msDraw =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();

  if (engine::Status st = engine::writeImage(path, color); !st) fail(st.error());
  if (a.stats) {
    const std::string source =
        a.pointsFile.empty() ? "sampled from scene '" + scene.name + "'" : "read from " + a.pointsFile;
    std::printf("points: %zu %s, %d threads, camera %s\n", positions.size(), source.c_str(), rast.threads(),
                cameraSource.c_str());
    std::printf(
        "splat: written %llu, culled %llu, non-finite %llu; %.2f ms (clear+splat+resolve %.2f ms, points "
        "%.2f ms)\n",
        static_cast<unsigned long long>(stats.written), static_cast<unsigned long long>(stats.culled),
        static_cast<unsigned long long>(stats.nonFinite), stats.ms, msDraw, msPoints);
  }
  std::printf("wrote %s (%dx%d, %zu points)\n", path.c_str(), a.width, a.height, positions.size());
  return 0;
}

}  // namespace penumbra::apps
