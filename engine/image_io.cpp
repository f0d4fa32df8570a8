#include "engine/image_io.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <system_error>
#include <vector>

#include "engine/atomic_file.h"
#include "engine/image_module.h"
#include "engine/png_encoder.h"
#include "engine/texture.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using image_module::oneLine;
using image_module::Pixels;
using image_module::SampleType;

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Formats that store 32-bit float samples; every other format gets 8-bit samples.
bool isFloatFormat(const std::string& ext) {
  return ext == ".exr" || ext == ".hdr" || ext == ".tif" || ext == ".tiff" || ext == ".pfm";
}

// PNG: encoded here; any other format through the image module (OpenImageIO).
Status writeAtomically(const std::string& path, const Pixels& px) {
  if (path.empty()) return Error{path, "no output file name"};
  if (px.width <= 0 || px.height <= 0) return Error{path, "cannot write an empty image"};
  const fs::path target(path);
  if (target.extension().empty()) return Error{path, "no file extension to choose the image format from"};
  if (lowerExtension(path) == ".png" && px.type == SampleType::UInt8) {
    try {
      const std::string bytes =
          encodePng(px.width, px.height, px.channels, static_cast<const uint8_t*>(px.data),
                    static_cast<size_t>(px.rowBytes));
      return writeFileAtomically(target, bytes);
    } catch (const std::exception& e) {
      return Error{path, "cannot write: " + oneLine(e.what())};
    }
  }
  const Result<const image_module::Table*> module = image_module::table();
  if (!module) return Error{path, "cannot write: " + module.error().line()};
  TempFile tmp(target);  // removed on every early return
  const Status written = (*module)->write(tmp.path().string(), path, px);
  if (!written) return written;
  return tmp.commit();
}

template <class T>
Pixels viewOf(const raster::Image<T>& img, int channels, SampleType type) {
  return {img.width(),
          img.height(),
          channels,
          type,
          img.data(),
          static_cast<std::ptrdiff_t>(sizeof(T)),
          static_cast<std::ptrdiff_t>(sizeof(T)) * img.stride()};
}

template <class T>
Pixels packedView(const std::vector<T>& samples, int width, int height, int channels, SampleType type) {
  const auto pixel = static_cast<std::ptrdiff_t>(sizeof(T)) * channels;
  return {width, height, channels, type, samples.data(), pixel, pixel * width};
}

size_t pixelCount(int w, int h) { return static_cast<size_t>(w) * static_cast<size_t>(h); }

uint8_t unitToByte(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(v * 255.0f));
}

const char* formatName(TextureFormat f) {
  switch (f) {
    case TextureFormat::Png: return "PNG";
    case TextureFormat::Jpeg: return "JPEG";
    case TextureFormat::Ktx2: return "KTX2";
    case TextureFormat::Webp: return "WebP";
    case TextureFormat::Unknown: break;
  }
  return "unknown";
}

// What a decoder writes to stderr (fd 2) while this lives is kept instead of reaching the
// terminal: libpng prints warnings and errors there itself. fd 2 is the process's, so captures
// are serialized; nothing else in Penumbra writes to stderr while a texture decodes (loading runs
// on one thread, before any progress line).
std::mutex gStderrMutex;

class StderrCapture {
 public:
  StderrCapture() : lock_(gStderrMutex) {
    std::fflush(stderr);
    file_ = ::memfd_create("penumbra-stderr", MFD_CLOEXEC);
    if (file_ < 0) return;
    saved_ = ::dup(STDERR_FILENO);
    if (saved_ < 0 || ::dup2(file_, STDERR_FILENO) < 0) {
      if (saved_ >= 0) ::close(saved_);
      ::close(file_);
      file_ = saved_ = -1;
    }
  }
  ~StderrCapture() { (void)finish(); }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Restores stderr; what was written meanwhile (at most 1 KiB of it).
  std::string finish() {
    if (file_ < 0) return {};
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
    std::string text(1024, '\0');
    const ssize_t n = ::pread(file_, text.data(), text.size(), 0);
    ::close(file_);
    file_ = saved_ = -1;
    text.resize(n > 0 ? static_cast<size_t>(n) : 0);
    return text;
  }

 private:
  std::lock_guard<std::mutex> lock_;
  int file_ = -1, saved_ = -1;
};

}  // namespace

TextureFormat textureFormatOf(const unsigned char* d, size_t n) {
  auto starts = [&](const char* magic, size_t len, size_t at = 0) { return n >= at + len && std::memcmp(d + at, magic, len) == 0; };
  if (starts("\x89PNG\r\n\x1a\n", 8)) return TextureFormat::Png;
  if (starts("\xFF\xD8\xFF", 3)) return TextureFormat::Jpeg;
  if (starts("\xABKTX 20\xBB\r\n\x1a\n", 12)) return TextureFormat::Ktx2;
  if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return TextureFormat::Webp;
  return TextureFormat::Unknown;
}

TextureFormat textureFormatOfMime(const std::string& m) {
  if (m == "image/png") return TextureFormat::Png;
  if (m == "image/jpeg") return TextureFormat::Jpeg;
  if (m == "image/ktx2") return TextureFormat::Ktx2;
  if (m == "image/webp") return TextureFormat::Webp;
  return TextureFormat::Unknown;
}

