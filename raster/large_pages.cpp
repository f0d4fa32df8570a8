#include "raster/large_pages.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace penumbra::raster {

void adviseLargePages([[maybe_unused]] void* p, [[maybe_unused]] size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // A hint: failure (no transparent huge pages in this kernel) leaves ordinary pages.
  (void)madvise(p, bytes, MADV_HUGEPAGE);
#endif
}

}  // namespace penumbra::raster
