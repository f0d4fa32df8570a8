// Helpers shared by the engine tests.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "engine/renderer.h"
#include "raster/image.h"

namespace penumbra::engine::test {

// The visible pixels' bytes, RGBA, row by row: compare frames byte for byte.
inline std::vector<uint8_t> bytes(const raster::ImageRgba8& img) {
  std::vector<uint8_t> b;
  for (const raster::Rgba8& p : img.packed()) b.insert(b.end(), {p.r, p.g, p.b, p.a});
  return b;
}

// A frame from options the test means to be valid: an Error is a failure, with its message.
inline Frame renderFrame(Renderer& r, const Scene& scene, const RenderOptions& options) {
  Result<Frame> f = r.render(scene, options);
  if (!f) throw std::runtime_error("render failed: " + f.error().line());
  return std::move(*f);
}

}  // namespace penumbra::engine::test
