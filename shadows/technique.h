// The shadow technique interface and registry (DESIGN.md, "Shadows").
//
// A technique estimates V(x) (area_light.h) for every receiver of a G-buffer. It has a name and
// typed parameters with defaults and ranges; `prepare` builds its maps by running the pipeline's
// own stages (depth-only passes, fragment stages writing moments, image kernels) on the light's
// views; `evaluate` fills the visibility image. The registry lists every technique; the CLI, the
// benchmark and the tests enumerate it, so a new technique is everywhere at once.
//
// Timing: a technique records the milliseconds of its own stages in ShadowContext::times (maps:
// rasterizing the light's views; filter: image kernels over the maps; evaluate: the per-receiver
// lookups), and what it did in ShadowContext::notes (printed with --stats).
// Thread-safety: a technique object is used by one thread at a time; it runs its parallel loops in
// the context's rasterizer arena. Results are deterministic, identical at every thread count.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "raster/image.h"
#include "raster/pipeline.h"
#include "shadows/area_light.h"
#include "shadows/light_view.h"
#include "shadows/result_cache.h"

namespace penumbra::shadows {

// ---- Parameters ---------------------------------------------------------------------------------

enum class ParamKind { Int, Float, Choice };

struct ParamSpec {
  std::string name;
  ParamKind kind = ParamKind::Float;
  double defaultValue = 0, minValue = 0, maxValue = 0;  // Choice: index into choices
  std::vector<std::string> choices;
  std::string help;
};

// A Choice parameter: `choices[defaultIndex]` unless set.
ParamSpec choiceParam(std::string name, int defaultIndex, std::vector<std::string> choices, std::string help);

// Values for a list of specs, each validated against its range when set.
class ParamSet {
 public:
  ParamSet() = default;
  explicit ParamSet(const std::vector<ParamSpec>& specs);

  // Parses and sets "name=value". Returns an error message (naming the parameter, its range or its
  // choices) or nothing.
  std::optional<std::string> set(std::string_view assignment);
  // Parses a comma-separated list of assignments ("" sets nothing).
  std::optional<std::string> setAll(std::string_view list);

  double number(std::string_view name) const;  // Int and Float
  int integer(std::string_view name) const;
  const std::string& choice(std::string_view name) const;
  // "name=value,name=value" for every parameter that differs from its default ("" when none).
  std::string changed() const;
  // Every parameter, in spec order.
  std::string all() const;
  const std::vector<ParamSpec>& specs() const { return *specs_; }

 private:
  size_t index(std::string_view name) const;
  std::string format(size_t i) const;
  const std::vector<ParamSpec>* specs_ = nullptr;
  std::vector<double> values_;
};

// ---- Inputs and context ------------------------------------------------------------------------

struct ShadowInputs {
  Geometry casters;                    // world-space triangles that may cast shadows
  const ReceiverImage* receivers = nullptr;
  RectLight light;
  ResultCache* cache = nullptr;        // techniques that keep results between runs (the ground truth)
                                       // use it; null = none
  // Cull triangles outside the light's region (LightRegion). Off only to measure what culling
  // saves: every triangle is drawn, with the same views (near plane and frustum) as with culling.
  bool cullCasters = true;
  // Moving casters (motion-blurred soft shadows): every vertex of `casters` at shutter open (t = 0)
  // and close (t = 1), indexed as casters.positions (which holds them at the frame's casters' time);
  // a vertex at time t is open + (close - open) t. Empty (the default) when nothing moves or the
  // frame freezes its casters. Techniques that sample time (the reference, sssm) trace or render
  // the casters at each sample's time; the others use casters.positions. Moving triangles are never
  // culled (ShadowContext::casters keeps them; the near plane allows for their whole path).
  std::span<const glm::vec3> castersOpen{}, castersClose{};
  bool castersMove() const { return !castersOpen.empty(); }
};

struct StageTimes {
  double msMaps = 0, msFilter = 0, msEvaluate = 0;
  // Parts of msMaps, where a technique makes its maps in two steps (vwss: point generation, then
  // clearing and splatting); 0 for the others.
  double msPoints = 0, msSplat = 0;
  double prepare() const { return msMaps + msFilter; }
  double total() const { return msMaps + msFilter + msEvaluate; }
};

struct ShadowContext {
  raster::Rasterizer& raster;
  const ShadowInputs& in;
  LightRegion region;   // fitted by the caller (fitRegion)
  CasterSet casters;    // culled by the caller (cullCasters); indices into in.casters.positions
  StageTimes times;
  std::vector<std::string> notes;
  raster::PassStats mapPasses;  // summed over the technique's rasterization passes

