#include "shadows/shadow_map.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <cstdio>

namespace penumbra::shadows {

ParamSpec casterCullParam(int defaultIndex) {
  return choiceParam("cull", defaultIndex, {"none", "back", "auto"},
                     "cull faces turned away from the light: none, back (every mesh: closed ones only), auto (the "
                     "closed meshes')");
}

CasterCull casterCull(const ParamSet& params) {
  const std::string& c = params.choice("cull");
  return c == "back" ? CasterCull::Back : c == "auto" ? CasterCull::Auto : CasterCull::None;
}

std::vector<CasterDraw> casterDraws(const Geometry& casters, CasterCull cull, const RectLight* light) {
  // sin 30 degrees: faces within 30 degrees of edge-on to some light corner are kept (below).
  constexpr float kGrazing = 0.5f;
  std::vector<CasterDraw> draws;
  if (light && cull != CasterCull::None) {
    glm::vec3 corners[4];
    for (int c = 0; c < 4; ++c) corners[c] = light->point({(c & 1) ? 1.0f : 0.0f, (c & 2) ? 1.0f : 0.0f});
    CasterDraw d;
    for (size_t t = 0; t < casters.triangles(); ++t) {
      const uint32_t* tri = &casters.indices[3 * t];
      bool keep = cull == CasterCull::Auto && !casters.isClosed(t);
      if (!keep) {  // counter-clockwise seen from outside: the normal points out
        const glm::vec3 p0 = casters.positions[tri[0]], p1 = casters.positions[tri[1]], p2 = casters.positions[tri[2]];
        const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
        const glm::vec3 a = (p0 + p1 + p2) / 3.0f;  // the angles are seen from the centroid
        // Kept unless every corner lies behind the plane, more than 30 degrees from it: a ray from
        // a light point grazing a closed mesh enters through a face the source view may see
        // edge-on (few points) and leaves through a face at that grazing angle too, which fills
        // the gaps; the faces well turned away (a sphere's underside) go.
        for (const glm::vec3& c : corners)
          keep = keep || glm::dot(n, c - a) > -kGrazing * glm::length(n) * glm::length(c - a);
        keep = keep || !(glm::dot(n, n) > 0.0f);  // degenerate (or not finite): left to the rasterizer
      }
      if (!keep) continue;
      d.indices.insert(d.indices.end(), tri, tri + 3);
      d.closed.push_back(casters.isClosed(t) ? 1 : 0);
    }
    if (!d.indices.empty()) draws.push_back(std::move(d));
    return draws;
  }
  if (cull != CasterCull::Auto) {
    CasterDraw d;
    d.indices.assign(casters.indices.begin(), casters.indices.end());
    d.closed.assign(casters.closed.begin(), casters.closed.end());
    d.cull = cull == CasterCull::Back ? raster::CullMode::Front : raster::CullMode::None;
    if (!d.indices.empty()) draws.push_back(std::move(d));
    return draws;
  }
  CasterDraw closed, open;
  closed.cull = raster::CullMode::Front;
  for (size_t t = 0; t < casters.triangles(); ++t) {
    CasterDraw& d = casters.isClosed(t) ? closed : open;
    d.indices.insert(d.indices.end(), casters.indices.begin() + 3 * static_cast<std::ptrdiff_t>(t),
                     casters.indices.begin() + 3 * static_cast<std::ptrdiff_t>(t) + 3);
    d.closed.push_back(casters.isClosed(t) ? 1 : 0);
  }
  for (CasterDraw* d : {&closed, &open})
    if (!d->indices.empty()) draws.push_back(std::move(*d));
  return draws;
}

void renderDepthMap(ShadowContext& ctx, ShadowMap& map, std::span<const CasterDraw> draws) {
  map.depth.resize(map.view.width, map.view.height, 0.0f);
  ctx.raster.clear(map.depth, 0.0f);
  const glm::vec3* pos = ctx.in.casters.positions.data();
  const glm::mat4 m = map.view.viewProj;
  const auto draw = [&](std::span<const uint32_t> indices, raster::CullMode cull) {
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(ctx.in.casters.positions.size());
    desc.indices = indices;
    desc.cull = cull;
    desc.depthFunc = raster::DepthFunc::Greater;
    ctx.mapPasses += ctx.raster.drawDepth(desc, map.depth, [&](uint32_t i) { return m * glm::vec4(pos[i], 1.0f); });
  };
  if (draws.empty()) {
    draw(ctx.casters.indices, raster::CullMode::None);
  } else {
    for (const CasterDraw& d : draws) draw(d.indices, d.cull);
  }
  map.depth.fillBorder(0.0f, map.view.casterCut);  // the sides cut to the casters read empty (light_view.h)
  map.prepareLookup();
}

WidenedView widenedView(const ShadowContext& ctx, int size) {
  const LightView fitted = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), size, size);
  const float nearest = std::max(ctx.casters.minDepth, fitted.znear);
  const glm::vec2 ext = fitted.tanHi - fitted.tanLo;
  const glm::vec2 margin =
      glm::min(1.5f * ext, 0.5f * glm::vec2(ctx.in.light.width, ctx.in.light.height) *
                               std::max(1.0f / nearest - 1.0f / std::max(ctx.region.hi.z, nearest), 0.0f));
  auto side = [&](float e, float m) {
    return static_cast<int>(
        std::min(2.0 * size, std::ceil(static_cast<double>(size) * static_cast<double>((e + 2.0f * m) / e))));
  };
  WidenedView w;
  w.margin = margin;
  w.view = makeLightView(ctx.in.light, ctx.region, glm::vec2(0.0f), ctx.nearPlane(), side(ext.x, margin.x),
                         side(ext.y, margin.y), margin);
  const glm::vec2 grown = (w.view.tanHi - w.view.tanLo) / ext;
  const double density =
      std::min(static_cast<double>(w.view.width) / (static_cast<double>(size) * static_cast<double>(grown.x)),
               static_cast<double>(w.view.height) / (static_cast<double>(size) * static_cast<double>(grown.y)));
  char line[160];
  std::snprintf(line, sizeof line,
                " (frustum widened %.2fx%.2f for occluders beside the receivers, %.2f of map_size's texel density)",
                static_cast<double>(grown.x), static_cast<double>(grown.y), density);
  w.note = line;
  return w;
}

