#include "shadows/sssm.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "shadows/moments.h"
#include "shadows/sampling.h"
#include "shadows/shadow_map.h"
#include "stochastic/rasterizer.h"

namespace penumbra::shadows {

namespace {

constexpr int kTile = 16;   // filter tiles, texels a side (section 7.2: 16 x 16 per thread group)
constexpr int kGather = 8;  // R_G: the gather radius of every level, texels
constexpr int kMaxLevels = 8;
constexpr float kInf = std::numeric_limits<float>::infinity();

// One texel of a filter plane's level: the samples merged into it.
struct Texel {
  float n = 0.0f;  // weight: samples (a fraction when part of them moved to a coarser level)
  float s = 0.0f;  // circle of confusion as a scale: half-extents (w/2, h/2) s in tangent units
  float d = kInf;  // nearest depth among them (the widening's "nearer sample")
  float m[4] = {0.0f, 0.0f, 0.0f, 0.0f};  // mean moments
};
// The gather's sums (Eq. 7 before normalization).
struct Acc {
  float w = 0.0f;
  float m[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  void add(const Acc& o, float f) {
    w += f * o.w;
    for (int c = 0; c < 4; ++c) m[c] += f * o.m[c];
  }
};

struct Level {
  int w = 0, h = 0, tilesX = 0, tilesY = 0;
  std::vector<Texel> tex;
  std::vector<Acc> acc;
  std::vector<uint8_t> active;  // per tile: filtered (the lighting or the resolve reads it)
  size_t at(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
  }
  void resize(int width, int height) {
    w = width, h = height;
    tilesX = (w + kTile - 1) / kTile, tilesY = (h + kTile - 1) / kTile;
    tex.assign(static_cast<size_t>(w) * static_cast<size_t>(h), Texel{});
    acc.assign(tex.size(), Acc{});
    active.assign(static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY), 0);
  }
  // Marks the tiles overlapping texels [x0, x1] x [y0, y1] (clamped).
  void mark(int x0, int y0, int x1, int y1) {
    x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, w - 1), y1 = std::min(y1, h - 1);
    for (int ty = y0 / kTile; ty <= y1 / kTile && y0 <= y1; ++ty)
      for (int tx = x0 / kTile; tx <= x1 / kTile && x0 <= x1; ++tx)
        active[static_cast<size_t>(ty) * static_cast<size_t>(tilesX) + static_cast<size_t>(tx)] = 1;
  }
};

// Rows 0 .. h-1 in parallel (in the caller's arena); f(y) writes only what row y owns.
template <class F>
void forRows(int h, F&& f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) f(y);
  });
}

// Eq. 8: the part of a sample of radius rho (texels of the finer level) that moves to the coarser.
float coarseWeight(float rho) {
  const auto rg = static_cast<float>(kGather);
  if (rho > 0.5f * rg) return 1.0f;
  if (rho < 0.4f * rg) return 0.0f;
  return 1.0f - (0.5f * rg - rho) / (0.1f * rg);
}

// Texels an extent h (>= 0.5) covers along one axis: the integers k with |k| < h; with interleaved
// sampling only those of one parity as the gathering texel's (every second one), counted from 0.
int coveredTexels(float h, bool interleave) {
  const int c = static_cast<int>(std::ceil(h)) - 1;  // the largest |k| < h
  return interleave ? 2 * (c / 2) + 1 : 2 * c + 1;
}

// 12 Poisson-disc taps within 32 texels (section 7.2), from a fixed dart throw: deterministic.
std::array<glm::vec2, 12> poissonTaps() {
  std::array<glm::vec2, 12> taps{};
  int n = 0;
  for (uint32_t i = 0; n < 12 && i < 100000; ++i) {
    const float a = unitFloat(hash3(i, 0x5e55u, 1u)), b = unitFloat(hash3(i, 0x5e55u, 2u));
    const glm::vec2 p(64.0f * a - 32.0f, 64.0f * b - 32.0f);
    if (glm::dot(p, p) > 32.0f * 32.0f || glm::dot(p, p) < 1.0f) continue;
    bool far = true;
    for (int k = 0; k < n && far; ++k) far = glm::distance(p, taps[static_cast<size_t>(k)]) >= 14.0f;
    if (far) taps[static_cast<size_t>(n++)] = p;
  }
  return taps;
}

struct Settings {
  int size = 512, planes = 4, levels = 2, strata = 4, frame = 0;
  bool inverseSpacing = true, exactCentres = true, coverage = true, widen = true, interleave = false,
       box = true, activeTiles = true;
  stochastic::BoundMethod method = stochastic::BoundMethod::DualSpace;
};

// Per-stage milliseconds (the paper's table, section 8.1) and what was skipped.
struct StageLog {
  double reproject = 0, init = 0, coarse = 0, filter = 0, resolve = 0;
  size_t tiles = 0, tilesFiltered = 0, dropped = 0, truncated = 0, texelsGathered = 0;
};

class Sssm final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override;
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override;

 private:
  void renderSamples(ShadowContext& ctx);
  // The planes around receiver depth d and the weight of the farther one (linear in 1/d or d).
  void bracket(float d, int& i0, int& i1, float& t) const;
  void markActive(ShadowContext& ctx, int plane);
  size_t reproject(int plane);  // returns the samples that left the map
  void widenRadii();
  void widenPool(Level& pool, const Level& front, const Level& back);
  void buildLevels(int pool);
  void filterLevel(ShadowContext& ctx, int pool, int level, StageLog& log);
  void resolve(ShadowContext& ctx, int pool);
  void combine(int plane);
  float rhoTexels(float s) const { return std::max(sx_, sy_) * s; }

  Settings set_;
  BiasParams bias_;
  double minVariance_ = 0, bleedReduction_ = 0;
  LightView view_;
  MomentWarp warp_;
  float zNear_ = 0, zFar_ = 1, focus_ = 1;
  float widenCap_ = kInf;                // the widening's largest circle, as a scale s
  float reach_ = kInf;                   // the widest circle the widening takes, texels
  float sx_ = 0, sy_ = 0;                // texels per unit of scale s along x and y: (w/2) kxT, (h/2) kyT
  std::vector<float> depth_;             // per texel of the stochastic map: d_k (+inf: no surface)
  std::vector<glm::vec2> lens_;          // its light point (light-space x, y in world units)
  std::vector<raster::Float4> moments_;  // the EVSM moments of d_k
  std::vector<float> planeDepth_;
  // The filter plane being built: two pools of samples, each with its levels: pools_[0] the samples
  // in front of the plane (d < D: occluders), pools_[1] the others (the receivers' surfaces,
  // nothing). The planes are built one after the other in the same buffers.
  std::array<std::vector<Level>, 2> pools_;
  std::array<int, 2> levelCount_{1, 1};
  std::array<std::vector<Acc>, 2> final_;  // per pool: the resolved sums at the finest level
  std::vector<MomentMap> result_;
  stochastic::StochasticStats stoch_;
};

