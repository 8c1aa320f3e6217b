// gi.plan (CPU): where the GI volume lies this frame and which of its cells gi.volume gathers
// (frame.md's gi.volume [000][001]; volume_layout.glsl.h says how a cell is stored).
//
// The volume is camera-centred on a world grid: `cells` per side of `cell_metres`, its lowest
// cell cells / 2 below the camera's on each axis. It scrolls a whole cell at a time as the camera
// crosses cell boundaries, and being stored toroidally, its cells stay where they are.
//
// Refresh: everything is gathered on a frame without history (frame 0, a camera cut), when the
// cells or their size changed, when the sky seen from the camera changed (sky.atmosphere's
// record: the sky's irradiance every cell holds is another) and when the camera moved past the
// whole previous volume. Otherwise only the cells that scrolled in (at most three slabs: those
// outside the previous volume's range on x, then on y, then on z) and the cells inside the box
// of each probe captured this frame (probes.plan: a probe over its budget is captured frames
// after its neighbourhood came in); the rest are kept. A still camera gathers nothing after its
// first frame (the probes all captured on the first).
// Records: gi.volume_data (the shaders' GpuGiVolume), gi.refresh (the boxes, GiBox) and gi.plan
// (GiPlan), which the next frame reads back as its history; all empty without the sky's record
// (no directional light, `--set sky.enabled=0`) or with `--set gi.enabled=0`.
#include <algorithm>
#include <cmath>
#include <optional>

#include "passes/core/context.h"
#include "passes/core/previous_record.h"
#include "passes/frame/scene_resources.h"
#include "passes/gi/stage.h"
#include "passes/gi/volume_layout.h"
#include "passes/probes/capture_layout.h"
#include "passes/probes/plan.h"
#include "passes/sky/atmosphere.glsl.h"

namespace nightcap {
namespace {

using glm::dvec3;
using glm::ivec3;

// A box of world cells [min, max).
struct CellBox {
  ivec3 min, max;
  bool empty() const { return glm::any(glm::lessThanEqual(max, min)); }
  CellBox meet(const CellBox& other) const { return {glm::max(min, other.min), glm::min(max, other.max)}; }
};

class GiPlanner {
 public:
  explicit GiPlanner(PassContext& ctx)
      : ctx_(ctx), camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)) {
    eye_ = dvec3(camera_.world[12], camera_.world[13], camera_.world[14]);
  }

  void run() {
    // Without the sky (no directional light, the sky switched off) there is nothing to gather,
    // and disabled, nothing is wanted: every output empty (gi.volume skips or clears the volume,
    // the composite lights with the sky's irradiance, if any). It still runs, so a replay of it
    // reproduces the record.
    if (!ctx_.flag("enabled") || !ctx_.reads("sky.atmosphere") || ctx_.host("sky.atmosphere").empty()) {
      ctx_.store<GpuGiVolume>("gi.volume_data", {});
      ctx_.store<GiBox>("gi.refresh", {});
      ctx_.store<GiPlan>("gi.plan", {});
      return;
    }
    GiPlan plan{};
    plan.cells = uint32_t(ctx_.param_int("cells"));
    plan.cell_metres = float(ctx_.param_float("cell_metres"));
    const double cell = plan.cell_metres;
    const dvec3 eye_cell = glm::floor(eye_ / cell);
    if (!glm::all(glm::lessThan(glm::abs(eye_cell), dvec3(1e9))))
      throw GraphError("gi.plan: the camera lies " + std::to_string(glm::length(eye_)) +
                       " m from the origin, past what a cell index holds");
    const ivec3 origin = ivec3(eye_cell) - int32_t(plan.cells / 2);
    for (int axis = 0; axis < 3; ++axis) plan.origin_cell[axis] = origin[axis];
    const CellBox volume{origin, origin + int32_t(plan.cells)};

    std::vector<GiBox> boxes;
    plan.refresh = uint32_t(whole_refresh(plan));
    if (plan.refresh != uint32_t(GiRefresh::kept)) {
      add(boxes, volume, GiBoxReason::whole);
    } else {
      const ivec3 before(previous_->origin_cell[0], previous_->origin_cell[1], previous_->origin_cell[2]);
      scrolled_in(CellBox{before, before + int32_t(plan.cells)}, volume, boxes);
      captured_probes(volume, cell, boxes);
    }
    plan.boxes = uint32_t(boxes.size());
    for (const GiBox& box : boxes) plan.refreshed_cells += box.cells;

    GpuGiVolume data{};
    data.origin = glm::vec4(glm::vec3(glm::dvec3(origin) * cell - eye_), float(cell));
    data.origin_cell = glm::ivec4(origin, int32_t(plan.cells));
    const uint32_t bands = uint32_t(ctx_.param_int("sh_order"));
    data.evaluation = glm::uvec4(bands, bands == 1 ? 3u : kGiVolumeTexels, 0u, 0u);
    ctx_.store<GpuGiVolume>("gi.volume_data", {&data, 1});
    ctx_.store<GiBox>("gi.refresh", boxes);
    ctx_.store<GiPlan>("gi.plan", {&plan, 1});
  }