Result<raster::ImageRgba8> decodeTexture(const unsigned char* data, size_t size, const std::string& mimeType,
                                         const std::string& name) {
  if (data == nullptr || size == 0) return Error{name, "image data is empty"};
  const TextureFormat format = textureFormatOf(data, size);
  const TextureFormat declared = textureFormatOfMime(mimeType);
  if (!mimeType.empty() && declared == TextureFormat::Unknown)
    return Error{name, "mimeType '" + mimeType + "' is not an image type glTF allows (image/png, image/jpeg)"};
  if (format == TextureFormat::Ktx2 || format == TextureFormat::Webp ||
      (format == TextureFormat::Unknown && (declared == TextureFormat::Ktx2 || declared == TextureFormat::Webp))) {
    const TextureFormat f = format != TextureFormat::Unknown ? format : declared;
    return Error{name, std::string(formatName(f)) + " images (" +
                           (f == TextureFormat::Ktx2 ? "KHR_texture_basisu" : "EXT_texture_webp") +
                           ") are not supported: only PNG and JPEG"};
  }
  if (format == TextureFormat::Unknown) return Error{name, "not a PNG or JPEG image (the only formats glTF allows)"};
  if (declared != TextureFormat::Unknown && declared != format)
    return Error{name, "declared " + mimeType + " but the bytes are " + formatName(format)};
  const Result<const image_module::Table*> module = image_module::table();
  if (!module) return Error{name, "cannot decode image: " + module.error().line()};
  std::string oiioError;
  Result<raster::ImageRgba8> out = Error{name, ""};
  std::string library;
  {
    StderrCapture capture;
    out = (*module)->decode(data, size, format == TextureFormat::Png, name, oiioError);
    library = capture.finish();
    (*module)->clearError();  // nothing pending for the next caller
  }
  if (out) return out;
  // One line: our reason, then what OIIO said, then what the decoding library printed (less what
  // OIIO already repeats).
  std::string why = out.error().what + " (" + formatName(format) + ")";
  std::string said = oiioError.empty() ? "" : oneLine(oiioError);
  for (std::string line : {library}) {
    if (line.empty()) continue;
    line = oneLine(line);
    for (const char* prefix : {"libpng error: ", "libpng warning: "})
      if (line.rfind(prefix, 0) == 0) line.erase(0, std::strlen(prefix));
    if (said.find(line) == std::string::npos) said += (said.empty() ? "" : "; ") + line;
  }
  return Error{name, said.empty() ? why : why + ": " + said};
}

Status writeImage(const std::string& path, const raster::ImageRgba8& image) {
  if (!isFloatFormat(lowerExtension(path))) return writeAtomically(path, viewOf(image, 4, SampleType::UInt8));
  std::vector<float> lin;
  lin.reserve(pixelCount(image.width(), image.height()) * 4);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const raster::Rgba8 p = image.row(y)[x];
      lin.insert(lin.end(), {srgbToLinear(p.r), srgbToLinear(p.g), srgbToLinear(p.b), static_cast<float>(p.a) / 255.0f});
    }
  return writeAtomically(path, packedView(lin, image.width(), image.height(), 4, SampleType::Float));
}

Status writeImage(const std::string& path, const raster::ImageFloat4& image) {
  if (isFloatFormat(lowerExtension(path))) return writeAtomically(path, viewOf(image, 4, SampleType::Float));
  std::vector<uint8_t> bytes;
  bytes.reserve(pixelCount(image.width(), image.height()) * 4);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const raster::Float4 p = image.row(y)[x];
      bytes.insert(bytes.end(), {linearToSrgb(p.r), linearToSrgb(p.g), linearToSrgb(p.b), unitToByte(p.a)});
    }
  return writeAtomically(path, packedView(bytes, image.width(), image.height(), 4, SampleType::UInt8));
}

Status writeImage(const std::string& path, const raster::ImageFloat& image) {
  if (isFloatFormat(lowerExtension(path))) return writeAtomically(path, viewOf(image, 1, SampleType::Float));
  std::vector<uint8_t> bytes;
  bytes.reserve(pixelCount(image.width(), image.height()));
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) bytes.push_back(unitToByte(image.row(y)[x]));
  return writeAtomically(path, packedView(bytes, image.width(), image.height(), 1, SampleType::UInt8));
}

Status writeFloatImage(const std::string& path, int width, int height, int channels, const std::vector<float>& samples) {
  if (channels != 1 && channels != 3 && channels != 4) return Error{path, "1, 3 or 4 channels expected"};
  if (samples.size() != pixelCount(width, height) * static_cast<size_t>(channels))
    return Error{path, "sample count does not match the image size"};
  if (!isFloatFormat(lowerExtension(path))) return Error{path, "float buffers are written as .exr"};
  return writeAtomically(path, packedView(samples, width, height, channels, SampleType::Float));
}

Result<raster::ImageRgba8> readImageRgba8(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Error{path, "cannot open file"};
  const Result<const image_module::Table*> module = image_module::table();
  if (!module) return Error{path, "cannot read image: " + module.error().line()};
  return (*module)->read(path);
}

}  // namespace penumbra::engine
