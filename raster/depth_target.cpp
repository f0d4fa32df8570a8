#include "raster/depth_target.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace penumbra::raster {

void DepthTarget::resize(int width, int height, float clearValue) {
  depth_.resize(width, height, clearValue);
  resizeBlocks(clearValue);
}

void DepthTarget::resizeParallel(int width, int height, float clearValue) {
  depth_.resizeParallel(width, height, clearValue);
  resizeBlocks(clearValue);
}

void DepthTarget::resizeBlocks(float clearValue) {
  blocksX_ = depth_.stride() / kBlockSize;
  blocksY_ = depth_.paddedRows() / kBlockSize;
  blockMin_.assign(static_cast<size_t>(blocksX_) * static_cast<size_t>(blocksY_), clearValue);
  blockMax_ = blockMin_;
}

void DepthTarget::clear(float value) {
  const int rows = depth_.paddedRows();
  const size_t stride = static_cast<size_t>(depth_.stride());
  float* data = depth_.data();
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 64), [&](const tbb::blocked_range<int>& r) {
    std::fill(data + static_cast<size_t>(r.begin()) * stride, data + static_cast<size_t>(r.end()) * stride, value);
  });
  std::fill(blockMin_.begin(), blockMin_.end(), value);
  std::fill(blockMax_.begin(), blockMax_.end(), value);
}

void DepthTarget::fillBorder(float value, unsigned sides) {
  const int w = depth_.width(), h = depth_.height();
  if (w <= 0 || h <= 0) return;
  const auto set = [&](int x, int y) {
    depth_.at(x, y) = value;
    const size_t b = static_cast<size_t>(y / kBlockSize) * static_cast<size_t>(blocksX_) +
                     static_cast<size_t>(x / kBlockSize);
    blockMin_[b] = std::min(blockMin_[b], value);
    blockMax_[b] = std::max(blockMax_[b], value);
  };
  for (int x = 0; x < w; ++x) {
    if (sides & 4u) set(x, 0);
    if (sides & 8u) set(x, h - 1);
  }
  for (int y = 0; y < h; ++y) {
    if (sides & 1u) set(0, y);
    if (sides & 2u) set(w - 1, y);
  }
}

}  // namespace penumbra::raster
