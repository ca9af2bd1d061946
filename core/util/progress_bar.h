#pragma once
// Progress of long work (loom-lab, the loom client) on stderr: a bar redrawn in place on a terminal,
// nothing when stderr is a file or pipe (the --json output is the record there).

#include <string>
#include <string_view>

namespace loom {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();  // ends the line if one was drawn

  // fraction in [0, 1]; redraws at most every 1/200 of the work or on a new stage.
  void Update(double fraction, std::string_view stage);

 private:
  std::string label_;
  bool terminal_;
  int last_permille_ = -1;
  std::string last_stage_;
};

}  // namespace loom
