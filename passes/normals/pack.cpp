// normals.bfn_lut (CPU) and normals.pack: world normals from the 10-bit G-buffer repacked as
// 8-bit best-fit normals with roughness (R8G8B8A8_UNORM), the form SSR and the later
// screen-space passes read.
#include <cstring>
#include <map>
#include <mutex>

#include "passes/core/context.h"
#include "passes/frame/frame_passes.h"
#include "passes/normals/bfn_lut.h"

namespace nightcap {
namespace {

constexpr uint32_t kLutSize = 1024;

// The table depends on nothing but its size: built once per process.
const std::vector<uint8_t>& cached_lut(uint32_t size) {
  static std::mutex mutex;
  static std::map<uint32_t, std::vector<uint8_t>> tables;
  std::lock_guard lock(mutex);
  auto it = tables.find(size);
  if (it == tables.end()) it = tables.emplace(size, build_bfn_lut(size)).first;
  return it->second;
}

}  // namespace

PassDecl normals_bfn_lut_pass() {
  ImageDecl lut{VK_FORMAT_R8_UINT, ResourceKind::lookup_table};
  lut.size = {SizeRule::Mode::absolute, kLutSize, kLutSize, ""};
  return PassDecl("normals.bfn_lut", PassType::cpu)
      .write("normals.bfn_lut", Use::host, lut)
      .run([](PassContext& ctx) { ctx.output("normals.bfn_lut") = cached_lut(kLutSize); });
}

PassDecl normals_pack_pass() {
  return PassDecl("normals.pack", PassType::graphics)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("normals.bfn_lut", Use::sampled)
      .write("normals.packed", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, ResourceKind::packed_normal})
      .shader("frame/fullscreen.vert")
      .shader("normals/pack.frag")
      .run([](PassContext& ctx) {
        GraphicsPipelineDesc desc;
        desc.vertex = "frame/fullscreen.vert";
        desc.fragment = "normals/pack.frag";
        desc.bindings.assign(3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
        desc.color_formats = {VK_FORMAT_R8G8B8A8_UNORM};
        ctx.begin_rendering({"normals.packed"});
        ctx.bind(desc);
        VkSampler nearest = ctx.nearest_clamp();
        ctx.push({Binding::texture(0, "gbuffer.normal", nearest), Binding::texture(1, "gbuffer.material", nearest),
                  Binding::texture(2, "normals.bfn_lut", nearest)});
        vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
        ctx.end_rendering();
      });
}

}  // namespace nightcap
