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

}  // namespace penumbra::raster
