// Malformed BVH files are refused with "<file>:<line>: <what was expected>", never a crash or a
// hang. Every corruption is made from real files: the bundled walk (always) and, when
// ../shared/data is present, real captures with LF, CRLF and mixed line endings.
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sinew/motion/bvh.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

using Lines = std::vector<std::string>;  // without their line breaks

struct Source {
  std::string name;
  Lines lines;
  std::string newline;  // what the motion section uses
};

Source load(const std::filesystem::path& path) {
  const std::string text = test::readText(path);
  Source source{path.filename().string(), {}, "\n"};
  std::string line;
  for (size_t n = 0; n < text.size(); ++n) {
    if (text[n] == '\r' || text[n] == '\n') {
      source.lines.push_back(line);
      line.clear();
      if (text[n] == '\r' && n + 1 < text.size() && text[n + 1] == '\n') ++n;
    } else {
      line += text[n];
    }
  }
  if (!line.empty()) source.lines.push_back(line);
  return source;
}

std::string join(const Lines& lines, const std::string& newline) {
  std::string text;
  for (const std::string& line : lines) text += line + newline;
  return text;
}

// Index of the first line whose trimmed text starts with `prefix`, from `from`.
int lineStarting(const Lines& lines, const std::string& prefix, int from = 0) {
  for (int n = from; n < static_cast<int>(lines.size()); ++n) {
    const size_t start = lines[n].find_first_not_of(" \t");
    if (start != std::string::npos && lines[n].compare(start, prefix.size(), prefix) == 0) return n;
  }
  ADD_FAILURE() << "no line starts with " << prefix;
  return 0;
}

int firstFrameLine(const Lines& lines) { return lineStarting(lines, "Frame Time") + 1; }

// Replaces the n-th whitespace-separated word of a line.
void replaceWord(std::string& line, int index, const std::string& word) {
  size_t at = 0;
  for (int w = 0;; ++w) {
    at = line.find_first_not_of(" \t", at);
    const size_t end = line.find_first_of(" \t", at);
    if (w == index) {
      line.replace(at, end == std::string::npos ? std::string::npos : end - at, word);
      return;
    }
    at = end;
  }
}

struct Corruption {
  const char* name;
  const char* expected;                  // part of the message
  std::function<int(Lines&)> apply;      // returns the 0-based line the message must name
};

