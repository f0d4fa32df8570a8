#include "apps/stress_raster.h"

#include <cmath>
#include <cstdio>
#include <glm/glm.hpp>
#include <numbers>
#include <random>

#include "engine/report.h"

namespace penumbra::apps {

namespace {

constexpr int kW = 160, kH = 120;

StressRow makeRow(const std::string& name, const std::string& param) {
  StressRow row;
  row.name = name;
  row.param = param;
  return row;
}

struct Mesh2 {
  std::vector<glm::vec4> clip;  // clip positions
  std::vector<uint32_t> idx;
};

// Per-pixel coverage counts of a draw with the depth test off, and non-finite values seen.
std::vector<uint32_t> countCoverage(raster::Rasterizer& r, const Mesh2& m, StressRow& row) {
  raster::DepthTarget depth(kW, kH, 1.0f);
  std::vector<uint32_t> count(static_cast<size_t>(kW * kH), 0);
  raster::DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(m.clip.size());
  d.indices = m.idx;
  d.depthFunc = raster::DepthFunc::Always;
  d.varyings = 1;
  std::vector<uint64_t> bad(static_cast<size_t>(kW * kH), 0);
  const raster::PassStats st = r.draw(
      d, depth,
      [&](uint32_t i, float* v) {
        v[0] = static_cast<float>(i & 1023);
        return m.clip[i];
      },
      [&](const raster::Fragment& f) {
        const size_t p = static_cast<size_t>(f.y * kW + f.x);
        ++count[p];
        if (!std::isfinite(f.depth) || !std::isfinite(f.varyings[0]) || !std::isfinite(f.b0) || !std::isfinite(f.b1) ||
            !std::isfinite(f.b2))
          ++bad[p];
      });
  row.clipped += st.trianglesClipped;
  for (uint64_t b : bad) row.nonFinite += b;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (!std::isfinite(depth.at(x, y))) ++row.nonFinite;
  return count;
}

// Exactly-once check of a tessellation that covers the whole screen.
void checkOnce(const std::vector<uint32_t>& c, StressRow& row) {
  for (uint32_t n : c) {
    ++row.pixels;
    if (n == 0) ++row.cracks;
    if (n > 1) ++row.doubles;
  }
}

// Clip position of view-space point p (camera at the origin looking down -z), zero-to-one depth.
glm::vec4 perspective(const glm::dvec3& p, double f, double n, double far, bool reversed) {
  const double aspect = double(kW) / kH;
  const double a = reversed ? n / (far - n) : far / (n - far);
  const double b = reversed ? n * far / (far - n) : n * far / (n - far);
  return glm::vec4(static_cast<float>(p.x * f / aspect), static_cast<float>(p.y * f), static_cast<float>(a * p.z + b),
                   static_cast<float>(-p.z));
}

// A grid of (cells x cells) quads over [x0, x1] x [y0, y1] through a point-mapping function;
// diagonals alternate, vertices jittered inside by `jitter` of a cell.
template <class Map>
Mesh2 grid(int cells, double x0, double x1, double y0, double y1, double jitter, uint64_t seed, Map map) {
  Mesh2 m;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const double dx = (x1 - x0) / cells, dy = (y1 - y0) / cells;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      const bool border = i == 0 || j == 0 || i == cells || j == cells;
      const double jx = border ? 0 : u(rng) * jitter, jy = border ? 0 : u(rng) * jitter;
      m.clip.push_back(map(x0 + (i + jx) * dx, y0 + (j + jy) * dy));
    }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      if ((i + j) % 2)
        m.idx.insert(m.idx.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      else
        m.idx.insert(m.idx.end(), {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

glm::vec4 screenToClip(double sx, double sy) {
  return glm::vec4(static_cast<float>(sx / kW * 2.0 - 1.0), static_cast<float>(1.0 - sy / kH * 2.0), 0.5f, 1.0f);
}

StressRow farFromOrigin(raster::Rasterizer& r, int exponent) {
  StressRow row = makeRow("far from origin", "1e" + std::to_string(exponent));
  // A plane 10^k from the origin in float world coordinates, seen from 100 units: the view
  // transform cancels catastrophically at 1e7 (float ulp = 1), yet shared vertices snap alike.
  const double off = std::pow(10.0, exponent);
  const glm::dvec3 origin(off, off, off), eye = origin + glm::dvec3(0, 0, 100);
  // View-projection in float, as an engine holding float matrices would apply it.
  const double f = 1.0 / std::tan(0.5 * 60.0 * std::numbers::pi / 180.0);
  glm::mat4 view(1.0f);
  view[3] = glm::vec4(glm::vec3(-eye), 1.0f);
  // Jitter of +-0.2 cell plus float rounding (at most 0.5 / 6.25 = 0.08 cell at 1e7) never folds.
  const Mesh2 m = grid(48, -150, 150, -150, 150, 0.4, 1 + static_cast<uint64_t>(exponent), [&](double x, double y) {
    const glm::vec3 world = glm::vec3(origin + glm::dvec3(x, y, 0));  // float world position
    const glm::vec4 v = view * glm::vec4(world, 1.0f);
    return perspective(glm::dvec3(v), f, 1.0, 1000.0, false);
  });
  checkOnce(countCoverage(r, m, row), row);
  return row;
}

StressRow nearPlaneCrossing(raster::Rasterizer& r, double nearPlane) {
  StressRow row = makeRow("near-plane crossing", "n=" + std::to_string(nearPlane).substr(0, 6));
  // A ground plane under the camera (height 1, looking 10 degrees down): the triangles under and
  // behind the camera cross the near plane. Expected per pixel: the ray meets the plane inside
  // its extent and between the near and far planes.
  const double pitch = -10.0 * std::numbers::pi / 180.0, f = 1.0 / std::tan(0.5 * 70.0 * std::numbers::pi / 180.0);
  const double far = 1000.0, extent = 100.0, h = 1.0;
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  // World (x, z ground, y up) to view: rotate about x by -pitch after moving the camera to y = h.
  auto toView = [&](double x, double y, double z) {
    const double yy = y - h;  // rotation about x by -pitch
    return glm::dvec3(x, cp * yy + sp * z, -sp * yy + cp * z);
  };
  const Mesh2 m = grid(64, -extent, extent, -extent, extent, 0.5, 7, [&](double x, double z) {
    return perspective(toView(x, 0.0, z), f, nearPlane, far, false);
  });
  const auto c = countCoverage(r, m, row);
  const double aspect = double(kW) / kH;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double nx = (x + 0.5) / kW * 2 - 1, ny = 1 - (y + 0.5) / kH * 2;
      const glm::dvec3 dv(nx * aspect / f, ny / f, -1.0);  // view ray, view depth 1 per unit
      // View to world: inverse rotation.
      const glm::dvec3 dw(dv.x, cp * dv.y - sp * dv.z, sp * dv.y + cp * dv.z);
      if (dw.y >= -1e-9) {  // parallel or upward: no hit
        ++row.pixels;
        if (c[static_cast<size_t>(y * kW + x)] != 0) ++row.doubles;
        continue;
      }
      const double t = h / -dw.y;  // view depth of the hit (dv.z = -1 per unit t)
      const glm::dvec3 hit(t * dw.x, 0.0, t * dw.z);
      const double edge = std::min(extent - std::abs(hit.x), extent - std::abs(hit.z));
      if (std::abs(edge) < 0.75 || std::abs(t - nearPlane) < 1e-3 * nearPlane || std::abs(t - far) < 1.0) continue;
      const bool expect = edge > 0 && t > nearPlane && t < far;
      const uint32_t got = c[static_cast<size_t>(y * kW + x)];
      ++row.pixels;
      if (expect && got == 0) ++row.cracks;
      if ((expect && got > 1) || (!expect && got > 0)) ++row.doubles;
    }
  return row;
}

StressRow guardBand(raster::Rasterizer& r, int exponent) {
  StressRow row = makeRow("guard-band fan", "radius 1e" + std::to_string(exponent) + " px");
  // A fan of 64 triangles around the screen centre reaching 10^k pixels away.
  Mesh2 m;
  m.clip.push_back(screenToClip(kW * 0.5 + 0.3, kH * 0.5 + 0.1));
  const int n = 64;
  const double rad = std::pow(10.0, exponent);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n + 0.1;
    m.clip.push_back(screenToClip(kW * 0.5 + rad * std::cos(a), kH * 0.5 + rad * std::sin(a)));
  }
  for (int i = 0; i < n; ++i) m.idx.insert(m.idx.end(), {0u, 1u + static_cast<uint32_t>(i), 1u + static_cast<uint32_t>((i + 1) % n)});
  checkOnce(countCoverage(r, m, row), row);
  return row;
}

StressRow slivers(raster::Rasterizer& r, int count) {
  StressRow row = makeRow("sliver fan", std::to_string(count) + " triangles");
  // A fan of very thin triangles (360/count degrees each) covering the screen.
  Mesh2 m;
  m.clip.push_back(screenToClip(kW * 0.37 + 0.01, kH * 0.61 + 0.02));
  for (int i = 0; i < count; ++i) {
    const double a = 2.0 * std::numbers::pi * i / count;
    m.clip.push_back(screenToClip(kW * 0.37 + 1000.0 * std::cos(a), kH * 0.61 + 1000.0 * std::sin(a)));
  }
  for (int i = 0; i < count; ++i)
    m.idx.insert(m.idx.end(), {0u, 1u + static_cast<uint32_t>(i), 1u + static_cast<uint32_t>((i + 1) % count)});
  checkOnce(countCoverage(r, m, row), row);
  return row;
}

StressRow subPixel(raster::Rasterizer& r, double cellPixels) {
  StressRow row = makeRow("sub-pixel grid", std::to_string(cellPixels).substr(0, 5) + " px cells");
  const int cells = static_cast<int>(std::ceil((kW + 4) / cellPixels));
  const Mesh2 m = grid(cells, -2, -2 + cells * cellPixels, -2, -2 + cells * cellPixels, 0.5, 11,
                       [&](double x, double y) { return screenToClip(x, y); });
  checkOnce(countCoverage(r, m, row), row);
  return row;
}

// Two screen-filling quads at view depths d and d (1 + gap); which one is seen where.
StressRow depthOrder(raster::Rasterizer& r, const std::string& name, double ratio, double d, double gap, bool reversed) {
  StressRow row = makeRow(name, "far/near=1e" + std::to_string(static_cast<int>(std::lround(std::log10(ratio)))) +
                          " d=" + (d > 1000 ? std::to_string(static_cast<long>(d)) : std::to_string(d).substr(0, 5)) +
                          " gap=" + std::to_string(gap).substr(0, 8) + (reversed ? " reversed-Z" : " standard Z"));
  const double n = 1.0, far = ratio * n, f = 1.0;
  raster::DepthTarget depth(kW, kH, reversed ? 0.0f : 1.0f);
  std::vector<uint8_t> id(static_cast<size_t>(kW * kH), 0), bad(static_cast<size_t>(kW * kH), 0);
  Mesh2 m;
  for (int q = 0; q < 2; ++q) {
    const double z = -d * (q == 0 ? 1.0 + gap : 1.0);  // quad 0 farther, drawn first... then reversed order below
    const double s = 2.0 * d;
    for (const auto& c : {glm::dvec2(-s, -s), glm::dvec2(s, -s), glm::dvec2(s, s), glm::dvec2(-s, s)})
      m.clip.push_back(perspective(glm::dvec3(c.x, c.y, z), f, n, far, reversed));
  }
  raster::DrawDesc desc;
  desc.depthFunc = reversed ? raster::DepthFunc::Greater : raster::DepthFunc::Less;
  desc.varyings = 0;
  for (int order = 0; order < 2; ++order) {
    // Order 0: far quad first, then near; order 1: near first, then far.
    const uint32_t far4 = 0, near4 = 4;
    std::vector<uint32_t> idx;
    for (uint32_t base : order == 0 ? std::vector<uint32_t>{far4, near4} : std::vector<uint32_t>{near4, far4})
      idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    desc.indices = idx;
    desc.vertexCount = static_cast<uint32_t>(m.clip.size());
    depth.clear(reversed ? 0.0f : 1.0f);
    std::fill(id.begin(), id.end(), 0);
    r.draw(
        desc, depth, [&](uint32_t i, float*) { return m.clip[i]; },
        [&](const raster::Fragment& fr) {
          const size_t p = static_cast<size_t>(fr.y * kW + fr.x);  // tiles own their pixels: no race
          id[p] = fr.primitive / 2 == (order == 0 ? 1u : 0u) ? 1 : 2;  // 1 = near
          if (!std::isfinite(fr.depth)) bad[p] = 1;
        });
    for (size_t p = 0; p < id.size(); ++p) {
      ++row.pixels;
      if (id[p] != 1) ++row.depthErrors;
      row.nonFinite += bad[p];
    }
  }
  return row;
}

}  // namespace

std::string StressRow::json() const {
  engine::report::Json j;
  j["case"] = name;
  j["param"] = param;
  j["pixels"] = pixels;
  j["cracks"] = cracks;
  j["double_hits"] = doubles;
  j["non_finite"] = nonFinite;
  j["depth_order_errors"] = depthErrors;
  j["clipped"] = clipped;
  j["judged"] = judged;
  j["ok"] = ok();
  return engine::report::jsonLine(j);
}

std::vector<StressRow> runRasterStress(raster::Rasterizer& r) {
  std::vector<StressRow> rows;
  for (int k = 3; k <= 7; ++k) rows.push_back(farFromOrigin(r, k));
  for (double n : {1e-1, 1e-3, 1e-5}) rows.push_back(nearPlaneCrossing(r, n));
  for (int k = 4; k <= 8; ++k) rows.push_back(guardBand(r, k));
  for (int n : {1000, 20000}) rows.push_back(slivers(r, n));
  for (double c : {0.7, 0.3, 0.11}) rows.push_back(subPixel(r, c));
  for (int k = 3; k <= 7; ++k) {
    const double ratio = std::pow(10.0, k);
    // Reversed-Z: float depth keeps ~24 bits of relative precision at every distance.
    StressRow rev = depthOrder(r, "depth order", ratio, std::sqrt(ratio), 1e-4, true);
    rows.push_back(rev);
    rows.push_back(depthOrder(r, "depth order", ratio, 0.5 * ratio, 1e-4, true));
    // Standard Z loses precision with distance: the two depths differ by about (n / d) gap near
    // z = 1, where a float step is 2^-24. Judged only where that is at least 4 steps.
    const double d = std::sqrt(ratio), gap = 1e-4;
    StressRow st = depthOrder(r, "depth order", ratio, d, gap, false);
    st.judged = (1.0 / d) * gap >= 4.0 * std::ldexp(1.0, -24);
    if (!st.judged) st.note = "standard Z beyond its precision; use reversed-Z";
    rows.push_back(st);
  }
  StressRow hair = depthOrder(r, "coplanar, a hair apart", 1e4, 10.0, 1e-5, true);
  rows.push_back(hair);
  return rows;
}

}  // namespace penumbra::apps
