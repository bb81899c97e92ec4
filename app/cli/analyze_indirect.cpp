#include "cli/analyze_indirect.h"

#include <algorithm>
#include <cstdio>

namespace sinew::app {
namespace {

constexpr int kTableJoints = 10;     // importance rows printed; --json has them all
constexpr int kSeriesHarmonics = 5;  // harmonics per indirect series in the JSON, strongest first

nlohmann::json vec3(const glm::dvec3& v) {
  return {v.x, v.y, v.z};
}

// Contact runs of one foot, seconds from the clip's first frame: [start, end).
std::vector<std::pair<double, double>> contactRuns(const std::vector<std::uint8_t>& down,
                                                   double dt) {
  std::vector<std::pair<double, double>> runs;
  const int n = static_cast<int>(down.size());
  for (int f = 0; f < n;) {
    int end = f;
    while (end < n && down[end] == down[f]) ++end;
    if (down[f]) runs.emplace_back(f * dt, std::min(end, n - 1) * dt);
    f = end;
  }
  return runs;
}

// The strongest harmonic of a series, for the table.
spectral::Harmonic strongest(const spectral::IndirectSeries& s) {
  const std::vector<spectral::Harmonic> top = s.series.strongest(1);
  return top.empty() ? spectral::Harmonic{} : top[0];
}

}  // namespace

IndirectReport measureIndirect(const motion::Skeleton& skeleton, const motion::Clip& clip,
                               const spectral::MotionSpectrum& spectrum) {
  IndirectReport report;
  Result<spectral::IndirectSignals> indirect = spectral::analyzeIndirect(skeleton, clip, spectrum);
  if (indirect.ok()) {
    report.indirect = std::move(indirect).value();
  } else {
    report.problems.push_back("indirect signals: " + indirect.message());
  }
  Result<spectral::ImportanceReport> importance =
      spectral::jointImportance(skeleton, clip, spectrum);
  if (importance.ok()) {
    report.importance = std::move(importance).value();
  } else {
    report.problems.push_back("joint importance: " + importance.message());
  }
  return report;
}

void printIndirect(const motion::Skeleton& skeleton, const IndirectReport& report) {
  std::printf("\n");
  for (const std::string& problem : report.problems)
    std::printf("note       %s\n", problem.c_str());
  if (report.indirect) {
    const spectral::IndirectSignals& in = *report.indirect;
    const spectral::GaitFigures& g = in.gait;
    std::printf("feet      ");
    for (size_t i = 0; i < in.feet.size(); ++i) {
      const spectral::Foot& foot = in.feet[i];
      int landings = 0;
      for (const spectral::Footfall& fall : in.footfalls)
        landings += fall.foot == static_cast<int>(i);
      std::printf("%s %s (%s, %s; ground %.1f cm, %d footfalls)", i == 0 ? "" : ",",
                  skeleton.names[foot.joint].c_str(), spectral::sideName(foot.side),
                  foot.by_name ? "by name" : "by geometry", 100.0 * in.ground_levels_m[i],
                  landings);
    }
    std::printf("\n");
    if (g.stride_intervals > 0) {
      std::printf("contacts   stride %.4f s from %d contact intervals", g.stride_period_s,
                  g.stride_intervals);
      if (g.analysis_period_s > 0.0) {
        std::printf(" against %.4f s analysed (%+.2f%%)", g.analysis_period_s,
                    100.0 * g.period_difference);
      }
      std::printf("; duty factor %.2f\n", g.duty_factor);
      std::printf("strides    %.1f cm, %.3f m/s from the footfalls\n", 100.0 * g.stride_length_m,
                  g.contact_speed_m_s);
    }
    if (!in.steps.empty()) {
      std::printf("steps      %zu: length %.1f cm, width %.1f cm, duration %.3f s\n",
                  in.steps.size(), 100.0 * g.step_length_m, 100.0 * g.step_width_m,
                  g.step_duration_s);
    }
    std::printf("com        %.3f m/s over the window", g.speed_m_s);
    // The first three spectra are the centre of mass's height, lateral and forward motion.
    const char* labels[] = {"bob", "sway", "surge"};
    for (size_t s = 0; s < std::min<size_t>(3, in.spectra.size()); ++s) {
      const spectral::Harmonic h = strongest(in.spectra[s]);
      std::printf("; %s %.2f cm (harmonic %d)", labels[s], 100.0 * h.amplitude, h.n);
    }
    std::printf("\n");
    for (const std::string& note : in.notes) std::printf("note       %s\n", note.c_str());
  }
  if (report.importance) {
    const spectral::ImportanceReport& imp = *report.importance;
    std::printf(
        "\nimportance: each joint frozen at its mean rotation (the model alone: %.3f cm "
        "mean, %.2f cm max)\n",
        imp.model_cm_mean, imp.model_cm_max);
    std::printf("%4s %-24s %9s %9s %12s %8s\n", "rank", "joint", "cm mean", "cm max", "energy rad2",
                "lever m");
    const int rows = std::min(kTableJoints, static_cast<int>(imp.joints.size()));
    for (int r = 0; r < rows; ++r) {
      const spectral::JointImportance& j = imp.joints[r];
      std::printf("%4d %-24s %9.3f %9.2f %12.4f %8.3f\n", r + 1, skeleton.names[j.joint].c_str(),
                  j.frozen_cm_mean, j.frozen_cm_max, j.energy_rad2, j.lever_m);
    }
    if (rows < static_cast<int>(imp.joints.size())) {
      std::printf("     (%zu more with --json)\n", imp.joints.size() - rows);
    }
  }
}

nlohmann::json indirectJson(const motion::Skeleton& skeleton, const IndirectReport& report) {
  nlohmann::json out = nlohmann::json::object();
  std::vector<std::string> notes = report.problems;
  if (report.indirect) {
    const spectral::IndirectSignals& in = *report.indirect;
    const spectral::ContactSettings defaults;  // what measureIndirect used
    nlohmann::json feet = nlohmann::json::array();
    for (size_t i = 0; i < in.feet.size(); ++i) {
      const spectral::Foot& foot = in.feet[i];
      nlohmann::json runs = nlohmann::json::array();
      for (const auto& [start, end] : contactRuns(in.contacts[i], in.frame_time)) {
        runs.push_back({{"start_s", start}, {"end_s", end}});
      }
      feet.push_back(
          {{"name", skeleton.names[foot.joint]},
           {"side", spectral::sideName(foot.side)},
           {"found_by", foot.by_name ? "name" : "geometry"},
           {"pair", foot.pair >= 0 ? nlohmann::json(skeleton.names[in.feet[foot.pair].joint])
                                   : nlohmann::json()},
           {"ground_level_m", in.ground_levels_m[i]},
           {"contacts", runs}});
    }
    out["foot_contacts"] = {{"height_tolerance_m", defaults.height_tolerance_m},
                            {"speed_tolerance_m_s", defaults.speed_tolerance_m_s},
                            {"duty_factor", in.gait.duty_factor},
                            {"feet", feet}};
    nlohmann::json falls = nlohmann::json::array();
    for (const spectral::Footfall& fall : in.footfalls) {
      falls.push_back({{"foot", skeleton.names[in.feet[fall.foot].joint]},
                       {"time_s", fall.time_s},
                       {"duration_s", fall.duration_s},
                       {"position_m", vec3(fall.position)}});
    }
    nlohmann::json steps = nlohmann::json::array();
    for (const spectral::Step& step : in.steps) {
      const spectral::Footfall& from = in.footfalls[step.from];
      const spectral::Footfall& to = in.footfalls[step.to];
      steps.push_back({{"from", skeleton.names[in.feet[from.foot].joint]},
                       {"to", skeleton.names[in.feet[to.foot].joint]},
                       {"time_s", from.time_s},
                       {"length_m", step.length_m},
                       {"width_m", step.width_m},
                       {"duration_s", step.duration_s}});
    }
    const spectral::GaitFigures& g = in.gait;
    out["steps"] = {{"stride_period_s", g.stride_period_s},
                    {"stride_intervals", g.stride_intervals},
                    {"analysis_period_s", g.analysis_period_s},
                    {"period_difference", g.period_difference},
                    {"stride_length_m", g.stride_length_m},
                    {"step_length_m", g.step_length_m},
                    {"step_width_m", g.step_width_m},
                    {"step_duration_s", g.step_duration_s},
                    {"speed_m_s", g.speed_m_s},
                    {"contact_speed_m_s", g.contact_speed_m_s},
                    {"forward", vec3(in.forward)},
                    {"footfalls", falls},
                    {"steps", steps}};
    nlohmann::json masses = nlohmann::json::array();
    for (int j = 0; j < skeleton.jointCount(); ++j) {
      if (in.masses.fractions[j] <= 0.0) continue;
      masses.push_back({{"joint", skeleton.names[j]},
                        {"segment", spectral::segmentName(in.masses.segments[j])},
                        {"fraction", in.masses.fractions[j]}});
    }
    nlohmann::json spectra = nlohmann::json::array();
    for (const spectral::IndirectSeries& s : in.spectra) {
      nlohmann::json harmonics = nlohmann::json::array();
      for (const spectral::Harmonic& h : s.series.strongest(kSeriesHarmonics)) {
        harmonics.push_back({{"n", h.n}, {"amplitude", h.amplitude}, {"phase", h.phase}});
      }
      spectra.push_back({{"name", s.name},
                         {"unit", s.unit},
                         {"mean", s.series.mean},
                         {"aperiodic_energy", s.aperiodic_energy},
                         {"harmonics", harmonics}});
    }
    out["centre_of_mass"] = {{"masses", masses}, {"spectra", spectra}};
    notes.insert(notes.end(), in.notes.begin(), in.notes.end());
  }
  if (report.importance) {
    nlohmann::json joints = nlohmann::json::array();
    int rank = 0;
    for (const spectral::JointImportance& j : report.importance->joints) {
      joints.push_back({{"rank", ++rank},
                        {"name", skeleton.names[j.joint]},
                        {"frozen_cm_mean", j.frozen_cm_mean},
                        {"frozen_cm_max", j.frozen_cm_max},
                        {"energy_rad2", j.energy_rad2},
                        {"lever_m", j.lever_m},
                        {"weighted_energy_m2", j.weighted_energy_m2}});
    }
    out["importance"] = {{"model_cm_mean", report.importance->model_cm_mean},
                         {"model_cm_max", report.importance->model_cm_max},
                         {"joints", joints}};
  }
  out["indirect_notes"] = notes;
  return out;
}

}  // namespace sinew::app
