// glTF features reach the G-buffer: the Khronos sample models of shared/data rendered through the
// Renderer, and every pixel whose content a CPU reference can predict without ambiguity compared
// with gbuffer.opaque's outputs.
//
// The reference is independent of the loader and of camera_math.h: it reads the .gltf JSON and
// its buffers itself, decodes the images with OpenImageIO, builds node transforms from the
// matrix or TRS, and casts one ray per pixel centre from the camera's basis vectors (image row 0
// at the top, +Y up). A pixel is predicted ("clean") only when it and its eight neighbours see
// the same surface plane (or all see nothing), so rasterisation rules at edges do not matter;
// alpha-tested surfaces are cut where the predicted alpha is below the cutoff by more than the
// 8-bit mip rounding, and pixels near the cutoff are left out.
//
// Textures are predicted where they are locally constant: every base-level texel within
// 2^(L+1)+1 texels of the sample point (after the sampler's wrap) is equal, where L is one mip
// level above the level the pixel's UV footprint selects. Any mip (box-filtered), bilinear or
// trilinear combination the sampler may produce there is then that texel, whatever the GPU's
// LOD approximation; the 8-bit sRGB round trip of nightcap's mip chain keeps the texel exact.
//
// Stated tolerances:
// - albedo (A2B10G10R10), NEAREST and LINEAR magnification alike: |code − 1023·predicted| ≤ 2.
//   Half a code is rounding to the nearest code; up to 1.22 codes is lavapipe's sRGB decode,
//   a cubic polynomial (Mesa's lp_build_srgb_to_linear, "crappy but just sufficient accuracy")
//   whose largest departure from the sRGB curve, at 8-bit value 218, is 1.22 ten-bit codes;
//   the rest covers float interpolation of vertex colours and bilinear weights.
// - depth (D32): relative 1e-5 (float division z/w, and the float camera-relative transform);
// - emissive (B10G11R11): one unit in the last place (R, G 6-bit mantissas: 2⁻⁶ relative;
//   B 5-bit: 2⁻⁵), since Vulkan lets the conversion round either way (lavapipe truncates);
// - gbuffer.material.a (8-bit log2(1 + luminance)/16): one code.
#include <algorithm>
#include <cmath>
#include <map>

#include "passes/depth/stage.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/view.h"
#include "passes/gbuffer/stage.h"
#include "tests/unit/gltf_reference.h"
#include "tests/unit/recorded_pass.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

class GltfGBuffer : public GpuTest {
 protected:
  static GBuffer render(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height) {
    return render_gbuffer(*gpu_, scene, camera, width, height);
  }

  struct Stats {
    size_t clean = 0, depth_checked = 0, albedo_checked = 0, failures = 0;
    double worst_albedo = 0, worst_depth = 0;
  };

  static constexpr double kAlbedoCodes = 2.0;

  // Depth at every clean pixel, albedo (and its unlit flag) wherever the base colour is
  // predictable; materials with an occlusion map are left out (it darkens the albedo).
  static Stats compare(const View& view, const GBuffer& g) {
    Stats s;
    auto fail = [&](const std::string& what) {
      if (++s.failures <= 8) ADD_FAILURE() << what;
    };
    for (uint32_t y = 0; y < g.height; ++y)
      for (uint32_t x = 0; x < g.width; ++x) {
        if (!view.clean(x, y)) continue;
        ++s.clean;
        const size_t i = size_t(y) * g.width + x;
        const PixelRef& p = view.at(x, y);
        const std::string where = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
        const double expected_depth = p.state == PixelRef::visible ? view.rays.znear / p.depth : 0.0;
        const double depth_error = std::abs(g.depth[i] - expected_depth) / std::max(expected_depth, 1e-30);
        ++s.depth_checked;
        if (p.state == PixelRef::background ? g.depth[i] != 0.0f : depth_error > 1e-5)
          fail(where + ": depth " + std::to_string(g.depth[i]) + ", predicted " + std::to_string(expected_depth));
        if (p.state == PixelRef::visible) s.worst_depth = std::max(s.worst_depth, depth_error);
        if (p.state != PixelRef::visible) continue;
        const RefMaterial& m = view.material(p);
        if (m.occlusion) continue;
        const auto base = view.base_color(p.tri, x, y);
        if (!base) continue;
        ++s.albedo_checked;
        const glm::dvec3 got = g.albedo_codes(i);
        double worst = 0;
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, std::abs(got[c] - std::clamp((*base)[c], 0.0, 1.0) * 1023.0));
        s.worst_albedo = std::max(s.worst_albedo, worst);
        if (worst > kAlbedoCodes)
          fail(where + " (" + m.name + "): albedo codes " + std::to_string(got.r) + " " + std::to_string(got.g) + " " +
               std::to_string(got.b) + ", predicted " + std::to_string((*base)[0] * 1023) + " " +
               std::to_string((*base)[1] * 1023) + " " + std::to_string((*base)[2] * 1023));
        if (g.albedo_alpha(i) != (m.unlit ? 1u : 0u))
          fail(where + " (" + m.name + "): albedo alpha " + std::to_string(g.albedo_alpha(i)));
      }
    EXPECT_EQ(s.failures, 0u);
    return s;
  }

  static void print(const char* what, const Stats& s) {
    std::printf("%s: %zu clean pixels, depth checked %zu (worst rel %.2g), albedo checked %zu (worst %.3f codes)\n",
                what, s.clean, s.depth_checked, s.worst_depth, s.albedo_checked, s.worst_albedo);
  }
};

