// Image kernels: separable blurs, summed-area tables (double and exact integer), min/max
// pyramids and box-filtered mip chains, the building blocks of pre-filtered shadows (DESIGN.md,
// "The pipeline", item 8).
//
// Conventions
// - Images are Image<T> (raster/image.h): row 0 at the top, x to the right. Kernels read and write
//   only the visible width x height pixels, never the padding.
// - Rectangles are inclusive-exclusive, [x0, x1) x [y0, y1) in pixels, clamped to the image; an
//   empty rectangle (after clamping) sums to 0 and has bounds (+inf, -inf).
// - Blurs address out-of-image pixels by clamping to the nearest edge pixel.
// - Pyramids and mips halve each dimension rounding up: level k+1 is ceil(w/2) x ceil(h/2) of level
//   k, down to 1x1 (13x7 -> 7x4 -> 4x2 -> 2x1 -> 1x1). Texel (i, j) of level k+1 has the children
//   (2i..2i+1, 2j..2j+1) of level k that exist (1, 2 or 4 of them), so it covers the pixels
//   [i*2^(k+1), (i+1)*2^(k+1)) x [j*2^(k+1), (j+1)*2^(k+1)) clamped to the image.
//
// Determinism: every output value is computed by one fixed sequence of operations that does not
// depend on how TBB splits the work, so results are bit-identical at any thread count. There are
// no floating-point reductions across tasks.
//
// Thread-safety: pure functions. Each runs tbb::parallel_for over rows (or strips of columns) in
// the caller's task arena (so inside Rasterizer::run it uses the rasterizer's threads). Distinct
// calls may run concurrently on distinct outputs. The built tables and pyramids are plain values,
// immutable after build, safe to query from any number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/image.h"

namespace penumbra::raster {

// --- Blurs -------------------------------------------------------------------------------------
// Separable: a horizontal pass into a float temporary, then a vertical pass into dst. Each pass
// accumulates in double in a fixed order, so a blur is within a few float ulps of the exact 2D
// convolution. dst is resized to src's size; src and dst may be the same image.

// Limits, validated (std::invalid_argument outside them). A radius of 1024 is a 2049-tap window;
// sigma 300 gives a 901-tap Gaussian. Both are far beyond any shadow-map filter we use.
inline constexpr int kMaxBlurRadius = 1024;
inline constexpr float kMaxBlurSigma = 300.0f;

// Box filter of width 2*radius+1 in x and in y (mean over the window), radius in [0, 1024];
// radius 0 copies. O(1) per pixel (running window sums in double).
void boxBlur(const ImageFloat& src, ImageFloat& dst, int radius);

// Gaussian filter, sigma in pixels in [0, 300]; sigma 0 copies. Taps k in [-r, r] with
// r = ceil(3 sigma), weights w_k = exp(-k^2 / (2 sigma^2)) / sum_j exp(-j^2 / (2 sigma^2)).
void gaussianBlur(const ImageFloat& src, ImageFloat& dst, float sigma);
// The same on four channels (moment shadow maps keep 2-4 moments per texel). Each channel gets
// exactly the operations of the single-channel overload, so channel c of the result equals
// gaussianBlur of channel c bit for bit.
void gaussianBlur(const ImageFloat4& src, ImageFloat4& dst, float sigma);

// --- Summed-area tables --------------------------------------------------------------------------
// S(x, y) = sum of src over [0, x) x [0, y), stored for x in [0, w], y in [0, h] (row and column 0
// are zero), so rectSum = S(x1,y1) - S(x0,y1) - S(x1,y0) + S(x0,y0) (Crow 1984).

// Double precision. Inputs convert to double exactly; each entry is a horizontal prefix over at
// most w terms then a vertical prefix over at most h terms, so |S error| <= (w + h) * 2^-53 * T
// where T = sum of |src| over the whole image (first order), and rectSum's absolute error is at
// most about (4 (w + h) + 3) * 2^-53 * T. That is a bound relative to the total, not to the
// rectangle: a small rectangle far from the origin loses the digits it shares with T. Use the
// integer table when exact differences matter.
struct SummedAreaTable {
  int width = 0, height = 0;
  std::vector<double> sums;  // (width+1) x (height+1), row-major, row stride width+1

  double at(int x, int y) const {  // S(x, y), x in [0, width], y in [0, height]
    return sums[static_cast<size_t>(y) * static_cast<size_t>(width + 1) + static_cast<size_t>(x)];
  }
  // Sum over [x0, x1) x [y0, y1), clamped to the image; 0 if empty.
  double rectSum(int x0, int y0, int x1, int y1) const;
};
SummedAreaTable buildSat(const ImageFloat& src);

// Exact integer table. Entries are kept modulo 2^64 and rectSum combines them modulo 2^64, so
// rectSum is exact whenever the rectangle's true sum is below 2^64, even if entries near the far
// corner wrapped. With 24-bit inputs (at most 2^24 - 1 each) that holds for every rectangle of up
// to 2^40 pixels, so for any image of up to 2^40 pixels (e.g. 1048576 x 1048576): the whole-image
// total is at most (2^24 - 1) * 2^40 < 2^64 and no entry ever wraps.
struct SummedAreaTableU64 {
  int width = 0, height = 0;
  std::vector<uint64_t> sums;  // (width+1) x (height+1), row-major, row stride width+1

