// `nightcap check`: every blob of a capture read, decoded and its content hash checked. A sound
// capture exits 0; each bad blob is named with what is wrong and the records that refer to it,
// and the command exits 2, whether or not any other command would ever read that blob.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>

#include "captures/capture.h"
#include "tests/e2e/cli.h"
#include "tests/e2e/damaged_capture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const char* kSmall = "--city-block --size 64x36";

fs::path copy_of_city(const std::string& name) {
  const fs::path copy = scratch(name) / "capture";
  fs::copy(shared_capture("city-small", kSmall), copy, fs::copy_options::recursive);
  return copy;
}

// The blob paths the manifest names, read from its JSON.
std::set<std::string> named_blobs(const fs::path& capture) {
  std::set<std::string> blobs;
  const json manifest = read_json(capture / "manifest.json");
  for (const json& frame : manifest.at("frames"))
    for (const json& pass : frame.at("passes")) {
      for (const char* side : {"inputs", "outputs"})
        for (const json& r : pass.at(side)) blobs.insert(r.at("blob").get<std::string>());
      for (const json& s : pass.at("shaders")) {
        blobs.insert(s.at("blob").get<std::string>());
        blobs.insert(s.at("source_blob").get<std::string>());
      }
    }
  return blobs;
}

const ResourceRecord& record_of(const Capture& capture, const std::string& pass, const std::string& resource,
                                bool output) {
  for (const PassRecord& p : capture.frame(0).passes)
    if (p.name == pass)
      for (const ResourceRecord& r : output ? p.outputs : p.inputs)
        if (r.resource == resource) return r;
  throw std::runtime_error("no " + resource + " of " + pass);
}

// check --json's bad blobs by blob path.
std::map<std::string, json> bad_blobs(const CliResult& r) {
  std::map<std::string, json> bad;
  const json out = json::parse(r.out);
  for (const json& b : out.at("bad")) bad[b.at("blob").get<std::string>()] = b;
  return bad;
}

TEST(Check, ASoundCapturePasses) {
  const fs::path capture = shared_capture("city-small", kSmall);
  const CliResult r = run_cli("check --json " + quote(capture));
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const json out = json::parse(r.out);
  EXPECT_TRUE(out.at("ok").get<bool>());
  EXPECT_EQ(out.at("bad"), json::array());
  EXPECT_EQ(out.at("blobs").get<size_t>(), named_blobs(capture).size());
  const CliResult text = run_cli("check " + quote(capture));
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("every blob reads, decodes and matches its hash"), std::string::npos) << text.out;
}

// Each blob replaced by one that decodes but hashes otherwise: every one is named, so every one
// was read and hashed.
TEST(Check, EveryBlobIsReadAndHashed) {
  const fs::path capture = copy_of_city("every");
  const std::set<std::string> damaged = damage_every_blob(capture);
  const CliResult r = run_cli("check --json " + quote(capture));
  EXPECT_EQ(r.code, 2) << r.err;
  std::set<std::string> named;
  for (const auto& [blob, b] : bad_blobs(r)) {
    named.insert(blob);
    EXPECT_EQ(b.at("problem"), "hash_mismatch") << b.dump();
  }
  EXPECT_EQ(named, damaged);
  EXPECT_GT(damaged.size(), named_blobs(capture).size() * 9 / 10) << "empty resources are all that is left";
}

