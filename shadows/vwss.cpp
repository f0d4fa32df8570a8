#include "shadows/vwss.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "raster/splat.h"
#include "shadows/light_samples.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

// The source view's draws (casterDraws: one, or the closed meshes' with their back faces culled
// and the rest), the depth test off (allLayers) or on, world position as varyings, into one depth
// target; before(the draw's geometry) runs before each draw, fs(fragment, the draw's geometry)
// gets every fragment that passes. With the test off nothing is written to the target, which the
// pipeline still reads (its coarse depth): one the size of the source view, cleared once.
template <class FS, class Before>
raster::PassStats drawSource(raster::Rasterizer& raster, const Geometry& casters, const LightView& source,
                             const RectLight& light, bool allLayers, CasterCull cull, FS&& fs,
                             Before&& before) {
  raster::DepthTarget depth(source.width, source.height, 0.0f);
  const glm::vec3* pos = casters.positions.data();
  const glm::mat4 m = source.viewProj;
  raster::PassStats stats;
  const std::vector<CasterDraw> draws = casterDraws(casters, cull, &light);
  for (const CasterDraw& d : draws) {
    const Geometry g = d.geometry(casters.positions);
    before(g);
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(casters.positions.size());
    desc.indices = d.indices;
    desc.varyings = 3;
    desc.cull = d.cull;
    desc.depthFunc = allLayers ? raster::DepthFunc::Always : raster::DepthFunc::Greater;
    desc.depthWrite = !allLayers;
    stats += raster.draw(
        desc, depth,
        [&](uint32_t i, float* v) {
          v[0] = pos[i].x, v[1] = pos[i].y, v[2] = pos[i].z;
          return m * glm::vec4(pos[i], 1.0f);
        },
        [&](const raster::Fragment& f) { fs(f, g); });
  }
  return stats;
}

// The surfel of the source pixel (x, y) on triangle t of `g` (raster/splat.h, SurfelAxes): the
// pixel's footprint on the triangle's plane, u between its left and right edges' rays, v between
// its top and bottom edges', each ray through the edge's middle (tangent coordinates as
// LightView::toMap inverts them). A plane seen at a grazing angle stretches the footprint without
// bound; each edge vector is kept within kMaxFootprint pixel sizes at the point's depth (and one
// that is not finite becomes the pixel's own square there).
raster::SurfelAxes surfelOf(const LightView& src, const Geometry& g, uint32_t t, int x, int y, glm::vec3 p) {
  constexpr float kMaxFootprint = 8.0f;
  const glm::vec3 a = g.positions[g.indices[3 * t]], b = g.positions[g.indices[3 * t + 1]],
                  c = g.positions[g.indices[3 * t + 2]];
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float k = glm::dot(n, a - src.origin);
  const glm::vec2 texel((src.tanHi.x - src.tanLo.x) / static_cast<float>(src.width),
                        (src.tanHi.y - src.tanLo.y) / static_cast<float>(src.height));
  const auto hit = [&](float px, float py) {  // the plane's point on the ray through map point (px, py)
    const glm::vec3 dir =
        src.right * (src.tanLo.x + px * texel.x) + src.up * (src.tanHi.y - py * texel.y) + src.axis;
    return src.origin + dir * (k / glm::dot(n, dir));
  };
  const float fx = static_cast<float>(x), fy = static_cast<float>(y);
  glm::vec3 u = hit(fx + 1.0f, fy + 0.5f) - hit(fx, fy + 0.5f);
  glm::vec3 v = hit(fx + 0.5f, fy + 1.0f) - hit(fx + 0.5f, fy);
  const float depth = glm::dot(p - src.origin, src.axis);
  const float limitU = kMaxFootprint * depth * texel.x, limitV = kMaxFootprint * depth * texel.y;
  const auto bound = [](glm::vec3 e, float limit, glm::vec3 own) {
    const float len = glm::length(e);
    if (!std::isfinite(len)) return own;
    return len > limit ? e * (limit / len) : e;
  };
  u = bound(u, limitU, src.right * (depth * texel.x));
  v = bound(v, limitV, -src.up * (depth * texel.y));
  return {u, v};
}

// The source view's side before Eq. 3: the map side times `oversample`.
int oversampledSide(int mapSize, float oversample) {
  return std::max(16, static_cast<int>(std::ceil(static_cast<float>(mapSize) * oversample)));
}
// max_source's automatic value: twice that side.
int autoMaxSource(int oversampled) {
  return std::min(16384, 2 * oversampled);
}

