// Built-in procedural scenes: they need no file, so `penumbra render` works on a fresh checkout.
// Pure functions (each call builds a new Scene).
// Thread-safety: pure functions; safe from any thread.
#pragma once

#include <string>
#include <vector>

#include "engine/scene.h"

namespace penumbra::engine {

inline constexpr const char* kDefaultScene = "default";

struct BuiltinInfo {
  std::string name, description;
};
std::vector<BuiltinInfo> builtinScenes();

// An unknown name is an Error listing the valid ones.
Result<Scene> makeBuiltinScene(const std::string& name);

}  // namespace penumbra::engine
