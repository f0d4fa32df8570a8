#include "apps/point_cloud.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <filesystem>
#include <fstream>
#include <optional>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "engine/texture.h"
#include "raster/splat.h"

namespace penumbra::apps {

namespace {

// The world-space corners of triangle t of an instance.
struct WorldTriangle {
  glm::vec3 a, b, c;
};
WorldTriangle worldTriangle(const engine::Mesh& mesh, const glm::mat4& transform, size_t t) {
  auto at = [&](size_t k) {
    return glm::vec3(transform * glm::vec4(mesh.positions[mesh.indices[3 * t + k]], 1.0f));
  };
  return {at(0), at(1), at(2)};
}

// Splits a line into fields separated by spaces or tabs.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// The field in quotes for a message, at most 32 characters of it.
std::string quoted(std::string_view s) {
  std::string out(1, '\'');
  out.append(s.substr(0, 32));
  out.append(s.size() > 32 ? "...'" : "'");
  return out;
}

}  // namespace

double pointRandom(uint64_t index, uint32_t dimension) {
  // SplitMix64: state k = k * golden gamma, output = its finalizer (two xor-shift-multiply rounds).
  uint64_t z = (4 * index + dimension + 1) * 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1p-53;
}

engine::Result<SurfacePoints> sampleSurface(const engine::Scene& scene, int64_t count, bool attributes) {
  if (count < 1 || count > kMaxCloudPoints)
    return engine::Error{"points", "count must be in [1, " + std::to_string(kMaxCloudPoints) + "]"};
  // Cumulative area over every instance's triangles, instance after instance; firstTriangle[k] is
  // the index in that table of instance k's first triangle.
  std::vector<double> cumulative;
  std::vector<size_t> firstTriangle;
  cumulative.reserve(scene.triangleCount());
  double total = 0.0;
  for (const engine::Instance& inst : scene.instances) {
    firstTriangle.push_back(cumulative.size());
    const engine::Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
      const WorldTriangle w = worldTriangle(mesh, inst.transform, t);
      total += 0.5 * static_cast<double>(glm::length(glm::cross(w.b - w.a, w.c - w.a)));
      cumulative.push_back(total);
    }
  }
  if (!(total > 0.0) || !std::isfinite(total))
    return engine::Error{"scene '" + scene.name + "'",
                         "no triangle of non-zero finite area to sample points from"};

  SurfacePoints out;
  const auto n = static_cast<size_t>(count);
  out.positions.resize(n);
  if (attributes) {
    out.normals.resize(n);
    out.materials.resize(n);
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      // The first triangle whose running sum exceeds u0 * total (zero-area triangles are never
      // chosen); u0 * total may round up to total, hence the clamp.
      const double x = pointRandom(i, 0) * total;
      size_t t =
          static_cast<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin());
      t = std::min(t, cumulative.size() - 1);
      const size_t k = static_cast<size_t>(std::upper_bound(firstTriangle.begin(), firstTriangle.end(), t) -
                                           firstTriangle.begin()) -
                       1;
      const engine::Instance& inst = scene.instances[k];
      const engine::Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
      const WorldTriangle w = worldTriangle(mesh, inst.transform, t - firstTriangle[k]);
      const auto r1 = static_cast<float>(std::sqrt(pointRandom(i, 1)));
      const auto u2 = static_cast<float>(pointRandom(i, 2));
      // a + b1 (b - a) + b2 (c - a): exact on the corner a, and off the plane only by rounding.
      out.positions[i] = w.a + (r1 * (1.0f - u2)) * (w.b - w.a) + (r1 * u2) * (w.c - w.a);
      if (attributes) {
        const glm::vec3 c = glm::cross(w.b - w.a, w.c - w.a);
        const float len = glm::length(c);
        out.normals[i] = len > 0.0f ? c / len : glm::vec3(0.0f, 1.0f, 0.0f);
        out.materials[i] = mesh.material;
      }
    }
  });
  return out;
}

std::vector<uint32_t> headlightColors(const engine::Scene& scene, const SurfacePoints& points,
                                      glm::vec3 eye) {
  std::vector<uint32_t> colors(points.positions.size());
  const engine::Material defaultMaterial{};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, colors.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const int32_t m = points.materials[i];
          const engine::Material& mat = m >= 0 ? scene.materials[static_cast<size_t>(m)] : defaultMaterial;
          const glm::vec3 d = eye - points.positions[i];
          const float len = glm::length(d);
          const float facing = len > 0.0f ? std::abs(glm::dot(points.normals[i], d / len)) : 1.0f;
          const glm::vec3 c = glm::vec3(mat.baseColorFactor) * (0.15f + 0.85f * facing);
          colors[i] = raster::packRgba8(
              {engine::linearToSrgb(c.x), engine::linearToSrgb(c.y), engine::linearToSrgb(c.z), 255});
        }
      });
  return colors;
}

