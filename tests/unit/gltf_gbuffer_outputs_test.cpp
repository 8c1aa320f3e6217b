// gbuffer.normal, gbuffer.motion, gbuffer.material (metalness, roughness), gbuffer.occlusion and
// the unoccluded gbuffer.albedo of the Khronos sample models against the independent reference of
// gltf_reference.h, and KHR_lights_punctual as loaded against the file.
// (Over 600 lines: one case per G-buffer output, sharing the models and the reference.)
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "tests/unit/gltf_reference.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

double angle_degrees(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

glm::dvec3 interpolate(const glm::dvec3 (&v)[3], const glm::dvec3& b) { return b.x * v[0] + b.y * v[1] + b.z * v[2]; }

// World centres of the normal map's hemispheres (texels tilted by more than 30°), one per
// 0.2 m cluster, from the triangles whose UV centroid lands on such a texel.
std::vector<glm::dvec3> bumps(const Reference& ref) {
  std::vector<glm::dvec3> found;
  for (const RefTriangle& t : ref.triangles) {
    const RefMaterial& m = ref.material_of(t);
    if (m.normal_map.image < 0) continue;
    const RefImage& image = ref.image(m.normal_map.image);
    const glm::dvec2 uv =
        (t.uvs[m.normal_map.texcoord][0] + t.uvs[m.normal_map.texcoord][1] + t.uvs[m.normal_map.texcoord][2]) / 3.0;
    const uint8_t* texel = image.texel(wrap(int(uv.x * image.width), image.width, kRepeat),
                                       wrap(int(uv.y * image.height), image.height, kRepeat));
    if (texel[2] > 127.5 * (1.0 + std::cos(glm::radians(30.0)))) continue;
    const glm::dvec3 p = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
    if (std::none_of(found.begin(), found.end(), [&](const glm::dvec3& q) { return glm::length(q - p) < 0.2; }))
      found.push_back(p);
  }
  return found;
}

class GltfGBufferOutputs : public GpuTest {
 protected:
  // Pixels whose normal-map sample lies within this many texels of a texel centre (each axis).
  static constexpr double kTexelCentre = 0.01;
  // A2B10G10R10 0.5n+0.5 rounds each component of n by ≤ 1/1023: √3/1023 rad at most.
  static constexpr double kNormalFormat = 0.097;

  struct NormalStats {
    size_t compared = 0, telling = 0;
    double worst = 0, sum = 0, floor_sum = 0, worst_excess = 0;
    void add(const NormalStats& o) {
      compared += o.compared;
      telling += o.telling;
      worst = std::max(worst, o.worst);
      worst_excess = std::max(worst_excess, o.worst_excess);
      sum += o.sum;
      floor_sum += o.floor_sum;
    }
  };

  // The tangent frame of a triangle without TANGENT, where the specification's MikkTSpace has
  // only one answer: every triangle sharing a corner position with it has the same vertex
  // normals at those corners, the same tangent direction dP/du and the same handedness. Then
  // MikkTSpace's per-corner average is that common tangent, whatever its weights and welding.
  // That is decided on the file's attributes (`file`, the same triangles in the same order); the
  // frame is the face's own as scene.geometry stores its vertices (`ref`), which is what the
  // renderer derives. (Half UVs and 16-bit positions turn a small face's dP/du: by up to 0.23°,
  // median 0.03°, on the 34 faces kept in NormalTangentTest, so neighbours that agree in the
  // file no longer agree exactly as stored.)
  struct FaceFrame {
    bool unambiguous = false;
    glm::dvec3 tangent{0.0};
    double w = 1.0;
  };

  static std::vector<FaceFrame> face_frames(const Reference& file, const Reference& ref) {
    EXPECT_EQ(file.triangles.size(), ref.triangles.size());
    if (file.triangles.size() != ref.triangles.size()) return {};
    const std::vector<FaceFrame> stored = face_frames(ref);
    std::vector<FaceFrame> frames = face_frames(file);
    for (size_t i = 0; i < frames.size(); ++i) {
      frames[i].unambiguous =
          frames[i].unambiguous && stored[i].tangent != glm::dvec3(0.0) && stored[i].w == frames[i].w;
      frames[i].tangent = stored[i].tangent;
    }
    return frames;
  }

  static std::vector<FaceFrame> face_frames(const Reference& ref) {
    std::vector<FaceFrame> frames(ref.triangles.size());
    std::vector<glm::dvec3> dpdu(ref.triangles.size()), dpdv(ref.triangles.size());
    std::map<std::tuple<double, double, double>, std::vector<size_t>> at_position;
    for (size_t i = 0; i < ref.triangles.size(); ++i) {
      const RefTriangle& t = ref.triangles[i];
      const int set = ref.material_of(t).normal_map.texcoord;
      const glm::dvec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0];
      const glm::dvec2 d1 = t.uvs[set][1] - t.uvs[set][0], d2 = t.uvs[set][2] - t.uvs[set][0];
      const double det = d1.x * d2.y - d1.y * d2.x;
      if (std::abs(det) < 1e-14) continue;
      dpdu[i] = (e1 * d2.y - e2 * d1.y) / det;
      dpdv[i] = (e2 * d1.x - e1 * d2.x) / det;
      frames[i].tangent = glm::normalize(dpdu[i]);
      // glTF's bitangent points to −v (the image's "up", +Y of the normal texture): the
      // convention of every TANGENT in NormalTangentMirrorTest, checked in NormalTangentMirror.
      frames[i].w = glm::dot(glm::cross(t.normal, dpdu[i]), dpdv[i]) < 0 ? 1.0 : -1.0;
      for (const glm::dvec3& p : t.p) at_position[{p.x, p.y, p.z}].push_back(i);
    }
    for (size_t i = 0; i < ref.triangles.size(); ++i) {
      const RefTriangle& t = ref.triangles[i];
      if (frames[i].tangent == glm::dvec3(0.0)) continue;
      bool same = true;
      for (int c = 0; c < 3 && same; ++c)
        for (size_t j : at_position[{t.p[c].x, t.p[c].y, t.p[c].z}]) {
          const RefTriangle& o = ref.triangles[j];
          same = same && frames[j].w == frames[i].w && glm::dot(frames[j].tangent, frames[i].tangent) > 1 - 1e-12;
          for (int k = 0; k < 3; ++k)
            same = same && glm::dot(glm::normalize(o.n[k]), glm::normalize(t.n[0])) > 1 - 1e-12;
        }
      frames[i].unambiguous = same;
    }
    return frames;
  }

  // gbuffer.normal at the pixels whose normal-map UV lands within `eps` texels of a texel centre
  // of mip 0 in magnification (λ < −1, clear of LOD approximations).
  static NormalStats compare_normals(const Reference& ref, const View& view, const GBuffer& g,
                                     const std::vector<FaceFrame>* frames) {
    NormalStats s;
    size_t failures = 0;
    for (uint32_t y = 0; y < g.height; ++y)
      for (uint32_t x = 0; x < g.width; ++x) {
        if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
        const PixelRef& p = view.at(x, y);
        const RefTriangle& tri = view.triangle(p);
        const RefMaterial& m = view.material(p);
        if (m.normal_map.image < 0) continue;
        const RefImage& image = ref.image(m.normal_map.image);
        const Footprint f = view.footprint(p.tri, x, y, m.normal_map.texcoord);
        const glm::dvec2 size(image.width, image.height);
        if (std::max(glm::length(f.dx * size), glm::length(f.dy * size)) > 0.5) continue;
        const glm::dvec2 st = f.uv * size - 0.5, centre = glm::round(st);
        if (std::max(std::abs(st.x - centre.x), std::abs(st.y - centre.y)) > kTexelCentre) continue;
        auto decoded = [&](int dx, int dy) {
          const uint8_t* texel = image.texel(wrap(int(centre.x) + dx, image.width, m.normal_map.sampler.wrap_s),
                                             wrap(int(centre.y) + dy, image.height, m.normal_map.sampler.wrap_t));
          return glm::dvec3(texel[0], texel[1], texel[2]) / 255.0 * 2.0 - 1.0;
        };
        glm::dvec3 tn = decoded(0, 0);
        // Off the centre by δ, a filter gives the other texels a total weight ≤ |δx| + |δy|.
        double reach = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) reach = std::max(reach, glm::length(decoded(dx, dy) - tn));
        const double allowance = glm::degrees((std::abs(st.x - centre.x) + std::abs(st.y - centre.y)) * reach /
                                              glm::length(tn) * std::max(1.0, m.normal_map.scale));
        tn.x *= m.normal_map.scale;
        tn.y *= m.normal_map.scale;

        double t;
        glm::dvec3 b;
        const glm::dvec3 d = view.rays.direction(x + 0.5, y + 0.5);
        plane_hit(tri, view.rays.eye, d, t, b);
        const glm::dvec3 n = glm::normalize(interpolate(tri.n, b));
        glm::dvec3 tangent;
        double w;
        if (frames) {
          const FaceFrame& frame = (*frames)[p.tri];
          if (!frame.unambiguous) continue;
          tangent = frame.tangent;
          w = frame.w;
        } else {
          if (tri.tangent[0].w != tri.tangent[1].w || tri.tangent[0].w != tri.tangent[2].w) continue;
          const glm::dvec3 ts[3] = {glm::dvec3(tri.tangent[0]), glm::dvec3(tri.tangent[1]), glm::dvec3(tri.tangent[2])};
          tangent = interpolate(ts, b);
          w = tri.tangent[0].w < 0 ? -1.0 : 1.0;
        }
        // TBN as the specification builds it: bitangent = cross(normal, tangent) · w.
        const glm::dvec3 T = glm::normalize(tangent - n * glm::dot(n, tangent));
        const glm::dvec3 B = glm::cross(n, T) * w;
        glm::dvec3 expected = glm::normalize(T * tn.x + B * tn.y + n * tn.z);
        // A visible back face has its normal reversed (glTF 2.0, 3.9.5 double-sided).
        if (glm::dot(tri.normal, d) > 0) expected = -expected;

        const double error = angle_degrees(g.normal_vector(size_t(y) * g.width + x), expected);
        // The format's floor here: the expected direction rounded to the nearest 10-bit codes.
        const glm::dvec3 rounded = glm::round((expected * 0.5 + 0.5) * 1023.0) / 1023.0 * 2.0 - 1.0;
        ++s.compared;
        s.telling += std::hypot(tn.x, tn.y) > 0.1;
        s.sum += error;
        s.floor_sum += angle_degrees(rounded, expected);
        s.worst = std::max(s.worst, error);
        s.worst_excess = std::max(s.worst_excess, error - allowance);
        if (error > kNormalFormat + allowance && ++failures <= 8)
          ADD_FAILURE() << "normal at (" << x << ", " << y << ") off by " << error << "° (allowed " << kNormalFormat
                        << " + " << allowance << "), map texel " << tn.x << " " << tn.y << " " << tn.z;
      }
    return s;
  }

  // Close-ups (~2.6 pixels per texel) of six of the normal map's hemispheres, three on each side of
  // the model's mirror line, from above and from the side.
  static NormalStats close_ups(GpuDevice& gpu, const std::string& name, bool derived_frames) {
    const std::string path = model_path(name);
    const Scene scene = load_gltf(path);
    const Reference ref(path);
    const std::vector<FaceFrame> frames = face_frames(Reference(path, Attributes::file), ref);
    std::vector<glm::dvec3> targets = bumps(ref);
    std::sort(targets.begin(), targets.end(), [](const glm::dvec3& a, const glm::dvec3& b) { return a.x < b.x; });
    EXPECT_GE(targets.size(), 6u);
    NormalStats total;
    for (size_t k : {size_t(0), size_t(1), size_t(2), targets.size() - 3, targets.size() - 2, targets.size() - 1}) {
      const Camera camera = orbit_camera(k % 2 ? 25.0 : -25.0, 75.0, 0.22, targets[k], 45.0);
      const View view(ref, camera, 512, 512);
      const GBuffer g = render_gbuffer(gpu, scene, camera, 512, 512);
      total.add(compare_normals(ref, view, g, derived_frames ? &frames : nullptr));
    }
    std::printf(
        "%s: %zu pixels within %.2f texel of a texel centre (%zu with the map tilted by > 0.1), worst %.4f° "
        "(worst beyond the filter's reach %.4f°), mean %.4f°; the 10-bit format's own floor there: mean %.4f°\n",
        name.c_str(), total.compared, kTexelCentre, total.telling, total.worst, total.worst_excess,
        total.sum / std::max<size_t>(total.compared, 1), total.floor_sum / std::max<size_t>(total.compared, 1));
    return total;
  }
};

