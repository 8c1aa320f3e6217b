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
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "passes/core/format.h"
#include "passes/frame/camera_math.h"
#include "passes/frame/renderer.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {

using nlohmann::json;

std::string model_path(const std::string& name) {
  return std::string(NIGHTCAP_SHARED_DATA) + "/gltf/" + name + "/glTF/" + name + ".gltf";
}

// ---------------------------------------------------------------------------------------------
// The reference glTF reader.

constexpr int kNearest = 9728, kLinear = 9729;
constexpr int kRepeat = 10497, kClamp = 33071, kMirror = 33648;

struct RefSampler {
  int mag = kLinear, min = -1, wrap_s = kRepeat, wrap_t = kRepeat;
  bool mipmaps() const { return min != kNearest && min != kLinear; }
};

struct RefImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
  const uint8_t* texel(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

struct RefMaterial {
  std::string name = "default";
  glm::dvec4 factor{1.0};
  int image = -1;
  RefSampler sampler;
  int texcoord = 0;
  std::string alpha_mode = "OPAQUE";
  double cutoff = 0.5;
  glm::dvec3 emissive{0.0};
  double strength = 1.0;
  bool unlit = false, double_sided = false, occlusion = false, emissive_texture = false;
};

struct RefTriangle {
  glm::dvec3 p[3];
  glm::dvec2 uv[3];  // the base colour texture's set
  glm::dvec4 color[3];
  int material = -1;  // -1: the default material
  int surface = 0;    // one per (node, primitive)
  glm::dvec3 normal;  // unit, from the winding
  double offset = 0;  // plane: dot(normal, x) = offset
};

double srgb_decode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

std::vector<uint8_t> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

RefImage read_image(const std::filesystem::path& file) {
  auto input = OIIO::ImageInput::open(file.string());
  if (!input) throw std::runtime_error("cannot open image " + file.string());
  const OIIO::ImageSpec& spec = input->spec();
  const int n = spec.nchannels;
  std::vector<uint8_t> pixels(size_t(spec.width) * spec.height * n);
  if (!input->read_image(0, 0, 0, n, OIIO::TypeDesc::UINT8, pixels.data()))
    throw std::runtime_error("cannot decode image " + file.string());
  RefImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgba.resize(size_t(spec.width) * spec.height * 4);
  for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i) {
    const uint8_t* p = &pixels[i * n];
    uint8_t* q = &image.rgba[i * 4];
    for (int c = 0; c < 3; ++c) q[c] = n >= 3 ? p[c] : p[0];
    q[3] = n == 4 ? p[3] : n == 2 ? p[1] : 255;
  }
  return image;
}

class Reference {
 public:
  explicit Reference(const std::string& path) {
    folder_ = std::filesystem::path(path).parent_path();
    std::ifstream in(path);
    doc_ = json::parse(in);
    for (const json& b : doc_["buffers"]) buffers_.push_back(read_bytes(folder_ / b["uri"].get<std::string>()));
    for (const json& m : doc_.value("materials", json::array())) materials_.push_back(material(m));
    for (const json& node : doc_["scenes"][doc_.value("scene", 0)]["nodes"]) visit(node.get<int>(), glm::dmat4(1.0));
  }

  const RefMaterial& material_of(const RefTriangle& t) const {
    return t.material < 0 ? default_ : materials_[t.material];
  }
  const RefImage& image(int index) const { return images_.at(index); }
  const std::vector<RefMaterial>& materials() const { return materials_; }
  int material_index(const std::string& name) const {
    for (size_t i = 0; i < materials_.size(); ++i)
      if (materials_[i].name == name) return int(i);
    throw std::runtime_error("no material " + name);
  }

  std::vector<RefTriangle> triangles;

