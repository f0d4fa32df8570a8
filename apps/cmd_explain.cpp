// `penumbra explain stochastic`: pictures that make the stochastic rasterizer visible (used by
// docs/stochastic.md): the sample pattern of pixels in (x, t) and (u, v), one moving triangle's
// footprint with each bounding method's bounds drawn over it, and heat maps of exact tests per
// pixel for each method on the built-in motion scene.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "apps/cli.h"
#include "apps/commands.h"
#include "engine/builtin_scenes.h"
#include "engine/image_io.h"
#include "engine/renderer.h"
#include "stochastic/bounds.h"
#include "stochastic/rasterizer.h"

namespace penumbra::apps {

namespace {

using raster::Rgba8;

// A small canvas with the few primitives the pictures need (alpha-blended, clipped).
struct Canvas {
  raster::ImageRgba8 img;
  Canvas(int w, int h, Rgba8 bg) : img(w, h, bg) {}
  void blend(int x, int y, Rgba8 c, float a = 1.0f) {
    if (x < 0 || y < 0 || x >= img.width() || y >= img.height()) return;
    Rgba8& p = img.at(x, y);
    auto mix = [&](uint8_t d, uint8_t s) { return static_cast<uint8_t>(std::lround(d + (s - d) * a)); };
    p = {mix(p.r, c.r), mix(p.g, c.g), mix(p.b, c.b), 255};
  }
  void fillRect(double x0, double y0, double x1, double y1, Rgba8 c, float a = 1.0f) {
    for (int y = static_cast<int>(std::floor(y0)); y < static_cast<int>(std::ceil(y1)); ++y)
      for (int x = static_cast<int>(std::floor(x0)); x < static_cast<int>(std::ceil(x1)); ++x) blend(x, y, c, a);
  }
  void line(double x0, double y0, double x1, double y1, Rgba8 c, float a = 1.0f) {
    const int n = static_cast<int>(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))) + 1;
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      blend(static_cast<int>(std::lround(x0 + (x1 - x0) * t)), static_cast<int>(std::lround(y0 + (y1 - y0) * t)), c, a);
    }
  }
  void rect(double x0, double y0, double x1, double y1, Rgba8 c, float a = 1.0f) {
    line(x0, y0, x1, y0, c, a), line(x1, y0, x1, y1, c, a), line(x1, y1, x0, y1, c, a), line(x0, y1, x0, y0, c, a);
  }
  void dot(double cx, double cy, double r, Rgba8 c) {
    for (int y = static_cast<int>(cy - r - 1); y <= static_cast<int>(cy + r + 1); ++y)
      for (int x = static_cast<int>(cx - r - 1); x <= static_cast<int>(cx + r + 1); ++x) {
        const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
        if (d <= r) blend(x, y, c, static_cast<float>(std::clamp(r - d + 0.5, 0.0, 1.0)));
      }
  }
};

// Time as color: blue (shutter open) to red (close).
Rgba8 timeColor(float t) {
  return {static_cast<uint8_t>(40 + 215 * t), static_cast<uint8_t>(60 + 80 * (1 - std::abs(2 * t - 1))),
          static_cast<uint8_t>(255 - 215 * t), 255};
}

void save(const std::filesystem::path& path, const raster::ImageRgba8& img) {
  if (engine::Status st = engine::writeImage(path.string(), img); !st) fail(st.error());
  std::printf("wrote %s\n", path.string().c_str());
}