// (a) BoxTextured: the camera convention, then the texture at every predictable pixel.
TEST_F(GltfGBuffer, BoxTexturedAlbedoIsTheTexel) {
  const std::string path = model_path("BoxTextured");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const uint32_t w = 256, h = 256;
  const Camera camera = orbit_camera(30.0, 60.0, 2.2, glm::dvec3(0.0), 45.0);
  // --orbit's convention (docs/commands/render.md): the eye at target + r·(sin φ sin θ, cos φ, sin φ cos θ).
  const double t = glm::radians(30.0), f = glm::radians(60.0);
  const glm::dvec3 eye = 2.2 * glm::dvec3(std::sin(f) * std::sin(t), std::cos(f), std::sin(f) * std::cos(t));
  EXPECT_LT(glm::length(glm::dvec3(camera.world[3]) - eye), 1e-12);
  EXPECT_LT(glm::length(-glm::dvec3(camera.world[2]) - glm::normalize(-eye)), 1e-12);

  // Known points of the cube through camera_math.h land where the independent rays say.
  const View view(ref, camera, w, h);
  const glm::dmat4 clip_from_relative =
      reversed_z_projection(camera.yfov, double(w) / h, camera.znear) * relative_view(camera.world);
  double worst_px = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p(corner & 1 ? 0.5 : -0.5, corner & 2 ? 0.5 : -0.5, corner & 4 ? 0.5 : -0.5);
    const glm::dvec4 c = clip_from_relative * glm::dvec4(p - eye, 1.0);
    const glm::dvec2 projected((c.x / c.w + 1.0) * 0.5 * w, (c.y / c.w + 1.0) * 0.5 * h);
    worst_px = std::max(worst_px, glm::length(projected - view.rays.pixel_of(p)));
  }
  EXPECT_LT(worst_px, 1e-9);

  const GBuffer g = render(scene, camera, w, h);
  // The centre of each face turned toward the camera: the projected pixel sees that face, at
  // the predicted depth. Top (+Y) lands in the upper half of the image, so Y is not flipped.
  int faces = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      glm::dvec3 centre(0.0), normal(0.0);
      normal[axis] = sign;
      centre[axis] = 0.5 * sign;
      if (glm::dot(normal, eye - centre) <= 0) continue;
      ++faces;
      const glm::dvec4 c = clip_from_relative * glm::dvec4(centre - eye, 1.0);
      const uint32_t px = uint32_t((c.x / c.w + 1.0) * 0.5 * w), py = uint32_t((c.y / c.w + 1.0) * 0.5 * h);
      const PixelRef& p = view.at(px, py);
      ASSERT_EQ(p.state, PixelRef::visible);
      EXPECT_NEAR(glm::dot(view.triangle(p).normal, normal), 1.0, 1e-9) << "face " << axis << sign;
      const float depth = g.depth[size_t(py) * w + px];
      EXPECT_NEAR(depth, camera.znear / p.depth, 1e-5 * depth) << "face " << axis << sign;
      if (axis == 1) {
        EXPECT_LT(py, h / 2) << "the top face should be in the upper half";
      }
    }
  EXPECT_EQ(faces, 3);

  const Stats s = compare(view, g);
  print("BoxTextured", s);
  EXPECT_GT(s.albedo_checked, 2000u);
}

