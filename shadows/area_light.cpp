#include "shadows/area_light.h"

#include <algorithm>
#include <cmath>

namespace penumbra::shadows {

bool makeRectLight(glm::vec3 center, glm::vec3 facing, glm::vec3 widthHint, float width, float height,
                   glm::vec3 color, float intensity, RectLight& out, std::string* why) {
  auto fail = [&](const char* msg) {
    if (why) *why = msg;
    return false;
  };
  const float len = glm::length(facing);
  if (!std::isfinite(len) || len <= 0.0f) return fail("the light's normal must be a finite non-zero vector");
  if (!(width > 0.0f) || !(height > 0.0f) || !std::isfinite(width) || !std::isfinite(height))
    return fail("the light's width and height must be finite and positive");
  if (!(intensity >= 0.0f) || !std::isfinite(intensity)) return fail("the light's intensity must be finite and >= 0");
  const glm::vec3 n = facing / len;
  glm::vec3 r = widthHint - glm::dot(widthHint, n) * n;
  if (!(glm::length(r) > 1e-4f * std::max(glm::length(widthHint), 1e-30f)))
    r = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) - n.x * n : glm::vec3(0, 0, 1) - n.z * n;
  r = glm::normalize(r);
  RectLight l;
  l.center = center;
  l.right = r;
  l.up = glm::cross(n, r);  // so that cross(right, up) = n
  l.width = width;
  l.height = height;
  l.color = color;
  l.intensity = intensity;
  out = l;
  return true;
}

float horizonFraction(const RectLight& light, glm::vec3 x, glm::vec3 n) {
  if (glm::dot(x - light.center, light.normal()) <= 0.0f) return 0.0f;
  // On the light, dot(n, y - x) = c0 + s * cs + t * ct is affine in the light's (s, t); clip the
  // rectangle [-w/2, w/2] x [-h/2, h/2] to where it is positive and take the area (shoelace).
  const float c0 = glm::dot(n, light.center - x), cs = glm::dot(n, light.right), ct = glm::dot(n, light.up);
  const float hw = 0.5f * light.width, hh = 0.5f * light.height;
  const glm::vec2 quad[4] = {{-hw, -hh}, {hw, -hh}, {hw, hh}, {-hw, hh}};
  glm::vec2 poly[8];
  int m = 0;
  for (int i = 0; i < 4; ++i) {
    const glm::vec2 a = quad[i], b = quad[(i + 1) & 3];
    const float da = c0 + a.x * cs + a.y * ct, db = c0 + b.x * cs + b.y * ct;
    if (da > 0.0f) poly[m++] = a;
    if ((da > 0.0f) != (db > 0.0f)) poly[m++] = a + (b - a) * (da / (da - db));
  }
  if (m < 3) return 0.0f;
  if (m == 4 && poly[0] == quad[0] && poly[1] == quad[1] && poly[2] == quad[2] && poly[3] == quad[3]) return 1.0f;
  double area = 0.0;
  for (int k = 0; k < m; ++k) {
    const glm::dvec2 a(poly[k]), b(poly[(k + 1) % m]);
    area += a.x * b.y - b.x * a.y;
  }
  const double full = static_cast<double>(light.width) * static_cast<double>(light.height);
  return static_cast<float>(std::clamp(0.5 * std::abs(area) / full, 0.0, 1.0));
}

float lambertAtan2(float y, float x) {
  using namespace lambert;
  const float ax = std::fabs(x);
  const bool steep = ax < y;
  const float t = (steep ? ax : y) / (steep ? y : ax);
  const bool reduced = kTanPi8 < t;
  const float u = reduced ? (t - 1.0f) / (t + 1.0f) : t;
  const float z = u * u;
  float p = kP0 * z - kP1;
  p = p * z + kP2;
  p = p * z - kP3;
  p = p * z * u + u;
  float r = reduced ? kPi4 + p : p;
  if (steep) r = kPi2 - r;
  if (x < 0.0f) r = kPi - r;
  return r;
}

float irradianceFactor(const RectLight& light, glm::vec3 x, glm::vec3 n) {
  const glm::vec3 ln = light.normal();
  if (glm::dot(x - light.center, ln) <= 0.0f) return 0.0f;  // behind the emitting side
  // Corners relative to x, then Sutherland-Hodgman against x's tangent plane (keep dot(n, p) >= 0).
  const glm::vec3 hw = 0.5f * light.width * light.right, hh = 0.5f * light.height * light.up;
  const glm::vec3 c = light.center - x;
  const glm::vec3 quad[4] = {c - hw - hh, c + hw - hh, c + hw + hh, c - hw + hh};
  glm::vec3 poly[8];
  int m = 0;
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 a = quad[i], b = quad[(i + 1) & 3];
    const float da = glm::dot(n, a), db = glm::dot(n, b);
    if (da >= 0.0f) poly[m++] = a;
    if ((da >= 0.0f) != (db >= 0.0f)) poly[m++] = a + (b - a) * (da / (da - db));
  }
  if (m < 3) return 0.0f;
  // Lambert: (1/2) * sum over edges of angle(p_k, p_k+1) * dot(n, unit(cross(p_k, p_k+1))). In
  // float: each term is within a few ulps, far below what shading can show (tests: 1e-5). The
  // lanes of irradianceFactors repeat these operations for unclipped rectangles (m = 4).
  float sum = 0.0f;
  glm::vec3 u[8];
  for (int k = 0; k < m; ++k) u[k] = poly[k] * (1.0f / std::sqrt(glm::dot(poly[k], poly[k])));
  for (int k = 0; k < m; ++k) {
    const glm::vec3 a = u[k], b = u[(k + 1) % m];
    const glm::vec3 cr = glm::cross(a, b);
    const float s = std::sqrt(glm::dot(cr, cr));
    if (!(s > 0.0f)) continue;
    sum += lambertAtan2(s, glm::dot(a, b)) * (glm::dot(n, cr) / s);
  }
  return std::min(std::abs(0.5f * sum), 3.14159265f);
}

}  // namespace penumbra::shadows
