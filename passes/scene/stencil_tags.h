// The stencil tags of frame.md (scene.h's `stencil` classes, the moving flag OR-ed on) as the
// tools show them: by name, and as a palette colour in pictures.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace nightcap {

// The class's name ("plain", "road", …; "unknown" for a tag no class has), moving flag aside.
std::string stencil_class_name(uint32_t stencil);
// The flags OR-ed onto the class: "moving".
std::vector<std::string> stencil_flags(uint32_t stencil);
// The class's palette colour (plain black, road grey, body and face skin tones, vehicle blue, hair
// brown, foliage green, unknown magenta), brightened where the moving flag is set; RGB.
std::array<uint8_t, 3> stencil_colour(uint32_t stencil);
// The tag as `inspect pixel` prints it: "stencil" (the value), "class" and "flags".
void describe_stencil_tag(uint32_t stencil, nlohmann::ordered_json& out);

}  // namespace nightcap
