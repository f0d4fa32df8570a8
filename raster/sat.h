// Multi-channel summed-area tables for the pre-filtered soft shadows (ESSM, SAVSM, VSSM, CSSM):
// float, double and exact-integer tables over several channels at once, box queries at fractional
// texel coordinates, the SAT tile grid (STG) of Shen, Feng & Yang, "Exponential Soft Shadow
// Mapping" (EGSR 2013, section 6), and multi-channel mip chains sampled trilinearly (post-filtered
// soft VSM). The single-channel tables, min/max pyramids and blurs are in kernels.h.
//
// Conventions
// - Planes<T>: width x height pixels of `channels` values each, interleaved (pixel-major), row 0 at
//   the top. Texel (i, j) covers the continuous square [i, i + 1) x [j, j + 1).
// - Box queries take a continuous box [x0, x1) x [y0, y1) in those coordinates, clamped to the
//   image, and return the exact integral of the piecewise-constant image over it: each texel
//   weighted by the area of its square inside the box. The result is the area-weighted sum per
//   channel; the function returns the box's area after clamping (0: empty, sums 0).
// - A box query splits the box at the texel borders of its first and last column and row: the
//   inner rectangle and the eight partial strips and corners are integer rectangles of the table,
//   each differenced in the table's own arithmetic (modulo 2^64 for the integer table), then
//   weighted in double. So the integer table's query is exact up to the final double weighting
//   (relative error ~1e-16 of the box's own sum, never of the table's total).
//
// Precision (ESSM section 6; measured by `penumbra stress --suite shadows`):
// - float table: entries carry 24 bits; an entry near the far corner holds the sum of up to w*h
//   values, so a small box's sum keeps about 24 - log2(w*h) bits of its values (23 + the hidden
//   bit, minus the accumulation): at 4096^2 nothing is left (24 - 24 = 0).
// - double table: 53 - log2(w*h) bits, 29 at 4096^2 (relative to the values' scale).
// - integer table: values quantized to `bits` (raster::quantize) and summed exactly modulo 2^64:
//   exact for any box whose true sum is below 2^63 (bits <= 24 and up to 2^39 pixels; the
//   difference goes to double through int64), the quantization step (range / (2^bits - 1), half
//   of it per texel) the only error.
// - tiled table (STG): T x T tiles, each with its own range [lo, hi] per channel (its texels'
//   exact min and max) quantized to `bits` and summed in uint32. A tile's sums stay below 2^32
//   when T^2 (2^bits - 1) < 2^32, so T = 2^floor((32 - bits) / 2) (bits 20: T = 64; 16: 256). A
//   query splits at tile borders and adds each tile's part in double: the error is at most half a
//   step of each tile it touches, (hi_t - lo_t) / (2 (2^bits - 1)) per texel, relative to the
//   tile's own range rather than the whole map's (the STG's point: a dark tile beside a bright one
//   keeps its digits). Per-tile ranges are Penumbra's addition; the paper normalizes globally and
//   chooses T from a pyramid of the values, which a per-tile range makes unnecessary (every tile's
//   values are then in [0, 2^bits - 1] by construction).
//
// Determinism: every entry is computed by one fixed sequence of operations (rows, then strips of
// columns, as kernels.h); results are bit-identical at any thread count.
// Thread-safety: builders run tbb::parallel_for in the caller's arena; built tables are immutable
// values, safe to query from any number of threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "raster/image.h"

namespace penumbra::raster {

template <class T>
struct Planes {
  int width = 0, height = 0, channels = 0;
  std::vector<T> data;  // width * height * channels

  Planes() = default;
  Planes(int w, int h, int c) : width(w), height(h), channels(c), data(static_cast<size_t>(w) * h * c) {}
  T* pixel(int x, int y) { return data.data() + (static_cast<size_t>(y) * width + x) * channels; }
  const T* pixel(int x, int y) const { return data.data() + (static_cast<size_t>(y) * width + x) * channels; }
};

inline constexpr int kMaxSatChannels = 34;  // CSSM: 4 M + 2 at M = 8

// S(x, y) per channel = sum over [0, x) x [0, y), x in [0, w], y in [0, h]; Sum is float, double or
// uint64_t (modulo 2^64).
template <class Sum>
struct MultiSat {
  int width = 0, height = 0, channels = 0;
  std::vector<Sum> sums;  // (width + 1) x (height + 1) entries of `channels` values

