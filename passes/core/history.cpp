#include "passes/core/history.h"

namespace nightcap {

HistoryPool::~HistoryPool() {
  for (auto& [name, slot] : slots_) destroy(slot);
}

HistorySlot* HistoryPool::find(const std::string& resource) {
  auto it = slots_.find(resource);
  return it == slots_.end() ? nullptr : &it->second;
}

HistorySlot& HistoryPool::replace(const std::string& resource, HistorySlot slot) {
  auto it = slots_.find(resource);
  if (it != slots_.end()) {
    destroy(it->second);
    it->second = std::move(slot);
    return it->second;
  }
  return slots_.emplace(resource, std::move(slot)).first->second;
}

HistoryPool::HostBytes HistoryPool::find_host(const std::string& resource) const {
  auto it = host_.find(resource);
  return it == host_.end() ? nullptr : it->second;
}

void HistoryPool::keep_host(const std::string& resource, HostBytes bytes) { host_[resource] = std::move(bytes); }

void HistoryPool::destroy(HistorySlot& slot) {
  gpu_.destroy(slot.resource.image);
  gpu_.destroy(slot.resource.buffer);
}

}  // namespace nightcap
