// The decal passes against CPU references (tests/reference/decal_reference.h).
//
// decals.projected, coverage: in a scene of axis-aligned boxes every pixel centre is ray-cast in
// double precision; the pass must change gbuffer.albedo exactly where the true surface point lies
// inside the decal box and is not on the moving box. Mismatches are allowed only (a) where the
// true point lies within ε of a box face: ε = footprint/256 + 2⁻²⁰·d, the footprint being the
// pixel's on the surface (d·pixel angle / cos incidence): the rasteriser snaps vertices to 1/256
// pixel, and the depth the pass reconstructs from is a float taken through float matrices (a few
// 2⁻²⁴ relative); and (b) on silhouette pixels, whose 4-neighbours see another box, where that
// snapping may pick the other surface.
//
// decals.projected, reconstructed position: a decal whose albedo is its local coordinate + 0.5
// must hold, on every covered pixel away from faces and silhouettes, the ray-cast point's local
// coordinate within one 10-bit code plus ε/size per channel (ε as above; Vulkan lets a float be
// stored as either of the two nearest UNORM codes, and blending with a = 1 is exact).
//
// decals.mesh, blend: on a slab coplanar with a wall (the depth bias must let it win everywhere)
// and on one tilted over the ground, every pixel well inside a slab's face holds
// a·decal + (1 − a)·surface in gbuffer.albedo rgb and gbuffer.material rgb (translucency toward
// the decal's 0; within one code:
// rounding to the target's code plus the blender's float), normalize((1 − a)·n_copy + a·n_decal)
// in gbuffer.normal with n_copy read from the recorded decals.normal_copy (within 0.1°: the
// 10-bit encoding's own error is at most 0.097°, shared/design/accuracy.md), and every pixel
// well outside both slabs keeps all three targets bit for bit. RT0's and RT1's 2-bit alpha flags
// and RT2's alpha (emissive) are kept everywhere.
//
// Empty lists: with decals in the scene but none in view, both passes run and leave every target
// bit for bit.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>

#include "passes/assembly/renderer.h"
#include "passes/cull/cull_stats.h"
#include "passes/frame/gpu_types.h"
#include "tests/reference/decal_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kWidth = 320, kHeight = 180;

// The version of `resource` a pass started from and the one it wrote.
struct Around {
  const std::vector<uint8_t>* before = nullptr;
  const std::vector<uint8_t>* after = nullptr;
};

Around around(const RenderedFrame& frame, const std::string& pass, const std::string& resource) {
  Around a;
  const std::vector<uint8_t>* last = nullptr;  // the latest version written before `pass`
  for (size_t i = 0; i < frame.graph.passes.size(); ++i) {
    const std::vector<uint8_t>* written = nullptr;
    for (int v : frame.execution.passes[i].outputs)
      if (frame.execution.versions[v].resource == resource && frame.execution.versions[v].bytes)
        written = frame.execution.versions[v].bytes.get();
    if (frame.graph.passes[i].decl->name == pass) {
      EXPECT_TRUE(frame.graph.passes[i].runs) << pass << ": " << frame.graph.passes[i].reason;
      a.before = last;
      a.after = written;
    }
    if (written) last = written;
  }
  if (!a.before || !a.after) throw std::runtime_error(pass + " did not read and write " + resource);
  return a;
}

uint32_t word_at(const std::vector<uint8_t>& bytes, size_t texel) {
  uint32_t w;
  std::memcpy(&w, bytes.data() + 4 * texel, 4);
  return w;
}

// A2B10G10R10: channel c (0 r, 1 g, 2 b) as its 10-bit code, 3 the 2-bit alpha.
uint32_t code(uint32_t word, int c) { return c == 3 ? word >> 30 : (word >> (10 * c)) & 1023; }

glm::dvec3 decode_normal(uint32_t word) {
  return glm::dvec3(code(word, 0), code(word, 1), code(word, 2)) / 1023.0 * 2.0 - 1.0;
}

