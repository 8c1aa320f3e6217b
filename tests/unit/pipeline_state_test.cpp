// Declared pipeline state (passes/core/pipeline_state.h) reaches both the pipeline and the
// description the capture records, and changes what is rendered as Vulkan says it must: one
// triangle over an 8×8 target, in fullscreen.vert's winding (clockwise in framebuffer space,
// so back-facing under a counter-clockwise front face), at depth `depth` + `slope`·x (NDC).
// Targets are cleared to colour 0.25, depth 0.25 and stencil 0; the triangle writes colour 0.5
// and the stencil reference 7.
#include <algorithm>
#include <cstring>
#include <regex>

#include "passes/core/context.h"
#include "passes/core/declared_pipeline.h"
#include "passes/core/shader.h"
#include "passes/core/shader_sources.h"
#include "passes/depth/kinds.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kSize = 8;

const std::map<std::string, std::string> kSources = {{"test/triangle.vert", R"(#version 460
layout(push_constant) uniform Constants { float depth, slope; };
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
  gl_Position = vec4(p, depth + slope * p.x, 1.0);
})"},
                                                     {"test/triangle.frag", R"(#version 460
layout(location = 0) out vec4 colour;
void main() { colour = vec4(0.5); })"}};

struct TriangleConstants {
  float depth, slope;
};

// The pass under test: `declare` adds the state.
PassDecl triangle_pass(const std::function<void(PassDecl&)>& declare) {
  ImageDecl colour{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour};
  for (int c = 0; c < 4; ++c) colour.clear.color.float32[c] = 0.25f;
  ImageDecl depth{VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil};
  depth.clear.depthStencil = {0.25f, 0};
  PassDecl pass("test.triangle", PassType::graphics);
  pass.write("colour", Use::color_attachment, colour)
      .write("depth", Use::depth_attachment, depth)
      .param_float("depth", 0.5, 0.0, 1.0, "depth of the triangle")
      .param_float("slope", 0.0, -1.0, 1.0, "depth change per NDC unit of x")
      .push_constants<TriangleConstants>()
      .shader("test/triangle.vert")
      .shader("test/triangle.frag")
      .run([](PassContext& ctx) {
        ctx.begin_rendering();
        ctx.bind_pipeline();
        vkCmdSetStencilReference(ctx.cmd(), VK_STENCIL_FACE_FRONT_AND_BACK, 7);
        ctx.push_constants(TriangleConstants{float(ctx.param_float("depth")), float(ctx.param_float("slope"))});
        vkCmdDraw(ctx.cmd(), 3, 1, 0, 0);
        ctx.end_rendering();
      });
  declare(pass);
  return pass;
}

struct Target {
  std::vector<uint16_t> colour;  // half-float codes, RGBA per pixel
  std::vector<float> depth;
  std::vector<uint8_t> stencil;
  nlohmann::json pipeline;  // as the capture records it
};

class PipelineState : public GpuTest {
 protected:
  static Target draw(const std::function<void(PassDecl&)>& declare, ParamValues params = {}) {
    const PassDecl pass = triangle_pass(declare);
    const IsolatedRun run = run_isolated(*gpu_, *cache_, pass, {}, params, kSize, kSize,
                                         [](const std::string&, const std::string& path, const std::string& bindings) {
                                           return compile_glsl(path, kSources.at(path), bindings);
                                         });
    Target t;
    const auto& colour = *run.outputs.at("colour");
    t.colour.resize(colour.size() / 2);
    std::memcpy(t.colour.data(), colour.data(), colour.size());
    const auto& depth = *run.outputs.at("depth");
    const FormatInfo f = *format_info(VK_FORMAT_D32_SFLOAT_S8_UINT);
    const ImageExtent extent = run.output_descs.at("depth").extent;
    const uint64_t stencil_offset = raw_subresource_offset(f, extent, 1, 0, 0);
    t.depth.resize(kSize * kSize);
    std::memcpy(t.depth.data(), depth.data(), t.depth.size() * 4);
    t.stencil.assign(depth.begin() + stencil_offset, depth.begin() + stencil_offset + kSize * kSize);
    t.pipeline = run.execution.passes.at(0).pipelines.at(0);
    return t;
  }
};

