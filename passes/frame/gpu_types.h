// Layouts of the buffers passes share with their shaders (std430, mirrored in
// passes/frame/types.glsl). Changing one side without the other is caught by the
// static_asserts here and by the reference tests.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "passes/core/buffer_schema.h"

namespace nightcap {

struct GpuFrameConstants {
  glm::mat4 view;        // world orientation only: the camera sits at the origin
  glm::mat4 projection;  // reversed-Z, infinite far plane, Y flipped for Vulkan
  glm::mat4 view_projection;
  glm::mat4 inverse_view_projection;
  glm::mat4 previous_view_projection;  // previous camera, for points relative to the current one
  glm::vec4 camera_world;              // world position (float, informational)
  glm::vec4 viewport;                  // width, height, 1/width, 1/height
  glm::vec4 sun_direction;             // xyz: the way sunlight travels; w: 1 when there is a sun
  glm::vec4 sun_radiance;              // rgb × illuminance
  glm::vec4 projection_params;         // znear, yfov, aspect
  glm::vec4 timing;                    // seconds since frame 0, seconds since the previous frame
  glm::uvec4 counts;  // light count, frame index, 1 on a camera cut, lights dropped (lighting nothing visible)
  // frame.lights is grouped by how lighting shades a light: directional, then point and spot,
  // then spheres (point lights with a radius), then tubes, each group in scene order. x, y, z:
  // the first index of the point-and-spot, sphere and tube groups.
  glm::uvec4 light_groups;
};
static_assert(sizeof(GpuFrameConstants) == 5 * 64 + 8 * 16);

// Camera-relative light. Types as LightType.
struct GpuLight {
  glm::vec4 position_type;        // xyz position (tube: first end), w: type
  glm::vec4 end_radius;           // tube: xyz second end, w: radius
  glm::vec4 color_range;          // rgb × intensity, w: range (0: none)
  glm::vec4 direction_cos_outer;  // xyz: the way light travels, w: cos(outer cone)
  // x: cos(inner cone); y: the light's index in scene.lights (frame.lights is culled per frame,
  // so shadow.local_plan follows a light across frames by it)
  glm::vec4 cos_inner;
};
static_assert(sizeof(GpuLight) == 80);

struct GpuDraw {
  glm::mat4 model;           // object → camera-relative world
  glm::mat4 normal_matrix;   // inverse transpose of model's 3×3 (in a mat4 for alignment)
  glm::mat4 previous_model;  // object → this frame's camera-relative world at the previous frame's time
  uint32_t first_index, index_count;
  int32_t vertex_offset;
  uint32_t material;
  uint32_t stencil;   // material class | flags
  uint32_t instance;  // index into scene.instances
  uint32_t mirrored;  // 1: the transform has a negative determinant, so front faces wind clockwise
  uint32_t pad;
  // The box scene.geometry's positions are quantised in: origin + step · q, q in [0, 65535]³
  // (xyz; see vertex_streams.h).
  glm::vec4 position_origin;
  glm::vec4 position_step;
};
static_assert(sizeof(GpuDraw) == 256);

// Neighbours of a sorted draw list that draw_scene issues as one instanced draw: the same mesh
// range, material, stencil reference and winding.
inline bool same_batch(const GpuDraw& a, const GpuDraw& b) {
  return a.first_index == b.first_index && a.index_count == b.index_count && a.vertex_offset == b.vertex_offset &&
         a.material == b.material && a.stencil == b.stencil && a.mirrored == b.mirrored;
}

// draws.decals.projected: one visible projected decal (Scene::decals), camera-relative.
struct GpuDecal {
  glm::mat4 model;             // unit cube [-0.5, 0.5]³ → camera-relative world
  glm::mat4 local_from_world;  // its inverse, computed in double before rounding to float
  glm::vec4 albedo;            // rgb, a: opacity
  glm::vec4 surface;           // metalness, roughness, normal weight, pattern scale
  glm::vec4 facing;            // xyz: the box's local +z in world space, unit length
  glm::uvec4 info;             // DecalPattern, index into Scene::decals, 1 when `model` mirrors, unused
};
static_assert(sizeof(GpuDecal) == 192);

// Texture slots of GpuMaterial, in order.
enum MaterialTexture : uint32_t { base_color = 0, metallic_roughness, normal, occlusion, emissive, count };

struct GpuMaterial {
  glm::vec4 base_color;
  glm::vec4 emissive;    // rgb × emissive strength
  glm::vec4 pbr;         // metallic, roughness, alpha cutoff, normal scale
  glm::vec4 extra;       // occlusion strength, translucency, alpha mode, flags (1 unlit, 2 double-sided, 4 decal)
  glm::ivec4 textures;   // base colour, metallic-roughness, normal, occlusion (-1: none)
  glm::ivec4 textures2;  // emissive, uv-set bits (bit k: slot k uses TEXCOORD_1), stencil class
  glm::uvec4 samplers;   // packed SamplerDesc per slot (see pack_sampler)
  glm::uvec4 samplers2;
};
static_assert(sizeof(GpuMaterial) == 128);

// How frame.constants, frame.lights and the draws.* lists decode (PassDecl::layout).
BufferSchema frame_constants_schema();
BufferSchema light_schema();
BufferSchema draw_schema();
BufferSchema decal_schema();

}  // namespace nightcap
