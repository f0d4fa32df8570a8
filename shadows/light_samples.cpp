#include "shadows/light_samples.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/common.hpp>

#include "shadows/kernel_taps.h"
#include "shadows/sampling.h"

namespace penumbra::shadows {

std::vector<glm::vec2> lightSamplePoints(const RectLight& light, int n) {
  std::vector<glm::vec2> pts;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 h = hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(n));
    pts.emplace_back((h.x - 0.5f) * light.width, (h.y - 0.5f) * light.height);
  }
  return pts;
}

LightSampleSet interleavedLightSamples(const RectLight& light, int n, int k) {
  LightSampleSet set;
  set.k = std::max(k, 1);
  while (set.k > 1 && set.k * set.k > n) --set.k;  // every subset holds at least one point
  const int subsets = set.k * set.k;
  set.count.assign(static_cast<size_t>(subsets), 0);
  if (set.k == 1) {
    set.points = lightSamplePoints(light, n);
    set.subset.assign(set.points.size(), 0);
    set.count[0] = n;
    return set;
  }
  for (int s = 0; s < subsets; ++s) {
    const int m = n / subsets + (s < n % subsets ? 1 : 0);
    const glm::vec2 shift((static_cast<float>(s) + 0.5f) / static_cast<float>(subsets),
                          radicalInverse2(static_cast<uint32_t>(s)));
    for (int i = 0; i < m; ++i) {
      glm::vec2 h = hammersley(static_cast<uint32_t>(i), static_cast<uint32_t>(m)) + shift;
      h -= glm::floor(h);
      set.points.emplace_back((h.x - 0.5f) * light.width, (h.y - 0.5f) * light.height);
      set.subset.push_back(s);
    }
    set.count[static_cast<size_t>(s)] = m;
  }
  return set;
}

std::vector<glm::vec2> poissonDiskPoints(const RectLight& light, int n) {
  constexpr int kCandidates = 32;
  std::vector<glm::vec2> pts;
  if (n <= 0) return pts;
  const float w = light.width, h = light.height;
  // A grid of cells about one point's share of the area on a side, each listing its points.
  const float cell = std::sqrt(w * h / static_cast<float>(n));
  const int gx = std::max(1, static_cast<int>(std::ceil(w / cell))), gy = std::max(1, static_cast<int>(std::ceil(h / cell)));
  std::vector<std::vector<int>> grid(static_cast<size_t>(gx) * static_cast<size_t>(gy));
  const auto cellOf = [&](glm::vec2 p, int& cx, int& cy) {
    cx = std::clamp(static_cast<int>((p.x + 0.5f * w) / cell), 0, gx - 1);
    cy = std::clamp(static_cast<int>((p.y + 0.5f * h) / cell), 0, gy - 1);
  };
  // Squared distance from p to the nearest point so far: rings of cells outwards until no nearer
  // point can lie beyond the ring.
  const auto nearest2 = [&](glm::vec2 p) {
    int cx, cy;
    cellOf(p, cx, cy);
    float best = INFINITY;
    for (int r = 0; r < std::max(gx, gy); ++r) {
      for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x) {
          if (x < 0 || y < 0 || x >= gx || y >= gy || (std::abs(x - cx) != r && std::abs(y - cy) != r)) continue;
          for (int i : grid[static_cast<size_t>(y) * static_cast<size_t>(gx) + static_cast<size_t>(x)]) {
            const glm::vec2 d = pts[static_cast<size_t>(i)] - p;
            best = std::min(best, d.x * d.x + d.y * d.y);
          }
        }
      const float reach = static_cast<float>(r) * cell;  // every point within reach has been seen
      if (best <= reach * reach) break;
    }
    return best;
  };
  for (int i = 0; i < n; ++i) {
    glm::vec2 pick(0.0f);
    float far = -1.0f;
    for (int c = 0; c < kCandidates; ++c) {
      const uint32_t hsh = hash3(static_cast<uint32_t>(n), static_cast<uint32_t>(i), static_cast<uint32_t>(c));
      const glm::vec2 q((unitFloat(hsh) - 0.5f) * w, (unitFloat(mix32(hsh ^ 0x68e31da4U)) - 0.5f) * h);
      const float d = nearest2(q);
      if (d > far) far = d, pick = q;
      if (i == 0) break;  // the first point: any candidate
    }
    int cx, cy;
    cellOf(pick, cx, cy);
    grid[static_cast<size_t>(cy) * static_cast<size_t>(gx) + static_cast<size_t>(cx)].push_back(i);
    pts.push_back(pick);
  }
  return pts;
}

LightSampleSet lightSamples(const RectLight& light, int n, int k, const std::string& pattern) {
  if (pattern != "poisson") return interleavedLightSamples(light, n, k);
  LightSampleSet set;
  set.k = std::max(k, 1);
  while (set.k > 1 && set.k * set.k > n) --set.k;
  const int subsets = set.k * set.k;
  set.points = poissonDiskPoints(light, n);
  set.count.assign(static_cast<size_t>(subsets), 0);
  for (int i = 0; i < n; ++i) {
    set.subset.push_back(i % subsets);
    ++set.count[static_cast<size_t>(i % subsets)];
  }
  return set;
}

