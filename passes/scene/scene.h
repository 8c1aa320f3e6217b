// The CPU-side scene: what a glTF file or the built-in city turns into before the frame
// uploads it as `scene.*` resources. Positions of instances, lights and cameras are double
// precision so a city 8 km from the origin keeps millimetres; the frame makes them
// camera-relative floats.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "passes/core/sampler.h"
#include "passes/scene/light_type.glsl.h"

namespace nightcap {

// Bad scene input: the message names the file and the problem.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Vertex {
  float position[3];
  float normal[3];
  float tangent[4];  // xyz tangent, w handedness; zero when the source has none
  float uv0[2];
  float uv1[2];
  float color[4];  // COLOR_0, white when absent
};
static_assert(sizeof(Vertex) == 72);

// Base level only, 8-bit RGBA; the frame builds the mip chain when it uploads.
struct Texture {
  std::string name;
  uint32_t width = 0, height = 0;
  bool srgb = false;  // base colour and emissive are sRGB-encoded
  std::vector<uint8_t> rgba8;
};

struct TextureRef {
  int32_t texture = -1;  // index into Scene::textures, -1 when unused
  uint32_t uv_set = 0;
  float scale = 1.0f;  // normalTexture.scale or occlusionTexture.strength
  SamplerDesc sampler;
};

enum class AlphaMode : uint32_t { opaque = 0, mask = 1, blend = 2 };

// Stencil material classes of frame.md; 0x02 (moving) is OR-ed on at draw time.
namespace stencil {
constexpr uint8_t plain = 0x00;
constexpr uint8_t moving = 0x02;
constexpr uint8_t road = 0x08;
constexpr uint8_t body = 0x15;
constexpr uint8_t face = 0x35;
constexpr uint8_t vehicle = 0x40;
constexpr uint8_t hair = 0x95;
constexpr uint8_t foliage = 0xA0;
}  // namespace stencil

struct Material {
  std::string name;
  glm::vec4 base_color{1.0f};
  float metallic = 1.0f;
  float roughness = 1.0f;
  glm::vec3 emissive{0.0f};        // emissiveFactor
  float emissive_strength = 1.0f;  // KHR_materials_emissive_strength
  TextureRef base_color_texture, metallic_roughness_texture, normal_texture, occlusion_texture, emissive_texture;
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
  bool unlit = false;  // KHR_materials_unlit
  float translucency = 0.0f;
  uint8_t stencil_class = stencil::plain;
  // A mesh decal [000]: instances with this material are drawn by decals.mesh over the G-buffer
  // (base colour alpha is their opacity), never by the geometry passes, and never occlude.
  bool decal = false;
};

// One drawable range of the shared vertex/index arrays; bounds are in object space. A
// primitive may name a coarser level of detail, drawn instead of it beyond `lod_distance`
// metres from the camera (to the centre of the instance's box); levels form a chain. Beyond a
// level's `draw_distance` nothing is drawn (small props vanish in the distance, the way an
// engine's cull distances do; it is a level of detail, not visibility).
struct Primitive {
  uint32_t first_index = 0, index_count = 0;
  int32_t vertex_offset = 0;  // added to each index
  uint32_t material = 0;
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};
  int32_t coarser = -1;  // the next level of detail, -1 for none
  float lod_distance = INFINITY;
  float draw_distance = INFINITY;
  // The triangles cull.main's occlusion buffer takes from this primitive: the first
  // `occluder_index_count` indices (all by default). A prefix of what the GPU draws is a subset of
  // it, so the buffer stays conservative; a mesh that leads with its big faces (a building's
  // body before its ledges) lets the buffer skip thousands of small triangles.
  uint32_t occluder_index_count = UINT32_MAX;
};

struct Instance {
  glm::dmat4 world{1.0};     // at time 0
  uint32_t primitive = 0;    // the finest level of detail
  bool moving = false;       // drawn by gbuffer.dynamic, not by the static passes
  glm::vec3 velocity{0.0f};  // metres per second, world space: world(t) = translate(velocity·t)·world
  int32_t material = -1;     // overrides the primitive's material when set, so meshes are shared
};

enum class LightType : uint32_t {
  directional = kLightDirectional,
  point = kLightPoint,
  spot = kLightSpot,
  tube = kLightTube
};

// Colours are linear RGB; intensity follows KHR_lights_punctual (candela for point/spot,
// lux for directional); a tube's intensity is candela per metre of its length.
struct Light {
  LightType type = LightType::point;
  glm::dvec3 position{0.0};       // tube: first end point
  glm::dvec3 end{0.0};            // tube: second end point
  glm::vec3 direction{0, -1, 0};  // directional/spot: the way light travels
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;  // 0: infinite (a falloff window is applied at 'range' when set)
  float inner_cone = 0.0f, outer_cone = 0.785398f;
  float radius = 0.0f;  // tube thickness, for the representative point
};

