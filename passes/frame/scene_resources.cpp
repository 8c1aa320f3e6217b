#include "passes/frame/scene_resources.h"

#include <cstring>

#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/scene/shadow_occluder.h"

namespace nightcap {
namespace {

template <typename T>
std::shared_ptr<std::vector<uint8_t>> bytes_of(const std::vector<T>& items) {
  auto bytes = std::make_shared<std::vector<uint8_t>>(items.size() * sizeof(T));
  if (!items.empty()) std::memcpy(bytes->data(), items.data(), bytes->size());
  return bytes;
}

ImportedData buffer(ResourceKind kind, std::shared_ptr<std::vector<uint8_t>> bytes) {
  ResourceDesc desc;
  desc.is_buffer = true;
  desc.kind = kind;
  desc.buffer_size = bytes->size();
  return {desc, std::move(bytes)};
}

// Box-filtered mip chain; sRGB textures are filtered in linear light.
ImportedData texture_with_mips(const Texture& texture) {
  ResourceDesc desc;
  desc.kind = kinds::texture;
  desc.format = texture.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
  desc.extent.width = texture.width;
  desc.extent.height = texture.height;
  desc.extent.mips = full_mip_count(texture.width, texture.height);
  auto bytes = std::make_shared<std::vector<uint8_t>>(texture.rgba8);
  std::vector<float> level(texture.rgba8.size());
  for (size_t i = 0; i < level.size(); ++i) {
    float v = texture.rgba8[i] / 255.0f;
    level[i] = texture.srgb && i % 4 != 3 ? srgb_to_linear(v) : v;
  }
  uint32_t w = texture.width, h = texture.height;
  for (uint32_t mip = 1; mip < desc.extent.mips; ++mip) {
    const uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
    std::vector<float> next(size_t(nw) * nh * 4);
    for (uint32_t y = 0; y < nh; ++y)
      for (uint32_t x = 0; x < nw; ++x)
        for (uint32_t c = 0; c < 4; ++c) {
          float sum = 0;
          int n = 0;
          for (uint32_t dy = 0; dy < 2; ++dy)
            for (uint32_t dx = 0; dx < 2; ++dx) {
              const uint32_t sx = std::min(w - 1, 2 * x + dx), sy = std::min(h - 1, 2 * y + dy);
              sum += level[(size_t(sy) * w + sx) * 4 + c];
              ++n;
            }
          next[(size_t(y) * nw + x) * 4 + c] = sum / n;
        }
    for (size_t i = 0; i < next.size(); ++i) {
      float v = texture.srgb && i % 4 != 3 ? linear_to_srgb(next[i]) : next[i];
      bytes->push_back(static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f));
    }
    level = std::move(next);
    w = nw;
    h = nh;
  }
  return {desc, std::move(bytes)};
}

}  // namespace

glm::dmat4 instance_model(const InstanceRecord& r, double time) {
  glm::dmat4 model(1.0);
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) model[c][row] = r.basis[c * 3 + row];
  glm::dvec3 translation(r.position[0], r.position[1], r.position[2]);
  if (r.flags & kInstanceMoving) translation += glm::dvec3(r.velocity[0], r.velocity[1], r.velocity[2]) * time;
  model[3] = glm::dvec4(translation, 1.0);
  return model;
}

std::string texture_resource(uint32_t index) { return "scene.texture." + std::to_string(index); }

uint32_t pack_sampler(const SamplerDesc& d) {
  return uint32_t(d.mag_filter) | uint32_t(d.min_filter) << 1 | uint32_t(d.mipmap_mode) << 2 |
         uint32_t(d.mipmaps) << 3 | uint32_t(d.wrap_u) << 4 | uint32_t(d.wrap_v) << 7;
}

