#include "core/scene/mesh_sequence_cache.h"

#include <algorithm>
#include <glm/glm.hpp>

namespace loom {
namespace {

std::string Key(const std::string& artifact, const std::string& mesh_name) { return artifact + '\n' + mesh_name; }

size_t SequenceBytes(const MeshSequence& sequence) {
  size_t bytes = sequence.mesh.uvs.size() * sizeof(glm::vec2) + sequence.mesh.indices.size() * sizeof(uint32_t);
  for (const std::vector<glm::vec3>& frame : sequence.frames) bytes += frame.size() * sizeof(glm::vec3);
  return bytes;
}

}  // namespace

MeshSequenceCache::MeshSequenceCache(size_t budget_bytes) : budget_(budget_bytes) {}

std::shared_ptr<const MeshSequence> MeshSequenceCache::Find(const std::string& artifact,
                                                             const std::string& mesh_name) {
  const std::string key = Key(artifact, mesh_name);
  const std::lock_guard lock(mutex_);
  const auto found = Locate(key);
  if (found == entries_.end()) return nullptr;
  entries_.splice(entries_.begin(), entries_, found);
  return found->sequence;
}

void MeshSequenceCache::Keep(const std::string& artifact, const std::string& mesh_name,
                             std::shared_ptr<const MeshSequence> sequence) {
  const size_t bytes = SequenceBytes(*sequence);
  if (bytes > budget_) return;
  const std::string key = Key(artifact, mesh_name);
  const std::lock_guard lock(mutex_);
  const auto found = Locate(key);
  if (found != entries_.end()) {
    bytes_ -= found->bytes;
    entries_.erase(found);
  }
  while (!entries_.empty() && bytes_ + bytes > budget_) {
    bytes_ -= entries_.back().bytes;
    entries_.pop_back();
  }
  entries_.push_front({key, std::move(sequence), bytes});
  bytes_ += bytes;
}

std::list<MeshSequenceCache::Entry>::iterator MeshSequenceCache::Locate(const std::string& key) {
  return std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.key == key; });
}

size_t MeshSequenceCache::bytes() const {
  const std::lock_guard lock(mutex_);
  return bytes_;
}

}  // namespace loom
