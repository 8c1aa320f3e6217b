#include "passes/scene/scene_kit.h"

namespace nightcap::scene_kit {
namespace {

void facade_textures(Random& random, Texture& base, Texture& emissive, double lit_share) {
  const uint32_t size = 256, cell = 64;
  base = {"facade.base", size, size, true, std::vector<uint8_t>(size * size * 4)};
  emissive = {"facade.emissive", size, size, true, std::vector<uint8_t>(size * size * 4)};
  std::array<std::array<uint8_t, 3>, 16> window_colour{};
  for (auto& c : window_colour) {
    if (random.uniform() > lit_share) continue;
    const bool warm = random.uniform() < 0.7;
    const double level = random.range(0.45, 1.0);
    c = warm ? std::array<uint8_t, 3>{uint8_t(255 * level), uint8_t(190 * level), uint8_t(110 * level)}
             : std::array<uint8_t, 3>{uint8_t(150 * level), uint8_t(200 * level), uint8_t(255 * level)};
  }
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const uint32_t cx = x % cell, cy = y % cell;
      const bool glass = cx >= 10 && cx < 54 && cy >= 14 && cy < 50;
      const uint8_t grain = uint8_t((x * 7 + y * 13) % 9);
      uint8_t* b = &base.rgba8[(y * size + x) * 4];
      uint8_t* e = &emissive.rgba8[(y * size + x) * 4];
      b[0] = glass ? 20 : uint8_t(58 + grain);
      b[1] = glass ? 24 : uint8_t(56 + grain);
      b[2] = glass ? 30 : uint8_t(60 + grain);
      b[3] = e[3] = 255;
      const auto& c = window_colour[(y / cell) * 4 + x / cell];
      for (int k = 0; k < 3; ++k) e[k] = glass ? c[k] : 0;
    }
}

}  // namespace

std::vector<uint32_t> facade_materials(Random& random, Builder& build) {
  Scene& scene = build.scene();
  std::vector<uint32_t> facades;
  for (int variant = 0; variant < 3; ++variant) {
    Texture base, emissive;
    facade_textures(random, base, emissive, 0.25 + 0.2 * variant);
    scene.textures.push_back(base);
    scene.textures.push_back(emissive);
    Material m = plain("facade." + std::to_string(variant), glm::vec3(1.0f), 0.0f, 0.55f, stencil::plain);
    m.base_color_texture.texture = int32_t(scene.textures.size() - 2);
    m.emissive_texture.texture = int32_t(scene.textures.size() - 1);
    m.emissive = glm::vec3(1.0f);
    m.emissive_strength = float(random.range(3.0, 8.0));
    facades.push_back(build.material(m));
  }
  return facades;
}

Material plain(const std::string& name, glm::vec3 colour, float metallic, float roughness, uint8_t stencil_class) {
  Material m;
  m.name = name;
  m.base_color = glm::vec4(colour, 1.0f);
  m.metallic = metallic;
  m.roughness = roughness;
  m.stencil_class = stencil_class;
  return m;
}

const std::array<glm::vec3, 5> kNeon = {glm::vec3(1.0f, 0.08f, 0.55f), glm::vec3(0.05f, 0.9f, 1.0f),
                                        glm::vec3(1.0f, 0.75f, 0.08f), glm::vec3(0.6f, 0.15f, 1.0f),
                                        glm::vec3(0.2f, 1.0f, 0.35f)};

Light neon_tube(const glm::dvec3& start, const glm::dvec3& end, const glm::vec3& colour, float range) {
  Light tube;
  tube.type = LightType::tube;
  tube.position = start;
  tube.end = end;
  tube.color = colour;
  tube.intensity = 60.0f;
  tube.range = range;
  tube.radius = 0.05f;
  return tube;
}

Light street_lamp(const glm::dvec3& position, float range) {
  Light lamp;
  lamp.type = LightType::point;
  lamp.position = position;
  lamp.color = {1.0f, 0.72f, 0.42f};
  lamp.intensity = 500.0f;
  lamp.range = range;
  return lamp;
}

Light moon() {
  Light moon;
  moon.type = LightType::directional;
  moon.direction = glm::normalize(glm::vec3(0.35f, -0.8f, 0.45f));
  moon.color = {0.55f, 0.65f, 1.0f};
  moon.intensity = 0.4f;
  return moon;
}

}  // namespace nightcap::scene_kit
