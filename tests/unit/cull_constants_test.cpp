// cull.main and frame.constants (the two CPU passes at the head of the frame) against references
// computed here in double precision, without camera_math.h for the culling reference:
//
// - cull.main, with its occlusion test off (occlusion=0; tests/unit/map_cull_test.cpp checks
//   occlusion against the rendered G-buffer), keeps exactly the instances whose world-space box
//   has, for each of the five
//   frustum planes (left, right, bottom, top, near; the far plane is at infinity), at least one
//   corner not outside it. The planes are built from the camera's basis vectors and half-angle
//   tangents, not from the projection matrix the pass uses, so a sign or axis mistake in either
//   shows. A box within 1e-9 (relative) of a plane is "marginal" and left out of the
//   comparison: double rounding may put it on either side. No marginal box occurred with the
//   seeds below; the count is printed.
// - Nothing dropped is visible: dense random points inside every dropped box, its corners and
//   the primitive's actual vertices all project outside the view.
// - frame.constants: every matrix equals the double-precision reference rounded to float
//   (bound: half an ulp of the value, 2⁻²⁴·|x|, plus slack for double rounding of near-zero
//   elements), lights are camera-relative (world − eye in double, then rounded), and the first
//   directional light is the sun.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <random>
#include <set>
#include <tuple>

#include "passes/cull/cull_stats.h"
#include "passes/cull/stage.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/constants.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/jitter.h"
#include "passes/frame/occlusion_buffer.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

// std::mt19937's raw sequence is fixed by the standard; the distributions are not.
class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}
  double uniform() { return double(engine_() >> 8) * (1.0 / 16777216.0); }
  double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::mt19937 engine_;
};

struct View {
  Camera camera;
  uint32_t width = 256, height = 256;
};

// Camera-to-world from yaw/pitch/roll, built without camera_math.h or glm::lookAt.
Camera make_camera(glm::dvec3 eye, double yaw, double pitch, double roll, double yfov, double znear) {
  const glm::dvec3 forward(std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw));
  const glm::dvec3 flat_right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
  const glm::dvec3 flat_up = glm::cross(flat_right, forward);
  const glm::dvec3 right = std::cos(roll) * flat_right + std::sin(roll) * flat_up;
  const glm::dvec3 up = glm::cross(right, forward);
  Camera camera;
  camera.world = glm::dmat4(glm::dvec4(right, 0), glm::dvec4(up, 0), glm::dvec4(-forward, 0), glm::dvec4(eye, 1));
  camera.yfov = float(yfov);
  camera.znear = float(znear);
  return camera;
}

// The view volume as five planes in world space, from the camera basis. Signed distances are
// positive inside; "outside" is strictly negative, as in the pass.
struct Frustum {
  glm::dvec3 eye, right, up, forward;
  double tx, ty, znear;

  explicit Frustum(const View& v) {
    const glm::dmat4& w = v.camera.world;
    eye = glm::dvec3(w[3]);
    right = glm::dvec3(w[0]);
    up = glm::dvec3(w[1]);
    forward = -glm::dvec3(w[2]);
    ty = std::tan(double(v.camera.yfov) / 2.0);
    tx = ty * double(v.width) / v.height;
    znear = v.camera.znear;
  }
  // left, right, bottom, top, near
  std::array<double, 5> distances(const glm::dvec3& p) const {
    const glm::dvec3 d = p - eye;
    const double x = glm::dot(d, right), y = glm::dot(d, up), z = glm::dot(d, forward);
    return {x + tx * z, tx * z - x, y + ty * z, ty * z - y, z - znear};
  }
  bool sees(const glm::dvec3& p) const {
    const auto s = distances(p);
    return std::all_of(s.begin(), s.end(), [](double v) { return v >= 0.0; });
  }
};

