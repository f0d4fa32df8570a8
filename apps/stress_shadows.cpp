#include "apps/stress_shadows.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "engine/report.h"
#include "raster/sat.h"
#include "shadows/technique.h"

namespace penumbra::apps {

namespace {

// A square light of side w at height h facing down over the origin; receivers on y = 0 over
// [-r, r]^2 (kN x kN); occluders given as axis-aligned horizontal rectangles. Receivers are
// classified analytically: in full umbra when every segment to the light crosses one rectangle,
// fully lit when none does (a conservative test on the light's corners and centre plus the
// rectangle's convexity: a segment family whose endpoints' crossing points all fall inside a
// rectangle lies inside it).
struct Rect {
  float x0, x1, z0, z1, y;
};

struct Setup {
  float lightHeight = 4, lightSize = 1, extent = 2;
  std::vector<Rect> rects;
};

constexpr int kN = 48;

// A technique as the suite runs it: its registry entry and settings (empty: the defaults).
struct StressTechnique {
  const shadows::TechniqueInfo& info;
  std::string settings;
  std::string label() const { return settings.empty() ? info.name : info.name + " " + settings; }
  shadows::ParamSet params() const {
    shadows::ParamSet p(info.params);
    if (const auto error = p.setAll(settings)) throw std::logic_error("stress variant " + label() + ": " + *error);
    return p;
  }
};

// Where the segment from receiver (x, 0, z) to light point (lx, h, lz) crosses height y.
glm::vec2 crossing(float x, float z, float lx, float lz, float h, float y) {
  const float t = y / h;
  return {x + (lx - x) * t, z + (lz - z) * t};
}

ShadowStressRow runCase(raster::Rasterizer& rast, const StressTechnique& info, const std::string& name,
                        const std::string& param, const Setup& s) {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  for (const Rect& r : s.rects) {
    const auto b = static_cast<uint32_t>(pos.size());
    pos.insert(pos.end(), {{r.x0, r.y, r.z0}, {r.x1, r.y, r.z0}, {r.x1, r.y, r.z1}, {r.x0, r.y, r.z1}});
    idx.insert(idx.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
  }
  shadows::ReceiverImage rec(kN, kN);
  std::vector<int> klass(static_cast<size_t>(kN * kN), 0);  // -1 umbra, 1 lit, 0 penumbra/unknown
  const float hw = 0.5f * s.lightSize;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const float x = s.extent * (2.0f * (static_cast<float>(i) + 0.5f) / kN - 1.0f);
      const float z = s.extent * (2.0f * (static_cast<float>(j) + 0.5f) / kN - 1.0f);
      rec.at(i, j) = {{x, 0.0f, z}, {0, 1, 0}, 1u};
      bool umbra = false, anyHit = false;
      for (const Rect& r : s.rects) {
        int inside = 0;
        float minX = INFINITY, maxX = -INFINITY, minZ = INFINITY, maxZ = -INFINITY;
        for (int c = 0; c < 4; ++c) {
          const glm::vec2 p = crossing(x, z, (c & 1) ? hw : -hw, (c & 2) ? hw : -hw, s.lightHeight, r.y);
          inside += (p.x > r.x0 && p.x < r.x1 && p.y > r.z0 && p.y < r.z1) ? 1 : 0;
          minX = std::min(minX, p.x), maxX = std::max(maxX, p.x), minZ = std::min(minZ, p.y), maxZ = std::max(maxZ, p.y);
        }
        if (inside == 4) umbra = true;
        if (!(maxX < r.x0 || minX > r.x1 || maxZ < r.z0 || minZ > r.z1)) anyHit = true;
      }
      klass[static_cast<size_t>(j * kN + i)] = umbra ? -1 : (anyHit ? 0 : 1);
    }
  shadows::ShadowInputs in;
  shadows::makeRectLight({0, s.lightHeight, 0}, {0, -1, 0}, {1, 0, 0}, s.lightSize, s.lightSize, glm::vec3(1), 1,
                         in.light);
  in.casters = {pos, idx};
  in.receivers = &rec;
  const shadows::ShadowResult res = shadows::computeShadows(rast, in, info.info, info.params());
  ShadowStressRow row;
  row.technique = info.label();
  row.name = name;
  row.param = param;
  double minLit = 1.0;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const float v = res.visibility.at(i, j);
      ++row.receivers;
      if (!std::isfinite(v)) {
        ++row.nonFinite;
        continue;
      }
      if (v < 0.0f || v > 1.0f) ++row.outOfRange;
      const int k = klass[static_cast<size_t>(j * kN + i)];
      if (k < 0) row.bleed = std::max(row.bleed, static_cast<double>(v)), ++row.umbra;
      if (k > 0) minLit = std::min(minLit, static_cast<double>(v)), ++row.lit;
    }
  row.darkening = 1.0 - minLit;
  return row;
}

// A case whose V is known per receiver: judged like the others, and compared with `exact` where
// that is not NaN.
ShadowStressRow runExact(raster::Rasterizer& rast, const StressTechnique& info, const std::string& name,
                         const std::string& param, const shadows::ShadowInputs& in, const std::vector<float>& exact) {
  const shadows::ShadowResult res = shadows::computeShadows(rast, in, info.info, info.params());
  ShadowStressRow row;
  row.technique = info.label();
  row.name = name;
  row.param = param;
  double sq = 0, sum = 0, minLit = 1.0;
  size_t n = 0;
  const shadows::ReceiverImage& rec = *in.receivers;
  for (int j = 0; j < rec.height(); ++j)
    for (int i = 0; i < rec.width(); ++i) {
      if (!rec.at(i, j).valid) continue;
      const float v = res.visibility.at(i, j), e = exact[static_cast<size_t>(j * rec.width() + i)];
      ++row.receivers;
      if (!std::isfinite(v)) {
        ++row.nonFinite;
        continue;
      }
      if (v < 0.0f || v > 1.0f) ++row.outOfRange;
      if (std::isnan(e)) continue;  // judged, not compared
      if (e == 0.0f) row.bleed = std::max(row.bleed, static_cast<double>(v)), ++row.umbra;
      if (e == 1.0f) minLit = std::min(minLit, static_cast<double>(v)), ++row.lit;
      const double d = static_cast<double>(v) - static_cast<double>(e);
      sq += d * d, sum += d, ++n;
    }
  row.darkening = 1.0 - minLit;
  if (n > 0) row.rmse = std::sqrt(sq / static_cast<double>(n)), row.bias = sum / static_cast<double>(n);
  return row;
}

struct Triangles {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const auto base = static_cast<uint32_t>(pos.size());
    pos.insert(pos.end(), {a, b, c, d});
    idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
};

// The terminator: a UV sphere (a convex polyhedron) lit from `elevation` degrees above its
// horizon; one receiver per facet facing the camera side, V = horizonFraction with the facet's
// plane, exactly (every ray leaving a facet above its plane misses a convex solid).
ShadowStressRow terminatorCase(raster::Rasterizer& rast, const StressTechnique& info, float elevation) {
  Triangles t;
  constexpr int kRings = 64, kSegments = 128;
  const auto at = [](int i, int j) {
    const double th = 3.14159265358979 * i / kRings, ph = 6.28318530717959 * (j % kSegments) / kSegments;
    return glm::vec3(static_cast<float>(std::sin(th) * std::cos(ph)), static_cast<float>(std::cos(th)),
                     static_cast<float>(std::sin(th) * std::sin(ph)));
  };
  for (int i = 0; i < kRings; ++i)
    for (int j = 0; j < kSegments; ++j) t.quad(at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
  shadows::ShadowInputs in;
  const float e = elevation * 3.14159265f / 180.0f;
  const glm::vec3 dir(std::cos(e), std::sin(e), 0.0f);  // towards the light
  shadows::makeRectLight(4.0f * dir, -dir, {0, 0, 1}, 1.0f, 1.0f, glm::vec3(1), 1, in.light);
  std::vector<shadows::Receiver> list;
  for (size_t k = 0; k + 2 < t.idx.size(); k += 3) {
    const glm::vec3 a = t.pos[t.idx[k]], b = t.pos[t.idx[k + 1]], c = t.pos[t.idx[k + 2]];
    const glm::vec3 cr = glm::cross(b - a, c - a);
    if (!(glm::length(cr) > 0.0f)) continue;
    glm::vec3 n = glm::normalize(cr);
    const glm::vec3 x = (a + b + c) / 3.0f;
    if (glm::dot(n, x) < 0.0f) n = -n;  // outward
    if (n.z > 0.0f && std::fabs(n.x) < 0.5f) list.push_back({x, n, 1u});  // a band across the terminator
  }
  const int w = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(list.size()))));
  shadows::ReceiverImage rec(w, w);
  std::vector<float> exact(static_cast<size_t>(w * w), 1.0f);
  for (size_t k = 0; k < list.size(); ++k) {
    rec.at(static_cast<int>(k % static_cast<size_t>(w)), static_cast<int>(k / static_cast<size_t>(w))) = list[k];
    exact[k] = shadows::horizonFraction(in.light, list[k].position, list[k].normal);
  }
  in.casters = {t.pos, t.idx};
  in.receivers = &rec;
  char p[64];
  std::snprintf(p, sizeof p, "sphere, light %g deg up", static_cast<double>(elevation));
  return runExact(rast, info, "terminator", p, in, exact);
}

