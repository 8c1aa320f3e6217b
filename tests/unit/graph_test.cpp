// The render graph's compile step: ordering, culling, skip reasons, sizes, barriers.
// (Over 600 lines: the compile step's cases, sharing the declarations they compile.)
#include <gtest/gtest.h>

#include "passes/core/graph.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

ImageDecl image(VkFormat format = VK_FORMAT_R8G8B8A8_UNORM) { return ImageDecl{format, kinds::colour}; }

std::vector<std::string> order(const CompiledGraph& graph) {
  std::vector<std::string> names;
  for (const CompiledPass& p : graph.passes) names.push_back(p.decl->name);
  return names;
}

const CompiledPass& pass(const CompiledGraph& graph, const std::string& name) {
  for (const CompiledPass& p : graph.passes)
    if (p.decl->name == name) return p;
  throw std::runtime_error("no pass " + name);
}

TEST(Graph, OrdersByDependenciesWhateverTheDeclarationOrder) {
  std::vector<PassDecl> passes;
  passes.push_back(
      PassDecl("c", PassType::graphics).read("b.out", Use::sampled).write("final.ldr", Use::color_attachment, image()));
  passes.push_back(
      PassDecl("b", PassType::graphics).read("a.out", Use::sampled).write("b.out", Use::color_attachment, image()));
  passes.push_back(PassDecl("a", PassType::graphics).write("a.out", Use::color_attachment, image()));
  const CompiledGraph graph = compile_graph(passes, {}, GraphSettings());
  EXPECT_EQ(order(graph), (std::vector<std::string>{"a", "b", "c"}));
}

// An optional input is read where a pass writes it (or it is imported), and is no input at all
// where nothing does: no dependency, no binding.
TEST(Graph, OptionalInputsAreConnectedWhereTheFrameHasThem) {
  const PassDecl reader = PassDecl("reader", PassType::compute)
                              .read("lit", Use::sampled)
                              .read_optional("ao", Use::sampled)
                              .write("final.ldr", Use::storage_write, image());
  std::vector<PassDecl> passes{reader, PassDecl("lit", PassType::compute).write("lit", Use::storage_write, image())};
  auto inputs_of_reader = [](const CompiledGraph& graph) {
    std::vector<std::string> names;
    for (const BoundUse& in : pass(graph, "reader").inputs) names.push_back(in.resource);
    return names;
  };
  const CompiledGraph without = compile_graph(passes, {}, GraphSettings());
  EXPECT_EQ(inputs_of_reader(without), (std::vector<std::string>{"lit"}));
  ASSERT_TRUE(without.connected);
  EXPECT_EQ(pass(without, "reader").decl->inputs.size(), 1u);
  EXPECT_EQ(passes[0].inputs.size(), 2u);  // the caller's declaration is left as it was

  passes.push_back(PassDecl("ao", PassType::compute).write("ao", Use::storage_write, image()));
  const CompiledGraph with = compile_graph(passes, {}, GraphSettings());
  EXPECT_EQ(inputs_of_reader(with), (std::vector<std::string>{"lit", "ao"}));
  EXPECT_EQ(order(with).back(), "reader");
  EXPECT_FALSE(with.connected);

  // Imported, as a replay imports what the capture recorded.
  ResourceDesc desc;
  desc.format = VK_FORMAT_R8G8B8A8_UNORM;
  desc.extent = {4, 4, 1, 1, 1};
  const std::vector<PassDecl> alone{reader};
  const CompiledGraph imported = compile_graph(alone, {{"lit", desc}, {"ao", desc}}, GraphSettings());
  EXPECT_EQ(inputs_of_reader(imported), (std::vector<std::string>{"lit", "ao"}));
}

TEST(Graph, ModifiersChainAndReadersSeeTheLastVersion) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("reader", PassType::graphics)
                       .read("depth", Use::sampled)
                       .write("final.ldr", Use::color_attachment, image()));
  passes.push_back(PassDecl("second", PassType::graphics).modify("depth", Use::depth_attachment));
  passes.push_back(
      PassDecl("first", PassType::graphics).write("depth", Use::depth_attachment, image(VK_FORMAT_D32_SFLOAT_S8_UINT)));
  const CompiledGraph graph = compile_graph(passes, {}, GraphSettings());
  EXPECT_EQ(order(graph), (std::vector<std::string>{"first", "second", "reader"}));
  const CompiledPass& second = pass(graph, "second");
  ASSERT_EQ(second.inputs.size(), 1u);
  EXPECT_EQ(second.inputs[0].resource, "depth");
  EXPECT_EQ(graph.passes[second.inputs[0].producer].decl->name, "first");
  EXPECT_EQ(graph.passes[pass(graph, "reader").inputs[0].producer].decl->name, "second");
}

