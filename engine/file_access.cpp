#include "engine/file_access.h"

#include <cctype>
#include <system_error>

namespace penumbra::engine {

namespace fs = std::filesystem;

std::string uriScheme(const std::string& uri) {
  // RFC 3986: scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":" -- before any '/', '?', '#'.
  if (uri.empty() || !std::isalpha(static_cast<unsigned char>(uri[0]))) return {};
  for (size_t i = 1; i < uri.size(); ++i) {
    const auto c = static_cast<unsigned char>(uri[i]);
    if (c == ':') return i > 1 ? uri.substr(0, i) : std::string();  // "C:" is a drive, not a scheme
    if (!std::isalnum(c) && c != '+' && c != '-' && c != '.') return {};
  }
  return {};
}

Result<fs::path> resolveReference(const fs::path& folder, const std::string& reference, const LoadOptions& options,
                                  const std::string& owner, const std::string& what) {
  if (reference.empty()) return Error{owner, what + " names no file"};
  if (reference.find('\0') != std::string::npos) return Error{owner, what + " holds a NUL byte"};
  const fs::path ref(reference);
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(folder.empty() ? fs::path(".") : folder, ec);
  if (ec) return Error{owner, "cannot resolve the folder of the file: " + ec.message()};
  if (ref.is_absolute() && !options.allowOutsidePaths)
    return Error{owner, what + " is an absolute path, outside the file's folder (--allow-outside-paths to allow it)"};
  const fs::path full = fs::weakly_canonical(ref.is_absolute() ? ref : base / ref, ec);
  if (ec) return Error{owner, what + " cannot be resolved: " + ec.message()};
  if (!options.allowOutsidePaths) {
    const fs::path rel = full.lexically_relative(base);
    if (rel.empty() || *rel.begin() == "..")
      return Error{owner, what + " resolves outside the file's folder (--allow-outside-paths to allow it)"};
  }
  if (!fs::is_regular_file(full, ec)) return Error{owner, what + " is missing or not a regular file"};
  return full;
}

}  // namespace penumbra::engine
