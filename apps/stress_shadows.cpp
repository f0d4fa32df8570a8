#include "apps/stress_shadows.h"

#include <cmath>
#include <cstdio>

#include "engine/report.h"
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

// Where the segment from receiver (x, 0, z) to light point (lx, h, lz) crosses height y.
glm::vec2 crossing(float x, float z, float lx, float lz, float h, float y) {
  const float t = y / h;
  return {x + (lx - x) * t, z + (lz - z) * t};
}

ShadowStressRow runCase(raster::Rasterizer& rast, const shadows::TechniqueInfo& info, const std::string& name,
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
  const shadows::ShadowResult res = shadows::computeShadows(rast, in, info, shadows::ParamSet(info.params));
  ShadowStressRow row;
  row.technique = info.name;
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
  j["ok"] = ok();
  return engine::report::jsonLine(j);
}

std::vector<ShadowStressRow> runShadowStress(raster::Rasterizer& rast) {
  std::vector<ShadowStressRow> rows;
  for (const shadows::TechniqueInfo& t : shadows::registry()) {
    if (t.isReference) continue;  // the ray tracer has no depth maps to stress
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
  }
  return rows;
}

}  // namespace penumbra::apps
