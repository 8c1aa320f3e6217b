#include "replay/isolate.h"

#include <iomanip>
#include <sstream>

#include "replay/replay.h"

namespace nightcap {

void isolate_passes(GpuDevice& gpu, const Capture& a, const Capture& b, CaptureDiff& diff) {
  for (FrameDiff& frame : diff.frames)
    for (PassDiff& pass : frame.passes) {
      if (pass.status != PassStatus::origin && pass.status != PassStatus::inherited) continue;
      const PassReplay run = replay_across(gpu, a, b, frame.index, pass.name);
      PassIsolation& isolation = pass.isolation.emplace();
      isolation.reason = run.reason;
      for (const OutputCheck& output : run.outputs) {
        std::ostringstream made;
        made << verdict_name(output.verdict);
        if (output.verdict != Verdict::identical) {
          made << " (" << output.metric;
          if (output.contract) made << ", max abs " << std::setprecision(4) << output.amount;
          made << ")";
        }
        isolation.outputs.push_back({output.resource, output.verdict != Verdict::different, made.str()});
      }
    }
}

}  // namespace nightcap