 private:
  RefMaterial material(const json& m) {
    RefMaterial r;
    r.name = m.value("name", "");
    const json pbr = m.value("pbrMetallicRoughness", json::object());
    if (pbr.contains("baseColorFactor"))
      for (int k = 0; k < 4; ++k) r.factor[k] = pbr["baseColorFactor"][k].get<double>();
    if (pbr.contains("baseColorTexture")) {
      const json& ref = pbr["baseColorTexture"];
      const json& texture = doc_["textures"][ref["index"].get<int>()];
      r.image = texture["source"].get<int>();
      if (!images_.count(r.image))
        images_[r.image] = read_image(folder_ / doc_["images"][r.image]["uri"].get<std::string>());
      if (texture.contains("sampler")) {
        const json& s = doc_["samplers"][texture["sampler"].get<int>()];
        r.sampler.mag = s.value("magFilter", kLinear);
        r.sampler.min = s.value("minFilter", -1);
        r.sampler.wrap_s = s.value("wrapS", kRepeat);
        r.sampler.wrap_t = s.value("wrapT", kRepeat);
      }
      r.texcoord = ref.value("texCoord", 0);
    }
    r.alpha_mode = m.value("alphaMode", "OPAQUE");
    r.cutoff = m.value("alphaCutoff", 0.5);
    if (m.contains("emissiveFactor"))
      for (int k = 0; k < 3; ++k) r.emissive[k] = m["emissiveFactor"][k].get<double>();
    const json extensions = m.value("extensions", json::object());
    if (extensions.contains("KHR_materials_emissive_strength"))
      r.strength = extensions["KHR_materials_emissive_strength"].value("emissiveStrength", 1.0);
    r.unlit = extensions.contains("KHR_materials_unlit");
    r.double_sided = m.value("doubleSided", false);
    r.occlusion = m.contains("occlusionTexture");
    r.emissive_texture = m.contains("emissiveTexture");
    return r;
  }

  // Elements of an accessor as doubles, normalised integers converted as the spec says.
  std::vector<double> accessor(int index, int& components) const {
    const json& a = doc_["accessors"][index];
    const std::string type = a["type"];
    components = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
    const int component_type = a["componentType"];
    const bool normalized = a.value("normalized", false);
    const size_t count = a["count"];
    std::vector<double> out(count * components, 0.0);
    if (!a.contains("bufferView")) return out;
    const json& view = doc_["bufferViews"][a["bufferView"].get<int>()];
    const std::vector<uint8_t>& buffer = buffers_.at(view["buffer"].get<int>());
    const size_t bytes = component_type == 5120 || component_type == 5121   ? 1
                         : component_type == 5122 || component_type == 5123 ? 2
                                                                            : 4;
    const size_t stride = view.value("byteStride", size_t(0)) ? view["byteStride"].get<size_t>() : bytes * components;
    const size_t start = view.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
    for (size_t i = 0; i < count; ++i)
      for (int c = 0; c < components; ++c) {
        const size_t at = start + i * stride + c * bytes;
        if (at + bytes > buffer.size())
          throw std::runtime_error("accessor " + std::to_string(index) + " past its buffer");
        const uint8_t* e = &buffer[at];
        double v = 0;
        switch (component_type) {
          case 5120:
            v = normalized ? std::max(int8_t(e[0]) / 127.0, -1.0) : int8_t(e[0]);
            break;
          case 5121:
            v = normalized ? e[0] / 255.0 : e[0];
            break;
          case 5122: {
            int16_t s;
            std::memcpy(&s, e, 2);
            v = normalized ? std::max(s / 32767.0, -1.0) : s;
            break;
          }
          case 5123: {
            uint16_t s;
            std::memcpy(&s, e, 2);
            v = normalized ? s / 65535.0 : s;
            break;
          }
          case 5125: {
            uint32_t s;
            std::memcpy(&s, e, 4);
            v = s;
            break;
          }
          case 5126: {
            float f;
            std::memcpy(&f, e, 4);
            v = f;
            break;
          }
          default:
            throw std::runtime_error("component type " + std::to_string(component_type));
        }
        out[i * components + c] = v;
      }
    return out;
  }

  void visit(int index, const glm::dmat4& parent) {
    const json& node = doc_["nodes"][index];
    glm::dmat4 local(1.0);
    if (node.contains("matrix")) {
      for (int k = 0; k < 16; ++k) local[k / 4][k % 4] = node["matrix"][k].get<double>();
    } else {
      glm::dvec3 t(0.0), s(1.0);
      glm::dvec4 q(0, 0, 0, 1);  // x, y, z, w
      for (int k = 0; k < 4; ++k) {
        if (k < 3 && node.contains("translation")) t[k] = node["translation"][k].get<double>();
        if (k < 3 && node.contains("scale")) s[k] = node["scale"][k].get<double>();
        if (node.contains("rotation")) q[k] = node["rotation"][k].get<double>();
      }
      const double x = q.x, y = q.y, z = q.z, w = q.w;
      // Rows of the rotation matrix of a unit quaternion.
      const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                              {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                              {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) local[col][row] = r[row][col] * s[col];
        local[3][row] = t[row];
      }
    }
    const glm::dmat4 world = parent * local;
    if (node.contains("mesh")) add_mesh(doc_["meshes"][node["mesh"].get<int>()], world);
    for (int child : node.value("children", std::vector<int>())) visit(child, world);
  }

