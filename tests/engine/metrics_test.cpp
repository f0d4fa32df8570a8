// Error metrics against hand-computed values: masked visibility errors, image RMSE in sRGB and
// linear, the heat map's colors at its stops, and the size checks.
#include "engine/metrics.h"

#include "engine/builtin_scenes.h"
#include "engine/renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace penumbra::engine {
namespace {

using raster::Rgba8;

// Errors chosen to be exact in binary: 0.25, -1/32, 0, 0.5 inside the mask.
struct Fixture {
  raster::ImageFloat v{3, 2}, ref{3, 2};
  raster::Image<uint8_t> mask{3, 2};
  Fixture() {
    const float vs[6] = {0.75f, 0.5f, 0.0f, 1.0f, 0.5f, 0.25f};
    const float rs[6] = {0.5f, 0.53125f, 1.0f, 1.0f, 0.0f, 0.25f};
    const uint8_t ms[6] = {1, 255, 0, 1, 1, 0};  // pixel 2 (error -1) and 5 are outside
    for (int i = 0; i < 6; ++i) {
      v.at(i % 3, i / 3) = vs[i];
      ref.at(i % 3, i / 3) = rs[i];
      mask.at(i % 3, i / 3) = ms[i];
    }
  }
};

TEST(Metrics, CompareVisibilityHandComputed) {
  Fixture f;
  const VisibilityError e = compareVisibility(f.v, f.ref, f.mask);
  EXPECT_EQ(e.pixels, 4u);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt((0.0625 + 1.0 / 1024 + 0.0 + 0.25) / 4));
  EXPECT_DOUBLE_EQ(e.maxErr, 0.5);
  EXPECT_DOUBLE_EQ(e.fracOver005, 0.5);  // 0.25 and 0.5; 1/32 is below 0.05
}

TEST(Metrics, CompareVisibilityIgnoresPaddingAndOutsideMask) {
  Fixture f;
  // Width 3 is padded to a stride of 8: texels beyond the width are not pixels.
  f.v.row(0)[5] = 100.0f;
  f.mask.row(0)[5] = 1;
  f.v.at(2, 1) = 50.0f;  // outside the mask
  const VisibilityError e = compareVisibility(f.v, f.ref, f.mask);
  EXPECT_EQ(e.pixels, 4u);
  EXPECT_DOUBLE_EQ(e.maxErr, 0.5);
}

TEST(Metrics, CompareVisibilityEmptyMaskAndNonFinite) {
  Fixture f;
  raster::Image<uint8_t> none(3, 2, 0);
  const VisibilityError z = compareVisibility(f.v, f.ref, none);
  EXPECT_EQ(z.pixels, 0u);
  EXPECT_EQ(z.rmse, 0.0);
  EXPECT_EQ(z.maxErr, 0.0);
  EXPECT_EQ(z.fracOver005, 0.0);

  // A NaN counts as error 1: errors 0.25, -1/32, 0, 1.
  f.v.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
  const VisibilityError e = compareVisibility(f.v, f.ref, f.mask);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt((0.0625 + 1.0 / 1024 + 0.0 + 1.0) / 4));
  EXPECT_DOUBLE_EQ(e.maxErr, 1.0);
  EXPECT_DOUBLE_EQ(e.fracOver005, 0.5);
}

TEST(Metrics, SizeMismatchThrows) {
  Fixture f;
  raster::ImageFloat wide(4, 2);
  raster::Image<uint8_t> tall(3, 3);
  EXPECT_THROW(compareVisibility(wide, f.ref, f.mask), std::invalid_argument);
  EXPECT_THROW(compareVisibility(f.v, f.ref, tall), std::invalid_argument);
  EXPECT_THROW(errorHeatMap(f.v, wide, f.mask), std::invalid_argument);
  EXPECT_THROW(errorHeatMap(f.v, f.ref, tall), std::invalid_argument);
  EXPECT_THROW(imageRmse(raster::ImageRgba8(2, 2), raster::ImageRgba8(2, 3)), std::invalid_argument);
  EXPECT_THROW(imageRmse(raster::ImageFloat4(2, 2), raster::ImageFloat4(1, 2)), std::invalid_argument);
}

