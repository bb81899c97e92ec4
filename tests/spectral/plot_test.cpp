#include "sinew/spectral/plot.h"

#include <cmath>
#include <numbers>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "support/test_support.h"

namespace sinew::spectral {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegrees = 180.0 / kPi;

struct Walker {
  motion::Skeleton skeleton;
  motion::Clip clip;
};

// Pelvis travelling along +Z with a small sway, thighs swinging 0.5 rad in antiphase, knees 0.3
// rad, a head that never moves. 1.1 s stride at 30 fps.
Walker makeWalker(const std::string& name = "walk") {
  Walker w;
  motion::Skeleton& s = w.skeleton;
  const int pelvis = s.addJoint("Hips", motion::kNoParent, {0, 0.9, 0});
  const int lhip = s.addJoint("LeftUpLeg", pelvis, {0.1, 0, 0});
  const int lknee = s.addJoint("LeftLeg", lhip, {0, -0.45, 0});
  s.end_sites[lknee] = glm::dvec3(0, -0.45, 0);
  const int rhip = s.addJoint("RightUpLeg", pelvis, {-0.1, 0, 0});
  const int rknee = s.addJoint("RightLeg", rhip, {0, -0.45, 0});
  s.end_sites[rknee] = glm::dvec3(0, -0.45, 0);
  const int head = s.addJoint("Head", pelvis, {0, 0.6, 0});
  s.end_sites[head] = glm::dvec3(0, 0.2, 0);
  motion::Clip& c = w.clip;
  c.name = name;
  c.frame_time = 1.0 / 30.0;
  c.frame_count = 121;
  c.joint_count = s.jointCount();
  const double omega = 2 * kPi / 1.1;
  const glm::dvec3 x(1, 0, 0);
  for (int f = 0; f < c.frame_count; ++f) {
    const double t = f * c.frame_time;
    c.translations.push_back({0.0, 0.9 + 0.02 * std::sin(2 * omega * t), 1.3 * t});
    c.rotations.push_back(glm::angleAxis(0.05 * std::sin(omega * t), glm::dvec3(0, 1, 0)));
    c.translations.push_back(s.offsets[lhip]);
    c.rotations.push_back(
        glm::angleAxis(0.5 * std::sin(omega * t) + 0.1 * std::sin(2 * omega * t + 1.0), x));
    c.translations.push_back(s.offsets[lknee]);
    c.rotations.push_back(glm::angleAxis(-0.4 - 0.3 * std::sin(omega * t + 0.5), x));
    c.translations.push_back(s.offsets[rhip]);
    c.rotations.push_back(
        glm::angleAxis(-0.5 * std::sin(omega * t) + 0.1 * std::sin(2 * omega * t + 1.0), x));
    c.translations.push_back(s.offsets[rknee]);
    c.rotations.push_back(glm::angleAxis(-0.4 + 0.3 * std::sin(omega * t + 0.5), x));
    c.translations.push_back(s.offsets[head]);
    c.rotations.push_back(glm::dquat(1, 0, 0, 0));
  }
  return w;
}

MotionSpectrum analyzeWalker(const Walker& w, int k = 3) {
  AnalysisSettings settings;
  settings.harmonics = k;
  Result<MotionSpectrum> spectrum = analyze(w.skeleton, w.clip, settings);
  EXPECT_TRUE(spectrum.ok()) << spectrum.message();
  return std::move(spectrum).value();
}

int countOf(const std::string& text, const std::string& needle) {
  int count = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) {
    ++count;
  }
  return count;
}

// The points="..." of every polyline with the given class, in document order.
std::vector<std::vector<std::pair<double, double>>> polylines(const std::string& svg,
                                                              const std::string& kind) {
  std::vector<std::vector<std::pair<double, double>>> out;
  const std::regex element("<polyline class=\"" + kind + "\"[^>]* points=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), element);
       it != std::sregex_iterator(); ++it) {
    std::istringstream points((*it)[1].str());
    std::vector<std::pair<double, double>> line;
    std::string point;
    while (points >> point) {
      const size_t comma = point.find(',');
      line.emplace_back(std::stod(point.substr(0, comma)), std::stod(point.substr(comma + 1)));
    }
    out.push_back(std::move(line));
  }
  return out;
}