// TANGENT given, with mirrored UVs on one side (w = −1 there).
TEST_F(GltfGBufferOutputs, NormalTangentMirrorTest) {
  // The data's handedness: cross(normal, tangent)·w points to −v at every corner, the convention
  // face_frames() applies to models without TANGENT.
  const Reference ref(model_path("NormalTangentMirrorTest"));
  size_t corners = 0, agreeing = 0;
  for (const RefTriangle& t : ref.triangles) {
    const glm::dvec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0];
    const glm::dvec2 d1 = t.uvs[0][1] - t.uvs[0][0], d2 = t.uvs[0][2] - t.uvs[0][0];
    const double det = d1.x * d2.y - d1.y * d2.x;
    if (std::abs(det) < 1e-14) continue;
    const glm::dvec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
    for (int c = 0; c < 3; ++c, ++corners)
      agreeing += glm::dot(glm::cross(t.n[c], glm::dvec3(t.tangent[c])) * t.tangent[c].w, dpdv) < 0;
  }
  EXPECT_EQ(agreeing, corners);

  // Bound: the format's √3/1023 rad (0.097°) per pixel, plus the filter's reach off the texel
  // centre; on average no more than 0.005° beyond the format's own rounding of the expected
  // direction at the same pixels (which the 8-bit map's directions make larger than the 0.043°
  // of uniformly spread directions).
  const NormalStats s = close_ups(*gpu_, "NormalTangentMirrorTest", false);
  EXPECT_GT(s.telling, 200u);
  EXPECT_LE(s.worst_excess, kNormalFormat);
  EXPECT_LE(s.sum / s.compared, s.floor_sum / s.compared + 0.005);
}

