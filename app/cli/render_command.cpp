// `sinew render FILE -o DIR [--turntable] [--size WxH] [--fps F] [--animation NAME] [--model]`:
// PNG frames of a motion (a clip, an evolved best.bvh, a project's clip) for review.
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "editor/render_frames.h"

namespace sinew::app {

void addRenderCommand(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<editor::RenderOptions>();
  auto size = std::make_shared<std::string>("960x540");
  CLI::App* command = app.add_subcommand(
      "render",
      "Render a motion (BVH, glTF, an evolved best.bvh, or a project) to PNG frames "
      "(needs a display; headless: xvfb-run)");
  command->add_option("file", options->file, "The motion or project")->required();
  command->add_option("-o,--out", options->out_dir, "Folder for frame_0001.png, ...")->required();
  command->add_option("--animation", options->animation, "Which glTF animation (by name)");
  command->add_option("--size", *size, "Frame size WIDTHxHEIGHT (default 960x540)");
  command->add_option("--fps", options->fps, "Frames per second (default: the clip's)")
      ->check(CLI::Range(1.0, 240.0));
  command->add_flag("--turntable", options->turntable,
                    "The camera goes once around the character over the clip");
  command->add_flag("--model", options->show_model, "Draw the harmonic model beside the clip");
  command->callback([options, size, &exit_code] {
    int w = 0, h = 0;
    char x = 0;
    if (std::sscanf(size->c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 ||
        w > 8192 || h > 8192) {
      exit_code = fail("--size '" + *size + "': expected WIDTHxHEIGHT, 16..8192 each");
      return;
    }
    options->width = w;
    options->height = h;
    options->shader_dir = SINEW_SHADER_DIR;
    exit_code = editor::renderFrames(*options);
  });
}

}  // namespace sinew::app
