#include "shadows/occtex.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "raster/sat.h"
#include "shadows/area_light.h"
#include "shadows/kernel_taps.h"
#include "shadows/shadow_map.h"

namespace penumbra::shadows {

namespace {

constexpr double kDepthScale = 16777215.0;  // 2^24 - 1: stored values in (0, 1]

struct Counts {
  uint64_t lookups = 0, missed = 0, settled = 0, blocks = 0, texels = 0;
};

// One layer as the receivers read it: the coverage table, and the stored values (b_0 / depth,
// the first layer's units, so that one receiver plane serves every layer) of its covered texels as
// two pyramids: the nearest over each block (empty texels 0) and the farthest covered one (empty
// texels +max, so a block's min is over its covered texels only).
struct Layer {
  float front = 0, back = 0;  // depth range of the slab
  // The tables cover only the rectangle of the map that holds covered texels: columns [x0, x0 + w),
  // rows [y0, y0 + h) (w = 0: nothing covered). Outside it the coverage is 0.
  int x0 = 0, y0 = 0, w = 0, h = 0;
  // Two channels, exact integers: covered (0 or 1), and covered times the stored value in
  // kDepthScale units (the mean depth of the covered texels of a box).
  raster::MultiSat<uint64_t> coverage;
  raster::MinMaxPyramid nearest, farthest;
};

class OcclusionTextures final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    bias_ = biasParams(params);
    const int size = params.integer("map_size");
    layers_ = params.integer("layers");
    planeTest_ = params.choice("plane_test") == "on";
    occluderDepth_ = params.choice("layer_depth") == "occluders";
    fromMap_ = params.choice("slices") == "map";
    sumFusion_ = params.choice("fusion") == "sum";
    const WidenedView wide = widenedView(ctx, size);
    view_ = wide.view;
    margin_ = wide.margin;
    texelTanX_ = (view_.tanHi.x - view_.tanLo.x) / static_cast<float>(view_.width);
    texelTanY_ = (view_.tanHi.y - view_.tanLo.y) / static_cast<float>(view_.height);
    mapW_ = static_cast<double>(view_.width), mapH_ = static_cast<double>(view_.height);
    texelsPerTan_ = {mapW_ / static_cast<double>(view_.tanHi.x - view_.tanLo.x),
                     mapH_ / static_cast<double>(view_.tanHi.y - view_.tanLo.y)};
    halfLight_ = {0.5f * ctx.in.light.width, 0.5f * ctx.in.light.height};
    // Slab bounds uniform in 1/depth from the near plane to the farthest receiver.
    const float z0 = view_.znear, z1 = std::max(ctx.region.hi.z, z0 * 1.0001f);
    bounds_.resize(static_cast<size_t>(layers_) + 1);
    for (int k = 0; k <= layers_; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(layers_);
      bounds_[static_cast<size_t>(k)] = 1.0f / ((1.0f - t) / z0 + t / z1);
    }
    bounds_.front() = z0, bounds_.back() = z1;
    // Each triangle to the slabs its depth range meets.
    draws_.assign(static_cast<size_t>(layers_), {});
    const std::vector<uint32_t>& idx = ctx.casters.indices;
    const glm::vec3* pos = ctx.in.casters.positions.data();
    binned_ = 0, split_ = 0;
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
      float lo = std::numeric_limits<float>::max(), hi = -lo;
      for (size_t v = 0; v < 3; ++v) {
        const float z = view_.toView(pos[idx[t + v]]).z;
        lo = std::min(lo, z), hi = std::max(hi, z);
      }
      if (!(hi >= z0) || !(lo < z1)) continue;  // NaN-free casters (the engine drops the others)
      size_t slabs = 0;
      for (int k = 0; k < layers_; ++k) {
        const auto uk = static_cast<size_t>(k);
        if (hi >= bounds_[uk] && lo < bounds_[uk + 1]) {
          draws_[uk].indices.insert(draws_[uk].indices.end(), {idx[t], idx[t + 1], idx[t + 2]});
          ++slabs;
        }
      }
      binned_ += slabs;
      split_ += slabs > 1 ? 1 : 0;
    }
    int used = 0;
    for (const CasterDraw& d : draws_) used += d.indices.empty() ? 0 : 1;
    char line[448];
    std::snprintf(
        line, sizeof line,
        "occtex: %d layers uniform in 1/depth over [%.4g, %.4g], %d with casters, %s, fusion %s; %zu of %zu "
        "triangles binned (%.2f layers each); %zu split across layers (where the parts of an occluder hide "
        "different parts of the light, a product of transmissions leaks); maps %dx%d",
        layers_, static_cast<double>(z0), static_cast<double>(z1), used,
        fromMap_ ? "dealt from one depth map" : "each rendered from its slab", sumFusion_ ? "sum" : "product",
        binned_, idx.size() / 3,
        static_cast<double>(binned_) / static_cast<double>(std::max<size_t>(idx.size() / 3, 1)), split_,
        view_.width, view_.height);
    ctx.notes.push_back(line + wide.note);
  }

  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const ReceiverImage& rec = *ctx.in.receivers;
    const auto tStart = Clock::now();
    transmission_.resize(rec.width(), rec.height());
    // Each receiver's lookup point in the light's view, once for every layer; (0, 0, 0) where it
    // has none (not a receiver, or behind the light): every layer skips it.
    lookups_.resize(rec.width(), rec.height());
    const glm::vec3 n = ctx.in.light.normal(), c = ctx.in.light.center;
    ctx.raster.run([&] {
      tbb::parallel_for(0, rec.height(), [&](int y) {
        for (int x = 0; x < rec.width(); ++x) {
          const Receiver& r = rec.at(x, y);
          const bool lit = r.valid && glm::dot(r.position - c, n) > 0.0f;
          transmission_.at(x, y) = 1.0f;
          const glm::vec3 v = lit ? lookupPoint(view_, r, bias_) : glm::vec3(0.0f);
          lookups_.at(x, y) = {v, v.z > 0.0f ? through(v) : Through{}};
        }
      });
    });
    ctx.times.msEvaluate += msSince(tStart);
    tbb::enumerable_thread_specific<Counts> counts;
    uint64_t layerTexels = 0, croppedTexels = 0;
    // slices=map: one depth map of every caster, its texels dealt to the layers by depth.
    ShadowMap full;
    if (fromMap_) {
      const auto t0 = Clock::now();
      full.view = view_;
      renderDepthMap(ctx, full);
      ctx.times.msMaps += msSince(t0);
    }
    for (int k = 0; k < layers_; ++k) {
      if (draws_[static_cast<size_t>(k)].indices.empty()) continue;
      const Layer layer = buildLayer(ctx, k, fromMap_ ? &full : nullptr);
      layerTexels += static_cast<uint64_t>(view_.width) * static_cast<uint64_t>(view_.height);
      croppedTexels += static_cast<uint64_t>(layer.w) * static_cast<uint64_t>(layer.h);
      if (layer.w == 0) continue;
      const auto t0 = Clock::now();
      const auto accumulate = [&](const tbb::blocked_range<int>& rows) {
        Counts& cnt = counts.local();
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < rec.width(); ++x) {
            float& t = transmission_.at(x, y);
            const Lookup& l = lookups_.at(x, y);
            // No receiver, or at or behind the light's view plane (a layer is never behind it).
            if (t == 0.0f || !(l.v.z > 0.0f)) continue;
            const float b = blocked(layer, l, rec.at(x, y).normal, cnt);
            t = sumFusion_ ? std::max(0.0f, t - b) : t * (1.0f - b);
          }
      };
      ctx.raster.run([&] { tbb::parallel_for(tbb::blocked_range<int>(0, rec.height(), 4), accumulate); });
      ctx.times.msEvaluate += msSince(t0);
    }
    const auto t0 = Clock::now();
    forEachReceiver(ctx, visibility, [&](int x, int y, const Receiver&) { return transmission_.at(x, y); });
    ctx.times.msEvaluate += msSince(t0);
    Counts sum;
    counts.combine_each([&](const Counts& q) {
      sum.lookups += q.lookups, sum.missed += q.missed, sum.settled += q.settled, sum.blocks += q.blocks;
      sum.texels += q.texels;
    });
    char line[400];
    std::snprintf(
        line, sizeof line,
        "occtex: tables over %.1f%% of the layers' texels (each layer's covered rectangle); %llu layer "
        "lookups, %llu skipped (the footprint misses the rectangle), %llu settled by the min/max pyramid "
        "alone; receiver-plane test %s: %.2f blocks and %.2f texels refined per lookup",
        100.0 * static_cast<double>(croppedTexels) / static_cast<double>(std::max<uint64_t>(layerTexels, 1)),
        static_cast<unsigned long long>(sum.lookups), static_cast<unsigned long long>(sum.missed),
        static_cast<unsigned long long>(sum.settled),
        planeTest_ ? "on" : "off",
        static_cast<double>(sum.blocks) / static_cast<double>(std::max<uint64_t>(sum.lookups, 1)),
        static_cast<double>(sum.texels) / static_cast<double>(std::max<uint64_t>(sum.lookups, 1)));
    ctx.notes.push_back(line);
  }

 private:
  // Renders slab k (near plane at its front, its binned triangles), or takes the full map's texels
  // whose depth lies in the slab, and builds its table and pyramids.
  Layer buildLayer(ShadowContext& ctx, int k, const ShadowMap* full) {
    const auto uk = static_cast<size_t>(k);
    Layer layer;
    layer.front = bounds_[uk], layer.back = bounds_[uk + 1];
    const auto t0 = Clock::now();
    ShadowMap map;
    if (!full) {
      map.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), layer.front, view_.width,
                               view_.height, margin_);
      // The frustum's extent comes from the receivers and the margin, not the near plane: every
      // layer has view_'s texels.
      renderDepthMap(ctx, map, std::span<const CasterDraw>(&draws_[uk], 1));
      ctx.times.msMaps += msSince(t0);
    }
    const auto t1 = Clock::now();
    // Stored near / depth: covered where depth < back, i.e. stored > near / back, and (the full
    // map) depth >= front, i.e. stored <= near / front.
    const float near = full ? view_.znear : layer.front;
    const float coveredAbove = near / layer.back, toFirst = view_.znear / near;
    const float coveredUpTo = full ? view_.znear / layer.front : std::numeric_limits<float>::max();
    const raster::ImageFloat& depth = (full ? *full : map).depth.image();
    auto isCovered = [&](float s) { return s > coveredAbove && s <= coveredUpTo; };
    // The rectangle of covered texels (a min/max reduction: the same at any thread count).
    struct Span {
      int x0 = std::numeric_limits<int>::max(), x1 = -1, y0 = std::numeric_limits<int>::max(), y1 = -1;
    };
    tbb::enumerable_thread_specific<Span> spans;
    ctx.raster.run([&] {
      tbb::parallel_for(0, view_.height, [&](int y) {
        int lo = -1, hi = -1;
        for (int x = 0; x < view_.width; ++x)
          if (isCovered(depth.at(x, y))) hi = x, lo = lo < 0 ? x : lo;
        if (lo < 0) return;
        Span& sp = spans.local();
        sp.x0 = std::min(sp.x0, lo), sp.x1 = std::max(sp.x1, hi + 1);
        sp.y0 = std::min(sp.y0, y), sp.y1 = std::max(sp.y1, y + 1);
      });
    });
    Span all;
    spans.combine_each([&](const Span& sp) {
      all.x0 = std::min(all.x0, sp.x0), all.x1 = std::max(all.x1, sp.x1);
      all.y0 = std::min(all.y0, sp.y0), all.y1 = std::max(all.y1, sp.y1);
    });
    if (all.x1 < 0) {
      ctx.times.msFilter += msSince(t1);
      return layer;
    }
    layer.x0 = all.x0, layer.y0 = all.y0, layer.w = all.x1 - all.x0, layer.h = all.y1 - all.y0;
    const int w = layer.w, h = layer.h;
    raster::ImageFloat nearest(w, h), farthest(w, h);
    raster::Planes<uint32_t> covered(w, h, 2);
    ctx.raster.run([&] {
      tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
          const float s = depth.at(x + layer.x0, y + layer.y0);
          const bool in = isCovered(s);
          nearest.at(x, y) = in ? s * toFirst : 0.0f;
          farthest.at(x, y) = in ? s * toFirst : std::numeric_limits<float>::max();
          uint32_t* c = covered.pixel(x, y);
          c[0] = in ? 1u : 0u;
          c[1] = in ? static_cast<uint32_t>(std::lround(static_cast<double>(s * toFirst) * kDepthScale)) : 0u;
        }
      });
      layer.coverage = raster::buildSatInteger(covered);
      if (planeTest_) {
        layer.nearest = raster::buildMinMaxPyramid(nearest);
        layer.farthest = raster::buildMinMaxPyramid(farthest);
      }
    });
    ctx.times.msFilter += msSince(t1);
    return layer;
  }

  // The receiver as footprints need it: its tangent point and 1 / depth.
  struct Through {
    float tx, ty, invZ;
  };
  static Through through(const glm::vec3& v) { return {v.x / v.z, v.y / v.z, 1.0f / v.z}; }
  // A receiver's lookup point in the light's view and its Through, computed once for all layers.
  struct Lookup {
    glm::vec3 v{0.0f};
    Through through{};
  };
  static_assert(sizeof(Lookup) == 24, "occtexTechnique's receiverBytes counts 24 bytes a receiver");

  // The fraction of the light's footprint box at `layer` that the layer's covered texels fill
  // (those nearer than the tangent plane of the receiver at lookup point l.v with the plane test),
  // 0 when the layer is not in front.
  float blocked(const Layer& layer, const Lookup& l, const glm::vec3& normal, Counts& cnt) const {
    const glm::vec3& v = l.v;
    const Through& through = l.through;
    const float dr = v.z;
    // The part of the slab in front of the receiver: the whole slab without the plane test (the
    // paper's layers above the receiver), up to the receiver with it.
    const float back = planeTest_ ? std::min(layer.back, dr) : layer.back;
    if (!(layer.front < back) || !(back <= dr) || layer.w == 0) return 0.0f;
    // The slab's part in front of the receiver, in 1/depth: the layer is taken at its middle, or at
    // the mean depth of what it holds in the light's footprint from there (clamped to the part).
    const float invFront = 1.0f / layer.front, invBack = 1.0f / back;
    // The widest footprint (at the slab's front) missing the covered rectangle: nothing to count.
    const Box widest = footprint(through, invFront);
    if (!(widest.x1 > layer.x0 && widest.x0 < layer.x0 + layer.w && widest.y1 > layer.y0 &&
          widest.y0 < layer.y0 + layer.h))
      return ++cnt.missed, 0.0f;
    ++cnt.lookups;
    Box box = footprint(through, 0.5f * (invFront + invBack));
    if (!(box.area() > 0.0)) return 0.0f;
    std::optional<ReceiverPlane> plane;
    if (planeTest_) plane.emplace(view_, v, normal, bias_);
    double sums[2] = {0.0, 0.0};
    covered(layer, box, plane ? &*plane : nullptr, sums, cnt);
    if (occluderDepth_ && sums[0] > 0.0) {
      const double invOcc = sums[1] / (sums[0] * kDepthScale) / static_cast<double>(view_.znear);
      box = footprint(through, std::clamp(static_cast<float>(invOcc), invBack, invFront));
      if (!(box.area() > 0.0)) return 0.0f;
      covered(layer, box, plane ? &*plane : nullptr, sums, cnt);
    }
    return static_cast<float>(std::clamp(sums[0] / box.area(), 0.0, 1.0));
  }

  // The light's footprint through receiver point v (light view, depth v.z) on the plane at depth
  // 1/invZ, in texel coordinates (column x, row y; rows grow downwards), clamped to the map: the
  // mean is over what the map holds (its edge stands for nothing beyond it).
  struct Box {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double area() const { return (x1 - x0) * (y1 - y0); }
  };
  Box footprint(const Through& r, float invZ) const {
    const float k = invZ - r.invZ;
    const float hx = halfLight_.x * k, hy = halfLight_.y * k;
    const double w = mapW_, h = mapH_, sx = texelsPerTan_.x, sy = texelsPerTan_.y;
    const auto lox = static_cast<double>(view_.tanLo.x), hiy = static_cast<double>(view_.tanHi.y);
    return {std::clamp((static_cast<double>(r.tx - hx) - lox) * sx, 0.0, w),
            std::clamp((hiy - static_cast<double>(r.ty + hy)) * sy, 0.0, h),
            std::clamp((static_cast<double>(r.tx + hx) - lox) * sx, 0.0, w),
            std::clamp((hiy - static_cast<double>(r.ty - hy)) * sy, 0.0, h)};
  }

  // sums = the box's covered area and its covered texels' stored values (kDepthScale units, area-
  // weighted), only of those nearer than `plane` when there is one.
  void covered(const Layer& layer, const Box& box, const ReceiverPlane* plane, double sums[2],
               Counts& cnt) const {
    sums[0] = sums[1] = 0.0;
    // In the layer's rectangle (its tables' coordinates); outside it nothing is covered.
    const Box b{std::max(box.x0 - layer.x0, 0.0), std::max(box.y0 - layer.y0, 0.0),
                std::min(box.x1 - layer.x0, static_cast<double>(layer.w)),
                std::min(box.y1 - layer.y0, static_cast<double>(layer.h))};
    if (!(b.x0 < b.x1) || !(b.y0 < b.y1)) return;
    if (!plane) {
      layer.coverage.boxSum(b.x0, b.y0, b.x1, b.y1, sums);
      return;
    }
    const Query q{b, texelPlane(layer, plane->tapPlane())};
    // The coarsest level whose blocks the box spans at most 2 x 2 of (the least L with an extent
    // of at most 2^L, i.e. ceil(extent) <= 2^L), then down.
    const auto extent = static_cast<unsigned>(ceilOf(std::max(b.x1 - b.x0, b.y1 - b.y0)));
    const int level =
        std::min(extent <= 1 ? 0 : static_cast<int>(std::bit_width(extent - 1)), layer.nearest.levels() - 1);
    const int c0 = static_cast<int>(b.x0) >> level, c1 = (ceilOf(b.x1) - 1) >> level;
    const int r0 = static_cast<int>(b.y0) >> level, r1 = (ceilOf(b.y1) - 1) >> level;
    if (level > 0) {
      // The box as a whole first: the plane's extremes over it bound those over each block's part,
      // and most boxes are settled so (in an umbra, in light, or where the plane lies behind every
      // occluder) without a block's own bounds.
      const auto l = static_cast<size_t>(level);
      const Range t = thresholds(q, b);
      bool any = false, nearer = true, behind = true;
      for (int j = r0; j <= r1; ++j)
        for (int i = c0; i <= c1; ++i) {
          const float sNear = layer.nearest.maxs[l].at(i, j);
          if (!(sNear > 0.0f)) continue;  // nothing covered
          any = true;
          behind = behind && !(sNear > t.lo);
          nearer = nearer && layer.farthest.mins[l].at(i, j) > t.hi;
        }
      if (!any || behind || nearer) {
        ++cnt.settled;
        if (any && nearer) layer.coverage.boxSum(b.x0, b.y0, b.x1, b.y1, sums);
        return;
      }
    }
    Part parts[2][2];
    bool whole = true, any = false, mixed = false;
    for (int j = r0; j <= r1; ++j)
      for (int i = c0; i <= c1; ++i) {
        Part& p = parts[j - r0][i - c0];
        p = classify(layer, q, level, i, j);
        whole = whole && (p.kind == Part::Empty || p.kind == Part::Nearer);
        any = any || p.kind == Part::Nearer;
        mixed = mixed || p.kind == Part::Mixed;
      }
    if (!mixed) ++cnt.settled;
    // Every block empty or wholly nearer than the plane (the common case: in an umbra, or where the
    // plane lies behind every occluder): one query of the box, not one per block.
    if (whole) {
      if (any) layer.coverage.boxSum(b.x0, b.y0, b.x1, b.y1, sums);
      return;
    }
    for (int j = r0; j <= r1; ++j)
      for (int i = c0; i <= c1; ++i) visit(layer, q, level, i, j, parts[j - r0][i - c0], sums, cnt);
  }

  // The ceiling of x in [0, 2^31) (std::ceil is a library call without SSE4.1).
  static int ceilOf(double x) {
    const int i = static_cast<int>(x);
    return static_cast<double>(i) < x ? i + 1 : i;
  }

  // The receiver-plane test (BlockerPlane: a texel value above the threshold is nearer than the
  // plane) in a layer's table coordinates x, y: tangent coordinates are linear in them, so the map
  // folds into the plane's coefficients.
  struct TexelPlane {
    float a, b, c, lo, scale;
    float threshold(double x, double y) const {
      return scale * std::max(lo, a * static_cast<float>(x) + b * static_cast<float>(y) + c);
    }
  };
  TexelPlane texelPlane(const Layer& layer, const TapPlane& p) const {
    // tanX = u0 + x texelTanX, tanY = w0 - y texelTanY at the table's texel (x, y).
    const float u0 = view_.tanLo.x + static_cast<float>(layer.x0) * texelTanX_;
    const float w0 = view_.tanHi.y - static_cast<float>(layer.y0) * texelTanY_;
    return {p.a * texelTanX_, -p.b * texelTanY_, p.a * u0 + p.b * w0 + p.c, p.lo, p.scale};
  }

  struct Query {
    const Box& box;
    TexelPlane plane;
  };

  // Block (i, j) of a pyramid level against the plane: its part of the query's box (the layer's
  // table coordinates) and whether its covered texels there are none, all behind the plane, all
  // nearer, or mixed (to be refined). A texel (level 0) is never mixed: it is tested at its
  // centre, as PCF's taps.
  struct Part {
    enum Kind { Empty, Behind, Nearer, Mixed } kind = Empty;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    float sNear = 0;  // the block's nearest covered value (a texel: its value)
  };
  Part classify(const Layer& layer, const Query& q, int level, int i, int j) const {
    const Box& b = q.box;
    Part p;
    p.x0 = std::max(b.x0, static_cast<double>(i << level));
    p.x1 = std::min(b.x1, static_cast<double>(std::min((i + 1) << level, layer.w)));
    p.y0 = std::max(b.y0, static_cast<double>(j << level));
    p.y1 = std::min(b.y1, static_cast<double>(std::min((j + 1) << level, layer.h)));
    if (!(p.x0 < p.x1) || !(p.y0 < p.y1)) return p;
    const auto l = static_cast<size_t>(level);
    p.sNear = layer.nearest.maxs[l].at(i, j);
    if (!(p.sNear > 0.0f)) return p;  // nothing covered
    if (level == 0) {
      const bool nearer = p.sNear > q.plane.threshold(i + 0.5, j + 0.5);
      p.kind = nearer ? Part::Nearer : Part::Behind;
      return p;
    }
    const Range t = thresholds(q, Box{p.x0, p.y0, p.x1, p.y1});
    if (!(p.sNear > t.lo))
      p.kind = Part::Behind;  // every covered texel behind the plane
    else
      p.kind = layer.farthest.mins[l].at(i, j) > t.hi ? Part::Nearer : Part::Mixed;
    return p;
  }

  // The plane's thresholds over box r (the layer's table coordinates): linear, so their extremes
  // are at its corners.
  struct Range {
    float lo, hi;
  };
  static Range thresholds(const Query& q, const Box& r) {
    const float t00 = q.plane.threshold(r.x0, r.y0), t01 = q.plane.threshold(r.x0, r.y1);
    const float t10 = q.plane.threshold(r.x1, r.y0), t11 = q.plane.threshold(r.x1, r.y1);
    return {std::min(std::min(t00, t01), std::min(t10, t11)),
            std::max(std::max(t00, t01), std::max(t10, t11))};
  }

  // Adds to sums the covered area (and stored values) nearer than the plane of block (i, j) of
  // `level` inside the box, classified as p.
  void visit(const Layer& layer, const Query& q, int level, int i, int j, const Part& p, double sums[2],
             Counts& cnt) const {
    if (p.kind == Part::Empty || p.kind == Part::Behind) return;
    if (p.kind == Part::Nearer) {
      if (level == 0) {
        // One covered texel: its table entries are 1 and its value in kDepthScale units (as
        // buildLayer stores them), weighted by the box's part of it, as boxSum would.
        const double area = (p.x1 - p.x0) * (p.y1 - p.y0);
        sums[0] += area;
        sums[1] += area * static_cast<double>(std::lround(static_cast<double>(p.sNear) * kDepthScale));
        return;
      }
      double part[2];
      layer.coverage.boxSum(p.x0, p.y0, p.x1, p.y1, part);
      sums[0] += part[0], sums[1] += part[1];
      return;
    }
    ++cnt.blocks;
    const int cw = layer.nearest.maxs[level - 1].width(), ch = layer.nearest.maxs[level - 1].height();
    for (int cj = 2 * j; cj < std::min(2 * j + 2, ch); ++cj)
      for (int ci = 2 * i; ci < std::min(2 * i + 2, cw); ++ci) {
        if (level == 1) ++cnt.texels;
        visit(layer, q, level - 1, ci, cj, classify(layer, q, level - 1, ci, cj), sums, cnt);
      }
  }

  LightView view_;
  float texelTanX_ = 0, texelTanY_ = 0;  // a texel's side in tangent units
  double mapW_ = 0, mapH_ = 0;
  glm::dvec2 texelsPerTan_{0.0};
  glm::vec2 halfLight_{0.0f};  // the light's half extents
  glm::vec2 margin_{0.0f};
  BiasParams bias_;
  int layers_ = 4;
  bool planeTest_ = true, occluderDepth_ = true, fromMap_ = false, sumFusion_ = false;
  std::vector<float> bounds_;
  std::vector<CasterDraw> draws_;
  size_t binned_ = 0, split_ = 0;
  raster::ImageFloat transmission_;
  raster::Image<Lookup> lookups_;
};

}  // namespace