  void add_mesh(const json& mesh, const glm::dmat4& world) {
    for (const json& p : mesh["primitives"]) {
      if (p.value("mode", 4) != 4) continue;
      const int surface = next_surface_++;
      const int material = p.value("material", -1);
      const RefMaterial& m = material < 0 ? default_ : materials_[material];
      const json& attributes = p["attributes"];
      int n = 0;
      const std::vector<double> positions = accessor(attributes["POSITION"].get<int>(), n);
      const size_t count = positions.size() / 3;
      std::vector<double> uvs, colors;
      int uv_n = 2, color_n = 4;
      const std::string uv_name = "TEXCOORD_" + std::to_string(m.texcoord);
      if (attributes.contains(uv_name)) uvs = accessor(attributes[uv_name].get<int>(), uv_n);
      if (attributes.contains("COLOR_0")) colors = accessor(attributes["COLOR_0"].get<int>(), color_n);
      std::vector<size_t> indices;
      if (p.contains("indices")) {
        int one = 0;
        for (double v : accessor(p["indices"].get<int>(), one)) indices.push_back(size_t(v));
      } else {
        for (size_t i = 0; i < count; ++i) indices.push_back(i);
      }
      for (size_t k = 0; k + 2 < indices.size(); k += 3) {
        RefTriangle t;
        t.material = material;
        t.surface = surface;
        for (int c = 0; c < 3; ++c) {
          const size_t v = indices[k + c];
          t.p[c] = glm::dvec3(world * glm::dvec4(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2], 1.0));
          t.uv[c] = uvs.empty() ? glm::dvec2(0.0) : glm::dvec2(uvs[v * uv_n], uvs[v * uv_n + 1]);
          t.color[c] = glm::dvec4(1.0);
          if (!colors.empty())
            for (int j = 0; j < color_n; ++j) t.color[c][j] = colors[v * color_n + j];
        }
        const glm::dvec3 cross = glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
        if (glm::length(cross) == 0.0) continue;
        t.normal = glm::normalize(cross);
        t.offset = glm::dot(t.normal, t.p[0]);
        triangles.push_back(t);
      }
    }
  }

  std::filesystem::path folder_;
  json doc_;
  std::vector<std::vector<uint8_t>> buffers_;
  std::vector<RefMaterial> materials_;
  std::map<int, RefImage> images_;
  RefMaterial default_;
  int next_surface_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Rays and texture prediction.

// Pixel rays from the camera basis: the direction's component along the view axis is 1, so a
// hit's ray parameter is its view depth.
struct Rays {
  glm::dvec3 eye, right, up, forward;
  double tx, ty, znear;
  uint32_t width, height;

  Rays(const Camera& camera, uint32_t w, uint32_t h) : width(w), height(h) {
    eye = glm::dvec3(camera.world[3]);
    right = glm::dvec3(camera.world[0]);
    up = glm::dvec3(camera.world[1]);
    forward = -glm::dvec3(camera.world[2]);
    ty = std::tan(double(camera.yfov) / 2.0);
    tx = ty * double(w) / h;
    znear = camera.znear;
  }
  // (x, y) in pixels from the top-left corner of the image; pixel centres at +0.5.
  glm::dvec3 direction(double x, double y) const {
    return forward + right * ((2.0 * x / width - 1.0) * tx) - up * ((2.0 * y / height - 1.0) * ty);
  }
  glm::dvec2 pixel_of(const glm::dvec3& p) const {
    const glm::dvec3 d = p - eye;
    const double z = glm::dot(d, forward);
    return {(glm::dot(d, right) / (z * tx) + 1.0) * 0.5 * width, (1.0 - glm::dot(d, up) / (z * ty)) * 0.5 * height};
  }
};

