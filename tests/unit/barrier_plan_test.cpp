// The barrier plan of the compile step, per mip and layer: a mip written while another is
// sampled, a layer rendered while the others keep their contents, a whole-image use after
// per-mip ones, 3D images and cubes, the clears of a partly written image, readbacks, NaN
// injections, and the declaration mistakes that must be GraphErrors.
#include <gtest/gtest.h>

#include <algorithm>

#include "passes/core/graph.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr VkFormat kHalf = VK_FORMAT_R16G16B16A16_SFLOAT;

ImageDecl chain_decl(uint32_t mips) {
  ImageDecl d{kHalf, kinds::hdr_colour};
  d.size = {SizeRule::Mode::absolute, 64, 32, ""};
  d.mips = mips;
  return d;
}

const CompiledPass& pass(const CompiledGraph& graph, const std::string& name) {
  for (const CompiledPass& p : graph.passes)
    if (p.decl->name == name) return p;
  throw std::runtime_error("no pass " + name);
}

std::vector<PlannedBarrier> of(const std::vector<PlannedBarrier>& barriers, const std::string& resource) {
  std::vector<PlannedBarrier> found;
  for (const PlannedBarrier& b : barriers)
    if (b.resource == resource) found.push_back(b);
  return found;
}

GraphSettings sinks(std::vector<std::string> names) {
  GraphSettings settings;
  settings.sinks = std::move(names);
  return settings;
}

const VkAccessFlags2 kStorageWrite = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

// A bloom-like chain: level 0 written fresh, level i written while level i - 1 is sampled.
std::vector<PassDecl> chain_passes(uint32_t levels) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("level0", PassType::compute)
                       .write("chain", Use::storage_write, chain_decl(levels), Subresources::mip(0)));
  for (uint32_t i = 1; i < levels; ++i)
    passes.push_back(PassDecl("level" + std::to_string(i), PassType::compute)
                         .read("chain", Use::sampled, Subresources::mip(i - 1))
                         .modify("chain", Use::storage_write, Subresources::mip(i)));
  return passes;
}

