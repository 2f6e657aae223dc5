// The CLI's one-line progress display on stderr: stage, step, percentage and the step's elapsed time, redrawn by a
// background ticker so a long build that reports nothing still shows it is alive.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace rayaccel::cli {

/// On a terminal the line is redrawn in place with the current step, its percentage (where the work reports one)
/// and, once a step has run for a second, its elapsed seconds (refreshed every second). Otherwise each stage prints
/// one line, and a step still running after kQuietNoteSeconds prints "... still <step> (N s)" lines that far apart.
class Progress {
 public:
  static constexpr int kQuietNoteSeconds = 30;

  Progress();
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Starts a stage (a line of its own when stderr is not a terminal).
  void stage(const std::string& label);
  /// A step within the current stage; shown only on a terminal; restarts the elapsed time.
  void step(const std::string& label);
  void update(float fraction);
  /// Ends the current line.
  void done();

 private:
  using Clock = std::chrono::steady_clock;
  void redraw_locked() const;
  void tick();

  const bool terminal_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::string label_;
  std::string step_;
  int last_percent_ = -1;
  bool open_ = false;
  bool stopping_ = false;
  Clock::time_point step_start_ = Clock::now();
  int last_note_seconds_ = 0;
  std::thread ticker_;
};

}  // namespace rayaccel::cli
