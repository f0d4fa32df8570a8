// Memory before it is allocated: an estimate of what a frame will hold at its peak, from the scene
// and the options alone (no allocation), and the limit it is held to -- the memory the machine has
// available now (/proc/meminfo MemAvailable), or what the user sets (--max-memory). A frame that
// would exceed it is refused with one line before any work, instead of failing after minutes.
//
// The estimate counts, at the sizes the code allocates them: the per-pixel targets (depth and
// coarse depth, the G-buffer, linear and sRGB color), per layer (three after a stochastic pass:
// resolved pixels, extra G-buffer layers) the receivers and each area light's V; the largest draw's
// vertex-stage buffers and one front-end batch; the stochastic pass's clip positions; per area light
// the casters flattened to world space (every instance: triangles after instancing) and the
// technique's own peak (TechniqueInfo::peakBytes). It is an upper estimate within some tens of
// percent (allocator overhead and TBB's per-thread scratch are not modelled).
//
// Thread-safety: pure functions (availableMemoryBytes reads /proc).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/error.h"
#include "engine/render_options.h"
#include "engine/scene.h"

namespace penumbra::engine {

struct MemoryEstimate {
  uint64_t bytes = 0;
  std::vector<std::pair<std::string, uint64_t>> parts;  // what it is made of, largest first
  // "2.4 GiB (G-buffer and targets 1.2 GiB, casters 0.9 GiB, ...)".
  std::string text() const;
};

MemoryEstimate estimateFrameMemory(const Scene& scene, const ResolvedOptions& options);

// MemAvailable of /proc/meminfo, in bytes; 0 when it cannot be read.
uint64_t availableMemoryBytes();

// "1.5 GiB", "300 MiB".
std::string formatBytes(uint64_t bytes);

// "8G", "512M", "1.5g", "1000000" (bytes): K, M, G, T are powers of 1024. Nothing else.
Result<uint64_t> parseBytes(const std::string& text, const std::string& option);

// Ok, or an Error (where `where`) saying the estimate and the limit when it exceeds it (a limit
// of 0 checks nothing).
Status checkMemory(const MemoryEstimate& estimate, uint64_t limit, const std::string& where,
                   const std::string& limitSource);

}  // namespace penumbra::engine
