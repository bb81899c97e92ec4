#include "editor/editor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <imgui_internal.h>  // FindWindowByName: the size a user dragged a panel to
#include "editor/gl.h"       // before GLFW: it defines GLFW_INCLUDE_NONE

#include "editor/bench.h"
#include "editor/camera.h"
#include "editor/editor_state.h"
#include "editor/frame_stats.h"
#include "editor/ghost.h"
#include "editor/panels/panels.h"
#include "editor/preferences.h"
#include "editor/project_model.h"
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
  Rect files, body, log, spectrum, evolve, exporting, timeline, viewport;
};

// The panels' sizes: the user's (dragged, persisted in the preferences) where set, else defaults
// for the window's size; always leaving the viewport at least 200 pixels.
Layout computeLayout(ImVec2 display, const PanelLayout& user) {
  auto chosen = [](float value, float fallback) { return value > 0.0f ? value : fallback; };
  float left_w = std::round(chosen(user.left_width, std::clamp(display.x * 0.23f, 260.0f, 380.0f)));
  float right_w =
      std::round(chosen(user.right_width, std::clamp(display.x * 0.3f, 320.0f, 500.0f)));
  left_w = std::clamp(left_w, 160.0f, std::max(160.0f, display.x * 0.4f));
  right_w = std::clamp(right_w, 200.0f, std::max(200.0f, display.x - left_w - 200.0f));
  const float timeline_h = std::round(
      std::clamp(chosen(user.timeline_height, 128.0f), 80.0f, std::max(80.0f, display.y * 0.5f)));
  const float files_h =
      std::round(display.y * std::clamp(chosen(user.files_fraction, 0.34f), 0.1f, 0.7f));
  const float body_h =
      std::round(display.y * std::clamp(chosen(user.body_fraction, 0.36f), 0.1f, 0.7f));
  const float centre_w = std::max(display.x - left_w - right_w, 1.0f);
  Layout l;
  l.files = {ImVec2(0, 0), ImVec2(left_w, files_h)};
  l.body = {ImVec2(0, files_h), ImVec2(left_w, body_h)};
  l.log = {ImVec2(0, files_h + body_h),
           ImVec2(left_w, std::max(display.y - files_h - body_h, 40.0f))};
  const float spectrum_h =
      std::round(display.y * std::clamp(chosen(user.spectrum_fraction, 0.46f), 0.15f, 0.7f));
  const float evolve_h =
      std::round(display.y * std::clamp(chosen(user.evolve_fraction, 0.34f), 0.1f, 0.7f));
  l.spectrum = {ImVec2(display.x - right_w, 0), ImVec2(right_w, spectrum_h)};
  l.evolve = {ImVec2(display.x - right_w, spectrum_h), ImVec2(right_w, evolve_h)};
  l.exporting = {ImVec2(display.x - right_w, spectrum_h + evolve_h),
                 ImVec2(right_w, std::max(display.y - spectrum_h - evolve_h, 40.0f))};
  l.timeline = {ImVec2(left_w, display.y - timeline_h), ImVec2(centre_w, timeline_h)};
  l.viewport = {ImVec2(left_w, 0), ImVec2(centre_w, std::max(display.y - timeline_h, 1.0f))};
  return l;
}

void place(const Rect& rect) {
  ImGui::SetNextWindowPos(rect.pos, ImGuiCond_Always);
  ImGui::SetNextWindowSize(rect.size, ImGuiCond_Always);
}

// A panel the user dragged to another size this frame moves the layout's split with it.
void followResizes(const Layout& placed, ImVec2 display, PanelLayout& user) {
  auto size = [](const char* name) {
    const ImGuiWindow* window = ImGui::FindWindowByName(name);
    return window != nullptr ? window->SizeFull : ImVec2(0, 0);
  };
  auto moved = [](float now, float was) { return now > 0.0f && std::abs(now - was) > 0.5f; };
  const ImVec2 files = size("Files"), body = size("Body"), log = size("Log"),
               spectrum = size("Spectrum"), evolve = size("Evolve"), timeline = size("Timeline");
  if (moved(files.x, placed.files.size.x)) user.left_width = files.x;
  if (moved(log.x, placed.log.size.x)) user.left_width = log.x;
  if (moved(files.y, placed.files.size.y)) user.files_fraction = files.y / display.y;
  if (moved(body.x, placed.body.size.x)) user.left_width = body.x;
  if (moved(body.y, placed.body.size.y)) user.body_fraction = body.y / display.y;
  if (moved(spectrum.x, placed.spectrum.size.x)) user.right_width = spectrum.x;
  if (moved(evolve.x, placed.evolve.size.x)) user.right_width = evolve.x;
  if (moved(evolve.y, placed.evolve.size.y)) user.evolve_fraction = evolve.y / display.y;
  if (moved(spectrum.y, placed.spectrum.size.y)) user.spectrum_fraction = spectrum.y / display.y;
  if (moved(timeline.y, placed.timeline.size.y)) user.timeline_height = timeline.y;
}

