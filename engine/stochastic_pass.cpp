#include "engine/stochastic_pass.h"

#include <algorithm>
#include <glm/geometric.hpp>

#include "engine/gbuffer_pass.h"
#include "raster/timing.h"
#include "stochastic/rasterizer.h"

namespace penumbra::engine {

namespace {

constexpr uint32_t kTriangleLimit = 0xFFFFFFF0u;  // above: kStaticSurface, kNoTriangle

// The stochastic instances flattened: clip positions at shutter open and close, indices, the
// surface (instance) of each triangle, where each instance's triangles start, its shading.
struct StochasticGeometry {
  std::vector<glm::vec4> clip0, clip1;
  std::vector<uint32_t> indices, surface, triStart;
  std::vector<InstanceShading> shading;
  std::vector<size_t> instances;
  bool anyMotion = false;
};

StochasticGeometry flatten(const Scene& scene, const FramePlan& plan) {
  StochasticGeometry g;
  g.instances = plan.stochastic;
  for (size_t vi : plan.stochastic) {
    const Instance& inst = scene.instances[vi];
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    glm::mat4 ta, tb;
    plan.transforms(inst, ta, tb);
    g.shading.push_back(prepareInstance(scene, inst, ta, tb));
    g.anyMotion |= g.shading.back().moves;
    const glm::mat4 m0 = plan.viewProj * ta, m1 = plan.viewProj * tb;
    const uint32_t base = static_cast<uint32_t>(g.clip0.size());
    for (const glm::vec3& p : mesh.positions) {
      g.clip0.push_back(m0 * glm::vec4(p, 1.0f));
      g.clip1.push_back(m1 * glm::vec4(p, 1.0f));
    }
    g.triStart.push_back(static_cast<uint32_t>(g.indices.size() / 3));
    for (uint32_t i : mesh.indices) g.indices.push_back(base + i);
    g.surface.resize(g.indices.size() / 3, static_cast<uint32_t>(vi));
  }
  g.triStart.push_back(static_cast<uint32_t>(g.indices.size() / 3));
  return g;
}

// Makes one layer's G-buffer texel and shadow receiver from the pixel's samples on its surface.
class LayerBuilder {
 public:
  LayerBuilder(const Scene& scene, const FramePlan& plan, const StochasticGeometry& geo, const stochastic::ThinLens& lens,
               int spp)
      : scene_(scene), plan_(plan), geo_(geo), lens_(lens), spp_(spp),
        target_(stochastic::makeSampleTarget(plan.width, plan.height, raster::CullMode::None)) {}

  void build(int x, int y, const stochastic::ResolvedLayer& L, const uint32_t* ref, const stochastic::Sample* samples,
             GBufferTexel& g, shadows::Receiver& rcv) const {
    const size_t k = static_cast<size_t>(std::upper_bound(geo_.triStart.begin(), geo_.triStart.end(), L.triangle) -
                                         geo_.triStart.begin() - 1);
    const InstanceShading& sh = geo_.shading[k];
    const Mesh& mesh = scene_.meshes[static_cast<size_t>(scene_.instances[geo_.instances[k]].mesh)];
    glm::vec3 sumP(0.0f), sumN(0.0f), sumG(0.0f), sumA(0.0f);
    GBufferTexel first;
    bool same = true;
    int n = 0;
    for (int s = 0; s < spp_; ++s) {
      const uint32_t tri = ref[s];
      if (tri >= kTriangleLimit || geo_.surface[tri] != L.surface) continue;
      const uint32_t prim = tri - geo_.triStart[k];  // the same instance: the same surface
      raster::Fragment f{};
      float out[raster::kMaxVaryings + 3];
      if (!fragment(mesh, sh, tri, prim, samples[s], x, y, f, out)) continue;
      f.primitive = prim;
      const GBufferTexel t = gbufferTexel(sh, f, samples[s].t, plan_.camera.eye, plan_.pixelAngle);
      if (s == L.sample) rcv = receiver(mesh, sh, f, t);
      if (n == 0) first = t;
      same &= t.position == first.position && t.normal == first.normal && t.albedo == first.albedo;
      sumP += t.position, sumN += t.normal, sumG += t.geometricNormal, sumA += t.albedo;
      ++n;
    }
    if (n == 0) {  // cannot happen (the resolve found these samples covered): blend as background
      g.material = -1;
      return;
    }
    if (same && !sh.moves) {
      g = first;
      rcv = {g.position, g.geometricNormal, 1u};
      return;
    }
    const float inv = 1.0f / static_cast<float>(n);
    g.position = sumP * inv;
    const float ln = glm::length(sumN), lg = glm::length(sumG);
    g.normal = ln > 0.0f ? sumN / ln : first.normal;
    g.geometricNormal = lg > 0.0f ? sumG / lg : first.geometricNormal;
    g.albedo = sumA * inv;
    g.material = first.material;
    g.instance = first.instance;
    g.triangle = first.triangle;  // of the first sample that saw the surface
    g.bary = first.bary;
  }

