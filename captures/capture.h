// The capture: a folder holding manifest.json and content-addressed blobs (see
// shared/design/architecture.md). CaptureWriter builds one in a temporary sibling folder and
// renames it into place only when complete; Capture opens one and verifies what it reads.
#pragma once

#include <nlohmann/json.hpp>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "captures/blob_codec.h"
#include "passes/core/buffer_schema.h"
#include "passes/core/contract.h"
#include "passes/core/format.h"
#include "passes/core/params.h"
#include "passes/core/pass_time.h"
#include "passes/core/resource_kind.h"

namespace nightcap {

// 2: frames record their output size and sinks, shaders their GLSL source, passes the pipeline
// and sampler state they bound, outputs their comparison contract (buffer outputs their schema,
// where declared).
// 3: frames record their time, camera cut and history resets; frame.camera carries the cut and
// time step. Earlier captures lack what replay and the tools need from these.
// 4: 8-bit codes are HALF samples in image blobs (UINT before).
// 5: scene.geometry holds compact vertex streams, scene.instances the split transform with
// scene.meshes and scene.hierarchy beside it, draw records carry the previous model and the
// quantisation box: a pass replayed from an older record would read garbage.
constexpr int kCaptureVersion = 5;
constexpr uint32_t kMaxImageSide = 16384;

// The file that marks a folder as a store of golden captures (captures/golden_store.h). A golden
// lives in STORE/goldens/NAME, and its manifest's blob paths are relative to STORE.
inline constexpr const char* kStoreMarker = "nightcap-store.json";

// A name that can be a path component and a resource, pass or golden name: printable ASCII
// without spaces, no '/' or '\\', not "." or "..", at most 256 characters.
bool safe_name(const std::string& name);

struct ResourceRecord {
  std::string resource;
  ResourceKind kind = kinds::buffer;
  bool is_buffer = true;
  VkFormat format = VK_FORMAT_UNDEFINED;  // images only
  ImageExtent extent;                     // images only
  bool cube = false;                      // images only: the layers are cube faces
  uint64_t buffer_size = 0;               // buffers only
  std::string hash;                       // content_hash of the raw bytes
  std::string blob;                       // path relative to the capture folder
  ComparisonContract contract;            // outputs only: how two versions of it compare
  std::optional<BufferSchema> schema;     // buffer outputs whose pass declared how they decode

