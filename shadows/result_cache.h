// A store of visibility images computed before, by a key that hashes everything they depend on
// (the ground truth's cache: groundTruthKey). shadows/ touches no files itself: the engine hands a
// technique one backed by a folder (engine/result_cache.h), tests one in memory.
//
// Thread-safety: a technique calls it from one thread at a time; implementations need not lock.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "raster/image.h"

namespace penumbra::shadows {

class ResultCache {
 public:
  virtual ~ResultCache() = default;
  // The image stored under key when it is there, whole and width x height; else nothing.
  virtual std::optional<raster::ImageFloat> load(uint64_t key, int width, int height) = 0;
  // Stores the image under key; why it could not (the computation stands anyway), or nothing.
  virtual std::optional<std::string> store(uint64_t key, const raster::ImageFloat& image) = 0;
  // How the entry of a key is named in notes and reports ("gt-0123456789abcdef.bin").
  virtual std::string name(uint64_t key) const = 0;
};

}  // namespace penumbra::shadows
