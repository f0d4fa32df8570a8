// Point splatting against a scalar reference written from the conventions in splat.h (sequential,
// glm's matrix product, "nearest d wins, then the smaller payload"), bit for bit; the same bytes at
// 1, 2 and 7 threads and at any number of views per pass; the viewport edges, the depth range and
// non-finite points; the resolve functions; the stats.
#include "raster/splat.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "raster/simd.h"

namespace penumbra::raster {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// What the reference keeps per pixel: the winning point's d = z / w and payload.
struct Hit {
  bool any = false;
  float d = 0;
  uint32_t payload = 0;
};

struct RefTarget {
  int width = 0, height = 0;
  std::vector<Hit> hits;
  RefTarget(int w, int h) : width(w), height(h), hits(static_cast<size_t>(w) * static_cast<size_t>(h)) {}
};

// Splats one point into one view, sequentially. Returns whether it landed.
bool referenceSplat(const glm::mat4& viewProj, glm::vec3 p, uint32_t payload, bool reversed, RefTarget& t) {
  const glm::vec4 c = viewProj * glm::vec4(p, 1.0f);
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) return false;
  if (!(c.w > 0.0f) || c.z < 0.0f || c.z > c.w) return false;
  const float sx = (c.x / c.w * 0.5f + 0.5f) * static_cast<float>(t.width);
  const float sy = (0.5f - c.y / c.w * 0.5f) * static_cast<float>(t.height);
  if (sx < 0.0f || sx >= static_cast<float>(t.width) || sy < 0.0f || sy >= static_cast<float>(t.height)) return false;
  const int x = static_cast<int>(std::floor(sx)), y = static_cast<int>(std::floor(sy));
  const float d = c.z / c.w;
  Hit& h = t.hits[static_cast<size_t>(y) * static_cast<size_t>(t.width) + static_cast<size_t>(x)];
  const bool nearer = reversed ? d > h.d : d < h.d;
  if (!h.any || nearer || (d == h.d && payload < h.payload)) h = {true, d, payload};
  return true;
}

// The key the conventions give for a reference hit.
uint64_t expectedKey(const Hit& h, bool reversed) {
  if (!h.any) return kEmptyKey;
  const uint32_t bits = std::bit_cast<uint32_t>(h.d + 0.0f);  // -0 + 0 = +0
  const uint32_t depth = reversed ? std::bit_cast<uint32_t>(1.0f) - bits : bits;
  return uint64_t{depth} << 32 | h.payload;
}

// Every key of the target, padding included (padding must stay empty), against the reference.
void expectMatches(const Image<uint64_t>& keys, const RefTarget& ref, bool reversed, int view) {
  ASSERT_EQ(keys.width(), ref.width);
  ASSERT_EQ(keys.height(), ref.height);
  size_t mismatches = 0;
  for (int y = 0; y < keys.paddedRows(); ++y)
    for (int x = 0; x < keys.stride(); ++x) {
      const bool inside = x < ref.width && y < ref.height;
      const uint64_t want =
          inside ? expectedKey(ref.hits[static_cast<size_t>(y) * static_cast<size_t>(ref.width) + static_cast<size_t>(x)],
                               reversed)
                 : kEmptyKey;
      if (keys.at(x, y) != want && mismatches++ < 5)
        ADD_FAILURE() << "view " << view << " pixel (" << x << ", " << y << "): key " << std::hex << keys.at(x, y)
                      << ", reference " << want;
    }
  EXPECT_EQ(mismatches, 0u) << "view " << view;
}