 private:
  // The fragment of triangle tri (the mesh's triangle prim) at sample `at` of pixel (x, y), as the
  // pipeline would make it.
  bool fragment(const Mesh& mesh, const InstanceShading& sh, uint32_t tri, uint32_t prim, const stochastic::Sample& at,
                int x, int y, raster::Fragment& f, float* out) const {
    glm::vec4 c[3];
    float vary[3][kGbufferMaxVaryings];
    const float* vp[3];
    for (int j = 0; j < 3; ++j) {
      const uint32_t vtx = geo_.indices[static_cast<size_t>(tri) * 3 + static_cast<size_t>(j)];
      c[j] = stochastic::clipAt(geo_.clip0[vtx], geo_.anyMotion ? geo_.clip1[vtx] : geo_.clip0[vtx], at.t, at.u, at.v,
                                lens_);
      vertexVaryings(mesh, sh, mesh.indices[static_cast<size_t>(prim) * 3 + static_cast<size_t>(j)], at.t, vary[j]);
      vp[j] = vary[j];
    }
    return stochastic::sampleFragment(c, vp, sh.varyings(), target_, x, y, f, out);
  }

  // The shadow receiver of the layer's median-time sample; a moving surface at the same
  // barycentric point at the casters' time.
  shadows::Receiver receiver(const Mesh& mesh, const InstanceShading& sh, const raster::Fragment& f,
                             const GBufferTexel& t) const {
    if (!sh.moves) return {t.position, t.geometricNormal, 1u};
    glm::vec3 rp(0.0f);
    const float b[3] = {f.b0, f.b1, f.b2};
    for (int j = 0; j < 3; ++j) {
      float v[kGbufferMaxVaryings];
      vertexVaryings(mesh, sh, mesh.indices[static_cast<size_t>(f.primitive) * 3 + static_cast<size_t>(j)],
                     plan_.casterTime, v);
      rp += glm::vec3(v[0], v[1], v[2]) * b[j];
    }
    // The face at the casters' time, on the side the layer's sample saw.
    glm::vec3 rn = faceNormal(sh, f.primitive, plan_.casterTime, rp, rp + t.geometricNormal, t.geometricNormal);
    return {rp, rn, 1u, plan_.casterTime};
  }

  const Scene& scene_;
  const FramePlan& plan_;
  const StochasticGeometry& geo_;
  stochastic::ThinLens lens_;
  int spp_;
  stochastic::SampleTarget target_;
};

}  // namespace

void runStochasticPass(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan,
                       const ResolvedOptions& options, Frame& frame,
                       std::vector<raster::Image<shadows::Receiver>>& layerReceivers) {
  const auto t0 = raster::Clock::now();
  FrameStats& st = frame.stats;
  const int w = plan.width, h = plan.height;
  const StochasticGeometry geo = flatten(scene, plan);
  st.instancesStochastic = geo.instances.size();
  st.trianglesStochastic = geo.indices.size() / 3;
  raster::Image<uint8_t> covered(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) covered.at(x, y) = frame.gbuffer.at(x, y).material >= 0 ? 1 : 0;
  const stochastic::ThinLens lens = plan.lensActive ? plan.lens : stochastic::ThinLens{};
  const stochastic::StochasticInput in{geo.clip0, geo.clip1, geo.indices, geo.surface, raster::CullMode::None, lens,
                                       geo.anyMotion};
  const stochastic::StochasticConfig& cfg = options.sampling;
  frame.resolved.resize(w, h);
  frame.spp = cfg.pattern.spp;
  constexpr int layers = stochastic::kMaxLayers;
  raster::Image<GBufferTexel> layer0(w, h);
  frame.extraLayers.assign(static_cast<size_t>(layers - 1), raster::Image<GBufferTexel>(w, h));
  layerReceivers.assign(static_cast<size_t>(layers), raster::Image<shadows::Receiver>(w, h));
  const LayerBuilder builder(scene, plan, geo, lens, frame.spp);
  const stochastic::PixelSink sink = [&](int x, int y, const stochastic::ResolvedPixel& rp, const uint32_t* ref,
                                         const stochastic::Sample* samples) {
    for (int l = 0; l < rp.layers; ++l) {
      const stochastic::ResolvedLayer& L = rp.layer[l];
      GBufferTexel& g = l == 0 ? layer0.at(x, y) : frame.extraLayers[static_cast<size_t>(l - 1)].at(x, y);
      shadows::Receiver& rcv = layerReceivers[static_cast<size_t>(l)].at(x, y);
      if (L.surface == stochastic::kStaticSurface) {
        g = frame.gbuffer.at(x, y);
        rcv = {g.position, g.geometricNormal, g.material >= 0 ? 1u : 0u};
        continue;
      }
      builder.build(x, y, L, ref, samples, g, rcv);
    }
  };
  stochastic::StochasticRasterizer sr(raster);
  st.stoch = sr.render(in, cfg, {&frame.depth, &covered}, frame.resolved, options.options.debug, &sink);
  st.boundMethod = stochastic::boundMethodName(cfg.method);
  st.msStochastic = raster::msSince(t0);
  frame.gbuffer = std::move(layer0);
}

}  // namespace penumbra::engine