// (b) TextureSettingsTest: every wrap mode where it changes the answer, and NEAREST against
// LINEAR magnification.
TEST_F(GltfGBuffer, TextureSettingsWrapModesAsPredicted) {
  const std::string path = model_path("TextureSettingsTest");
  const Scene scene = load_gltf(path);
  const Reference ref(path);

  // The loader hands the glTF sampler through unchanged.
  for (const RefMaterial& r : ref.materials()) {
    if (r.image < 0) continue;
    const auto m = std::find_if(scene.materials.begin(), scene.materials.end(),
                                [&](const Material& x) { return x.name == r.name; });
    ASSERT_NE(m, scene.materials.end()) << r.name;
    const SamplerDesc& s = m->base_color_texture.sampler;
    auto mode = [](int gl) {
      return gl == kClamp    ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
             : gl == kMirror ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                             : VK_SAMPLER_ADDRESS_MODE_REPEAT;
    };
    EXPECT_EQ(s.wrap_u, mode(r.sampler.wrap_s)) << r.name;
    EXPECT_EQ(s.wrap_v, mode(r.sampler.wrap_t)) << r.name;
    EXPECT_EQ(s.mag_filter, r.sampler.mag == kNearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR) << r.name;
    EXPECT_EQ(s.mipmaps, r.sampler.mipmaps()) << r.name;
  }

  // Two close-ups of the column of wrap-mode quads (world x 0…3, y −5.2…0.9 once the root
  // node's rotation stands the model up), so their texels are about one per pixel.
  const char* wrapped[] = {"TextureMirrorMaterialT", "TextureMirrorMaterialS", "TextureRepeatMaterialT",
                           "TextureClampMaterialT",  "TextureRepeatMaterialS", "TextureClampMaterialS"};
  std::map<std::string, size_t> telling;  // pixels where another wrap mode predicts another colour
  Stats total;
  for (double centre_y : {-3.68, -0.57}) {
    const Camera camera = orbit_camera(0.0, 90.0, 4.1, glm::dvec3(1.53, centre_y, 0.0), 45.0);
    const View view(ref, camera, 256, 256);
    const GBuffer g = render(scene, camera, 256, 256);
    const Stats s = compare(view, g);
    total.clean += s.clean;
    total.depth_checked += s.depth_checked;
    total.albedo_checked += s.albedo_checked;
    total.worst_albedo = std::max(total.worst_albedo, s.worst_albedo);
    total.worst_depth = std::max(total.worst_depth, s.worst_depth);
    for (uint32_t y = 0; y < 256; ++y)
      for (uint32_t x = 0; x < 256; ++x) {
        if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
        const PixelRef& p = view.at(x, y);
        const RefMaterial& m = view.material(p);
        if (std::find(std::begin(wrapped), std::end(wrapped), m.name) == std::end(wrapped)) continue;
        const auto declared = view.base_color(p.tri, x, y);
        if (!declared) continue;
        for (int mode : {kRepeat, kClamp, kMirror}) {
          RefSampler other = m.sampler;
          other.wrap_s = m.name.back() == 'S' ? mode : other.wrap_s;
          other.wrap_t = m.name.back() == 'T' ? mode : other.wrap_t;
          const auto alternative = view.base_color(p.tri, x, y, &other);
          if (alternative && glm::length(glm::dvec3(*alternative - *declared)) > 0.25) {
            ++telling[m.name];
            break;
          }
        }
      }
  }
  print("TextureSettingsTest wrap close-ups", total);
  for (const char* name : wrapped) {
    std::printf("  %s: %zu pixels where another wrap mode would show another colour\n", name, telling[name]);
    EXPECT_GT(telling[name], 100u) << name;
  }
}

