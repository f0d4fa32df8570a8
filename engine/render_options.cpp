#include "engine/render_options.h"

#include <cmath>
#include <cstdio>

namespace penumbra::engine {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

}  // namespace

std::string OptionSpec::range() const {
  const std::string r = std::string(loOpen ? "(" : "[") + num(lo) + ", " + num(hi) + (hiOpen ? ")" : "]");
  return powerOfTwo ? "a power of 2 in " + r : r;
}

bool OptionSpec::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (loOpen ? !(v > lo) : !(v >= lo)) return false;
  if (hiOpen ? !(v < hi) : !(v <= hi)) return false;
  if (powerOfTwo) {
    const auto i = static_cast<long long>(v);
    if (static_cast<double>(i) != v || i < 1 || (i & (i - 1)) != 0) return false;
  }
  return true;
}

Status OptionSpec::check(double v) const {
  if (contains(v)) return Ok{};
  return Error{std::string("option ") + option, "must be " + std::string(powerOfTwo ? "" : "in ") + range() + ", got " + num(v)};
}

const char* toneMapName(ToneMap t) { return t == ToneMap::Aces ? "aces" : "none"; }

bool parseToneMap(const std::string& name, ToneMap& t) {
  if (name == "none") t = ToneMap::None;
  else if (name == "aces") t = ToneMap::Aces;
  else return false;
  return true;
}

Result<ResolvedOptions> resolveOptions(const RenderOptions& o) {
  for (const auto& [spec, v] : {std::pair{&kWidthOption, double(o.width)}, std::pair{&kHeightOption, double(o.height)},
                                std::pair{&kSppOption, double(o.spp)}, std::pair{&kDualBlockOption, double(o.dualBlock)},
                                std::pair{&kMsaaOption, double(o.msaa)},
                                std::pair{&kFrameOption, double(o.frame)}, std::pair{&kExposureOption, o.exposure}})
    if (Status st = spec->check(v); !st) return st.error();
  if (o.timeStrata)
    if (Status st = kTimeStrataOption.check(*o.timeStrata); !st) return st.error();
  if (o.lensStrata)
    if (Status st = kLensStrataOption.check(*o.lensStrata); !st) return st.error();
  if (o.camera) {
    const Camera& c = *o.camera;
    if (Status st = kFovOption.check(c.fovYDegrees); !st) return st.error();
    if (Status st = kApertureOption.check(c.apertureRadius); !st) return st.error();
    if (c.focusDistance != 0.0f)  // 0: the distance from eye to target
      if (Status st = kFocusOption.check(c.focusDistance); !st) return st.error();
    for (const glm::vec3& v : {c.eye, c.target, c.up})
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        return Error{"option --eye/--target", "the camera needs finite coordinates"};
    if (c.eye == c.target) return Error{"option --eye", "camera eye and target coincide"};
  }
  if (o.at) {
    const stochastic::Sample& s = *o.at;
    if (!(s.t >= 0.0f && s.t <= 1.0f) || !(s.u * s.u + s.v * s.v <= 1.0f))
      return Error{"fixed sample", "needs t in [0, 1] and (u, v) in the unit disk"};
  }

  ResolvedOptions r;
  r.options = o;
  if (o.shadow == "none") {
    if (!o.shadowParams.empty()) return Error{"option --param", "the shadow technique 'none' has no parameters"};
  } else {
    r.technique = shadows::findTechnique(o.shadow);
    if (!r.technique)
      return Error{"option --shadow", "unknown technique '" + o.shadow + "' (valid: none, " + shadows::techniqueNames() + ")"};
    r.params = shadows::ParamSet(r.technique->params);
    for (const std::string& p : o.shadowParams)
      if (auto err = r.params.setAll(p)) return Error{"option --param", *err + " for technique '" + o.shadow + "'"};
  }
  stochastic::StochasticConfig& cfg = r.sampling;
  cfg.method = o.bounds;
  cfg.timeStrata = o.timeStrata.value_or(0);  // 0: the rasterizer's default
  cfg.lensStrata = o.lensStrata.value_or(0);
  cfg.dualBlock = o.dualBlock;
  cfg.staticShortcut = o.staticShortcut;
  cfg.pattern.spp = o.spp;
  cfg.pattern.frame = static_cast<uint32_t>(o.frame);
  return r;
}

}  // namespace penumbra::engine
