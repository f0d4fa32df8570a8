#include "engine/msaa_pass.h"

#include <algorithm>
#include <array>

#include "engine/gbuffer_pass.h"
#include "raster/timing.h"

namespace penumbra::engine {

namespace {

// What one sample saw: the instance (its index in plan.ordinary; -1: nothing), the triangle of its
// mesh and the perspective-correct barycentrics at the sample.
struct SampleHit {
  int32_t slot = -1;
  uint32_t primitive = 0;
  float b0 = 0, b1 = 0, b2 = 0;
};

// The layers of one pixel from its samples: per triangle seen its count and representative
// sample, largest count first (ties: the earlier instance, then the lower triangle), at most
// kMaxLayers; the samples of a triangle beyond those join the first kept layer of the same instance
// (a neighbour on the same surface), or the largest layer when none is of that instance. Returns
// true when samples joined another instance's layer.
bool resolveSamples(const SampleHit* hits, int samples, const std::array<int, raster::kMaxSamples>& order,
                    stochastic::ResolvedPixel& rp) {
  struct Group {
    int32_t slot;
    uint32_t primitive;
    uint16_t count;
    int rep;
    bool before(const Group& o) const {
      if (count != o.count) return count > o.count;
      return slot != o.slot ? slot < o.slot : primitive < o.primitive;
    }
  };
  std::array<Group, raster::kMaxSamples> g{};
  int groups = 0;
  rp = stochastic::ResolvedPixel{};
  for (int k = 0; k < samples; ++k) {
    const int s = order[static_cast<size_t>(k)];
    const SampleHit& h = hits[s];
    if (h.slot < 0) {
      ++rp.background;
      continue;
    }
    int i = 0;
    while (i < groups &&
           (g[static_cast<size_t>(i)].slot != h.slot || g[static_cast<size_t>(i)].primitive != h.primitive))
      ++i;
    if (i == groups)
      g[static_cast<size_t>(groups++)] = {h.slot, h.primitive, 0, s};  // the first seen is the nearest
    ++g[static_cast<size_t>(i)].count;
  }
  // Insertion sort (at most 8 groups).
  for (int i = 1; i < groups; ++i)
    for (int j = i; j > 0 && g[static_cast<size_t>(j)].before(g[static_cast<size_t>(j - 1)]); --j)
      std::swap(g[static_cast<size_t>(j)], g[static_cast<size_t>(j - 1)]);
  const int kept = std::min(groups, stochastic::kMaxLayers);
  rp.layers = static_cast<uint8_t>(kept);
  for (int l = 0; l < kept; ++l) {
    stochastic::ResolvedLayer& L = rp.layer[l];
    L.surface = static_cast<uint32_t>(g[static_cast<size_t>(l)].slot);
    L.count = g[static_cast<size_t>(l)].count;
    L.sample = static_cast<uint16_t>(g[static_cast<size_t>(l)].rep);
    L.triangle = g[static_cast<size_t>(l)].primitive;
  }
  bool acrossInstances = false;
  for (int d = kept; d < groups; ++d) {
    int into = 0;
    while (into < kept && rp.layer[into].surface != static_cast<uint32_t>(g[static_cast<size_t>(d)].slot))
      ++into;
    if (into == kept) into = 0, acrossInstances = true;
    rp.layer[into].count = static_cast<uint16_t>(rp.layer[into].count + g[static_cast<size_t>(d)].count);
  }
  return acrossInstances;
}

// The G-buffer texel of a sample, made as the ordinary pass makes one from its fragment.
GBufferTexel sampleTexel(const InstanceShading& sh, const SampleHit& h, int x, int y, float t,
                         const FramePlan& plan) {
  const Mesh& mesh = *sh.mesh;
  float v[3][kGbufferMaxVaryings];
  for (int k = 0; k < 3; ++k)
    vertexVaryings(mesh, sh, mesh.indices[static_cast<size_t>(h.primitive) * 3 + static_cast<size_t>(k)], t,
                   v[k]);
  float interp[kGbufferMaxVaryings];
  for (int c = 0; c < sh.varyings(); ++c) interp[c] = v[0][c] * h.b0 + v[1][c] * h.b1 + v[2][c] * h.b2;
  raster::Fragment f{};
  f.x = x, f.y = y;
  f.primitive = h.primitive;
  f.b0 = h.b0, f.b1 = h.b1, f.b2 = h.b2;
  f.varyings = interp;
  return gbufferTexel(sh, f, t, plan.camera.eye, plan.pixelAngle);
}

}  // namespace

void drawGBufferMultisample(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                            int samples, Frame& frame,
                            std::vector<raster::Image<shadows::Receiver>>& layerReceivers) {
  const auto t0 = raster::Clock::now();
  FrameStats& st = frame.stats;
  const int w = plan.width, h = plan.height;
  const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);
  std::vector<raster::DepthTarget> depth(static_cast<size_t>(samples));
  for (raster::DepthTarget& d : depth) {
    d.resize(w, h, 1.0f);
    raster.clear(d, 1.0f);
  }
  std::vector<SampleHit> hits(pixels * static_cast<size_t>(samples));
  const float shadeTime = plan.at ? plan.at->t : 0.0f;
  std::vector<InstanceShading> shading;
  for (size_t k = 0; k < plan.ordinary.size(); ++k) {
    const Instance& inst = scene.instances[plan.ordinary[k]];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    glm::mat4 ta, tb;
    plan.transforms(inst, ta, tb);
    shading.push_back(plan.at ? prepareInstance(scene, inst, inst.transform,
                                                inst.moves() ? *inst.transformClose : inst.transform)
                              : prepareInstance(scene, inst, ta, ta));
    const glm::mat4 mvp = plan.viewProj * ta;
    raster::DrawDesc desc;
    desc.vertexCount = static_cast<uint32_t>(mesh.positions.size());
    desc.indices = mesh.indices;
    const auto slot = static_cast<int32_t>(k);
    st.gbuffer += raster.drawSamples(
        desc, depth, [&](uint32_t i, float*) { return mvp * glm::vec4(mesh.positions[i], 1.0f); },
        [&](const raster::Fragment& f) {
          hits[(static_cast<size_t>(f.y) * static_cast<size_t>(w) + static_cast<size_t>(f.x)) *
                   static_cast<size_t>(samples) +
               static_cast<size_t>(f.sample)] = {slot, f.primitive, f.b0, f.b1, f.b2};
        });
    ++st.instancesOrdinary;
    st.trianglesOrdinary += mesh.indices.size() / 3;
  }

