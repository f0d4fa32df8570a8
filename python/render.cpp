#include "render.h"

#include <algorithm>
#include <cmath>

#include "engine/aov.h"
#include "engine/image_io.h"
#include "engine/memory.h"
#include "engine/renderer.h"
#include "raster/pipeline.h"
#include "raster/reference.h"

namespace penumbra::python {

void PyScene::beginChange(const char* what) {
  if (rendering.load() != 0)
    raise(std::string(what) + ": the scene is being rendered (change it after render returns)");
  validated = false;
  if (scene.defaultLighting) {  // re-derived from the new contents at the next render
    scene.areaLights.clear();
    scene.sky = userSky;
    scene.defaultLighting = false;
  }
}

namespace {

// Holds PyScene::rendering up while a render runs without the GIL.
class RenderingScope {
 public:
  explicit RenderingScope(PyScene& s) : s_(s) { ++s_.rendering; }
  ~RenderingScope() { --s_.rendering; }
  RenderingScope(const RenderingScope&) = delete;
  RenderingScope& operator=(const RenderingScope&) = delete;

 private:
  PyScene& s_;
};

// Validated, and lit by default or not as asked (with the GIL, before any render of it runs).
void prepareScene(PyScene& s, bool defaultLight) {
  if (!s.validated) {
    if (s.rendering.load() != 0) raise("render: the scene changed while another render of it runs");
    if (engine::Status st =
            engine::validateScene(s.scene, s.scene.name.empty() ? "scene" : "scene '" + s.scene.name + "'");
        !st)
      raise(st.error());
    s.validated = true;
  }
  if (defaultLight == s.scene.defaultLighting) return;
  if (defaultLight) {  // nothing to add to a scene with lights of its own or without geometry
    const engine::Scene& sc = s.scene;
    glm::vec3 lo, hi;
    if (!sc.areaLights.empty() || !sc.directionalLights.empty() || !sc.pointLights.empty() ||
        !sc.spotLights.empty() || !sc.objectBounds(lo, hi))
      return;
  }
  if (s.rendering.load() != 0)
    raise("render: default_light differs from a render of this scene still running");
  if (defaultLight) {
    s.userSky = s.scene.sky;
    engine::addDefaultLighting(s.scene);
  } else {
    s.scene.areaLights.clear();
    s.scene.sky = s.userSky;
    s.scene.defaultLighting = false;
  }
}

engine::RenderOptions renderOptions(const PyScene& s, const RenderArgs& a) {
  if (s.cameraAspect) {
    const float aspect = static_cast<float>(a.width) / static_cast<float>(a.height);
    if (std::abs(aspect - *s.cameraAspect) > 1e-3f * *s.cameraAspect)
      raise("render: the camera's projection has aspect " + std::to_string(*s.cameraAspect) + ", the image " +
            std::to_string(a.width) + "x" + std::to_string(a.height) + " has " + std::to_string(aspect));
  }
  engine::RenderOptions o;
  o.width = a.width;
  o.height = a.height;
  o.shadow = a.shadow;
  o.shadowParams = a.params;
  o.spp = a.spp;
  o.msaa = a.msaa;
  o.exposure = a.exposure;
  o.frame = a.frame;
  if (!engine::parseToneMap(a.tonemap, o.toneMap))
    raise("option tonemap: expected 'none' or 'aces', got '" + a.tonemap + "'");
  return o;
}

std::vector<engine::Aov> parseAovs(const std::vector<std::string>& names) {
  if (names.empty()) return {};
  std::string list;
  for (std::string n : names) {
    std::replace(n.begin(), n.end(), '_', '-');
    list += (list.empty() ? "" : ",") + n;
  }
  engine::Result<std::vector<engine::Aov>> r = engine::parseAovList(list, "option aov");
  if (!r) raise(r.error());
  return *r;
}

std::string pyName(engine::Aov a) {
  std::string n = engine::aovName(a);
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
}

// One AOV as arrays: float H x W (x 3), NaN on background; instance and triangle int32, -1 there.
void addAov(py::dict& out, const engine::Frame& f, engine::Aov a) {
  const py::ssize_t w = f.gbuffer.width(), h = f.gbuffer.height();
  if (a == engine::Aov::Instance || a == engine::Aov::Triangle) {
    py::array_t<int32_t> ids({h, w});
    int32_t* d = ids.mutable_data();
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const engine::GBufferTexel& t = f.gbuffer.at(x, y);
        *d++ = t.material < 0 ? -1 : (a == engine::Aov::Instance ? t.instance : t.triangle);
      }
    out[py::str(pyName(a))] = ids;
    return;
  }
  const size_t lights = a == engine::Aov::Visibility ? std::max<size_t>(f.visibility.size(), 1) : 1;
  for (size_t l = 0; l < lights; ++l) {
    int channels = 0;
    const std::vector<float> v = engine::aovSamples(f, a, l, channels);
    std::vector<py::ssize_t> shape{h, w};
    if (channels > 1) shape.push_back(channels);
    std::string key = pyName(a);
    if (l > 0) key += '_' + std::to_string(l);
    out[py::str(key)] = toArray(v, shape);
  }
}

}  // namespace

