// The standard rasterizer workloads W1 (depth-only 2048^2 shadow-map pass) and W2 (shaded 1080p
// pass) of shared/WORKLOADS.md, on one world-space triangle mesh.
// Thread-safety: pure functions of their arguments; runWorkload owns its rasterizer.
#pragma once

#include <glm/mat4x4.hpp>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "raster/pipeline.h"

namespace penumbra::apps {

struct WorkloadResult {
  std::string name, workload, res;
  size_t tris = 0;
  int threads = 0;
  int frames = 0;
  double medianMs = 0, minMs = 0, maxMs = 0, mtrisPerS = 0;
  raster::PassStats stats;  // of the last frame
  int samples = 1;          // W2 multisampled: samples per pixel
  double edgeRmse = -1;     // >= 0: the antialiasing error (w2EdgeError) at these samples
  size_t edgePixels = 0;
  std::string json() const;
  std::string line() const;
};

// The view fit of WORKLOADS.md: c = bounding-box centre, r = largest distance from c to a vertex.
struct ViewFit {
  glm::vec3 centre{0.0f};
  float radius = 1.0f;
};
ViewFit fitView(const engine::Mesh& mesh);

glm::mat4 w1LightMatrix(const ViewFit& fit);
glm::mat4 w2CameraMatrix(const ViewFit& fit, glm::vec3* lightDir);

// Runs W1 or W2 ("W1", "W2") on `mesh` with `threads` threads: 3 warm-up frames, then at least
// `minFrames` frames and `minSeconds`. Each frame clears and draws everything.
// `config.threads` is replaced by `threads`; the other fields (tile size, chunk and batch sizes)
// are used as given.
WorkloadResult runWorkload(const std::string& workload, const std::string& meshName, const engine::Mesh& mesh,
                           int threads, int minFrames, double minSeconds, raster::ImageRgba8* colorOut = nullptr,
                           raster::DepthTarget* depthOut = nullptr, raster::RasterConfig config = {});

// W2 multisampled (samples in {2, 4, 8}): each sample's triangle and barycentrics, then per pixel
// one shaded texel per triangle seen, blended by sample counts (the engine's msaa resolve), timed
// like runWorkload. Its workload name is "W2x<samples>".
WorkloadResult runW2Multisample(const std::string& meshName, const engine::Mesh& mesh, int threads, int samples,
                                int minFrames, double minSeconds);

// Antialiasing error of W2's image at width x height with `samples` samples per pixel against a
// 16 x 16 supersampled reference (the ordinary pass at 16 times the resolution, box-filtered):
// RMSE of linear RGB over the silhouette pixels (those whose 256 sub-pixels are partly covered).
struct EdgeError {
  double rmse = 0;
  size_t edgePixels = 0;
};
EdgeError w2EdgeError(const engine::Mesh& mesh, int samples, int width, int height, int threads);

}  // namespace penumbra::apps
