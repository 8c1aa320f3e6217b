#include "inspect/pick.h"

#include <cstring>

#include "inspect/decode.h"
#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/core/declared_pipeline.h"
#include "passes/core/pipeline_cache.h"
#include "passes/core/shader.h"
#include "replay/replay.h"

namespace nightcap {

namespace {

constexpr const char* kDrawIds = "inspect.draw_ids";
constexpr const char* kFragment = "gbuffer/opaque.frag";

const PassRecord& picked_pass(const FrameRecord& frame) {
  for (const PassRecord& p : frame.passes)
    if (p.name == kPickedPass) {
      if (!p.ran)
        throw InspectError(std::string(kPickedPass) + " was skipped in frame " + std::to_string(frame.index) + " (" +
                           p.reason + "): no geometry to pick");
      return p;
    }
  throw InspectError("frame " + std::to_string(frame.index) + " has no " + kPickedPass + ": no geometry to pick");
}

const ResourceRecord& input_of(const PassRecord& pass, const std::string& name) {
  for (const ResourceRecord& r : pass.inputs)
    if (r.resource == name) return r;
  throw InspectError(pass.name + " recorded no input " + name);
}

// The recorded fragment shader, renamed so that a new main() runs it and then writes the draw
// index (the vertex stage's flat `in_draw`) to one more colour target. A discarded fragment
// writes nothing, and the depth test picks the same winner as the render did.
std::string with_draw_id_output(const std::string& source, uint32_t location) {
  const size_t version_end = source.find('\n', source.find("#version"));
  if (source.find("#version") == std::string::npos || version_end == std::string::npos)
    throw InspectError(std::string(kFragment) + " as recorded has no #version line");
  return source.substr(0, version_end + 1) + "#define main nightcap_geometry_main\n#line 2\n" +
         source.substr(version_end + 1) + "\n#undef main\nlayout(location = " + std::to_string(location) +
         ") out uint nightcap_draw_id;\nvoid main() {\n  nightcap_geometry_main();\n"
         "  nightcap_draw_id = in_draw + 1u;\n}\n";
}

template <typename T>
T element(const std::vector<uint8_t>& bytes, uint64_t index, const std::string& what) {
  if ((index + 1) * sizeof(T) > bytes.size())
    throw InspectError(what + " has no element " + std::to_string(index) + " (" + std::to_string(bytes.size()) + " B)");
  T value;
  std::memcpy(&value, bytes.data() + index * sizeof(T), sizeof(T));
  return value;
}

}  // namespace

DrawIdImage render_draw_ids(GpuDevice& gpu, const Capture& capture, const FrameRecord& frame) {
  const PassRecord& record = picked_pass(frame);
  const std::vector<PassDecl> passes = frame_passes();
  PassDecl decl = *find_pass(passes, kPickedPass);
  const uint32_t location = static_cast<uint32_t>(colour_targets(decl).size());
  // Never recorded or visualised: the kind only has to be an image's.
  decl.write(kDrawIds, Use::color_attachment, ImageDecl{VK_FORMAT_R32_UINT, kinds::colour});

  std::map<std::string, std::vector<uint32_t>> recorded_spirv;
  std::string fragment_source;
  for (const ShaderRecord& s : record.shaders) {
    recorded_spirv[s.path] = capture.load_shader(s);
    if (s.path == kFragment) fragment_source = capture.load_shader_source(s);
  }
  if (fragment_source.empty()) fragment_source = shader_source(kFragment);  // a capture without GLSL
  fragment_source = with_draw_id_output(fragment_source, location);
  auto shaders = [&](const std::string&, const std::string& path, const std::string& bindings) {
    if (path == kFragment) return compile_glsl(kFragment, fragment_source, bindings);
    auto it = recorded_spirv.find(path);
    return it != recorded_spirv.end() ? it->second : builtin_spirv(path, bindings);
  };

  PipelineCache cache(gpu);
  const IsolatedRun run = run_isolated(gpu, cache, decl, recorded_inputs(capture, record), record.params, frame.width,
                                       frame.height, shaders);
  const auto& bytes = *run.outputs.at(kDrawIds);
  DrawIdImage image{frame.width, frame.height, std::vector<uint32_t>(size_t(frame.width) * frame.height)};
  std::memcpy(image.ids.data(), bytes.data(), image.ids.size() * sizeof(uint32_t));
  return image;
}

std::optional<Pick> pick(const DrawIdImage& ids, const Capture& capture, const FrameRecord& frame, uint32_t x,
                         uint32_t y) {
  if (x >= ids.width || y >= ids.height)
    throw InspectError("pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                       std::to_string(ids.width) + "x" + std::to_string(ids.height) + " output");
  const uint32_t id = ids.ids[size_t(y) * ids.width + x];
  if (id == 0) return std::nullopt;
  const PassRecord& record = picked_pass(frame);
  Pick result;
  result.draw = id - 1;
  const ResourceRecord& draws = input_of(record, "draws.gbuffer.opaque");
  result.record = element<GpuDraw>(capture.load(draws), result.draw, draws.resource);
  const ResourceRecord& materials = input_of(record, "scene.materials");
  result.material = element<GpuMaterial>(capture.load(materials), result.record.material, materials.resource);
  return result;
}

}  // namespace nightcap
