// The glTF loader. Input: a .gltf (JSON) or, when it starts with the binary magic, a .glb. A scene
// that loads must hold what the renderer relies on without checking again: every primitive's
// indices, after its vertex offset, inside the vertex array; materials, textures and primitives
// referenced by index exist; texture pixels match their size. The camera that frames it and its
// feature list must be computable.
#include <cstring>

#include "passes/scene/scene.h"
#include "tests/fuzz/scratch_file.h"

namespace nc = nightcap;

namespace {

void check_texture_ref(const nc::Scene& scene, const nc::TextureRef& ref) {
  if (ref.texture < -1 || ref.texture >= int32_t(scene.textures.size())) __builtin_trap();
  if (ref.uv_set > 1) __builtin_trap();
}

void check(const nc::Scene& scene) {
  for (const nc::Primitive& p : scene.primitives) {
    if (uint64_t(p.first_index) + p.index_count > scene.indices.size()) __builtin_trap();
    if (p.material >= scene.materials.size()) __builtin_trap();
    for (uint32_t i = p.first_index; i < p.first_index + p.index_count; ++i) {
      const int64_t vertex = int64_t(p.vertex_offset) + scene.indices[i];
      if (vertex < 0 || vertex >= int64_t(scene.vertices.size())) __builtin_trap();
    }
  }
  for (const nc::Material& m : scene.materials)
    for (const nc::TextureRef* ref : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                                      &m.occlusion_texture, &m.emissive_texture})
      check_texture_ref(scene, *ref);
  for (const nc::Texture& t : scene.textures)
    if (t.rgba8.size() != uint64_t(t.width) * t.height * 4) __builtin_trap();
  for (const nc::Instance& instance : scene.instances)
    if (instance.primitive >= scene.primitives.size()) __builtin_trap();
  (void)scene.features();
  (void)nc::framing_camera(scene, 16.0 / 9.0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const auto file = nc::fuzz::write_scratch(binary ? "scene.glb" : "scene.gltf", {data, size});
  nc::Scene scene;
  try {
    scene = nc::load_gltf(file.string());
  } catch (const nc::SceneError&) {
    return 0;
  }
  check(scene);
  return 0;
}
