#include "shadows/moments.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>

#include "raster/kernels.h"

namespace penumbra::shadows {

namespace {

// Texel index and weight of the lower neighbour for a continuous coordinate (centres at +0.5).
void bilinearAxis(float pos, int size, int& i0, int& i1, double& f) {
  double u = static_cast<double>(pos) - 0.5;
  // Clamp before the conversion to int: receivers far outside the map (or NaN) read the edge.
  if (!(u >= 0.0)) u = 0.0;
  if (u > static_cast<double>(size - 1)) u = static_cast<double>(size - 1);
  const double fl = std::floor(u);
  i0 = static_cast<int>(fl);
  i1 = std::min(i0 + 1, size - 1);
  f = u - fl;
}

constexpr float raster::Float4::*kChannel[4] = {&raster::Float4::r, &raster::Float4::g, &raster::Float4::b,
                                                &raster::Float4::a};

}  // namespace

std::vector<uint32_t> momentCasters(const Geometry& casters, const LightView& view, float zFar) {
  std::vector<uint32_t> out;
  out.reserve(casters.indices.size());
  // Sequential: the list keeps submission order (the fragment stage's nearest-wins relies on the
  // depth test only, but the pass's statistics and bits should not depend on scheduling).
  for (size_t t = 0; t < casters.triangles(); ++t) {
    const uint32_t* tri = &casters.indices[t * 3];
    unsigned all = ~0u;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 v = view.toView(casters.positions[tri[k]]);
      unsigned m = 0;
      if (!(v.z > 0.0f)) m |= 1u;  // behind the light plane (or not finite)
      if (v.z > zFar) m |= 2u;
      if (v.x > view.tanHi.x * v.z) m |= 4u;
      if (v.x < view.tanLo.x * v.z) m |= 8u;
      if (v.y > view.tanHi.y * v.z) m |= 16u;
      if (v.y < view.tanLo.y * v.z) m |= 32u;
      all &= m;
    }
    if (all == 0) out.insert(out.end(), tri, tri + 3);
  }
  return out;
}

MomentSample MomentMap::sample(glm::vec2 mapPos) const {
  int x0, x1, y0, y1;
  double fx, fy;
  bilinearAxis(mapPos.x, texels.width(), x0, x1, fx);
  bilinearAxis(mapPos.y, texels.height(), y0, y1, fy);
  const raster::Float4 t00 = texels.at(x0, y0), t10 = texels.at(x1, y0);
  const raster::Float4 t01 = texels.at(x0, y1), t11 = texels.at(x1, y1);
  MomentSample s;
  const int n = warp.channels();
  for (int c = 0; c < n; ++c) {
    const auto ch = kChannel[c];
    const double top = (1.0 - fx) * static_cast<double>(t00.*ch) + fx * static_cast<double>(t10.*ch);
    const double bottom = (1.0 - fx) * static_cast<double>(t01.*ch) + fx * static_cast<double>(t11.*ch);
    s.m[c] = (1.0 - fy) * top + fy * bottom;
  }
  return s;
}

std::vector<ParamSpec> momentMapParams(double defaultSigma) {
  std::vector<ParamSpec> specs = depthMapParams(1024, 0.5, 1.0);
  specs.push_back({.name = "filter_sigma",
                   .kind = ParamKind::Float,
                   .defaultValue = defaultSigma,
                   .minValue = 0,
                   .maxValue = 64,
                   .choices = {},
                   .help = "Gaussian pre-filter of the moment map, sigma in texels (fixed penumbra width: no "
                           "contact hardening)"});
  return specs;
}

std::vector<ParamSpec> chebyshevParams(double defaultMinVariance) {
  return {
      {.name = "min_variance",
       .kind = ParamKind::Float,
       .defaultValue = defaultMinVariance,
       .minValue = 0,
       .maxValue = 0.01,
       .choices = {},
       .help =
           "lower bound on the filtered depth variance, in normalized depth^2 (EVSM scales it by the warp's "
           "squared derivative)"},
      {.name = "bleed_reduction",
       .kind = ParamKind::Float,
       .defaultValue = 0.2,
       .minValue = 0,
       .maxValue = 0.99,
       .choices = {},
       .help = "Chebyshev bounds below this are cut to 0 and the rest rescaled: less light bleeding, darker "
               "penumbrae"},
  };
}

