// Error metrics for shadow techniques and the images that show them (`penumbra bench shadows`).
//
// Quantities: V is the visible fraction of the area light seen from a receiver (shadows/area_light.h),
// in [0, 1]; a technique's V is compared with the ray-traced reference's. The signed error is
// e = V - V_ref: negative means too much shadow (too dark), positive means light leaking (too bright).
// A mask selects the pixels compared: non-zero where a receiver is in front of the light (background
// and receivers facing away have V = 1 or 0 by construction, for every technique alike, and would
// only dilute the error).
//
// Determinism: sums are taken in double, pixel by pixel within a row, rows added in order from the
// top; the results are the same bits on every run and at every thread count (all of it is serial).
// Non-finite values: a pair whose error is not finite (NaN or infinite V) counts as error 1, the
// largest that two values in [0, 1] can differ by, so one broken pixel shows up without turning the
// whole metric into NaN.
//
// Thread-safety: every function is pure and may be called from any number of threads at once.
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/frame.h"
#include "engine/scene.h"
#include "raster/image.h"
#include "shadows/area_light.h"

namespace penumbra::engine {

struct VisibilityError {
  double rmse = 0;         // sqrt(mean(e^2)) over the masked pixels
  double bias = 0;         // mean(e), signed: > 0 too bright (a non-finite e counts as +1)
  double maxErr = 0;       // max |e|
  double fracOver005 = 0;  // fraction of masked pixels with |e| > 0.05, in [0, 1]
  size_t pixels = 0;       // masked pixels compared; all fields are 0 when there are none
};

// Compares v with reference where (mask & select) != 0. Throws std::invalid_argument when the
// three images do not have the same size.
VisibilityError compareVisibility(const raster::ImageFloat& v, const raster::ImageFloat& reference,
                                  const raster::Image<uint8_t>& mask, uint8_t select = 0xff);

// Receiver classes, to report errors where techniques fail differently (`bench shadows`): bits of
// a mask per G-buffer pixel, 0 where nothing is compared (background, or no part of the light above
// the receiver's geometric tangent plane: V = 0 for every technique alike).
//   kGroundReceiver   on a flat instance (Scene::flatInstances: a ground, a wall, a card)
//   kObjectReceiver   on any other instance (the objects' own surfaces)
//   kContactReceiver  either, and within kContactPixels pixels on screen of a receiver of another
//                     instance that is closer in the world than kContactPixels pixel footprints
//                     (|eye - x| * 2 tan(fovY / 2) / height each): where an object meets the
//                     ground or another object, as far as the camera sees it.
inline constexpr uint8_t kGroundReceiver = 1, kObjectReceiver = 2, kContactReceiver = 4;
inline constexpr int kContactPixels = 4;
raster::Image<uint8_t> receiverClasses(const Scene& scene, const Frame& frame, const shadows::RectLight& light);

// Root mean square difference of the R, G and B channels over all pixels (alpha ignored), each
// channel divided by 255: the difference of the sRGB-encoded images as displayed, in [0, 1].
// 0 for empty images; throws std::invalid_argument when the sizes differ.
double imageRmse(const raster::ImageRgba8& a, const raster::ImageRgba8& b);

// The same over linear RGB, each channel clamped to [0, 1] first (NaN counts as 0): the difference
// of the radiance that would be displayed, before the sRGB encoding.
double imageRmse(const raster::ImageFloat4& a, const raster::ImageFloat4& b);

// Heat map of the signed error e = v - reference, on a diverging blue-white-red scale (ColorBrewer
// RdBu ends): t = clamp(e / scale, -1, 1) is interpolated in sRGB bytes through the stops
//     t = -1 kHeatBlue, -0.5 kHeatLightBlue, 0 white, 0.5 kHeatLightRed, 1 kHeatRed,
// so blue is too much shadow, red is light leaking, and |e| >= scale saturates. Pixels outside the
// mask are kHeatOutside; a non-finite error is kHeatInvalid. Alpha is 255. scale is in units of V,
// finite and > 0; throws std::invalid_argument otherwise or when the sizes differ.
inline constexpr raster::Rgba8 kHeatBlue{5, 113, 176, 255};
inline constexpr raster::Rgba8 kHeatLightBlue{146, 197, 222, 255};
inline constexpr raster::Rgba8 kHeatWhite{255, 255, 255, 255};
inline constexpr raster::Rgba8 kHeatLightRed{244, 165, 130, 255};
inline constexpr raster::Rgba8 kHeatRed{202, 0, 32, 255};
inline constexpr raster::Rgba8 kHeatOutside{64, 64, 64, 255};
inline constexpr raster::Rgba8 kHeatInvalid{255, 0, 255, 255};
raster::ImageRgba8 errorHeatMap(const raster::ImageFloat& v, const raster::ImageFloat& reference,
                                const raster::Image<uint8_t>& mask, float scale = 0.25f);

// V as grey: byte = round(255 * clamp(V, 0, 1)), linear like engine::writeImage's 8-bit gray (V is
// data, not color); NaN is kHeatInvalid. Alpha is 255.
raster::ImageRgba8 visibilityImage(const raster::ImageFloat& v);

}  // namespace penumbra::engine
