// glTF 2.0 through tinygltf. Images are decoded with OpenImageIO through the image module
// (tinygltf's bundled stb is not used), so every format OIIO reads works and errors name the file.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <cmath>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>

#include "images/images.h"
#include "passes/scene/scene.h"

namespace nightcap {
namespace {

constexpr uint32_t kMaxTextureSide = 16384;

// tinygltf hands embedded images (data URIs, .glb buffer views) to this callback, with the
// model being loaded as `model`. tinygltf 2.7 does not check that an image's buffer view lies
// inside its buffer (found by tests/fuzz/gltf_fuzz.cpp: it read freed memory), so that is
// checked here before a byte is read.
bool decode_embedded(tinygltf::Image* image, const int, std::string* err, std::string*, int, int,
                     const unsigned char* bytes, int size, void* model) {
  if (image->bufferView >= 0) {
    const auto& m = *static_cast<const tinygltf::Model*>(model);
    const tinygltf::BufferView& view = m.bufferViews.at(size_t(image->bufferView));
    const uint64_t buffer_size = m.buffers.at(size_t(view.buffer)).data.size();
    if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset || size < 0) {
      if (err) *err += "image '" + image->name + "': its buffer view lies outside its buffer\n";
      return false;
    }
  }
  const std::string name = image->mimeType == "image/png" ? "embedded.png" : "embedded.jpg";
  Rgba8Image decoded;
  try {
    decoded = decode_image_memory(name, {bytes, size_t(size)}, kMaxTextureSide);
  } catch (const ImageError& e) {
    if (err) *err += "cannot decode embedded image '" + image->name + "': " + e.what() + "\n";
    return false;
  }
  image->width = int(decoded.width);
  image->height = int(decoded.height);
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image = std::move(decoded.pixels);
  return true;
}

std::string url_decode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
        std::isxdigit(uint8_t(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

class Loader {
 public:
  Loader(const std::string& path, const tinygltf::Model& model) : path_(path), model_(model) {
    folder_ = std::filesystem::path(path).parent_path();
  }

  Scene load() {
    scene_.source = path_;
    const int scene_index = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    std::vector<int> roots;
    if (scene_index < int(model_.scenes.size())) {
      roots = model_.scenes[scene_index].nodes;
    } else {
      std::vector<bool> child(model_.nodes.size(), false);
      for (const auto& node : model_.nodes)
        for (int c : node.children)
          if (c >= 0 && size_t(c) < child.size()) child[c] = true;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!child[i]) roots.push_back(int(i));
    }
    for (int root : roots) visit(root, glm::dmat4(1.0), 0);
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const { throw SceneError(path_ + ": " + problem); }

  template <typename T>
  const T& at(const std::vector<T>& list, int index, const char* what) const {
    if (index < 0 || size_t(index) >= list.size())
      fail(std::string(what) + " " + std::to_string(index) + " out of range");
    return list[size_t(index)];
  }

  void visit(int index, const glm::dmat4& parent, int depth) {
    if (depth > 64) fail("node hierarchy deeper than 64 (cycle?)");
    const tinygltf::Node& node = at(model_.nodes, index, "node");
    glm::dmat4 local(1.0);
    if (node.matrix.size() == 16) {
      local = glm::make_mat4(node.matrix.data());
    } else {
      glm::dvec3 t(0.0), s(1.0);
      glm::dquat r(1.0, 0.0, 0.0, 0.0);
      if (node.translation.size() == 3) t = glm::make_vec3(node.translation.data());
      if (node.scale.size() == 3) s = glm::make_vec3(node.scale.data());
      if (node.rotation.size() == 4)
        r = glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
      local = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(r) * glm::scale(glm::dmat4(1.0), s);
    }
    const glm::dmat4 world = parent * local;
    if (node.mesh >= 0) add_mesh(node.mesh, world);
    if (node.camera >= 0 && !scene_.camera) add_camera(node.camera, world);
    auto light = node.extensions.find("KHR_lights_punctual");
    if (light != node.extensions.end() && light->second.Has("light"))
      add_light(light->second.Get("light").GetNumberAsInt(), world);
    for (int child : node.children) visit(child, world, depth + 1);
  }

  void add_camera(int index, const glm::dmat4& world) {
    const tinygltf::Camera& c = at(model_.cameras, index, "camera");
    if (c.type != "perspective") return;
    Camera camera;
    // Cameras ignore scale: keep only rotation and translation.
    camera.world = world;
    for (int k = 0; k < 3; ++k) camera.world[k] = glm::dvec4(glm::normalize(glm::dvec3(world[k])), 0.0);
    camera.yfov = float(c.perspective.yfov);
    camera.znear = float(c.perspective.znear > 0 ? c.perspective.znear : 0.01);
    if (!(camera.yfov > 0.0f && camera.yfov < 3.14f)) fail("camera " + std::to_string(index) + " has a bad yfov");
    scene_.camera = camera;
  }

  void add_light(int index, const glm::dmat4& world) {
    const tinygltf::Light& l = at(model_.lights, index, "light");
    Light light;
    if (l.type == "directional")
      light.type = LightType::directional;
    else if (l.type == "point")
      light.type = LightType::point;
    else if (l.type == "spot")
      light.type = LightType::spot;
    else
      fail("light " + std::to_string(index) + " has unknown type '" + l.type + "'");
    light.position = glm::dvec3(world[3]);
    light.direction = glm::normalize(glm::vec3(-glm::dvec3(world[2])));
    if (l.color.size() == 3) light.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
    light.intensity = float(l.intensity);
    light.range = float(l.range);
    light.inner_cone = float(l.spot.innerConeAngle);
    light.outer_cone = float(l.spot.outerConeAngle);
    scene_.lights.push_back(light);
  }

  // Reads `components` floats per element, converting normalized integers.
  std::vector<float> read(int accessor_index, int components) const {
    const tinygltf::Accessor& a = at(model_.accessors, accessor_index, "accessor");
    if (a.sparse.isSparse) fail("accessor " + std::to_string(accessor_index) + " is sparse (not supported)");
    const int have = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    const int bytes = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (have <= 0 || bytes <= 0 || have < components - (components == 4 ? 1 : 0) || have > 4)
      fail("accessor " + std::to_string(accessor_index) + " has the wrong type");
    std::vector<float> out(a.count * size_t(components), 0.0f);
    if (a.bufferView < 0) return out;  // all zeros, per the specification
    const tinygltf::BufferView& view = at(model_.bufferViews, a.bufferView, "bufferView");
    const tinygltf::Buffer& buffer = at(model_.buffers, view.buffer, "buffer");
    const uint64_t element = uint64_t(have) * bytes;
    const uint64_t stride = view.byteStride ? view.byteStride : element;
    const uint64_t start = uint64_t(view.byteOffset) + a.byteOffset;
    if (stride < element || view.byteOffset + uint64_t(view.byteLength) > buffer.data.size() ||
        (a.count > 0 && a.byteOffset + stride * (a.count - 1) + element > view.byteLength))
      fail("accessor " + std::to_string(accessor_index) + " reads past its buffer");
    const uint8_t* base = buffer.data.data() + start;
    for (size_t i = 0; i < a.count; ++i) {
      const uint8_t* e = base + i * stride;
      for (int c = 0; c < std::min(have, components); ++c) {
        float v = 0;
        switch (a.componentType) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT:
            std::memcpy(&v, e + 4 * c, 4);
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            v = e[c] / 255.0f;
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t s;
            std::memcpy(&s, e + 2 * c, 2);
            v = s / 65535.0f;
            break;
          }
          case TINYGLTF_COMPONENT_TYPE_BYTE:
            v = std::max(int8_t(e[c]) / 127.0f, -1.0f);
            break;
          case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t s;
            std::memcpy(&s, e + 2 * c, 2);
            v = std::max(s / 32767.0f, -1.0f);
            break;
          }
          default:
            fail("accessor " + std::to_string(accessor_index) + " has an unsupported component type");
        }
        if (!std::isfinite(v)) fail("accessor " + std::to_string(accessor_index) + " holds NaN or Inf");
        out[i * components + c] = v;
      }
      if (have == 3 && components == 4) out[i * 4 + 3] = 1.0f;
    }
    return out;
  }

