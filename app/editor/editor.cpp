#include "editor/editor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

#include "editor/gl.h"  // before GLFW: it defines GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "editor/camera.h"
#include "editor/editor_state.h"
#include "editor/panels/panels.h"
#include "editor/renderer.h"
#include "editor/scene.h"
#include "editor/screenshot.h"
#include "editor/theme.h"

namespace sinew::editor {
namespace {

constexpr int kWindowWidth = 1600;
constexpr int kWindowHeight = 900;
constexpr double kScreenshotDt = 1.0 / 30.0;  // fixed playback step in screenshot mode, seconds

struct Rect {
  ImVec2 pos, size;
  bool contains(ImVec2 p) const {
    return p.x >= pos.x && p.y >= pos.y && p.x < pos.x + size.x && p.y < pos.y + size.y;
  }
};

// Fixed regions (ImGui 1.86 has no docking): Files over Log on the left, Spectrum on the right,
// Timeline under the viewport, the viewport in the middle. Window coordinates.
struct Layout {
  Rect files, log, spectrum, evolve, timeline, viewport;
};

Layout computeLayout(ImVec2 display) {
  const float left_w = std::round(std::clamp(display.x * 0.2f, 260.0f, 340.0f));
  const float right_w = std::round(std::clamp(display.x * 0.3f, 320.0f, 500.0f));
  const float timeline_h = 128.0f;
  const float files_h = std::round(display.y * 0.42f);
  const float centre_w = std::max(display.x - left_w - right_w, 1.0f);
  Layout l;
  l.files = {ImVec2(0, 0), ImVec2(left_w, files_h)};
  l.log = {ImVec2(0, files_h), ImVec2(left_w, display.y - files_h)};
  const float spectrum_h = std::round(display.y * 0.6f);
  l.spectrum = {ImVec2(display.x - right_w, 0), ImVec2(right_w, spectrum_h)};
  l.evolve = {ImVec2(display.x - right_w, spectrum_h), ImVec2(right_w, display.y - spectrum_h)};
  l.timeline = {ImVec2(left_w, display.y - timeline_h), ImVec2(centre_w, timeline_h)};
  l.viewport = {ImVec2(left_w, 0), ImVec2(centre_w, std::max(display.y - timeline_h, 1.0f))};
  return l;
}

void place(const Rect& rect) {
  ImGui::SetNextWindowPos(rect.pos, ImGuiCond_Always);
  ImGui::SetNextWindowSize(rect.size, ImGuiCond_Always);
}

struct ViewportDrag {
  bool orbit = false;
  bool pan = false;
};

// LMB orbit, MMB or Shift+LMB pan, wheel zoom; only when the mouse is over the viewport (or a
// drag started there).
void handleViewportMouse(OrbitCamera& camera, ViewportDrag& drag, const Rect& viewport) {
  const ImGuiIO& io = ImGui::GetIO();
  const bool hovered = !io.WantCaptureMouse && viewport.contains(io.MousePos);
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    (io.KeyShift ? drag.pan : drag.orbit) = true;
  }
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) drag.pan = true;
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) && !ImGui::IsMouseDown(ImGuiMouseButton_Middle)) {
    drag = {};
  }
  if (drag.orbit) camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
  if (drag.pan) camera.pan(io.MouseDelta.x, io.MouseDelta.y, viewport.size.y);
  if (hovered && io.MouseWheel != 0.0f) camera.zoom(io.MouseWheel);
}

// Space play/pause, Left/Right step a frame, Home rewinds, F frames the character.
void handleKeys(EditorState& state) {
  if (ImGui::GetIO().WantCaptureKeyboard) return;
  const motion::Clip* clip = state.clip();
  if (ImGui::IsKeyPressed(GLFW_KEY_F, false)) state.frame_requested = true;
  if (clip == nullptr) return;
  Playback& playback = state.playback;
  if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) playback.playing = !playback.playing;
  if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) playback.time_s = 0.0;
  const int step = ImGui::IsKeyPressed(GLFW_KEY_RIGHT) ? 1 : ImGui::IsKeyPressed(GLFW_KEY_LEFT) ? -1 : 0;
  if (step != 0) {
    playback.playing = false;
    const int frame = static_cast<int>(std::lround(playback.time_s / clip->frame_time)) + step;
    playback.time_s = std::clamp(frame, 0, clip->frame_count - 1) * clip->frame_time;
  }
}

void updateCamera(OrbitCamera& camera, EditorState& state, const Scene& scene, double dt) {
  if (scene.empty) return;
  if (state.frame_requested) {
    camera.frame(scene.bounds_min, scene.bounds_max);
    state.frame_requested = false;
    return;
  }
  if (!state.view.follow) return;
  const glm::vec3 centre = 0.5f * (scene.bounds_min + scene.bounds_max);
  const glm::vec2 goal(centre.x, centre.z);
  glm::vec2 now(camera.target.x, camera.target.z);
  if (glm::length(goal - now) > 3.0f) {
    now = goal;  // a loop jumped the character back: cut, do not swoop
  } else {
    now += (goal - now) * static_cast<float>(1.0 - std::exp(-8.0 * dt));
  }
  camera.target.x = now.x;
  camera.target.z = now.y;
}