// No TANGENT: the frame glTF asks for (MikkTSpace), where it is unambiguous.
TEST_F(GltfGBufferOutputs, NormalTangentTest) {
  // Bound as in NormalTangentMirrorTest.
  const NormalStats s = close_ups(*gpu_, "NormalTangentTest", true);
  EXPECT_GT(s.telling, 200u);
  EXPECT_LE(s.worst_excess, kNormalFormat);
  EXPECT_LE(s.sum / s.compared, s.floor_sum / s.compared + 0.005);
}

// gbuffer.motion of frame 1 (the camera dollied forward from frame 0's) against the analytic
// reprojection: the point each pixel-centre ray hits, projected with frame 0's camera.
// Bound per component: half an ulp of the R16 half float (2⁻¹¹ relative, 2⁻²⁵ in the subnormal
// range) plus 2⁻¹⁹ for the float evaluation of current − previous uv: both are near 0.5 and
// come from the float camera-relative position through a float matrix and a division, a few
// units of 2⁻²⁴ each. Depth precision only moves the point along its ray, which changes the
// motion by the parallax factor (the dolly over the depth, ~10⁻³) times that error: nothing.
TEST_F(GltfGBufferOutputs, MotionIsAnalyticReprojection) {
  const std::string path = model_path("DamagedHelmet");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const uint32_t w = 256, h = 256;
  const Camera previous = orbit_camera(30.0, 70.0, 2.2, glm::dvec3(0.0), 45.0);
  const GBuffer g = render_gbuffer(*gpu_, scene, previous, w, h, 1);
  // Frame 1 moved the camera along its view axis only.
  const glm::dvec3 moved = glm::dvec3(g.camera.world[3] - previous.world[3]);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(g.camera.world[k], previous.world[k]);
  EXPECT_GT(glm::length(moved), 0.0);
  EXPECT_LT(glm::length(glm::cross(moved, glm::dvec3(previous.world[2]))), 1e-12 * glm::length(moved));

  // Frame 1 is jittered: pixel (x, y) shows what lies at (x + 0.5, y + 0.5) − jitter, and its
  // motion vector is that position's, unjittered.
  ASSERT_NE(g.jitter, glm::dvec2(0.0));
  const View view(ref, g.camera, w, h, g.jitter);
  const Rays before(previous, w, h);
  size_t compared = 0, telling = 0, failures = 0;
  double worst = 0, worst_excess = 0, largest = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
      const glm::dvec2 at(x + 0.5 - g.jitter.x, y + 0.5 - g.jitter.y);
      const glm::dvec3 hit = view.rays.eye + view.rays.direction(at.x, at.y) * view.at(x, y).depth;
      const glm::dvec2 then = before.pixel_of(hit);
      // UV units, current − previous, v down like the image rows.
      const glm::dvec2 expected((at.x - then.x) / w, (at.y - then.y) / h);
      const glm::dvec2 got = g.motion(size_t(y) * w + x);
      ++compared;
      // Far above the bound: a wrong sign or camera would show.
      telling += glm::length(expected) > 1e-4;
      for (int c = 0; c < 2; ++c) {
        const double error = std::abs(got[c] - expected[c]);
        const double half_ulp = std::ldexp(1.0, std::max(std::ilogb(std::abs(expected[c])), -14) - 11);
        worst = std::max(worst, error);
        worst_excess = std::max(worst_excess, error - half_ulp);
        largest = std::max(largest, std::abs(expected[c]));
        if (error > half_ulp + 0x1p-19 && ++failures <= 8)
          ADD_FAILURE() << "motion at (" << x << ", " << y << ")[" << c << "]: " << got[c] << ", expected "
                        << expected[c];
      }
    }
  std::printf("motion: %zu pixels (%zu moving by > 1e-4), largest %.4g; worst error %.3g, %.3g beyond half an ulp\n",
              compared, telling, largest, worst, worst_excess);
  EXPECT_GT(compared, 10000u);
  EXPECT_GT(telling, 5000u);
}

