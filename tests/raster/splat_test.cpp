// Point splatting against a scalar reference written from the conventions in splat.h (sequential,
// glm's matrix product, "nearest d wins, then the smaller payload"), bit for bit; the same bytes at
// 1, 2 and 7 threads and at any number of views per pass; the viewport edges, the depth range and
// non-finite points; the resolve functions; the stats.
#include "raster/splat.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
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

// ---- Depth-only splatting (32-bit depth bits read in place) ----------------------------------

struct DepthResult {
  std::vector<Image<uint32_t>> targets;
  std::vector<SplatRect> touched;
  SplatStats stats;
};

DepthResult splatDepthOf(const Scene& s, bool reversed, int threads, int k,
                         int64_t simd = 0) {
  const DepthKey key = reversed ? DepthKey::ReversedZOverW : DepthKey::ZOverW;
  DepthResult r;
  r.targets.resize(static_cast<size_t>(s.targets));
  for (int t = 0; t < s.targets; ++t)
    r.targets[static_cast<size_t>(t)].resize(s.width[static_cast<size_t>(t)], s.height[static_cast<size_t>(t)], 12345u);
  std::vector<DepthSplatView> views;
  for (size_t v = 0; v < s.viewProj.size(); ++v) views.push_back({s.viewProj[v], &r.targets[static_cast<size_t>(s.targetOf[v])]});
  r.touched.resize(views.size());
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (auto& t : r.targets) clearDepthBits(t, key);
    r.stats = splatDepth(s.points, {}, views, key, k, simd, r.touched);
  });
  return r;
}

// The depth splat's maps are the 64-bit splat's resolved depth, bit for bit (padding left empty),
// its stats the same, and each view's touched rectangle the bounding box of the texels its points
// landed in (from the reference, view by view).
TEST(SplatDepth, EqualsTheResolvedKeysAtAnyThreadCountPassAndTarget) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  for (bool reversed : {false, true}) {
    const DepthKey key = reversed ? DepthKey::ReversedZOverW : DepthKey::ZOverW;
    const Scene s = makeScene(reversed);
    const Reference ref = reference(s, reversed, false);
    std::vector<SplatRect> want(s.viewProj.size());
    for (size_t v = 0; v < s.viewProj.size(); ++v) {
      RefTarget one(s.width[v], s.height[v]);
      for (const glm::vec3& p : s.points) referenceSplat(s.viewProj[v], p, 0, reversed, one);
      for (int y = 0; y < one.height; ++y)
        for (int x = 0; x < one.width; ++x)
          if (one.hits[static_cast<size_t>(y) * static_cast<size_t>(one.width) + static_cast<size_t>(x)].any)
            want[v].add({x, y, x + 1, y + 1});
    }
    const Result keys = splat(s, reversed, false, 2, 0);
    const float emptyValue = std::bit_cast<float>(emptyDepthBits(key));
    std::vector<std::pair<int, int64_t>> runs = {{1, 0}, {2, 0}, {7, 0}};
    for (int64_t target : supportedSimdTargets()) runs.push_back({2, target});
    for (const auto& [threads, simd] : runs)
      for (int k : {1, 5, 24}) {
        SCOPED_TRACE(testing::Message() << (reversed ? "reversed, " : "") << threads << " threads, K = " << k << ", "
                                        << simdTargetName(simdTargetRun(simd)));
        const DepthResult r = splatDepthOf(s, reversed, threads, k, simd);
        EXPECT_EQ(r.stats.written, ref.landed);
        EXPECT_EQ(r.stats.written + r.stats.culled, s.points.size() * s.viewProj.size());
        EXPECT_EQ(r.stats.nonFinite, s.nonFinite);
        EXPECT_EQ(r.stats.passes, static_cast<uint64_t>((24 + k - 1) / k));
        ImageFloat depth;
        for (size_t t = 0; t < r.targets.size(); ++t) {
          resolveDepth(keys.targets[t], key, depth, emptyValue);
          size_t bad = 0;
          for (int y = 0; y < r.targets[t].paddedRows(); ++y)
            for (int x = 0; x < r.targets[t].stride(); ++x) {
              const bool inside = x < depth.width() && y < depth.height();
              const uint32_t expected = inside ? std::bit_cast<uint32_t>(depth.at(x, y)) : emptyDepthBits(key);
              if (r.targets[t].at(x, y) != expected && bad++ < 3)
                ADD_FAILURE() << "target " << t << " (" << x << ", " << y << "): " << std::hex << r.targets[t].at(x, y)
                              << " want " << expected;
            }
          EXPECT_EQ(bad, 0u);
        }
        for (size_t v = 0; v < want.size(); ++v) {
          EXPECT_EQ(r.touched[v].x0, want[v].x0) << "view " << v;
          EXPECT_EQ(r.touched[v].y0, want[v].y0) << "view " << v;
          EXPECT_EQ(r.touched[v].x1, want[v].x1) << "view " << v;
          EXPECT_EQ(r.touched[v].y1, want[v].y1) << "view " << v;
        }
      }
  }
}

