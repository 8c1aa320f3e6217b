// What lighting.composite's shaders share with its pass (passes/core/gpu_layout.glsl.h says
// how this header is read by both compilers).
#ifndef NIGHTCAP_LIGHTING_COMPOSITE_GLSL_H
#define NIGHTCAP_LIGHTING_COMPOSITE_GLSL_H

#include "../core/gpu_layout.glsl.h"

#define NC_COMPOSITE_CONSTANTS_FIELDS(F, A, P)                      \
  /* rgb radiance of the uniform ambient term */                    \
  F(vec4, ambient)                                                  \
  /* rgb radiance where nothing was drawn */                        \
  F(vec4, sky)                                                      \
  /* x: 1 when sky.atmosphere holds a record (the sky's passes ran) \
     and sky.view is drawn, 0 for the constant `sky`; y: 1 to add   \
     the image-based specular's multiple scattering; z: 1 when      \
     gi.volume_data holds a record (the GI volume's passes ran) */  \
  F(uvec4, sky_source)                                              \
  /* x: metres over which a reflection probe's weight fades to 0 at \
     the faces of its box; y: the slots probes.slots lists (those   \
     holding a capture) */                                          \
  F(vec4, probes)
NC_PUSH_CONSTANTS(CompositeConstants, NC_COMPOSITE_CONSTANTS_FIELDS)

#endif
