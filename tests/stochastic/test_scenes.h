// Random time-continuous triangles for the stochastic tests.
#pragma once

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/glm.hpp>
#include <random>
#include <vector>

#include "stochastic/coverage.h"

namespace penumbra::stochastic::test {

inline glm::mat4 testProjection(int width, int height) {
  return glm::perspectiveRH_ZO(glm::radians(60.0f), static_cast<float>(width) / static_cast<float>(height), 0.1f, 100.0f);
}

struct MovingSoup {
  std::vector<glm::vec4> clip0, clip1;
  std::vector<uint32_t> indices, surface;
};

// n triangles of view-space size `size` around random points at view depth [dmin, dmax] (negative
// z in front of the camera, so dmin < 0 puts vertices behind it), moving by up to `motion`
// (view units) during the shutter.
inline MovingSoup randomSoup(std::mt19937& rng, int n, const glm::mat4& proj, float dmin, float dmax, float size,
                             float motion, int surfaces = 4) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), depth(dmin, dmax);
  MovingSoup s;
  for (int i = 0; i < n; ++i) {
    const float d = depth(rng);
    const glm::vec3 centre(unit(rng) * std::max(std::abs(d), 1.0f) * 0.6f, unit(rng) * std::max(std::abs(d), 1.0f) * 0.4f, -d);
    const glm::vec3 move(unit(rng) * motion, unit(rng) * motion, unit(rng) * motion * 0.5f);
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = centre + glm::vec3(unit(rng), unit(rng), unit(rng) * 0.5f) * size;
      s.clip0.push_back(proj * glm::vec4(p, 1.0f));
      s.clip1.push_back(proj * glm::vec4(p + move, 1.0f));
      s.indices.push_back(static_cast<uint32_t>(s.indices.size()));
    }
    s.surface.push_back(static_cast<uint32_t>(i % surfaces));
  }
  return s;
}

}  // namespace penumbra::stochastic::test
