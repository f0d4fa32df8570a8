// DepthTarget: a float depth image plus its coarse depth (min and max of every 8x8 block), which
// the tile stage uses to reject blocks hidden behind what is already drawn. The coarse record is
// conservative: it always bounds the depths actually stored in the block (padding included).
//
// Thread-safety: not thread-safe; the rasterizer gives each tile (and so each block) to one task.
#pragma once

#include <vector>

#include "raster/conventions.h"
#include "raster/image.h"

namespace penumbra::raster {

class DepthTarget {
 public:
  DepthTarget() = default;
  DepthTarget(int width, int height, float clearValue = 1.0f) { resize(width, height, clearValue); }

  void resize(int width, int height, float clearValue = 1.0f);
  // As resize, the depths written by TBB's tasks in the calling arena (Image::resizeParallel).
  void resizeParallel(int width, int height, float clearValue = 1.0f);
  // Sets every depth (padding included) and the coarse record to `value`. Tile-parallel in the
  // calling TBB arena.
  void clear(float value);
  // Sets the outermost depths on the sides in `sides` (bits: 1 column 0, 2 column width - 1, 4 row
  // 0, 8 row height - 1) to `value`, the coarse record of their blocks widened to keep bounding them.
  void fillBorder(float value, unsigned sides = 15u);

  int width() const { return depth_.width(); }
  int height() const { return depth_.height(); }
  int blocksX() const { return blocksX_; }
  int blocksY() const { return blocksY_; }
  ImageFloat& image() { return depth_; }
  const ImageFloat& image() const { return depth_; }
  float at(int x, int y) const { return depth_.at(x, y); }

  float* blockMin() { return blockMin_.data(); }
  float* blockMax() { return blockMax_.data(); }

 private:
  void resizeBlocks(float clearValue);  // the coarse record for depth_'s size, every block at clearValue

  ImageFloat depth_;
  int blocksX_ = 0, blocksY_ = 0;
  std::vector<float> blockMin_, blockMax_;
};

}  // namespace penumbra::raster