struct ViewportDrag {
  bool orbit = false;
  bool pan = false;
  ImVec2 pressed_at{0, 0};  // where the left button went down in the viewport
  bool click = false;       // released there without dragging: pick what is under it
};

// LMB orbit, MMB or Shift+LMB pan, wheel zoom; only when the mouse is over the viewport (or a
// drag started there).
void handleViewportMouse(OrbitCamera& camera, ViewportDrag& drag, const Rect& viewport) {
  const ImGuiIO& io = ImGui::GetIO();
  const bool hovered = !io.WantCaptureMouse && viewport.contains(io.MousePos);
  drag.click = false;
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    (io.KeyShift ? drag.pan : drag.orbit) = true;
    drag.pressed_at = io.MousePos;
  }
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) drag.pan = true;
  if (drag.orbit && ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    const float dx = io.MousePos.x - drag.pressed_at.x, dy = io.MousePos.y - drag.pressed_at.y;
    drag.click = dx * dx + dy * dy < 16.0f;  // moved less than 4 pixels: a click, not an orbit
  }
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) && !ImGui::IsMouseDown(ImGuiMouseButton_Middle)) {
    drag.orbit = drag.pan = false;
  }
  if (drag.orbit) camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
  if (drag.pan) camera.pan(io.MouseDelta.x, io.MouseDelta.y, viewport.size.y);
  if (hovered && io.MouseWheel != 0.0f) camera.zoom(io.MouseWheel);
}

// What GLFW delivers between two frames, queued by its callbacks and handled by the main loop at
// one defined point. Keys are queued rather than read from ImGui's per-frame key state: at the
// frame rates of a software renderer under load (10-20 fps) a quick tap starts and ends within
// one frame, and ImGui 1.86 would never see it pressed.
struct WindowEvents {
  struct Key {
    int key = 0, mods = 0;
    bool repeat = false;
  };
  std::vector<std::string> dropped;
  std::vector<Key> keys;
  int input = 0;  // counts every event (mouse, keys, text, resize, expose): the loop redraws
};

// Space play/pause, Left/Right step a frame, Home rewinds, F frames the character; Ctrl+Z undo,
// Ctrl+Shift+Z or Ctrl+Y redo, Ctrl+S save, Ctrl+N new; E starts, pauses or resumes the search,
// Shift+E stops it. Not while a text field has the keyboard (it has its own undo).
void handleKeys(EditorState& state, FilesPanelState& files_panel,
                const std::vector<WindowEvents::Key>& keys) {
  if (ImGui::GetIO().WantCaptureKeyboard) return;
  for (const WindowEvents::Key& press : keys) {
    const bool ctrl = (press.mods & GLFW_MOD_CONTROL) != 0;
    const bool shift = (press.mods & GLFW_MOD_SHIFT) != 0;
    const motion::Clip* clip = state.clip();
    Playback& playback = state.playback;
    if (ctrl) {
      if (press.key == GLFW_KEY_Z) shift ? redo(state) : undo(state);
      if (press.key == GLFW_KEY_Y) redo(state);
      if (press.key == GLFW_KEY_S && !press.repeat) saveOpenProject(state, files_panel);
      if (press.key == GLFW_KEY_N && !press.repeat) newProject(state);
    } else if (press.key == GLFW_KEY_E && !press.repeat) {
      const search::SessionState run = evolutionState(state);
      if (shift) {
        stopEvolution(state);
      } else if (run == search::SessionState::kRunning) {
        pauseEvolution(state);
      } else if (run == search::SessionState::kPaused) {
        resumeEvolution(state);
      } else {
        startEvolution(state);
      }
    } else if (press.key == GLFW_KEY_F && !press.repeat) {
      state.frame_requested = true;
    } else if (clip != nullptr && press.key == GLFW_KEY_SPACE && !press.repeat) {
      playback.playing = !playback.playing;
    } else if (clip != nullptr && press.key == GLFW_KEY_HOME) {
      playback.time_s = 0.0;
    } else if (clip != nullptr && (press.key == GLFW_KEY_LEFT || press.key == GLFW_KEY_RIGHT)) {
      playback.playing = false;
      const int frame = static_cast<int>(std::lround(playback.time_s / clip->frame_time)) +
                        (press.key == GLFW_KEY_RIGHT ? 1 : -1);
      playback.time_s = std::clamp(frame, 0, clip->frame_count - 1) * clip->frame_time;
    }
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
  draw->AddText(ImVec2(at.x, viewport.pos.y + viewport.size.y - 24.0f),
                IM_COL32(120, 125, 135, 255),
                "LMB orbit   MMB / Shift+LMB pan   wheel zoom   F frame   Space play   "
                "E evolve   Ctrl+Z undo   Ctrl+S save");
}

// The unsaved-changes prompt on quit. Returns true when the editor may close now.
bool drawQuitPrompt(EditorState& state, FilesPanelState& files_panel, bool& asked) {
  if (asked) {
    ImGui::OpenPopup("Unsaved changes");
    asked = false;
  }
  bool quit = false;
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    const std::string name = state.project_path.empty() ? "the untitled project"
                                                        : state.project_path.filename().string();
    ImGui::Text("Save the changes to %s before closing?", name.c_str());
    if (state.project_path.empty())
      ImGui::TextDisabled("It will be saved as %s", files_panel.save_path.c_str());
    if (ImGui::Button("Save and close")) {
      saveOpenProject(state, files_panel);
      quit = !hasUnsavedChanges(state);  // a failed save keeps the editor open (see Log)
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Close without saving")) {
      quit = true;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  return quit;
}

void onGlfwError(int code, const char* description) {
  std::cerr << "sinew edit: GLFW error " << code << ": " << description << '\n';
}

// Files dropped on the window, queued here and opened by the main loop at a defined point.
void onDrop(GLFWwindow* window, int count, const char** paths) {
  auto* events = static_cast<WindowEvents*>(glfwGetWindowUserPointer(window));
  for (int i = 0; i < count; ++i) events->dropped.emplace_back(paths[i]);
  ++events->input;
}

// Any other event: the next frame is drawn (these are installed before ImGui's backend, which
// calls the ones it also handles after its own).
void onInput(GLFWwindow* window) {
  ++static_cast<WindowEvents*>(glfwGetWindowUserPointer(window))->input;
}
void onCursor(GLFWwindow* window, double, double) {
  onInput(window);
}
void onButton(GLFWwindow* window, int, int, int) {
  onInput(window);
}
void onScroll(GLFWwindow* window, double, double) {
  onInput(window);
}
void onChar(GLFWwindow* window, unsigned) {
  onInput(window);
}
void onSize(GLFWwindow* window, int, int) {
  onInput(window);
}
void onFocus(GLFWwindow* window, int) {
  onInput(window);
}
void onEnter(GLFWwindow* window, int) {
  onInput(window);
}

// Installed before ImGui's backend, which calls it after its own handling.
void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int mods) {
  auto* events = static_cast<WindowEvents*>(glfwGetWindowUserPointer(window));
  ++events->input;
  if (action == GLFW_RELEASE) return;
  events->keys.push_back({key, mods, action == GLFW_REPEAT});
}

}  // namespace