std::array<glm::dvec3, 8> world_corners(const Scene& scene, const Instance& instance) {
  const Primitive& p = scene.primitives.at(instance.primitive);
  std::array<glm::dvec3, 8> out;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec4 local(c & 1 ? p.bounds_max.x : p.bounds_min.x, c & 2 ? p.bounds_max.y : p.bounds_min.y,
                           c & 4 ? p.bounds_max.z : p.bounds_min.z, 1.0);
    out[c] = glm::dvec3(instance.world * local);
  }
  return out;
}

enum class Verdict { visible, culled, marginal };

Verdict reference_verdict(const Frustum& f, const Scene& scene, const Instance& instance) {
  const auto corners = world_corners(scene, instance);
  double size = 0;
  for (const auto& c : corners) size = std::max(size, glm::length(c - corners[0]));
  const double margin = 1e-9 * std::max({size, glm::length(corners[0] - f.eye), 1.0});
  bool marginal = false;
  for (int plane = 0; plane < 5; ++plane) {
    double best = -INFINITY;
    for (const auto& c : corners) best = std::max(best, f.distances(c)[plane]);
    if (std::abs(best) <= margin)
      marginal = true;
    else if (best < 0)
      return Verdict::culled;
  }
  return marginal ? Verdict::marginal : Verdict::visible;
}

IsolatedInput input(const ImportedData& data) { return IsolatedInput{data.desc, data.bytes}; }

template <typename T>
std::vector<T> records(const std::shared_ptr<const std::vector<uint8_t>>& bytes) {
  EXPECT_TRUE(bytes);
  if (!bytes) return {};
  EXPECT_EQ(bytes->size() % sizeof(T), 0u);
  std::vector<T> out(bytes->size() / sizeof(T));
  if (!out.empty()) std::memcpy(out.data(), bytes->data(), out.size() * sizeof(T));
  return out;
}

