// The independent glTF reference shared by the G-buffer and light tests: its own reader of the
// .gltf JSON and buffers (images decoded with OpenImageIO, node transforms from the matrix or
// TRS), one ray per pixel centre from the camera's basis vectors (image row 0 at the top, +Y up),
// the "clean" pixel selection and the texture-window prediction described in
// gltf_gbuffer_test.cpp. Nothing here calls the loader or camera_math.h.
//
// Vertex attributes are taken as scene.geometry stores them (vertex_streams.h): positions on the
// 16-bit grid of their primitive's box, half UVs, octahedral normals and tangents, 8-bit colours
// (Attributes::file takes the file's values). These tests bound what the passes make of the
// stored vertices; vertex_streams_test.cpp bounds the storage against the file's floats.
// Against the file's own attributes the stored ones cost, measured with Attributes::file: half
// UVs move a 2048² normal map's samples by up to half a texel where uv < 1 (a whole texel up
// to 2), which put gbuffer.normal up to 2.66° beyond the filter's reach in
// NormalTangentMirrorTest where 0.097° is allowed; 16-bit positions in a primitive much larger
// than its distance to the camera moved depth by up to 8·10⁻⁵ relative (EmissiveStrengthTest)
// where 10⁻⁵ is allowed.
// (Over 600 lines: a glTF reader, a ray caster and the texture prediction, which must share
// nothing with the renderer's code to stay independent of it.)
#pragma once

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/packing.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "passes/assembly/renderer.h"
#include "passes/core/format.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/vertex_streams.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {

using nlohmann::json;

