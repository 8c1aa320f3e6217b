// cull.main (CPU): what the geometry passes draw this frame. The static instances are visited
// through scene.hierarchy and tested against the view frustum; moving instances (their
// translation advanced to this frame's time) are tested one by one. Each survivor picks its
// level of detail by distance. The largest nearby opaque survivors are the occluders: they are
// rasterised into a small conservative CPU depth buffer (passes/frame/occlusion_buffer.h), and
// every other instance whose box is behind it is dropped. The occluders are what depth.prepass
// draws. Lists are sorted in the seeds' order (static meshes; ground and emissive; foliage),
// then by material and mesh, so equal neighbours are drawn instanced (draw_scene batches them).
//
// Decals [000]: instances of a decal material are culled like the others but go to
// draws.decals.mesh (never occluders, never in the G-buffer lists); the projected decals of
// scene.decals are boxes tested against the frustum and the occlusion buffer alike and go, with
// camera-relative transforms computed in double, to draws.decals.projected.
//
// `frustum=0` / `occlusion=0` keep what those tests would drop (the references use them); the
// lists are otherwise the same, so a culled and an unculled frame draw in the same order.
// (A few lines over 600: the Culler's steps, the walk, the occluders, the decals and the lists,
// share its state, and the pass declaration sits beside it.)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <queue>
#include <tuple>

#include "passes/core/context.h"
#include "passes/cull/cull_stats.h"
#include "passes/cull/stage.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/draw_scene.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/hierarchy.h"
#include "passes/frame/level_of_detail.h"
#include "passes/frame/occlusion_buffer.h"
#include "passes/frame/scene_resources.h"