TEST(Graph, CullsPassesNobodyConsumesAndSkipsMissingFeatures) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("orphan", PassType::graphics).write("unused", Use::color_attachment, image()));
  passes.push_back(
      PassDecl("shadows", PassType::graphics).needs("sun").write("shadow", Use::color_attachment, image()));
  passes.push_back(PassDecl("final", PassType::graphics)
                       .read("shadow", Use::sampled)
                       .write("final.ldr", Use::color_attachment, image()));
  GraphSettings settings;
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  EXPECT_TRUE(pass(graph, "orphan").culled);
  EXPECT_EQ(pass(graph, "orphan").reason, "culled: no pass consumes its outputs");
  EXPECT_FALSE(pass(graph, "shadows").culled);
  EXPECT_FALSE(pass(graph, "shadows").runs);
  EXPECT_EQ(pass(graph, "shadows").reason, "scene has no sun");
  EXPECT_TRUE(pass(graph, "final").runs);

  settings.frame.features = {"sun"};
  EXPECT_TRUE(pass(compile_graph(passes, {}, settings), "shadows").runs);
  settings.keep = {"orphan"};
  EXPECT_TRUE(pass(compile_graph(passes, {}, settings), "orphan").runs);
}

TEST(Graph, SkipConditionSeesTheFrame) {
  std::vector<PassDecl> passes;
  passes.push_back(
      PassDecl("motion", PassType::graphics)
          .skip_when([](const SkipContext& f) { return f.camera_moved ? "" : std::string("camera static"); })
          .write("final.ldr", Use::color_attachment, image()));
  GraphSettings settings;
  EXPECT_EQ(compile_graph(passes, {}, settings).passes[0].reason, "camera static");
  settings.frame.camera_moved = true;
  EXPECT_TRUE(compile_graph(passes, {}, settings).passes[0].runs);
}

// geometry (skipped: no mesh) → convert (its input cleared: skipped) → pyramid (likewise) →
// final, which also reads a constant nobody clears and so runs. A modifier that runs makes its
// resource no longer cleared; one that is skipped leaves it as it was.
TEST(Graph, PassesWhoseInputsAreAllClearedAreSkippedDownTheFrame) {
  std::vector<PassDecl> passes;
  passes.push_back(
      PassDecl("geometry", PassType::graphics).needs("mesh").write("depth", Use::color_attachment, image()));
  passes.push_back(PassDecl("decals", PassType::graphics).needs("decal").modify("depth", Use::color_attachment));
  passes.push_back(PassDecl("convert", PassType::compute)
                       .read("constants", Use::uniform_buffer)
                       .read("depth", Use::sampled)
                       .write("linear", Use::storage_write, image())
                       .param_float("sky", 1e6, 1, 1e9, "")
                       .skip_when_cleared({"depth"}, [](const ParamValues& p) { return p.at("sky") == 1e6; }));
  passes.push_back(PassDecl("pyramid", PassType::compute)
                       .read("linear", Use::sampled)
                       .write("pyramid", Use::storage_write, image())
                       .skip_when_cleared({"linear"}));
  passes.push_back(PassDecl("final", PassType::graphics)
                       .read("pyramid", Use::sampled)
                       .read("constants", Use::uniform_buffer)
                       .write("final.ldr", Use::color_attachment, image())
                       .skip_when_cleared({"pyramid", "constants"}));
  ResourceDesc constants;
  constants.is_buffer = true;
  constants.kind = kinds::buffer;
  constants.buffer_size = 64;
  const std::vector<ImportedResource> imports = {{"constants", constants}};
  GraphSettings settings;
  CompiledGraph graph = compile_graph(passes, imports, settings);
  EXPECT_EQ(pass(graph, "geometry").reason, "scene has no mesh");
  EXPECT_FALSE(pass(graph, "convert").runs);
  EXPECT_TRUE(pass(graph, "convert").inputs_known);
  EXPECT_EQ(pass(graph, "convert").reason, "inputs all cleared (depth)");
  EXPECT_EQ(pass(graph, "pyramid").reason, "inputs all cleared (linear)");
  EXPECT_TRUE(pass(graph, "final").runs);  // an import is never cleared
  // The skipped passes' fresh outputs are cleared for the passes that read them.
  ASSERT_EQ(pass(graph, "final").sync.clears.size(), 0u);
  EXPECT_EQ(pass(graph, "pyramid").sync.clears.at(0).resource, "pyramid");

  // A parameter for which the cleared result would not hold: the pass runs, and so do its readers.
  settings.params["convert"]["sky"] = 5;
  graph = compile_graph(passes, imports, settings);
  EXPECT_TRUE(pass(graph, "convert").runs);
  EXPECT_TRUE(pass(graph, "pyramid").runs);
  settings.params.clear();

  // A modifier that runs writes into the cleared depth: nothing after it is skipped.
  settings.frame.features = {"decal"};
  graph = compile_graph(passes, imports, settings);
  EXPECT_TRUE(pass(graph, "decals").runs);
  EXPECT_TRUE(pass(graph, "convert").runs);
  EXPECT_FALSE(pass(graph, "convert").inputs_known);

  // Kept passes (a replay) run whatever their inputs.
  settings.frame.features = {};
  settings.keep = {"convert"};
  EXPECT_TRUE(pass(compile_graph(passes, imports, settings), "convert").runs);
}