// One surfel into one view, written plainly from splat.h's formulas (the kernel's operations in
// its order): each covered texel centre's depth, kept if nearer (reversed depth: larger).
void referenceSurfel(const glm::mat4& vp, glm::vec3 p, const SurfelAxes& ax, Image<uint32_t>& map) {
  const auto row = [&](int r) { return glm::vec4(vp[0][r], vp[1][r], vp[2][r], vp[3][r]); };
  const auto proj = [&](glm::vec4 m) { return (m.x * p.x + m.y * p.y) + (m.z * p.z + m.w); };
  const auto lin = [&](glm::vec4 m, glm::vec3 e) { return (m.x * e.x + m.y * e.y) + m.z * e.z; };
  const glm::vec4 rx = row(0), ry = row(1), rz = row(2), rw = row(3);
  const float W = static_cast<float>(map.width()), H = static_cast<float>(map.height());
  const float cx = proj(rx), cy = proj(ry), cz = proj(rz), cw = proj(rw);
  const float X = cx / cw, Y = cy / cw, d = cz / cw;
  const float sx = (X * 0.5f + 0.5f) * W, sy = (0.5f - Y * 0.5f) * H;
  const float R = static_cast<float>(kMaxSurfelReach);  // centres up to R texels outside the view
  if (!(cw > 0.0f && cw <= std::numeric_limits<float>::max() && cz >= 0.0f && cz <= cw && sx >= -R && sx < W + R &&
        sy >= -R && sy < H + R))
    return;
  const float k = 1.0f / cw, hw = 0.5f * W, nh = -0.5f * H;
  const float ruw = lin(rw, ax.u), rvw = lin(rw, ax.v);
  const float Ax = hw * ((lin(rx, ax.u) - X * ruw) * k), Ay = nh * ((lin(ry, ax.u) - Y * ruw) * k);
  const float Bx = hw * ((lin(rx, ax.v) - X * rvw) * k), By = nh * ((lin(ry, ax.v) - Y * rvw) * k);
  const float Du = (lin(rz, ax.u) - d * ruw) * k, Dv = (lin(rz, ax.v) - d * rvw) * k;
  const float inv = 1.0f / (Ax * By - Ay * Bx);
  const float h = 0.5f + 1.0f / 64.0f, reach = static_cast<float>(kMaxSurfelReach);
  float ex = (std::abs(Ax) + std::abs(Bx)) * h, ey = (std::abs(Ay) + std::abs(By)) * h;
  ex = ex <= reach ? ex : reach, ey = ey <= reach ? ey : reach;
  const int ix = static_cast<int>(std::floor(sx)), iy = static_cast<int>(std::floor(sy));
  const int i0 = std::max(static_cast<int>(std::ceil((sx - ex) - 0.5f)), std::max(0, ix - kMaxSurfelReach));
  const int i1 = std::min(static_cast<int>(std::floor((sx + ex) - 0.5f)), std::min(map.width() - 1, ix + kMaxSurfelReach));
  const int j0 = std::max(static_cast<int>(std::ceil((sy - ey) - 0.5f)), std::max(0, iy - kMaxSurfelReach));
  const int j1 = std::min(static_cast<int>(std::floor((sy + ey) - 0.5f)), std::min(map.height() - 1, iy + kMaxSurfelReach));
  const float m00 = By * inv, m01 = -(Bx * inv), m10 = -(Ay * inv), m11 = Ax * inv;
  for (int y = j0; y <= j1; ++y)
    for (int x = i0; x <= i1; ++x) {
      const float qx = (static_cast<float>(x) + 0.5f) - sx, qy = (static_cast<float>(y) + 0.5f) - sy;
      const float a = m00 * qx + m01 * qy, b = m10 * qx + m11 * qy;
      float dc = d + (a * Du + b * Dv);
      if (!(std::abs(a) <= h && std::abs(b) <= h) || std::isnan(dc)) continue;
      dc = std::clamp(dc, 0.5f * d, std::min(2.0f * d, 1.0f));
      map.at(x, y) = std::max(map.at(x, y), std::bit_cast<uint32_t>(dc) & 0x7FFFFFFFu);
    }
}

