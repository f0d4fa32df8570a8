#include "apps/cli.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <vector>

#include "engine/builtin_scenes.h"
#include "engine/scene_file.h"

namespace penumbra::apps {

std::pair<std::string, engine::Scene> loadSceneArgument(const std::string& name, const engine::LoadOptions& options,
                                                        const std::string& option) {
  const bool isFile = name.find('.') != std::string::npos || name.find('/') != std::string::npos;
  engine::Result<engine::Scene> s = isFile ? engine::loadScene(name, options) : engine::makeBuiltinScene(name);
  if (!s) {
    if (isFile) fail(s.error());
    fail("option " + option, s.error().line());
  }
  engine::addDefaultLighting(*s);  // a file without lights gets the key light render would give it
  return {isFile ? std::filesystem::path(name).stem().string() : name, std::move(*s)};
}

engine::ResolvedOptions resolveOrFail(const engine::RenderOptions& options) {
  engine::Result<engine::ResolvedOptions> r = engine::resolveOptions(options);
  if (!r) fail(r.error());
  return std::move(*r);
}

void refuseOverwritingInputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  for (const std::string& out : outputs) {
    if (out.empty()) continue;
    std::error_code ec;
    const fs::path o = fs::weakly_canonical(out, ec);
    for (const std::string& in : inputs) {
      std::error_code e1, e2;
      const bool same = (fs::exists(out, e1) && fs::equivalent(out, in, e2)) || (!ec && o == fs::weakly_canonical(in, e2));
      if (same) fail(out, "is an input of this run (" + in + "): refusing to overwrite it");
    }
  }
}

glm::vec3 parseVec3(const std::string& option, const std::string& text) {
  std::vector<float> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    char* end = nullptr;
    const float f = std::strtof(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(f))
      fail("option " + option, "expected three finite numbers X,Y,Z, got '" + text + "'");
    v.push_back(f);
  }
  if (v.size() != 3) fail("option " + option, "expected three numbers X,Y,Z, got '" + text + "'");
  return {v[0], v[1], v[2]};
}

void Progress::step(int index, int total, const std::string& what) {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (s < delay_) return;
  if (!any_) tty_ = isatty(STDERR_FILENO) != 0;
  any_ = true;
  if (!tty_) return;
  std::fprintf(stderr, "\r\033[K[%s %d/%d %.0fs] %s", task_.c_str(), index, total, s, what.c_str());
  std::fflush(stderr);
}

void Progress::done() {
  if (any_ && tty_) std::fprintf(stderr, "\r\033[K");
}

}  // namespace penumbra::apps