// geometry (skipped) clears depth to 0 → shade folds (depth uniform 0: lit = 0.25) → blur
// folds (the value stays) → sharpen, a modifier, folds too: left as it is where its value stays,
// cleared to its new value where not → final runs, its input known uniform. Outputs nothing that
// runs reads are not cleared: no memory, no time.
TEST(Graph, PassesOnUniformInputsAreFoldedAndOnlyWhatIsReadIsCleared) {
  auto colour = [](float v) {
    VkClearValue value{};
    for (float& c : value.color.float32) c = v;
    return value;
  };
  auto same = [](const VkClearValue& a, const VkClearValue& b) {
    return same_value(VK_FORMAT_R16G16B16A16_SFLOAT, a, b);
  };
  ImageDecl chain = image();
  chain.mips = 2;
  std::vector<PassDecl> passes;
  passes.push_back(
      PassDecl("geometry", PassType::graphics).needs("mesh").write("depth", Use::color_attachment, image()));
  passes.push_back(PassDecl("shade", PassType::graphics)
                       .read("depth", Use::sampled)
                       .write("lit", Use::color_attachment, image())
                       .fold_when_uniform({"depth"}, [&](const UniformValues& in, const ParamValues&) {
                         return in.at("depth").color.float32[0] == 0
                                    ? std::optional(UniformValues{{"lit", colour(0.25f)}})
                                    : std::nullopt;
                       }));
  // Writes mip 0 of a two-mip chain: its fold sets mip 0, mip 1 keeps the declared clear.
  passes.push_back(PassDecl("blur", PassType::compute)
                       .read("lit", Use::sampled)
                       .write("blurred", Use::storage_write, chain, Subresources::mip(0))
                       .fold_when_uniform({"lit"}, [](const UniformValues& in, const ParamValues&) {
                         return std::optional(UniformValues{{"blurred", in.at("lit")}});
                       }));
  passes.push_back(
      PassDecl("sharpen", PassType::compute)
          .read("blurred", Use::sampled, Subresources::mip(0))
          .modify("blurred", Use::storage_write, Subresources::mip(1))
          .fold_when_uniform({"blurred"},
                             [&](const UniformValues& in, const ParamValues& p) {
                               return std::optional(UniformValues{
                                   {"blurred", p.at("to") < 0 ? in.at("blurred") : colour(float(p.at("to")))}});
                             })
          .param_int("to", -1, -1, 1, "-1: the value of mip 0"));
  passes.push_back(PassDecl("final", PassType::graphics)
                       .read("blurred", Use::sampled)
                       .write("final.ldr", Use::color_attachment, image()));
  GraphSettings settings;
  CompiledGraph graph = compile_graph(passes, {}, settings);
  EXPECT_EQ(pass(graph, "shade").reason, "inputs uniform (depth): folded");
  EXPECT_TRUE(pass(graph, "shade").inputs_known);
  EXPECT_TRUE(same(pass(graph, "shade").folded.at("lit"), colour(0.25f)));
  EXPECT_EQ(pass(graph, "blur").reason, "inputs uniform (lit): folded");
  EXPECT_EQ(pass(graph, "sharpen").reason, "inputs uniform (blurred): folded");
  EXPECT_EQ(pass(graph, "final").uniform_inputs, std::set<std::string>{"blurred"});  // both mips 0.25
  // depth and lit feed only folded passes: never cleared, never allocated. blurred is cleared,
  // mip 0 by blur's fold and mip 1 by sharpen's.
  EXPECT_TRUE(pass(graph, "geometry").sync.clears.empty());
  EXPECT_TRUE(pass(graph, "shade").sync.clears.empty());
  EXPECT_FALSE(graph.lifetimes.count("depth") || graph.lifetimes.count("lit"));
  ASSERT_EQ(pass(graph, "blur").sync.clears.size(), 2u);
  for (const PlannedClear& clear : pass(graph, "blur").sync.clears)
    EXPECT_TRUE(same(clear.value, colour(clear.range.base_mip == 0 ? 0.25f : 0.0f))) << clear.range.base_mip;
  ASSERT_EQ(pass(graph, "sharpen").sync.clears.size(), 1u);
  EXPECT_EQ(pass(graph, "sharpen").sync.clears[0].range, (Subresources{1, 1, 0, 1}));
  EXPECT_TRUE(same(pass(graph, "sharpen").sync.clears[0].value, colour(0.25f)));

  // sharpen's fold gives mip 1 what it holds: it is left as it is, and final sees two mips apart.
  settings.params["sharpen"]["to"] = 0;
  graph = compile_graph(passes, {}, settings);
  EXPECT_EQ(pass(graph, "sharpen").reason, "inputs uniform (blurred): folded");
  EXPECT_TRUE(pass(graph, "sharpen").folded.empty());
  EXPECT_TRUE(pass(graph, "sharpen").sync.clears.empty());
  EXPECT_TRUE(pass(graph, "final").uniform_inputs.empty());
  settings.params.clear();

  // A capture reads every version back, so every skipped output is cleared.
  settings.capture = true;
  graph = compile_graph(passes, {}, settings);
  ASSERT_EQ(pass(graph, "shade").sync.clears.size(), 1u);
  EXPECT_TRUE(same(pass(graph, "shade").sync.clears[0].value, colour(0.25f)));
  EXPECT_EQ(pass(graph, "geometry").sync.clears.size(), 1u);
  settings.capture = false;

  // A fold that cannot tell (depth not 0) lets the pass run, and its readers.
  ImageDecl far = image();
  far.clear.color.float32[0] = 1.0f;
  passes[0] = PassDecl("geometry", PassType::graphics).needs("mesh").write("depth", Use::color_attachment, far);
  graph = compile_graph(passes, {}, settings);
  EXPECT_TRUE(pass(graph, "shade").runs);
  EXPECT_EQ(pass(graph, "shade").uniform_inputs, std::set<std::string>{"depth"});
  EXPECT_TRUE(pass(graph, "blur").runs);
  EXPECT_TRUE(pass(graph, "sharpen").runs);

  // Kept passes (a replay) run whatever their inputs.
  passes[0] = PassDecl("geometry", PassType::graphics).needs("mesh").write("depth", Use::color_attachment, image());
  settings.keep = {"blur"};
  graph = compile_graph(passes, {}, settings);
  EXPECT_EQ(pass(graph, "shade").reason, "inputs uniform (depth): folded");
  EXPECT_TRUE(pass(graph, "blur").runs);
}

