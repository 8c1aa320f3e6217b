#include "passes/scene/stencil_tags.h"

#include <algorithm>
#include <utility>

#include "passes/scene/scene.h"

namespace nightcap {
namespace {

struct TagClass {
  uint8_t tag;
  const char* name;
  std::array<uint8_t, 3> colour;
};

constexpr TagClass kClasses[] = {{stencil::plain, "plain", {0, 0, 0}},         {stencil::road, "road", {110, 110, 110}},
                                 {stencil::body, "body", {200, 150, 120}},     {stencil::face, "face", {240, 190, 160}},
                                 {stencil::vehicle, "vehicle", {40, 90, 220}}, {stencil::hair, "hair", {110, 70, 30}},
                                 {stencil::foliage, "foliage", {40, 170, 60}}};

const TagClass* class_of(uint32_t stencil) {
  for (const TagClass& c : kClasses)
    if ((stencil & ~uint32_t(stencil::moving)) == c.tag) return &c;
  return nullptr;
}

}  // namespace

std::string stencil_class_name(uint32_t stencil) {
  const TagClass* c = class_of(stencil);
  return c ? c->name : "unknown";
}

std::vector<std::string> stencil_flags(uint32_t stencil) {
  std::vector<std::string> flags;
  if (stencil & stencil::moving) flags.push_back("moving");
  return flags;
}

std::array<uint8_t, 3> stencil_colour(uint32_t stencil) {
  const TagClass* c = class_of(stencil);
  std::array<uint8_t, 3> colour = c ? c->colour : std::array<uint8_t, 3>{255, 0, 255};
  if (stencil & stencil::moving)
    for (uint8_t& channel : colour) channel = uint8_t(std::min(255, channel + 60));
  return colour;
}

void describe_stencil_tag(uint32_t stencil, nlohmann::ordered_json& out) {
  out["stencil"] = stencil;
  out["class"] = stencil_class_name(stencil);
  out["flags"] = stencil_flags(stencil);
}

}  // namespace nightcap