namespace nightcap {
namespace {

struct Plane {
  glm::dvec3 normal;
  double offset;  // inside where dot(normal, p) + offset ≥ 0
};

// Left, right, bottom, top and near planes of a camera-relative view-projection (the far plane
// is at infinity), in camera-relative world space.
std::array<Plane, 5> frustum_planes(const glm::dmat4& m) {
  const glm::dvec4 row0(m[0][0], m[1][0], m[2][0], m[3][0]), row1(m[0][1], m[1][1], m[2][1], m[3][1]),
      row2(m[0][2], m[1][2], m[2][2], m[3][2]), row3(m[0][3], m[1][3], m[2][3], m[3][3]);
  const glm::dvec4 rows[5] = {row3 + row0, row3 - row0, row3 + row1, row3 - row1, row3 - row2};
  std::array<Plane, 5> planes;
  for (int k = 0; k < 5; ++k) planes[k] = {glm::dvec3(rows[k]), rows[k].w};
  return planes;
}

enum class Containment { outside, crossing, inside };

// Outside only when the box lies wholly outside one plane (so its every corner is outside it);
// inside when it lies wholly inside every plane, with rounding slack on both sides.
Containment box_in_frustum(const std::array<Plane, 5>& planes, const glm::dvec3& lo, const glm::dvec3& hi) {
  Containment result = Containment::inside;
  for (const Plane& p : planes) {
    const glm::dvec3 far_corner(p.normal.x >= 0 ? hi.x : lo.x, p.normal.y >= 0 ? hi.y : lo.y,
                                p.normal.z >= 0 ? hi.z : lo.z);
    const glm::dvec3 near_corner(p.normal.x >= 0 ? lo.x : hi.x, p.normal.y >= 0 ? lo.y : hi.y,
                                 p.normal.z >= 0 ? lo.z : hi.z);
    const double slack = 1e-9 * (std::abs(p.offset) + glm::dot(glm::abs(p.normal), glm::abs(lo) + glm::abs(hi)));
    if (glm::dot(p.normal, far_corner) + p.offset < -slack) return Containment::outside;
    if (glm::dot(p.normal, near_corner) + p.offset < slack) result = Containment::crossing;
  }
  return result;
}

glm::dvec3 mesh_min(const MeshRecord& m) { return {m.bounds_min[0], m.bounds_min[1], m.bounds_min[2]}; }
glm::dvec3 mesh_max(const MeshRecord& m) { return {m.bounds_max[0], m.bounds_max[1], m.bounds_max[2]}; }

// What a draw list holds of an instance until its record is written: enough to sort it and to
// build its GpuDraw (draw_record), a fraction of the record's 256 bytes.
struct Drawn {
  const MeshRecord* mesh;  // the level of detail drawn
  glm::dvec3 translation, previous_translation;
  uint32_t instance;
  bool moving;  // drawn by gbuffer.dynamic
};

// The lists' order as two integers compared in turn: (draw class, material), (mesh's first
// index, instance). Each instance is drawn once, so no two keys of a list are equal.
struct DrawKey {
  uint64_t major, minor;
  auto operator<=>(const DrawKey&) const = default;
};

// A draw list's entry: the draw and its place in the list's order.
struct ListedDraw {
  DrawKey key;
  Drawn drawn;
};

struct Candidate {
  Drawn drawn;
  glm::dmat4 model;       // object → camera-relative world, in double
  glm::dvec4 corners[8];  // clip space, of the drawn level's box
  double score;           // occluder quality: squared box size over squared distance
  uint32_t material, lod;
  bool in_frustum;
  bool decal;              // drawn by decals.mesh
  bool occluder_material;  // opaque (not alpha-tested or blended), static and not a decal
};

glm::dvec3 position_of(const InstanceRecord& r) { return {r.position[0], r.position[1], r.position[2]}; }

// Asks for every cache line of the record ahead of its use (a record spans up to three).
void prefetch(const InstanceRecord& r) {
  const char* bytes = reinterpret_cast<const char*>(&r);
  __builtin_prefetch(bytes);
  __builtin_prefetch(bytes + 64);
  __builtin_prefetch(bytes + sizeof(r) - 1);
}

// How many records ahead a walk over scattered instances asks for.
constexpr size_t kPrefetchAhead = 8;

glm::dvec3 node_min(const HierarchyNode& n) { return {n.bounds_min[0], n.bounds_min[1], n.bounds_min[2]}; }
glm::dvec3 node_max(const HierarchyNode& n) { return {n.bounds_max[0], n.bounds_max[1], n.bounds_max[2]}; }

class Culler {
 public:
  explicit Culler(PassContext& ctx)
      : ctx_(ctx),
        camera_(host_records<CameraRecordGpu>(ctx.host("frame.camera")).at(0)),
        instances_(host_view<InstanceRecord>(ctx.host("scene.instances"))),
        meshes_(host_view<MeshRecord>(ctx.host("scene.meshes"))),
        materials_(host_records<GpuMaterial>(ctx.host("scene.materials"))),
        decals_(host_view<DecalRecord>(ctx.host("scene.decals"))),
        geometry_(ctx.host("scene.geometry")),
        hierarchy_(Hierarchy::parse(ctx.host("scene.hierarchy"), instances_.size())),
        keep_outside_(!ctx.flag("frustum")),
        keep_hidden_(!ctx.flag("occlusion")) {
    std::memcpy(&world_[0][0], camera_.world, sizeof(camera_.world));
    eye_ = glm::dvec3(world_[3]);
    if (!(camera_.width > 0 && camera_.height > 0)) throw GraphError("cull.main: frame.camera has no size");
    view_projection_ = reversed_z_projection(camera_.yfov, double(camera_.width) / camera_.height, camera_.znear) *
                       relative_view(world_);
    planes_ = frustum_planes(view_projection_);
    if (geometry_.size() < sizeof(GeometryHeader)) throw GraphError("cull.main: scene.geometry has no header");
    std::memcpy(&geometry_header_, geometry_.data(), sizeof(geometry_header_));
    // The occluders are read from these streams: a corrupt header must not send reads past them.
    uint64_t end = uint64_t(geometry_header_.index_offset) + uint64_t(geometry_header_.index_count) * 4;
    for (uint32_t s = 0; s < vertex_stream_count; ++s)
      end = std::max(end, uint64_t(geometry_header_.stream_offset[s]) +
                              uint64_t(geometry_header_.vertex_count) * kVertexStreamBytes[s]);
    if (end > geometry_.size()) throw GraphError("cull.main: scene.geometry's header points past the buffer");
  }

  void run() {
    choose_occluders();
    rasterise_occluders();
    if (!hierarchy_.static_order.empty()) visit(0, false);
    const std::span<const uint32_t> moving = hierarchy_.moving;
    for (size_t k = 0; k < moving.size(); ++k) {
      // The moving instances' records lie apart in scene.instances: each is asked for a few
      // iterations ahead, so its cache misses overlap the work on the ones before.
      if (k + kPrefetchAhead < moving.size()) prefetch(instances_[moving[k + kPrefetchAhead]]);
      const uint32_t i = moving[k];
      const InstanceRecord& r = instances_[i];
      const glm::dvec3 velocity(r.velocity[0], r.velocity[1], r.velocity[2]);
      const glm::dvec3 translation = position_of(r) + velocity * camera_.time;
      consider(i, translation, translation - velocity * camera_.time_step);
    }
    cull_decals();
    finish();
  }

