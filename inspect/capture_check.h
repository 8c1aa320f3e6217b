// `nightcap check`: every blob of a capture read, decoded and its content hash checked. Other
// commands read only the blobs they need (replay compares hashes, not recorded blobs), so this is
// the one that vouches for a whole capture.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "captures/blob_check.h"
#include "captures/capture.h"

namespace nightcap {

// A record of the manifest that names a blob.
struct BlobReference {
  uint32_t frame = 0;
  std::string pass;
  std::string role;  // "input", "output", "shader" or "shader source"
  std::string name;  // the resource, or the shader's path
};

struct BadBlob {
  std::string blob;  // as the manifest names it, relative to the capture (or its store)
  BlobCheck check;
  std::vector<BlobReference> references;  // in manifest order
};

struct CaptureCheck {
  uint64_t blobs = 0;
  uint64_t bytes_on_disk = 0;  // of the blobs found
  std::vector<BadBlob> bad;    // sorted by blob
};

// Reads every blob the manifest names once, on a worker per core, largest first.
CaptureCheck check_capture(const Capture& capture);
nlohmann::json to_json(const CaptureCheck& check);
// "output normals.packed of normals.pack (frame 0)".
std::string describe(const BlobReference& reference);

}  // namespace nightcap
