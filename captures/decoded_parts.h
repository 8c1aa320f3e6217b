// Decoded parts of image blobs, found again by their compressed bytes.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

namespace nightcap {

// A resource that passes write in turn (a mip chain a level at a time, the layers of an atlas) is
// recorded whole after each of them, and most of its parts are the same bytes in every record.
// Reading a blob through this cache decodes such a part once: read_image_blob finds it by a digest
// of the part's compressed chunks (with its shape, format and codec), and copies it. Safe to share
// between threads; it keeps at most `budget` bytes of parts, dropping the oldest first.
class DecodedParts {
 public:
  using Digest = std::pair<uint64_t, uint64_t>;  // XXH3-128

  explicit DecodedParts(uint64_t budget) : budget_(budget) {}

  // The part's decoded bytes, or null.
  std::shared_ptr<const std::vector<uint8_t>> find(const Digest& digest) const;
  void keep(const Digest& digest, std::span<const uint8_t> decoded);

  uint64_t hits() const;

 private:
  const uint64_t budget_;
  mutable std::mutex mutex_;
  std::map<Digest, std::shared_ptr<const std::vector<uint8_t>>> parts_;
  std::deque<Digest> oldest_first_;
  uint64_t bytes_ = 0;
  mutable uint64_t hits_ = 0;
};

}  // namespace nightcap