double angle_degrees(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

// Frame 0 of a still camera; the renderer owns the declarations the frame's graph points at.
struct Rendered {
  std::unique_ptr<Renderer> renderer;
  RenderedFrame frame;
};

Rendered render(GpuDevice& gpu, const Scene& scene) {
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.path.motion = CameraPath::Motion::still;
  Rendered r{std::make_unique<Renderer>(gpu, scene, settings), {}};
  r.frame = r.renderer->render_frame(0, true);
  return r;
}

// How far the surface a pixel shows may lie from the ray-cast point: the rasteriser snaps vertices
// to 1/256 of a pixel (lavapipe: 8 sub-pixel bits), which moves the surface under a pixel centre
// by up to 1/256 of the pixel's footprint on it (wider at grazing incidence), plus the float
// depth and matrices' few 2⁻²⁴ relative (bounded here by 2⁻²⁰·d).
double epsilon(const reference::RayHit& hit) {
  const double pixel_angle = 2.0 * std::tan(glm::radians(60.0) / 2) / kHeight;
  return pixel_angle * hit.distance / std::max(hit.cos_incidence, 1e-3) / 256.0 + std::ldexp(hit.distance, -20);
}

struct Cast {
  std::vector<std::optional<reference::RayHit>> hits;
  bool silhouette(uint32_t x, uint32_t y) const {
    const int box = hits[y * kWidth + x] ? hits[y * kWidth + x]->box : -1;
    const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int nx = int(x) + dx[k], ny = int(y) + dy[k];
      if (nx < 0 || ny < 0 || nx >= int(kWidth) || ny >= int(kHeight)) continue;
      const auto& n = hits[size_t(ny) * kWidth + nx];
      if ((n ? n->box : -1) != box) return true;
    }
    return false;
  }
};

Cast cast_all(const reference::DecalTestScene& s, const Camera& camera) {
  Cast c;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) c.hits.push_back(reference::cast_pixel(s, camera, kWidth, kHeight, x, y));
  return c;
}

class DecalsProjected : public GpuTest {};

TEST_F(DecalsProjected, CoverageIsTheBoxVolumeLessMovingPixels) {
  reference::DecalTestScene s = reference::decal_test_scene();
  Decal decal;
  decal.world = reference::decal_test_box();
  decal.albedo = {1.0f, 0.0f, 0.0f};
  s.scene.decals.push_back(decal);
  const Rendered rendered = render(*gpu_, s.scene);
  const RenderedFrame& frame = rendered.frame;
  const Around albedo = around(frame, "decals.projected", "gbuffer.albedo");
  const Cast cast = cast_all(s, frame.camera);
  size_t covered = 0, moving_in_box = 0, at_faces = 0, at_silhouettes = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      const auto& hit = cast.hits[i];
      const bool inside = hit && glm::all(glm::lessThanEqual(
                                     glm::abs(reference::decal_local(decal.world, hit->position)), glm::dvec3(0.5)));
      const bool expected = inside && !hit->moving;
      const bool changed = word_at(*albedo.before, i) != word_at(*albedo.after, i);
      covered += expected;
      moving_in_box += inside && hit->moving;
      if (changed == expected) continue;
      if (hit && reference::distance_to_faces(decal.world, hit->position) <= epsilon(*hit)) {
        ++at_faces;
        continue;
      }
      if (cast.silhouette(x, y)) {
        ++at_silhouettes;
        continue;
      }
      ADD_FAILURE() << "pixel " << x << "," << y << (expected ? " not covered" : " covered wrongly");
    }
  EXPECT_GT(covered, 1000u);
  EXPECT_GT(moving_in_box, 200u) << "the moving box must cross the decal";
  std::printf(
      "decals.projected coverage: %zu pixels covered, %zu moving pixels inside the box left alone; "
      "mismatches %zu within eps of a face, %zu on silhouettes\n",
      covered, moving_in_box, at_faces, at_silhouettes);
}