  // Resolve: layers per pixel, one texel and receiver per layer.
  constexpr int kLayers = stochastic::kMaxLayers;
  frame.resolved.resize(w, h);
  frame.spp = samples;
  frame.gbuffer.resize(w, h);
  frame.extraLayers.assign(static_cast<size_t>(kLayers - 1), raster::Image<GBufferTexel>(w, h));
  layerReceivers.assign(static_cast<size_t>(kLayers), raster::Image<shadows::Receiver>(w, h));
  const std::array<int, raster::kMaxSamples> order = raster::samplesNearestFirst(samples);
  st.msaaPixelsMerged = raster.run([&] {
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, h, 8), size_t{0},
        [&](const tbb::blocked_range<int>& rows, size_t merged) {
          for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
              const SampleHit* px =
                  &hits[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) *
                        static_cast<size_t>(samples)];
              stochastic::ResolvedPixel& rp = frame.resolved.at(x, y);
              merged += resolveSamples(px, samples, order, rp) ? 1 : 0;
              for (int l = 0; l < rp.layers; ++l) {
                const stochastic::ResolvedLayer& L = rp.layer[l];
                GBufferTexel& g =
                    l == 0 ? frame.gbuffer.at(x, y) : frame.extraLayers[static_cast<size_t>(l - 1)].at(x, y);
                g = sampleTexel(shading[L.surface], px[L.sample], x, y, shadeTime, plan);
                layerReceivers[static_cast<size_t>(l)].at(x, y) = {g.position, g.geometricNormal, 1u};
              }
            }
          return merged;
        },
        [](size_t a, size_t b) { return a + b; });
  });
  frame.depth = std::move(depth[0]);
  st.msaa = samples;
  st.msGbuffer = raster::msSince(t0);
}

}  // namespace penumbra::engine
