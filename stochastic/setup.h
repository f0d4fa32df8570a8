// Setup stage of the stochastic rasterizer: per triangle, in parallel, whether it is valid (indices
// in range, finite positions), static (no motion, no lens: the ordinary pipeline's single test per
// pixel), and the pixel rectangle of its bound (bounds.h footprint over the whole shutter and
// lens; for the interval method also one rectangle per stratum of time and lens).
//
// Interval strata: the shutter cut into T strata and the lens square into L x L cells. The strata's
// boundaries are one array of floats that both the footprints' domains and the samples' membership
// use, so a sample at a boundary belongs to exactly one stratum, whose domain holds it.
//
// Thread-safety: pure functions and plain values; setupTriangles runs TBB loops in the caller's
// arena and writes only its output.
#pragma once

#include <cstdint>
#include <glm/vec4.hpp>
#include <span>
#include <vector>

#include "stochastic/bounds.h"
#include "stochastic/sample_pattern.h"

namespace penumbra::stochastic {

struct Strata {
  int time = 1, lens = 1;  // T in [1, 64], L in [1, 8]
  float tEdge[65] = {}, lEdge[9] = {};

  Strata() = default;
  Strata(int timeStrata, int lensStrata);
  int count() const { return time * lens * lens; }
  // Stratum index (t * L + u) * L + v of a sample.
  uint16_t of(const Sample& s) const {
    return static_cast<uint16_t>((cell(tEdge, time, s.t) * lens + cell(lEdge, lens, s.u)) * lens + cell(lEdge, lens, s.v));
  }
  // The (t, u, v) box of stratum si; the first and last cells reach to the domain's ends.
  Domain domain(int si) const;
  // The time stratum of stratum si.
  int timeOf(int si) const { return si / (lens * lens); }

 private:
  static int cell(const float* edge, int n, float v) {  // the cell [edge[c], edge[c + 1]) holding v
    int c = 0;
    while (c + 1 < n && v >= edge[c + 1]) ++c;
    return c;
  }
};

// The triangles as the stochastic rasterizer takes them: clip positions at shutter open and close
// per vertex, 3 indices per triangle.
struct TriangleSource {
  std::span<const glm::vec4> clip0, clip1;
  std::span<const uint32_t> indices;
  bool motion = true;  // false: clip1 is ignored
  // Clip positions of triangle t's vertices at open (a) and close (b); b = a without motion.
  void fetch(size_t t, glm::vec4 a[3], glm::vec4 b[3]) const {
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = indices[t * 3 + static_cast<size_t>(k)];
      a[k] = clip0[i];
      b[k] = motion ? clip1[i] : clip0[i];
    }
  }
};

struct TriangleBound {
  PixelRect rect;        // the footprint over the whole shutter and lens (clamped to the viewport)
  bool valid = false;    // indices in range, positions finite
  bool isStatic = false; // no motion and no lens: one test per pixel serves all its samples
  bool live = false;     // valid and its footprint holds a pixel centre
};

struct SetupOptions {
  ThinLens lens;
  int width = 0, height = 0;
  bool staticShortcut = true;
  bool exhaustive = false;  // every triangle's rect is the whole viewport (tests)
  const Strata* strata = nullptr;  // the interval method's strata, or null
};

struct TriangleSetup {
  std::vector<TriangleBound> tris;
  std::vector<PixelRect> strataRects;  // interval method: strata->count() per triangle (live, moving ones)
};

void setupTriangles(const TriangleSource& src, const SetupOptions& options, TriangleSetup& out);

}  // namespace penumbra::stochastic
