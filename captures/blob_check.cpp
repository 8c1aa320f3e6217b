#include "captures/blob_check.h"

#include <fcntl.h>
#include <openexr.h>
#include <unistd.h>
#include <zstd.h>
#include <zstd_errors.h>

#include <optional>

#include "passes/core/hash.h"

namespace nightcap {
namespace fs = std::filesystem;

namespace {

// The blob's file, or why it is not read: absent, or refused by Capture::blob_file (a directory,
// a link leading out of the capture).
std::optional<BlobCheck> locate(const Capture& capture, const std::string& blob, fs::path& file) {
  try {
    file = capture.blob_file(blob);
    return std::nullopt;
  } catch (const CaptureError& e) {
    std::error_code error;
    const bool present = fs::exists(fs::symlink_status(capture.blob_root() / blob, error));
    return BlobCheck{present ? BlobProblem::refused : BlobProblem::missing, e.what()};
  }
}

// A zstd frame cut short: its header announces more than the file holds. A file that cannot be
// opened is not called cut.
bool zstd_truncated(const fs::path& file) {
  std::vector<uint8_t> bytes;
  try {
    bytes = read_file_bytes(file);
  } catch (const CaptureError&) {
    return false;
  }
  if (bytes.empty()) return true;
  const size_t size = ZSTD_findFrameCompressedSize(bytes.data(), bytes.size());
  return ZSTD_isError(size) && ZSTD_getErrorCode(size) == ZSTD_error_srcSize_wrong;
}

// OpenEXR reads through pread and is told no file size: it then takes the chunk offsets and sizes
// the file states as they are (instead of refusing those past the end as corrupt), and a read past
// the end comes back short.
int64_t read_unsized(exr_const_context_t, void* fd, void* buffer, uint64_t size, uint64_t offset,
                     exr_stream_error_func_ptr_t) {
  return ::pread(*static_cast<int*>(fd), buffer, size, off_t(offset));
}

// An OpenEXR file cut short: its headers or chunk offset table end early, or a chunk they point
// to reaches past the end of the file. Asked only of a blob that did not decode, after
// check_exr_headers has vetted what OpenEXR will read.
bool exr_truncated(const fs::path& file) {
  std::error_code error;
  const uint64_t file_size = fs::file_size(file, error);
  if (error) return false;
  int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char*) {};
  init.user_data = &fd;
  init.read_fn = &read_unsized;
  init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER | EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t context = nullptr;
  bool truncated = false;
  if (const exr_result_t opened = exr_start_read(&context, file.c_str(), &init); opened != EXR_ERR_SUCCESS) {
    truncated = opened == EXR_ERR_READ_IO;
  } else {
    int parts = 0;
    exr_get_count(context, &parts);
    for (int part = 0; part < parts && !truncated; ++part) {
      exr_attr_box2i_t window;
      int32_t rows_per_chunk = 0, chunks = 0;
      if (exr_get_data_window(context, part, &window) != EXR_ERR_SUCCESS ||
          exr_get_scanlines_per_chunk(context, part, &rows_per_chunk) != EXR_ERR_SUCCESS ||
          exr_get_chunk_count(context, part, &chunks) != EXR_ERR_SUCCESS || rows_per_chunk <= 0)
        break;
      for (int32_t chunk = 0; chunk < chunks && !truncated; ++chunk) {
        exr_chunk_info_t info;
        const exr_result_t read =
            exr_read_scanline_chunk_info(context, part, window.min.y + chunk * rows_per_chunk, &info);
        truncated =
            read == EXR_ERR_READ_IO || (read == EXR_ERR_SUCCESS && info.data_offset + info.packed_size > file_size);
      }
    }
  }
  exr_finish(&context);
  ::close(fd);
  return truncated;
}

}  // namespace

std::string blob_problem_name(BlobProblem problem) {
  switch (problem) {
    case BlobProblem::none:
      return "none";
    case BlobProblem::missing:
      return "missing";
    case BlobProblem::refused:
      return "refused";
    case BlobProblem::truncated:
      return "truncated";
    case BlobProblem::undecodable:
      return "undecodable";
    case BlobProblem::hash_mismatch:
      return "hash_mismatch";
  }
  return "";
}

BlobCheck check_resource_blob(const Capture& capture, const ResourceRecord& record, int threads,
                              DecodedParts* decoded_parts) {
  fs::path file;
  if (auto refused = locate(capture, record.blob, file)) return *refused;
  std::vector<uint8_t> raw;
  try {
    raw = decode_resource_blob(file, record, threads, decoded_parts);
  } catch (const std::exception& e) {
    const bool truncated = record.is_buffer ? zstd_truncated(file) : exr_truncated(file);
    return {truncated ? BlobProblem::truncated : BlobProblem::undecodable, e.what()};
  }
  if (const std::string hash = content_hash(raw); hash != record.hash)
    return {BlobProblem::hash_mismatch, file.string() + ": content hashes to " + hash + ", not " + record.hash};
  return {};
}

BlobCheck check_file_blob(const Capture& capture, const std::string& blob, const std::string& hash) {
  fs::path file;
  if (auto refused = locate(capture, blob, file)) return *refused;
  // Shader blobs are the bytes themselves: a cut one is told only by its hash.
  std::vector<uint8_t> bytes;
  try {
    bytes = read_file_bytes(file);
  } catch (const CaptureError& e) {
    return {BlobProblem::undecodable, e.what()};
  }
  if (const std::string actual = content_hash(bytes); actual != hash)
    return {BlobProblem::hash_mismatch, file.string() + ": content hashes to " + actual + ", not " + hash};
  return {};
}

}  // namespace nightcap