 private:
  GiRefresh whole_refresh(const GiPlan& plan) {
    previous_ = previous_record<GiPlan>(ctx_, "gi.plan");
    if (!previous_) return GiRefresh::no_history;
    if (previous_->cells != plan.cells || previous_->cell_metres != plan.cell_metres) return GiRefresh::changed;
    if (ctx_.reads("sky.atmosphere")) {
      const std::span<const uint8_t> sky = ctx_.host("sky.atmosphere");
      if (sky.size() == sizeof(GpuAtmosphere) && host_records<GpuAtmosphere>(sky).at(0).changed.y != 0u)
        return GiRefresh::sky_changed;
    }
    for (int axis = 0; axis < 3; ++axis)
      if (std::abs(int64_t(plan.origin_cell[axis]) - previous_->origin_cell[axis]) >= int64_t(plan.cells))
        return GiRefresh::jumped;
    return GiRefresh::kept;
  }

  static void add(std::vector<GiBox>& boxes, const CellBox& box, GiBoxReason reason) {
    if (box.empty()) return;
    GiBox record{};
    const ivec3 size = box.max - box.min;
    for (int axis = 0; axis < 3; ++axis) {
      record.min[axis] = box.min[axis];
      record.size[axis] = uint32_t(size[axis]);
    }
    record.reason = uint32_t(reason);
    record.cells = record.size[0] * record.size[1] * record.size[2];
    boxes.push_back(record);
  }

  // The cells of `now` outside `before`, as disjoint slabs: outside before's x range; then,
  // within it, outside its y range; then, within both, outside its z range.
  static void scrolled_in(const CellBox& before, const CellBox& now, std::vector<GiBox>& boxes) {
    CellBox rest = now;
    for (int axis = 0; axis < 3; ++axis) {
      CellBox below = rest, above = rest;
      below.max[axis] = std::min(rest.max[axis], before.min[axis]);
      above.min[axis] = std::max(rest.min[axis], before.max[axis]);
      add(boxes, below, GiBoxReason::scrolled_in);
      add(boxes, above, GiBoxReason::scrolled_in);
      rest.min[axis] = std::max(rest.min[axis], before.min[axis]);
      rest.max[axis] = std::min(rest.max[axis], before.max[axis]);
    }
  }

  // The volume's cells whose centres lie inside the box of a probe captured this frame.
  void captured_probes(const CellBox& volume, double cell, std::vector<GiBox>& boxes) const {
    if (!ctx_.reads("probes.plan") || !ctx_.reads("probes.slots")) return;
    const ProbePlan plan = read_probe_plan(ctx_.host("probes.plan"));
    if (plan.captured > kProbeSlots)
      throw GraphError("gi.plan: probes.plan records " + std::to_string(plan.captured) + " captures");
    const auto slots = host_view<GpuProbeSlot>(ctx_.host("probes.slots"));
    for (uint32_t k = 0; k < plan.captured; ++k)
      for (const GpuProbeSlot& slot : slots) {
        if (uint32_t(slot.position.w) != plan.capture_slot[k]) continue;
        // Centre (i + 0.5) · cell inside [min, max]: i from ceil(min / cell − 0.5) to floor(max / cell − 0.5).
        const dvec3 low = (dvec3(glm::vec3(slot.box_min)) + eye_) / cell - 0.5;
        const dvec3 high = (dvec3(glm::vec3(slot.box_max)) + eye_) / cell - 0.5;
        const CellBox inside{ivec3(glm::clamp(glm::ceil(low), dvec3(-2e9), dvec3(2e9))),
                             ivec3(glm::clamp(glm::floor(high) + 1.0, dvec3(-2e9), dvec3(2e9)))};
        add(boxes, inside.meet(volume), GiBoxReason::probe_captured);
      }
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  dvec3 eye_{0.0};
  std::optional<GiPlan> previous_;
};

}  // namespace

PassDecl gi_plan_pass() {
  return PassDecl("gi.plan", PassType::cpu)
      .read("frame.camera", Use::host)
      .read_optional("sky.atmosphere", Use::host)
      .read_optional("probes.plan", Use::host)
      .read_optional("probes.slots", Use::host)
      .read_previous("gi.plan", Use::host)
      .write("gi.volume_data", Use::host, BufferDecl{kinds::buffer})
      .write("gi.refresh", Use::host, BufferDecl{kinds::buffer})
      .write("gi.plan", Use::host, BufferDecl{kinds::buffer})
      .layout("gi.volume_data", gi_volume_schema())
      .layout("gi.refresh", gi_box_schema())
      .layout("gi.plan", gi_plan_schema())
      .param(gi_cells_param())
      .param_float("cell_metres", 2.0, 0.25, 64.0, "a GI volume cell's side")
      .choice("sh_order", 2, {{"L1", 1}, {"L2", 2}},
              "the spherical-harmonic bands lighting.composite evaluates: L1 (0–1) or L2 (0–2)")
      .param(ParamDecl::boolean("enabled", true, "0 skips the GI volume (indirect diffuse from the sky's irradiance)")
                 .shared_by("gi"))
      .run([](PassContext& ctx) { GiPlanner(ctx).run(); });
}

}  // namespace nightcap
