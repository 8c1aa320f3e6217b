// Parameters shadow passes share, each declared once as a group (ParamDecl::group): the passes
// that plan a map and the passes that draw it must agree on its size, so one `--set` sets both.
#pragma once

#include "passes/core/params.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap {

// shadow.cull plans the sun's cascades at this size and shadow.cascades_static draws them
// (`--set shadow.resolution=N`).
inline ParamDecl sun_shadow_resolution() {
  return ParamDecl::integer("resolution", kShadowResolution, 64, 4096, "texels per side of each cascade (even)")
      .shared_by("shadow");
}

// shadow.distant_plan plans the distant levels at this size and shadow.distant draws them
// (`--set shadow.distant.resolution=N`).
inline ParamDecl distant_shadow_resolution() {
  return ParamDecl::integer("resolution", kDistantResolution, 64, 4096,
                            "texels per side of each level (a multiple of 8)")
      .shared_by("shadow.distant");
}

// Texels per side of the top-down map (shadow.topdown_plan projects it, shadow.topdown sizes it).
inline ParamDecl topdown_resolution() {
  return ParamDecl::integer("resolution", 2048, 64, 8192, "texels per side of the top-down map (a multiple of 8)")
      .shared_by("shadow.topdown");
}

}  // namespace nightcap