// What a test changes in the Scene and, identically, in the prediction: the metallic and
// roughness factors and the occlusion strength of every material, and the base colour texture
// dropped (the base colour is then the factor, so occlusion is predictable wherever its own
// map is locally constant).
struct MaterialOverride {
  double metallic, roughness, strength;
};

Scene overridden(Scene scene, const MaterialOverride& o) {
  for (Material& m : scene.materials) {
    m.metallic = float(o.metallic);
    m.roughness = float(o.roughness);
    m.occlusion_texture.scale = float(o.strength);
    m.base_color_texture.texture = -1;
  }
  return scene;
}

// Close-up cameras on patches of `map` that are constant over `channels` within the narrowest
// window (3 texels) with a texel `wanted` accepts: texels on a 4-texel grid, placed on the
// surface through a triangle whose UV triangle holds them, one per 5 cm cluster, `count` of
// them spread over the list, each seen along its face normal from `distance`.
std::vector<Camera> patches(const Reference& ref, RefTexture RefMaterial::*map, uint32_t channels,
                            bool (*wanted)(const uint8_t*), size_t count, double distance) {
  std::vector<std::pair<glm::dvec3, glm::dvec3>> found;
  std::set<int> scanned;
  for (const RefMaterial& m : ref.materials()) {
    const RefTexture& texture = m.*map;
    if (texture.image < 0 || !scanned.insert(texture.image).second) continue;
    const RefImage& image = ref.image(texture.image);
    std::vector<glm::dvec2> candidates;
    for (int ty = 0; ty < image.height; ty += 4)
      for (int tx = 0; tx < image.width; tx += 4) {
        const glm::dvec2 uv((tx + 0.5) / image.width, (ty + 0.5) / image.height);
        const Window w = window(image, texture.sampler.wrap_s, texture.sampler.wrap_t, uv, 3.0, false, channels);
        if (w.constant && wanted(image.texel(tx, ty))) candidates.push_back(uv);
      }
    // At most 64 of them, evenly spaced: each costs a pass over the triangles.
    for (size_t k = 0; k < std::min<size_t>(candidates.size(), 64); ++k) {
      const glm::dvec2 uv = candidates[k * candidates.size() / std::min<size_t>(candidates.size(), 64)];
      for (const RefTriangle& t : ref.triangles) {
        if ((ref.material_of(t).*map).image != texture.image) continue;
        const glm::dvec2* v = t.uvs[texture.texcoord];
        const glm::dvec2 e1 = v[1] - v[0], e2 = v[2] - v[0];
        // Repeat wraps: DamagedHelmet's v runs from 1 to 2.
        const glm::dvec2 d = uv + glm::floor(v[0]) - v[0];
        const double det = e1.x * e2.y - e1.y * e2.x;
        if (std::abs(det) < 1e-14) continue;
        const double b1 = (d.x * e2.y - d.y * e2.x) / det, b2 = (e1.x * d.y - e1.y * d.x) / det;
        if (b1 < 0 || b2 < 0 || b1 + b2 > 1) continue;
        const glm::dvec3 p = t.p[0] + b1 * (t.p[1] - t.p[0]) + b2 * (t.p[2] - t.p[0]);
        if (std::none_of(found.begin(), found.end(), [&](const auto& q) { return glm::length(q.first - p) < 0.05; }))
          found.push_back({p, t.normal});
        break;
      }
    }
  }
  std::vector<Camera> cameras;
  for (size_t k = 0; k < count && k < found.size(); ++k) {
    const auto& [p, n] = found[k * found.size() / count];
    const double phi = std::clamp(glm::degrees(std::acos(std::clamp(n.y, -1.0, 1.0))), 10.0, 170.0);
    cameras.push_back(orbit_camera(glm::degrees(std::atan2(n.x, n.z)), phi, distance, p, 45.0));
  }
  return cameras;
}