  const Sum* entry(int x, int y) const {
    return sums.data() + (static_cast<size_t>(y) * static_cast<size_t>(width + 1) + static_cast<size_t>(x)) *
                             static_cast<size_t>(channels);
  }
  // Area-weighted sums over the continuous box (see the conventions); out has `channels` values.
  double boxSum(double x0, double y0, double x1, double y1, double* out) const;
  // A bound on the rounding error of boxSum's or gridSums' results inside [0, x1) x [0, y1), for
  // non-negative inputs: 4 (w + h) u S(x1, y1) per channel, u = 2^-24 (float), 2^-53 (double), 0
  // (integer: exact; the quantization step is the caller's). Entries hold at most (w + h) roundings
  // of at most S(x1, y1) each, and a query differences four of them.
  void roundingBound(double x1, double y1, double* bound) const;
  // The box split into n x n equal sub-boxes (n in [1, 8]): out[(j * n + i) * channels + c] is
  // sub-box (i, j)'s sum of channel c, area[j * n + i] its area after clamping. One pass over the
  // (n + 1)^2 grid points instead of n^2 separate queries, exact in the same sense.
  void gridSums(double x0, double y0, double x1, double y1, int n, double* out, double* area) const;
};

MultiSat<float> buildSatFloat(const Planes<float>& src);
MultiSat<double> buildSatDouble(const Planes<float>& src);
MultiSat<uint64_t> buildSatInteger(const Planes<uint32_t>& src);

// Per channel fixed point: q = round((v - lo[c]) / (hi[c] - lo[c]) * (2^bits - 1)), clamped (NaN
// gives 0), bits in [1, 24]; a channel with hi <= lo quantizes to 0. The value of q is
// lo + q * step, step = (hi - lo) / (2^bits - 1).
Planes<uint32_t> quantizePlanes(const Planes<float>& src, const std::vector<double>& lo,
                                const std::vector<double>& hi, int bits);

// The SAT tile grid. tileNeeded (tilesX * tilesY flags, row-major; empty = all) says which tiles to
// build: the others are skipped (queries must not reach them; a query that does gets NaN).
struct TiledSat {
  int width = 0, height = 0, channels = 0, tile = 0, bits = 0, tilesX = 0, tilesY = 0;
  size_t tilesBuilt = 0;
  std::vector<uint8_t> built;    // per tile
  std::vector<double> lo, step;  // per tile per channel
  std::vector<uint32_t> sums;    // per tile (tile + 1)^2 entries of `channels` values (built tiles only)
  std::vector<uint32_t> offset;  // per tile: index of its first entry / entry size, or ~0u

  // bound (optional, `channels` values): the quantization error bound of each channel's sum, half
  // a step of each tile per unit of area it contributes.
  double boxSum(double x0, double y0, double x1, double y1, double* out, double* bound = nullptr) const;
  // The box split into n x n equal sub-boxes (n in [1, 8]), laid out as MultiSat::gridSums, and
  // bound (optional, n * n * channels values) as boxSum's per sub-box. Each tile the box touches
  // is read once for the parts of every sub-box inside it (the tile's integral at the grid points,
  // bilinear in its entries), not once per sub-box: the same sums as n^2 boxSum calls to the
  // rounding of that double arithmetic (relative to the tile's sums, which are below 2^32: about
  // 2^-20 of a quantization step, against the bound's half step per texel).
  void gridSums(double x0, double y0, double x1, double y1, int n, double* out, double* area,
                double* bound = nullptr) const;
};
// T = 2^floor((32 - bits) / 2): T^2 (2^bits - 1) < 2^32 (bits in [1, 24]).
int stgTileSize(int bits);
TiledSat buildTiledSat(const Planes<float>& src, int bits, const std::vector<uint8_t>& tileNeeded = {});
// The same from a generator instead of a whole image: fill(x0, y0, w, h, out) writes the `channels`
// values of each texel of [x0, x0 + w) x [y0, y0 + h), row-major, into out. It is called once per
// built tile, from several threads at once, so only the tiles that are needed are ever computed
// (the same table as from the image the generator describes).
using TileFill = std::function<void(int x0, int y0, int w, int h, float* out)>;
TiledSat buildTiledSat(int width, int height, int channels, int bits, const TileFill& fill,
                       const std::vector<uint8_t>& tileNeeded = {});

// Box-filtered mip chain of a four-channel image (the conventions of kernels.h: ceil halving, each
// texel the mean in double of its 1, 2 or 4 children).
std::vector<ImageFloat4> mipChain4(const ImageFloat4& src);
// Trilinear lookup at level-0 continuous coordinates (texel centres at +0.5) and fractional level
// (clamped to the chain): bilinear in the two nearest levels (a level-k texel i has its centre at
// (i + 0.5) 2^k), edge texels clamped, then linear between the levels; in double.
std::array<double, 4> sampleTrilinear(const std::vector<ImageFloat4>& mips, double x, double y, double level);

}  // namespace penumbra::raster