// |got − exact| within rounding of `exact` to float, with `slack` for what double rounding in
// the pass may add to elements that should be zero.
::testing::AssertionResult float_of(double got, double exact, double slack = 0.0) {
  const double bound = std::ldexp(std::abs(exact), -24) * (1 + 1e-9) + slack;
  if (std::abs(got - exact) <= bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << got << " vs exact " << exact << " (bound " << bound << ")";
}

class CullMain : public GpuTest {
 protected:
  struct Result {
    std::vector<GpuDraw> prepass, gbuffer;
  };

  static Result cull(const Imports& scene, const View& view) {
    std::map<std::string, IsolatedInput> inputs;
    for (const char* name :
         {"scene.instances", "scene.meshes", "scene.hierarchy", "scene.materials", "scene.geometry", "scene.decals"})
      inputs[name] = input(scene.at(name));
    inputs["frame.camera"] =
        input(camera_import(view.camera, view.camera, view.width, view.height, 0, false).at("frame.camera"));
    const IsolatedRun run_result = run(cull_main_pass(), inputs, view.width, view.height, {{"occlusion", 0.0}});
    return {records<GpuDraw>(run_result.outputs.at("draws.depth.prepass")),
            records<GpuDraw>(run_result.outputs.at("draws.gbuffer.opaque"))};
  }

  struct Tally {
    size_t drawn = 0, culled = 0, marginal = 0, samples = 0;
  };

  // Everything the pass promises about one camera, against the references above.
  static void check(const Scene& scene, const View& view, const Result& result, Tally& tally) {
    const Frustum frustum(view);
    std::set<uint32_t> drawn;
    for (const GpuDraw& d : result.gbuffer) {
      EXPECT_TRUE(drawn.insert(d.instance).second) << "instance " << d.instance << " drawn twice";
      ASSERT_LT(d.instance, scene.instances.size());
      const Instance& instance = scene.instances[d.instance];
      const Primitive& p = scene.primitives[instance.primitive];
      const Material& m = scene.materials[p.material];
      EXPECT_EQ(d.first_index, p.first_index);
      EXPECT_EQ(d.index_count, p.index_count);
      EXPECT_EQ(d.vertex_offset, p.vertex_offset);
      EXPECT_EQ(d.material, p.material);
      EXPECT_EQ(d.stencil, m.stencil_class);
      // The box its positions are quantised in: the primitive's bounds, which hold its vertices.
      EXPECT_EQ(glm::vec3(d.position_origin), p.bounds_min);
      EXPECT_EQ(glm::vec3(d.position_step), position_step(p.bounds_min, p.bounds_max));
      // Camera-relative model: the translation subtracted in double, then rounded.
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) {
          const double exact = c < 3 ? instance.world[c][r] : instance.world[3][r] - frustum.eye[r];
          EXPECT_TRUE(float_of(d.model[c][r], exact)) << "model[" << c << "][" << r << "] of instance " << d.instance;
        }
      const glm::dmat3 normal = glm::transpose(glm::inverse(glm::dmat3(instance.world)));
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_TRUE(float_of(d.normal_matrix[c][r], normal[c][r], 1e-12));
    }
    // Within the seeds' groups (static; ground and emissive; foliage), sorted by material, mesh,
    // then instance, so bindings change least, equal meshes sit together and the order is stable.
    auto group = [&](const GpuDraw& d) {
      const Material& m = scene.materials[d.material];
      if (m.stencil_class == stencil::foliage) return 2;
      return (m.stencil_class & stencil::road) || m.emissive != glm::vec3(0.0f) ? 1 : 0;
    };
    for (size_t i = 1; i < result.gbuffer.size(); ++i) {
      const GpuDraw &a = result.gbuffer[i - 1], &b = result.gbuffer[i];
      EXPECT_LE(std::tuple(group(a), a.material, a.first_index, a.instance),
                std::tuple(group(b), b.material, b.first_index, b.instance))
          << "draws " << i - 1 << " and " << i << " out of order";
    }
    // The prepass list (the occluders) is a subset of the gbuffer list, opaque materials only.
    EXPECT_LE(result.prepass.size(), 64u);
    for (const GpuDraw& d : result.prepass) {
      EXPECT_TRUE(drawn.count(d.instance)) << "prepass instance " << d.instance << " not in the G-buffer list";
      EXPECT_EQ(scene.materials[d.material].alpha_mode, AlphaMode::opaque) << "prepass instance " << d.instance;
    }

    Random random(uint32_t(drawn.size() * 7919 + scene.instances.size()));
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
      const Instance& instance = scene.instances[i];
      const Verdict verdict = reference_verdict(frustum, scene, instance);
      if (verdict == Verdict::marginal) {
        ++tally.marginal;
        continue;
      }
      const bool is_drawn = drawn.count(i) > 0;
      EXPECT_EQ(is_drawn, verdict == Verdict::visible)
          << "instance " << i << (is_drawn ? " drawn although outside" : " dropped although its box reaches into")
          << " the frustum";
      if (verdict == Verdict::visible) ++tally.drawn;
      if (is_drawn) continue;
      ++tally.culled;
      // Independent of the corner rule: nothing of a dropped instance may be in view.
      const Primitive& p = scene.primitives[instance.primitive];
      for (const glm::dvec3& c : world_corners(scene, instance)) EXPECT_FALSE(frustum.sees(c)) << "instance " << i;
      for (int s = 0; s < 256; ++s) {
        const glm::dvec4 local(random.range(p.bounds_min.x, p.bounds_max.x),
                               random.range(p.bounds_min.y, p.bounds_max.y),
                               random.range(p.bounds_min.z, p.bounds_max.z), 1.0);
        ASSERT_FALSE(frustum.sees(glm::dvec3(instance.world * local)))
            << "a point of dropped instance " << i << " is in view";
        ++tally.samples;
      }
      for (uint32_t k = 0; k < p.index_count; ++k) {
        const Vertex& v = scene.vertices[size_t(p.vertex_offset) + scene.indices[p.first_index + k]];
        const glm::dvec3 w(instance.world * glm::dvec4(v.position[0], v.position[1], v.position[2], 1.0));
        ASSERT_FALSE(frustum.sees(w)) << "a vertex of dropped instance " << i << " is in view";
      }
    }
  }
};