TEST(Graph, FoldingOnAnInputThePassDoesNotReadIsAMistake) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("p", PassType::graphics)
                       .write("final.ldr", Use::color_attachment, image())
                       .fold_when_uniform({"depth"}, [](const UniformValues&, const ParamValues&) {
                         return std::optional<UniformValues>();
                       }));
  EXPECT_THROW(compile_graph(passes, {}, GraphSettings()), GraphError);
}

TEST(Graph, SkippingOnAClearedInputThePassDoesNotReadIsAMistake) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("p", PassType::graphics)
                       .write("final.ldr", Use::color_attachment, image())
                       .skip_when_cleared({"depth"}));
  EXPECT_THROW(compile_graph(passes, {}, GraphSettings()), GraphError);
  // An empty CPU list is known only after the barriers are planned: a fresh output the pass
  // would leave unwritten may only be read by passes that skip on the same list (a sink is read
  // by whoever asked for the frame).
  passes.clear();
  passes.push_back(PassDecl("cull", PassType::cpu).write("draws", Use::host, BufferDecl{}));
  passes.push_back(PassDecl("draw", PassType::graphics)
                       .read("draws", Use::storage_read)
                       .write("final.ldr", Use::color_attachment, image())
                       .skip_when_cleared({"draws"}));
  EXPECT_THROW(compile_graph(passes, {}, GraphSettings()), GraphError);

  passes.clear();
  passes.push_back(PassDecl("cull", PassType::cpu).write("draws", Use::host, BufferDecl{}));
  passes.push_back(PassDecl("geometry", PassType::graphics).write("final.ldr", Use::color_attachment, image()));
  passes.push_back(PassDecl("copy", PassType::compute)
                       .read("draws", Use::host)
                       .modify("final.ldr", Use::storage_write)  // read as decals finds it
                       .write("copy", Use::storage_write, image())
                       .skip_when_cleared({"draws"}));
  passes.push_back(PassDecl("decals", PassType::graphics)
                       .read("draws", Use::storage_read)
                       .read("copy", Use::sampled)
                       .modify("final.ldr", Use::color_attachment)
                       .skip_when_cleared({"draws"}));
  GraphSettings settings;
  settings.sinks = {"final.ldr"};
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  const CompiledPass& copy = pass(graph, "copy");
  EXPECT_TRUE(copy.clears_if_skipped);
  ASSERT_EQ(copy.sync.clears.size(), 1u);
  EXPECT_TRUE(copy.sync.clears[0].only_if_skipped);
  EXPECT_FALSE(pass(graph, "decals").clears_if_skipped);  // it only modifies

  // A reader that runs whatever the list holds would read what the skipped pass left unwritten.
  passes.push_back(
      PassDecl("show", PassType::graphics).read("copy", Use::sampled).write("shown", Use::color_attachment, image()));
  settings.sinks = {"final.ldr", "shown"};
  try {
    compile_graph(passes, {}, settings);
    ADD_FAILURE() << "a reader that does not skip was accepted";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("show reads it and does not skip on the same lists"), std::string::npos)
        << e.what();
  }
}

