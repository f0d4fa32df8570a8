// What the module's Python functions do, apart from argument binding (module.cpp): the Scene a
// Python program builds, render() and rasterize() with the GIL released while the pipeline runs.
//
// Thread-safety: a PyScene may be rendered from several Python threads at once (renders only
// read it); changing it while a render runs raises penumbra.Error.
#pragma once

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "convert.h"
#include "engine/scene.h"

namespace penumbra::python {

struct PyScene {
  engine::Scene scene;
  bool validated = false;                   // validateScene ran since the last change
  std::optional<float> cameraAspect;        // set_camera_matrices: the projection's width / height
  std::atomic<int> rendering{0};            // renders in flight (the GIL is released during them)
  std::optional<engine::SkyLight> userSky;  // the sky before default lighting replaced it

  // Raises when a render is in flight; marks the scene as changed.
  void beginChange(const char* what);
};

struct RenderArgs {
  int width = 640, height = 360;
  std::string shadow = "pcss";
  std::vector<std::string> params;  // "name=value"
  int spp = 16;
  int msaa = 1;
  int threads = 0;
  std::vector<std::string> aov;  // buffer names (aov_names())
  double exposure = 0.0;
  std::string tonemap = "none";
  int64_t frame = 0;
  bool stats = false;
  bool defaultLight = true;  // a scene without lights is lit like `penumbra render` lights it
  uint64_t maxMemory = 0;    // 0: the memory available
};

// The names render() accepts in `aov`, in the order the dict lists them.
std::vector<std::string> aovNames();

py::dict render(PyScene& scene, const RenderArgs& args);

// The bare pipeline: clip-space vertices (N x 4) and triangles (M x 3) into a width x height
// target, depth test less, per pixel the nearest triangle's index, depth z/w and perspective-correct
// barycentrics.
py::dict rasterize(py::handle verticesClip, py::handle triangles, int width, int height,
                   const std::string& cull, int threads);

// The scalar reference rasterizer (raster/reference.h) on one triangle (3 x 4 clip-space vertices,
// w > 0, |x/w|, |y/w| <= 2): per pixel how many times its centre is covered (0 or 1), for
// checking rasterize() against it.
py::array_t<uint32_t> referenceCoverage(py::handle triangle, int width, int height);

// Writes an image array: uint8 H x W x 4 (or 3, alpha 255) as PNG (sRGB bytes as given), float32
// H x W, H x W x 3 or x 4 as OpenEXR (.exr path). Atomic: a failure leaves no file.
void writeImageArray(const std::string& path, py::handle image);

}  // namespace penumbra::python