std::vector<std::string> aovNames() {
  const engine::Result<std::vector<engine::Aov>> all = engine::parseAovList(
      "visibility,depth,position,normal,geometric-normal,albedo,instance,triangle,barycentrics");
  std::vector<std::string> n;
  for (engine::Aov a : *all) n.push_back(pyName(a));
  return n;
}

py::dict render(PyScene& s, const RenderArgs& a) {
  prepareScene(s, a.defaultLight);
  const engine::RenderOptions options = renderOptions(s, a);
  engine::Result<engine::ResolvedOptions> resolved = engine::resolveOptions(options);
  if (!resolved) raise(resolved.error());
  if (a.threads < 0 || a.threads > 1024)
    raise("option threads: must be in [0, 1024], got " + std::to_string(a.threads));
  const std::vector<engine::Aov> aovs = parseAovs(a.aov);
  // The frame's peak and the arrays handed back (color 4 + linear 16 bytes, 12 per AOV per pixel).
  engine::MemoryEstimate memory = engine::estimateFrameMemory(s.scene, *resolved);
  const uint64_t pixels = static_cast<uint64_t>(a.width) * static_cast<uint64_t>(a.height);
  const uint64_t lights = std::max<uint64_t>(s.scene.areaLights.size(), 1);
  memory.parts.emplace_back("output arrays", pixels * (20 + 12 * aovs.size() + 4 * (lights - 1)));
  memory.bytes += memory.parts.back().second;
  const uint64_t limit = a.maxMemory ? a.maxMemory : engine::availableMemoryBytes();
  if (engine::Status st =
          engine::checkMemory(memory, limit, "render", a.maxMemory ? "max_memory" : "the memory available");
      !st)
    raise(st.error());

  engine::Frame frame;
  {
    RenderingScope busy(s);
    py::gil_scoped_release nogil;
    engine::Renderer renderer(a.threads);
    frame = renderer.render(s.scene, *resolved);
  }
  py::dict out;
  const py::ssize_t w = a.width, h = a.height;
  py::array_t<uint8_t> color({h, w, py::ssize_t{4}});
  py::array_t<float> linear({h, w, py::ssize_t{4}});
  uint8_t* c = color.mutable_data();
  float* l = linear.mutable_data();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const raster::Rgba8 p = frame.color.at(x, y);
      *c++ = p.r, *c++ = p.g, *c++ = p.b, *c++ = p.a;
      const raster::Float4 q = frame.linear.at(x, y);
      *l++ = q.r, *l++ = q.g, *l++ = q.b, *l++ = q.a;
    }
  out["color"] = color;
  out["linear"] = linear;
  for (engine::Aov aov : aovs) addAov(out, frame, aov);
  if (a.stats) out["stats"] = py::str(frame.stats.report());
  return out;
}

