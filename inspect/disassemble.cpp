#include "inspect/disassemble.h"

#include <spirv-tools/libspirv.hpp>

#include "inspect/decode.h"

namespace nightcap {

std::string disassemble_spirv(std::span<const uint32_t> words) {
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_3);
  std::string message;
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* text) {
    if (message.empty()) message = text;
  });
  std::string text;
  if (!tools.Disassemble(words.data(), words.size(), &text,
                         SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES | SPV_BINARY_TO_TEXT_OPTION_INDENT))
    throw InspectError("SPIR-V disassembly failed: " + (message.empty() ? std::string("unreadable module") : message));
  return text;
}

}  // namespace nightcap
