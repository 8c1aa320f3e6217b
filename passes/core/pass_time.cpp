#include "passes/core/pass_time.h"

#include <unistd.h>

#include <cstdint>
#include <vector>

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

namespace {

// sysconf's answer, or `fallback` where the C library does not know it.
size_t cache_figure(int name, size_t fallback) {
  const long value = sysconf(name);
  return value > 0 ? static_cast<size_t>(value) : fallback;
}

}  // namespace

void flush_host_caches() {
  static const size_t line = cache_figure(_SC_LEVEL1_DCACHE_LINESIZE, 64);
  static const std::vector<uint8_t> sweep(2 * cache_figure(_SC_LEVEL3_CACHE_SIZE, size_t{32} << 20), 1);
  // Read, not written: dirty lines would be written back while the timed pass runs.
  uint8_t sum = 0;
  for (size_t at = 0; at < sweep.size(); at += line) sum += sweep[at];
  volatile uint8_t keep = sum;
  (void)keep;
}

}  // namespace nightcap
