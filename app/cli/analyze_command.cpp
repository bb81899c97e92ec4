// sinew analyze CLIP: the stride, the harmonics kept per joint and what that costs in degrees
// and centimetres, for people (a table) and pipelines (--json).
#include <cstdio>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/analyze_indirect.h"
#include "cli/analyze_plot.h"
#include "cli/commands.h"
#include "sinew/core/file_io.h"
#include "sinew/core/text.h"
#include "sinew/spectral/analysis.h"

namespace sinew::app {
namespace {

struct AnalyzeArgs {
  std::string file;
  std::string animation;
  std::string harmonics = "5";
  double tolerance_cm = 1.0;
  int strides = 1;
  std::string json_path;
  std::string plot_path;
  std::vector<std::string> plot_joints;
  ImportFlags import;
};

const char* axisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

nlohmann::json spectrumJson(const motion::Skeleton& skeleton, const spectral::MotionSpectrum& s) {
  nlohmann::json joints = nlohmann::json::array();
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const spectral::JointError& e = s.joint_errors[j];
    nlohmann::json channels = nlohmann::json::array();
    for (size_t c = 0; c < s.signals.channels.size(); ++c) {
      const spectral::SignalChannel& channel = s.signals.channels[c];
      if (channel.joint != j) continue;
      nlohmann::json kept = nlohmann::json::array();
      for (const spectral::Harmonic& h : s.series[c].strongest(s.joint_k[j])) {
        kept.push_back({{"n", h.n}, {"amplitude", h.amplitude}, {"phase", h.phase}});
      }
      channels.push_back(
          {{"kind", channel.kind == spectral::SignalKind::kRotation ? "rotation" : "translation"},
           {"axis", axisName(channel.axis)},
           {"unit", channel.kind == spectral::SignalKind::kRotation ? "rad" : "m"},
           {"mean", s.series[c].mean},
           {"trend_per_s", s.trends[c]},
           {"harmonics", kept}});
    }
    joints.push_back({{"name", skeleton.names[j]},
                      {"k", s.joint_k[j]},
                      {"moving", !channels.empty()},
                      {"rot_err_deg_rms", e.rot_err_deg_rms},
                      {"rot_err_deg_max", e.rot_err_deg_max},
                      {"pos_err_cm_mean", e.pos_err_cm_mean},
                      {"pos_err_cm_max", e.pos_err_cm_max},
                      {"channels", channels}});
  }
  return {{"stride_found", s.stride.found},
          {"period_s", s.period_s},
          {"stride_similarity", s.stride.similarity},
          {"strides", s.window.strides},
          {"window_start_s", s.window.start_s},
          {"seam_rad", s.window.seam},
          {"samples_per_stride", s.samples_per_stride},
          {"omega0_rad_s", s.omega0},
          {"travel_velocity_m_s", {s.travel_velocity.x, s.travel_velocity.y, s.travel_velocity.z}},
          {"coefficients", s.coefficientCount()},
          {"rot_err_deg_rms", s.total.rot_err_deg_rms},
          {"rot_err_deg_max", s.total.rot_err_deg_max},
          {"pos_err_cm_mean", s.total.pos_err_cm_mean},
          {"pos_err_cm_max", s.total.pos_err_cm_max},
          {"notes", s.notes},
          {"joints", joints}};
}

void printTable(const motion::Skeleton& skeleton, const spectral::MotionSpectrum& s) {
  if (s.stride.found) {
    std::printf("stride     %.4f s (%.3f Hz, similarity %.2f); analysed %d stride(s) from %.3f s, "
                "seam %.2f deg\n",
                s.period_s, 1.0 / s.period_s, s.stride.similarity, s.window.strides,
                s.window.start_s, glm::degrees(s.window.seam));
  }
  for (const std::string& note : s.notes) std::printf("note       %s\n", note.c_str());
  const glm::dvec3 v = s.travel_velocity;
  std::printf("travel     %.3f m/s (x %.3f, y %.3f, z %.3f)\n", glm::length(v), v.x, v.y, v.z);
  std::printf("samples    %d per stride; %d coefficients kept\n\n", s.samples_per_stride,
              s.coefficientCount());
  std::printf("%-24s %3s  %9s %9s  %9s %9s  %s\n", "joint", "K", "deg RMS", "deg max", "cm mean",
              "cm max", "strongest harmonics (n: amplitude)");
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    std::string strongest;
    double best = 0.0;
    int best_channel = -1;
    for (size_t c = 0; c < s.signals.channels.size(); ++c) {
      if (s.signals.channels[c].joint != j || s.signals.channels[c].kind != spectral::SignalKind::kRotation) continue;
      const auto top = s.series[c].strongest(1);
      if (!top.empty() && top[0].amplitude > best) {
        best = top[0].amplitude;
        best_channel = static_cast<int>(c);
      }
    }
    if (best_channel >= 0) {
      for (const spectral::Harmonic& h : s.series[best_channel].strongest(std::min(3, s.joint_k[j]))) {
        char term[48];
        std::snprintf(term, sizeof(term), "%s%d: %.1f deg", strongest.empty() ? "" : ", ", h.n,
                      glm::degrees(h.amplitude));
        strongest += term;
      }
    }
    const spectral::JointError& e = s.joint_errors[j];
    std::printf("%-24s %3d  %9.3f %9.3f  %9.3f %9.3f  %s\n", skeleton.names[j].c_str(),
                best_channel >= 0 ? s.joint_k[j] : 0, e.rot_err_deg_rms, e.rot_err_deg_max,
                e.pos_err_cm_mean, e.pos_err_cm_max,
                best_channel >= 0 ? strongest.c_str() : "(does not move)");
  }
  std::printf("%-24s %3s  %9.3f %9.3f  %9.3f %9.3f\n", "total", "", s.total.rot_err_deg_rms,
              s.total.rot_err_deg_max, s.total.pos_err_cm_mean, s.total.pos_err_cm_max);
}

