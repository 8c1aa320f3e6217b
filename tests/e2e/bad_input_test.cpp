// Bad input gets a clear message naming the file or flag, exit code 2, no crash, and nothing
// written outside -o.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <thread>

#include "captures/blob_codec.h"
#include "passes/core/hash.h"
#include "passes/frame/hierarchy.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kSmall = "--city-block --size 64x36";

void expect_bad_input(const CliResult& r, const std::string& names) {
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(names), std::string::npos) << "stderr does not name '" << names << "': " << r.err;
}

// Everything in `dir` after the command: only what the command was allowed to create.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

void write(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
}

fs::path copy_of_city(const std::string& name) {
  const fs::path copy = scratch(name) / "capture";
  fs::copy(shared_capture("city-small", kSmall), copy, fs::copy_options::recursive);
  return copy;
}

TEST(BadInput, MissingScene) {
  const fs::path dir = scratch("out");
  expect_bad_input(run_cli("render /nonexistent/scene.gltf -o " + quote(dir / "cap")), "/nonexistent/scene.gltf");
  EXPECT_TRUE(entries(dir).empty());
}

TEST(BadInput, MalformedGltf) {
  const fs::path dir = scratch("out");
  write(dir / "broken.gltf", "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ { ");
  expect_bad_input(run_cli("render " + quote(dir / "broken.gltf") + " -o " + quote(dir / "cap")), "broken.gltf");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"broken.gltf"});
}

TEST(BadInput, MissingTexture) {
  const fs::path dir = scratch("out");
  const fs::path source = fs::path(NIGHTCAP_SHARED_DATA) / "gltf/BoxTextured/glTF";
  fs::copy_file(source / "BoxTextured0.bin", dir / "BoxTextured0.bin");
  nlohmann::json gltf = read_json(source / "BoxTextured.gltf");
  gltf["images"][0]["uri"] = "missing.png";
  write_json(dir / "box.gltf", gltf);
  expect_bad_input(run_cli("render " + quote(dir / "box.gltf") + " --size 64x36 -o " + quote(dir / "cap")),
                   "missing.png");
  EXPECT_FALSE(fs::exists(dir / "cap"));
}

TEST(BadInput, ExistingOutputIsRefusedWithoutForce) {
  const fs::path dir = scratch("out");
  fs::create_directories(dir / "cap");
  write(dir / "cap" / "keep.txt", "mine");
  expect_bad_input(run_cli(std::string("render ") + kSmall + " -o " + quote(dir / "cap")), "exists");
  EXPECT_TRUE(fs::exists(dir / "cap" / "keep.txt"));
}

TEST(BadInput, ZeroSizeAndUnknownParameters) {
  const fs::path dir = scratch("out");
  expect_bad_input(run_cli("render --size 0x0 -o " + quote(dir / "cap")), "--size");
  expect_bad_input(run_cli("render --size 20000x10 -o " + quote(dir / "cap")), "--size");
  expect_bad_input(run_cli(std::string("render ") + kSmall + " --set tonemap.nonsense=1 -o " + quote(dir / "cap")),
                   "tonemap.nonsense");
  expect_bad_input(run_cli(std::string("render ") + kSmall + " --set nopass.x=1 -o " + quote(dir / "cap")), "nopass");
  expect_bad_input(run_cli(std::string("render ") + kSmall + " --set tonemap.exposure=abc -o " + quote(dir / "cap")),
                   "tonemap.exposure");
  EXPECT_TRUE(entries(dir).empty());
}

