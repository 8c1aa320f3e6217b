// What is wrong with one blob of a capture, if anything. Commands read only the blobs they need,
// so a blob nobody reads can rot unseen; `nightcap check` reads every one through this.
#pragma once

#include <string>

#include "captures/capture.h"

namespace nightcap {

enum class BlobProblem {
  none,
  missing,        // no file at its path
  refused,        // not a regular file, or a link that leaves the capture (or store): never read
  truncated,      // the file ends before the data its own header or frame says it holds
  undecodable,    // not a blob of the recorded format and extent (or buffer size)
  hash_mismatch,  // decodes, but its content is not what its name (the content hash) says
};
// "missing", "refused", "truncated", "undecodable", "hash_mismatch".
std::string blob_problem_name(BlobProblem problem);

struct BlobCheck {
  BlobProblem problem = BlobProblem::none;
  std::string detail;  // the reader's message, naming the file; empty when sound
};

// A resource's blob decoded to its raw bytes, whose hash must be record.hash. `threads` and
// `decoded_parts` as read_image_blob's.
BlobCheck check_resource_blob(const Capture& capture, const ResourceRecord& record, int threads,
                              DecodedParts* decoded_parts);
// A shader's SPIR-V or GLSL blob: its bytes must hash to `hash`.
BlobCheck check_file_blob(const Capture& capture, const std::string& blob, const std::string& hash);

}  // namespace nightcap
