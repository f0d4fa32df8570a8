// Dispatch by SimdChoice: the index of a target's entry in Highway's dispatch tables, and a table
// of its own that reports which target ran (tests check the mapping with it).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "raster/simd.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster {
namespace HWY_NAMESPACE {
int64_t TargetOfThisTable() { return HWY_TARGET; }
}  // namespace HWY_NAMESPACE
}  // namespace penumbra::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>

namespace penumbra::raster {

HWY_EXPORT(TargetOfThisTable);

std::vector<int64_t> supportedSimdTargets() { return hwy::SupportedAndGeneratedTargets(); }

const char* simdTargetName(int64_t target) { return target == 0 ? "best" : hwy::TargetName(target); }

bool isSupportedSimdTarget(int64_t target) {
  if (target == 0) return true;
  const std::vector<int64_t> all = supportedSimdTargets();
  return std::find(all.begin(), all.end(), target) != all.end();
}

size_t simdDispatchIndex(int64_t target) {
  // 0: Highway's own choice, as HWY_DYNAMIC_DISPATCH makes it (entry 0, which chooses and caches,
  // until the first dispatch; then the cached best). Entry 0 on every call would re-detect the CPU
  // each time.
  if (target == 0) return hwy::GetChosenTarget().GetIndex();
  // HWY_EXPORT tables: entry 0 chooses, then one entry per dynamic target (HWY_CHOSEN_TARGET_SHIFT
  // of its bit, hwy/targets.h), the scalar fallback last.
  if (target == HWY_SCALAR || target == HWY_EMU128) return HWY_MAX_DYNAMIC_TARGETS + 1;
  return hwy::Num0BitsBelowLS1Bit_Nonzero64(static_cast<uint64_t>(HWY_CHOSEN_TARGET_SHIFT(target)));
}

int64_t simdTargetRun(int64_t target) {
  auto* fn = HWY_DISPATCH_TABLE(TargetOfThisTable)[simdDispatchIndex(target)];
  return (fn ? fn : HWY_DISPATCH_TABLE(TargetOfThisTable)[0])();
}

}  // namespace penumbra::raster
#endif  // HWY_ONCE