TEST_F(CullMain, RandomCamerasMatchTheBruteForceFrustumTest) {
  Scene scene = build_city(11);
  // One alpha-tested material, so the prepass list has something to leave out.
  for (Material& m : scene.materials)
    if (m.name == "roof") m.alpha_mode = AlphaMode::mask;
  const Imports imports = scene_imports(scene);
  Random random(2024);
  const std::pair<uint32_t, uint32_t> sizes[] = {{320, 180}, {256, 256}, {180, 320}, {1000, 100}};
  const double nears[] = {0.05, 0.1, 1.0, 5.0};
  Tally tally;
  size_t empty_views = 0, full_views = 0;
  for (int k = 0; k < 120; ++k) {
    View view;
    const auto [w, h] = sizes[k % 4];
    view.width = w;
    view.height = h;
    const glm::dvec3 eye(random.range(-140, 140), random.range(0.5, 160), random.range(-140, 140));
    double yaw = random.range(0, 2 * M_PI), pitch = glm::radians(random.range(-80, 80));
    if (k % 2) {
      // Every other camera looks at a point of the block, so many views hold many instances.
      const glm::dvec3 target(random.range(-90, 90), random.range(0, 40), random.range(-90, 90));
      const glm::dvec3 d = glm::normalize(target - eye);
      yaw = std::atan2(d.x, -d.z);
      pitch = std::asin(std::clamp(d.y, -0.99, 0.99));
    }
    view.camera = make_camera(eye, yaw, pitch, glm::radians(random.range(-30, 30)), glm::radians(random.range(20, 110)),
                              nears[(k / 4) % 4]);
    const Result result = cull(imports, view);
    const size_t before = tally.drawn;
    check(scene, view, result, tally);
    if (tally.drawn == before) ++empty_views;
    if (result.gbuffer.size() == scene.instances.size()) ++full_views;
    if (HasFatalFailure()) return;
  }
  std::printf(
      "cull.main: 120 cameras, %zu instances each: %zu drawn, %zu culled, %zu marginal, %zu points of "
      "culled boxes sampled, %zu views with nothing, %zu with everything\n",
      scene.instances.size(), tally.drawn, tally.culled, tally.marginal, tally.samples, empty_views, full_views);
  EXPECT_EQ(tally.marginal, 0u);
  // The sample must exercise both outcomes a lot, or it proves little.
  EXPECT_GT(tally.drawn, 1000u);
  EXPECT_GT(tally.culled, 1000u);
}

TEST_F(CullMain, CameraInsideABuildingKeepsThatBuilding) {
  const Scene scene = build_city(11);
  // The tallest box is a building; its centre is inside it.
  uint32_t tallest = 0;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const auto height = [&](uint32_t k) {
      const Primitive& p = scene.primitives[scene.instances[k].primitive];
      return p.bounds_max.y - p.bounds_min.y;
    };
    if (height(i) > height(tallest)) tallest = i;
  }
  const glm::dvec3 centre(scene.instances[tallest].world[3]);
  const Imports imports = scene_imports(scene);
  Tally tally;
  for (int k = 0; k < 8; ++k) {
    View view;
    view.camera = make_camera(centre, k * M_PI / 4, glm::radians(k % 2 ? 60.0 : -10.0), 0.0, glm::radians(70.0), 0.1);
    const Result result = cull(imports, view);
    check(scene, view, result, tally);
    EXPECT_TRUE(std::any_of(result.gbuffer.begin(), result.gbuffer.end(),
                            [&](const GpuDraw& d) { return d.instance == tallest; }))
        << "the building the camera stands in was culled (view " << k << ")";
    if (HasFatalFailure()) return;
  }
  EXPECT_EQ(tally.marginal, 0u);
}

