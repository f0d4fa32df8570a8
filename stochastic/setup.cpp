#include "stochastic/setup.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace penumbra::stochastic {

Strata::Strata(int timeStrata, int lensStrata) : time(timeStrata), lens(lensStrata) {
  for (int i = 0; i <= time; ++i) tEdge[i] = static_cast<float>(i) / static_cast<float>(time);
  for (int i = 0; i <= lens; ++i) lEdge[i] = -1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(lens);
}

Domain Strata::domain(int si) const {
  const int ti = si / (lens * lens), ui = (si / lens) % lens, vi = si % lens;
  Domain d;
  d.t0 = tEdge[ti], d.t1 = tEdge[ti + 1];
  d.u0 = lEdge[ui], d.u1 = lEdge[ui + 1];
  d.v0 = lEdge[vi], d.v1 = lEdge[vi + 1];
  return d;
}

void setupTriangles(const TriangleSource& src, const SetupOptions& o, TriangleSetup& out) {
  const size_t triCount = src.indices.size() / 3;
  const uint32_t vertexCount = static_cast<uint32_t>(src.clip0.size());
  const bool lens = o.lens.active();
  const int strata = o.strata ? o.strata->count() : 0;
  out.tris.assign(triCount, TriangleBound{});
  out.strataRects.assign(o.strata ? triCount * static_cast<size_t>(strata) : 0, PixelRect{});
  tbb::parallel_for(tbb::blocked_range<size_t>(0, triCount, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t tri = r.begin(); tri != r.end(); ++tri) {
      TriangleBound& s = out.tris[tri];
      bool valid = true;
      for (int k = 0; k < 3; ++k) valid &= src.indices[tri * 3 + static_cast<size_t>(k)] < vertexCount;
      if (!valid) continue;
      glm::vec4 a[3], b[3];
      src.fetch(tri, a, b);
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 4; ++c) valid &= std::isfinite(a[k][c]) && std::isfinite(b[k][c]);
      if (!valid) continue;
      s.valid = true;
      s.isStatic = o.staticShortcut && !lens && (!src.motion || (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]));
      s.rect = o.exhaustive ? PixelRect{0, 0, o.width - 1, o.height - 1}
                            : footprint(a, b, Domain{}, o.lens, src.motion && !s.isStatic, o.width, o.height);
      s.live = !s.rect.empty();
      if (s.live && o.strata && !s.isStatic)
        for (int si = 0; si < strata; ++si)
          out.strataRects[tri * static_cast<size_t>(strata) + static_cast<size_t>(si)] =
              footprint(a, b, o.strata->domain(si), o.lens, src.motion, o.width, o.height);
    }
  });
}

}  // namespace penumbra::stochastic
