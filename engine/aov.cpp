#include "engine/aov.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>

#include "engine/image_io.h"

namespace penumbra::engine {

namespace {

struct AovInfo {
  Aov aov;
  const char* name;
};
constexpr AovInfo kAovs[] = {{Aov::Visibility, "visibility"}, {Aov::Depth, "depth"},
                             {Aov::Position, "position"},     {Aov::Normal, "normal"},
                             {Aov::GeometricNormal, "geometric-normal"}, {Aov::Albedo, "albedo"},
                             {Aov::Instance, "instance"},     {Aov::Triangle, "triangle"},
                             {Aov::Barycentrics, "barycentrics"}};

std::string validNames() {
  std::string s;
  for (const AovInfo& i : kAovs) s += (s.empty() ? "" : ", ") + std::string(i.name);
  return s;
}

}  // namespace

const char* aovName(Aov a) {
  for (const AovInfo& i : kAovs)
    if (i.aov == a) return i.name;
  return "?";
}

Result<std::vector<Aov>> parseAovList(const std::string& list, const std::string& option) {
  std::vector<Aov> out;
  size_t start = 0;
  while (true) {
    const size_t comma = list.find(',', start);
    const std::string name = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const AovInfo* found = nullptr;
    for (const AovInfo& i : kAovs)
      if (name == i.name) found = &i;
    if (!found) return Error{option, "unknown buffer '" + name + "' (valid: " + validNames() + ")"};
    for (Aov a : out)
      if (a == found->aov) return Error{option, "'" + name + "' is listed twice"};
    out.push_back(found->aov);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<std::string> aovPaths(const std::string& prefix, const std::vector<Aov>& aovs, size_t areaLights) {
  std::vector<std::string> paths;
  for (Aov a : aovs) {
    paths.push_back(prefix + "." + aovName(a) + ".exr");
    if (a == Aov::Visibility)
      for (size_t l = 1; l < areaLights; ++l) paths.push_back(prefix + ".visibility-" + std::to_string(l) + ".exr");
  }
  return paths;
}

std::vector<float> aovSamples(const Frame& frame, Aov aov, size_t light, int& channels) {
  const raster::Image<GBufferTexel>& g = frame.gbuffer;
  channels = aov == Aov::Visibility || aov == Aov::Depth || aov == Aov::Instance || aov == Aov::Triangle ? 1 : 3;
  std::vector<float> out;
  out.reserve(static_cast<size_t>(g.width()) * static_cast<size_t>(g.height()) * static_cast<size_t>(channels));
  const Camera& cam = frame.stats.camera;
  const glm::vec3 forward = glm::normalize(cam.target - cam.eye);
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const GBufferTexel& t = g.at(x, y);
      if (t.material < 0) {
        out.insert(out.end(), static_cast<size_t>(channels), NAN);
        continue;
      }
      const auto vec = [&](glm::vec3 v) { out.insert(out.end(), {v.x, v.y, v.z}); };
      switch (aov) {
        case Aov::Visibility:
          out.push_back(light < frame.visibility.size() ? frame.visibility[light].at(x, y) : 1.0f);
          break;
        case Aov::Depth:
          out.push_back(glm::dot(t.position - cam.eye, forward));
          break;
        case Aov::Position:
          vec(t.position);
          break;
        case Aov::Normal:
          vec(t.normal);
          break;
        case Aov::GeometricNormal:
          vec(t.geometricNormal);
          break;
        case Aov::Albedo:
          vec(t.albedo);
          break;
        case Aov::Instance:
          out.push_back(static_cast<float>(t.instance));
          break;
        case Aov::Triangle:
          out.push_back(static_cast<float>(t.triangle));
          break;
        case Aov::Barycentrics:
          vec(t.bary);
          break;
      }
    }
  return out;
}

Status writeAovs(const Frame& frame, const std::vector<Aov>& aovs, const std::string& prefix) {
  const std::vector<std::string> paths = aovPaths(prefix, aovs, frame.visibility.size());
  size_t next = 0;
  const auto undo = [&] {
    std::error_code ec;
    for (size_t i = 0; i < next; ++i) std::filesystem::remove(paths[i], ec);
  };
  for (Aov a : aovs) {
    const size_t lights = a == Aov::Visibility ? std::max<size_t>(frame.visibility.size(), 1) : 1;
    for (size_t l = 0; l < lights; ++l) {
      int channels = 0;
      const std::vector<float> samples = aovSamples(frame, a, l, channels);
      if (Status st = writeFloatImage(paths[next], frame.gbuffer.width(), frame.gbuffer.height(), channels, samples);
          !st) {
        undo();
        return st;
      }
      ++next;
    }
  }
  return Ok{};
}

}  // namespace penumbra::engine
