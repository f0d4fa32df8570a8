// The ray-traced ground truth ("reference"): the analytic penumbra of a straight edge, exact 0 and
// 1 where nothing is random, convergence with the sample count, the same bytes at every thread
// count and on both Embree paths, the disk cache, and the errors.
//
// The penumbra scene: a light facing down (-y) at height H, an opaque half-plane (the occluder) at
// height ho covering u < 0 along one light axis (x or z), the receivers on the ground y = 0 (which
// is itself a caster). Seen from a receiver at u, the occluder's edge hides the part of the light
// below u_light = -u * (H - ho) / ho (similar triangles about the edge), so with L the light's
// extent along that axis
//     V(u) = clamp(0.5 + u * (H - ho) / (ho * L), 0, 1),
// a linear ramp of width L * ho / (H - ho) = L * (d_r - d_o) / d_o (d_o, d_r: distances of the
// occluder and the receiver plane from the light plane).
#include <gtest/gtest.h>

#include <map>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "raster/pipeline.h"
#include "shadows/ground_truth.h"
#include "shadows/technique.h"

namespace penumbra::shadows {
namespace {

namespace fs = std::filesystem;

// Triangle soup owning its storage; geometry() views it.
struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;

  // Quad a b c d (two triangles, a b c and a c d).
  void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const auto base = static_cast<uint32_t>(positions.size());
    positions.insert(positions.end(), {a, b, c, d});
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  // Horizontal quad at height y over [x0, x1] x [z0, z1].
  void horizontal(float y, float x0, float x1, float z0, float z1) {
    quad({x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1});
  }
  // Closed axis-aligned box.
  void box(glm::vec3 lo, glm::vec3 hi) {
    horizontal(lo.y, lo.x, hi.x, lo.z, hi.z);
    horizontal(hi.y, lo.x, hi.x, lo.z, hi.z);
    quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z});
    quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});
    quad({lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {lo.x, lo.y, hi.z});
    quad({hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z});
  }
  Geometry geometry() const { return {positions, indices}; }
};

constexpr float kH = 5.0f;   // light height
constexpr float kHo = 1.5f;  // occluder height

RectLight downLight(float width, float height) {
  RectLight l;
  l.center = {0.0f, kH, 0.0f};
  l.right = {1.0f, 0.0f, 0.0f};
  l.up = {0.0f, 0.0f, 1.0f};  // normal = cross(right, up) = -y
  l.width = width;
  l.height = height;
  return l;
}

// The occluder half-plane covering u < 0 along x (alongX) or z, and the ground.
Mesh penumbraMesh(bool alongX) {
  Mesh m;
  if (alongX)
    m.horizontal(kHo, -100.0f, 0.0f, -100.0f, 100.0f);
  else
    m.horizontal(kHo, -100.0f, 100.0f, -100.0f, 0.0f);
  m.horizontal(0.0f, -100.0f, 100.0f, -100.0f, 100.0f);
  return m;
}

double analyticV(double u, double extent) {
  const double h = kH, ho = kHo;
  return std::clamp(0.5 + u * (h - ho) / (ho * extent), 0.0, 1.0);
}

// Receivers on the ground facing up: `count` columns spanning u in [-span, span] along x or z,
// `rows` rows at different positions along the edge.
struct Row {
  ReceiverImage image;
  std::vector<double> u;
};
Row penumbraRow(bool alongX, int count, float span, int rows) {
  Row r;
  r.image.resize(count, rows);
  for (int i = 0; i < count; ++i) {
    const float u = -span + 2.0f * span * (static_cast<float>(i) + 0.5f) / static_cast<float>(count);
    r.u.push_back(u);
    for (int j = 0; j < rows; ++j) {
      const float along = 0.37f * static_cast<float>(j) - 0.2f;
      Receiver& rec = r.image.at(i, j);
      rec.position = alongX ? glm::vec3(u, 0.0f, along) : glm::vec3(along, 0.0f, u);
      rec.normal = {0.0f, 1.0f, 0.0f};
      rec.valid = 1;
    }
  }
  return r;
}

