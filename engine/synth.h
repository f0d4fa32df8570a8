// The synthetic benchmark mesh `synth N` of shared/WORKLOADS.md: an 8x8 grid of UV spheres, vertex
// and index order identical to tools/llvmpipe_bench make_synth(), so both tools rasterize the same
// triangles. Pure function.
// Thread-safety: a pure function; safe from any thread.
#pragma once

#include "engine/scene.h"

namespace penumbra::engine {

// R is the ring count that brings the total triangle count nearest to `targetTriangles`
// (ties to the smaller R): R = 63 for 1,000,000 (999,936 triangles), 125 for 4,000,000.
Mesh makeSynthMesh(long targetTriangles);

}  // namespace penumbra::engine
