// How inspect commands print: resources and numbers for people on one line, and as JSON.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>

#include "captures/capture.h"

namespace nightcap::inspect_cli {

using ojson = nlohmann::ordered_json;

// Milliseconds with three decimals; "-" for none.
std::string format_ms(const std::optional<double>& value);
// "R16G16_SFLOAT 1280x720 mips 11", or a buffer's bytes.
std::string shape(const ResourceRecord& r);
// A resource's record as `info` lists it; an output adds its contract and schema.
ojson resource_json(const ResourceRecord& r, bool output);
// A JSON value on one line for people: numbers with 6 significant digits, arrays in brackets.
std::string brief(const ojson& value);
// JSON has no NaN or Inf: those are named.
ojson number_or_name(double value);
// Flattened "a.b.c: value" lines, for pipeline and sampler state.
void print_flat(std::ostream& out, const nlohmann::json& value, const std::string& prefix);

}  // namespace nightcap::inspect_cli
