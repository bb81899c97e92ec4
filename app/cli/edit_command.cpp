// `sinew edit [PROJECT | FILE] [--animation NAME] [--evolve [--evolve-minutes M]
// [--evolve-generations G --export DIR]] [--screenshot
// OUT.png --frames N [--evolve-generations G] [--panel-shots DIR]] [--bench --shown N]
// [--no-shadows] [--no-mesh]`: the editor.
#include <cstdint>
#include <memory>

#include "cli/commands.h"
#include "editor/editor.h"

namespace sinew::app {

void addEditCommand(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<editor::EditorOptions>();
  CLI::App* command =
      app.add_subcommand("edit", "Open the editor (the default when sinew runs without a command)");
  command->add_option("file", options->file,
                      "A project (.json), or a BVH or glTF file to open (default: the bundled "
                      "default project, the biped walk)");
  command->add_option("--animation", options->animation, "Animation to open in a glTF, by name");
  command->add_option("--screenshot", options->screenshot,
                      "Render --frames frames with playback running, save the window as this PNG "
                      "and exit");
  command->add_option("--frames", options->frames, "Frames before the screenshot (default 30)")
      ->check(CLI::Range(1, 100000));
  command->add_flag("--evolve", options->evolve,
                    "Start evolving the opened clip's physical motion at once (the Evolve panel's "
                    "Start)");
  command
      ->add_option("--evolve-minutes", options->evolve_minutes, "The search's budget (default 2)")
      ->check(CLI::Range(0.1, 600.0));
  command
      ->add_option("--evolve-generations", options->evolve_generations,
                   "With --evolve: the search's budget in generations (with --screenshot: "
                   "wait for this many first, at most 2 minutes)")
      ->check(CLI::Range(0, 10000));
  command->add_option("--export", options->export_dir,
                      "With --evolve: no window; run the search (--evolve-generations, else "
                      "--evolve-minutes) and write what `sinew evolve --out DIR` writes here");
  command
      ->add_option("--shown", options->shown,
                   "Individuals of the population drawn in the viewport, best first (default 8)")
      ->check(CLI::Range(1, 64));
  command->add_option(
      "--panel-shots", options->panel_dir,
      "With --screenshot: also save each panel as DIR/<panel>.png (the user guide's "
      "pictures)");
  command->add_flag(
      "--bench", options->bench,
      "Print the editor's frame time (median, 95th percentile): --frames frames of the "
      "clip alone, then as many while the search runs with --shown characters");
  command->add_flag_function(
      "--no-shadows", [options](std::int64_t) { options->shadows = false; },
      "Start with the key light's shadows off (the Timeline's Shadows toggle)");
  command->add_flag_function(
      "--no-mesh", [options](std::int64_t) { options->mesh = false; },
      "Start with glTF characters drawn as capsules, not their skinned meshes");
  command->callback([options, &exit_code] {
    if (options->file.empty()) options->file = SINEW_ASSET_DIR "/default.sinew.json";
    if (!options->export_dir.empty() && !options->evolve) {
      exit_code = fail("--export writes a search's results: give --evolve too");
      return;
    }
    options->shader_dir = SINEW_SHADER_DIR;
    exit_code = editor::runEditor(*options);
  });
}

}  // namespace sinew::app
