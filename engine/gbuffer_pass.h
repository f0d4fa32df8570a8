// The G-buffer pass: the ordinary path's instances drawn through the pipeline (raster/pipeline.h)
// into world position, normal, albedo and material per pixel, and the building blocks the
// stochastic pass (stochastic_pass.h) shares to make its layers' texels the same way.
//
// Per instance: its material and texture, normal matrices and the texture's texels per world unit
// of each triangle (the level of detail); per vertex 8 varyings (world position, world normal,
// uv), 11 with vertex colors, at a shutter time; per fragment a texel (the normal faces the viewer; the texture sampled
// trilinearly at the fragment's level of detail).
//
// Thread-safety: InstanceShading is immutable once prepared; vertexVaryings and gbufferTexel are
// pure (the pipeline calls them from several threads); drawGBuffer runs in the rasterizer's arena.
#pragma once

#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <vector>

#include "engine/frame.h"
#include "engine/frame_plan.h"
#include "engine/scene.h"
#include "raster/pipeline.h"

namespace penumbra::engine {

inline constexpr int kGbufferVaryings = 8;       // world position, world normal, uv
inline constexpr int kGbufferMaxVaryings = 11;   // and the vertex color (Mesh::colors)

// What the G-buffer needs of one instance, with transforms t0 at shutter open and t1 at close.
struct InstanceShading {
  const Mesh* mesh = nullptr;
  int32_t instance = -1;  // index in scene.instances
  const Material* mat = nullptr;
  const Texture* tex = nullptr;
  int32_t material = -1;  // the G-buffer's material index
  glm::mat4 t0{1.0f}, t1{1.0f};
  glm::mat3 n0{1.0f}, n1{1.0f};
  bool moves = false, hasUv = false, hasColor = false;
  std::vector<float> texelsPerUnit;
  int varyings() const { return hasColor ? kGbufferMaxVaryings : kGbufferVaryings; }
};
InstanceShading prepareInstance(const Scene& scene, const Instance& inst, const glm::mat4& t0, const glm::mat4& t1);

// The G-buffer varyings of vertex i at shutter time t: positions and normals move on straight
// lines (a static instance gives the shutter-open values bit for bit).
void vertexVaryings(const Mesh& mesh, const InstanceShading& sh, uint32_t i, float t, float* v);

// One G-buffer texel from a fragment of the mesh's triangle f.primitive at shutter time t (the
// ordinary pass and the stochastic layers alike).
GBufferTexel gbufferTexel(const InstanceShading& sh, const raster::Fragment& f, float t, const glm::vec3& eye,
                          float pixelAngle);

// The unit face normal of the mesh's triangle `primitive` at shutter time t in world space, turned
// to face `towards` (from a point on it); the shading normal `fallback` for a degenerate triangle.
glm::vec3 faceNormal(const InstanceShading& sh, uint32_t primitive, float t, const glm::vec3& pointOn,
                     const glm::vec3& towards, const glm::vec3& fallback);

// The material of a G-buffer texel's index (InstanceShading::material): the scene's, or the default
// material for the index one past the scene's list.
const Material& gbufferMaterial(const Scene& scene, int32_t material);

// Clears frame.depth and frame.gbuffer to the plan's size and draws the plan's ordinary instances
// (a fixed-sample frame: at its time); fills stats.gbuffer, instancesOrdinary, trianglesOrdinary,
// msGbuffer.
void drawGBuffer(raster::Rasterizer& raster, const Scene& scene, const FramePlan& plan, Frame& frame);

}  // namespace penumbra::engine
