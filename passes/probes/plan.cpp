// probes.plan (CPU): which reflection probes are captured this frame, and the views they are
// captured from (frame.md's probes.update [000][001], planned as shadow.local_plan plans its
// cache).
//
// In range: the probes of scene.probes within `range_metres` of the camera; the nearest
// kProbeSlots (one texture array) hold a slot, ties by index. A slot keeps its probe while the
// probe stays among them, so its capture stays where it is; a probe that comes in range takes a
// free slot. A capture stays valid (the scene's static light does not change between frames);
// with `refresh_frames` > 0, one older than that is stale and is captured again.
//
// Budget: a frame without history (the first, a camera cut; the graph empties every history)
// captures every probe in range, as the shadow cache's reset draws every layer. After it, at
// most `max_updates` a frame: first those never captured, nearest first, then the stale ones,
// oldest capture first. A probe over the budget waits (recorded) and reflections where it would
// be show the sky until it is captured. With a still camera, every frame after the reset
// captures nothing.
//
// Views: six per captured probe in probes.views, the cube's faces in Vulkan's order, 90° square
// `face_size` views from the probe's position relative to the camera (perspective_view()), each
// the face seen as a camera sees it (kFaceAxes: the cube's texels mirrored left to right).
// What each slot holds and did is in the record (ProbePlan, ProbeSlotState), which the next
// frame reads back as its history; probes.slots lists the slots holding a capture for the GPU
// passes that read probes.array: each one's probe and box relative to the camera.
// `--set probes.enabled=0` leaves every output empty (no probes: the composite reflects the sky).
#include <algorithm>
#include <array>
#include <cstring>
#include <numeric>
#include <tuple>

#include "passes/core/context.h"
#include "passes/core/previous_record.h"
#include "passes/frame/scene_resources.h"
#include "passes/frame/view.h"
#include "passes/probes/capture_layout.h"
#include "passes/probes/plan.h"
#include "passes/probes/stage.h"

namespace nightcap {
namespace {

// The axes of each cube face's view as a camera's (columns: right, up, back). A cube map is
// left-handed: on every face the texel to the right of another (s growing) lies to the left of it
// as a camera facing the face sees it. The views are ordinary cameras (right × up is the back: no
// winding flipped, screen-space derivatives as the frame's), so view pixel (x, y) looks along cube
// texel (face_size − 1 − x, y), cube.glsl's cube_direction(face, st): probes.light mirrors x as
// it writes the cube.
const std::array<glm::dmat3, 6> kFaceAxes = {
    glm::dmat3(glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0)),    // +X
    glm::dmat3(glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0)),    // −X
    glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, -1, 0)),  // +Y
    glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0)),    // −Y
    glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1)),   // +Z
    glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)),     // −Z
};

glm::dvec3 probe_position(const ProbeRecord& p) { return {p.position[0], p.position[1], p.position[2]}; }