ParamSpec samplePatternParam() {
  return choiceParam("samples", 0, {"hammersley", "poisson"},
                     "light sample points: a Hammersley set (stratified) or Poisson-disk (best candidate, as the VWSS "
                     "paper)");
}

ParamSpec mapFitParam(int defaultIndex) {
  return choiceParam(
      "fit", defaultIndex, {"receivers", "casters"},
      "each map's frustum: the receivers' box, or that box cut to the casters' as the light sample "
      "sees them (finer texels where objects stand on a wide ground)");
}

ParamSpec interleaveParam() {
  return {.name = "interleave", .kind = ParamKind::Int, .defaultValue = 1, .minValue = 1, .maxValue = 4, .choices = {},
          .help = "k: pixels in each k x k block use disjoint subsets of the views (noise instead of stacked edge "
                  "copies in wide penumbrae); 1 = off"};
}

SampleMap SampleMap::of(const ShadowMap& map, glm::vec2 lightPoint, int subset) {
  SampleMap m;
  m.view = map.view;
  m.depth = map.tapMap().data;
  m.stride = map.tapMap().stride;
  m.lightPoint = lightPoint;
  m.subset = subset;
  return m;
}

SampleMap SampleMap::ofBits(const LightView& view, const raster::Image<uint32_t>& bits, glm::vec2 lightPoint,
                            int subset) {
  SampleMap m;
  m.view = view;
  m.depthBits = bits.data();
  m.stride = bits.stride();
  m.lightPoint = lightPoint;
  m.subset = subset;
  return m;
}

namespace {

// The lookup constants of ShadowMap::prepareLookup (the same expressions: the same texels).
SampleLookup lookupOf(const SampleMap& m) {
  const LightView& v = m.view;
  SampleLookup l;
  l.data = m.depthBits ? static_cast<const void*>(m.depthBits) : static_cast<const void*>(m.depth);
  l.bits = m.depthBits != nullptr;
  l.stride = m.stride;
  l.ax = static_cast<float>(v.width) / (v.tanHi.x - v.tanLo.x);
  l.bx = -v.tanLo.x * l.ax;
  l.ay = -static_cast<float>(v.height) / (v.tanHi.y - v.tanLo.y);
  l.by = -v.tanHi.y * l.ay;
  l.maxX = static_cast<float>(v.width - 1);
  l.maxY = static_cast<float>(v.height - 1);
  l.invAx = 1.0f / l.ax;
  l.invAy = 1.0f / l.ay;
  l.texelTanX = (v.tanHi.x - v.tanLo.x) / static_cast<float>(v.width);
  l.texelTanY = (v.tanHi.y - v.tanLo.y) / static_cast<float>(v.height);
  l.texel = v.texelWorld(1.0f);
  l.znear = v.znear;
  l.lpx = m.lightPoint.x;
  l.lpy = m.lightPoint.y;
  l.subset = m.subset;
  return l;
}

}  // namespace

void LightSampleTests::prepare(ShadowContext& ctx, BiasParams bias, int interleave) {
  interleave_ = std::max(interleave, 1);
  const ReceiverImage& rec = *ctx.in.receivers;
  const RectLight& light = ctx.in.light;
  width_ = rec.width();
  height_ = rec.height();
  padded_ = (width_ + kTapLanes - 1) / kTapLanes * kTapLanes;
  normalOffset_ = bias.normal;
  const size_t n = static_cast<size_t>(padded_) * static_cast<size_t>(height_);
  for (std::vector<float>* a : {&x_, &y_, &invD_, &bias_, &nx_, &ny_, &nz_}) a->assign(n, 0.0f);
  d_.assign(n, -1.0f);  // nothing to test
  subsetOfX_.resize(static_cast<size_t>(padded_));
  for (int x = 0; x < padded_; ++x) subsetOfX_[static_cast<size_t>(x)] = x % interleave_;
  counts_.resize(width_, height_, 0);
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height_, 4), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < width_; ++x) {
          const Receiver& r = rec.at(x, y);
          const size_t i = static_cast<size_t>(y) * static_cast<size_t>(padded_) + static_cast<size_t>(x);
          const glm::vec3 v = toLightSpace(light, r.position);
          const glm::vec3 nl(glm::dot(r.normal, light.right), glm::dot(r.normal, light.up),
                             glm::dot(r.normal, light.normal()));
          x_[i] = v.x, y_[i] = v.y, nx_[i] = nl.x, ny_[i] = nl.y, nz_[i] = nl.z;
          if (!r.valid || !(v.z > 0.0f)) continue;  // d stays -1: nothing to test
          d_[i] = v.z;
          invD_[i] = 1.0f / v.z;
          const float c = std::abs(glm::dot(nl, v)) / glm::length(v);
          const float tanTheta = std::min(std::sqrt(std::max(1.0f - c * c, 0.0f)) / std::max(c, 1e-6f), 10.0f);
          bias_[i] = bias.constant + bias.slope * tanTheta;
        }
    });
  });
}

