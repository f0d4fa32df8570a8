// Occlusion textures (Eisemann & Décoret, "Plausible image based soft shadows using occlusion
// textures", SIBGRAPI 2006; the course slides in ../shared/papers): the casters sliced into layers
// parallel to the light, each layer a coverage texture, pre-filtered (a summed-area table), and a
// receiver's visibility the product of the layers' transmissions through the light's footprint.
//
// 1. Layers: L slabs between the map's near plane and the farthest receiver, uniform in 1/depth
//    (the resolution of a perspective map). Each slab is rendered by the pipeline into a depth map
//    whose near plane is the slab's front (homogeneous clipping), from only the triangles whose
//    depth range meets the slab; a texel whose nearest surface lies before the slab's back is
//    covered. Triangles are binned to the slabs they span, so the L renders cost about one or two
//    full ones. Slabs no triangle reaches are skipped (no render, no pass over the receivers).
//    A layer's tables (below) cover only the rectangle of its covered texels, and a receiver whose
//    widest footprint on the slab (at its front) misses that rectangle skips the layer: casters
//    fill a few percent of the receivers' frustum, so most of each map is neither filtered nor
//    read. Default 4 layers: more split more solids (see Fails) and cost more.
// 2. Filter: a receiver at depth d_r sees the light through a layer at depth z in the light's
//    rectangle scaled by (d_r - z) / d_r, in the map's tangent units half-extents (w/2, h/2)
//    (1/z - 1/d_r) around its own tangent point (Soler & Sillion's convolution). The paper takes
//    each layer at its slab's back plane, which sharpens every shadow by a slab's worth; Penumbra
//    takes it at the middle (in 1/depth) of the slab's part in front of the receiver
//    (layer_depth=slab) or, by default (layer_depth=occluders), at the mean depth of the covered
//    texels in that middle footprint, clamped to the part: a blocker search per layer, which
//    gives each occluder its own penumbra width however thick the slab. The mean coverage over the
//    box is an exact query of the layer's integer summed-area table (raster/sat.h; a second
//    channel sums the covered texels' depths): constant time in the light's size.
// 3. Fusion: V = horizonFraction * prod_k (1 - coverage_k), layers in a fixed order (the paper's
//    multiplicative accumulation: it treats the layers' occlusions as independent).
// 3b. Penumbra's variant (slices=map, fusion=sum; not the default): the layers dealt from one
//    depth map (each texel to the slab of its nearest surface: what the light's centre sees, each
//    surface once, occluders hidden behind others lost as in every single-map technique) and their
//    occlusions summed (V = 1 - sum, clamped: disjoint, which a height field's depth bands nearly
//    are). It trades the paper's over-darkening of solids split across slabs for the area
//    accumulation's over-counting of occluders that overlap only as a receiver sees them.
// 4. Receiver-plane test (plane_test=on, Penumbra's addition, default): the paper filters only
//    the layers wholly in front of the receiver, so an occluder in the receiver's own slab (a foot
//    on the ground, a fold) casts nothing there. The test adds that slab's part in front of the
//    receiver, counting only its covered texels nearer the light than the receiver's tangent plane
//    (biased, as PCF's taps; else the receiver's own surface would shadow it): a min/max depth
//    pyramid of the layer settles whole blocks (all nearer: the table's coverage of the block;
//    none: nothing) and refines the others down to texels. It applies to every layer, which
//    removes self-shadowing where a curved surface crosses the slabs. A point behind the tangent
//    plane can only hide light below it, which V's definition already counts as blocked.
// Fails (the paper's method) where the layers' independence is wrong. One occluder split across
// layers: where its parts hide disjoint parts of the light (a wall seen edge-on, a steep or curved
// surface) the product leaks light (two halves each hiding half: 1/4 instead of 0; L equal parts
// tend to e^-1), where they hide the same part (a box's top and its sides) it is too dark in the
// penumbra. Separate occluders in one layer count as their union (right), in different layers as
// independent (right on average, wrong where they overlap exactly). A slab is flattened to one
// depth per footprint, so occluders at different depths in one footprint share a penumbra width.
// The note counts the triangles split across layers. docs/techniques/occtex.md.
//
// Thread-safety: as every technique (technique.h): one thread at a time uses an instance.
#pragma once

#include "shadows/technique.h"

namespace penumbra::shadows {
TechniqueInfo occtexTechnique();
}