// Standard perspective (z / w = 0 at the near plane) looking at the origin.
glm::mat4 perspectiveAt(glm::vec3 eye, float fovDeg, float aspect, float zNear, float zFar) {
  return glm::perspectiveRH_ZO(glm::radians(fovDeg), aspect, zNear, zFar) *
         glm::lookAtRH(eye, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
}

// Reversed infinite perspective as in shadows/light_view.h: clip z = near, w = distance along the
// view axis, so z / w = near / distance.
glm::mat4 reversedAt(glm::vec3 eye, float tanHalf, float aspect, float zNear) {
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f / (tanHalf * aspect);
  p[1][1] = 1.0f / tanHalf;
  p[3][2] = zNear;  // z = near
  p[2][3] = -1.0f;  // w = -z_view
  return p * glm::lookAtRH(eye, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
}

struct Scene {
  std::vector<glm::vec3> points;
  std::vector<uint32_t> payloads;
  std::vector<glm::mat4> viewProj;
  std::vector<glm::vec3> eye;
  std::vector<int> width, height;
  std::vector<int> targetOf;  // views may share a target
  int targets = 0;
  uint64_t nonFinite = 0;
};

// 50,000 random points in and around [-1, 1]^3, a few non-finite ones, and 10,000 colliding ones:
// 5,000 on one ray from view 0's eye (one pixel of view 0, many depths) and 5,000 copies of one
// position (one pixel in every view, equal depths, ties broken by payload). 24 views of various
// sizes (few multiples of 8), one inside the cloud (half the points behind it), one orthographic,
// the last two sharing a target.
Scene makeScene(bool reversed) {
  Scene s;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> u(-1.3f, 1.3f);
  std::uniform_int_distribution<uint32_t> pay(0, 1000);  // small range: equal payloads happen too
  const int sizes[][2] = {{1, 1},    {7, 5},     {8, 8},    {13, 29},  {64, 48},  {100, 77}, {257, 131}, {31, 300},
                          {512, 3},  {3, 512},   {90, 90},  {129, 65}, {40, 41},  {17, 200}, {200, 17},  {61, 59},
                          {33, 34},  {255, 255}, {9, 1000}, {77, 23},  {120, 80}, {2, 2},    {150, 100}, {150, 100}};
  for (int v = 0; v < 24; ++v) {
    const float a = 0.7f * static_cast<float>(v), e = 0.4f * std::sin(1.3f * static_cast<float>(v));
    const glm::vec3 eye = (2.5f + 0.1f * static_cast<float>(v % 5)) * glm::vec3(std::cos(a) * std::cos(e), std::sin(e),
                                                                                 std::sin(a) * std::cos(e));
    const float aspect = static_cast<float>(sizes[v][0]) / static_cast<float>(sizes[v][1]);
    glm::mat4 m;
    if (v == 5) {  // inside the cloud, looking at the origin from (0, 0, 0.5)
      m = reversed ? reversedAt(glm::vec3(0.0f, 0.0f, 0.5f), 1.0f, aspect, 0.01f)
                   : perspectiveAt(glm::vec3(0.0f, 0.0f, 0.5f), 90.0f, aspect, 0.01f, 5.0f);
    } else if (v == 9 && !reversed) {
      m = glm::orthoRH_ZO(-1.1f, 1.1f, -1.1f, 1.1f, 0.5f, 4.0f) * glm::lookAtRH(eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    } else {
      const float fov = 30.0f + 2.0f * static_cast<float>(v);
      m = reversed ? reversedAt(eye, std::tan(glm::radians(fov) * 0.5f), aspect, 0.5f + 0.05f * static_cast<float>(v))
                   : perspectiveAt(eye, fov, aspect, 1.0f, 3.0f + 0.1f * static_cast<float>(v));  // far clips some
    }
    s.viewProj.push_back(m);
    s.eye.push_back(v == 5 ? glm::vec3(0.0f, 0.0f, 0.5f) : eye);
    s.width.push_back(sizes[v][0]);
    s.height.push_back(sizes[v][1]);
    s.targetOf.push_back(v == 23 ? 22 : v);
  }
  s.targets = 23;
  for (int i = 0; i < 50000; ++i) {
    glm::vec3 p(u(rng), u(rng), u(rng));
    if (i % 5000 == 17) p.x = kNaN;
    if (i % 5000 == 18) p.y = kInf;
    if (i % 5000 == 19) p.z = -kInf;
    if (i % 5000 == 20) p = glm::vec3(kNaN);
    s.points.push_back(p);
  }
  s.nonFinite = 4 * 10;
  // A ray from view 0's eye through a point at NDC (0.3, -0.2, 0.5): every point on it projects to
  // (nearly) the same pixel of view 0, at depths from 0.7 to 1.9 times that point's.
  const glm::vec4 q = glm::inverse(s.viewProj[0]) * glm::vec4(0.3f, -0.2f, 0.5f, 1.0f);
  const glm::vec3 eye0 = s.eye[0], dir = glm::vec3(q) / q.w - eye0;
  for (int i = 0; i < 5000; ++i) s.points.push_back(eye0 + (0.7f + 1.2f * static_cast<float>(i) / 5000.0f) * dir);
  for (int i = 0; i < 5000; ++i) s.points.push_back(glm::vec3(0.1f, 0.2f, -0.15f));
  std::shuffle(s.points.begin(), s.points.end(), rng);
  for (size_t i = 0; i < s.points.size(); ++i) s.payloads.push_back(pay(rng));
  return s;
}

struct Result {
  std::vector<Image<uint64_t>> targets;
  SplatStats stats;
};

// calls > 1 splits the points into consecutive slices, one call each (payloads must then be given:
// index payloads are relative to a call).
Result splat(const Scene& s, bool reversed, bool indexPayload, int threads, int viewsPerPass, int calls = 1,
             int64_t simd = 0) {
  Result r;
  r.targets.resize(static_cast<size_t>(s.targets));
  for (int t = 0; t < s.targets; ++t) r.targets[static_cast<size_t>(t)].resize(s.width[static_cast<size_t>(t)], s.height[static_cast<size_t>(t)]);
  std::vector<SplatView> views;
  for (size_t v = 0; v < s.viewProj.size(); ++v)
    views.push_back({s.viewProj[v], &r.targets[static_cast<size_t>(s.targetOf[v])]});
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (auto& t : r.targets) clearKeys(t);
    // Several calls over consecutive slices of the points accumulate like one call.
    const size_t n = s.points.size();
    for (int c = 0; c < calls; ++c) {
      const size_t b = n * static_cast<size_t>(c) / static_cast<size_t>(calls);
      const size_t e = n * static_cast<size_t>(c + 1) / static_cast<size_t>(calls);
      const std::span<const glm::vec3> pts(s.points.data() + b, e - b);
      const std::span<const uint32_t> pay = indexPayload ? std::span<const uint32_t>() : std::span(s.payloads.data() + b, e - b);
      const SplatStats st =
          splatPoints(pts, pay, views, reversed ? DepthKey::ReversedZOverW : DepthKey::ZOverW, viewsPerPass, simd);
      r.stats.points += st.points;
      r.stats.views = st.views;
      r.stats.passes += st.passes;
      r.stats.written += st.written;
      r.stats.culled += st.culled;
      r.stats.nonFinite += st.nonFinite;
    }
  });
  return r;
}

struct Reference {
  std::vector<RefTarget> targets;
  uint64_t landed = 0;
};

Reference reference(const Scene& s, bool reversed, bool indexPayload) {
  Reference ref;
  for (int t = 0; t < s.targets; ++t) ref.targets.emplace_back(s.width[static_cast<size_t>(t)], s.height[static_cast<size_t>(t)]);
  for (size_t i = 0; i < s.points.size(); ++i)
    for (size_t v = 0; v < s.viewProj.size(); ++v)
      ref.landed += referenceSplat(s.viewProj[v], s.points[i], indexPayload ? static_cast<uint32_t>(i) : s.payloads[i],
                                   reversed, ref.targets[static_cast<size_t>(s.targetOf[v])]);
  return ref;
}

void checkAgainst(const Result& r, const Reference& ref, const Scene& s, bool reversed) {
  for (size_t t = 0; t < ref.targets.size(); ++t) expectMatches(r.targets[t], ref.targets[t], reversed, static_cast<int>(t));
  EXPECT_EQ(r.stats.points, s.points.size());
  EXPECT_EQ(r.stats.views, s.viewProj.size());
  EXPECT_EQ(r.stats.written, ref.landed);
  EXPECT_EQ(r.stats.written + r.stats.culled, s.points.size() * s.viewProj.size());
  EXPECT_EQ(r.stats.nonFinite, s.nonFinite);
}

TEST(Splat, MatchesReferenceAtAnyThreadCountAndViewsPerPass) {
  // 7 threads even on a 2-core machine: the arena then really runs 7 workers.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  const Scene s = makeScene(false);
  const Reference ref = reference(s, false, false);
  // The scene exercises what it should: most pairs land, many are culled, view 0's ray collides.
  EXPECT_GT(ref.landed, s.points.size() * s.viewProj.size() / 3);
  EXPECT_LT(ref.landed, s.points.size() * s.viewProj.size() * 9 / 10);
  for (int threads : {1, 2, 7})
    for (int k : {1, 3, 24}) {
      SCOPED_TRACE(testing::Message() << threads << " threads, K = " << k);
      const Result r = splat(s, false, false, threads, k);
      checkAgainst(r, ref, s, false);
      EXPECT_EQ(r.stats.passes, static_cast<uint64_t>((24 + k - 1) / k));
    }
  // Three calls over slices of the points accumulate into the same targets; K = 0 means all views.
  const Result r = splat(s, false, false, 2, 0, 3);
  checkAgainst(r, ref, s, false);
  EXPECT_EQ(r.stats.passes, 3u);
}

// The projection is SIMD: every target this CPU runs gives the reference's bits, both depth keys.
TEST(Splat, EverySimdTargetMatchesReference) {
  for (bool reversed : {false, true}) {
    const Scene s = makeScene(reversed);
    const Reference ref = reference(s, reversed, false);
    for (int64_t target : supportedSimdTargets()) {
      SCOPED_TRACE(testing::Message() << simdTargetName(target) << (reversed ? ", reversed" : ""));
      checkAgainst(splat(s, reversed, false, 2, 7, 1, target), ref, s, reversed);
    }
  }
}

TEST(Splat, ReversedDepthWithIndexPayloadMatchesReference) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  const Scene s = makeScene(true);
  const Reference ref = reference(s, true, true);
  EXPECT_GT(ref.landed, s.points.size() * s.viewProj.size() / 3);
  for (int threads : {1, 7}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    const Result r = splat(s, true, true, threads, 5);
    checkAgainst(r, ref, s, true);
    // resolveDepth gives back d = z / w itself (larger nearer), resolvePayload the point index.
    ImageFloat depth;
    Image<uint32_t> payload;
    for (size_t t = 0; t < ref.targets.size(); ++t) {
      resolveDepth(r.targets[t], DepthKey::ReversedZOverW, depth, -1.0f);
      resolvePayload(r.targets[t], payload, 0xDEADBEEFu);
      const RefTarget& rt = ref.targets[t];
      for (int y = 0; y < rt.height; ++y)
        for (int x = 0; x < rt.width; ++x) {
          const Hit& h = rt.hits[static_cast<size_t>(y) * static_cast<size_t>(rt.width) + static_cast<size_t>(x)];
          ASSERT_EQ(depth.at(x, y), h.any ? h.d : -1.0f) << "target " << t << " (" << x << ", " << y << ")";
          ASSERT_EQ(payload.at(x, y), h.any ? h.payload : 0xDEADBEEFu);
        }
    }
  }
}

