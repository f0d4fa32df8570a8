// The subcommands and their arguments (filled by CLI11 in main.cpp).
// Thread-safety: plain argument structs; each run* function runs on the main thread.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::engine {
struct Scene;
}

namespace penumbra::apps {

// Values as the user gave them: the engine checks them (engine/render_options.h), the command line
// only parses text into numbers. An option not given is empty, never a sentinel value.
struct RenderArgs {
  std::string scene, builtin, exr;
  std::string aov, aovOut;  // --aov LIST, --aov-out PREFIX (engine/aov.h)
  std::optional<std::string> output;  // none: <scene name>.png
  bool listBuiltins = false, stats = false;
  int width = 1280, height = 720, threads = 0;
  std::string eye, target;
  std::optional<double> fov;  // none: the scene's
  std::string shadow = "pcss";        // technique of the shadows/ registry, "reference" or "none"
  std::vector<std::string> params;    // name=value for the technique
  std::string cache;                  // cache folder for the ground truth ("" = none)
  bool listShadows = false;
  bool points = false;                // draw a point cloud with the splatter instead (cmd_points.cpp)
  std::optional<int64_t> pointCount;  // points sampled from the scene, [1, 2^26]; none: 2,000,000
  std::string pointsFile;             // .xyz file of points instead of sampling the scene
  // Motion blur and depth of field (the stochastic pass, when the scene moves or has a lens).
  int spp = 16;                       // samples per pixel [1, 64]
  int msaa = 1;                       // G-buffer samples per pixel: 1, 2, 4, 8
  std::string bounds = "dual";        // box, interval, dual
  std::string strata;                 // interval bounds "T" or "T,L" (time strata, lens cells per axis)
  int64_t frame = 0;                  // seeds the sample pattern, [0, 2^32)
  int dualBlock = 4;                  // dual-space block side, power of 2 in [1, 64]
  bool noStaticPath = false;          // static instances through the stochastic pass too
  std::optional<double> aperture, focus;  // override the camera's lens (none: the scene's)
  bool allowOutsidePaths = false;     // files may name files outside their own folder
  std::string maxMemory;              // "8G", ...; "" = the memory available now
  bool noDefaultLight = false;        // a scene without lights stays unlit (ambient only)
  double exposure = 0.0;              // stops, for the PNG
  std::string toneMap = "none";       // none, aces
};
int runRender(const RenderArgs& args);
// render --points: checks the point options (and that none is given without --points), then, once
// the scene is loaded, draws the points to the PNG at `path` (cmd_points.cpp).
void checkPointOptions(const RenderArgs& args);
// memoryLimit: refuse (before allocating) points and targets estimated beyond it; 0: no limit.
int renderPoints(const RenderArgs& args, const engine::Scene& scene, std::optional<glm::vec3> eye,
                 std::optional<glm::vec3> target, const std::string& path, uint64_t memoryLimit,
                 const std::string& limitSource);

struct BenchRasterArgs {
  std::vector<std::string> meshes;
  std::vector<long> synth;
  std::vector<int> threads;
  std::string workload = "both";
  std::vector<int> msaa;  // W2 also at these sample counts (1, 2, 4, 8), with the edge error
  int frames = 10;
  double minSeconds = 1.0;
  bool json = false;
  bool allowOutsidePaths = false;
};
int runBenchRaster(const BenchRasterArgs& args);

struct BenchShadowsArgs {
  std::vector<std::string> scenes;      // built-in names or scene files; default: the five bench scenes
  std::vector<std::string> techniques;  // default: every technique of the registry but the reference
  std::vector<std::string> settings;    // extra "technique:name=value,..." settings
  int width = 480, height = 270, runs = 3, gtSamples = 1024, threads = 0;
  double lightScale = 1.0;  // every area light's width and height times this, about its centre; (0, 64]
  std::string out = "out/bench-shadows", cache;
  bool json = false;
  bool allowOutsidePaths = false;
};
int runBenchShadows(const BenchShadowsArgs& args);

struct BenchStochasticArgs {
  std::vector<std::string> scenes;   // built-in names or scene files; default motion, defocus, motion-defocus
  std::vector<std::string> methods;  // box, interval, dual (default all three)
  std::vector<int> spp;              // default 4, 16, 64
  int width = 480, height = 270, runs = 3, refFrames = 512, threads = 0;
  std::string shadow = "none";       // shadow technique of the frames (default none: the error is the blur's)
  std::string out = "out/bench-stochastic";
  bool json = false;
  bool allowOutsidePaths = false;
};
int runBenchStochastic(const BenchStochasticArgs& args);

struct BenchPointsArgs {
  int64_t points = 4000000;  // sampled from the built-in scene 'complex', [1, 2^26]
  std::vector<int> views;    // M per run, each in [1, 1024]; default 1, 8, 32, 128
  int size = 512;            // each view is size x size pixels, [1, 4096]
  std::vector<int> threads;  // thread counts, each in [1, 1024]; default 1, 2
  int runs = 5;              // timed runs per (views, threads); medians are reported; [1, 1000]
  bool json = false;
};
int runBenchPoints(const BenchPointsArgs& args);

struct ExplainArgs {
  std::string topic;                        // "stochastic"
  std::string out = "out/explain-stochastic";
  int spp = 16;
};
int runExplain(const ExplainArgs& args);

struct StressArgs {
  std::string suite = "raster";
  int threads = 0;
  bool json = false;
};
int runStress(const StressArgs& args);

// Prints the registry: techniques, their parameters, defaults and ranges.
void listShadowTechniques();

}  // namespace penumbra::apps
