#include "passes/core/shader.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <filesystem>
#include <mutex>

#include "passes/core/shader_sources.h"

namespace nightcap {
namespace {

class EmbeddedIncluder : public glslang::TShader::Includer {
 public:
  IncludeResult* includeLocal(const char* header, const char* includer, size_t) override {
    const std::string folder = std::filesystem::path(includer).parent_path().string();
    const auto& sources = embedded_shader_sources();
    for (const std::string& candidate :
         {(std::filesystem::path(folder) / header).lexically_normal().string(), std::string(header)}) {
      auto it = sources.find(candidate);
      if (it != sources.end()) return new IncludeResult(it->first, it->second.data(), it->second.size(), nullptr);
    }
    return nullptr;
  }
  IncludeResult* includeSystem(const char* header, const char* includer, size_t depth) override {
    return includeLocal(header, includer, depth);
  }
  void releaseInclude(IncludeResult* result) override { delete result; }
};

EShLanguage stage_of(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".vert") return EShLangVertex;
  if (ext == ".frag") return EShLangFragment;
  if (ext == ".comp") return EShLangCompute;
  throw ShaderError(path + ": unknown shader stage (expected .vert, .frag or .comp)");
}

}  // namespace

const std::string& shader_source(const std::string& path) {
  const auto& sources = embedded_shader_sources();
  auto it = sources.find(path);
  if (it == sources.end()) throw ShaderError(path + ": no such built-in shader");
  return it->second;
}

std::vector<uint32_t> compile_glsl(const std::string& path, const std::string& source, const std::string& preamble) {
  static std::once_flag init;
  std::call_once(init, [] { glslang::InitializeProcess(); });

  const EShLanguage stage = stage_of(path);
  glslang::TShader shader(stage);
  const char* text = source.c_str();
  const char* name = path.c_str();
  shader.setStringsWithLengthsAndNames(&text, nullptr, &name, 1);
  const std::string full_preamble = "#extension GL_GOOGLE_include_directive : require\n" + preamble;
  shader.setPreamble(full_preamble.c_str());
  shader.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_3);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_6);
  EmbeddedIncluder includer;
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
  if (!shader.parse(GetDefaultResources(), 460, false, messages, includer))
    throw ShaderError(path + ": GLSL compile failed:\n" + shader.getInfoLog());
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) throw ShaderError(path + ": link failed:\n" + program.getInfoLog());
  std::vector<uint32_t> spirv;
  glslang::SpvOptions options;
  options.disableOptimizer = false;
  glslang::GlslangToSpv(*program.getIntermediate(stage), spirv, &options);
  return spirv;
}

}  // namespace nightcap