int runAnalyze(const AnalyzeArgs& args) {
  Result<motion::ImportOptions> options = args.import.options();
  if (!options.ok()) return fail(options.message());
  Result<motion::MotionAsset> asset = motion::importMotion(args.file, options.value());
  if (!asset.ok()) return fail(asset.message());
  Result<int> clip = selectClip(asset.value(), args.animation);
  if (!clip.ok()) return fail(clip.message());

  spectral::AnalysisSettings settings;
  if (args.harmonics == "auto") {
    settings.auto_harmonics = true;
  } else {
    try {
      size_t used = 0;
      settings.harmonics = std::stoi(args.harmonics, &used);
      if (used != args.harmonics.size()) throw std::invalid_argument(args.harmonics);
    } catch (const std::exception&) {
      return fail("--harmonics: expected a whole number or 'auto', got '" + args.harmonics + "'");
    }
  }
  settings.tolerance_cm = args.tolerance_cm;
  settings.max_strides = args.strides;
  const motion::Skeleton& skeleton = asset.value().skeleton;
  Result<spectral::MotionSpectrum> spectrum =
      spectral::analyze(skeleton, asset.value().clips[clip.value()], settings);
  if (!spectrum.ok()) return fail(args.file + ": " + spectrum.message());
  std::printf("glitches   %s\n", glitchSummary(asset.value(), clip.value()).c_str());
  for (const motion::Glitch& glitch : asset.value().glitches[clip.value()]) {
    std::printf("  glitch   %s\n", motion::describeGlitch(skeleton, glitch).c_str());
  }
  printTable(skeleton, spectrum.value());
  const IndirectReport indirect =
      measureIndirect(skeleton, asset.value().clips[clip.value()], spectrum.value());
  printIndirect(skeleton, indirect);
  if (!args.json_path.empty()) {
    nlohmann::json json = spectrumJson(skeleton, spectrum.value());
    json.update(indirectJson(skeleton, indirect));
    json["file"] = toUtf8(args.file);  // a path is bytes; JSON text is UTF-8
    json["animation"] = asset.value().clips[clip.value()].name;
    json["glitches"] = glitchJson(asset.value(), clip.value());
    json["settings"] = {{"harmonics", args.harmonics}, {"tolerance_cm", args.tolerance_cm},
                        {"max_strides", args.strides}};
    Status status = writeFileAtomically(
        args.json_path, json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    if (!status.ok()) return fail(status.message());
    std::printf("\nwrote %s\n", args.json_path.c_str());
  }
  if (!args.plot_path.empty()) {
    Status status = writePlot(args.plot_path, skeleton, asset.value().clips[clip.value()],
                              spectrum.value(), args.plot_joints);
    if (!status.ok()) return fail(status.message());
    std::printf("wrote %s\n", args.plot_path.c_str());
  }
  return 0;
}

}  // namespace

void addAnalyzeCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<AnalyzeArgs>();
  CLI::App* command = app.add_subcommand(
      "analyze", "Find the stride, measure every joint's harmonics and the error of keeping K");
  command->add_option("clip", args->file, "A .bvh, .glb or .gltf file")->required();
  command->add_option("--animation", args->animation, "Which glTF animation (by name)");
  command->add_option("--harmonics", args->harmonics,
                      "Harmonics kept per joint: a number, or 'auto' (fewest within "
                      "--tolerance-cm)")
      ->default_val("5");
  command->add_option("--tolerance-cm", args->tolerance_cm,
                      "Worst joint position error allowed by --harmonics auto, cm")
      ->default_val(1.0)
      ->check(CLI::Validator(
          [](std::string& text) {
            double cm = 0.0;
            const bool number = CLI::detail::lexical_cast(text, cm);
            return number && cm > 0.0 && cm <= 1000.0
                       ? std::string()
                       : "expected centimetres in (0, 1000], got " + text;
          },
          "CM in (0, 1000]"));
  command->add_option("--strides", args->strides, "Most whole strides to analyse together")
      ->default_val(1)
      ->check(CLI::Range(1, 1000));
  command->add_option("--json", args->json_path, "Also write the results as JSON to this file");
  CLI::Option* plot = command->add_option(
      "--plot", args->plot_path,
      "Also draw original vs model curves and the harmonic amplitudes of chosen joints: .svg, "
      "or .png (needs rsvg-convert, Debian's librsvg2-bin)");
  command->add_option("--joints", args->plot_joints,
                      "Joints to plot, comma-separated (default: the four that rotate most)")
      ->delimiter(',')
      ->needs(plot);
  args->import.addTo(*command);
  command->callback([args, &exit_code]() { exit_code = runAnalyze(*args); });
}

}  // namespace sinew::app