  uint64_t raw_bytes() const;
};

struct ShaderRecord {
  std::string path;  // shader source path relative to passes/, e.g. "gbuffer/opaque.frag"
  std::string hash;  // of the SPIR-V words
  std::string blob;
  std::string source_hash;  // of the GLSL text the SPIR-V was compiled from
  std::string source_blob;
};

// The NaN `render --inject-nan` wrote into one texel of a pass's output after the pass ran; the
// recorded output holds it, and replay writes it again.
struct InjectedNanRecord {
  std::string resource;
  uint32_t x = 0, y = 0;  // a texel of mip 0, layer 0
};

struct PassRecord {
  std::string name;
  std::string stage;  // PassDecl::stage; empty in captures made before stages were recorded
  bool ran = false;
  std::string reason;            // why it was skipped
  std::optional<double> gpu_ms;  // the device's timestamps; null for CPU passes and skipped ones
  double cpu_ms = 0.0;
  // The pass's time as the tools show it, measured by `clock` (ExecutionOptions::pass_timing):
  // on a CPU device the timestamps absorb other work, so a pass is timed alone there.
  double time_ms = 0.0;
  PassClock clock = PassClock::host;
  double record_ms = 0.0;  // PassExecution::record_ms; 0 in captures made before it was recorded
  std::map<std::string, double> params;
  // How each parameter is declared: its type, range or choices and group (not its help); absent
  // in captures made before parameters had types.
  std::vector<ParamDecl> param_types;
  std::vector<ShaderRecord> shaders;
  std::vector<ResourceRecord> inputs, outputs;
  // Pipeline and sampler state the pass bound, as passes/core/pipeline_cache.h describes it:
  // for tools to show, not read back by replay (which re-runs the pass's own code).
  nlohmann::json pipelines = nlohmann::json::array(), samplers = nlohmann::json::array();
  std::optional<InjectedNanRecord> injected_nan;
};

struct CameraRecord {
  std::array<double, 16> view{}, projection{};  // column-major, camera-relative view
  std::array<double, 3> position{};             // world position (double)
  double yfov = 0.0, znear = 0.0;
  std::string depth_convention = "reversed-z, infinite far plane";
};

struct FrameRecord {
  uint32_t index = 0;
  uint32_t width = 0, height = 0;  // output size the graph resolved relative sizes against
  std::vector<std::string> sinks;  // resources the frame had to produce
  double time = 0.0;               // seconds since frame 0
  // The host's wall clock from the frame's first command to its last result (execute_graph);
  // absent in captures made before it was recorded.
  std::optional<double> wall_ms;
  bool camera_cut = false;  // the view jumped here: every history restarted
  // History resources that started from their initial value in this frame, and why.
  std::map<std::string, std::string> history_reset;
  CameraRecord camera;
  std::vector<PassRecord> passes;
};

struct CaptureManifest {
  int version = kCaptureVersion;
  nlohmann::json device;    // name, driver, api version
  nlohmann::json settings;  // size, frames, seed, params given on the command line
  nlohmann::json scene;     // source, counts, notes
  std::vector<FrameRecord> frames;
  // A golden of a store ("blobs": "store"): blob paths are relative to the store, not the
  // capture folder, and `golden` says where it came from ({"source", "updated"}).
  bool blobs_in_store = false;
  nlohmann::json golden;
};

nlohmann::json to_json(const ResourceRecord& record);
nlohmann::json to_json(const CaptureManifest& manifest);
// Throws CaptureError naming `file` for anything malformed: missing fields, unknown formats,
// sizes over kMaxImageSide or whose byte count overflows, blob paths that leave the capture.
CaptureManifest manifest_from_json(const nlohmann::json& json, const std::string& file);

// A blob file read and checked against the hash its record states: a resource decoded to its raw
// bytes, a shader or its source as the bytes of the file. Throw CaptureError naming `file`.
std::vector<uint8_t> read_resource_blob(const std::filesystem::path& file, const ResourceRecord& record,
                                        int threads = -1, DecodedParts* decoded_parts = nullptr);
std::vector<uint8_t> read_file_blob(const std::filesystem::path& file, const std::string& hash);
// The same reads without the hash check, for a caller that tells a blob that does not decode from
// one whose content is not its hash (`nightcap check`). Throw naming `file`.
std::vector<uint8_t> decode_resource_blob(const std::filesystem::path& file, const ResourceRecord& record,
                                          int threads = -1, DecodedParts* decoded_parts = nullptr);
std::vector<uint8_t> read_file_bytes(const std::filesystem::path& file);

// Removes `<target>.tmp-<pid>` and `<target>.old-<pid>` folders whose process is gone (a killed
// writer's); those of a live process are kept.
void remove_stale_siblings(const std::filesystem::path& target);

// Builds a capture in `<target>.tmp-<pid>` and renames it to `target` on commit. Blobs are
// written once per hash, encoded on a pool of workers while the caller goes on (rendering the
// next frame). Safe to call add_* from several threads.
class CaptureWriter {
 public:
  struct Options {
    // The codec of every image blob; unset: the one chosen for its kind (codec_choice.h).
    std::optional<ImageEncoding> images;
    int zstd_level = 3;
    unsigned workers = 0;  // blobs encoded at once; 0: one per core
  };
  // Throws CaptureError if target exists and !force, or the folder cannot be created.
  CaptureWriter(std::filesystem::path target, bool force, Options options);
  ~CaptureWriter();  // abandons queued blobs and removes the temporary folder unless committed
  CaptureWriter(const CaptureWriter&) = delete;
  CaptureWriter& operator=(const CaptureWriter&) = delete;