// stencil.half is written and read by no pass (until the half-resolution passes that read it
// land), and replay compares what it makes with the recorded hashes: its blob is read by `check`
// alone.
TEST(Check, ACorruptBlobNoPassReadsIsNamedWhileReplayVerifies) {
  const fs::path capture = copy_of_city("unread");
  const Capture opened = Capture::open(capture);
  std::string writer;
  for (const PassRecord& p : opened.frame(0).passes) {
    for (const ResourceRecord& r : p.inputs) ASSERT_NE(r.resource, "stencil.half") << p.name << " reads it";
    for (const ResourceRecord& r : p.outputs)
      if (r.resource == "stencil.half") writer = p.name;
  }
  ASSERT_FALSE(writer.empty());
  const ResourceRecord& stencil = record_of(opened, writer, "stencil.half", true);
  std::vector<uint8_t> other(stencil.raw_bytes(), 0);
  other[0] = 1;
  write_image_blob(capture / stencil.blob, *format_info(stencil.format), stencil.extent, other, {ExrCompression::zip});

  const CliResult replay = run_cli("replay --verify " + quote(capture));
  EXPECT_EQ(replay.code, 0) << replay.err;
  EXPECT_NE(replay.out.find("replay matches the capture"), std::string::npos) << replay.out;

  const CliResult r = run_cli("check --json " + quote(capture));
  EXPECT_EQ(r.code, 2) << r.err;
  const std::map<std::string, json> bad = bad_blobs(r);
  ASSERT_EQ(bad.size(), 1u) << r.out;
  const json& b = bad.begin()->second;
  EXPECT_EQ(bad.begin()->first, stencil.blob);
  EXPECT_EQ(b.at("problem"), "hash_mismatch");
  EXPECT_NE(b.at("detail").get<std::string>().find(stencil.blob), std::string::npos) << b.dump();
  EXPECT_EQ(b.at("references"), (json{{{"frame", 0}, {"pass", writer}, {"role", "output"}, {"name", "stencil.half"}}}));

  const CliResult text = run_cli("check " + quote(capture));
  EXPECT_EQ(text.code, 2);
  EXPECT_NE(text.out.find(stencil.blob + ": hash_mismatch"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("output stencil.half of " + writer + " (frame 0)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(": 1 bad"), std::string::npos) << text.out;
}

// An image and a buffer cut short (at several lengths), one removed, a buffer of another size, an
// image of full length whose last bytes (compressed pixels) are garbage: each is named with its
// own problem, every other blob is sound.
TEST(Check, TruncatedMissingAndUndecodableBlobs) {
  const fs::path capture = copy_of_city("damaged");
  const Capture opened = Capture::open(capture);
  const ResourceRecord& image = record_of(opened, "lighting.composite", "lighting.lit", true);
  const ResourceRecord& buffer = record_of(opened, "cull.main", "scene.geometry", false);
  const ResourceRecord& removed = record_of(opened, "tonemap", "final.ldr", true);
  const ResourceRecord& resized = record_of(opened, "cull.main", "scene.instances", false);
  const ResourceRecord& garbled = record_of(opened, "lighting.tiled", "lighting.diffuse", true);
  ASSERT_EQ((std::set<std::string>{image.blob, buffer.blob, removed.blob, resized.blob, garbled.blob}).size(), 5u);
  {
    std::fstream file(capture / garbled.blob, std::ios::binary | std::ios::in | std::ios::out);
    file.seekp(-64, std::ios::end);
    file << std::string(64, '\xff');
  }
  const std::vector<uint8_t> longer(resized.raw_bytes() + 4, 0);
  write_buffer_blob(capture / resized.blob, longer, 3);
  fs::remove(capture / removed.blob);
  const auto image_size = fs::file_size(capture / image.blob), buffer_size = fs::file_size(capture / buffer.blob);
  for (const double kept : {0.9, 0.5, 0.01}) {
    fs::resize_file(capture / image.blob, uintmax_t(double(image_size) * kept));
    fs::resize_file(capture / buffer.blob, uintmax_t(double(buffer_size) * kept));
    const CliResult r = run_cli("check --json " + quote(capture));
    EXPECT_EQ(r.code, 2) << r.err;
    std::map<std::string, std::string> problems;
    for (const auto& [blob, b] : bad_blobs(r)) problems[blob] = b.at("problem");
    EXPECT_EQ(problems, (std::map<std::string, std::string>{{image.blob, "truncated"},
                                                            {buffer.blob, "truncated"},
                                                            {removed.blob, "missing"},
                                                            {resized.blob, "undecodable"},
                                                            {garbled.blob, "undecodable"}}))
        << "kept " << kept << " of the image and the buffer: " << r.out;
  }
}

// A manifest that names a blob outside blobs/ is refused before anything is read; a blob that is a
// link to a sound copy outside the capture is refused, not followed (it would pass if read).
TEST(Check, BlobsOutsideTheCaptureAreRefusedUnread) {
  const fs::path capture = copy_of_city("outside");
  const fs::path outside = capture.parent_path() / "outside.exr";
  const json manifest = read_json(capture / "manifest.json");
  const Capture opened = Capture::open(capture);
  const ResourceRecord& ldr = record_of(opened, "tonemap", "final.ldr", true);
  fs::copy_file(capture / ldr.blob, outside);
  for (const std::string& path :
       {std::string("../outside.exr"), std::string("blobs/../../outside.exr"), outside.string()}) {
    json edited = manifest;
    for (json& pass : edited.at("frames")[0].at("passes"))
      if (pass.at("name") == "tonemap") pass.at("outputs")[0]["blob"] = path;
    write_json(capture / "manifest.json", edited);
    const CliResult r = run_cli("check " + quote(capture));
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.err.find("blob path '" + path + "' leaves blobs/"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << "refused before any blob is read";
  }
  write_json(capture / "manifest.json", manifest);
  fs::remove(capture / ldr.blob);
  fs::create_symlink(outside, capture / ldr.blob);
  const CliResult r = run_cli("check --json " + quote(capture));
  EXPECT_EQ(r.code, 2) << r.err;
  const std::map<std::string, json> bad = bad_blobs(r);
  ASSERT_EQ(bad.size(), 1u) << r.out;
  EXPECT_EQ(bad.begin()->first, ldr.blob);
  EXPECT_EQ(bad.begin()->second.at("problem"), "refused");
  EXPECT_NE(bad.begin()->second.at("detail").get<std::string>().find("leaves the capture folder"), std::string::npos)
      << r.out;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
