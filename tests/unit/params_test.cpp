// Typed parameters (passes/core/params.h): checked once at graph compile, `--set` parsed by type,
// groups set as one, and read by type from a pass.
#include <gtest/gtest.h>

#include <set>

#include "passes/assembly/frame_passes.h"
#include "passes/core/graph.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

ImageDecl image() { return ImageDecl(VK_FORMAT_R8G8B8A8_UNORM, kinds::colour); }

PassDecl typed_pass() {
  return PassDecl("shade", PassType::compute)
      .write("final.ldr", Use::storage_write, image())
      .param_float("gain", 1.0, 0.0, 4.0, "")
      .param_int("steps", 8, 1, 64, "")
      .flag("contact", true, "")
      .choice("filter", 1, {{"nearest", 0}, {"linear", 1}, {"cubic", 2}}, "");
}

// The message of the GraphError compile_graph throws for `params`, or "" when it compiles.
std::string compile_error(const std::vector<PassDecl>& passes, const ParamOverrides& params) {
  GraphSettings settings;
  settings.params = params;
  try {
    compile_graph(passes, {}, settings);
  } catch (const GraphError& e) {
    return e.what();
  }
  return "";
}

TEST(Params, CompileResolvesDefaultsAndOverridesIntoTheCompiledPass) {
  GraphSettings settings;
  settings.params["shade"] = {{"steps", 16}, {"filter", 2}};
  const CompiledGraph graph = compile_graph({typed_pass()}, {}, settings);
  EXPECT_EQ(graph.passes.at(0).params, (ParamValues{{"gain", 1.0}, {"steps", 16}, {"contact", 1}, {"filter", 2}}));
}

TEST(Params, CompileRefusesAValueOfTheWrongTypeOrRangeNamingWhatIsAllowed) {
  const std::vector<PassDecl> passes = {typed_pass()};
  EXPECT_EQ(compile_error(passes, {{"shade", {{"steps", 2.5}}}}),
            "shade.steps = 2.5: int parameter, expected a whole number in [1, 64]");
  EXPECT_EQ(compile_error(passes, {{"shade", {{"steps", 65}}}}),
            "shade.steps = 65: int parameter, expected a whole number in [1, 64]");
  EXPECT_EQ(compile_error(passes, {{"shade", {{"gain", -1}}}}),
            "shade.gain = -1: float parameter, expected a number in [0, 4]");
  EXPECT_EQ(compile_error(passes, {{"shade", {{"contact", 0.5}}}}),
            "shade.contact = 0.5: bool parameter, expected 0 or 1 (false or true)");
  EXPECT_EQ(compile_error(passes, {{"shade", {{"filter", 3}}}}),
            "shade.filter = 3: enum parameter, expected one of nearest (0), linear (1), cubic (2)");
  EXPECT_EQ(compile_error(passes, {{"shade", {{"gian", 1}}}}),
            "shade.gian: unknown parameter (shade has: shade.gain, shade.steps, shade.contact, shade.filter)");
  EXPECT_EQ(compile_error(passes, {{"shadee", {{"gain", 1}}}}), "shadee.gain: no pass or group named 'shadee'");
}

TEST(Params, CompileRefusesADefaultOutsideItsDeclaration) {
  EXPECT_EQ(compile_error({PassDecl("p", PassType::compute)
                               .write("final.ldr", Use::storage_write, image())
                               .param_int("n", 0, 1, 4, "")},
                          {}),
            "p.n = 0 (its default): int parameter, expected a whole number in [1, 4]");
}