constexpr uint16_t kHalfQuarter = 0x3400, kHalfHalf = 0x3800, kHalfThreeQuarters = 0x3A00;

void expect_every_pixel(const Target& t, uint16_t colour, float depth, uint8_t stencil) {
  for (uint32_t i = 0; i < kSize * kSize; ++i) {
    for (int c = 0; c < 4; ++c) ASSERT_EQ(t.colour[4 * i + c], colour) << "pixel " << i << " channel " << c;
    ASSERT_EQ(t.depth[i], depth) << "pixel " << i;
    ASSERT_EQ(t.stencil[i], stencil) << "pixel " << i;
  }
}

TEST_F(PipelineState, EveryDeclaredStateIsRecorded) {
  const Target t = draw([](PassDecl& p) {
    RasterState raster;
    raster.cull_mode = VK_CULL_MODE_FRONT_BIT;
    raster.front_face = VK_FRONT_FACE_CLOCKWISE;
    raster.depth_bias = {3.0f, 1.5f, 0.25f};
    DepthStencilState depth = DepthStencilState::depth(VK_COMPARE_OP_ALWAYS, true).writing_stencil();
    depth.stencil_write_mask = 0x0f;
    p.raster(raster).depth_stencil(depth).blend("colour", BlendState::additive());
  });
  const nlohmann::json& d = t.pipeline;
  EXPECT_EQ(d.at("vertex"), "test/triangle.vert");
  EXPECT_EQ(d.at("fragment"), "test/triangle.frag");
  EXPECT_EQ(d.at("push_constant_bytes"), sizeof(TriangleConstants));
  EXPECT_EQ(d.at("color_formats"), nlohmann::json::array({"R16G16B16A16_SFLOAT"}));
  EXPECT_EQ(d.at("blend")[0].at("enabled"), true);
  EXPECT_EQ(d.at("blend")[0].at("color"), (nlohmann::json{{"src", "one"}, {"dst", "one"}, {"op", "add"}}));
  EXPECT_EQ(d.at("blend")[0].at("write_mask"), "rgba");
  EXPECT_EQ(d.at("raster").at("cull_mode"), "front");
  EXPECT_EQ(d.at("raster").at("front_face"), "clockwise");
  EXPECT_EQ(d.at("raster").at("per_draw_faces"), false);
  EXPECT_EQ(d.at("raster").at("depth_bias"), (nlohmann::json{{"constant", 3.0}, {"slope", 1.5}, {"clamp", 0.25}}));
  EXPECT_EQ(d.at("depth"),
            (nlohmann::json{{"format", "D32_SFLOAT_S8_UINT"}, {"test", true}, {"write", true}, {"compare", "always"}}));
  EXPECT_EQ(d.at("stencil").at("write"), true);
  EXPECT_EQ(d.at("stencil").at("write_mask"), 0x0f);
  EXPECT_EQ(d.at("dynamic_state"), nlohmann::json::array({"viewport", "scissor", "stencil_reference"}));
}

TEST_F(PipelineState, TheDefaultsDrawEverythingAndWriteNothingButColour) {
  // No depth test, no depth or stencil write, no culling, no blending.
  expect_every_pixel(draw([](PassDecl&) {}), kHalfHalf, 0.25f, 0);
}

TEST_F(PipelineState, AdditiveBlendingAddsToTheTarget) {
  const Target t = draw([](PassDecl& p) { p.blend("colour", BlendState::additive()); });
  expect_every_pixel(t, kHalfThreeQuarters, 0.25f, 0);  // 0.5 + 0.25
}

TEST_F(PipelineState, CullingFollowsTheDeclaredModeAndFrontFace) {
  auto cull = [](VkCullModeFlags mode, VkFrontFace front) {
    return [=](PassDecl& p) { p.raster({mode, front, false, {}}); };
  };
  // Clockwise in framebuffer space: back-facing under counter-clockwise, front-facing under clockwise.
  expect_every_pixel(draw(cull(VK_CULL_MODE_BACK_BIT, VK_FRONT_FACE_COUNTER_CLOCKWISE)), kHalfQuarter, 0.25f, 0);
  expect_every_pixel(draw(cull(VK_CULL_MODE_NONE, VK_FRONT_FACE_COUNTER_CLOCKWISE)), kHalfHalf, 0.25f, 0);
  expect_every_pixel(draw(cull(VK_CULL_MODE_BACK_BIT, VK_FRONT_FACE_CLOCKWISE)), kHalfHalf, 0.25f, 0);
  expect_every_pixel(draw(cull(VK_CULL_MODE_FRONT_BIT, VK_FRONT_FACE_CLOCKWISE)), kHalfQuarter, 0.25f, 0);
}

