// The record a CPU pass wrote on the previous frame, read back as its history
// (PassDecl::read_previous): the plans that decide from what they decided a frame before.
#pragma once

#include <cstring>
#include <optional>
#include <string>
#include <type_traits>

#include "passes/core/context.h"
#include "passes/core/history_name.h"

namespace nightcap {

// `resource` as the previous frame left it: none on frame 0, after a camera cut or when nothing
// was written; a GraphError naming the pass when its bytes are not one Record.
template <typename Record>
std::optional<Record> previous_record(const PassContext& ctx, const std::string& resource) {
  static_assert(std::is_trivially_copyable_v<Record>);
  const std::span<const uint8_t> bytes = ctx.host(previous(resource));
  if (bytes.empty()) return std::nullopt;
  if (bytes.size() != sizeof(Record))
    throw GraphError(ctx.pass() + ": the previous frame's record holds " + std::to_string(bytes.size()) +
                     " bytes, not " + std::to_string(sizeof(Record)));
  Record record;
  std::memcpy(&record, bytes.data(), sizeof record);
  return record;
}

}  // namespace nightcap
