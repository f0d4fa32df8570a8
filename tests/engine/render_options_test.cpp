// Options are checked once, by resolveOptions: each bad value is an Error naming the option and
// its range (the specs the command line's help quotes); good ones resolve to the technique, its
// parameter values and the stochastic pass's settings.
#include "engine/render_options.h"

#include <gtest/gtest.h>

#include <functional>

namespace penumbra::engine {
namespace {

void expectRejected(const std::function<void(RenderOptions&)>& change, const std::string& where,
                    const std::string& mention) {
  RenderOptions o;
  change(o);
  const Result<ResolvedOptions> r = resolveOptions(o);
  ASSERT_FALSE(r.ok()) << where;
  EXPECT_EQ(r.error().where, where);
  EXPECT_NE(r.error().line().find(mention), std::string::npos) << r.error().line();
}

TEST(RenderOptions, DefaultsResolve) {
  const Result<ResolvedOptions> r = resolveOptions(RenderOptions{});
  ASSERT_TRUE(r.ok()) << r.error().line();
  ASSERT_NE(r->technique, nullptr);
  EXPECT_EQ(r->technique->name, "pcss");
  EXPECT_EQ(r->sampling.pattern.spp, 16);
  EXPECT_EQ(r->sampling.timeStrata, 0);  // the rasterizer's default
}

TEST(RenderOptions, EveryRangeIsCheckedAndNamed) {
  expectRejected([](RenderOptions& o) { o.width = 0; }, "option --width", "[1, 16384]");
  expectRejected([](RenderOptions& o) { o.height = 16385; }, "option --height", "[1, 16384]");
  expectRejected([](RenderOptions& o) { o.spp = 65; }, "option --spp", "[1, 64], got 65");
  expectRejected([](RenderOptions& o) { o.spp = 0; }, "option --spp", "got 0");
  expectRejected([](RenderOptions& o) { o.dualBlock = 3; }, "option --dual-block", "a power of 2 in [1, 64]");
  expectRejected([](RenderOptions& o) { o.dualBlock = 128; }, "option --dual-block", "power of 2");
  expectRejected([](RenderOptions& o) { o.timeStrata = 0; }, "option --strata (time strata T)", "[1, 64]");
  expectRejected([](RenderOptions& o) { o.lensStrata = 9; }, "option --strata (lens cells L)", "[1, 8]");
  expectRejected([](RenderOptions& o) { o.frame = -1; }, "option --frame", "[0, 4294967295]");
  expectRejected([](RenderOptions& o) { o.frame = int64_t{1} << 32; }, "option --frame", "got 4294967296");
}

TEST(RenderOptions, CameraOverridesAreChecked) {
  auto withCamera = [](auto change) {
    return [change](RenderOptions& o) {
      Camera c;
      change(c);
      o.camera = c;
    };
  };
  expectRejected(withCamera([](Camera& c) { c.fovYDegrees = 0; }), "option --fov", "(0, 180)");
  expectRejected(withCamera([](Camera& c) { c.fovYDegrees = 180; }), "option --fov", "got 180");
  expectRejected(withCamera([](Camera& c) { c.apertureRadius = -1; }), "option --aperture", "[0, 1000000)");
  expectRejected(withCamera([](Camera& c) { c.focusDistance = -1; }), "option --focus", "(0, 1000000000)");
  expectRejected(withCamera([](Camera& c) { c.eye = c.target; }), "option --eye", "coincide");
  expectRejected(withCamera([](Camera& c) { c.eye.x = NAN; }), "option --eye/--target", "finite");
  RenderOptions ok;
  ok.camera = Camera{};
  ok.camera->apertureRadius = 0.5f;
  EXPECT_TRUE(resolveOptions(ok).ok());
}

TEST(RenderOptions, TechniqueAndParametersResolveOnce) {
  expectRejected([](RenderOptions& o) { o.shadow = "nosuch"; }, "option --shadow", "valid: none, hard");
  expectRejected([](RenderOptions& o) { o.shadow = "none", o.shadowParams = {"a=1"}; }, "option --param", "no parameters");
  expectRejected([](RenderOptions& o) { o.shadow = "mvr", o.shadowParams = {"views=0"}; }, "option --param",
                 "'views' must be in [1, 1024]");
  expectRejected([](RenderOptions& o) { o.shadow = "pcf", o.shadowParams = {"nosuch=1"}; }, "option --param",
                 "unknown parameter 'nosuch'");
  RenderOptions o;
  o.shadow = "mvr";
  o.shadowParams = {"views=24", "map_size=256,bias=2"};  // one assignment, or a comma list
  const Result<ResolvedOptions> r = resolveOptions(o);
  ASSERT_TRUE(r.ok()) << r.error().line();
  EXPECT_EQ(r->params.integer("views"), 24);
  EXPECT_EQ(r->params.integer("map_size"), 256);
  EXPECT_EQ(r->params.number("bias"), 2.0);
  o.shadow = "none";
  o.shadowParams.clear();
  ASSERT_TRUE(resolveOptions(o).ok());
  EXPECT_EQ(resolveOptions(o)->technique, nullptr);
}

TEST(RenderOptions, SpecsPrintTheirRanges) {
  EXPECT_EQ(kSppOption.range(), "[1, 64]");
  EXPECT_EQ(kFovOption.range(), "(0, 180)");
  EXPECT_EQ(kApertureOption.range(), "[0, 1000000)");
  EXPECT_EQ(kDualBlockOption.range(), "a power of 2 in [1, 64]");
  EXPECT_TRUE(kDualBlockOption.contains(16));
  EXPECT_FALSE(kDualBlockOption.contains(12));
  EXPECT_FALSE(kWidthOption.contains(NAN));
  EXPECT_FALSE(kFocusOption.contains(INFINITY));
}

}  // namespace
}  // namespace penumbra::engine