TEST(Graph, ResolvesRelativeSizesAndMipChains) {
  std::vector<PassDecl> passes;
  ImageDecl pyramid = image(VK_FORMAT_R32G32_SFLOAT);
  pyramid.size.mode = SizeRule::Mode::output_half;
  pyramid.mips = 0;
  ImageDecl like = image();
  like.size.mode = SizeRule::Mode::like;
  like.size.like = "pyramid";
  ImageDecl tiles = image(VK_FORMAT_R32G32_UINT);
  tiles.size.mode = SizeRule::Mode::output_tiles;
  tiles.size.tile = 32;
  tiles.depth = 64;
  passes.push_back(PassDecl("p", PassType::compute).write("pyramid", Use::storage_write, pyramid));
  passes.push_back(
      PassDecl("q", PassType::graphics).read("pyramid", Use::sampled).write("final.ldr", Use::color_attachment, like));
  passes.push_back(PassDecl("t", PassType::compute).write("tiles", Use::storage_write, tiles));
  GraphSettings settings;
  settings.width = 1279;
  settings.height = 719;
  settings.sinks = {"final.ldr", "tiles"};
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  const ResourceDesc& p = graph.resources.at("pyramid");
  EXPECT_EQ(p.extent.width, 640u);
  EXPECT_EQ(p.extent.height, 360u);
  EXPECT_EQ(p.extent.mips, 10u);  // 640 → 1
  EXPECT_EQ(graph.resources.at("final.ldr").extent.width, 640u);
  // One texel per 32×32 tile, the partial last column and row included.
  const ResourceDesc& t = graph.resources.at("tiles");
  EXPECT_EQ(t.extent.width, 40u);
  EXPECT_EQ(t.extent.height, 23u);
  EXPECT_EQ(t.extent.depth, 64u);
  EXPECT_EQ(t.extent.mips, 1u);
}

