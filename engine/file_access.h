// What an untrusted file may name: the trust model of loading (docs/architecture.md, "Trust").
//
// A scene file or a glTF names other files (glTF files, buffers, images) by relative paths or
// URIs. Each is resolved against the folder of the file that names it, symbolic links followed,
// and must stay inside that folder: an absolute path, a path that climbs out ("../") or a link
// that leads out is refused with one line naming the reference, unless the user allows it
// (LoadOptions::allowOutsidePaths, the command line's --allow-outside-paths). URI schemes other
// than data: are refused always. Only regular files are read (never a FIFO or a device), and
// their size is known before a byte is read.
//
// Thread-safety: pure functions of their arguments and the file system.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "engine/error.h"

namespace penumbra::engine {

struct LoadOptions {
  bool allowOutsidePaths = false;  // files may name files outside their own folder
  uint64_t maxBytes = 0;           // a model whose files (the glTF, its buffers) exceed this is refused
                                   // before they are read; 0: no limit
  size_t maxTriangles = 0;         // a scene file's procedural shapes, in all; 0: the default cap (2^26)
};

// `reference` (a relative path, already percent-decoded where it came from a URI) resolved against
// `folder`: the canonical path of an existing regular file inside it. `what` names the reference
// in errors ("buffer 1 ('mesh.bin')"); the Error's where is `owner` (the file that names it).
Result<std::filesystem::path> resolveReference(const std::filesystem::path& folder, const std::string& reference,
                                               const LoadOptions& options, const std::string& owner,
                                               const std::string& what);

// The scheme of a URI ("data", "file", "http"), or "" for a relative reference.
std::string uriScheme(const std::string& uri);

}  // namespace penumbra::engine