 private:
  enum class Refusal { none, degenerate, distance };

  // The instance's model matrix: object → camera-relative world, the translation subtracted in
  // double.
  glm::dmat4 relative_model(const InstanceRecord& r, const glm::dvec3& translation) const {
    glm::dmat4 model(1.0);
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) model[c][row] = r.basis[c * 3 + row];
    model[3] = glm::dvec4(translation - eye_, 1.0);
    return model;
  }

  // Fills `c` with the instance as it would be drawn this frame; anything but Refusal::none says
  // why it is not drawn (and leaves `c` partly written). `c` is the caller's so that the ~0.5 kB
  // candidate is neither cleared nor copied for each of the tens of thousands of instances looked at.
  Refusal evaluate(uint32_t index, const glm::dvec3& translation, const glm::dvec3& previous_translation,
                   Candidate& c) const {
    const InstanceRecord& r = instances_[index];
    const glm::dmat4 model = relative_model(r, translation);
    // A zero-scale transform covers no pixel and has no normal matrix.
    const double determinant = glm::determinant(glm::dmat3(model));
    const MeshRecord* mesh = mesh_at(r.primitive, index);
    if (!std::isfinite(determinant) || determinant == 0.0 || mesh->index_count == 0 || r.material >= materials_.size())
      return Refusal::degenerate;
    const double distance = glm::length(box_centre(model, *mesh));
    const LevelOfDetail level = level_of_detail(*mesh, distance, meshes_.size(), "cull.main",
                                                [&](uint32_t coarser) { return mesh_at(coarser, index); });
    if (!level.drawn) return Refusal::distance;
    mesh = level.mesh;
    box_corners(view_projection_ * model, mesh_min(*mesh), mesh_max(*mesh), c.corners);
    c.in_frustum = !outside_frustum(c.corners);
    const GpuMaterial& m = materials_[r.material];
    c.drawn = {mesh, translation, previous_translation, index, (r.flags & kInstanceMoving) != 0};
    c.model = model;
    c.material = r.material;
    c.lod = level.steps;
    c.decal = (int(m.extra.w) & 4) != 0;
    const glm::dvec3 size(mesh->bounds_max[0] - mesh->bounds_min[0], mesh->bounds_max[1] - mesh->bounds_min[1],
                          mesh->bounds_max[2] - mesh->bounds_min[2]);
    const glm::dvec3 diagonal = glm::dmat3(model) * size;
    c.score = glm::dot(diagonal, diagonal) / std::max(distance * distance, 1e-6);
    c.occluder_material = m.extra.z == float(AlphaMode::opaque) && !c.drawn.moving && !c.decal;
    return Refusal::none;
  }

  // A static instance where it stands.
  Refusal evaluate_at_rest(uint32_t index, Candidate& c) const {
    return evaluate(index, position_of(instances_[index]), position_of(instances_[index]), c);
  }

  // The draw record of an instance that is drawn or occludes: matrices, mesh range, material,
  // flags and the box scene.geometry quantised the mesh's positions in (vertex_streams.h).
  GpuDraw draw_record(const Drawn& drawn) const {
    const InstanceRecord& r = instances_[drawn.instance];
    const glm::dmat4 model = relative_model(r, drawn.translation);
    GpuDraw d{};
    d.model = glm::mat4(model);
    glm::dmat4 previous_model = model;
    previous_model[3] = glm::dvec4(drawn.previous_translation - eye_, 1.0);
    d.previous_model = glm::mat4(previous_model);
    d.normal_matrix = glm::mat4(glm::transpose(glm::inverse(glm::dmat3(model))));
    const MeshRecord& mesh = *drawn.mesh;
    d.first_index = mesh.first_index;
    d.index_count = mesh.index_count;
    d.vertex_offset = mesh.vertex_offset;
    d.material = r.material;
    d.stencil = uint32_t(materials_[r.material].textures2.z) | (drawn.moving ? stencil::moving : 0u);
    d.instance = drawn.instance;
    d.mirrored = glm::determinant(glm::dmat3(model)) < 0.0;
    const glm::vec3 lo = glm::make_vec3(mesh.bounds_min), hi = glm::make_vec3(mesh.bounds_max);
    d.position_origin = glm::vec4(lo, 0.0f);
    d.position_step = glm::vec4(position_step(lo, hi), 0.0f);
    return d;
  }