TEST_F(GltfGBuffer, TextureSettingsNearestAgainstLinearMagnification) {
  const std::string path = model_path("TextureSettingsTest");
  const Scene linear = load_gltf(path);
  // The model has no NEAREST sampler: the same scene with the quad's magnification filter
  // switched shows the filter reaches the sampler.
  Scene nearest = linear;
  for (Material& m : nearest.materials)
    if (m.name == "TextureRepeatMaterialT") m.base_color_texture.sampler.mag_filter = VK_FILTER_NEAREST;
  const Reference ref(path);
  const RefMaterial& m = ref.materials()[ref.material_index("TextureRepeatMaterialT")];
  const RefImage& image = ref.image(m.image);

  // Close enough to the in-range quad (x 2.15…3.05, y −3.09…−2.19) for ~2 pixels per texel.
  const Camera camera = orbit_camera(0.0, 90.0, 1.0, glm::dvec3(2.6, -2.64, 0.0), 45.0);
  const View view(ref, camera, 256, 256);
  const GBuffer gl = render(linear, camera, 256, 256), gn = render(nearest, camera, 256, 256);

  size_t compared = 0, telling = 0, telling_ok = 0;
  double worst_linear = 0, worst_nearest = 0, worst_lambda = -INFINITY;
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 256; ++x) {
      if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
      const PixelRef& p = view.at(x, y);
      if (view.material(p).name != m.name) continue;
      const Footprint f = view.footprint(p.tri, x, y);
      const glm::dvec2 size(image.width, image.height);
      worst_lambda = std::max(worst_lambda, std::log2(std::max(glm::length(f.dx * size), glm::length(f.dy * size))));
      // NEAREST: the texel containing uv·size; skip samples within 2% of a texel border.
      const glm::dvec2 st = f.uv * size;
      const glm::dvec2 fraction = st - glm::floor(st);
      // LINEAR: four texels around uv·size − ½, decoded to linear before weighting (as Vulkan
      // requires for sRGB formats).
      const glm::dvec2 s2 = st - 0.5;
      const glm::dvec2 i0 = glm::floor(s2), a = s2 - i0;
      glm::dvec4 bilinear(0.0);
      for (int j = 0; j < 4; ++j) {
        const int tx = wrap(int(i0.x) + (j & 1), image.width, m.sampler.wrap_s);
        const int ty = wrap(int(i0.y) + (j >> 1), image.height, m.sampler.wrap_t);
        bilinear += decode(image.texel(tx, ty)) * ((j & 1 ? a.x : 1 - a.x) * (j >> 1 ? a.y : 1 - a.y));
      }
      const size_t i = size_t(y) * 256 + x;
      const glm::dvec3 got_linear = gl.albedo_codes(i), got_nearest = gn.albedo_codes(i);
      double err_linear = 0;
      for (int c = 0; c < 3; ++c) err_linear = std::max(err_linear, std::abs(got_linear[c] - bilinear[c] * 1023));
      worst_linear = std::max(worst_linear, err_linear);
      EXPECT_LE(err_linear, kAlbedoCodes) << "LINEAR at pixel (" << x << ", " << y << ")";
      ++compared;
      if (std::min({fraction.x, fraction.y, 1 - fraction.x, 1 - fraction.y}) < 0.02) continue;
      const glm::dvec4 texel = decode(image.texel(wrap(int(std::floor(st.x)), image.width, m.sampler.wrap_s),
                                                  wrap(int(std::floor(st.y)), image.height, m.sampler.wrap_t)));
      double err_nearest = 0;
      for (int c = 0; c < 3; ++c) err_nearest = std::max(err_nearest, std::abs(got_nearest[c] - texel[c] * 1023));
      worst_nearest = std::max(worst_nearest, err_nearest);
      EXPECT_LE(err_nearest, kAlbedoCodes) << "NEAREST at pixel (" << x << ", " << y << ")";
      if (glm::length(glm::dvec3(texel - bilinear)) > 0.1) {
        ++telling;
        telling_ok += err_nearest <= kAlbedoCodes && err_linear <= kAlbedoCodes;
      }
    }
  std::printf(
      "NEAREST vs LINEAR: %zu pixels (λ ≤ %.2f), %zu where the filters differ by > 0.1, all matching: %s; "
      "worst LINEAR %.2f codes, worst NEAREST %.2f codes\n",
      compared, worst_lambda, telling, telling_ok == telling ? "yes" : "no", worst_linear, worst_nearest);
  EXPECT_LT(worst_lambda, -0.5) << "the close-up must magnify";
  EXPECT_GT(compared, 10000u);
  EXPECT_GT(telling, 200u);
  EXPECT_EQ(telling_ok, telling);
}

