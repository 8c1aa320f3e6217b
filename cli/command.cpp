#include "cli/command.h"

#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace nightcap::cli {

bool validation_requested() {
  const char* value = std::getenv("NIGHTCAP_VALIDATION");
  return value && std::string(value) == "1";
}

std::string ms(const std::optional<double>& value) {
  if (!value) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << *value;
  return s.str();
}

}  // namespace nightcap::cli