TEST(Metrics, ImageRmseRgba8) {
  raster::ImageRgba8 a(2, 1), b(2, 1);
  a.at(0, 0) = {255, 0, 0, 0};
  b.at(0, 0) = {0, 0, 0, 255};  // alpha differs: ignored
  a.at(1, 0) = b.at(1, 0) = {10, 20, 30, 40};
  EXPECT_DOUBLE_EQ(imageRmse(a, b), std::sqrt(1.0 / 6));
  a.at(1, 0) = {10, 20, 81, 40};  // 51 = 255 / 5
  EXPECT_DOUBLE_EQ(imageRmse(a, b), std::sqrt((1.0 + 0.04) / 6));
  EXPECT_EQ(imageRmse(a, a), 0.0);
  EXPECT_EQ(imageRmse(raster::ImageRgba8(), raster::ImageRgba8()), 0.0);
}

TEST(Metrics, ImageRmseLinearClamps) {
  raster::ImageFloat4 a(1, 1), b(1, 1);
  a.at(0, 0) = {2.0f, -1.0f, 0.5f, 0.0f};
  b.at(0, 0) = {1.0f, 0.0f, 0.25f, 1.0f};  // r and g equal after clamping, alpha ignored
  EXPECT_DOUBLE_EQ(imageRmse(a, b), std::sqrt(0.0625 / 3));
  a.at(0, 0) = {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.25f, 0.0f};  // NaN counts as 0
  b.at(0, 0) = {0.0f, 0.0f, 0.25f, 0.0f};
  EXPECT_EQ(imageRmse(a, b), 0.0);
}

TEST(Metrics, HeatMapColors) {
  const float scale = 0.25f;
  const float errors[] = {-0.25f, -0.125f, 0.0f, 0.125f, 0.25f, -3.0f, 3.0f, 0.0625f, 0.0f, 0.0f};
  const int n = 10;
  raster::ImageFloat v(n, 1), ref(n, 1, 0.5f);
  raster::Image<uint8_t> mask(n, 1, 1);
  for (int x = 0; x < n; ++x) v.at(x, 0) = 0.5f + errors[x];
  mask.at(8, 0) = 0;
  v.at(9, 0) = std::numeric_limits<float>::infinity();
  const raster::ImageRgba8 h = errorHeatMap(v, ref, mask, scale);
  EXPECT_EQ(h.at(0, 0), kHeatBlue);  // too dark
  EXPECT_EQ(h.at(1, 0), kHeatLightBlue);
  EXPECT_EQ(h.at(2, 0), (Rgba8{255, 255, 255, 255}));
  EXPECT_EQ(h.at(3, 0), kHeatLightRed);
  EXPECT_EQ(h.at(4, 0), kHeatRed);   // light leak
  EXPECT_EQ(h.at(5, 0), kHeatBlue);  // saturated
  EXPECT_EQ(h.at(6, 0), kHeatRed);
  // Halfway between white and light red: (255 + 244) / 2 = 249.5 -> 250, 210, 192.5 -> 193.
  EXPECT_EQ(h.at(7, 0), (Rgba8{250, 210, 193, 255}));
  EXPECT_EQ(h.at(8, 0), kHeatOutside);
  EXPECT_EQ(h.at(9, 0), kHeatInvalid);
  EXPECT_GT(kHeatRed.r, kHeatRed.b);
  EXPECT_GT(kHeatBlue.b, kHeatBlue.r);

  // The same errors at twice the scale land on the inner stops.
  const raster::ImageRgba8 h2 = errorHeatMap(v, ref, mask, 0.5f);
  EXPECT_EQ(h2.at(0, 0), kHeatLightBlue);
  EXPECT_EQ(h2.at(4, 0), kHeatLightRed);
}

TEST(Metrics, HeatMapRejectsBadScale) {
  raster::ImageFloat v(1, 1), ref(1, 1);
  raster::Image<uint8_t> mask(1, 1, 1);
  EXPECT_THROW(errorHeatMap(v, ref, mask, 0.0f), std::invalid_argument);
  EXPECT_THROW(errorHeatMap(v, ref, mask, -1.0f), std::invalid_argument);
  EXPECT_THROW(errorHeatMap(v, ref, mask, std::numeric_limits<float>::quiet_NaN()), std::invalid_argument);
  EXPECT_THROW(errorHeatMap(v, ref, mask, std::numeric_limits<float>::infinity()), std::invalid_argument);
}

