// The area light's unshadowed irradiance without libm: lambertAtan2 against double atan2, the
// polygon formula against a double-precision Lambert sum, and the SIMD lanes of irradianceFactors
// against irradianceFactor bit for bit on every SIMD target.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "raster/simd.h"
#include "shadows/area_light.h"

namespace penumbra::shadows {
namespace {

// ulps between two floats of the same sign.
int64_t ulps(float a, float b) {
  return std::abs(static_cast<int64_t>(std::bit_cast<int32_t>(a)) - static_cast<int64_t>(std::bit_cast<int32_t>(b)));
}

TEST(LambertAtan2, WithinThreeUlpsOfDoubleAtan2) {
  // Every octant boundary and the reduction point, then random angles and magnitudes.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(1e-7, std::numbers::pi - 1e-7), decade(-30.0, 30.0);
  int64_t worst = 0;
  auto check = [&](float y, float x) {
    const float want = static_cast<float>(std::atan2(static_cast<double>(y), static_cast<double>(x)));
    const float got = lambertAtan2(y, x);
    worst = std::max(worst, ulps(got, want));
    ASSERT_LE(ulps(got, want), 3) << "atan2(" << y << ", " << x << ") = " << want << ", got " << got;
  };
  for (float y : {1.0f, 1e-30f, 3e30f}) {
    check(y, 0.0f);
    check(y, -0.0f);
    check(y, y);
    check(y, -y);
    check(y, y / lambert::kTanPi8);
    check(y, -y / lambert::kTanPi8);
    check(y, y * lambert::kTanPi8);
    check(y, std::nextafter(y * lambert::kTanPi8, 0.0f));
  }
  for (int i = 0; i < 2000000; ++i) {
    const double a = angle(rng), r = std::pow(10.0, decade(rng));
    const float y = static_cast<float>(r * std::sin(a)), x = static_cast<float>(r * std::cos(a));
    if (!(y > 0.0f) || !std::isfinite(y) || !std::isfinite(x)) continue;
    check(y, x);
  }
  // Tiny angles (the far light's edges): relative accuracy kept down to the smallest.
  for (float t = 1e-30f; t < 1.0f; t *= 1.37f) check(t, 1.0f);
  RecordProperty("worst_ulps", static_cast<int>(worst));
}

// Lambert's formula in double with std::atan2, the rectangle clipped as irradianceFactor clips it.
double lambertDouble(const RectLight& light, glm::dvec3 x, glm::dvec3 n) {
  const glm::dvec3 ln(light.normal());
  if (glm::dot(x - glm::dvec3(light.center), ln) <= 0.0) return 0.0;
  const glm::dvec3 hw = 0.5 * double(light.width) * glm::dvec3(light.right);
  const glm::dvec3 hh = 0.5 * double(light.height) * glm::dvec3(light.up);
  const glm::dvec3 c = glm::dvec3(light.center) - x;
  const glm::dvec3 quad[4] = {c - hw - hh, c + hw - hh, c + hw + hh, c - hw + hh};
  std::vector<glm::dvec3> poly;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 a = quad[i], b = quad[(i + 1) & 3];
    const double da = glm::dot(n, a), db = glm::dot(n, b);
    if (da >= 0.0) poly.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) poly.push_back(a + (b - a) * (da / (da - db)));
  }
  double sum = 0.0;
  for (size_t k = 0; k < poly.size(); ++k) {
    const glm::dvec3 a = glm::normalize(poly[k]), b = glm::normalize(poly[(k + 1) % poly.size()]);
    const glm::dvec3 cr = glm::cross(a, b);
    const double s = glm::length(cr);
    if (s > 0.0) sum += std::atan2(s, glm::dot(a, b)) * glm::dot(n, cr) / s;
  }
  return std::min(std::abs(0.5 * sum), std::numbers::pi);
}

RectLight randomLight(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), size(0.05f, 4.0f);
  RectLight l;
  const glm::vec3 facing(u(rng), u(rng) - 1.5f, u(rng));
  EXPECT_TRUE(makeRectLight({u(rng), 3.0f + u(rng), u(rng)}, facing, {u(rng), u(rng), u(rng)}, size(rng), size(rng),
                            glm::vec3(1.0f), 1.0f, l));
  return l;
}