TEST_F(PipelineState, DepthTestCompareOpAndStencilWriteAreHonoured) {
  auto depth = [](VkCompareOp op, bool stencil) {
    return [=](PassDecl& p) {
      const DepthStencilState state = DepthStencilState::depth(op, true);
      p.depth_stencil(stencil ? state.writing_stencil() : state);
    };
  };
  // The triangle (0.5) is in front of the cleared 0.25 under reversed-Z: GREATER passes, LESS fails.
  expect_every_pixel(draw(depth(VK_COMPARE_OP_GREATER, false)), kHalfHalf, 0.5f, 0);
  expect_every_pixel(draw(depth(VK_COMPARE_OP_GREATER, true)), kHalfHalf, 0.5f, 7);
  expect_every_pixel(draw(depth(VK_COMPARE_OP_LESS, true)), kHalfQuarter, 0.25f, 0);
  // Tested but not written.
  expect_every_pixel(draw([](PassDecl& p) { p.depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_GREATER, false)); }),
                     kHalfHalf, 0.25f, 0);
}

TEST_F(PipelineState, DepthBiasMovesDepthByTheDeclaredAmount) {
  auto biased = [](float constant, float slope) {
    return [=](PassDecl& p) {
      RasterState raster;
      raster.depth_bias = {constant, slope, 0.0f};
      p.raster(raster).depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_ALWAYS, true));
    };
  };
  // Constant: r = 2^(e − 23) for a float depth buffer, e the exponent of the primitive's largest
  // depth (0.5 = 2^-1): 1024 units are 2^-14.
  expect_every_pixel(draw(biased(1024.0f, 0.0f)), kHalfHalf, 0.5f + 0x1p-14f, 0);
  // The clamp limits it.
  expect_every_pixel(draw([](PassDecl& p) {
                       RasterState raster;
                       raster.depth_bias = {1024.0f, 0.0f, 0x1p-16f};
                       p.raster(raster).depth_stencil(DepthStencilState::depth(VK_COMPARE_OP_ALWAYS, true));
                     }),
                     kHalfHalf, 0.5f + 0x1p-16f, 0);
  // Slope: depth 0.5 + x/64 over NDC x, so ∂z/∂x is (1/64)·(2/8) = 2^-8 per pixel; slope factor 4
  // adds 2^-6 on top of each pixel's unbiased depth.
  const Target flat = draw(biased(0.0f, 0.0f), {{"slope", 1.0 / 64}});
  const Target sloped = draw(biased(0.0f, 4.0f), {{"slope", 1.0 / 64}});
  for (uint32_t i = 0; i < kSize * kSize; ++i) {
    const float x = ((i % kSize) + 0.5f) / kSize * 2.0f - 1.0f;
    ASSERT_EQ(flat.depth[i], 0.5f + x / 64) << "pixel " << i;
    ASSERT_NEAR(sloped.depth[i], flat.depth[i] + 0x1p-6f, 0x1p-22f) << "pixel " << i;
  }
}

