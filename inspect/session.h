// The state of an inspect session: an open capture, the current frame and the current pass, and
// which version of a resource the current pass sees. Blobs are read when a command first needs
// them and kept for the session, so stepping through passes re-reads nothing.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "captures/capture.h"
#include "inspect/decode.h"
#include "passes/core/device.h"

namespace nightcap {

class InspectSession {
 public:
  // `device`: where commands that run passes again (replay, pick) run them; the device is
  // created when one first does, so a session that only reads the capture never starts Vulkan.
  InspectSession(Capture capture, GpuDevice::Options device);

  const Capture& capture() const { return capture_; }
  const FrameRecord& frame() const { return capture_.manifest().frames[frame_position_]; }
  size_t frame_position() const { return frame_position_; }  // in the manifest's frames
  const PassRecord& pass() const { return frame().passes[pass_index_]; }
  size_t pass_index() const { return pass_index_; }

  // Throws InspectError naming what is missing. Changing frame keeps the current pass by name
  // where the other frame has it.
  void go_to_frame(uint32_t index);
  void go_to_pass(const std::string& name);
  void next_pass();
  void previous_pass();

  // The version of `resource` the current pass sees: what it wrote, else what it read, else
  // the last version written before it, else the first version the frame holds. Outputs of a
  // pass (which carry the contract and schema) are preferred over equal inputs.
  const ResourceRecord& resource(const std::string& name) const;
  // The same, in frame `frame` at the pass of the current pass's name (for following a pixel
  // across frames); nullptr when that frame lacks the pass or the resource.
  const ResourceRecord* resource_in_frame(const FrameRecord& frame, const std::string& name) const;
  // The schema of the buffer version `record` (recorded with the output that wrote it).
  const BufferSchema* schema_of(const ResourceRecord& record) const;

  const std::vector<uint8_t>& load(const ResourceRecord& record);

  GpuDevice& gpu();

  std::vector<std::string> pass_names() const;
  std::vector<std::string> resource_names() const;  // every resource of the current frame

 private:
  Capture capture_;
  GpuDevice::Options device_options_;
  std::unique_ptr<GpuDevice> gpu_;
  size_t frame_position_ = 0, pass_index_ = 0;
  std::map<std::string, std::vector<uint8_t>> blobs_;  // raw bytes by content hash
};

}  // namespace nightcap
