#include "shadows/vwss.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "raster/splat.h"
#include "shadows/light_samples.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

// The PCF of each map: the texel alone, or with its 4 neighbours (offsets in texels).
constexpr glm::vec2 kFiveTaps[5] = {{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}};

// Faces turned away from the light, in the light's views. Those views mirror the usual camera
// (right x up is the viewing direction, light_view.h), so counter-clockwise faces turned towards
// the light appear clockwise there: "back" in the world is "front" in these views.
raster::CullMode sourceCull(bool cullBackFaces) {
  return cullBackFaces ? raster::CullMode::Front : raster::CullMode::None;
}

// The source view's draw: back faces culled, depth test off (allLayers) or on, world position as
// varyings; fs gets every fragment that passes.
template <class FS>
raster::PassStats drawSource(raster::Rasterizer& raster, const Geometry& casters, const LightView& source,
                             bool allLayers, raster::CullMode cull, FS&& fs) {
  raster::DepthTarget depth(source.width, source.height, 0.0f);
  raster.clear(depth, 0.0f);
  const glm::vec3* pos = casters.positions.data();
  raster::DrawDesc desc;
  desc.vertexCount = static_cast<uint32_t>(casters.positions.size());
  desc.indices = casters.indices;
  desc.varyings = 3;
  desc.cull = cull;
  desc.depthFunc = allLayers ? raster::DepthFunc::Always : raster::DepthFunc::Greater;
  desc.depthWrite = !allLayers;
  const glm::mat4 m = source.viewProj;
  return raster.draw(
      desc, depth,
      [&](uint32_t i, float* v) {
        v[0] = pos[i].x, v[1] = pos[i].y, v[2] = pos[i].z;
        return m * glm::vec4(pos[i], 1.0f);
      },
      fs);
}

