// Image files: PNG and EXR round trips through the reader, channel conversions, decoding from
// memory, and failures that must leave no file behind.
#include "engine/image_io.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/png_encoder.h"
#include "engine/texture.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;
using raster::Rgba8;

class ImageIo : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra-image-io-" + std::to_string(::getpid()) + "-" +
            testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

raster::ImageRgba8 pattern(int w, int h) {
  raster::ImageRgba8 img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(x, y) = {static_cast<uint8_t>(x * 40), static_cast<uint8_t>(y * 60), static_cast<uint8_t>(x * y * 7 + 3),
                      static_cast<uint8_t>(255 - x * 10)};
  return img;
}

void expectSame(const raster::ImageRgba8& a, const raster::ImageRgba8& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) ASSERT_EQ(a.at(x, y), b.at(x, y)) << "pixel " << x << ", " << y;
}

std::vector<unsigned char> bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(ImageIo, PngRoundTripIsExact) {
  const raster::ImageRgba8 img = pattern(5, 3);  // width 5: rows are padded in memory, not in the file
  ASSERT_TRUE(writeImage(file("a.png"), img).ok());
  Result<raster::ImageRgba8> back = readImageRgba8(file("a.png"));
  ASSERT_TRUE(back.ok()) << back.error().line();
  expectSame(*back, img);
  EXPECT_EQ(listing(), std::vector<std::string>{"a.png"});  // no temporary left
}

// The same image gives the same file bytes in a later second: no timestamp in the file (OIIO's
// OpenEXR writer stamps the time unless told otherwise).
TEST_F(ImageIo, FilesCarryNoTimestamp) {
  raster::ImageFloat4 lin(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) lin.at(x, y) = {0.25f * static_cast<float>(x), 0.5f, 2.0f, 1.0f};
  for (const char* ext : {".exr", ".png"}) {
    const std::string a = file(std::string("a") + ext), b = file(std::string("b") + ext);
    ASSERT_TRUE(writeImage(a, lin).ok());
    ::usleep(1100 * 1000);  // past the next second of any clock the writer could read
    ASSERT_TRUE(writeImage(b, lin).ok());
    EXPECT_EQ(bytesOf(a), bytesOf(b)) << ext;
  }
}

TEST_F(ImageIo, OverwritesAnExistingFile) {
  ASSERT_TRUE(writeImage(file("a.png"), pattern(2, 2)).ok());
  ASSERT_TRUE(writeImage(file("a.png"), pattern(9, 4)).ok());
  Result<raster::ImageRgba8> back = readImageRgba8(file("a.png"));
  ASSERT_TRUE(back.ok());
  expectSame(*back, pattern(9, 4));
  EXPECT_EQ(listing(), std::vector<std::string>{"a.png"});
}

