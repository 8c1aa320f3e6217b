// Subresources on the GPU against CPU values: each layer of a 2D array rendered by its own pass
// (and one mip of one layer), the array then sampled whole by compute; a 3D image written by
// compute, mip 1 computed from mip 0 of the same image. Every value is an exact float, so the
// comparisons are exact. The shaders are test-only GLSL compiled at run time.
#include <cstring>

#include "passes/core/shader.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

const std::map<std::string, std::string> kShaders = {
    {"test/layer.frag", R"(#version 460
layout(push_constant) uniform Params { float base; };
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_value;
void main() { out_value = vec4(base + gl_FragCoord.y * 16.0 + gl_FragCoord.x - 8.5, 0.0, 0.0, 1.0); }
)"},
    {"test/sum_layers.comp", R"(#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2DArray layers;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D sum;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(sum)))) return;
  float s = 0.0;
  for (int l = 0; l < textureSize(layers, 0).z; ++l) s += texelFetch(layers, ivec3(p, l), 0).r;
  imageStore(sum, p, vec4(s));
}
)"},
    {"test/fill_volume.comp", R"(#version 460
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(set = 0, binding = 0, r32f) uniform writeonly image3D volume;
void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, imageSize(volume)))) return;
  imageStore(volume, p, vec4(float(p.x + 100 * p.y + 10000 * p.z)));
}
)"},
    {"test/halve_volume.comp", R"(#version 460
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(set = 0, binding = 0) uniform sampler3D source;
layout(set = 0, binding = 1, r32f) uniform writeonly image3D target;
void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, imageSize(target)))) return;
  float s = 0.0;
  for (int i = 0; i < 8; ++i) s += texelFetch(source, 2 * p + ivec3(i & 1, (i >> 1) & 1, i >> 2), 0).r;
  imageStore(target, p, vec4(s / 8.0));
}
)"},
};

class SubresourcesOnGpu : public GpuTest {
 protected:
  static Execution run_graph(const std::vector<PassDecl>& passes, CompiledGraph& graph, const std::string& sink) {
    GraphSettings settings;
    settings.sinks = {sink};
    settings.capture = true;
    graph = compile_graph(passes, {}, settings);
    ExecutionOptions options;
    options.shaders = [](const std::string&, const std::string& path, const std::string& bindings) {
      auto it = kShaders.find(path);
      return it == kShaders.end() ? builtin_spirv(path, bindings) : compile_glsl(path, it->second, bindings);
    };
    return execute_graph(*gpu_, *cache_, graph, {}, options);
  }

  static std::vector<float> floats(const VersionData& v, uint32_t mip, uint32_t layer) {
    const FormatInfo f = *format_info(v.desc.format);
    const uint64_t offset = raw_subresource_offset(f, v.desc.extent, 0, mip, layer);
    std::vector<float> values(raw_subresource_bytes(f, v.desc.extent, 0, mip) / 4);
    std::memcpy(values.data(), v.bytes->data() + offset, values.size() * 4);
    return values;
  }
};

float layer_value(uint32_t base, uint32_t x, uint32_t y) { return float(base + y * 16 + x); }

