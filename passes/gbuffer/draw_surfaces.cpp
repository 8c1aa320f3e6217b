#include "passes/gbuffer/draw_surfaces.h"

#include "passes/frame/draw_scene.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

void draw_surfaces(PassContext& ctx, const std::string& draws) {
  ctx.begin_rendering();
  ctx.bind_pipeline();
  auto bindings = geometry_bindings(ctx, draws);
  bindings.push_back(Binding::storage(ctx.slot("scene.materials"), "scene.materials"));
  ctx.push(bindings);
  draw_scene(ctx, draws, [&](uint32_t, const GpuMaterial& m) {
    const int32_t indices[MaterialTexture::count] = {m.textures.x, m.textures.y, m.textures.z, m.textures.w,
                                                     m.textures2.x};
    const uint32_t samplers[MaterialTexture::count] = {m.samplers.x, m.samplers.y, m.samplers.z, m.samplers.w,
                                                       m.samplers2.x};
    std::vector<Binding> textures;
    const uint32_t first = ctx.slot("scene.texture.");
    for (uint32_t slot = 0; slot < MaterialTexture::count; ++slot) {
      const bool used = indices[slot] >= 0;
      const std::string name = texture_resource(uint32_t(used ? indices[slot] : m.textures2.w));
      textures.push_back(Binding::texture(first + slot, name, ctx.sampler(unpack_sampler(samplers[slot]))));
    }
    ctx.push(textures);
  });
  ctx.end_rendering();
}

}  // namespace nightcap
