// The views a pass draws scene geometry from, each draw naming its own (GpuDraw::view): the pass
// reads its view list as `views` (frame.views for the frame's camera).
layout(std430, set = 0, binding = NC_BINDING(views)) readonly buffer ViewBlock { GpuView views[]; };
