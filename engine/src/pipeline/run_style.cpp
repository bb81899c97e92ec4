#include "sinew/pipeline/run_style.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "sinew/pipeline/pipeline.h"
#include "sinew/spectral/style.h"

namespace sinew::pipeline {
namespace {

constexpr double kSampleFps = 30.0;  // the tracked target sampled for analysis like a clip
constexpr int kSampleStrides = 4;

struct PairTargets {
  std::string label;
  spectral::TargetMotion neutral, styled;
};

// `motion`'s score of each label and amount along each pair.
Result<std::vector<MeasuredStyle>> measureAgainst(const motion::Skeleton& skeleton,
                                                  const spectral::TargetMotion& motion,
                                                  const std::vector<PairTargets>& pairs,
                                                  std::string& closest) {
  std::vector<spectral::StyleExample> library;
  library.push_back({"neutral", pairs.front().neutral, pairs.front().neutral});
  for (const PairTargets& p : pairs) library.push_back({p.label, p.neutral, p.styled});
  std::vector<MeasuredStyle> out;
  for (const PairTargets& p : pairs) {
    // Each pair's own neutral is the reference of its measurement.
    Result<spectral::StyleScores> scores =
        spectral::scoreStyleRelative(skeleton, motion, p.neutral, library);
    if (!scores.ok()) return Status::error("style '" + p.label + "': " + scores.message());
    MeasuredStyle m;
    for (const auto& [label, score] : scores.value().scores)
      if (label == p.label) m.score = score;
    m.amount = spectral::styleAmount(skeleton, motion, p.neutral, p.styled);
    if (&p == &pairs.front()) closest = scores.value().closest;
    out.push_back(m);
  }
  return out;
}

}  // namespace

std::vector<std::string> RunStyleReport::lines() const {
  std::vector<std::string> out;
  for (const StyleSurvival& s : styles) {
    char line[256];
    if (s.simulated_measured)
      std::snprintf(line, sizeof line,
                    "%s (weight %.2f): target score %.2f amount %.2f, simulated score %.2f amount "
                    "%.2f",
                    s.label.c_str(), s.weight, s.target.score, s.target.amount, s.simulated.score,
                    s.simulated.amount);
    else
      std::snprintf(line, sizeof line,
                    "%s (weight %.2f): target score %.2f amount %.2f, simulated not measured: %s",
                    s.label.c_str(), s.weight, s.target.score, s.target.amount,
                    s.not_measured.c_str());
    out.emplace_back(line);
  }
  return out;
}

nlohmann::json RunStyleReport::json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const StyleSurvival& s : styles) {
    nlohmann::json item = {{"label", s.label},
                           {"weight", s.weight},
                           {"target", {{"score", s.target.score}, {"amount", s.target.amount}}}};
    if (s.simulated_measured)
      item["simulated"] = {{"score", s.simulated.score}, {"amount", s.simulated.amount}};
    else
      item["simulated_not_measured"] = s.not_measured;
    list.push_back(std::move(item));
  }
  nlohmann::json out = {{"styles", list}, {"target_closest", target_closest}};
  if (!simulated_closest.empty()) out["simulated_closest"] = simulated_closest;
  return out;
}

Result<RunStyleReport> measureRunStyle(const motion::Skeleton& skeleton,
                                       const spectral::TargetMotion& tracked,
                                       const motion::Clip& run, double skip_s,
                                       double stride_s, const MotionEdits& edits) {
  RunStyleReport report;
  if (edits.styles.empty()) return report;
  std::vector<PairTargets> pairs;
  for (const StylePair& pair : edits.styles) {
    Result<spectral::TargetMotion> neutral = styleClipTarget(pair.neutral, skeleton);
    if (!neutral.ok()) return Status::error("style '" + pair.label + "': " + neutral.message());
    Result<spectral::TargetMotion> styled = styleClipTarget(pair.styled, skeleton);
    if (!styled.ok()) return Status::error("style '" + pair.label + "': " + styled.message());
    pairs.push_back({pair.label, std::move(neutral).value(), std::move(styled).value()});
  }
  // The tracked motion and the run, each analysed the way the pairs' clips were.
  Result<spectral::TargetMotion> target =
      styleTarget(skeleton, tracked.sample(kSampleFps, kSampleStrides), "the tracked motion");
  if (!target.ok()) return target.status();
  Result<std::vector<MeasuredStyle>> of_target =
      measureAgainst(skeleton, target.value(), pairs, report.target_closest);
  if (!of_target.ok()) return of_target.status();
  const int skip = static_cast<int>(std::lround(skip_s / run.frame_time));
  Result<spectral::TargetMotion> simulated =
      skip + 2 < run.frame_count
          ? styleTarget(skeleton, motion::clipFrames(run, skip, run.frame_count - skip),
                        "the simulated run", stride_s)
          : Result<spectral::TargetMotion>(Status::error("the run ended before its first stride did"));
  Result<std::vector<MeasuredStyle>> of_run = Status::error("not measured");
  if (simulated.ok())
    of_run = measureAgainst(skeleton, simulated.value(), pairs, report.simulated_closest);
  for (size_t i = 0; i < pairs.size(); ++i) {
    StyleSurvival s;
    s.label = pairs[i].label;
    s.weight = edits.styles[i].weight;
    s.target = of_target.value()[i];
    s.simulated_measured = of_run.ok();
    if (of_run.ok()) s.simulated = of_run.value()[i];
    else s.not_measured = simulated.ok() ? of_run.message() : simulated.message();
    report.styles.push_back(std::move(s));
  }
  if (!of_run.ok()) report.simulated_closest.clear();
  return report;
}

}  // namespace sinew::pipeline
