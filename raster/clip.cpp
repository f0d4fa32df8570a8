#include "raster/clip.h"

#include <cstring>
#include <utility>

namespace penumbra::raster {

namespace {

// Signed distance of vertex v to plane k, >= 0 inside: 0 near, 1 far, 2..5 the guard band.
double distance(int k, const double* v, const GuardPlanes& g) {
  switch (k) {
    case 0: return v[2];         // z >= 0
    case 1: return v[3] - v[2];  // z <= w
    default: {
      double d[4];
      guardDistances(g, v[0], v[1], v[3], d);
      return d[k - 2];
    }
  }
}

int clipPolygon(int plane, const GuardPlanes& g, const double* in, int n, int stride, double* out) {
  int m = 0;
  for (int i = 0; i < n && m + 2 <= kMaxClipVerts; ++i) {
    const double* a = in + i * stride;
    const double* b = in + ((i + 1) % n) * stride;
    const double da = distance(plane, a, g), db = distance(plane, b, g);
    const bool ina = da >= 0.0, inb = db >= 0.0;
    if (ina) {
      std::memcpy(out + m * stride, a, sizeof(double) * static_cast<size_t>(stride));
      ++m;
    }
    if (ina != inb) {
      // Interpolate from the inside endpoint P towards the outside one Q (canonical direction).
      const double* p = ina ? a : b;
      const double* q = ina ? b : a;
      const double dp = ina ? da : db, dq = ina ? db : da;
      const double t = dp / (dp - dq);
      double* r = out + m * stride;
      for (int c = 0; c < stride; ++c) r[c] = p[c] + t * (q[c] - p[c]);
      ++m;
    }
  }
  return m;
}

}  // namespace

int clipTriangle(const double* const in[3], int nv, const GuardPlanes& guard, double* out) {
  const int stride = 4 + nv;
  double bufA[kMaxClipVerts * kClipStride], bufB[kMaxClipVerts * kClipStride];
  for (int i = 0; i < 3; ++i) std::memcpy(bufA + i * stride, in[i], sizeof(double) * static_cast<size_t>(stride));
  int n = 3;
  double* cur = bufA;
  double* nxt = bufB;
  // Every clipped triangle meets the same planes in the same order, so that two triangles sharing
  // an edge cut it identically (a plane a polygon lies inside changes nothing).
  for (int plane = 0; plane < 6 && n >= 3; ++plane) {
    n = clipPolygon(plane, guard, cur, n, stride, nxt);
    std::swap(cur, nxt);
  }
  if (n < 3) return 0;
  for (int i = 0; i < n; ++i) std::memcpy(out + i * kClipStride, cur + i * stride, sizeof(double) * static_cast<size_t>(stride));
  return n;
}

}  // namespace penumbra::raster
