#pragma once
// Uploaded glTF sequences kept parsed, by the artifact they came from and the
// mesh taken from it. A frame-range render is a job a frame of one sequence: the
// server (checking each submission) and a worker (downloading and rendering each
// frame) would otherwise read and parse the whole file once a frame.
// Artifacts are content-addressed, so what is kept never goes stale. At most
// `budget_bytes` of positions are kept, the least recently used dropped first; a
// sequence larger than the budget is not kept. Thread-safe.

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>

#include "core/scene/gltf_loader.h"

namespace loom {

class MeshSequenceCache {
 public:
  static constexpr size_t kDefaultBudgetBytes = size_t{512} << 20;

  explicit MeshSequenceCache(size_t budget_bytes = kDefaultBudgetBytes);

  // The sequence kept for mesh `mesh_name` of artifact `artifact`, or null.
  std::shared_ptr<const MeshSequence> Find(const std::string& artifact, const std::string& mesh_name);
  void Keep(const std::string& artifact, const std::string& mesh_name, std::shared_ptr<const MeshSequence> sequence);

  size_t bytes() const;  // of the sequences kept

 private:
  struct Entry {
    std::string key;
    std::shared_ptr<const MeshSequence> sequence;
    size_t bytes = 0;
  };
  // The entry of `key`, or end(); under mutex_.
  std::list<Entry>::iterator Locate(const std::string& key);

  const size_t budget_;
  mutable std::mutex mutex_;
  std::list<Entry> entries_;  // the most recently used first
  size_t bytes_ = 0;
};

}  // namespace loom