TEST_F(CullMain, EightKilometresOutTheSameInstancesAreDrawn) {
  const Scene near = build_city(5);
  Scene far = near;
  const glm::dvec3 offset(8000.0, 0.0, -8000.0);
  for (Instance& instance : far.instances) instance.world[3] += glm::dvec4(offset, 0.0);
  const Imports near_imports = scene_imports(near), far_imports = scene_imports(far);
  Random random(77);
  Tally tally;
  for (int k = 0; k < 24; ++k) {
    View view;
    const glm::dvec3 eye(random.range(-100, 100), random.range(1, 60), random.range(-100, 100));
    view.camera =
        make_camera(eye, random.range(0, 2 * M_PI), glm::radians(random.range(-40, 40)), 0.0, glm::radians(60.0), 0.1);
    View moved = view;
    moved.camera.world[3] += glm::dvec4(offset, 0.0);
    const Result a = cull(near_imports, view), b = cull(far_imports, moved);
    check(far, moved, b, tally);
    ASSERT_EQ(a.gbuffer.size(), b.gbuffer.size()) << "camera " << k;
    for (size_t i = 0; i < a.gbuffer.size(); ++i) {
      EXPECT_EQ(a.gbuffer[i].instance, b.gbuffer[i].instance);
      // Camera-relative translations of metres: the 8 km cancel in double before rounding.
      for (int r = 0; r < 3; ++r) {
        const double exact = near.instances[a.gbuffer[i].instance].world[3][r] - eye[r];
        EXPECT_TRUE(float_of(b.gbuffer[i].model[3][r], exact, 1e-11));
      }
    }
    if (HasFatalFailure()) return;
  }
  EXPECT_EQ(tally.marginal, 0u);
  EXPECT_GT(tally.drawn, 100u);
}

TEST_F(CullMain, SceneWithoutInstancesGivesEmptyDrawLists) {
  Scene scene = build_city(1);
  scene.instances.clear();
  View view;
  view.camera = *scene.camera;
  const Result result = cull(scene_imports(scene), view);
  EXPECT_TRUE(result.gbuffer.empty());
  EXPECT_TRUE(result.prepass.empty());
}

class FrameConstants : public GpuTest {
 protected:
  struct Result {
    GpuFrameConstants constants{};
    GpuView camera{};
    std::vector<GpuLight> lights;
  };

  static Result build(const Scene& scene, const Camera& camera, const Camera& previous, uint32_t width, uint32_t height,
                      uint32_t frame, bool cut) {
    std::map<std::string, IsolatedInput> inputs;
    inputs["scene.lights"] = input(scene_imports(scene).at("scene.lights"));
    inputs["frame.camera"] = input(camera_import(camera, previous, width, height, frame, cut).at("frame.camera"));
    // An occlusion buffer with no occluder: only the frustum drops lights here.
    ResourceDesc occlusion;
    occlusion.is_buffer = true;
    const OcclusionHeader header{8, 8};
    auto bytes = std::make_shared<std::vector<uint8_t>>(sizeof(header) + 64 * 4, 0);
    std::memcpy(bytes->data(), &header, sizeof(header));
    occlusion.buffer_size = bytes->size();
    inputs["cull.occlusion"] = IsolatedInput{occlusion, bytes};
    const IsolatedRun run_result = run(frame_constants_pass(), inputs, width, height);
    Result r;
    const auto constants = records<GpuFrameConstants>(run_result.outputs.at("frame.constants"));
    EXPECT_EQ(constants.size(), 1u);
    if (!constants.empty()) r.constants = constants[0];
    const auto views = records<GpuView>(run_result.outputs.at("frame.views"));
    EXPECT_EQ(views.size(), 1u) << "frame.views holds the camera alone";
    if (!views.empty()) r.camera = views[0];
    r.lights = records<GpuLight>(run_result.outputs.at("frame.lights"));
    return r;
  }

  static inline uint32_t lights_dropped = 0;  // over every view checked, so a test can ask for some
  // Largest |error| / 2⁻²⁴|exact| seen, for the report.
  static inline double worst_ulps = 0;