const std::vector<Corruption>& corruptions() {
  static const std::vector<Corruption> all = {
      {"truncated motion", "truncated MOTION: file ends after 10 of",
       [](Lines& l) {
         l.resize(firstFrameLine(l) + 10);
         return static_cast<int>(l.size()) - 1;
       }},
      {"cut inside a frame line", "numbers, found",
       [](Lines& l) {
         const int n = firstFrameLine(l) + 3;
         l[n].resize(l[n].size() / 2);
         l.resize(n + 1);
         return n;
       }},
      {"too few numbers", "frame 8: expected",
       [](Lines& l) {
         const int n = firstFrameLine(l) + 7;
         l[n].erase(l[n].find_last_not_of(" \t") + 1);
         l[n].erase(l[n].find_last_of(" \t"));
         return n;
       }},
      {"too many numbers", "frame 5: expected",
       [](Lines& l) {
         const int n = firstFrameLine(l) + 4;
         l[n] += " 0.5";
         return n;
       }},
      {"a word among the numbers", "'abc' is not a number",
       [](Lines& l) {
         const int n = firstFrameLine(l) + 2;
         replaceWord(l[n], 4, "abc");
         return n;
       }},
      {"nan among the numbers", "'nan' is not a number",
       [](Lines& l) {
         const int n = firstFrameLine(l) + 1;
         replaceWord(l[n], 0, "nan");
         return n;
       }},
      {"missing closing brace", "unbalanced braces",
       [](Lines& l) {
         const int motion = lineStarting(l, "MOTION");
         l.erase(l.begin() + motion - 1);  // the ROOT's closing brace
         return motion - 1;                // MOTION moved up one line
       }},
      {"extra closing brace", "'}' without a matching '{'",
       [](Lines& l) {
         const int motion = lineStarting(l, "MOTION");
         l.insert(l.begin() + motion, "}");
         return motion;
       }},
      {"zero frames", "zero frames",
       [](Lines& l) {
         const int n = lineStarting(l, "Frames:");
         l[n] = "Frames: 0";
         return n;
       }},
      {"negative frame time", "frame time must be from 0.0001 to 60 seconds",
       [](Lines& l) {
         const int n = lineStarting(l, "Frame Time");
         l[n] = "Frame Time: -0.0333333";
         return n;
       }},
      {"zero frame time", "frame time must be from 0.0001 to 60 seconds",
       [](Lines& l) {
         const int n = lineStarting(l, "Frame Time");
         l[n] = "Frame Time:\t0";
         return n;
       }},
      {"duplicate joint name", "duplicate joint name",
       [](Lines& l) {
         const int first = lineStarting(l, "JOINT");
         const int second = lineStarting(l, "JOINT", first + 1);
         std::string name = l[first].substr(l[first].find("JOINT") + 6);
         l[second] = l[second].substr(0, l[second].find("JOINT")) + "JOINT " + name;
         return second;
       }},
      {"CHANNELS count does not match", "does not match the 2 channel names",
       [](Lines& l) {
         const int joint = lineStarting(l, "JOINT");
         const int n = lineStarting(l, "CHANNELS", joint);
         l[n] = "CHANNELS 3 Zrotation Xrotation";
         return n;
       }},
      {"more frames declared than given", "truncated MOTION: file ends after",
       [](Lines& l) {
         l[lineStarting(l, "Frames:")] = "Frames: 99999";
         while (!l.empty() && l.back().find_first_not_of(" \t") == std::string::npos) l.pop_back();
         return static_cast<int>(l.size()) - 1;
       }},
      {"fewer frames declared than given", "more frame lines than 'Frames: 3'",
       [](Lines& l) {
         l[lineStarting(l, "Frames:")] = "Frames: 3";
         return firstFrameLine(l) + 3;
       }},
      {"no HIERARCHY keyword", "expected HIERARCHY",
       [](Lines& l) {
         const int n = lineStarting(l, "HIERARCHY");
         l[n] = "HIERARCHIE";
         return n;
       }},
      {"no MOTION section", "no MOTION section",
       [](Lines& l) {
         l.resize(lineStarting(l, "MOTION"));
         return static_cast<int>(l.size()) - 1;
       }},
      {"misspelt channel", "expected a channel name",
       [](Lines& l) {
         const int n = lineStarting(l, "CHANNELS", lineStarting(l, "JOINT"));
         l[n] = "CHANNELS 3 Zrotation Xrotaton Yrotation";
         return n;
       }},
      {"OFFSET with two numbers", "expected 3 numbers for OFFSET",
       [](Lines& l) {
         const int n = lineStarting(l, "OFFSET", lineStarting(l, "JOINT"));
         l[n] = "OFFSET 1.0 2.0";
         return n;
       }},
      {"fractional frame count", "expected 'Frames: N' with a whole number",
       [](Lines& l) {
         const int n = lineStarting(l, "Frames:");
         l[n] = "Frames: 2.5";
         return n;
       }},
      {"channel named twice", "appears twice",
       [](Lines& l) {
         const int n = lineStarting(l, "CHANNELS", lineStarting(l, "JOINT"));
         l[n] = "CHANNELS 3 Zrotation Xrotation Zrotation";
         return n;
       }},
      {"End Site without OFFSET", "expected End Site { OFFSET x y z }",
       [](Lines& l) {
         const int n = lineStarting(l, "End Site");
         l.erase(l.begin() + n + 2);  // End Site, {, [OFFSET], }
         return n;
       }},
      {"JOINT outside ROOT", "JOINT outside any ROOT",
       [](Lines& l) {
         const int n = lineStarting(l, "ROOT");
         l[n] = "JOINT Hips";
         return n;
       }},
  };
  return all;
}