// 1. Samples of 8 pixels in a row: x (pixel) against t, and the lens (u, v) of 4 of them.
void samplePictures(const std::filesystem::path& dir, int spp) {
  stochastic::SamplePattern p;
  p.spp = spp;
  stochastic::Sample s[stochastic::kMaxSpp];
  constexpr int kPx = 8, kCell = 80, kH = 400;
  Canvas xt(kPx * kCell + 40, kH + 40, {255, 255, 255, 255});
  for (int k = 0; k <= spp; ++k) {  // the time strata
    const double y = 20 + kH * (1.0 - static_cast<double>(k) / spp);
    xt.line(20, y, 20 + kPx * kCell, y, {225, 225, 225, 255});
  }
  for (int i = 0; i <= kPx; ++i) xt.line(20 + i * kCell, 20, 20 + i * kCell, 20 + kH, {160, 160, 160, 255});
  for (int i = 0; i < kPx; ++i) {
    stochastic::pixelSamples(p, i, 0, s);
    for (int k = 0; k < spp; ++k) {
      // x: the pixel centre, spread by the sample's lens u so that samples at equal times separate.
      const double x = 20 + (i + 0.5) * kCell + double{s[k].u} * kCell * 0.4;
      xt.dot(x, 20 + kH * (1.0 - double{s[k].t}), 4, timeColor(s[k].t));
    }
  }
  save(dir / "samples-xt.png", xt.img);

  constexpr int kD = 300;
  Canvas uv(2 * kD + 60, 2 * kD + 60, {255, 255, 255, 255});
  const double c = kD + 30;
  for (int a = 0; a < 720; ++a) {
    const double th = a * M_PI / 360.0;
    uv.blend(static_cast<int>(c + kD * std::cos(th)), static_cast<int>(c + kD * std::sin(th)), {120, 120, 120, 255});
  }
  uv.line(c - kD, c, c + kD, c, {220, 220, 220, 255});
  uv.line(c, c - kD, c, c + kD, {220, 220, 220, 255});
  const Rgba8 pixelColor[4] = {{30, 30, 30, 255}, {200, 60, 40, 255}, {40, 120, 200, 255}, {40, 160, 80, 255}};
  for (int i = 0; i < 4; ++i) {
    stochastic::pixelSamples(p, i, 0, s);
    for (int k = 0; k < spp; ++k) uv.dot(c + kD * double{s[k].u}, c - kD * double{s[k].v}, i == 0 ? 6 : 4, i == 0 ? timeColor(s[k].t) : pixelColor[i]);
  }
  save(dir / "samples-uv.png", uv.img);
}

// 2. A triangle moving and turning during the shutter, seen through a lens: its positions over
// time, the box, the interval strata and the dual-space blocks' time ranges.
void footprintPicture(const std::filesystem::path& dir) {
  constexpr int kW = 160, kH = 100, kScale = 5;
  const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(50.0f), static_cast<float>(kW) / kH, 0.1f, 100.0f);
  const glm::vec3 p0[3] = {{-2.2f, -0.3f, -6.0f}, {-1.4f, -0.2f, -6.0f}, {-1.9f, 0.6f, -6.2f}};
  glm::vec4 c0[3], c1[3];
  const glm::mat4 move = glm::rotate(glm::translate(glm::mat4(1.0f), {2.8f, 0.2f, -0.5f}), 0.9f, glm::vec3(0, 0, 1));
  for (int i = 0; i < 3; ++i) {
    c0[i] = proj * glm::vec4(p0[i], 1.0f);
    c1[i] = proj * move * glm::vec4(p0[i], 1.0f);
  }
  const stochastic::ThinLens lens = stochastic::makeThinLens(proj[0][0], proj[1][1], 0.08f, 4.0f);
  Canvas cv(kW * kScale, kH * kScale, {255, 255, 255, 255});
  for (int x = 0; x <= kW; x += 4) cv.line(x * kScale, 0, x * kScale, kH * kScale, {238, 238, 238, 255});
  for (int y = 0; y <= kH; y += 4) cv.line(0, y * kScale, kW * kScale, y * kScale, {238, 238, 238, 255});
  // Dual space: each 4x4 block shaded by the share of the shutter its bound keeps.
  const stochastic::PixelRect box = stochastic::footprint(c0, c1, stochastic::Domain{}, lens, true, kW, kH);
  for (int by = box.y0 & ~3; by <= box.y1; by += 4)
    for (int bx = box.x0 & ~3; bx <= box.x1; bx += 4) {
      stochastic::Domain d;
      const stochastic::PixelRect br{bx, by, bx + 3, by + 3};
      if (!stochastic::dualSpaceDomain(c0, c1, lens, true, br, kW, kH, d)) continue;
      const float keep = std::clamp(d.t1 - d.t0, 0.0f, 1.0f);
      cv.fillRect(bx * kScale, by * kScale, (bx + 4) * kScale, (by + 4) * kScale, timeColor(0.5f * (d.t0 + d.t1)),
                  0.15f + 0.35f * keep);
    }
  // Interval strata (time only, pinhole lens corners included).
  for (int i = 0; i < 8; ++i) {
    stochastic::Domain d;
    d.t0 = static_cast<float>(i) / 8.0f, d.t1 = static_cast<float>(i + 1) / 8.0f;
    const stochastic::PixelRect r = stochastic::footprint(c0, c1, d, lens, true, kW, kH);
    cv.rect(r.x0 * kScale, r.y0 * kScale, (r.x1 + 1) * kScale, (r.y1 + 1) * kScale, timeColor((static_cast<float>(i) + 0.5f) / 8.0f), 0.9f);
  }
  // The box over the whole shutter and lens.
  cv.rect(box.x0 * kScale - 1, box.y0 * kScale - 1, (box.x1 + 1) * kScale + 1, (box.y1 + 1) * kScale + 1, {20, 20, 20, 255});
  cv.rect(box.x0 * kScale - 2, box.y0 * kScale - 2, (box.x1 + 1) * kScale + 2, (box.y1 + 1) * kScale + 2, {20, 20, 20, 255});
  // The triangle through the pinhole at 9 times.
  for (int k = 0; k <= 8; ++k) {
    const float t = static_cast<float>(k) / 8.0f;
    double sx[3], sy[3];
    for (int i = 0; i < 3; ++i) {
      const glm::vec4 c = stochastic::clipAt(c0[i], c1[i], t, 0.0f, 0.0f, lens);
      sx[i] = (double{c.x / c.w} * 0.5 + 0.5) * kW * kScale;
      sy[i] = (0.5 - double{c.y / c.w} * 0.5) * kH * kScale;
    }
    for (int i = 0; i < 3; ++i) cv.line(sx[i], sy[i], sx[(i + 1) % 3], sy[(i + 1) % 3], timeColor(t));
  }
  save(dir / "footprint-bounds.png", cv.img);
}