inline std::string model_path(const std::string& name) {
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

// A non-colour texture of a material: normal, metallic-roughness or occlusion.
struct RefTexture {
  int image = -1;
  RefSampler sampler;
  int texcoord = 0;
  double scale = 1.0;  // normalTexture.scale, occlusionTexture.strength
};

struct RefMaterial {
  std::string name = "default";
  glm::dvec4 factor{1.0};
  double metallic = 1.0, roughness = 1.0;
  RefTexture normal_map, metal_rough, occlusion_map;
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
  glm::dvec2 uv[3];      // the base colour texture's set
  glm::dvec2 uvs[2][3];  // TEXCOORD_0 and TEXCOORD_1
  glm::dvec4 color[3];
  // World-space vertex normals (normal matrix applied, not renormalised) and tangents (model
  // matrix applied to xyz, w the handedness); zero when the primitive has none.
  glm::dvec3 n[3];
  glm::dvec4 tangent[3];
  int material = -1;  // -1: the default material
  int surface = 0;    // one per (node, primitive)
  glm::dvec3 normal;  // unit, from the winding
  double offset = 0;  // plane: dot(normal, x) = offset
};

// A KHR_lights_punctual light placed by its node: the spec's defaults filled in, range 0 where
// the file gives none (infinite).
struct RefLight {
  std::string type;
  glm::dvec3 color{1.0};
  double intensity = 1.0, range = 0.0, inner_cone = 0.0, outer_cone = M_PI / 4.0;
  glm::dvec3 position{0.0}, direction{0.0, 0.0, -1.0};  // world; direction: the node's −Z
};

inline double srgb_decode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

inline std::vector<uint8_t> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline RefImage read_image(const std::filesystem::path& file) {
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

// What the reference takes a vertex attribute to be: as scene.geometry stores it, or the file's
// value.
enum class Attributes { stored, file };

class Reference {
 public:
  explicit Reference(const std::string& path, Attributes attributes = Attributes::stored) : attributes_(attributes) {
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
  std::vector<RefLight> lights;  // in the order of a depth-first walk of the default scene

 private:
  RefMaterial material(const json& m) {
    RefMaterial r;
    r.name = m.value("name", "");
    const json pbr = m.value("pbrMetallicRoughness", json::object());
    if (pbr.contains("baseColorFactor"))
      for (int k = 0; k < 4; ++k) r.factor[k] = pbr["baseColorFactor"][k].get<double>();
    if (pbr.contains("baseColorTexture")) {
      const RefTexture t = texture(pbr["baseColorTexture"], "");
      r.image = t.image;
      r.sampler = t.sampler;
      r.texcoord = t.texcoord;
    }
    r.metallic = pbr.value("metallicFactor", 1.0);
    r.roughness = pbr.value("roughnessFactor", 1.0);
    if (pbr.contains("metallicRoughnessTexture")) r.metal_rough = texture(pbr["metallicRoughnessTexture"], "");
    if (m.contains("normalTexture")) r.normal_map = texture(m["normalTexture"], "scale");
    if (m.contains("occlusionTexture")) r.occlusion_map = texture(m["occlusionTexture"], "strength");
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

  RefTexture texture(const json& ref, const char* scale) {
    RefTexture r;
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
    if (*scale) r.scale = ref.value(scale, 1.0);
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
    if (node.contains("extensions") && node["extensions"].contains("KHR_lights_punctual"))
      add_light(node["extensions"]["KHR_lights_punctual"]["light"].get<int>(), world);
    for (int child : node.value("children", std::vector<int>())) visit(child, world);
  }

  void add_light(int index, const glm::dmat4& world) {
    const json& l = doc_["extensions"]["KHR_lights_punctual"]["lights"][index];
    RefLight r;
    r.type = l["type"];
    if (l.contains("color"))
      for (int k = 0; k < 3; ++k) r.color[k] = l["color"][k].get<double>();
    r.intensity = l.value("intensity", 1.0);
    r.range = l.value("range", 0.0);
    if (l.contains("spot")) {
      r.inner_cone = l["spot"].value("innerConeAngle", 0.0);
      r.outer_cone = l["spot"].value("outerConeAngle", M_PI / 4.0);
    }
    r.position = glm::dvec3(world[3]);
    r.direction = glm::normalize(-glm::dvec3(world[2]));
    lights.push_back(r);
  }

  // The attributes of one primitive rounded as scene.geometry stores them. The position box is
  // the loader's culling box: the box of every vertex when the primitive has normals, else of
  // the vertices its triangles use (it is flat-shaded from those alone).
  static void store_as_scene_geometry(std::vector<double>& positions, const std::vector<size_t>& indices,
                                      bool has_normals, std::vector<double> (&uvs)[2], const int (&uv_n)[2],
                                      std::vector<double>& colors, int color_n, std::vector<double>& normals,
                                      std::vector<double>& tangents) {
    std::vector<size_t> used;
    if (has_normals)
      for (size_t v = 0; v < positions.size() / 3; ++v) used.push_back(v);
    else
      for (size_t k = 0; k < indices.size() / 3 * 3; ++k) used.push_back(indices[k]);
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (size_t v : used)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], float(positions[v * 3 + k]));
        hi[k] = std::max(hi[k], float(positions[v * 3 + k]));
      }
    const glm::vec3 step = position_step(lo, hi);
    for (size_t v : used)
      for (int k = 0; k < 3; ++k)
        positions[v * 3 + k] =
            dequantise_position(quantise_position(float(positions[v * 3 + k]), lo[k], step[k]), lo[k], step[k]);
    for (int set = 0; set < 2; ++set)
      for (size_t i = 0; i + 1 < uvs[set].size(); i += uv_n[set]) {
        const float uv[2] = {float(uvs[set][i]), float(uvs[set][i + 1])};
        const glm::vec2 stored = decode_uv(encode_uv(uv));
        uvs[set][i] = stored.x;
        uvs[set][i + 1] = stored.y;
      }
    for (size_t i = 0; i + color_n <= colors.size(); i += color_n) {
      float rgba[4] = {1.0f, 1.0f, 1.0f, 1.0f};
      for (int j = 0; j < color_n; ++j) rgba[j] = float(colors[i + j]);
      const glm::vec4 stored = decode_color(encode_color(rgba));
      for (int j = 0; j < color_n; ++j) colors[i + j] = stored[j];
    }
    for (size_t i = 0; i + 3 <= normals.size(); i += 3) {
      const glm::vec3 stored = decode_normal(encode_normal(glm::vec3(normals[i], normals[i + 1], normals[i + 2])));
      for (int j = 0; j < 3; ++j) normals[i + j] = stored[j];
    }
    for (size_t i = 0; i + 4 <= tangents.size(); i += 4) {
      const glm::vec4 stored =
          decode_tangent(encode_tangent(glm::vec4(tangents[i], tangents[i + 1], tangents[i + 2], tangents[i + 3])));
      for (int j = 0; j < 4; ++j) tangents[i + j] = stored[j];
    }
  }

  void add_mesh(const json& mesh, const glm::dmat4& world) {
    for (const json& p : mesh["primitives"]) {
      if (p.value("mode", 4) != 4) continue;
      const int surface = next_surface_++;
      const int material = p.value("material", -1);
      const RefMaterial& m = material < 0 ? default_ : materials_[material];
      const json& attributes = p["attributes"];
      int n = 0;
      std::vector<double> positions = accessor(attributes["POSITION"].get<int>(), n);
      const size_t count = positions.size() / 3;
      std::vector<double> uvs[2], colors, normals, tangents;
      int uv_n[2] = {2, 2}, color_n = 4, normal_n = 3, tangent_n = 4;
      for (int set = 0; set < 2; ++set) {
        const std::string uv_name = "TEXCOORD_" + std::to_string(set);
        if (attributes.contains(uv_name)) uvs[set] = accessor(attributes[uv_name].get<int>(), uv_n[set]);
      }
      if (attributes.contains("COLOR_0")) colors = accessor(attributes["COLOR_0"].get<int>(), color_n);
      if (attributes.contains("NORMAL")) normals = accessor(attributes["NORMAL"].get<int>(), normal_n);
      if (attributes.contains("TANGENT")) tangents = accessor(attributes["TANGENT"].get<int>(), tangent_n);
      const glm::dmat3 linear(world), normal_matrix = glm::transpose(glm::inverse(linear));
      std::vector<size_t> indices;
      if (p.contains("indices")) {
        int one = 0;
        for (double v : accessor(p["indices"].get<int>(), one)) indices.push_back(size_t(v));
      } else {
        for (size_t i = 0; i < count; ++i) indices.push_back(i);
      }
      if (attributes_ == Attributes::stored)
        store_as_scene_geometry(positions, indices, !normals.empty(), uvs, uv_n, colors, color_n, normals, tangents);
      for (size_t k = 0; k + 2 < indices.size(); k += 3) {
        RefTriangle t;
        t.material = material;
        t.surface = surface;
        for (int c = 0; c < 3; ++c) {
          const size_t v = indices[k + c];
          t.p[c] = glm::dvec3(world * glm::dvec4(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2], 1.0));
          for (int set = 0; set < 2; ++set)
            t.uvs[set][c] =
                uvs[set].empty() ? glm::dvec2(0.0) : glm::dvec2(uvs[set][v * uv_n[set]], uvs[set][v * uv_n[set] + 1]);
          t.uv[c] = t.uvs[std::clamp(m.texcoord, 0, 1)][c];
          t.n[c] = normals.empty() ? glm::dvec3(0.0)
                                   : normal_matrix * glm::dvec3(normals[v * 3], normals[v * 3 + 1], normals[v * 3 + 2]);
          t.tangent[c] =
              tangents.empty()
                  ? glm::dvec4(0.0)
                  : glm::dvec4(linear * glm::dvec3(tangents[v * 4], tangents[v * 4 + 1], tangents[v * 4 + 2]),
                               tangents[v * 4 + 3]);
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

  Attributes attributes_;
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
inline bool plane_hit(const RefTriangle& tri, const glm::dvec3& origin, const glm::dvec3& d, double& t,
                      glm::dvec3& bary) {
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

inline int wrap(int i, int n, int mode) {
  if (mode == kClamp) return std::clamp(i, 0, n - 1);
  if (mode == kMirror) {
    const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
    return m < n ? m : 2 * n - 1 - m;
  }
  return ((i % n) + n) % n;
}

inline glm::dvec4 decode(const uint8_t* texel) {
  return {srgb_decode(texel[0] / 255.0), srgb_decode(texel[1] / 255.0), srgb_decode(texel[2] / 255.0),
          texel[3] / 255.0};
}

struct Footprint {
  glm::dvec2 uv, dx, dy;  // uv and its change per pixel right and down
  glm::dvec4 color{1.0};  // interpolated COLOR_0
};

struct Window {
  bool constant = true;   // every texel of the window equal (all four channels)
  glm::dvec4 texel{1.0};  // sRGB-decoded RGB (colour textures)
  glm::dvec4 unorm{1.0};  // the same texel as stored, / 255 (non-colour textures)
  double alpha_min = 1.0, alpha_max = 0.0;
};

// Half-width in base texels of the region any sample at this footprint may read.
inline double window_radius(const RefImage& image, const RefSampler& sampler, const Footprint& f) {
  const glm::dvec2 size(image.width, image.height);
  const double rho = std::max(glm::length(f.dx * size), glm::length(f.dy * size));
  const int levels = int(std::bit_width(uint32_t(std::max(image.width, image.height))));
  int top = 0;
  if (sampler.mipmaps()) top = std::clamp(int(std::ceil(std::log2(std::max(rho, 1e-30)))) + 1, 0, levels - 1);
  return std::ldexp(1.0, top + 1) + 1.0;
}

// Wider windows (grazing angles) are not worth their cost: such pixels are not predicted.
constexpr double kMaxRadius = 40.0;

// With `alpha_range` false the scan stops at the first texel that differs. `channels` masks the
// bytes (R lowest) that must be equal.
inline Window window(const RefImage& image, int wrap_s, int wrap_t, glm::dvec2 uv, double radius, bool alpha_range,
                     uint32_t channels = 0xffffffffu) {
  Window w;
  if (radius > kMaxRadius) return {false, glm::dvec4(0.0), glm::dvec4(0.0), 0.0, 1.0};
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
      if ((bits ^ first_bits) & channels) {
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
  w.unorm = glm::dvec4(first[0], first[1], first[2], first[3]) / 255.0;
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
  // `jitter`: the frame's TAA offset (GpuView::jitter), in pixels: pixel (x, y) shows what lies at
  // (x + 0.5, y + 0.5) − jitter unjittered.
  View(const Reference& ref, const Camera& camera, uint32_t width, uint32_t height, glm::dvec2 jitter = glm::dvec2(0.0))
      : ref_(ref), rays(camera, width, height), pixels(size_t(width) * height) {
    bin_triangles();
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x)
        pixels[size_t(y) * width + x] = resolve(x + 0.5 - jitter.x, y + 0.5 - jitter.y);
  }

  // `set`: the TEXCOORD set; -1 for the base colour texture's.
  Footprint footprint(int tri_index, uint32_t x, uint32_t y, int set = -1) const {
    const RefTriangle& tri = ref_.triangles[tri_index];
    const glm::dvec2* uv = set < 0 ? tri.uv : tri.uvs[set];
    auto at = [&](double px, double py, glm::dvec4* color) {
      double t;
      glm::dvec3 b;
      plane_hit(tri, rays.eye, rays.direction(px, py), t, b);
      if (color) *color = b.x * tri.color[0] + b.y * tri.color[1] + b.z * tri.color[2];
      return b.x * uv[0] + b.y * uv[1] + b.z * uv[2];
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
  // Each pixel tests only the triangles whose projected bounds (two pixels wider) reach its
  // tile, and those crossing the near plane: the models of hundreds of thousands of pixels and
  // ten thousand triangles would otherwise take minutes.
  static constexpr uint32_t kTile = 8;
  size_t tiles_x_ = 0;
  std::vector<std::vector<int>> tiles_;

  void bin_triangles() {
    tiles_x_ = (rays.width + kTile - 1) / kTile;
    const size_t tiles_y = (rays.height + kTile - 1) / kTile;
    tiles_.assign(tiles_x_ * tiles_y, {});
    for (size_t i = 0; i < ref_.triangles.size(); ++i) {
      const RefTriangle& tri = ref_.triangles[i];
      int in_front = 0;
      glm::dvec2 lo(INFINITY), hi(-INFINITY);
      for (const glm::dvec3& p : tri.p) {
        if (glm::dot(p - rays.eye, rays.forward) < rays.znear) continue;
        ++in_front;
        lo = glm::min(lo, rays.pixel_of(p));
        hi = glm::max(hi, rays.pixel_of(p));
      }
      if (in_front == 0) continue;  // every hit would be nearer than znear
      if (in_front < 3) {
        lo = glm::dvec2(0.0);
        hi = glm::dvec2(rays.width, rays.height);
      }
      const double x0 = std::max(lo.x - 2, 0.0), y0 = std::max(lo.y - 2, 0.0);
      const double x1 = std::min(hi.x + 2, rays.width - 1.0), y1 = std::min(hi.y + 2, rays.height - 1.0);
      if (x0 > x1 || y0 > y1) continue;
      for (size_t ty = size_t(y0) / kTile; ty <= size_t(y1) / kTile; ++ty)
        for (size_t tx = size_t(x0) / kTile; tx <= size_t(x1) / kTile; ++tx)
          tiles_[ty * tiles_x_ + tx].push_back(int(i));
    }
  }

  PixelRef resolve(double px, double py) const {
    struct Hit {
      double t;
      int tri;
    };
    std::vector<Hit> hits;
    const glm::dvec3 d = rays.direction(px, py);
    for (int i : tiles_[size_t(py / kTile) * tiles_x_ + size_t(px / kTile)]) {
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
  Camera camera;        // the frame's
  glm::dvec2 jitter{};  // the frame's TAA offset in pixels (frame.views)
  std::vector<uint32_t> albedo, normal;
  std::vector<uint8_t> material;   // RGBA8
  std::vector<uint8_t> occlusion;  // R8: the material's occlusion
  std::vector<float> depth;
  std::vector<uint8_t> emissive_bytes, motion_bytes;

  glm::dvec3 albedo_codes(size_t i) const {
    return {double(albedo[i] & 1023), double((albedo[i] >> 10) & 1023), double((albedo[i] >> 20) & 1023)};
  }
  uint32_t albedo_alpha(size_t i) const { return albedo[i] >> 30; }
  glm::dvec3 emitted(size_t i) const {
    float out[3];
    decode_texel(*format_info(VK_FORMAT_B10G11R11_UFLOAT_PACK32), 0, emissive_bytes, i, out);
    return {out[0], out[1], out[2]};
  }
  // The stored 0.5n+0.5 decoded, not renormalised.
  glm::dvec3 normal_vector(size_t i) const {
    return glm::dvec3(normal[i] & 1023, (normal[i] >> 10) & 1023, (normal[i] >> 20) & 1023) / 1023.0 * 2.0 - 1.0;
  }
  glm::dvec2 motion(size_t i) const {
    uint16_t half[2];
    std::memcpy(half, &motion_bytes.at(i * 4), 4);
    return {glm::unpackHalf1x16(half[0]), glm::unpackHalf1x16(half[1])};
  }
};

inline const VersionData& output(const RenderedFrame& frame, const std::string& pass, const std::string& resource) {
  for (size_t i = 0; i < frame.graph.passes.size(); ++i)
    if (frame.graph.passes[i].decl->name == pass)
      for (int v : frame.execution.passes[i].outputs)
        if (frame.execution.versions[v].resource == resource) return frame.execution.versions[v];
  throw std::runtime_error(pass + " wrote no " + resource);
}

template <typename T>
inline std::vector<T> as(const VersionData& v, size_t count) {
  std::vector<T> out(count);
  EXPECT_GE(v.bytes->size(), count * sizeof(T)) << v.resource;
  std::memcpy(out.data(), v.bytes->data(), std::min(v.bytes->size(), count * sizeof(T)));
  return out;
}

// Frame `index` of the Renderer (frame_camera dollies the camera forward from frame 1 on).
inline GBuffer render_gbuffer(GpuDevice& gpu, const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                              uint32_t index = 0) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.camera = camera;
  Renderer renderer(gpu, scene, settings);
  const RenderedFrame frame = renderer.render_frame(index, true);
  if (index == 0) {
    EXPECT_EQ(frame.camera.world, camera.world) << "frame 0 should use the camera as given";
  }
  GBuffer g;
  g.width = width;
  g.height = height;
  g.camera = frame.camera;
  const size_t n = size_t(width) * height;
  g.albedo = as<uint32_t>(output(frame, "gbuffer.opaque", "gbuffer.albedo"), n);
  g.normal = as<uint32_t>(output(frame, "gbuffer.opaque", "gbuffer.normal"), n);
  g.emissive_bytes = *output(frame, "gbuffer.opaque", "gbuffer.emissive").bytes;
  g.motion_bytes = *output(frame, "gbuffer.opaque", "gbuffer.motion").bytes;
  g.material = as<uint8_t>(output(frame, "gbuffer.opaque", "gbuffer.material"), n * 4);
  g.occlusion = as<uint8_t>(output(frame, "gbuffer.opaque", "gbuffer.occlusion"), n);
  g.depth = as<float>(output(frame, "gbuffer.opaque", "scene.depth"), n);
  const GpuView view = host_records<GpuView>(*output(frame, "frame.constants", "frame.views").bytes).at(0);
  g.jitter = {view.jitter.x, view.jitter.y};
  return g;
}

}  // namespace nightcap::test