TEST(Metrics, VisibilityImageGrey) {
  const float vs[] = {0.0f, 1.0f, 0.5f, 2.0f, -1.0f, 0.2f};
  raster::ImageFloat v(7, 1);
  for (int x = 0; x < 6; ++x) v.at(x, 0) = vs[x];
  v.at(6, 0) = std::numeric_limits<float>::quiet_NaN();
  const raster::ImageRgba8 g = visibilityImage(v);
  ASSERT_EQ(g.width(), 7);
  ASSERT_EQ(g.height(), 1);
  EXPECT_EQ(g.at(0, 0), (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(g.at(1, 0), (Rgba8{255, 255, 255, 255}));
  EXPECT_EQ(g.at(2, 0), (Rgba8{128, 128, 128, 255}));  // 127.5 rounds up
  EXPECT_EQ(g.at(3, 0), (Rgba8{255, 255, 255, 255}));
  EXPECT_EQ(g.at(4, 0), (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(g.at(5, 0), (Rgba8{51, 51, 51, 255}));  // linear, not sRGB-encoded
  EXPECT_EQ(g.at(6, 0), kHeatInvalid);
}

TEST(VisibilityMetric, BiasIsSignedAndSelectPicksAClass) {
  raster::ImageFloat v(4, 1), ref(4, 1, 0.5f);
  raster::Image<uint8_t> mask(4, 1, 0);
  v.at(0, 0) = 0.7f, mask.at(0, 0) = kGroundReceiver;                     // +0.2
  v.at(1, 0) = 0.4f, mask.at(1, 0) = kObjectReceiver;                     // -0.1
  v.at(2, 0) = 0.6f, mask.at(2, 0) = kObjectReceiver | kContactReceiver;  // +0.1
  v.at(3, 0) = 0.0f;                                                      // not compared
  const VisibilityError all = compareVisibility(v, ref, mask);
  EXPECT_EQ(all.pixels, 3u);
  EXPECT_NEAR(all.bias, 0.2 / 3.0, 1e-6);
  EXPECT_NEAR(compareVisibility(v, ref, mask, kGroundReceiver).bias, 0.2, 1e-6);
  EXPECT_NEAR(compareVisibility(v, ref, mask, kObjectReceiver).bias, 0.0, 1e-6);
  EXPECT_EQ(compareVisibility(v, ref, mask, kContactReceiver).pixels, 1u);
  EXPECT_NEAR(compareVisibility(v, ref, mask, kContactReceiver).rmse, 0.1, 1e-6);
}

TEST(VisibilityMetric, ReceiverClassesOfABuiltInScene) {
  Result<Scene> scene = makeBuiltinScene("creature");
  ASSERT_TRUE(scene.ok());
  Renderer r(2);
  RenderOptions opt;
  opt.width = 160;
  opt.height = 90;
  opt.shadow = "none";
  const Frame f = r.render(*scene, *resolveOptions(opt));
  const raster::Image<uint8_t> c = receiverClasses(*scene, f, scene->areaLights[0]);
  size_t ground = 0, object = 0, contact = 0;
  for (int y = 0; y < c.height(); ++y)
    for (int x = 0; x < c.width(); ++x) {
      const uint8_t k = c.at(x, y);
      const GBufferTexel& t = f.gbuffer.at(x, y);
      if (t.material < 0) EXPECT_EQ(k, 0) << "background is never compared";
      ground += (k & kGroundReceiver) ? 1 : 0;
      object += (k & kObjectReceiver) ? 1 : 0;
      contact += (k & kContactReceiver) ? 1 : 0;
      EXPECT_NE((k & kGroundReceiver) != 0 && (k & kObjectReceiver) != 0, true);
      // Contact receivers are near the creature's feet: close to the ground plane y = 0.
      if (k & kContactReceiver) EXPECT_LT(t.position.y, 0.25f) << x << "," << y;
      // The ground is the flat instance 0.
      if (k & kGroundReceiver) EXPECT_EQ(t.instance, 0);
    }
  EXPECT_GT(ground, 5000u);
  EXPECT_GT(object, 1000u);
  EXPECT_GT(contact, 10u);
}

}  // namespace
}  // namespace penumbra::engine
