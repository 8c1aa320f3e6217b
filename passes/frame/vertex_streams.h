// scene.geometry's vertex streams, packed as seed 001 describes them ("All vertex buffers
// uploaded to GPU memory are packed as SOA"): each attribute group is its own array, 28 bytes a
// vertex against the 72 of the float Vertex.
//   VB0  nshort4        position: x, y, z as 16-bit unsigned-normalised coordinates in the
//                       primitive's object-space box (PackedGeometry::boxes), w 0
//   VB1  half2          TEXCOORD_0
//   VB2  xint, xint     normal: octahedral snorm 16:16; tangent: octahedral snorm 16:15 + sign
//   VB3  unbyte4, half2 COLOR_0 as RGBA8 unorm, TEXCOORD_1
// passes/frame/vertex_streams.glsl decodes them; the functions here are the CPU side of the same
// encoding, for the packer, the tests and the tools.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <vector>

#include "passes/scene/scene.h"

namespace nightcap {

enum VertexStream : uint32_t { position_stream = 0, uv0_stream, frame_stream, color_uv1_stream, vertex_stream_count };
constexpr std::array<uint32_t, vertex_stream_count> kVertexStreamBytes = {8, 4, 8, 8};

// Quantised positions: p ≈ origin + step · q with q in [0, levels]. `position_step` is the one
// float computation of the step; cull.main gives the GPU the same value in GpuDraw.
constexpr uint32_t kPositionLevels = 65535;
glm::vec3 position_step(const glm::vec3& lo, const glm::vec3& hi, uint32_t levels = kPositionLevels);
uint32_t quantise_position(float p, float origin, float step, uint32_t levels = kPositionLevels);
// As the shader does it: origin + step · q in float, one rounding each.
float dequantise_position(uint32_t q, float origin, float step);

// A direction that is zero, or not finite, is stored as this code and decodes to (0, 0, 0): the
// G-buffer pass then falls back to the face normal, and to the screen-space tangent frame, as it
// did for such float vertices. (0x8000 is −32768 in the low snorm16, a code the encoder never
// produces: it rounds to ±32767.)
constexpr uint32_t kNoDirection = 0x8000;
uint32_t encode_normal(const glm::vec3& n);
glm::vec3 decode_normal(uint32_t code);
// xyz as encode_normal with y on 15 bits; bit 31 holds w < 0 (glTF handedness, ±1).
uint32_t encode_tangent(const glm::vec4& t);
glm::vec4 decode_tangent(uint32_t code);

// Two halves, nearest (ties to even). Beyond ±65504 a half is infinite, so UVs are clamped
// there; the error is ≤ 2⁻¹¹·|uv| (2⁻²⁵ below 2⁻¹⁴), which grows with |uv|: a texture tiled 1000
// times along a face (|uv| ≥ 512) is off by up to 1/8 of a tile.
uint32_t encode_uv(const float uv[2]);
glm::vec2 decode_uv(uint32_t code);
// RGBA8 unorm, each component clamped to [0, 1] (glTF's range for COLOR_0) and rounded.
uint32_t encode_color(const float rgba[4]);
glm::vec4 decode_color(uint32_t code);

struct PositionBox {
  glm::vec3 min{0.0f}, max{0.0f};
};

// scene.geometry starts with this header; the vertex streams and the index stream follow at
// their offsets, each aligned for a storage-buffer binding of its own.
struct GeometryHeader {
  uint32_t vertex_count, index_count;
  uint32_t index_offset;                        // bytes from the start of the buffer
  uint32_t stream_offset[vertex_stream_count];  // by VertexStream
  uint32_t pad;
};
static_assert(sizeof(GeometryHeader) == 32 && offsetof(GeometryHeader, stream_offset) == 12);  // vertex_streams.glsl
constexpr uint32_t kGeometryAlignment = 256;  // the largest minStorageBufferOffsetAlignment Vulkan allows

struct PackedGeometry {
  std::vector<uint8_t> bytes;  // scene.geometry
  // Per primitive: the box its vertices are quantised in, which is also its culling box. It is
  // the primitive's bounds, grown to the vertices it draws where the bounds miss one, and to the
  // union with every primitive that shares a vertex with it.
  std::vector<PositionBox> boxes;
};

PackedGeometry pack_geometry(const Scene& scene);

// Vertex `vertex` of scene.geometry decoded on the CPU as vertex_streams.glsl decodes it (up to
// the float normalisation of the directions), with the position box of the draw that draws it
// (GpuDraw::position_origin, position_step).
Vertex geometry_vertex(const std::vector<uint8_t>& geometry, uint32_t vertex, const glm::vec3& origin,
                       const glm::vec3& step);

}  // namespace nightcap
