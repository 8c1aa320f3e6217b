// SPIR-V as text, through SPIRV-Tools' disassembler (what `spirv-dis` prints).
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace nightcap {

// Throws InspectError when the words are not a module SPIRV-Tools can read.
std::string disassemble_spirv(std::span<const uint32_t> words);

}  // namespace nightcap