// Frame times of the last frames, seconds; median and 95th percentile for the overlay.
class FrameTimes {
 public:
  void add(double seconds) {
    if (times_.size() < 240) {
      times_.push_back(seconds);
    } else {
      times_[next_] = seconds;
      next_ = (next_ + 1) % times_.size();
    }
  }
  double percentile(double p) const {
    if (times_.empty()) return 0.0;
    std::vector<double> sorted = times_;
    std::sort(sorted.begin(), sorted.end());
    return sorted[static_cast<size_t>(p * (sorted.size() - 1))];
  }

 private:
  std::vector<double> times_;
  size_t next_ = 0;
};

void drawOverlay(const EditorState& state, const Rect& viewport, const FrameTimes& times,
                 bool renderer_ready) {
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const ImVec2 at(viewport.pos.x + 12.0f, viewport.pos.y + 10.0f);
  char text[256];
  const double median = times.percentile(0.5);
  std::snprintf(text, sizeof text, "%.0f fps  (%.1f ms)", median > 0 ? 1.0 / median : 0.0,
                median * 1000.0);
  const ImVec2 size = ImGui::CalcTextSize(text);
  draw->AddText(ImVec2(viewport.pos.x + viewport.size.x - size.x - 12.0f, at.y),
                IM_COL32(150, 155, 165, 255), text);
  if (const motion::Clip* clip = state.clip()) {
    std::snprintf(text, sizeof text, "%s  -  %s", state.file_name.c_str(), clip->name.c_str());
    draw->AddText(at, IM_COL32(225, 228, 232, 255), text);
    const int frame = static_cast<int>(std::lround(state.playback.time_s / clip->frame_time));
    std::snprintf(text, sizeof text, "frame %d   %.2f s", frame, state.playback.time_s);
    draw->AddText(ImVec2(at.x, at.y + 20.0f), IM_COL32(150, 155, 165, 255), text);
    if (state.view.show_model && state.analysis) {
      draw->AddText(ImVec2(at.x, at.y + 40.0f), IM_COL32(90, 215, 190, 255),
                    state.view.model_beside ? "model (translucent) beside the original"
                                            : "model (translucent) over the original");
    }
  } else {
    draw->AddText(at, IM_COL32(150, 155, 165, 255), "Drop a .bvh / .glb file here");
  }
  if (!renderer_ready) {
    draw->AddText(ImVec2(at.x, at.y + 64.0f), IM_COL32(255, 115, 100, 255),
                  "The 3D view is off: its shaders did not load (see Log).");
  }
  draw->AddText(ImVec2(at.x, viewport.pos.y + viewport.size.y - 24.0f), IM_COL32(120, 125, 135, 255),
                "LMB orbit   MMB / Shift+LMB pan   wheel zoom   F frame   Space play");
}

void onGlfwError(int code, const char* description) {
  std::cerr << "sinew edit: GLFW error " << code << ": " << description << '\n';
}

// Files dropped on the window, queued here and opened by the main loop at a defined point.
void onDrop(GLFWwindow* window, int count, const char** paths) {
  auto* pending = static_cast<std::vector<std::string>*>(glfwGetWindowUserPointer(window));
  for (int i = 0; i < count; ++i) pending->emplace_back(paths[i]);
}

}  // namespace