// The pipeline a declaration implies, without a device: every fact from one place.
TEST(DeclaredPipeline, LayoutFormatsShadersAndConstantsComeFromTheDeclaration) {
  ImageDecl colour{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour};
  PassDecl pass("test.declared", PassType::graphics);
  pass.read("constants", Use::uniform_buffer)
      .read("list", Use::storage_read)
      .read("host.only", Use::host)
      .read_all("texture.", Use::sampled)
      .slots("texture.", 3)
      .read("depth", Use::depth_attachment)
      .write("lit", Use::color_attachment, colour)
      .write("extra", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, kinds::colour})
      .blend("extra", BlendState::additive())
      .push_constants<TriangleConstants>()
      .shader("test/a.vert")
      .shader("test/a.frag");
  std::map<std::string, ResourceDesc> descs;
  descs["list"].is_buffer = true;
  descs["depth"].format = VK_FORMAT_D32_SFLOAT;
  descs["lit"].format = VK_FORMAT_R16G16B16A16_SFLOAT;
  descs["extra"].format = VK_FORMAT_R8G8B8A8_UNORM;
  const GraphicsPipelineDesc desc =
      declared_graphics_pipeline(pass, [&](const std::string& r) -> const ResourceDesc& { return descs.at(r); });
  EXPECT_EQ(desc.vertex, "test/a.vert");
  EXPECT_EQ(desc.fragment, "test/a.frag");
  EXPECT_EQ(desc.bindings, (std::vector<VkDescriptorType>{
                               VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                               VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                               VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}));
  EXPECT_EQ(desc.color_formats, (std::vector<VkFormat>{VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM}));
  ASSERT_EQ(desc.blend.size(), 2u);
  EXPECT_FALSE(desc.blend[0].enabled);
  EXPECT_TRUE(desc.blend[1].enabled);
  EXPECT_EQ(desc.depth_format, VK_FORMAT_D32_SFLOAT);
  EXPECT_EQ(desc.push_constant_bytes, sizeof(TriangleConstants));
  EXPECT_EQ(colour_targets(pass), (std::vector<std::string>{"lit", "extra"}));
  EXPECT_EQ(depth_target(pass), "depth");
  EXPECT_THROW(pass.blend("depth", BlendState::additive()), std::logic_error);
}

