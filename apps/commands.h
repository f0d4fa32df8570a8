// The subcommands and their arguments (filled by CLI11 in main.cpp).
#pragma once

#include <string>
#include <vector>

namespace penumbra::apps {

struct RenderArgs {
  std::string scene, builtin, output, exr;
  bool listBuiltins = false, stats = false;
  int width = 1280, height = 720, threads = 0;
  std::string eye, target;
  double fov = 0.0;  // 0: the scene's
  std::string shadow = "pcss";        // technique of the shadows/ registry, "reference" or "none"
  std::vector<std::string> params;    // name=value for the technique
  std::string cache;                  // cache folder for the ground truth ("" = none)
  bool listShadows = false;
};
int runRender(const RenderArgs& args);

struct BenchRasterArgs {
  std::vector<std::string> meshes;
  std::vector<long> synth;
  std::vector<int> threads;
  std::string workload = "both";
  int frames = 10;
  double minSeconds = 1.0;
  bool json = false;
};
int runBenchRaster(const BenchRasterArgs& args);

struct BenchShadowsArgs {
  std::vector<std::string> scenes;      // built-in names or scene files; default: the five bench scenes
  std::vector<std::string> techniques;  // default: every technique of the registry but the reference
  std::vector<std::string> settings;    // extra "technique:name=value,..." settings
  int width = 480, height = 270, runs = 3, gtSamples = 1024, threads = 0;
  std::string out = "out/bench-shadows", cache;
  bool json = false;
};
int runBenchShadows(const BenchShadowsArgs& args);

struct StressArgs {
  std::string suite = "raster";
  int threads = 0;
  bool json = false;
};
int runStress(const StressArgs& args);

// Checks a technique name and its name=value parameters (UsageError naming the option), returns
// the comma-joined parameter list for engine::RenderOptions::shadowParams.
std::string checkShadowOptions(const std::string& shadow, const std::vector<std::string>& params);
// Prints the registry: techniques, their parameters, defaults and ranges.
void listShadowTechniques();

// Sets the TBB worker limit for the whole process (so that --threads N may exceed the cores).
void allowThreads(int threads);

}  // namespace penumbra::apps
