#include "inspect/command_output.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace nightcap::inspect_cli {

std::string format_ms(const std::optional<double>& value) {
  if (!value) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << *value;
  return s.str();
}

std::string shape(const ResourceRecord& r) {
  if (r.is_buffer) return std::to_string(r.buffer_size) + " B";
  std::string text = std::string(format_info(r.format)->name) + " " + std::to_string(r.extent.width) + "x" +
                     std::to_string(r.extent.height);
  if (r.extent.depth > 1) text += "x" + std::to_string(r.extent.depth);
  if (r.extent.mips > 1) text += " mips " + std::to_string(r.extent.mips);
  if (r.extent.layers > 1) text += " layers " + std::to_string(r.extent.layers);
  return text;
}

ojson resource_json(const ResourceRecord& r, bool output) {
  ojson j = {{"resource", r.resource}, {"kind", r.kind.name()}};
  if (r.is_buffer) {
    j["format"] = "BUFFER";
    j["bytes"] = r.buffer_size;
  } else {
    j["format"] = format_info(r.format)->name;
    j["width"] = r.extent.width;
    j["height"] = r.extent.height;
    j["depth"] = r.extent.depth;
    j["mips"] = r.extent.mips;
    j["layers"] = r.extent.layers;
    j["bytes"] = r.raw_bytes();
  }
  j["hash"] = r.hash;
  if (output) {
    j["contract"] = {{"kind", contract_kind_name(r.contract.kind)},
                     {"description", contract_description(r.contract)},
                     {"reason", r.contract.reason}};
    if (r.schema) j["schema"] = to_json(*r.schema);
  }
  return j;
}

std::string brief(const ojson& value) {
  if (value.is_number_float()) {
    std::ostringstream s;
    s << std::setprecision(6) << value.get<double>();
    return s.str();
  }
  if (value.is_array()) {
    std::string text = "(";
    for (size_t i = 0; i < value.size(); ++i) text += (i ? ", " : "") + brief(value[i]);
    return text + ")";
  }
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

ojson number_or_name(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  return value;
}

void print_flat(std::ostream& out, const nlohmann::json& value, const std::string& prefix) {
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) print_flat(out, item, prefix.empty() ? key : prefix + "." + key);
  } else if (value.is_array() && !value.empty() && (value[0].is_object() || value[0].is_array())) {
    for (size_t i = 0; i < value.size(); ++i) print_flat(out, value[i], prefix + "[" + std::to_string(i) + "]");
  } else {
    out << "  " << prefix << ": " << (value.is_string() ? value.get<std::string>() : value.dump()) << "\n";
  }
}

}  // namespace nightcap::inspect_cli
