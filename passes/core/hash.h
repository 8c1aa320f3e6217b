#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace nightcap {

// Content hash of a resource's raw bytes: XXH3-128 as 32 lowercase hex digits.
std::string content_hash(std::span<const uint8_t> bytes);
bool is_content_hash(const std::string& text);

}  // namespace nightcap
