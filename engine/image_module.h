// The OpenImageIO part of engine/image_io, a module loaded on first use: linking OpenImageIO
// loads about 260 shared libraries and runs their initializers, 0.4 s and 130 MB in every process
// (docs/architecture.md), half the default render's wall time. PNG renders are encoded without it
// (engine/png_encoder.h); EXR and other formats, reading images and decoding textures load the
// module libpenumbra_image_oiio.so, found in this order:
//   1. the file $PENUMBRA_IMAGE_MODULE names;
//   2. beside the binary holding the engine's code (the Python extension has it there), when its
//      path is absolute: never from the folder the process runs in;
//   3. where this build tree built it;
//   4. <install prefix>/<libdir>/penumbra, where `cmake --install` puts it (the prefix the build
//      was configured with), and <the executable's folder>/../<libdir>/penumbra.
// The module is built from the same sources with the same compiler as the engine, so the table's
// C++ types cross the boundary as they are; kImageModuleAbi changes with the table.
//
// Thread-safety: loading happens once (the first caller loads, others wait); the functions are as
// engine/image_io.h's.
#pragma once

#include <cstddef>
#include <string>

#include "engine/error.h"
#include "raster/image.h"

namespace penumbra::engine::image_module {

inline constexpr int kImageModuleAbi = 1;

enum class SampleType { UInt8, Float };

// `channels` samples of `type` per pixel, pixels `pixelBytes` and rows `rowBytes` apart.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  SampleType type = SampleType::UInt8;
  const void* data = nullptr;
  std::ptrdiff_t pixelBytes = 0, rowBytes = 0;
};

struct Table {
  int abi = 0;
  // Writes `px` to `file` in the format its extension names; errors name `nameForErrors`.
  Status (*write)(const std::string& file, const std::string& nameForErrors, const Pixels& px) = nullptr;
  // An image file's first subimage as RGBA8 (engine/image_io.h: readImageRgba8).
  Result<raster::ImageRgba8> (*read)(const std::string& path) = nullptr;
  // `size` bytes of PNG (png = true) or JPEG by that format's plugin alone, from memory. What OIIO
  // said on failure is left in oiioError.
  Result<raster::ImageRgba8> (*decode)(const unsigned char* data, size_t size, bool png,
                                       const std::string& name, std::string& oiioError) = nullptr;
  // Drops OIIO's pending error message, if any.
  void (*clearError)() = nullptr;
};

// The loaded module's table, or why it could not be loaded (one line).
Result<const Table*> table();

// Decoders' and OIIO's messages can span lines; our errors are one line: control whitespace
// becomes spaces, runs of spaces one, no leading or trailing space ("unknown error" when empty).
inline std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  const size_t b = s.find_first_not_of(' ');
  const size_t e = s.find_last_not_of(' ');
  if (b == std::string::npos) return "unknown error";
  s = s.substr(b, e - b + 1);
  std::string out;
  for (char c : s)
    if (!(c == ' ' && !out.empty() && out.back() == ' ')) out += c;
  return out;
}

}  // namespace penumbra::engine::image_module

// The module's one exported symbol.
extern "C" const penumbra::engine::image_module::Table* penumbra_image_module_table();