// Receivers `gap` above a caster's surface (a plane under them), nothing else: V = the fraction
// of the light above their plane. Flat, the plane cannot shadow them and is culled; sloped, the
// light (3 x 3, at height 2) straddles the plane's extension, the plane is drawn into every map
// and only the bias keeps it from shadowing its own receivers (acne).
ShadowStressRow aboveCase(raster::Rasterizer& rast, const StressTechnique& info, float gap, float slopeDeg) {
  Triangles t;
  const float a = slopeDeg * 3.14159265f / 180.0f;
  const glm::vec3 u(std::cos(a), std::sin(a), 0.0f), w(0, 0, 1), n(-std::sin(a), std::cos(a), 0.0f);
  t.quad(-4.0f * u + 4.0f * w, 4.0f * u + 4.0f * w, 4.0f * u - 4.0f * w, -4.0f * u - 4.0f * w);
  shadows::ShadowInputs in;
  const bool sloped = slopeDeg != 0.0f;
  shadows::makeRectLight({0, sloped ? 2.0f : 4.0f, 0}, {0, -1, 0}, {1, 0, 0}, sloped ? 3.0f : 1.0f, sloped ? 3.0f : 1.0f,
                         glm::vec3(1), 1, in.light);
  shadows::ReceiverImage rec(kN, kN);
  std::vector<float> exact(static_cast<size_t>(kN * kN));
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const glm::vec3 x = (2.0f * (static_cast<float>(i) + 0.5f) / kN - 1.0f) * 2.0f * u +
                          (2.0f * (static_cast<float>(j) + 0.5f) / kN - 1.0f) * 2.0f * w + gap * n;
      rec.at(i, j) = {x, n, 1u};
      exact[static_cast<size_t>(j * kN + i)] = shadows::horizonFraction(in.light, x, n);
    }
  in.casters = {t.pos, t.idx};
  in.receivers = &rec;
  char p[64];
  std::snprintf(p, sizeof p, "gap %.0e, slope %g deg", static_cast<double>(gap), static_cast<double>(slopeDeg));
  return runExact(rast, info, "above caster", p, in, exact);
}

