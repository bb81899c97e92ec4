// sinew convert IN OUT: BVH <-> glTF in any direction (and BVH -> BVH, glTF -> glTF).
#include <iostream>

#include "cli/commands.h"
#include "sinew/motion/bvh.h"

namespace sinew::app {
namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  std::string animation;
  std::string out_units;
  std::string out_up;
  ImportFlags import;
};

int runConvert(const ConvertArgs& args) {
  Result<motion::ImportOptions> options = args.import.options();
  if (!options.ok()) return fail(options.message());
  Result<motion::MotionAsset> asset = motion::importMotion(args.input, options.value());
  if (!asset.ok()) return fail(asset.message());
  Result<int> clip = selectClip(asset.value(), args.animation);
  if (!clip.ok()) return fail(clip.message());

  motion::ExportOptions export_options;
  if (!args.out_units.empty() || !args.out_up.empty()) {
    motion::SourceFrame frame = motion::defaultBvhFrame(asset.value().skeleton);
    if (!args.out_units.empty()) frame.unit = *motion::unitFromName(args.out_units);
    if (!args.out_up.empty()) frame.up = *motion::upAxisFromName(args.out_up);
    export_options.bvh_frame = frame;
  }
  // glTF keys are resampled at import; BVH frames are resampled on the way out.
  // The report says what was written, so the resampling happens here rather than in export.
  const motion::Clip& chosen = asset.value().clips[clip.value()];
  const motion::Clip written = options.value().fps && !asset.value().gltf
                                   ? motion::resampleClip(chosen, 1.0 / *options.value().fps)
                                   : chosen;
  Status status = motion::exportMotion(args.output, asset.value(), written, export_options);
  if (!status.ok()) return fail(status.message());
  std::cout << "wrote " << args.output << ": animation '" << written.name << "', "
            << asset.value().skeleton.jointCount() << " joints, " << written.frame_count
            << " frames at " << written.fps() << " fps\n";
  return 0;
}

}  // namespace

void addConvertCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* command = app.add_subcommand(
      "convert", "Convert between BVH and glTF (.bvh, .glb, .gltf), keeping the skeleton, "
                 "the animation and, from glTF, the mesh and skin");
  command->add_option("input", args->input, "The file to read")->required();
  command->add_option("output", args->output, "The file to write (.bvh, .glb or .gltf)")
      ->required();
  command->add_option("--animation", args->animation, "Which glTF animation (by name)");
  command->add_option("--out-units", args->out_units, "BVH output unit (default: the source's; "
                                                      "cm for glTF sources)")
      ->check(CLI::IsMember({"m", "cm", "mm", "in"}));
  command->add_option("--out-up", args->out_up, "BVH output up axis (default: the source's)")
      ->check(CLI::IsMember({"Y", "Z", "y", "z"}));
  args->import.addTo(*command);
  command->callback([args, &exit_code]() { exit_code = runConvert(*args); });
}

}  // namespace sinew::app
