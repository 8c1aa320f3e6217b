// ShadowCuller's casters: the static ones across the sun from a map's areas, the static ones
// through the hierarchy and the moving ones, each culled by the cascade's volume, the view's
// occluders, the sun's and the time of day; which stale units are redrawn within the budget;
// and the level of detail and box an instance is drawn with.
#include "passes/shadow/shadow_culler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

#include "passes/frame/level_of_detail.h"
#include "passes/shadow/caster_draw.h"

namespace nightcap::shadow_cull {

std::vector<LightRect> ShadowCuller::level_changes(const std::array<Cascade, kShadowCascades>& cascades) {
  glm::dmat4 previous_world;
  std::memcpy(&previous_world[0][0], camera_.previous_world, sizeof(camera_.previous_world));
  const dvec3 previous_eye(previous_world[3]);
  std::vector<LightRect> maps;
  for (const Cascade& c : cascades) maps.push_back(c.map.whole());
  std::vector<LightRect> changed;
  visit_static_across_sun(hierarchy_, axes_, maps, [&](uint32_t index) {
    const glm::dmat4 model = model_of(index, eye_, camera_.time);
    const MeshRecord* now = drawn_mesh(index, model);
    const MeshRecord* then = drawn_mesh(index, model_of(index, previous_eye, camera_.time - camera_.time_step));
    if (now == then) return;
    ++stats_.level_changes;
    LightRect r;
    for (const MeshRecord* mesh : {now, then}) {
      if (!mesh) continue;
      const Box box = box_of(model, *mesh);
      const LightRect across = across_sun(axes_, box.min + eye_, box.max + eye_);
      r.grow(across.lo);
      r.grow(across.hi);
    }
    changed.push_back(r);
  });
  return changed;
}

bool ShadowCuller::keeps_static(uint32_t index, const Box& box, const MeshRecord& mesh, uint32_t k, bool first) {
  const uint32_t triangles = mesh.index_count / 3;
  if (first) ++stats_.casters_tested[k];
  if (light_occluders_.hides(box)) {
    if (first) ++stats_.casters_light_hidden[k];
    stats_.light_hidden_triangles[k] += triangles;
    if (culling_) return false;
  }
  if (!tod_visible_.empty() && !(tod_visible_[index] & tod_bits_)) {
    if (first) ++stats_.casters_tod_dropped[k];
    stats_.tod_triangles_saved[k] += triangles;
    return false;
  }
  return true;
}

void ShadowCuller::whole_layers(const std::array<Cascade, kShadowCascades>& cascades,
                                std::array<std::vector<GpuDraw>, kShadowCascades>& statics) {
  std::vector<LightRect> maps;
  for (const Cascade& c : cascades) maps.push_back(c.map.whole());
  visit_static_across_sun(hierarchy_, axes_, maps, [&](uint32_t index) {
    Box box;
    const MeshRecord* mesh = nullptr;
    if (!world_box(index, box, &mesh, eye_, camera_.time)) return;
    const LightRect across = across_sun(axes_, box.min + eye_, box.max + eye_);
    for (uint32_t k = 0; k < kShadowCascades; ++k)
      if (across.meets(maps[k]) && keeps_static(index, box, *mesh, k, true))
        statics[k].push_back(draw_of(index, *mesh));
  });
}

ShadowCuller::Refresh ShadowCuller::refresh(const std::array<Cascade, kShadowCascades>& cascades,
                                            const std::array<uint64_t, kShadowCascades>& stale,
                                            const std::array<uint64_t, kShadowCascades>& partial,
                                            const std::array<uint64_t, kShadowCascades>& needed) {
  const uint32_t per_cascade = cascades[0].map.tiles * cascades[0].map.tiles;
  // Rectangles to gather casters for, with the unit they are scheduled in (a tile, or both
  // strips of cascade k: kCascadeUnits + k) and their draws' list.
  struct Area {
    uint32_t unit;
    std::vector<GpuDraw>* list;
    LightRect rect;
  };
  units_.assign(kCascadeUnits, {});
  strips_ = {};
  std::vector<Area> areas;
  // The needed strips, the needed tiles, then the others; tiles longest waiting first.
  std::vector<uint32_t> order[3];
  for (uint32_t k = 0; k < kShadowCascades; ++k) {
    const TiledMap& map = cascades[k].map;
    if (partial[k]) {
      const UncoveredStrips strips = uncovered_strips(map.resolution, cascades[k].shift);
      order[(partial[k] & needed[k]) ? 0 : 2].push_back(kCascadeUnits + k);
      if (!strips.columns.empty()) areas.push_back({kCascadeUnits + k, &strips_[k][0], map.texels(strips.columns)});
      if (!strips.rows.empty()) areas.push_back({kCascadeUnits + k, &strips_[k][1], map.texels(strips.rows)});
    }
    for (uint32_t t = 0; t < per_cascade; ++t)
      if ((stale[k] & ~partial[k]) >> t & 1u) {
        order[(needed[k] >> t & 1u) ? 1 : 2].push_back(k * per_cascade + t);
        areas.push_back({k * per_cascade + t, &units_[k * per_cascade + t], map.tile(t)});
      }
  }
  for (std::vector<uint32_t>& units : order)
    std::stable_sort(units.begin(), units.end(), [&](uint32_t a, uint32_t b) {
      return (a < kCascadeUnits ? stats_.unit_waiting[a] : 0) > (b < kCascadeUnits ? stats_.unit_waiting[b] : 0);
    });
  std::vector<uint32_t> triangles_of(kCascadeUnits + kShadowCascades, 0);
  auto cascade_of = [&](uint32_t unit) { return unit >= kCascadeUnits ? unit - kCascadeUnits : unit / per_cascade; };
  std::vector<LightRect> rects;
  for (const Area& a : areas) rects.push_back(a.rect);
  visit_static_across_sun(hierarchy_, axes_, rects, [&](uint32_t index) {
    Box box;
    const MeshRecord* mesh = nullptr;
    if (!world_box(index, box, &mesh, eye_, camera_.time)) return;
    const LightRect across = across_sun(axes_, box.min + eye_, box.max + eye_);
    uint32_t met = 0;  // cascades whose areas it meets
    std::optional<GpuDraw> draw;
    for (const Area& a : areas) {
      if (!across.meets(a.rect)) continue;
      const uint32_t k = cascade_of(a.unit);
      const bool first = !(met >> k & 1u);
      met |= 1u << k;
      if (!keeps_static(index, box, *mesh, k, first)) continue;
      if (!draw) draw = draw_of(index, *mesh);
      a.list->push_back(*draw);
      triangles_of[a.unit] += mesh->index_count / 3;
    }
  });
  Refresh done;
  uint64_t filled = 0;
  bool any = false;
  for (const std::vector<uint32_t>& units : order)
    for (uint32_t unit : units) {
      const uint32_t k = cascade_of(unit), triangles = triangles_of[unit];
      if (unit < kCascadeUnits)
        stats_.unit_triangles[unit] = triangles;
      else
        stats_.strip_triangles[k] = triangles;
      if (any && filled + triangles > stats_.budget_triangles) {
        ++stats_.pending;
        continue;
      }
      any = true;
      filled += triangles;
      if (triangles > stats_.budget_triangles) stats_.over_budget = 1;
      if (unit >= kCascadeUnits) {
        done.strips |= 1u << k;
        for (uint32_t axis = 0; axis < 2; ++axis) {
          sort_for_batching(strips_[k][axis]);
          stats_.strip_draws[2 * k + axis] = uint32_t(strips_[k][axis].size());
        }
      } else {
        done.tiles[k] |= uint64_t(1) << (unit % per_cascade);
        sort_for_batching(units_[unit]);
        stats_.unit_draws[unit] = uint32_t(units_[unit].size());
      }
    }
  stats_.static_triangles = uint32_t(filled);
  return done;
}

glm::dmat4 ShadowCuller::model_of(uint32_t index, const dvec3& eye, double time) const {
  glm::dmat4 model = instance_model(instances_[index], time);
  model[3] -= glm::dvec4(eye, 0.0);
  return model;
}

const MeshRecord* ShadowCuller::mesh_at(uint32_t index) const {
  if (index >= meshes_.size()) throw GraphError("shadow.cull: an instance names mesh " + std::to_string(index));
  return &meshes_[index];
}

const MeshRecord* ShadowCuller::drawn_mesh(uint32_t index, const glm::dmat4& model) const {
  const InstanceRecord& r = instances_[index];
  if (r.material >= materials_.size()) return nullptr;
  const GpuMaterial& m = materials_[r.material];
  if (!casts_shadow(m)) return nullptr;
  const double determinant = glm::determinant(glm::dmat3(model));
  const MeshRecord* mesh = mesh_at(r.primitive);
  if (!std::isfinite(determinant) || determinant == 0.0 || mesh->index_count == 0) return nullptr;
  const LevelOfDetail level = level_of_detail(*mesh, glm::length(box_centre(model, *mesh)), meshes_.size(),
                                              "shadow.cull", [&](uint32_t coarser) { return mesh_at(coarser); });
  return level.drawn ? level.mesh : nullptr;
}

bool ShadowCuller::world_box(uint32_t index, Box& box, const MeshRecord** drawn, const dvec3& eye, double time) const {
  const glm::dmat4 model = model_of(index, eye, time);
  const MeshRecord* mesh = drawn_mesh(index, model);
  if (!mesh) return false;
  box = box_of(model, *mesh);
  if (drawn) *drawn = mesh;
  return true;
}

Box ShadowCuller::box_of(const glm::dmat4& model, const MeshRecord& mesh) {
  Box box{dvec3(INFINITY), dvec3(-INFINITY)};
  for (int k = 0; k < 8; ++k) {
    const dvec3 p(model * glm::dvec4(k & 1 ? mesh.bounds_max[0] : mesh.bounds_min[0],
                                     k & 2 ? mesh.bounds_max[1] : mesh.bounds_min[1],
                                     k & 4 ? mesh.bounds_max[2] : mesh.bounds_min[2], 1.0));
    box.min = glm::min(box.min, p);
    box.max = glm::max(box.max, p);
  }
  return box;
}

bool ShadowCuller::shadow_hidden(const Box& box, double far, double margin, double depth_margin) const {
  double nearest = INFINITY;
  for (int k = 0; k < 8; ++k)
    nearest = std::min(nearest, glm::dot(dvec3(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                                               k & 4 ? box.max.z : box.min.z),
                                         travel_));
  // No receiver lies past the cascade's far light depth, nor below the scene's lowest point.
  const double to_bottom = (box.max.y - bottom_) / -travel_.y;
  const dvec3 sweep = travel_ * std::max(0.0, std::min(far - nearest, to_bottom));
  const dvec3 back = -travel_ * depth_margin;
  const dvec3 lo = glm::min(glm::min(box.min, box.min + sweep), box.min + back) - margin;
  const dvec3 hi = glm::max(glm::max(box.max, box.max + sweep), box.max + back) + margin;
  glm::dvec4 corners[8];
  for (int k = 0; k < 8; ++k)
    corners[k] = view_projection_ * glm::dvec4(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z, 1.0);
  return occlusion_.hidden(corners);
}

void ShadowCuller::casters(const Cascade& c, uint32_t cascade, bool statics, std::vector<GpuDraw>& out) {
  const double far = c.far_light - glm::dot(eye_, travel_);
  auto consider = [&](uint32_t i) {
    Box box;
    const MeshRecord* mesh = nullptr;
    if (!world_box(i, box, &mesh, eye_, camera_.time)) return;
    ++stats_.casters_tested[cascade];
    if (c.volume.excludes(box.min, box.max)) {
      ++stats_.casters_culled[cascade];
      if (culling_) return;
    } else if (shadow_hidden(box, far, c.margin, c.depth_margin)) {
      ++stats_.casters_hidden[cascade];
      if (culling_) return;
    } else if (light_occluders_.hides(box)) {
      ++stats_.casters_light_hidden[cascade];
      stats_.light_hidden_triangles[cascade] += mesh->index_count / 3;
      if (culling_) return;
    }
    if (!tod_visible_.empty() && !(tod_visible_[i] & tod_bits_)) {
      ++stats_.casters_tod_dropped[cascade];
      stats_.tod_triangles_saved[cascade] += mesh->index_count / 3;
      return;
    }
    out.push_back(draw_of(i, *mesh));
  };
  if (!statics) {
    for (uint32_t i : hierarchy_.moving) consider(i);
    return;
  }
  std::vector<uint32_t> stack;
  if (!hierarchy_.static_order.empty()) stack.push_back(0);
  while (!stack.empty()) {
    const HierarchyNode& node = hierarchy_.nodes[stack.back()];
    stack.pop_back();
    const dvec3 lo = dvec3(node.bounds_min[0], node.bounds_min[1], node.bounds_min[2]) - eye_;
    const dvec3 hi = dvec3(node.bounds_max[0], node.bounds_max[1], node.bounds_max[2]) - eye_;
    if (culling_ && c.volume.excludes(lo, hi)) {
      const uint32_t count = leaf_count(node);
      stats_.casters_tested[cascade] += count;
      stats_.casters_culled[cascade] += count;
      continue;
    }
    if (culling_ && shadow_hidden({lo, hi}, far, c.margin, c.depth_margin)) {
      const uint32_t count = leaf_count(node);
      stats_.casters_tested[cascade] += count;
      stats_.casters_hidden[cascade] += count;
      continue;
    }
    if (node.count > 0) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) consider(hierarchy_.static_order[k]);
    } else {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
    }
  }
}

uint32_t ShadowCuller::leaf_count(const HierarchyNode& node) const {
  if (node.count > 0) return node.count;
  return leaf_count(hierarchy_.nodes[node.first]) + leaf_count(hierarchy_.nodes[node.first + 1]);
}

GpuDraw ShadowCuller::draw_of(uint32_t index, const MeshRecord& mesh) const {
  return caster_draw(index, instances_[index], model_of(index, eye_, camera_.time), mesh);
}

}  // namespace nightcap::shadow_cull