  // The `occluders` best static opaque instances in the frustum by squared size over squared
  // distance, found best-first: a node's bound is its own squared diagonal over its squared
  // distance, which no instance inside it can beat.
  void choose_occluders() {
    const size_t budget = size_t(ctx_.param_int("occluders"));
    if (budget == 0 || hierarchy_.static_order.empty()) return;
    auto bound = [&](uint32_t n) {
      const HierarchyNode& node = hierarchy_.nodes[n];
      const glm::dvec3 lo = node_min(node) - eye_, hi = node_max(node) - eye_;
      const glm::dvec3 nearest = glm::clamp(glm::dvec3(0.0), lo, hi);
      const glm::dvec3 diagonal = hi - lo;
      return glm::dot(diagonal, diagonal) / std::max(glm::dot(nearest, nearest), 1e-6);
    };
    using Entry = std::pair<double, uint32_t>;
    std::priority_queue<Entry> open;  // nodes, best bound first
    // The chosen so far, worst (score, instance) on top, each with its slot in `chosen_`.
    using Chosen = std::tuple<double, uint32_t, size_t>;
    std::priority_queue<Chosen, std::vector<Chosen>, std::greater<Chosen>> best;
    Candidate candidate;
    open.push({bound(0), 0});
    while (!open.empty()) {
      const auto [node_bound, n] = open.top();
      open.pop();
      if (best.size() == budget && node_bound <= std::get<0>(best.top())) break;
      const HierarchyNode& node = hierarchy_.nodes[n];
      if (box_in_frustum(planes_, node_min(node) - eye_, node_max(node) - eye_) == Containment::outside) continue;
      if (node.count == 0) {
        open.push({bound(node.first), node.first});
        open.push({bound(node.first + 1), node.first + 1});
        continue;
      }
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        const uint32_t i = hierarchy_.static_order[k];
        if (evaluate_at_rest(i, candidate) != Refusal::none || !candidate.in_frustum || !candidate.occluder_material)
          continue;
        if (best.size() < budget) {
          best.push({candidate.score, i, chosen_.size()});
          chosen_.push_back(candidate.drawn);
        } else if (candidate.score > std::get<0>(best.top())) {
          const size_t slot = std::get<2>(best.top());
          best.pop();
          chosen_[slot] = candidate.drawn;
          best.push({candidate.score, i, slot});
        }
      }
    }
    std::sort(chosen_.begin(), chosen_.end(), [](const Drawn& a, const Drawn& b) { return a.instance < b.instance; });
    for (const Drawn& d : chosen_) occluders_.push_back(d.instance);
  }

  bool is_occluder(uint32_t instance) const {
    return std::binary_search(occluders_.begin(), occluders_.end(), instance);
  }

  void rasterise_occluders() {
    const uint32_t width = uint32_t(ctx_.param_int("occlusion_width"));
    const uint32_t height = std::max(1u, uint32_t(std::lround(double(width) * camera_.height / camera_.width)));
    buffer_.emplace(width, height);
    for (const Drawn& d : chosen_) {
      rasterise(draw_record(d), *d.mesh);
      stats_.occluders += 1;
      stats_.occluder_triangles += std::min(d.mesh->occluder_index_count, d.mesh->index_count) / 3;
    }
  }

  void rasterise(const GpuDraw& draw, const MeshRecord& mesh) {
    const GpuMaterial& m = materials_[draw.material];
    const bool two_sided = (int(m.extra.w) & 2) != 0;
    // Front faces are counter-clockwise (the passes' declared face), clockwise when mirrored.
    const bool front_ccw = !draw.mirrored;
    // The draw's float model is what the GPU uses; the buffer follows it.
    const glm::dmat4 clip_from_object = view_projection_ * glm::dmat4(draw.model);
    const uint8_t* index_bytes = geometry_.data() + geometry_header_.index_offset;
    const uint32_t indices = std::min(mesh.occluder_index_count, mesh.index_count);
    for (uint32_t t = 0; t + 2 < indices; t += 3) {
      glm::dvec4 clip[3];
      for (int v = 0; v < 3; ++v) {
        uint32_t index;
        std::memcpy(&index, index_bytes + (size_t(mesh.first_index) + t + v) * 4, 4);
        const int64_t vertex = int64_t(index) + mesh.vertex_offset;
        if (vertex < 0 || uint64_t(vertex) >= geometry_header_.vertex_count) return;  // no occlusion from garbage
        clip[v] = clip_from_object * glm::dvec4(vertex_position(uint32_t(vertex), draw), 1.0);
      }
      buffer_->rasterise(clip[0], clip[1], clip[2], front_ccw, two_sided);
    }
  }

