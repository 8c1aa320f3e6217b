// Writes the seed corpora of the four harnesses into DIR/<harness>/ from valid inputs that the
// project's own writers make, so fuzzing starts from blobs and scenes the readers accept:
//   make_seeds DIR
// Image blobs: every format, three extents (mips, layers, depth), a codec each in turn. Buffer
// blobs: zstd frames of a few sizes. glTF: scenes written here that use what the loader reads
// (indexed and unindexed primitives of every index type, normals, tangents, two UV sets,
// COLOR_0, textures with samplers, alpha modes, emission, unlit, the node hierarchy, a camera,
// punctual lights), as .gltf with data URIs and as .glb. The manifest corpus is a real capture's
// manifest (see README.md), not made here.
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <iostream>
#include <random>

#include "captures/blob_codec.h"
#include "images/images.h"

namespace nc = nightcap;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

void write_file(const fs::path& file, std::span<const uint8_t> bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out.flush()) throw std::runtime_error(file.string() + ": cannot write");
}

std::vector<uint8_t> read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Prefixes a blob file with the harness's header and writes it as a seed.
void write_seed(const fs::path& blob, std::vector<uint8_t> header, const fs::path& seed) {
  const std::vector<uint8_t> bytes = read_file(blob);
  header.insert(header.end(), bytes.begin(), bytes.end());
  write_file(seed, header);
}

void image_seeds(const fs::path& dir, std::mt19937& random) {
  const std::vector<nc::ImageEncoding> codecs = {{nc::ExrCompression::zip, 1},   {nc::ExrCompression::piz, 4},
                                                 {nc::ExrCompression::rle, 4},   {nc::ExrCompression::none, 4},
                                                 {nc::ExrCompression::pxr24, 1}, {nc::ExrCompression::zips, 1}};
  const std::vector<nc::ImageExtent> extents = {{4, 3, 1, 1, 1}, {5, 3, 1, 3, 2}, {4, 4, 2, 2, 1}};
  const auto& formats = nc::all_formats();
  size_t n = 0;
  for (size_t f = 0; f < formats.size(); ++f)
    for (const nc::ImageExtent& e : extents) {
      std::vector<uint8_t> raw(nc::raw_image_bytes(formats[f], e));
      for (uint8_t& b : raw) b = uint8_t(random());
      if (formats[f].has_stencil || formats[f].is_depth) {
        // Depth is a float in [0, 1]: random bits would be refused by nothing, but real depth
        // is what the reader meets.
        for (size_t i = 0; i + 4 <= nc::raw_subresource_offset(formats[f], e, 1, 0, 0); i += 4) {
          const float d = float(random() % 1000) / 1000.0f;
          std::memcpy(&raw[i], &d, 4);
        }
      }
      const fs::path blob = dir / "blob.tmp";
      nc::write_image_blob(blob, formats[f], e, raw, codecs[n % codecs.size()], 0);
      write_seed(blob,
                 {uint8_t(f), uint8_t(e.width - 1), uint8_t(e.height - 1), uint8_t(e.mips - 1), uint8_t(e.layers - 1),
                  uint8_t(e.depth - 1)},
                 dir / ("image_" + std::to_string(n++)));
      fs::remove(blob);
    }
}