// (c) VertexColorTest: COLOR_0 multiplies the base colour.
TEST_F(GltfGBuffer, VertexColorsReachAlbedo) {
  const std::string path = model_path("VertexColorTest");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const Camera camera = orbit_camera(0.0, 90.0, 2.6, glm::dvec3(0.0), 45.0);
  const View view(ref, camera, 256, 256);
  const GBuffer g = render(scene, camera, 256, 256);
  const Stats s = compare(view, g);
  print("VertexColorTest", s);
  // Where ignoring COLOR_0 would give another colour, the G-buffer has the coloured one.
  size_t telling = 0;
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 256; ++x) {
      if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
      const PixelRef& p = view.at(x, y);
      const auto with = view.base_color(p.tri, x, y), without = view.base_color(p.tri, x, y, nullptr, false);
      if (with && without && glm::length(glm::dvec3(*with - *without)) > 0.25) ++telling;
    }
  std::printf("  %zu pixels where COLOR_0 changes the colour by > 0.25\n", telling);
  EXPECT_GT(s.albedo_checked, 3000u);
  EXPECT_GT(telling, 500u);
}

// (d) AlphaBlendModeTest: MASK cuts holes exactly where alpha < cutoff; BLEND is drawn opaque and
// says so in the notes.
TEST_F(GltfGBuffer, AlphaMaskCutsWhereAlphaIsBelowTheCutoff) {
  const std::string path = model_path("AlphaBlendModeTest");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  EXPECT_TRUE(std::any_of(scene.notes.begin(), scene.notes.end(), [](const std::string& n) {
    return n.find("'MatBlend'") != std::string::npos && n.find("BLEND drawn as opaque") != std::string::npos;
  })) << "BLEND not reported in Scene::notes";
  for (const Material& m : scene.materials) {
    if (m.name == "MatCutoff25") {
      EXPECT_EQ(m.alpha_cutoff, 0.25f);
    }
    if (m.name == "MatCutoffDefault") {
      EXPECT_EQ(m.alpha_cutoff, 0.5f);
    }
  }

  // The five test quads (x −3.55…3.55, y 0.1…1.97, z 0) from the front.
  const uint32_t w = 512, h = 256;
  const Camera camera = orbit_camera(0.0, 90.0, 4.5, glm::dvec3(0.0, 1.04, 0.0), 45.0);
  const View view(ref, camera, w, h);
  const GBuffer g = render(scene, camera, w, h);
  const Stats s = compare(view, g);
  print("AlphaBlendModeTest", s);

  std::map<std::string, int> surface_of;
  for (const RefTriangle& t : ref.triangles) surface_of[ref.material_of(t).name] = t.surface;
  std::map<std::string, std::pair<size_t, size_t>> counts;  // holes, covered
  size_t blend_low_alpha = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      if (!view.clean(x, y)) continue;
      const PixelRef& p = view.at(x, y);
      const size_t i = size_t(y) * w + x;
      for (const char* name : {"MatCutoff25", "MatCutoffDefault", "MatCutoff75"}) {
        if (std::count(p.holes.begin(), p.holes.end(), surface_of[name])) {
          // Cut away: the depth is whatever lies behind (compare() checked its value); it is
          // not the quad's plane z = 0.
          ++counts[name].first;
          const double quad_depth = glm::dot(-view.rays.eye, view.rays.forward);
          EXPECT_GT(std::abs(g.depth[i] - camera.znear / quad_depth), 1e-3 * camera.znear / quad_depth)
              << name << " drawn at (" << x << ", " << y << ") where alpha is below the cutoff";
        } else if (p.state == PixelRef::visible && view.material(p).name == name) {
          ++counts[name].second;
        }
      }
      if (p.state == PixelRef::visible && view.material(p).name == "MatBlend") {
        // Drawn as opaque: covered even where its alpha is near zero.
        const Footprint f = view.footprint(p.tri, x, y);
        const RefImage& image = ref.image(view.material(p).image);
        const Window win =
            window(image, kRepeat, kRepeat, f.uv, window_radius(image, view.material(p).sampler, f), true);
        if (win.alpha_max < 0.2) ++blend_low_alpha;
      }
    }
  for (const char* name : {"MatCutoff25", "MatCutoffDefault", "MatCutoff75"}) {
    std::printf("  %s: %zu pixels cut away, %zu covered\n", name, counts[name].first, counts[name].second);
    EXPECT_GT(counts[name].first, 300u) << name;
    EXPECT_GT(counts[name].second, 300u) << name;
  }
  // Higher cutoffs cut more.
  EXPECT_LT(counts["MatCutoff25"].first, counts["MatCutoffDefault"].first);
  EXPECT_LT(counts["MatCutoffDefault"].first, counts["MatCutoff75"].first);
  std::printf("  MatBlend: %zu covered pixels with alpha < 0.2\n", blend_low_alpha);
  EXPECT_GT(blend_low_alpha, 100u);
}

