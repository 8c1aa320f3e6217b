// Bad input gets a clear message naming the file or flag, exit code 2, no crash, and nothing
// written outside -o.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace fs = std::filesystem;

const char* kSmall = "--size 64x36";

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
  expect_bad_input(run_cli("render " + quote(dir / "box.gltf") + " " + kSmall + " -o " + quote(dir / "cap")),
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
  const std::string lit = first_output(manifest, "lighting.composite")["blob"];
  const std::string diffuse = first_output(manifest, "lighting.deferred")["blob"];
  // tonemap reads lighting.lit: give its file another valid blob of the same format and size,
  // which decodes fine but hashes differently.
  fs::copy_file(capture / diffuse, capture / lit, fs::copy_options::overwrite_existing);
  const CliResult r = run_cli("replay --verify --pass tonemap " + quote(capture));
  expect_bad_input(r, lit.substr(lit.find('/') + 1));
  EXPECT_NE(r.err.find("hash"), std::string::npos) << r.err;
}

TEST(BadInput, BlobPathsThatLeaveTheCapture) {
  const fs::path capture = copy_of_city("escape");
  nlohmann::json manifest = read_json(capture / "manifest.json");
  for (const char* path : {"../../../etc/passwd", "/etc/passwd", "blobs/../../outside.exr"}) {
    nlohmann::json edited = manifest;
    first_output(edited, "tonemap")["blob"] = path;
    write_json(capture / "manifest.json", edited);
    expect_bad_input(run_cli("passes " + quote(capture)), "manifest.json");
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
  expect_bad_input(edit([](nlohmann::json& o) { o["width"] = 70000; }), "70000");
  expect_bad_input(edit([](nlohmann::json& o) {
                     o["width"] = 16384;
                     o["height"] = 16384;
                     o["layers"] = 2048;
                   }),
                   "manifest.json");
  expect_bad_input(edit([](nlohmann::json& o) { o["width"] = -1; }), "manifest.json");
}

TEST(BadInput, MissingCaptureAndUnknownPass) {
  expect_bad_input(run_cli("passes /nonexistent/capture"), "/nonexistent/capture");
  const fs::path capture = shared_capture("city-small", kSmall);
  expect_bad_input(run_cli("replay --pass no.such.pass " + quote(capture)), "no.such.pass");
  expect_bad_input(run_cli("replay --frame 7 " + quote(capture)), "frame");
}

TEST(Cli, EveryCommandHasHelp) {
  for (const char* command : {"", "render ", "passes ", "replay ", "diff "}) {
    const CliResult r = run_cli(std::string(command) + "--help");
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << command << r.out;
  }
}

}  // namespace
}  // namespace nightcap::test