class ProbePlanner {
 public:
  explicit ProbePlanner(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        probes_(host_view<ProbeRecord>(ctx.host("scene.probes"))) {
    eye_ = glm::dvec3(camera_.world[12], camera_.world[13], camera_.world[14]);
  }

  void run() {
    // Disabled (the group's other passes skip), it plans nothing: no slot, no capture. It still
    // runs, so a replay of it reproduces the record.
    if (!ctx_.flag("enabled")) {
      ctx_.store<ProbePlan>("probes.plan", {});
      ctx_.store<GpuView>("probes.views", {});
      ctx_.store<GpuProbeSlot>("probes.slots", {});
      return;
    }
    ProbePlan plan{};
    std::fill(std::begin(plan.slot_probe), std::end(plan.slot_probe), kNoProbe);
    const std::vector<uint32_t> nearest = in_range(plan);
    const std::optional<ProbePlan> before = previous_record<ProbePlan>(ctx_, "probes.plan");
    plan.reset = before ? 0u : 1u;
    plan.max_updates = uint32_t(ctx_.param_int("max_updates"));

    std::vector<uint32_t> to_capture;  // slots, in the order they are captured
    if (plan.reset) {
      for (uint32_t slot = 0; slot < nearest.size(); ++slot) {
        plan.slot_probe[slot] = nearest[slot];
        plan.slot_state[slot] = uint32_t(ProbeSlotState::captured_reset);
        to_capture.push_back(slot);
      }
    } else {
      keep_slots(*before, nearest, plan);
      to_capture = choose_updates(plan);
    }

    std::vector<GpuView> views;
    for (const uint32_t slot : to_capture) {
      plan.slot_captured[slot] = camera_.frame_index;
      plan.capture_slot[plan.captured++] = slot;
      for (const glm::dmat3& axes : kFaceAxes) views.push_back(face_view(probes_[plan.slot_probe[slot]], axes));
    }
    ctx_.store<ProbePlan>("probes.plan", {&plan, 1});
    ctx_.store<GpuView>("probes.views", views);
    // The slots holding a capture (captured now or before), in slot order: what the composite
    // loops over at every pixel.
    std::vector<GpuProbeSlot> slots;
    for (uint32_t slot = 0; slot < kProbeSlots; ++slot) {
      if (plan.slot_probe[slot] == kNoProbe || plan.slot_state[slot] == uint32_t(ProbeSlotState::waiting)) continue;
      const ProbeRecord& probe = probes_[plan.slot_probe[slot]];
      auto relative = [&](const double(&p)[3]) {
        return glm::vec4(glm::vec3(glm::dvec3(p[0], p[1], p[2]) - eye_), 0.0f);
      };
      GpuProbeSlot record{relative(probe.position), relative(probe.box_min), relative(probe.box_max)};
      record.position.w = float(slot);
      slots.push_back(record);
    }
    ctx_.store<GpuProbeSlot>("probes.slots", slots);
  }

 private:
  // The probes in range, nearest first (ties by index), at most kProbeSlots; counts them all.
  std::vector<uint32_t> in_range(ProbePlan& plan) const {
    const double range = ctx_.param_float("range_metres");
    std::vector<std::pair<double, uint32_t>> found;
    for (uint32_t i = 0; i < probes_.size(); ++i) {
      const double distance = glm::length(probe_position(probes_[i]) - eye_);
      if (distance <= range) found.push_back({distance, i});
    }
    plan.in_range = uint32_t(found.size());
    std::sort(found.begin(), found.end());
    std::vector<uint32_t> nearest;
    for (size_t k = 0; k < found.size() && k < kProbeSlots; ++k) nearest.push_back(found[k].second);
    return nearest;
  }

  // A slot keeps a probe still among the nearest, with its capture; the others come in range and
  // take the free slots, lowest first.
  void keep_slots(const ProbePlan& before, const std::vector<uint32_t>& nearest, ProbePlan& plan) const {
    std::vector<bool> placed(nearest.size(), false);
    for (uint32_t slot = 0; slot < kProbeSlots; ++slot) {
      const auto at = std::find(nearest.begin(), nearest.end(), before.slot_probe[slot]);
      if (at == nearest.end()) continue;
      placed[size_t(at - nearest.begin())] = true;
      plan.slot_probe[slot] = before.slot_probe[slot];
      const bool captured = before.slot_state[slot] != uint32_t(ProbeSlotState::waiting) &&
                            before.slot_state[slot] != uint32_t(ProbeSlotState::empty);
      plan.slot_state[slot] = uint32_t(captured ? ProbeSlotState::up_to_date : ProbeSlotState::waiting);
      plan.slot_captured[slot] = captured ? before.slot_captured[slot] : 0u;
    }
    uint32_t free_slot = 0;
    for (size_t k = 0; k < nearest.size(); ++k) {
      if (placed[k]) continue;
      while (plan.slot_probe[free_slot] != kNoProbe) ++free_slot;  // nearest ≤ kProbeSlots: one is free
      plan.slot_probe[free_slot] = nearest[k];
      plan.slot_state[free_slot] = uint32_t(ProbeSlotState::waiting);
    }
  }

  // The slots captured this frame within the budget: those never captured, nearest first, then
  // those older than refresh_frames, oldest first. The rest wait (a stale one keeps its capture).
  std::vector<uint32_t> choose_updates(ProbePlan& plan) const {
    const uint32_t refresh = uint32_t(ctx_.param_int("refresh_frames"));
    struct Need {
      bool stale;
      double order;  // distance for a probe never captured, minus the capture's age for a stale one
      uint32_t slot;
    };
    std::vector<Need> needs;
    for (uint32_t slot = 0; slot < kProbeSlots; ++slot) {
      const uint32_t probe = plan.slot_probe[slot];
      if (probe == kNoProbe) continue;
      if (plan.slot_state[slot] == uint32_t(ProbeSlotState::waiting)) {
        needs.push_back({false, glm::length(probe_position(probes_[probe]) - eye_), slot});
      } else if (refresh > 0 && camera_.frame_index - plan.slot_captured[slot] >= refresh) {
        needs.push_back({true, -double(camera_.frame_index - plan.slot_captured[slot]), slot});
      }
    }
    std::sort(needs.begin(), needs.end(), [](const Need& a, const Need& b) {
      return std::tie(a.stale, a.order, a.slot) < std::tie(b.stale, b.order, b.slot);
    });
    std::vector<uint32_t> chosen;
    for (const Need& need : needs) {
      if (chosen.size() >= plan.max_updates) break;
      plan.slot_state[need.slot] = uint32_t(need.stale ? ProbeSlotState::captured_stale : ProbeSlotState::captured_new);
      chosen.push_back(need.slot);
    }
    return chosen;
  }

  GpuView face_view(const ProbeRecord& probe, const glm::dmat3& axes) const {
    const uint32_t side = uint32_t(ctx_.param_int("face_size"));
    return perspective_view({.eye = probe_position(probe) - eye_,
                             .orientation = axes,
                             .yfov = glm::radians(90.0),
                             .znear = ctx_.param_float("near_metres"),
                             .width = side,
                             .height = side});
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  std::span<const ProbeRecord> probes_;
  glm::dvec3 eye_{0.0};
};

}  // namespace

ProbePlan read_probe_plan(std::span<const uint8_t> record) {
  ProbePlan plan{};
  std::fill(std::begin(plan.slot_probe), std::end(plan.slot_probe), kNoProbe);
  if (record.empty()) return plan;
  if (record.size() != sizeof(plan))
    throw GraphError("probes.plan holds " + std::to_string(record.size()) + " bytes, not " +
                     std::to_string(sizeof(plan)));
  std::memcpy(&plan, record.data(), sizeof(plan));
  return plan;
}

BufferSchema probe_face_schema() { return NC_SCHEMA_OF(GpuProbeFace, NC_GPU_PROBE_FACE_FIELDS); }
BufferSchema probe_slot_schema() { return NC_SCHEMA_OF(GpuProbeSlot, NC_GPU_PROBE_SLOT_FIELDS); }

PassDecl probes_plan_pass() {
  return PassDecl("probes.plan", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("scene.probes", Use::host)
      .read_previous("probes.plan", Use::host)
      .write("probes.plan", Use::host, BufferDecl{kinds::buffer})
      .write("probes.views", Use::host, BufferDecl{kinds::buffer})
      .write("probes.slots", Use::host, BufferDecl{kinds::buffer})
      .layout("probes.plan", probe_plan_schema())
      .layout("probes.views", view_schema())
      .layout("probes.slots", probe_slot_schema())
      .param_float("range_metres", 150.0, 1.0, 10000.0, "probes within this distance of the camera are in range")
      .param_int("max_updates", 2, 0, kProbeSlots,
                 "probes captured per frame at most after a reset (a frame without history captures every probe "
                 "in range)")
      .param_int("refresh_frames", 0, 0, 100000,
                 "frames after which a capture is stale and captured again as the budget allows (0: never)")
      .param(probe_face_size())
      .param_float("near_metres", 0.05, 0.001, 10.0, "the captures' near plane")
      .param(ParamDecl::boolean("enabled", true, "0 skips the pass (reflection probes disabled by settings)")
                 .shared_by("probes"))
      .run([](PassContext& ctx) { ProbePlanner(ctx).run(); });
}

}  // namespace nightcap
