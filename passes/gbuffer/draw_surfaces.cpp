#include "passes/gbuffer/draw_surfaces.h"

#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

void draw_surfaces(PassContext& ctx, const std::string& draws, DrawRange range) {
  ctx.bind_pipeline();
  ctx.push_declared();
  draw_scene(
      ctx, draws,
      [&](uint32_t, const GpuMaterial& m) {
        const int32_t indices[MaterialTexture::count] = {m.textures.x, m.textures.y, m.textures.z, m.textures.w,
                                                         m.textures2.x};
        const uint32_t samplers[MaterialTexture::count] = {m.samplers.x, m.samplers.y, m.samplers.z, m.samplers.w,
                                                           m.samplers2.x};
        std::vector<PassContext::DrawTexture> textures;
        for (uint32_t slot = 0; slot < MaterialTexture::count; ++slot) {
          const bool used = indices[slot] >= 0;
          textures.push_back(
              {texture_resource(uint32_t(used ? indices[slot] : m.textures2.w)), unpack_sampler(samplers[slot])});
        }
        ctx.push_draw_textures(textures);
      },
      range);
}

PassDecl surface_drawing_pass(std::string name, const std::string& views, const std::string& draws) {
  return PassDecl(std::move(name), PassType::graphics)
      .read(views, Use::storage_read)
      .as("views")
      .read("scene.geometry", Use::storage_read)
      .read("scene.geometry", Use::index_buffer)
      .read(draws, Use::storage_read)
      .as("draws")
      .read("scene.materials", Use::storage_read)
      .read_all("scene.texture.", Use::sampled)
      .slots("scene.texture.", MaterialTexture::count)
      .raster(RasterState::per_draw(VK_CULL_MODE_BACK_BIT));
}

PassDecl surface_pass(std::string name, const std::string& draws) {
  return surface_drawing_pass(std::move(name), "frame.views", draws)
      .modify("scene.depth", Use::depth_attachment)
      .run([draws](PassContext& ctx) {
        ctx.begin_rendering();
        draw_surfaces(ctx, draws);
        ctx.end_rendering();
      });
}

}  // namespace nightcap