struct ErrorStats {
  double rmse = 0, maxAbs = 0;
};
ErrorStats errorAgainstRamp(const raster::ImageFloat& v, const Row& row, double extent) {
  ErrorStats e;
  double sum = 0;
  for (int j = 0; j < v.height(); ++j)
    for (int i = 0; i < v.width(); ++i) {
      const double d = static_cast<double>(v.at(i, j)) - analyticV(row.u[static_cast<size_t>(i)], extent);
      sum += d * d;
      e.maxAbs = std::max(e.maxAbs, std::fabs(d));
    }
  e.rmse = std::sqrt(sum / (static_cast<double>(v.width()) * static_cast<double>(v.height())));
  return e;
}

raster::ImageFloat trace(const Mesh& mesh, const ReceiverImage& rec, const RectLight& light, int samples,
                         GroundTruthStats* stats = nullptr, ResultCache* cache = nullptr) {
  raster::ImageFloat out;
  const GroundTruthStats s = computeGroundTruth(mesh.geometry(), rec, light, {.samples = samples, .cache = cache}, out);
  if (stats) *stats = s;
  return out;
}

bool sameBytes(const raster::ImageFloat& a, const raster::ImageFloat& b) {
  if (a.width() != b.width() || a.height() != b.height()) return false;
  const std::vector<float> pa = a.packed(), pb = b.packed();
  return std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(float)) == 0;
}

// ---- Grid and registry --------------------------------------------------------------------------

TEST(GroundTruthGrid, ShapeFollowsTheLight) {
  const SampleGrid square = sampleGrid(downLight(1, 1), 1024);
  EXPECT_EQ(square.rows, 32);
  EXPECT_EQ(square.base(), 32);
  EXPECT_EQ(square.longRows(), 0);
  const SampleGrid wide = sampleGrid(downLight(2, 1), 512);  // cells of 2/32 x 1/16: square
  EXPECT_EQ(wide.rows, 16);
  EXPECT_EQ(wide.base(), 32);
  const SampleGrid tall = sampleGrid(downLight(1, 4), 64);
  EXPECT_EQ(tall.rows, 16);
  EXPECT_EQ(tall.base(), 4);
  // Not a whole grid: exactly the count asked for, in 32 rows of 31 or 32 (1000 = 8 * 32 + 24 * 31).
  const SampleGrid odd = sampleGrid(downLight(1, 1), 1000);
  EXPECT_EQ(odd.count(), 1000);
  EXPECT_EQ(odd.rows, 32);
  EXPECT_EQ(odd.base(), 31);
  EXPECT_EQ(odd.longRows(), 8);
  EXPECT_EQ(odd.rowStart(8), 256);
  EXPECT_EQ(odd.rowStart(32), 1000);
  EXPECT_EQ(sampleGrid(downLight(1, 1), 1).count(), 1);
  EXPECT_EQ(sampleGrid(downLight(1, 1), 65536).rows, 256);
  const SampleGrid sliver = sampleGrid(downLight(1000, 1), 16);  // one row of 16
  EXPECT_EQ(sliver.rows, 1);
  EXPECT_EQ(sliver.base(), 16);
  EXPECT_EQ(sampleGrid(downLight(1, 1000), 16).rows, 16);  // rows clamp to the count
  for (int n : {1, 2, 3, 7, 100, 1000, 1021, 4097}) {
    const SampleGrid g = sampleGrid(downLight(1.3f, 0.6f), n);
    EXPECT_EQ(g.count(), n);
    EXPECT_EQ(g.rowStart(g.rows), n) << n;
    for (int j = 0; j < g.rows; ++j) EXPECT_GE(g.cellsIn(j), 1) << n;
  }
  EXPECT_THROW(sampleGrid(downLight(1, 1), 0), std::invalid_argument);
  EXPECT_THROW(sampleGrid(downLight(1, 1), 65537), std::invalid_argument);
}

TEST(GroundTruthRegistry, ReferenceIsLastWithItsParameter) {
  const TechniqueInfo* ref = findTechnique("reference");
  ASSERT_NE(ref, nullptr);
  EXPECT_EQ(ref, &registry().back());
  EXPECT_TRUE(ref->isReference);
  ParamSet p(ref->params);
  EXPECT_EQ(p.integer("samples"), 1024);
  EXPECT_TRUE(p.set("samples=0"));
  EXPECT_TRUE(p.set("samples=65537"));
  EXPECT_FALSE(p.set("samples=65536"));
  for (const TechniqueInfo& t : registry())
    if (&t != ref) {
      EXPECT_FALSE(t.isReference) << t.name;
    }
}

// ---- Accuracy -----------------------------------------------------------------------------------