// Tiles and slices a pass's parameters give (lights.cluster's tile_size and slices): its defaults,
// what the settings set, and a value that is no size refused by name.
TEST(Graph, SizesByTheWritersParameters) {
  ImageDecl tiles = image(VK_FORMAT_R32G32_UINT);
  tiles.size.mode = SizeRule::Mode::output_tiles;
  tiles.size.tile_param = "tile";
  tiles.depth_param = "slices";
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("t", PassType::compute)
                       .write("tiles", Use::storage_write, tiles)
                       .param_int("tile", 32, 1, 64, "pixels per tile")
                       .param_int("slices", 64, 1, 128, "depth slices"));
  GraphSettings settings;
  settings.width = 1279;
  settings.height = 719;
  settings.sinks = {"tiles"};
  const ResourceDesc by_default = compile_graph(passes, {}, settings).resources.at("tiles");
  EXPECT_EQ(by_default.extent.width, 40u);
  EXPECT_EQ(by_default.extent.height, 23u);
  EXPECT_EQ(by_default.extent.depth, 64u);
  settings.params["t"] = {{"tile", 16}, {"slices", 32}};
  const ResourceDesc set = compile_graph(passes, {}, settings).resources.at("tiles");
  EXPECT_EQ(set.extent.width, 80u);
  EXPECT_EQ(set.extent.height, 45u);
  EXPECT_EQ(set.extent.depth, 32u);
  settings.params["t"] = {{"slices", 2.5}};
  try {
    compile_graph(passes, {}, settings);
    ADD_FAILURE() << "2.5 slices were accepted";
  } catch (const GraphError& e) {
    EXPECT_EQ(std::string(e.what()), "t.slices = 2.5: int parameter, expected a whole number in [1, 128]");
  }
  passes[0].params[1] = ParamDecl::real("slices", 64, 0, 128, "depth slices");
  settings.params.clear();
  try {
    compile_graph(passes, {}, settings);
    ADD_FAILURE() << "a float parameter sized an image";
  } catch (const GraphError& e) {
    EXPECT_EQ(std::string(e.what()),
              "t: output 'tiles' is sized by 'slices', which is not an int from 1 (or an enum of such values)");
  }
}

// A square output whose side is a parameter of its writer: the default, an override, and a
// parameter the pass does not declare refused.
TEST(Graph, SizesAnOutputByItsWritersParameter) {
  ImageDecl map = image(VK_FORMAT_D32_SFLOAT);
  map.size.mode = SizeRule::Mode::square_param;
  map.size.param = "resolution";
  map.layers = 4;
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("s", PassType::graphics)
                       .write("map", Use::depth_attachment, map)
                       .param_int("resolution", 1024, 64, 4096, "texels a side"));
  GraphSettings settings;
  settings.sinks = {"map"};
  EXPECT_EQ(compile_graph(passes, {}, settings).resources.at("map").extent.width, 1024u);
  settings.params["s"]["resolution"] = 512;
  const ResourceDesc d = compile_graph(passes, {}, settings).resources.at("map");
  EXPECT_EQ(d.extent.width, 512u);
  EXPECT_EQ(d.extent.height, 512u);
  EXPECT_EQ(d.extent.layers, 4u);
  map.size.param = "texels";
  passes[0] = PassDecl("s", PassType::graphics).write("map", Use::depth_attachment, map);
  EXPECT_THROW(compile_graph(passes, {}, settings), GraphError);
}

