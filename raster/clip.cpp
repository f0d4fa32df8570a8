#include "raster/clip.h"

#include <cstring>
#include <utility>

namespace penumbra::raster {

namespace {

// Signed distance of a clip-space vertex to one plane, >= 0 inside.
struct Plane {
  float cx, cy, cz, cw;
  float dist(const float* v) const { return cx * v[0] + cy * v[1] + cz * v[2] + cw * v[3]; }
};

int clipPolygon(const Plane& pl, const float* in, int n, int stride, float* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const float* a = in + i * stride;
    const float* b = in + ((i + 1) % n) * stride;
    const float da = pl.dist(a), db = pl.dist(b);
    const bool ina = da >= 0.0f, inb = db >= 0.0f;
    if (ina) {
      std::memcpy(out + m * stride, a, sizeof(float) * static_cast<size_t>(stride));
      ++m;
    }
    if (ina != inb) {
      // Interpolate from the inside endpoint P towards the outside one Q (canonical direction).
      const float* p = ina ? a : b;
      const float* q = ina ? b : a;
      const float dp = ina ? da : db, dq = ina ? db : da;
      const float t = dp / (dp - dq);
      float* r = out + m * stride;
      for (int c = 0; c < stride; ++c) r[c] = p[c] + t * (q[c] - p[c]);
      ++m;
    }
  }
  return m;
}

}  // namespace

int clipTriangle(const float* const in[3], int nv, uint32_t planes, const Viewport& vp, float* out) {
  const int stride = 4 + nv;
  float bufA[kMaxClipVerts * kClipStride], bufB[kMaxClipVerts * kClipStride];
  for (int i = 0; i < 3; ++i) std::memcpy(bufA + i * stride, in[i], sizeof(float) * static_cast<size_t>(stride));
  int n = 3;
  float* cur = bufA;
  float* nxt = bufB;
  Plane list[7];
  int np = 0;
  if (planes & kOutNear) list[np++] = {0, 0, 1, 0};   // z >= 0
  if (planes & kOutFar) list[np++] = {0, 0, -1, 1};   // z <= w
  if (planes & kOutGuard) {
    // Screen x in [-G, G] <=> ndc.x in [-(2G/W + 1), 2G/W - 1]; y is flipped. G sits 16 pixels
    // inside the projection's limit so that rounding here never lands a vertex outside it.
    const double g = kGuardBandPixels - 16.0;
    const auto xhi = static_cast<float>(2.0 * g / vp.width - 1.0), xlo = static_cast<float>(-(2.0 * g / vp.width + 1.0));
    const auto yhi = static_cast<float>(2.0 * g / vp.height + 1.0), ylo = static_cast<float>(1.0 - 2.0 * g / vp.height);
    list[np++] = {-1, 0, 0, xhi};  // x <= xhi w
    list[np++] = {1, 0, 0, -xlo};  // x >= xlo w
    list[np++] = {0, -1, 0, yhi};  // y <= yhi w
    list[np++] = {0, 1, 0, -ylo};  // y >= ylo w
    // w > 0 is implied by near (z >= 0) and far (z <= w) together; without them keep w positive.
    if (!(planes & kOutNear) || !(planes & kOutFar)) list[np++] = {0, 0, 0, 1};
  }
  for (int i = 0; i < np && n >= 3; ++i) {
    n = clipPolygon(list[i], cur, n, stride, nxt);
    std::swap(cur, nxt);
  }
  if (n < 3) return 0;
  for (int i = 0; i < n; ++i) std::memcpy(out + i * kClipStride, cur + i * stride, sizeof(float) * static_cast<size_t>(stride));
  return n;
}

}  // namespace penumbra::raster