SamplerDesc unpack_sampler(uint32_t bits) {
  SamplerDesc d;
  d.mag_filter = VkFilter(bits & 1);
  d.min_filter = VkFilter((bits >> 1) & 1);
  d.mipmap_mode = VkSamplerMipmapMode((bits >> 2) & 1);
  d.mipmaps = (bits >> 3) & 1;
  d.wrap_u = VkSamplerAddressMode((bits >> 4) & 7);
  d.wrap_v = VkSamplerAddressMode((bits >> 7) & 7);
  return d;
}

Imports scene_imports(const Scene& scene) {
  Imports imports;
  PackedGeometry geometry = pack_geometry(scene);
  imports["scene.geometry"] = buffer(kinds::buffer, std::make_shared<std::vector<uint8_t>>(std::move(geometry.bytes)));

  std::vector<MeshRecord> meshes;
  meshes.reserve(scene.primitives.size());
  for (size_t i = 0; i < scene.primitives.size(); ++i) {
    const Primitive& p = scene.primitives[i];
    MeshRecord r{};
    r.first_index = p.first_index;
    r.index_count = p.index_count;
    r.vertex_offset = p.vertex_offset;
    r.material = p.material;
    const PositionBox& box = geometry.boxes.at(i);
    for (int k = 0; k < 3; ++k) {
      r.bounds_min[k] = box.min[k];
      r.bounds_max[k] = box.max[k];
    }
    r.coarser = p.coarser;
    r.lod_distance = p.lod_distance;
    r.draw_distance = p.draw_distance;
    r.occluder_index_count = std::min(p.occluder_index_count, p.index_count);
    meshes.push_back(r);
  }
  std::vector<InstanceRecord> instances;
  instances.reserve(scene.instances.size());
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    InstanceRecord r{};
    for (int k = 0; k < 3; ++k) {
      r.position[k] = instance.world[3][k];
      r.velocity[k] = instance.velocity[k];
      for (int row = 0; row < 3; ++row) r.basis[k * 3 + row] = instance.world[k][row];
    }
    r.primitive = instance.primitive;
    r.material = scene.material_of(instance);
    r.flags =
        (instance.moving ? kInstanceMoving : 0) | (shadow_occluder_indices(scene, i) > 0 ? kInstanceShadowOccluder : 0);
    instances.push_back(r);
  }
  imports["scene.meshes"] = buffer(kinds::buffer, bytes_of(meshes));
  imports["scene.hierarchy"] =
      buffer(kinds::buffer, std::make_shared<std::vector<uint8_t>>(build_hierarchy(instances, meshes)));
  imports["scene.instances"] = buffer(kinds::buffer, bytes_of(instances));

  const int32_t white = static_cast<int32_t>(scene.textures.size());
  std::vector<GpuMaterial> materials;
  for (const Material& m : scene.materials) {
    GpuMaterial g{};
    g.base_color = m.base_color;
    g.emissive = glm::vec4(m.emissive * m.emissive_strength, 0.0f);
    g.pbr = {m.metallic, m.roughness, m.alpha_mode == AlphaMode::mask ? m.alpha_cutoff : -1.0f, m.normal_texture.scale};
    g.extra = {m.occlusion_texture.scale, m.translucency, float(m.alpha_mode),
               float((m.unlit ? 1 : 0) | (m.double_sided ? 2 : 0) | (m.decal ? 4 : 0))};
    const TextureRef* slots[] = {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                                 &m.occlusion_texture, &m.emissive_texture};
    int32_t uv_bits = 0;
    for (int s = 0; s < 5; ++s) {
      const int32_t index = slots[s]->texture;
      if (s < 4)
        g.textures[s] = index;
      else
        g.textures2.x = index;
      if (slots[s]->uv_set == 1) uv_bits |= 1 << s;
      if (s < 4)
        g.samplers[s] = pack_sampler(slots[s]->sampler);
      else
        g.samplers2.x = pack_sampler(slots[s]->sampler);
    }
    g.textures2.y = uv_bits;
    g.textures2.z = m.stencil_class;
    g.textures2.w = white;
    materials.push_back(g);
  }
  imports["scene.materials"] = buffer(kinds::buffer, bytes_of(materials));

  std::vector<LightRecord> lights;
  for (const Light& l : scene.lights) {
    LightRecord r{};
    for (int k = 0; k < 3; ++k) {
      r.position[k] = l.position[k];
      r.end[k] = l.end[k];
      r.direction[k] = l.direction[k];
      r.color[k] = l.color[k];
    }
    r.intensity = l.intensity;
    r.range = l.range;
    r.inner_cone = l.inner_cone;
    r.outer_cone = l.outer_cone;
    r.radius = l.radius;
    r.type = static_cast<uint32_t>(l.type);
    lights.push_back(r);
  }
  imports["scene.lights"] = buffer(kinds::buffer, bytes_of(lights));

  std::vector<DecalRecord> decals;
  for (const Decal& d : scene.decals) {
    DecalRecord r{};
    std::memcpy(r.world, &d.world[0][0], sizeof(r.world));
    for (int k = 0; k < 3; ++k) r.albedo[k] = d.albedo[k];
    r.opacity = d.opacity;
    r.metallic = d.metallic;
    r.roughness = d.roughness;
    r.normal_weight = d.normal_weight;
    r.scale = d.scale;
    r.pattern = uint32_t(d.pattern);
    r.draw_distance = d.draw_distance;
    decals.push_back(r);
  }
  imports["scene.decals"] = buffer(kinds::buffer, bytes_of(decals));

  std::vector<ProbeRecord> probes;
  for (const ReflectionProbe& p : scene.probes) {
    ProbeRecord r{};
    for (int k = 0; k < 3; ++k) {
      r.position[k] = p.position[k];
      r.box_min[k] = p.box_min[k];
      r.box_max[k] = p.box_max[k];
    }
    probes.push_back(r);
  }
  imports["scene.probes"] = buffer(kinds::buffer, bytes_of(probes));

  std::vector<uint32_t> tod;
  if (!scene.tod_visible.empty()) {
    const TodRecordHeader header{float(scene.tod_hour), uint32_t(scene.tod_visible.size())};
    static_assert(sizeof(header) == 2 * sizeof(uint32_t));
    tod.resize(2);
    std::memcpy(tod.data(), &header, sizeof(header));
    tod.insert(tod.end(), scene.tod_visible.begin(), scene.tod_visible.end());
  }
  imports["scene.tod"] = buffer(kinds::buffer, bytes_of(tod));

  for (uint32_t i = 0; i < scene.textures.size(); ++i)
    imports[texture_resource(i)] = texture_with_mips(scene.textures[i]);
  Texture white_texture{"white", 1, 1, false, {255, 255, 255, 255}};
  imports[texture_resource(white)] = texture_with_mips(white_texture);
  return imports;
}

Imports camera_import(const Camera& current, const Camera& previous, uint32_t width, uint32_t height,
                      uint32_t frame_index, bool cut) {
  CameraRecordGpu r{};
  std::memcpy(r.world, &current.world[0][0], sizeof(r.world));
  std::memcpy(r.previous_world, &previous.world[0][0], sizeof(r.previous_world));
  r.yfov = current.yfov;
  r.znear = current.znear;
  r.width = width;
  r.height = height;
  r.frame_index = frame_index;
  r.cut = cut;
  r.time = frame_index * kFrameSeconds;
  r.time_step = kFrameSeconds;
  auto bytes = std::make_shared<std::vector<uint8_t>>(sizeof(r));
  std::memcpy(bytes->data(), &r, sizeof(r));
  Imports imports;
  imports["frame.camera"] = buffer(kinds::buffer, bytes);
  return imports;
}

std::vector<ImportedResource> as_graph_imports(const Imports& imports) {
  std::vector<ImportedResource> list;
  for (const auto& [name, data] : imports) list.push_back({name, data.desc});
  return list;
}

}  // namespace nightcap
