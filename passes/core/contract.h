// How two versions of one output are compared: declared with the output, recorded in the
// capture, and used by `replay --verify` and `diff`. On the machine that made a capture a replay
// is bitwise unless the contract says the result depends on execution order; between builds or
// devices `diff` holds each output to its contract's bound.
#pragma once

#include <string>
#include <string_view>

namespace nightcap {

struct ComparisonContract {
  enum class Kind {
    exact,         // every byte equal
    float_values,  // per channel |b − a| ≤ absolute + relative·|a|
    unorm_codes,   // per channel within `absolute` codes of the format's bit depth
    angle,         // normals: the angle between the decoded vectors ≤ `absolute` degrees
    linear_depth,  // depth: |b − a| ≤ relative·a in the depth aspect; stencil exact
    set,           // buffers of 32-bit words: equal as multisets (lists built with atomics)
  };
  Kind kind = Kind::exact;
  double absolute = 0.0, relative = 0.0;
  // The GPU result depends on execution order (atomics): replay --verify on the same machine
  // holds it to the contract instead of bitwise equality.
  bool order_dependent = false;
  std::string reason;  // why this bound, stated with the declaration

  static ComparisonContract floats(double absolute, double relative, std::string why);
  static ComparisonContract codes(double codes, std::string why);
  static ComparisonContract degrees(double degrees, std::string why);
  static ComparisonContract depth(double relative, std::string why);
  static ComparisonContract unordered(std::string why);
};

std::string_view contract_kind_name(ComparisonContract::Kind kind);
// One line for people: "exact", "|b - a| <= 1e-07 + 0.002|a|", "within 1 code", …
std::string contract_description(const ComparisonContract& contract);
bool contract_kind_by_name(std::string_view name, ComparisonContract::Kind& kind);

}  // namespace nightcap
