#version 460
// shadow.cascades and shadow.cascades_static: one layer of a depth array laid down as it is,
// before casters are drawn over it (this frame's static depth under its moving casters; the
// previous frame's static depth kept).
layout(set = 0, binding = 0) uniform sampler2DArray source;

layout(push_constant) uniform Params { uint layer; };

void main() { gl_FragDepth = texelFetch(source, ivec3(ivec2(gl_FragCoord.xy), int(layer)), 0).r; }