class Vwss final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    size_ = params.integer("map_size");
    samples_ = lightSamples(ctx.in.light, params.integer("views"), params.integer("interleave"),
                            params.choice("samples"));
    perPass_ = params.integer("views_per_pass");
    if (perPass_ == 0 || perPass_ > static_cast<int>(samples_.points.size()))
      perPass_ = static_cast<int>(samples_.points.size());
    taps_ = params.choice("pcf") == "5" ? 5 : 1;
    buffered_ = params.choice("mode") == "buffered";
    allLayers_ = params.choice("layers") == "all";
    containing_ = params.choice("containing") == "on";
    cull_ = casterCull(params);
    surfels_ = params.choice("splat") == "surfel";
    znear_ = ctx.nearPlane();
    fitCasters_ = params.choice("fit") == "casters";
    const LightView centre = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), znear_, size_, size_,
                                           glm::vec2(0.0f), fitCasters_ ? &ctx.casters : nullptr);
    // Oversampling the source view: a point lands in one texel of each map, and a map texel that
    // no point lands in is a hole; Eq. 3 matches the texel sizes only for surfaces facing both views.
    const float over = static_cast<float>(params.number("oversample"));
    LightView scaled = centre;
    scaled.width = oversampledSide(size_, over);
    // The containing view's Eq. 3 grows with (near + D) / near: a caster just below the light
    // asks for a source view far finer than the maps can use. Auto caps it at twice the
    // oversampled map side (the bench scenes need at most 1.7 times).
    maxSource_ = params.integer("max_source");
    maxSource_ = maxSource_ == 0 ? autoMaxSource(scaled.width) : std::max(16, maxSource_);  // 1..15: 16
    scaled.width = std::min(scaled.width, maxSource_);
    scaled.height = scaled.width;
    source_ = containing_ ? makeContainingView(ctx.in.light, ctx.region, scaled, znear_, maxSource_)
                          : makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), znear_, scaled.width,
                                          scaled.height);
    if (buffered_) {
      const auto t0 = Clock::now();
      LightPoints lp = generateLightPoints(ctx.raster, ctx.casterGeometry(), source_, ctx.in.light,
                                           allLayers_, cull_, surfels_);
      ctx.mapPasses += lp.pass;
      cloud_ = std::move(lp.points);
      axes_ = std::move(lp.surfels);
      const double ms = msSince(t0);
      ctx.times.msMaps += ms;
      ctx.times.msPoints += ms;
    }
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    LightSampleTests tests;
    tests.prepare(ctx, bias_, samples_.k);
    ctx.times.msEvaluate += msSince(t0);
    const std::vector<glm::vec2>& points = samples_.points;
    const int m = static_cast<int>(points.size());
    // The maps of one pass, reused pass after pass: depth bits (raster/splat.h, splatDepth), read
    // in place by the tests. A new map is all 0 (empty); after a pass only the rectangle its points
    // touched is cleared again.
    const auto t1 = Clock::now();
    std::vector<raster::Image<uint32_t>> maps(static_cast<size_t>(perPass_));
    ctx.raster.run([&] {
      tbb::parallel_for(size_t{0}, maps.size(), [&](size_t i) {
        maps[i].resize(size_, size_, raster::emptyDepthBits(raster::DepthKey::ReversedZOverW));
      });
    });
    std::vector<raster::SplatRect> touched(maps.size());
    std::vector<LightView> views(maps.size());
    std::vector<raster::DepthSplatView> splat(maps.size());
    std::vector<SampleMap> group(maps.size());
    const double msAlloc = msSince(t1);
    ctx.times.msMaps += msAlloc;
    ctx.times.msSplat += msAlloc;
    uint64_t written = 0;
    size_t generated = 0;
    int passes = 0;
    const std::span<const glm::vec2> taps(kPcfTaps, static_cast<size_t>(taps_));
    for (int first = 0; first < m; first += perPass_) {
      const int count = std::min(perPass_, m - first);
      const auto t2 = Clock::now();
      for (int k = 0; k < count; ++k) {
        const size_t i = static_cast<size_t>(k);
        views[i] = makeLightView(ctx.in.light, ctx.region, points[static_cast<size_t>(first + k)], znear_,
                                 size_, size_, glm::vec2(0.0f), fitCasters_ ? &ctx.casters : nullptr);
        if (maps[i].width() != views[i].width ||
            maps[i].height() != views[i].height) {  // not for fitted views
          maps[i].resize(views[i].width, views[i].height,
                         raster::emptyDepthBits(raster::DepthKey::ReversedZOverW));
          touched[i] = {};
        }
        splat[i] = {views[i].viewProj, &maps[i]};
      }
      if (first > 0)  // what the previous pass wrote, map by map in parallel
        ctx.raster.run([&] {
          tbb::parallel_for(size_t{0}, maps.size(), [&](size_t i) {
            raster::clearDepthBits(maps[i], raster::DepthKey::ReversedZOverW, &touched[i]);
          });
        });
      const std::span<const raster::DepthSplatView> pass(splat.data(), static_cast<size_t>(count));
      const std::span<raster::SplatRect> passTouched(touched.data(), static_cast<size_t>(count));
      if (buffered_) {
        raster::SplatStats st;
        ctx.raster.run([&] {
          st = raster::splatDepth(cloud_, axes_, pass, raster::DepthKey::ReversedZOverW, 0,
                                  ctx.raster.config().simd.splat, passTouched);
        });
        written += st.written;
        const double ms = msSince(t2);
        ctx.times.msMaps += ms;
        ctx.times.msSplat += ms;
      } else {
        generated = splatFragments(ctx, pass, passTouched);
        ctx.times.msMaps += msSince(t2);
      }
      ++passes;
      for (int k = 0; k < count; ++k)  // the sides cut to the casters read empty (light_view.h)
        clearCasterCutBorder(views[static_cast<size_t>(k)], maps[static_cast<size_t>(k)],
                             raster::emptyDepthBits(raster::DepthKey::ReversedZOverW));
      const auto t3 = Clock::now();
      for (int k = 0; k < count; ++k) {
        const size_t i = static_cast<size_t>(k);
        group[i] = SampleMap::ofBits(views[i], maps[i], points[static_cast<size_t>(first + k)],
                                     samples_.k > 1 ? samples_.subset[static_cast<size_t>(first + k)] : -1);
      }
      tests.accumulate(ctx, std::span<const SampleMap>(group.data(), static_cast<size_t>(count)), taps);
      ctx.times.msEvaluate += msSince(t3);
    }
    const auto t4 = Clock::now();
    tests.finish(ctx, taps_, samples_, visibility);
    ctx.times.msEvaluate += msSince(t4);
    const size_t pointCount = buffered_ ? cloud_.size() : generated;
    ctx.notes.push_back(
        "vwss: " + std::string(buffered_ ? "buffered" : "unbuffered") + ", " + std::to_string(pointCount) +
        (surfels_ ? " surfels" : " points") + " from " + std::to_string(ctx.casters.trianglesKept()) +
        " triangles (source view " + std::to_string(source_.width) + "x" + std::to_string(source_.height) +
        (containing_ ? ", containing the light" : ", on the light") +
        (std::max(source_.width, source_.height) >= maxSource_
             ? ", capped at " + std::to_string(maxSource_) +
                   " (max_source): casters near the light get coarser points"
             : std::string()) +
        (allLayers_ ? ", every layer" : ", nearest layer only") +
        (cull_ == CasterCull::Back   ? ", faces turned away from the whole light culled"
         : cull_ == CasterCull::Auto ? ", closed meshes' faces turned away from the whole light culled"
                                     : "") +
        "), " + std::to_string(m) + " maps " + std::to_string(size_) +
        "^2 of 32-bit depth read in place, in " + std::to_string(passes) + " passes of up to " +
        std::to_string(perPass_) + ", " + std::to_string(taps_) + " taps per map");
  }

 private:
  // Unbuffered: the source view's fragments splatted straight into the pass's maps as they are
  // rasterized (the point generation repeated per pass). Returns the number of points.
  size_t splatFragments(ShadowContext& ctx, std::span<const raster::DepthSplatView> pass,
                        std::span<raster::SplatRect> passTouched) {
    const Geometry g = ctx.casterGeometry();
    if (!allLayers_) {  // the nearest layer only: the points first, then splatted
      LightPoints lp = generateLightPoints(ctx.raster, g, source_, ctx.in.light, false, cull_, surfels_);
      ctx.mapPasses += lp.pass;
      ctx.raster.run([&] {
        raster::splatDepth(lp.points, lp.surfels, pass, raster::DepthKey::ReversedZOverW, 0,
                           ctx.raster.config().simd.splat, passTouched);
      });
      return lp.points.size();
    }
    raster::DepthSplatter splatter(pass, raster::DepthKey::ReversedZOverW, surfels_,
                                   ctx.raster.config().simd.splat);
    ctx.mapPasses += drawSource(
        ctx.raster, g, source_, ctx.in.light, true, cull_,
        [&](const raster::Fragment& f, const Geometry& drawn) {
          const glm::vec3 p(f.varyings[0], f.varyings[1], f.varyings[2]);
          splatter.add(p,
                       surfels_ ? surfelOf(source_, drawn, f.primitive, f.x, f.y, p) : raster::SurfelAxes{});
        },
        [](const Geometry&) {});
    splatter.flush();
    for (size_t v = 0; v < pass.size(); ++v) passTouched[v] = splatter.touched(v);
    return static_cast<size_t>(splatter.points());
  }

  BiasParams bias_;
  int size_ = 0, perPass_ = 0, taps_ = 5, maxSource_ = 0;
  bool buffered_ = true, allLayers_ = true, containing_ = true, surfels_ = true, fitCasters_ = true;
  CasterCull cull_ = CasterCull::None;
  float znear_ = 0;
  LightView source_;
  LightSampleSet samples_;
  std::vector<glm::vec3> cloud_;
  std::vector<raster::SurfelAxes> axes_;
};

}  // namespace

