// The scene and the camera as graph resources: everything a pass reads about the world is an
// imported resource with host bytes, so the capture records it and replay can feed it back.
#pragma once

#include <glm/glm.hpp>

#include <cstring>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "passes/core/graph.h"
#include "passes/frame/vertex_streams.h"
#include "passes/scene/scene.h"

namespace nightcap {

// scene.meshes: one record per primitive, the shared meshes instances point at.
struct MeshRecord {
  uint32_t first_index, index_count;
  int32_t vertex_offset;
  uint32_t material;
  float bounds_min[3], bounds_max[3];  // object space; also the box its positions are quantised in
  int32_t coarser;                     // next level of detail, -1 for none
  float lod_distance;                  // metres from the camera beyond which `coarser` is drawn
  float draw_distance;                 // metres from the camera beyond which nothing is drawn
  uint32_t occluder_index_count;       // the leading indices the occlusion buffer rasterises
};

// scene.instances: one record per drawable instance (host-side, read by cull.main). The
// transform is split so a map of 100 000 instances stays small: a double translation and a
// 3×3 basis (column-major), both as authored.
struct InstanceRecord {
  double position[3];
  double basis[9];
  float velocity[3];   // metres per second: the translation at time t is position + velocity·t
  uint32_t primitive;  // the finest level of detail
  uint32_t material;   // the effective material (an instance may override its mesh's)
  uint32_t flags;      // kInstanceMoving, kInstanceShadowOccluder
};
constexpr uint32_t kInstanceMoving = 1;
// Its finest mesh's occluder prefix (MeshRecord::occluder_index_count, whole triangles) is in
// every shadow map the instance is drawn into, at any level and distance
// (passes/scene/shadow_occluder.h).
constexpr uint32_t kInstanceShadowOccluder = 2;

// An instance's world model matrix at `time` seconds (a moving one along its velocity).
glm::dmat4 instance_model(const InstanceRecord& r, double time);

// scene.lights: world-space lights (host-side, read by frame.constants).
struct LightRecord {
  double position[3], end[3];
  float direction[3], color[3];
  float intensity, range, inner_cone, outer_cone, radius;
  uint32_t type;
};

// scene.decals: the projected decals (host-side, read by cull.main), as Scene::decals holds them.
struct DecalRecord {
  double world[16];  // column-major: the unit cube → world
  float albedo[3], opacity;
  float metallic, roughness, normal_weight, scale;
  uint32_t pattern;
  float draw_distance;
};
static_assert(sizeof(DecalRecord) == 168);

// scene.probes: the reflection probes (host-side, read by probes.plan), as Scene::probes holds them.
struct ProbeRecord {
  double position[3], box_min[3], box_max[3];
};

// scene.tod: the time-of-day table of Scene::tod_visible (nothing when none is loaded): this
// header, then one uint32 per instance (bit k: it casts a visible shadow at 2k:00). shadow.cull
// keeps a static caster only when it is visible at a baked hour tod_hour_bits(hour) names.
struct TodRecordHeader {
  float hour;
  uint32_t instances;
};

// frame.camera: this frame's and the previous frame's camera (the same on a cut), and the clock.
struct CameraRecordGpu {
  double world[16], previous_world[16];
  double yfov, znear;
  uint32_t width, height, frame_index, cut;
  double time, time_step;  // seconds
};

// Frames advance this much each: the clock of motion, adaptation and every history.
constexpr double kFrameSeconds = 1.0 / 60.0;

struct ImportedData {
  ResourceDesc desc;
  std::shared_ptr<const std::vector<uint8_t>> bytes;
};
using Imports = std::map<std::string, ImportedData>;

// scene.geometry (pack_geometry), scene.meshes, scene.instances, scene.hierarchy
// (passes/frame/hierarchy.h), scene.materials, scene.lights, scene.decals, scene.probes, scene.tod and scene.texture.<n> (mip chains
// built here; the last texture is 1×1 white, bound where a material has none).
Imports scene_imports(const Scene& scene);
// frame.camera of frame `frame_index` (at frame_index × kFrameSeconds); `cut`: the view jumped.
Imports camera_import(const Camera& current, const Camera& previous, uint32_t width, uint32_t height,
                      uint32_t frame_index, bool cut);

std::string texture_resource(uint32_t index);
uint32_t pack_sampler(const SamplerDesc& desc);
SamplerDesc unpack_sampler(uint32_t bits);

std::vector<ImportedResource> as_graph_imports(const Imports& imports);

// The records of a host buffer in place, without a copy (scene.instances of a 16 km map is
// 11 MB); the buffer must be aligned for T, as the graph's host buffers are.
template <typename T>
std::span<const T> host_view(std::span<const uint8_t> bytes) {
  if (reinterpret_cast<uintptr_t>(bytes.data()) % alignof(T) != 0)
    throw std::logic_error("host buffer not aligned for its records");
  return {reinterpret_cast<const T*>(bytes.data()), bytes.size() / sizeof(T)};
}

// The records of a host buffer (scene.*, frame.camera, draws.*) as structs.
template <typename T>
std::vector<T> host_records(std::span<const uint8_t> bytes) {
  std::vector<T> out(bytes.size() / sizeof(T));
  if (!out.empty()) std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

}  // namespace nightcap