// 3. Exact tests per pixel of each method on the motion scene.
void heatPictures(const std::filesystem::path& dir, int spp) {
  engine::Result<engine::Scene> scene = engine::makeBuiltinScene("motion");
  if (!scene) fail(scene.error());
  engine::Renderer renderer;
  for (stochastic::BoundMethod m : {stochastic::BoundMethod::Box, stochastic::BoundMethod::Interval, stochastic::BoundMethod::DualSpace}) {
    engine::RenderOptions o;
    o.width = 480, o.height = 270, o.spp = spp, o.bounds = m, o.shadow = "none";
    std::vector<uint32_t> tests;
    o.debug.testsPerPixel = &tests;
    const engine::Frame f = renderer.render(*scene, resolveOrFail(o));
    raster::ImageRgba8 img(o.width, o.height);
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        const uint32_t n = tests[static_cast<size_t>(y) * static_cast<size_t>(o.width) + static_cast<size_t>(x)];
        const Rgba8 base = f.color.at(x, y);
        const uint8_t grey = static_cast<uint8_t>((base.r + base.g + base.b) / 9);
        // Tests per sample on a log scale: dark (none), then magenta to yellow (>= 64 per sample).
        const float t = n == 0 ? 0.0f : std::min(1.0f, std::log2(1.0f + static_cast<float>(n) / static_cast<float>(spp)) / 6.0f);
        img.at(x, y) = n == 0 ? Rgba8{grey, grey, grey, 255}
                              : Rgba8{static_cast<uint8_t>(120 + 135 * t), static_cast<uint8_t>(255 * t * t),
                                      static_cast<uint8_t>(140 * (1 - t)), 255};
      }
    save(dir / (std::string("tests-") + stochastic::boundMethodName(m) + ".png"), img);
    std::printf("  %s: %llu exact tests, %llu hits, STE %.3f\n", stochastic::boundMethodName(m),
                static_cast<unsigned long long>(f.stats.stoch.tests), static_cast<unsigned long long>(f.stats.stoch.hits),
                f.stats.stoch.ste());
  }
}

}  // namespace

int runExplain(const ExplainArgs& a) {
  if (a.topic != "stochastic") fail("explain", "unknown topic '" + a.topic + "' (valid: stochastic)");
  if (a.spp < 1 || a.spp > stochastic::kMaxSpp) fail("option --spp", "must be in [1, 64]");
  const std::filesystem::path dir(a.out);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail(a.out, "cannot create the folder: " + ec.message());
  samplePictures(dir, a.spp);
  footprintPicture(dir);
  heatPictures(dir, a.spp);
  return 0;
}

}  // namespace penumbra::apps
