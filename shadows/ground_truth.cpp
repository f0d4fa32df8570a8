#include "shadows/ground_truth.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <vector>

#include "shadows/sampling.h"

namespace penumbra::shadows {

namespace {

// Bumped whenever the image for given inputs could change (sampling, ray offsets, the definition
// of V): it is part of the key, so older cache entries are never read.
constexpr uint32_t kFormatVersion = 2;
constexpr int kMaxSamples = 65536;

// Rays end this far short of the light (in units of the origin-to-light-point segment).
constexpr float kTFar = 1.0f - 1e-4f;
// eps = kEpsScene * D + kEpsUlps * max_i |x_i| (ground_truth.h); kEpsUlps is about 32 float ulps
// (an ulp of v is at most 2^-23 |v| = 1.19e-7 |v|).
constexpr float kEpsScene = 2e-6f;
constexpr float kEpsUlps = 4e-6f;

// ---- Embree errors ------------------------------------------------------------------------------

const char* errorName(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "unrecognised error";
}

// Throws when Embree reports an error on `device` (nullptr: device creation) after `what`.
void checkEmbree(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("embree: ") + what + " failed: " + errorName(e));
}

// ---- Hashing ------------------------------------------------------------------------------------

// splitmix64's finalizer: a bijection on 64-bit words with good avalanche.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Hash of a sequence of 32-bit words, taken two at a time: h = mix64((h ^ word) + golden ratio).
// Each step is a bijection of h for a fixed word, so sequences differing in one word differ.
class Hasher {
 public:
  void u32(uint32_t v) {
    if (!pending_) {
      lo_ = v;
      pending_ = true;
    } else {
      word(uint64_t{lo_} | (uint64_t{v} << 32));
      pending_ = false;
    }
  }
  void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
  void vec3(glm::vec3 v) {
    f32(v.x);
    f32(v.y);
    f32(v.z);
  }
  uint64_t finish() {
    if (pending_) u32(0);
    word(count_);
    return h_;
  }

 private:
  void word(uint64_t w) {
    h_ = mix64((h_ ^ w) + 0x9e3779b97f4a7c15ULL);
    ++count_;
  }
  uint64_t h_ = 0x50656e756d627261ULL;  // "Penumbra"
  uint64_t count_ = 0;
  uint32_t lo_ = 0;
  bool pending_ = false;
};

// ---- Sampling -----------------------------------------------------------------------------------

// Light uv of sample `sample` of the grid for pixel (px, py): cell i of row j (sampleGrid),
// jittered by hash3(px, py, 2 * sample + dimension).
glm::vec2 samplePoint(uint32_t px, uint32_t py, int sample, SampleGrid g) {
  const int longCells = g.longRows() * (g.base() + 1);
  const int j = sample < longCells ? sample / (g.base() + 1) : g.longRows() + (sample - longCells) / g.base();
  const int n = g.cellsIn(j), start = g.rowStart(j), i = sample - start;
  const uint32_t d = 2u * static_cast<uint32_t>(sample);
  return {(static_cast<float>(i) + unitFloat(hash3(px, py, d))) / static_cast<float>(n),
          (static_cast<float>(start) + static_cast<float>(n) * unitFloat(hash3(px, py, d + 1u))) /
              static_cast<float>(g.samples)};
}

// Shutter time of sample `sample` for a receiver over the whole shutter (ground_truth.h): the
// golden-ratio sequence rotated by hash3(px, py, kTimeDimension), fract(r + sample / phi).
constexpr uint32_t kTimeDimension = 0x7fffffffu;  // above every light dimension (2 * 65536 + 1)
float sampleTime(uint32_t px, uint32_t py, int sample) {
  constexpr double kInvPhi = 0.61803398874989484820;
  const double r = static_cast<double>(unitFloat(hash3(px, py, kTimeDimension)));
  const double t = r + static_cast<double>(sample) * kInvPhi;
  return std::min(static_cast<float>(t - std::floor(t)), std::nextafter(1.0f, 0.0f));
}

// The time of every ray of one receiver: its own (a point of a moving surface), or one per sample
// over the whole shutter; 0 when nothing moves (Embree ignores it then).
struct RayTimes {
  bool perSample = false;
  float fixed = 0.0f;
  uint32_t px = 0, py = 0;
  float at(int sample) const { return perSample ? sampleTime(px, py, sample) : fixed; }
};

// One receiver's rays (ground_truth.h): from x + eps n.
struct ReceiverRays {
  glm::vec3 x, n, org;