void Sssm::bracket(float d, int& i0, int& i1, float& t) const {
  const int n = static_cast<int>(planeDepth_.size());
  auto key = [&](float x) { return set_.inverseSpacing ? -1.0f / x : x; };
  if (n == 1 || !(d > planeDepth_.front())) {
    i0 = i1 = 0, t = 0.0f;
    return;
  }
  if (d >= planeDepth_.back()) {
    i0 = i1 = n - 1, t = 0.0f;
    return;
  }
  int i = 0;
  while (i + 2 < n && d >= planeDepth_[static_cast<size_t>(i + 1)]) ++i;
  i0 = i, i1 = i + 1;
  const float a = key(planeDepth_[static_cast<size_t>(i)]), b = key(planeDepth_[static_cast<size_t>(i + 1)]);
  t = std::clamp((key(d) - a) / (b - a), 0.0f, 1.0f);
}

void Sssm::prepare(ShadowContext& ctx, const ParamSet& params) {
  const auto t0 = Clock::now();
  set_.size = params.integer("map_size");
  set_.planes = params.integer("planes");
  set_.levels = params.integer("levels");
  set_.strata = params.integer("strata");
  set_.frame = params.integer("frame");
  set_.inverseSpacing = params.choice("spacing") == "inverse";
  set_.widen = params.choice("widen") == "on";
  set_.exactCentres = params.choice("centres") == "exact";
  set_.coverage = params.choice("estimator") == "coverage";
  set_.interleave = params.choice("interleave") == "on";
  set_.box = params.choice("box") == "on";
  set_.activeTiles = params.choice("active_tiles") == "on";
  stochastic::parseBoundMethod(params.choice("bound"), set_.method);
  bias_ = biasParams(params);
  minVariance_ = params.number("min_variance");
  bleedReduction_ = params.number("bleed_reduction");
  warp_ = {.kind = MomentKind::Evsm4,
           .cPos = static_cast<float>(params.number("exponent_pos")),
           .cNeg = static_cast<float>(params.number("exponent_neg"))};

  const WidenedView wide = widenedView(ctx, set_.size);
  view_ = wide.view;
  zNear_ = view_.znear;
  zFar_ = std::max(1.01f * ctx.region.hi.z, zNear_ * 1.01f);
  sx_ = 0.5f * ctx.in.light.width * static_cast<float>(view_.width) / (view_.tanHi.x - view_.tanLo.x);
  sy_ = 0.5f * ctx.in.light.height * static_cast<float>(view_.height) / (view_.tanHi.y - view_.tanLo.y);
  const double cap = params.number("widen_max");
  widenCap_ = cap > 0.0 ? static_cast<float>(cap) / std::max(sx_, sy_) : kInf;
  // Four times the coarsest level's gather: a circle the filter cuts to a quarter of its width or
  // less is not one a sample can be widened to (the gather still takes it, cut).
  reach_ = set_.levels > 0 ? static_cast<float>(4 * (kGather << set_.levels)) : kInf;

  // Filter planes over the receivers' depth range, uniform in 1/d (or d); the lens focuses on the
  // middle one, whose plane is the stochastic map itself.
  const float lo = std::max(ctx.region.lo.z, zNear_), hi = std::max(ctx.region.hi.z, lo);
  planeDepth_.assign(static_cast<size_t>(set_.planes), 0.5f * (lo + hi));
  for (int i = 0; i < set_.planes && set_.planes > 1; ++i) {
    const float f = static_cast<float>(i) / static_cast<float>(set_.planes - 1);
    planeDepth_[static_cast<size_t>(i)] =
        set_.inverseSpacing ? 1.0f / (1.0f / lo + f * (1.0f / hi - 1.0f / lo)) : lo + f * (hi - lo);
  }
  focus_ = planeDepth_[static_cast<size_t>(set_.planes / 2)];

  renderSamples(ctx);
  ctx.times.msMaps += msSince(t0);

  const auto t1 = Clock::now();
  StageLog log;
  result_.assign(planeDepth_.size(), MomentMap{});
  int levelsUsed = 0;
  for (int p = 0; p < set_.planes; ++p) {
    auto t = Clock::now();
    ctx.raster.run([&] { log.dropped += reproject(p); });
    log.reproject += msSince(t);
    t = Clock::now();
    if (set_.widen) ctx.raster.run([&] { widenRadii(); });
    log.init += msSince(t);
    t = Clock::now();
    ctx.raster.run([&] {
      for (int k = 0; k < 2; ++k) buildLevels(k);
    });
    log.coarse += msSince(t);
    levelsUsed = std::max({levelsUsed, levelCount_[0], levelCount_[1]});
    markActive(ctx, p);
    t = Clock::now();
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < levelCount_[static_cast<size_t>(k)]; ++l) filterLevel(ctx, k, l, log);
    log.filter += msSince(t);
    t = Clock::now();
    for (int k = 0; k < 2; ++k) resolve(ctx, k);
    ctx.raster.run([&] { combine(p); });
    log.resolve += msSince(t);
  }
  ctx.times.msFilter += msSince(t1);

  char buf[400];
  std::snprintf(
      buf, sizeof buf,
      "sssm: stochastic map %dx%d, 1 sample per texel, light strata %dx%d per %dx%d texels, lens focused "
      "at depth %.4g%s",
      view_.width, view_.height, std::max(set_.strata, 1), std::max(set_.strata, 1), std::max(set_.strata, 1),
      std::max(set_.strata, 1), static_cast<double>(focus_), wide.note.c_str());
  ctx.notes.push_back(buf);
  ctx.notes.push_back("sssm: light-lens pass: " + stoch_.report(stochastic::boundMethodName(set_.method)));
  if (ctx.in.castersMove())
    ctx.notes.push_back(
        "sssm: casters move: every sample also has a shutter time (the light strata's blocks take the "
        "shutter's "
        "strata too), so the map holds the casters over the whole shutter: motion-blurred soft shadows");
  std::string depths;
  for (float d : planeDepth_) {
    std::snprintf(buf, sizeof buf, "%s%.4g", depths.empty() ? "" : ", ", static_cast<double>(d));
    depths += buf;
  }
  std::snprintf(buf, sizeof buf, "sssm: %d filter plane(s) at depth %s (uniform in %s), %zu level(s)",
                set_.planes, depths.c_str(), set_.inverseSpacing ? "1/depth" : "depth",
                static_cast<size_t>(levelsUsed));
  ctx.notes.push_back(buf);
  std::snprintf(
      buf, sizeof buf,
      "sssm: pre-filter ms: reproject %.2f, init finest %.2f, coarse levels %.2f, filter levels %.2f, "
      "resolve %.2f",
      log.reproject, log.init, log.coarse, log.filter, log.resolve);
  ctx.notes.push_back(buf);
  std::snprintf(
      buf, sizeof buf,
      "sssm: tiles filtered %zu of %zu (%.1f%% skipped: no receiver reads them%s), %zu texel gathers; "
      "%zu sample(s) reprojected off the map; %zu coarsest texel(s) wider than the gather",
      log.tilesFiltered, log.tiles,
      log.tiles ? 100.0 * static_cast<double>(log.tiles - log.tilesFiltered) / static_cast<double>(log.tiles)
                : 0.0,
      set_.activeTiles ? "" : "; active_tiles=off filters every tile", log.texelsGathered, log.dropped,
      log.truncated);
  ctx.notes.push_back(buf);
}

