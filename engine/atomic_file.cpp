#include "engine/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <system_error>

namespace penumbra::engine {

namespace fs = std::filesystem;

namespace {

std::string errnoMessage(int err) { return std::error_code(err, std::generic_category()).message(); }

// The live temporaries, as C strings a signal handler can pass to unlink(): a fixed table (no
// allocation while a signal may arrive); a slot is claimed under a lock and released on removal.
constexpr int kSlots = 64;
constexpr size_t kPathMax = 4096;
struct Live {
  std::atomic<bool> used{false};
  char path[kPathMax] = {};
};
Live gLive[kSlots];
std::mutex gLiveMutex;
std::atomic<unsigned> gCounter{0};

int claimSlot(const fs::path& p) {
  const std::string s = p.string();
  if (s.size() >= kPathMax) return -1;
  std::lock_guard<std::mutex> lock(gLiveMutex);
  for (int i = 0; i < kSlots; ++i)
    if (!gLive[i].used.load()) {
      std::memcpy(gLive[i].path, s.c_str(), s.size() + 1);
      gLive[i].used.store(true);
      return i;
    }
  return -1;  // more than kSlots at once: still written atomically, only not removed on a signal
}

void releaseSlot(int i) {
  if (i >= 0) gLive[i].used.store(false);
}

// Flushes a file (or a directory's entries) to disk.
bool syncPath(const char* p, int flags) {
  const int fd = ::open(p, flags | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

void removeTempFilesOnSignal() {
  for (Live& l : gLive)
    if (l.used.load()) ::unlink(l.path);
}

TempFile::TempFile(const fs::path& target) : target_(target) {
  const unsigned n = gCounter.fetch_add(1, std::memory_order_relaxed);
  // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on "." + std::string.
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-";
  name += std::to_string(static_cast<long>(::getpid()));
  name += "-";
  name += std::to_string(n);
  name += target.extension().string();
  tmp_ = target.parent_path() / name;
  slot_ = claimSlot(tmp_);
}

TempFile::~TempFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
  releaseSlot(slot_);
}

Status TempFile::commit() {
  const std::string where = target_.string();
  if (!syncPath(tmp_.c_str(), O_RDONLY)) return Error{where, "cannot write: " + errnoMessage(errno)};
  std::error_code ec;
  fs::rename(tmp_, target_, ec);
  if (ec) return Error{where, "cannot replace the file: " + ec.message()};
  committed_ = true;
  // The rename reaches the disk with the directory's entries.
  const fs::path dir = target_.parent_path();
  syncPath(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  return Ok{};
}

Status writeFileAtomically(const fs::path& target, std::string_view bytes) {
  const std::string where = target.string();
  TempFile tmp(target);
  std::FILE* f = std::fopen(tmp.path().c_str(), "wb");
  if (f == nullptr) return Error{where, "cannot write: " + errnoMessage(errno)};
  bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  int err = ok ? 0 : errno;
  if (std::fclose(f) != 0 && ok) {
    ok = false;
    err = errno;
  }
  if (!ok) return Error{where, "cannot write: " + errnoMessage(err)};
  return tmp.commit();
}

}  // namespace penumbra::engine
