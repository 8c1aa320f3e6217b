#include "passes/frame/gpu_types.h"

namespace nightcap {

BufferSchema frame_constants_schema() {
  using C = GpuFrameConstants;
  return BufferSchema::of<C>()
      .field("view", &C::view)
      .field("projection", &C::projection)
      .field("view_projection", &C::view_projection)
      .field("inverse_view_projection", &C::inverse_view_projection)
      .field("previous_view_projection", &C::previous_view_projection)
      .field("camera_world", &C::camera_world)
      .field("viewport", &C::viewport)
      .field("sun_direction", &C::sun_direction)
      .field("sun_radiance", &C::sun_radiance)
      .field("projection_params", &C::projection_params)
      .field("counts", &C::counts)
      .field("light_groups", &C::light_groups);
}

BufferSchema light_schema() {
  using L = GpuLight;
  return BufferSchema::of<L>()
      .field("position_type", &L::position_type)
      .field("end_radius", &L::end_radius)
      .field("color_range", &L::color_range)
      .field("direction_cos_outer", &L::direction_cos_outer)
      .field("cos_inner", &L::cos_inner);
}

BufferSchema draw_schema() {
  using D = GpuDraw;
  return BufferSchema::of<D>()
      .field("model", &D::model)
      .field("normal_matrix", &D::normal_matrix)
      .field("previous_model", &D::previous_model)
      .field("first_index", &D::first_index)
      .field("index_count", &D::index_count)
      .field("vertex_offset", &D::vertex_offset)
      .field("material", &D::material)
      .field("stencil", &D::stencil)
      .field("instance", &D::instance)
      .field("mirrored", &D::mirrored)
      .field("position_origin", &D::position_origin)
      .field("position_step", &D::position_step);
}

BufferSchema decal_schema() {
  using D = GpuDecal;
  return BufferSchema::of<D>()
      .field("model", &D::model)
      .field("local_from_world", &D::local_from_world)
      .field("albedo", &D::albedo)
      .field("surface", &D::surface)
      .field("facing", &D::facing)
      .field("info", &D::info);
}

}  // namespace nightcap
