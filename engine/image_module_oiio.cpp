// libpenumbra_image_oiio.so: what engine/image_io does through OpenImageIO (engine/image_module.h).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/image_io.h"
#include "engine/image_module.h"

namespace penumbra::engine::image_module {
namespace {

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

size_t pixelCount(int w, int h) {
  return static_cast<size_t>(w) * static_cast<size_t>(h);
}

Status write(const std::string& file, const std::string& name, const Pixels& px) {
  try {
    std::unique_ptr<ImageOutput> out = ImageOutput::create(file);
    if (!out) {
      (void)OIIO::geterror();  // retrieve (and drop) OIIO's pending message
      const std::string ext = std::filesystem::path(name).extension().string();
      return Error{name, "unsupported image file type '" + ext + "'"};
    }
    const TypeDesc type = px.type == SampleType::Float ? TypeDesc::FLOAT : TypeDesc::UINT8;
    ImageSpec spec(px.width, px.height, px.channels, type);
    if (px.channels == 4) spec.alpha_channel = 3;
    if (px.channels == 1) spec.channelnames = {"Y"};
    spec.attribute("oiio:UnassociatedAlpha", 1);  // alpha is straight: no un-premultiplication
    // No timestamp: OIIO's OpenEXR writer stamps the current time as capDate unless DateTime is
    // set; an empty one keeps the same render's file the same bytes.
    spec.attribute("DateTime", "");
    if (!out->open(file, spec)) return Error{name, "cannot write: " + oneLine(out->geterror())};
    const bool written = out->write_image(type, px.data, px.pixelBytes, px.rowBytes);
    std::string why = written ? std::string() : oneLine(out->geterror());
    const bool closed = out->close();
    if (written && !closed) why = oneLine(out->geterror());
    if (!written || !closed) return Error{name, "cannot write: " + why};
    return Ok{};
  } catch (const std::exception& e) {
    return Error{name, "cannot write: " + oneLine(e.what())};
  }
}

// Reads the opened image's first subimage into RGBA8.
Result<raster::ImageRgba8> readOpened(ImageInput& in, const std::string& name) {
  const ImageSpec& spec = in.spec();
  if (spec.deep) return Error{name, "deep images are not supported"};
  if (spec.depth > 1) return Error{name, "volume images are not supported"};
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return Error{name, "image has no pixels"};
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide ||
      pixelCount(spec.width, spec.height) > kMaxImagePixels)
    return Error{name, "image of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                           " pixels is larger than supported (" + std::to_string(kMaxImageSide) +
                           " per side)"};
  const int w = spec.width, h = spec.height, nch = std::min(spec.nchannels, 4);
  std::vector<uint8_t> buf(pixelCount(w, h) * static_cast<size_t>(nch));
  if (!in.read_image(0, 0, 0, nch, TypeDesc::UINT8, buf.data()))
    return Error{name, "cannot decode image: " + oneLine(in.geterror())};
  raster::ImageRgba8 img(w, h);
  for (int y = 0; y < h; ++y) {
    raster::Rgba8* row = img.row(y);
    for (int x = 0; x < w; ++x) {
      const uint8_t* s =
          buf.data() + (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) *
                           static_cast<size_t>(nch);
      switch (nch) {
        case 1:
          row[x] = {s[0], s[0], s[0], 255};
          break;
        case 2:
          row[x] = {s[0], s[0], s[0], s[1]};
          break;
        case 3:
          row[x] = {s[0], s[1], s[2], 255};
          break;
        default:
          row[x] = {s[0], s[1], s[2], s[3]};
          break;
      }
    }
  }
  return img;
}

Result<raster::ImageRgba8> read(const std::string& path) {
  try {
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // keep straight alpha: no premultiplication
    std::unique_ptr<ImageInput> in = ImageInput::open(path, &config);
    if (!in) return Error{path, "cannot read image: " + oneLine(OIIO::geterror())};
    return readOpened(*in, path);
  } catch (const std::exception& e) {
    return Error{path, "cannot read image: " + oneLine(e.what())};
  }
}

// The decode proper, with the format's plugin alone reading from memory.
Result<raster::ImageRgba8> decode(const unsigned char* data, size_t size, bool png, const std::string& name,
                                  std::string& oiioError) {
  const char* plugin = png ? "png" : "jpeg";
  const std::string format = png ? "PNG" : "JPEG";
  try {
    OIIO::Filesystem::IOMemReader memory(data, size);
    // A format name, not a file name: OIIO creates that plugin and no other.
    std::unique_ptr<ImageInput> in = ImageInput::create(plugin, false, nullptr, &memory);
    if (!in) {
      oiioError = OIIO::geterror();
      return Error{name, "no " + format + " decoder"};
    }
    if (!in->supports("ioproxy")) return Error{name, "the " + format + " decoder cannot read from memory"};
    ImageSpec config;
    void* proxy = &memory;
    config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
    config.attribute("oiio:UnassociatedAlpha", 1);
    ImageSpec spec;
    if (!in->open(std::string("memory.") + plugin, spec, config)) {
      oiioError = in->geterror();
      return Error{name, "cannot decode image"};
    }
    Result<raster::ImageRgba8> out = readOpened(*in, name);
    if (!out) oiioError = in->geterror();
    return out;
  } catch (const std::exception& e) {
    oiioError = e.what();
    return Error{name, "cannot decode image"};
  }
}

void clearError() {
  (void)OIIO::geterror();
}

const Table kTable{kImageModuleAbi, &write, &read, &decode, &clearError};

}  // namespace
}  // namespace penumbra::engine::image_module

extern "C" __attribute__((visibility("default"))) const penumbra::engine::image_module::Table*
penumbra_image_module_table() {
  return &penumbra::engine::image_module::kTable;
}
