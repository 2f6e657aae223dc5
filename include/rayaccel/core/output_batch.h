// A run's output files committed together, all or none: each is written to a temporary beside its target, and the
// temporaries replace their targets only when the whole run has succeeded (output_file.h writes each one).
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

namespace rayaccel {

class OutputBatch {
 public:
  OutputBatch() = default;
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;
  /// Removes every temporary not committed: a run that failed leaves each target as it was.
  ~OutputBatch();

  /// The path to write `target` to in this run: a fresh temporary name beside it, or the target itself when that is
  /// an existing non-regular file (a device or a pipe, written in place as write_file_atomically() does).
  std::filesystem::path stage(const std::filesystem::path& target);
  /// Renames every staged temporary over its target, in the order staged. Throws Error naming the target when one
  /// was never written or cannot be renamed.
  void commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  ///< (temporary, target)
};

}  // namespace rayaccel
