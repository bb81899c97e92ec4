#include "editor/render_frames.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <GLFW/glfw3.h>
#include "editor/gl.h"  // before GLFW: it defines GLFW_INCLUDE_NONE

#include "editor/camera.h"
#include "editor/editor_state.h"
#include "editor/project_model.h"
#include "editor/renderer.h"
#include "editor/scene.h"
#include "editor/screenshot.h"

namespace sinew::editor {
namespace {

int fail(const std::string& message) {
  std::cerr << "sinew render: " << message << '\n';
  return 1;
}

}  // namespace

int renderFrames(const RenderOptions& options) {
  if (glfwInit() == GLFW_FALSE)
    return fail("cannot open a window (no display? run under xvfb-run)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow* window =
      glfwCreateWindow(options.width, options.height, "Sinew render", nullptr, nullptr);
  if (window == nullptr) {
    glfwTerminate();
    return fail("cannot create an OpenGL 3.3 core context");
  }
  glfwMakeContextCurrent(window);
  int exit_code = 0;
  {
    Renderer renderer;
    EditorState state;
    if (Status status = renderer.init(options.shader_dir); !status.ok()) {
      exit_code = fail(status.message());
    } else if (!openAny(state, options.file, options.animation) || state.clip() == nullptr) {
      exit_code = fail(state.log.lines().empty() ? options.file + ": nothing to render"
                                                 : state.log.lines().back().text);
    } else {
      std::error_code ec;
      std::filesystem::create_directories(options.out_dir, ec);
      if (ec) exit_code = fail(options.out_dir + ": cannot create the folder: " + ec.message());
    }
    if (exit_code == 0) {
      const motion::Clip& clip = *state.clip();
      state.view.show_model = options.show_model;
      state.view.follow = false;
      state.selected_joint = -1;  // no joint highlighted: this is the motion, not the editor
      const double fps = options.fps > 0.0 ? options.fps : clip.fps();
      const int frames =
          std::max(1, static_cast<int>(std::floor(clip.duration() * fps + 1e-9)) + 1);
      // The first pose framed with some room, then the camera follows the character's middle.
      OrbitCamera camera;
      state.playback.time_s = 0.0;
      if (const Scene first = buildScene(state); !first.empty)
        camera.frame(first.bounds_min, first.bounds_max);
      camera.distance *= 1.4f;
      const float yaw0 = camera.yaw;
      int fb_w = 0, fb_h = 0;
      glfwGetFramebufferSize(window, &fb_w, &fb_h);
      for (int f = 0; f < frames && exit_code == 0; ++f) {
        state.playback.time_s = std::min(f / fps, clip.duration());
        if (options.turntable)
          camera.yaw = yaw0 + 6.2831853f * static_cast<float>(f) / static_cast<float>(frames);
        const Scene scene = buildScene(state);
        if (!scene.empty) {
          const glm::vec3 centre = 0.5f * (scene.bounds_min + scene.bounds_max);
          camera.target.x = centre.x;
          camera.target.z = centre.z;
        }
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.06f, 0.06f, 0.07f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        renderer.draw({0, 0, fb_w, fb_h}, camera, scene, state.view.show_grid);
        glFinish();
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d.png", f + 1);
        const std::string path = (std::filesystem::path(options.out_dir) / name).string();
        if (Status status = saveFramebufferPng(path, fb_w, fb_h); !status.ok())
          exit_code = fail(status.message());
      }
      if (exit_code == 0) {
        std::printf("sinew render: %s '%s': %d frames (%.0f fps, %dx%d%s) in %s\n",
                    options.file.c_str(), clip.name.c_str(), frames, fps, fb_w, fb_h,
                    options.turntable ? ", turntable" : "", options.out_dir.c_str());
      }
    }
  }  // GL objects go before the context
  glfwDestroyWindow(window);
  glfwTerminate();
  return exit_code;
}

}  // namespace sinew::editor