// (e) EmissiveStrengthTest: emissiveFactor × KHR_materials_emissive_strength, beyond 1.
TEST_F(GltfGBuffer, EmissiveStrengthReachesTheEmissiveTarget) {
  const std::string path = model_path("EmissiveStrengthTest");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const uint32_t w = 512, h = 256;
  const Camera camera = orbit_camera(0.0, 80.0, 12.0, glm::dvec3(0.0), 45.0);
  const View view(ref, camera, w, h);
  const GBuffer g = render(scene, camera, w, h);
  const Stats s = compare(view, g);
  print("EmissiveStrengthTest", s);

  std::map<double, size_t> per_strength;
  double brightest = 0, worst_rel = 0;
  int worst_material_code = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      if (!view.clean(x, y) || view.at(x, y).state != PixelRef::visible) continue;
      const RefMaterial& m = view.material(view.at(x, y));
      ASSERT_FALSE(m.emissive_texture);
      const size_t i = size_t(y) * w + x;
      const glm::dvec3 expected = m.emissive * m.strength, got = g.emitted(i);
      for (int c = 0; c < 3; ++c) {
        // One ulp of the packed float: 6 mantissa bits for R and G, 5 for B.
        const double ulp = c < 2 ? std::ldexp(1.0, -6) : std::ldexp(1.0, -5);
        EXPECT_LE(std::abs(got[c] - expected[c]), ulp * expected[c])
            << m.name << " channel " << c << " at (" << x << ", " << y << ")";
        if (expected[c] > 0) worst_rel = std::max(worst_rel, std::abs(got[c] - expected[c]) / expected[c]);
        brightest = std::max(brightest, got[c]);
      }
      const double luminance = glm::dot(expected, glm::dvec3(0.2126, 0.7152, 0.0722));
      const int code = int(std::lround(std::clamp(std::log2(1.0 + luminance) / 16.0, 0.0, 1.0) * 255.0));
      const int got_code = g.material[i * 4 + 3];
      worst_material_code = std::max(worst_material_code, std::abs(got_code - code));
      EXPECT_LE(std::abs(got_code - code), 1) << m.name << " emissive intensity at (" << x << ", " << y << ")";
      if (m.strength > 0 && m.emissive != glm::dvec3(0.0)) ++per_strength[m.strength];
    }
  std::printf("  emissive: worst relative error %.4f, brightest %.2f, worst material.a %d codes;", worst_rel, brightest,
              worst_material_code);
  for (const auto& [strength, count] : per_strength) std::printf(" strength %g: %zu px", strength, count);
  std::printf("\n");
  for (double strength : {1.0, 2.0, 4.0, 8.0, 16.0}) EXPECT_GT(per_strength[strength], 100u) << strength;
  EXPECT_GT(brightest, 14.0);  // 0.9 × 16 in blue
}

// (f) UnlitTest: KHR_materials_unlit sets RT0's 2-bit alpha to 1/3 and keeps the colour.
TEST_F(GltfGBuffer, UnlitFlagInAlbedoAlpha) {
  const std::string path = model_path("UnlitTest");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const Camera camera = orbit_camera(20.0, 75.0, 7.0, glm::dvec3(0.0), 45.0);
  const View view(ref, camera, 256, 256);
  const GBuffer g = render(scene, camera, 256, 256);
  const Stats s = compare(view, g);  // checks alpha == 1 for unlit, 0 otherwise
  print("UnlitTest", s);
  size_t unlit = 0;
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 256; ++x)
      if (view.clean(x, y) && view.at(x, y).state == PixelRef::visible && view.material(view.at(x, y)).unlit) {
        ++unlit;
        EXPECT_EQ(g.albedo_alpha(size_t(y) * 256 + x), 1u);
      }
  EXPECT_GT(unlit, 4000u);
}