void Sssm::renderSamples(ShadowContext& ctx) {
  const RectLight& light = ctx.in.light;
  const Geometry& geo = ctx.in.casters;
  // Moving casters: each sample also draws a shutter time, and the lens sees every triangle where
  // it is at that time (the vertices at open and close, stochastic/coverage.h's time-continuous
  // triangles). Static: the one set of positions (open = close).
  const bool motion = ctx.in.castersMove();
  const std::span<const glm::vec3> open = motion ? ctx.in.castersOpen : geo.positions;
  const std::span<const glm::vec3> close = motion ? ctx.in.castersClose : geo.positions;
  // Every surface, receivers included (the moments of a lit texel must be its surface's, as for
  // every moment map: moments.h momentCasters), less what lies wholly behind the light or beyond
  // the farthest receiver; the lens sees beyond the centre's frustum, so its sides do not cull.
  std::vector<uint32_t> tris;
  tris.reserve(geo.indices.size());
  for (size_t t = 0; t < geo.triangles(); ++t) {
    const uint32_t* tri = &geo.indices[t * 3];
    bool behind = true, beyond = true;  // at both ends, so at every time (depth is linear in it)
    for (int k = 0; k < 3; ++k)
      for (const glm::vec3& p : {open[tri[k]], close[tri[k]]}) {
        const float d = view_.toView(p).z;
        behind = behind && !(d > 0.0f);
        beyond = beyond && d > zFar_;
      }
    if (!behind && !beyond) tris.insert(tris.end(), tri, tri + 3);
  }
  // Clip positions with a conventional depth (the stochastic rasterizer keeps the smaller z / w):
  // the view's x, y and w rows, z = w - near (0 at the near plane, towards 1 far away).
  glm::mat4 m = view_.viewProj;
  for (int c = 0; c < 4; ++c) m[c][2] = m[c][3] - m[c][2];
  std::vector<glm::vec4> clip(geo.positions.size()), clip1;
  for (size_t i = 0; i < clip.size(); ++i) clip[i] = m * glm::vec4(open[i], 1.0f);
  if (motion) {
    clip1.resize(clip.size());
    for (size_t i = 0; i < clip.size(); ++i) clip1[i] = m * glm::vec4(close[i], 1.0f);
  }
  const std::vector<uint32_t> surface(tris.size() / 3, 0u);

  // The light as the lens: a lens point (u, v) in [-1, 1]^2 is the light point (u w/2, v h/2);
  // coverage.h's shear x += u kx (w - F) with kx = (w/2) P00 / F, P00 = 2 / (tanHi.x - tanLo.x).
  stochastic::StochasticInput in;
  in.clip0 = clip;
  in.clip1 = motion ? std::span<const glm::vec4>(clip1) : std::span<const glm::vec4>(clip);
  in.indices = tris;
  in.surface = surface;
  in.motion = motion;
  in.lens.kx = 0.5f * light.width * (2.0f / (view_.tanHi.x - view_.tanLo.x)) / focus_;
  in.lens.ky = 0.5f * light.height * (2.0f / (view_.tanHi.y - view_.tanLo.y)) / focus_;
  in.lens.focusW = focus_;
  stochastic::StochasticConfig cfg;
  cfg.method = set_.method;
  cfg.pattern.spp = 1;
  cfg.pattern.frame = static_cast<uint32_t>(set_.frame);
  cfg.pattern.motion = motion;
  cfg.pattern.shape = stochastic::LensShape::Square;
  cfg.pattern.blockStrata = set_.strata > 1 ? set_.strata : 0;
  std::vector<uint32_t> sampleTri;
  std::vector<float> sampleZ;
  stochastic::StochasticDebug debug;
  debug.sampleTriangle = &sampleTri;
  debug.sampleDepth = &sampleZ;
  raster::Image<stochastic::ResolvedPixel> resolved(view_.width, view_.height);
  stochastic::StochasticRasterizer sr(ctx.raster);
  stoch_ = sr.render(in, cfg, {}, resolved, debug);

  // Per texel its ray (light point L through the texel's point of the focus plane) and the depth
  // of the surface that covers it, as the ray meets that triangle's plane (double).
  const auto n = static_cast<size_t>(view_.width) * static_cast<size_t>(view_.height);
  depth_.assign(n, kInf);
  lens_.assign(n, glm::vec2(0.0f));
  // A ray that meets nothing (before the farthest receiver) is unblocked for every receiver: its
  // moments are those of the farthest receiver's depth, not of the far plane beyond it. The
  // exponential warp makes a small mass beyond a receiver weigh heavily in the Chebyshev bound
  // (5% at the far plane, 1% of the range behind, lets 0.7 through an umbra); at the farthest
  // receiver it lets through what it should.
  const float hiZ = std::clamp((ctx.region.hi.z - zNear_) / (zFar_ - zNear_), 0.0f, 1.0f);
  moments_.assign(n, warp_.moments(hiZ));
  const glm::dvec3 c(light.center), right(light.right), up(light.up), axis(light.normal());
  const double ex = static_cast<double>(view_.tanHi.x - view_.tanLo.x),
               ey = static_cast<double>(view_.tanHi.y - view_.tanLo.y);
  ctx.raster.run([&] {
    tbb::parallel_for(0, view_.height, [&](int y) {
      for (int x = 0; x < view_.width; ++x) {
        const size_t k = static_cast<size_t>(y) * static_cast<size_t>(view_.width) + static_cast<size_t>(x);
        stochastic::Sample s;
        stochastic::pixelSamples(cfg.pattern, x, y, &s);
        const glm::vec2 L(s.u * 0.5f * light.width, s.v * 0.5f * light.height);
        lens_[k] = L;
        const uint32_t t = sampleTri[k];
        if (t == stochastic::kNoTriangle) continue;
        const double tx = static_cast<double>(view_.tanLo.x) + (x + 0.5) / view_.width * ex;
        const double ty = static_cast<double>(view_.tanHi.y) - (y + 0.5) / view_.height * ey;
        const double f = static_cast<double>(focus_);
        const glm::dvec3 o = c + static_cast<double>(L.x) * right + static_cast<double>(L.y) * up;
        const glm::dvec3 q = c + f * (tx * right + ty * up + axis);
        // The triangle at the sample's time (open + (close - open) t, in double).
        const auto at = [&](size_t j) {
          const glm::dvec3 a(open[tris[t * 3 + j]]), b(close[tris[t * 3 + j]]);
          return a + (b - a) * static_cast<double>(s.t);
        };
        const glm::dvec3 p0 = at(0), p1 = at(1), p2 = at(2);
        const glm::dvec3 nrm = glm::cross(p1 - p0, p2 - p0);
        const double den = glm::dot(q - o, nrm);
        double d = den != 0.0 ? f * glm::dot(p0 - o, nrm) / den : 0.0;
        // Grazing rays: the rasterizer's own depth (z / w = 1 - near / d).
        if (!(d > 0.0) || !std::isfinite(d))
          d = static_cast<double>(zNear_) / (1.0 - static_cast<double>(sampleZ[k]));
        depth_[k] = static_cast<float>(std::min(d, static_cast<double>(std::numeric_limits<float>::max())));
        moments_[k] = warp_.moments(std::clamp((depth_[k] - zNear_) / (zFar_ - zNear_), 0.0f, 1.0f));
      }
    });
  });
}

