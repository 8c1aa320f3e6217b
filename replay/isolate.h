// `diff --isolate`: tells "this pass changed" from "its inputs changed" for each pass a diff
// found different, by running the pass as one capture recorded it on the other's inputs.
#pragma once

#include "captures/capture.h"
#include "compare/diff.h"
#include "passes/core/device.h"

namespace nightcap {

// Fills `isolation` of every pass of `diff` whose outputs differ (origin or inherited): the
// pass as `b` recorded it, run on `a`'s inputs, against `a`'s outputs. Throws as replay_capture.
void isolate_passes(GpuDevice& gpu, const Capture& a, const Capture& b, CaptureDiff& diff);

}  // namespace nightcap
