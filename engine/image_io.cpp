#include "engine/image_io.h"

#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <system_error>
#include <vector>

#include "engine/atomic_file.h"
#include "engine/texture.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// OIIO error text can span lines; our errors are one line.
std::string oneLine(std::string s) {
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

// Formats that store 32-bit float samples; every other format gets 8-bit samples.
bool isFloatFormat(const std::string& ext) {
  return ext == ".exr" || ext == ".hdr" || ext == ".tif" || ext == ".tiff" || ext == ".pfm";
}

// Pixels ready for OIIO: `channels` samples of `type` per pixel, rows `rowBytes` apart.
struct PixelView {
  int width = 0, height = 0, channels = 0;
  TypeDesc type;
  const void* data = nullptr;
  OIIO::stride_t pixelBytes = 0, rowBytes = 0;
};

Status writeAtomically(const std::string& path, const PixelView& px) {
  if (path.empty()) return Error{path, "no output file name"};
  if (px.width <= 0 || px.height <= 0) return Error{path, "cannot write an empty image"};
  const fs::path target(path);
  if (target.extension().empty()) return Error{path, "no file extension to choose the image format from"};
  TempFile tmp(target);  // removed on every early return
  try {
    std::unique_ptr<ImageOutput> out = ImageOutput::create(tmp.path().string());
    if (!out) {
      (void)OIIO::geterror();  // retrieve (and drop) OIIO's pending message
      return Error{path, "unsupported image file type '" + target.extension().string() + "'"};
    }
    ImageSpec spec(px.width, px.height, px.channels, px.type);
    if (px.channels == 4) spec.alpha_channel = 3;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // alpha is straight: no un-premultiplication
    // No timestamp: OIIO's OpenEXR writer stamps the current time as capDate unless DateTime is
    // set; an empty one keeps the same render's file the same bytes.
    spec.attribute("DateTime", "");
    if (!out->open(tmp.path().string(), spec)) return Error{path, "cannot write: " + oneLine(out->geterror())};
    const bool written = out->write_image(px.type, px.data, px.pixelBytes, px.rowBytes);
    std::string why = written ? std::string() : oneLine(out->geterror());
    const bool closed = out->close();
    if (written && !closed) why = oneLine(out->geterror());
    out.reset();
    if (!written || !closed) return Error{path, "cannot write: " + why};
    return tmp.commit();
  } catch (const std::exception& e) {
    return Error{path, "cannot write: " + oneLine(e.what())};
  }
}

template <class T>
PixelView viewOf(const raster::Image<T>& img, int channels, TypeDesc type) {
  return {img.width(), img.height(), channels, type, img.data(), static_cast<OIIO::stride_t>(sizeof(T)),
          static_cast<OIIO::stride_t>(sizeof(T)) * img.stride()};
}

template <class T>
PixelView packedView(const std::vector<T>& samples, int width, int height, int channels, TypeDesc type) {
  const auto pixel = static_cast<OIIO::stride_t>(sizeof(T)) * channels;
  return {width, height, channels, type, samples.data(), pixel, pixel * width};
}

size_t pixelCount(int w, int h) { return static_cast<size_t>(w) * static_cast<size_t>(h); }

uint8_t unitToByte(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(v * 255.0f));
}