TEST_F(SubresourcesOnGpu, EachLayerOfAnArrayRenderedByItsOwnPass) {
  const uint32_t width = 16, height = 8, layers = 4;
  ImageDecl array{VK_FORMAT_R32_SFLOAT, kinds::colour};
  array.size = {SizeRule::Mode::absolute, width, height, ""};
  array.layers = layers;
  array.mips = 2;
  array.clear.color.float32[0] = -1.0f;
  auto draw = [](uint32_t base) {
    return [base](const PassContext&) {
      struct {
        float base;
      } constants{float(base)};
      return constants;
    };
  };
  ImageDecl sum_decl{VK_FORMAT_R32_SFLOAT, kinds::colour};
  sum_decl.size = array.size;
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("layer0", PassType::graphics)
                       .write("array", Use::color_attachment, array, Subresources::at(0, 0))
                       .fullscreen("test/layer.frag", draw(0)));
  for (uint32_t l = 1; l < layers; ++l)
    passes.push_back(PassDecl("layer" + std::to_string(l), PassType::graphics)
                         .modify("array", Use::color_attachment, Subresources::at(0, l))
                         .fullscreen("test/layer.frag", draw(1000 * l)));
  // One more: mip 1 of layer 2 only.
  passes.push_back(PassDecl("mip1.layer2", PassType::graphics)
                       .modify("array", Use::color_attachment, Subresources::at(1, 2))
                       .fullscreen("test/layer.frag", draw(50000)));
  passes.push_back(PassDecl("sum", PassType::compute)
                       .read("array", Use::sampled)
                       .write("sum", Use::storage_write, sum_decl)
                       .run([](PassContext& ctx) {
                         ComputePipelineDesc desc;
                         desc.shader = "test/sum_layers.comp";
                         desc.bindings = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
                         ctx.bind(desc);
                         ctx.push({Binding::texture(0, "array", ctx.nearest_clamp()), Binding::image(1, "sum")});
                         vkCmdDispatch(ctx.cmd(), 2, 1, 1);
                       }));
  passes.back().shader("test/sum_layers.comp");
  CompiledGraph graph;
  const Execution execution = run_graph(passes, graph, "sum");
  const VersionData& final = *execution.final_version("array");
  for (uint32_t l = 0; l < layers; ++l) {
    const std::vector<float> mip0 = floats(final, 0, l);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x)
        ASSERT_EQ(mip0[y * width + x], layer_value(1000 * l, x, y)) << "layer " << l << " at " << x << "," << y;
    const std::vector<float> mip1 = floats(final, 1, l);
    for (uint32_t y = 0; y < height / 2; ++y)
      for (uint32_t x = 0; x < width / 2; ++x)
        ASSERT_EQ(mip1[y * width / 2 + x], l == 2 ? layer_value(50000, x, y) : -1.0f)
            << "mip 1 layer " << l << ": drawn by mip1.layer2 or left at the clear value";
  }
  // After layer0 ran, the other layers and mips hold the clear value.
  const VersionData& first = execution.versions[execution.passes[0].outputs[0]];
  EXPECT_EQ(floats(first, 0, 3)[5], -1.0f);
  EXPECT_EQ(floats(first, 0, 0)[5], layer_value(0, 5, 0));
  const std::vector<float> sum = floats(*execution.final_version("sum"), 0, 0);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      ASSERT_EQ(sum[y * width + x],
                layer_value(0, x, y) + layer_value(1000, x, y) + layer_value(2000, x, y) + layer_value(3000, x, y))
          << x << "," << y;
}

TEST_F(SubresourcesOnGpu, ThreeDimensionalImageWrittenByComputeAndHalvedIntoItsNextMip) {
  const uint32_t width = 16, height = 8, depth = 12;
  ImageDecl volume{VK_FORMAT_R32_SFLOAT, kinds::colour};
  volume.size = {SizeRule::Mode::absolute, width, height, ""};
  volume.depth = depth;
  volume.mips = 2;
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("fill", PassType::compute)
                       .write("volume", Use::storage_write, volume, Subresources::mip(0))
                       .shader("test/fill_volume.comp")
                       .run([](PassContext& ctx) {
                         ComputePipelineDesc desc;
                         desc.shader = "test/fill_volume.comp";
                         desc.bindings = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
                         ctx.bind(desc);
                         ctx.push({Binding::image(0, "volume", 0)});
                         vkCmdDispatch(ctx.cmd(), 4, 2, 3);
                       }));
  passes.push_back(PassDecl("halve", PassType::compute)
                       .read("volume", Use::sampled, Subresources::mip(0))
                       .modify("volume", Use::storage_write, Subresources::mip(1))
                       .shader("test/halve_volume.comp")
                       .run([](PassContext& ctx) {
                         ComputePipelineDesc desc;
                         desc.shader = "test/halve_volume.comp";
                         desc.bindings = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
                         ctx.bind(desc);
                         ctx.push({Binding::texture(0, "volume", ctx.nearest_clamp(), ViewAspect::natural, 0),
                                   Binding::image(1, "volume", 1)});
                         vkCmdDispatch(ctx.cmd(), 2, 1, 2);
                       }));
  CompiledGraph graph;
  const Execution execution = run_graph(passes, graph, "volume");
  const VersionData& result = *execution.final_version("volume");
  ASSERT_EQ(result.desc.extent.depth, depth);
  const std::vector<float> mip0 = floats(result, 0, 0), mip1 = floats(result, 1, 0);
  ASSERT_EQ(mip0.size(), size_t(width) * height * depth);
  auto f = [](uint32_t x, uint32_t y, uint32_t z) { return float(x + 100 * y + 10000 * z); };
  for (uint32_t z = 0; z < depth; ++z)
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x)
        ASSERT_EQ(mip0[(z * height + y) * width + x], f(x, y, z)) << x << "," << y << "," << z;
  ASSERT_EQ(mip1.size(), size_t(width / 2) * (height / 2) * (depth / 2));
  for (uint32_t z = 0; z < depth / 2; ++z)
    for (uint32_t y = 0; y < height / 2; ++y)
      for (uint32_t x = 0; x < width / 2; ++x) {
        // The mean of a 2×2×2 block of f is f at its centre: f(2x + ½, 2y + ½, 2z + ½).
        const float exact = float(2 * x + 0.5 + 100 * (2 * y + 0.5) + 10000 * (2 * z + 0.5));
        ASSERT_EQ(mip1[(z * (height / 2) + y) * (width / 2) + x], exact) << x << "," << y << "," << z;
      }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