namespace {
// Draws the map's casters; write(x, y, z) receives each texel's nearest caster's normalized depth
// (fragments of a tile arrive in submission order and only when nearer than what the texel holds,
// so the last write is the nearest caster's).
template <class Write>
void drawMomentCasters(ShadowContext& ctx, MomentMap& map, Write write) {
  const LightView& view = map.view;
  map.zNear = view.znear;
  // The farthest receiver with 1% margin; never at or in front of the near plane.
  map.zFar = std::max(ctx.region.hi.z * 1.01f, view.znear * 1.01f + 1e-30f);
  raster::DepthTarget depth(view.width, view.height, 0.0f);
  ctx.raster.clear(depth, 0.0f);
  const glm::vec3* pos = ctx.in.casters.positions.data();
  const std::vector<uint32_t> indices = momentCasters(ctx.in.casters, view, map.zFar);
  raster::DrawDesc desc;
  desc.vertexCount = static_cast<uint32_t>(ctx.in.casters.positions.size());
  desc.indices = indices;
  desc.varyings = 1;
  desc.cull = raster::CullMode::None;
  desc.depthFunc = raster::DepthFunc::Greater;  // reversed depth near / d: keeps the nearest caster
  const glm::mat4 m = view.viewProj;
  const MomentMap& mm = map;
  ctx.mapPasses += ctx.raster.draw(
      desc, depth,
      [&](uint32_t i, float* vary) {
        // d is linear in world space: its perspective-correct interpolation is exact.
        vary[0] = view.toView(pos[i]).z;
        return m * glm::vec4(pos[i], 1.0f);
      },
      [&](const raster::Fragment& f) { write(f.x, f.y, mm.normalizedDepth(f.varyings[0])); });
}
}  // namespace

void renderMomentMap(ShadowContext& ctx, MomentMap& map) {
  const MomentWarp warp = map.warp;
  map.texels.resize(map.view.width, map.view.height, warp.moments(1.0f));
  raster::ImageFloat4& target = map.texels;
  drawMomentCasters(ctx, map, [&](int x, int y, float z) { target.at(x, y) = warp.moments(z); });
}

void renderNormalizedDepth(ShadowContext& ctx, MomentMap& map, raster::ImageFloat& z) {
  map.texels = raster::ImageFloat4();
  ctx.raster.run([&] { z.resizeParallel(map.view.width, map.view.height, 1.0f); });
  drawMomentCasters(ctx, map, [&](int x, int y, float zn) { z.at(x, y) = zn; });
}

void filterMomentMap(ShadowContext& ctx, MomentMap& map, float sigma) {
  if (!(sigma > 0.0f)) return;
  raster::ImageFloat4& t = map.texels;
  const int channels = map.warp.channels();
  ctx.raster.run([&] {
    if (channels == 4) {
      raster::gaussianBlur(t, t, sigma);
      return;
    }
    // Fewer channels: blur each used one as its own plane (the single-channel kernel gives the
    // same bits as the four-channel one, at a quarter or half the work).
    raster::ImageFloat plane(t.width(), t.height());
    for (int c = 0; c < channels; ++c) {
      const auto ch = kChannel[c];
      tbb::parallel_for(tbb::blocked_range<int>(0, t.height(), 16), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < t.width(); ++x) plane.at(x, y) = t.at(x, y).*ch;
      });
      raster::gaussianBlur(plane, plane, sigma);
      tbb::parallel_for(tbb::blocked_range<int>(0, t.height(), 16), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < t.width(); ++x) t.at(x, y).*ch = plane.at(x, y);
      });
    }
  });
}

void prepareMomentMap(ShadowContext& ctx, const ParamSet& params, MomentWarp warp, MomentMap& map) {
  const auto t0 = Clock::now();
  const int size = params.integer("map_size");
  map.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
  map.warp = warp;
  renderMomentMap(ctx, map);
  ctx.times.msMaps += msSince(t0);

  const auto t1 = Clock::now();
  const float sigma = static_cast<float>(params.number("filter_sigma"));
  filterMomentMap(ctx, map, sigma);
  ctx.times.msFilter += msSince(t1);

  char buf[200];
  std::snprintf(buf, sizeof buf, "%s: %d moment(s), map %d^2 from the light centre, Gaussian sigma %g texels",
                warp.name(), warp.channels(), size, static_cast<double>(sigma));
  ctx.notes.push_back(buf);
}

}  // namespace penumbra::shadows
