// The frame's camera, frame.views[0], for the passes that work on its pixels.
layout(std140, set = 0, binding = NC_BINDING(frame_views)) uniform CameraBlock { GpuView camera; };