TEST(Graph, DeclarationMistakesAreCaughtBeforeRunning) {
  std::vector<PassDecl> unknown;
  unknown.push_back(PassDecl("x", PassType::graphics)
                        .read("nothing", Use::sampled)
                        .write("final.ldr", Use::color_attachment, image()));
  EXPECT_THROW(compile_graph(unknown, {}, GraphSettings()), GraphError);

  std::vector<PassDecl> twice;
  twice.push_back(PassDecl("a", PassType::graphics).write("final.ldr", Use::color_attachment, image()));
  twice.push_back(PassDecl("b", PassType::graphics).write("final.ldr", Use::color_attachment, image()));
  EXPECT_THROW(compile_graph(twice, {}, GraphSettings()), GraphError);

  std::vector<PassDecl> cycle;
  cycle.push_back(
      PassDecl("a", PassType::graphics).read("b.out", Use::sampled).write("a.out", Use::color_attachment, image()));
  cycle.push_back(
      PassDecl("b", PassType::graphics).read("a.out", Use::sampled).write("b.out", Use::color_attachment, image()));
  EXPECT_THROW(compile_graph(cycle, {}, GraphSettings()), GraphError);

  std::vector<PassDecl> orphan_modify;
  orphan_modify.push_back(PassDecl("m", PassType::graphics).modify("ghost", Use::color_attachment));
  EXPECT_THROW(compile_graph(orphan_modify, {}, GraphSettings()), GraphError);

  // Only a CPU pass may size its output buffer when it runs; a GPU buffer needs its size declared.
  std::vector<PassDecl> unsized;
  unsized.push_back(PassDecl("g", PassType::compute).write("final.ldr", Use::storage_write, BufferDecl(kinds::buffer)));
  try {
    compile_graph(unsized, {}, GraphSettings());
    ADD_FAILURE() << "an unsized GPU buffer compiled";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("g: GPU buffer 'final.ldr' has no declared size"), std::string::npos)
        << e.what();
  }
  std::vector<PassDecl> cpu_sized;
  cpu_sized.push_back(PassDecl("c", PassType::cpu).write("final.ldr", Use::host, BufferDecl(kinds::buffer)));
  EXPECT_NO_THROW(compile_graph(cpu_sized, {}, GraphSettings()));
}

TEST(Graph, PrefixReadsBindEveryMatchingImport) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("g", PassType::graphics)
                       .read_all("scene.texture.", Use::sampled)
                       .write("final.ldr", Use::color_attachment, image()));
  ResourceDesc tex;
  tex.format = VK_FORMAT_R8G8B8A8_SRGB;
  const CompiledGraph graph = compile_graph(
      passes, {{"scene.texture.0", tex}, {"scene.texture.1", tex}, {"scene.other", tex}}, GraphSettings());
  ASSERT_EQ(graph.passes[0].inputs.size(), 2u);
  EXPECT_EQ(graph.passes[0].inputs[0].resource, "scene.texture.0");
  EXPECT_EQ(graph.passes[0].inputs[1].resource, "scene.texture.1");
}

TEST(Graph, AHistoryReadOrdersNothingAndKeepsItsWriterRunning) {
  // "taa" reads its own previous output, and "probe" the previous output of a pass nothing
  // else consumes: that writer must run (for the next frame) but is not ordered before probe.
  std::vector<PassDecl> passes;
  ImageDecl half = image(VK_FORMAT_R16G16B16A16_SFLOAT);
  half.size.mode = SizeRule::Mode::output_half;
  half.clear.color.float32[0] = 0.5f;
  passes.push_back(PassDecl("probe", PassType::graphics)
                       .read_previous("stats", Use::sampled)
                       .write("final.ldr", Use::color_attachment, image()));
  passes.push_back(PassDecl("taa", PassType::graphics)
                       .read_previous("taa.history", Use::sampled)
                       .write("taa.history", Use::color_attachment, half));
  passes.push_back(PassDecl("stats", PassType::compute).write("stats", Use::storage_write, half));
  GraphSettings settings;
  settings.sinks = {"final.ldr", "taa.history"};
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  EXPECT_EQ(order(graph), (std::vector<std::string>{"probe", "taa", "stats"}));
  EXPECT_FALSE(pass(graph, "stats").culled) << "the next frame's probe reads what it writes now";
  const BoundUse& history = pass(graph, "taa").inputs.at(0);
  EXPECT_EQ(history.resource, "taa.history@previous");
  EXPECT_TRUE(history.history);
  EXPECT_EQ(history.producer, -1);
  EXPECT_EQ(history.desc.extent.width, 640u) << "described like the resource it remembers";
  EXPECT_EQ(history.desc.clear.color.float32[0], 0.5f) << "whose clear value is its initial value";
  EXPECT_EQ(graph.resources.at("taa.history@previous").format, VK_FORMAT_R16G16B16A16_SFLOAT);
}