TEST_F(ImageIo, ExrStoresLinearFloats) {
  // k / 255 read back through the 8-bit reader gives k: the file holds the floats as given.
  raster::ImageFloat4 img(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      img.at(x, y) = {static_cast<float>(x * 50 + 5) / 255.0f, static_cast<float>(y * 100 + 20) / 255.0f, 128 / 255.0f,
                      static_cast<float>((x + y * 3) * 40) / 255.0f};
  ASSERT_TRUE(writeImage(file("f.exr"), img).ok());
  Result<raster::ImageRgba8> back = readImageRgba8(file("f.exr"));
  ASSERT_TRUE(back.ok()) << back.error().line();
  ASSERT_EQ(back->width(), 3);
  ASSERT_EQ(back->height(), 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      EXPECT_EQ(back->at(x, y), (Rgba8{static_cast<uint8_t>(x * 50 + 5), static_cast<uint8_t>(y * 100 + 20), 128,
                                       static_cast<uint8_t>((x + y * 3) * 40)}));
}

TEST_F(ImageIo, SingleChannelExrAndPngReadBackAsGray) {
  raster::ImageFloat img(4, 1);
  for (int x = 0; x < 4; ++x) img.at(x, 0) = static_cast<float>(x * 60) / 255.0f;
  img.at(3, 0) = 7.0f;  // data above 1: kept in EXR, clamped in PNG
  ASSERT_TRUE(writeImage(file("d.exr"), img).ok());
  ASSERT_TRUE(writeImage(file("d.png"), img).ok());
  Result<raster::ImageRgba8> png = readImageRgba8(file("d.png"));
  ASSERT_TRUE(png.ok()) << png.error().line();
  for (int x = 0; x < 3; ++x) {
    const auto v = static_cast<uint8_t>(x * 60);
    EXPECT_EQ(png->at(x, 0), (Rgba8{v, v, v, 255}));
  }
  EXPECT_EQ(png->at(3, 0), (Rgba8{255, 255, 255, 255}));
  Result<raster::ImageRgba8> exr = readImageRgba8(file("d.exr"));
  ASSERT_TRUE(exr.ok()) << exr.error().line();
  EXPECT_EQ(exr->at(2, 0), (Rgba8{120, 120, 120, 255}));
}

TEST_F(ImageIo, FloatToPngIsSrgbEncoded) {
  raster::ImageFloat4 img(2, 1);
  img.at(0, 0) = {0.5f, 0.0f, 1.0f, 0.5f};
  img.at(1, 0) = {-1.0f, 2.0f, 0.2158605f, 1.0f};
  ASSERT_TRUE(writeImage(file("c.png"), img).ok());
  Result<raster::ImageRgba8> back = readImageRgba8(file("c.png"));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->at(0, 0), (Rgba8{188, 0, 255, 128}));
  EXPECT_EQ(back->at(1, 0), (Rgba8{0, 255, 128, 255}));
}

TEST_F(ImageIo, DecodesFromMemory) {
  const raster::ImageRgba8 img = pattern(6, 4);
  ASSERT_TRUE(writeImage(file("m.png"), img).ok());
  const std::vector<unsigned char> png = bytesOf(file("m.png"));
  Result<raster::ImageRgba8> back = decodeTexture(png.data(), png.size(), "image/png", "embedded");
  ASSERT_TRUE(back.ok()) << back.error().line();
  expectSame(*back, img);
  // JPEG is lossy: only check that it decodes to the right size.
  ASSERT_TRUE(writeImage(file("m.jpg"), img).ok());
  const std::vector<unsigned char> jpg = bytesOf(file("m.jpg"));
  Result<raster::ImageRgba8> j = decodeTexture(jpg.data(), jpg.size(), "", "photo");
  ASSERT_TRUE(j.ok()) << j.error().line();
  EXPECT_EQ(j->width(), 6);
  EXPECT_EQ(j->height(), 4);
  EXPECT_EQ(j->at(0, 0).a, 255);
}

TEST_F(ImageIo, GarbageAndTruncatedDataAreErrors) {
  const std::vector<unsigned char> garbage(100, 0x5a);
  Result<raster::ImageRgba8> r = decodeTexture(garbage.data(), garbage.size(), "", "textures/x.png");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where, "textures/x.png");
  EXPECT_FALSE(decodeTexture(nullptr, 0, "", "empty").ok());
  ASSERT_TRUE(writeImage(file("t.png"), pattern(16, 16)).ok());
  const std::vector<unsigned char> png = bytesOf(file("t.png"));
  for (size_t cut : {size_t{8}, size_t{30}, png.size() / 2, png.size() - 13}) {
    Result<raster::ImageRgba8> t = decodeTexture(png.data(), cut, "", "cut.png");
    EXPECT_FALSE(t.ok()) << "cut at " << cut;
  }
}

// What fd 2 receives while f runs.
template <class F>
std::string stderrDuring(F&& f) {
  std::fflush(stderr);
  const int saved = ::dup(2);
  char name[] = "/tmp/penumbra-stderr-XXXXXX";
  const int file = ::mkstemp(name);
  ::dup2(file, 2);
  f();
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  std::string text(4096, '\0');
  const ssize_t n = ::pread(file, text.data(), text.size(), 0);
  ::close(file);
  ::unlink(name);
  text.resize(n > 0 ? static_cast<size_t>(n) : 0);
  return text;
}

