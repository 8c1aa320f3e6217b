#include "passes/core/pass_time.h"

namespace nightcap {

PassTiming default_pass_timing(bool device_is_cpu) {
  return device_is_cpu ? PassTiming::alone : PassTiming::overlapped;
}

std::string_view pass_timing_name(PassTiming timing) { return timing == PassTiming::alone ? "alone" : "overlapped"; }

std::optional<PassTiming> pass_timing_from_name(std::string_view name) {
  for (PassTiming timing : {PassTiming::overlapped, PassTiming::alone})
    if (pass_timing_name(timing) == name) return timing;
  return std::nullopt;
}

std::string_view pass_clock_name(PassClock clock) {
  switch (clock) {
    case PassClock::device:
      return "device";
    case PassClock::host_alone:
      return "host-alone";
    case PassClock::host:
      break;
  }
  return "host";
}

std::optional<PassClock> pass_clock_from_name(std::string_view name) {
  for (PassClock clock : {PassClock::device, PassClock::host_alone, PassClock::host})
    if (pass_clock_name(clock) == name) return clock;
  return std::nullopt;
}

}  // namespace nightcap