TEST(BadInput, TruncatedManifest) {
  const fs::path capture = copy_of_city("truncated");
  const std::string text = [&] {
    std::ifstream in(capture / "manifest.json");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  for (size_t length : {size_t(0), size_t(1), text.size() / 3, text.size() - 2}) {
    write(capture / "manifest.json", text.substr(0, length));
    expect_bad_input(run_cli("passes " + quote(capture)), "manifest.json");
    expect_bad_input(run_cli("replay --verify " + quote(capture)), "manifest.json");
  }
}

nlohmann::json& first_output(nlohmann::json& manifest, const std::string& pass) {
  for (auto& p : manifest["frames"][0]["passes"])
    if (p["name"] == pass) return p["outputs"][0];
  throw std::runtime_error("no pass " + pass);
}

TEST(BadInput, BlobWhoseContentDoesNotMatchItsHash) {
  const fs::path capture = copy_of_city("hash");
  nlohmann::json manifest = read_json(capture / "manifest.json");
  const std::string lit = first_output(manifest, "taa")["blob"];
  const std::string diffuse = first_output(manifest, "lighting.tiled")["blob"];
  // tonemap reads taa.resolved: give its file another valid blob of the same format and size,
  // which decodes fine but hashes differently.
  fs::copy_file(capture / diffuse, capture / lit, fs::copy_options::overwrite_existing);
  const CliResult r = run_cli("replay --verify --pass tonemap " + quote(capture));
  expect_bad_input(r, lit.substr(lit.find('/') + 1));
  EXPECT_NE(r.err.find("hash"), std::string::npos) << r.err;
}

// Each edit alone, so that the message names the problem that edit made and no other check
// (the byte count cross-check included) can be what refused the manifest.
TEST(BadInput, BlobPathsThatLeaveTheCapture) {
  const fs::path capture = copy_of_city("escape");
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  for (const char* path : {"../../../etc/passwd", "/etc/passwd", "blobs/../../outside.exr"}) {
    nlohmann::json edited = manifest;
    first_output(edited, "tonemap")["blob"] = path;
    write_json(capture / "manifest.json", edited);
    const CliResult r = run_cli("passes " + quote(capture));
    expect_bad_input(r, "manifest.json");
    expect_bad_input(r, std::string("blob path '") + path + "' leaves blobs/");
  }
}

TEST(BadInput, HostileSizesInTheManifest) {
  const fs::path capture = copy_of_city("sizes");
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  auto edit = [&](const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json edited = manifest;
    change(first_output(edited, "tonemap"));
    write_json(capture / "manifest.json", edited);
    return run_cli("replay --verify " + quote(capture));
  };
  // final.ldr is R8G8B8A8_SRGB: 4 bytes a texel; "bytes" is kept consistent with each size.
  expect_bad_input(edit([](nlohmann::json& o) {
                     o["width"] = 70000;
                     o["bytes"] = uint64_t(70000) * o["height"].get<uint64_t>() * 4;
                   }),
                   "width 70000 outside 1..16384");
  expect_bad_input(edit([](nlohmann::json& o) {
                     o["width"] = 16384;
                     o["height"] = 16384;
                     o["layers"] = 2048;
                     o["bytes"] = uint64_t(16384) * 16384 * 2048 * 4;
                   }),
                   "image of 16384x16384x2048 is too large");
  expect_bad_input(edit([](nlohmann::json& o) { o["width"] = -1; }), "width -1 outside 1..16384");
  expect_bad_input(edit([](nlohmann::json& o) { o["mips"] = 40; }), "mips 40 outside");
  expect_bad_input(edit([](nlohmann::json& o) { o["bytes"] = o["bytes"].get<uint64_t>() + 1; }),
                   "does not match the size");
}

// A capture whose scene.hierarchy is consistent with its hash but not with itself (a hostile
// or buggy writer): replaying cull.main refuses it by name instead of walking out of bounds.
TEST(BadInput, AHierarchyThatPointsOutsideItselfIsRefused) {
  const fs::path capture = scratch("hierarchy") / "capture";
  const CliResult render = run_cli("render --map-size 1 --shot street --size 64x36 -o " + quote(capture));
  ASSERT_EQ(render.code, 0) << render.err;
  const nlohmann::json manifest = read_json(capture / "manifest.json");
  nlohmann::json* recorded = nullptr;
  nlohmann::json edited = manifest;
  for (auto& pass : edited["frames"][0]["passes"])
    if (pass["name"] == "cull.main")
      for (auto& input : pass["inputs"])
        if (input["resource"] == "scene.hierarchy") recorded = &input;
  ASSERT_NE(recorded, nullptr);
  const std::vector<uint8_t> original =
      read_buffer_blob(capture / (*recorded)["blob"].get<std::string>(), (*recorded)["bytes"].get<uint64_t>());
  struct Edit {
    size_t offset;  // of a 32-bit word
    uint32_t value;
    std::string problem;
  };
  HierarchyHeader header;
  ASSERT_GE(original.size(), sizeof(header));
  std::memcpy(&header, original.data(), sizeof(header));
  const size_t root = sizeof(header), static_order = sizeof(header) + header.node_count * sizeof(HierarchyNode);
  for (const Edit& edit : {Edit{offsetof(HierarchyHeader, node_count), 1u << 30, "its header does not match its size"},
                           Edit{root + offsetof(HierarchyNode, first), 0, "node 0 has bad children"},
                           Edit{static_order, 0xFFFFFFF0u, "instance 4294967280 is out of range"}}) {
    std::vector<uint8_t> bytes = original;
    std::memcpy(bytes.data() + edit.offset, &edit.value, 4);
    const std::string hash = content_hash(bytes);
    const std::string blob = "blobs/" + hash + "." + buffer_blob_extension();
    write_buffer_blob(capture / blob, bytes, 1);
    (*recorded)["blob"] = blob;
    (*recorded)["hash"] = hash;
    write_json(capture / "manifest.json", edited);
    const CliResult r = run_cli("replay --pass cull.main " + quote(capture));
    expect_bad_input(r, "scene.hierarchy: " + edit.problem);
  }
}

TEST(BadInput, AnOlderCaptureVersionIsRefusedByName) {
  const fs::path capture = copy_of_city("version");
  nlohmann::json manifest = read_json(capture / "manifest.json");
  for (int version : {1, 3, 4}) {
    manifest["version"] = version;
    write_json(capture / "manifest.json", manifest);
    expect_bad_input(run_cli("passes " + quote(capture)),
                     "capture version " + std::to_string(version) + " is no longer read");
  }
  manifest["version"] = 6;
  write_json(capture / "manifest.json", manifest);
  expect_bad_input(run_cli("passes " + quote(capture)), "capture version 6 is newer");
}

TEST(BadInput, MissingCaptureAndUnknownPass) {
  expect_bad_input(run_cli("passes /nonexistent/capture"), "/nonexistent/capture");
  const fs::path capture = shared_capture("city-small", kSmall);
  expect_bad_input(run_cli("replay --pass no.such.pass " + quote(capture)), "no.such.pass");
  expect_bad_input(run_cli("replay --frame 7 " + quote(capture)), "frame");
}

// Starts `nightcap ARGS...` without waiting; stdout and stderr go to files in `dir`.
pid_t spawn_cli(const std::vector<std::string>& args, const fs::path& dir) {
  const std::string out = (dir / "stdout").string(), err = (dir / "stderr").string();
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> argv_strings = {NIGHTCAP_CLI};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, NIGHTCAP_CLI, &files, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&files);
  return pid;
}