void ShadowMap::prepareLookup() {
  data_ = &depth.image().at(0, 0);
  stride_ = static_cast<size_t>(depth.image().stride());
  // column = (tanX - tanLo.x) / (tanHi.x - tanLo.x) * width; row = (tanHi.y - tanY) / (...) * height.
  ax_ = static_cast<float>(view.width) / (view.tanHi.x - view.tanLo.x);
  bx_ = -view.tanLo.x * ax_;
  ay_ = -static_cast<float>(view.height) / (view.tanHi.y - view.tanLo.y);
  by_ = -view.tanHi.y * ay_;
  maxX_ = static_cast<float>(view.width - 1);
  maxY_ = static_cast<float>(view.height - 1);
}

std::vector<ParamSpec> depthMapParams(int defaultSize, double defaultBias, double defaultSlope, double defaultNormal) {
  return {
      {.name = "map_size", .kind = ParamKind::Int, .defaultValue = static_cast<double>(defaultSize), .minValue = 16,
       .maxValue = 8192, .choices = {}, .help = "shadow map width and height, texels"},
      {.name = "bias", .kind = ParamKind::Float, .defaultValue = defaultBias, .minValue = 0, .maxValue = 64,
       .choices = {}, .help = "constant depth bias, in texel footprints at the receiver"},
      {.name = "slope_bias", .kind = ParamKind::Float, .defaultValue = defaultSlope, .minValue = 0, .maxValue = 64,
       .choices = {}, .help = "depth bias per unit tan(angle between normal and light ray), in texel footprints"},
      {.name = "normal_offset", .kind = ParamKind::Float, .defaultValue = defaultNormal, .minValue = 0,
       .maxValue = 16, .choices = {},
       .help = "lookup point moved along the geometric normal, in texel footprints at the receiver"},
  };
}