  ReceiverRays(const Receiver& r, float sceneEps) : x(r.position), n(r.normal) {
    const float big = std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z)});
    org = x + (sceneEps + kEpsUlps * big) * n;
  }
  // Whether light point y is above the tangent plane, and if so the ray towards it: direction
  // (origin -> y is t in [0, 1]).
  bool make(glm::vec3 y, glm::vec3& dir) const {
    if (!(glm::dot(n, y - x) > 0.0f)) return false;
    dir = y - org;
    return true;
  }
};

// Embree's packet types and calls by width.
template <int N>
struct PacketCall;
template <>
struct PacketCall<4> {
  using Ray = RTCRay4;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded4(valid, s, c, r);
  }
};
template <>
struct PacketCall<8> {
  using Ray = RTCRay8;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded8(valid, s, c, r);
  }
};
template <>
struct PacketCall<16> {
  using Ray = RTCRay16;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded16(valid, s, c, r);
  }
};

// Unoccluded rays of one receiver, N rays per Embree call (the samples above its tangent plane,
// packed in order).
template <int N>
int litPacket(RTCScene scene, const ReceiverRays& rr, const RectLight& light, uint32_t px, uint32_t py,
              SampleGrid grid, const RayTimes& times) {
  using Call = PacketCall<N>;
  typename Call::Ray ray;
  alignas(64) int valid[N];
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // one origin, directions within the light's cone
  int lit = 0, lanes = 0;
  const auto set = [&](int l, glm::vec3 org, glm::vec3 dir, float time, bool on) {
    valid[l] = on ? -1 : 0;
    ray.org_x[l] = org.x;
    ray.org_y[l] = org.y;
    ray.org_z[l] = org.z;
    ray.dir_x[l] = dir.x;
    ray.dir_y[l] = dir.y;
    ray.dir_z[l] = dir.z;
    ray.tnear[l] = 0.0f;
    ray.tfar[l] = kTFar;
    ray.time[l] = time;
    ray.mask[l] = ~0u;
    ray.id[l] = 0;
    ray.flags[l] = 0;
  };
  const auto flush = [&] {
    for (int l = lanes; l < N; ++l)
      set(l, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f, false);  // masked off
    Call::occluded(valid, scene, &ctx, &ray);
    for (int l = 0; l < lanes; ++l) lit += ray.tfar[l] >= 0.0f ? 1 : 0;  // occluded: tfar = -inf
    lanes = 0;
  };
  for (int s = 0; s < grid.count(); ++s) {
    glm::vec3 dir;
    if (!rr.make(light.point(samplePoint(px, py, s, grid)), dir)) continue;
    set(lanes++, rr.org, dir, times.at(s), true);
    if (lanes == N) flush();
  }
  if (lanes > 0) flush();
  return lit;
}

int litSingle(RTCScene scene, const ReceiverRays& rr, const RectLight& light, uint32_t px, uint32_t py,
              SampleGrid grid, const RayTimes& times) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  int lit = 0;
  for (int s = 0; s < grid.count(); ++s) {
    glm::vec3 dir;
    if (!rr.make(light.point(samplePoint(px, py, s, grid)), dir)) continue;
    RTCRay ray{.org_x = rr.org.x,
               .org_y = rr.org.y,
               .org_z = rr.org.z,
               .tnear = 0.0f,
               .dir_x = dir.x,
               .dir_y = dir.y,
               .dir_z = dir.z,
               .time = times.at(s),
               .tfar = kTFar,
               .mask = ~0u,
               .id = 0,
               .flags = 0};
    rtcOccluded1(scene, &ctx, &ray);
    lit += ray.tfar >= 0.0f ? 1 : 0;
  }
  return lit;
}

