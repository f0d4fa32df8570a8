#include "engine/image_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace penumbra::engine::image_module {
namespace {

namespace fs = std::filesystem;
constexpr const char* kFileName = "libpenumbra_image_oiio.so";

// Where the module may be, in the order of engine/image_module.h.
std::vector<fs::path> candidates() {
  std::vector<fs::path> paths;
  if (const char* env = std::getenv("PENUMBRA_IMAGE_MODULE"); env && *env) return {fs::path(env)};
  // Only an absolute path: for the main program dladdr gives argv[0], which may be relative, and a
  // module in whatever folder the process runs in must never be loaded.
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&candidates), &info) != 0 && info.dli_fname &&
      fs::path(info.dli_fname).is_absolute())
    paths.push_back(fs::path(info.dli_fname).parent_path() / kFileName);
#ifdef PENUMBRA_IMAGE_MODULE_BUILT
  paths.emplace_back(PENUMBRA_IMAGE_MODULE_BUILT);
#endif
#ifdef PENUMBRA_IMAGE_MODULE_INSTALLED
  paths.emplace_back(PENUMBRA_IMAGE_MODULE_INSTALLED);
#endif
#ifdef PENUMBRA_INSTALL_LIBDIR
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    paths.push_back(exe.parent_path().parent_path() / PENUMBRA_INSTALL_LIBDIR / "penumbra" / kFileName);
#endif
  return paths;
}

Result<const Table*> load() {
  std::string tried;
  for (const fs::path& p : candidates()) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) {
      tried += (tried.empty() ? "" : ", ") + p.string();
      continue;
    }
    // Never unloaded: OpenImageIO keeps threads and plugin state for the process's life.
    void* handle = ::dlopen(p.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = ::dlerror();
      return Error{p.string(), "cannot load the image module: " + oneLine(why ? why : "")};
    }
    using Entry = const Table* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, "penumbra_image_module_table"));
    const Table* t = entry ? entry() : nullptr;
    if (!t || t->abi != kImageModuleAbi)
      return Error{p.string(),
                   "not the image module of this build (rebuild Penumbra, or unset PENUMBRA_IMAGE_MODULE)"};
    return t;
  }
  return Error{kFileName,
               "image module not found (looked at " + tried +
                   "; set PENUMBRA_IMAGE_MODULE to its path): needed for images other than PNG output"};
}

}  // namespace

Result<const Table*> table() {
  static const Result<const Table*> loaded = load();
  return loaded;
}

}  // namespace penumbra::engine::image_module
