// How a pass is timed. On a GPU the device's timestamps around a pass are its time. On a CPU
// device (lavapipe) they are not: the device's threads run whatever else the host runs meanwhile
// (a capture's encoding workers), and a draw is rasterised when a later command flushes it, so
// a compute pass after a draw pass is charged for the draws. There a pass is submitted alone,
// after everything before it has finished, and timed by the host's clock until its fence.
#pragma once

#include <optional>
#include <string_view>

namespace nightcap {

enum class PassTiming {
  overlapped,  // the frame runs as a whole, a capture encoding what is read back meanwhile
  alone,       // each GPU pass submitted and waited for alone; encoding starts after the frame
};
// `alone` on a CPU device, `overlapped` on a GPU (whose timestamps hold).
PassTiming default_pass_timing(bool device_is_cpu);
std::string_view pass_timing_name(PassTiming timing);  // "overlapped", "alone"
std::optional<PassTiming> pass_timing_from_name(std::string_view name);

// What a pass's time_ms was measured with.
enum class PassClock {
  device,      // the device's timestamps around the pass (its gpu_ms)
  host_alone,  // the host's steady clock from the pass's submit to its fence, the pass alone
  host,        // the host's steady clock around a CPU pass
};
std::string_view pass_clock_name(PassClock clock);  // "device", "host-alone", "host"
std::optional<PassClock> pass_clock_from_name(std::string_view name);

// Pushes what a pass could find in the host's caches out of them, by reading a buffer twice the
// size of the last-level cache. On a CPU device a pass replayed alone would otherwise read the
// inputs its upload has just written from cache, while in a frame the passes between a
// resource's writer and its reader have pushed it out (on lavapipe at 1280x720, depth.convert
// took 1.4x as long in the frame as replayed warm, and the same replayed cold).
void flush_host_caches();

}  // namespace nightcap
