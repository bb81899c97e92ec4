// sinew info FILE: what a motion file holds, for people (text) and pipelines (--json).
#include <iomanip>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "sinew/core/text.h"
#include "sinew/motion/anatomy.h"

namespace sinew::app {
namespace {

struct InfoArgs {
  std::string file;
  std::string animation;
  bool json = false;
  ImportFlags import;
};

std::string layoutText(const motion::ChannelLayout& layout) {
  std::string text;
  for (motion::ChannelType type : layout.types) {
    if (!text.empty()) text += ' ';
    text += motion::channelName(type);
  }
  return text;
}

nlohmann::json clipJson(const motion::Clip& clip) {
  return {{"name", clip.name},
          {"frames", clip.frame_count},
          {"frame_time_s", clip.frame_time},
          {"fps", clip.fps()},
          {"duration_s", clip.duration()}};
}

// The figure's family, size and mass (motion::estimateBody, what the body plan weighs it by) in
// the chosen clip, or the rest pose when there is none.
motion::BodyEstimate bodyOf(const motion::MotionAsset& asset, int selected) {
  const motion::Clip rest = motion::restClip(asset.skeleton, 1, 1.0 / 30.0);
  const motion::Clip& clip = selected >= 0 ? asset.clips[selected] : rest;
  std::vector<motion::Foot> feet;
  if (auto found = motion::findFeet(asset.skeleton, clip); found.ok()) feet = found.value();
  return motion::estimateBody(asset.skeleton, clip, feet);
}

// "stature 1.63 m (the joints reach 1.33 m)": the height a person means, then what was measured.
std::string heightText(const motion::BodyEstimate& body) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2);
  if (body.stature_m > 0.0)
    text << "stature " << body.stature_m << " m (the joints reach " << body.extent_m << " m)";
  else if (body.trunk_length_m > 0.0)
    text << body.figure.hip_height << " m at the hips, trunk " << body.trunk_length_m
         << " m (the joints reach " << body.extent_m << " m)";
  else
    text << "the joints reach " << body.extent_m << " m";
  return text.str();
}

void addBodyJson(const motion::BodyEstimate& body, nlohmann::json& info) {
  info["family"] = body.figure.human ? "human" : motion::familyName(body.figure.family);
  info["height_m"] = body.stature_m > 0.0 ? body.stature_m : body.extent_m;
  info["joint_extent_m"] = body.extent_m;
  info["hip_height_m"] = body.figure.hip_height;
  info["leg_length_m"] = body.leg_length_m;
  if (body.stature_m > 0.0) info["stature_m"] = body.stature_m;
  if (body.trunk_length_m > 0.0) info["trunk_length_m"] = body.trunk_length_m;
  if (body.mass_kg > 0.0) info["mass_kg"] = body.mass_kg;
  info["body"] = body.basis;
}

nlohmann::json infoJson(const motion::MotionAsset& asset, int selected) {
  const motion::Skeleton& skeleton = asset.skeleton;
  nlohmann::json joints = nlohmann::json::array();
  int end_sites = 0;
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    nlohmann::json joint = {
        {"name", skeleton.names[j]},
        {"parent", skeleton.parents[j]},
        {"offset_m", {skeleton.offsets[j].x, skeleton.offsets[j].y, skeleton.offsets[j].z}}};
    nlohmann::json channels = nlohmann::json::array();
    for (motion::ChannelType type : skeleton.channels[j].types) {
      channels.push_back(motion::channelName(type));
    }
    joint["channels"] = channels;
    if (skeleton.channels[j].rotationCount() == 3) {
      joint["rotation_order"] = skeleton.channels[j].eulerOrder().name().data();
    }
    if (skeleton.end_sites[j]) {
      ++end_sites;
      const glm::dvec3& e = *skeleton.end_sites[j];
      joint["end_site_m"] = {e.x, e.y, e.z};
    }
    joints.push_back(joint);
  }
  nlohmann::json clips = nlohmann::json::array();
  for (const motion::Clip& clip : asset.clips) clips.push_back(clipJson(clip));
  nlohmann::json meshes = nlohmann::json::array();
  for (const motion::SkinnedMesh& mesh : asset.meshes) {
    meshes.push_back({{"name", mesh.name},
                      {"vertices", mesh.positions.size()},
                      {"triangles", mesh.indices.size() / 3}});
  }
  nlohmann::json info = {
      {"file", toUtf8(asset.path.string())},  // a path is bytes; JSON text is UTF-8
      {"format", asset.gltf ? "gltf" : "bvh"},
      {"joint_count", skeleton.jointCount()},
      {"end_site_count", end_sites},
      {"channel_count", skeleton.channelCount()},
      {"units", motion::unitName(asset.detection.frame.unit)},
      {"up_axis", motion::upAxisName(asset.detection.frame.up)},
      {"height_file_units", asset.detection.height_in_file_units},
      {"detection", asset.detection.reason},
      {"joints", joints},
      {"animations", clips},
      {"meshes", meshes},
      {"skins", asset.gltf ? asset.gltf->skin_count : 0},
      {"warnings", asset.warnings},
  };
  addBodyJson(bodyOf(asset, selected), info);
  if (selected >= 0) {
    const motion::Clip& clip = asset.clips[selected];
    info["animation"] = clip.name;
    info["frames"] = clip.frame_count;
    info["fps"] = clip.fps();
    info["frame_time_s"] = clip.frame_time;
    info["duration_s"] = clip.duration();
    info["glitches"] = glitchJson(asset, selected);
  }
  return info;
}

