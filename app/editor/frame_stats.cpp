#include "editor/frame_stats.h"

#include <algorithm>

namespace sinew::editor {

void FrameTimes::add(double seconds) {
  if (times_.size() < capacity_) {
    times_.push_back(seconds);
  } else {
    times_[next_] = seconds;
    next_ = (next_ + 1) % times_.size();
  }
}

void FrameTimes::clear() {
  times_.clear();
  next_ = 0;
}

double FrameTimes::percentile(double p) const {
  if (times_.empty()) return 0.0;
  std::vector<double> sorted = times_;
  std::sort(sorted.begin(), sorted.end());
  return sorted[static_cast<size_t>(std::clamp(p, 0.0, 1.0) *
                                    static_cast<double>(sorted.size() - 1))];
}

double FrameTimes::longest() const {
  return times_.empty() ? 0.0 : *std::max_element(times_.begin(), times_.end());
}

const char* frameStageName(FrameStage stage) {
  switch (stage) {
    case FrameStage::kEvents:
      return "events";
    case FrameStage::kPanels:
      return "panels";
    case FrameStage::kScene:
      return "scene";
    case FrameStage::kShadow:
      return "shadow";
    case FrameStage::kViewport:
      return "3D view";
    case FrameStage::kImgui:
      return "ImGui draw";
    case FrameStage::kSwap:
      return "swap";
    case FrameStage::kCount:
      break;
  }
  return "?";
}

void StageProfile::mark(FrameStage stage) {
  const Clock::time_point now = Clock::now();
  total_s_[static_cast<size_t>(stage)] += std::chrono::duration<double>(now - last_).count();
  last_ = now;
}

void StageProfile::clear() {
  total_s_.fill(0.0);
  frames_ = 0;
}

double StageProfile::meanMs(FrameStage stage) const {
  return frames_ > 0 ? 1000.0 * total_s_[static_cast<size_t>(stage)] / frames_ : 0.0;
}

}  // namespace sinew::editor
