#include "passes/shadow/caster_draw.h"

#include <algorithm>
#include <glm/gtc/type_ptr.hpp>

#include "passes/frame/vertex_streams.h"

namespace nightcap {
namespace {

const KindRegistration kLightDepth({
    .kind = kinds::light_depth,
    .describe =
        [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
          out["depth"] = t.raw[0];
          out["drawn"] = t.raw[0] < 1.0;
        },
    // The drawn depths from the nearest (white) to the farthest; nothing drawn is black.
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          return TexelPicture{TexelPicture::Scale::distance, {t.raw[0] < 1.0 ? t.raw[0] : 0.0, 0, 0}};
        },
    .over_output = false,
    .measure = KindMeasure::depth,
});

}  // namespace

GpuDraw caster_draw(uint32_t instance, const InstanceRecord& record, const glm::dmat4& relative_model,
                    const MeshRecord& mesh) {
  GpuDraw d{};
  d.model = glm::mat4(relative_model);
  d.previous_model = d.model;
  d.normal_matrix = glm::mat4(glm::transpose(glm::inverse(glm::dmat3(relative_model))));
  d.first_index = mesh.first_index;
  d.index_count = mesh.index_count;
  d.vertex_offset = mesh.vertex_offset;
  d.material = record.material;
  d.instance = instance;
  d.mirrored = glm::determinant(glm::dmat3(relative_model)) < 0.0;
  // The box scene.geometry quantised the mesh's positions in (vertex_streams.h).
  const glm::vec3 lo = glm::make_vec3(mesh.bounds_min), hi = glm::make_vec3(mesh.bounds_max);
  d.position_origin = glm::vec4(lo, 0.0f);
  d.position_step = glm::vec4(position_step(lo, hi), 0.0f);
  return d;
}

void sort_for_batching(std::vector<GpuDraw>& draws) {
  std::sort(draws.begin(), draws.end(), [](const GpuDraw& a, const GpuDraw& b) {
    if (a.material != b.material) return a.material < b.material;
    if (a.first_index != b.first_index) return a.first_index < b.first_index;
    return a.instance < b.instance;
  });
}

ImageDecl shadow_depth_array(uint32_t layers) {
  ImageDecl map{VK_FORMAT_D32_SFLOAT, kinds::light_depth};
  map.size.mode = SizeRule::Mode::square_param;
  map.size.param = "resolution";
  map.layers = layers;
  map.clear.depthStencil = {1.0f, 0};
  return map;
}

void bind_casters(PassContext& ctx, uint32_t layer) {
  ctx.bind_pipeline();
  ctx.push_declared();
  ctx.push_constants(CasterConstants{layer});
}

void draw_casters(PassContext& ctx, const std::string& draws, DrawRange range) {
  draw_scene(
      ctx, draws, [](uint32_t, const GpuMaterial&) {}, range);
}

}  // namespace nightcap
