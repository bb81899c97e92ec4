// The editor's frame-time figures: the last frames' times (the overlay's fps) and, in the
// benchmark, where each frame's time went stage by stage. Plain code, no ImGui or OpenGL.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <vector>

namespace sinew::editor {

// Frame times in seconds; the median and 95th percentile of the last `capacity` of them.
class FrameTimes {
 public:
  explicit FrameTimes(size_t capacity = 240) : capacity_(capacity) {}
  void add(double seconds);
  void clear();
  size_t size() const { return times_.size(); }
  double percentile(double p) const;  // p in [0, 1]; 0 when empty
  double longest() const;             // 0 when empty

 private:
  size_t capacity_;
  std::vector<double> times_;
  size_t next_ = 0;
};

// The stages of one frame, in the order the main loop runs them.
enum class FrameStage : int {
  kEvents,    // GLFW events, dropped files, playback
  kPanels,    // ImGui's panels (and polling the search's snapshot)
  kScene,     // the scene built from the state, picking, the camera, ImGui::Render
  kShadow,    // the key light's shadow map (GL, finished)
  kViewport,  // the 3D view: capsules, meshes, grid (GL, finished)
  kImgui,     // ImGui's draw lists rasterised (GL, finished)
  kSwap,      // glfwSwapBuffers
  kCount
};
inline constexpr int kFrameStageCount = static_cast<int>(FrameStage::kCount);
const char* frameStageName(FrameStage stage);

// Seconds spent per stage over the frames since the last clear(). A stage is timed from the end
// of the one before (mark()), so the stages add up to the frame's work.
class StageProfile {
 public:
  using Clock = std::chrono::steady_clock;
  void beginFrame() { last_ = Clock::now(); }
  void mark(FrameStage stage);  // the time since the last mark (or beginFrame) goes to `stage`
  void endFrame() { ++frames_; }
  void clear();
  int frames() const { return frames_; }
  double meanMs(FrameStage stage) const;  // per frame

 private:
  Clock::time_point last_{};
  std::array<double, kFrameStageCount> total_s_{};
  int frames_ = 0;
};

}  // namespace sinew::editor