size_t Sssm::reproject(int plane) {
  const float D = planeDepth_[static_cast<size_t>(plane)];
  const int w = view_.width, h = view_.height;
  Level* pool[2];
  for (size_t k = 0; k < 2; ++k) {
    if (pools_[k].empty()) pools_[k].emplace_back();
    pools_[k][0].resize(w, h);  // the buffers of the previous plane, cleared
    levelCount_[k] = 1;
    pool[k] = &pools_[k][0];
  }
  // Each sample's destination (texel * 2 + pool), in parallel.
  constexpr uint32_t kOff = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> dest(depth_.size(), kOff);
  const float shift = 1.0f / D - 1.0f / focus_;
  const float kx = static_cast<float>(w) / (view_.tanHi.x - view_.tanLo.x);
  const float ky = static_cast<float>(h) / (view_.tanHi.y - view_.tanLo.y);
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t k = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
      const float d = depth_[k];
      const bool front = d < D;
      // Where the ray crosses the plane, t_k + L (1/D - 1/F); or, for a sample in front of the
      // plane with exact centres, its hit point seen from the light centre, t_k + L (1/d - 1/F):
      // the centre of its circle of confusion. In texels, x grows with tan x, y with -tan y.
      const float g = set_.exactCentres && front ? 1.0f / d - 1.0f / focus_ : shift;
      int dx = x, dy = y;
      if (g != 0.0f) {
        const float fx = static_cast<float>(x) + 0.5f + lens_[k].x * g * kx;
        const float fy = static_cast<float>(y) + 0.5f - lens_[k].y * g * ky;
        if (!(fx >= 0.0f && fx < static_cast<float>(w) && fy >= 0.0f && fy < static_cast<float>(h))) continue;
        dx = static_cast<int>(fx), dy = static_cast<int>(fy);
      }
      dest[k] = static_cast<uint32_t>(pool[0]->at(dx, dy) * 2 + (front ? 0 : 1));
    }
  });
  // The samples by destination band of kTile rows, in sample order (a stable counting sort), so
  // that each band merges its texels' samples in a fixed order: deterministic at any thread count.
  const int bands = (h + kTile - 1) / kTile;
  const auto rowsPerBand = static_cast<uint32_t>(kTile) * static_cast<uint32_t>(w) * 2u;
  std::vector<uint32_t> first(static_cast<size_t>(bands) + 1, 0);
  size_t dropped = 0;
  for (uint32_t o : dest) {
    if (o == kOff) {
      ++dropped;
      continue;
    }
    ++first[o / rowsPerBand + 1];
  }
  for (size_t b = 1; b < first.size(); ++b) first[b] += first[b - 1];
  std::vector<uint32_t> order(first.back());
  std::vector<uint32_t> fill(first.begin(), first.end() - 1);
  for (size_t k = 0; k < dest.size(); ++k)
    if (dest[k] != kOff) order[fill[dest[k] / rowsPerBand]++] = static_cast<uint32_t>(k);
  forRows(bands, [&](int b) {
    for (uint32_t i = first[static_cast<size_t>(b)]; i < first[static_cast<size_t>(b) + 1]; ++i) {
      const uint32_t k = order[i];
      const float d = depth_[k];
      Texel& t = pool[dest[k] & 1u]->tex[dest[k] / 2];
      t.n += 1.0f;
      // A ray that meets nothing has no point to spread by a circle of confusion (at infinite depth
      // it would be the light's whole footprint, 1/D, and its light would leak into umbrae beside
      // it): it holds for its own texel, and the widening grows it like any other sample.
      t.s += std::isinf(d) ? 0.0f : std::abs(1.0f / d - 1.0f / D);
      const raster::Float4& m = moments_[k];
      t.m[0] += m.r, t.m[1] += m.g, t.m[2] += m.b, t.m[3] += m.a;
      t.d = std::min(t.d, d);
    }
    for (int y = b * kTile; y < std::min(h, (b + 1) * kTile); ++y)
      for (int x = 0; x < w; ++x)
        for (Level* L : pool) {
          Texel& t = L->tex[L->at(x, y)];
          if (t.n == 0.0f) continue;
          t.s /= t.n;
          for (float& c : t.m) c /= t.n;
        }
  });
  return dropped;
}