BiasParams biasParams(const ParamSet& params) {
  return {static_cast<float>(params.number("bias")), static_cast<float>(params.number("slope_bias")),
          static_cast<float>(params.number("normal_offset"))};
}

namespace {

// Bias in world units per unit depth: texelWorld(d) / d * (constant + slope * tan(theta)).
float biasPerDepth(const LightView& view, glm::vec3 v, glm::vec3 nv, BiasParams b) {
  const float c = std::abs(glm::dot(nv, v)) / std::max(glm::length(v), 1e-30f);
  const float tanTheta = std::min(std::sqrt(std::max(1.0f - c * c, 0.0f)) / std::max(c, 1e-6f), 10.0f);
  return view.texelWorld(1.0f) * (b.constant + b.slope * tanTheta);
}

glm::vec3 toViewDir(const LightView& view, glm::vec3 n) {
  return {glm::dot(n, view.right), glm::dot(n, view.up), glm::dot(n, view.axis)};
}

}  // namespace

BoxTest testBox(const ShadowMap& map, const raster::MinMaxPyramid& pyramid, const ReceiverPlane& plane, float x0,
                float y0, float x1, float y1) {
  // One texel of slack on each side for taps rounded just outside the box. Rows grow downwards
  // as tangent y decreases.
  const int c0 = map.column(x0) - 1, c1 = map.column(x1) + 2;
  const int r0 = map.row(y1) - 1, r1 = map.row(y0) + 2;
  float mn, mx;
  queryMinMax(pyramid, c0, r0, c1, r1, mn, mx);
  const float t00 = plane.threshold(x0, y0), t01 = plane.threshold(x0, y1), t10 = plane.threshold(x1, y0),
              t11 = plane.threshold(x1, y1);
  const float tMin = std::min(std::min(t00, t01), std::min(t10, t11));
  const float tMax = std::max(std::max(t00, t01), std::max(t10, t11));
  if (mx <= tMin * (1.0f - 1e-5f)) return BoxTest::AllLit;
  if (mn > tMax * (1.0f + 1e-5f)) return BoxTest::AllBlocked;
  return BoxTest::Mixed;
}

ParamSpec minMaxParam() {
  return {.name = "minmax", .kind = ParamKind::Choice, .defaultValue = 1, .minValue = 0, .maxValue = 1,
          .choices = {"off", "on"},
          .help = "skip the taps of receivers whose kernel is uniformly lit or blocked (min/max pyramid); same image"};
}

float biasedDepth(const LightView& view, glm::vec3 v, glm::vec3 n, BiasParams b) {
  return v.z - v.z * biasPerDepth(view, v, toViewDir(view, n), b);
}

ReceiverPlane::ReceiverPlane(const LightView& view, glm::vec3 v, glm::vec3 n, BiasParams b) {
  glm::vec3 nv = toViewDir(view, n);
  // Orient the normal so that k = dot(nv, v) > 0: rays meeting the plane in front have 1/d > 0.
  if (glm::dot(nv, v) < 0.0f) nv = -nv;
  const float k = std::max(glm::dot(nv, v), 1e-30f);
  a_ = nv.x / k;
  b_ = nv.y / k;
  c_ = nv.z / k;
  lo_ = 0.5f / v.z;
  hi_ = 2.0f / v.z;
  const float beta = biasPerDepth(view, v, nv, b);
  scale_ = beta < 1.0f ? view.znear / (1.0f - beta) : INFINITY;
  tx_ = v.x / v.z;
  ty_ = v.y / v.z;
  d_ = v.z;
}

}  // namespace penumbra::shadows