// Stratified sampling: only the grid column (row, for an edge along x) holding the edge is random,
// with standard deviation sqrt(p (1 - p) / rows) / columns <= 0.5 / (columns * sqrt(rows)) =: sigma
// (0.0028 for a 32 x 32 grid); over receivers spread evenly along the ramp, p is uniform and the
// RMSE is sqrt(1/6) / (columns * sqrt(rows)) = 0.82 sigma.
TEST(GroundTruthPenumbra, MatchesTheAnalyticRamp) {
  struct Case {
    bool alongX;
    float width, height;
  };
  for (const Case c : {Case{true, 1.0f, 1.0f}, Case{true, 2.0f, 0.5f}, Case{false, 2.0f, 0.5f}}) {
    const RectLight light = downLight(c.width, c.height);
    const double extent = c.alongX ? c.width : c.height;
    const float halfRamp = static_cast<float>(0.5 * extent) * kHo / (kH - kHo);
    const Mesh mesh = penumbraMesh(c.alongX);
    const Row row = penumbraRow(c.alongX, 256, 1.25f * halfRamp, 4);
    GroundTruthStats stats;
    const raster::ImageFloat v = trace(mesh, row.image, light, 1024, &stats);
    const ErrorStats e = errorAgainstRamp(v, row, extent);
    std::printf("penumbra along %s, light %gx%g, grid %dx%d: RMSE %.5f, max |error| %.5f\n",
                c.alongX ? "x" : "z", static_cast<double>(c.width), static_cast<double>(c.height),
                stats.grid.base(), stats.grid.rows, e.rmse, e.maxAbs);
    const int across = c.alongX ? stats.grid.base() : stats.grid.rows;
    const int along = c.alongX ? stats.grid.rows : stats.grid.base();
    const double sigma = 0.5 / (across * std::sqrt(static_cast<double>(along)));
    // 80% of the receivers are on the ramp; ~800 draws stay within 4.5 sigma.
    EXPECT_LT(e.rmse, 1.2 * 0.82 * sigma) << "along " << (c.alongX ? "x" : "z");
    EXPECT_LT(e.maxAbs, 4.5 * sigma) << "along " << (c.alongX ? "x" : "z");
    EXPECT_EQ(stats.rays, uint64_t{1024} * 256 * 4);
    // Outside the ramp nothing is random: exactly 0 and 1.
    for (int j = 0; j < v.height(); ++j)
      for (int i = 0; i < v.width(); ++i) {
        const double a = analyticV(row.u[static_cast<size_t>(i)], extent);
        if (std::fabs(row.u[static_cast<size_t>(i)]) > 1.01 * static_cast<double>(halfRamp)) {
          EXPECT_EQ(v.at(i, j), static_cast<float>(a));
        }
      }
  }
}

TEST(GroundTruthPenumbra, ConvergesWithSamples) {
  const RectLight light = downLight(1.0f, 1.0f);
  const Mesh mesh = penumbraMesh(true);
  const float halfRamp = 0.5f * kHo / (kH - kHo);
  const Row row = penumbraRow(true, 512, halfRamp, 2);  // the ramp only
  std::vector<double> rmse;
  for (int samples : {16, 64, 256, 1024, 4096}) {
    const ErrorStats e = errorAgainstRamp(trace(mesh, row.image, light, samples), row, 1.0);
    rmse.push_back(e.rmse);
    std::printf("samples %5d: RMSE %.6f, max |error| %.6f, RMSE * N^(3/4) %.3f\n", samples, e.rmse, e.maxAbs,
                e.rmse * std::pow(samples, 0.75));
  }
  EXPECT_LT(rmse[2], rmse[0]);
  EXPECT_LT(rmse[4], rmse[2]);
  for (size_t i = 1; i < rmse.size(); ++i) EXPECT_LT(rmse[i], rmse[i - 1]) << "step " << i;
  // Stratification: error ~ N^(-3/4), so 256x the samples cut it by ~64x (>= 20x with margin).
  EXPECT_LT(rmse[4] * 20.0, rmse[0]);
}

