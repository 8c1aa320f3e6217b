#include "passes/frame/draw_scene.h"

#include <algorithm>
#include <cstring>

#include "passes/frame/scene_resources.h"
#include "passes/scene/scene.h"

namespace nightcap {

uint32_t draw_order_class(const GpuMaterial& m) {
  const uint32_t stencil_class = uint32_t(m.textures2.z);
  if (stencil_class == stencil::foliage) return 2;
  if ((stencil_class & stencil::road) || m.emissive.x > 0 || m.emissive.y > 0 || m.emissive.z > 0) return 1;
  return 0;
}
namespace {

GeometryHeader geometry_header(PassContext& ctx) {
  auto bytes = ctx.host("scene.geometry");
  GeometryHeader header{};
  if (bytes.size() < sizeof(header)) throw GraphError(ctx.pass() + ": scene.geometry has no header");
  std::memcpy(&header, bytes.data(), sizeof(header));
  uint64_t end = uint64_t(header.index_offset) + uint64_t(header.index_count) * 4;
  for (uint32_t s = 0; s < vertex_stream_count; ++s)
    end = std::max(end, uint64_t(header.stream_offset[s]) + uint64_t(header.vertex_count) * kVertexStreamBytes[s]);
  if (end > bytes.size()) throw GraphError(ctx.pass() + ": scene.geometry header points past the buffer");
  return header;
}

}  // namespace

void draw_scene(PassContext& ctx, const std::string& draws,
                const std::function<void(uint32_t, const GpuMaterial&)>& on_material, DrawRange range) {
  const GeometryHeader header = geometry_header(ctx);
  auto draw_bytes = ctx.host(draws);
  auto material_bytes = ctx.host("scene.materials");
  const size_t listed = draw_bytes.size() / sizeof(GpuDraw);
  if (range.count == SIZE_MAX) range.count = listed - std::min(range.first, listed);
  if (range.first > listed || range.count > listed - range.first)
    throw GraphError(ctx.pass() + ": a draw range reaches past the end of " + draws);
  const size_t draw_count = range.first + range.count;
  const size_t material_count = material_bytes.size() / sizeof(GpuMaterial);
  if (range.count == 0) return;
  vkCmdBindIndexBuffer(ctx.cmd(), ctx.buffer("scene.geometry"), header.index_offset, VK_INDEX_TYPE_UINT32);
  // The declared faces, which the pipeline bound as the current dynamic state.
  const RasterState& declared = ctx.declaration().raster_state;
  if (!declared.per_draw_faces) throw GraphError(ctx.pass() + ": scene draws set faces per draw (per_draw_faces)");
  const VkFrontFace flipped =
      declared.front_face == VK_FRONT_FACE_CLOCKWISE ? VK_FRONT_FACE_COUNTER_CLOCKWISE : VK_FRONT_FACE_CLOCKWISE;
  uint32_t current = UINT32_MAX;
  VkFrontFace current_front = declared.front_face;
  auto draw_at = [&](size_t i) {
    GpuDraw draw;
    std::memcpy(&draw, draw_bytes.data() + i * sizeof(GpuDraw), sizeof(draw));
    return draw;
  };
  for (size_t i = range.first; i < draw_count;) {
    const GpuDraw draw = draw_at(i);
    if (draw.material >= material_count || uint64_t(draw.first_index) + draw.index_count > header.index_count)
      throw GraphError(ctx.pass() + ": draw " + std::to_string(i) + " of " + draws + " is out of range");
    // Equal neighbours (cull.main sorts them together) become one instanced draw; each instance
    // still reads its own record through gl_InstanceIndex.
    size_t end = i + 1;
    while (end < draw_count && same_batch(draw, draw_at(end))) ++end;
    if (draw.material != current) {
      current = draw.material;
      GpuMaterial material;
      std::memcpy(&material, material_bytes.data() + current * sizeof(GpuMaterial), sizeof(material));
      const bool double_sided = (int(material.extra.w) & 2) != 0;
      vkCmdSetCullMode(ctx.cmd(), double_sided ? VkCullModeFlags(VK_CULL_MODE_NONE) : declared.cull_mode);
      on_material(current, material);
    }
    // glTF: a mirroring transform turns counter-clockwise front faces clockwise.
    const VkFrontFace front = draw.mirrored ? flipped : declared.front_face;
    if (front != current_front) {
      vkCmdSetFrontFace(ctx.cmd(), front);
      current_front = front;
    }
    vkCmdSetStencilReference(ctx.cmd(), VK_STENCIL_FACE_FRONT_AND_BACK, draw.stencil & 0xff);
    vkCmdDrawIndexed(ctx.cmd(), draw.index_count, uint32_t(end - i), draw.first_index, draw.vertex_offset, uint32_t(i));
    i = end;
  }
}

}  // namespace nightcap
