// Mirrors passes/frame/gpu_types.h.
struct FrameConstants {
  mat4 view;
  mat4 projection;
  mat4 view_projection;
  mat4 inverse_view_projection;
  mat4 previous_view_projection;
  vec4 camera_world;
  vec4 viewport;
  vec4 sun_direction;
  vec4 sun_radiance;
  vec4 projection_params;
  vec4 timing;
  uvec4 counts;
  uvec4 light_groups;  // gpu_types.h says what
};

struct Light {
  vec4 position_type;
  vec4 end_radius;
  vec4 color_range;
  vec4 direction_cos_outer;
  vec4 cos_inner;
};

struct Draw {
  mat4 model;
  mat4 normal_matrix;
  mat4 previous_model;
  uint first_index;
  uint index_count;
  int vertex_offset;
  uint material;
  uint stencil;
  uint instance;
  uint mirrored;
  uint pad;
  vec4 position_origin;
  vec4 position_step;
};

struct Decal {
  mat4 model;
  mat4 local_from_world;
  vec4 albedo;
  vec4 surface;
  vec4 facing;
  uvec4 info;
};

struct Material {
  vec4 base_color;
  vec4 emissive;
  vec4 pbr;
  vec4 extra;
  ivec4 textures;
  ivec4 textures2;
  uvec4 samplers;
  uvec4 samplers2;
};

const uint LIGHT_DIRECTIONAL = 0u;
const uint LIGHT_POINT = 1u;
const uint LIGHT_SPOT = 2u;
const uint LIGHT_TUBE = 3u;

const float PI = 3.14159265358979;