// Ray against the triangle's plane; barycentrics are extrapolated outside the triangle.
bool plane_hit(const RefTriangle& tri, const glm::dvec3& origin, const glm::dvec3& d, double& t, glm::dvec3& bary) {
  const glm::dvec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
  const glm::dvec3 pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-300) return false;
  const glm::dvec3 tv = origin - tri.p[0];
  const double u = glm::dot(tv, pv) / det;
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double v = glm::dot(d, qv) / det;
  t = glm::dot(e2, qv) / det;
  bary = {1.0 - u - v, u, v};
  return true;
}

int wrap(int i, int n, int mode) {
  if (mode == kClamp) return std::clamp(i, 0, n - 1);
  if (mode == kMirror) {
    const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
    return m < n ? m : 2 * n - 1 - m;
  }
  return ((i % n) + n) % n;
}

glm::dvec4 decode(const uint8_t* texel) {
  return {srgb_decode(texel[0] / 255.0), srgb_decode(texel[1] / 255.0), srgb_decode(texel[2] / 255.0),
          texel[3] / 255.0};
}

struct Footprint {
  glm::dvec2 uv, dx, dy;  // uv and its change per pixel right and down
  glm::dvec4 color{1.0};  // interpolated COLOR_0
};

struct Window {
  bool constant = true;  // every texel of the window equal (all four channels)
  glm::dvec4 texel{1.0};
  double alpha_min = 1.0, alpha_max = 0.0;
};

// Half-width in base texels of the region any sample at this footprint may read.
double window_radius(const RefImage& image, const RefSampler& sampler, const Footprint& f) {
  const glm::dvec2 size(image.width, image.height);
  const double rho = std::max(glm::length(f.dx * size), glm::length(f.dy * size));
  const int levels = int(std::bit_width(uint32_t(std::max(image.width, image.height))));
  int top = 0;
  if (sampler.mipmaps()) top = std::clamp(int(std::ceil(std::log2(std::max(rho, 1e-30)))) + 1, 0, levels - 1);
  return std::ldexp(1.0, top + 1) + 1.0;
}

// Wider windows (grazing angles) are not worth their cost: such pixels are not predicted.
constexpr double kMaxRadius = 40.0;

// With `alpha_range` false the scan stops at the first texel that differs.
Window window(const RefImage& image, int wrap_s, int wrap_t, glm::dvec2 uv, double radius, bool alpha_range) {
  Window w;
  if (radius > kMaxRadius) return {false, glm::dvec4(0.0), 0.0, 1.0};
  const double cx = uv.x * image.width - 0.5, cy = uv.y * image.height - 0.5;
  // Wrapped once per row and column rather than per texel: this loop dominates the test's time.
  std::vector<int> xs, ys;
  for (int x = int(std::floor(cx - radius)); x <= int(std::floor(cx + radius)) + 1; ++x)
    xs.push_back(wrap(x, image.width, wrap_s));
  for (int y = int(std::floor(cy - radius)); y <= int(std::floor(cy + radius)) + 1; ++y)
    ys.push_back(wrap(y, image.height, wrap_t));
  const uint8_t* first = image.texel(xs[0], ys[0]);
  uint32_t first_bits;
  std::memcpy(&first_bits, first, 4);
  uint8_t alpha_lo = 255, alpha_hi = 0;
  for (int y : ys) {
    const uint8_t* row = image.texel(0, y);
    for (int x : xs) {
      const uint8_t* t = row + size_t(x) * 4;
      uint32_t bits;
      std::memcpy(&bits, t, 4);
      if (bits != first_bits) {
        w.constant = false;
        if (!alpha_range) return w;
      }
      alpha_lo = std::min(alpha_lo, t[3]);
      alpha_hi = std::max(alpha_hi, t[3]);
    }
  }
  w.alpha_min = alpha_lo / 255.0;
  w.alpha_max = alpha_hi / 255.0;
  w.texel = decode(first);
  return w;
}

// ---------------------------------------------------------------------------------------------
// The reference image: what each pixel centre sees.

struct PixelRef {
  enum State { background, visible, ambiguous } state = background;
  int tri = -1;
  double depth = 0;        // view depth of the visible surface
  std::vector<int> holes;  // surfaces of alpha-tested triangles cut away in front of it
};

