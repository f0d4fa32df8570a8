// Scene loading by file type, and Penumbra's JSON scene file (format: docs/scene-format.md).
//
// A scene file places glTF files and procedural shapes (engine/shapes.h) in the world, and sets the
// camera, lights, ambient and background colors. File paths are relative to the scene file's
// folder and must stay inside it (file_access.h) unless LoadOptions allow otherwise. The file is checked strictly: an unknown key is an error that lists the valid
// keys, a value of the wrong type or out of range is an error that names its JSON path
// ("objects[2].radius must be > 0"); every error is one line naming the scene file.
//
// Thread-safety: no state is kept between calls; concurrent calls are safe.
#pragma once

#include <string>

#include "engine/error.h"
#include "engine/file_access.h"
#include "engine/scene.h"

namespace penumbra::engine {

// By extension (case-insensitive): .gltf and .glb go to loadGltf(), .json to loadSceneFile();
// anything else is an error.
Result<Scene> loadScene(const std::string& path, const LoadOptions& options = {});

// Reads and parses a JSON scene file.
Result<Scene> loadSceneFile(const std::string& path, const LoadOptions& options = {});

// Parses scene-file text; `path` names the file in errors and its directory resolves relative
// glTF paths.
Result<Scene> parseSceneFile(const std::string& text, const std::string& path, const LoadOptions& options = {});

}  // namespace penumbra::engine