LightPoints generateLightPoints(raster::Rasterizer& raster, const Geometry& casters, const LightView& source,
                                const RectLight& light, bool allLayers, CasterCull cull, bool surfels) {
  LightPoints out;
  const int w = source.width, h = source.height;
  if (!allLayers) {
    // The last fragment that passed the depth test at a texel is the nearest (fragments reach a
    // texel in submission order, each tile in one task), and its triangle.
    const size_t texels = static_cast<size_t>(w) * static_cast<size_t>(h);
    std::vector<glm::vec4> nearest(texels, glm::vec4(0.0f));
    std::vector<raster::SurfelAxes> axes(surfels ? texels : 0);
    out.pass = drawSource(
        raster, casters, source, light, false, cull,
        [&](const raster::Fragment& f, const Geometry& drawn) {
          const size_t i = static_cast<size_t>(f.y) * static_cast<size_t>(w) + static_cast<size_t>(f.x);
          nearest[i] = glm::vec4(f.varyings[0], f.varyings[1], f.varyings[2], 1.0f);
          if (surfels) axes[i] = surfelOf(source, drawn, f.primitive, f.x, f.y, glm::vec3(nearest[i]));
        },
        [](const Geometry&) {});
    for (size_t i = 0; i < texels; ++i)
      if (nearest[i].w != 0.0f) {
        out.points.emplace_back(nearest[i]);
        out.payloads.push_back(static_cast<uint32_t>(i));
        if (surfels) out.surfels.push_back(axes[i]);
      }
    return out;
  }
  // Every layer: per-tile lists (each tile is one task, the fragment says which), joined in tile
  // order.
  const raster::TileGrid grid = raster.tileGrid(w, h);
  struct TilePoints {
    std::vector<glm::vec3> points;
    std::vector<raster::SurfelAxes> surfels;
    std::vector<uint32_t> payloads;
  };
  // Per draw, its tiles' points are joined in tile order, then the next draw's.
  std::vector<TilePoints> tiles;
  size_t drawFirst = 0;
  bool started = false;
  out.pass = drawSource(
      raster, casters, source, light, true, cull,
      [&](const raster::Fragment& f, const Geometry& drawn) {
        TilePoints& t = tiles[drawFirst + f.tile];
        t.points.emplace_back(f.varyings[0], f.varyings[1], f.varyings[2]);
        t.payloads.push_back(static_cast<uint32_t>(f.y) * static_cast<uint32_t>(w) +
                             static_cast<uint32_t>(f.x));
        if (surfels) t.surfels.push_back(surfelOf(source, drawn, f.primitive, f.x, f.y, t.points.back()));
      },
      [&](const Geometry&) {  // before each draw: its own tile lists
        if (started) drawFirst += grid.count();
        started = true;
        tiles.resize(drawFirst + grid.count());
      });
  size_t total = 0;
  for (const TilePoints& t : tiles) total += t.points.size();
  out.points.reserve(total);
  out.payloads.reserve(total);
  out.surfels.reserve(surfels ? total : 0);
  for (const TilePoints& t : tiles) {
    out.points.insert(out.points.end(), t.points.begin(), t.points.end());
    out.payloads.insert(out.payloads.end(), t.payloads.begin(), t.payloads.end());
    out.surfels.insert(out.surfels.end(), t.surfels.begin(), t.surfels.end());
  }
  return out;
}