  static void expect_matrix(const glm::mat4& got, const glm::dmat4& exact, const char* what) {
    double scale = 0;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) scale = std::max(scale, std::abs(exact[c][r]));
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        EXPECT_TRUE(float_of(got[c][r], exact[c][r], 1e-13 * scale)) << what << "[" << c << "][" << r << "]";
        if (exact[c][r] != 0)
          worst_ulps = std::max(worst_ulps, std::abs(got[c][r] - exact[c][r]) / std::ldexp(std::abs(exact[c][r]), -24));
      }
  }

  static void check(const Scene& scene, const Camera& camera, const Camera& previous, uint32_t width, uint32_t height) {
    const Result r = build(scene, camera, previous, width, height, 7, true);
    const GpuFrameConstants& c = r.constants;
    const GpuView& v = r.camera;
    const glm::dvec3 eye(camera.world[3]);
    // The view only rotates: the transpose of the camera's orthonormal basis.
    glm::dmat4 view(1.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) view[j][i] = camera.world[i][j];
    const double aspect = double(width) / height, f = 1.0 / std::tan(double(camera.yfov) / 2.0);
    // Reversed-Z, infinite far, Vulkan's Y pointing down: y_clip = −f·y_view.
    glm::dmat4 projection(0.0);
    projection[0][0] = f / aspect;
    projection[1][1] = -f;
    projection[2][3] = -1.0;
    projection[3][2] = camera.znear;
    // TAA's jitter of frame 7 (its sequence: TaaJitter in taa_test.cpp) moves what is drawn by
    // that many pixels: NDC spans 2 over the viewport, and w is −z in view space.
    const glm::dvec2 jitter = taa_jitter(7);
    const glm::dmat4 unjittered = projection;
    projection[2][0] = -2.0 * jitter.x / width;
    projection[2][1] = -2.0 * jitter.y / height;
    EXPECT_EQ(v.jitter, glm::vec4(float(jitter.x), float(jitter.y), float(jitter.x / width), float(jitter.y / height)));
    expect_matrix(v.view, view, "view");
    expect_matrix(v.projection, projection, "projection");
    expect_matrix(v.view_projection, projection * view, "view_projection");
    expect_matrix(v.inverse_view_projection, glm::inverse(projection * view), "inverse_view_projection");
    glm::dmat4 previous_view(1.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) previous_view[j][i] = previous.world[i][j];
    const glm::dvec3 moved = eye - glm::dvec3(previous.world[3]);
    expect_matrix(v.previous_view_projection, unjittered * previous_view * glm::translate(glm::dmat4(1.0), moved),
                  "previous_view_projection");
    for (int k = 0; k < 3; ++k) EXPECT_EQ(c.camera_world[k], float(eye[k]));
    EXPECT_EQ(v.eye, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)) << "the camera's view stands at the origin";
    EXPECT_EQ(v.viewport, glm::vec4(float(width), float(height), 1.0f / width, 1.0f / height));
    EXPECT_EQ(v.projection_params, glm::vec4(camera.znear, camera.yfov, float(aspect), 0.0f));
    EXPECT_EQ(c.timing, glm::vec4(float(7 * kFrameSeconds), float(kFrameSeconds), 0.0f, 0.0f));
    EXPECT_EQ(c.counts.y, 7u);
    EXPECT_EQ(c.counts.z, 1u) << "frame 7 was built as a camera cut";

    // The reference light list: every light but the first directional one, in scene order,
    // less the lights whose range box lies wholly outside one plane of the view (they light no
    // visible point: their reach ends at their range).
    View seen;
    seen.camera = camera;
    seen.width = width;
    seen.height = height;
    const Frustum frustum(seen);
    auto lights_nothing_in_view = [&](const Light& l) {
      if (l.type == LightType::directional || !(l.range > 0.0f)) return false;
      const glm::dvec3 lo = glm::min(l.position, l.type == LightType::tube ? l.end : l.position) - double(l.range);
      const glm::dvec3 hi = glm::max(l.position, l.type == LightType::tube ? l.end : l.position) + double(l.range);
      for (int plane = 0; plane < 5; ++plane) {
        double best = -INFINITY;
        for (int k = 0; k < 8; ++k)
          best =
              std::max(best, frustum.distances({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z})[plane]);
        if (best < -1e-9 * glm::length(hi - lo + glm::abs(lo - eye))) return true;
      }
      return false;
    };
    const Light* sun = nullptr;
    std::vector<const Light*> local;
    uint32_t dropped = 0;
    for (const Light& l : scene.lights) {
      if (l.type == LightType::directional && !sun)
        sun = &l;
      else if (lights_nothing_in_view(l))
        ++dropped;
      else
        local.push_back(&l);
    }
    // Grouped by kind, each group in scene order: directional, point and spot, sphere, tube.
    auto group = [](const Light* l) {
      if (l->type == LightType::directional) return 0;
      if (l->type == LightType::tube) return 3;
      return l->type == LightType::point && l->radius > 0 ? 2 : 1;
    };
    std::stable_sort(local.begin(), local.end(), [&](const Light* a, const Light* b) { return group(a) < group(b); });
    for (int k = 1; k < 4; ++k)
      EXPECT_EQ(c.light_groups[k - 1],
                std::find_if(local.begin(), local.end(), [&](const Light* l) { return group(l) >= k; }) - local.begin())
          << "group " << k;
    EXPECT_EQ(c.counts.x, local.size());
    EXPECT_EQ(c.counts.w, dropped);
    lights_dropped += dropped;
    ASSERT_EQ(r.lights.size(), local.size());
    if (sun) {
      const glm::dvec3 d = glm::normalize(glm::dvec3(sun->direction));
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(c.sun_direction[k], d[k], 3e-7);
        EXPECT_EQ(c.sun_radiance[k], sun->color[k] * sun->intensity);
      }
      EXPECT_EQ(c.sun_direction.w, 1.0f);
    } else {
      EXPECT_EQ(c.sun_direction.w, 0.0f) << "a sun without a directional light";
    }
    for (size_t i = 0; i < local.size(); ++i) {
      const Light& l = *local[i];
      const GpuLight& g = r.lights[i];
      EXPECT_EQ(g.position_type.w, float(uint32_t(l.type))) << "light " << i;
      for (int k = 0; k < 3; ++k) {
        // Camera-relative in double, then rounded: exact to the float of the small value.
        EXPECT_TRUE(float_of(g.position_type[k], l.position[k] - eye[k], 1e-11)) << "light " << i << " position";
        EXPECT_TRUE(float_of(g.end_radius[k], l.end[k] - eye[k], 1e-11)) << "light " << i << " end";
        EXPECT_EQ(g.color_range[k], l.color[k] * l.intensity) << "light " << i;
      }
      const glm::dvec3 d = glm::normalize(glm::dvec3(l.direction));
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.direction_cos_outer[k], d[k], 3e-7) << "light " << i;
      EXPECT_EQ(g.end_radius.w, l.radius);
      EXPECT_EQ(g.color_range.w, l.range);
      EXPECT_NEAR(g.direction_cos_outer.w, std::cos(double(l.outer_cone)), 1.2e-7);
      EXPECT_NEAR(g.cos_inner.x, std::cos(double(l.inner_cone)), 1.2e-7);
    }
  }
};

