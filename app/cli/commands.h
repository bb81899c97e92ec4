// Command-line front end: each command registers its options on the CLI11 app and runs when
// chosen. A command's run function returns the process exit code; failures print one line on
// stderr ("sinew: <file>:<line>: <reason>").
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json_fwd.hpp>

#include "sinew/motion/asset.h"

namespace sinew::app {

// Import options shared by every command that reads a motion file.
struct ImportFlags {
  std::string units;  // "", m, cm, mm, in
  std::string up;     // "", Y, Z
  double fps = 0.0;   // 0: the file's own rate
  bool keep_glitches = false;  // leave rotation glitches as they are (they are still reported)
  void addTo(CLI::App& command);
  // Options for the importer, or a message naming the bad flag.
  Result<motion::ImportOptions> options() const;
};

// The clip called `name` (the first clip when empty), or a message listing the names there are.
Result<int> selectClip(const motion::MotionAsset& asset, const std::string& name);

// The rotation glitches import found in clip `clip`: "none", or how many, in which joints, and
// whether they were repaired (the warnings list each one).
std::string glitchSummary(const motion::MotionAsset& asset, int clip);
// The same as a JSON array of {joint, first_frame, frames, size_deg, repaired}.
nlohmann::json glitchJson(const motion::MotionAsset& asset, int clip);

int fail(const std::string& message);  // prints "sinew: message" to stderr, returns 1

// For integer options: digits only, at most `max` ("4.5", "-1" and "1e9" are refused rather than
// truncated or wrapped; CLI11 alone reads "-1" into an unsigned 64-bit seed as 2^64 - 1). The
// message names the range: "expected a whole number from 0 to 10000, got '1e9'".
CLI::Validator wholeNumber(std::uint64_t max = std::numeric_limits<std::uint64_t>::max());

void addInfoCommand(CLI::App& app, int& exit_code);
void addConvertCommand(CLI::App& app, int& exit_code);
void addAnalyzeCommand(CLI::App& app, int& exit_code);
void addStyleCommand(CLI::App& app, int& exit_code);
void addSimulateCommand(CLI::App& app, int& exit_code);
void addEvolveCommand(CLI::App& app, int& exit_code);
void addEditCommand(CLI::App& app, int& exit_code);
void addRenderCommand(CLI::App& app, int& exit_code);
void addCreatureCommand(CLI::App& app, int& exit_code);

}  // namespace sinew::app
