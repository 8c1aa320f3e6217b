// The reference taa is measured against (`render --supersample N`, the taa tests and benchmark):
// the same still frame rendered N² times without TAA, each render's projection offset to another
// part of the pixel, its lit colour averaged in double, put where taa's resolve would be.
#pragma once

#include <cstdint>
#include <vector>

#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"

namespace nightcap {

// Writes the supersampled colour into taa.resolved in place of taa. Its output is made from
// renders, not from inputs a capture records, so replay has nothing to run it on.
inline constexpr char kSupersampledPass[] = "taa.supersampled";

// `scene` held still: cars and pedestrians stopped and drawn as static geometry (`render
// --freeze`), so that every frame of a still camera renders the same picture.
Scene frozen(Scene scene);

// The mean, in double, of lighting.lit's RGB (RGB per pixel) over n² frames 0..n²-1 of
// `settings`' camera and parameters, TAA off, frame k's projection offset to sample k of an n×n
// multi-jittered pattern over the pixel (frame.constants.supersample): a box filter of n² samples.
// Meaningful for a still camera of a frozen scene; throws SceneError for a camera that moves or
// cuts. `monitor` sees each render and may stop them (RenderInterrupted).
std::vector<double> supersampled_lit(GpuDevice& gpu, const Scene& scene, RenderSettings settings, uint32_t n,
                                     const RenderMonitor& monitor = {});

// The frame of frame_passes(lighting) with taa replaced by kSupersampledPass, which writes `lit`
// (as supersampled_lit returns it, rounded to halves, alpha 1) into taa.resolved every frame;
// `samples` (n²) is recorded as its parameter.
std::vector<PassDecl> supersampled_frame_passes(const std::vector<double>& lit, uint32_t samples,
                                                FrameLighting lighting = FrameLighting::tiled);

}  // namespace nightcap