void LightSampleTests::accumulate(ShadowContext& ctx, std::span<const SampleMap> maps, std::span<const glm::vec2> taps) {
  std::vector<SampleLookup> lookups;
  lookups.reserve(maps.size());
  for (const SampleMap& m : maps) lookups.push_back(lookupOf(m));
  std::vector<float> tx(taps.size()), ty(taps.size());
  for (size_t t = 0; t < taps.size(); ++t) tx[t] = taps[t].x, ty[t] = taps[t].y;
  const int64_t simd = ctx.raster.config().simd.taps;
  ctx.raster.run([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, height_, 2), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y) {
        const size_t o = static_cast<size_t>(y) * static_cast<size_t>(padded_);
        const SampleRow row{x_.data() + o,  y_.data() + o,  d_.data() + o,  invD_.data() + o,  bias_.data() + o,
                            nx_.data() + o, ny_.data() + o, nz_.data() + o, subsetOfX_.data(), interleave_ * (y % interleave_),
                            width_,         normalOffset_};
        accumulateSampleRow(row, lookups, tx.data(), ty.data(), static_cast<int>(taps.size()), &counts_.at(0, y), simd);
      }
    });
  });
}

void LightSampleTests::accumulate(ShadowContext& ctx, const ShadowMap& map, glm::vec2 lightPoint,
                                  std::span<const glm::vec2> taps, int subset) {
  const SampleMap one = SampleMap::of(map, lightPoint, subset);
  accumulate(ctx, std::span<const SampleMap>(&one, 1), taps);
}

void accumulateSampleRowReference(const SampleRow& row, std::span<const SampleLookup> maps, const float* tapX,
                                  const float* tapY, int taps, uint16_t* counts) {
  for (int x = 0; x < row.count; ++x) {
    const float d = row.d[x];
    if (!(d > 0.0f)) continue;
    const float nx = row.nx[x], ny = row.ny[x], nz = row.nz[x];
    int lit = 0;
    for (const SampleLookup& m : maps) {
      if (m.subset >= 0 && m.subset != row.subsetOfX[x] + row.subsetBase) continue;
      // Receiver at light-space (x, y, d), view origin (lx, ly, 0): view-space (x - lx, y - ly, d).
      float vx = row.x[x] - m.lpx, vy = row.y[x] - m.lpy, vz = d;
      if (!(-(nx * vx + ny * vy + nz * vz) > 0.0f)) continue;  // below the horizon
      // The lookup point, moved along the normal by normalOffset texel footprints (shadow_map.h).
      const float offset = row.normalOffset * m.texel;
      if (offset != 0.0f) {
        const float o = offset * d;
        vx += nx * o, vy += ny * o, vz += nz * o;
      }
      const float invD = offset != 0.0f ? 1.0f / vz : row.invD[x];
      // Receiver-plane depth at the texel's centre (shadow_map.h, TexelCentres): what the receiver's
      // own surface stored there, whatever its slope; the bias then only covers curvature and rounding.
      const float invK = 1.0f / (nx * vx + ny * vy + nz * vz);
      const float beta = m.texel * row.bias[x];
      const float scale = beta < 1.0f ? m.znear / (1.0f - beta) : INFINITY;
      const float tx = vx * invD, ty = vy * invD;
      for (int t = 0; t < taps; ++t) {
        const float qx = tx + tapX[t] * m.texelTanX, qy = ty + tapY[t] * m.texelTanY;
        const float fx = std::min(m.maxX, std::max(0.0f, m.ax * qx + m.bx));
        const float fy = std::min(m.maxY, std::max(0.0f, m.ay * qy + m.by));
        const size_t i = static_cast<size_t>(fy) * static_cast<size_t>(m.stride) + static_cast<size_t>(fx);
        const float stored = m.bits ? std::bit_cast<float>(static_cast<const uint32_t*>(m.data)[i])
                                    : static_cast<const float*>(m.data)[i];
        const float cx = (std::floor(fx) + 0.5f - m.bx) * m.invAx, cy = (std::floor(fy) + 0.5f - m.by) * m.invAy;
        const float inv = (nx * cx + ny * cy + nz) * invK;
        lit += stored <= scale * std::min(2.0f * invD, std::max(0.5f * invD, inv)) ? 1 : 0;
      }
    }
    counts[x] = static_cast<uint16_t>(counts[x] + lit);
  }
}

void LightSampleTests::finish(ShadowContext& ctx, int taps, const LightSampleSet& samples,
                              raster::ImageFloat& visibility) const {
  const int k = samples.k;
  forEachReceiver(
      ctx, visibility,
      [&](int x, int y, const Receiver&) {
        const int n = samples.count[static_cast<size_t>(x % k + k * (y % k))] * taps;
        return n > 0 ? static_cast<float>(counts_.at(x, y)) / static_cast<float>(n) : 1.0f;
      },
      SelfShadow::Handled);
}

}  // namespace penumbra::shadows