  // The position the GPU decodes from the position stream: origin + step · q in float.
  glm::dvec3 vertex_position(uint32_t vertex, const GpuDraw& draw) const {
    uint16_t q[4];
    std::memcpy(q, geometry_.data() + geometry_header_.stream_offset[position_stream] + size_t(vertex) * 8, sizeof(q));
    return {dequantise_position(q[0], draw.position_origin.x, draw.position_step.x),
            dequantise_position(q[1], draw.position_origin.y, draw.position_step.y),
            dequantise_position(q[2], draw.position_origin.z, draw.position_step.z)};
  }

  // Walks the hierarchy: a node outside the frustum or behind the occluders drops every
  // instance under it; below a node wholly inside the frustum no plane is tested again.
  void visit(uint32_t index, bool inside) {
    const HierarchyNode& node = hierarchy_.nodes[index];
    const glm::dvec3 lo = node_min(node) - eye_, hi = node_max(node) - eye_;
    if (!inside) {
      const Containment containment = box_in_frustum(planes_, lo, hi);
      if (containment == Containment::outside) {
        const uint32_t count = leaf_count(index);
        stats_.instances_tested += count;
        stats_.culled_frustum += count;
        if (!keep_outside_) return;
        keep_everything_under(index);
        return;
      }
      inside = containment == Containment::inside;
    }
    if (!keep_hidden_) {
      glm::dvec4 corners[8];
      box_corners(view_projection_, lo, hi, corners);
      if (buffer_->hidden(corners)) {
        const uint32_t count = leaf_count(index);
        stats_.instances_tested += count;
        stats_.culled_occlusion += count;
        return;
      }
    }
    if (node.count > 0) {
      // The leaf's records lie apart in scene.instances: asked for all at once, their cache
      // misses overlap instead of coming one after the other.
      for (uint32_t k = node.first; k < node.first + node.count; ++k) prefetch(instances_[hierarchy_.static_order[k]]);
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        const uint32_t i = hierarchy_.static_order[k];
        consider(i, position_of(instances_[i]), position_of(instances_[i]));
      }
      return;
    }
    visit(node.first, inside);
    visit(node.first + 1, inside);
  }

  // frustum=0: what a culled node held is drawn all the same (already counted as culled).
  void keep_everything_under(uint32_t index) {
    const HierarchyNode& node = hierarchy_.nodes[index];
    if (node.count == 0) {
      keep_everything_under(node.first);
      keep_everything_under(node.first + 1);
      return;
    }
    Candidate c;
    for (uint32_t k = node.first; k < node.first + node.count; ++k)
      if (evaluate_at_rest(hierarchy_.static_order[k], c) == Refusal::none) keep(c);
  }

  uint32_t leaf_count(uint32_t index) const {
    const HierarchyNode& node = hierarchy_.nodes[index];
    if (node.count > 0) return node.count;
    return leaf_count(node.first) + leaf_count(node.first + 1);
  }

  const MeshRecord* mesh_at(uint32_t index, uint32_t instance) const {
    if (index >= meshes_.size())
      throw GraphError("cull.main: instance " + std::to_string(instance) + " names mesh " + std::to_string(index) +
                       " of " + std::to_string(meshes_.size()));
    const MeshRecord& m = meshes_[index];
    if (uint64_t(m.first_index) + m.index_count > geometry_header_.index_count)
      throw GraphError("cull.main: mesh " + std::to_string(index) + " reaches past scene.geometry's indices");
    return &m;
  }

  void consider(uint32_t index, const glm::dvec3& translation, const glm::dvec3& previous_translation) {
    ++stats_.instances_tested;
    Candidate c;
    const Refusal refusal = evaluate(index, translation, previous_translation, c);
    if (refusal != Refusal::none) {
      ++(refusal == Refusal::distance ? stats_.culled_distance : stats_.culled_degenerate);
      return;
    }
    if (!c.in_frustum) {
      ++stats_.culled_frustum;
      if (keep_outside_) keep(c);
      return;
    }
    if (!is_occluder(index) && buffer_->hidden(c.corners)) {
      ++stats_.culled_occlusion;
      if (!keep_hidden_) return;
    } else {
      ++stats_.visible;
      stats_.lod_histogram[std::min<uint32_t>(c.lod, kLodBins - 1)] += 1;
    }
    keep(c);
  }

  // Lists the candidate in the draw lists it is drawn in, with its place in their order.
  void keep(const Candidate& c) {
    const Drawn& drawn = c.drawn;
    const DrawKey key{uint64_t(draw_order_class(materials_[c.material])) << 32 | c.material,
                      uint64_t(drawn.mesh->first_index) << 32 | drawn.instance};
    if (c.decal) {
      // Decals blend: the later one covers the earlier, so their order is the instances' order.
      decal_draws_.push_back({{0, drawn.instance}, drawn});
    } else {
      (drawn.moving ? dynamic_draws_ : gbuffer_draws_).push_back({key, drawn});
    }
    if (!drawn.moving && is_occluder(drawn.instance)) prepass_draws_.push_back({key, drawn});
  }

  // A box is drawn unless it is beyond its draw distance or lies wholly outside the frustum or
  // behind the occluders: a surface point inside a hidden box would be hidden too, so no visible
  // pixel loses its decal. A box of zero or non-finite volume holds no surface point and has no
  // inverse: it is dropped.
  void cull_decals() {
    for (uint32_t i = 0; i < decals_.size(); ++i) {
      const DecalRecord& r = decals_[i];
      glm::dmat4 model;
      std::memcpy(&model[0][0], r.world, sizeof(r.world));
      model[3] -= glm::dvec4(eye_, 0.0);  // camera-relative, subtracted in double
      const double determinant = glm::determinant(glm::dmat3(model));
      if (!std::isfinite(determinant) || determinant == 0.0 || !std::isfinite(glm::dot(model[3], model[3]))) continue;
      if (glm::length(glm::dvec3(model[3])) > r.draw_distance) continue;
      glm::dvec4 corners[8];
      box_corners(view_projection_ * model, glm::dvec3(-0.5), glm::dvec3(0.5), corners);
      if (outside_frustum(corners) && !keep_outside_) continue;
      if (!keep_hidden_ && buffer_->hidden(corners)) continue;
      GpuDecal d{};
      d.model = glm::mat4(model);
      d.local_from_world = glm::mat4(glm::inverse(model));
      d.albedo = glm::vec4(r.albedo[0], r.albedo[1], r.albedo[2], r.opacity);
      d.surface = glm::vec4(r.metallic, r.roughness, r.normal_weight, r.scale);
      d.facing = glm::vec4(glm::vec3(glm::normalize(glm::dvec3(model[2]))), 0.0f);
      d.info = glm::uvec4(r.pattern, i, determinant < 0.0 ? 1u : 0u, 0u);
      projected_.push_back(d);
    }
  }

  void finish() {
    for (std::vector<ListedDraw>* list : {&prepass_draws_, &gbuffer_draws_, &dynamic_draws_, &decal_draws_})
      std::sort(list->begin(), list->end(), [](const ListedDraw& a, const ListedDraw& b) { return a.key < b.key; });
    const ListStats prepass = store_draws("draws.depth.prepass", prepass_draws_);
    const ListStats gbuffer = store_draws("draws.gbuffer.opaque", gbuffer_draws_);
    const ListStats dynamic = store_draws("draws.gbuffer.dynamic", dynamic_draws_);
    store_draws("draws.decals.mesh", decal_draws_);
    ctx_.store<GpuDecal>("draws.decals.projected", projected_);
    stats_.draws_prepass = prepass.batches;
    stats_.draws_gbuffer = gbuffer.batches;
    stats_.draws_dynamic = dynamic.batches;
    stats_.triangles_prepass = prepass.triangles;
    stats_.triangles_gbuffer = gbuffer.triangles;
    stats_.triangles_dynamic = dynamic.triangles;
    stats_.decals_mesh = uint32_t(decal_draws_.size());
    stats_.decals_projected = uint32_t(projected_.size());
    auto& stats = ctx_.output("cull.stats");
    stats.resize(sizeof(stats_));
    std::memcpy(stats.data(), &stats_, sizeof(stats_));
    auto& depth = ctx_.output("cull.occlusion");
    const OcclusionHeader header{buffer_->width(), buffer_->height()};
    depth.resize(sizeof(header) + buffer_->depth().size_bytes());
    std::memcpy(depth.data(), &header, sizeof(header));
    std::memcpy(depth.data() + sizeof(header), buffer_->depth().data(), buffer_->depth().size_bytes());
  }

  struct ListStats {
    uint32_t batches = 0;    // instanced draw calls draw_scene issues for the list
    uint32_t triangles = 0;  // of every draw in it
  };

  // Writes a sorted list's draw records straight into its output, built only now that the list
  // is final.
  ListStats store_draws(const char* resource, const std::vector<ListedDraw>& list) {
    std::vector<uint8_t>& out = ctx_.output(resource);
    out.resize(list.size() * sizeof(GpuDraw));
    ListStats stats;
    GpuDraw previous{};
    for (size_t i = 0; i < list.size(); ++i) {
      const GpuDraw draw = draw_record(list[i].drawn);
      stats.batches += i == 0 || !same_batch(previous, draw);
      stats.triangles += draw.index_count / 3;
      std::memcpy(out.data() + i * sizeof(GpuDraw), &draw, sizeof(draw));
      previous = draw;
    }
    return stats;
  }

  PassContext& ctx_;
  CameraRecordGpu camera_;
  std::span<const InstanceRecord> instances_;
  std::span<const MeshRecord> meshes_;
  std::vector<GpuMaterial> materials_;
  std::span<const DecalRecord> decals_;
  std::span<const uint8_t> geometry_;
  Hierarchy hierarchy_;
  bool keep_outside_, keep_hidden_;
  GeometryHeader geometry_header_{};
  glm::dmat4 world_{1.0}, view_projection_{1.0};
  glm::dvec3 eye_{0.0};
  std::array<Plane, 5> planes_{};
  std::vector<Drawn> chosen_;        // the occluders, as evaluated when they were chosen
  std::vector<uint32_t> occluders_;  // their instance indices, sorted
  // What each list draws: depth.prepass, gbuffer.opaque, gbuffer.dynamic and decals.mesh.
  std::vector<ListedDraw> prepass_draws_, gbuffer_draws_, dynamic_draws_, decal_draws_;
  std::vector<GpuDecal> projected_;  // draws.decals.projected, in scene.decals' order
  std::optional<OcclusionBuffer> buffer_;
  CullStats stats_{};
};

}  // namespace