namespace {

// One line of an .xyz file into `out`; an Error naming the file and line, or nothing.
std::optional<engine::Error> xyzLine(std::string_view view, int64_t lineNo, const std::string& path, XyzCloud& out) {
  if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
  const std::vector<std::string_view> f = fields(view);
  if (f.empty() || f[0][0] == '#') return std::nullopt;
  auto bad = [&](const std::string& what) {
    return std::optional<engine::Error>(engine::Error{path, "line " + std::to_string(lineNo) + ": " + what});
  };
  if (f.size() != 3 && f.size() != 6)
    return bad("expected 3 fields (x y z) or 6 (x y z r g b), got " + std::to_string(f.size()));
  if (static_cast<int64_t>(out.positions.size()) == kMaxCloudPoints)
    return bad("more than " + std::to_string(kMaxCloudPoints) + " points");
  float xyz[3];
  for (int k = 0; k < 3; ++k) {
    std::string_view s = f[static_cast<size_t>(k)];
    if (s.size() > 1 && s[0] == '+' && s[1] != '+' && s[1] != '-')
      s.remove_prefix(1);  // from_chars takes no '+'
    // Parsed as double, then rounded to float: a magnitude too small for a float becomes 0 (or a
    // subnormal) whatever its exponent; one too large for a float is an error.
    double v = 0.0;
    const auto [end, err] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (err != std::errc() && err != std::errc::result_out_of_range)
      return bad("coordinate " + quoted(s) + " is not a number");
    if (end != s.data() + s.size()) return bad("coordinate " + quoted(s) + " is not a number");
    if (err == std::errc::result_out_of_range) {
      // Out of double's range: below its smallest subnormal (a tiny exponent) is 0; above is too large.
      const size_t e = s.find_first_of("eE");
      const bool tiny = e != std::string_view::npos && e + 1 < s.size() && s[e + 1] == '-';
      if (!tiny) return bad("coordinate " + quoted(s) + " is out of the float range");
      v = 0.0;
    }
    if (!std::isfinite(v)) return bad("coordinate " + quoted(s) + " is not finite");
    if (std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
      return bad("coordinate " + quoted(s) + " is out of the float range");
    xyz[k] = static_cast<float>(v);
  }
  uint8_t rgb[3] = {255, 255, 255};
  for (size_t k = 0; k < 3 && f.size() == 6; ++k) {
    const std::string_view s = f[3 + k];
    int v = -1;
    const auto [end, err] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (err != std::errc() || end != s.data() + s.size() || v < 0 || v > 255)
      return bad("color " + quoted(s) + " is not an integer in [0, 255]");
    rgb[k] = static_cast<uint8_t>(v);
  }
  out.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  out.colors.push_back(raster::packRgba8({rgb[0], rgb[1], rgb[2], 255}));
  return std::nullopt;
}

}  // namespace

engine::Result<XyzCloud> readXyz(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return engine::Error{path, "no such file"};
  if (!std::filesystem::is_regular_file(path, ec)) return engine::Error{path, "not a regular file"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return engine::Error{path, "cannot open the file"};
  XyzCloud out;
  std::string line;
  int64_t lineNo = 0;
  while (std::getline(in, line))
    if (std::optional<engine::Error> e = xyzLine(line, ++lineNo, path, out)) return *e;
  if (in.bad()) return engine::Error{path, "read error after line " + std::to_string(lineNo)};
  if (out.positions.empty()) return engine::Error{path, "no points in the file"};
  return out;
}

engine::Result<XyzCloud> parseXyz(std::string_view text, const std::string& name) {
  XyzCloud out;
  int64_t lineNo = 0;
  for (size_t start = 0; start < text.size();) {
    size_t lineEnd = text.find('\n', start);
    if (lineEnd == std::string_view::npos) lineEnd = text.size();
    if (std::optional<engine::Error> e = xyzLine(text.substr(start, lineEnd - start), ++lineNo, name, out)) return *e;
    start = lineEnd + 1;
  }
  if (out.positions.empty()) return engine::Error{name, "no points in the file"};
  return out;
}

}  // namespace penumbra::apps
