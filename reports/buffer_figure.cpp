#include "reports/buffer_figure.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "compare/markup.h"
#include "inspect/decode.h"

namespace nightcap {
namespace {

using ojson = nlohmann::ordered_json;

// One component as decode_buffer_element gives it, in the fewest digits that read back as the
// value its field stores: a f32 printed as a double would show digits the float never held.
std::string exact(const ojson& value, Scalar scalar) {
  if (!value.is_number_float()) return value.dump();
  const double v = value.get<double>();
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  char text[32];
  const auto end = scalar == Scalar::f64 ? std::to_chars(text, text + sizeof text, v).ptr
                                         : std::to_chars(text, text + sizeof text, float(v)).ptr;
  return std::string(text, end);
}

// A field's value: one component, or its components in parentheses, as `inspect buffer` shows them.
std::string field_text(const SchemaField& field, const ojson& value) {
  if (field.count == 1) return exact(value, field.scalar);
  std::string text = "(";
  for (size_t c = 0; c < value.size(); ++c) text += (c ? ", " : "") + exact(value[c], field.scalar);
  return text + ")";
}

std::string record_table(const BufferSchema& schema, std::span<const uint8_t> raw) {
  const ojson fields = decode_buffer_element(schema, raw, 0);
  std::ostringstream html;
  html << "<div class=\"buffer-view\"><table class=\"record\">";
  for (const SchemaField& field : schema.fields)
    html << "<tr><th>" << escape_markup(field.name) << "</th><td>"
         << escape_markup(field_text(field, fields.at(field.name))) << "</td></tr>";
  html << "</table></div>";
  return html.str();
}

std::string list_table(const BufferSchema& schema, std::span<const uint8_t> raw, uint64_t count) {
  std::ostringstream html;
  html << "<div class=\"buffer-view\"><p class=\"count\">" << count << (count == 1 ? " element" : " elements") << " of "
       << schema.stride << " B</p>";
  if (count == 0) return html.str() + "</div>";
  html << "<table class=\"list\"><tr><th>#</th>";
  for (const SchemaField& field : schema.fields) html << "<th>" << escape_markup(field.name) << "</th>";
  html << "</tr>";
  const uint64_t shown = std::min(count, kListEntriesShown);
  for (uint64_t e = 0; e < shown; ++e) {
    const ojson fields = decode_buffer_element(schema, raw, e);
    html << "<tr><th>" << e << "</th>";
    for (const SchemaField& field : schema.fields)
      html << "<td>" << escape_markup(field_text(field, fields.at(field.name))) << "</td>";
    html << "</tr>";
  }
  html << "</table>";
  if (count > shown) html << "<p class=\"more\">… " << count - shown << " more</p>";
  html << "</div>";
  return html.str();
}

bool has_field(const BufferSchema& schema, const std::string& name) {
  for (const SchemaField& field : schema.fields)
    if (field.name == name) return true;
  return false;
}

// Each element is one draw of indexed triangles (passes/frame/gpu_types.h's GpuDraw: the frame's
// draw lists are recorded on the host, so every element is a draw); an element with an
// instance_count draws that many.
std::string draw_list_summary(const BufferSchema& schema, std::span<const uint8_t> raw, uint64_t count) {
  std::ostringstream html;
  html << "<div class=\"buffer-view draws\">" << count << (count == 1 ? " draw" : " draws");
  if (has_field(schema, "index_count")) {
    const bool instanced = has_field(schema, "instance_count");
    uint64_t triangles = 0;
    for (uint64_t e = 0; e < count; ++e) {
      const ojson fields = decode_buffer_element(schema, raw, e);
      triangles += fields.at("index_count").get<uint64_t>() / 3 *
                   (instanced ? fields.at("instance_count").get<uint64_t>() : uint64_t(1));
    }
    html << " · " << triangles << (triangles == 1 ? " triangle" : " triangles");
  }
  html << "</div>";
  return html.str();
}

}  // namespace

BufferFigure buffer_figure(const ResourceRecord& record, const BufferSchema* schema, std::span<const uint8_t> raw) {
  if (!schema) return {"<div class=\"no-picture\">" + std::to_string(record.buffer_size) + " bytes</div>"};
  const uint64_t count = buffer_elements(*schema, raw.size());
  if (record.kind == kinds::draw_list) return {draw_list_summary(*schema, raw, count)};
  if (count == 1)
    return {record_table(*schema, raw), std::any_of(schema->fields.begin(), schema->fields.end(),
                                                    [](const SchemaField& f) { return f.count > 4; })};
  return {list_table(*schema, raw, count), count > 0};
}

}  // namespace nightcap
