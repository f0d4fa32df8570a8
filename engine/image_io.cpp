#include "engine/image_io.h"

#include <unistd.h>

#include <sys/mman.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

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
    if (px.channels == 1) spec.channelnames = {"Y"};
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

// The decode proper, with the format's plugin alone reading from memory.
Result<raster::ImageRgba8> decodeWithPlugin(const unsigned char* data, size_t size, TextureFormat format,
                                            const std::string& name, std::string& oiioError) {
  const char* plugin = format == TextureFormat::Png ? "png" : "jpeg";
  OIIO::Filesystem::IOMemReader memory(data, size);
  // A format name, not a file name: OIIO creates that plugin and no other.
  std::unique_ptr<ImageInput> in = ImageInput::create(plugin, false, nullptr, &memory);
  if (!in) {
    oiioError = OIIO::geterror();
    return Error{name, std::string("no ") + formatName(format) + " decoder"};
  }
  if (!in->supports("ioproxy")) return Error{name, std::string("the ") + formatName(format) + " decoder cannot read from memory"};
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
}

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
  std::string oiioError;
  Result<raster::ImageRgba8> out = Error{name, ""};
  std::string library;
  {
    StderrCapture capture;
    try {
      out = decodeWithPlugin(data, size, format, name, oiioError);
    } catch (const std::exception& e) {
      out = Error{name, "cannot decode image"};
      oiioError = e.what();
    }
    library = capture.finish();
    (void)OIIO::geterror();  // nothing pending for the next caller
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

Status writeFloatImage(const std::string& path, int width, int height, int channels, const std::vector<float>& samples) {
  if (channels != 1 && channels != 3 && channels != 4) return Error{path, "1, 3 or 4 channels expected"};
  if (samples.size() != pixelCount(width, height) * static_cast<size_t>(channels))
    return Error{path, "sample count does not match the image size"};
  if (!isFloatFormat(lowerExtension(path))) return Error{path, "float buffers are written as .exr"};
  return writeAtomically(path, packedView(samples, width, height, channels, TypeDesc::FLOAT));
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

}  // namespace penumbra::engine