class Vwss final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    size_ = params.integer("map_size");
    samples_ = interleavedLightSamples(ctx.in.light, params.integer("views"), params.integer("interleave"));
    const std::vector<glm::vec2>& points_ = samples_.points;
    perPass_ = params.integer("views_per_pass");
    if (perPass_ == 0 || perPass_ > static_cast<int>(points_.size())) perPass_ = static_cast<int>(points_.size());
    taps_ = params.choice("pcf") == "5" ? 5 : 1;
    buffered_ = params.choice("mode") == "buffered";
    allLayers_ = params.choice("layers") == "all";
    containing_ = params.choice("containing") == "on";
    cullBack_ = params.choice("cull") == "back";
    maxSource_ = params.integer("max_source");
    znear_ = ctx.nearPlane();
    const LightView centre = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), znear_, size_, size_);
    // Oversampling the source view: a point lands in one texel of each map, and a map texel that
    // no point lands in is a hole; Eq. 3 matches the texel sizes only for surfaces facing both views.
    const float over = static_cast<float>(params.number("oversample"));
    LightView scaled = centre;
    scaled.width = std::clamp(static_cast<int>(std::ceil(static_cast<float>(size_) * over)), 16, maxSource_);
    scaled.height = scaled.width;
    source_ = containing_ ? makeContainingView(ctx.in.light, ctx.region, scaled, znear_, maxSource_)
                          : makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), znear_, scaled.width, scaled.height);
    if (buffered_) {
      const auto t0 = Clock::now();
      generatePoints(ctx, nullptr);
      ctx.times.msMaps += msSince(t0);
    }
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    LightSampleTests tests;
    tests.prepare(ctx, bias_, samples_.k);
    const std::vector<glm::vec2>& points_ = samples_.points;
    ctx.times.msEvaluate += msSince(t0);
    const int m = static_cast<int>(points_.size());
    std::vector<raster::Image<uint64_t>> keys(static_cast<size_t>(perPass_));
    std::vector<raster::SplatView> views(static_cast<size_t>(perPass_));
    ShadowMap map;
    uint64_t written = 0;
    size_t generated = 0;
    int passes = 0;
    for (int first = 0; first < m; first += perPass_) {
      const int count = std::min(perPass_, m - first);
      // Depth maps of this pass: clear, splat, (resolve below, one at a time).
      const auto t1 = Clock::now();
      for (int k = 0; k < count; ++k) {
        const LightView v = makeLightView(ctx.in.light, ctx.region, points_[static_cast<size_t>(first + k)], znear_,
                                          size_, size_);
        keys[static_cast<size_t>(k)].resize(v.width, v.height);
        ctx.raster.run([&] { raster::clearKeys(keys[static_cast<size_t>(k)]); });
        views[static_cast<size_t>(k)] = {v.viewProj, &keys[static_cast<size_t>(k)]};
      }
      const std::span<const raster::SplatView> pass(views.data(), static_cast<size_t>(count));
      if (buffered_) {
        raster::SplatStats st;
        ctx.raster.run([&] {
          st = raster::splatPoints(cloud_, payload_, pass, raster::DepthKey::ReversedZOverW, 0, ctx.raster.config().simd.splat);
        });
        written += st.written;
      } else {
        generated = generatePoints(ctx, &pass);
      }
      ++passes;
      ctx.times.msMaps += msSince(t1);
      for (int k = 0; k < count; ++k) {
        const auto t2 = Clock::now();
        const glm::vec2 lp = points_[static_cast<size_t>(first + k)];
        map.view = makeLightView(ctx.in.light, ctx.region, lp, znear_, size_, size_);
        map.depth.resize(map.view.width, map.view.height, 0.0f);
        ctx.raster.run([&] {
          raster::resolveDepth(keys[static_cast<size_t>(k)], raster::DepthKey::ReversedZOverW, map.depth.image(), 0.0f);
        });
        map.prepareLookup();
        ctx.times.msMaps += msSince(t2);
        const auto t3 = Clock::now();
        tests.accumulate(ctx, map, lp, std::span<const glm::vec2>(kFiveTaps, static_cast<size_t>(taps_)),
                         samples_.k > 1 ? samples_.subset[static_cast<size_t>(first + k)] : -1);
        ctx.times.msEvaluate += msSince(t3);
      }
    }
    const auto t4 = Clock::now();
    tests.finish(ctx, taps_, samples_, visibility);
    ctx.times.msEvaluate += msSince(t4);
    const size_t pointCount = buffered_ ? cloud_.size() : generated;
    ctx.notes.push_back("vwss: " + std::string(buffered_ ? "buffered" : "unbuffered") + ", " +
                        std::to_string(pointCount) + " points from " + std::to_string(ctx.casters.trianglesKept()) +
                        " triangles (source view " + std::to_string(source_.width) + "x" +
                        std::to_string(source_.height) + (containing_ ? ", containing the light" : ", on the light") +
                        (allLayers_ ? ", every layer" : ", nearest layer only") + (cullBack_ ? ", back faces culled" : "") + "), " + std::to_string(m) +
                        " maps " + std::to_string(size_) + "^2 in " + std::to_string(passes) + " passes of up to " +
                        std::to_string(perPass_) + ", " + std::to_string(taps_) + " taps per map");
  }

 private:
  // Buffered: the point cloud. Unbuffered (pass given): the same fragments splatted straight into
  // the pass's maps. Returns the number of points.
  size_t generatePoints(ShadowContext& ctx, const std::span<const raster::SplatView>* pass) {
    if (!pass || !allLayers_) {
      LightPoints lp = generateLightPoints(ctx.raster, ctx.casterGeometry(), source_, allLayers_, cullBack_);
      ctx.mapPasses += lp.pass;
      cloud_ = std::move(lp.points);
      payload_ = std::move(lp.payloads);
      if (pass)
        ctx.raster.run([&] {
          raster::splatPoints(cloud_, payload_, *pass, raster::DepthKey::ReversedZOverW, 0, ctx.raster.config().simd.splat);
        });
      return cloud_.size();
    }
    raster::PointSplatter splatter(*pass, raster::DepthKey::ReversedZOverW, ctx.raster.config().simd.splat);
    const uint32_t w = static_cast<uint32_t>(source_.width);
    ctx.mapPasses += drawSource(ctx.raster, ctx.casterGeometry(), source_, true, sourceCull(cullBack_), [&](const raster::Fragment& f) {
      splatter.add(glm::vec3(f.varyings[0], f.varyings[1], f.varyings[2]),
                   static_cast<uint32_t>(f.y) * w + static_cast<uint32_t>(f.x));
    });
    splatter.flush();
    return static_cast<size_t>(splatter.points());
  }

  BiasParams bias_;
  int size_ = 0, perPass_ = 0, taps_ = 5, maxSource_ = 8192;
  bool buffered_ = true, allLayers_ = true, containing_ = true, cullBack_ = false;
  float znear_ = 0;
  LightView source_;
  LightSampleSet samples_;
  std::vector<glm::vec3> cloud_;
  std::vector<uint32_t> payload_;
};

}  // namespace

