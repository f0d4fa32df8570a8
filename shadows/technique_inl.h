// Template definitions for technique.h.
// Thread-safety: as forEachReceiver's declaration (technique.h): rows in parallel, f called from
// several threads for distinct texels.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace penumbra::shadows {

template <class F>
void forEachReceiver(ShadowContext& ctx, raster::ImageFloat& visibility, F&& f, SelfShadow self) {
  const ReceiverImage& rec = *ctx.in.receivers;
  const glm::vec3 n = ctx.in.light.normal(), c = ctx.in.light.center;
  ctx.raster.run([&] {
    visibility.resizeParallel(rec.width(), rec.height());
    tbb::parallel_for(tbb::blocked_range<int>(0, rec.height(), 4), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < rec.width(); ++x) {
          const Receiver& r = rec.at(x, y);
          float v = 1.0f;
          if (r.valid) {
            v = glm::dot(r.position - c, n) > 0.0f ? f(x, y, r) : 0.0f;
            if (self == SelfShadow::Horizon && v > 0.0f) v *= horizonFraction(ctx.in.light, r.position, r.normal);
          }
          visibility.at(x, y) = v;
        }
    });
  });
}

}  // namespace penumbra::shadows
