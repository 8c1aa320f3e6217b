// The history pool: what passes read one frame later (PassDecl::read_previous). The caller keeps
// it across frames; execute_graph binds each previous(name) to its slot, starts a slot from the
// resource's clear value when it has no valid history (first frame, camera cut, resize), and at
// the end of the frame copies the resource's final version into the slot for the next frame
// unless that version is the clear value: then the slot is cleared when a frame starts from it,
// once (an empty scene's skipped shadow maps cost no clear and no copy per frame).
// A CPU pass's output read by a CPU pass a frame later (a plan that remembers what it decided)
// is kept as its bytes; with no valid history it reads as empty.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "passes/core/execution_state.h"

namespace nightcap {

struct HistorySlot {
  // Between frames it is where the frame's last command, the copy into it, left it: the graph's
  // barrier plan starts it there (or clears it when its history is reset).
  PhysicalResource resource;
  VkImageUsageFlags usage = 0;
  bool filled = false;  // holds a value some frame wrote
  // The last frame left the resource at its clear value (its writers skipped) and copied nothing:
  // the slot's value is the clear value, which its bytes are when holds_clear_value.
  bool at_clear_value = false;
  bool holds_clear_value = false;  // cleared, and not copied into since
};

class HistoryPool {
 public:
  explicit HistoryPool(GpuDevice& gpu) : gpu_(gpu) {}
  ~HistoryPool();
  HistoryPool(const HistoryPool&) = delete;
  HistoryPool& operator=(const HistoryPool&) = delete;

  // The slot remembering `resource`; nullptr when there is none yet.
  HistorySlot* find(const std::string& resource);
  // A new, unfilled slot for `resource` (replacing one of another size or usage).
  HistorySlot& replace(const std::string& resource, HistorySlot slot);

  using HostBytes = std::shared_ptr<const std::vector<uint8_t>>;
  // The bytes a CPU pass wrote to `resource` in the last frame that kept them; null when none has.
  HostBytes find_host(const std::string& resource) const;
  void keep_host(const std::string& resource, HostBytes bytes);

 private:
  void destroy(HistorySlot& slot);
  GpuDevice& gpu_;
  std::map<std::string, HistorySlot> slots_;
  std::map<std::string, HostBytes> host_;
};

}  // namespace nightcap