void Sssm::widenRadii() {
  // The coverage estimator takes the blocked fraction from the samples in front of the plane,
  // whose circles are exact: only the others are widened (they fill the rest of the light).
  for (size_t k = set_.coverage ? 1 : 0; k < 2; ++k) widenPool(pools_[k][0], pools_[0][0], pools_[1][0]);
}

void Sssm::widenPool(Level& L0, const Level& front, const Level& back) {
  const int w = L0.w, h = L0.h;
  std::vector<float> rho(L0.tex.size(), 0.0f);
  static const std::array<glm::vec2, 12> taps = poissonTaps();
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const Texel& t = L0.tex[L0.at(x, y)];
      if (t.n == 0.0f) continue;
      // The smallest circle of a nearer sample that holds this one, among the rotated taps.
      const float angle = 2.0f * std::numbers::pi_v<float> *
                          unitFloat(hash3(static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0xc0c0u));
      const float ca = std::cos(angle), sa = std::sin(angle);
      float cl = kInf;
      for (const glm::vec2& p : taps) {
        const int ox = static_cast<int>(std::lround(ca * p.x - sa * p.y));
        const int oy = static_cast<int>(std::lround(sa * p.x + ca * p.y));
        const int lx = x + ox, ly = y + oy;
        if (lx < 0 || ly < 0 || lx >= w || ly >= h) continue;
        for (const Level* pool : {&front, &back}) {
          const Texel& l = pool->tex[pool->at(lx, ly)];
          // A nearer sample whose circle the filter cannot hold (far wider than its reach: an
          // occluder next to the light) would widen every sample around it to the whole map and
          // spread their light into umbrae; it does not widen.
          if (l.n == 0.0f || !(l.d < t.d) || rhoTexels(l.s) > reach_) continue;
          if (static_cast<float>(std::abs(ox)) < sx_ * l.s && static_cast<float>(std::abs(oy)) < sy_ * l.s)
            cl = std::min(cl, l.s);
        }
      }
      rho[L0.at(x, y)] = cl < kInf ? std::max(t.s, std::min(cl, widenCap_)) : t.s;
    }
  });
  // A Gaussian of radius 2 texels (sigma 1) over the widened scales, weighted by sample counts.
  constexpr float kG[3] = {1.0f, 0.60653066f, 0.13533528f};
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      Texel& t = L0.tex[L0.at(x, y)];
      if (t.n == 0.0f) continue;
      float sum = 0.0f, wsum = 0.0f;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const size_t q = L0.at(qx, qy);
          // Nor do such circles reach their neighbours through the smoothing.
          if (rhoTexels(rho[q]) > reach_ && (dx != 0 || dy != 0)) continue;
          const float g = kG[std::abs(dx)] * kG[std::abs(dy)] * L0.tex[q].n;
          sum += g * rho[q], wsum += g;
        }
      t.s = std::max(t.s, sum / wsum);
    }
  });
}

void Sssm::buildLevels(int pool) {
  std::vector<Level>& levels = pools_[static_cast<size_t>(pool)];
  int count = set_.levels;
  if (count == 0) {
    float rmax = 0.0f;
    for (const Texel& t : levels[0].tex)
      if (t.n > 0.0f) rmax = std::max(rmax, rhoTexels(t.s));
    // Until the largest circle stays on its level by Eq. 8 (radius at most 0.5 R_G there).
    while (count < kMaxLevels && rmax / static_cast<float>(1 << count) > 0.5f * static_cast<float>(kGather))
      ++count;
  }
  int& used = levelCount_[static_cast<size_t>(pool)];
  for (int l = 1; l <= count; ++l) {
    const int fw = levels[static_cast<size_t>(l - 1)].w, fh = levels[static_cast<size_t>(l - 1)].h;
    if (fw < 2 && fh < 2) break;
    if (static_cast<int>(levels.size()) == l) levels.emplace_back();
    levels[static_cast<size_t>(l)].resize((fw + 1) / 2, (fh + 1) / 2);
    used = l + 1;
    Level& f = levels[static_cast<size_t>(l - 1)];
    Level& c = levels[static_cast<size_t>(l)];
    const float scale = 1.0f / static_cast<float>(1 << (l - 1));
    forRows(c.h, [&](int y) {
      for (int x = 0; x < c.w; ++x) {
        Texel& o = c.tex[c.at(x, y)];
        double n = 0, s = 0, m[4] = {0, 0, 0, 0};
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) {
            const int fx = 2 * x + i, fy = 2 * y + j;
            if (fx >= f.w || fy >= f.h) continue;
            Texel& t = f.tex[f.at(fx, fy)];
            if (t.n == 0.0f) continue;
            const float moved = t.n * coarseWeight(rhoTexels(t.s) * scale);
            if (moved == 0.0f) continue;
            t.n -= moved;
            n += static_cast<double>(moved);
            s += static_cast<double>(moved) * static_cast<double>(t.s);
            for (int k = 0; k < 4; ++k) m[k] += static_cast<double>(moved) * static_cast<double>(t.m[k]);
            o.d = std::min(o.d, t.d);
          }
        if (n == 0.0) continue;
        o.n = static_cast<float>(n);
        o.s = static_cast<float>(s / n);
        for (int k = 0; k < 4; ++k) o.m[k] = static_cast<float>(m[k] / n);
      }
    });
  }
}

