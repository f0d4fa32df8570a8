// Image<T>: a 2D array of pixels, row 0 at the top, x to the right.
//
// Storage is padded: the row stride and the allocated row count are rounded up to a multiple of
// kImagePad (8) so that the tile rasterizer can read and write whole 8-pixel rows of an 8x8 block
// without bounds checks. Pixels outside width x height exist in memory but are never part of the
// image (they are never covered, never read by kernels, never written to files).
//
// Thread-safety: not thread-safe for writes to the same pixel; distinct pixels may be written from
// distinct threads (the tile rasterizer gives each tile to one task).
#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "raster/large_pages.h"

namespace penumbra::raster {

inline constexpr int kImagePad = 8;

struct Rgba8 {
  uint8_t r = 0, g = 0, b = 0, a = 0;
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

struct Float4 {
  float r = 0, g = 0, b = 0, a = 0;
  friend bool operator==(const Float4&, const Float4&) = default;
};

template <class T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, const T& value = T{}) { resize(width, height, value); }

  void resize(int width, int height, const T& value = T{}) {
    assert(width >= 0 && height >= 0);
    width_ = width;
    height_ = height;
    stride_ = (width + kImagePad - 1) / kImagePad * kImagePad;
    rows_ = (height + kImagePad - 1) / kImagePad * kImagePad;
    data_.assign(static_cast<size_t>(stride_) * static_cast<size_t>(rows_), value);
  }
  // As resize, with the elements written by TBB's tasks in the current arena (call it inside
  // Rasterizer::run to keep its thread count): the first touch of a frame-sized image -- its page
  // faults and the kernel's zeroing -- is spread over the threads instead of taken by one.
  void resizeParallel(int width, int height, const T& value = T{}) {
    assert(width >= 0 && height >= 0);
    width_ = width;
    height_ = height;
    stride_ = (width + kImagePad - 1) / kImagePad * kImagePad;
    rows_ = (height + kImagePad - 1) / kImagePad * kImagePad;
    data_ = {};
    data_.resize(static_cast<size_t>(stride_) * static_cast<size_t>(rows_));  // not written (large_pages.h)
    tbb::parallel_for(tbb::blocked_range<int>(0, rows_, kImagePad), [&](const tbb::blocked_range<int>& r) {
      std::fill(row(r.begin()), row(r.begin()) + static_cast<size_t>(r.size()) * static_cast<size_t>(stride_), value);
    });
  }
  void fill(const T& value) { std::fill(data_.begin(), data_.end(), value); }

  int width() const { return width_; }
  int height() const { return height_; }
  int stride() const { return stride_; }   // elements between rows (>= width, multiple of 8)
  int paddedRows() const { return rows_; }  // allocated rows (>= height, multiple of 8)
  bool empty() const { return width_ == 0 || height_ == 0; }

  T& at(int x, int y) {
    assert(x >= 0 && y >= 0 && x < stride_ && y < rows_);
    return data_[static_cast<size_t>(y) * static_cast<size_t>(stride_) + static_cast<size_t>(x)];
  }
  const T& at(int x, int y) const {
    assert(x >= 0 && y >= 0 && x < stride_ && y < rows_);
    return data_[static_cast<size_t>(y) * static_cast<size_t>(stride_) + static_cast<size_t>(x)];
  }
  T* row(int y) { return data_.data() + static_cast<size_t>(y) * static_cast<size_t>(stride_); }
  const T* row(int y) const { return data_.data() + static_cast<size_t>(y) * static_cast<size_t>(stride_); }
  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }

  // Visible pixels only (padding excluded), row-major, tightly packed.
  std::vector<T> packed() const {
    std::vector<T> out;
    out.reserve(static_cast<size_t>(width_) * static_cast<size_t>(height_));
    for (int y = 0; y < height_; ++y) out.insert(out.end(), row(y), row(y) + width_);
    return out;
  }

 private:
  int width_ = 0, height_ = 0, stride_ = 0, rows_ = 0;
  std::vector<T, LargePageAllocator<T>> data_;  // large images on huge pages (large_pages.h)
};

using ImageRgba8 = Image<Rgba8>;
using ImageFloat4 = Image<Float4>;
using ImageFloat = Image<float>;

}  // namespace penumbra::raster