// A unit cube on the ground; receivers on the ground in front of its +x face, the compared ones at
// its foot (x = 0.5 + 0.002): V = the fraction of the light in front of the face's plane.
ShadowStressRow cubeContactCase(raster::Rasterizer& rast, const StressTechnique& info) {
  Triangles t;
  const float h = 0.5f;
  t.quad({-8, 0, 8}, {8, 0, 8}, {8, 0, -8}, {-8, 0, -8});
  t.quad({h, 0, h}, {h, 0, -h}, {h, 1, -h}, {h, 1, h});
  t.quad({-h, 0, -h}, {-h, 0, h}, {-h, 1, h}, {-h, 1, -h});
  t.quad({-h, 1, -h}, {-h, 1, h}, {h, 1, h}, {h, 1, -h});
  t.quad({-h, 0, h}, {h, 0, h}, {h, 1, h}, {-h, 1, h});
  t.quad({h, 0, -h}, {-h, 0, -h}, {-h, 1, -h}, {h, 1, -h});
  shadows::ShadowInputs in;
  shadows::makeRectLight({0.3f, 3.0f, 0.0f}, {0, -1, 0}, {1, 0, 0}, 1.0f, 1.0f, glm::vec3(1), 1, in.light);
  // Row 0 is the contact row; the ground in front (as a frame would hold it, so that the maps
  // cover the neighbourhood) is judged but not compared.
  shadows::ReceiverImage rec(kN, kN / 2);
  std::vector<float> exact(static_cast<size_t>(kN * (kN / 2)), NAN);
  for (int j = 0; j < kN / 2; ++j)
    for (int i = 0; i < kN; ++i) {
      const glm::vec3 x(h + 0.002f + 2.0f * static_cast<float>(j) / kN, 0.0f,
                        -0.3f + 0.6f * (static_cast<float>(i) + 0.5f) / kN);
      rec.at(i, j) = {x, {0, 1, 0}, 1u};
      if (j == 0) exact[static_cast<size_t>(i)] = shadows::horizonFraction(in.light, x, {1, 0, 0});
    }
  in.casters = {t.pos, t.idx};
  in.receivers = &rec;
  return runExact(rast, info, "contact", "cube foot, 2e-3 from its face", in, exact);
}

}  // namespace

