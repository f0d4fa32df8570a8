// Writes the seed corpus of the fuzz targets into DIR/{gltf,scene,image,xyz}: small valid inputs
// that reach every part of each reader (glTF text and binary, data URIs and buffer views, indexed
// and strip primitives, node hierarchies, cameras, KHR_lights_punctual, textures; every scene-file
// feature; PNG in RGBA and gray, JPEG; .xyz with and without colors). Made by the program, not
// stored, so they follow the formats as the code changes.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/image_io.h"

namespace fs = std::filesystem;
using nlohmann::json;
using penumbra::raster::Rgba8;

namespace {

void put(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

std::string readAll(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string base64(const std::string& d) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (size_t i = 0; i < d.size(); i += 3) {
    const auto b = [&](size_t k) { return k < d.size() ? static_cast<uint32_t>(static_cast<unsigned char>(d[k])) : 0u; };
    const uint32_t v = (b(i) << 16) | (b(i + 1) << 8) | b(i + 2);
    s += t[(v >> 18) & 63];
    s += t[(v >> 12) & 63];
    s += i + 1 < d.size() ? t[(v >> 6) & 63] : '=';
    s += i + 2 < d.size() ? t[v & 63] : '=';
  }
  return s;
}

template <class T>
void append(std::string& bin, const std::vector<T>& v) {
  bin.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  while (bin.size() % 4) bin.push_back('\0');
}

// A textured quad (two triangles, u16 indices), a strip, a camera and lights, in buffer `bin`.
json model(std::string& bin, const std::string& png, bool imageInView) {
  json doc = {{"asset", {{"version", "2.0"}}}};
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  auto view = [&](size_t offset, size_t length) {
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
    return doc["bufferViews"].size() - 1;
  };
  size_t at = bin.size();
  append(bin, pos);
  doc["accessors"].push_back({{"bufferView", view(at, 48)}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                              {"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
  at = bin.size();
  append(bin, uv);
  doc["accessors"].push_back({{"bufferView", view(at, 32)}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
  at = bin.size();
  append(bin, idx);
  doc["accessors"].push_back({{"bufferView", view(at, 12)}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}});
  if (imageInView) {
    at = bin.size();
    bin += png;
    while (bin.size() % 4) bin.push_back('\0');
    doc["images"] = {{{"bufferView", view(at, png.size())}, {"mimeType", "image/png"}}};
  } else {
    doc["images"] = {{{"uri", "data:image/png;base64," + base64(png)}}};
  }
  doc["textures"] = {{{"source", 0}}};
  doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {1, 0.8, 0.6, 1}}}}}};
  doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}, {"material", 0}},
                                    {{"attributes", {{"POSITION", 0}}}, {"mode", 5}}}}}};
  doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
  doc["extensionsUsed"] = {"KHR_lights_punctual"};
  json lights = json::array();
  lights.push_back({{"type", "spot"}, {"intensity", 10}});
  lights.push_back({{"type", "point"}, {"range", 5}});
  doc["extensions"]["KHR_lights_punctual"]["lights"] = lights;
  doc["nodes"] = {{{"mesh", 0}, {"children", {1, 2}}, {"rotation", {0, 0.38268343, 0, 0.92387953}}},
                  {{"camera", 0}, {"translation", {0, 0, 4}}},
                  {{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}};
  doc["scenes"] = {{{"nodes", {0}}}};
  doc["scene"] = 0;
  return doc;
}

