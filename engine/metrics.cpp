#include "engine/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penumbra::engine {
namespace {

template <class A, class B>
void requireSameSize(const raster::Image<A>& a, const raster::Image<B>& b, const char* what) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument(std::string(what) + ": image sizes differ (" + std::to_string(a.width()) +
                                "x" + std::to_string(a.height()) + " and " + std::to_string(b.width()) + "x" +
                                std::to_string(b.height()) + ")");
}

// |v - ref|, or 1 when that is not finite (see the header).
double absError(float v, float ref) {
  const double e = std::fabs(static_cast<double>(v) - static_cast<double>(ref));
  return std::isfinite(e) ? e : 1.0;
}

double clamp01(float x) {
  if (!(x > 0.0f)) return 0.0;  // also NaN
  return x >= 1.0f ? 1.0 : static_cast<double>(x);
}

uint8_t lerpByte(uint8_t a, uint8_t b, float f) {
  const float c = static_cast<float>(a) + (static_cast<float>(b) - static_cast<float>(a)) * f;
  return static_cast<uint8_t>(std::lround(std::clamp(c, 0.0f, 255.0f)));
}

raster::Rgba8 lerpColor(raster::Rgba8 a, raster::Rgba8 b, float f) {
  return {lerpByte(a.r, b.r, f), lerpByte(a.g, b.g, f), lerpByte(a.b, b.b, f), 255};
}

// The diverging scale at t in [-1, 1]: stops every 0.5 (see the header).
raster::Rgba8 diverging(float t) {
  static constexpr std::array<raster::Rgba8, 5> kStops{kHeatBlue, kHeatLightBlue, kHeatWhite, kHeatLightRed,
                                                       kHeatRed};
  const float s = (std::clamp(t, -1.0f, 1.0f) + 1.0f) * 2.0f;  // [0, 4]
  const int i = std::min(static_cast<int>(s), 3);
  return lerpColor(kStops[static_cast<size_t>(i)], kStops[static_cast<size_t>(i) + 1],
                   s - static_cast<float>(i));
}

}  // namespace

VisibilityError compareVisibility(const raster::ImageFloat& v, const raster::ImageFloat& reference,
                                  const raster::Image<uint8_t>& mask, uint8_t select) {
  requireSameSize(v, reference, "compareVisibility");
  requireSameSize(v, mask, "compareVisibility (mask)");
  VisibilityError out;
  double sumSq = 0, sum = 0;
  size_t over = 0;
  for (int y = 0; y < v.height(); ++y) {
    const float* vr = v.row(y);
    const float* rr = reference.row(y);
    const uint8_t* mr = mask.row(y);
    double rowSq = 0, rowSum = 0;
    for (int x = 0; x < v.width(); ++x) {
      if ((mr[x] & select) == 0) continue;
      const double e = absError(vr[x], rr[x]);
      const double signedE = static_cast<double>(vr[x]) - static_cast<double>(rr[x]);
      rowSum += std::isfinite(signedE) ? signedE : 1.0;
      rowSq += e * e;
      out.maxErr = std::max(out.maxErr, e);
      if (e > 0.05) ++over;
      ++out.pixels;
    }
    sumSq += rowSq;
    sum += rowSum;
  }
  if (out.pixels > 0) {
    const auto n = static_cast<double>(out.pixels);
    out.rmse = std::sqrt(sumSq / n);
    out.bias = sum / n;
    out.fracOver005 = static_cast<double>(over) / n;
  }
  return out;
}

