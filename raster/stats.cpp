#include "raster/stats.h"

#include <cstdio>

namespace penumbra::raster {

PassStats& PassStats::operator+=(const PassStats& o) {
  verticesIn += o.verticesIn;
  verticesNonFinite += o.verticesNonFinite;
  trianglesIn += o.trianglesIn;
  trianglesDroppedInvalid += o.trianglesDroppedInvalid;
  trianglesCulledFrustum += o.trianglesCulledFrustum;
  trianglesCulledFacing += o.trianglesCulledFacing;
  trianglesCulledDegenerate += o.trianglesCulledDegenerate;
  trianglesCulledNoSample += o.trianglesCulledNoSample;
  trianglesClipped += o.trianglesClipped;
  trianglesFromClipping += o.trianglesFromClipping;
  trianglesBinned += o.trianglesBinned;
  binEntries += o.binEntries;
  tilesTotal += o.tilesTotal;
  tilesTouched += o.tilesTouched;
  tilesSkipped += o.tilesSkipped;
  blocksTested += o.blocksTested;
  blocksRejectedEdge += o.blocksRejectedEdge;
  blocksRejectedDepth += o.blocksRejectedDepth;
  blocksAccepted += o.blocksAccepted;
  blocksPartial += o.blocksPartial;
  pixelsTested += o.pixelsTested;
  pixelsCovered += o.pixelsCovered;
  pixelsDepthPassed += o.pixelsDepthPassed;
  msVertex += o.msVertex;
  msSetupBin += o.msSetupBin;
  msRaster += o.msRaster;
  msTotal += o.msTotal;
  return *this;
}

std::string PassStats::report(const std::string& title) const {
  char buf[2048];
  auto ull = [](uint64_t v) { return static_cast<unsigned long long>(v); };
  std::snprintf(
      buf, sizeof buf,
      "%s: %.2f ms (vertex %.2f, setup+bin %.2f, raster %.2f)\n"
      "  vertices %llu (non-finite dropped %llu)\n"
      "  triangles in %llu: dropped invalid %llu, culled frustum %llu, facing %llu, degenerate %llu, "
      "no sample %llu; clipped %llu -> %llu; binned %llu (%llu tile entries)\n"
      "  tiles %llu: touched %llu, skipped (empty) %llu\n"
      "  blocks tested %llu: rejected by edges %llu, by coarse depth %llu; accepted whole %llu, partial %llu\n"
      "  pixels tested %llu, covered %llu, passed depth %llu\n",
      title.c_str(), msTotal, msVertex, msSetupBin, msRaster, ull(verticesIn), ull(verticesNonFinite),
      ull(trianglesIn), ull(trianglesDroppedInvalid), ull(trianglesCulledFrustum), ull(trianglesCulledFacing),
      ull(trianglesCulledDegenerate), ull(trianglesCulledNoSample), ull(trianglesClipped),
      ull(trianglesFromClipping), ull(trianglesBinned), ull(binEntries), ull(tilesTotal), ull(tilesTouched),
      ull(tilesSkipped), ull(blocksTested), ull(blocksRejectedEdge), ull(blocksRejectedDepth),
      ull(blocksAccepted), ull(blocksPartial), ull(pixelsTested), ull(pixelsCovered), ull(pixelsDepthPassed));
  return buf;
}

}  // namespace penumbra::raster
