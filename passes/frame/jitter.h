// TAA's jitter: the sub-pixel offset frame.constants gives the camera's projection each frame
// (GpuView::jitter), so that a still camera's frames sample every part of each pixel and TAA's
// history averages them into an anti-aliased image.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "passes/core/params.h"

namespace nightcap {

// Frames before the jitter repeats: 32 points of the Halton (2, 3) sequence.
constexpr uint32_t kJitterPeriod = 32;

// Frame `frame_index`'s offset in pixels, inside (-0.5, 0.5)²: 0 for frame 0, so that a single
// frame renders as it would without TAA; then, period after period, the Halton (2, 3) points of
// indices 1..kJitterPeriod less their mean, so that the samples a still pixel averages centre on
// it (the points themselves average (0.471, 0.463): an image shifted by 0.05 pixel).
glm::dvec2 taa_jitter(uint32_t frame_index);

// Sample frame_index mod n² of n² over the pixel, in pixels from its centre: one in each cell of
// an n×n grid, placed so that no two share a column or a row of the n²×n² grid (multi-jittered
// sampling, Chiu, Shirley and Wang 1994, without the shuffles): n² still frames offset so and
// averaged supersample the frame with a box filter, thin lines resolved to 1/n² of a pixel
// either way.
glm::dvec2 supersample_offset(uint32_t frame_index, uint32_t n);

// `taa.enabled`, which frame.constants (the jitter) and taa (the resolve) share.
ParamDecl taa_enabled_param();

}  // namespace nightcap