std::vector<std::filesystem::path> sources() {
  std::vector<std::filesystem::path> paths = {test::sourceDir() / "assets" / "biped_walk.bvh"};
  if (test::haveSharedData()) {
    for (const char* file : {"bandai_dataset-1_walk_normal_001.bvh", "cmu_131_01.bvh",
                             "mann-dog_D1_009_KAN01_001.bvh"}) {
      paths.push_back(test::sharedData() / "bvh" / file);
    }
  }
  return paths;
}

TEST(BvhCorruptTest, EveryCorruptionIsRefusedWithFileLineAndExpectation) {
  ASSERT_GE(corruptions().size(), 15u);
  if (!test::haveSharedData()) {
    std::printf("  note: %s not found; corrupting the bundled walk only\n",
                test::sharedData().string().c_str());
  }
  for (const auto& path : sources()) {
    const Source source = load(path);
    ASSERT_TRUE(readBvh(join(source.lines, "\n"), source.name).ok()) << source.name;
    for (const Corruption& corruption : corruptions()) {
      SCOPED_TRACE(source.name + ": " + corruption.name);
      Lines lines = source.lines;
      const int line = corruption.apply(lines) + 1;
      // CRLF and LF both: the line numbers must not change.
      for (const char* newline : {"\n", "\r\n"}) {
        Result<MotionAsset> result = readBvh(join(lines, newline), source.name);
        ASSERT_FALSE(result.ok());
        const std::string prefix = source.name + ":" + std::to_string(line) + ": ";
        EXPECT_EQ(result.message().rfind(prefix, 0), 0u)
            << "message: " << result.message() << "\nexpected it to start with " << prefix;
        EXPECT_NE(result.message().find(corruption.expected), std::string::npos)
            << "message: " << result.message();
      }
    }
  }
}

TEST(BvhCorruptTest, EmptyAndBinaryFilesAreRefused) {
  EXPECT_EQ(readBvh("", "empty.bvh").message(), "empty.bvh:1: empty file; expected HIERARCHY");
  constexpr char kGlbStart[] = "glTF\x02\0\0\0\xff\xfe{\"asset\"";
  const std::string binary(kGlbStart, sizeof(kGlbStart) - 1);
  Result<MotionAsset> result = readBvh(binary, "model.bvh");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.message().find("expected HIERARCHY"), std::string::npos) << result.message();
}

TEST(BvhCorruptTest, DeepNestingDoesNotOverflowTheStack) {
  std::string text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 3 Xrotation Yrotation Zrotation\n";
  constexpr int kDepth = 200000;
  for (int n = 0; n < kDepth; ++n) text += "JOINT j" + std::to_string(n) + "\n{\nOFFSET 0 1 0\n";
  Result<MotionAsset> result = readBvh(text, "deep.bvh");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.message().find("unbalanced braces: file ends inside joint 'j199999'"),
            std::string::npos)
      << result.message();
}

TEST(BvhCorruptTest, ImportNamesThePath) {
  test::TempDir dir;
  const auto path = dir / "broken.bvh";
  test::writeText(path, "HIERARCHY\nROOT a\n{\nOFFSET 0 0\n");
  Result<MotionAsset> result = importMotion(path);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.message().rfind(path.string() + ":4: expected 3 numbers for OFFSET", 0), 0u)
      << result.message();
  Result<MotionAsset> missing = importMotion(dir / "missing.bvh");
  EXPECT_NE(missing.message().find("missing.bvh: no such file"), std::string::npos);
  Result<MotionAsset> unknown = importMotion(dir / "clip.fbx");
  EXPECT_NE(unknown.message().find("unknown file type '.fbx'"), std::string::npos);
}

}  // namespace
}  // namespace sinew::motion
