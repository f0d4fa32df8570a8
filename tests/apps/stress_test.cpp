// The raster stress suite passes (every judged case: no crack, double hit, NaN or depth-order
// error), and each check would notice a failure.
#include <gtest/gtest.h>

#include "apps/stress_raster.h"

namespace penumbra::apps {
namespace {

TEST(Stress, RasterSuitePasses) {
  raster::Rasterizer r({.threads = 2});
  const std::vector<StressRow> rows = runRasterStress(r);
  ASSERT_GT(rows.size(), 20u);
  int judged = 0;
  for (const StressRow& row : rows) {
    EXPECT_TRUE(row.ok()) << row.json();
    EXPECT_GT(row.pixels, 0u) << row.json();
    judged += row.judged;
  }
  EXPECT_GT(judged, 25);
}

TEST(Stress, StandardZAtExtremeRatiosIsReportedAsBroken) {
  // The unjudged standard-Z row at far/near = 1e7 really does fail: the check can see failure.
  raster::Rasterizer r({.threads = 1});
  bool sawErrors = false;
  for (const StressRow& row : runRasterStress(r))
    if (!row.judged && row.depthErrors > 0) sawErrors = true;
  EXPECT_TRUE(sawErrors);
}

}  // namespace
}  // namespace penumbra::apps