// A view as shadows/light_view.h makes them: reversed infinite depth, from `eye` down -y.
glm::mat4 reversedDown(glm::vec3 eye, float tanHalf) {
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f / tanHalf, proj[1][1] = 1.0f / tanHalf, proj[3][2] = 0.5f, proj[2][3] = -1.0f;
  return proj * glm::lookAtRH(eye, eye - glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f));
}

// Surfels tiling a tilted plane: a grid of cells c x c on it, each surfel centred in its cell with
// the cell's edges as axes (the union of their parallelograms is the plane's rectangle R exactly).
struct TiledPlane {
  std::vector<glm::vec3> points;
  std::vector<SurfelAxes> axes;
  glm::vec3 origin{-1.0f, 0.0f, -0.8f}, du, dv;  // R = origin + [0, nu] du + [0, nv] dv
  int nu = 0, nv = 0;
  TiledPlane(int cellsU, int cellsV, float cell) : nu(cellsU), nv(cellsV) {
    du = cell * glm::normalize(glm::vec3(1.0f, 0.35f, 0.0f));
    dv = cell * glm::normalize(glm::vec3(0.1f, -0.25f, 1.0f));
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        points.push_back(origin + (static_cast<float>(i) + 0.5f) * du + (static_cast<float>(j) + 0.5f) * dv);
        axes.push_back({du, dv});
      }
  }
};

// Surfels: every SIMD target, 1 and 3 threads, the view-by-view and the chunked traversal (a cloud
// over 4 MiB: 160,000 surfels) and the streaming splatter give the plain reference's bits, with touched
// rectangles holding every written texel.
TEST(SplatDepth, SurfelsMatchTheReferenceOnEveryTargetAndTraversal) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int cloud : {3000, 160000}) {
    // A tilted plane tiled by cells of a third of a texel, then random surfels of every size and
    // orientation (grazing and degenerate ones among them).
    const int side = cloud == 3000 ? 40 : 400;
    const TiledPlane plane(side, side, 0.006f);
    std::vector<glm::vec3> pts = plane.points;
    std::vector<SurfelAxes> axes = plane.axes;
    for (int i = 0; i < 1500; ++i) {
      pts.push_back(glm::vec3(u(rng), 0.5f * u(rng), u(rng)));
      const float size = std::pow(10.0f, -3.0f + 2.0f * (0.5f + 0.5f * u(rng)));
      axes.push_back({size * glm::vec3(u(rng), u(rng), u(rng)), size * glm::vec3(u(rng), u(rng), u(rng))});
    }
    axes[axes.size() - 1] = {glm::vec3(0.01f, 0, 0), glm::vec3(0.02f, 0, 0)};  // degenerate: covers nothing
    axes[axes.size() - 2] = {glm::vec3(0.0f, 0.3f, 0.0f), glm::vec3(0.0f, 0.0f, 0.01f)};  // edge-on, long
    const glm::mat4 views[] = {reversedDown({0.2f, 3.0f, 0.1f}, 0.45f), reversedDown({-0.5f, 2.5f, 0.4f}, 0.6f)};
    const int sizes[][2] = {{96, 96}, {61, 77}};
    std::vector<Image<uint32_t>> want;
    for (int v = 0; v < 2; ++v) {
      want.emplace_back(sizes[v][0], sizes[v][1], 0u);
      for (size_t i = 0; i < pts.size(); ++i) referenceSurfel(views[v], pts[i], axes[i], want.back());
    }
    size_t written = 0;
    for (int y = 0; y < want[0].height(); ++y)
      for (int x = 0; x < want[0].width(); ++x) written += want[0].at(x, y) != 0u ? 1 : 0;
    EXPECT_GT(written, 500u);
    const auto check = [&](std::vector<Image<uint32_t>>& maps, std::span<const SplatRect> touched, const char* what) {
      for (int v = 0; v < 2; ++v) {
        size_t bad = 0, outside = 0;
        for (int y = 0; y < maps[v].height(); ++y)
          for (int x = 0; x < maps[v].width(); ++x) {
            bad += maps[v].at(x, y) != want[v].at(x, y) ? 1 : 0;
            const SplatRect& r = touched[v];
            outside += maps[v].at(x, y) != 0u && !(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1) ? 1 : 0;
          }
        EXPECT_EQ(bad, 0u) << what << ", view " << v;
        EXPECT_EQ(outside, 0u) << what << ", view " << v;
      }
    };
    for (int threads : {1, 3})
      for (int64_t target : supportedSimdTargets()) {
        SCOPED_TRACE(testing::Message() << cloud << " points, " << threads << " threads, " << simdTargetName(target));
        std::vector<Image<uint32_t>> maps;
        for (int v = 0; v < 2; ++v) maps.emplace_back(sizes[v][0], sizes[v][1], 0u);
        const DepthSplatView dv[] = {{views[0], &maps[0]}, {views[1], &maps[1]}};
        std::vector<SplatRect> touched(2);
        tbb::task_arena arena(threads);
        arena.execute([&] { splatDepth(pts, axes, dv, DepthKey::ReversedZOverW, 1, target, touched); });
        check(maps, touched, "splatDepth");
        // The streaming splatter, the surfels added from several threads in any order.
        std::vector<Image<uint32_t>> streamed;
        for (int v = 0; v < 2; ++v) streamed.emplace_back(sizes[v][0], sizes[v][1], 0u);
        const DepthSplatView sv[] = {{views[0], &streamed[0]}, {views[1], &streamed[1]}};
        DepthSplatter splatter(sv, DepthKey::ReversedZOverW, true, target);
        arena.execute([&] {
          tbb::parallel_for(size_t{0}, pts.size(), [&](size_t i) { splatter.add(pts[i], axes[i]); });
        });
        splatter.flush();
        const SplatRect st[] = {splatter.touched(0), splatter.touched(1)};
        check(streamed, st, "DepthSplatter");
      }
  }
}

