#include "raster/reference.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra::raster::reference {

SnappedTriangle snap(const glm::vec4 clip[3], int width, int height) {
  SnappedTriangle t;
  for (int k = 0; k < 3; ++k) {
    const double w = clip[k].w;
    const double sx = (double{clip[k].x} / w * 0.5 + 0.5) * width;   // pixel units, y down
    const double sy = (0.5 - double{clip[k].y} / w * 0.5) * height;
    // 1/256 pixel units, pixel centre (i + 0.5) at 256 i.
    t.x[k] = static_cast<int64_t>(std::nearbyint(sx * 256.0 - 128.0));
    t.y[k] = static_cast<int64_t>(std::nearbyint(sy * 256.0 - 128.0));
    t.z[k] = double{clip[k].z} / w;
  }
  return t;
}

namespace {

// Is the sample on the inside of edge a -> b of a triangle whose signed area is positive?
bool insideEdge(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px, int64_t py) {
  const int64_t e = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
  if (e > 0) return true;
  if (e < 0) return false;
  // On the edge: owned by top edges (horizontal, going right) and left edges (going up).
  const int64_t dx = bx - ax, dy = by - ay;
  const bool top = dy == 0 && dx > 0;
  const bool left = dy < 0;
  return top || left;
}

}  // namespace

void coverage(const SnappedTriangle& t, int width, int height, std::vector<uint32_t>& count, int dx16, int dy16) {
  const int64_t area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
  if (area == 0) return;
  int a = 0, b = 1, c = 2;
  if (area < 0) std::swap(b, c);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const int64_t px = int64_t{i} * 256 + int64_t{dx16} * 16, py = int64_t{j} * 256 + int64_t{dy16} * 16;
      if (insideEdge(t.x[a], t.y[a], t.x[b], t.y[b], px, py) && insideEdge(t.x[b], t.y[b], t.x[c], t.y[c], px, py) &&
          insideEdge(t.x[c], t.y[c], t.x[a], t.y[a], px, py))
        ++count[static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)];
    }
  }
}

std::vector<uint8_t> homogeneousCoverage(const glm::vec4 clip[3], int width, int height, double margin) {
  std::vector<uint8_t> out(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  // Rows of the inverse of M = [x; y; w] (columns are vertices): e_k(s) = row k of adj(M) . s
  // gives the (unnormalised) homogeneous barycentric of vertex k at sample s = (sx, sy, 1).
  double m[3][3];
  for (int k = 0; k < 3; ++k) {
    m[0][k] = clip[k].x;
    m[1][k] = clip[k].y;
    m[2][k] = clip[k].w;
  }
  double adj[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      adj[r][c] = m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];
    }
  const double det = m[0][0] * adj[0][0] + m[0][1] * adj[1][0] + m[0][2] * adj[2][0];
  if (det == 0.0) return out;
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const double sx = (i + 0.5) / width * 2.0 - 1.0;
      const double sy = 1.0 - (j + 0.5) / height * 2.0;
      double e[3], scale = 0;
      for (int k = 0; k < 3; ++k) {
        e[k] = (adj[k][0] * sx + adj[k][1] * sy + adj[k][2]) / det;
        scale = std::max(scale, std::abs(adj[k][0]) + std::abs(adj[k][1]) + std::abs(adj[k][2]));
      }
      // Inside the (possibly external) triangle and in front of the eye: all e_k >= 0, sum > 0
      // (the sum is 1/w of the sample's point on the triangle's plane, up to sign handled above).
      const double tol = margin * scale / std::abs(det);
      bool inside = true, ambiguous = false;
      for (int k = 0; k < 3; ++k) {
        if (e[k] < -tol) inside = false;
        else if (e[k] <= tol) ambiguous = true;
      }
      uint8_t v = 0;
      if (inside) {
        // The point of the triangle's plane seen through the sample is sum b_k V_k with
        // b_k = e_k / sum e_k, at w = 1 / sum e_k; hence z/w = sum e_k z_k.
        const double sw = e[0] + e[1] + e[2];
        const double z = e[0] * double{clip[0].z} + e[1] * double{clip[1].z} + e[2] * double{clip[2].z};
        if (!(sw > 0)) v = 0;
        else if (z < -margin || z > 1.0 + margin) v = 0;
        else if (z < margin || z > 1.0 - margin) v = 2;
        else v = ambiguous ? 2 : 1;
      }
      out[static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i)] = v;
    }
  }
  return out;
}

}  // namespace penumbra::raster::reference
