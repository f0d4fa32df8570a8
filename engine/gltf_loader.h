// glTF 2.0 loading (.gltf with external or data-URI buffers and images, and .glb) into a Scene.
//
// What is read: the default scene (else scene 0, else every root node); node hierarchies with
// matrix or TRS transforms, flattened to world-space Instances (one per node and primitive); one
// Mesh per primitive (TRIANGLES; TRIANGLE_STRIP and TRIANGLE_FAN converted to lists; POINTS and
// LINES* skipped and counted); POSITION (required), NORMAL (computed when absent or invalid) and
// the TEXCOORD set the base color texture uses (TEXCOORD_0 otherwise), from float or normalized
// integer accessors, interleaved or not; u8/u16/u32 or no indices; pbrMetallicRoughness base color
// factor and texture (one Texture per image, shared, mips built); the first perspective camera
// met in a depth-first walk of the scene (eye at the node origin, looking down its -z, up its +y).
// Skins, morph targets, animations and the other material inputs are ignored: the static pose is
// loaded. Supported required extensions: KHR_mesh_quantization; any other required extension is
// an error, as are sparse accessors.
//
// Every index and every accessor's byte range is checked against its buffer view and buffer before
// anything is read: a malformed file gives an Error naming the file, never a crash.
//
// Thread-safety: loadGltf() keeps no state between calls; concurrent calls are safe.
#pragma once

#include <string>
#include <vector>

#include "engine/error.h"
#include "engine/file_access.h"
#include "engine/scene.h"

namespace penumbra::engine {

// What the loader left out, for the caller to report.
struct GltfLoadStats {
  int skippedPrimitives = 0;  // POINTS, LINES, LINE_LOOP and LINE_STRIP primitives
  int buffersSkipped = 0;     // external buffers no accessor or image uses: never read
};

Result<Scene> loadGltf(const std::string& path, const LoadOptions& options = {});
Result<Scene> loadGltf(const std::string& path, const LoadOptions& options, GltfLoadStats& stats);
// The same from the file's bytes in memory (.gltf text or .glb); `path` names it in errors and its
// folder is where the files it names are looked for.
Result<Scene> parseGltf(std::vector<unsigned char> bytes, const std::string& path, const LoadOptions& options = {});

}  // namespace penumbra::engine
