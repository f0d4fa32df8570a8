// Texture filtering: sRGB conversions, the box-filtered mip chain and trilinear sampling.
//
// Conventions: texels are RGBA8 with sRGB-encoded color and linear alpha (glTF base color).
// Texture coordinates follow glTF: u to the right, v down, (0, 0) is the top-left corner of
// texel (0, 0), texel (x, y) has its center at ((x + 0.5) / width, (y + 0.5) / height).
// Wrapping is repeat on both axes. Filtering is done in linear space: texels are decoded to linear
// before they are averaged or interpolated.
//
// Thread-safety: all functions are pure. buildMips() writes the texture it is given (one thread per
// texture); sampleBilinear() only reads and may be called from any number of threads at once.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "engine/scene.h"

namespace penumbra::engine {

// sRGB transfer function (IEC 61966-2-1), decode: c / 12.92 below 0.04045, else
// ((c + 0.055) / 1.055)^2.4, with c = v / 255. Exact to float precision through a 256-entry table.
float srgbToLinear(uint8_t v);

// The inverse encode, rounded to the nearest 8-bit code: 12.92 x below 0.0031308, else
// 1.055 x^(1/2.4) - 0.055. Input clamped to [0, 1]; NaN gives 0. linearToSrgb(srgbToLinear(v)) == v.
uint8_t linearToSrgb(float linear);

// Replaces mips[1..] with the chain built from mips[0]: level k + 1 has size
// (max(1, w_k / 2), max(1, h_k / 2)), down to 1x1. Each texel is the area-weighted box average of
// the footprint it covers in the level above (exact for odd sizes too: a footprint then spans
// parts of three texels), color averaged in linear space and re-encoded to sRGB, alpha averaged
// as stored. Colors are not premultiplied by alpha. Does nothing if mips is empty or mips[0] is.
void buildMips(Texture& texture);

// Trilinear lookup: bilinear within levels floor(lod) and floor(lod) + 1, linear between them.
// lod is the mip level (0 = full resolution), clamped to [0, mips.size() - 1]. Returns linear RGB
// (sRGB decoded) and alpha as stored, in [0, 1]. A texture without texels samples as opaque white;
// non-finite uv or lod are treated as 0.
glm::vec4 sampleBilinear(const Texture& texture, glm::vec2 uv, float lod);

}  // namespace penumbra::engine
