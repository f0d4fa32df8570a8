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

struct StressArgs {
  std::string suite = "raster";
  int threads = 0;
  bool json = false;
};
int runStress(const StressArgs& args);

// Sets the TBB worker limit for the whole process (so that --threads N may exceed the cores).
void allowThreads(int threads);

}  // namespace penumbra::apps