// Textures are untrusted: only PNG and JPEG are decoded, by their own plugin, whatever other
// format the bytes are in or the name suggests.
TEST_F(ImageIo, TexturesArePngOrJpegOnly) {
  const raster::ImageRgba8 img = pattern(4, 4);
  for (const char* ext : {".exr", ".tif", ".bmp", ".tga", ".dpx"}) {
    ASSERT_TRUE(writeImage(file(std::string("x") + ext), img).ok()) << ext;
    const std::vector<unsigned char> bytes = bytesOf(file(std::string("x") + ext));
    const Result<raster::ImageRgba8> r = decodeTexture(bytes.data(), bytes.size(), "", std::string("t") + ext);
    ASSERT_FALSE(r.ok()) << ext << " was decoded";
    EXPECT_NE(r.error().what.find("not a PNG or JPEG"), std::string::npos) << r.error().line();
  }
  ASSERT_TRUE(writeImage(file("p.png"), img).ok());
  const std::vector<unsigned char> png = bytesOf(file("p.png"));
  EXPECT_EQ(textureFormatOf(png.data(), png.size()), TextureFormat::Png);
  // The declared type must agree with the bytes, and be one glTF allows.
  const Result<raster::ImageRgba8> lie = decodeTexture(png.data(), png.size(), "image/jpeg", "lie");
  ASSERT_FALSE(lie.ok());
  EXPECT_NE(lie.error().what.find("declared image/jpeg but the bytes are PNG"), std::string::npos) << lie.error().line();
  EXPECT_FALSE(decodeTexture(png.data(), png.size(), "image/gif", "gif").ok());
  // KTX2 and WebP are named, and refused.
  const unsigned char ktx2[16] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n', 0, 0, 0, 0};
  const Result<raster::ImageRgba8> k = decodeTexture(ktx2, sizeof ktx2, "", "k");
  ASSERT_FALSE(k.ok());
  EXPECT_NE(k.error().what.find("KHR_texture_basisu"), std::string::npos) << k.error().line();
  const unsigned char webp[16] = {'R', 'I', 'F', 'F', 8, 0, 0, 0, 'W', 'E', 'B', 'P', 'V', 'P', '8', ' '};
  EXPECT_NE(decodeTexture(webp, sizeof webp, "", "w").error().what.find("WebP"), std::string::npos);
}

// A corrupt PNG: one line naming the image, and libpng's own messages never reach the terminal.
TEST_F(ImageIo, CorruptTextureMessagesAreFoldedIntoOneLine) {
  ASSERT_TRUE(writeImage(file("c.png"), pattern(64, 64)).ok());
  std::vector<unsigned char> png = bytesOf(file("c.png"));
  for (size_t i = 60; i < png.size() - 20; i += 7) png[i] = static_cast<unsigned char>(png[i] ^ 0x5a);  // IDAT and CRCs
  Result<raster::ImageRgba8> r = Error{"", ""};
  const std::string printed = stderrDuring([&] { r = decodeTexture(png.data(), png.size(), "image/png", "image 3"); });
  EXPECT_EQ(printed, "");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where, "image 3");
  EXPECT_EQ(r.error().line().find('\n'), std::string::npos);
}

TEST_F(ImageIo, UnwritableDirectoryIsAnErrorAndLeavesNoFile) {
  const std::string path = file("no/such/dir/out.png");
  const Status s = writeImage(path, pattern(2, 2));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().where, path);
  EXPECT_NE(s.error().line().find(path), std::string::npos);
  EXPECT_FALSE(fs::exists(file("no")));
  EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIo, FailedRenameRemovesTheTemporary) {
  fs::create_directory(file("taken.png"));  // a directory where the file should go
  const Status s = writeImage(file("taken.png"), pattern(3, 3));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(listing(), std::vector<std::string>{"taken.png"});
  EXPECT_TRUE(fs::is_directory(file("taken.png")));
}

TEST_F(ImageIo, UnsupportedExtensionIsAnError) {
  for (const std::string name : {"x.foo", "noextension"}) {
    const Status s = writeImage(file(name), pattern(2, 2));
    ASSERT_FALSE(s.ok()) << name;
    EXPECT_EQ(s.error().where, file(name));
  }
  EXPECT_NE(writeImage(file("x.foo"), pattern(1, 1)).error().what.find(".foo"), std::string::npos);
  EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIo, EmptyImageIsAnError) {
  EXPECT_FALSE(writeImage(file("e.png"), raster::ImageRgba8()).ok());
  EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIo, MissingOrInvalidFileIsAnError) {
  Result<raster::ImageRgba8> r = readImageRgba8(file("missing.png"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where, file("missing.png"));
  std::ofstream(file("bad.png")) << "not an image";
  Result<raster::ImageRgba8> b = readImageRgba8(file("bad.png"));
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().where, file("bad.png"));
  EXPECT_EQ(b.error().line().find('\n'), std::string::npos);
}