void Sssm::markActive(ShadowContext& ctx, int plane) {
  for (auto& levels : pools_)
    for (Level& l : levels) std::fill(l.active.begin(), l.active.end(), set_.activeTiles ? 0 : 1);
  if (!set_.activeTiles) return;
  // Level 0: the texels a receiver's bilinear lookup reads, and the 3 x 3 box around them.
  const ReceiverImage& rec = *ctx.in.receivers;
  for (int y = 0; y < rec.height(); ++y)
    for (int x = 0; x < rec.width(); ++x) {
      const Receiver& r = rec.at(x, y);
      if (!r.valid) continue;
      const glm::vec3 v = lookupPoint(view_, r, bias_);
      if (!(v.z > 0.0f)) continue;
      const glm::vec2 p = view_.toMap(v);
      if (!(std::isfinite(p.x) && std::isfinite(p.y))) continue;
      const int px =
          static_cast<int>(std::floor(std::clamp(p.x, -2.0f, static_cast<float>(view_.width) + 2.0f) - 0.5f));
      const int py = static_cast<int>(
          std::floor(std::clamp(p.y, -2.0f, static_cast<float>(view_.height) + 2.0f) - 0.5f));
      int i0, i1;
      float t;
      bracket(v.z, i0, i1, t);
      if (i0 == plane || (t > 0.0f && i1 == plane))
        for (auto& levels : pools_) levels[0].mark(px - 1, py - 1, px + 2, py + 2);
    }
  // Coarser levels: what the resolve of each active finer tile reads (bilinear, then the box).
  for (size_t k = 0; k < 2; ++k)
    for (size_t l = 1; l < static_cast<size_t>(levelCount_[k]); ++l) {
      const std::vector<Level>& levels = pools_[k];
      const Level& f = levels[l - 1];
      Level& c = pools_[k][l];
      for (int ty = 0; ty < f.tilesY; ++ty)
        for (int tx = 0; tx < f.tilesX; ++tx) {
          if (!f.active[static_cast<size_t>(ty) * static_cast<size_t>(f.tilesX) + static_cast<size_t>(tx)])
            continue;
          const int x0 = tx * kTile, y0 = ty * kTile, x1 = x0 + kTile - 1, y1 = y0 + kTile - 1;
          c.mark((x0 - 1) / 2 - 2, (y0 - 1) / 2 - 2, (x1 + 1) / 2 + 2, (y1 + 1) / 2 + 2);
        }
    }
}

void Sssm::filterLevel(ShadowContext& ctx, int pool, int level, StageLog& log) {
  Level& L = pools_[static_cast<size_t>(pool)][static_cast<size_t>(level)];
  const bool coarsest = level + 1 == levelCount_[static_cast<size_t>(pool)];
  const float scale = 1.0f / static_cast<float>(1 << level);
  const auto area = static_cast<double>(1 << (2 * level));  // finest texels per texel of this level
  // Per tile the largest radius of its samples (texels of this level).
  std::vector<float> tileRho(L.active.size(), -1.0f);
  std::vector<size_t> wide(static_cast<size_t>(L.tilesY), 0);
  forRows(L.tilesY, [&](int ty) {
    for (int y = ty * kTile; y < std::min(L.h, (ty + 1) * kTile); ++y)
      for (int x = 0; x < L.w; ++x) {
        const Texel& t = L.tex[L.at(x, y)];
        if (t.n == 0.0f) continue;
        float& r =
            tileRho[static_cast<size_t>(ty) * static_cast<size_t>(L.tilesX) + static_cast<size_t>(x / kTile)];
        r = std::max(r, rhoTexels(t.s) * scale);
        if (coarsest && rhoTexels(t.s) * scale > static_cast<float>(kGather)) ++wide[static_cast<size_t>(ty)];
      }
  });
  for (size_t n : wide) log.truncated += n;
  std::vector<size_t> gathered(L.active.size(), 0);
  ctx.raster.run([&] {
    tbb::parallel_for(size_t{0}, L.active.size(), [&](size_t ti) {
      if (!L.active[ti]) return;
      const int tx = static_cast<int>(ti % static_cast<size_t>(L.tilesX)),
                ty = static_cast<int>(ti / static_cast<size_t>(L.tilesX));
      // The window: the largest radius among the tile and its neighbours (R_G < kTile), at most R_G.
      float rmax = -1.0f;
      for (int j = std::max(ty - 1, 0); j <= std::min(ty + 1, L.tilesY - 1); ++j)
        for (int i = std::max(tx - 1, 0); i <= std::min(tx + 1, L.tilesX - 1); ++i)
          rmax = std::max(
              rmax, tileRho[static_cast<size_t>(j) * static_cast<size_t>(L.tilesX) + static_cast<size_t>(i)]);
      if (rmax < 0.0f) return;
      const int R =
          std::max(0, static_cast<int>(std::ceil(std::min(rmax, static_cast<float>(kGather + 1)))) - 1);
      size_t count = 0;
      for (int y = ty * kTile; y < std::min(L.h, (ty + 1) * kTile); ++y)
        for (int x = tx * kTile; x < std::min(L.w, (tx + 1) * kTile); ++x) {
          double aw = 0.0, am[4] = {0.0, 0.0, 0.0, 0.0};
          for (int dy = -R; dy <= R; ++dy) {
            if (set_.interleave && (dy & 1)) continue;
            const int qy = y + dy;
            if (qy < 0 || qy >= L.h) continue;
            for (int dx = -R; dx <= R; ++dx) {
              if (set_.interleave && (dx & 1)) continue;
              const int qx = x + dx;
              if (qx < 0 || qx >= L.w) continue;
              const Texel& q = L.tex[L.at(qx, qy)];
              if (q.n == 0.0f) continue;
              const float hx = std::min(std::max(0.5f, sx_ * q.s * scale), kGather + 0.5f);
              const float hy = std::min(std::max(0.5f, sy_ * q.s * scale), kGather + 0.5f);
              if (!(static_cast<float>(std::abs(dx)) < hx && static_cast<float>(std::abs(dy)) < hy)) continue;
              const double alpha =
                  static_cast<double>(q.n) / (static_cast<double>(coveredTexels(hx, set_.interleave)) *
                                              coveredTexels(hy, set_.interleave) * area);
              aw += alpha;
              for (int c = 0; c < 4; ++c) am[c] += alpha * static_cast<double>(q.m[c]);
            }
          }
          count += static_cast<size_t>((2 * R + 1) * (2 * R + 1));
          L.acc[L.at(x, y)] = {static_cast<float>(aw),
                               {static_cast<float>(am[0]), static_cast<float>(am[1]),
                                static_cast<float>(am[2]), static_cast<float>(am[3])}};
        }
      gathered[ti] = count;
    });
  });
  log.tiles += L.active.size();
  for (size_t ti = 0; ti < L.active.size(); ++ti) {
    log.tilesFiltered += L.active[ti];
    log.texelsGathered += gathered[ti];
  }
}