struct MaterialStats {
  size_t metal_rough = 0;        // pixels whose metalness and roughness are predicted
  size_t textured = 0;           // … of them through the metal-rough texture
  size_t texture_telling = 0;    // … where the factors alone would be off by > 2 codes
  size_t channels_telling = 0;   // … where metalness and roughness differ by > 2 codes
  size_t occlusion = 0;          // pixels whose occlusion is predicted
  size_t occlusion_telling = 0;  // … where no occlusion (1) would be off by > 2 codes
  size_t strength_telling = 0;   // … where strength 1 instead of the material's would be
  double worst_metal = 0, worst_rough = 0, worst_albedo = 0, worst_occlusion = 0;
  void add(const MaterialStats& o) {
    metal_rough += o.metal_rough;
    textured += o.textured;
    texture_telling += o.texture_telling;
    channels_telling += o.channels_telling;
    occlusion += o.occlusion;
    occlusion_telling += o.occlusion_telling;
    strength_telling += o.strength_telling;
    worst_metal = std::max(worst_metal, o.worst_metal);
    worst_rough = std::max(worst_rough, o.worst_rough);
    worst_albedo = std::max(worst_albedo, o.worst_albedo);
    worst_occlusion = std::max(worst_occlusion, o.worst_occlusion);
  }
  void print(const char* what) const {
    std::printf(
        "%s: metal/rough at %zu pixels (%zu through the texture, %zu where the factors alone would be off by > 2 "
        "codes, %zu where swapped channels would be), worst metalness %.3f codes, roughness %.3f codes; occlusion "
        "at %zu pixels (%zu where none would be off by > 2 codes, %zu where strength 1 would be), worst %.3f "
        "codes; worst albedo %.3f codes\n",
        what, metal_rough, textured, texture_telling, channels_telling, worst_metal, worst_rough, occlusion,
        occlusion_telling, strength_telling, worst_occlusion, worst_albedo);
  }
};