// Our PNG encoder against OpenImageIO's decoder (libpng), for every channel count and sizes from
// one pixel to several IDAT chunks, on content that makes every row filter the cheapest somewhere
// (the filter types are read back from the inflated data: each must have been used and decoded).
TEST(PngEncoder, OpenImageIOsDecoderReadsBackThePixelsWithEveryFilter) {
  int used[5] = {0, 0, 0, 0, 0};
  for (int channels = 1; channels <= 4; ++channels)
    for (const auto& [w, h] :
         std::vector<std::pair<int, int>>{{1, 1}, {7, 1}, {1, 9}, {61, 37}, {300, 230}}) {
      // Rows of the same value (Up), horizontal ramps (Sub), diagonal ramps (Average, Paeth), noise (None).
      const size_t rowBytes = static_cast<size_t>(w * channels) + 3;  // padded rows
      std::vector<uint8_t> px(rowBytes * static_cast<size_t>(h), 0xEE);
      uint32_t state = 12345u + static_cast<uint32_t>(channels * 7919 + w);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < channels; ++c) {
            state = state * 1664525u + 1013904223u;
            const int band = (y / 6) % 5;
            const int v = band == 0   ? 77 + c
                          : band == 1 ? 3 * x + c
                          : band == 2 ? x + 2 * y + 5 * c
                          : band == 3 ? (x * x + y * 3) / 4 + c
                                      : static_cast<int>(state >> 24);
            px[static_cast<size_t>(y) * rowBytes + static_cast<size_t>(x * channels + c)] =
                static_cast<uint8_t>(v);
          }
      const std::string png = encodePng(w, h, channels, px.data(), rowBytes);
      // The same bytes at any thread count (the 300-pixel-wide images are deflated in several bands).
      std::string alone;
      tbb::task_arena(1).execute([&] { alone = encodePng(w, h, channels, px.data(), rowBytes); });
      EXPECT_EQ(png, alone);
      Result<raster::ImageRgba8> back = decodeTexture(reinterpret_cast<const unsigned char*>(png.data()),
                                                      png.size(), "image/png", "encoded");
      ASSERT_TRUE(back.ok()) << back.error().line();
      ASSERT_EQ(back->width(), w);
      ASSERT_EQ(back->height(), h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const uint8_t* s = &px[static_cast<size_t>(y) * rowBytes + static_cast<size_t>(x * channels)];
          const Rgba8 want = channels == 1   ? Rgba8{s[0], s[0], s[0], 255}
                             : channels == 2 ? Rgba8{s[0], s[0], s[0], s[1]}
                             : channels == 3 ? Rgba8{s[0], s[1], s[2], 255}
                                             : Rgba8{s[0], s[1], s[2], s[3]};
          ASSERT_EQ(back->at(x, y), want)
              << channels << " channels, " << w << "x" << h << ", pixel " << x << ", " << y;
        }
      // The filter byte of every row, from the concatenated IDAT data.
      std::string idat;
      for (size_t at = 8; at + 12 <= png.size();) {
        const auto* b = reinterpret_cast<const unsigned char*>(png.data() + at);
        const size_t len = (size_t{b[0]} << 24) | (size_t{b[1]} << 16) | (size_t{b[2]} << 8) | b[3];
        if (png.compare(at + 4, 4, "IDAT") == 0) idat.append(png, at + 8, len);
        at += 12 + len;
      }
      std::vector<unsigned char> raw((static_cast<size_t>(w * channels) + 1) * static_cast<size_t>(h));
      uLongf rawSize = raw.size();
      ASSERT_EQ(uncompress(raw.data(), &rawSize, reinterpret_cast<const Bytef*>(idat.data()), idat.size()),
                Z_OK);
      ASSERT_EQ(rawSize, raw.size());
      for (int y = 0; y < h; ++y) {
        const unsigned f = raw[static_cast<size_t>(y) * (static_cast<size_t>(w * channels) + 1)];
        ASSERT_LE(f, 4u);
        ++used[f];
      }
    }
  for (int f = 0; f <= 4; ++f) EXPECT_GT(used[f], 0) << "filter " << f << " never chosen";
}

}  // namespace
}  // namespace penumbra::engine
