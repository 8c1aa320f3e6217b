#include "captures/golden_store.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>

namespace nightcap {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string now_utc() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// Flushed to disk before it is renamed into place, so that a crash never leaves a short file
// under its final name.
void sync_file(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

void write_synced(const fs::path& file, const std::string& text) {
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw CaptureError(file.string() + ": cannot write");
  }
  sync_file(file);
}

void rename_or_throw(const fs::path& from, const fs::path& to) {
  std::error_code error;
  fs::rename(from, to, error);
  if (error) throw CaptureError(to.string() + ": cannot move into place: " + error.message());
}

// A folder to create the store in: absent, or empty (a store's marker is its first file).
void create_store(const fs::path& dir) {
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_empty(dir, error))
    throw CaptureError(dir.string() + ": not a golden store (no " + kStoreMarker + ") and not empty");
  for (const char* sub : {"blobs", "goldens", "tmp"}) {
    fs::create_directories(dir / sub, error);
    if (error) throw CaptureError((dir / sub).string() + ": cannot create: " + error.message());
  }
  const fs::path marker = dir / kStoreMarker;
  fs::path temp = dir / "tmp" / kStoreMarker;
  temp += ".tmp-" + std::to_string(::getpid());
  write_synced(temp, json{{"format", "nightcap-store"}, {"version", kStoreVersion}}.dump(1) + "\n");
  rename_or_throw(temp, marker);
}

// Removes a folder when it goes out of scope, unless released.
struct RemoveOnExit {
  fs::path path;
  ~RemoveOnExit() {
    std::error_code error;
    if (!path.empty()) fs::remove_all(path, error);
  }
};

GoldenInfo info_of(const std::string& name, const CaptureManifest& m) {
  GoldenInfo info{name, uint32_t(m.frames.size()), m.frames.empty() ? 0 : m.frames.front().passes.size(), "", ""};
  if (m.golden.is_object()) {
    info.source = m.golden.at("source").get<std::string>();
    info.updated = m.golden.at("updated").get<std::string>();
  }
  return info;
}

}  // namespace

GoldenStore GoldenStore::open(const fs::path& dir) {
  const fs::path marker = dir / kStoreMarker;
  if (!fs::is_regular_file(marker)) throw CaptureError(marker.string() + ": missing (not a golden store)");
  std::ifstream in(marker, std::ios::binary);
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw CaptureError(marker.string() + ": malformed JSON: " + e.what());
  }
  if (!j.is_object() || j.value("format", "") != "nightcap-store")
    throw CaptureError(marker.string() + ": not a nightcap store (\"format\")");
  const json version = j.value("version", json());
  if (!version.is_number_integer() || version.get<int64_t>() < 1 || version.get<int64_t>() > kStoreVersion)
    throw CaptureError(marker.string() + ": store version " + version.dump() + " is not one this nightcap reads (" +
                       std::to_string(kStoreVersion) + ")");
  std::error_code error;
  const fs::path root = fs::canonical(dir, error);
  if (error) throw CaptureError(dir.string() + ": " + error.message());
  return GoldenStore(root);
}

GoldenUpdate GoldenStore::update(const fs::path& dir, const fs::path& source, const std::string& name) {
  if (!safe_name(name)) throw CaptureError("golden name '" + name + "': not a safe file name");
  // Read before the store is touched: a capture that cannot be opened changes nothing.
  const Capture capture = Capture::open(source);
  std::error_code error;
  // A store this update creates holds nothing else: a failure takes it away again.
  RemoveOnExit created{fs::exists(dir, error) ? fs::path() : dir};
  if (!fs::exists(dir / kStoreMarker, error)) create_store(dir);
  GoldenUpdate result = open(dir).record(capture, source, name);
  created.path.clear();
  return result;
}