TEST(Graph, AnImportedHistoryIsReadAsIs) {
  // Replay imports previous(name) from the capture: no writer is needed, nothing is pooled.
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("exposure", PassType::compute)
                       .read_previous("exposure.value", Use::sampled)
                       .write("exposure.value", Use::storage_write, image(VK_FORMAT_R32G32B32A32_SFLOAT)));
  ResourceDesc recorded;
  recorded.format = VK_FORMAT_R32G32B32A32_SFLOAT;
  GraphSettings settings;
  settings.keep = {"exposure"};
  const CompiledGraph graph = compile_graph(passes, {{"exposure.value@previous", recorded}}, settings);
  const BoundUse& history = pass(graph, "exposure").inputs.at(0);
  EXPECT_EQ(history.resource, "exposure.value@previous");
  EXPECT_TRUE(history.history);
  EXPECT_EQ(history.desc.extent.width, 1u);
}

TEST(Graph, HistoryMistakesAreCaughtBeforeRunning) {
  auto expect_error = [](std::vector<PassDecl> passes, const std::string& message) {
    try {
      compile_graph(passes, {}, GraphSettings());
      ADD_FAILURE() << "expected: " << message;
    } catch (const GraphError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  expect_error({PassDecl("taa", PassType::graphics)
                    .read_previous("nobody.writes", Use::sampled)
                    .write("final.ldr", Use::color_attachment, image())},
               "taa: reads the previous frame's 'nobody.writes', which no pass writes");
  expect_error({PassDecl("cpu", PassType::cpu).write("list", Use::host, BufferDecl{kinds::buffer}),
                PassDecl("reader", PassType::graphics)
                    .read_previous("list", Use::storage_read)
                    .write("final.ldr", Use::color_attachment, image())},
               "a CPU pass's output");
  expect_error({PassDecl("bad", PassType::graphics).write("final.ldr@previous", Use::color_attachment, image())},
               "'@' is reserved");
}

TEST(Graph, CanDisableSkipsWithItsReason) {
  std::vector<PassDecl> passes;
  passes.push_back(PassDecl("exposure", PassType::compute)
                       .can_disable("fixed exposure")
                       .write("final.ldr", Use::storage_write, image()));
  EXPECT_EQ(passes[0].default_params().at("enabled"), 1.0);
  GraphSettings settings;
  EXPECT_TRUE(compile_graph(passes, {}, settings).passes[0].runs);
  settings.params["exposure"]["enabled"] = 0;
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  EXPECT_FALSE(graph.passes[0].runs);
  EXPECT_EQ(graph.passes[0].reason, "fixed exposure (exposure.enabled=0)");
}

TEST(Barriers, ReadAfterWriteWaitsOnceAndLayoutChangesAlwaysWait) {
  SyncState state;
  // First write discards: a layout transition from UNDEFINED.
  auto write = plan_barrier(state, required_state(Use::color_attachment, PassType::graphics, false), true);
  ASSERT_TRUE(write);
  EXPECT_EQ(write->before.layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(write->after.layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

  auto read = plan_barrier(state, required_state(Use::sampled, PassType::graphics, false));
  ASSERT_TRUE(read);
  EXPECT_EQ(read->before.access, VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  EXPECT_EQ(read->after.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

  // A second fragment-shader read needs nothing; a compute read in another stage waits.
  EXPECT_FALSE(plan_barrier(state, required_state(Use::sampled, PassType::graphics, false)));
  auto compute_read = plan_barrier(state, required_state(Use::sampled, PassType::compute, false));
  ASSERT_TRUE(compute_read);
  EXPECT_EQ(compute_read->after.stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);

  // Write after read waits for the reads (WAR).
  auto transfer = plan_barrier(state, transfer_state(false));
  ASSERT_TRUE(transfer);
  EXPECT_EQ(transfer->after.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  auto war = plan_barrier(state, required_state(Use::storage_write, PassType::compute, false));
  ASSERT_TRUE(war);
  EXPECT_NE(war->before.stages & VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, 0u);
}

TEST(Barriers, DepthFormatsSampleInTheReadOnlyDepthLayout) {
  EXPECT_EQ(required_state(Use::sampled, PassType::graphics, true).layout,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
  EXPECT_EQ(required_state(Use::depth_attachment, PassType::graphics, true).layout,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
