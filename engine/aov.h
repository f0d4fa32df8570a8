// Arbitrary output variables: the frame's buffers as float OpenEXR files (`penumbra render --aov
// LIST --aov-out PREFIX`), so users compare techniques and debug scenes with their own tools.
//
// Each buffer is written to PREFIX.<name>.exr, full float, the render's width x height, rows top to
// bottom. Pixels with no receiver (background) are NaN in every channel. With a stochastic pass
// the buffers are those of each pixel's first (nearest) layer.
//   visibility        Y: V of the first area light (shadows/area_light.h; 0 behind the light); a
//                     scene with L > 1 area lights also gets visibility-1 ... visibility-(L-1)
//   depth             Y: distance along the camera's view direction, world units
//   position          R, G, B = world x, y, z
//   normal            R, G, B = the shading normal (unit, facing the viewer)
//   geometric-normal  R, G, B = the face normal V is defined by (unit, facing the viewer)
//   albedo            R, G, B = linear base color
//   instance          Y: the scene's instance index (exact as a float up to 2^24)
//   triangle          Y: the triangle seen, its index in the instance's mesh (exact up to 2^24)
//   barycentrics      R, G, B = perspective-correct barycentrics of that triangle's vertices 0, 1, 2
//                     (a stochastic pass's blended surface: those of its first sample)
// Files carry no timestamp: the same render gives the same bytes (engine/image_io.h).
//
// Thread-safety: pure functions apart from writeAovs's files.
#pragma once

#include <string>
#include <vector>

#include "engine/error.h"
#include "engine/frame.h"

namespace penumbra::engine {

enum class Aov { Visibility, Depth, Position, Normal, GeometricNormal, Albedo, Instance, Triangle, Barycentrics };

// "visibility,depth,...": the names above, each at most once, in any order. The error names
// `option` and lists the valid names.
Result<std::vector<Aov>> parseAovList(const std::string& list, const std::string& option = "option --aov");
const char* aovName(Aov a);

// The files writeAovs writes for `aovs` with `areaLights` area lights, in order.
std::vector<std::string> aovPaths(const std::string& prefix, const std::vector<Aov>& aovs, size_t areaLights);

// The buffer of one AOV (channels per pixel, packed, NaN on background); light: which area light's
// visibility.
std::vector<float> aovSamples(const Frame& frame, Aov aov, size_t light, int& channels);

// Writes every file of aovPaths (each atomically); on a failure removes the ones already written:
// all or nothing.
Status writeAovs(const Frame& frame, const std::vector<Aov>& aovs, const std::string& prefix);

}  // namespace penumbra::engine