// The texels of L's active tiles in parallel (tiles, then rows, then columns); f(x, y) writes only
// what texel (x, y) owns.
template <class F>
void forActiveTexels(const Level& L, F&& f) {
  tbb::parallel_for(size_t{0}, L.active.size(), [&](size_t ti) {
    if (!L.active[ti]) return;
    const int tx = static_cast<int>(ti % static_cast<size_t>(L.tilesX)),
              ty = static_cast<int>(ti / static_cast<size_t>(L.tilesX));
    for (int y = ty * kTile; y < std::min(L.h, (ty + 1) * kTile); ++y)
      for (int x = tx * kTile; x < std::min(L.w, (tx + 1) * kTile); ++x) f(x, y);
  });
}

void Sssm::resolve(ShadowContext& ctx, int pool) {
  std::vector<Level>& levels = pools_[static_cast<size_t>(pool)];
  const auto count = static_cast<size_t>(levelCount_[static_cast<size_t>(pool)]);
  ctx.raster.run([&] {
    // A 3 x 3 box of each level's own sums (Fig. 10: it removes the structured noise of the strata
    // and of interleaving), on the active tiles: they hold every texel the finer level's active
    // tiles read (markActive). Not of what the coarser levels add: that would blur them again at
    // every level on the way down.
    std::vector<Acc> own;
    for (size_t l = 0; l < count && set_.box; ++l) {
      Level& L = levels[l];
      own = L.acc;
      forActiveTexels(L, [&](int x, int y) {
        Acc a;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            a.add(own[L.at(std::clamp(x + dx, 0, L.w - 1), std::clamp(y + dy, 0, L.h - 1))], 1.0f / 9.0f);
        L.acc[L.at(x, y)] = a;
      });
    }
    // Coarsest to finest: each finer texel adds the coarser level's sums, bilinearly up-sampled.
    for (size_t l = count - 1; l >= 1; --l) {
      const Level& c = levels[l];
      Level& f = levels[l - 1];
      forActiveTexels(f, [&](int x, int y) {
        const float cy = (static_cast<float>(y) + 0.5f) / 2.0f - 0.5f;
        const int y0 = std::clamp(static_cast<int>(std::floor(cy)), 0, c.h - 1),
                  y1 = std::min(y0 + 1, c.h - 1);
        const float fy = std::clamp(cy - std::floor(cy), 0.0f, 1.0f);
        const float cx = (static_cast<float>(x) + 0.5f) / 2.0f - 0.5f;
        const int x0 = std::clamp(static_cast<int>(std::floor(cx)), 0, c.w - 1),
                  x1 = std::min(x0 + 1, c.w - 1);
        const float fx = std::clamp(cx - std::floor(cx), 0.0f, 1.0f);
        Acc& a = f.acc[f.at(x, y)];
        a.add(c.acc[c.at(x0, y0)], (1 - fx) * (1 - fy));
        a.add(c.acc[c.at(x1, y0)], fx * (1 - fy));
        a.add(c.acc[c.at(x0, y1)], (1 - fx) * fy);
        a.add(c.acc[c.at(x1, y1)], fx * fy);
      });
    }
  });
  final_[static_cast<size_t>(pool)] = levels[0].acc;
}

void Sssm::combine(int plane) {
  const std::vector<Acc>& front = final_[0];
  const std::vector<Acc>& back = final_[1];
  const Level& L0 = pools_[0][0];
  MomentMap& out = result_[static_cast<size_t>(plane)];
  out.view = view_;
  out.zNear = zNear_;
  out.zFar = zFar_;
  out.warp = warp_;
  out.texels.resize(L0.w, L0.h);
  const raster::Float4 lit = warp_.moments(1.0f);
  forActiveTexels(L0, [&](int x, int y) {
    const Acc& a = front[L0.at(x, y)];
    const Acc& b = back[L0.at(x, y)];
    const auto aw = static_cast<double>(a.w), bw = static_cast<double>(b.w);
    double m[4];
    for (int c = 0; c < 4; ++c) {
      const auto am = static_cast<double>(a.m[c]), bm = static_cast<double>(b.m[c]);
      const auto none = static_cast<double>((&lit.r)[c]);
      if (!set_.coverage)  // Eq. 7: one weighted average of every sample whose circle holds the texel
        m[c] = aw + bw > 0.0 ? (am + bm) / (aw + bw) : none;
      else if (aw >= 1.0)
        m[c] = am / aw;
      else  // the samples in front cover the fraction a.w of the light (each first hit counted once);
            // the rest sees the depths behind the plane (their average), or nothing
        m[c] = am + (1.0 - aw) * (bw > 0.0 ? bm / bw : none);
    }
    out.texels.at(x, y) = {static_cast<float>(m[0]), static_cast<float>(m[1]), static_cast<float>(m[2]),
                           static_cast<float>(m[3])};
  });
}