raster::Image<uint8_t> receiverClasses(const Scene& scene, const Frame& frame, const shadows::RectLight& light) {
  const raster::Image<GBufferTexel>& g = frame.gbuffer;
  const int w = g.width(), h = g.height();
  raster::Image<uint8_t> out(w, h, 0);
  const std::vector<char> flat = scene.flatInstances();
  const Camera& cam = frame.stats.camera;
  const float perDistance =
      2.0f * std::tan(0.5f * cam.fovYDegrees * std::numbers::pi_v<float> / 180.0f) / static_cast<float>(std::max(h, 1));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const GBufferTexel& t = g.at(x, y);
      if (t.material < 0 || !(shadows::horizonFraction(light, t.position, t.geometricNormal) > 0.0f)) continue;
      const bool ground = t.instance >= 0 && static_cast<size_t>(t.instance) < flat.size() &&
                          flat[static_cast<size_t>(t.instance)] != 0;
      uint8_t c = ground ? kGroundReceiver : kObjectReceiver;
      const float reach = static_cast<float>(kContactPixels) * glm::length(t.position - cam.eye) * perDistance;
      for (int dy = -kContactPixels; dy <= kContactPixels && !(c & kContactReceiver); ++dy)
        for (int dx = -kContactPixels; dx <= kContactPixels; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const GBufferTexel& q = g.at(qx, qy);
          if (q.material < 0 || q.instance == t.instance) continue;
          if (glm::length(q.position - t.position) < reach) {
            c |= kContactReceiver;
            break;
          }
        }
      out.at(x, y) = c;
    }
  return out;
}

double imageRmse(const raster::ImageRgba8& a, const raster::ImageRgba8& b) {
  requireSameSize(a, b, "imageRmse");
  double sum = 0;
  for (int y = 0; y < a.height(); ++y) {
    const raster::Rgba8* ar = a.row(y);
    const raster::Rgba8* br = b.row(y);
    long long rowSum = 0;  // exact: at most 3 * 255^2 * kMaxTargetSize per row
    for (int x = 0; x < a.width(); ++x) {
      const int dr = ar[x].r - br[x].r, dg = ar[x].g - br[x].g, db = ar[x].b - br[x].b;
      rowSum += dr * dr + dg * dg + db * db;
    }
    sum += static_cast<double>(rowSum);
  }
  const double n = 3.0 * static_cast<double>(a.width()) * static_cast<double>(a.height());
  return n > 0 ? std::sqrt(sum / n) / 255.0 : 0.0;
}

double imageRmse(const raster::ImageFloat4& a, const raster::ImageFloat4& b) {
  requireSameSize(a, b, "imageRmse");
  double sum = 0;
  for (int y = 0; y < a.height(); ++y) {
    const raster::Float4* ar = a.row(y);
    const raster::Float4* br = b.row(y);
    double rowSum = 0;
    for (int x = 0; x < a.width(); ++x) {
      const double dr = clamp01(ar[x].r) - clamp01(br[x].r);
      const double dg = clamp01(ar[x].g) - clamp01(br[x].g);
      const double db = clamp01(ar[x].b) - clamp01(br[x].b);
      rowSum += dr * dr + dg * dg + db * db;
    }
    sum += rowSum;
  }
  const double n = 3.0 * static_cast<double>(a.width()) * static_cast<double>(a.height());
  return n > 0 ? std::sqrt(sum / n) : 0.0;
}

raster::ImageRgba8 errorHeatMap(const raster::ImageFloat& v, const raster::ImageFloat& reference,
                                const raster::Image<uint8_t>& mask, float scale) {
  requireSameSize(v, reference, "errorHeatMap");
  requireSameSize(v, mask, "errorHeatMap (mask)");
  if (!(std::isfinite(scale) && scale > 0.0f))
    throw std::invalid_argument("errorHeatMap: scale must be finite and > 0, got " + std::to_string(scale));
  raster::ImageRgba8 out(v.width(), v.height());
  for (int y = 0; y < v.height(); ++y) {
    for (int x = 0; x < v.width(); ++x) {
      if (mask.at(x, y) == 0) {
        out.at(x, y) = kHeatOutside;
        continue;
      }
      const float e = v.at(x, y) - reference.at(x, y);
      out.at(x, y) = std::isfinite(e) ? diverging(e / scale) : kHeatInvalid;
    }
  }
  return out;
}

raster::ImageRgba8 visibilityImage(const raster::ImageFloat& v) {
  raster::ImageRgba8 out(v.width(), v.height());
  for (int y = 0; y < v.height(); ++y) {
    for (int x = 0; x < v.width(); ++x) {
      const float s = v.at(x, y);
      if (std::isnan(s)) {
        out.at(x, y) = kHeatInvalid;
        continue;
      }
      const auto g = static_cast<uint8_t>(std::lround(clamp01(s) * 255.0));
      out.at(x, y) = {g, g, g, 255};
    }
  }
  return out;
}

}  // namespace penumbra::engine