TEST(GroundTruthMotion, MatchesTheTimeAveragedRampAndAReceiverAtOneTime) {
  // The occluder half-plane u < s(t) moving along x from s = -a to +a over the shutter: a frozen
  // edge at s shifts the ramp by s * H / (H - ho) (the similar triangles about the edge), so a static
  // receiver sees the ramp averaged over the shutter (midpoint rule, 4096 steps here); a receiver
  // placed at time t sees the ramp of s(t).
  const RectLight light = downLight(1.0f, 1.0f);
  const Mesh mesh = penumbraMesh(true);
  const float a = 0.3f;
  const double ad = static_cast<double>(a);
  std::vector<glm::vec3> open = mesh.positions, close = mesh.positions;
  for (size_t k = 0; k < 4; ++k) open[k].x -= a, close[k].x += a;  // the occluder's quad
  const double gain = kH / (kH - kHo);
  const auto shifted = [&](double u, double sh) { return analyticV(u - sh * gain, 1.0); };
  const auto averaged = [&](double u) {
    double sum = 0;
    for (int k = 0; k < 4096; ++k) sum += shifted(u, -ad + 2.0 * ad * (k + 0.5) / 4096.0);
    return sum / 4096.0;
  };
  Row row = penumbraRow(true, 256, 1.0f, 2);
  for (int i = 0; i < 256; ++i) row.image.at(i, 1).time = 0.75f;  // the second row at t = 0.75
  raster::ImageFloat v;
  GroundTruthStats stats;
  ASSERT_NO_THROW(stats = computeGroundTruth(
                      mesh.geometry(), row.image, light,
                      {.samples = 1024, .cache = nullptr, .castersOpen = open, .castersClose = close}, v));
  EXPECT_TRUE(stats.moving);
  double sumWhole = 0, sumAt = 0, sumFrozen = 0;
  for (int i = 0; i < 256; ++i) {
    const double u = row.u[static_cast<size_t>(i)];
    sumWhole += std::pow(static_cast<double>(v.at(i, 0)) - averaged(u), 2);
    sumFrozen += std::pow(shifted(u, 0.0) - averaged(u), 2);
    sumAt += std::pow(static_cast<double>(v.at(i, 1)) - shifted(u, 0.5 * ad), 2);
  }
  const double whole = std::sqrt(sumWhole / 256), at = std::sqrt(sumAt / 256),
               frozen = std::sqrt(sumFrozen / 256);
  std::printf(
      "moving edge: RMSE over the shutter %.5f (the mid-shutter ramp is %.4f off), at t = 0.75 %.5f\n", whole,
      frozen, at);
  // Static: 0.41 N^(-3/4) on the ramp = 0.0024 at 1024; time adds its own noise. Measured 0.002.
  EXPECT_LT(whole, 0.006);
  EXPECT_LT(at, 0.006);
  EXPECT_GT(frozen, 10.0 * whole);
  // Without the motion the same receivers see the static edge: the key differs.
  EXPECT_NE(groundTruthKey(mesh.geometry(), row.image, light, 1024),
            groundTruthKey(mesh.geometry(), row.image, light, 1024, open, close));
}

// ---- Exact cases --------------------------------------------------------------------------------

TEST(GroundTruthExact, UmbraLitBackgroundBehindAndOwnSurface) {
  const RectLight light = downLight(1.0f, 1.0f);
  Mesh mesh = penumbraMesh(true);
  mesh.box({2.8f, -0.5f, -0.5f}, {3.2f, 0.5f, 0.5f});  // a closed box around a receiver
  mesh.horizontal(kH, -10.0f, 10.0f, -10.0f, 10.0f);   // a quad in the light's own plane
  ReceiverImage rec(8, 1);
  auto set = [&](int i, glm::vec3 p, glm::vec3 n) {
    rec.at(i, 0) = {.position = p, .normal = n, .valid = 1};
  };
  set(0, {-2.0f, 0.0f, 0.0f}, {0, 1, 0});  // deep in the umbra
  set(1, {2.0f, 0.0f, 0.0f}, {0, 1, 0});   // fully lit
  rec.at(2, 0) = {};                       // background
  set(3, {0.0f, 6.0f, 0.0f}, {0, -1, 0});  // behind the light
  set(4, {0.3f, kH, 0.0f}, {0, -1, 0});    // on the light plane
  set(5, {2.0f, 0.0f, 0.5f}, {0, -1, 0});  // unoccluded, but the whole light below its tangent plane
  set(6, {3.0f, 0.0f, 0.0f}, {0, 1, 0});   // inside the box
  set(7, {0.0f, 3.0f, 0.2f}, {1, 0, 0});   // unoccluded, half the light below its tangent plane
  const raster::ImageFloat v = trace(mesh, rec, light, 256);
  EXPECT_EQ(v.at(0, 0), 0.0f);
  EXPECT_EQ(v.at(1, 0), 1.0f);
  EXPECT_EQ(v.at(2, 0), 1.0f);
  EXPECT_EQ(v.at(3, 0), 0.0f);
  EXPECT_EQ(v.at(4, 0), 0.0f);
  EXPECT_EQ(v.at(5, 0), 0.0f);
  EXPECT_EQ(v.at(6, 0), 0.0f);
  EXPECT_EQ(v.at(7, 0), 0.5f);  // 8 of every row's 16 cells lie at x > 0
}