class View {
  const Reference& ref_;  // first: the members below are built from it

 public:
  View(const Reference& ref, const Camera& camera, uint32_t width, uint32_t height)
      : ref_(ref), rays(camera, width, height), pixels(size_t(width) * height) {
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) pixels[size_t(y) * width + x] = resolve(x + 0.5, y + 0.5);
  }

  Footprint footprint(int tri_index, uint32_t x, uint32_t y) const {
    const RefTriangle& tri = ref_.triangles[tri_index];
    auto at = [&](double px, double py, glm::dvec4* color) {
      double t;
      glm::dvec3 b;
      plane_hit(tri, rays.eye, rays.direction(px, py), t, b);
      if (color) *color = b.x * tri.color[0] + b.y * tri.color[1] + b.z * tri.color[2];
      return b.x * tri.uv[0] + b.y * tri.uv[1] + b.z * tri.uv[2];
    };
    Footprint f;
    f.uv = at(x + 0.5, y + 0.5, &f.color);
    f.dx = at(x + 1.5, y + 0.5, nullptr) - f.uv;
    f.dy = at(x + 0.5, y + 1.5, nullptr) - f.uv;
    return f;
  }

  // Base colour (linear, alpha included) where the prediction is unambiguous.
  std::optional<glm::dvec4> base_color(int tri_index, uint32_t x, uint32_t y, const RefSampler* sampler = nullptr,
                                       bool with_vertex_color = true) const {
    const RefTriangle& tri = ref_.triangles[tri_index];
    const RefMaterial& m = ref_.material_of(tri);
    const Footprint f = footprint(tri_index, x, y);
    glm::dvec4 c = m.factor * (with_vertex_color ? f.color : glm::dvec4(1.0));
    if (m.image >= 0) {
      const RefImage& image = ref_.image(m.image);
      const RefSampler& s = sampler ? *sampler : m.sampler;
      const Window w = window(image, s.wrap_s, s.wrap_t, f.uv, window_radius(image, s, f), false);
      if (!w.constant) return std::nullopt;
      c *= w.texel;
    }
    return c;
  }

  // Neighbours all see the same thing, so coverage and depth do not hinge on edge rules.
  bool clean(uint32_t x, uint32_t y) const {
    if (x == 0 || y == 0 || x + 1 >= rays.width || y + 1 >= rays.height) return false;
    const PixelRef& centre = at(x, y);
    if (centre.state == PixelRef::ambiguous) return false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const PixelRef& n = at(x + dx, y + dy);
        if (n.state != centre.state || n.holes != centre.holes) return false;
        if (centre.state != PixelRef::visible) continue;
        const RefTriangle &a = ref_.triangles[centre.tri], &b = ref_.triangles[n.tri];
        if (a.surface != b.surface || glm::dot(a.normal, b.normal) < 1 - 1e-9 ||
            std::abs(a.offset - b.offset) > 1e-9 * (1 + std::abs(a.offset)))
          return false;
      }
    return true;
  }

  const PixelRef& at(uint32_t x, uint32_t y) const { return pixels[size_t(y) * rays.width + x]; }
  const RefTriangle& triangle(const PixelRef& p) const { return ref_.triangles[p.tri]; }
  const RefMaterial& material(const PixelRef& p) const { return ref_.material_of(ref_.triangles[p.tri]); }

  Rays rays;
  std::vector<PixelRef> pixels;

 private:
  PixelRef resolve(double px, double py) const {
    struct Hit {
      double t;
      int tri;
    };
    std::vector<Hit> hits;
    const glm::dvec3 d = rays.direction(px, py);
    for (size_t i = 0; i < ref_.triangles.size(); ++i) {
      const RefTriangle& tri = ref_.triangles[i];
      double t;
      glm::dvec3 b;
      if (!plane_hit(tri, rays.eye, d, t, b) || t < rays.znear) continue;
      // A hair of slack so a ray along a shared edge cannot slip between two triangles.
      if (b.x < -1e-9 || b.y < -1e-9 || b.z < -1e-9) continue;
      const bool front = glm::dot(tri.normal, d) < 0;
      if (!front && !ref_.material_of(tri).double_sided) continue;
      hits.push_back({t, int(i)});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
    PixelRef p;
    for (size_t k = 0; k < hits.size(); ++k) {
      const RefTriangle& tri = ref_.triangles[hits[k].tri];
      const RefMaterial& m = ref_.material_of(tri);
      if (m.alpha_mode == "MASK") {
        const uint32_t x = uint32_t(px), y = uint32_t(py);
        const Footprint f = footprint(hits[k].tri, x, y);
        double lo = m.factor.a * f.color.a, hi = lo;
        if (m.image >= 0) {
          const RefImage& image = ref_.image(m.image);
          const Window w =
              window(image, m.sampler.wrap_s, m.sampler.wrap_t, f.uv, window_radius(image, m.sampler, f), true);
          lo *= w.alpha_min;
          hi *= w.alpha_max;
        }
        // Mip texels are rounded to 8 bits: two codes of margin either side of the cutoff.
        const double margin = 2.0 / 255.0;
        if (hi < m.cutoff - margin) {
          p.holes.push_back(tri.surface);
          continue;
        }
        if (lo < m.cutoff + margin) {
          p.state = PixelRef::ambiguous;
          return p;
        }
      }
      // Another surface within 1e-4 of the same depth: which one wins is not predictable.
      for (size_t j = k + 1; j < hits.size() && hits[j].t < hits[k].t * (1 + 1e-4); ++j)
        if (ref_.triangles[hits[j].tri].surface != tri.surface) {
          p.state = PixelRef::ambiguous;
          return p;
        }
      p.state = PixelRef::visible;
      p.tri = hits[k].tri;
      p.depth = hits[k].t;
      return p;
    }
    return p;
  }
};