PassDecl cull_main_pass() {
  return PassDecl("cull.main", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read("scene.geometry", Use::host)
      .read("scene.decals", Use::host)
      .write("draws.depth.prepass", Use::host, BufferDecl{kinds::draw_list})
      .write("draws.gbuffer.opaque", Use::host, BufferDecl{kinds::draw_list})
      .write("draws.gbuffer.dynamic", Use::host, BufferDecl{kinds::draw_list})
      .write("draws.decals.mesh", Use::host, BufferDecl{kinds::draw_list})
      .write("draws.decals.projected", Use::host, BufferDecl{kinds::draw_list})
      .write("cull.stats", Use::host, BufferDecl{kinds::buffer})
      .write("cull.occlusion", Use::host, BufferDecl{kinds::buffer})
      .layout("draws.depth.prepass", draw_schema())
      .layout("draws.gbuffer.opaque", draw_schema())
      .layout("draws.gbuffer.dynamic", draw_schema())
      .layout("draws.decals.mesh", draw_schema())
      .layout("draws.decals.projected", decal_schema())
      .layout("cull.stats", cull_stats_schema())
      .flag("frustum", true, "1: drop instances outside the view frustum")
      .flag("occlusion", true, "1: drop instances hidden behind the occluders")
      .param_int("occluders", 64, 0, 4096,
                 "how many of the largest nearby opaque instances occlude (and depth.prepass draws)")
      .param_int("occlusion_width", 256, 8, 2048,
                 "width of the CPU occlusion buffer in cells (height follows the aspect)")
      .run([](PassContext& ctx) { Culler(ctx).run(); });
}

}  // namespace nightcap
