// Layouts of the buffers passes share with their shaders (std430), read by both compilers
// (passes/core/gpu_layout.glsl.h says how); gpu_types.h checks their C++ sizes and names their
// schemas.
#ifndef NIGHTCAP_FRAME_GPU_TYPES_GLSL_H
#define NIGHTCAP_FRAME_GPU_TYPES_GLSL_H

#include "../core/gpu_layout.glsl.h"

// One view of the scene: what a pass needs to place geometry on its image and to shade what it
// sees. The frame's camera is frame.views[0]; a pass that renders elsewhere (a probe's cube
// faces) writes its own list, and each draw names its view (GpuDraw::view). Every position is in
// the frame's camera-relative world, so a view's eye is where it stands relative to the camera.
#define NC_GPU_VIEW_FIELDS(F, A, P)                                                               \
  /* camera-relative world → view space: world orientation, then the eye moved to the origin */ \
  F(mat4, view)                                                                                   \
  /* reversed-Z, infinite far plane, Y flipped for Vulkan */                                      \
  F(mat4, projection)                                                                             \
  F(mat4, view_projection)                                                                        \
  F(mat4, inverse_view_projection)                                                                \
  /* the previous frame's view-projection of this view, for points relative to this frame's       \
     camera */                                                                                    \
  F(mat4, previous_view_projection)                                                               \
  /* xyz: the eye, camera-relative (0 for the frame's camera) */                                  \
  F(vec4, eye)                                                                                    \
  /* width, height, 1/width, 1/height */                                                          \
  F(vec4, viewport)                                                                               \
  /* znear, yfov, aspect */                                                                       \
  F(vec4, projection_params)                                                                      \
  /* xy: TAA's sub-pixel jitter in pixels, already in projection (what is drawn at pixel p sits   \
     at p - xy unjittered); zw: the same in uv units. 0 for a view TAA does not resolve */        \
  F(vec4, jitter)
NC_STRUCT(GpuView, NC_GPU_VIEW_FIELDS)

#define NC_GPU_FRAME_CONSTANTS_FIELDS(F, A, P)                                                  \
  /* the world position of the camera-relative origin (float, informational) */                 \
  F(vec4, camera_world)                                                                         \
  /* xyz: the way sunlight travels; w: 1 when there is a sun */                                 \
  F(vec4, sun_direction)                                                                        \
  /* rgb × illuminance */                                                                      \
  F(vec4, sun_radiance)                                                                         \
  /* seconds since frame 0, seconds since the previous frame */                                 \
  F(vec4, timing)                                                                               \
  /* light count, frame index, 1 on a camera cut, lights dropped (lighting nothing visible) */  \
  F(uvec4, counts)                                                                              \
  /* frame.lights is grouped by how lighting shades a light: directional, then point and spot,  \
     then spheres (point lights with a radius), then tubes, each group in scene order. x, y, z: \
     the first index of the point-and-spot, sphere and tube groups. */                          \
  F(uvec4, light_groups)
NC_STRUCT(GpuFrameConstants, NC_GPU_FRAME_CONSTANTS_FIELDS)

// Camera-relative light. Types as LightType (kLight*, passes/scene/light_type.glsl.h).
#define NC_GPU_LIGHT_FIELDS(F, A, P)                                                             \
  /* xyz position (tube: first end), w: type */                                                  \
  F(vec4, position_type)                                                                         \
  /* tube: xyz second end, w: radius */                                                          \
  F(vec4, end_radius)                                                                            \
  /* rgb × intensity, w: range (0: none) */                                                     \
  F(vec4, color_range)                                                                           \
  /* xyz: the way light travels, w: cos(outer cone) */                                           \
  F(vec4, direction_cos_outer)                                                                   \
  /* x: cos(inner cone); y: the light's index in scene.lights (frame.lights is culled per frame, \
     so shadow.local_plan follows a light across frames by it) */                                \
  F(vec4, cos_inner)
NC_STRUCT(GpuLight, NC_GPU_LIGHT_FIELDS)

#define NC_GPU_DRAW_FIELDS(F, A, P)                                                             \
  /* object → camera-relative world */                                                        \
  F(mat4, model)                                                                                \
  /* inverse transpose of model's 3×3 (in a mat4 for alignment) */                             \
  F(mat4, normal_matrix)                                                                        \
  /* object → this frame's camera-relative world at the previous frame's time */              \
  F(mat4, previous_model)                                                                       \
  F(uint, first_index)                                                                          \
  F(uint, index_count)                                                                          \
  F(int, vertex_offset)                                                                         \
  F(uint, material)                                                                             \
  /* material class | flags */                                                                  \
  F(uint, stencil)                                                                              \
  /* index into scene.instances */                                                              \
  F(uint, instance)                                                                             \
  /* 1: the transform has a negative determinant, so front faces wind clockwise */              \
  F(uint, mirrored)                                                                             \
  /* the index in the pass's view list (frame.views for the camera) of the view it is drawn     \
     from */                                                                                    \
  F(uint, view)                                                                                 \
  /* The box scene.geometry's positions are quantised in: origin + step · q, q in [0, 65535]³ \
     (xyz; see vertex_streams.h). */                                                            \
  F(vec4, position_origin)                                                                      \
  F(vec4, position_step)
NC_STRUCT(GpuDraw, NC_GPU_DRAW_FIELDS)

// draws.decals.projected: one visible projected decal (Scene::decals), camera-relative.
#define NC_GPU_DECAL_FIELDS(F, A, P)                                           \
  /* unit cube [-0.5, 0.5]³ → camera-relative world */                      \
  F(mat4, model)                                                               \
  /* its inverse, computed in double before rounding to float */               \
  F(mat4, local_from_world)                                                    \
  /* rgb, a: opacity */                                                        \
  F(vec4, albedo)                                                              \
  /* metalness, roughness, normal weight, pattern scale */                     \
  F(vec4, surface)                                                             \
  /* xyz: the box's local +z in world space, unit length */                    \
  F(vec4, facing)                                                              \
  /* DecalPattern, index into Scene::decals, 1 when `model` mirrors, unused */ \
  F(uvec4, info)
NC_STRUCT(GpuDecal, NC_GPU_DECAL_FIELDS)

#define NC_GPU_MATERIAL_FIELDS(F, A, P)                                                        \
  F(vec4, base_color)                                                                          \
  /* rgb × emissive strength */                                                               \
  F(vec4, emissive)                                                                            \
  /* metallic, roughness, alpha cutoff, normal scale */                                        \
  F(vec4, pbr)                                                                                 \
  /* occlusion strength, translucency, alpha mode, flags (1 unlit, 2 double-sided, 4 decal) */ \
  F(vec4, extra)                                                                               \
  /* base colour, metallic-roughness, normal, occlusion (-1: none) */                          \
  F(ivec4, textures)                                                                           \
  /* emissive, uv-set bits (bit k: slot k uses TEXCOORD_1), stencil class */                   \
  F(ivec4, textures2)                                                                          \
  /* packed SamplerDesc per slot (see pack_sampler) */                                         \
  F(uvec4, samplers)                                                                           \
  F(uvec4, samplers2)
NC_STRUCT(GpuMaterial, NC_GPU_MATERIAL_FIELDS)

#endif
