// The layout of a buffer output, declared with it (PassDecl::layout) and recorded in the capture,
// so diff and replay compare it field by field instead of as float words: an array of elements
// of `stride` bytes, each holding named fields of 32- or 64-bit scalars, vectors or matrices.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

namespace nightcap {

enum class Scalar { u32, i32, f32, f64 };

struct SchemaField {
  std::string name;
  Scalar scalar = Scalar::f32;
  uint32_t count = 1;  // components: 1 scalar, 2–4 vector, 16 mat4, or an array's length
  uint32_t offset = 0;

  uint32_t bytes() const { return count * (scalar == Scalar::f64 ? 8 : 4); }
};

struct BufferSchema {
  uint32_t stride = 0;
  std::vector<SchemaField> fields;  // by offset; bytes between them are padding

  // Fields of a standard-layout struct T by member pointer: the offset and type come from the
  // member itself, so the schema cannot drift from the struct the CPU or shader side writes.
  template <typename T>
  static BufferSchema of() {
    return BufferSchema{uint32_t(sizeof(T)), {}};
  }
  template <typename T, typename M>
  BufferSchema& field(std::string name, M T::*member);
};

// "u32", "f32", "vec3", "uvec4", "ivec2", "mat4", "f64[16]", …: one name per (scalar, count).
std::string type_name(const SchemaField& field);
// The scalar and count that `type`, one of type_name()'s names, stands for, into `field`; false
// for any other name.
bool read_type(std::string_view type, SchemaField& field);
nlohmann::json to_json(const BufferSchema& schema);
// Throws std::invalid_argument saying what is wrong: unknown type, a field past the stride.
BufferSchema schema_from_json(const nlohmann::json& json);

// Component `component` of `field` in element `element` of `bytes`, as a double (exact for
// every 32-bit value and every f64).
double read_component(std::span<const uint8_t> bytes, uint32_t stride, uint64_t element, const SchemaField& field,
                      uint32_t component);
// "model[13]", "counts.y" style: the field, and the component when it has more than one.
std::string component_name(const SchemaField& field, uint32_t component);

namespace schema_detail {

template <Scalar S>
struct ScalarType {
  static constexpr Scalar scalar = S;
  static constexpr uint32_t count = 1;
};
template <typename M>
struct FieldType;
template <>
struct FieldType<uint32_t> : ScalarType<Scalar::u32> {};
template <>
struct FieldType<int32_t> : ScalarType<Scalar::i32> {};
template <>
struct FieldType<float> : ScalarType<Scalar::f32> {};
template <>
struct FieldType<double> : ScalarType<Scalar::f64> {};
template <glm::length_t N, typename S>
struct FieldType<glm::vec<N, S>> {
  static constexpr Scalar scalar = FieldType<S>::scalar;
  static constexpr uint32_t count = N;
};
template <>
struct FieldType<glm::mat4> {
  static constexpr Scalar scalar = Scalar::f32;
  static constexpr uint32_t count = 16;
};
template <typename S, size_t N>
struct FieldType<S[N]> {
  static constexpr Scalar scalar = FieldType<S>::scalar;
  static constexpr uint32_t count = uint32_t(N) * FieldType<S>::count;
};

}  // namespace schema_detail

template <typename T, typename M>
BufferSchema& BufferSchema::field(std::string name, M T::*member) {
  static_assert(std::is_standard_layout_v<T> && std::is_trivially_copyable_v<T>, "a schema describes plain data");
  if (stride != sizeof(T)) throw std::logic_error("schema of " + name + ": built for a struct of another size");
  // The member's offset, measured on a value: offsetof cannot take a member pointer.
  static const T probe{};
  const auto offset = reinterpret_cast<const char*>(&(probe.*member)) - reinterpret_cast<const char*>(&probe);
  using Type = schema_detail::FieldType<M>;
  fields.push_back({std::move(name), Type::scalar, Type::count, uint32_t(offset)});
  return *this;
}

}  // namespace nightcap