  // Fills hash and blob of `record` (whose other fields describe `raw`) at once, and queues the
  // blob's encoding; `raw` is kept until it is written.
  void add_resource(ResourceRecord& record, std::shared_ptr<const std::vector<uint8_t>> raw);
  ShaderRecord add_shader(const std::string& path, std::span<const uint32_t> spirv, const std::string& source);
  void write_final_png(const std::vector<uint8_t>& rgba8, uint32_t width, uint32_t height);
  // Waits for every queued blob; throws the first error any of them met.
  void flush();
  void commit(const CaptureManifest& manifest);  // flushes first

  uint64_t bytes_written();  // flushes first

 private:
  // The content hash of `raw`, computed once for the same bytes given again: a frame's versions
  // are added as they are read back and again when the frame is recorded.
  std::string hash_of(const std::shared_ptr<const std::vector<uint8_t>>& raw);
  void encode(const ResourceRecord& record, const std::shared_ptr<const std::vector<uint8_t>>& raw);
  void work();
  // Writes `bytes` once as blobs/<hash>.<extension>; returns the hash and the blob path.
  std::pair<std::string, std::string> add_file_blob(std::span<const uint8_t> bytes, const std::string& extension);
  std::filesystem::path target_, temp_;
  bool force_;
  Options options_;
  bool committed_ = false;
  std::mutex mutex_;
  std::condition_variable queued_, drained_;
  std::set<std::string> blobs_;  // hashes written or queued
  struct Hashed {
    std::weak_ptr<const std::vector<uint8_t>> bytes;  // expired: the address may hold other bytes now
    std::string hash;
  };
  std::map<const std::vector<uint8_t>*, Hashed> hashed_;
  size_t hashed_after_pruning_ = 64;
  std::deque<std::function<void()>> queue_;
  size_t busy_ = 0;  // queued or being encoded
  bool stopping_ = false;
  std::exception_ptr failure_;
  uint64_t bytes_written_ = 0;
  std::vector<std::thread> workers_;
};

// What one opened capture keeps of its decoded shared parts (DecodedParts), at most.
constexpr uint64_t kDecodedPartsBudget = 64u << 20;

class Capture {
 public:
  // Reads and validates the manifest, and nothing else. Throws CaptureError naming the file.
  static Capture open(const std::filesystem::path& folder);

  const std::filesystem::path& folder() const { return folder_; }
  // What blob paths are relative to: the capture folder, or the store a golden lives in.
  const std::filesystem::path& blob_root() const { return blob_root_; }
  const CaptureManifest& manifest() const { return manifest_; }
  const FrameRecord& frame(uint32_t index) const;  // throws CaptureError if absent

  // Blobs are read only through these, when a command needs them, and each one's content hash is
  // checked as it is read. They throw CaptureError naming the blob file.
  // Decoded to its raw bytes; `threads` as read_image_blob's.
  std::vector<uint8_t> load(const ResourceRecord& record, int threads = -1) const;
  std::vector<uint32_t> load_shader(const ShaderRecord& record) const;
  std::string load_shader_source(const ShaderRecord& record) const;  // the GLSL of the SPIR-V
  // The file of a blob path, refused (CaptureError) when it resolves outside blob_root(), a
  // symbolic link included, or is not a regular file.
  std::filesystem::path blob_file(const std::string& blob) const;

 private:
  std::filesystem::path folder_, blob_root_;
  // Parts that several of its image blobs share, decoded once (the resources that passes write a
  // level or a layer at a time).
  std::shared_ptr<DecodedParts> decoded_parts_ = std::make_shared<DecodedParts>(kDecodedPartsBudget);
  CaptureManifest manifest_;
};

}  // namespace nightcap