TEST_F(FrameConstants, MatricesAndLightsMatchTheDoubleReference) {
  const Scene scene = build_city(11);
  Random random(99);
  for (int k = 0; k < 16; ++k) {
    const glm::dvec3 eye(random.range(-140, 140), random.range(0.5, 160), random.range(-140, 140));
    const Camera camera =
        make_camera(eye, random.range(0, 2 * M_PI), glm::radians(random.range(-80, 80)),
                    glm::radians(random.range(-30, 30)), glm::radians(random.range(20, 110)), random.range(0.01, 2.0));
    const Camera previous = make_camera(eye + glm::dvec3(random.range(-1, 1), random.range(-1, 1), random.range(-1, 1)),
                                        random.range(0, 2 * M_PI), 0.1, 0.0, camera.yfov, camera.znear);
    check(scene, camera, previous, k % 2 ? 320 : 333, k % 3 ? 180 : 401);
    if (HasFatalFailure()) return;
  }
  std::printf("frame.constants: worst matrix element error %.3f of 2^-24|x|; %u lights dropped\n", worst_ulps,
              lights_dropped);
  EXPECT_GT(lights_dropped, 0u) << "no view dropped a light: the test proves nothing about dropping";
}

TEST_F(FrameConstants, EightKilometresOutLightsStayExactAndTheFirstDirectionalIsTheSun) {
  Scene scene;
  const glm::dvec3 eye(8000.3, 12.7, -7999.6);
  auto light = [&](LightType type, glm::dvec3 offset) {
    Light l;
    l.type = type;
    l.position = eye + offset;
    l.end = eye + offset + glm::dvec3(0.0, 0.25, 0.0);
    l.direction = glm::vec3(0.3f, -1.0f, 0.2f);
    l.color = {0.9f, 0.5f, 0.25f};
    l.intensity = 37.0f;
    l.range = 12.0f;
    l.inner_cone = 0.2f;
    l.outer_cone = 0.6f;
    l.radius = 0.05f;
    scene.lights.push_back(l);
  };
  // Offsets of millimetres to metres: float(world) − float(eye) would be wrong by up to 4.9e-4 m.
  light(LightType::point, {0.001234, -0.5, 3.25});
  light(LightType::directional, {0, 0, 0});
  light(LightType::tube, {-0.0007, 0.0003, 0.0011});
  light(LightType::spot, {12.5, -7.25, 0.004});
  light(LightType::directional, {1, 1, 1});  // the second directional light is an ordinary light
  scene.lights[1].direction = glm::vec3(0.0f, -2.0f, 0.0f);
  scene.lights[1].color = {0.2f, 0.3f, 1.0f};
  const Camera camera = make_camera(eye, 0.3, 0.1, 0.0, glm::radians(60.0), 0.1);
  check(scene, camera, camera, 320, 180);

  const Result r = build(scene, camera, camera, 320, 180, 7, false);
  double worst = 0, naive = 0;
  // frame.lights, grouped by kind: the second directional light, the spot, the point (a sphere:
  // its radius is 0.05 m), the tube.
  const size_t scene_index[4] = {4, 3, 0, 2};
  for (size_t i = 0; i < r.lights.size(); ++i) {
    const Light& l = scene.lights[scene_index[i]];
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, std::abs(r.lights[i].position_type[k] - (l.position[k] - eye[k])));
      naive = std::max(naive, std::abs(double(float(l.position[k]) - float(eye[k])) - (l.position[k] - eye[k])));
    }
  }
  EXPECT_EQ(r.constants.sun_direction, glm::vec4(0.0f, -1.0f, 0.0f, 1.0f));
  EXPECT_EQ(r.lights.size(), 4u);
  EXPECT_EQ(r.lights.front().position_type.w, float(uint32_t(LightType::directional)));
  EXPECT_EQ(r.lights.back().position_type.w, float(uint32_t(LightType::tube)));
  std::printf("8 km: worst light position error %.3g m (float-first subtraction: %.3g m)\n", worst, naive);
  EXPECT_LT(worst, 1e-6);
}

TEST_F(FrameConstants, NoDirectionalLightMeansNoSun) {
  Scene scene;
  Light lamp;
  lamp.position = {1, 2, 3};
  scene.lights.push_back(lamp);
  const Camera camera = make_camera({0, 1, 0}, 0.0, 0.0, 0.0, 1.0, 0.1);
  check(scene, camera, camera, 64, 64);
  Scene dark;
  check(dark, camera, camera, 64, 64);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
