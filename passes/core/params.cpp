#include "passes/core/params.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "passes/core/graph.h"

namespace nightcap {
namespace {

std::string number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// The declaration `key.name` sets, or why it sets none.
struct Settable {
  const ParamDecl* decl = nullptr;
  std::string problem;
};

Settable settable(const std::vector<PassDecl>& passes, const std::string& key, const std::string& name) {
  for (const PassDecl& pass : passes)
    for (const ParamDecl& param : pass.params)
      if (param.name == name && override_key(pass, param) == key) return {&param, ""};
  const std::string what = key + "." + name;
  if (const PassDecl* pass = find_pass(passes, key)) {
    if (const ParamDecl* param = pass->find_param(name)) {
      std::string members;
      for (const PassDecl& other : passes)
        if (const ParamDecl* shared = other.find_param(name); shared && shared->group == param->group)
          members += (members.empty() ? "" : ", ") + other.name;
      return {nullptr, what + ": shared by " + members + ": set " + param->group + "." + name};
    }
    std::string known;
    for (const ParamDecl& param : pass->params)
      known += (known.empty() ? "" : ", ") + override_key(*pass, param) + "." + param.name;
    return {nullptr, what + ": unknown parameter (" + key + " has: " + (known.empty() ? "none" : known) + ")"};
  }
  std::set<std::string> members;  // a group's parameter once, however many passes share it
  for (const PassDecl& pass : passes)
    for (const ParamDecl& param : pass.params)
      if (override_key(pass, param) == key) members.insert(param.name);
  std::string known;
  for (const std::string& member : members) known += (known.empty() ? "" : ", ") + member;
  if (!known.empty()) return {nullptr, what + ": unknown parameter (group " + key + " has: " + known + ")"};
  return {nullptr, what + ": no pass or group named '" + key + "'"};
}

}  // namespace

ParamDecl ParamDecl::real(std::string name, double default_value, double min, double max, std::string help) {
  return {std::move(name), ParamType::real, default_value, min, max, {}, std::move(help), {}};
}

ParamDecl ParamDecl::integer(std::string name, double default_value, double min, double max, std::string help) {
  return {std::move(name), ParamType::integer, default_value, min, max, {}, std::move(help), {}};
}

ParamDecl ParamDecl::boolean(std::string name, bool default_value, std::string help) {
  return {std::move(name), ParamType::boolean, default_value ? 1.0 : 0.0, 0.0, 1.0, {}, std::move(help), {}};
}

ParamDecl ParamDecl::choice(std::string name, double default_value, std::vector<ParamChoice> choices,
                            std::string help) {
  // PassContext::param_int reads an enum's value.
  for (const ParamChoice& c : choices)
    if (c.value != std::floor(c.value)) throw std::logic_error(name + ": choice " + c.name + " is not a whole number");
  return {std::move(name), ParamType::choice, default_value, 0.0, 0.0, std::move(choices), std::move(help), {}};
}

ParamDecl ParamDecl::shared_by(std::string group_name) && {
  group = std::move(group_name);
  return std::move(*this);
}

std::string ParamDecl::problem_with(double value) const {
  switch (type) {
    case ParamType::real:
      if (std::isfinite(value) && value >= min && value <= max) return "";
      return "expected a number in [" + number(min) + ", " + number(max) + "]";
    case ParamType::integer:
      if (value == std::floor(value) && value >= min && value <= max) return "";
      return "expected a whole number in [" + number(min) + ", " + number(max) + "]";
    case ParamType::boolean:
      if (value == 0 || value == 1) return "";
      return "expected 0 or 1 (false or true)";
    case ParamType::choice: {
      std::string names;
      for (const ParamChoice& c : choices) {
        if (c.value == value) return "";
        const bool named_by_value = c.name == number(c.value);
        names += (names.empty() ? "" : ", ") + (named_by_value ? c.name : c.name + " (" + number(c.value) + ")");
      }
      return "expected one of " + names;
    }
  }
  return "unknown type";
}

bool ParamDecl::same_values_as(const ParamDecl& other) const {
  return type == other.type && default_value == other.default_value && min == other.min && max == other.max &&
         choices == other.choices;
}

std::vector<ParamChoice> numbered_choices(std::span<const uint32_t> values) {
  std::vector<ParamChoice> choices;
  for (uint32_t v : values) choices.push_back({std::to_string(v), double(v)});
  return choices;
}

const std::string& override_key(const PassDecl& pass, const ParamDecl& param) {
  return param.group.empty() ? pass.name : param.group;
}

void check_overrides(const std::vector<PassDecl>& passes, const ParamOverrides& overrides) {
  for (const auto& [key, values] : overrides)
    for (const auto& [name, value] : values)
      if (const Settable found = settable(passes, key, name); !found.decl) throw GraphError(found.problem);
  std::map<std::pair<std::string, std::string>, std::pair<const PassDecl*, const ParamDecl*>> first_member;
  for (const PassDecl& pass : passes)
    for (const ParamDecl& param : pass.params) {
      if (param.group.empty()) continue;
      auto [it, added] = first_member.try_emplace({param.group, param.name}, &pass, &param);
      if (!added && !param.same_values_as(*it->second.second))
        throw GraphError(param.group + "." + param.name + ": " + it->second.first->name + " and " + pass.name +
                         " declare it differently (declare the group's parameter once)");
    }
}

ParamValues resolve_params(const PassDecl& pass, const ParamOverrides& overrides) {
  ParamValues values;
  for (const ParamDecl& param : pass.params) {
    const std::string& key = override_key(pass, param);
    double value = param.default_value;
    std::string given = " (its default)";
    if (auto set = overrides.find(key); set != overrides.end())
      if (auto it = set->second.find(param.name); it != set->second.end()) {
        value = it->second;
        given = key == pass.name ? "" : " (set as " + key + "." + param.name + ")";
      }
    if (const std::string problem = param.problem_with(value); !problem.empty())
      throw GraphError(pass.name + "." + param.name + " = " + number(value) + given + ": " + type_name(param.type) +
                       " parameter, " + problem);
    values[param.name] = value;
  }
  return values;
}

ParamOverrides overrides_of(const PassDecl& pass, const ParamValues& values) {
  ParamOverrides overrides;
  for (const auto& [name, value] : values) {
    const ParamDecl* param = pass.find_param(name);
    overrides[param ? override_key(pass, *param) : pass.name][name] = value;
  }
  return overrides;
}

void parse_set(const std::vector<PassDecl>& passes, const std::string& text, ParamOverrides& overrides) {
  const size_t equals = text.find('=');
  const size_t dot = text.rfind('.', equals);
  if (equals == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= equals)
    throw SetError("--set '" + text + "': expected PASS.PARAM=VALUE (or GROUP.PARAM=VALUE)");
  const std::string key = text.substr(0, dot), name = text.substr(dot + 1, equals - dot - 1);
  const std::string given = text.substr(equals + 1);
  const Settable found = settable(passes, key, name);
  if (!found.decl) throw SetError("--set " + found.problem);
  const ParamDecl& param = *found.decl;
  double value = std::nan("");
  if (param.type == ParamType::boolean && (given == "true" || given == "false")) value = given == "true";
  for (const ParamChoice& c : param.choices)
    if (c.name == given) value = c.value;
  if (std::isnan(value)) {
    char* end = nullptr;
    value = std::strtod(given.c_str(), &end);
    if (given.empty() || *end != '\0' || !std::isfinite(value))
      throw SetError("--set '" + text + "': " + type_name(param.type) + " parameter, " +
                     param.problem_with(std::nan("")));
  }
  if (const std::string problem = param.problem_with(value); !problem.empty())
    throw SetError("--set '" + text + "': " + type_name(param.type) + " parameter, " + problem);
  overrides[key][name] = value;
}

}  // namespace nightcap