// ---------------------------------------------------------------------------------------------
// The GPU side.

struct GBuffer {
  uint32_t width = 0, height = 0;
  std::vector<uint32_t> albedo;
  std::vector<uint8_t> material;  // RGBA8
  std::vector<float> depth;
  std::vector<uint8_t> emissive_bytes;

  glm::dvec3 albedo_codes(size_t i) const {
    return {double(albedo[i] & 1023), double((albedo[i] >> 10) & 1023), double((albedo[i] >> 20) & 1023)};
  }
  uint32_t albedo_alpha(size_t i) const { return albedo[i] >> 30; }
  glm::dvec3 emitted(size_t i) const {
    float out[3];
    decode_texel(*format_info(VK_FORMAT_B10G11R11_UFLOAT_PACK32), 0, emissive_bytes, i, out);
    return {out[0], out[1], out[2]};
  }
};

const VersionData& output(const RenderedFrame& frame, const std::string& pass, const std::string& resource) {
  for (size_t i = 0; i < frame.graph.passes.size(); ++i)
    if (frame.graph.passes[i].decl->name == pass)
      for (int v : frame.execution.passes[i].outputs)
        if (frame.execution.versions[v].resource == resource) return frame.execution.versions[v];
  throw std::runtime_error(pass + " wrote no " + resource);
}

template <typename T>
std::vector<T> as(const VersionData& v, size_t count) {
  std::vector<T> out(count);
  EXPECT_GE(v.bytes->size(), count * sizeof(T)) << v.resource;
  std::memcpy(out.data(), v.bytes->data(), std::min(v.bytes->size(), count * sizeof(T)));
  return out;
}

class GltfGBuffer : public GpuTest {
 protected:
  static GBuffer render(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height) {
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.camera = camera;
    Renderer renderer(*gpu_, scene, settings);
    const RenderedFrame frame = renderer.render_frame(0, true);
    EXPECT_EQ(frame.camera.world, camera.world) << "frame 0 should use the camera as given";
    GBuffer g;
    g.width = width;
    g.height = height;
    const size_t n = size_t(width) * height;
    g.albedo = as<uint32_t>(output(frame, "gbuffer.opaque", "gbuffer.albedo"), n);
    g.emissive_bytes = *output(frame, "gbuffer.opaque", "gbuffer.emissive").bytes;
    g.material = as<uint8_t>(output(frame, "gbuffer.opaque", "gbuffer.material"), n * 4);
    g.depth = as<float>(output(frame, "gbuffer.opaque", "scene.depth"), n);
    return g;
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
  // The README's convention: the eye at target + r·(sin φ sin θ, cos φ, sin φ cos θ).
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

}  // namespace
}  // namespace nightcap::test