// An identity-like view: clip = (x, y, z, w) with w given by the point's own z (see below).
// Target 13 x 7 so that clip x = -w is screen x 0 and clip x = w is screen x 13 exactly.
TEST(Splat, ViewportEdgesDepthRangeAndNonFinite) {
  glm::mat4 m(0.0f);  // clip = (p.x, p.y, 0.25, p.z): w is the point's z, clip z is 0.25
  m[0][0] = 1.0f;
  m[1][1] = 1.0f;
  m[3][2] = 0.25f;
  m[2][3] = 1.0f;
  const float almost = 1.0f - std::ldexp(1.0f, -20);
  struct Case {
    glm::vec3 p;
    int x, y;  // expected pixel, or x = -1: culled
  };
  const Case cases[] = {
      {{-1.0f, 1.0f, 1.0f}, 0, 0},       // clip x = -w: column 0; y = w: row 0
      {{1.0f, 0.0f, 1.0f}, -1, 0},       // x = w: screen x = width, skipped
      {{0.0f, -1.0f, 1.0f}, -1, 0},      // y = -w: screen y = height, skipped
      {{almost, -almost, 1.0f}, 12, 6},  // just inside the far corner
      {{-2.0f, 2.0f, 2.0f}, 0, 0},       // the same at w = 2
      {{-1.0001f, 0.0f, 1.0f}, -1, 0},   // left of the viewport
      {{0.0f, 1.0001f, 1.0f}, -1, 0},    // above
      {{0.0f, 0.0f, 0.25f}, 6, 3},       // z = w: the far plane, kept
      {{0.0f, 0.0f, 0.2f}, -1, 0},       // z > w: beyond the far plane
      {{0.0f, 0.0f, 0.0f}, -1, 0},       // w = 0
      {{0.0f, 0.0f, -1.0f}, -1, 0},      // behind: w < 0
      {{kNaN, 0.0f, 1.0f}, -1, 0},       // non-finite
      {{0.0f, kInf, 1.0f}, -1, 0},
      {{0.0f, 0.0f, kInf}, -1, 0},
      {{-kInf, kNaN, -kInf}, -1, 0},
  };
  std::vector<glm::vec3> pts;
  for (const Case& c : cases) pts.push_back(c.p);
  Image<uint64_t> keys(13, 7, 12345);
  clearKeys(keys);
  const SplatView views[] = {{m, &keys}};
  const SplatStats st = splatPoints(pts, {}, views, DepthKey::ZOverW, 1);
  Image<uint64_t> want(13, 7, kEmptyKey);
  uint64_t landed = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Case& c = cases[i];
    if (c.x < 0) continue;
    ++landed;
    const float d = 0.25f / c.p.z;
    uint64_t& k = want.at(c.x, c.y);
    k = std::min(k, uint64_t{std::bit_cast<uint32_t>(d)} << 32 | i);
  }
  for (int y = 0; y < keys.paddedRows(); ++y)
    for (int x = 0; x < keys.stride(); ++x) EXPECT_EQ(keys.at(x, y), want.at(x, y)) << x << ", " << y;
  EXPECT_EQ(st.points, pts.size());
  EXPECT_EQ(st.views, 1u);
  EXPECT_EQ(st.passes, 1u);
  EXPECT_EQ(st.written, landed);
  EXPECT_EQ(st.written, 4u);
  EXPECT_EQ(st.culled, pts.size() - landed);
  EXPECT_EQ(st.nonFinite, 4u);
}

