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
// Float operations only, no libm call, so that irradianceFactors below gives the same bits in SIMD
// lanes on every target; the angles come from lambertAtan2 (within 3 ulps of double atan2
// rounded to float: tests).
float irradianceFactor(const RectLight& light, glm::vec3 x, glm::vec3 n);

// atan2(y, x) for y > 0, in (0, pi]: |x| and y ordered so that t = min / max is in [0, 1], t
// reduced to [-tan(pi/8), tan(pi/8)] by atan(t) = pi/4 + atan((t - 1) / (t + 1)) above tan(pi/8),
// Cephes' atanf polynomial there, then pi/2 - r where y > |x| and pi - r where x < 0. Written as
// the operations irradianceFactors' lanes repeat (no FMA: the project builds with
// -ffp-contract=off).
float lambertAtan2(float y, float x);

// Points and unit normals as separate coordinate arrays (n of each).
struct SurfacePoints {
  const float *px, *py, *pz, *nx, *ny, *nz;
};

// out[i] = irradianceFactor(light, p_i, n_i), bit for bit, for i < n: one point per float lane, up
// to 16 at a time (the SIMD target `simd` names, raster/simd.h; 0 = the best this CPU has). A lane whose
// rectangle crosses its tangent plane (the polygon is clipped) and the last n mod lanes are handed
// to irradianceFactor itself.
void irradianceFactors(const RectLight& light, const SurfacePoints& points, int n, float* out, int64_t simd = 0);

// The constants of lambertAtan2, shared with its SIMD lanes.
namespace lambert {
inline constexpr float kTanPi8 = 0.41421356f;
inline constexpr float kP0 = 8.05374449538e-2f, kP1 = 1.38776856032e-1f, kP2 = 1.99777106478e-1f,
                       kP3 = 3.33329491539e-1f;
inline constexpr float kPi4 = 0.785398163f, kPi2 = 1.57079633f, kPi = 3.14159265f;
}  // namespace lambert

// The fraction of the light's area above x's tangent plane (dot(n, y - x) > 0), in [0, 1]; 0 when x
// is behind the light. A closed surface blocks the rest itself, so V(x) <= horizonFraction(x):
// techniques whose depth comparisons are biased away from the receiver's own surface recover that
// self-shadowing with it (MVR per light sample, the single-map techniques as a factor).
float horizonFraction(const RectLight& light, glm::vec3 x, glm::vec3 n);

}  // namespace penumbra::shadows