// A view is data (GpuView): the prepass and the G-buffer pass draw from whichever view each draw
// names. The frame is rendered from one camera; its recorded inputs are run again with a second
// view appended to frame.views, standing elsewhere and looking another way, and every draw
// naming it. The G-buffer must be what the independent ray cast sees from there, within the
// tolerances above, and hold no motion beyond float rounding (the view does not move).
TEST_F(GltfGBuffer, ADrawFromAnotherViewIsWhatThatViewSees) {
  const std::string path = model_path("BoxTextured");
  const Scene scene = load_gltf(path);
  const Reference ref(path);
  const uint32_t w = 256, h = 256;
  const Camera camera = orbit_camera(30.0, 60.0, 2.2, glm::dvec3(0.0), 45.0);
  const Camera elsewhere = orbit_camera(-130.0, 35.0, 2.8, glm::dvec3(0.1, -0.05, 0.0), 50.0);
  RenderSettings settings;
  settings.width = w;
  settings.height = h;
  settings.camera = camera;
  Renderer renderer(*gpu_, scene, settings);
  const RenderedFrame frame = renderer.render_frame(0, true);

  const GpuView other = perspective_view({.eye = glm::dvec3(elsewhere.world[3]) - glm::dvec3(camera.world[3]),
                                          .orientation = glm::dmat3(elsewhere.world),
                                          .yfov = elsewhere.yfov,
                                          .znear = elsewhere.znear,
                                          .width = w,
                                          .height = h});
  auto with_other_view = [&](std::map<std::string, IsolatedInput> inputs, const std::string& draws) {
    std::vector<GpuView> views = host_records<GpuView>(*inputs.at("frame.views").bytes);
    EXPECT_EQ(views.size(), 1u);
    views.push_back(other);
    inputs["frame.views"] = records_input<GpuView>(views);
    std::vector<GpuDraw> list = host_records<GpuDraw>(*inputs.at(draws).bytes);
    EXPECT_FALSE(list.empty()) << draws;
    for (GpuDraw& d : list) d.view = 1;
    inputs[draws] = records_input<GpuDraw>(list);
    return inputs;
  };
  const IsolatedRun prepass = run(
      depth_prepass_pass(), with_other_view(recorded_pass(frame, "depth.prepass").inputs, "draws.depth.prepass"), w, h);
  auto surfaces = with_other_view(recorded_pass(frame, "gbuffer.opaque").inputs, "draws.gbuffer.opaque");
  surfaces["scene.depth"] = {prepass.output_descs.at("scene.depth"), prepass.outputs.at("scene.depth")};
  const IsolatedRun opaque = run(gbuffer_opaque_pass(), surfaces, w, h);

  GBuffer g;
  g.width = w;
  g.height = h;
  const size_t n = size_t(w) * h;
  auto output = [&](const char* name) {
    VersionData v;
    v.resource = name;
    v.bytes = opaque.outputs.at(name);
    return v;
  };
  g.albedo = as<uint32_t>(output("gbuffer.albedo"), n);
  g.normal = as<uint32_t>(output("gbuffer.normal"), n);
  g.motion_bytes = *opaque.outputs.at("gbuffer.motion");
  g.depth = as<float>(output("scene.depth"), n);
  const Stats s = compare(View(ref, elsewhere, w, h), g);
  print("BoxTextured from another view", s);
  EXPECT_GT(s.albedo_checked, 1500u);
  // The rasteriser's pixel centre against the projected interpolated position: float rounding,
  // far below a pixel.
  size_t drawn = 0;
  double worst_motion_px = 0;
  for (size_t i = 0; i < n; ++i) {
    if (g.depth[i] <= 0.0f) continue;
    ++drawn;
    const glm::dvec2 m = g.motion(i) * glm::dvec2(w, h);
    worst_motion_px = std::max(worst_motion_px, std::max(std::abs(m.x), std::abs(m.y)));
  }
  EXPECT_GT(drawn, n / 10);
  EXPECT_LT(worst_motion_px, 0.05) << "a still view records no motion";
  std::printf("worst motion of the still view: %.3g px\n", worst_motion_px);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