TEST_F(DecalsProjected, ReconstructedPositionMatchesTheRayCastOne) {
  reference::DecalTestScene s = reference::decal_test_scene();
  Decal decal;
  decal.world = reference::decal_test_box();
  decal.pattern = DecalPattern::coordinates;
  s.scene.decals.push_back(decal);
  const Rendered rendered = render(*gpu_, s.scene);
  const RenderedFrame& frame = rendered.frame;
  const Around albedo = around(frame, "decals.projected", "gbuffer.albedo");
  const Cast cast = cast_all(s, frame.camera);
  const glm::dvec3 size(glm::length(decal.world[0]), glm::length(decal.world[1]), glm::length(decal.world[2]));
  size_t checked = 0;
  double worst_codes = 0.0, worst_ratio = 0.0, worst_metres = 0.0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      const auto& hit = cast.hits[i];
      if (!hit || hit->moving || cast.silhouette(x, y)) continue;
      const glm::dvec3 local = reference::decal_local(decal.world, hit->position);
      const double eps = epsilon(*hit);
      if (!glm::all(glm::lessThanEqual(glm::abs(local), glm::dvec3(0.5))) ||
          reference::distance_to_faces(decal.world, hit->position) <= eps)
        continue;
      const uint32_t word = word_at(*albedo.after, i);
      for (int c = 0; c < 3; ++c) {
        const double got = code(word, c) / 1023.0, expected = local[c] + 0.5;
        const double bound = 1.0 / 1023.0 + eps / size[c] + 1e-9;
        worst_codes = std::max(worst_codes, std::abs(got - expected) * 1023.0);
        worst_ratio = std::max(worst_ratio, std::abs(got - expected) / bound);
        worst_metres = std::max(worst_metres, std::abs(got - expected) * size[c]);
        ASSERT_LE(std::abs(got - expected), bound) << "pixel " << x << "," << y << " channel " << c;
      }
      ++checked;
    }
  EXPECT_GT(checked, 1000u);
  std::printf(
      "decals.projected position: %zu pixels, max |RT0 - CPU| %.3f codes (bound 1 code + eps/size), "
      "%.3f of the bound; %.2f mm in box coordinates (quantisation included)\n",
      checked, worst_codes, worst_ratio, worst_metres * 1e3);
}

class DecalsMesh : public GpuTest {};

struct Slab {
  glm::dmat4 world;
  glm::dvec3 half;
  int face_axis;  // the face the camera sees: local +axis
};

// Where the ray through pixel (x, y) crosses the slab's visible face, in the face's local
// coordinates (metres), or nothing if it crosses behind the camera.
std::optional<glm::dvec2> on_face(const Slab& slab, const Camera& camera, uint32_t x, uint32_t y, double* distance) {
  const reference::Ray ray = reference::pixel_ray(camera, kWidth, kHeight, x, y);
  const glm::dmat4 inverse = glm::inverse(slab.world);
  const glm::dvec3 o(inverse * glm::dvec4(ray.origin, 1.0)), d(inverse * glm::dvec4(ray.direction, 0.0));
  const int k = slab.face_axis;
  const double t = (slab.half[k] - o[k]) / d[k];
  if (!(t > 0.0)) return std::nullopt;
  const glm::dvec3 p = o + d * t;
  *distance = t;
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  return glm::dvec2(p[u], p[v]);
}

