// penumbra: the command line. Subcommands:
//   render  render a scene file, glTF file or built-in scene to PNG (and EXR); --points: its surface
//           as a point cloud drawn by the point splatter
//   bench   raster: time the standard workloads W1/W2 (shared/WORKLOADS.md)
//           shadows: soft-shadow techniques, run time per stage against error vs the ground truth
//           points: point splatting throughput against a memory-bandwidth bound
//   stress  raster: sweep the numerically hard cases and report what broke
// Bad input (files, options, values) ends with one line on stderr and exit status 2, before any
// output file is written.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "apps/cli.h"
#include "apps/commands.h"
#include "engine/atomic_file.h"
#include "engine/builtin_scenes.h"
#include "engine/render_options.h"
#include "engine/version.h"

using namespace penumbra;
using namespace penumbra::apps;

namespace {

// SIGINT / SIGTERM: the temporaries of files being written are removed (a partial output never
// stays behind), one line says so, and the process exits 128 + the signal (130, 143). Only
// async-signal-safe calls.
extern "C" void onSignal(int sig) {
  penumbra::engine::removeTempFilesOnSignal();
  const char* msg = sig == SIGINT ? "\r\033[Kpenumbra: interrupted (SIGINT); no output left half-written\n"
                                  : "\r\033[Kpenumbra: terminated (SIGTERM); no output left half-written\n";
  const char* text = isatty(STDERR_FILENO) ? msg : msg + 4;  // no terminal control codes in a log
  size_t n = 0;
  while (text[n] != '\0') ++n;
  ssize_t ignored = ::write(STDERR_FILENO, text, n);
  (void)ignored;
  ::_exit(128 + sig);
}

void installSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

// The error line, after clearing a progress line on a terminal.
void printError(const std::string& line, const char* hint = "") {
  std::fprintf(stderr, "%spenumbra: error: %s%s\n", isatty(STDERR_FILENO) ? "\r\033[K" : "", line.c_str(), hint);
}

// The render subcommand and its options, filling `a`.
CLI::App* addRenderCommand(CLI::App& app, RenderArgs& a) {
  CLI::App* r = app.add_subcommand("render", "Render a scene (file or built-in) to an image");
  r->add_option("scene", a.scene, "Scene file: .json (scene format), .gltf or .glb");
  r->add_option("--builtin", a.builtin, "Built-in scene name (default: " + std::string(engine::kDefaultScene) + ")");
  r->add_flag("--list-builtins", a.listBuiltins, "List the built-in scenes and exit");
  r->add_option("-o,--output", a.output, "Output PNG path (default: <scene name>.png)");
  r->add_option("--exr", a.exr, "Also write the linear image as OpenEXR to this path");
  r->add_option("--aov", a.aov,
                "Also write buffers as float OpenEXR: a comma list of visibility, depth, position, normal, "
                "geometric-normal, albedo, instance, triangle, barycentrics (NaN where there is no receiver)");
  r->add_option("--aov-out", a.aovOut, "Path prefix of the --aov files: PREFIX.<buffer>.exr");
  r->add_option("--width", a.width, "Image width in pixels " + engine::kWidthOption.range());
  r->add_option("--height", a.height, "Image height in pixels " + engine::kHeightOption.range());
  r->add_option("--threads", a.threads, "Worker threads " + engine::kThreadsOption.range() + " (0 = all cores)");
  r->add_option("--eye", a.eye, "Camera position X,Y,Z");
  r->add_option("--target", a.target, "Camera target X,Y,Z");
  r->add_option("--fov", a.fov, "Vertical field of view in degrees " + engine::kFovOption.range());
  r->add_flag("--stats", a.stats, "Print the frame plan: what each pass did and skipped");
  r->add_option("--shadow", a.shadow,
                "Soft-shadow technique for the area lights (default pcss; 'reference' = ray-traced ground truth; "
                "'none'; see --list-shadows)");
  r->add_option("--param", a.params, "Technique parameter name=value (repeatable)");
  r->add_option("--cache", a.cache, "Folder caching the ground truth between runs (default: none)");
  r->add_flag("--list-shadows", a.listShadows, "List the shadow techniques and their parameters and exit");
  r->add_flag("--points", a.points,
              "Draw a point cloud with the point splatter instead of triangles (from the scene or --points-file)");
  r->add_option("--point-count", a.pointCount,
                "Points sampled from the scene's surfaces [1, 2^26] (default 2000000)");
  r->add_option("--points-file", a.pointsFile,
                "Text file of points, one 'x y z' or 'x y z r g b' (0..255) per line; camera fitted to them "
                "unless a scene is named");

  r->add_option("--msaa", a.msaa,
                "Multisample antialiasing: samples per pixel of the G-buffer pass, " + engine::kMsaaOption.range() +
                    " (default 1; a stochastic pass antialiases by its own samples)");
  r->add_option("--spp", a.spp,
                "Samples per pixel of the stochastic pass (motion blur, depth of field) " + engine::kSppOption.range());
  r->add_option("--bounds", a.bounds, "Stochastic bounding method: box, interval or dual (default dual)");
  r->add_option("--strata", a.strata,
                "Interval bounds: time strata T " + engine::kTimeStrataOption.range() + " or T,L with L lens cells per axis " +
                    engine::kLensStrataOption.range());
  r->add_option("--dual-block", a.dualBlock,
                "Dual-space bounds: pixel block side, " + engine::kDualBlockOption.range() + " (default 4)");
  r->add_option("--frame", a.frame, "Frame number seeding the sample pattern " + engine::kFrameOption.range());
  r->add_flag("--no-static-path", a.noStaticPath,
              "Send static instances through the stochastic pass too (to measure what the ordinary path saves)");
  r->add_option("--aperture", a.aperture,
                "Lens aperture radius in world units " + engine::kApertureOption.range() + " (0 = pinhole; default: the scene's)");
  r->add_flag("--no-default-light", a.noDefaultLight,
              "Leave a scene without lights unlit (by default it gets a key area light and a sky ambient)");
  r->add_option("--exposure", a.exposure,
                "Exposure of the PNG in stops " + engine::kExposureOption.range() + " (default 0; the EXR keeps radiance)");
  r->add_option("--tonemap", a.toneMap, "Tone map of the PNG: none (clamp, default) or aces (filmic roll-off)");
  r->add_option("--max-memory", a.maxMemory,
                "Refuse a frame estimated to need more memory than this (e.g. 8G, 512M; default: what the machine has "
                "available now)");
  r->add_flag("--allow-outside-paths", a.allowOutsidePaths,
              "Let scene and glTF files name files outside their own folder (absolute or ../ paths)");
  r->add_option("--focus", a.focus, "Focus distance in world units " + engine::kFocusOption.range() + " (default: the scene's)");
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  installSignalHandlers();
  CLI::App app{"penumbra: a deterministic CPU rasterizer and soft-shadow laboratory"};
  app.set_version_flag("--version", std::string("penumbra ") + penumbra::kVersion);
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show help for all subcommands");

  RenderArgs render;
  CLI::App* r = addRenderCommand(app, render);

  BenchRasterArgs bench;
  CLI::App* b = app.add_subcommand("bench", "Benchmarks");
  b->require_subcommand(1);
  CLI::App* br = b->add_subcommand("raster", "Time the standard workloads W1 (depth 2048^2) and W2 (shaded 1080p)");
  br->add_option("--mesh", bench.meshes, "A .glb/.gltf/.json scene, flattened to one mesh (repeatable)");
  br->add_option("--synth", bench.synth, "Synthetic mesh with about N triangles (repeatable; default 1000000 4000000)");
  br->add_option("--threads", bench.threads, "Thread counts to run (default: 1 and 2)")->delimiter(',');
  br->add_option("--workload", bench.workload, "W1, W2 or both")->check(CLI::IsMember({"W1", "W2", "both"}));
  br->add_option("--msaa", bench.msaa,
                 "Also W2 multisampled at these sample counts (1, 2, 4, 8; e.g. 1,4,8), each with its edge error "
                 "against 16x16 supersampling")
      ->delimiter(',');
  br->add_option("--frames", bench.frames, "Minimum timed frames per run (default 10)");
  br->add_option("--min-time", bench.minSeconds, "Minimum seconds per run (default 1)");
  br->add_flag("--json", bench.json, "One JSON object per run on stdout");
  br->add_flag("--allow-outside-paths", bench.allowOutsidePaths, "Let --mesh files name files outside their folder");

  BenchShadowsArgs benchShadows;
  CLI::App* bs = b->add_subcommand("shadows", "Soft-shadow techniques: run time per stage against error vs the ground truth");
  bs->add_option("--scene", benchShadows.scenes, "Built-in scene or scene file (repeatable; default the five bench scenes)");
  bs->add_option("--technique", benchShadows.techniques, "Technique to run with its bench settings (repeatable; default all)");
  bs->add_option("--setting", benchShadows.settings, "Extra setting technique:name=value,... (repeatable)");
  bs->add_option("--width", benchShadows.width, "Image width " + kBenchWidthOption.range() + " (default 480)");
  bs->add_option("--height", benchShadows.height, "Image height " + kBenchHeightOption.range() + " (default 270)");
  bs->add_option("--runs", benchShadows.runs,
                 "Timed runs per setting " + kBenchRunsOption.range() + "; medians are reported (default 3)");
  bs->add_option("--gt-samples", benchShadows.gtSamples,
                 "Ground-truth rays per receiver " + kGtSamplesOption.range() + " (default 1024)");
  bs->add_option("--threads", benchShadows.threads, "Worker threads " + engine::kThreadsOption.range() + " (0 = all cores)");
  bs->add_option("--light-scale", benchShadows.lightScale,
                 "Every area light's width and height times this, about its centre, (0, 64] (default 1: the "
                 "growing-light study, scripts/growing-light.sh)");
  bs->add_option("--out", benchShadows.out, "Report folder (default out/bench-shadows)");
  bs->add_option("--cache", benchShadows.cache, "Ground-truth cache folder (default <out>/gt-cache)");
  bs->add_flag("--json", benchShadows.json, "One JSON object per (scene, technique, setting) on stdout");
  bs->add_flag("--allow-outside-paths", benchShadows.allowOutsidePaths, "Let scene files name files outside their folder");

  BenchStochasticArgs benchStoch;
  CLI::App* bst = b->add_subcommand(
      "stochastic", "Motion blur and depth of field: bounding methods' tests, STE and time against error vs accumulation");
  bst->add_option("--scene", benchStoch.scenes, "Built-in scene or scene file (repeatable; default motion, defocus, motion-defocus)");
  bst->add_option("--method", benchStoch.methods, "Bounding method box, interval or dual (repeatable; default all)");
  bst->add_option("--spp", benchStoch.spp, "Samples per pixel to run, each " + engine::kSppOption.range() + " (default 4,16,64)")
      ->delimiter(',');
  bst->add_option("--width", benchStoch.width, "Image width " + kBenchWidthOption.range() + " (default 480)");
  bst->add_option("--height", benchStoch.height, "Image height " + kBenchHeightOption.range() + " (default 270)");
  bst->add_option("--runs", benchStoch.runs,
                  "Timed runs per setting " + kBenchRunsOption.range() + "; medians are reported (default 3)");
  bst->add_option("--ref-frames", benchStoch.refFrames,
                  "Pinhole frames in the accumulation reference " + kRefFramesOption.range() + " (default 512)");
  bst->add_option("--shadow", benchStoch.shadow, "Shadow technique of every frame (default none)");
  bst->add_option("--threads", benchStoch.threads, "Worker threads " + engine::kThreadsOption.range() + " (0 = all cores)");
  bst->add_option("--out", benchStoch.out, "Report folder (default out/bench-stochastic)");
  bst->add_flag("--json", benchStoch.json, "One JSON object per run on stdout");
  bst->add_flag("--allow-outside-paths", benchStoch.allowOutsidePaths, "Let scene files name files outside their folder");

  BenchPointsArgs benchPoints;
  CLI::App* bp =
      b->add_subcommand("points", "Point splatting: points and point-views per second against a bandwidth bound");
  bp->add_option("--points", benchPoints.points,
                 "Points sampled from the built-in scene 'complex' [1, 2^26] (default 4000000)");
  bp->add_option("--views", benchPoints.views, "View counts M, all splatted in one traversal (default 1,8,32,128)")
      ->delimiter(',');
  bp->add_option("--size", benchPoints.size, "Each view is size x size pixels [1, 4096] (default 512)");
  bp->add_option("--threads", benchPoints.threads, "Thread counts to run (default: 1 and 2)")->delimiter(',');
  bp->add_option("--runs", benchPoints.runs, "Timed runs per (views, threads); medians are reported (default 5)");
  bp->add_flag("--json", benchPoints.json, "One JSON object per (views, threads) on stdout");

  ExplainArgs explain;
  CLI::App* ex = app.add_subcommand("explain", "Pictures that explain a method (topic: stochastic)");
  ex->add_option("topic", explain.topic, "What to explain: stochastic")->required();
  ex->add_option("--out", explain.out, "Folder for the pictures (default out/explain-stochastic)");
  ex->add_option("--spp", explain.spp, "Samples per pixel shown [1, 64] (default 16)");

  StressArgs stress;
  CLI::App* s = app.add_subcommand("stress", "Sweep numerically hard cases; exit 1 if anything broke");
  s->add_option("--suite", stress.suite, "Suite to run: raster (default), shadows or stochastic")
      ->check(CLI::IsMember({"raster", "shadows", "stochastic"}));
  s->add_option("--threads", stress.threads, "Worker threads " + engine::kThreadsOption.range() + " (0 = all cores)");
  s->add_flag("--json", stress.json, "One JSON object per case on stdout");

  if (argc > 1 && argv[1][0] != '-') {
    const std::string sub = argv[1];
    if (sub != "render" && sub != "bench" && sub != "stress" && sub != "explain") {
      const engine::Error e{"", "unknown subcommand '" + sub + "' (valid: render, bench, stress, explain)"};
      printError(e.line());
      return kExitBadInput;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    printError(engine::Error{"", e.what()}.line(), " (see penumbra --help)");
    return kExitBadInput;
  }

  try {
    if (r->parsed()) return runRender(render);
    if (br->parsed()) return runBenchRaster(bench);
    if (bs->parsed()) return runBenchShadows(benchShadows);
    if (bp->parsed()) return runBenchPoints(benchPoints);
    if (bst->parsed()) return runBenchStochastic(benchStoch);
    if (s->parsed()) return runStress(stress);
    if (ex->parsed()) return runExplain(explain);
  } catch (const UsageError& e) {
    printError(e.error.line());
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    printError("out of memory");
    return kExitBadInput;
  } catch (const std::exception& e) {
    printError(engine::Error{"", e.what()}.line());
    return kExitBadInput;
  }
  return 0;
}
