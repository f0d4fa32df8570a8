// Files appear whole or not at all: everything Penumbra writes (images, reports, caches) is
// written to a temporary file in the target's directory, flushed to disk (fsync), then renamed
// over the target, which is atomic on POSIX within one file system. A reader sees the old file or
// the new one, never a part; a failed write leaves nothing behind.
//
// TempFile names its file ".<target name>.tmp-<pid>-<n><ext>": hidden, unique in the process (n
// counts up) and between processes (pid), and ending in the target's extension so that a writer
// choosing the format by extension (OpenImageIO) picks the target's. Live temporary files are
// listed so that a signal handler can remove them (removeTempFilesOnSignal: async-signal-safe).
//
// Thread-safety: TempFile objects are independent; the list of live temporaries is guarded.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "engine/error.h"

namespace penumbra::engine {

class TempFile {
 public:
  explicit TempFile(const std::filesystem::path& target);
  ~TempFile();  // removes the temporary unless committed
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::filesystem::path& path() const { return tmp_; }
  // Flushes the written temporary to disk and renames it over the target. Errors name the target.
  Status commit();

 private:
  std::filesystem::path target_, tmp_;
  int slot_ = -1;  // in the list of live temporaries
  bool committed_ = false;
};

// `bytes` as the whole content of `target`. Errors name the target.
Status writeFileAtomically(const std::filesystem::path& target, std::string_view bytes);

// Removes every live temporary file (for SIGINT/SIGTERM handlers: only async-signal-safe calls).
void removeTempFilesOnSignal();

}  // namespace penumbra::engine