  uint64_t at(int x, int y) const {
    return sums[static_cast<size_t>(y) * static_cast<size_t>(width + 1) + static_cast<size_t>(x)];
  }
  uint64_t rectSum(int x0, int y0, int x1, int y1) const;
};
SummedAreaTableU64 buildSatU64(const Image<uint32_t>& src);

// Fixed-point quantization for the integer table: q = round((v - lo) / (hi - lo) * (2^bits - 1)),
// clamped to [0, 2^bits - 1] (NaN maps to 0), computed in double. bits in [1, 24] (24 bits is a
// float's mantissa, and keeps the U64 table exact up to 2^40 pixels); lo < hi, both finite.
// Throws std::invalid_argument otherwise.
Image<uint32_t> quantize(const ImageFloat& src, float lo, float hi, int bits);

// --- Min/max pyramid ---------------------------------------------------------------------------
// mins[k] and maxs[k] are level k (see the conventions above): level 0 is the input, each texel of
// level k+1 the min (max) of its existing children, so it is the exact min (max) of the pixels it
// covers. An empty input gives an empty pyramid. Inputs are assumed free of NaN.
struct MinMaxPyramid {
  std::vector<ImageFloat> mins, maxs;
  int levels() const { return static_cast<int>(mins.size()); }
};
MinMaxPyramid buildMinMaxPyramid(const ImageFloat& depth);

// Conservative bounds of the pixels in [x0, x1) x [y0, y1) (clamped to the image): mn <= every
// pixel's value <= mx. Uses the finest level at which the rectangle spans at most 2x2 texels and
// returns the exact min/max of those texels, so the bounds are exact when the rectangle is a single
// texel's footprint at some level (e.g. one pixel). An empty rectangle or pyramid gives
// mn = +inf, mx = -inf.
void queryMinMax(const MinMaxPyramid& pyramid, int x0, int y0, int x1, int y1, float& mn, float& mx);
// The same, and the pixel rectangle the bounds are over (the texels it read, in level-0 pixels,
// clamped to the image): covered = {x0, y0, x1, y1}, containing the query's rectangle.
void queryMinMax(const MinMaxPyramid& pyramid, int x0, int y0, int x1, int y1, float& mn, float& mx, int covered[4]);

// --- Min/max stack (multi-scale shadow map; hybrid Y shadow map) ---------------------------------
// Over the grid of pyramid level `base` (texels of 2^base pixels; base 0: the pixels themselves):
// mins[k] and maxs[k] are, at every grid texel (i, j), the min (max) of the 2^k x 2^k grid texels
// [i, i + 2^k) x [j, j + 2^k) (cut at the grid's edge), for every k while 2^(k-1) is below the
// grid's larger side: a stack of full-resolution images, not a pyramid (Schwarz & Stamminger
// 2007's multi-scale shadow map at base 0; their hybrid Y shadow map keeps the pyramid's finest
// `base` levels and this stack on level `base`). A rectangle of grid texels is the union of at most
// ceil(w / 2^k) x ceil(h / 2^k) such windows with 2^k <= min(w, h): bounds exact over the grid
// texels it touches, so tight where the pyramid's aligned texels are loose.
struct MinMaxStack {
  int base = 0, width = 0, height = 0;  // width and height: the pixels' (pyramid level 0)
  std::vector<ImageFloat> mins, maxs;
  int levels() const { return static_cast<int>(mins.size()); }
};
MinMaxStack buildMinMaxStack(const MinMaxPyramid& pyramid, int base);

// Bounds of the pixels in [x0, x1) x [y0, y1) (clamped to the image): the exact min and max over
// the grid texels the rectangle touches (its pixels exactly when base is 0). An empty rectangle or
// stack gives mn = +inf, mx = -inf. `windows` (optional) receives the number of texels read.
void queryMinMax(const MinMaxStack& stack, int x0, int y0, int x1, int y1, float& mn, float& mx,
                 int* windows = nullptr);

// --- Mip chain -----------------------------------------------------------------------------------
// Box-filtered mips: level 0 is a copy of src, each texel of level k+1 the mean (in double, then
// rounded to float) of its existing children. Children counts are 1, 2 or 4, so a constant image
// stays exactly constant. An empty input gives an empty chain.
std::vector<ImageFloat> mipChain(const ImageFloat& src);

}  // namespace penumbra::raster
