// Helpers shared by the raster tests.
#pragma once

#include <glm/glm.hpp>
#include <random>
#include <span>
#include <vector>

#include "raster/pipeline.h"

namespace penumbra::raster::test {

// Clip position of a screen-space point (pixels, y down) at depth z in [0, 1], with w = w.
inline glm::vec4 clipFromScreen(double sx, double sy, double z, double w, int width, int height) {
  const double nx = sx / width * 2.0 - 1.0, ny = 1.0 - sy / height * 2.0;
  return glm::vec4(static_cast<float>(nx * w), static_cast<float>(ny * w), static_cast<float>(z * w),
                   static_cast<float>(w));
}

// Number of times each pixel is shaded by the fragment path (depth test off).
inline std::vector<uint32_t> drawCount(Rasterizer& r, int width, int height, std::span<const glm::vec4> verts,
                                       std::span<const uint32_t> indices, CullMode cull = CullMode::None,
                                       PassStats* stats = nullptr) {
  DepthTarget depth(width, height, 1.0f);
  std::vector<uint32_t> count(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  DrawDesc d;
  d.vertexCount = static_cast<uint32_t>(verts.size());
  d.indices = indices;
  d.cull = cull;
  d.depthFunc = DepthFunc::Always;
  d.depthWrite = false;
  const PassStats st = r.draw(
      d, depth, [&](uint32_t i, float*) { return verts[i]; },
      [&](const Fragment& f) { ++count[static_cast<size_t>(f.y) * static_cast<size_t>(width) + static_cast<size_t>(f.x)]; });
  if (stats) *stats = st;
  return count;
}

}  // namespace penumbra::raster::test
