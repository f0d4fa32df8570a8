// Shared pieces of the `penumbra` subcommands: errors (one line, exit status 2), option parsing
// helpers, progress lines.
// Thread-safety: the command line runs one subcommand on one thread; Progress and ThreadLimit
// belong to it.
#pragma once

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/error.h"
#include "engine/file_access.h"
#include "engine/render_options.h"
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

// The engine's verdict on an option value, as a UsageError.
inline void require(const engine::Status& st) {
  if (!st) fail(st.error());
}
inline void require(const engine::OptionSpec& spec, double value) { require(spec.check(value)); }
// The benches' own options (their help quotes these ranges).
inline constexpr engine::OptionSpec kBenchWidthOption{"--width", 16, 4096};
inline constexpr engine::OptionSpec kBenchHeightOption{"--height", 16, 4096};
inline constexpr engine::OptionSpec kBenchRunsOption{"--runs", 1, 100};
inline constexpr engine::OptionSpec kGtSamplesOption{"--gt-samples", 1, 65536};
inline constexpr engine::OptionSpec kRefFramesOption{"--ref-frames", 1, 65536};
// The image size, runs and threads every image bench takes.
inline void requireBenchBasics(int width, int height, int runs, int threads) {
  require(kBenchWidthOption, width);
  require(kBenchHeightOption, height);
  require(kBenchRunsOption, runs);
  require(engine::kThreadsOption, threads);
}

// The options resolved by the engine, or a UsageError naming the bad one.
engine::ResolvedOptions resolveOrFail(const engine::RenderOptions& options);

// Lets TBB run up to `threads` workers (more than the cores, if asked) while it lives; 0 changes
// nothing. One per subcommand run, on its stack.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads) {
    if (threads > 0) control_.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  }

 private:
  std::optional<tbb::global_control> control_;
};

// "X,Y,Z" -> vector; anything else is a UsageError naming the option.
glm::vec3 parseVec3(const std::string& option, const std::string& text);

// A bench's --scene argument: a built-in scene's name, or a scene file when it holds a '.' or a
// '/' (then labelled by its stem). Bad names and files are a UsageError.
std::pair<std::string, engine::Scene> loadSceneArgument(const std::string& name, const engine::LoadOptions& options,
                                                        const std::string& option = "--scene");

// Outputs may not be any file the inputs were read from (a scene's files, a points file): a
// UsageError naming the output.
void refuseOverwritingInputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs);

// Progress on stderr, for a person watching: on a terminal only, one line overwritten in place per
// step and cleared when done (or by the error line). Elsewhere (a pipe, a log, a test) nothing, so
// a failure is exactly one line. With a delay, steps are shown only once the task has run that
// many seconds (quick commands stay quiet).
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