TechniqueInfo vwssTechnique() {
  std::vector<ParamSpec> p =
      depthMapParams(512, 0.5, 0.3);  // splatted maps: more constant bias than mvr (docs/techniques/vwss.md)
  p.push_back({.name = "views",
               .kind = ParamKind::Int,
               .defaultValue = 64,
               .minValue = 1,
               .maxValue = 1024,
               .choices = {},
               .help = "depth maps, from the same stratified light points as mvr"});
  p.push_back(interleaveParam());
  p.push_back({.name = "views_per_pass",
               .kind = ParamKind::Int,
               .defaultValue = 8,
               .minValue = 0,
               .maxValue = 1024,
               .choices = {},
               .help = "maps splatted per traversal of the points and kept for the tests together (K; "
                       "0 = all: fully parallel)"});
  p.push_back(choiceParam(
      "pcf", 0, {"1", "5"},
      "taps per map: the texel (as mvr), or the texel and its 4 neighbours (the paper's 5-tap PCF)"));
  p.push_back({.name = "mode",
               .kind = ParamKind::Choice,
               .defaultValue = 0,
               .minValue = 0,
               .maxValue = 1,
               .choices = {"buffered", "unbuffered"},
               .help = "store the points then splat, or splat each fragment as it is rasterized"});
  p.push_back(
      {.name = "layers",
       .kind = ParamKind::Choice,
       .defaultValue = 0,
       .minValue = 0,
       .maxValue = 1,
       .choices = {"all", "nearest"},
       .help = "every front-facing fragment (the paper), or the nearest only (naive warping: leaks)"});
  p.push_back(
      {.name = "containing",
       .kind = ParamKind::Choice,
       .defaultValue = 1,
       .minValue = 0,
       .maxValue = 1,
       .choices = {"off", "on"},
       .help =
           "source view behind the light containing it (the paper), or on its centre (leaks at the border)"});
  p.push_back(casterCullParam(2));
  p.push_back({.name = "oversample",
               .kind = ParamKind::Float,
               .defaultValue = 1.5,
               .minValue = 0.25,
               .maxValue = 8,
               .choices = {},
               .help = "source view resolution over Eq. 3's, per axis (surfels: finer outlines, more "
                       "points; points: fewer holes, more bloat)"});
  p.push_back(
      {.name = "max_source",
       .kind = ParamKind::Int,
       .defaultValue = 0,
       .minValue = 0,
       .maxValue = 16384,
       .choices = {},
       .help = "largest side of the source view, texels, at least 16 (0: twice the oversampled map side); "
               "past it both sides shrink alike"});
  p.push_back(choiceParam(
      "splat", 0, {"surfel", "point"},
      "what a point writes: its source pixel's footprint, at the texel centres it covers with its "
      "plane's depth there (surfel), or its own depth in the texel it falls in (point, the paper)"));
  p.push_back(samplePatternParam());
  // Fitted to the receivers: cut to the casters, Eq. 3 asks the source view for the maps' finer
  // texels, 3-10 times the surfels (docs/techniques/vwss.md).
  p.push_back(mapFitParam(0));
  return {
      .name = "vwss",
      .summary = "view-warped multi-view soft shadows: one rasterization into points, splatted into N maps",
      .params = std::move(p),
      // views=128,splat=point: the paper's splat alone; the last two: the paper's method whole
      // (its splat, 5-tap PCF, Poisson-disk samples), against mvr's same variant. A point's depth
      // is its own, off the texel centre by up to half a texel times the slope: the point splat
      // keeps the slope bias of 0.5 it was measured with (docs/techniques/vwss.md, Bias).
      .benchSettings = {"views=24", "", "views=128", "views=128,splat=point,slope_bias=0.5",
                        "views=24,splat=point,pcf=5,samples=poisson,slope_bias=0.5",
                        "views=128,splat=point,pcf=5,samples=poisson,slope_bias=0.5"},
      .isReference = false,
      .make = [] { return std::make_unique<Vwss>(); },
      // One pass of 32-bit maps and the points (a source view up to max_source^2 texels, a few
      // layers of them; per point its position, surfel axes, payload and the splat's transposed
      // copy, about 100 bytes).
      .peakBytes =
          [](const ParamSet& q, uint64_t) {
            const uint64_t size = static_cast<uint64_t>(q.integer("map_size"));
            uint64_t pass = static_cast<uint64_t>(q.integer("views_per_pass"));
            if (pass == 0) pass = static_cast<uint64_t>(q.integer("views"));
            uint64_t source = static_cast<uint64_t>(q.integer("max_source"));
            if (source == 0)
              source = static_cast<uint64_t>(autoMaxSource(
                  oversampledSide(q.integer("map_size"), static_cast<float>(q.number("oversample")))));
            return pass * size * size * 4 + std::min<uint64_t>(source * source, size * size * 64) * 100;
          }};
}

}  // namespace penumbra::shadows
