// View-warped multi-view soft shadows (Marrs, Watson, Healey, "View-Warped Multi-View Soft
// Shadows for Local Area Lights", JCGT 2018; ../shared/papers): MVR's depth maps without
// rasterizing the casters once per map.
//
//  1. Point generation (section 3.1): the casters are rasterized once, from a source view behind
//     the light's centre that contains the whole light and every receiver (makeContainingView,
//     Eqs. 1-3: moved back by D, near plane on the light, resolution raised by (near + D) / near,
//     times `oversample`), with the depth test off: every fragment becomes a world-space point,
//     the hidden layers included (which is what removes the disocclusion leaks of naive warping,
//     the paper's Fig. 4 b; the containing view removes the field-of-view leaks, Fig. 4 a, c).
//     With splat=surfel each point carries its source pixel's footprint on its triangle's plane.
//     cull=auto (default) leaves out the faces of closed meshes that the whole light sees from
//     behind by more than 30 degrees (shadow_map.h casterDraws).
//  2. Depth maps (section 3.2): the points are splatted (raster/splat.h splatDepth: an atomic max
//     on the bits of the reversed depth, the paper's Listing 2) into M light-sample views -- the
//     same light points and fitted views as `mvr` -- K views per traversal of the points; the K
//     maps are 32-bit depth read in place by the tests, reused pass after pass with only the
//     rectangle the points touched cleared. A surfel covers the texel centres inside its
//     projected footprint with its plane's depth there; a point (splat=point, the paper) its own
//     texel with its own depth.
//  3. Shading: per receiver and map, the texel (or, pcf=5, with its 4 neighbours) with the
//     receiver-plane test of `mvr` and the receiver's horizon exactly per light sample, over the K
//     maps of a pass at once (light_samples.h); V = lit taps / all taps.
//
// Variants: `buffered` (points stored, then splatted: one rasterization) and `unbuffered`
// (fragments splatted straight from the point-generation pass: one rasterization per pass of K
// maps, no point storage). Two deliberately naive variants show what the method fixes:
// `layers=nearest` keeps only the nearest fragment per source texel (a plain depth map warped),
// `containing=off` puts the source view on the light's centre.
//
// Timing: point generation (ms_points) and clearing and splatting (ms_splat) make "maps" (ms_maps),
// the tests "evaluate". docs/techniques/vwss.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance;
// generateLightPoints runs in the rasterizer's arena and writes only its result.
#pragma once

#include <glm/vec3.hpp>
#include <vector>

#include "raster/splat.h"
#include "shadows/shadow_map.h"
#include "shadows/technique.h"

namespace penumbra::shadows {

TechniqueInfo vwssTechnique();

// Point generation: rasterizes `casters` from `source` (faces that the whole light sees from behind
// culled as `cull` says, shadow_map.h casterDraws) and either the depth test off (allLayers: every fragment becomes a point) or
// on (the nearest fragment of each texel only: what warping a plain depth map would use). Points
// are world positions; the payload of a point is its source texel y * width + x; with `surfels`,
// each point's surfel axes too: its source pixel's footprint on its triangle's plane
// (raster/splat.h). Deterministic order: tiles in order, each tile's fragments in submission order.
struct LightPoints {
  std::vector<glm::vec3> points;
  std::vector<raster::SurfelAxes> surfels;
  std::vector<uint32_t> payloads;
  raster::PassStats pass;
};
LightPoints generateLightPoints(raster::Rasterizer& raster, const Geometry& casters, const LightView& source,
                                const RectLight& light, bool allLayers, CasterCull cull, bool surfels = false);

}  // namespace penumbra::shadows