// A non-finite clip position is never written: from a NaN in the matrix, or from w overflowing.
TEST(Splat, NonFiniteClipPositionWritesNothing) {
  glm::mat4 m(1.0f);
  m[3][3] = kNaN;
  Image<uint64_t> keys(9, 9);
  clearKeys(keys);
  const std::vector<glm::vec3> pts(100, glm::vec3(0.1f, 0.2f, 0.3f));
  const SplatView views[] = {{m, &keys}};
  const SplatStats st = splatPoints(pts, {}, views, DepthKey::ZOverW);
  EXPECT_EQ(st.written, 0u);
  EXPECT_EQ(st.culled, 100u);
  EXPECT_EQ(st.nonFinite, 0u);
  for (uint64_t k : keys.packed()) EXPECT_EQ(k, kEmptyKey);

  // Finite point, finite matrix, w overflowing to +Inf (x, y, z finite): culled. clip = (x, y, 0,
  // 1e30 z); the second point (w = 1e20) lands, at depth 0.
  glm::mat4 big(1.0f);
  big[2][2] = 0.0f;
  big[2][3] = 1e30f;
  big[3][3] = 0.0f;
  const std::vector<glm::vec3> far = {{0.1f, 0.2f, 1e10f}, {0.1f, 0.2f, 1e-10f}};
  clearKeys(keys);
  const SplatView bigViews[] = {{big, &keys}};
  const SplatStats st2 = splatPoints(far, {}, bigViews, DepthKey::ZOverW);
  EXPECT_EQ(st2.written, 1u);
  EXPECT_EQ(st2.culled, 1u);
  EXPECT_EQ(keys.at(4, 4), uint64_t{1});
}

