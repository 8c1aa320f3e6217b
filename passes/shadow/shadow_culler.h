// ShadowCuller: what shadow.cull runs each frame (passes/shadow/cull.cpp says what and why). It
// fits the sun's cascades to the view and plans what each draws (shadow_culler.cpp); which casters
// those are, walked through the hierarchy and culled, and which static tiles are redrawn within
// the budget, is shadow_culler_casters.cpp's.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "passes/core/context.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/occlusion_buffer.h"
#include "passes/frame/scene_resources.h"
#include "passes/shadow/cull_volume.h"
#include "passes/shadow/light_occluders.h"
#include "passes/shadow/light_tiles.h"
#include "passes/shadow/shadow_layout.h"

namespace nightcap::shadow_cull {

using glm::dvec3;

class ShadowCuller {
 public:
  explicit ShadowCuller(PassContext& ctx);

  void run();

 private:
  // The light depth every cascade spans: from the scene's side nearest the sun to its far side,
  // rounded outward to 16 m so that moving instances inside the static scene's box never move it.
  struct LightRange {
    double near, depth;
  };

  struct Cascade {
    glm::mat4 light_from_world;
    TiledMap map;
    glm::ivec2 centre;    // in whole texels of world light space
    glm::ivec2 shift{0};  // the previous frame's texel under this frame's (0, 0)
    LightRect footprint;  // the slice across the sun, grown by the margin: what the view needs of the map
    double far_light, margin, depth_margin;
    Volume volume;
  };

  // The cascades, fitted to the view, and the previous frame's record (shadow_culler.cpp).

  // The cascade over view depths [a, b].
  Cascade cascade(double a, double b, uint32_t resolution, uint32_t tiles, const LightRange& range) const;

  // The previous frame's record, or null when there is none to keep (frame 0, a cut, a frame
  // without cascades).
  const ShadowCullStats* previous_record();

  std::array<double, kShadowCascades + 1> split_distances() const;

  // Corners, relative to the camera at `world`, of its view between depths `a` and `b` along the view axis.
  Corners slice_corners(const glm::dmat4& world, double a, double b) const;

  // The light depth the cascades span (world, along the sun's travel): the hierarchy's root box
  // and every moving instance where it is now, a metre to spare, rounded outward to 16 m. Also
  // sets bottom_, the scene's lowest point relative to the camera.
  LightRange light_range();

  // The casters: which each cascade draws, and the static tiles redrawn this frame
  // (shadow_culler_casters.cpp).

  // Across the sun, the boxes of the static casters within the cascades' maps that a frame ago
  // were drawn at another level of detail or not at all (both levels' boxes): their tiles hold
  // the other level's depth. Also counts them (level_changes).
  std::vector<LightRect> level_changes(const std::array<Cascade, kShadowCascades>& cascades);

  // Whether a static caster across the sun from one of cascade k's areas is drawn there: not
  // when it lies behind the sun's occluders or the time of day hides it (neither changes a
  // texel, passes/shadow/cull.cpp says why). `first`: the first of the cascade's areas it meets,
  // to count it once.
  bool keeps_static(uint32_t index, const Box& box, const MeshRecord& mesh, uint32_t k, bool first);

  // Each static layer after a reset: every static caster across the sun from its map.
  void whole_layers(const std::array<Cascade, kShadowCascades>& cascades,
                    std::array<std::vector<GpuDraw>, kShadowCascades>& statics);

  // What to redraw this frame: each cascade's strips, when a tile misses only the texels they
  // hold, and its stale tiles; the strips the view needs first (they keep their tiles complete
  // for a fraction of a tile's cost), then the tiles it needs, then the others, tiles that have
  // waited longest first (else finest cascade first), while their triangles fit the budget (the
  // first even when it alone is over). Their draws are left in units_ and strips_.
  struct Refresh {
    std::array<uint64_t, kShadowCascades> tiles{};
    uint32_t strips = 0;  // bit k: cascade k's strips
  };
  Refresh refresh(const std::array<Cascade, kShadowCascades>& cascades,
                  const std::array<uint64_t, kShadowCascades>& stale,
                  const std::array<uint64_t, kShadowCascades>& partial,
                  const std::array<uint64_t, kShadowCascades>& needed);

  // The instance's model matrix relative to a camera at `eye`, at `time`.
  glm::dmat4 model_of(uint32_t index, const dvec3& eye, double time) const;

  const MeshRecord* mesh_at(uint32_t index) const;

  // The level the main view draws (cull.main picks it by the same distance), or null when the
  // instance is not drawn at all: degenerate, beyond its draw distance, or not an opaque caster.
  const MeshRecord* drawn_mesh(uint32_t index, const glm::dmat4& model) const;

  // The box, relative to a camera at `eye`, of the instance's drawn level at `time`; false when
  // it is not drawn.
  bool world_box(uint32_t index, Box& box, const MeshRecord** drawn, const dvec3& eye, double time) const;

  // The box of `mesh` under `model`.
  static Box box_of(const glm::dmat4& model, const MeshRecord& mesh);

  // Whether the camera-relative box's shadow, out to light depth `far` (camera-relative),
  // `margin` metres around and `depth_margin` toward the sun (extruded_slice says why), lies
  // wholly behind the view's occluders.
  bool shadow_hidden(const Box& box, double far, double margin, double depth_margin) const;

  // The cascade's static casters (through the hierarchy: a node outside the volume drops what it
  // holds) or its moving ones, culled by its volume, the view's occluders and the sun's.
  void casters(const Cascade& c, uint32_t cascade, bool statics, std::vector<GpuDraw>& out);

  uint32_t leaf_count(const HierarchyNode& node) const;

  GpuDraw draw_of(uint32_t index, const MeshRecord& mesh) const;

  PassContext& ctx_;
  CameraRecordGpu camera_;
  GpuFrameConstants constants_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  Hierarchy hierarchy_;
  OcclusionBuffer occlusion_;
  LightOccluders light_occluders_;
  bool culling_;
  std::span<const uint32_t> tod_visible_;  // empty: no table, every caster casts
  uint16_t tod_bits_ = 0;                  // the baked hours that decide at this hour
  glm::dmat4 world_{1.0}, view_projection_{1.0};
  dvec3 eye_{0.0}, travel_{0.0};
  LightAxes axes_;
  double bottom_ = INFINITY;  // the scene's lowest point, camera-relative
  ShadowCullStats stats_{};
  ShadowCullStats previous_{};
  std::vector<std::vector<GpuDraw>> units_;  // this frame's draws of each tile it considered
  // And of each cascade's strips: the columns' and the rows' the move uncovered.
  std::array<std::array<std::vector<GpuDraw>, 2>, kShadowCascades> strips_;
};

}  // namespace nightcap::shadow_cull
