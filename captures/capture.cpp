#include "captures/capture.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "captures/codec_choice.h"
#include "images/images.h"
#include "passes/core/hash.h"

namespace nightcap {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

void fsync_path(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

uint64_t ResourceRecord::raw_bytes() const {
  return is_buffer ? buffer_size : raw_image_bytes(*format_info(format), extent);
}

void remove_stale_siblings(const fs::path& target) {
  std::error_code error;
  const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string name = target.filename().string();
  for (const auto& entry : fs::directory_iterator(parent, error)) {
    const std::string sibling = entry.path().filename().string();
    for (const std::string suffix : {".tmp-", ".old-"}) {
      const std::string prefix = name + suffix;
      if (sibling.size() <= prefix.size() || sibling.compare(0, prefix.size(), prefix) != 0) continue;
      const std::string digits = sibling.substr(prefix.size());
      if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
      const pid_t pid = pid_t(std::stol(digits));
      const bool alive = pid > 0 && (::kill(pid, 0) == 0 || errno == EPERM);
      if (!alive) fs::remove_all(entry.path(), error);
    }
  }
}

CaptureWriter::CaptureWriter(fs::path target, bool force, Options options)
    : target_(std::move(target)), force_(force), options_(options) {
  if (target_.filename().empty()) target_ = target_.parent_path();
  if (fs::exists(target_) && !force_) throw CaptureError(target_.string() + ": exists (use --force to overwrite)");
  remove_stale_siblings(target_);
  temp_ = target_;
  temp_ += ".tmp-" + std::to_string(::getpid());
  std::error_code error;
  fs::remove_all(temp_, error);
  fs::create_directories(temp_ / "blobs", error);
  if (error) throw CaptureError(target_.string() + ": cannot create the capture folder: " + error.message());
  const unsigned workers = options_.workers ? options_.workers : std::max(1u, std::thread::hardware_concurrency());
  for (unsigned w = 0; w < workers; ++w) workers_.emplace_back([this] { work(); });
}

CaptureWriter::~CaptureWriter() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    queue_.clear();
  }
  queued_.notify_all();
  for (std::thread& worker : workers_) worker.join();
  if (committed_) return;
  std::error_code error;
  fs::remove_all(temp_, error);
}

void CaptureWriter::work() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock lock(mutex_);
      queued_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    try {
      task();
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!failure_) failure_ = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    if (--busy_ == 0) drained_.notify_all();
  }
}

void CaptureWriter::add_resource(ResourceRecord& record, std::shared_ptr<const std::vector<uint8_t>> raw) {
  if (!raw || raw->size() != record.raw_bytes())
    throw std::logic_error("add_resource: " + record.resource + " size mismatch");
  record.hash = hash_of(raw);
  // Equal bytes in two image formats or extents are two files: the blob states its format.
  std::string name = record.hash;
  if (!record.is_buffer) {
    name += "." + std::string(format_info(record.format)->name) + "." + std::to_string(record.extent.width) + "x" +
            std::to_string(record.extent.height) + "x" + std::to_string(record.extent.depth) + "m" +
            std::to_string(record.extent.mips) + "l" + std::to_string(record.extent.layers);
  }
  record.blob = "blobs/" + name + "." + (record.is_buffer ? buffer_blob_extension() : image_blob_extension());
  std::lock_guard lock(mutex_);
  if (!blobs_.insert(record.blob).second) return;
  ++busy_;
  queue_.push_back([this, record, raw = std::move(raw)] { encode(record, raw); });
  queued_.notify_one();
}

std::string CaptureWriter::hash_of(const std::shared_ptr<const std::vector<uint8_t>>& raw) {
  {
    std::lock_guard lock(mutex_);
    const auto known = hashed_.find(raw.get());
    if (known != hashed_.end() && known->second.bytes.lock() == raw) return known->second.hash;
  }
  std::string hash = content_hash(*raw);
  std::lock_guard lock(mutex_);
  // Bytes no longer held by anyone are forgotten once as many entries were added as remain.
  if (hashed_.size() >= 2 * hashed_after_pruning_) {
    std::erase_if(hashed_, [](const auto& entry) { return entry.second.bytes.expired(); });
    hashed_after_pruning_ = std::max<size_t>(hashed_.size(), 64);
  }
  hashed_[raw.get()] = {raw, hash};
  return hash;
}

