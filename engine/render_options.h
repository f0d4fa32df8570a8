// What a frame is asked for (RenderOptions) and the one place it is checked: resolveOptions turns
// it into ResolvedOptions (the shadow technique and its parameter values, the stochastic pass's
// sample settings) or an Error naming the option and its range. The renderer takes only resolved
// options; the command line and the benchmarks pass the user's values through unchecked and print
// the Error; their help text quotes the ranges from the specs below.
//
// Thread-safety: plain values; resolveOptions is a pure function, safe from any thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/error.h"
#include "engine/scene.h"
#include "shadows/technique.h"
#include "stochastic/rasterizer.h"

namespace penumbra::engine {

// The range of a numeric option: [lo, hi], an end open where said; a power of two where said.
struct OptionSpec {
  const char* option;  // how the command line spells it, "--spp"; errors name it
  double lo = 0, hi = 0;
  bool loOpen = false, hiOpen = false;
  bool powerOfTwo = false;
  // "[1, 64]", "(0, 180)", "a power of 2 in [1, 64]".
  std::string range() const;
  bool contains(double v) const;
  // Ok, or Error{"option --spp", "must be in [1, 64], got 65"}.
  Status check(double v) const;
};

inline constexpr OptionSpec kWidthOption{"--width", 1, 16384};
inline constexpr OptionSpec kHeightOption{"--height", 1, 16384};
inline constexpr OptionSpec kThreadsOption{"--threads", 0, 1024};  // 0: all hardware threads
inline constexpr OptionSpec kFovOption{"--fov", 0, 180, true, true};
inline constexpr OptionSpec kApertureOption{"--aperture", 0, 1e6, false, true};
inline constexpr OptionSpec kFocusOption{"--focus", 0, 1e9, true, true};
inline constexpr OptionSpec kSppOption{"--spp", 1, stochastic::kMaxSpp};
inline constexpr OptionSpec kTimeStrataOption{"--strata (time strata T)", 1, stochastic::kMaxTimeStrata};
inline constexpr OptionSpec kLensStrataOption{"--strata (lens cells L)", 1, stochastic::kMaxLensStrata};
inline constexpr OptionSpec kDualBlockOption{"--dual-block", 1, stochastic::kMaxDualBlock, false, false, true};
inline constexpr OptionSpec kFrameOption{"--frame", 0, 4294967295.0};
inline constexpr OptionSpec kExposureOption{"--exposure", -20, 20};
inline constexpr OptionSpec kMsaaOption{"--msaa", 1, 8, false, false, true};

// How linear radiance becomes the 8-bit image (the EXR keeps the radiance as it is).
enum class ToneMap : uint8_t {
  None,  // clamp to [0, 1]
  Aces,  // Narkowicz's fit of the ACES filmic curve: highlights roll off instead of clipping
};
const char* toneMapName(ToneMap t);
bool parseToneMap(const std::string& name, ToneMap& t);  // "none", "aces"

struct RenderOptions {
  int width = 1280;    // pixels, kWidthOption
  int height = 720;    // pixels, kHeightOption
  // Overrides the scene's camera; its field of view, aperture and focus distance are checked
  // against kFovOption, kApertureOption and kFocusOption, eye and target must differ.
  std::optional<Camera> camera;
  // Soft shadows of the area lights: a technique of the shadows/ registry ("reference" is the
  // ray-traced ground truth) or "none" (unshadowed), with "name=value" parameters (each checked
  // against the technique's ParamSpec; a list "a=1,b=2" in one string is split at the commas).
  std::string shadow = "pcss";
  std::vector<std::string> shadowParams;
  // Where techniques may keep results between runs (the ground truth): engine/result_cache.h's
  // folder, or any ResultCache; null: none.
  std::shared_ptr<shadows::ResultCache> cache;
  bool shadowCulling = true;  // cull casters outside each light's region (off: to measure the saving)
  // Moving casters over the whole shutter for the techniques that sample time (reference, sssm:
  // motion-blurred soft shadows); off, or a frame at one fixed time: frozen at the casters' time
  // (mid-shutter), as every other technique always has them.
  bool shadowMotion = true;
  // Motion blur and depth of field: the stochastic pass (stochastic/), taken when a visible
  // instance moves or the camera has an aperture.
  int spp = 16;  // samples per pixel, kSppOption
  stochastic::BoundMethod bounds = stochastic::BoundMethod::DualSpace;
  // Interval bounds: time strata (kTimeStrataOption) and lens cells per axis (kLensStrataOption);
  // none: the defaults of StochasticConfig.
  std::optional<int> timeStrata, lensStrata;
  int dualBlock = 4;                   // dual-space bounds: block side, kDualBlockOption
  int64_t frame = 0;                   // seeds the sample pattern, kFrameOption
  bool staticPath = true;         // static instances seen through a pinhole take the ordinary G-buffer pass
  bool staticShortcut = true;     // in the stochastic pass, one test per pixel for a static triangle (pinhole)
  bool forceStochastic = false;   // a stochastic pass even with no motion and a pinhole (tests)
  // Keep Frame::linear, the radiance image (an EXR, an error measure, the Python module's array);
  // off: only the 8-bit image is written, and the frame neither fills nor allocates the 16 bytes a
  // pixel the radiance takes (the command line's render without --exr).
  bool linearImage = true;
  // Instead of a stochastic pass, the pinhole frame at one shutter time and lens position: every
  // instance at time t, the camera looking through lens point (u, v). Averaging many of these is
  // the accumulation-buffer reference of motion blur and depth of field. t in [0, 1), (u, v) in
  // the unit disk (t in [0, 1], both ends of the shutter included).
  std::optional<stochastic::Sample> at;
  stochastic::StochasticDebug debug;  // optional per-sample / per-pixel outputs of the stochastic pass
  // The 8-bit image: radiance times 2^exposure (kExposureOption, stops), then the tone map, then
  // sRGB. 0 and None leave the bytes as without them.
  double exposure = 0.0;
  ToneMap toneMap = ToneMap::None;
  // Multisample antialiasing of the ordinary G-buffer pass: samples per pixel, kMsaaOption (1, 2,
  // 4 or 8; 1: none). Not applied where a stochastic pass runs (its samples already antialias).
  int msaa = 1;
};

struct ResolvedOptions {
  RenderOptions options;                              // as given, every value in range
  const shadows::TechniqueInfo* technique = nullptr;  // null: "none"
  shadows::ParamSet params;                           // the technique's values
  stochastic::StochasticConfig sampling;              // method, strata, dual block, spp, frame, shortcut
};

// Checks every option; the Error names the first bad one ("option --spp", "option --param", ...).
Result<ResolvedOptions> resolveOptions(const RenderOptions& options);

}  // namespace penumbra::engine