// One 8-bit code of gbuffer.material; the albedo tolerance of gltf_gbuffer_test.cpp.
constexpr double kMaterialCodes = 1.0;
constexpr double kAlbedoCodes = 2.0;

// gbuffer.material.rg, gbuffer.occlusion and the unoccluded gbuffer.albedo at every clean pixel where the
// textures involved are locally constant (window() of gltf_reference.h, over the channels the
// shader reads). Non-colour textures are used as stored: no sRGB decode (glTF 2.0, 3.9.3/3.9.4).
MaterialStats compare_material(const Reference& ref, const View& view, const GBuffer& g,
                               const std::optional<MaterialOverride>& o) {
  MaterialStats s;
  size_t failures = 0;
  for (uint32_t y = 0; y < g.height; ++y)
    for (uint32_t x = 0; x < g.width; ++x) {
      if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
      const PixelRef& p = view.at(x, y);
      RefMaterial m = view.material(p);
      if (o) {
        m.metallic = o->metallic;
        m.roughness = o->roughness;
        m.occlusion_map.scale = o->strength;
      }
      const size_t i = size_t(y) * g.width + x;

      // glTF: roughness = roughnessFactor · G, metalness = metallicFactor · B.
      double metal = m.metallic, rough = m.roughness;
      bool predicted = true;
      if (m.metal_rough.image >= 0) {
        const RefImage& image = ref.image(m.metal_rough.image);
        const RefSampler& sampler = m.metal_rough.sampler;
        const Footprint f = view.footprint(p.tri, x, y, m.metal_rough.texcoord);
        // G and B only: R is not read, and JPEG noise in it must not hide constant G and B.
        const Window w =
            window(image, sampler.wrap_s, sampler.wrap_t, f.uv, window_radius(image, sampler, f), false, 0x00ffff00u);
        predicted = w.constant;
        rough *= w.unorm.g;
        metal *= w.unorm.b;
      }
      if (predicted) {
        const double expected_metal = std::clamp(metal, 0.0, 1.0) * 255.0;
        const double expected_rough = std::clamp(rough, 0.0, 1.0) * 255.0;
        const double error_metal = std::abs(g.material[i * 4] - expected_metal);
        const double error_rough = std::abs(g.material[i * 4 + 1] - expected_rough);
        ++s.metal_rough;
        if (m.metal_rough.image >= 0) {
          ++s.textured;
          s.texture_telling +=
              std::max(std::abs(std::clamp(m.metallic, 0.0, 1.0) * 255.0 - expected_metal),
                       std::abs(std::clamp(m.roughness, 0.0, 1.0) * 255.0 - expected_rough)) > 2 * kMaterialCodes;
        }
        s.channels_telling += std::abs(expected_metal - expected_rough) > 2 * kMaterialCodes;
        s.worst_metal = std::max(s.worst_metal, error_metal);
        s.worst_rough = std::max(s.worst_rough, error_rough);
        if (std::max(error_metal, error_rough) > kMaterialCodes && ++failures <= 8)
          ADD_FAILURE() << m.name << " at (" << x << ", " << y << "): metalness " << int(g.material[i * 4])
                        << ", roughness " << int(g.material[i * 4 + 1]) << " codes; predicted " << expected_metal
                        << ", " << expected_rough;
      }

      // gbuffer.occlusion holds 1 + strength · (R − 1), glTF 2.0's occlusionTexture.strength, for
      // lit materials (KHR_materials_unlit ignores it: 1), and the albedo is the base colour
      // alone (occlusion is for indirect light).
      if (m.occlusion_map.image < 0 || m.unlit) continue;
      const RefImage& image = ref.image(m.occlusion_map.image);
      const RefSampler& sampler = m.occlusion_map.sampler;
      const Footprint f = view.footprint(p.tri, x, y, m.occlusion_map.texcoord);
      const Window w =
          window(image, sampler.wrap_s, sampler.wrap_t, f.uv, window_radius(image, sampler, f), false, 0x000000ffu);
      if (!w.constant) continue;
      const double occlusion = std::clamp(1.0 + m.occlusion_map.scale * (w.unorm.r - 1.0), 0.0, 1.0);
      const double expected_code = occlusion * 255.0, got_code = g.occlusion[i];
      ++s.occlusion;
      s.occlusion_telling += std::abs(255.0 - expected_code) > 2 * kMaterialCodes;
      s.strength_telling += std::abs(w.unorm.r * 255.0 - expected_code) > 2 * kMaterialCodes;
      const double error = std::abs(got_code - expected_code);
      s.worst_occlusion = std::max(s.worst_occlusion, error);
      if (error > kMaterialCodes && ++failures <= 8)
        ADD_FAILURE() << m.name << " at (" << x << ", " << y << "): occlusion code " << got_code << ", predicted "
                      << expected_code;
      const auto base = o ? std::optional(m.factor * view.footprint(p.tri, x, y).color) : view.base_color(p.tri, x, y);
      if (!base) continue;
      const glm::dvec3 got = g.albedo_codes(i);
      double albedo_error = 0;
      for (int c = 0; c < 3; ++c)
        albedo_error = std::max(albedo_error, std::abs(got[c] - std::clamp((*base)[c], 0.0, 1.0) * 1023.0));
      s.worst_albedo = std::max(s.worst_albedo, albedo_error);
      if (albedo_error > kAlbedoCodes && ++failures <= 8)
        ADD_FAILURE() << m.name << " at (" << x << ", " << y << "): albedo codes " << got.r << " " << got.g << " "
                      << got.b << ", predicted the base colour " << (*base)[0] * 1023.0 << " " << (*base)[1] * 1023.0
                      << " " << (*base)[2] * 1023.0;
    }
  return s;
}

