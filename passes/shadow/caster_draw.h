// The draw record of a shadow caster, as shadow.cull, shadow.distant_plan and shadow.local_plan
// list them: a shadow map holds no motion, so the previous model is the model.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "passes/frame/gpu_types.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {

// `relative_model`: the instance's model matrix relative to the camera, as every draw list.
GpuDraw caster_draw(uint32_t instance, const InstanceRecord& record, const glm::dmat4& relative_model,
                    const MeshRecord& mesh);

}  // namespace nightcap
