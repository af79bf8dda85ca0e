#include "dlo/mrpt/progress_bar.h"

#include <algorithm>
#include <cstdio>

namespace dlo {

ProgressBar::ProgressBar(size_t total, std::string unit, bool enabled)
    : total_(total), unit_(std::move(unit)), enabled_(enabled) {}

ProgressBar::~ProgressBar() {
  if (drawn_ && !finished_) std::fputc('\n', stderr);
}

void ProgressBar::update(size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  draw(done);
}

void ProgressBar::finish(size_t done) {
  if (!enabled_) return;
  draw(done);
  std::fputc('\n', stderr);
  finished_ = true;
}

void ProgressBar::draw(size_t done) {
  drawn_ = true;
  if (total_ == 0) {
    std::fprintf(stderr, "\r%zu %s", done, unit_.c_str());
  } else {
    constexpr size_t kWidth = 40;
    const size_t filled = std::min(kWidth, done * kWidth / total_);
    const std::string bar = std::string(filled, '#') + std::string(kWidth - filled, ' ');
    std::fprintf(stderr, "\r[%s] %zu/%zu %s", bar.c_str(), done, total_, unit_.c_str());
  }
  std::fflush(stderr);
}

}  // namespace dlo