TEST(GroundTruthExact, NoCastersEverythingInFrontIsLit) {
  const Mesh empty;
  const Row row = penumbraRow(true, 16, 1.0f, 2);
  GroundTruthStats stats;
  const raster::ImageFloat v = trace(empty, row.image, downLight(1, 1), 64, &stats);
  for (float x : v.packed()) EXPECT_EQ(x, 1.0f);
  EXPECT_EQ(stats.triangles, 0u);
  EXPECT_EQ(stats.rays, uint64_t{64} * 32);
}

TEST(GroundTruthExact, NonFiniteAndDegenerateTrianglesBlockNothing) {
  const RectLight light = downLight(1.0f, 1.0f);
  const Mesh clean = penumbraMesh(true);
  Mesh bad = clean;
  const auto base = static_cast<uint32_t>(bad.positions.size());
  // Over the lit side, between the receivers and the light: a NaN, an infinite and a zero-area triangle.
  bad.positions.insert(bad.positions.end(), {{0.1f, 3, -1},
                                             {NAN, 3, 1},
                                             {3, 3, 0},
                                             {0.1f, 3.1f, -1},
                                             {INFINITY, 3.1f, 1},
                                             {0.2f, 3.2f, 0},
                                             {2, 3.2f, 0},
                                             {1, 3.2f, 0}});
  bad.indices.insert(bad.indices.end(),
                     {base, base + 1, base + 2, base + 3, base + 4, base + 2, base + 5, base + 6, base + 7});
  const Row row = penumbraRow(true, 64, 1.0f, 2);
  GroundTruthStats stats;
  const raster::ImageFloat a = trace(clean, row.image, light, 64),
                           b = trace(bad, row.image, light, 64, &stats);
  EXPECT_TRUE(sameBytes(a, b));
  EXPECT_EQ(stats.dropped, 2u);
  EXPECT_EQ(stats.triangles, 5u);
  EXPECT_NE(stats.summary().find("2 non-finite triangles left out"), std::string::npos) << stats.summary();
}

TEST(GroundTruthErrors, IndexOutOfRangeThrows) {
  const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  const std::vector<uint32_t> idx = {0, 1, 3};
  ReceiverImage rec(1, 1);
  raster::ImageFloat out;
  EXPECT_THROW(computeGroundTruth({p, idx}, rec, downLight(1, 1), {}, out), std::invalid_argument);
  EXPECT_THROW(
      computeGroundTruth({p, {idx.data(), 0}}, rec, downLight(1, 1), {.samples = 0, .cache = nullptr}, out),
      std::invalid_argument);
}

// ---- Determinism --------------------------------------------------------------------------------

// A 48 x 32 view of the ground and the occluder's edge, with background and receivers behind the light.
ReceiverImage mixedImage() {
  ReceiverImage rec(48, 32);
  for (int y = 0; y < rec.height(); ++y)
    for (int x = 0; x < rec.width(); ++x) {
      Receiver& r = rec.at(x, y);
      if ((x * 7 + y * 3) % 11 == 0) continue;  // background
      r.position = {-1.2f + 0.05f * static_cast<float>(x), 0.0f, -0.8f + 0.05f * static_cast<float>(y)};
      r.normal = {0, 1, 0};
      r.valid = 1;
      if (y == 5) r.position.y = 6.0f;  // behind the light
    }
  return rec;
}

