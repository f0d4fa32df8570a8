#include "shadows/technique.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "shadows/registry_list.h"

namespace penumbra::shadows {

// ---- ParamSet -----------------------------------------------------------------------------------

ParamSet::ParamSet(const std::vector<ParamSpec>& specs) : specs_(&specs) {
  for (const ParamSpec& s : specs) values_.push_back(s.defaultValue);
}

size_t ParamSet::index(std::string_view name) const {
  for (size_t i = 0; specs_ && i < specs_->size(); ++i)
    if ((*specs_)[i].name == name) return i;
  throw std::invalid_argument("no parameter '" + std::string(name) + "'");
}

std::string ParamSet::format(size_t i) const {
  const ParamSpec& s = (*specs_)[i];
  const double v = values_[i];
  switch (s.kind) {
    case ParamKind::Int: return std::to_string(static_cast<long long>(v));
    case ParamKind::Choice: return s.choices[static_cast<size_t>(v)];
    case ParamKind::Float: {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%g", v);
      return buf;
    }
  }
  return {};
}

std::optional<std::string> ParamSet::set(std::string_view assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0)
    return "parameter '" + std::string(assignment) + "' is not of the form name=value";
  const std::string_view name = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  size_t i = 0;
  for (; specs_ && i < specs_->size(); ++i)
    if ((*specs_)[i].name == name) break;
  if (!specs_ || i == specs_->size()) {
    std::string known;
    for (size_t k = 0; specs_ && k < specs_->size(); ++k) known += (k ? ", " : "") + (*specs_)[k].name;
    return "unknown parameter '" + std::string(name) + "' (known: " + (known.empty() ? "none" : known) + ")";
  }
  const ParamSpec& s = (*specs_)[i];
  if (s.kind == ParamKind::Choice) {
    for (size_t c = 0; c < s.choices.size(); ++c)
      if (s.choices[c] == text) {
        values_[i] = static_cast<double>(c);
        return std::nullopt;
      }
    std::string list;
    for (size_t c = 0; c < s.choices.size(); ++c) list += (c ? ", " : "") + s.choices[c];
    return "parameter '" + s.name + "' must be one of " + list + ", not '" + std::string(text) + "'";
  }
  double v = 0;
  const char* end = text.data() + text.size();
  if (s.kind == ParamKind::Int) {
    long long iv = 0;
    const auto r = std::from_chars(text.data(), end, iv);
    if (text.empty() || r.ec != std::errc() || r.ptr != end)
      return "parameter '" + s.name + "' must be an integer, not '" + std::string(text) + "'";
    v = static_cast<double>(iv);
  } else {
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
      return "parameter '" + s.name + "' must be a finite number, not '" + std::string(text) + "'";
  }
  if (v < s.minValue || v > s.maxValue) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "parameter '%s' must be in [%g, %g], not %s", s.name.c_str(), s.minValue, s.maxValue,
                  std::string(text).c_str());
    return std::string(buf);
  }
  values_[i] = v;
  return std::nullopt;
}

