// Scene: what a frame renders, in world space (right-handed, y up, metres by convention).
// Built by the glTF loader, the scene-file loader or a built-in generator; validated once by
// validateScene(); immutable while rendered (thread-safe for concurrent reads).
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/error.h"
#include "raster/image.h"
#include "shadows/area_light.h"

namespace penumbra::engine {

// A base color texture: RGBA8 texels as stored (sRGB encoded), with its mip chain
// (mips[0] is the full image, each next level halves width and height down to 1x1).
struct Texture {
  std::string name;
  std::vector<raster::ImageRgba8> mips;
};

struct Material {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};  // linear RGBA
  int baseColorTexture = -1;        // index into Scene::textures, -1: none
  float specular = 0.0f;            // Blinn-Phong specular weight [0, 1]
  float shininess = 32.0f;          // Blinn-Phong exponent [1, 4096]
};

// One triangle list (one glTF primitive), in object space.
struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;    // same count as positions (computed when the source has none)
  std::vector<glm::vec2> texcoords;  // empty, or same count as positions
  std::vector<glm::vec3> colors;     // empty, or same count as positions: linear RGB per vertex, finite,
                                     // multiplied into the material's base color
  std::vector<uint32_t> indices;     // 3 per triangle, each < positions.size()
  int material = -1;                 // index into Scene::materials, -1: default material
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // object-space bounding box of positions
  // Closed and wound outward (computed by validateScene, meshIsClosed): every face of a closed
  // mesh has an inside behind it, so a shadow technique may drop the faces turned away from the
  // light (the back faces' depths lie behind the front faces' along every ray from the light).
  bool closed = false;
};

// A mesh placed in the world (the node hierarchy flattened).
struct Instance {
  std::string name;
  int mesh = 0;
  glm::mat4 transform{1.0f};  // object to world (at shutter open when the instance moves)
  // Motion: the object-to-world transform at shutter close; every vertex moves on the straight
  // line between its two positions (so the transform at time t is the element-wise blend
  // (1 - t) transform + t transformClose). None: static.
  std::optional<glm::mat4> transformClose{};
  bool moves() const { return transformClose && *transformClose != transform; }
  glm::mat4 transformAt(float t) const;
};

struct Camera {
  glm::vec3 eye{0.0f, 1.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 45.0f;  // vertical field of view, (0, 180)
  float znear = 0.0f;         // 0: fitted to the scene bounds
  float zfar = 0.0f;          // 0: fitted to the scene bounds
  // Thin lens (depth of field): aperture radius in world units (0: a pinhole) and the distance
  // in focus along the view direction (0: the distance from eye to target).
  float apertureRadius = 0.0f;
  float focusDistance = 0.0f;
};

struct DirectionalLight {
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // direction the light travels (towards the scene)
  glm::vec3 color{1.0f};
  float intensity = 1.0f;                  // irradiance scale, >= 0
};

struct PointLight {
  glm::vec3 position{0.0f};
  glm::vec3 color{1.0f};
  float intensity = 1.0f;                  // radiant intensity, falls off with 1 / d^2; >= 0
  float range = 0.0f;                      // > 0: faded out smoothly by distance `range` (KHR_lights_punctual)
};

// A point light limited to a cone (KHR_lights_punctual's spot): full inside innerCone, fading to 0
// at outerCone (half-angles from the direction, radians, 0 <= inner < outer <= pi/2).
struct SpotLight {
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // unit, where the cone points
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;
  float innerCone = 0.0f, outerCone = 0.7853982f;
};

// Ambient light from a sky above and the ground below, blended by the shading normal's y:
// ambient = albedo * mix(ground, sky, (1 + n.y) / 2). Replaces Scene::ambient when set.
struct SkyLight {
  glm::vec3 sky{0.30f, 0.34f, 0.40f};
  glm::vec3 ground{0.10f, 0.09f, 0.08f};
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Instance> instances;
  std::optional<Camera> camera;  // none: the renderer frames the scene bounds
  std::vector<DirectionalLight> directionalLights;
  std::vector<PointLight> pointLights;
  std::vector<SpotLight> spotLights;
  std::optional<SkyLight> sky;
  // Rectangular area lights: the lights that cast (soft) shadows, with the technique chosen in
  // RenderOptions. Directional and point lights are unshadowed.
  std::vector<shadows::RectLight> areaLights;
  glm::vec3 ambient{0.08f};      // constant ambient term added to the lit color
  glm::vec3 background{0.1f, 0.1f, 0.12f};

  // Set by addDefaultLighting: the scene had no light and got a default key light and sky.
  bool defaultLighting = false;
  // Every file the scene was read from (canonical paths): the scene file, glTF files, buffers,
  // images. An output must not overwrite any of them.
  std::vector<std::string> sourceFiles;

  size_t triangleCount() const;
  // World-space bounding box of all instances; false when the scene is empty.
  bool worldBounds(glm::vec3& lo, glm::vec3& hi) const;
  // The same, leaving out a ground or backdrop: flat instances (thinner than 1e-3 of their extent)
  // more than twice the size of the rest; all instances when every one is flat. What a fitted
  // camera frames and a default light is placed by.
  bool objectBounds(glm::vec3& lo, glm::vec3& hi) const;
  // Per instance, 1 when it is flat: its world bounding box thinner than 1e-3 of its largest
  // extent (a ground, a wall, a card); 0 otherwise and for an instance without geometry.
  std::vector<char> flatInstances() const;
};

// Bounds and normals computed, references checked (mesh, material and texture indices, index
// ranges), non-finite vertex positions reported. `where` names the source in the error.
Status validateScene(Scene& scene, const std::string& where);

// A scene without any light (the usual glTF file) gets what a viewer would show it with: a key
// light -- a rectangular area light above, in front and to the left of the bounds, facing their
// centre, 0.35 of their radius wide, bright enough that a white surface facing it reflects about
// 0.8 -- and a sky ambient (SkyLight). Returns false (and changes nothing) when the scene has a
// light or no geometry. Soft shadows then come from the key light like from any area light.
bool addDefaultLighting(Scene& scene);

// Area-weighted vertex normals (for meshes without normals).
void computeNormals(Mesh& mesh);
void computeBounds(Mesh& mesh);
// Whether the mesh is a closed, consistently oriented surface wound counter-clockwise seen from
// outside: with vertices welded by exact position (glTF splits vertices at seams), every edge of a
// non-degenerate triangle is used once in each direction (so twice in all, by two triangles that
// agree on its orientation), and the enclosed signed volume is positive. Degenerate triangles
// (two welded vertices equal) are ignored; an empty mesh is not closed.
bool meshIsClosed(const Mesh& mesh);

}  // namespace penumbra::engine