TEST(GroundTruthDeterminism, SameBytesAtOneAndThreeThreads) {
  const Mesh mesh = penumbraMesh(true);
  const ReceiverImage rec = mixedImage();
  ShadowInputs in{
      .casters = mesh.geometry(), .receivers = &rec, .light = downLight(1.0f, 0.7f), .cache = nullptr};
  const TechniqueInfo* ref = findTechnique("reference");
  ASSERT_NE(ref, nullptr);
  ParamSet params(ref->params);
  ASSERT_FALSE(params.set("samples=256"));
  raster::Rasterizer one(raster::RasterConfig{.threads = 1});
  raster::Rasterizer three(raster::RasterConfig{.threads = 3});
  const ShadowResult a = computeShadows(one, in, *ref, params);
  const ShadowResult b = computeShadows(three, in, *ref, params);
  ASSERT_FALSE(a.skipped) << a.skipReason;
  EXPECT_TRUE(sameBytes(a.visibility, b.visibility));
  // Some of everything: shadowed, penumbra, lit.
  size_t zeros = 0, ones = 0, between = 0;
  for (float v : a.visibility.packed()) (v == 0.0f ? zeros : v == 1.0f ? ones : between)++;
  EXPECT_GT(zeros, 100u);
  EXPECT_GT(ones, 100u);
  EXPECT_GT(between, 100u);
  // Culling only drops triangles that cannot shadow: the same image as from every caster.
  raster::ImageFloat direct;
  one.run(
      [&] { computeGroundTruth(mesh.geometry(), rec, in.light, {.samples = 256, .cache = nullptr}, direct); });
  EXPECT_TRUE(sameBytes(a.visibility, direct));
  ASSERT_FALSE(a.notes.empty());
  // A 1 x 0.7 light: exactly 256 samples in 13 rows of 19 or 20 cells (about 0.051 x 0.054).
  EXPECT_NE(a.notes.back().find("256 samples per receiver (13 rows of 19 or 20)"), std::string::npos)
      << a.notes.back();
  EXPECT_NE(a.notes.back().find("no cache"), std::string::npos) << a.notes.back();
}

TEST(GroundTruthDeterminism, PacketsAndSingleRaysAgree) {
  const Mesh mesh = penumbraMesh(false);
  const ReceiverImage rec = mixedImage();
  const RectLight light = downLight(0.8f, 1.3f);
  const RayScene scene(mesh.geometry());
  raster::ImageFloat packets, single;
  const uint64_t n1 = traceVisibility(scene, rec, light, sampleGrid(light, 100), packets);
  const uint64_t n2 = traceVisibility(scene, rec, light, sampleGrid(light, 100), single, true);
  EXPECT_EQ(n1, n2);
  EXPECT_TRUE(sameBytes(packets, single)) << "packet width " << scene.packetWidth();
}

// ---- Cache --------------------------------------------------------------------------------------

// Entries in memory; `refuse` makes every store fail.
class MemoryCache final : public ResultCache {
 public:
  std::optional<raster::ImageFloat> load(uint64_t key, int width, int height) override {
    ++loads;
    const auto it = entries.find(key);
    if (it == entries.end() || it->second.width() != width || it->second.height() != height) return std::nullopt;
    return it->second;
  }
  std::optional<std::string> store(uint64_t key, const raster::ImageFloat& image) override {
    if (refuse) return "refused";
    entries[key] = image;
    return std::nullopt;
  }
  std::string name(uint64_t key) const override { return "mem-" + std::to_string(key); }
  std::map<uint64_t, raster::ImageFloat> entries;
  int loads = 0;
  bool refuse = false;
};

TEST(GroundTruthCache, HitMissAndUnwritable) {
  const Mesh mesh = penumbraMesh(true);
  const Row row = penumbraRow(true, 32, 0.3f, 3);
  const RectLight light = downLight(1, 1);
  MemoryCache cache;
  GroundTruthStats s1, s2;
  const raster::ImageFloat first = trace(mesh, row.image, light, 64, &s1, &cache);
  EXPECT_FALSE(s1.cacheHit);
  EXPECT_TRUE(s1.cacheWritten) << s1.cacheError;
  EXPECT_EQ(s1.cacheEntry, cache.name(s1.key));
  ASSERT_EQ(cache.entries.size(), 1u);
  EXPECT_TRUE(sameBytes(cache.entries.at(s1.key), first));
  const raster::ImageFloat second = trace(mesh, row.image, light, 64, &s2, &cache);
  EXPECT_TRUE(s2.cacheHit);
  EXPECT_EQ(s2.rays, 0u);
  EXPECT_EQ(s2.triangles, 0u);  // no scene built
  EXPECT_TRUE(sameBytes(first, second));
  EXPECT_NE(s2.summary().find("cache hit mem-"), std::string::npos) << s2.summary();
  // Another sample count: another key, another entry.
  GroundTruthStats s3;
  trace(mesh, row.image, light, 16, &s3, &cache);
  EXPECT_NE(s3.key, s1.key);
  EXPECT_FALSE(s3.cacheHit);
  EXPECT_EQ(cache.entries.size(), 2u);
  // A cache that cannot store: computed anyway, and said so.
  MemoryCache refusing;
  refusing.refuse = true;
  GroundTruthStats s4;
  EXPECT_TRUE(sameBytes(first, trace(mesh, row.image, light, 64, &s4, &refusing)));
  EXPECT_FALSE(s4.cacheWritten);
  EXPECT_EQ(s4.cacheError, "refused");
  EXPECT_NE(s4.summary().find("not written: refused"), std::string::npos) << s4.summary();
}