void printText(const motion::MotionAsset& asset, int selected, std::ostream& out) {
  const motion::Skeleton& skeleton = asset.skeleton;
  const nlohmann::json info = infoJson(asset, selected);
  const motion::BodyEstimate body = bodyOf(asset, selected);
  out << asset.path.string() << '\n';
  out << "  format     " << (asset.gltf ? "glTF" : "BVH") << '\n';
  out << "  joints     " << skeleton.jointCount();
  if (!asset.gltf) {  // channels and End Sites are BVH notions
    out << " (+" << info["end_site_count"].get<int>() << " end sites), " << skeleton.channelCount()
        << " channels";
  }
  out << '\n';
  if (selected >= 0) {
    const motion::Clip& clip = asset.clips[selected];
    out << "  animation  '" << clip.name << "': " << clip.frame_count << " frames at "
        << std::setprecision(6) << clip.fps() << " fps (frame time " << clip.frame_time << " s), "
        << std::fixed << std::setprecision(3) << clip.duration() << " s\n"
        << std::defaultfloat;
  }
  out << "  units      " << motion::unitName(asset.detection.frame.unit) << ", up "
      << motion::upAxisName(asset.detection.frame.up) << "  (" << asset.detection.reason << ")\n"
      << "  height     " << heightText(body) << '\n'
      << "  body       " << body.basis << '\n';
  if (selected >= 0) out << "  glitches   " << glitchSummary(asset, selected) << '\n';
  if (asset.clips.size() > 1 || asset.gltf) {
    out << "  animations " << asset.clips.size() << '\n';
    for (const motion::Clip& clip : asset.clips) {
      out << "    " << std::left << std::setw(16) << ("'" + clip.name + "'") << std::right
          << clip.frame_count << " frames, " << std::setprecision(6) << clip.fps() << " fps, "
          << std::fixed << std::setprecision(3) << clip.duration() << " s\n"
          << std::defaultfloat;
    }
  }
  if (asset.gltf) {
    out << "  skins      " << asset.gltf->skin_count
        << (asset.gltf->skin_count > 1 ? " (the first is imported)" : "") << "\n  meshes     "
        << asset.meshes.size() << '\n';
    for (const motion::SkinnedMesh& mesh : asset.meshes) {
      out << "    '" << mesh.name << "': " << mesh.positions.size() << " vertices, "
          << mesh.indices.size() / 3 << " triangles\n";
    }
  }
  for (const std::string& warning : asset.warnings) out << "  warning    " << warning << '\n';
  out << "joint tree (channels as in the file):\n";
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    out << "  " << std::string(2 * skeleton.depth(j), ' ') << skeleton.names[j];
    const std::string layout = layoutText(skeleton.channels[j]);
    if (!layout.empty()) out << "  [" << layout << "]";
    if (skeleton.end_sites[j]) out << "  + End Site";
    out << '\n';
  }
}

int runInfo(const InfoArgs& args) {
  Result<motion::ImportOptions> options = args.import.options();
  if (!options.ok()) return fail(options.message());
  Result<motion::MotionAsset> asset = motion::importMotion(args.file, options.value());
  if (!asset.ok()) return fail(asset.message());
  int selected = -1;
  if (!asset.value().clips.empty() || !args.animation.empty()) {
    Result<int> clip = selectClip(asset.value(), args.animation);
    if (!clip.ok()) return fail(clip.message());
    selected = clip.value();
  }
  if (args.json) {
    std::cout << infoJson(asset.value(), selected)
                     .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
              << '\n';
  } else {
    printText(asset.value(), selected, std::cout);
  }
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* command = app.add_subcommand("info",
                                         "Show a motion file's joints, channels, frames, "
                                         "units and (glTF) animations, skins and meshes");
  command->add_option("file", args->file, "A .bvh, .glb or .gltf file")->required();
  command->add_option("--animation", args->animation, "Which glTF animation to report (by name)");
  command->add_flag("--json", args->json, "Print machine-readable JSON");
  args->import.addTo(*command);
  command->callback([args, &exit_code]() { exit_code = runInfo(*args); });
}

}  // namespace sinew::app