void buffer_seeds(const fs::path& dir) {
  for (uint32_t size : {0u, 1u, 64u, 4096u}) {
    std::vector<uint8_t> raw(size);
    for (uint32_t i = 0; i < size; ++i) raw[i] = uint8_t(i * 7 / 5);
    const fs::path blob = dir / "blob.tmp";
    nc::write_buffer_blob(blob, raw, 3);
    std::vector<uint8_t> header(4);
    std::memcpy(header.data(), &size, 4);
    write_seed(blob, header, dir / ("buffer_" + std::to_string(size)));
    fs::remove(blob);
  }
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t group = 0;
    for (size_t k = 0; k < 3; ++k) group = group << 8 | (k < n ? bytes[i + k] : 0);
    for (size_t k = 0; k < 4; ++k) out += k <= n ? digits[(group >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

// A glTF document and the bytes of its one buffer, which accessors are appended to.
struct Builder {
  json gltf = {{"asset", {{"version", "2.0"}}}};
  std::vector<uint8_t> bin;

  template <class T>
  int add_accessor(const std::vector<T>& values, int component_type, const char* type, size_t count,
                   bool with_bounds = false) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    bin.resize(offset + values.size() * sizeof(T));
    std::memcpy(bin.data() + offset, values.data(), values.size() * sizeof(T));
    gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    json accessor = {{"bufferView", gltf["bufferViews"].size() - 1},
                     {"componentType", component_type},
                     {"count", count},
                     {"type", type}};
    if (with_bounds) accessor["min"] = {-1, -1, 0}, accessor["max"] = {1, 1, 0};
    gltf["accessors"].push_back(accessor);
    return int(gltf["accessors"].size() - 1);
  }
};

void textured_scene(Builder& b, const std::vector<uint8_t>& png, bool image_in_buffer) {
  json& g = b.gltf;
  const int position = b.add_accessor<float>({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, 5126, "VEC3", 4, true);
  const int normal = b.add_accessor<float>({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 5126, "VEC3", 4);
  const int tangent = b.add_accessor<float>({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, -1, 1, 0, 0, 1}, 5126, "VEC4", 4);
  const int uv = b.add_accessor<float>({0, 1, 1, 1, 1, 0, 0, 0}, 5126, "VEC2", 4);
  const int uv1 = b.add_accessor<uint16_t>({0, 65535, 65535, 65535, 65535, 0, 0, 0}, 5123, "VEC2", 4);
  const int color =
      b.add_accessor<uint8_t>({255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 9, 9, 9, 255}, 5121, "VEC4", 4);
  const int indices16 = b.add_accessor<uint16_t>({0, 1, 2, 0, 2, 3}, 5123, "SCALAR", 6);
  const int indices8 = b.add_accessor<uint8_t>({0, 1, 2}, 5121, "SCALAR", 3);
  const int indices32 = b.add_accessor<uint32_t>({2, 3, 0}, 5125, "SCALAR", 3);
  json attributes = {{"POSITION", position}, {"NORMAL", normal},  {"TANGENT", tangent},
                     {"TEXCOORD_0", uv},     {"TEXCOORD_1", uv1}, {"COLOR_0", color}};
  g["meshes"] = {{{"name", "quad"},
                  {"primitives",
                   {{{"attributes", attributes}, {"indices", indices16}, {"material", 0}},
                    {{"attributes", attributes}, {"indices", indices8}, {"material", 1}},
                    {{"attributes", attributes}, {"indices", indices32}, {"material", 2}},
                    {{"attributes", {{"POSITION", position}}}, {"mode", 4}}}}}};
  if (image_in_buffer) {
    const size_t offset = b.bin.size();
    b.bin.insert(b.bin.end(), png.begin(), png.end());
    g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", png.size()}});
    g["images"] = {{{"bufferView", g["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
  } else {
    g["images"] = {{{"uri", "data:image/png;base64," + base64(png)}}};
  }
  g["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9987}, {"wrapS", 33648}, {"wrapT", 33071}},
                   {{"magFilter", 9729}, {"minFilter", 9729}}};
  g["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 0}, {"sampler", 1}}};
  const json tex0 = {{"index", 0}}, tex1 = {{"index", 1}, {"texCoord", 1}};
  g["materials"] = {
      {{"name", "textured"},
       {"pbrMetallicRoughness",
        {{"baseColorTexture", tex0}, {"metallicRoughnessTexture", tex1}, {"baseColorFactor", {1, 0.5, 0.25, 1}}}},
       {"normalTexture", {{"index", 0}, {"scale", 0.5}}},
       {"occlusionTexture", {{"index", 1}, {"strength", 0.7}}},
       {"emissiveTexture", tex0},
       {"emissiveFactor", {1, 1, 1}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}},
      {{"name", "cutout"}, {"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"doubleSided", true}},
      {{"name", "unlit"}, {"alphaMode", "BLEND"}, {"extensions", {{"KHR_materials_unlit", json::object()}}}}};
  g["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_lights_punctual"};
  g["extensions"] = {
      {"KHR_lights_punctual",
       {{"lights",
         {{{"type", "point"}, {"color", {1, 0.8, 0.6}}, {"intensity", 40}, {"range", 10}},
          {{"type", "spot"}, {"intensity", 100}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
          {{"type", "directional"}, {"intensity", 3}}}}}}};
  g["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"aspectRatio", 1.5}}}}};
  g["nodes"] = {{{"name", "root"}, {"children", {1, 2, 3, 4}}, {"translation", {0, 1, 0}}},
                {{"mesh", 0}, {"rotation", {0, 0.7071068, 0, 0.7071068}}, {"scale", {1, -1, 1}}},
                {{"camera", 0}, {"translation", {0, 0, 5}}},
                {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}},
                 {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 2, 2, 1}}},
                {{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}}};
  g["scenes"] = {{{"nodes", {0}}}};
  g["scene"] = 0;
}

void write_gltf(const fs::path& file, Builder& b) {
  b.gltf["buffers"] = {
      {{"byteLength", b.bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(b.bin)}}};
  const std::string text = b.gltf.dump();
  write_file(file, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
}

void write_glb(const fs::path& file, Builder& b) {
  while (b.bin.size() % 4) b.bin.push_back(0);
  b.gltf["buffers"] = {{{"byteLength", b.bin.size()}}};
  std::string text = b.gltf.dump();
  while (text.size() % 4) text += ' ';
  std::vector<uint8_t> out;
  auto word = [&](uint32_t w) {
    out.insert(out.end(), reinterpret_cast<uint8_t*>(&w), reinterpret_cast<uint8_t*>(&w) + 4);
  };
  word(0x46546C67), word(2), word(uint32_t(12 + 8 + text.size() + 8 + b.bin.size()));
  word(uint32_t(text.size())), word(0x4E4F534A);
  out.insert(out.end(), text.begin(), text.end());
  word(uint32_t(b.bin.size())), word(0x004E4942);
  out.insert(out.end(), b.bin.begin(), b.bin.end());
  write_file(file, out);
}

void gltf_seeds(const fs::path& dir) {
  const std::vector<uint8_t> rgba = {255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 255, 255, 255, 0};
  nc::write_png(dir / "texture.png", rgba, 2, 2);
  const std::vector<uint8_t> png = read_file(dir / "texture.png");
  fs::remove(dir / "texture.png");

  Builder triangle;
  const int position = triangle.add_accessor<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}, 5126, "VEC3", 3, true);
  triangle.gltf["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", position}}}}}}}};
  triangle.gltf["nodes"] = {{{"mesh", 0}}};
  triangle.gltf["scenes"] = {{{"nodes", {0}}}};
  write_gltf(dir / "triangle.gltf", triangle);

  Builder embedded;
  textured_scene(embedded, png, false);
  write_gltf(dir / "textured.gltf", embedded);
  Builder binary;
  textured_scene(binary, png, true);
  write_glb(dir / "textured.glb", binary);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) == "--help") {
    std::cerr << "usage: make_seeds DIR  (writes DIR/image_blob, DIR/buffer_blob, DIR/gltf)\n";
    return argc == 2 ? 0 : 2;
  }
  try {
    const fs::path root = argv[1];
    for (const char* harness : {"image_blob", "buffer_blob", "gltf"}) fs::create_directories(root / harness);
    std::mt19937 random(1);
    image_seeds(root / "image_blob", random);
    buffer_seeds(root / "buffer_blob");
    gltf_seeds(root / "gltf");
  } catch (const std::exception& e) {
    std::cerr << "make_seeds: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