TEST(GroundTruthCache, ThroughTheTechniqueNotes) {
  const Mesh mesh = penumbraMesh(true);
  const ReceiverImage rec = mixedImage();
  MemoryCache cache;
  ShadowInputs in{.casters = mesh.geometry(), .receivers = &rec, .light = downLight(1, 1), .cache = &cache};
  const TechniqueInfo* ref = findTechnique("reference");
  ASSERT_NE(ref, nullptr);
  ParamSet params(ref->params);
  ASSERT_FALSE(params.set("samples=64"));
  raster::Rasterizer raster(raster::RasterConfig{.threads = 2});
  const ShadowResult a = computeShadows(raster, in, *ref, params);
  const ShadowResult b = computeShadows(raster, in, *ref, params);
  ASSERT_FALSE(a.notes.empty());
  ASSERT_FALSE(b.notes.empty());
  EXPECT_NE(a.notes.back().find("cache miss, wrote mem-"), std::string::npos) << a.notes.back();
  EXPECT_NE(b.notes.back().find("cache hit mem-"), std::string::npos) << b.notes.back();
  EXPECT_TRUE(sameBytes(a.visibility, b.visibility));
}

TEST(GroundTruthKey, ChangesWithEveryInputItDependsOn) {
  const Mesh mesh = penumbraMesh(true);
  const Row row = penumbraRow(true, 8, 0.3f, 2);
  const RectLight light = downLight(1, 1);
  const uint64_t k = groundTruthKey(mesh.geometry(), row.image, light, 64);
  EXPECT_EQ(k, groundTruthKey(mesh.geometry(), row.image, light, 64));
  EXPECT_NE(k, groundTruthKey(mesh.geometry(), row.image, light, 65));

  RectLight l2 = light;
  l2.width = 1.01f;
  EXPECT_NE(k, groundTruthKey(mesh.geometry(), row.image, l2, 64));
  l2 = light;
  l2.center.y += 0.01f;
  EXPECT_NE(k, groundTruthKey(mesh.geometry(), row.image, l2, 64));
  l2 = light;
  l2.intensity = 7.0f;  // V does not depend on it
  l2.color = {1, 0, 0};
  EXPECT_EQ(k, groundTruthKey(mesh.geometry(), row.image, l2, 64));

  Mesh m2 = mesh;
  m2.positions[1].x += 1e-3f;
  EXPECT_NE(k, groundTruthKey(m2.geometry(), row.image, light, 64));
  m2 = mesh;
  std::swap(m2.indices[0], m2.indices[1]);
  EXPECT_NE(k, groundTruthKey(m2.geometry(), row.image, light, 64));
  m2 = mesh;
  m2.positions.push_back({9, 9, 9});  // unreferenced: no effect
  EXPECT_EQ(k, groundTruthKey(m2.geometry(), row.image, light, 64));

  Row r2 = row;
  r2.image.at(3, 1).normal = {0, 0, 1};
  EXPECT_NE(k, groundTruthKey(mesh.geometry(), r2.image, light, 64));
  r2 = row;
  r2.image.at(3, 1).valid = 0;
  EXPECT_NE(k, groundTruthKey(mesh.geometry(), r2.image, light, 64));
  Row r3 = r2;
  r3.image.at(3, 1).position = {5, 5, 5};  // background texel: its position does not matter
  EXPECT_EQ(groundTruthKey(mesh.geometry(), r2.image, light, 64),
            groundTruthKey(mesh.geometry(), r3.image, light, 64));
}

}  // namespace
}  // namespace penumbra::shadows