// What each declared slot binds, without a device: a pass writes no resource name on a binding line.
TEST(DeclaredPipeline, BindingsComeFromTheDeclaredUses) {
  ImageDecl chain{VK_FORMAT_R32_SFLOAT, kinds::depth_minmax};
  chain.mips = 4;
  const SamplerDesc bilinear_repeat;  // SamplerDesc's defaults, unlike the nearest clamp-to-edge default
  PassDecl pass("test.bindings", PassType::compute);
  pass.read("constants", Use::uniform_buffer)
      .read("list", Use::storage_read)
      .read("host.only", Use::host)
      .read("depth", Use::sampled)
      .aspects("depth", {ViewAspect::depth, ViewAspect::stencil})
      .read_previous("exposure", Use::sampled)
      .read("moments", Use::sampled, Subresources::mip(2))
      .sampler("moments", bilinear_repeat)
      .write("pyramid", Use::storage_write, chain, Subresources::mip(3));
  std::map<std::string, ResourceDesc> descs;
  descs["list"].is_buffer = true;
  descs["pyramid"].format = VK_FORMAT_R32_SFLOAT;
  const DescOf desc_of = [&](const std::string& r) -> const ResourceDesc& { return descs.at(r); };
  // Each sampler asked for gets a handle of its own: handle i + 1 is made[i].
  std::vector<SamplerDesc> made;
  const auto sampler_of = [&](const SamplerDesc& desc) {
    made.push_back(desc);
    return reinterpret_cast<VkSampler>(uintptr_t(made.size()));
  };
  const std::vector<Binding> bindings = declared_bindings(pass, desc_of, sampler_of);
  ASSERT_EQ(bindings.size(), 7u);
  struct Expected {
    VkDescriptorType type;
    std::string resource;
    ViewAspect aspect;
    int mip;
  };
  const std::vector<Expected> expected{
      {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, "constants", ViewAspect::natural, -1},
      {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, "list", ViewAspect::natural, -1},
      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, "depth", ViewAspect::depth, -1},
      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, "depth", ViewAspect::stencil, -1},
      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, previous("exposure"), ViewAspect::natural, -1},
      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, "moments", ViewAspect::natural, 2},
      {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, "pyramid", ViewAspect::natural, 3}};
  for (uint32_t i = 0; i < bindings.size(); ++i) {
    SCOPED_TRACE(expected[i].resource);
    EXPECT_EQ(bindings[i].binding, i);  // the layout's slot: declared_layout numbers them alike
    EXPECT_EQ(bindings[i].type, expected[i].type);
    EXPECT_EQ(bindings[i].resource, expected[i].resource);
    EXPECT_EQ(bindings[i].aspect, expected[i].aspect);
    EXPECT_EQ(bindings[i].mip, expected[i].mip);
    EXPECT_EQ(bindings[i].layer, -1);
    EXPECT_EQ(bindings[i].sampler == VK_NULL_HANDLE, expected[i].type != VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  }
  EXPECT_EQ(declared_layout(pass, desc_of).size(), bindings.size());
  auto sampler_at = [&](uint32_t i) { return made.at(reinterpret_cast<uintptr_t>(bindings[i].sampler) - 1); };
  for (uint32_t i : {2u, 3u, 4u}) {
    EXPECT_EQ(sampler_at(i).mag_filter, VK_FILTER_NEAREST);
    EXPECT_EQ(sampler_at(i).wrap_u, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  }
  EXPECT_EQ(bindings[2].sampler, bindings[3].sampler);  // one sampler for both aspects
  EXPECT_EQ(sampler_at(5).mag_filter, VK_FILTER_LINEAR);
  EXPECT_EQ(sampler_at(5).wrap_u, VK_SAMPLER_ADDRESS_MODE_REPEAT);

  EXPECT_THROW(pass.sampler("list", bilinear_repeat), std::logic_error);
}

// Choices that change per dispatch or per draw are declared too: the mips a level's dispatch
// binds, and the slots a prefix read's textures take.
TEST(DeclaredPipeline, PerLevelMipsAndPerDrawTexturesAreDeclared) {
  ImageDecl chain{VK_FORMAT_R32G32_SFLOAT, kinds::depth_minmax};
  chain.mips = 0;
  PassDecl pyramid("test.pyramid", PassType::compute);
  pyramid.read("source", Use::sampled)
      .write("chain", Use::storage_write, chain)
      .level_mips("chain", {-1, 0})
      .read_all("texture.", Use::sampled)
      .slots("texture.", 2);
  std::map<std::string, ResourceDesc> descs;
  descs["chain"].format = VK_FORMAT_R32G32_SFLOAT;
  const DescOf desc_of = [&](const std::string& r) -> const ResourceDesc& { return descs.at(r); };
  const auto sampler_of = [](const SamplerDesc&) { return reinterpret_cast<VkSampler>(uintptr_t(1)); };
  // Inputs, then outputs: source, the two textures, the chain twice.
  EXPECT_EQ(declared_layout(pyramid, desc_of).size(), 5u);
  // A level's mips need the level.
  EXPECT_THROW(declared_bindings(pyramid, desc_of, sampler_of), GraphError);
  for (uint32_t level : {0u, 3u}) {
    SCOPED_TRACE(level);
    const std::vector<Binding> bindings = declared_bindings(pyramid, desc_of, sampler_of, level);
    ASSERT_EQ(bindings.size(), 3u);  // the prefix read's textures are pushed per draw
    EXPECT_EQ(bindings[0].resource, "source");
    for (uint32_t i : {1u, 2u}) {
      EXPECT_EQ(bindings[i].binding, i + 2);
      EXPECT_EQ(bindings[i].resource, "chain");
      EXPECT_EQ(bindings[i].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    }
    EXPECT_EQ(bindings[1].mip, level == 0 ? 0 : int(level) - 1);  // no level above 0: clamped to it
    EXPECT_EQ(bindings[2].mip, int(level));
  }
  const DeclaredSlot textures = prefix_slot(pyramid, desc_of);
  EXPECT_EQ(textures.first, 1u);
  EXPECT_EQ(textures.count, 2u);
  EXPECT_THROW(prefix_slot(PassDecl("test.none", PassType::graphics), desc_of), GraphError);
  EXPECT_THROW(pyramid.level_mips("missing", {0}), std::logic_error);
}

// The bindings a declared pass gives its shaders, in the order declared_layout numbers them.
std::vector<uint32_t> decorated_bindings(const std::vector<uint32_t>& spirv) {
  constexpr uint32_t kOpDecorate = 71, kDecorationBinding = 33;
  std::vector<uint32_t> bindings;
  for (size_t i = 5; i < spirv.size(); i += spirv[i] >> 16) {
    if ((spirv[i] & 0xffff) == kOpDecorate && spirv[i + 2] == kDecorationBinding) bindings.push_back(spirv[i + 3]);
    if ((spirv[i] >> 16) == 0) break;
  }
  return bindings;
}

// Shaders name each binding by the use it binds, NC_BINDING(name): the number comes from the
// declaration, so a shader never repeats its order.
TEST(DeclaredPipeline, ShadersNameTheirBindingsByTheDeclaredUse) {
  PassDecl pass("test.named", PassType::compute);
  pass.read("frame.constants", Use::uniform_buffer)
      .read("host.only", Use::host)
      .read_all("scene.texture.", Use::sampled)
      .slots("scene.texture.", 2)
      .read_previous("exposure.value", Use::sampled)
      .read("chain", Use::sampled, Subresources::mip(0))
      .as("source")
      .modify("chain", Use::storage_write, Subresources::mip(1))
      .shader("test/named.comp");
  std::map<std::string, ResourceDesc> descs;
  descs["chain"].format = VK_FORMAT_R16G16B16A16_SFLOAT;
  const DescOf desc_of = [&](const std::string& r) -> const ResourceDesc& { return descs.at(r); };
  const std::string defines = binding_defines(pass, desc_of);
  for (const char* line : {"#define NC_BINDING_frame_constants 0\n", "#define NC_BINDING_scene_texture 1\n",
                           "#define NC_BINDING_exposure_value_previous 3\n", "#define NC_BINDING_source 4\n",
                           "#define NC_BINDING_chain 5\n"})
    EXPECT_NE(defines.find(line), std::string::npos) << line << " in\n" << defines;

  const std::string shader = R"(#version 460
layout(local_size_x = 1) in;
layout(set = 0, binding = NC_BINDING(scene_texture) + 1) uniform sampler2D second_texture;
layout(set = 0, binding = NC_BINDING(source)) uniform sampler2D source;
layout(set = 0, binding = NC_BINDING(chain), rgba16f) uniform writeonly image2D chain;
void main() { imageStore(chain, ivec2(0), texelFetch(source, ivec2(0), 0) + texelFetch(second_texture, ivec2(0), 0)); }
)";
  std::vector<uint32_t> bindings = decorated_bindings(compile_glsl("test/named.comp", shader, defines));
  std::sort(bindings.begin(), bindings.end());
  EXPECT_EQ(bindings, (std::vector<uint32_t>{2, 4, 5}));

  // A name the pass does not declare fails the compile and is named.
  try {
    compile_glsl("test/named.comp",
                 "#version 460\nlayout(local_size_x = 1) in;\n"
                 "layout(set = 0, binding = NC_BINDING(missing)) uniform sampler2D m;\n"
                 "void main() {}\n",
                 defines);
    ADD_FAILURE() << "compiled a binding the pass does not declare";
  } catch (const ShaderError& e) {
    EXPECT_NE(std::string(e.what()).find("NC_BINDING_missing"), std::string::npos) << e.what();
  }

  // A name two uses share binds neither; names GLSL cannot spell are refused.
  PassDecl twice("test.twice", PassType::compute);
  twice.read("chain", Use::sampled, Subresources::mip(0)).modify("chain", Use::storage_write, Subresources::mip(1));
  try {
    compile_glsl("test/twice.comp",
                 "#version 460\nlayout(local_size_x = 1) in;\n"
                 "layout(set = 0, binding = NC_BINDING(chain)) uniform sampler2D m;\nvoid main() {}\n",
                 binding_defines(twice, desc_of));
    ADD_FAILURE() << "compiled a binding two uses share";
  } catch (const ShaderError& e) {
    EXPECT_NE(std::string(e.what()).find("chain_is_bound_twice_name_one_use_with_as"), std::string::npos) << e.what();
  }
  EXPECT_THROW(PassDecl("test.bad", PassType::compute).read("a", Use::sampled).as("a.b"), std::logic_error);
  EXPECT_THROW(PassDecl("test.bad", PassType::compute).as("a"), std::logic_error);
}

// Every built-in shader takes its bindings from its pass's declaration.
TEST(DeclaredPipeline, NoBuiltInShaderNumbersABinding) {
  const std::regex numbered(R"(binding\s*=\s*[0-9])");
  for (const auto& [path, source] : embedded_shader_sources())
    EXPECT_FALSE(std::regex_search(source, numbered)) << path << " numbers a binding: write NC_BINDING(name)";
}
}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
