// frame.constants: the camera, sun and frame facts every pass reads (passes/frame/constants.cpp).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "passes/core/pass.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

PassDecl frame_constants_pass();

// scene.lights[index] as the shading passes read it (frame.lights, probes.lights): relative to `eye`, its
// radiance the colour times the intensity, its index kept (cos_inner.y).
GpuLight relative_light(const LightRecord& light, uint32_t index, const glm::dvec3& eye);

}  // namespace nightcap