TechniqueInfo occtexTechnique() {
  std::vector<ParamSpec> p = depthMapParams(512, 0.5, 0.5);
  p.push_back({.name = "layers",
               .kind = ParamKind::Int,
               .defaultValue = 4,
               .minValue = 1,
               .maxValue = 64,
               .choices = {},
               .help = "slabs parallel to the light, uniform in 1/depth, one coverage texture each"});
  p.push_back(
      choiceParam("plane_test", 1, {"off", "on"},
                  "count only covered texels nearer the light than the receiver's tangent plane (off: the "
                  "paper's box filter of whole layers in front of the receiver)"));
  p.push_back(
      choiceParam("slices", 0, {"render", "map"},
                  "each layer rendered from its slab's casters (the paper: occluders hidden from the light's "
                  "centre count), or one depth map's texels dealt to the layers by depth (only what the "
                  "centre sees: no solid counted twice)"));
  p.push_back(
      choiceParam("fusion", 0, {"product", "sum"},
                  "the layers' occlusions combined as independent (V the product of the transmissions, the "
                  "paper) or as disjoint (V = 1 - their sum, clamped)"));
  p.push_back(
      choiceParam("layer_depth", 1, {"slab", "occluders"},
                  "the depth a layer's footprint is taken at: the middle of the slab's part in front of the "
                  "receiver, or the mean depth of its covered texels there (a blocker search per layer)"));
  return {.name = "occtex",
          .summary =
              "occlusion textures: the casters in layers parallel to the light, each a pre-filtered coverage "
              "texture, transmissions multiplied",
          .params = std::move(p),
          .benchSettings = {"", "layers=8", "layers=16", "slices=map", "slices=map,fusion=sum",
                            "layer_depth=slab", "plane_test=off"},
          .isReference = false,
          .make = [] { return std::make_unique<OcclusionTextures>(); },
          // One layer at a time over the widened map (up to 2 map_size per side): its depth target,
          // two float images and the two-channel coverage plane (20 B), the integer table (16 B)
          // and two min/max pyramids (about 22 B) per texel, with slices=map the full map (4 B);
          // each caster's indices once or twice.
          .peakBytes = [](const ParamSet& params, uint64_t casterTriangles) -> uint64_t {
            const auto side = 2 * static_cast<uint64_t>(params.integer("map_size"));
            return side * side * 62 + casterTriangles * 24;
          },
          // The transmissions and the receivers' lookup points.
          .receiverBytes = sizeof(float) + 24};
}

}  // namespace penumbra::shadows