TEST(PlotTest, RefusesInvalidInput) {
  const Walker w = makeWalker();
  const MotionSpectrum spectrum = analyzeWalker(w);
  PlotSettings settings;
  settings.joints = {"LeftUpLeg", "Tail"};
  Result<PlotData> plot = preparePlot(w.skeleton, w.clip, spectrum, settings);
  ASSERT_FALSE(plot.ok());
  EXPECT_NE(plot.message().find("unknown joint 'Tail'"), std::string::npos) << plot.message();
  EXPECT_NE(plot.message().find("LeftUpLeg"), std::string::npos) << "lists the joints there are";

  settings.joints = {"Head"};
  plot = preparePlot(w.skeleton, w.clip, spectrum, settings);
  EXPECT_NE(plot.message().find("joint 'Head' does not rotate"), std::string::npos)
      << plot.message();

  settings.joints = {"LeftLeg", "LeftLeg"};
  EXPECT_NE(
      plotSvg(w.skeleton, w.clip, spectrum, settings).message().find("'LeftLeg' is listed twice"),
      std::string::npos);
  settings.joints = {""};
  EXPECT_NE(preparePlot(w.skeleton, w.clip, spectrum, settings).message().find("empty"),
            std::string::npos);
  settings = {};
  settings.default_joint_count = 0;
  EXPECT_NE(
      preparePlot(w.skeleton, w.clip, spectrum, settings).message().find("default_joint_count"),
      std::string::npos);
  settings = {};
  settings.max_harmonic = 0;
  EXPECT_NE(preparePlot(w.skeleton, w.clip, spectrum, settings).message().find("max_harmonic"),
            std::string::npos);

  // A spectrum from another clip (its frame count differs).
  motion::Clip shorter = w.clip;
  shorter.frame_count = 60;
  shorter.rotations.resize(60 * shorter.joint_count);
  shorter.translations.resize(60 * shorter.joint_count);
  EXPECT_NE(preparePlot(w.skeleton, shorter, spectrum).message().find("not analysed from clip"),
            std::string::npos);
}

TEST(PlotTest, DefaultJointsAreTheLargestRotationsInSkeletonOrder) {
  const Walker w = makeWalker();
  const MotionSpectrum spectrum = analyzeWalker(w);
  PlotSettings settings;
  settings.default_joint_count = 2;
  Result<PlotData> plot = preparePlot(w.skeleton, w.clip, spectrum, settings);
  ASSERT_TRUE(plot.ok()) << plot.message();
  ASSERT_EQ(plot.value().rows.size(), 2u);
  EXPECT_EQ(plot.value().rows[0].name, "LeftUpLeg");
  EXPECT_EQ(plot.value().rows[1].name, "RightUpLeg");
  // Four by default; the static head is never among them.
  plot = preparePlot(w.skeleton, w.clip, spectrum);
  ASSERT_TRUE(plot.ok());
  ASSERT_EQ(plot.value().rows.size(), 4u);
  for (const PlotRow& row : plot.value().rows) EXPECT_NE(row.name, "Head");
}

TEST(PlotTest, SvgIsWellFormedXmlWithOneRowPerJoint) {
  const Walker w = makeWalker("walk & <run> \"1\"");
  const MotionSpectrum spectrum = analyzeWalker(w);
  PlotSettings settings;
  settings.joints = {"Hips", "LeftLeg", "RightUpLeg"};
  Result<std::string> svg = plotSvg(w.skeleton, w.clip, spectrum, settings);
  ASSERT_TRUE(svg.ok()) << svg.message();
  EXPECT_EQ(countOf(svg.value(), "<g class=\"row\">"), 3);
  EXPECT_NE(svg.value().find("walk &amp; &lt;run&gt; &quot;1&quot;"), std::string::npos);

  test::TempDir dir;
  test::writeText(dir / "plot.svg", svg.value());
  // Python's XML parser (python3 is in every test environment; Blender's test needs it too).
  const test::CommandResult parsed = test::runCommand(
      "python3 -c \"import sys, xml.etree.ElementTree as ET; root = "
      "ET.parse(sys.argv[1]).getroot(); "
      "ns = '{http://www.w3.org/2000/svg}'; "
      "print(root.tag == ns + 'svg', len(root.findall('.//' + ns + 'polyline')))\" " +
      test::quote(dir / "plot.svg"));
  if (parsed.exit_code == 127) GTEST_SKIP() << "python3 not found";
  ASSERT_EQ(parsed.exit_code, 0) << parsed.err;
  EXPECT_EQ(parsed.out, "True 18\n");  // 3 rows x 3 axes x (original, model)
}