LightPoints generateLightPoints(raster::Rasterizer& raster, const Geometry& casters, const LightView& source,
                                bool allLayers, bool cullBackFaces) {
  const raster::CullMode cull = sourceCull(cullBackFaces);
  LightPoints out;
  const int w = source.width, h = source.height;
  if (!allLayers) {
    // The last fragment that passed the depth test at a texel is the nearest (fragments reach a
    // texel in submission order, each tile in one task).
    std::vector<glm::vec4> nearest(static_cast<size_t>(w) * static_cast<size_t>(h), glm::vec4(0.0f));
    out.pass = drawSource(raster, casters, source, false, cull, [&](const raster::Fragment& f) {
      nearest[static_cast<size_t>(f.y) * static_cast<size_t>(w) + static_cast<size_t>(f.x)] =
          glm::vec4(f.varyings[0], f.varyings[1], f.varyings[2], 1.0f);
    });
    for (size_t i = 0; i < nearest.size(); ++i)
      if (nearest[i].w != 0.0f) {
        out.points.emplace_back(nearest[i]);
        out.payloads.push_back(static_cast<uint32_t>(i));
      }
    return out;
  }
  // Every layer: per-tile lists (each tile is one task, the fragment says which), joined in tile
  // order.
  const raster::TileGrid grid = raster.tileGrid(w, h);
  std::vector<std::vector<glm::vec3>> tilePoints(grid.count());
  std::vector<std::vector<uint32_t>> tilePayload(tilePoints.size());
  out.pass = drawSource(raster, casters, source, true, cull, [&](const raster::Fragment& f) {
    tilePoints[f.tile].emplace_back(f.varyings[0], f.varyings[1], f.varyings[2]);
    tilePayload[f.tile].push_back(static_cast<uint32_t>(f.y) * static_cast<uint32_t>(w) + static_cast<uint32_t>(f.x));
  });
  size_t total = 0;
  for (const auto& t : tilePoints) total += t.size();
  out.points.reserve(total);
  out.payloads.reserve(total);
  for (size_t t = 0; t < tilePoints.size(); ++t) {
    out.points.insert(out.points.end(), tilePoints[t].begin(), tilePoints[t].end());
    out.payloads.insert(out.payloads.end(), tilePayload[t].begin(), tilePayload[t].end());
  }
  return out;
}

TechniqueInfo vwssTechnique() {
  std::vector<ParamSpec> p = depthMapParams(512, 0.5, 0.5);  // splatted maps: more bias than mvr (docs/techniques/vwss.md)
  p.push_back({.name = "views", .kind = ParamKind::Int, .defaultValue = 64, .minValue = 1, .maxValue = 1024,
               .choices = {}, .help = "depth maps, from the same stratified light points as mvr"});
  p.push_back(interleaveParam());
  p.push_back({.name = "views_per_pass", .kind = ParamKind::Int, .defaultValue = 16, .minValue = 0, .maxValue = 1024,
               .choices = {}, .help = "maps splatted per traversal of the points (K; 0 = all: fully parallel)"});
  p.push_back({.name = "pcf", .kind = ParamKind::Choice, .defaultValue = 1, .minValue = 0, .maxValue = 1,
               .choices = {"1", "5"}, .help = "taps per map: the texel, or the texel and its 4 neighbours"});
  p.push_back({.name = "mode", .kind = ParamKind::Choice, .defaultValue = 0, .minValue = 0, .maxValue = 1,
               .choices = {"buffered", "unbuffered"},
               .help = "store the points then splat, or splat each fragment as it is rasterized"});
  p.push_back({.name = "layers", .kind = ParamKind::Choice, .defaultValue = 0, .minValue = 0, .maxValue = 1,
               .choices = {"all", "nearest"},
               .help = "every front-facing fragment (the paper), or the nearest only (naive warping: leaks)"});
  p.push_back({.name = "containing", .kind = ParamKind::Choice, .defaultValue = 1, .minValue = 0, .maxValue = 1,
               .choices = {"off", "on"},
               .help = "source view behind the light containing it (the paper), or on its centre (leaks at the border)"});
  p.push_back({.name = "cull", .kind = ParamKind::Choice, .defaultValue = 0, .minValue = 0, .maxValue = 1,
               .choices = {"none", "back"},
               .help = "cull faces turned away from the light when generating points (halves them; closed meshes only)"});
  p.push_back({.name = "oversample", .kind = ParamKind::Float, .defaultValue = 1, .minValue = 0.25, .maxValue = 8,
               .choices = {}, .help = "source view resolution over Eq. 3's, per axis (more: fewer holes, more bloat)"});
  p.push_back({.name = "max_source", .kind = ParamKind::Int, .defaultValue = 8192, .minValue = 16, .maxValue = 16384,
               .choices = {}, .help = "largest side of the source view, texels"});
  return {.name = "vwss",
          .summary = "view-warped multi-view soft shadows: one rasterization into points, splatted into N maps",
          .params = std::move(p),
          .benchSettings = {"views=24", "", "views=128", "views=128,mode=unbuffered,views_per_pass=128"},
          .isReference = false,
          .make = [] { return std::make_unique<Vwss>(); },
          // 64-bit keys of one pass of maps, one float map, and the points (a source view up to
          // max_source^2 texels, a few layers of 16 bytes each).
          .peakBytes = [](const ParamSet& q, uint64_t) {
            const uint64_t size = static_cast<uint64_t>(q.integer("map_size"));
            uint64_t pass = static_cast<uint64_t>(q.integer("views_per_pass"));
            if (pass == 0) pass = static_cast<uint64_t>(q.integer("views"));
            const uint64_t source = static_cast<uint64_t>(q.integer("max_source"));
            return pass * size * size * 8 + size * size * 4 + std::min<uint64_t>(source * source, size * size * 64) * 64;
          }};
}

}  // namespace penumbra::shadows