// 10,000 points in one pixel: the nearest wins; among equal depths, the smallest payload; -0 and
// +0 are the same depth.
TEST(Splat, CollisionsNearestThenSmallestPayload) {
  // clip = (x, y, z, 1), with the constant term of z -0, so that z = -0 gives clip z = -0 (with +0
  // the sum would round to +0) and z / w = -0.
  glm::mat4 m(1.0f);
  m[3][2] = -0.0f;
  Image<uint64_t> keys(4, 4);
  std::vector<glm::vec3> pts;
  std::vector<uint32_t> pay;
  std::mt19937 rng(3);
  for (uint32_t i = 0; i < 10000; ++i) {
    pts.push_back({0.1f, 0.1f, 0.5f + static_cast<float>(i % 97) * 0.001f});  // pixel (2, 1)
    pay.push_back(1000000u - i);
  }
  for (uint32_t i = 0; i < 10000; ++i) {
    pts.push_back({-0.9f, -0.9f, (i & 1) ? -0.0f : 0.0f});  // pixel (0, 3), depth 0 (both signs)
    pay.push_back(500u + ((i + 1) * 7919u) % 10000u);       // 500..10499, the smallest (500) at i = 9999: -0
  }
  std::vector<size_t> order(pts.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<glm::vec3> p2;
  std::vector<uint32_t> q2;
  for (size_t i : order) p2.push_back(pts[i]), q2.push_back(pay[i]);
  const SplatView views[] = {{m, &keys}};
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  for (int threads : {1, 2, 7}) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      clearKeys(keys);
      splatPoints(p2, q2, views, DepthKey::ZOverW);
    });
    // Depth 0.5 is held by i = 0, 97, 194, ...: the largest such i has the smallest payload.
    const uint32_t best = 1000000u - (9999u / 97u) * 97u;
    EXPECT_EQ(keys.at(2, 1), uint64_t{std::bit_cast<uint32_t>(0.5f)} << 32 | best);
    EXPECT_EQ(keys.at(0, 3), uint64_t{500});  // depth bits 0, payload 500
    int nonEmpty = 0;
    for (uint64_t k : keys.packed()) nonEmpty += k != kEmptyKey;
    EXPECT_EQ(nonEmpty, 2);
  }
  // Reversed: the largest z / w wins (0.5 + 96 * 0.001, i = 96, 193, ...).
  clearKeys(keys);
  splatPoints(p2, q2, views, DepthKey::ReversedZOverW);
  const float dmax = 0.5f + 96.0f * 0.001f;
  const uint32_t best = 1000000u - ((9999u - 96u) / 97u * 97u + 96u);
  EXPECT_EQ(keys.at(2, 1), uint64_t{0x3F800000u - std::bit_cast<uint32_t>(dmax)} << 32 | best);
  EXPECT_EQ(keys.at(0, 3), uint64_t{0x3F800000u} << 32 | 500u);  // d = 0: the farthest possible
}

