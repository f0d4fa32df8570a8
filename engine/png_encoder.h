// PNG encoding of 8-bit images, our own (zlib's deflate, zlib's CRC): the format of every render
// Penumbra writes by default, so that writing one does not load OpenImageIO (engine/image_io.h).
//
// The file holds IHDR, the image data and IEND, nothing else: no timestamp, no text, no colour
// chunk (8-bit colour is sRGB by convention). Each row's filter is chosen as libpng's default
// heuristic does (the least sum of the filtered bytes as signed magnitudes); deflate at level 6,
// in bands of about 128 KiB of rows compressed in parallel, each primed with the 32 KiB before it
// and ended on a byte boundary (Z_SYNC_FLUSH), so that they concatenate into one stream (pigz's
// method; the default render came out 0.15% smaller than one stream); 64 KiB IDAT chunks. The
// same pixels give the same bytes at any thread count (for one zlib).
//
// Thread-safety: a pure function; it runs on TBB's threads (the caller's limit applies).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace penumbra::engine {

// `channels` (1 gray, 2 gray + alpha, 3 RGB, 4 RGBA) 8-bit samples per pixel, rows `rowBytes`
// apart from `data`; width and height ≥ 1. The encoded file's bytes.
std::string encodePng(int width, int height, int channels, const uint8_t* data, size_t rowBytes);

}  // namespace penumbra::engine