void CaptureWriter::encode(const ResourceRecord& record, const std::shared_ptr<const std::vector<uint8_t>>& raw) {
  const fs::path file = temp_ / record.blob;
  if (record.is_buffer)
    write_buffer_blob(file, *raw, options_.zstd_level);
  else
    write_image_blob(file, *format_info(record.format), record.extent, *raw,
                     options_.images.value_or(image_encoding_for(record.kind, *format_info(record.format))), 0);
  const uint64_t size = fs::file_size(file);
  std::lock_guard lock(mutex_);
  bytes_written_ += size;
}

void CaptureWriter::flush() {
  std::unique_lock lock(mutex_);
  drained_.wait(lock, [&] { return busy_ == 0; });
  if (failure_) std::rethrow_exception(failure_);
}

uint64_t CaptureWriter::bytes_written() {
  flush();
  std::lock_guard lock(mutex_);
  return bytes_written_;
}

ShaderRecord CaptureWriter::add_shader(const std::string& path, std::span<const uint32_t> spirv,
                                       const std::string& source) {
  ShaderRecord record{path, "", "", "", ""};
  std::tie(record.hash, record.blob) =
      add_file_blob({reinterpret_cast<const uint8_t*>(spirv.data()), spirv.size_bytes()}, "spv");
  std::tie(record.source_hash, record.source_blob) =
      add_file_blob({reinterpret_cast<const uint8_t*>(source.data()), source.size()}, "glsl");
  return record;
}

std::pair<std::string, std::string> CaptureWriter::add_file_blob(std::span<const uint8_t> bytes,
                                                                 const std::string& extension) {
  const std::string hash = content_hash(bytes);
  const std::string blob = "blobs/" + hash + "." + extension;
  std::lock_guard lock(mutex_);
  if (!blobs_.count(blob)) {
    std::ofstream out(temp_ / blob, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) throw CaptureError((temp_ / blob).string() + ": cannot write");
    blobs_.insert(blob);
    bytes_written_ += bytes.size();
  }
  return {hash, blob};
}

void CaptureWriter::write_final_png(const std::vector<uint8_t>& rgba8, uint32_t width, uint32_t height) {
  const fs::path file = temp_ / "final.png";
  try {
    write_png(file, rgba8, width, height);
  } catch (const ImageError& e) {
    throw CaptureError(file.string() + ": cannot write PNG: " + e.what());
  }
  std::lock_guard lock(mutex_);
  bytes_written_ += fs::file_size(file);
}

void CaptureWriter::commit(const CaptureManifest& manifest) {
  flush();
  const fs::path manifest_file = temp_ / "manifest.json";
  {
    std::ofstream out(manifest_file, std::ios::binary | std::ios::trunc);
    out << to_json(manifest).dump(1) << "\n";
    if (!out) throw CaptureError(manifest_file.string() + ": cannot write");
  }
  {
    std::lock_guard lock(mutex_);
    bytes_written_ += fs::file_size(manifest_file);
  }
  fsync_path(manifest_file, false);
  fsync_path(temp_ / "blobs", true);
  fsync_path(temp_, true);
  std::error_code error;
  fs::path old;
  if (fs::exists(target_)) {
    // Someone else created it while this capture was being written: never clobber it.
    if (!force_) throw CaptureError(target_.string() + ": exists (use --force to overwrite)");
    old = target_;
    old += ".old-" + std::to_string(::getpid());
    fs::rename(target_, old, error);
    if (error) throw CaptureError(target_.string() + ": cannot replace: " + error.message());
  }
  fs::rename(temp_, target_, error);
  if (error)
    throw CaptureError(target_.string() + ": cannot rename the finished capture into place: " + error.message());
  committed_ = true;
  if (!old.empty()) fs::remove_all(old, error);
  fsync_path(target_.parent_path().empty() ? fs::path(".") : target_.parent_path(), true);
}