TEST(Splat, ResolveFunctions) {
  Image<uint64_t> keys(3, 2);
  clearKeys(keys);
  const Rgba8 red{255, 0, 0, 255}, teal{0, 128, 128, 7};
  keys.at(0, 0) = uint64_t{std::bit_cast<uint32_t>(0.25f)} << 32 | packRgba8(red);
  keys.at(2, 1) = uint64_t{std::bit_cast<uint32_t>(1.0f)} << 32 | packRgba8(teal);
  keys.at(1, 1) = uint64_t{0x3F800000u - std::bit_cast<uint32_t>(0.75f)} << 32 | 42u;

  EXPECT_EQ(packRgba8(Rgba8{1, 2, 3, 4}), 0x04030201u);
  EXPECT_EQ(unpackRgba8(0x04030201u), (Rgba8{1, 2, 3, 4}));

  ImageFloat depth;
  resolveDepth(keys, DepthKey::ZOverW, depth, 9.0f);
  ASSERT_EQ(depth.width(), 3);
  ASSERT_EQ(depth.height(), 2);
  EXPECT_EQ(depth.at(0, 0), 0.25f);
  EXPECT_EQ(depth.at(2, 1), 1.0f);
  EXPECT_EQ(depth.at(1, 0), 9.0f);
  resolveDepth(keys, DepthKey::ReversedZOverW, depth, 0.0f);
  EXPECT_EQ(depth.at(1, 1), 0.75f);
  EXPECT_EQ(depth.at(2, 0), 0.0f);

  Image<uint32_t> payload;
  resolvePayload(keys, payload);
  EXPECT_EQ(payload.at(1, 1), 42u);
  EXPECT_EQ(payload.at(0, 0), packRgba8(red));
  EXPECT_EQ(payload.at(0, 1), UINT32_MAX);

  ImageRgba8 color;
  const Rgba8 bg{1, 2, 3, 0};
  resolveColor(keys, color, bg);
  EXPECT_EQ(color.at(0, 0), red);
  EXPECT_EQ(color.at(2, 1), teal);
  EXPECT_EQ(color.at(1, 0), bg);
  EXPECT_EQ(color.at(0, 1), bg);
}

