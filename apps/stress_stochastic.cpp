#include "apps/stress_stochastic.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "engine/report.h"
#include "stochastic/rasterizer.h"

namespace penumbra::apps {

std::string StochasticStressRow::json() const {
  engine::report::Json j;
  j["case"] = name;
  j["param"] = param;
  j["method"] = method;
  j["ms"] = engine::report::jsonNumber(ms);
  j["tests"] = tests;
  j["hits"] = hits;
  j["samples"] = samples;
  j["triangles"] = triangles;
  j["mismatches"] = mismatches;
  j["bad_depth"] = badDepth;
  j["ok"] = ok();
  return engine::report::jsonLine(j);
}

namespace {

constexpr int kW = 96, kH = 64, kSpp = 8;

struct Case {
  std::string name, param;
  std::vector<glm::vec4> c0, c1;
  std::vector<uint32_t> indices, surface;
  stochastic::ThinLens lens;
};

glm::mat4 projection() {
  return glm::perspectiveRH_ZO(glm::radians(60.0f), static_cast<float>(kW) / kH, 0.1f, 1000.0f);
}

void addTriangle(Case& c, const glm::mat4& proj, glm::vec3 a, glm::vec3 b, glm::vec3 d, glm::vec3 move) {
  for (const glm::vec3& p : {a, b, d}) {
    c.c0.push_back(proj * glm::vec4(p, 1.0f));
    c.c1.push_back(proj * glm::vec4(p + move, 1.0f));
    c.indices.push_back(static_cast<uint32_t>(c.indices.size()));
  }
  c.surface.push_back(static_cast<uint32_t>(c.surface.size()));
}

// A small fan of triangles around (x, y, z), moving by `move`.
void addFan(Case& c, const glm::mat4& proj, glm::vec3 at, float size, glm::vec3 move) {
  for (int i = 0; i < 6; ++i) {
    const float a0 = static_cast<float>(i) * 1.0472f, a1 = a0 + 1.0472f;
    addTriangle(c, proj, at, at + size * glm::vec3(std::cos(a0), std::sin(a0), 0.0f),
                at + size * glm::vec3(std::cos(a1), std::sin(a1), 0.0f), move);
  }
}

std::vector<Case> cases() {
  const glm::mat4 proj = projection();
  std::vector<Case> out;
  for (float screens : {0.5f, 5.0f, 50.0f, 500.0f, 5000.0f}) {  // screen widths crossed in one shutter (at z = -5)
    char label[32];
    std::snprintf(label, sizeof label, "%g screens", static_cast<double>(screens));
    Case c{"motion across", label, {}, {}, {}, {}, {}};
    addFan(c, proj, {-3.0f, 0.0f, -5.0f}, 0.6f, {screens * 5.8f, 0.3f, 0.0f});
    out.push_back(std::move(c));
  }
  for (float aperture : {0.05f, 0.5f, 5.0f, 50.0f}) {  // circle of confusion up to hundreds of screens
    char label[32];
    std::snprintf(label, sizeof label, "aperture %g", static_cast<double>(aperture));
    Case c{"huge circle of confusion", label, {}, {}, {}, {}, {}};
    c.lens = stochastic::makeThinLens(proj[0][0], proj[1][1], aperture, 40.0f);
    addFan(c, proj, {0.0f, 0.0f, -2.0f}, 0.5f, {0.0f, 0.0f, 0.0f});
    addFan(c, proj, {1.0f, 0.5f, -200.0f}, 20.0f, {0.0f, 0.0f, 0.0f});
    out.push_back(std::move(c));
  }
  {
    Case c{"zero-length motion", "c0 == c1", {}, {}, {}, {}, {}};
    addFan(c, proj, {0.0f, 0.0f, -4.0f}, 1.0f, {0.0f, 0.0f, 0.0f});
    out.push_back(std::move(c));
  }
  {
    Case c{"degenerate", "collinear, point, sliver", {}, {}, {}, {}, {}};
    addTriangle(c, proj, {0, 0, -5}, {1, 1, -5}, {2, 2, -5}, {1, 0, 0});
    addTriangle(c, proj, {0, 0, -5}, {0, 0, -5}, {0, 0, -5}, {0, 2, 0});
    addTriangle(c, proj, {-2, 0, -5}, {2, 0.0001f, -5}, {2, 0, -5}, {0, 1, 0});
    addTriangle(c, proj, {0, 0, -5}, {1, 0, -5}, {0, 1, -5}, {0, 0, 0});
    out.push_back(std::move(c));
  }
  {
    Case c{"camera plane crossing", "z from +3 to -3", {}, {}, {}, {}, {}};
    addTriangle(c, proj, {-1, -1, 3}, {1, -1, 3}, {0, 1, 2}, {0.5f, 0, -6});
    addTriangle(c, proj, {-3, -1, -0.5f}, {3, -1, 0.5f}, {0, 2, -0.05f}, {0, 0, -1});
    out.push_back(std::move(c));
  }
  {
    // A triangle reaching 1e6 units off screen (guard-band clipping at every sample) sweeping by 2e5.
    Case c{"huge coordinates", "1e6 units, moving 2e5", {}, {}, {}, {}, {}};
    addTriangle(c, proj, {-1e6f, -300.0f, -900.0f}, {1e6f, -300.0f, -900.0f}, {0.0f, 1e6f, -900.0f}, {2e5f, 0.0f, 0.0f});
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

std::vector<StochasticStressRow> runStochasticStress(raster::Rasterizer& rast) {
  std::vector<StochasticStressRow> rows;
  stochastic::StochasticRasterizer sr(rast);
  for (const Case& c : cases()) {
    const stochastic::StochasticInput in{c.c0, c.c1, c.indices, c.surface, raster::CullMode::None, c.lens, true};
    auto run = [&](stochastic::BoundMethod m, bool exhaustive, std::vector<uint32_t>& tri, std::vector<float>& depth) {
      stochastic::StochasticConfig cfg;
      cfg.method = m;
      cfg.exhaustive = exhaustive;
      cfg.pattern.spp = kSpp;
      raster::Image<stochastic::ResolvedPixel> out(kW, kH);
      stochastic::StochasticDebug dbg;
      dbg.sampleTriangle = &tri;
      dbg.sampleDepth = &depth;
      return sr.render(in, cfg, {}, out, dbg);
    };
    std::vector<uint32_t> refTri;
    std::vector<float> refDepth;
    run(stochastic::BoundMethod::Box, true, refTri, refDepth);
    for (stochastic::BoundMethod m :
         {stochastic::BoundMethod::Box, stochastic::BoundMethod::Interval, stochastic::BoundMethod::DualSpace}) {
      std::vector<uint32_t> tri;
      std::vector<float> depth;
      const stochastic::StochasticStats st = run(m, false, tri, depth);
      StochasticStressRow r;
      r.name = c.name, r.param = c.param, r.method = stochastic::boundMethodName(m);
      r.tests = st.tests, r.hits = st.hits, r.samples = st.samples, r.triangles = st.triangles, r.ms = st.msTotal;
      for (size_t i = 0; i < tri.size(); ++i) {
        if (tri[i] != refTri[i] || std::memcmp(&depth[i], &refDepth[i], sizeof(float)) != 0) ++r.mismatches;
        if (!(depth[i] >= 0.0f && depth[i] <= 1.0f)) ++r.badDepth;
      }
      rows.push_back(r);
    }
  }
  return rows;
}

}  // namespace penumbra::apps
