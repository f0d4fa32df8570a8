#include "engine/png_encoder.h"

#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <vector>

namespace penumbra::engine {
namespace {

void putU32(std::string& out, uint32_t v) {
  out.push_back(static_cast<char>(v >> 24)), out.push_back(static_cast<char>(v >> 16));
  out.push_back(static_cast<char>(v >> 8)), out.push_back(static_cast<char>(v));
}

// A chunk: length, type, data, CRC of type and data.
void putChunk(std::string& out, const char* type, const unsigned char* data, size_t size) {
  putU32(out, static_cast<uint32_t>(size));
  const size_t start = out.size();
  out.append(type, 4);
  if (size > 0) out.append(reinterpret_cast<const char*>(data), size);
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(out.data() + start), 4 + size);
  putU32(out, static_cast<uint32_t>(crc));
}

uint8_t paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return static_cast<uint8_t>(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

// Row `cur` (`prev` the row above, zeros for the first) filtered with filter type f into out[1..];
// out[0] = f. The sum of the filtered bytes as signed magnitudes.
unsigned filterRow(int f, const uint8_t* cur, const uint8_t* prev, size_t n, size_t bpp, uint8_t* out) {
  out[0] = static_cast<uint8_t>(f);
  unsigned sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const int a = i >= bpp ? cur[i - bpp] : 0, b = prev[i], c = i >= bpp ? prev[i - bpp] : 0;
    uint8_t v = cur[i];
    switch (f) {
      case 1:
        v = static_cast<uint8_t>(v - a);
        break;
      case 2:
        v = static_cast<uint8_t>(v - b);
        break;
      case 3:
        v = static_cast<uint8_t>(v - ((a + b) >> 1));
        break;
      case 4:
        v = static_cast<uint8_t>(v - paeth(a, b, c));
        break;
      default:
        break;
    }
    out[i + 1] = v;
    sum += v < 128 ? v : 256u - v;
  }
  return sum;
}

}  // namespace

std::string encodePng(int width, int height, int channels, const uint8_t* data, size_t rowBytes) {
  if (width < 1 || height < 1 || channels < 1 || channels > 4)
    throw std::invalid_argument("encodePng: empty image or channel count not 1-4");
  static constexpr unsigned char kColorType[] = {0, 4, 2, 6};  // gray, gray+alpha, RGB, RGBA
  const auto w = static_cast<uint32_t>(width), h = static_cast<uint32_t>(height);
  const size_t bpp = static_cast<size_t>(channels), n = bpp * w;

  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, 15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::bad_alloc();
  std::string idat;
  std::vector<uint8_t> zero(n, 0), best(n + 1), trial(n + 1);
  unsigned char buffer[1 << 16];
  // Feeds `in` to deflate (the last row with Z_FINISH), appending what comes out to idat.
  auto feed = [&](uint8_t* in, size_t size, int flush) {
    z.next_in = in, z.avail_in = static_cast<uInt>(size);
    int rc = Z_OK;
    do {
      z.next_out = buffer, z.avail_out = sizeof buffer;
      rc = deflate(&z, flush);
      idat.append(reinterpret_cast<const char*>(buffer), sizeof buffer - z.avail_out);
    } while (z.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
  };
  for (uint32_t y = 0; y < h; ++y) {
    const uint8_t* cur = data + y * rowBytes;
    const uint8_t* prev = y > 0 ? data + (y - 1) * rowBytes : zero.data();
    unsigned least = filterRow(0, cur, prev, n, bpp, best.data());
    for (int f = 1; f <= 4; ++f) {
      const unsigned s = filterRow(f, cur, prev, n, bpp, trial.data());
      if (s < least) least = s, best.swap(trial);
    }
    feed(best.data(), n + 1, y + 1 == h ? Z_FINISH : Z_NO_FLUSH);
  }
  deflateEnd(&z);

  std::string out("\x89PNG\r\n\x1a\n", 8);
  unsigned char ihdr[13];
  for (int i = 0; i < 4; ++i) {
    ihdr[i] = static_cast<unsigned char>(w >> (24 - 8 * i));
    ihdr[4 + i] = static_cast<unsigned char>(h >> (24 - 8 * i));
  }
  ihdr[8] = 8;  // bits per sample
  ihdr[9] = kColorType[channels - 1];
  ihdr[10] = ihdr[11] = ihdr[12] = 0;  // deflate, adaptive filtering, no interlace
  putChunk(out, "IHDR", ihdr, sizeof ihdr);
  const auto* z8 = reinterpret_cast<const unsigned char*>(idat.data());
  for (size_t at = 0; at < idat.size(); at += sizeof buffer)
    putChunk(out, "IDAT", z8 + at, std::min(sizeof buffer, idat.size() - at));
  putChunk(out, "IEND", nullptr, 0);
  return out;
}

}  // namespace penumbra::engine