  Geometry casterGeometry() const { return {in.casters.positions, casters.indices, casters.closed}; }
  // Near plane for views of this light: a little in front of the nearest kept caster.
  float nearPlane() const;
};

// ---- Techniques and the registry ---------------------------------------------------------------

class Technique {
 public:
  virtual ~Technique() = default;
  virtual void prepare(ShadowContext& ctx, const ParamSet& params) = 0;
  // visibility is resized to the receivers' size; background texels get 1, receivers behind the
  // light 0.
  virtual void evaluate(ShadowContext& ctx, raster::ImageFloat& visibility) = 0;
};

struct TechniqueInfo {
  std::string name;
  std::string summary;               // one line
  std::vector<ParamSpec> params;
  std::vector<std::string> benchSettings;  // parameter lists `penumbra bench shadows` runs
  bool isReference = false;          // the ray-traced ground truth (not benchmarked against itself)
  std::function<std::unique_ptr<Technique>()> make;
  // Bytes the technique holds at its peak for one light (maps, buffers, acceleration structures)
  // beyond the shared inputs, for `casterTriangles` casters; the engine's memory estimate adds it.
  // Empty: 32 bytes per texel of one map_size^2 map (up to four float moments, a blur buffer and a
  // min/max pyramid), or nothing without map_size.
  std::function<uint64_t(const ParamSet& params, uint64_t casterTriangles)> peakBytes = nullptr;
  // Bytes the technique keeps per receiver pixel beyond the shared inputs (the engine's estimate
  // adds them per pixel and layer).
  uint64_t receiverBytes = 0;
  // Samples shutter time: moving casters (ShadowInputs::castersOpen) cast motion-blurred soft
  // shadows. The engine hands the casters' motion only to these; the others see them frozen.
  bool samplesTime = false;
};

// Every technique, in a fixed order (the ground truth, "reference", last).
const std::vector<TechniqueInfo>& registry();
const TechniqueInfo* findTechnique(std::string_view name);
// "hard, pcf, pcss, ..." for messages.
std::string techniqueNames();

// The whole computation for one light: fit the region, cull casters, prepare, evaluate. The
// returned context holds the stage times and notes.
struct ShadowResult {
  raster::ImageFloat visibility;
  StageTimes times;
  std::vector<std::string> notes;
  LightRegion region;
  size_t trianglesIn = 0, trianglesCulled = 0;
  bool skipped = false;             // no receiver in front of the light, or no caster reaches one
  std::string skipReason;
  raster::PassStats mapPasses;
  double msFit = 0;                 // region fitting and caster culling
};
ShadowResult computeShadows(raster::Rasterizer& raster, const ShadowInputs& in, const TechniqueInfo& info,
                            const ParamSet& params);

// Helpers shared by techniques.
// Stage timing: milliseconds since t (steady clock).
using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// How a technique accounts for the receiver's own surface, which its biased depth tests do not
// see: Horizon multiplies its V by horizonFraction (area_light.h: the part of the light below the
// tangent plane is blocked by a closed surface itself; treated as independent of the other
// occluders); Handled: the technique applies it itself (exactly, per light sample) or has no need.
enum class SelfShadow { Horizon, Handled };
// Fills background texels with 1 and receivers behind the light with 0 and calls f(x, y, receiver)
// for the others, rows in parallel in the rasterizer's arena; f returns V.
template <class F>
void forEachReceiver(ShadowContext& ctx, raster::ImageFloat& visibility, F&& f,
                     SelfShadow self = SelfShadow::Horizon);

}  // namespace penumbra::shadows

#include "shadows/technique_inl.h"
