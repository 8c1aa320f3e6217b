// A store of golden captures, the references `nightcap diff --golden` compares against. A folder:
// DIR/nightcap-store.json marks it (format and version), DIR/blobs/<hash>.<ext> holds one copy of
// every blob of every golden, DIR/goldens/NAME a golden's manifest.json ("blobs": "store": its
// blob paths are relative to DIR) and final.png, and DIR/tmp the updates under way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "captures/capture.h"

namespace nightcap {

constexpr int kStoreVersion = 1;

struct GoldenInfo {
  std::string name;
  uint32_t frames = 0;
  size_t passes = 0;    // of its first frame
  std::string source;   // the capture it was recorded from, as an absolute path
  std::string updated;  // when, in UTC (ISO 8601)
};

struct GoldenUpdate {
  GoldenInfo golden;
  size_t blobs_copied = 0, blobs_shared = 0;  // shared: the store held them already
};

class GoldenStore {
 public:
  // Throws CaptureError naming DIR/nightcap-store.json unless DIR is a store of a version this
  // nightcap reads.
  static GoldenStore open(const std::filesystem::path& dir);

  // Records capture `source` as golden `name` (a safe_name), replacing an earlier one of that
  // name; DIR becomes a store first when it does not exist or is an empty folder. Only the blobs
  // the store lacks are copied, each checked against its hash as copied. Nothing is visible
  // until every blob is checked, and the golden's folder replaces the old one by a rename, so a
  // failure (CaptureError naming the file) leaves the store as it was.
  static GoldenUpdate update(const std::filesystem::path& dir, const std::filesystem::path& source,
                             const std::string& name);

  const std::filesystem::path& root() const { return root_; }
  bool contains(const std::string& name) const;
  Capture golden(const std::string& name) const;  // throws CaptureError when absent
  std::vector<GoldenInfo> list() const;           // by name

 private:
  explicit GoldenStore(std::filesystem::path root) : root_(std::move(root)) {}
  GoldenUpdate record(const Capture& source, const std::filesystem::path& source_path, const std::string& name) const;
  std::filesystem::path root_;
};

}  // namespace nightcap
