#include "engine/shadow_pass.h"

#include <tbb/parallel_for.h>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "raster/timing.h"

namespace penumbra::engine {

namespace {

// The instances that may shadow a receiver of the light's region, flattened to world space at
// the casters' time; with `motion` (a frame over the whole shutter with a moving instance), every
// vertex also at shutter open and close (ShadowInputs::castersOpen), and a moving instance is culled
// by the box of its path's ends (its box at any time lies inside: the transform is their blend).
struct Casters {
  std::vector<glm::vec3> positions, open, close;
  std::vector<uint32_t> indices;
  std::vector<uint8_t> closed;  // per triangle (shadows::Geometry::closed)
  size_t movingTriangles = 0;
};

Casters flattenCasters(const Scene& scene, const shadows::RectLight& light,
                       const shadows::LightRegion& region, float casterTime, bool motion, bool cull,
                       LightShadowStats& st) {
  Casters c;
  bool anyMoves = false;
  for (const Instance& inst : scene.instances) {
    const Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
    const bool moves = inst.moves();
    const glm::mat4 transform = moves ? inst.transformAt(casterTime) : inst.transform;
    const bool sweep = motion && moves;
    const auto corner = [&](const glm::mat4& tr, int k) {
      return glm::vec3(tr * glm::vec4((k & 1) ? m.boundsMax.x : m.boundsMin.x,
                                      (k & 2) ? m.boundsMax.y : m.boundsMin.y,
                                      (k & 4) ? m.boundsMax.z : m.boundsMin.z, 1.0f));
    };
    glm::vec3 corners[8];
    for (int k = 0; k < 8; ++k) corners[k] = corner(transform, k);
    if (sweep) {  // the world box of both ends
      glm::vec3 lo(INFINITY), hi(-INFINITY);
      for (int k = 0; k < 16; ++k) {
        const glm::vec3 p = corner(k < 8 ? inst.transform : *inst.transformClose, k & 7);
        lo = glm::min(lo, p), hi = glm::max(hi, p);
      }
      for (int k = 0; k < 8; ++k)
        corners[k] = {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    }
    if (m.indices.empty()) continue;
    if (cull && !region.mayShadow(light, corners)) {
      ++st.instancesCulled;
      continue;
    }
    const uint32_t base = static_cast<uint32_t>(c.positions.size());
    for (const glm::vec3& p : m.positions) c.positions.push_back(glm::vec3(transform * glm::vec4(p, 1.0f)));
    for (uint32_t i : m.indices) c.indices.push_back(base + i);
    // A mirroring transform turns the winding inside out: such an instance counts as open.
    const bool closed = m.closed && glm::determinant(glm::mat3(transform)) > 0.0f;
    c.closed.insert(c.closed.end(), m.indices.size() / 3, closed ? 1 : 0);
    if (!motion) continue;
    for (const glm::vec3& p : m.positions) {
      c.open.push_back(sweep ? glm::vec3(inst.transform * glm::vec4(p, 1.0f)) : c.positions[c.open.size()]);
      c.close.push_back(sweep ? glm::vec3(*inst.transformClose * glm::vec4(p, 1.0f))
                              : c.positions[c.close.size()]);
    }
    anyMoves = anyMoves || sweep;
    if (sweep) c.movingTriangles += m.indices.size() / 3;
  }
  if (!anyMoves) c.open.clear(), c.close.clear();
  return c;
}

// V of one area light over the receivers.
raster::ImageFloat lightVisibility(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                                   const ResolvedOptions& options, const shadows::ReceiverImage& rec,
                                   const shadows::RectLight& light, LightShadowStats& st) {
  const auto t0 = raster::Clock::now();
  shadows::LightRegion region;
  raster.run([&] { region = shadows::fitRegion(light, rec); });
  st.receivers = region.receivers;
  st.receiversBehind = region.receiversBehind;
  st.receiversOutside = region.receiversOutside;
  // Casters over the whole shutter: a frame that samples time (not one fixed sample's time).
  const bool motion =
      options.options.shadowMotion && !plan.at && options.technique && options.technique->samplesTime;
  const Casters casters =
      flattenCasters(scene, light, region, plan.casterTime, motion, options.options.shadowCulling, st);
  st.trianglesFlattened = casters.indices.size() / 3;
  st.trianglesMoving = casters.movingTriangles;
  st.casterTime = plan.casterTime;
  st.msFlatten = raster::msSince(t0);
  if (!options.technique) return raster::ImageFloat(rec.width(), rec.height(), 1.0f);  // "none": unshadowed
  shadows::ShadowInputs in;
  in.casters = {casters.positions, casters.indices, casters.closed};
  in.castersOpen = casters.open;
  in.castersClose = casters.close;
  in.receivers = &rec;
  in.light = light;
  in.cache = options.options.cache.get();
  in.cullCasters = options.options.shadowCulling;
  shadows::ShadowResult r = shadows::computeShadows(raster, in, *options.technique, options.params);
  st.trianglesCulled = r.trianglesCulled;
  st.skipped = r.skipped;
  st.skipReason = r.skipReason;
  st.times = r.times;
  st.msFit = r.msFit;
  st.notes = std::move(r.notes);
  st.maps = r.mapPasses;
  return std::move(r.visibility);
}

}  // namespace

shadows::ReceiverImage stackReceivers(raster::Rasterizer& raster, const Frame& frame,
                                      const std::vector<raster::Image<shadows::Receiver>>& layerReceivers) {
  const int w = frame.gbuffer.width(), h = frame.gbuffer.height();
  const int layers = layerReceivers.empty() ? 1 : static_cast<int>(layerReceivers.size());
  shadows::ReceiverImage rec;
  raster.run([&] {
    rec.resizeParallel(w, h * layers);  // padding stays invalid
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          if (layerReceivers.empty()) {
            const GBufferTexel& g = frame.gbuffer.at(x, y);
            rec.at(x, y) = {g.position, g.geometricNormal, g.material >= 0 ? 1u : 0u};
            continue;
          }
          const int n = frame.resolved.at(x, y).layers;
          for (int l = 0; l < layers; ++l) {
            shadows::Receiver r = layerReceivers[static_cast<size_t>(l)].at(x, y);
            if (l >= n) r.valid = 0;
            rec.at(x, y + l * h) = r;
          }
        }
    });
  });
  return rec;
}

std::vector<raster::ImageFloat> runShadowPass(raster::Rasterizer& raster, const Scene& scene,
                                              const FramePlan& plan, const ResolvedOptions& options,
                                              const shadows::ReceiverImage& receivers, FrameStats& stats) {
  const auto t0 = raster::Clock::now();
  std::vector<raster::ImageFloat> visibility;
  for (const shadows::RectLight& light : scene.areaLights) {
    LightShadowStats ls;
    ls.technique = options.technique ? options.technique->name : "none";
    ls.params = options.technique ? options.params.changed() : "";
    visibility.push_back(lightVisibility(raster, scene, plan, options, receivers, light, ls));
    stats.shadows.push_back(std::move(ls));
  }
  stats.msShadows = raster::msSince(t0);
  return visibility;
}

}  // namespace penumbra::engine