// The scene's scale term of the ray offset: kEpsScene times the diagonal of the bounding box of
// the light's corners and the valid receivers in front of it.
float sceneEps(const ReceiverImage& receivers, const RectLight& light) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (float s : {0.0f, 1.0f})
    for (float t : {0.0f, 1.0f}) {
      const glm::vec3 p = light.point({s, t});
      lo = glm::min(lo, p), hi = glm::max(hi, p);
    }
  const glm::vec3 c = light.center, ln = light.normal();
  for (int y = 0; y < receivers.height(); ++y)
    for (int x = 0; x < receivers.width(); ++x) {
      const Receiver& r = receivers.at(x, y);
      if (!r.valid || !(glm::dot(r.position - c, ln) > 0.0f)) continue;
      if (!std::isfinite(r.position.x + r.position.y + r.position.z)) continue;
      lo = glm::min(lo, r.position), hi = glm::max(hi, r.position);
    }
  return kEpsScene * glm::length(hi - lo);
}

}  // namespace

// ---- Grid ---------------------------------------------------------------------------------------

SampleGrid sampleGrid(const RectLight& light, int samples) {
  if (samples < 1 || samples > kMaxSamples)
    throw std::invalid_argument("ground truth: samples must be in [1, 65536], not " +
                                std::to_string(samples));
  const double aspect = static_cast<double>(light.height) / static_cast<double>(light.width);
  const double r = std::round(std::sqrt(static_cast<double>(samples) * aspect));
  SampleGrid g;
  g.samples = samples;
  g.rows = std::isfinite(r) ? static_cast<int>(std::clamp(r, 1.0, static_cast<double>(samples))) : 1;
  return g;
}

// ---- Scene --------------------------------------------------------------------------------------

