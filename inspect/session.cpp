#include "inspect/session.h"

#include <set>

namespace nightcap {

namespace {

const ResourceRecord* find(const std::vector<ResourceRecord>& records, const std::string& name) {
  for (const ResourceRecord& r : records)
    if (r.resource == name) return &r;
  return nullptr;
}

const ResourceRecord* visible_at(const FrameRecord& frame, size_t pass_index, const std::string& name) {
  const PassRecord& pass = frame.passes[pass_index];
  if (const ResourceRecord* r = find(pass.outputs, name)) return r;
  if (const ResourceRecord* r = find(pass.inputs, name)) {
    // The writer's record of the same version carries its contract and schema.
    for (size_t i = pass_index; i-- > 0;)
      if (const ResourceRecord* w = find(frame.passes[i].outputs, name); w && w->hash == r->hash) return w;
    return r;
  }
  for (size_t i = pass_index; i-- > 0;)
    if (const ResourceRecord* r = find(frame.passes[i].outputs, name)) return r;
  for (const PassRecord& p : frame.passes) {
    if (const ResourceRecord* r = find(p.inputs, name)) return r;
    if (const ResourceRecord* r = find(p.outputs, name)) return r;
  }
  return nullptr;
}

}  // namespace

InspectSession::InspectSession(Capture capture, GpuDevice::Options device)
    : capture_(std::move(capture)), device_options_(std::move(device)) {
  if (capture_.manifest().frames.empty()) throw InspectError(capture_.folder().string() + ": the capture has no frame");
}

void InspectSession::go_to_frame(uint32_t index) {
  const auto& frames = capture_.manifest().frames;
  for (size_t position = 0; position < frames.size(); ++position) {
    if (frames[position].index != index) continue;
    const std::string current = pass().name;
    frame_position_ = position;
    pass_index_ = 0;
    for (size_t i = 0; i < frame().passes.size(); ++i)
      if (frame().passes[i].name == current) pass_index_ = i;
    return;
  }
  std::string recorded;
  for (const FrameRecord& f : frames) recorded += (recorded.empty() ? "" : ", ") + std::to_string(f.index);
  throw InspectError("no frame " + std::to_string(index) + " in the capture (recorded: " + recorded + ")");
}

void InspectSession::go_to_pass(const std::string& name) {
  for (size_t i = 0; i < frame().passes.size(); ++i)
    if (frame().passes[i].name == name) {
      pass_index_ = i;
      return;
    }
  throw InspectError("no pass '" + name + "' in frame " + std::to_string(frame().index) + " (see `passes`)");
}

void InspectSession::next_pass() {
  if (pass_index_ + 1 >= frame().passes.size()) throw InspectError("already at the last pass, " + pass().name);
  ++pass_index_;
}

void InspectSession::previous_pass() {
  if (pass_index_ == 0) throw InspectError("already at the first pass, " + pass().name);
  --pass_index_;
}

const ResourceRecord& InspectSession::resource(const std::string& name) const {
  if (const ResourceRecord* r = visible_at(frame(), pass_index_, name)) return *r;
  throw InspectError("no resource '" + name + "' in frame " + std::to_string(frame().index) + " (see `info`)");
}

const ResourceRecord* InspectSession::resource_in_frame(const FrameRecord& other, const std::string& name) const {
  for (size_t i = 0; i < other.passes.size(); ++i)
    if (other.passes[i].name == pass().name) return visible_at(other, i, name);
  return nullptr;
}

const BufferSchema* InspectSession::schema_of(const ResourceRecord& record) const {
  return nightcap::schema_of(record, frame());
}

const std::vector<uint8_t>& InspectSession::load(const ResourceRecord& record) {
  auto found = blobs_.find(record.hash);
  if (found == blobs_.end()) found = blobs_.emplace(record.hash, capture_.load(record)).first;
  return found->second;
}

GpuDevice& InspectSession::gpu() {
  if (!gpu_) gpu_ = std::make_unique<GpuDevice>(device_options_);
  return *gpu_;
}

std::vector<std::string> InspectSession::pass_names() const {
  std::vector<std::string> names;
  for (const PassRecord& p : frame().passes) names.push_back(p.name);
  return names;
}

std::vector<std::string> InspectSession::resource_names() const {
  std::set<std::string> names;
  for (const PassRecord& p : frame().passes)
    for (const auto* side : {&p.inputs, &p.outputs})
      for (const ResourceRecord& r : *side) names.insert(r.resource);
  return {names.begin(), names.end()};
}

}  // namespace nightcap