std::string glb(const json& doc, const std::string& bin) {
  std::string js = doc.dump();
  while (js.size() % 4) js += ' ';
  std::string out = "glTF";
  auto u32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(v >> (8 * i)));
  };
  u32(2);
  u32(static_cast<uint32_t>(12 + 8 + js.size() + 8 + bin.size()));
  u32(static_cast<uint32_t>(js.size()));
  u32(0x4E4F534Au);
  out += js;
  u32(static_cast<uint32_t>(bin.size()));
  u32(0x004E4942u);
  return out + bin;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds DIR\n");
    return 2;
  }
  const fs::path dir(argv[1]);
  for (const char* t : {"gltf", "scene", "image", "xyz"}) fs::create_directories(dir / t);
  // Images.
  penumbra::raster::ImageRgba8 rgba(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      rgba.at(x, y) = Rgba8{static_cast<uint8_t>(x * 30), static_cast<uint8_t>(y * 40), 99, static_cast<uint8_t>(200 + x)};
  penumbra::raster::ImageFloat gray(5, 3, 0.25f);
  const fs::path tmp = dir / "tmp";
  fs::create_directories(tmp);
  if (!penumbra::engine::writeImage((tmp / "a.png").string(), rgba).ok() ||
      !penumbra::engine::writeImage((tmp / "g.png").string(), gray).ok() ||
      !penumbra::engine::writeImage((tmp / "j.jpg").string(), rgba).ok()) {
    std::fprintf(stderr, "make_seeds: cannot write images\n");
    return 1;
  }
  const std::string png = readAll(tmp / "a.png");
  put(dir / "image" / "rgba.png", png);
  put(dir / "image" / "gray.png", readAll(tmp / "g.png"));
  put(dir / "image" / "photo.jpg", readAll(tmp / "j.jpg"));
  fs::remove_all(tmp);
  // glTF.
  std::string bin;
  json doc = model(bin, png, false);
  json text = doc;
  text["buffers"] = {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
  put(dir / "gltf" / "quad.gltf", text.dump(1));
  std::string bin2;
  json withView = model(bin2, png, true);
  withView["buffers"] = {{{"byteLength", bin2.size()}}};
  put(dir / "gltf" / "quad.glb", glb(withView, bin2));
  json external = doc;
  external["buffers"] = {{{"byteLength", bin.size()}, {"uri", "quad.bin"}}, {{"byteLength", 4}, {"uri", "../unused.bin"}}};
  put(dir / "gltf" / "external.gltf", external.dump());
  // Scene files: every feature.
  put(dir / "scene" / "shapes.json", R"({"name": "s", "objects": [
 {"shape": "plane", "size": [4, 4], "divisions": 3, "material": {"color": [0.5, 0.5, 0.5]}},
 {"shape": "sphere", "radius": 0.5, "rings": 6, "segments": 8, "transform": {"translate": [0, 0.5, 0]},
  "motion": {"translate": [0.2, 0.5, 0]}},
 {"shape": "box", "size": [0.3, 0.6, 0.3], "transform": {"rotate_deg": [0, 30, 0], "scale": 1.5}},
 {"shape": "cylinder", "radius": 0.2, "height": 1, "segments": 7, "transform": {"rotate_axis_deg": [1, 0, 0, 20]}},
 {"shape": "torus", "major_radius": 0.5, "minor_radius": 0.1, "rings": 6, "segments": 5,
  "material": {"color": [1, 0, 0], "specular": 0.5, "shininess": 32}}],
 "camera": {"eye": [3, 2, 4], "target": [0, 0, 0], "fov_deg": 40, "aperture": 0.05, "focus_distance": 4},
 "lights": [{"type": "directional", "direction": [0, -1, 0]}, {"type": "point", "position": [1, 2, 1]},
  {"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0], "inner_deg": 10, "outer_deg": 30},
  {"type": "area", "center": [0, 4, 0], "normal": [0, -1, 0], "width": 1, "height": 2, "intensity": 10}],
 "ambient": [0.1, 0.1, 0.1], "background": [0, 0, 0]})");
  put(dir / "scene" / "gltf.json", R"({"gltf": [{"file": "model.glb", "transform": {"translate": [1, 0, 0]}}]})");
  // .xyz.
  put(dir / "xyz" / "plain.xyz", "# points\n0 0 0\n1.5 -2e3 +3\n\n1e-39 4 5\n");
  put(dir / "xyz" / "colors.xyz", "0 0 0 255 0 0\r\n1 1 1 0 128 255\r\n");
  std::printf("wrote the seeds in %s\n", dir.c_str());
  return 0;
}
