#version 460
// Static surfaces: what moved on screen is the camera alone.
#include "surface.glsl"

void main() { write_gbuffer(in_position); }