RayScene::RayScene(const Geometry& casters, std::span<const glm::vec3> open,
                   std::span<const glm::vec3> close) {
  if (open.size() != close.size() || (!open.empty() && open.size() != casters.positions.size()))
    throw std::invalid_argument(
        "ground truth: the casters' open and close positions must match their positions");
  moves_ = !open.empty();
  device_ = rtcNewDevice(nullptr);
  if (!device_) {
    checkEmbree(nullptr, "rtcNewDevice");
    throw std::runtime_error("embree: rtcNewDevice returned no device");
  }
  try {
    const ssize_t native16 = rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED);
    const ssize_t native8 = rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED);
    const ssize_t native4 = rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED);
    packetWidth_ = native16 ? 16 : native8 ? 8 : native4 ? 4 : 1;
    scene_ = rtcNewScene(device_);
    checkEmbree(device_, "rtcNewScene");
    // Robust traversal: box tests never miss a triangle the ray meets, so the answer is the
    // triangle tests' whatever the BVH's shape.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

    // Copy the vertices of the finite triangles (a non-finite one blocks nothing), renumbered in
    // order of first use.
    constexpr uint32_t kUnused = ~0u;
    std::vector<uint32_t> remap(casters.positions.size(), kUnused);
    std::vector<glm::vec3> vertices;
    std::vector<uint32_t> source;  // each copied vertex's index in `casters`
    std::vector<uint32_t> indices;
    indices.reserve(casters.indices.size());
    for (size_t t = 0; t < casters.triangles(); ++t) {
      bool finite = true;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = casters.indices[3 * t + static_cast<size_t>(k)];
        if (v >= casters.positions.size())
          throw std::invalid_argument("ground truth: caster index " + std::to_string(v) + " out of range");
        const auto ok = [](glm::vec3 p) {
          return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        };
        finite = finite && (moves_ ? ok(open[v]) && ok(close[v]) : ok(casters.positions[v]));
      }
      if (!finite) {
        ++dropped_;
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = casters.indices[3 * t + static_cast<size_t>(k)];
        if (remap[v] == kUnused) {
          remap[v] = static_cast<uint32_t>(vertices.size());
          vertices.push_back(casters.positions[v]);
          source.push_back(v);
        }
        indices.push_back(remap[v]);
      }
    }
    triangles_ = indices.size() / 3;
    if (triangles_ > 0) {
      RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      if (const RTCError e = rtcGetDeviceError(device_); e != RTC_ERROR_NONE || !geom) {
        if (geom) rtcReleaseGeometry(geom);
        throw std::runtime_error(std::string("embree: rtcNewGeometry failed: ") + errorName(e));
      }
      // Moving casters: two time steps (open, close), which Embree blends linearly over the
      // ray's time in [0, 1]. Buffers Embree allocates itself are padded so that the last vertex
      // can be read with a 16-byte load.
      const unsigned steps = moves_ ? 2u : 1u;
      if (moves_) rtcSetGeometryTimeStepCount(geom, steps);
      float* vb[2] = {nullptr, nullptr};
      for (unsigned k = 0; k < steps; ++k)
        vb[k] = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
      auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
          geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles_));
      if (!vb[0] || (moves_ && !vb[1]) || !ib) {
        rtcReleaseGeometry(geom);
        checkEmbree(device_, "rtcSetNewGeometryBuffer");
        throw std::runtime_error("embree: rtcSetNewGeometryBuffer returned no buffer");
      }
      for (unsigned k = 0; k < steps; ++k)
        for (size_t i = 0; i < vertices.size(); ++i) {
          const glm::vec3 p = !moves_ ? vertices[i] : k == 0 ? open[source[i]] : close[source[i]];
          vb[k][3 * i + 0] = p.x;
          vb[k][3 * i + 1] = p.y;
          vb[k][3 * i + 2] = p.z;
        }
      std::copy(indices.begin(), indices.end(), ib);
      rtcCommitGeometry(geom);
      rtcAttachGeometry(scene_, geom);
      rtcReleaseGeometry(geom);  // the scene holds it (or, on failure, nothing does: released)
      checkEmbree(device_, "adding the caster triangles");
    }
    rtcCommitScene(scene_);  // builds the BVH with TBB in the caller's arena
    checkEmbree(device_, "rtcCommitScene");
  } catch (...) {
    if (scene_) rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
    throw;
  }
}

RayScene::~RayScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

// ---- Tracing ------------------------------------------------------------------------------------

uint64_t traceVisibility(const RayScene& scene, const ReceiverImage& receivers, const RectLight& light,
                         SampleGrid grid, raster::ImageFloat& out, bool force1) {
  const int w = receivers.width(), h = receivers.height();
  out.resize(w, h);
  const glm::vec3 c = light.center, ln = light.normal();
  const int width = force1 ? 1 : scene.packetWidth();
  const float eps = sceneEps(receivers, light);
  std::vector<uint64_t> rowRays(static_cast<size_t>(h), 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = 0; x < w; ++x) {
        const Receiver& r = receivers.at(x, y);
        float v = 1.0f;
        if (r.valid) {
          v = 0.0f;
          if (glm::dot(r.position - c, ln) > 0.0f) {
            const ReceiverRays rr(r, eps);
            const auto px = static_cast<uint32_t>(x), py = static_cast<uint32_t>(y);
            RayTimes times;
            if (scene.moves()) {
              times = {
                  .perSample = r.wholeShutter(), .fixed = std::clamp(r.time, 0.0f, 1.0f), .px = px, .py = py};
            }
            int lit = 0;
            switch (width) {
              case 16:
                lit = litPacket<16>(scene.handle(), rr, light, px, py, grid, times);
                break;
              case 8:
                lit = litPacket<8>(scene.handle(), rr, light, px, py, grid, times);
                break;
              case 4:
                lit = litPacket<4>(scene.handle(), rr, light, px, py, grid, times);
                break;
              default:
                lit = litSingle(scene.handle(), rr, light, px, py, grid, times);
                break;
            }
            v = static_cast<float>(lit) / static_cast<float>(grid.count());  // exactly 1 when all lit
            rowRays[static_cast<size_t>(y)] += static_cast<uint64_t>(grid.count());
          }
        }
        out.at(x, y) = v;
      }
    }
  });
  uint64_t rays = 0;
  for (uint64_t n : rowRays) rays += n;
  return rays;
}