// gbuffer.material.r (metalness) and .g (roughness) against metallicFactor · B and
// roughnessFactor · G of the metal-rough texture, gbuffer.occlusion against
// 1 + strength · (occlusion R − 1) and gbuffer.albedo against the base colour alone (the
// occlusion is for indirect light: frame.md's deviations), at clean pixels where every texture
// involved is locally constant over the channels the shader reads (the window of
// gltf_gbuffer_test.cpp). Bounds: metalness, roughness and occlusion within one 8-bit code (half a code of UNORM
// rounding; the texel, exact through the 8-bit mip chain of a constant window, times a float factor adds nothing near
// another half); albedo within gltf_gbuffer_test.cpp's 2 ten-bit codes (rounding, lavapipe's cubic sRGB decode of the
// base colour, float products). DamagedHelmet as the file has it (factors 1, strength 1), then with factors 0.6 and
// 0.35, strength 0.5 and no base colour texture, so the products and the strength formula tell: the JPEG base colour is
// practically never constant where the JPEG occlusion is constant and below 1, so with the file's base colour the
// albedo there is only checked where predictable (none or few pixels, not required). Close-ups on patches of the maps
// that are constant. Then EmissiveStrengthTest and UnlitTest, where the factors alone decide (roughness 0.5 and 0.8
// with metalness 0; the defaults 1 and 1).
TEST_F(GltfGBufferOutputs, MetalRoughnessAndOcclusion) {
  const std::string path = model_path("DamagedHelmet");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const MaterialOverride changed{0.6, 0.35, 0.5};
  const Scene changed_scene = overridden(scene, changed);
  const std::vector<Camera> metal_rough = patches(
      ref, &RefMaterial::metal_rough, 0x00ffff00u, [](const uint8_t*) { return true; }, 2, 0.25);
  // Occluded patches: R well below 255 (most of the map's constant patches are 254 or 255).
  // They are small: closer cameras put more pixels on them.
  const std::vector<Camera> occluded = patches(
      ref, &RefMaterial::occlusion_map, 0x000000ffu, [](const uint8_t* t) { return t[0] < 0xf8; }, 3, 0.06);
  EXPECT_EQ(metal_rough.size(), 2u);
  EXPECT_EQ(occluded.size(), 3u);
  MaterialStats as_file, with_override;
  for (const Camera& camera : metal_rough) {
    const View view(ref, camera, 256, 256);
    as_file.add(compare_material(ref, view, render_gbuffer(*gpu_, scene, camera, 256, 256), std::nullopt));
    with_override.add(compare_material(ref, view, render_gbuffer(*gpu_, changed_scene, camera, 256, 256), changed));
  }
  // The file's base colour texture is almost never constant on these patches: the changed
  // scene only.
  for (const Camera& camera : occluded)
    with_override.add(compare_material(ref, View(ref, camera, 256, 256),
                                       render_gbuffer(*gpu_, changed_scene, camera, 256, 256), changed));
  as_file.print("DamagedHelmet");
  with_override.print("DamagedHelmet, factors 0.6 / 0.35, strength 0.5, no base colour texture");

  MaterialStats factors;
  {
    const std::string emissive = model_path("EmissiveStrengthTest");
    const Reference r(emissive);
    const Camera camera = orbit_camera(0.0, 80.0, 12.0, glm::dvec3(0.0), 45.0);
    factors.add(compare_material(r, View(r, camera, 512, 256),
                                 render_gbuffer(*gpu_, load_gltf(emissive), camera, 512, 256), std::nullopt));
  }
  {
    const std::string unlit = model_path("UnlitTest");
    const Reference r(unlit);
    const Camera camera = orbit_camera(20.0, 75.0, 7.0, glm::dvec3(0.0), 45.0);
    factors.add(compare_material(r, View(r, camera, 256, 256),
                                 render_gbuffer(*gpu_, load_gltf(unlit), camera, 256, 256), std::nullopt));
  }
  factors.print("EmissiveStrengthTest and UnlitTest (factors only)");

  for (const MaterialStats* s : {&as_file, &with_override, &factors}) {
    EXPECT_LE(s->worst_metal, kMaterialCodes);
    EXPECT_LE(s->worst_rough, kMaterialCodes);
    EXPECT_LE(s->worst_albedo, kAlbedoCodes);
    EXPECT_LE(s->worst_occlusion, kMaterialCodes);
  }
  EXPECT_GT(as_file.textured, 1000u);
  EXPECT_GT(as_file.texture_telling, 500u);
  EXPECT_GT(as_file.channels_telling, 500u);
  EXPECT_GT(with_override.occlusion_telling, 100u);
  EXPECT_GT(with_override.texture_telling, 500u);
  EXPECT_GT(with_override.strength_telling, 100u);
  EXPECT_GT(factors.metal_rough, 10000u);
  EXPECT_GT(factors.channels_telling, 5000u);
}

