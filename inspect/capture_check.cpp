#include "inspect/capture_check.h"

#include <algorithm>
#include <map>
#include <memory>

#include "compare/parallel.h"

namespace nightcap {
namespace {

// One blob to read: the first record naming it says how (a resource decodes, a shader's bytes
// are hashed as they are); every record naming it is a reference.
struct BlobToCheck {
  const ResourceRecord* resource = nullptr;
  std::string hash;  // of a shader blob
  uint64_t cost = 0;
  std::vector<BlobReference> references;
};

std::map<std::string, BlobToCheck> blobs_of(const CaptureManifest& manifest) {
  std::map<std::string, BlobToCheck> blobs;
  for (const FrameRecord& frame : manifest.frames)
    for (const PassRecord& pass : frame.passes) {
      for (const auto& [role, records] : {std::pair{"input", &pass.inputs}, std::pair{"output", &pass.outputs}})
        for (const ResourceRecord& r : *records) {
          BlobToCheck& b = blobs[r.blob];
          if (!b.resource) {
            b.resource = &r;
            b.cost = r.raw_bytes();
          }
          b.references.push_back({frame.index, pass.name, role, r.resource});
        }
      for (const ShaderRecord& s : pass.shaders)
        for (const auto& [role, blob, hash] :
             {std::tuple{"shader", &s.blob, &s.hash}, std::tuple{"shader source", &s.source_blob, &s.source_hash}}) {
          BlobToCheck& b = blobs[*blob];
          b.hash = *hash;
          b.references.push_back({frame.index, pass.name, role, s.path});
        }
    }
  return blobs;
}

}  // namespace

std::string describe(const BlobReference& r) {
  return r.role + " " + r.name + " of " + r.pass + " (frame " + std::to_string(r.frame) + ")";
}

CaptureCheck check_capture(const Capture& capture) {
  const std::map<std::string, BlobToCheck> blobs = blobs_of(capture.manifest());
  std::vector<const std::pair<const std::string, BlobToCheck>*> order;
  for (const auto& entry : blobs) order.push_back(&entry);
  // Largest first, so that no worker starts a long one while the others run out of work.
  std::stable_sort(order.begin(), order.end(), [](auto* x, auto* y) { return x->second.cost > y->second.cost; });
  // Mip chains recorded after each level's pass share most of their parts: decoded once.
  DecodedParts decoded_parts(kDecodedPartsBudget);
  std::vector<BlobCheck> results(order.size());
  std::vector<uint64_t> sizes(order.size(), 0);
  // Every core reads a blob of its own: each decodes on its worker alone.
  for_each_on_cores(order.size(), [&](size_t i) {
    const auto& [blob, what] = *order[i];
    results[i] = what.resource ? check_resource_blob(capture, *what.resource, 0, &decoded_parts)
                               : check_file_blob(capture, blob, what.hash);
    std::error_code error;
    const uint64_t size = std::filesystem::file_size(capture.blob_root() / blob, error);
    if (!error && results[i].problem != BlobProblem::refused) sizes[i] = size;
  });
  CaptureCheck check;
  check.blobs = order.size();
  for (size_t i = 0; i < order.size(); ++i) {
    check.bytes_on_disk += sizes[i];
    if (results[i].problem != BlobProblem::none)
      check.bad.push_back({order[i]->first, results[i], order[i]->second.references});
  }
  std::sort(check.bad.begin(), check.bad.end(), [](const BadBlob& x, const BadBlob& y) { return x.blob < y.blob; });
  return check;
}

nlohmann::json to_json(const CaptureCheck& check) {
  nlohmann::json bad = nlohmann::json::array();
  for (const BadBlob& b : check.bad) {
    nlohmann::json references = nlohmann::json::array();
    for (const BlobReference& r : b.references)
      references.push_back({{"frame", r.frame}, {"pass", r.pass}, {"role", r.role}, {"name", r.name}});
    bad.push_back({{"blob", b.blob},
                   {"problem", blob_problem_name(b.check.problem)},
                   {"detail", b.check.detail},
                   {"references", references}});
  }
  return {{"blobs", check.blobs}, {"bytes_on_disk", check.bytes_on_disk}, {"ok", check.bad.empty()}, {"bad", bad}};
}

}  // namespace nightcap
