#include "passes/core/contract.h"

#include <array>
#include <iomanip>
#include <sstream>
#include <utility>

namespace nightcap {
namespace {

using Kind = ComparisonContract::Kind;
constexpr std::array<std::pair<Kind, std::string_view>, 6> kNames = {{{Kind::exact, "exact"},
                                                                      {Kind::float_values, "float"},
                                                                      {Kind::unorm_codes, "unorm_codes"},
                                                                      {Kind::angle, "angle"},
                                                                      {Kind::linear_depth, "linear_depth"},
                                                                      {Kind::set, "set"}}};

ComparisonContract make(Kind kind, double absolute, double relative, std::string why) {
  ComparisonContract c;
  c.kind = kind;
  c.absolute = absolute;
  c.relative = relative;
  c.reason = std::move(why);
  return c;
}

}  // namespace

ComparisonContract ComparisonContract::floats(double absolute, double relative, std::string why) {
  return make(Kind::float_values, absolute, relative, std::move(why));
}
ComparisonContract ComparisonContract::codes(double codes, std::string why) {
  return make(Kind::unorm_codes, codes, 0.0, std::move(why));
}
ComparisonContract ComparisonContract::degrees(double degrees, std::string why) {
  return make(Kind::angle, degrees, 0.0, std::move(why));
}
ComparisonContract ComparisonContract::depth(double relative, std::string why) {
  return make(Kind::linear_depth, 0.0, relative, std::move(why));
}
ComparisonContract ComparisonContract::unordered(std::string why) {
  ComparisonContract c = make(Kind::set, 0.0, 0.0, std::move(why));
  c.order_dependent = true;
  return c;
}

std::string_view contract_kind_name(Kind kind) {
  for (const auto& [k, name] : kNames)
    if (k == kind) return name;
  return "exact";
}

std::string contract_description(const ComparisonContract& c) {
  std::ostringstream text;
  text << std::setprecision(4);
  switch (c.kind) {
    case Kind::exact:
      text << "exact";
      break;
    case Kind::float_values:
      text << "|b - a| <= " << c.absolute << " + " << c.relative << "|a|";
      break;
    case Kind::unorm_codes:
      text << "within " << c.absolute << " code" << (c.absolute == 1.0 ? "" : "s");
      break;
    case Kind::angle:
      text << "angle <= " << c.absolute << " deg";
      break;
    case Kind::linear_depth:
      text << "depth within " << c.relative << " relative, stencil exact";
      break;
    case Kind::set:
      text << "equal as sets";
      break;
  }
  return text.str();
}

bool contract_kind_by_name(std::string_view name, Kind& kind) {
  for (const auto& [k, n] : kNames)
    if (n == name) {
      kind = k;
      return true;
    }
  return false;
}

}  // namespace nightcap
