// Shared pieces of the `penumbra` subcommands: errors (one line, exit status 2), option parsing
// helpers, progress lines.
#pragma once

#include <chrono>
#include <cstdio>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <utility>

#include "engine/error.h"
#include "engine/scene.h"

namespace penumbra::apps {

inline constexpr int kExitBadInput = 2;

// Thrown by subcommands for bad input; main() prints "penumbra: error: <where>: <what>" and
// exits with status 2 before anything is written.
struct UsageError {
  engine::Error error;
};
[[noreturn]] inline void fail(const std::string& where, const std::string& what) { throw UsageError{{where, what}}; }
[[noreturn]] inline void fail(const engine::Error& e) { throw UsageError{e}; }

// "X,Y,Z" -> vector; anything else is a UsageError naming the option.
glm::vec3 parseVec3(const std::string& option, const std::string& text);

// A bench's --scene argument: a built-in scene's name, or a scene file when it holds a '.' or a
// '/' (then labelled by its stem). Bad names and files are a UsageError.
std::pair<std::string, engine::Scene> loadSceneArgument(const std::string& name);

// Progress on stderr: one line per step (overwritten in place on a terminal). With a delay, steps
// are shown only once the task has run that many seconds (quick commands stay quiet).
class Progress {
 public:
  explicit Progress(std::string task, double delaySeconds = 0.0) : task_(std::move(task)), delay_(delaySeconds) {}
  void step(int index, int total, const std::string& what);
  void done();

 private:
  std::string task_;
  double delay_ = 0.0;
  bool tty_ = false, any_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};


}  // namespace penumbra::apps