// KHR_lights_punctual as load_gltf places it. Bounds: type, range and position exact to 1e-12 m
// (the loader keeps doubles); colour, intensity and cone angles within one float rounding of
// the file's doubles (2⁻²⁴ relative); direction (a float) within 1e-6 rad.
TEST(GltfLights, LightsPunctualLamp) {
  const std::string path = model_path("LightsPunctualLamp");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  ASSERT_EQ(ref.lights.size(), 5u);
  ASSERT_EQ(scene.lights.size(), ref.lights.size());
  const std::map<std::string, LightType> types = {
      {"directional", LightType::directional}, {"point", LightType::point}, {"spot", LightType::spot}};
  auto close = [](double got, double expected) { return std::abs(got - expected) <= 0x1p-24 * std::abs(expected); };
  double worst_position = 0, worst_direction = 0, worst_relative = 0;
  for (size_t i = 0; i < ref.lights.size(); ++i) {
    const RefLight& r = ref.lights[i];
    const Light& l = scene.lights[i];
    EXPECT_EQ(l.type, types.at(r.type)) << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(close(l.color[k], r.color[k])) << "light " << i << " colour " << l.color[k] << " vs " << r.color[k];
      if (r.color[k] != 0) worst_relative = std::max(worst_relative, std::abs(l.color[k] - r.color[k]) / r.color[k]);
    }
    EXPECT_TRUE(close(l.intensity, r.intensity)) << "light " << i << " intensity " << l.intensity;
    worst_relative = std::max(worst_relative, std::abs(l.intensity - r.intensity) / r.intensity);
    EXPECT_EQ(l.range, r.range) << i;
    if (r.type == "spot") {
      EXPECT_TRUE(close(l.inner_cone, r.inner_cone)) << i;
      EXPECT_TRUE(close(l.outer_cone, r.outer_cone)) << i;
    }
    worst_position = std::max(worst_position, glm::length(l.position - r.position));
    worst_direction = std::max(worst_direction, glm::radians(angle_degrees(glm::dvec3(l.direction), r.direction)));
  }
  // The file has point lights only: cone angles are not exercised here.
  EXPECT_TRUE(std::all_of(ref.lights.begin(), ref.lights.end(), [](const RefLight& r) { return r.type == "point"; }));
  std::printf(
      "LightsPunctualLamp: %zu point lights; worst position %.3g m, direction %.3g rad, colour/intensity %.3g "
      "relative\n",
      ref.lights.size(), worst_position, worst_direction, worst_relative);
  EXPECT_LE(worst_position, 1e-12);
  EXPECT_LE(worst_direction, 1e-6);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
