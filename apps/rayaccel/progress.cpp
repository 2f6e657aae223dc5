// The stderr progress line of the CLI (see progress.h).
#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace rayaccel::cli {

Progress::Progress() : terminal_(isatty(fileno(stderr)) != 0), ticker_([this] { tick(); }) {}

Progress::~Progress() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  ticker_.join();
  done();
}

void Progress::stage(const std::string& label) {
  done();
  const std::lock_guard lock(mutex_);
  label_ = label;
  step_.clear();
  last_percent_ = -1;
  open_ = true;
  step_start_ = Clock::now();
  last_note_seconds_ = 0;
  if (terminal_) {
    redraw_locked();
  } else {
    std::cerr << label_ << "\n" << std::flush;
  }
}

void Progress::step(const std::string& label) {
  const std::lock_guard lock(mutex_);
  step_ = label;
  last_percent_ = -1;
  step_start_ = Clock::now();
  last_note_seconds_ = 0;
  if (open_ && terminal_) redraw_locked();
}

void Progress::update(float fraction) {
  const std::lock_guard lock(mutex_);
  if (!open_ || !terminal_) return;
  const int percent = static_cast<int>(std::clamp(fraction, 0.0f, 1.0f) * 100.0f);
  if (percent == last_percent_) return;
  last_percent_ = percent;
  redraw_locked();
}

void Progress::redraw_locked() const {
  std::cerr << "\r\033[K" << label_;
  if (!step_.empty()) std::cerr << ": " << step_;
  if (last_percent_ >= 0) std::cerr << " " << last_percent_ << "%";
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - step_start_).count();
  if (seconds >= 1) std::cerr << " (" << seconds << " s)";
  std::cerr << std::flush;
}

void Progress::done() {
  const std::lock_guard lock(mutex_);
  if (open_ && terminal_) std::cerr << "\r\033[K" << std::flush;
  open_ = false;
}

void Progress::tick() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::seconds(1));
    if (stopping_ || !open_) continue;
    if (terminal_) {
      redraw_locked();
      continue;
    }
    const auto seconds =
        static_cast<int>(std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - step_start_).count());
    if (seconds >= last_note_seconds_ + kQuietNoteSeconds) {
      last_note_seconds_ = seconds - seconds % kQuietNoteSeconds;
      std::cerr << "... still " << (step_.empty() ? label_ : label_ + ": " + step_) << " (" << seconds << " s)\n"
                << std::flush;
    }
  }
}

}  // namespace rayaccel::cli