// Points under, beside and behind the light, with unit normals facing it, crossing it (clipped
// polygons) or facing away; a few degenerate ones (on the light's corner, zero and NaN normals).
struct Cloud {
  std::vector<float> p[3], n[3];
  SurfacePoints view() const { return {p[0].data(), p[1].data(), p[2].data(), n[0].data(), n[1].data(), n[2].data()}; }
  glm::vec3 point(size_t i) const { return {p[0][i], p[1][i], p[2][i]}; }
  glm::vec3 normal(size_t i) const { return {n[0][i], n[1][i], n[2][i]}; }
};

Cloud randomCloud(std::mt19937& rng, const RectLight& light, int count) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), spread(-6.0f, 6.0f), unit(0.0f, 1.0f);
  Cloud c;
  for (int i = 0; i < count; ++i) {
    glm::vec3 x(spread(rng), 3.0f * u(rng), spread(rng));
    glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0, 0.5f, 0));
    const float r = unit(rng);
    if (r < 0.25f) n = glm::normalize(light.center - x);  // facing the light: mostly unclipped
    else if (r < 0.3f) x = light.point({unit(rng) < 0.5f ? 0.0f : 1.0f, unit(rng) < 0.5f ? 0.0f : 1.0f});
    else if (r < 0.32f) n = glm::vec3(0.0f);
    else if (r < 0.33f) n = glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0, 0);
    else if (r < 0.34f) x = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    else if (r < 0.4f) x = light.center + light.normal() * unit(rng) * 1e-3f;  // just in front
    else if (r < 0.45f) x = light.center - light.normal() * unit(rng);      // behind
    for (int k = 0; k < 3; ++k) c.p[k].push_back(x[k]), c.n[k].push_back(n[k]);
  }
  return c;
}

TEST(Irradiance, PolygonFormulaWithinFloatRoundingOfDouble) {
  std::mt19937 rng(11);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const RectLight light = randomLight(rng);
    const Cloud c = randomCloud(rng, light, 500);
    for (size_t i = 0; i < c.p[0].size(); ++i) {
      const glm::vec3 x = c.point(i), n = c.normal(i);
      if (!std::isfinite(x.x) || !std::isfinite(n.x) || glm::dot(n, n) < 0.5f) continue;
      // Near the light's plane the float inputs decide neither the side nor (the corners nearly
      // coplanar with x) the angles to better than ~1e-5: those are compared bit for bit below only.
      if (std::abs(glm::dot(x - light.center, light.normal())) < 1e-2f) continue;
      const double want = lambertDouble(light, glm::dvec3(x), glm::dvec3(n));
      const float got = irradianceFactor(light, x, n);
      // Float inputs to a sum of up to five terms of size <= pi: absolute error, relative to pi.
      worst = std::max(worst, std::abs(double(got) - want));
      ASSERT_NEAR(got, want, 2e-6 * std::numbers::pi + 1e-5 * want)
          << trial << " " << i << " x " << x.x << "," << x.y << "," << x.z << " n " << n.x << "," << n.y << "," << n.z
          << " plane " << glm::dot(x - light.center, light.normal());
    }
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("worst_abs", text);
}

TEST(Irradiance, LanesEqualIrradianceFactorBitForBitOnEveryTarget) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 120; ++trial) {
    const RectLight light = randomLight(rng);
    const int count = trial < 40 ? trial : 300;  // every partial vector, then full ones
    const Cloud c = randomCloud(rng, light, count);
    std::vector<uint32_t> want(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i)
      want[static_cast<size_t>(i)] = std::bit_cast<uint32_t>(irradianceFactor(light, c.point(i), c.normal(i)));
    for (int64_t target : raster::supportedSimdTargets()) {
      std::vector<float> got(static_cast<size_t>(count) + 1, -7.0f);
      irradianceFactors(light, c.view(), count, got.data(), target);
      for (int i = 0; i < count; ++i)
        ASSERT_EQ(std::bit_cast<uint32_t>(got[static_cast<size_t>(i)]), want[static_cast<size_t>(i)])
            << raster::simdTargetName(target) << " trial " << trial << " point " << i;
      EXPECT_EQ(got.back(), -7.0f) << "wrote past n";
    }
  }
}

}  // namespace
}  // namespace penumbra::shadows