std::string ShadowStressRow::json() const {
  engine::report::Json j;
  j["suite"] = "shadows";
  j["technique"] = technique;
  j["case"] = name;
  j["param"] = param;
  j["receivers"] = receivers;
  j["umbra"] = umbra;
  j["lit"] = lit;
  j["non_finite"] = nonFinite;
  j["out_of_range"] = outOfRange;
  j["bleed"] = engine::report::jsonNumber(bleed);
  j["darkening"] = engine::report::jsonNumber(darkening);
  j["rmse"] = engine::report::jsonNumber(rmse);
  j["bias"] = engine::report::jsonNumber(bias);
  j["ok"] = ok();
  return engine::report::jsonLine(j);
}

const std::vector<std::pair<std::string, std::string>>& shadowStressVariants() {
  static const std::vector<std::pair<std::string, std::string>> variants = {
      {"backproj", "gap_fill=off"},
      {"backproj", "micro=quads,gap_fill=off"},
      {"backproj", "micro=quads_outline"},
      {"backproj", "search=mssm"},
  };
  return variants;
}

std::vector<ShadowStressRow> runShadowStress(raster::Rasterizer& rast) {
  std::vector<ShadowStressRow> rows;
  std::vector<StressTechnique> techniques;
  for (const shadows::TechniqueInfo& t : shadows::registry())
    if (!t.isReference) techniques.push_back({t, ""});  // the ray tracer has no depth maps to stress
  for (const auto& [name, settings] : shadowStressVariants()) techniques.push_back({*shadows::findTechnique(name), settings});
  for (const StressTechnique& t : techniques) {
    // Depth range: a half-plane occluder 0.5 above the receivers and a tiny one delta below the
    // light (inside its footprint, so it is kept and sets the near plane): far / near = h / delta.
    for (const auto& [h, delta] : {std::pair{10.0f, 0.1f}, {10.0f, 1e-3f}, {10.0f, 1e-5f}, {1e5f, 1.0f}}) {
      Setup s;
      s.lightHeight = h;
      s.lightSize = 0.5f;
      s.extent = 2.0f;
      const float b = 0.01f * delta;
      s.rects = {{-1e3f, 0.0f, -1e3f, 1e3f, 0.5f}, {-b, b, -b, b, h - delta}};
      char p[64];
      // far / near as the views use it: the near plane is clamped at 1e-5 of the farthest receiver.
      const double nearPlane = std::max(0.99 * static_cast<double>(delta), 1e-5 * static_cast<double>(h));
      std::snprintf(p, sizeof p, "h %g, far/near %.0e", static_cast<double>(h), static_cast<double>(h) / nearPlane);
      rows.push_back(runCase(rast, t, "depth range", p, s));
    }
    // Contact: receivers 1e-4 below the occluder (and a lit half beside it).
    for (float gap : {1e-2f, 1e-4f}) {
      Setup s;
      s.rects = {{-10.0f, 0.0f, -10.0f, 10.0f, gap}};
      char p[64];
      std::snprintf(p, sizeof p, "gap %.0e", static_cast<double>(gap));
      rows.push_back(runCase(rast, t, "contact", p, s));
    }
    // Light bleeding: a high occluder over a low one, offset; under both, full umbra.
    {
      Setup s;
      s.lightSize = 1.0f;
      s.rects = {{-1.5f, 0.5f, -1.5f, 1.5f, 3.0f}, {-0.2f, 1.5f, -1.0f, 1.0f, 0.3f}};
      rows.push_back(runCase(rast, t, "bleeding", "occluders at 3.0 and 0.3", s));
    }
    // Curved and touching geometry, V known exactly.
    for (float elevation : {30.0f, 5.0f}) rows.push_back(terminatorCase(rast, t, elevation));
    for (float slope : {0.0f, 60.0f}) rows.push_back(aboveCase(rast, t, 1e-4f, slope));
    rows.push_back(cubeContactCase(rast, t));
    // Kernels wider than the map: a light six times the receivers' extent, near them.
    {
      Setup s;
      s.lightHeight = 2.0f;
      s.lightSize = 12.0f;
      s.rects = {{-1e3f, 0.0f, -1e3f, 1e3f, 0.5f}};
      rows.push_back(runCase(rast, t, "wide kernel", "light 12 over 4, at 2", s));
    }
    // Non-planar blockers: a step from 0.3 to 1.0 at x = 0, both halves covering the receivers.
    {
      Setup s;
      s.rects = {{-1e3f, 0.0f, -1e3f, 1e3f, 0.3f}, {0.0f, 1e3f, -1e3f, 1e3f, 1.0f}};
      rows.push_back(runCase(rast, t, "step", "occluders 0.3 | 1.0 at x = 0", s));
    }
  }
  return rows;
}