// Reads the opened image's first subimage into RGBA8.
Result<raster::ImageRgba8> readOpened(ImageInput& in, const std::string& name) {
  const ImageSpec& spec = in.spec();
  if (spec.deep) return Error{name, "deep images are not supported"};
  if (spec.depth > 1) return Error{name, "volume images are not supported"};
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return Error{name, "image has no pixels"};
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide || pixelCount(spec.width, spec.height) > kMaxImagePixels)
    return Error{name, "image of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                           " pixels is larger than supported (" + std::to_string(kMaxImageSide) + " per side)"};
  const int w = spec.width, h = spec.height, nch = std::min(spec.nchannels, 4);
  std::vector<uint8_t> buf(pixelCount(w, h) * static_cast<size_t>(nch));
  if (!in.read_image(0, 0, 0, nch, TypeDesc::UINT8, buf.data()))
    return Error{name, "cannot decode image: " + oneLine(in.geterror())};
  raster::ImageRgba8 img(w, h);
  for (int y = 0; y < h; ++y) {
    raster::Rgba8* row = img.row(y);
    for (int x = 0; x < w; ++x) {
      const uint8_t* s = buf.data() + (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * static_cast<size_t>(nch);
      switch (nch) {
        case 1: row[x] = {s[0], s[0], s[0], 255}; break;
        case 2: row[x] = {s[0], s[0], s[0], s[1]}; break;
        case 3: row[x] = {s[0], s[1], s[2], 255}; break;
        default: row[x] = {s[0], s[1], s[2], s[3]}; break;
      }
    }
  }
  return img;
}

// A file name whose extension names the format of the encoded bytes, from their signature.
std::string formatHint(const unsigned char* d, size_t n, const std::string& nameForErrors) {
  auto starts = [&](const char* magic, size_t len, size_t at = 0) { return n >= at + len && std::memcmp(d + at, magic, len) == 0; };
  if (starts("\x89PNG", 4)) return "memory.png";
  if (starts("\xFF\xD8\xFF", 3)) return "memory.jpg";
  if (starts("GIF8", 4)) return "memory.gif";
  if (starts("BM", 2)) return "memory.bmp";
  if (starts("\x76\x2F\x31\x01", 4)) return "memory.exr";
  if (starts("II*\0", 4) || starts("MM\0*", 4)) return "memory.tif";
  if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return "memory.webp";
  if (starts("#?", 2)) return "memory.hdr";
  const std::string ext = lowerExtension(nameForErrors);
  return "memory" + (ext.empty() ? std::string(".png") : ext);
}

}  // namespace

Status writeImage(const std::string& path, const raster::ImageRgba8& image) {
  if (!isFloatFormat(lowerExtension(path))) return writeAtomically(path, viewOf(image, 4, TypeDesc::UINT8));
  std::vector<float> lin;
  lin.reserve(pixelCount(image.width(), image.height()) * 4);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const raster::Rgba8 p = image.row(y)[x];
      lin.insert(lin.end(), {srgbToLinear(p.r), srgbToLinear(p.g), srgbToLinear(p.b), static_cast<float>(p.a) / 255.0f});
    }
  return writeAtomically(path, packedView(lin, image.width(), image.height(), 4, TypeDesc::FLOAT));
}

Status writeImage(const std::string& path, const raster::ImageFloat4& image) {
  if (isFloatFormat(lowerExtension(path))) return writeAtomically(path, viewOf(image, 4, TypeDesc::FLOAT));
  std::vector<uint8_t> bytes;
  bytes.reserve(pixelCount(image.width(), image.height()) * 4);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const raster::Float4 p = image.row(y)[x];
      bytes.insert(bytes.end(), {linearToSrgb(p.r), linearToSrgb(p.g), linearToSrgb(p.b), unitToByte(p.a)});
    }
  return writeAtomically(path, packedView(bytes, image.width(), image.height(), 4, TypeDesc::UINT8));
}

Status writeImage(const std::string& path, const raster::ImageFloat& image) {
  if (isFloatFormat(lowerExtension(path))) return writeAtomically(path, viewOf(image, 1, TypeDesc::FLOAT));
  std::vector<uint8_t> bytes;
  bytes.reserve(pixelCount(image.width(), image.height()));
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) bytes.push_back(unitToByte(image.row(y)[x]));
  return writeAtomically(path, packedView(bytes, image.width(), image.height(), 1, TypeDesc::UINT8));
}

Result<raster::ImageRgba8> readImageRgba8(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Error{path, "cannot open file"};
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

Result<raster::ImageRgba8> decodeImageRgba8(const unsigned char* data, size_t size, const std::string& nameForErrors) {
  if (data == nullptr || size == 0) return Error{nameForErrors, "image data is empty"};
  try {
    const std::string hint = formatHint(data, size, nameForErrors);
    OIIO::Filesystem::IOMemReader memory(data, size);
    std::unique_ptr<ImageInput> in = ImageInput::create(hint, false, nullptr, &memory);
    if (!in) return Error{nameForErrors, "cannot decode image: " + oneLine(OIIO::geterror())};
    ImageSpec config;
    void* proxy = &memory;
    config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
    config.attribute("oiio:UnassociatedAlpha", 1);
    ImageSpec spec;
    if (!in->open(hint, spec, config)) return Error{nameForErrors, "cannot decode image: " + oneLine(in->geterror())};
    return readOpened(*in, nameForErrors);
  } catch (const std::exception& e) {
    return Error{nameForErrors, "cannot decode image: " + oneLine(e.what())};
  }
}

}  // namespace penumbra::engine