// Waits until the render's temporary capture folder exists (it is made before the first frame).
bool wait_for(const fs::path& path) {
  for (int i = 0; i < 600 && !fs::exists(path); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  return fs::exists(path);
}

// A render of 500 small frames to dir/cap, started and seen to have made its temporary folder.
struct LongRender {
  pid_t pid = -1;
  fs::path temporary;
};
LongRender start_long_render(const fs::path& dir, const fs::path& logs) {
  LongRender render;
  render.pid =
      spawn_cli({"render", "--city-block", "--size", "64x36", "--frames", "500", "-o", (dir / "cap").string()}, logs);
  render.temporary = dir / ("cap.tmp-" + std::to_string(render.pid));
  EXPECT_GT(render.pid, 0);
  EXPECT_TRUE(wait_for(render.temporary)) << render.temporary << " never appeared";
  return render;
}

// SIGTERM (a service manager's stop) and SIGINT (Ctrl-C at a terminal) stop a render between
// frames alike.
class InterruptedRender : public ::testing::TestWithParam<int> {};

TEST_P(InterruptedRender, LeavesNothingBehind) {
  const fs::path dir = scratch("out"), logs = scratch("logs");
  const LongRender render = start_long_render(dir, logs);
  ASSERT_FALSE(::testing::Test::HasFailure());
  kill(render.pid, GetParam());
  int status = 0;
  waitpid(render.pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "render died of its signal instead of stopping";
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream err(logs / "stderr");
  const std::string message((std::istreambuf_iterator<char>(err)), {});
  EXPECT_NE(message.find("interrupted: no capture written to " + (dir / "cap").string()), std::string::npos) << message;
  EXPECT_TRUE(entries(dir).empty());
}

INSTANTIATE_TEST_SUITE_P(BadInput, InterruptedRender, ::testing::Values(SIGTERM, SIGINT),
                         [](const auto& info) { return std::string(info.param == SIGINT ? "SIGINT" : "SIGTERM"); });

TEST(BadInput, AKilledRendersTemporaryIsRemovedByTheNextRender) {
  const fs::path dir = scratch("out"), logs = scratch("logs");
  const LongRender render = start_long_render(dir, logs);
  ASSERT_FALSE(::testing::Test::HasFailure());
  kill(render.pid, SIGKILL);
  waitpid(render.pid, nullptr, 0);
  ASSERT_TRUE(fs::exists(render.temporary)) << "SIGKILL cannot be caught: the temporary must still be there";
  // A temporary whose writer is alive (this test process stands in for one) is left alone.
  const fs::path live = dir / ("cap.tmp-" + std::to_string(getpid()));
  fs::create_directories(live);
  const CliResult r = run_cli(std::string("render ") + kSmall + " -o " + quote(dir / "cap"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"cap", live.filename().string()}));
}

TEST(Cli, EveryCommandHasHelp) {
  for (const char* command :
       {"", "render ", "passes ", "check ", "replay ", "diff ", "golden ", "golden update ", "golden list "}) {
    const CliResult r = run_cli(std::string(command) + "--help");
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << command << r.out;
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
