#include "passes/frame/gpu_types.h"

namespace nightcap {

BufferSchema frame_constants_schema() { return NC_SCHEMA_OF(GpuFrameConstants, NC_GPU_FRAME_CONSTANTS_FIELDS); }
BufferSchema view_schema() { return NC_SCHEMA_OF(GpuView, NC_GPU_VIEW_FIELDS); }
BufferSchema light_schema() { return NC_SCHEMA_OF(GpuLight, NC_GPU_LIGHT_FIELDS); }
BufferSchema draw_schema() { return NC_SCHEMA_OF(GpuDraw, NC_GPU_DRAW_FIELDS); }
BufferSchema decal_schema() { return NC_SCHEMA_OF(GpuDecal, NC_GPU_DECAL_FIELDS); }

}  // namespace nightcap
