#include "passes/core/buffer_schema.h"

#include <charconv>
#include <cstring>
#include <optional>
#include <string_view>

namespace nightcap {
namespace {

const char* scalar_name(Scalar s) {
  switch (s) {
    case Scalar::u32:
      return "u32";
    case Scalar::i32:
      return "i32";
    case Scalar::f32:
      return "f32";
    case Scalar::f64:
      return "f64";
  }
  return "";
}

// GLSL's vector prefix of a 32-bit scalar: vec3, uvec3, ivec3.
const char* vector_prefix(Scalar s) { return s == Scalar::u32 ? "u" : s == Scalar::i32 ? "i" : ""; }

template <typename T>
double load(const uint8_t* at) {
  T value;
  std::memcpy(&value, at, sizeof value);
  return double(value);
}

std::optional<Scalar> scalar_named(std::string_view name) {
  for (Scalar s : {Scalar::u32, Scalar::i32, Scalar::f32, Scalar::f64})
    if (name == scalar_name(s)) return s;
  return std::nullopt;
}

}  // namespace

// The scalar and count of `type` into `field`, where type_name() gives `type` for a count up to
// 1024 (a record's per-tile arrays): parsed, then printed back, so that a name it would spell
// otherwise ("f32[3]" for "vec3") is unknown.
bool read_type(std::string_view type, SchemaField& field) {
  std::optional<Scalar> scalar;
  uint32_t count = 1;
  if (type == "mat4") {
    scalar = Scalar::f32;
    count = 16;
  } else if (const size_t open = type.find('['); open != type.npos && type.back() == ']') {
    scalar = scalar_named(type.substr(0, open));
    const std::string_view digits = type.substr(open + 1, type.size() - open - 2);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
    if (error != std::errc() || end != digits.data() + digits.size()) return false;
  } else if (const size_t vec = type.find("vec"); vec != type.npos && type.size() == vec + 4) {
    const std::string_view prefix = type.substr(0, vec);
    scalar = prefix == "u" ? Scalar::u32 : prefix == "i" ? Scalar::i32 : Scalar::f32;
    count = uint32_t(type.back() - '0');
  } else {
    scalar = scalar_named(type);
  }
  if (!scalar || count < 1 || count > 1024 || type_name({"", *scalar, count, 0}) != type) return false;
  field.scalar = *scalar;
  field.count = count;
  return true;
}

std::string type_name(const SchemaField& field) {
  if (field.count == 1) return scalar_name(field.scalar);
  if (field.scalar != Scalar::f64 && field.count <= 4)
    return std::string(vector_prefix(field.scalar)) + "vec" + std::to_string(field.count);
  if (field.scalar == Scalar::f32 && field.count == 16) return "mat4";
  return std::string(scalar_name(field.scalar)) + "[" + std::to_string(field.count) + "]";
}

nlohmann::json to_json(const BufferSchema& schema) {
  nlohmann::json fields = nlohmann::json::array();
  for (const SchemaField& f : schema.fields)
    fields.push_back({{"name", f.name}, {"type", type_name(f)}, {"offset", f.offset}});
  return {{"stride", schema.stride}, {"fields", fields}};
}

BufferSchema schema_from_json(const nlohmann::json& json) {
  BufferSchema schema;
  if (!json.is_object() || !json.contains("stride") || !json.at("stride").is_number_unsigned() ||
      !json.contains("fields") || !json.at("fields").is_array())
    throw std::invalid_argument("a schema needs an unsigned \"stride\" and a \"fields\" array");
  schema.stride = json.at("stride").get<uint32_t>();
  if (schema.stride == 0 || schema.stride > 65536) throw std::invalid_argument("schema stride outside 1..65536");
  for (const nlohmann::json& f : json.at("fields")) {
    if (!f.is_object() || !f.contains("name") || !f.at("name").is_string() || !f.contains("type") ||
        !f.at("type").is_string() || !f.contains("offset") || !f.at("offset").is_number_unsigned())
      throw std::invalid_argument("a schema field needs a \"name\", a \"type\" and an unsigned \"offset\"");
    SchemaField field;
    field.name = f.at("name").get<std::string>();
    field.offset = f.at("offset").get<uint32_t>();
    const std::string type = f.at("type").get<std::string>();
    if (!read_type(type, field))
      throw std::invalid_argument("field '" + field.name + "' has unknown type '" + type + "'");
    if (uint64_t(field.offset) + field.bytes() > schema.stride)
      throw std::invalid_argument("field '" + field.name + "' ends past the stride");
    schema.fields.push_back(std::move(field));
  }
  return schema;
}

double read_component(std::span<const uint8_t> bytes, uint32_t stride, uint64_t element, const SchemaField& field,
                      uint32_t component) {
  const uint32_t size = field.scalar == Scalar::f64 ? 8 : 4;
  const uint8_t* at = bytes.data() + element * stride + field.offset + component * size;
  switch (field.scalar) {
    case Scalar::u32:
      return load<uint32_t>(at);
    case Scalar::i32:
      return load<int32_t>(at);
    case Scalar::f32:
      return load<float>(at);
    case Scalar::f64:
      return load<double>(at);
  }
  return 0.0;
}

std::string component_name(const SchemaField& field, uint32_t component) {
  if (field.count == 1) return field.name;
  if (field.count <= 4) return field.name + "." + "xyzw"[component];
  return field.name + "[" + std::to_string(component) + "]";
}

}  // namespace nightcap