int runEditor(const EditorOptions& options) {
  glfwSetErrorCallback(onGlfwError);
  if (glfwInit() == GLFW_FALSE) {
    std::cerr << "sinew edit: cannot open a window (no display? set DISPLAY or run under "
                 "xvfb-run)\n";
    return 1;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  // No multisampling: on Mesa's software rasteriser 4x MSAA cost 3x the frame time (13 fps).
  glfwWindowHint(GLFW_SAMPLES, 0);
  GLFWwindow* window = glfwCreateWindow(kWindowWidth, kWindowHeight, "Sinew", nullptr, nullptr);
  if (window == nullptr) {
    std::cerr << "sinew edit: cannot create an OpenGL 3.3 core window\n";
    glfwTerminate();
    return 1;
  }
  glfwMakeContextCurrent(window);
  const bool headless = !options.screenshot.empty();
  glfwSwapInterval(headless ? 0 : 1);
  std::vector<std::string> dropped;
  glfwSetWindowUserPointer(window, &dropped);
  glfwSetDropCallback(window, onDrop);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed; nothing to persist yet
  applyTheme();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  int exit_code = 0;
  {
    EditorState state;
    FilesPanelState files_panel;
    SpectrumPanelState spectrum_panel;
    OrbitCamera camera;
    ViewportDrag drag;
    FrameTimes frame_times;
    Renderer renderer;
    state.log.info(std::string("OpenGL ") + reinterpret_cast<const char*>(glGetString(GL_VERSION)) +
                   " on " + reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    if (Status status = renderer.init(options.shader_dir); !status.ok()) {
      state.log.error(status.message());
    }
    state.view.shadows = options.shadows;
    state.view.show_mesh = options.mesh;
    if (!options.file.empty()) {
      files_panel.path = options.file;
      files_panel.animation = options.animation;
      openFile(state, options.file, options.animation);
    }
    if (options.evolve) {
      state.evolution.settings.minutes = options.evolve_minutes;
      startEvolution(state);
    }
    if (state.analysis) spectrum_panel.global_k = state.analysis->joint_k.empty() ? 5 : state.analysis->joint_k[0];

    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    Clock::time_point last = start;
    int frame = 0;
    while (!glfwWindowShouldClose(window)) {
      glfwPollEvents();
      const Clock::time_point now = Clock::now();
      const double dt = headless ? kScreenshotDt : std::chrono::duration<double>(now - last).count();
      if (frame > 0) frame_times.add(std::chrono::duration<double>(now - last).count());
      last = now;
      state.log.clock_s = std::chrono::duration<double>(now - start).count();

      for (const std::string& path : dropped) {
        if (openFile(state, path)) files_panel.path = path;
      }
      dropped.clear();
      advancePlayback(state, std::min(dt, 0.25));
      const std::string title = state.file_name.empty() ? "Sinew" : "Sinew - " + state.file_name;
      glfwSetWindowTitle(window, title.c_str());

      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      const Layout layout = computeLayout(ImGui::GetIO().DisplaySize);
      place(layout.files);
      drawFilesPanel(state, files_panel);
      place(layout.log);
      drawLogPanel(state);
      place(layout.timeline);
      drawTimelinePanel(state);
      place(layout.spectrum);
      drawSpectrumPanel(state, spectrum_panel);
      pollEvolution(state);
      place(layout.evolve);
      drawEvolvePanel(state);
      handleKeys(state);
      handleViewportMouse(camera, drag, layout.viewport);
      const Scene scene = buildScene(state);
      updateCamera(camera, state, scene, dt);
      drawOverlay(state, layout.viewport, frame_times, renderer.ready());
      ImGui::Render();

      int fb_w = 0, fb_h = 0, win_w = 0, win_h = 0;
      glfwGetFramebufferSize(window, &fb_w, &fb_h);
      glfwGetWindowSize(window, &win_w, &win_h);
      const float sx = win_w > 0 ? float(fb_w) / float(win_w) : 1.0f;
      const float sy = win_h > 0 ? float(fb_h) / float(win_h) : 1.0f;
      glViewport(0, 0, fb_w, fb_h);
      glClearColor(0.06f, 0.06f, 0.07f, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      const Rect& v = layout.viewport;
      ViewportRect rect;
      rect.x = static_cast<int>(std::lround(v.pos.x * sx));
      rect.width = std::max(static_cast<int>(std::lround(v.size.x * sx)), 1);
      rect.height = std::max(static_cast<int>(std::lround(v.size.y * sy)), 1);
      rect.y = fb_h - static_cast<int>(std::lround(v.pos.y * sy)) - rect.height;
      renderer.draw(rect, camera, scene, state.view.show_grid);
      for (LogLine& line : renderer.takeMessages()) state.log.add(line.level, std::move(line.text));
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

      // A screenshot of a search waits for its generations (at most two minutes of wall time).
      const bool waiting = headless && options.evolve && state.evolution.snapshot &&
                           state.evolution.snapshot->generation < options.evolve_generations &&
                           state.evolution.snapshot->state == "running" &&
                           std::chrono::duration<double>(now - start).count() < 120.0;
      if (!waiting) ++frame;
      if (headless && frame >= options.frames) {
        if (Status status = saveFramebufferPng(options.screenshot, fb_w, fb_h); !status.ok()) {
          std::cerr << "sinew edit: " << status.message() << '\n';
          exit_code = 1;
        } else {
          std::printf("sinew edit: wrote %s (%dx%d) after %d frames; frame time median %.1f ms "
                      "(%.0f fps), 95th percentile %.1f ms\n",
                      options.screenshot.c_str(), fb_w, fb_h, frame,
                      frame_times.percentile(0.5) * 1000.0,
                      frame_times.percentile(0.5) > 0 ? 1.0 / frame_times.percentile(0.5) : 0.0,
                      frame_times.percentile(0.95) * 1000.0);
        }
        glfwSetWindowShouldClose(window, GLFW_TRUE);
      }
      glfwSwapBuffers(window);
    }
  }  // GL objects go before the context

  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return exit_code;
}

}  // namespace sinew::editor