TEST(PlotTest, PolylinesHaveOnePointPerWindowFrame) {
  const Walker w = makeWalker();
  const MotionSpectrum spectrum = analyzeWalker(w);
  const int frames = windowFrames(w.clip, spectrum).frame_count;
  Result<std::string> svg = plotSvg(w.skeleton, w.clip, spectrum);
  ASSERT_TRUE(svg.ok()) << svg.message();
  for (const char* kind : {"original", "model"}) {
    const auto lines = polylines(svg.value(), kind);
    EXPECT_EQ(lines.size(), 4u * 3u) << kind;
    for (const auto& line : lines) EXPECT_EQ(static_cast<int>(line.size()), frames) << kind;
  }
}

TEST(PlotTest, PlottedModelIsTheKeptHarmonicsAtFrameTimes) {
  const Walker w = makeWalker();
  const MotionSpectrum spectrum = analyzeWalker(w, 2);
  PlotSettings settings;
  settings.joints = {"LeftUpLeg", "LeftLeg"};
  Result<PlotData> result = preparePlot(w.skeleton, w.clip, spectrum, settings);
  ASSERT_TRUE(result.ok()) << result.message();
  const PlotData& plot = result.value();
  const double dt = w.clip.frame_time;
  ASSERT_EQ(static_cast<int>(plot.times_s.size()), windowFrames(w.clip, spectrum).frame_count);
  for (const PlotRow& row : plot.rows) {
    EXPECT_EQ(row.k, 2);
    ASSERT_EQ(row.channels.size(), 3u);
    for (const PlotChannel& channel : row.channels) {
      const HarmonicSeries& series = spectrum.series[channel.channel];
      const auto terms = series.strongest(2);
      for (size_t i = 0; i < plot.times_s.size(); ++i) {
        const int frame = plot.first_frame + static_cast<int>(i);
        const double t = frame * dt - spectrum.window.start_s;
        ASSERT_NEAR(plot.times_s[i], t, 1e-12);
        EXPECT_NEAR(channel.model_deg[i],
                    kDegrees * evaluate(series.mean, terms, spectrum.omega0, t), 1e-6);
        EXPECT_NEAR(channel.original_deg[i],
                    kDegrees * spectrum.signals.channels[channel.channel].values[frame], 1e-6);
      }
      int kept = 0;
      for (bool k : channel.kept) kept += k;
      EXPECT_LE(kept, 2);
    }
    // The original curve is the window's original frames: the rotation relative to the mean.
    const int frame = plot.first_frame;
    const glm::dvec3 vector(row.channels[0].original_deg[0], row.channels[1].original_deg[0],
                            row.channels[2].original_deg[0]);
    const glm::dquat relative = glm::inverse(spectrum.signals.mean_rotations[row.joint]) *
                                w.clip.rotation(frame, row.joint);
    EXPECT_NEAR(std::abs(glm::dot(fromRotationVector(vector / kDegrees), relative)), 1.0, 1e-9);
  }
  // The thigh swings 0.5 rad at the stride frequency: the first bar of its X channel.
  EXPECT_NEAR(plot.rows[0].channels[0].amplitude_deg[0], kDegrees * 0.5, 0.5);
  EXPECT_TRUE(plot.rows[0].channels[0].kept[0]);

  // The drawing is those values: an affine map from degrees to pixels (0.1 px rounding).
  const std::string svg = renderPlotSvg(spectrum, plot);
  const auto lines = polylines(svg, "model");
  ASSERT_EQ(lines.size(), 6u);
  const auto& line = lines[0];
  const auto& values = plot.rows[0].channels[0].model_deg;
  size_t lo = 0, hi = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    if (values[i] < values[lo]) lo = i;
    if (values[i] > values[hi]) hi = i;
  }
  const double scale = (line[hi].second - line[lo].second) / (values[hi] - values[lo]);
  EXPECT_LT(scale, 0.0) << "up is larger";
  for (size_t i = 0; i < values.size(); ++i) {
    EXPECT_NEAR(line[i].second, line[lo].second + scale * (values[i] - values[lo]), 0.15);
  }
}

}  // namespace
}  // namespace sinew::spectral
