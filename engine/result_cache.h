// The folder the ground truth keeps its images in between runs (shadows/result_cache.h backed by
// files): entry <folder>/gt-<key as 16 lower-case hex digits>.bin.
//
// File layout (native byte order, x86-64: little-endian): a 40-byte header
//     char magic[8] = "PNBRGT\r\n", uint32 version, uint32 width, uint32 height, uint32 zero,
//     uint64 key, uint64 payload checksum (FNV-1a 64 of the float bytes),
// then width * height float32 values, row-major, top row first. A file is used only when it is a
// regular file of exactly that size and every field matches; anything else is a miss (a corrupt
// or foreign file is never an error, and never read past its size). Entries are written whole or
// not at all (atomic_file.h), the folder created on the first one.
//
// Thread-safety: one object per user; several processes may share a folder (entries are renamed
// into place).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "engine/error.h"
#include "shadows/result_cache.h"

namespace penumbra::engine {

class FileResultCache final : public shadows::ResultCache {
 public:
  explicit FileResultCache(std::filesystem::path folder) : folder_(std::move(folder)) {}
  std::optional<raster::ImageFloat> load(uint64_t key, int width, int height) override;
  std::optional<std::string> store(uint64_t key, const raster::ImageFloat& image) override;
  std::string name(uint64_t key) const override;
  std::filesystem::path path(uint64_t key) const { return folder_ / name(key); }

 private:
  std::filesystem::path folder_;
};

// Whether `folder` can be a cache: an existing directory, or a path whose nearest existing
// ancestor is a writable directory (the folders between are created on the first entry). The
// Error names `option` ("option --cache").
Status checkCacheFolder(const std::string& folder, const std::string& option);

}  // namespace penumbra::engine