// What surfels are for: a plane tiled by surfels is covered like a rasterized plane -- every texel
// whose centre's ray meets the tiled rectangle R (by more than the margin, 1/64 of a cell) is
// written, none whose ray misses it is, at the plane's true depth there -- where the same points
// without axes (the paper's splat) both bloat R's outline and, with cells larger than a texel,
// leave holes inside it. A second, narrow view sees only the middle of R: the surfels centred just
// outside it still cover its border texels (no holes along the edge).
TEST(SplatDepth, SurfelsCoverAPlaneAsRasterizingItWould) {
  struct Setup {
    glm::vec3 eye;
    float tanHalf;
    float cells[2];  // about half a texel and 1.6 texels
  };
  for (const Setup& setup : {Setup{{0.3f, 4.0f, 0.2f}, 0.5f, {0.02f, 0.065f}},
                             Setup{{-0.2f, 4.0f, -0.1f}, 0.12f, {0.005f, 0.015f}}}) {
  for (float cell : setup.cells) {
    const bool whole = setup.tanHalf > 0.2f;  // the view sees all of R
    const glm::mat4 vp = reversedDown(setup.eye, setup.tanHalf);
    const int w = 101, h = 87;
    const glm::dmat4 inv = glm::inverse(glm::dmat4(vp));
    SCOPED_TRACE(testing::Message() << "cells of " << cell << (whole ? ", whole plane" : ", its middle"));
    const TiledPlane plane(static_cast<int>(1.6f / cell), static_cast<int>(1.4f / cell), cell);
    Image<uint32_t> surf(w, h, 0u), pointMap(w, h, 0u);
    const DepthSplatView sv[] = {{vp, &surf}}, pv[] = {{vp, &pointMap}};
    splatDepth(plane.points, plane.axes, sv, DepthKey::ReversedZOverW);
    splatDepth(plane.points, {}, pv, DepthKey::ReversedZOverW);
    const glm::dvec3 o(plane.origin), a(plane.du), b(plane.dv), n = glm::cross(a, b);
    int holes = 0, bloat = 0, pointHoles = 0, pointBloat = 0, inside = 0;
    double worstDepth = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        // The centre's ray, unprojected at two depths, against the plane: its (s, t) in cells.
        const double uu = (x + 0.5) * 2.0 / w - 1.0, vv = 1.0 - (y + 0.5) * 2.0 / h;
        const glm::dvec4 pa4 = inv * glm::dvec4(uu, vv, 1.0, 1.0), pb4 = inv * glm::dvec4(uu, vv, 0.25, 1.0);
        const glm::dvec3 pa = glm::dvec3(pa4) / pa4.w, pb = glm::dvec3(pb4) / pb4.w;
        const double t = glm::dot(n, o - pa) / glm::dot(n, pb - pa);
        const glm::dvec3 q = pa + t * (pb - pa) - o;
        const double s = glm::dot(q, glm::cross(b, n)) / glm::dot(a, glm::cross(b, n));
        const double r = glm::dot(q, glm::cross(a, n)) / glm::dot(b, glm::cross(a, n));
        const double margin = 1.0 / 64.0 + 1e-3;
        const bool in = s > margin && s < plane.nu - margin && r > margin && r < plane.nv - margin;
        const bool out = s < -margin || s > plane.nu + margin || r < -margin || r > plane.nv + margin;
        const bool covered = surf.at(x, y) != 0u, pointCovered = pointMap.at(x, y) != 0u;
        inside += in ? 1 : 0;
        holes += in && !covered ? 1 : 0;
        bloat += out && covered ? 1 : 0;
        pointHoles += in && !pointCovered ? 1 : 0;
        pointBloat += out && pointCovered ? 1 : 0;
        if (covered && in) {
          const glm::dvec4 c = glm::dmat4(vp) * glm::dvec4(pa + t * (pb - pa), 1.0);
          const double d = c.z / c.w;
          worstDepth = std::max(worstDepth, std::abs(static_cast<double>(std::bit_cast<float>(surf.at(x, y))) - d) / d);
        }
      }
    std::printf("cells %.3f: %d texels inside; surfels: %d holes, %d outside, depth within %.2g; points: %d holes, "
                "%d outside\n",
                static_cast<double>(cell), inside, holes, bloat, worstDepth, pointHoles, pointBloat);
    EXPECT_GT(inside, whole ? 1000 : w * h - 1);
    EXPECT_EQ(holes, 0);
    EXPECT_EQ(bloat, 0);
    EXPECT_LT(worstDepth, 1e-5);
    if (cell == setup.cells[1]) {
      EXPECT_GT(pointHoles, 100);  // sparse points: holes
    } else if (whole) {
      EXPECT_GT(pointBloat, 20);  // dense points: the outline grows
    }
  }
  }
}