void Sssm::evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) {
  const auto t0 = Clock::now();
  forEachReceiver(ctx, visibility, [&](int, int, const Receiver& r) {
    const glm::vec3 v = lookupPoint(view_, r, bias_);
    const glm::vec2 pos = view_.toMap(v);
    const auto z = static_cast<double>(receiverDepth(result_[0], v, r.normal, bias_));
    int i0, i1;
    float t;
    bracket(v.z, i0, i1, t);
    double p = evsmBound(result_[static_cast<size_t>(i0)].sample(pos), warp_, z, minVariance_);
    if (t > 0.0f)
      p = (1.0 - static_cast<double>(t)) * p +
          static_cast<double>(t) *
              evsmBound(result_[static_cast<size_t>(i1)].sample(pos), warp_, z, minVariance_);
    return static_cast<float>(reduceLightBleeding(p, bleedReduction_));
  });
  ctx.times.msEvaluate += msSince(t0);
}

std::vector<ParamSpec> sssmParams() {
  std::vector<ParamSpec> p = depthMapParams(512, 0.5, 1.0);
  p.push_back(
      {.name = "planes",
       .kind = ParamKind::Int,
       .defaultValue = 4,
       .minValue = 1,
       .maxValue = 8,
       .choices = {},
       .help = "filter planes over the receivers' depth range (section 7.4; 4: 2 over-blur the shadows of "
               "curved objects on themselves, Fig. 17)"});
  p.push_back(
      choiceParam("spacing", 0, {"inverse", "depth"},
                  "filter planes uniform in 1/depth (the circles of confusion are linear in it) or in depth "
                  "(the paper)"));
  p.push_back(
      {.name = "levels",
       .kind = ParamKind::Int,
       .defaultValue = 2,
       .minValue = 0,
       .maxValue = kMaxLevels,
       .choices = {},
       .help =
           "coarse levels of the multi-resolution filter (section 7.2; 2 as the paper); 0: as many as the "
           "largest circle of confusion needs (no circle cut by the gather radius, more blur from the "
           "resolve)"});
  p.push_back(
      {.name = "strata",
       .kind = ParamKind::Int,
       .defaultValue = 4,
       .minValue = 0,
       .maxValue = 8,
       .choices = {},
       .help = "n: each n x n block of texels takes n^2 different strata of the light (section 7.1); 0 or 1: "
               "an R2 point per texel"});
  p.push_back(choiceParam("bound", 2, {"box", "interval", "dual"},
                          "bounding method of the light-lens rasterization (same map; STE in --stats)"));
  p.push_back(
      choiceParam("centres", 0, {"exact", "texel"},
                  "a sample in front of a plane filters around its hit point seen from the light centre "
                  "(exact), or around the texel its ray crosses (the paper's approximation, section 7.3)"));
  p.push_back(
      choiceParam("estimator", 1, {"coverage", "paper"},
                  "coverage: the samples in front of a plane give the blocked fraction (their circles' "
                  "weights summed), the others the rest; paper: one weighted average of all (Eq. 7)"));
  p.push_back(
      choiceParam("widen", 1, {"off", "on"},
                  "widen each sample's circle to the nearest overlapping nearer sample's (12 Poisson taps "
                  "within 32 texels, then a Gaussian of radius 2; section 5.2)"));
  p.push_back({.name = "widen_max",
               .kind = ParamKind::Float,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1024,
               .choices = {},
               .help = "the widened circle's largest radius, texels (0: none, the paper)"});
  p.push_back(
      choiceParam("interleave", 0, {"off", "on"},
                  "interleaved sampling: each texel gathers every second sample per axis (section 7.3)"));
  p.push_back(
      choiceParam("box", 1, {"off", "on"}, "a 3 x 3 box of each level's own sums in the resolve (Fig. 10)"));
  p.push_back(choiceParam("active_tiles", 1, {"off", "on"},
                          "filter only the tiles the receivers read (section 7.5; the image is the same)"));
  p.push_back({.name = "frame",
               .kind = ParamKind::Int,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1 << 20,
               .choices = {},
               .help = "seeds the light samples (another frame, other samples)"});
  p.push_back({.name = "exponent_pos",
               .kind = ParamKind::Float,
               .defaultValue = 40,
               .minValue = 0,
               .maxValue = 42,
               .choices = {},
               .help = "EVSM c+ (moments.h: <= 42 keeps exp(2 c+) below FLT_MAX)"});
  p.push_back({.name = "exponent_neg",
               .kind = ParamKind::Float,
               .defaultValue = 5,
               .minValue = 0,
               .maxValue = 42,
               .choices = {},
               .help = "EVSM c-"});
  for (ParamSpec& s : chebyshevParams(1e-7)) {
    // 0.1: the bound of a filtered mixture is never exactly 0 (min_variance); this makes umbrae 0.
    if (s.name == "bleed_reduction") s.defaultValue = 0.1;
    p.push_back(std::move(s));
  }
  return p;
}

}  // namespace

TechniqueInfo sssmTechnique() {
  return {.name = "sssm",
          .summary =
              "stochastic soft shadow map: the light as the lens of the stochastic rasterizer, EVSM moments "
              "pre-filtered per filter plane with per-sample circles of confusion",
          .params = sssmParams(),
          .benchSettings = {"", "planes=2", "planes=8"},
          .isReference = false,
          .make = [] { return std::make_unique<Sssm>(); },
          .peakBytes = [](const ParamSet& params, uint64_t) -> uint64_t {
            // Twice map_size per side at most (widenedView); per texel the samples (depth, light
            // point, moments, triangle, rasterizer depth, resolved pixel: ~100 B), the plane being
            // built (two pools of texels 28 B and sums 20 B, 4/3 for the coarse levels; the
            // resolved sums of both, a copy for the box, the destinations: ~196 B) and per plane
            // the result (16 B).
            const auto side = static_cast<uint64_t>(2 * params.integer("map_size"));
            const uint64_t texels = side * side;
            const auto planes = static_cast<uint64_t>(params.integer("planes"));
            return texels * (100 + 196 + 16 * planes);
          },
          .samplesTime = true};
}

}  // namespace penumbra::shadows
