#include "engine/png_encoder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
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

// The filtered byte of filter F for x = cur[i], a = the byte bpp to the left, b = above, c = above
// left (0 beyond the row's start).
template <int F>
uint8_t filterByte(int x, int a, int b, int c) {
  if constexpr (F == 1) return static_cast<uint8_t>(x - a);
  if constexpr (F == 2) return static_cast<uint8_t>(x - b);
  if constexpr (F == 3) return static_cast<uint8_t>(x - ((a + b) >> 1));
  if constexpr (F == 4) return static_cast<uint8_t>(x - paeth(a, b, c));
  return static_cast<uint8_t>(x);
}

// Row `cur` (`prev` the row above, zeros for the first) filtered with filter type F into out[1..];
// out[0] = F. The sum of the filtered bytes as signed magnitudes. (One loop per filter and the
// row's first pixel apart: the loops have no branch and vectorize.)
template <int F>
unsigned filterRow(const uint8_t* cur, const uint8_t* prev, size_t n, size_t bpp, uint8_t* out) {
  out[0] = static_cast<uint8_t>(F);
  unsigned sum = 0;
  const size_t head = std::min(bpp, n);
  for (size_t i = 0; i < head; ++i) {
    const uint8_t v = filterByte<F>(cur[i], 0, prev[i], 0);
    out[i + 1] = v;
    sum += v < 128 ? v : 256u - v;
  }
  for (size_t i = head; i < n; ++i) {
    const uint8_t v = filterByte<F>(cur[i], cur[i - bpp], prev[i], prev[i - bpp]);
    out[i + 1] = v;
    sum += v < 128 ? v : 256u - v;
  }
  return sum;
}

using FilterFn = unsigned (*)(const uint8_t*, const uint8_t*, size_t, size_t, uint8_t*);
constexpr FilterFn kFilters[5] = {&filterRow<0>, &filterRow<1>, &filterRow<2>, &filterRow<3>, &filterRow<4>};

// Deflates `size` bytes at `in` as raw deflate data (no zlib header), continuing a stream whose
// previous `dictSize` bytes end at `in`: a band of rows, Z_SYNC_FLUSH-ed so that bands concatenate
// (the last one Z_FINISH-ed), as pigz does.
std::string deflateBand(const uint8_t* in, size_t size, size_t dictSize, bool last) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::bad_alloc();
  if (dictSize > 0) deflateSetDictionary(&z, in - dictSize, static_cast<uInt>(dictSize));
  std::string out;
  unsigned char buffer[1 << 16];
  z.next_in = const_cast<uint8_t*>(in), z.avail_in = static_cast<uInt>(size);
  const int flush = last ? Z_FINISH : Z_SYNC_FLUSH;
  int rc = Z_OK;
  do {
    z.next_out = buffer, z.avail_out = sizeof buffer;
    rc = deflate(&z, flush);
    out.append(reinterpret_cast<const char*>(buffer), sizeof buffer - z.avail_out);
  } while (z.avail_out == 0 || (last && rc != Z_STREAM_END));
  deflateEnd(&z);
  return out;
}

}  // namespace

std::string encodePng(int width, int height, int channels, const uint8_t* data, size_t rowBytes) {
  if (width < 1 || height < 1 || channels < 1 || channels > 4)
    throw std::invalid_argument("encodePng: empty image or channel count not 1-4");
  static constexpr unsigned char kColorType[] = {0, 4, 2, 6};  // gray, gray+alpha, RGB, RGBA
  const auto w = static_cast<uint32_t>(width), h = static_cast<uint32_t>(height);
  const size_t bpp = static_cast<size_t>(channels), n = bpp * w, stride = n + 1;

  // Every row filtered (rows are independent: a filter reads the row above unfiltered).
  std::vector<uint8_t> filtered(stride * h), zero(n, 0);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, h, 16), [&](const tbb::blocked_range<uint32_t>& rows) {
    std::vector<uint8_t> trial(stride);
    for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
      const uint8_t* cur = data + y * rowBytes;
      const uint8_t* prev = y > 0 ? data + (y - 1) * rowBytes : zero.data();
      uint8_t* best = filtered.data() + y * stride;
      unsigned least = kFilters[0](cur, prev, n, bpp, best);
      for (int f = 1; f <= 4; ++f) {
        const unsigned s = kFilters[f](cur, prev, n, bpp, trial.data());
        if (s < least) least = s, std::copy(trial.begin(), trial.end(), best);
      }
    }
  });
  // Deflated in bands of about 128 KiB, each primed with the 32 KiB before it: the same bytes at any
  // thread count (the bands depend on the image alone), in a zlib wrapper whose checksum covers all.
  const size_t total = filtered.size();
  const size_t band = std::max<size_t>(1, (size_t{1} << 17) / stride) * stride;
  const size_t bands = (total + band - 1) / band;
  std::vector<std::string> parts(bands);
  tbb::parallel_for(size_t{0}, bands, [&](size_t k) {
    const size_t at = k * band;
    parts[k] = deflateBand(filtered.data() + at, std::min(band, total - at), std::min<size_t>(at, 32768),
                           k + 1 == bands);
  });
  std::string idat("\x78\x9c", 2);  // deflate, 32 KiB window, default level; no preset dictionary
  for (const std::string& p : parts) idat += p;
  const uLong adler = adler32_z(adler32(0L, Z_NULL, 0), filtered.data(), total);
  putU32(idat, static_cast<uint32_t>(adler));

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
  constexpr size_t kChunk = size_t{1} << 16;
  for (size_t at = 0; at < idat.size(); at += kChunk)
    putChunk(out, "IDAT", z8 + at, std::min(kChunk, idat.size() - at));
  putChunk(out, "IEND", nullptr, 0);
  return out;
}

}  // namespace penumbra::engine