TEST(Params, SetParsesByType) {
  const std::vector<PassDecl> passes = {typed_pass()};
  ParamOverrides set;
  parse_set(passes, "shade.filter=cubic", set);
  EXPECT_EQ(set["shade"]["filter"], 2);
  parse_set(passes, "shade.filter=0", set);
  EXPECT_EQ(set["shade"]["filter"], 0) << "an enum's value is accepted too";
  parse_set(passes, "shade.contact=false", set);
  EXPECT_EQ(set["shade"]["contact"], 0);
  parse_set(passes, "shade.steps=32", set);
  EXPECT_EQ(set["shade"]["steps"], 32);
  auto error = [&](const std::string& text) {
    try {
      parse_set(passes, text, set);
    } catch (const SetError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("shade.filter=bilinear"),
            "--set 'shade.filter=bilinear': enum parameter, expected one of nearest (0), linear (1), cubic (2)");
  EXPECT_EQ(error("shade.steps=3.5"), "--set 'shade.steps=3.5': int parameter, expected a whole number in [1, 64]");
  EXPECT_EQ(error("shade.contact=yes"), "--set 'shade.contact=yes': bool parameter, expected 0 or 1 (false or true)");
  EXPECT_EQ(error("shade.gain=x"), "--set 'shade.gain=x': float parameter, expected a number in [0, 4]");
  EXPECT_EQ(error("shade=1"), "--set 'shade=1': expected PASS.PARAM=VALUE (or GROUP.PARAM=VALUE)");
  EXPECT_EQ(error("other.gain=1"), "--set other.gain: no pass or group named 'other'");
}

// Two passes that must agree on a size declare it once, as a group.
ParamDecl shared_size() { return ParamDecl::integer("size", 256, 64, 1024, "").shared_by("maps"); }

std::vector<PassDecl> group_passes() {
  return {PassDecl("maps.plan", PassType::cpu).write("plan", Use::host, BufferDecl{}).param(shared_size()),
          PassDecl("maps.draw", PassType::compute)
              .read("plan", Use::storage_read)
              .write("final.ldr", Use::storage_write, image())
              .param(shared_size())
              .param_int("layers", 2, 1, 4, "")};
}

TEST(Params, AGroupsParameterIsSetOnceForEveryMember) {
  const std::vector<PassDecl> passes = group_passes();
  ParamOverrides set;
  parse_set(passes, "maps.size=512", set);
  EXPECT_EQ(set, (ParamOverrides{{"maps", {{"size", 512}}}}));
  GraphSettings settings;
  settings.params = set;
  const CompiledGraph graph = compile_graph(passes, {}, settings);
  for (const CompiledPass& pass : graph.passes) EXPECT_EQ(pass.params.at("size"), 512) << pass.decl->name;
}

TEST(Params, AGroupMemberCannotBeSetAlone) {
  const std::vector<PassDecl> passes = group_passes();
  ParamOverrides set;
  EXPECT_THROW(parse_set(passes, "maps.draw.size=512", set), SetError);
  EXPECT_EQ(compile_error(passes, {{"maps.draw", {{"size", 512}}}}),
            "maps.draw.size: shared by maps.plan, maps.draw: set maps.size");
}

TEST(Params, AGroupsMembersMustDeclareItAlike) {
  std::vector<PassDecl> passes = group_passes();
  passes[1].params[0].max = 2048;
  EXPECT_EQ(compile_error(passes, {}),
            "maps.size: maps.plan and maps.draw declare it differently (declare the group's parameter once)");
}

TEST(Params, TheShadowPassesShareTheirResolutions) {
  const std::vector<PassDecl> passes = frame_passes();
  ParamOverrides set;
  parse_set(passes, "shadow.resolution=2048", set);
  parse_set(passes, "shadow.distant.resolution=512", set);
  for (const char* name : {"shadow.cull", "shadow.cascades_static"})
    EXPECT_EQ(resolve_params(*find_pass(passes, name), set).at("resolution"), 2048) << name;
  for (const char* name : {"shadow.distant_plan", "shadow.distant"})
    EXPECT_EQ(resolve_params(*find_pass(passes, name), set).at("resolution"), 512) << name;
  EXPECT_THROW(parse_set(passes, "shadow.cull.resolution=2048", set), SetError);
  EXPECT_THROW(parse_set(passes, "shadow.distant_plan.resolution=512", set), SetError);
  EXPECT_NO_THROW(parse_set(passes, "shadow.distant.enabled=0", set)) << "shadow.distant's own switch";
}

class PassParams : public test::GpuTest {
 protected:
  // Runs a CPU pass declaring an int `n` that reads `read`; the GraphError it throws, or "".
  static std::string read_error(const std::function<void(PassContext&)>& read) {
    const PassDecl pass = PassDecl("reader", PassType::cpu)
                              .write("list", Use::host, BufferDecl{})
                              .param_int("n", 2, 1, 4, "")
                              .run([read](PassContext& ctx) {
                                read(ctx);
                                ctx.output("list").assign(4, 0);
                              });
    try {
      run(pass, {}, 4, 4);
    } catch (const GraphError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(PassParams, APassReadsItsParametersByTheirDeclaredType) {
  EXPECT_EQ(read_error([](PassContext& ctx) { EXPECT_EQ(ctx.param_int("n"), 2); }), "");
  EXPECT_EQ(read_error([](PassContext& ctx) { ctx.param_float("n"); }), "reader: reads int parameter 'n' as float");
  EXPECT_EQ(read_error([](PassContext& ctx) { ctx.flag("m"); }), "reader: reads undeclared parameter 'm'");
}

// A pass that reads a parameter it did not declare, or as another type, throws when it records:
// every registered pass records in one of these frames, so such a mistake fails here.
TEST_F(PassParams, EveryRegisteredPassRecordsWithTheParametersItDeclares) {
  std::set<std::string> ran;
  auto render = [&](const Scene& scene, FrameLighting lighting, uint32_t frames) {
    RenderSettings settings;
    settings.width = 128;
    settings.height = 72;
    settings.lighting = lighting;
    Renderer renderer(*gpu_, scene, settings);
    for (uint32_t k = 0; k < frames; ++k)
      for (const CompiledPass& pass : renderer.render_frame(k, false).graph.passes)
        if (pass.runs) ran.insert(pass.decl->name);
  };
  Scene city = build_city(1);
  add_default_lighting(city);
  // The city has spot lights with shadow maps; the street has decals and moving geometry; the
  // second frame of each moves the camera (motion.stencil).
  ASSERT_NO_THROW(render(city, FrameLighting::tiled, 2));
  ASSERT_NO_THROW(render(build_map({1, 2.0, Shot::street}), FrameLighting::tiled, 2));
  ASSERT_NO_THROW(render(city, FrameLighting::deferred, 1));
  std::string never;
  for (const PassDecl& pass : all_passes())
    if (!ran.count(pass.name)) never += " " + pass.name;
  EXPECT_EQ(never, "") << "registered passes that never ran here, so never read their parameters";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