TEST(BarrierPlan, MipWrittenWhileThePreviousIsSampled) {
  const std::vector<PassDecl> passes = chain_passes(3);
  const CompiledGraph graph = compile_graph(passes, {}, sinks({"chain"}));
  ASSERT_EQ(graph.passes.size(), 3u);
  EXPECT_EQ(graph.passes[1].decl->name, "level1");
  EXPECT_EQ(graph.passes[2].decl->name, "level2");

  // level0 writes mip 0 only: mips 1-2 are cleared first (one rectangle), from UNDEFINED.
  const PassSync& first = pass(graph, "level0").sync;
  ASSERT_EQ(first.clears.size(), 1u);
  EXPECT_EQ(first.clears[0].range, (Subresources{1, 2, 0, 1}));
  ASSERT_EQ(first.before_clears.size(), 1u);
  EXPECT_EQ(first.before_clears[0].plan.before.layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(first.before_clears[0].plan.after.layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  ASSERT_EQ(first.before_pass.size(), 1u);
  EXPECT_EQ(first.before_pass[0].range, (Subresources{0, 1, 0, 1}));
  EXPECT_EQ(first.before_pass[0].plan.before.layout, VK_IMAGE_LAYOUT_UNDEFINED);  // discarded
  EXPECT_EQ(first.before_pass[0].plan.after.layout, VK_IMAGE_LAYOUT_GENERAL);

  // level1: mip 0 from the storage write to sampled, mip 1 from the clear to storage; mip 2
  // is not touched.
  const CompiledPass& second = pass(graph, "level1");
  EXPECT_TRUE(second.sync.clears.empty());
  ASSERT_EQ(second.sync.before_pass.size(), 2u);
  for (const PlannedBarrier& b : second.sync.before_pass) {
    ASSERT_EQ(b.range.mip_count, 1u);
    if (b.range.base_mip == 0) {
      EXPECT_EQ(b.plan.before.layout, VK_IMAGE_LAYOUT_GENERAL);
      EXPECT_EQ(b.plan.before.stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
      EXPECT_EQ(b.plan.before.access, kStorageWrite);
      EXPECT_EQ(b.plan.after.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      EXPECT_EQ(b.plan.after.access, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    } else {
      EXPECT_EQ(b.range.base_mip, 1u);
      EXPECT_EQ(b.plan.before.layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);  // kept: modified, not discarded
      EXPECT_EQ(b.plan.before.access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
      EXPECT_EQ(b.plan.after.layout, VK_IMAGE_LAYOUT_GENERAL);
    }
  }
  // The sampled read is of the version before level1's own: level0's.
  ASSERT_EQ(second.inputs.size(), 1u) << "read and modify of one resource are one input";
  EXPECT_EQ(graph.passes[second.inputs[0].producer].decl->name, "level0");
  EXPECT_EQ(second.inputs[0].range, (Subresources{0, 1, 0, 1}));
  EXPECT_EQ(second.outputs[0].range, (Subresources{1, 1, 0, 1}));
}

TEST(BarrierPlan, WholeImageUseAfterPerMipUsesMergesTheirStates) {
  std::vector<PassDecl> passes = chain_passes(3);
  passes.push_back(PassDecl("reader", PassType::graphics)
                       .read("chain", Use::sampled)
                       .write("final.ldr", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, kinds::colour}));
  passes.push_back(PassDecl("reader2", PassType::graphics)
                       .read("chain", Use::sampled)
                       .write("other", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, kinds::colour}));
  GraphSettings settings = sinks({"final.ldr", "other"});
  const CompiledGraph graph = compile_graph(passes, {}, settings);

  // Mips 0 and 1 were sampled by compute (the fragment stage must still wait for their
  // writes), mip 2 was written as a storage image by level2: two barriers, not three.
  const auto reader = of(pass(graph, "reader").sync.before_pass, "chain");
  ASSERT_EQ(reader.size(), 2u);
  for (const PlannedBarrier& b : reader) {
    EXPECT_EQ(b.plan.after.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(b.plan.after.stages, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    EXPECT_EQ(b.plan.before.stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    if (b.range.base_mip == 0) {
      EXPECT_EQ(b.range, (Subresources{0, 2, 0, 1})) << "mips 0 and 1 moved alike: one barrier";
      EXPECT_EQ(b.plan.before.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      // The writes were made available by the barrier into the compute read; this one chains
      // on it (compute stage) and makes them visible to the fragment stage.
      EXPECT_EQ(b.plan.before.access, VK_ACCESS_2_NONE);
    } else {
      EXPECT_EQ(b.range, (Subresources{2, 1, 0, 1}));
      EXPECT_EQ(b.plan.before.layout, VK_IMAGE_LAYOUT_GENERAL);
      EXPECT_EQ(b.plan.before.access, kStorageWrite);
    }
  }
  // Now every mip is visible to the fragment stage: a second reader needs nothing.
  EXPECT_TRUE(of(pass(graph, "reader2").sync.before_pass, "chain").empty());
  // The final version of a resource to read back is copied after its last writer, whole.
  settings.readback = {"chain"};
  const CompiledGraph read_back = compile_graph(passes, {}, settings);
  const PassSync& last = pass(read_back, "level2").sync;
  ASSERT_EQ(last.readback, std::vector<std::string>{"chain"});
  EXPECT_TRUE(pass(read_back, "level1").sync.readback.empty());
  EXPECT_TRUE(pass(graph, "level2").sync.readback.empty());
  for (const PlannedBarrier& b : last.before_readback)
    EXPECT_EQ(b.plan.after.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  uint32_t covered = 0;
  for (const PlannedBarrier& b : last.before_readback) covered += b.range.mip_count * b.range.layer_count;
  EXPECT_EQ(covered, 3u);
}

TEST(BarrierPlan, EachLayerOfAnArrayRenderedByItsOwnPass) {
  ImageDecl array{VK_FORMAT_R32_SFLOAT, kinds::colour};
  array.layers = 4;
  std::vector<PassDecl> passes;
  passes.push_back(
      PassDecl("layer0", PassType::graphics).write("array", Use::color_attachment, array, Subresources::layer(0)));
  for (uint32_t l = 1; l < 4; ++l)
    passes.push_back(PassDecl("layer" + std::to_string(l), PassType::graphics)
                         .modify("array", Use::color_attachment, Subresources::layer(l)));
  passes.push_back(PassDecl("reader", PassType::compute)
                       .read("array", Use::sampled)
                       .write("out", Use::storage_write, ImageDecl{VK_FORMAT_R32_SFLOAT, kinds::colour}));
  const CompiledGraph graph = compile_graph(passes, {}, sinks({"out"}));

  ASSERT_EQ(pass(graph, "layer0").sync.clears.size(), 1u);
  EXPECT_EQ(pass(graph, "layer0").sync.clears[0].range, (Subresources{0, 1, 1, 3}));
  for (uint32_t l = 1; l < 4; ++l) {
    const auto barriers = of(pass(graph, "layer" + std::to_string(l)).sync.before_pass, "array");
    ASSERT_EQ(barriers.size(), 1u) << "layer " << l;
    EXPECT_EQ(barriers[0].range, (Subresources{0, 1, l, 1}));
    EXPECT_EQ(barriers[0].plan.before.layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL) << "the other layers' clear";
    EXPECT_EQ(barriers[0].plan.after.layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  }
  // Every layer was last written as an attachment: one barrier covers the array.
  const auto read = of(pass(graph, "reader").sync.before_pass, "array");
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].range, (Subresources{0, 1, 0, 4}));
  EXPECT_EQ(read[0].plan.before.layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  EXPECT_EQ(read[0].plan.before.stages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
  EXPECT_EQ(read[0].plan.after.stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
}

TEST(BarrierPlan, ThreeDimensionalImagesAreOneLayerWithDepthInTheirMips) {
  ImageDecl volume{VK_FORMAT_R32_SFLOAT, kinds::colour};
  volume.size = {SizeRule::Mode::absolute, 16, 8, ""};
  volume.depth = 32;
  volume.mips = 0;
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("fill", PassType::compute).write("volume", Use::storage_write, volume));
  GraphSettings settings = sinks({"volume"});
  settings.capture = true;
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  const ResourceDesc& desc = graph.resources.at("volume");
  EXPECT_EQ(desc.extent.depth, 32u);
  EXPECT_EQ(desc.extent.layers, 1u);
  EXPECT_EQ(desc.extent.mips, 6u) << "32 slices halve down to 1 over 6 levels";
  const PassSync& sync = pass(graph, "fill").sync;
  EXPECT_TRUE(sync.clears.empty());
  ASSERT_EQ(sync.before_pass.size(), 1u);
  EXPECT_EQ(sync.before_pass[0].range, (Subresources{0, 6, 0, 1}));
  ASSERT_EQ(sync.before_readback.size(), 1u);
  EXPECT_EQ(sync.before_readback[0].plan.before.access, kStorageWrite);

  passes.push_back(PassDecl("slice", PassType::compute).modify("volume", Use::storage_write, Subresources::layer(1)));
  settings.keep = {"slice"};
  EXPECT_THROW(compile_graph(passes, {}, settings), GraphError) << "a 3D image has one layer";
  volume.layers = 2;
  EXPECT_THROW(compile_graph({PassDecl("fill", PassType::compute).write("volume", Use::storage_write, volume)}, {},
                             sinks({"volume"})),
               GraphError)
      << "Vulkan has no 3D arrays";
}

TEST(BarrierPlan, CubeFacesAreLayers) {
  ImageDecl cube{kHalf, kinds::hdr_colour};
  cube.size = {SizeRule::Mode::absolute, 32, 32, ""};
  cube.layers = 6;
  cube.cube = true;
  std::vector<PassDecl> passes;
  passes.push_back(
      PassDecl("face0", PassType::graphics).write("probe", Use::color_attachment, cube, Subresources::layer(0)));
  passes.push_back(
      PassDecl("face3", PassType::graphics).modify("probe", Use::color_attachment, Subresources::layer(3)));
  const CompiledGraph graph = compile_graph(passes, {}, sinks({"probe"}));
  EXPECT_TRUE(graph.resources.at("probe").cube);
  // Faces 1-5 are cleared; face 3 then goes from that clear to an attachment alone.
  EXPECT_EQ(pass(graph, "face0").sync.clears[0].range, (Subresources{0, 1, 1, 5}));
  ASSERT_EQ(pass(graph, "face3").sync.before_pass.size(), 1u);
  EXPECT_EQ(pass(graph, "face3").sync.before_pass[0].range, (Subresources{0, 1, 3, 1}));

  ImageDecl oblong = cube;
  oblong.size.height = 16;
  EXPECT_THROW(compile_graph({PassDecl("p", PassType::graphics).write("probe", Use::color_attachment, oblong)}, {},
                             sinks({"probe"})),
               GraphError);
  ImageDecl four = cube;
  four.layers = 4;
  EXPECT_THROW(compile_graph({PassDecl("p", PassType::graphics).write("probe", Use::color_attachment, four)}, {},
                             sinks({"probe"})),
               GraphError);
}

TEST(BarrierPlan, SkippedPassClearsItsFreshOutputsWhole) {
  std::vector<PassDecl> passes = chain_passes(2);
  passes[0].can_disable("off for the test");
  passes[1].can_disable("off for the test");
  GraphSettings settings = sinks({"chain"});
  settings.params["level0"]["enabled"] = 0;
  settings.params["level1"]["enabled"] = 0;
  // Unread, the chain would not be cleared at all.
  EXPECT_TRUE(pass(compile_graph(passes, {}, settings), "level0").sync.clears.empty());
  settings.readback = {"chain"};
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  EXPECT_EQ(pass(graph, "level0").reason, "off for the test (level0.enabled=0)");
  ASSERT_EQ(pass(graph, "level0").sync.clears.size(), 1u);
  EXPECT_EQ(pass(graph, "level0").sync.clears[0].range, (Subresources{0, 2, 0, 1}));
  EXPECT_TRUE(pass(graph, "level0").sync.before_pass.empty());
  EXPECT_TRUE(pass(graph, "level1").sync.clears.empty()) << "a skipped modifier leaves the version it got";
  EXPECT_TRUE(pass(graph, "level1").sync.before_pass.empty());
}

TEST(BarrierPlan, UploadsComeFirstAndTwoUsesOfABufferWaitTogether) {
  ResourceDesc buffer;
  buffer.is_buffer = true;
  buffer.kind = kinds::buffer;
  buffer.buffer_size = 64;
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("draw", PassType::graphics)
                       .read("scene.geometry", Use::storage_read)
                       .read("scene.geometry", Use::index_buffer)
                       .write("final.ldr", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, kinds::colour}));
  const CompiledGraph graph = compile_graph(passes, {{"scene.geometry", buffer}}, GraphSettings());
  EXPECT_EQ(graph.uploads, std::vector<std::string>{"scene.geometry"});
  ASSERT_EQ(graph.before_uploads.size(), 1u) << "a first use is planned, so memory it takes over can be waited for";
  EXPECT_TRUE(graph.before_uploads[0].first_use);
  EXPECT_EQ(graph.before_uploads[0].plan.before, AccessState{}) << "nothing of the frame precedes it";
  const auto draw = of(pass(graph, "draw").sync.before_pass, "scene.geometry");
  ASSERT_EQ(draw.size(), 1u) << "the two reads of the buffer wait together for the upload";
  EXPECT_EQ(draw[0].plan.before.access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  EXPECT_EQ(draw[0].plan.after.layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(draw[0].plan.after.access, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT);
  EXPECT_NE(draw[0].plan.after.stages & VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, 0u);
  EXPECT_EQ(pass(graph, "draw").inputs.size(), 2u);
}

TEST(BarrierPlan, DeclarationMistakesAreGraphErrors) {
  auto message = [](const std::vector<PassDecl>& passes, const std::vector<std::string>& sink) {
    try {
      compile_graph(passes, {}, sinks(sink));
    } catch (const GraphError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // A mip beyond the chain.
  std::vector<PassDecl> beyond = chain_passes(2);
  beyond.push_back(PassDecl("level5", PassType::compute).modify("chain", Use::storage_write, Subresources::mip(5)));
  EXPECT_EQ(message(beyond, {"chain"}), "level5: mip 5 of 'chain' is outside the image (2 mips)");
  // Sampling and writing one mip at once.
  std::vector<PassDecl> feedback = chain_passes(1);
  feedback.push_back(PassDecl("loop", PassType::compute)
                         .read("chain", Use::sampled, Subresources::mip(0))
                         .modify("chain", Use::storage_write));
  EXPECT_NE(message(feedback, {"chain"}).find("loop: uses mip 0 layer 0 of 'chain' in two layouts"), std::string::npos);
  // A range on a buffer.
  std::vector<PassDecl> buffer;
  buffer.push_back(
      PassDecl("fill", PassType::compute).write("list", Use::storage_write, BufferDecl(kinds::buffer, 64)));
  buffer.push_back(PassDecl("use", PassType::compute)
                       .read("list", Use::storage_read, Subresources::mip(1))
                       .write("out", Use::storage_write, ImageDecl{VK_FORMAT_R32_SFLOAT, kinds::colour}));
  EXPECT_EQ(message(buffer, {"out"}), "use: 'list' is a buffer: a use of it has no mips or layers");
}

TEST(BarrierPlan, DeclaredMipsStopAtTheChainOfASmallImage) {
  ImageDecl tiny = chain_decl(6);
  tiny.size = {SizeRule::Mode::absolute, 3, 5, ""};
  const CompiledGraph graph =
      compile_graph({PassDecl("w", PassType::compute).write("chain", Use::storage_write, tiny)}, {}, sinks({"chain"}));
  EXPECT_EQ(graph.resources.at("chain").extent.mips, 3u) << "5, 2, 1";
}

TEST(BarrierPlan, NanInjectionWritesOneSubresourceBetweenThePassAndItsReadback) {
  const std::vector<PassDecl> passes = chain_passes(2);
  GraphSettings settings = sinks({"chain"});
  settings.capture = true;
  settings.nan_injections = {{"level0", "chain", 3, 4}};
  const CompiledGraph graph = compile_graph(passes, {}, settings);

  const PassSync& level0 = pass(graph, "level0").sync;
  EXPECT_EQ(level0.injections, settings.nan_injections);
  ASSERT_EQ(level0.before_injections.size(), 1u);
  const PlannedBarrier& inject = level0.before_injections[0];
  EXPECT_EQ(inject.range, Subresources::at(0, 0));
  EXPECT_EQ(inject.plan.before.layout, VK_IMAGE_LAYOUT_GENERAL) << "the texels around it are kept";
  EXPECT_EQ(inject.plan.before.stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(inject.plan.before.access, kStorageWrite);
  EXPECT_EQ(inject.plan.after, transfer_state(true));
  // The readback of the version waits for the injected texel: mip 0 now moves from the transfer
  // write as the cleared mip 1 does, so both go in one barrier.
  const auto readback = of(level0.before_readback, "chain");
  ASSERT_EQ(readback.size(), 1u);
  EXPECT_EQ(readback[0].range, (Subresources{0, 2, 0, 1}));
  EXPECT_EQ(readback[0].plan.before, transfer_state(true));
  EXPECT_EQ(readback[0].plan.after, transfer_state(false));
  EXPECT_TRUE(pass(graph, "level1").sync.injections.empty());
  EXPECT_TRUE(pass(graph, "level1").sync.before_injections.empty());
}

TEST(BarrierPlan, NanInjectionIsVisibleToTheNextReaderWithoutACapture) {
  const std::vector<PassDecl> passes = chain_passes(2);
  GraphSettings settings = sinks({"chain"});
  settings.nan_injections = {{"level0", "chain", 0, 0}};
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  EXPECT_TRUE(pass(graph, "level0").sync.before_readback.empty());
  const auto reader = of(pass(graph, "level1").sync.before_pass, "chain");
  const auto mip0 = std::find_if(reader.begin(), reader.end(), [](const auto& b) { return b.range.base_mip == 0; });
  ASSERT_NE(mip0, reader.end());
  EXPECT_EQ(mip0->plan.before.layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  EXPECT_EQ(mip0->plan.before.stages, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT);
  EXPECT_EQ(mip0->plan.before.access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  EXPECT_EQ(mip0->plan.after.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

TEST(BarrierPlan, NanInjectionMistakesAreGraphErrors) {
  std::vector<PassDecl> passes = chain_passes(2);
  passes[1].can_disable("off for the test");
  passes.push_back(PassDecl("ldr", PassType::graphics)
                       .read("chain", Use::sampled)
                       .write("final.ldr", Use::color_attachment, ImageDecl{VK_FORMAT_R8G8B8A8_UNORM, kinds::colour})
                       .write("list", Use::storage_write, BufferDecl(kinds::buffer, 64)));
  auto message = [&](const NanInjection& nan) {
    GraphSettings settings = sinks({"final.ldr", "list"});
    settings.params["level1"]["enabled"] = 0;
    settings.nan_injections = {nan};
    try {
      compile_graph(passes, {}, settings);
    } catch (const GraphError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({"level0", "chain", 63, 31}), "no error");
  EXPECT_EQ(message({"nowhere", "chain", 0, 0}), "NaN injection into nowhere (chain): no such pass");
  EXPECT_EQ(message({"level1", "chain", 0, 0}),
            "NaN injection into level1 (chain): the pass does not run (off for the test (level1.enabled=0))");
  EXPECT_EQ(message({"ldr", "final.ldr", 0, 0}),
            "NaN injection into ldr (final.ldr): not a float colour image the pass writes");
  EXPECT_EQ(message({"ldr", "list", 0, 0}), "NaN injection into ldr (list): not a float colour image the pass writes");
  EXPECT_EQ(message({"ldr", "chain", 0, 0}), "NaN injection into ldr (chain): not a float colour image the pass writes")
      << "an input is not an output";
  EXPECT_EQ(message({"level0", "chain", 64, 0}),
            "NaN injection into level0 (chain): texel (64, 0) is outside its 64x32 mip 0");
  EXPECT_EQ(message({"level0", "chain", 0, 32}),
            "NaN injection into level0 (chain): texel (0, 32) is outside its 64x32 mip 0");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
