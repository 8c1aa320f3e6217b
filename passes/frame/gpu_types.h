// Layouts of the buffers passes share with their shaders: the structs are gpu_types.glsl.h's,
// written once for C++, GLSL and the schemas; their sizes are checked here, since C++ lays out
// glm types by other rules than std430.
#pragma once

#include "passes/frame/gpu_types.glsl.h"

namespace nightcap {

static_assert(sizeof(GpuView) == 5 * 64 + 4 * 16);
static_assert(sizeof(GpuFrameConstants) == 6 * 16);
static_assert(sizeof(GpuLight) == 80);
static_assert(sizeof(GpuDraw) == 256);
static_assert(sizeof(GpuDecal) == 192);
static_assert(sizeof(GpuMaterial) == 128);

// Neighbours of a sorted draw list that draw_scene issues as one instanced draw: the same mesh
// range, material, stencil reference and winding.
inline bool same_batch(const GpuDraw& a, const GpuDraw& b) {
  return a.first_index == b.first_index && a.index_count == b.index_count && a.vertex_offset == b.vertex_offset &&
         a.material == b.material && a.stencil == b.stencil && a.mirrored == b.mirrored;
}

// Texture slots of GpuMaterial, in order.
enum MaterialTexture : uint32_t { base_color = 0, metallic_roughness, normal, occlusion, emissive, count };

// How frame.constants, frame.views, frame.lights and the draws.* lists decode (PassDecl::layout).
BufferSchema frame_constants_schema();
BufferSchema view_schema();
BufferSchema light_schema();
BufferSchema draw_schema();
BufferSchema decal_schema();

}  // namespace nightcap
