// A rectangular area light: a one-sided Lambertian emitter of uniform radiance. All shadow
// techniques estimate the same quantity for it (DESIGN.md, "Shadows"): the visible fraction of the
// light's area seen from a receiver point,
//     V(x) = (1/A) * integral over the light of v(x, y) dA_y,   v = 1 when the segment x-y is free.
// Shading uses V times the unshadowed irradiance E(x) (exact, from the polygon formula below).
//
// Conventions: world space, right-handed. The light spans center + s*right + t*up for
// s in [-width/2, width/2], t in [-height/2, height/2]; it emits on the side of normal() =
// cross(right, up). Light "uv" coordinates (s, t) in [0,1]^2 map to that rectangle.
//
// Thread-safety: RectLight is a plain value; the functions are pure, safe from any thread.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>

namespace penumbra::shadows {

struct RectLight {
  glm::vec3 center{0.0f, 4.0f, 0.0f};
  glm::vec3 right{1.0f, 0.0f, 0.0f};   // unit, along the width
  glm::vec3 up{0.0f, 0.0f, 1.0f};      // unit, along the height, orthogonal to right
  float width = 1.0f, height = 1.0f;   // > 0, world units
  glm::vec3 color{1.0f};               // linear RGB
  float intensity = 1.0f;              // emitted radiance is color * intensity; >= 0

  glm::vec3 normal() const { return glm::cross(right, up); }
  float area() const { return width * height; }
  // The point at light uv (s, t) in [0,1]^2.
  glm::vec3 point(glm::vec2 st) const {
    return center + (st.x - 0.5f) * width * right + (st.y - 0.5f) * height * up;
  }
};

// A light facing `facing` (the direction it emits towards, need not be unit), its width along a
// direction derived from `widthHint` (projected onto the light plane; any other vector is used when
// the hint is parallel to `facing`). Returns false and leaves `out` alone when facing is zero or
// not finite, or width/height/intensity are out of range.
bool makeRectLight(glm::vec3 center, glm::vec3 facing, glm::vec3 widthHint, float width, float height,
                   glm::vec3 color, float intensity, RectLight& out, std::string* why = nullptr);

// Cosine-weighted solid angle of the light seen from x with unit normal n: the integral over the
// light of cos(theta_x) cos(theta_y) / r^2 dA, with only the part above x's tangent plane counted
// and 0 when x is behind the light. The unshadowed irradiance is E = radiance * this; a Lambertian
// receiver of albedo rho reflects rho / pi * E. Exact (Lambert's polygon formula, the rectangle
// clipped to x's hemisphere), in [0, pi].
float irradianceFactor(const RectLight& light, glm::vec3 x, glm::vec3 n);

// The fraction of the light's area above x's tangent plane (dot(n, y - x) > 0), in [0, 1]; 0 when x
// is behind the light. A closed surface blocks the rest itself, so V(x) <= horizonFraction(x):
// techniques whose depth comparisons are biased away from the receiver's own surface recover that
// self-shadowing with it (MVR per light sample, the single-map techniques as a factor).
float horizonFraction(const RectLight& light, glm::vec3 x, glm::vec3 n);

}  // namespace penumbra::shadows
