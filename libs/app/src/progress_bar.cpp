#include "dlo/app/progress_bar.h"

#include <algorithm>
#include <cstdio>

namespace dlo {

ProgressBar::ProgressBar(size_t total, std::string unit, bool enabled)
    : total_(total),
      unit_(std::move(unit)),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()) {}

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
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
  if (total_ == 0) {
    std::fprintf(stderr, "\r%zu %s (%.1f/s)   ", done, unit_.c_str(), rate);
  } else {
    constexpr size_t kWidth = 40;
    const size_t filled = std::min(kWidth, done * kWidth / total_);
    const std::string bar = std::string(filled, '#') + std::string(kWidth - filled, ' ');
    std::fprintf(stderr, "\r[%s] %zu/%zu %s (%.1f/s)   ", bar.c_str(), done, total_, unit_.c_str(),
                 rate);
  }
  std::fflush(stderr);
}

}  // namespace dlo
