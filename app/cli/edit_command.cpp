// `sinew edit [FILE] [--animation NAME] [--evolve [--evolve-minutes M]] [--screenshot OUT.png
// --frames N [--evolve-generations G]] [--no-shadows] [--no-mesh]`: the editor.
#include <cstdint>
#include <memory>

#include "cli/commands.h"
#include "editor/editor.h"

namespace sinew::app {

void addEditCommand(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<editor::EditorOptions>();
  CLI::App* command = app.add_subcommand(
      "edit", "Open the editor (the default when sinew runs without a command)");
  command->add_option("file", options->file,
                      "BVH or glTF file to open (default: the bundled biped walk)");
  command->add_option("--animation", options->animation, "Animation to open in a glTF, by name");
  command->add_option("--screenshot", options->screenshot,
                      "Render --frames frames with playback running, save the window as this PNG "
                      "and exit");
  command->add_option("--frames", options->frames, "Frames before the screenshot (default 30)")
      ->check(CLI::Range(1, 100000));
  command->add_flag("--evolve", options->evolve,
                    "Start evolving the opened clip's physical motion at once (the Evolve panel's "
                    "Start)");
  command->add_option("--evolve-minutes", options->evolve_minutes, "The search's budget (default 2)")
      ->check(CLI::Range(0.1, 600.0));
  command->add_option("--evolve-generations", options->evolve_generations,
                      "With --screenshot and --evolve: wait for this many generations first "
                      "(at most 2 minutes)")
      ->check(CLI::Range(0, 10000));
  command->add_flag_function("--no-shadows", [options](std::int64_t) { options->shadows = false; },
                    "Start with the key light's shadows off (the Timeline's Shadows toggle)");
  command->add_flag_function("--no-mesh", [options](std::int64_t) { options->mesh = false; },
                    "Start with glTF characters drawn as capsules, not their skinned meshes");
  command->callback([options, &exit_code] {
    if (options->file.empty()) options->file = SINEW_ASSET_DIR "/biped_walk.bvh";
    options->shader_dir = SINEW_SHADER_DIR;
    exit_code = editor::runEditor(*options);
  });
}

}  // namespace sinew::app
