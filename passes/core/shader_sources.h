#pragma once

#include <map>
#include <string>

namespace nightcap {

// GLSL sources under passes/, keyed by path relative to passes/ ("gbuffer/opaque.frag").
// Generated at build time by embed_shaders.cmake.
const std::map<std::string, std::string>& embedded_shader_sources();

}  // namespace nightcap
