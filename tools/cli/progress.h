// Progress on stderr for long commands (`bench`, `run`): a redrawn bar when stderr is a terminal, else plain lines
// (one per announced item) so logs stay readable.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

namespace penumbra::cli {

class Progress {
 public:
  Progress(size_t total, bool enabled, std::string prefix = "bench")
      : total_(std::max<size_t>(total, 1)), enabled_(enabled), prefix_(std::move(prefix)) {
    terminal_ = enabled && isatty(fileno(stderr)) != 0;
  }
  bool terminal() const { return terminal_; }
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // A new item begins (plain mode prints it).
  void announce(const std::string& what) {
    label_ = what;
    if (enabled_ && !terminal_)
      fmt::print(stderr, "{}: {} ({}% done)\n", prefix_, what, std::min(done_, total_) * 100 / total_);
    draw();
  }
  // `done` units finished, described by `what` (terminal mode redraws the bar; plain mode prints nothing).
  void update(size_t done, const std::string& what) {
    done_ = done, label_ = what;
    draw();
  }
  // One unit of work done (terminal mode redraws the bar).
  void advance() {
    ++done_;
    draw();
  }
  void finish() {
    if (terminal_ && drawn_) fmt::print(stderr, "\n");
    drawn_ = false;
  }

 private:
  void draw() {
    if (!terminal_) return;
    constexpr size_t kWidth = 30;
    const size_t filled = std::min(done_, total_) * kWidth / total_;
    fmt::print(stderr, "\r[{}{}] {:>3}% {:<60.60}", std::string(filled, '#'), std::string(kWidth - filled, '.'),
               std::min(done_, total_) * 100 / total_, label_);
    std::fflush(stderr);
    drawn_ = true;
  }

  size_t total_, done_ = 0;
  bool enabled_, terminal_ = false, drawn_ = false;
  std::string prefix_, label_;
};

}  // namespace penumbra::cli