int runHeadlessEvolve(const EditorOptions& options) {
  EditorState state;
  if (!openAny(state, options.file, options.animation)) return 1;
  state.evolution.settings.search.minutes = options.evolve_minutes;
  if (!startEvolution(state, options.evolve_generations)) return 1;
  while (!search::ended(evolutionState(state))) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    pollEvolution(state);
  }
  pollEvolution(state);
  if (!exportEvolutionResults(state, options.export_dir)) return 1;
  if (state.evolution.snapshot && !state.evolution.snapshot->best_point.empty()) {
    std::printf("sinew edit: best after %d generations: cost %.17g\n",
                state.evolution.snapshot->generation, state.evolution.snapshot->best_terms.total);
  }
  return 0;
}

namespace {

using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------- the platform window

// What the editor remembers between runs; `error` says why the defaults are used.
Preferences loadEditorPreferences(const std::filesystem::path& config, std::string& error) {
  if (config.empty()) return {};
  Result<Preferences> loaded = loadPreferences(config / kPreferencesFile);
  if (loaded.ok()) return loaded.value();
  error = loaded.message();
  return {};
}

// A GLFW window with an OpenGL 3.3 core context and ImGui on it, its events queued in `events`;
// nullptr (and GLFW terminated) when it cannot be made. Precondition: glfwInit succeeded.
GLFWwindow* openWindow(int width, int height, bool headless, WindowEvents& events) {
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  // No multisampling: on Mesa's software rasteriser 4x MSAA cost 3x the frame time (13 fps).
  glfwWindowHint(GLFW_SAMPLES, 0);
  GLFWwindow* window = glfwCreateWindow(width, height, "Sinew", nullptr, nullptr);
  if (window == nullptr) {
    std::cerr << "sinew edit: cannot create an OpenGL 3.3 core window\n";
    glfwTerminate();
    return nullptr;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(headless ? 0 : 1);
  glfwSetWindowUserPointer(window, &events);
  glfwSetDropCallback(window, onDrop);
  glfwSetKeyCallback(window, onKey);
  glfwSetCursorPosCallback(window, onCursor);
  glfwSetMouseButtonCallback(window, onButton);
  glfwSetScrollCallback(window, onScroll);
  glfwSetCharCallback(window, onChar);
  glfwSetFramebufferSizeCallback(window, onSize);
  glfwSetWindowRefreshCallback(window, onInput);
  glfwSetWindowFocusCallback(window, onFocus);
  glfwSetCursorEnterCallback(window, onEnter);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the layout is ours (Preferences), not ImGui's ini
  applyTheme();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  return window;
}

void closeWindow(GLFWwindow* window) {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
}

// ---------------------------------------------------------------- the UI thread's state

// Everything one run of the window owns besides the window: the model, the panels' own state,
// the view. Holds GL objects (the renderer): destroyed before the context.
struct EditorSession {
  EditorState state;
  FilesPanelState files_panel;
  SpectrumPanelState spectrum_panel;
  StylePanelState style_panel;
  int right_tab = 0;                // Spectrum or Style
  bool style_shot_pending = false;  // --panel-shots: the Style tab's picture is next
  OrbitCamera camera;
  ViewportDrag drag;
  FrameTimes frame_times;
  StageProfile profile;  // --bench: where the frames' time goes
  bool profile_enabled = false;
  Renderer renderer;
  std::filesystem::path recovery;  // the autosave file, empty in headless runs
};

// A recovery file left behind means the last session ended without closing: keep it aside
// (this session autosaves over the usual name) and offer it at the top of Recent.
void keepRecovery(EditorState& state, const std::filesystem::path& config,
                  const std::filesystem::path& recovery) {
  if (recovery.empty() || !std::filesystem::exists(recovery)) return;
  const std::filesystem::path kept = config / "recovered.sinew.json";
  std::error_code ec;
  std::filesystem::rename(recovery, kept, ec);
  if (!ec) {
    rememberRecent(state, kept.string());
    state.log.warning("the last session ended with unsaved changes; they are in " + kept.string() +
                      " (first in Recent)");
  }
}

// The renderer, the remembered files, and what the command line asked for.
void startSession(EditorSession& s, const EditorOptions& options, const Preferences& preferences,
                  const std::string& preferences_error, const std::filesystem::path& config) {
  EditorState& state = s.state;
  state.log.info(std::string("OpenGL ") + reinterpret_cast<const char*>(glGetString(GL_VERSION)) +
                 " on " + reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  if (Status status = s.renderer.init(options.shader_dir); !status.ok()) {
    state.log.error(status.message());
  }
  state.recent_files = preferences.recent_files;
  if (!preferences_error.empty()) state.log.warning(preferences_error + " (using the defaults)");
  s.recovery = config.empty() ? config : config / kRecoveryFile;
  keepRecovery(state, config, s.recovery);
  state.view.shadows = options.shadows;
  state.view.show_mesh = options.mesh;
  if (!options.file.empty()) {
    s.files_panel.path = options.file;
    s.files_panel.animation = options.animation;
    if (!openAny(state, options.file, options.animation)) startUntitled(state);
  }
  state.evolution.settings.shown = options.shown;
  // The window draws while the search runs: it leaves the UI and the GL driver a core.
  state.evolution.threads = editorSearchThreads();
  if (options.bench) {
    // The benchmark's search: its population is the characters shown (its generations come
    // sooner than the default 23's, and each phase waits for two of them).
    state.evolution.settings.search.minutes = options.evolve_minutes;
    state.evolution.settings.search.population = options.shown;
  }
  if (options.evolve) {
    state.evolution.settings.search.minutes = options.evolve_minutes;
    startEvolution(state);
  }
  if (state.analysis)
    s.spectrum_panel.global_k = state.analysis->joint_k.empty() ? 5 : state.analysis->joint_k[0];
}

// Closed on purpose: nothing to recover; the recent files and the window's size are kept.
void rememberOnClose(Preferences& preferences, const EditorSession& s, GLFWwindow* window,
                     const std::filesystem::path& config) {
  std::error_code ec;
  std::filesystem::remove(s.recovery, ec);
  preferences.recent_files = s.state.recent_files;
  int w = 0, h = 0;
  glfwGetWindowSize(window, &w, &h);
  if (w >= 320 && h >= 240) {
    preferences.window_width = w;
    preferences.window_height = h;
  }
  if (Status saved = savePreferences(preferences, config / kPreferencesFile); !saved.ok()) {
    std::cerr << "sinew edit: " << saved.message() << '\n';
  }
}

// ---------------------------------------------------------------- one frame

// Files dropped on the window since the last frame, opened now.
void openDropped(EditorSession& s, WindowEvents& events) {
  for (const std::string& path : events.dropped) {
    if (openAny(s.state, path)) {
      s.files_panel.path = path;
      s.files_panel.save_path.clear();
    }
  }
  events.dropped.clear();
}

void setWindowTitle(GLFWwindow* window, const EditorState& state, bool unsaved) {
  std::string title = "Sinew";
  if (!state.project_path.empty()) title += " - " + state.project_path.filename().string();
  if (!state.file_name.empty()) title += " - " + state.file_name;
  if (unsaved) title += " *";
  glfwSetWindowTitle(window, title.c_str());
}

// Every panel in its place, the keys, the quit prompt and the undo history. Returns true when
// the user confirmed closing with unsaved changes.
bool drawPanels(EditorSession& s, const Layout& layout, WindowEvents& events, bool& ask_to_quit) {
  EditorState& state = s.state;
  place(layout.files);
  drawFilesPanel(state, s.files_panel);
  place(layout.body);
  drawBodyPanel(state);
  place(layout.log);
  drawLogPanel(state);
  place(layout.timeline);
  drawTimelinePanel(state);
  place(layout.spectrum);
  if (s.right_tab == 0) {
    drawSpectrumPanel(state, s.spectrum_panel, s.right_tab);
  } else {
    drawStylePanel(state, s.style_panel, s.right_tab);
  }
  applyEdits(state);  // undo, redo and project loads change the edits too
  pollEvolution(state);
  place(layout.evolve);
  drawEvolvePanel(state);
  place(layout.exporting);
  drawExportPanel(state);
  handleKeys(state, s.files_panel, events.keys);
  events.keys.clear();
  return drawQuitPrompt(state, s.files_panel, ask_to_quit);
}

// A click on an individual of the population selects it in every panel (the ground: the best).
void pickClicked(EditorSession& s, const Scene& scene, const Rect& v) {
  if (!s.drag.click || scene.individuals.empty()) return;
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const float x = (mouse.x - v.pos.x) / v.size.x * 2.0f - 1.0f;
  const float y = 1.0f - (mouse.y - v.pos.y) / v.size.y * 2.0f;
  selectIndividual(
      s.state.evolution,
      pickIndividual(scene, s.camera.eye(), s.camera.rayDirection(x, y, v.size.x / v.size.y)));
}

// The framebuffer's size in pixels and its scale from window coordinates (HiDPI).
struct Framebuffer {
  int width = 0;
  int height = 0;
  float sx = 1.0f;
  float sy = 1.0f;

  Status savePanel(const std::string& path, const Rect& r) const {
    return saveFramebufferRegionPng(
        path, width, height, static_cast<int>(std::lround(r.pos.x * sx)),
        static_cast<int>(std::lround(r.pos.y * sy)), static_cast<int>(std::lround(r.size.x * sx)),
        static_cast<int>(std::lround(r.size.y * sy)));
  }
};

// The 3D view in the viewport's pixels, then ImGui over it.
Framebuffer renderFrame(GLFWwindow* window, EditorSession& s, const Layout& layout,
                        const Scene& scene) {
  Framebuffer fb;
  int win_w = 0, win_h = 0;
  glfwGetFramebufferSize(window, &fb.width, &fb.height);
  glfwGetWindowSize(window, &win_w, &win_h);
  fb.sx = win_w > 0 ? float(fb.width) / float(win_w) : 1.0f;
  fb.sy = win_h > 0 ? float(fb.height) / float(win_h) : 1.0f;
  glViewport(0, 0, fb.width, fb.height);
  glClearColor(0.06f, 0.06f, 0.07f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const Rect& v = layout.viewport;
  ViewportRect rect;
  rect.x = static_cast<int>(std::lround(v.pos.x * fb.sx));
  rect.width = std::max(static_cast<int>(std::lround(v.size.x * fb.sx)), 1);
  rect.height = std::max(static_cast<int>(std::lround(v.size.y * fb.sy)), 1);
  rect.y = fb.height - static_cast<int>(std::lround(v.pos.y * fb.sy)) - rect.height;
  s.renderer.draw(rect, s.camera, scene, s.state.view.show_grid);
  for (LogLine& line : s.renderer.takeMessages()) s.state.log.add(line.level, std::move(line.text));
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  if (s.profile_enabled) {
    glFinish();
    s.profile.mark(FrameStage::kImgui);
  }
  return fb;
}

// ---------------------------------------------------------------- headless runs

// Where a headless run (--screenshot, --bench, --panel-shots) is: frames counted, the
// benchmark, and whether anything failed.
struct RunProgress {
  int frame = 0;
  double longest_after_first_s = 0.0;  // the longest frame once the first second has passed
  int frames_after_first = 0;
  std::unique_ptr<EditorBench> bench;  // --bench
  int exit_code = 0;
};

bool searchRunning(const EditorState& state) {
  return state.evolution.snapshot &&
         state.evolution.snapshot->state == search::SessionState::kRunning;
}
int searchGeneration(const EditorState& state) {
  return state.evolution.snapshot ? state.evolution.snapshot->generation : 0;
}

// Counts this frame towards --frames; returns true when the run's frames are all drawn (the
// benchmark: when its phases are done).
bool countFrame(RunProgress& run, EditorSession& s, const EditorOptions& options, bool headless,
                double elapsed_s, GLFWwindow* window) {
  if (run.bench) {
    ++run.frame;
    if (run.bench->failed()) {
      run.exit_code = 1;
      glfwSetWindowShouldClose(window, GLFW_TRUE);
    }
    return run.bench->done() && !run.bench->failed();
  }
  // A screenshot of a search waits for its generations (at most two minutes of wall time).
  const bool waiting = headless && options.evolve && searchRunning(s.state) &&
                       searchGeneration(s.state) < options.evolve_generations && elapsed_s < 120.0;
  if (!waiting) ++run.frame;
  return headless && run.frame >= options.frames;
}

void printBench(const RunProgress& run, const EditorSession& s, const Framebuffer& fb) {
  std::fputs(run.bench
                 ->report(reinterpret_cast<const char*>(glGetString(GL_RENDERER)), fb.width,
                          fb.height, s.state.evolution.settings.shown)
                 .c_str(),
             stdout);
  std::fflush(stdout);
}

// The ghost's figures as the Evolve panel shows them (tests read them).
void printGhost(const EditorState& state) {
  const std::optional<Ghost> ghost = currentGhost(state);
  if (!ghost) return;
  const GhostSummary summary = summarise(*ghost);
  const std::string worst = summary.worst_joint >= 0 && state.asset &&
                                    summary.worst_joint < state.asset->skeleton.jointCount()
                                ? state.asset->skeleton.names[summary.worst_joint]
                                : "-";
  std::printf(
      "sinew edit: ghost of individual %d at %.2f s: off the target by %.2f deg mean, "
      "%.2f deg at most (%s), over %zu joints\n",
      ghost->individual, ghost->time_s, summary.mean_deg, summary.max_deg, worst.c_str(),
      ghost->deviation_rad.size());
}

void writeScreenshot(RunProgress& run, const EditorSession& s, const EditorOptions& options,
                     const Framebuffer& fb) {
  if (Status status = saveFramebufferPng(options.screenshot, fb.width, fb.height); !status.ok()) {
    std::cerr << "sinew edit: " << status.message() << '\n';
    run.exit_code = 1;
    return;
  }
  const FrameTimes& times = s.frame_times;
  std::printf(
      "sinew edit: wrote %s (%dx%d) after %d frames; frame time median %.1f ms "
      "(%.0f fps), 95th percentile %.1f ms\n",
      options.screenshot.c_str(), fb.width, fb.height, run.frame, times.percentile(0.5) * 1000.0,
      times.percentile(0.5) > 0 ? 1.0 / times.percentile(0.5) : 0.0,
      times.percentile(0.95) * 1000.0);
  const EvolutionState& evolution = s.state.evolution;
  if (evolution.session) {
    // What keeps frames short while the search runs: the UI thread never waits for it.
    std::printf(
        "sinew edit: longest frame after the first second %.1f ms (%d frames); the search's "
        "snapshot polled every frame: longest wait %.3f ms, %d polls over %.0f ms\n",
        run.longest_after_first_s * 1000.0, run.frames_after_first,
        evolution.longest_poll_wait_s * 1000.0, evolution.slow_polls, kSlowPoll_s * 1000.0);
  }
  printGhost(s.state);
}

// One PNG per panel, for the user guide.
void writePanelShots(RunProgress& run, const EditorOptions& options, const Layout& layout,
                     const Framebuffer& fb) {
  std::error_code ec;
  std::filesystem::create_directories(options.panel_dir, ec);
  const std::pair<const char*, const Rect*> panels[] = {
      {"files", &layout.files},       {"body", &layout.body},         {"log", &layout.log},
      {"timeline", &layout.timeline}, {"spectrum", &layout.spectrum}, {"evolve", &layout.evolve},
      {"export", &layout.exporting},  {"viewport", &layout.viewport}};
  for (const auto& [name, r] : panels) {
    const std::string path =
        (std::filesystem::path(options.panel_dir) / (std::string(name) + ".png")).string();
    if (Status status = fb.savePanel(path, *r); !status.ok()) {
      std::cerr << "sinew edit: " << status.message() << '\n';
      run.exit_code = 1;
    }
  }
  std::printf("sinew edit: wrote the panels to %s\n", options.panel_dir.c_str());
}

// After this frame is drawn: the pictures a headless run asked for, and closing when it is done.
void finishHeadlessFrame(RunProgress& run, EditorSession& s, const EditorOptions& options,
                         const Layout& layout, const Framebuffer& fb, bool done,
                         GLFWwindow* window) {
  if (s.style_shot_pending) {
    // The Style tab, drawn this frame in the Spectrum panel's place.
    const std::string path = (std::filesystem::path(options.panel_dir) / "style.png").string();
    if (Status status = fb.savePanel(path, layout.spectrum); !status.ok()) {
      std::cerr << "sinew edit: " << status.message() << '\n';
      run.exit_code = 1;
    }
    glfwSetWindowShouldClose(window, GLFW_TRUE);
    return;
  }
  if (!done) return;
  if (run.bench) printBench(run, s, fb);
  if (!options.screenshot.empty()) writeScreenshot(run, s, options, fb);
  if (options.panel_dir.empty()) {
    glfwSetWindowShouldClose(window, GLFW_TRUE);
    return;
  }
  writePanelShots(run, options, layout, fb);
  s.right_tab = 1;  // one more frame for the Style tab
  s.style_shot_pending = true;
}

// Autosave to the recovery file every 30 s while there are unsaved changes.
struct Autosave {
  Clock::time_point last;
  app::Project saved;  // what the recovery file holds
};

void autosave(Autosave& autosaved, EditorSession& s, bool unsaved, Clock::time_point now) {
  if (s.recovery.empty() || !unsaved || now - autosaved.last <= std::chrono::seconds(30)) return;
  autosaved.last = now;
  const app::Project current = captureProject(s.state);
  if (current == autosaved.saved) return;
  if (Status status = writeRecovery(s.state, s.recovery); !status.ok()) {
    s.state.log.warning("autosave: " + status.message());
  }
  autosaved.saved = current;
}

// Drawing only when something changed: a paused, unchanged scene costs nothing. After any change
// (input, playback, a drag, the camera gliding, a new generation or log line) a few more frames
// are drawn, for ImGui's hover and focus to settle; then the loop sleeps in
// glfwWaitEventsTimeout and draws again on input or when the search publishes a generation.
struct Redraw {
  static constexpr int kSettleFrames = 3;
  int settle = kSettleFrames;  // frames still to draw before the loop may sleep
  int input_seen = 0;          // WindowEvents::input when the last frame began
  const search::Snapshot* snapshot_seen = nullptr;
  size_t log_seen = 0;
  bool after_wait = false;  // this frame followed a sleep: its interval is not a frame time
};

// Whether this frame changed nothing that the next one would draw differently.
bool frameWasStill(const EditorSession& s, const WindowEvents& events, const Redraw& redraw,
                   const glm::vec3& camera_before) {
  const EditorState& state = s.state;
  return !(state.clip() != nullptr && state.playback.playing) && !state.frame_requested &&
         events.input == redraw.input_seen && !ImGui::IsAnyItemActive() &&
         !ImGui::IsAnyMouseDown() && !s.drag.orbit && !s.drag.pan &&
         glm::length(s.camera.target - camera_before) < 5e-4f * std::max(s.camera.distance, 1.0f) &&
         state.evolution.snapshot.get() == redraw.snapshot_seen &&
         state.log.lines().size() == redraw.log_seen;
}

// Sleeps until an event arrives or the search publishes a snapshot (polled twice a second), 30 s
// at most (a frame then, for the autosave).
void waitForChange(GLFWwindow* window, const EditorSession& s, const WindowEvents& events,
                   const Redraw& redraw) {
  const Clock::time_point until = Clock::now() + std::chrono::seconds(30);
  while (!glfwWindowShouldClose(window) && Clock::now() < until) {
    glfwWaitEventsTimeout(0.5);
    const EvolutionState& evolution = s.state.evolution;
    if (events.input != redraw.input_seen) return;
    if (evolution.session && evolution.session->snapshot() != evolution.snapshot) return;
  }
}

// One frame: the panels, the scene, the 3D view and ImGui over it (swapped by the caller).
Framebuffer drawFrame(GLFWwindow* window, EditorSession& s, WindowEvents& events,
                      PanelLayout& user_layout, bool headless, double dt, bool& ask_to_quit,
                      bool& quit_confirmed, Layout& layout) {
  const bool profiling = s.profile_enabled;
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  layout = computeLayout(display, user_layout);
  if (drawPanels(s, layout, events, ask_to_quit)) {
    quit_confirmed = true;
    glfwSetWindowShouldClose(window, GLFW_TRUE);
  }
  if (!headless) followResizes(layout, display, user_layout);
  // One undo step per finished edit: nothing is recorded while a slider is being dragged.
  if (!ImGui::IsAnyItemActive()) recordHistory(s.state);
  if (profiling) s.profile.mark(FrameStage::kPanels);
  handleViewportMouse(s.camera, s.drag, layout.viewport);
  const Scene scene = buildScene(s.state);
  pickClicked(s, scene, layout.viewport);
  updateCamera(s.camera, s.state, scene, dt);
  drawOverlay(s.state, layout.viewport, s.frame_times, s.renderer.ready());
  ImGui::Render();
  if (profiling) s.profile.mark(FrameStage::kScene);
  return renderFrame(window, s, layout, scene);
}

// A screenshot that waits for the search's generations draws (the population, its publishes) at
// most kWaitingFps frames a second: the frames are not counted, and on a software GL drawing
// flat out would leave the search (at niceness 10) almost nothing.
void paceWhileWaiting(const EditorSession& s, const EditorOptions& options, bool headless,
                      const RunProgress& run, Clock::time_point frame_start) {
  constexpr double kWaitingFps = 5.0;
  const bool waiting = headless && !run.bench && options.evolve && run.frame == 0 &&
                       searchRunning(s.state) &&
                       searchGeneration(s.state) < options.evolve_generations;
  if (!waiting) return;
  const auto next = frame_start + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(1.0 / kWaitingFps));
  std::this_thread::sleep_until(next);
}

// The main loop, until the window closes: events, panels, the 3D view, headless pictures,
// autosave. Returns the exit code.
int runFrames(GLFWwindow* window, WindowEvents& events, EditorSession& s,
              const EditorOptions& options, PanelLayout& user_layout, bool headless) {
  const Clock::time_point start = Clock::now();
  Clock::time_point last = start;
  Autosave autosaved{start, s.state.saved};
  bool ask_to_quit = false;
  bool quit_confirmed = false;
  RunProgress run;
  if (options.bench) run.bench = std::make_unique<EditorBench>(options.frames);
  s.profile_enabled = options.bench;
  s.renderer.setProfile(s.profile_enabled ? &s.profile : nullptr);
  Redraw redraw;
  while (true) {
    if (glfwWindowShouldClose(window)) {
      // Unsaved changes: ask first (never in headless runs).
      if (headless || quit_confirmed || !hasUnsavedChanges(s.state)) break;
      glfwSetWindowShouldClose(window, GLFW_FALSE);
      ask_to_quit = true;
    }
    // Headless runs count frames and never sleep, but for the benchmark's paused scene.
    const bool may_sleep = !headless || (run.bench && run.bench->phase() == BenchPhase::kPaused);
    redraw.after_wait = may_sleep && redraw.settle <= 0;
    if (redraw.after_wait) waitForChange(window, s, events, redraw);
    glfwPollEvents();
    const Clock::time_point now = Clock::now();
    const double interval = std::chrono::duration<double>(now - last).count();
    const double dt = headless && !redraw.after_wait ? kScreenshotDt : interval;
    if (run.frame > 0 && !redraw.after_wait) s.frame_times.add(interval);
    // Every frame, counted or not (a screenshot of a search waits for its generations drawing).
    if (!redraw.after_wait && std::chrono::duration<double>(last - start).count() > 1.0) {
      run.longest_after_first_s = std::max(run.longest_after_first_s, interval);
      ++run.frames_after_first;
    }
    last = now;
    s.profile.beginFrame();
    s.state.log.clock_s = std::chrono::duration<double>(now - start).count();
    openDropped(s, events);
    advancePlayback(s.state, std::min(dt, 0.25));
    const bool unsaved = hasUnsavedChanges(s.state);
    setWindowTitle(window, s.state, unsaved);
    if (s.profile_enabled) s.profile.mark(FrameStage::kEvents);

    const glm::vec3 camera_before = s.camera.target;
    Layout layout;
    const Framebuffer fb = drawFrame(window, s, events, user_layout, headless, dt, ask_to_quit,
                                     quit_confirmed, layout);
    const double elapsed_s = std::chrono::duration<double>(now - start).count();
    const bool done = countFrame(run, s, options, headless, elapsed_s, window);
    finishHeadlessFrame(run, s, options, layout, fb, done, window);
    glfwSwapBuffers(window);
    if (s.profile_enabled) s.profile.mark(FrameStage::kSwap);
    paceWhileWaiting(s, options, headless, run, now);
    if (run.bench) {
      const double end_s = std::chrono::duration<double>(Clock::now() - start).count();
      run.bench->frameDrawn(s.state, interval, end_s - elapsed_s, end_s,
                            s.state.evolution.poll_wait_s, s.profile);
    }
    redraw.settle =
        frameWasStill(s, events, redraw, camera_before) ? redraw.settle - 1 : Redraw::kSettleFrames;
    redraw.input_seen = events.input;
    redraw.snapshot_seen = s.state.evolution.snapshot.get();
    redraw.log_seen = s.state.log.lines().size();
    autosave(autosaved, s, unsaved, now);
  }
  return run.exit_code;
}

}  // namespace

int runEditor(const EditorOptions& options) {
  if (!options.export_dir.empty()) return runHeadlessEvolve(options);
  glfwSetErrorCallback(onGlfwError);
  if (glfwInit() == GLFW_FALSE) {
    std::cerr << "sinew edit: cannot open a window (no display? set DISPLAY or run under "
                 "xvfb-run)\n";
    return 1;
  }
  // What the editor remembers between runs (not in headless runs: screenshots and tests see the
  // defaults and leave the user's files alone).
  const bool headless = !options.screenshot.empty() || options.bench;
  const std::filesystem::path config = headless ? std::filesystem::path() : configDir();
  std::string preferences_error;
  Preferences preferences = loadEditorPreferences(config, preferences_error);
  const int width = headless ? kWindowWidth : preferences.window_width;
  const int height = headless ? kWindowHeight : preferences.window_height;
  WindowEvents events;
  GLFWwindow* window = openWindow(width, height, headless, events);
  if (window == nullptr) return 1;
  int exit_code = 0;
  {
    EditorSession session;
    startSession(session, options, preferences, preferences_error, config);
    exit_code = runFrames(window, events, session, options, preferences.layout, headless);
    stopEvolution(session.state);
    if (!config.empty()) rememberOnClose(preferences, session, window, config);
  }  // GL objects go before the context
  closeWindow(window);
  return exit_code;
}

}  // namespace sinew::editor