// What a projected decal lays onto the surfaces inside its box (decals/projected.frag), as a
// function of the box's local (u, v) = (x, y) in [-0.5, 0.5]².
enum class DecalPattern : uint32_t {
  solid = 0,        // the albedo everywhere
  stripes = 1,      // dashes along u (`scale` of them), a road marking
  grime = 2,        // value noise (`scale` cells across) fading toward the box's sides
  coordinates = 3,  // albedo = local position + 0.5: a debugging ramp the reference test reads
};

// A projected decal [000]: the unit cube [-0.5, 0.5]³ under `world` (double precision, like
// instances) is its volume; decals.projected blends its pattern into the G-buffer wherever the
// depth buffer's surface lies inside it, except on pixels tagged moving. Local +z is the way the
// decal faces: the surface normal is pulled toward it by `normal_weight`.
struct Decal {
  glm::dmat4 world{1.0};
  DecalPattern pattern = DecalPattern::solid;
  glm::vec3 albedo{1.0f};
  float opacity = 1.0f;
  float metallic = 0.0f, roughness = 0.5f;
  float normal_weight = 0.0f;  // 0: the surface keeps its normal; 1: faces +z where fully opaque
  float scale = 1.0f;          // the pattern's repeat (stripes, grime)
  // Beyond this many metres from the camera (to the box's centre) it is not drawn: a level of
  // detail, as for Primitive::draw_distance.
  float draw_distance = INFINITY;
};

// A reflection probe: where its cube is captured from, and the box its reflections are
// parallax-corrected against (the walls around it, roughly), in world space.
struct ReflectionProbe {
  glm::dvec3 position{0.0};
  glm::dvec3 box_min{0.0}, box_max{0.0};
};

// A pinhole camera: camera-to-world transform (looks down -Z, +Y up), vertical FOV.
struct Camera {
  glm::dmat4 world{1.0};
  float yfov = 0.785398f;  // radians
  float znear = 0.05f;     // infinite far plane
};

struct Scene {
  std::string source;  // file path, or "built-in city (seed N)"
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<Primitive> primitives;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Instance> instances;
  std::vector<Light> lights;
  std::vector<Decal> decals;       // projected decals
  std::vector<ReflectionProbe> probes;
  std::optional<Camera> camera;    // the first glTF camera, if any
  std::vector<std::string> notes;  // what was approximated, e.g. BLEND drawn as opaque
  // A table of `nightcap bake-tod` for `tod_hour` (passes/scene/time_of_day.h): per instance, bit
  // k set when it can cast a visible shadow at 2k:00. Empty: none loaded, every caster casts.
  std::vector<uint16_t> tod_visible;
  double tod_hour = 0.0;

  uint32_t material_of(const Instance& instance) const {
    return instance.material >= 0 ? uint32_t(instance.material) : primitives.at(instance.primitive).material;
  }
  // World-space bounds of all instances (at time 0).
  glm::dvec3 bounds_min() const;
  glm::dvec3 bounds_max() const;
  // Feature names passes may require: "opaque_geometry", "mask_geometry", "sun",
  // "local_lights", "emissive", "moving_geometry", "mesh_decals" (an instance of a decal
  // material), "projected_decals", "sun_above_horizon" (the first directional light shines down).
  std::set<std::string> features() const;
};

// Loads a glTF 2.0 file (.gltf or .glb) through tinygltf. Throws SceneError naming the file.
Scene load_gltf(const std::string& path);

// The built-in Night City block, deterministic from the seed.
Scene build_city(uint32_t seed);

// The shots of the built-in map (`render --shot`), each placed from the seed anywhere on it.
enum class Shot { street, rooftop, aerial };
Shot parse_shot(const std::string& name);  // throws SceneError naming the flag
std::string shot_name(Shot shot);

struct MapOptions {
  uint32_t seed = 1;
  double size_km = 16.0;  // the map is size × size, centred on the origin
  Shot shot = Shot::street;
};
// The built-in map: a Night City-sized grid of districts (streets, buildings with levels of
// detail, signs and neon, street lamps, trees, traffic, pedestrians), deterministic from the
// seed; its camera is the requested shot.
Scene build_map(const MapOptions& options);

// The camera convention of shared/data/README.md: the camera sits at
// target + radius·(sin φ sin θ, cos φ, sin φ cos θ), looks at the target with +Y up.
Camera orbit_camera(double theta_degrees, double phi_degrees, double radius, glm::dvec3 target, double yfov_degrees);
// A camera that frames the whole scene (used when the scene has none).
Camera framing_camera(const Scene& scene, double aspect);

// One probe for a scene without a placement of its own (a glTF file, the one-block city): at the
// centre of its bounds, in a box of its bounds. None for a scene with nothing in it.
std::vector<ReflectionProbe> probe_in_bounds(const Scene& scene);

}  // namespace nightcap