// ---- Key and cache ------------------------------------------------------------------------------

uint64_t groundTruthKey(const Geometry& casters, const ReceiverImage& receivers, const RectLight& light,
                        int samples, std::span<const glm::vec3> open, std::span<const glm::vec3> close) {
  const bool moves = !open.empty();
  Hasher h;
  h.u32(kFormatVersion);
  h.u32(static_cast<uint32_t>(samples));
  h.vec3(light.center);
  h.vec3(light.right);
  h.vec3(light.up);
  h.f32(light.width);
  h.f32(light.height);
  h.u32(static_cast<uint32_t>(receivers.width()));
  h.u32(static_cast<uint32_t>(receivers.height()));
  for (int y = 0; y < receivers.height(); ++y)
    for (int x = 0; x < receivers.width(); ++x) {
      const Receiver& r = receivers.at(x, y);
      h.u32(r.valid ? 1u : 0u);
      if (!r.valid) continue;
      h.vec3(r.position);
      h.vec3(r.normal);
      if (moves) h.f32(r.time);
    }
  const size_t tris = casters.triangles();
  h.u32(static_cast<uint32_t>(tris));
  h.u32(static_cast<uint32_t>(tris >> 32));
  for (size_t i = 0; i < tris * 3; ++i) {
    const uint32_t v = casters.indices[i];
    h.u32(v);
    h.vec3(v < casters.positions.size() ? casters.positions[v] : glm::vec3(NAN));
  }
  if (moves) {           // static scenes keep their keys (and cache entries)
    h.u32(0x6d6f7665u);  // "move"
    for (size_t i = 0; i < tris * 3; ++i) {
      const uint32_t v = casters.indices[i];
      h.vec3(v < open.size() ? open[v] : glm::vec3(NAN));
      h.vec3(v < close.size() ? close[v] : glm::vec3(NAN));
    }
  }
  return h.finish();
}

// ---- The whole computation ----------------------------------------------------------------------

std::string GroundTruthStats::summary() const {
  char buf[320];
  std::string line;
  if (grid.longRows() == 0)
    std::snprintf(buf, sizeof buf, "reference: %d samples per receiver (%d rows of %d)", grid.count(),
                  grid.rows, grid.base());
  else
    std::snprintf(buf, sizeof buf, "reference: %d samples per receiver (%d rows of %d or %d)", grid.count(),
                  grid.rows, grid.base(), grid.base() + 1);
  line = buf;
  if (cacheHit) {
    line += "; cache hit " + cacheEntry + ", nothing traced";
    return line;
  }
  const double mrays = msTrace > 0 ? static_cast<double>(rays) / (msTrace * 1e3) : 0.0;
  std::snprintf(buf, sizeof buf,
                ", %llu receivers, %llu light samples (rays where above the receiver's plane) against %zu "
                "triangles (packets of %d) in %.1f ms: %.2f Msamples/s",
                static_cast<unsigned long long>(receivers), static_cast<unsigned long long>(rays), triangles,
                packetWidth, msTrace, mrays);
  line += buf;
  if (dropped > 0) line += " (" + std::to_string(dropped) + " non-finite triangles left out)";
  if (moving) line += "; casters moving: rays at shutter times (static receivers: the whole shutter)";
  if (cacheEntry.empty())
    line += "; no cache";
  else if (cacheWritten)
    line += "; cache miss, wrote " + cacheEntry;
  else
    line += "; cache miss, not written: " + cacheError;
  return line;
}