  std::vector<uint32_t> read_indices(int accessor_index, size_t vertex_count) const {
    const tinygltf::Accessor& a = at(model_.accessors, accessor_index, "accessor");
    if (a.type != TINYGLTF_TYPE_SCALAR || a.bufferView < 0 || a.sparse.isSparse)
      fail("index accessor " + std::to_string(accessor_index) + " is not a plain scalar list");
    const tinygltf::BufferView& view = at(model_.bufferViews, a.bufferView, "bufferView");
    const tinygltf::Buffer& buffer = at(model_.buffers, view.buffer, "buffer");
    const int bytes = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (bytes != 1 && bytes != 2 && bytes != 4)
      fail("index accessor " + std::to_string(accessor_index) + " has a bad type");
    const uint64_t stride = view.byteStride ? view.byteStride : uint64_t(bytes);
    if (view.byteOffset + uint64_t(view.byteLength) > buffer.data.size() ||
        (a.count > 0 && a.byteOffset + stride * (a.count - 1) + bytes > view.byteLength))
      fail("index accessor " + std::to_string(accessor_index) + " reads past its buffer");
    std::vector<uint32_t> out(a.count);
    const uint8_t* base = buffer.data.data() + view.byteOffset + a.byteOffset;
    for (size_t i = 0; i < a.count; ++i) {
      uint32_t v = 0;
      std::memcpy(&v, base + i * stride, size_t(bytes));
      if (v >= vertex_count)
        fail("index " + std::to_string(v) + " past the " + std::to_string(vertex_count) + " vertices");
      out[i] = v;
    }
    return out;
  }

