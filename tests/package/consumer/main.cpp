// A consumer of the installed Penumbra package: a scene built in code, rendered with and without
// soft shadows, the bare pipeline on one triangle, a PNG written through Penumbra::engine.
// Exits 0 when every check holds and prints what failed otherwise.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/image_io.h"
#include "engine/renderer.h"
#include "engine/shapes.h"
#include "engine/version.h"
#include "raster/pipeline.h"
#include "raster/reference.h"

namespace pe = penumbra::engine;
namespace pr = penumbra::raster;

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "consumer: FAILED: %s\n", what.c_str());
    ++failures;
  }
}

pe::Scene boxOnGround() {
  pe::Scene s;
  s.name = "consumer";
  s.meshes.push_back(pe::makePlane(8.0f, 8.0f, 1));
  s.meshes.push_back(pe::makeBox(glm::vec3(1.0f)));
  s.instances.push_back({.name = "ground", .mesh = 0});
  pe::Instance box{.name = "box", .mesh = 1};
  box.transform[3] = glm::vec4(0.0f, 0.5f, 0.0f, 1.0f);
  s.instances.push_back(box);
  penumbra::shadows::RectLight light;
  light.center = glm::vec3(0.0f, 4.0f, 0.0f);
  light.right = glm::vec3(1, 0, 0);
  light.up = glm::vec3(0, 0, 1);  // right x up = -y: facing down
  light.intensity = 4.0f;
  s.areaLights.push_back(light);
  s.camera = pe::Camera{.eye = glm::vec3(0.0f, 5.0f, 6.0f), .target = glm::vec3(0.0f)};
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::printf("Penumbra %s\n", penumbra::kVersion);
  pe::Scene scene = boxOnGround();
  check(pe::validateScene(scene, "consumer scene").ok(), "the scene validates");

  pe::Renderer renderer(2);
  pe::RenderOptions opt;
  opt.width = 96;
  opt.height = 64;
  opt.shadow = "none";
  pe::Result<pe::Frame> lit = renderer.render(scene, opt);
  opt.shadow = "pcss";
  pe::Result<pe::Frame> shadowed = renderer.render(scene, opt);
  check(lit.ok() && shadowed.ok(), "both frames render");
  if (lit.ok() && shadowed.ok()) {
    // Ground pixels next to the box are darker with shadows; none is brighter.
    int darker = 0, brighter = 0;
    for (int y = 0; y < opt.height; ++y)
      for (int x = 0; x < opt.width; ++x) {
        const int a = lit->color.at(x, y).r, b = shadowed->color.at(x, y).r;
        darker += b + 8 < a;
        brighter += b > a + 1;
      }
    check(darker > 20, "shadowed pixels: " + std::to_string(darker));
    check(brighter == 0, "pixels brighter with shadows: " + std::to_string(brighter));
  }
  pe::RenderOptions bad = opt;
  bad.spp = 0;
  const pe::Result<pe::Frame> refused = renderer.render(scene, bad);
  check(!refused.ok() && refused.error().line().find("--spp") != std::string::npos,
        "a bad option is an Error");

  // The bare pipeline on one triangle, against the scalar reference rasterizer, pixel for pixel.
  pr::Rasterizer raster({.threads = 2});
  constexpr int kW = 37, kH = 23;
  pr::DepthTarget depth(kW, kH, 1.0f);
  const glm::vec4 clip[3] = {{-0.8f, -0.9f, 0.3f, 1}, {0.95f, -0.2f, 0.5f, 1}, {-0.3f, 0.85f, 0.7f, 1}};
  std::vector<uint32_t> fast(kW * kH, 0), ref(kW * kH, 0);
  pr::DrawDesc desc;
  desc.vertexCount = 3;
  raster.draw(
      desc, depth, [&](uint32_t i, float*) { return clip[i]; },
      [&](const pr::Fragment& f) { ++fast[static_cast<size_t>(f.y * kW + f.x)]; });
  pr::reference::coverage(pr::reference::snap(clip, kW, kH), kW, kH, ref);
  size_t covered = 0;
  for (uint32_t c : fast) covered += c;
  check(fast == ref && covered > 100,
        "triangle coverage equals the reference (" + std::to_string(covered) + " pixels)");

  if (argc > 1 && lit.ok()) {
    const std::filesystem::path out = std::filesystem::path(argv[1]) / "consumer.png";
    check(pe::writeImage(out.string(), lit->color).ok(), "writes " + out.string());
    check(std::filesystem::file_size(out) > 100, "the PNG has content");
    // An EXR goes through the installed image module (run.sh points PENUMBRA_IMAGE_MODULE at it).
    const std::filesystem::path exr = std::filesystem::path(argv[1]) / "consumer.exr";
    const pe::Status wroteExr = pe::writeImage(exr.string(), lit->color);
    check(wroteExr.ok(), "writes " + exr.string() + (wroteExr.ok() ? "" : ": " + wroteExr.error().line()));
  }
  if (failures == 0) std::printf("consumer: all checks passed\n");
  return failures == 0 ? 0 : 1;
}
