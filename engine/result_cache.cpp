#include "engine/result_cache.h"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <system_error>
#include <vector>

#include "engine/atomic_file.h"

namespace penumbra::engine {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'P', 'N', 'B', 'R', 'G', 'T', '\r', '\n'};
constexpr uint32_t kFileVersion = 2;  // 2: the checksum is FNV-1a 64
constexpr size_t kHeaderBytes = 40;

struct Header {
  uint32_t version = 0, width = 0, height = 0, zero = 0;
  uint64_t key = 0, payload = 0;
};

uint64_t checksum(const void* data, size_t bytes) {
  uint64_t h = 0xcbf29ce484222325ULL;
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
  return h;
}

}  // namespace

std::string FileResultCache::name(uint64_t key) const {
  char buf[32];
  std::snprintf(buf, sizeof buf, "gt-%016llx.bin", static_cast<unsigned long long>(key));
  return buf;
}

std::optional<raster::ImageFloat> FileResultCache::load(uint64_t key, int width, int height) {
  const fs::path file = path(key);
  std::error_code ec;
  if (width < 1 || height < 1 || !fs::is_regular_file(file, ec)) return std::nullopt;
  const uintmax_t size = fs::file_size(file, ec);
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (ec || size != kHeaderBytes + n * sizeof(float)) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  char head[kHeaderBytes];
  if (!in.read(head, kHeaderBytes)) return std::nullopt;
  Header hd;
  std::memcpy(&hd.version, head + 8, 4);
  std::memcpy(&hd.width, head + 12, 4);
  std::memcpy(&hd.height, head + 16, 4);
  std::memcpy(&hd.zero, head + 20, 4);
  std::memcpy(&hd.key, head + 24, 8);
  std::memcpy(&hd.payload, head + 32, 8);
  if (std::memcmp(head, kMagic, 8) != 0 || hd.version != kFileVersion || hd.key != key || hd.zero != 0 ||
      hd.width != static_cast<uint32_t>(width) || hd.height != static_cast<uint32_t>(height))
    return std::nullopt;
  std::vector<float> values(n);
  if (!in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(n * sizeof(float))))
    return std::nullopt;
  if (checksum(values.data(), n * sizeof(float)) != hd.payload) return std::nullopt;
  raster::ImageFloat out(width, height);
  for (int y = 0; y < height; ++y)
    std::copy_n(values.data() + static_cast<size_t>(y) * static_cast<size_t>(width), width, out.row(y));
  return out;
}

std::optional<std::string> FileResultCache::store(uint64_t key, const raster::ImageFloat& image) {
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec) return "cannot create directory " + folder_.string() + ": " + ec.message();
  const std::vector<float> values = image.packed();
  const Header hd{.version = kFileVersion,
                  .width = static_cast<uint32_t>(image.width()),
                  .height = static_cast<uint32_t>(image.height()),
                  .zero = 0,
                  .key = key,
                  .payload = checksum(values.data(), values.size() * sizeof(float))};
  std::string bytes(kHeaderBytes + values.size() * sizeof(float), '\0');
  std::memcpy(bytes.data(), kMagic, 8);
  std::memcpy(bytes.data() + 8, &hd.version, 4);
  std::memcpy(bytes.data() + 12, &hd.width, 4);
  std::memcpy(bytes.data() + 16, &hd.height, 4);
  std::memcpy(bytes.data() + 20, &hd.zero, 4);
  std::memcpy(bytes.data() + 24, &hd.key, 8);
  std::memcpy(bytes.data() + 32, &hd.payload, 8);
  std::memcpy(bytes.data() + kHeaderBytes, values.data(), values.size() * sizeof(float));
  if (Status st = writeFileAtomically(path(key), bytes); !st) return st.error().line();
  return std::nullopt;
}

Status checkCacheFolder(const std::string& folder, const std::string& option) {
  if (folder.empty()) return Error{option, "is empty (give a folder)"};
  std::error_code ec;
  fs::path p(folder);
  if (fs::exists(p, ec)) {
    if (!fs::is_directory(p, ec)) return Error{option, "'" + folder + "' is not a folder"};
    if (::access(p.c_str(), W_OK | X_OK) != 0) return Error{option, "the folder '" + folder + "' is not writable"};
    return Ok{};
  }
  // The nearest existing ancestor must be a writable folder.
  fs::path a = p.has_parent_path() ? p.parent_path() : fs::path(".");
  while (!a.empty() && !fs::exists(a, ec)) a = a.has_parent_path() && a.parent_path() != a ? a.parent_path() : fs::path();
  if (a.empty()) a = ".";
  if (!fs::is_directory(a, ec)) return Error{option, "'" + folder + "' cannot be made: '" + a.string() + "' is not a folder"};
  if (::access(a.c_str(), W_OK | X_OK) != 0)
    return Error{option, "'" + folder + "' cannot be made: '" + a.string() + "' is not writable"};
  return Ok{};
}

}  // namespace penumbra::engine