namespace {

// The stages of one computation, shared by computeGroundTruth and the technique.
class Job {
 public:
  // Key and cache lookup; on a miss, the scene. In the caller's arena.
  void prepare(const Geometry& casters, const ReceiverImage& receivers, const RectLight& light, int samples,
               ResultCache* cache, std::span<const glm::vec3> open, std::span<const glm::vec3> close) {
    const auto t0 = Clock::now();
    receivers_ = &receivers;
    light_ = light;
    cache_ = cache;
    stats.grid = sampleGrid(light, samples);
    if (cache) {
      stats.key = groundTruthKey(casters, receivers, light, samples, open, close);
      stats.cacheEntry = cache->name(stats.key);
      if (std::optional<raster::ImageFloat> hit =
              cache->load(stats.key, receivers.width(), receivers.height())) {
        cached_ = std::move(*hit);
        stats.cacheHit = true;
      }
    }
    if (!stats.cacheHit) {
      scene_ = std::make_unique<RayScene>(casters, open, close);
      stats.moving = scene_->moves();
      stats.packetWidth = scene_->packetWidth();
      stats.triangles = scene_->triangles();
      stats.dropped = scene_->dropped();
    }
    stats.msPrepare = msSince(t0);
  }
  // Traces (or hands over the cached image) and writes the cache. In the caller's arena.
  void evaluate(raster::ImageFloat& out) {
    const auto t0 = Clock::now();
    if (stats.cacheHit) {
      out = std::move(cached_);
      stats.msTrace = msSince(t0);
      return;
    }
    stats.rays = traceVisibility(*scene_, *receivers_, light_, stats.grid, out);
    stats.receivers = stats.rays / static_cast<uint64_t>(stats.grid.count());
    stats.msTrace = msSince(t0);
    scene_.reset();
    if (cache_) {
      const std::optional<std::string> err = cache_->store(stats.key, out);
      stats.cacheWritten = !err;
      if (err) stats.cacheError = *err;
    }
  }

  GroundTruthStats stats;

 private:
  const ReceiverImage* receivers_ = nullptr;
  ResultCache* cache_ = nullptr;
  RectLight light_;
  std::unique_ptr<RayScene> scene_;
  raster::ImageFloat cached_;
};

class Reference final : public Technique {
 public:
  void prepare(ShadowContext& ctx, const ParamSet& params) override {
    const auto t0 = Clock::now();
    const int samples = params.integer("samples");
    ctx.raster.run([&] {
      job_.prepare(ctx.casterGeometry(), *ctx.in.receivers, ctx.in.light, samples, ctx.in.cache,
                   ctx.in.castersOpen, ctx.in.castersClose);
    });
    ctx.times.msMaps += msSince(t0);
  }
  void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) override {
    const auto t0 = Clock::now();
    ctx.raster.run([&] { job_.evaluate(visibility); });
    ctx.times.msEvaluate += msSince(t0);
    ctx.notes.push_back(job_.stats.summary());
  }

 private:
  Job job_;
};

}  // namespace

GroundTruthStats computeGroundTruth(const Geometry& casters, const ReceiverImage& receivers,
                                    const RectLight& light, const GroundTruthOptions& options,
                                    raster::ImageFloat& out) {
  Job job;
  job.prepare(casters, receivers, light, options.samples, options.cache, options.castersOpen,
              options.castersClose);
  job.evaluate(out);
  return job.stats;
}

TechniqueInfo referenceTechnique() {
  return {
      .name = "reference",
      .summary = "ray-traced ground truth: Embree occlusion rays to a stratified jittered grid on the light",
      .params = {{.name = "samples",
                  .kind = ParamKind::Int,
                  .defaultValue = 1024,
                  .minValue = 1,
                  .maxValue = kMaxSamples,
                  .choices = {},
                  .help = "light samples per receiver, exactly: cells of equal area in rows of nearly square "
                          "cells (1024 on a square light: 32x32)"}},
      .benchSettings = {""},
      .isReference = true,
      .make = [] { return std::make_unique<Reference>(); },
      // Embree's high-quality BVH and its copy of the vertices: about 160 bytes per triangle.
      .peakBytes = [](const ParamSet&, uint64_t triangles) { return triangles * 160; },
      .samplesTime = true};
}

}  // namespace penumbra::shadows
