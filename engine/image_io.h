// Image files: writing renders (PNG, EXR, anything OpenImageIO writes, chosen by the file
// extension) and reading textures as RGBA8, from a file or from memory. PNG is encoded here
// (engine/png_encoder.h); everything else goes through OpenImageIO, in a module loaded on first
// use (engine/image_module.h: a process that writes only PNG never loads it).
//
// Writes never leave a partial file: the image goes to a temporary file in the destination
// directory, which is renamed over the destination only once it is complete; on any failure the
// temporary is removed and the destination is untouched.
//
// Pixel conventions: row 0 is the top row. Alpha is straight (not premultiplied) and is passed
// through as is: OIIO's premultiplication on read and un-premultiplication on write are turned off.
// ImageFloat4 holds linear RGBA: float formats (.exr,
// .hdr, .tif, .tiff, .pfm) store it as 32-bit float as is; 8-bit formats store color clamped to
// [0, 1] and sRGB-encoded, alpha clamped and linear. ImageFloat is data (depth, visibility, error):
// float formats store it as is, 8-bit formats store it clamped to [0, 1], linearly, as gray.
// Decoded images larger than kMaxImageSide per side or kMaxImagePixels in all are refused.
//
// Thread-safety: every function may be called from several threads at once (distinct paths).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "engine/error.h"
#include "raster/image.h"

namespace penumbra::engine {

inline constexpr int kMaxImageSide = 32768;
inline constexpr size_t kMaxImagePixels = size_t{1} << 26;  // 256 MiB as RGBA8

Status writeImage(const std::string& path, const raster::ImageRgba8& image);
Status writeImage(const std::string& path, const raster::ImageFloat4& image);
Status writeImage(const std::string& path, const raster::ImageFloat& image);
// Float samples, `channels` per pixel packed row by row, as a float image (an .exr path): channels
// named Y (1), R G B (3) or R G B A (4). The same samples give the same bytes (no timestamp).
Status writeFloatImage(const std::string& path, int width, int height, int channels, const std::vector<float>& samples);

// 1-channel images become gray (r = g = b), 2-channel gray + alpha, 3-channel RGB with alpha 255,
// more than 4 channels keep the first four. Samples of other types are converted to 8 bits by
// OIIO (rescaled, no transfer function applied).
Result<raster::ImageRgba8> readImageRgba8(const std::string& path);

// Our own outputs only (tests read renders back): any format OIIO reads. Untrusted images go
// through decodeTexture.

// The image formats a texture may be in: the two glTF 2.0 core allows. KTX2 (KHR_texture_basisu)
// and WebP (EXT_texture_webp) are recognized, to say so, and refused.
enum class TextureFormat { Png, Jpeg, Ktx2, Webp, Unknown };
// From the bytes' signature (PNG's 8 bytes, JPEG's SOI marker, KTX2's identifier, RIFF....WEBP).
TextureFormat textureFormatOf(const unsigned char* data, size_t size);
// From a glTF mimeType ("image/png", "image/jpeg", "image/ktx2", "image/webp"; "" -> Unknown).
TextureFormat textureFormatOfMime(const std::string& mimeType);

// An untrusted texture from encoded bytes in memory (a glTF image: a data URI, a file the model
// names, a buffer view). Decoded only when the signature is PNG or JPEG (and agrees with
// `mimeType` when one is declared), by that format's OpenImageIO plugin alone, from memory: no
// other plugin ever sees the bytes and nothing is read from or written to a file. The decoders'
// own messages (libpng, libjpeg, OIIO) never reach the terminal: they are folded into the error,
// one line naming `nameForErrors`. Images larger than kMaxImageSide / kMaxImagePixels are refused
// from their header, before their pixels are decoded.
Result<raster::ImageRgba8> decodeTexture(const unsigned char* data, size_t size, const std::string& mimeType,
                                         const std::string& nameForErrors);

}  // namespace penumbra::engine