  int32_t texture(int texture_index, bool srgb, SamplerDesc& sampler) {
    if (texture_index < 0) return -1;
    const tinygltf::Texture& t = at(model_.textures, texture_index, "texture");
    if (t.sampler >= 0) {
      const tinygltf::Sampler& s = at(model_.samplers, t.sampler, "sampler");
      auto wrap = [](int mode) {
        return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
               : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                                               : VK_SAMPLER_ADDRESS_MODE_REPEAT;
      };
      sampler.wrap_u = wrap(s.wrapS);
      sampler.wrap_v = wrap(s.wrapT);
      sampler.mag_filter = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
      switch (s.minFilter) {
        case TINYGLTF_TEXTURE_FILTER_NEAREST:
          sampler = {sampler.mag_filter, VK_FILTER_NEAREST, VK_SAMPLER_MIPMAP_MODE_NEAREST, false,
                     sampler.wrap_u,     sampler.wrap_v};
          break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR:
          sampler = {sampler.mag_filter, VK_FILTER_LINEAR, VK_SAMPLER_MIPMAP_MODE_NEAREST, false,
                     sampler.wrap_u,     sampler.wrap_v};
          break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
          sampler.min_filter = VK_FILTER_NEAREST;
          sampler.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
          break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
          sampler.min_filter = VK_FILTER_LINEAR;
          sampler.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
          break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
          sampler.min_filter = VK_FILTER_NEAREST;
          sampler.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
          break;
        default:
          sampler.min_filter = VK_FILTER_LINEAR;
          sampler.mipmap_mode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
          break;
      }
    }
    if (t.source < 0) return -1;
    const auto key = std::make_pair(t.source, srgb);
    auto found = textures_.find(key);
    if (found != textures_.end()) return found->second;
    const tinygltf::Image& image = at(model_.images, t.source, "image");
    Texture out;
    out.name = image.name.empty() ? image.uri : image.name;
    out.srgb = srgb;
    if (!image.image.empty()) {
      if (image.component != 4 || image.bits != 8 || image.width <= 0 || image.height <= 0)
        fail("image " + std::to_string(t.source) + " could not be decoded");
      out.width = uint32_t(image.width);
      out.height = uint32_t(image.height);
      out.rgba8 = image.image;
    } else {
      const std::string file = (folder_ / url_decode(image.uri)).string();
      if (image.uri.empty() || !std::filesystem::exists(file)) fail("missing texture '" + image.uri + "'");
      Rgba8Image decoded;
      try {
        decoded = decode_image_file(file, kMaxTextureSide);
      } catch (const ImageError& e) {
        fail("cannot read texture '" + image.uri + "': " + e.what());
      }
      out.width = decoded.width;
      out.height = decoded.height;
      out.rgba8 = std::move(decoded.pixels);
    }
    scene_.textures.push_back(std::move(out));
    const int32_t index = int32_t(scene_.textures.size() - 1);
    textures_[key] = index;
    return index;
  }