namespace {

// A golden's blobs are those of the store holding it, STORE/goldens/NAME: found from where the
// golden is, never from anything its manifest says.
fs::path store_root(const fs::path& folder, const fs::path& manifest_file) {
  std::error_code error;
  const fs::path real = fs::canonical(folder, error);
  if (error) throw CaptureError(manifest_file.string() + ": cannot resolve its folder: " + error.message());
  if (real.parent_path().filename() != "goldens")
    throw CaptureError(manifest_file.string() + ": its blobs live in a store, but it is not in a store's goldens/");
  const fs::path root = real.parent_path().parent_path();
  if (!fs::is_regular_file(root / kStoreMarker))
    throw CaptureError(manifest_file.string() + ": its blobs live in the store " + root.string() + ", which has no " +
                       kStoreMarker);
  return root;
}

}  // namespace

Capture Capture::open(const fs::path& folder) {
  Capture capture;
  capture.folder_ = folder;
  if (!fs::is_directory(folder)) throw CaptureError(folder.string() + ": no such capture");
  const fs::path file = folder / "manifest.json";
  if (!fs::exists(file)) throw CaptureError(file.string() + ": missing (not a capture)");
  const std::vector<uint8_t> text = read_file_bytes(file);
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    throw CaptureError(file.string() + ": malformed JSON: " + e.what());
  }
  capture.manifest_ = manifest_from_json(j, file.string());
  capture.blob_root_ = capture.manifest_.blobs_in_store ? store_root(folder, file) : folder;
  return capture;
}

const FrameRecord& Capture::frame(uint32_t index) const {
  for (const FrameRecord& f : manifest_.frames)
    if (f.index == index) return f;
  throw CaptureError((folder_ / "manifest.json").string() + ": no frame " + std::to_string(index) + " (capture has " +
                     std::to_string(manifest_.frames.size()) + ")");
}

fs::path Capture::blob_file(const std::string& blob) const {
  const fs::path file = blob_root_ / blob;
  std::error_code error;
  const fs::path real = fs::weakly_canonical(file, error);
  const fs::path root = fs::weakly_canonical(blob_root_, error);
  const std::string prefix = root.string() + "/";
  if (error || real.string().rfind(prefix, 0) != 0)
    throw CaptureError(file.string() + ": leaves the " + (manifest_.blobs_in_store ? "store" : "capture folder"));
  if (!fs::is_regular_file(real)) throw CaptureError(file.string() + ": missing blob");
  return real;
}

std::vector<uint8_t> read_file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw CaptureError(file.string() + ": cannot open");
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::vector<uint8_t> decode_resource_blob(const fs::path& file, const ResourceRecord& record, int threads,
                                          DecodedParts* decoded_parts) {
  return record.is_buffer ? read_buffer_blob(file, record.buffer_size)
                          : read_image_blob(file, *format_info(record.format), record.extent, threads, decoded_parts);
}

std::vector<uint8_t> read_resource_blob(const fs::path& file, const ResourceRecord& record, int threads,
                                        DecodedParts* decoded_parts) {
  std::vector<uint8_t> raw = decode_resource_blob(file, record, threads, decoded_parts);
  if (content_hash(raw) != record.hash)
    throw CaptureError(file.string() + ": content does not match its hash " + record.hash + " (corrupt capture)");
  return raw;
}

std::vector<uint8_t> read_file_blob(const fs::path& file, const std::string& hash) {
  std::vector<uint8_t> bytes = read_file_bytes(file);
  if (content_hash(bytes) != hash)
    throw CaptureError(file.string() + ": content does not match its hash " + hash + " (corrupt capture)");
  return bytes;
}

std::vector<uint8_t> Capture::load(const ResourceRecord& record, int threads) const {
  return read_resource_blob(blob_file(record.blob), record, threads, decoded_parts_.get());
}

std::string Capture::load_shader_source(const ShaderRecord& record) const {
  const std::vector<uint8_t> bytes = read_file_blob(blob_file(record.source_blob), record.source_hash);
  return std::string(bytes.begin(), bytes.end());
}

std::vector<uint32_t> Capture::load_shader(const ShaderRecord& record) const {
  const fs::path file = blob_file(record.blob);
  const std::vector<uint8_t> bytes = read_file_blob(file, record.hash);
  if (bytes.size() % 4 != 0 || bytes.empty()) throw CaptureError(file.string() + ": not SPIR-V");
  std::vector<uint32_t> words(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), bytes.size());
  return words;
}

}  // namespace nightcap
