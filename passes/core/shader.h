// GLSL → SPIR-V with glslang at run time, so replay can swap a pass's source.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace nightcap {

struct ShaderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Compiles `source` after `preamble` (lines of #define: a pass's binding_defines); the stage
// comes from the extension of `path` (.vert, .frag, .comp). `#include "x.glsl"` resolves
// against the embedded sources (relative to passes/, or to the including file's folder).
// Throws ShaderError with glslang's log, naming `path`.
std::vector<uint32_t> compile_glsl(const std::string& path, const std::string& source,
                                   const std::string& preamble = "");

// The embedded source of a shader path; throws ShaderError when unknown.
const std::string& shader_source(const std::string& path);

}  // namespace nightcap
