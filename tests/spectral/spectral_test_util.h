// Shared by the spectral tests: a file analysed into a TargetMotion with every harmonic up to 10.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/spectral/target_motion.h"
#include "support/test_support.h"

namespace sinew::spectral::test_util {

struct Analysed {
  motion::MotionAsset asset;
  TargetMotion target;
};

// Every harmonic up to 10 kept, so styles and blends see the whole spectrum.
inline Analysed analyseFile(const std::filesystem::path& path) {
  Analysed out;
  Result<motion::MotionAsset> asset = motion::importMotion(path);
  EXPECT_TRUE(asset.ok()) << asset.message();
  out.asset = std::move(asset).value();
  AnalysisSettings settings;
  settings.harmonics = 10;
  Result<MotionSpectrum> spectrum = analyze(out.asset.skeleton, out.asset.clips[0], settings);
  EXPECT_TRUE(spectrum.ok()) << spectrum.message();
  out.target = targetFromSpectrum(spectrum.value(), {}, path.stem().string());
  return out;
}

// A Bandai take in ../shared/data: "walk_tired" -> bandai_dataset-1_walk_tired_001.bvh.
inline std::filesystem::path bandai(const std::string& what) {
  return test::sharedData() / "bvh" / ("bandai_dataset-1_" + what + "_001.bvh");
}

}  // namespace sinew::spectral::test_util
