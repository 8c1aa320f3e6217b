// A pass's parameters: typed declarations (float, int, bool, enum), the groups that share one
// value, `--set` parsing, and the one merge of defaults and overrides: compile_graph resolves and
// checks every pass's values once (CompiledPass::params), and the executor, the capture and
// replay read them there.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace nightcap {

struct PassDecl;

enum class ParamType { real, integer, boolean, choice };
// As the capture records it; inline, as the capture readers are built without the graph.
constexpr const char* type_name(ParamType type) {
  switch (type) {
    case ParamType::real:
      return "float";
    case ParamType::integer:
      return "int";
    case ParamType::boolean:
      return "bool";
    case ParamType::choice:
      return "enum";
  }
  return "?";
}

// A named value of an enum parameter: `--set pass.mode=name` (or the value itself).
struct ParamChoice {
  std::string name;
  double value = 0.0;
  bool operator==(const ParamChoice&) const = default;
};

struct ParamDecl {
  std::string name;
  ParamType type = ParamType::real;
  double default_value = 0.0;
  double min = 0.0, max = 0.0;       // float and int: the values allowed, both included
  std::vector<ParamChoice> choices;  // enum: the values allowed
  std::string help;
  // Set as GROUP.NAME instead of PASS.NAME: every pass that declares it with this group takes the
  // one value (passes that must agree, such as the shadow passes' resolution). Declared once, as
  // a function returning the ParamDecl that each member passes to PassDecl::param.
  std::string group;

  static ParamDecl real(std::string name, double default_value, double min, double max, std::string help);
  static ParamDecl integer(std::string name, double default_value, double min, double max, std::string help);
  static ParamDecl boolean(std::string name, bool default_value, std::string help);
  static ParamDecl choice(std::string name, double default_value, std::vector<ParamChoice> choices, std::string help);
  ParamDecl shared_by(std::string group_name) &&;

  // "" when `value` is allowed; else what is ("a whole number in [64, 4096]", "one of 8, 16").
  std::string problem_with(double value) const;
  bool same_values_as(const ParamDecl& other) const;  // type, default, range and choices
};

// Enum choices named by their values (a tile size of 8, 16, 32 or 64).
std::vector<ParamChoice> numbered_choices(std::span<const uint32_t> values);

using ParamValues = std::map<std::string, double>;
// Values by the name they are set under: a pass's name, or a group's for what it shares.
using ParamOverrides = std::map<std::string, ParamValues>;

// The name `param` of `pass` is set under: its group, or the pass's name.
const std::string& override_key(const PassDecl& pass, const ParamDecl& param);

// Throws GraphError for an override that sets no declared parameter (an unknown name, or a
// group's member set on its own) and for a group whose members declare it differently.
void check_overrides(const std::vector<PassDecl>& passes, const ParamOverrides& overrides);
// Every declared parameter of `pass`: its default or its override, checked against its type
// and range; throws GraphError naming the pass, the parameter, the value and what is allowed.
ParamValues resolve_params(const PassDecl& pass, const ParamOverrides& overrides);
// `values` of `pass` (some or all of its parameters) filed under their override keys.
ParamOverrides overrides_of(const PassDecl& pass, const ParamValues& values);

// A `--set` the frame's parameters do not allow: the message names the flag and what is allowed.
struct SetError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Parses "PASS.PARAM=VALUE" or "GROUP.PARAM=VALUE" into `overrides`: the value by the
// parameter's type (an enum's choice by name, a bool as 0, 1, false or true) and checked; throws
// SetError.
void parse_set(const std::vector<PassDecl>& passes, const std::string& text, ParamOverrides& overrides);

}  // namespace nightcap