std::string SatPrecisionRow::json() const {
  engine::report::Json j;
  j["suite"] = "shadows";
  j["case"] = "sat precision";
  j["table"] = table;
  j["size"] = size;
  j["queries"] = queries;
  j["max_error"] = engine::report::jsonNumber(maxError);
  j["max_relative"] = engine::report::jsonNumber(maxRelative);
  j["max_bound_ratio"] = engine::report::jsonNumber(maxBoundRatio);
  j["ok"] = ok();
  return engine::report::jsonLine(j);
}

std::vector<SatPrecisionRow> runSatPrecision(int n) {
  raster::Planes<float> p(n, n, 1);
  const double span = 2.0 * (n - 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) p.pixel(x, y)[0] = static_cast<float>(std::exp(-80.0 * (x + y) / span));
  // Boxes along the diagonal (where the values fall from 1 to e^-80), sizes 1 to 16 texels, at
  // fractional corners; the last ones in the dimmest corner.
  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  for (int k = 0; k < 64; ++k) {
    const double t = (k + 0.5) / 64.0, w = 1.0 + (k * 5) % 16, h = 1.0 + (k * 3) % 16;
    const double x0 = std::min(t * (n - 20) + 0.37, n - w - 0.1), y0 = std::min(t * (n - 20) + 0.61, n - h - 0.1);
    boxes.push_back({x0, y0, x0 + w + 0.25, y0 + h + 0.5});
  }
  const auto exact = [&](const Box& b) {
    long double sum = 0;
    for (int y = static_cast<int>(b.y0); y < static_cast<int>(std::ceil(b.y1)); ++y)
      for (int x = static_cast<int>(b.x0); x < static_cast<int>(std::ceil(b.x1)); ++x) {
        const double wx = std::min(b.x1, x + 1.0) - std::max(b.x0, static_cast<double>(x));
        const double wy = std::min(b.y1, y + 1.0) - std::max(b.y0, static_cast<double>(y));
        sum += static_cast<long double>(wx * wy) * static_cast<long double>(p.pixel(x, y)[0]);
      }
    return static_cast<double>(sum);
  };
  std::vector<SatPrecisionRow> rows;
  // query(b, out, bound) -> area; the bound is of the sum.
  const auto measure = [&](const std::string& name, const auto& query) {
    SatPrecisionRow r{.table = name, .size = n};
    for (const Box& b : boxes) {
      double got = 0, bound = 0;
      const double area = query(b, got, bound);
      const double e = exact(b), err = std::abs(got - e);
      ++r.queries;
      r.maxError = std::max(r.maxError, err / area);
      r.maxRelative = std::max(r.maxRelative, err / std::max(e, 1e-300));
      r.maxBoundRatio = std::max(r.maxBoundRatio, bound > 0.0 ? err / bound : (err > 0.0 ? std::numeric_limits<double>::infinity() : 0.0));
    }
    rows.push_back(r);
  };
  {
    const raster::MultiSat<float> t = raster::buildSatFloat(p);
    measure("float", [&](const Box& b, double& got, double& bound) {
      t.roundingBound(b.x1, b.y1, &bound);
      return t.boxSum(b.x0, b.y0, b.x1, b.y1, &got);
    });
  }
  {
    const raster::MultiSat<double> t = raster::buildSatDouble(p);
    measure("double", [&](const Box& b, double& got, double& bound) {
      t.roundingBound(b.x1, b.y1, &bound);
      // The float inputs are exact in double; the bound covers the table's own rounding.
      return t.boxSum(b.x0, b.y0, b.x1, b.y1, &got);
    });
  }
  for (int bits : {20, 24}) {
    // One table over the map with the global range [0, 1] (the paper's normalization).
    const double step = 1.0 / ((1u << bits) - 1u);
    const raster::MultiSat<uint64_t> t = raster::buildSatInteger(raster::quantizePlanes(p, {0.0}, {1.0}, bits));
    measure("integer mu " + std::to_string(bits), [&](const Box& b, double& got, double& bound) {
      const double area = t.boxSum(b.x0, b.y0, b.x1, b.y1, &got);
      got *= step;
      bound = 0.5 * step * area;
      return area;
    });
  }
  for (int bits : {20, 24}) {
    const raster::TiledSat t = raster::buildTiledSat(p, bits);
    measure("tiled mu " + std::to_string(bits), [&](const Box& b, double& got, double& bound) {
      return t.boxSum(b.x0, b.y0, b.x1, b.y1, &got, &bound);
    });
  }
  return rows;
}

}  // namespace penumbra::apps
