#include "engine/synth.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

namespace penumbra::engine {

Mesh makeSynthMesh(long targetTriangles) {
  constexpr int kGrid = 8;
  constexpr float kRadius = 0.45f;
  const long per = std::max(8L, targetTriangles / (kGrid * kGrid));
  const long r0 = std::max(2L, static_cast<long>(std::floor((1.0 + std::sqrt(1.0 + static_cast<double>(per))) / 2.0)));
  auto total = [](long r) { return 4 * r * (r - 1) * kGrid * kGrid; };
  long best = r0;
  for (long r = std::max(2L, r0 - 1); r <= r0 + 2; ++r)
    if (std::labs(total(r) - targetTriangles) < std::labs(total(best) - targetTriangles)) best = r;
  const long rings = best, segs = 2 * rings;
  const long perSphere = 2 + (rings - 1) * segs;

  Mesh m;
  m.name = "synth" + std::to_string(targetTriangles);
  m.positions.reserve(static_cast<size_t>(perSphere * kGrid * kGrid));
  m.normals.reserve(m.positions.capacity());
  m.indices.reserve(static_cast<size_t>(total(rings) * 3));
  for (int gi = 0; gi < kGrid; ++gi)
    for (int gj = 0; gj < kGrid; ++gj) {
      const glm::vec3 c(static_cast<float>(gi) - (kGrid - 1) * 0.5f, 0.0f, static_cast<float>(gj) - (kGrid - 1) * 0.5f);
      const auto base = static_cast<uint32_t>(m.positions.size());
      auto put = [&](glm::vec3 n) {
        m.positions.push_back(c + n * kRadius);
        m.normals.push_back(n);
      };
      put({0, 1, 0});
      for (long k = 1; k < rings; ++k) {
        const double th = std::numbers::pi * static_cast<double>(k) / static_cast<double>(rings);
        for (long s = 0; s < segs; ++s) {
          const double ph = 2.0 * std::numbers::pi * static_cast<double>(s) / static_cast<double>(segs);
          put({static_cast<float>(std::sin(th) * std::cos(ph)), static_cast<float>(std::cos(th)),
               static_cast<float>(std::sin(th) * std::sin(ph))});
        }
      }
      put({0, -1, 0});
      auto ring = [&](long k, long s) { return base + 1 + static_cast<uint32_t>((k - 1) * segs + (s % segs)); };
      const uint32_t north = base, south = base + static_cast<uint32_t>(perSphere) - 1;
      for (long s = 0; s < segs; ++s) m.indices.insert(m.indices.end(), {north, ring(1, s + 1), ring(1, s)});
      for (long k = 1; k < rings - 1; ++k)
        for (long s = 0; s < segs; ++s) {
          const uint32_t a = ring(k, s), b = ring(k, s + 1), cc = ring(k + 1, s), d = ring(k + 1, s + 1);
          m.indices.insert(m.indices.end(), {a, b, d});
          m.indices.insert(m.indices.end(), {a, d, cc});
        }
      for (long s = 0; s < segs; ++s) m.indices.insert(m.indices.end(), {south, ring(rings - 1, s), ring(rings - 1, s + 1)});
    }
  computeBounds(m);
  return m;
}

}  // namespace penumbra::engine