TEST(SplatDepth, ClearRectangleAndInvalidArguments) {
  Image<uint32_t> map(10, 6, 7u);
  const SplatRect r{2, 1, 5, 3};
  clearDepthBits(map, DepthKey::ZOverW, &r);
  for (int y = 0; y < map.paddedRows(); ++y)
    for (int x = 0; x < map.stride(); ++x)
      ASSERT_EQ(map.at(x, y), (x >= 2 && x < 5 && y >= 1 && y < 3) ? 0x3F800000u : 7u) << x << ", " << y;
  const SplatRect outside{-5, -5, 100, 2};  // clipped to the image
  clearDepthBits(map, DepthKey::ReversedZOverW, &outside);
  EXPECT_EQ(map.at(9, 1), 0u);
  EXPECT_EQ(map.at(9, 2), 7u);
  clearDepthBits(map, DepthKey::ReversedZOverW);
  for (int y = 0; y < map.paddedRows(); ++y)
    for (int x = 0; x < map.stride(); ++x) ASSERT_EQ(map.at(x, y), 0u);
  const std::vector<glm::vec3> pts(3, glm::vec3(0.0f));
  const std::vector<SurfelAxes> twoSurfels(2);
  Image<uint32_t> empty;
  const DepthSplatView one[] = {{glm::mat4(1.0f), &map}}, none[] = {{glm::mat4(1.0f), nullptr}},
                      zero[] = {{glm::mat4(1.0f), &empty}};
  std::vector<SplatRect> rects(2);
  EXPECT_THROW(splatDepth(pts, twoSurfels, one, DepthKey::ZOverW), std::invalid_argument);
  EXPECT_THROW(splatDepth(pts, {}, none, DepthKey::ZOverW), std::invalid_argument);
  EXPECT_THROW(splatDepth(pts, {}, zero, DepthKey::ZOverW), std::invalid_argument);
  EXPECT_THROW(splatDepth(pts, {}, one, DepthKey::ZOverW, 2), std::invalid_argument);
  EXPECT_THROW(splatDepth(pts, {}, one, DepthKey::ZOverW, 0, 0, rects), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::raster
