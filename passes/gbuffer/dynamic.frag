#version 460
// Moving surfaces: each point's own previous position gives its motion vector.
#include "surface.glsl"

layout(location = 6) in vec3 in_previous_position;

void main() { write_gbuffer(in_previous_position); }
