#include "captures/decoded_parts.h"

namespace nightcap {

std::shared_ptr<const std::vector<uint8_t>> DecodedParts::find(const Digest& digest) const {
  const std::lock_guard lock(mutex_);
  const auto found = parts_.find(digest);
  if (found == parts_.end()) return nullptr;
  ++hits_;
  return found->second;
}

void DecodedParts::keep(const Digest& digest, std::span<const uint8_t> decoded) {
  if (decoded.size() > budget_) return;
  auto copy = std::make_shared<const std::vector<uint8_t>>(decoded.begin(), decoded.end());
  const std::lock_guard lock(mutex_);
  if (!parts_.emplace(digest, std::move(copy)).second) return;  // another thread decoded it too
  oldest_first_.push_back(digest);
  bytes_ += decoded.size();
  while (bytes_ > budget_) {
    const auto oldest = parts_.find(oldest_first_.front());
    bytes_ -= oldest->second->size();
    parts_.erase(oldest);
    oldest_first_.pop_front();
  }
}

uint64_t DecodedParts::hits() const {
  const std::lock_guard lock(mutex_);
  return hits_;
}

}  // namespace nightcap