py::dict rasterize(py::handle verticesClip, py::handle triangles, int width, int height,
                   const std::string& cull, int threads) {
  const std::vector<glm::vec4> clip = vec4Rows(verticesClip, "vertices_clip");
  const std::vector<uint32_t> indices = triangleRows(triangles, clip.size(), "triangles");
  if (engine::Status st = engine::kWidthOption.check(width); !st) raise("option width: " + st.error().what);
  if (engine::Status st = engine::kHeightOption.check(height); !st)
    raise("option height: " + st.error().what);
  if (threads < 0 || threads > 1024)
    raise("option threads: must be in [0, 1024], got " + std::to_string(threads));
  raster::DrawDesc desc;
  if (cull == "none")
    desc.cull = raster::CullMode::None;
  else if (cull == "back")
    desc.cull = raster::CullMode::Back;
  else if (cull == "front")
    desc.cull = raster::CullMode::Front;
  else
    raise("option cull: expected 'none', 'back' or 'front', got '" + cull + "'");
  desc.vertexCount = static_cast<uint32_t>(clip.size());
  desc.indices = indices;
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  // Depth target, the four outputs and their arrays, the vertex stage and one batch of triangles.
  engine::MemoryEstimate memory;
  memory.parts = {{"targets and outputs", pixels * (5 + 2 * 21)},
                  {"pipeline", clip.size() * 36 + std::min<uint64_t>(indices.size() / 3, 1u << 20) * 128}};
  memory.bytes = memory.parts[0].second + memory.parts[1].second;
  if (engine::Status st = engine::checkMemory(memory, engine::availableMemoryBytes(), "rasterize",
                                              "the memory available");
      !st)
    raise(st.error());
  std::vector<int32_t> tri(pixels, -1);
  std::vector<float> depth(pixels, NAN), bary(pixels * 3, NAN);
  std::vector<uint8_t> front(pixels, 0);
  raster::PassStats stats;
  if (!indices.empty()) {
    py::gil_scoped_release nogil;
    raster::Rasterizer r({.threads = threads});
    raster::DepthTarget target(width, height, 1.0f);
    // In submission order per tile after the depth test: the last write to a pixel is its nearest
    // triangle (the first of equal depths).
    stats = r.draw(
        desc, target, [&](uint32_t i, float*) { return clip[i]; },
        [&](const raster::Fragment& f) {
          const size_t p = static_cast<size_t>(f.y) * static_cast<size_t>(width) + static_cast<size_t>(f.x);
          tri[p] = static_cast<int32_t>(f.primitive);
          depth[p] = f.depth;
          bary[3 * p] = f.b0, bary[3 * p + 1] = f.b1, bary[3 * p + 2] = f.b2;
          front[p] = f.frontFacing ? 1 : 0;
        });
  }
  py::dict out;
  out["triangle"] = toArray(tri, {height, width});
  out["depth"] = toArray(depth, {height, width});
  out["barycentrics"] = toArray(bary, {height, width, 3});
  out["front_facing"] = toArray(front, {height, width}).attr("astype")("bool");
  py::dict st;
  st["triangles"] = stats.trianglesIn;
  st["culled_frustum"] = stats.trianglesCulledFrustum;
  st["culled_facing"] = stats.trianglesCulledFacing;
  st["culled_degenerate"] = stats.trianglesCulledDegenerate;
  st["culled_no_sample"] = stats.trianglesCulledNoSample;
  st["clipped"] = stats.trianglesClipped;
  out["stats"] = st;
  return out;
}

py::array_t<uint32_t> referenceCoverage(py::handle triangle, int width, int height) {
  const std::vector<glm::vec4> v = vec4Rows(triangle, "triangle");
  if (v.size() != 3) raise("triangle: expected 3 vertices, got " + std::to_string(v.size()));
  for (const glm::vec4& c : v)
    if (!(c.w > 0.0f) || std::abs(c.x / c.w) > 2.0f || std::abs(c.y / c.w) > 2.0f)
      raise("triangle: the reference needs w > 0 and |x/w|, |y/w| <= 2");
  if (engine::Status st = engine::kWidthOption.check(width); !st) raise("option width: " + st.error().what);
  if (engine::Status st = engine::kHeightOption.check(height); !st)
    raise("option height: " + st.error().what);
  std::vector<uint32_t> count(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  raster::reference::coverage(raster::reference::snap(v.data(), width, height), width, height, count);
  return toArray(count, {height, width});
}

void writeImageArray(const std::string& path, py::handle image) {
  py::array a = py::array::ensure(image);
  if (!a) raise("image: expected an array");
  const bool rgb8 = a.dtype().is(py::dtype::of<uint8_t>());
  if (!(a.ndim() == 3 && (a.shape(2) == 3 || a.shape(2) == 4)) && !(!rgb8 && a.ndim() == 2))
    raise("image: expected shape (H, W, 3) or (H, W, 4)" + std::string(rgb8 ? "" : " or (H, W)"));
  const py::ssize_t h = a.shape(0), w = a.shape(1), ch = a.ndim() == 3 ? a.shape(2) : 1;
  if (h < 1 || w < 1 || h > engine::kMaxImageSide || w > engine::kMaxImageSide)
    raise("image: " + std::to_string(w) + "x" + std::to_string(h) + " is not a size in [1, 32768]");
  const bool exr = path.size() > 4 && path.compare(path.size() - 4, 4, ".exr") == 0;
  engine::Status st = engine::Ok{};
  if (rgb8) {
    if (exr) raise(path + ": uint8 images are written as PNG, not EXR");
    const auto px = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
    raster::ImageRgba8 img(static_cast<int>(w), static_cast<int>(h));
    const uint8_t* d = px.data();
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x, d += ch) img.at(x, y) = {d[0], d[1], d[2], ch == 4 ? d[3] : uint8_t{255}};
    st = engine::writeImage(path, img);
  } else {
    if (a.dtype().kind() != 'f')
      raise("image: expected uint8 (PNG) or float (EXR), got dtype " + std::string(py::str(a.dtype())));
    if (!exr) raise(path + ": float images are written as OpenEXR (.exr)");
    const auto px = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    std::vector<float> samples(px.data(), px.data() + px.size());
    st = engine::writeFloatImage(path, static_cast<int>(w), static_cast<int>(h), static_cast<int>(ch),
                                 samples);
  }
  if (!st) raise(st.error());
}

}  // namespace penumbra::python