  uint32_t material(int index) {
    auto found = materials_.find(index);
    if (found != materials_.end()) return found->second;
    Material m;
    if (index < 0) {
      m.name = "default";
    } else {
      const tinygltf::Material& g = at(model_.materials, index, "material");
      m.name = g.name;
      const auto& pbr = g.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4)
        m.base_color =
            glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
      m.metallic = float(pbr.metallicFactor);
      m.roughness = float(pbr.roughnessFactor);
      m.base_color_texture.texture = texture(pbr.baseColorTexture.index, true, m.base_color_texture.sampler);
      m.base_color_texture.uv_set = uint32_t(pbr.baseColorTexture.texCoord);
      m.metallic_roughness_texture.texture =
          texture(pbr.metallicRoughnessTexture.index, false, m.metallic_roughness_texture.sampler);
      m.metallic_roughness_texture.uv_set = uint32_t(pbr.metallicRoughnessTexture.texCoord);
      m.normal_texture.texture = texture(g.normalTexture.index, false, m.normal_texture.sampler);
      m.normal_texture.uv_set = uint32_t(g.normalTexture.texCoord);
      m.normal_texture.scale = float(g.normalTexture.scale);
      m.occlusion_texture.texture = texture(g.occlusionTexture.index, false, m.occlusion_texture.sampler);
      m.occlusion_texture.uv_set = uint32_t(g.occlusionTexture.texCoord);
      m.occlusion_texture.scale = float(g.occlusionTexture.strength);
      m.emissive_texture.texture = texture(g.emissiveTexture.index, true, m.emissive_texture.sampler);
      m.emissive_texture.uv_set = uint32_t(g.emissiveTexture.texCoord);
      if (g.emissiveFactor.size() == 3)
        m.emissive = glm::vec3(g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]);
      auto strength = g.extensions.find("KHR_materials_emissive_strength");
      if (strength != g.extensions.end() && strength->second.Has("emissiveStrength"))
        m.emissive_strength = float(strength->second.Get("emissiveStrength").GetNumberAsDouble());
      m.unlit = g.extensions.count("KHR_materials_unlit") > 0;
      m.double_sided = g.doubleSided;
      m.alpha_cutoff = float(g.alphaCutoff);
      if (g.alphaMode == "MASK") m.alpha_mode = AlphaMode::mask;
      if (g.alphaMode == "BLEND") {
        m.alpha_mode = AlphaMode::blend;
        scene_.notes.push_back("material '" + m.name + "': BLEND drawn as opaque (no transparency pass yet)");
      }
      for (const TextureRef* ref : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                                    &m.occlusion_texture, &m.emissive_texture})
        if (ref->uv_set > 1)
          fail("material '" + m.name + "' uses TEXCOORD_" + std::to_string(ref->uv_set) +
               " (only 0 and 1 are supported)");
    }
    scene_.materials.push_back(std::move(m));
    const uint32_t id = uint32_t(scene_.materials.size() - 1);
    materials_[index] = id;
    return id;
  }

  void add_mesh(int mesh_index, const glm::dmat4& world) {
    auto cached = meshes_.find(mesh_index);
    if (cached == meshes_.end()) cached = meshes_.emplace(mesh_index, load_mesh(mesh_index)).first;
    for (uint32_t primitive : cached->second) {
      Instance instance;
      instance.world = world;
      instance.primitive = primitive;
      scene_.instances.push_back(instance);
    }
  }

  std::vector<uint32_t> load_mesh(int mesh_index) {
    const tinygltf::Mesh& mesh = at(model_.meshes, mesh_index, "mesh");
    std::vector<uint32_t> primitives;
    for (const tinygltf::Primitive& p : mesh.primitives) {
      if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) {
        scene_.notes.push_back("mesh " + std::to_string(mesh_index) + ": non-triangle primitive skipped");
        continue;
      }
      auto attribute = [&](const char* name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
      };
      const int position = attribute("POSITION");
      if (position < 0) fail("mesh " + std::to_string(mesh_index) + " has a primitive without POSITION");
      const std::vector<float> positions = read(position, 3);
      const size_t count = positions.size() / 3;
      if (count > (1u << 26)) fail("mesh " + std::to_string(mesh_index) + " has too many vertices");
      std::vector<float> normals = attribute("NORMAL") >= 0 ? read(attribute("NORMAL"), 3) : std::vector<float>();
      std::vector<float> tangents = attribute("TANGENT") >= 0 ? read(attribute("TANGENT"), 4) : std::vector<float>();
      std::vector<float> uv0 = attribute("TEXCOORD_0") >= 0 ? read(attribute("TEXCOORD_0"), 2) : std::vector<float>();
      std::vector<float> uv1 = attribute("TEXCOORD_1") >= 0 ? read(attribute("TEXCOORD_1"), 2) : std::vector<float>();
      std::vector<float> colors = attribute("COLOR_0") >= 0 ? read(attribute("COLOR_0"), 4) : std::vector<float>();
      for (const auto* stream : {&normals, &tangents, &uv0, &uv1, &colors})
        if (!stream->empty() && stream->size() / (stream == &tangents || stream == &colors ? 4
                                                  : stream == &normals                     ? 3
                                                                                           : 2) !=
                                    count)
          fail("mesh " + std::to_string(mesh_index) + " has attributes of different lengths");
      std::vector<uint32_t> indices;
      if (p.indices >= 0) {
        indices = read_indices(p.indices, count);
      } else {
        indices.resize(count);
        for (size_t i = 0; i < count; ++i) indices[i] = uint32_t(i);
      }
      indices.resize(indices.size() / 3 * 3);
      if (indices.empty()) continue;

      Primitive prim;
      prim.material = material(p.material);
      prim.first_index = uint32_t(scene_.indices.size());
      prim.vertex_offset = int32_t(scene_.vertices.size());
      prim.bounds_min = glm::vec3(INFINITY);
      prim.bounds_max = glm::vec3(-INFINITY);
      auto vertex = [&](size_t i) {
        Vertex v{};
        for (int k = 0; k < 3; ++k) {
          v.position[k] = positions[i * 3 + k];
          if (!normals.empty()) v.normal[k] = normals[i * 3 + k];
        }
        for (int k = 0; k < 4; ++k) {
          if (!tangents.empty()) v.tangent[k] = tangents[i * 4 + k];
          v.color[k] = colors.empty() ? 1.0f : colors[i * 4 + k];
        }
        for (int k = 0; k < 2; ++k) {
          if (!uv0.empty()) v.uv0[k] = uv0[i * 2 + k];
          if (!uv1.empty()) v.uv1[k] = uv1[i * 2 + k];
        }
        prim.bounds_min = glm::min(prim.bounds_min, glm::make_vec3(v.position));
        prim.bounds_max = glm::max(prim.bounds_max, glm::make_vec3(v.position));
        return v;
      };
      if (!normals.empty()) {
        for (size_t i = 0; i < count; ++i) scene_.vertices.push_back(vertex(i));
        for (uint32_t index : indices) scene_.indices.push_back(index);
      } else {
        // No normals: flat shading, as the specification asks, with one vertex per corner.
        for (size_t t = 0; t < indices.size(); t += 3) {
          Vertex corner[3] = {vertex(indices[t]), vertex(indices[t + 1]), vertex(indices[t + 2])};
          const glm::vec3 a = glm::make_vec3(corner[0].position), b = glm::make_vec3(corner[1].position),
                          c = glm::make_vec3(corner[2].position);
          glm::vec3 n = glm::cross(b - a, c - a);
          n = glm::length(n) > 0 ? glm::normalize(n) : glm::vec3(0, 0, 1);
          for (int k = 0; k < 3; ++k) {
            for (int j = 0; j < 3; ++j) corner[k].normal[j] = n[j];
            scene_.indices.push_back(uint32_t(scene_.vertices.size() - prim.vertex_offset));
            scene_.vertices.push_back(corner[k]);
          }
        }
      }
      prim.index_count = uint32_t(scene_.indices.size()) - prim.first_index;
      scene_.primitives.push_back(prim);
      primitives.push_back(uint32_t(scene_.primitives.size() - 1));
    }
    return primitives;
  }

  std::string path_;
  std::filesystem::path folder_;
  const tinygltf::Model& model_;
  Scene scene_;
  std::map<std::pair<int, bool>, int32_t> textures_;
  std::map<int, uint32_t> materials_;
  std::map<int, std::vector<uint32_t>> meshes_;
};

}  // namespace

Scene load_gltf(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw SceneError(path + ": cannot open file (no such file)");
  tinygltf::TinyGLTF reader;
  tinygltf::Model model;
  reader.SetImageLoader(decode_embedded, &model);
  std::string error, warning;
  const bool binary = std::filesystem::path(path).extension() == ".glb";
  bool ok = false;
  try {
    ok = binary ? reader.LoadBinaryFromFile(&model, &error, &warning, path)
                : reader.LoadASCIIFromFile(&model, &error, &warning, path);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!ok) {
    while (!error.empty() && error.back() == '\n') error.pop_back();
    throw SceneError(path + ": malformed glTF: " + (error.empty() ? "unreadable" : error));
  }
  Scene scene = Loader(path, model).load();
  scene.probes = probe_in_bounds(scene);
  return scene;
}

}  // namespace nightcap
