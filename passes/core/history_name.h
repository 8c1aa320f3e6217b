// How a history input is named: the previous frame's value of a resource is the resource read
// under "<name>@previous". Captures record that name, so the tools that read captures need the
// convention without the rest of the pass declaration.
#pragma once

#include <string>
#include <string_view>

namespace nightcap {

inline constexpr std::string_view kPreviousSuffix = "@previous";

// The name under which a pass reads the previous frame's `resource` (PassDecl::read_previous):
// "exposure.value" -> "exposure.value@previous". '@' is reserved for it.
inline std::string previous(const std::string& resource) { return resource + std::string(kPreviousSuffix); }

// previous()'s inverse: "exposure.value@previous" -> "exposure.value"; "" for any other name.
inline std::string history_source(const std::string& name) {
  if (name.size() <= kPreviousSuffix.size() || !name.ends_with(kPreviousSuffix)) return "";
  return name.substr(0, name.size() - kPreviousSuffix.size());
}

}  // namespace nightcap