TEST(Splat, ClearKeysFillsPadding) {
  Image<uint64_t> keys(5, 3, 7);
  clearKeys(keys);
  for (int y = 0; y < keys.paddedRows(); ++y)
    for (int x = 0; x < keys.stride(); ++x) ASSERT_EQ(keys.at(x, y), kEmptyKey);
}

TEST(Splat, InvalidArgumentsThrow) {
  Image<uint64_t> keys(4, 4), empty;
  const std::vector<glm::vec3> pts(3, glm::vec3(0.0f));
  const std::vector<uint32_t> twoPayloads(2, 0u);
  const SplatView one[] = {{glm::mat4(1.0f), &keys}};
  const SplatView none[] = {{glm::mat4(1.0f), nullptr}};
  const SplatView zero[] = {{glm::mat4(1.0f), &empty}};
  EXPECT_THROW(splatPoints(pts, twoPayloads, one, DepthKey::ZOverW), std::invalid_argument);
  EXPECT_THROW(splatPoints(pts, {}, none, DepthKey::ZOverW), std::invalid_argument);
  EXPECT_THROW(splatPoints(pts, {}, zero, DepthKey::ZOverW), std::invalid_argument);
  EXPECT_THROW(splatPoints(pts, {}, one, DepthKey::ZOverW, 2), std::invalid_argument);
  EXPECT_THROW(splatPoints(pts, {}, one, DepthKey::ZOverW, -1), std::invalid_argument);
  // No points or no views: nothing to do, zero stats.
  const SplatStats st = splatPoints({}, {}, one, DepthKey::ZOverW);
  EXPECT_EQ(st.written + st.culled + st.passes, 0u);
  EXPECT_EQ(splatPoints(pts, {}, {}, DepthKey::ZOverW).passes, 0u);
}

}  // namespace
}  // namespace penumbra::raster