std::optional<std::string> ParamSet::setAll(std::string_view list) {
  while (!list.empty()) {
    const size_t comma = list.find(',');
    const std::string_view one = list.substr(0, comma);
    if (auto err = set(one)) return err;
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return std::nullopt;
}

double ParamSet::number(std::string_view name) const { return values_[index(name)]; }
int ParamSet::integer(std::string_view name) const { return static_cast<int>(values_[index(name)]); }
const std::string& ParamSet::choice(std::string_view name) const {
  const size_t i = index(name);
  return (*specs_)[i].choices[static_cast<size_t>(values_[i])];
}

std::string ParamSet::changed() const {
  std::string out;
  for (size_t i = 0; specs_ && i < specs_->size(); ++i)
    if (values_[i] != (*specs_)[i].defaultValue) out += (out.empty() ? "" : ",") + (*specs_)[i].name + "=" + format(i);
  return out;
}

std::string ParamSet::all() const {
  std::string out;
  for (size_t i = 0; specs_ && i < specs_->size(); ++i) out += (i ? "," : "") + (*specs_)[i].name + "=" + format(i);
  return out;
}

// ---- Context, registry, driver ------------------------------------------------------------------

ParamSpec choiceParam(std::string name, int defaultIndex, std::vector<std::string> choices, std::string help) {
  const double last = static_cast<double>(choices.size() - 1);
  return {.name = std::move(name),
          .kind = ParamKind::Choice,
          .defaultValue = static_cast<double>(defaultIndex),
          .minValue = 0,
          .maxValue = last,
          .choices = std::move(choices),
          .help = std::move(help)};
}

float ShadowContext::nearPlane() const {
  // Views start at the light plane; the nearest kept caster bounds how far the near plane may go.
  const float farthest = std::max(region.hi.z, 1e-6f);
  const float nearest = casters.minDepth > 0.0f ? casters.minDepth : farthest;
  return std::max(nearest * 0.99f, farthest * 1e-5f);
}

const std::vector<TechniqueInfo>& registry() {
  static const std::vector<TechniqueInfo> list = allTechniques();
  return list;
}

const TechniqueInfo* findTechnique(std::string_view name) {
  for (const TechniqueInfo& t : registry())
    if (t.name == name) return &t;
  return nullptr;
}

std::string techniqueNames() {
  std::string s;
  for (const TechniqueInfo& t : registry()) s += (s.empty() ? "" : ", ") + t.name;
  return s;
}

namespace {

// Moving casters: the culling tested each triangle where it is at the casters' time, but on its
// way it may cross the light's region. Every triangle with a moving vertex is kept (in order, among
// the kept static ones), and the nearest depth allows for each kept vertex's open and close
// positions (depth along the light's axis is linear in time, so its minimum is at an end).
void keepMovingCasters(const ShadowInputs& in, CasterSet& set) {
  const Geometry& g = in.casters;
  if (in.castersOpen.size() != g.positions.size() || in.castersClose.size() != g.positions.size())
    throw std::invalid_argument("shadows: castersOpen and castersClose must match the casters' positions");
  const auto moves = [&](uint32_t v) {
    return v < g.positions.size() && in.castersOpen[v] != in.castersClose[v];
  };
  std::vector<uint32_t> kept;
  kept.reserve(set.indices.size());
  size_t next = 0;  // the next triangle of set.indices (a subsequence of g.indices, in order)
  for (size_t t = 0; t < g.triangles(); ++t) {
    const uint32_t* tri = &g.indices[3 * t];
    const bool inSet = next + 3 <= set.indices.size() &&
                       std::equal(tri, tri + 3, set.indices.begin() + static_cast<std::ptrdiff_t>(next));
    if (inSet) next += 3;
    if (inSet || moves(tri[0]) || moves(tri[1]) || moves(tri[2])) kept.insert(kept.end(), tri, tri + 3);
  }
  set.trianglesCulled = set.trianglesIn - kept.size() / 3;
  set.indices = std::move(kept);
  const RectLight& light = in.light;
  if (set.minDepth == 0.0f) set.minDepth = std::numeric_limits<float>::max();  // 0: none kept
  for (uint32_t v : set.indices) {
    if (v >= g.positions.size()) continue;
    for (const glm::vec3& p : {in.castersOpen[v], in.castersClose[v]}) {
      const float d = toLightSpace(light, p).z;
      if (d > 0.0f && d < set.minDepth) set.minDepth = d;
    }
  }
  if (set.indices.empty() || set.minDepth == std::numeric_limits<float>::max()) set.minDepth = 0.0f;
}

}  // namespace

ShadowResult computeShadows(raster::Rasterizer& raster, const ShadowInputs& in, const TechniqueInfo& info,
                            const ParamSet& params) {
  ShadowResult out;
  const auto t0 = Clock::now();
  ShadowContext ctx{.raster = raster, .in = in, .region = {}, .casters = {}, .times = {}, .notes = {}, .mapPasses = {}};
  raster.run([&] {
    ctx.region = fitRegion(in.light, *in.receivers);
    ctx.casters = cullCasters(in.light, ctx.region, in.casters, in.receivers);
  });
  if (!in.cullCasters && !ctx.region.empty) {  // same near plane, every triangle drawn
    ctx.casters.indices.assign(in.casters.indices.begin(), in.casters.indices.end());
    ctx.casters.trianglesCulled = 0;
  }
  if (in.castersMove() && !ctx.region.empty) keepMovingCasters(in, ctx.casters);
  out.msFit = msSince(t0);
  out.region = ctx.region;
  out.trianglesIn = ctx.casters.trianglesIn;
  out.trianglesCulled = ctx.casters.trianglesCulled;
  if (ctx.region.empty || ctx.casters.indices.empty()) {
    // Nothing can be shadowed: every receiver in front of the light sees all of it.
    out.skipped = true;
    out.skipReason = ctx.region.empty ? "no visible receiver in front of the light"
                                      : "no caster can reach a visible receiver";
    const auto t1 = Clock::now();
    forEachReceiver(ctx, out.visibility, [](int, int, const Receiver&) { return 1.0f; }, SelfShadow::Handled);
    out.times.msEvaluate = msSince(t1);
    return out;
  }
  std::unique_ptr<Technique> tech = info.make();
  tech->prepare(ctx, params);
  tech->evaluate(ctx, out.visibility);
  out.times = ctx.times;
  out.notes = std::move(ctx.notes);
  out.mapPasses = ctx.mapPasses;
  return out;
}

}  // namespace penumbra::shadows