TEST_F(DecalsMesh, CustomBlendMatchesTheCpuFormulaAndFlagsSurvive) {
  reference::DecalTestScene s = reference::decal_test_scene();
  Scene& scene = s.scene;
  scene.materials[scene.material_of(scene.instances[0])].unlit = true;  // the ground: RT0 flag 1
  scene_kit::Builder build(scene);
  Material paint = scene_kit::plain("decal.paint", {0.9f, 0.2f, 0.1f}, 0.3f, 0.2f, stencil::plain);
  paint.base_color.a = 0.6f;
  paint.decal = true;
  const uint32_t material = build.material(paint);
  const float a = paint.base_color.a;
  // Coplanar with the static box's +z face (z = 1), and tilted 25° above the ground.
  const std::vector<Slab> slabs = {
      {glm::translate(glm::dmat4(1.0), {2.2, 1.0, 0.995}), {0.4, 0.4, 0.005}, 2},
      {glm::rotate(glm::translate(glm::dmat4(1.0), {-2.0, 0.3, 2.0}), glm::radians(25.0), glm::dvec3(1, 0, 0)),
       {0.5, 0.005, 0.5},
       1}};
  for (const Slab& slab : slabs) {
    Instance& i = build.place(build.box(glm::vec3(slab.half), material, 1.0f, true, true), {0, 0, 0});
    i.world = slab.world;
  }
  const Rendered rendered = render(*gpu_, scene);
  const RenderedFrame& frame = rendered.frame;
  const Around albedo = around(frame, "decals.mesh", "gbuffer.albedo");
  const Around normal = around(frame, "decals.mesh", "gbuffer.normal");
  const Around mat = around(frame, "decals.mesh", "gbuffer.material");
  const auto& copy = *frame.execution.final_version("decals.normal_copy")->bytes;
  EXPECT_EQ(copy, *normal.before) << "the copy is exact";
  const double pixel_angle = 2.0 * std::tan(double(frame.camera.yfov) / 2) / kHeight;
  size_t inside = 0, outside = 0;
  double worst_angle = 0.0, worst_albedo = 0.0, worst_material = 0.0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      const uint32_t a0 = word_at(*albedo.before, i), a1 = word_at(*albedo.after, i);
      const uint32_t n0 = word_at(*normal.before, i), n1 = word_at(*normal.after, i);
      uint8_t m0[4], m1[4];
      std::memcpy(m0, mat.before->data() + 4 * i, 4);
      std::memcpy(m1, mat.after->data() + 4 * i, 4);
      ASSERT_EQ(code(a0, 3), code(a1, 3)) << "RT0 flags at " << x << "," << y;
      ASSERT_EQ(code(n0, 3), code(n1, 3)) << "RT1 flag at " << x << "," << y;
      ASSERT_EQ(m0[3], m1[3]) << "emissive at " << x << "," << y;
      // Inside: three pixels' footprint (and 2 cm) in from a slab face's edges; outside: as far
      // out from every slab, its sides included.
      const Slab* in = nullptr;
      bool near = false;
      for (const Slab& slab : slabs) {
        double distance = 0.0;
        const auto uv = on_face(slab, frame.camera, x, y, &distance);
        if (!uv) continue;
        const double margin = 3.0 * pixel_angle * distance + 0.02;
        const double hu = slab.half[(slab.face_axis + 1) % 3], hv = slab.half[(slab.face_axis + 2) % 3];
        if (std::abs(uv->x) < hu - margin && std::abs(uv->y) < hv - margin) in = &slab;
        if (std::abs(uv->x) < hu + margin && std::abs(uv->y) < hv + margin) near = true;
      }
      const int where = in ? 1 : near ? 0 : -1;
      if (where == -1) {
        ++outside;
        ASSERT_EQ(a0, a1) << "albedo changed outside the decals at " << x << "," << y;
        ASSERT_EQ(n0, n1) << "normal changed outside the decals at " << x << "," << y;
        ASSERT_EQ(std::memcmp(m0, m1, 4), 0) << "material changed outside the decals at " << x << "," << y;
        continue;
      }
      if (where == 0) continue;
      ++inside;
      const glm::dvec3 decal_normal = glm::normalize(glm::dmat3(in->world)[in->face_axis]);
      const glm::dvec3 blended = (1.0 - a) * decode_normal(word_at(copy, i)) + double(a) * decal_normal;
      const double angle = angle_degrees(decode_normal(n1), glm::normalize(blended));
      worst_angle = std::max(worst_angle, angle);
      ASSERT_LE(angle, 0.1) << "normal at " << x << "," << y;
      const glm::dvec3 colour(paint.base_color);
      for (int c = 0; c < 3; ++c) {
        const double expected = a * colour[c] + (1.0 - a) * code(a0, c) / 1023.0;
        const double error = std::abs(code(a1, c) - expected * 1023.0);
        worst_albedo = std::max(worst_albedo, error);
        ASSERT_LE(error, 1.0) << "albedo at " << x << "," << y << " channel " << c;
      }
      const double surface[3] = {paint.metallic, paint.roughness, 0.0};
      for (int c = 0; c < 3; ++c) {
        const double expected = a * surface[c] + (1.0 - a) * m0[c] / 255.0;
        const double error = std::abs(m1[c] - expected * 255.0);
        worst_material = std::max(worst_material, error);
        ASSERT_LE(error, 1.0) << "material at " << x << "," << y << " channel " << c;
      }
    }
  EXPECT_GT(inside, 150u);
  EXPECT_GT(outside, 20000u);
  std::printf(
      "decals.mesh: %zu pixels inside the slabs, %zu outside untouched; worst normal %.4f deg (bound 0.1), "
      "albedo %.3f codes, material %.3f codes (bound 1)\n",
      inside, outside, worst_angle, worst_albedo, worst_material);
}

