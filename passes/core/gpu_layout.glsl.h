// How a struct or constant that crosses to the GPU is written once, for both compilers. A
// `.glsl.h` header is read by the C++ compiler and by glslang (shaders `#include` it; CMake embeds
// it with the shaders), so it holds only what both preprocessors read alike: no variadic macros,
// no `#pragma once` (glslang ignores it: include guards), no `//` comment on a line a backslash
// continues (it would swallow the continuation: `/* */` there).
//
// A struct is a field list macro taking three macros, F(type, name) for a member,
// A(type, name, count) for an array and P(type, name) for padding (a member the schema leaves
// out, so tools read its bytes as padding), with GLSL's type names, one field a line and a `/* why */`
// comment above it (passes/frame/gpu_types.glsl.h is one), then NC_STRUCT(GpuLight,
// NC_GPU_LIGHT_FIELDS).
// NC_STRUCT declares the struct under one name in both languages (glm types in C++), and in C++
// NC_SCHEMA_OF(GpuLight, NC_GPU_LIGHT_FIELDS) is its BufferSchema, every field but padding in order, so the
// member list is written once for the struct, the shader and the capture. The layout rules
// differ (std140/std430 against C++'s, where glm::vec4 aligns to 4 bytes), so the C++ side keeps a
// static_assert on each struct's size and pads explicitly where GLSL would.
//
// Push constants are a field list too, in the pass's header: NC_PUSH_CONSTANTS(Name, FIELDS) is
// the C++ struct, and the one shader that pushes them declares the block (another shader may
// include the header: a stage has one push-constant block), members read unqualified:
//   layout(push_constant) uniform Name { NC_BLOCK_MEMBERS(FIELDS) };
//
// A constant both sides read (a table's size, a workgroup's side) is NC_CONST(uint, kName, 16u):
// a `const` in GLSL (array sizes and local_size_x take it), a constexpr in namespace nightcap.
#ifndef NIGHTCAP_GPU_LAYOUT_GLSL_H
#define NIGHTCAP_GPU_LAYOUT_GLSL_H

#ifdef __cplusplus

#include <cstdint>
#include <glm/glm.hpp>

#include "passes/core/buffer_schema.h"

// GLSL's type names as C++ types: a member's type token pasted onto `_type`, since `int` and
// `float` are keywords no alias can take.
namespace nightcap::glsl {
using float_type = float;
using int_type = int32_t;
using uint_type = uint32_t;
using vec2_type = glm::vec2;
using vec3_type = glm::vec3;
using vec4_type = glm::vec4;
using ivec2_type = glm::ivec2;
using ivec4_type = glm::ivec4;
using uvec2_type = glm::uvec2;
using uvec4_type = glm::uvec4;
using mat4_type = glm::mat4;
}  // namespace nightcap::glsl

#define NC_MEMBER(type, name) ::nightcap::glsl::type##_type name;
#define NC_ARRAY(type, name, count) ::nightcap::glsl::type##_type name[count];
#define NC_CONST(type, name, value)                            \
  namespace nightcap {                                         \
  inline constexpr ::nightcap::glsl::type##_type name = value; \
  }

#define NC_STRUCT(Name, FIELDS)            \
  namespace nightcap {                     \
  struct Name {                            \
    FIELDS(NC_MEMBER, NC_ARRAY, NC_MEMBER) \
  };                                       \
  }

#define NC_PUSH_CONSTANTS(Name, FIELDS) NC_STRUCT(Name, FIELDS)

namespace nightcap {
// Workgroups of `side` invocations along an axis that cover `size` (the last may reach past it).
constexpr uint32_t group_count(uint32_t size, uint32_t side) { return (size + side - 1) / side; }
}  // namespace nightcap

#define NC_SCHEMA_FIELD(type, name) .field(#name, &Layout::name)
#define NC_SCHEMA_ARRAY(type, name, count) .field(#name, &Layout::name)
#define NC_SCHEMA_PADDING(type, name)
// The BufferSchema of a struct NC_STRUCT declared from FIELDS.
#define NC_SCHEMA_OF(Name, FIELDS)                                                                             \
  [] {                                                                                                         \
    using Layout = Name;                                                                                       \
    return ::nightcap::BufferSchema::of<Layout>() FIELDS(NC_SCHEMA_FIELD, NC_SCHEMA_ARRAY, NC_SCHEMA_PADDING); \
  }()

#else

#define NC_MEMBER(type, name) type name;
#define NC_ARRAY(type, name, count) type name[count];
#define NC_CONST(type, name, value) const type name = value;
#define NC_STRUCT(Name, FIELDS)            \
  struct Name {                            \
    FIELDS(NC_MEMBER, NC_ARRAY, NC_MEMBER) \
  };
#define NC_PUSH_CONSTANTS(Name, FIELDS)
#define NC_BLOCK_MEMBERS(FIELDS) FIELDS(NC_MEMBER, NC_ARRAY, NC_MEMBER)

#endif

#endif