GoldenUpdate GoldenStore::record(const Capture& source, const fs::path& source_path, const std::string& name) const {
  // Every blob the golden references, with the check of a file that claims to hold it.
  std::map<std::string, std::function<void(const fs::path&)>> blobs;
  for (const FrameRecord& frame : source.manifest().frames)
    for (const PassRecord& pass : frame.passes) {
      for (const auto* side : {&pass.inputs, &pass.outputs})
        for (const ResourceRecord& r : *side)
          blobs.emplace(r.blob, [r](const fs::path& file) { read_resource_blob(file, r); });
      for (const ShaderRecord& s : pass.shaders) {
        blobs.emplace(s.blob, [hash = s.hash](const fs::path& file) { read_file_blob(file, hash); });
        blobs.emplace(s.source_blob, [hash = s.source_hash](const fs::path& file) { read_file_blob(file, hash); });
      }
    }

  const fs::path tmp = root_ / "tmp", target = root_ / "goldens" / name;
  remove_stale_siblings(tmp / name);
  fs::path staging = tmp / name;
  staging += ".tmp-" + std::to_string(::getpid());
  std::error_code error;
  fs::remove_all(staging, error);
  for (const fs::path& folder : {staging / "blobs", root_ / "goldens"}) {
    fs::create_directories(folder, error);
    if (error) throw CaptureError(folder.string() + ": cannot create: " + error.message());
  }
  RemoveOnExit cleanup{staging};

  // Staged in the store and checked there, so that what is renamed into blobs/ is what was checked.
  GoldenUpdate result;
  std::vector<std::string> staged;
  for (const auto& [blob, check] : blobs) {
    if (fs::is_regular_file(root_ / blob)) {
      ++result.blobs_shared;
      continue;
    }
    const fs::path from = source.blob_file(blob), copy = staging / blob;
    fs::copy_file(from, copy, error);
    if (error) throw CaptureError(from.string() + ": cannot copy into the store: " + error.message());
    try {
      check(copy);
    } catch (const CaptureError&) {
      check(from);  // names the capture's own file when that is what is damaged
      throw;
    }
    sync_file(copy);
    staged.push_back(blob);
  }
  // Not a blob: the picture of the last frame, when the capture has one (and it is no link).
  if (fs::is_regular_file(fs::symlink_status(source.folder() / "final.png"))) {
    fs::copy_file(source.folder() / "final.png", staging / "final.png", error);
    if (error) throw CaptureError((source.folder() / "final.png").string() + ": cannot copy: " + error.message());
  }
  CaptureManifest manifest = source.manifest();
  manifest.blobs_in_store = true;
  manifest.golden = {{"source", fs::absolute(source_path).lexically_normal().string()}, {"updated", now_utc()}};
  write_synced(staging / "manifest.json", to_json(manifest).dump(1) + "\n");

  // Every blob checked: now they move in (each whole, by a rename), then the golden that uses them.
  for (const std::string& blob : staged)
    if (!fs::exists(root_ / blob)) rename_or_throw(staging / blob, root_ / blob);
  fs::remove_all(staging / "blobs", error);
  fs::path old;
  if (fs::exists(target)) {
    old = tmp / name;
    old += ".old-" + std::to_string(::getpid());
    fs::remove_all(old, error);
    rename_or_throw(target, old);
  }
  fs::rename(staging, target, error);
  if (error) {
    if (!old.empty()) fs::rename(old, target, error);
    throw CaptureError(target.string() + ": cannot move the golden into place: " + error.message());
  }
  cleanup.path = old;
  result.blobs_copied = staged.size();
  result.golden = info_of(name, manifest);
  return result;
}

bool GoldenStore::contains(const std::string& name) const {
  return safe_name(name) && fs::is_regular_file(root_ / "goldens" / name / "manifest.json");
}

Capture GoldenStore::golden(const std::string& name) const {
  if (!contains(name)) throw CaptureError("golden '" + name + "' missing from store " + root_.string());
  return Capture::open(root_ / "goldens" / name);
}

std::vector<GoldenInfo> GoldenStore::list() const {
  std::vector<GoldenInfo> goldens;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(root_ / "goldens", error)) {
    const std::string name = entry.path().filename().string();
    if (contains(name)) goldens.push_back(info_of(name, golden(name).manifest()));
  }
  if (error) throw CaptureError((root_ / "goldens").string() + ": cannot list: " + error.message());
  std::sort(goldens.begin(), goldens.end(), [](const GoldenInfo& a, const GoldenInfo& b) { return a.name < b.name; });
  return goldens;
}

}  // namespace nightcap