class Decals : public GpuTest {};

// Decals in the scene but none in view: cull.main leaves both lists empty, so the executor skips
// both passes ("inputs all cleared") and decals.normal_copy with decals.mesh, and the G-buffer
// is bit for bit the one of the scene without decals.
TEST_F(Decals, NoneInViewSkipsBothPassesAndLeavesTheGBufferBitForBit) {
  reference::DecalTestScene s = reference::decal_test_scene();
  const Rendered without = render(*gpu_, s.scene);
  Scene& scene = s.scene;
  scene_kit::Builder build(scene);
  Material paint = scene_kit::plain("decal.paint", {0.9f, 0.2f, 0.1f}, 0.3f, 0.2f, stencil::plain);
  paint.decal = true;
  // Both behind the camera (which stands at z = 8 looking toward -z).
  build.place(build.box({0.5f, 0.5f, 0.005f}, build.material(paint), 1.0f), {0.0, 1.0, 20.0});
  Decal decal;
  decal.world = glm::translate(glm::dmat4(1.0), {0.0, 0.0, 20.0});
  scene.decals.push_back(decal);
  const Rendered rendered = render(*gpu_, scene);
  const RenderedFrame& frame = rendered.frame;
  for (const CompiledPass& pass : frame.graph.passes) {
    const std::string& name = pass.decl->name;
    if (name == "decals.mesh" || name == "decals.projected") {
      EXPECT_FALSE(pass.runs) << name;
      EXPECT_EQ(pass.reason, "inputs all cleared (draws." + name + ")");
    }
    if (name == "decals.normal_copy") {
      EXPECT_FALSE(pass.runs);
      EXPECT_FALSE(pass.inputs_known) << "a replay has nothing to check: its output is cleared, not the copy";
      EXPECT_EQ(pass.reason,
                "inputs all cleared (draws.decals.mesh); its outputs left cleared: every pass that reads them skips "
                "too");
    }
  }
  const auto& copy = *frame.execution.final_version("decals.normal_copy")->bytes;
  EXPECT_TRUE(std::all_of(copy.begin(), copy.end(), [](uint8_t b) { return b == 0; }))
      << "decals.normal_copy is not its declared clear value";
  for (const char* target : {"gbuffer.albedo", "gbuffer.normal", "gbuffer.material", "scene.depth"})
    EXPECT_EQ(*frame.execution.final_version(target)->bytes, *without.frame.execution.final_version(target)->bytes)
        << target;
  CullStats stats{};
  std::memcpy(&stats, frame.execution.final_version("cull.stats")->bytes->data(), sizeof(stats));
  EXPECT_EQ(stats.decals_mesh, 0u);
  EXPECT_EQ(stats.decals_projected, 0u);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
