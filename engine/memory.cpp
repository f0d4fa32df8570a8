#include "engine/memory.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "engine/frame.h"
#include "engine/gbuffer_pass.h"

namespace penumbra::engine {

std::string formatBytes(uint64_t b) {
  char buf[32];
  const double v = static_cast<double>(b);
  if (v >= 1024.0 * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.1f GiB", v / (1024.0 * 1024 * 1024));
  else if (v >= 1024.0 * 1024) std::snprintf(buf, sizeof buf, "%.0f MiB", v / (1024.0 * 1024));
  else std::snprintf(buf, sizeof buf, "%.0f KiB", v / 1024.0);
  return buf;
}

std::string MemoryEstimate::text() const {
  std::string s = formatBytes(bytes) + " (";
  for (size_t i = 0; i < parts.size() && i < 4; ++i) s += (i ? ", " : "") + parts[i].first + " " + formatBytes(parts[i].second);
  return s + ")";
}

MemoryEstimate estimateFrameMemory(const Scene& scene, const ResolvedOptions& resolved) {
  const RenderOptions& o = resolved.options;
  const uint64_t pixels = static_cast<uint64_t>(o.width) * static_cast<uint64_t>(o.height);
  // A stochastic pass is possible when something moves or there is a lens.
  bool stochastic = o.forceStochastic;
  for (const Instance& inst : scene.instances) stochastic |= inst.moves();
  const Camera* cam = o.camera ? &*o.camera : scene.camera ? &*scene.camera : nullptr;
  stochastic |= cam && cam->apertureRadius > 0.0f;
  stochastic &= !o.at.has_value();
  const uint64_t msaa = o.msaa > 1 && !stochastic ? static_cast<uint64_t>(o.msaa) : 1;
  const uint64_t layers = stochastic || msaa > 1 ? stochastic::kMaxLayers : 1;
  const uint64_t lights = scene.areaLights.size();

  uint64_t largestMesh = 0, allVertices = 0, allTriangles = 0, stochasticVertices = 0, stochasticTriangles = 0;
  for (const Instance& inst : scene.instances) {
    const Mesh& m = scene.meshes[static_cast<size_t>(inst.mesh)];
    largestMesh = std::max<uint64_t>(largestMesh, m.positions.size());
    allVertices += m.positions.size();
    allTriangles += m.indices.size() / 3;
    if (stochastic && (inst.moves() || (cam && cam->apertureRadius > 0.0f))) {
      stochasticVertices += m.positions.size();
      stochasticTriangles += m.indices.size() / 3;
    }
  }
  MemoryEstimate e;
  auto part = [&](const std::string& what, uint64_t bytes) {
    if (bytes) e.parts.emplace_back(what, bytes);
  };
  // Depth + coarse depth, G-buffer, linear (when kept) + sRGB color, a visibility image per light (kept).
  part("targets and G-buffer", pixels * (4 + 1 + sizeof(GBufferTexel) + (o.linearImage ? 16 : 0) + 4 + 4 * lights));
  if (stochastic)
    part("stochastic layers", pixels * (sizeof(stochastic::ResolvedPixel) + (layers - 1) * sizeof(GBufferTexel) +
                                        layers * sizeof(shadows::Receiver) + 1) +
                                  stochasticVertices * 32 + stochasticTriangles * 16);
  // Multisampling: a depth target (depth + coarse) and a hit record (msaa_pass.cpp) per sample, the
  // layers as a stochastic pass's, and every instance's shading prepared at once.
  if (msaa > 1)
    part("multisample targets and layers", pixels * (msaa * (4 + 1 + 20) + sizeof(stochastic::ResolvedPixel) +
                                                     (layers - 1) * sizeof(GBufferTexel) + layers * sizeof(shadows::Receiver)) +
                                               allTriangles * 4);  // every instance's texture LOD at once
  // Vertex stage of the largest draw (clip, screen, 8 varyings) and one batch of set-up triangles
  // with their attributes and bins.
  const uint64_t batch = std::min<uint64_t>(allTriangles, uint64_t{1} << 20);
  part("pipeline", largestMesh * (16 + 20 + 4 * kGbufferMaxVaryings) + batch * (64 + 48 + 16));
  if (lights > 0 && resolved.technique) {
    // One light at a time: receivers and V of every layer, the casters flattened, the technique.
    part("shadow receivers", pixels * layers * (sizeof(shadows::Receiver) + 4));
    part("casters", allVertices * 12 + allTriangles * 12 * 2);
    uint64_t tech = 0;
    if (resolved.technique->peakBytes) {
      tech = resolved.technique->peakBytes(resolved.params, allTriangles);
    } else {
      for (const shadows::ParamSpec& p : resolved.technique->params)
        if (p.name == "map_size") {
          const auto size = static_cast<uint64_t>(resolved.params.integer("map_size"));
          tech = size * size * 32;
        }
    }
    tech += pixels * layers * resolved.technique->receiverBytes;
    part("technique " + resolved.technique->name, tech);
  }
  std::sort(e.parts.begin(), e.parts.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  for (const auto& [what, bytes] : e.parts) e.bytes += bytes;
  return e;
}

uint64_t availableMemoryBytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t value = 0;
  std::string unit;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return value * 1024;  // kB
  }
  return 0;
}

Result<uint64_t> parseBytes(const std::string& text, const std::string& option) {
  const std::string where = "option " + option;
  const Error bad{where, "expected a size like 8G, 512M or a number of bytes, got '" + text + "'"};
  if (text.empty()) return bad;
  double v = 0;
  const char* end = text.data() + text.size();
  const auto r = std::from_chars(text.data(), end, v);
  if (r.ec != std::errc() || !(v > 0) || !std::isfinite(v)) return bad;
  double scale = 1;
  if (r.ptr != end) {
    if (r.ptr + 1 != end) return bad;
    switch (*r.ptr) {
      case 'k': case 'K': scale = 1024.0; break;
      case 'm': case 'M': scale = 1024.0 * 1024; break;
      case 'g': case 'G': scale = 1024.0 * 1024 * 1024; break;
      case 't': case 'T': scale = 1024.0 * 1024 * 1024 * 1024; break;
      default: return bad;
    }
  }
  const double bytes = v * scale;
  if (bytes < 1 || bytes > 1.8e19) return bad;
  return static_cast<uint64_t>(bytes);
}

Status checkMemory(const MemoryEstimate& e, uint64_t limit, const std::string& where, const std::string& limitSource) {
  if (limit == 0 || e.bytes <= limit) return Ok{};
  return Error{where, "the frame needs about " + e.text() + ", more than " + limitSource + " (" + formatBytes(limit) +
                          "); give --max-memory to change the limit"};
}

}  // namespace penumbra::engine
