#include "inspect/command_line.h"

#include <cctype>
#include <sstream>

namespace nightcap::inspect_cli {

const std::vector<CommandSpec>& specs() {
  static const std::vector<CommandSpec> table = {
      {{"passes", "passes", "the frame's passes: ran or why skipped, GPU/CPU time, outputs; '>' marks the current"},
       {}},
      {{"goto", "goto PASS", "make PASS the current pass"}, {}},
      {{"next", "next", "go to the next pass"}, {}},
      {{"prev", "prev", "go to the previous pass"}, {}},
      {{"frame", "frame [K]", "show the current frame, or go to recorded frame K (keeping the pass)"}, {}},
      {{"info", "info",
        "what the current pass read and wrote: kind, format, size, hash, and each output's comparison contract"},
       {}},
      {{"pipeline", "pipeline", "the pipeline and sampler state the current pass bound"}, {}},
      {{"shader", "shader [PATH]",
        "the current pass's shaders (or the one whose path ends in PATH): recorded GLSL and SPIR-V disassembly"},
       {}},
      {{"pixel", "pixel X Y [RESOURCE] [--mip M] [--layer L] [--slice Z] [--frames]",
        "the texel under output pixel (X, Y) decoded by what RESOURCE holds (default: the current pass's first "
        "output), with its raw values; --slice: the depth slice of a 3D image; --frames: the same pixel in every "
        "recorded frame. lights.clusters: the froxel the pixel falls in at its depth.linear (or --slice) and that "
        "froxel's list of frame.lights indices"},
       {{"--mip", 1}, {"--layer", 1}, {"--slice", 1}, {"--frames", 0}}},
      {{"direction", "direction DX DY DZ [RESOURCE] [--mip M] [--slot S]",
        "the texel of a cube map (sky.cubemap, sky.specular; default: the current pass's first output) that the "
        "world direction (DX, DY, DZ) looks along, found by Vulkan's face selection, decoded with its face and "
        "raw values; of sky.view, the texel the composite reads along it (by the frame's sky.atmosphere record: "
        "the light and the camera's height), with its uv; of probes.array, the texel of slot S's hemisphere "
        "(dual paraboloid) the direction is read at"},
       {{"--mip", 1}, {"--slot", 1}}},
      {{"history", "history X Y [RESOURCE]",
        "output pixel (X, Y) through the frame: each pass that wrote a screen-space resource (depth and stencil "
        "included; every mip of a pyramid), in order, with the texel before and after, and 'unchanged' where the pass "
        "wrote the resource but left that texel as it was. The capture records passes, not draws: a pass is one "
        "step, however many of its draws touched the pixel"},
       {}},
      {{"pick", "pick X Y",
        "the draw that covers output pixel (X, Y): its instance, mesh (index range) and material, found by running "
        "gbuffer.opaque again from its recorded inputs with one more target, the draw index (once per frame)"},
       {}},
      {{"buffer", "buffer RESOURCE [--element N]",
        "a buffer decoded field by field by the schema its pass declared, else as 32-bit words"},
       {{"--element", 1}}},
      {{"stats", "stats RESOURCE [--mip M] [--layer L] [--slice Z] [--rect X Y W H]",
        "per channel: min, max, mean of the finite values, a 16-bin histogram, NaN, Inf and denormal counts; "
        "--rect in output pixels"},
       {{"--mip", 1}, {"--layer", 1}, {"--slice", 1}, {"--rect", 4}}},
      {{"export",
        "export RESOURCE [--mip M] [--layer L] [--slice Z] [--stencil] [--half] [--uncompressed] -o FILE.exr|FILE.png; "
        "export CLUSTERS --heatmap [--slice Z] -o FILE.png; "
        "export PASS --all [--no-pictures] [--half] [--uncompressed] -o DIR",
        "FILE.exr: the values as float channels; FILE.png: a picture for its kind (normals as colour, depth "
        "linearised, motion on a colour wheel, HDR tonemapped; --stencil: stencil classes as a palette). --all: "
        "every output of PASS into DIR, images as RESOURCE.exr and RESOURCE.png (and RESOURCE.stencil.png), "
        "buffers as their raw bytes, RESOURCE.bin. --heatmap: a light-cluster image (lights.clusters) as the "
        "length of each tile's longest list over its slices (or of slice Z), one block of the cluster tile's size "
        "per tile so it lies over the frame, from dark blue (1 light) to white (the longest); --json adds the "
        "longest and the mean over tiles with a list. EXR channels are FLOAT and ZIP-compressed unless --half (HALF, "
        "as "
        "RenderDoc writes them) or --uncompressed; --no-pictures: --all writes no PNG"},
       {{"--mip", 1},
        {"--layer", 1},
        {"--slice", 1},
        {"--stencil", 0},
        {"--all", 0},
        {"--no-pictures", 0},
        {"--half", 0},
        {"--uncompressed", 0},
        {"--heatmap", 0},
        {"-o", 1}}},
      {{"replay", "replay [--set PARAM=VALUE]... [--shader FILE]",
        "run the current pass again from its recorded inputs on the session's device (inspect --device), with its "
        "parameter PARAM or its shader of FILE's stage (.vert/.frag/.comp) replaced, and compare each output with "
        "the recorded one: the bytes, and the output's comparison contract"},
       {{"--set", 1}, {"--shader", 1}}},
      {{"nan", "nan [--this-frame] [--limit N]",
        "where NaNs and Infs were born: walks every recorded frame's passes in order (--this-frame: only the "
        "current frame's) and names each pass that wrote a NaN or an Inf into a float output (colour, float depth, "
        "buffer fields their schema declares f32/f64) while every input it read, the version it modified among "
        "them, held finite values (passes that carry one on are not named), and each version no searched pass "
        "wrote that holds one, where it is first read; with how many, the first N (default 8) texels at their "
        "output pixels and there the values of every image input of the pass (mip 0, layer 0), or the first N "
        "buffer elements and fields. It checks each pass's outputs: the capture records per pass, not per draw"},
       {{"--this-frame", 0}, {"--limit", 1}}},
      {{"help", "help [COMMAND]", "the commands, or one command's usage"}, {}},
      {{"quit", "quit", "end the session"}, {}},
  };
  return table;
}

const CommandSpec* spec_of(const std::string& name) {
  for (const CommandSpec& spec : specs())
    if (spec.help.name == name) return &spec;
  return nullptr;
}

Arguments parse_arguments(const CommandSpec& spec, const std::vector<std::string>& words) {
  Arguments args;
  for (size_t i = 1; i < words.size(); ++i) {
    const std::string& word = words[i];
    // Options are words; a negative number (a direction's component) is a positional.
    if (word.size() < 2 || word[0] != '-' || std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.') {
      args.positional.push_back(word);
      continue;
    }
    int count = 0;
    if (word != "--json") {
      const auto found = spec.options.find(word);
      if (found == spec.options.end()) throw InspectError(spec.help.name + ": unknown option " + word);
      count = found->second;
    }
    if (i + count >= words.size())
      throw InspectError(spec.help.name + ": " + word + " takes " + std::to_string(count) + " value(s)");
    std::vector<std::string>& values = args.options[word];
    for (int k = 0; k < count; ++k) values.push_back(words[++i]);
  }
  return args;
}

uint32_t parse_index(const std::string& what, const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos)
    throw InspectError(what + " '" + text + "': expected a whole number");
  return uint32_t(std::stoul(text));
}

uint32_t option_index(const Arguments& args, const std::string& option, uint32_t fallback) {
  return args.has(option) ? parse_index(option, args.options.at(option)[0]) : fallback;
}

Subimage subimage_of(const Arguments& args) {
  return {option_index(args, "--mip", 0), option_index(args, "--layer", 0), option_index(args, "--slice", 0)};
}

void expect_positionals(const CommandSpec& spec, const Arguments& args, size_t min, size_t max) {
  if (args.positional.size() < min || args.positional.size() > max)
    throw InspectError(spec.help.name + ": usage: " + spec.help.usage);
}

std::vector<std::string> words_of(const std::string& command) {
  std::istringstream stream(command);
  std::vector<std::string> words;
  for (std::string word; stream >> word;) words.push_back(word);
  return words;
}

}  // namespace nightcap::inspect_cli
