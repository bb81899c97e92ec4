// BVH reader. Two passes over the text: the HIERARCHY as tokens (with line numbers), then the
// MOTION section line by line. No recursion (deeply nested input cannot overflow the stack) and no
// allocation sized by a declared count (a lying "Frames:" cannot exhaust memory).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <unordered_set>

#include "sinew/core/text.h"
#include "sinew/motion/bvh.h"
#include "sinew/motion/anatomy.h"
#include "sinew/motion/limits.h"

namespace sinew::motion {
namespace {

struct Line {
  std::string_view text;
  int number = 0;  // 1-based
};

// Splits on LF, CRLF and lone CR, so mixed line endings read the same.
std::vector<Line> splitLines(std::string_view text) {
  std::vector<Line> lines;
  int number = 1;
  size_t start = 0;
  for (size_t n = 0; n < text.size(); ++n) {
    if (text[n] == '\n' || text[n] == '\r') {
      lines.push_back({text.substr(start, n - start), number++});
      if (text[n] == '\r' && n + 1 < text.size() && text[n + 1] == '\n') ++n;
      start = n + 1;
    }
  }
  if (start < text.size()) lines.push_back({text.substr(start), number});
  return lines;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

// Whitespace-separated words of one line; braces are words of their own even when attached.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t n = 0;
  while (n < line.size()) {
    while (n < line.size() && isSpace(line[n])) ++n;
    if (n >= line.size()) break;
    if (line[n] == '{' || line[n] == '}') {
      out.push_back(line.substr(n, 1));
      ++n;
      continue;
    }
    const size_t start = n;
    while (n < line.size() && !isSpace(line[n]) && line[n] != '{' && line[n] != '}') ++n;
    out.push_back(line.substr(start, n - start));
  }
  return out;
}

// A finite double, written the way BVH files write them: "-1.5", ".0083333", "1.87e-05", "+2".
bool parseNumber(std::string_view word, double& value) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  if (word.empty()) return false;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  return error == std::errc() && end == word.data() + word.size() && std::isfinite(value);
}

// Offsets and channel values (file units or degrees) beyond this are refused: 1 km in mm,
// 10 km in cm, and far past any unwrapped angle. It keeps every value within float range.
constexpr double kMaxValue = 1e6;

std::string quoted(std::string_view word) {
  constexpr size_t kMaxShown = 40;
  std::string shown(word.substr(0, kMaxShown));
  for (char& c : shown) {
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  }
  return "'" + shown + (word.size() > kMaxShown ? "...'" : "'");
}

std::optional<ChannelType> channelFromName(std::string_view word) {
  static constexpr std::string_view kNames[] = {"Xposition", "Yposition", "Zposition",
                                                "Xrotation", "Yrotation", "Zrotation"};
  for (int n = 0; n < 6; ++n) {
    if (word.size() == kNames[n].size() &&
        std::equal(word.begin(), word.end(), kNames[n].begin(),
                   [](char a, char b) { return std::tolower(a) == std::tolower(b); })) {
      return static_cast<ChannelType>(n);
    }
  }
  return std::nullopt;
}

class BvhParser {
 public:
  BvhParser(std::string_view text, std::string_view source) : source_(source) {
    lines_ = splitLines(text);
  }

  Result<MotionAsset> run(const ImportOptions& options) {
    if (Status status = parseHierarchy(); !status.ok()) return status;
    if (Status status = parseMotion(); !status.ok()) return status;
    return build(options);
  }

 private:
  struct Token {
    std::string_view word;
    int line_index = 0;  // into lines_
    int word_index = 0;  // position within its line
  };

  struct PendingJoint {
    int joint = -1;
    int open_line = 0;
    bool has_offset = false;
    bool has_channels = false;
  };

  Status fail(int line_number, const std::string& what) const {
    return Status::error(std::string(source_) + ":" + std::to_string(line_number) + ": " + what);
  }

  int lineNumber(const Token& token) const { return lines_[token.line_index].number; }

  Status parseHierarchy() {
    // Tokenise up to and including the MOTION keyword.
    for (int l = 0; l < static_cast<int>(lines_.size()) && motion_line_ < 0; ++l) {
      const std::vector<std::string_view> line_words = words(lines_[l].text);
      for (int w = 0; w < static_cast<int>(line_words.size()); ++w) {
        tokens_.push_back({line_words[w], l, w});
        if (line_words[w] == "MOTION") {
          motion_line_ = l;
          break;
        }
      }
    }
    size_t at = 0;
    const auto next = [&]() -> const Token* { return at < tokens_.size() ? &tokens_[at++] : nullptr; };
    const auto lastLine = [&]() { return lines_.empty() ? 1 : lines_.back().number; };

    const Token* first = next();
    if (first == nullptr) return fail(1, "empty file; expected HIERARCHY");
    if (first->word != "HIERARCHY") {
      return fail(lineNumber(*first), "expected HIERARCHY, found " + quoted(first->word));
    }
    std::vector<PendingJoint> stack;
    while (const Token* token = next()) {
      const int line = lineNumber(*token);
      const std::string_view word = token->word;
      if (word == "MOTION") {
        if (!stack.empty()) {
          return fail(line, "unbalanced braces: MOTION found while joint '" +
                                skeleton_.names[stack.back().joint] + "' (opened at line " +
                                std::to_string(stack.back().open_line) + ") is not closed by '}'");
        }
        if (skeleton_.jointCount() == 0) return fail(line, "expected ROOT before MOTION");
        return {};
      }
      if (word == "ROOT" || word == "JOINT") {
        if (word == "ROOT" && !stack.empty()) {
          return fail(line, "ROOT inside joint '" + skeleton_.names[stack.back().joint] +
                                "'; expected JOINT, End Site or '}'");
        }
        if (word == "JOINT" && stack.empty()) {
          return fail(line, "JOINT outside any ROOT; expected ROOT or MOTION");
        }
        // The name is the rest of the line (before any '{'): names may contain ':' or spaces.
        std::string name;
        while (at < tokens_.size() && tokens_[at].line_index == token->line_index &&
               tokens_[at].word != "{") {
          if (!name.empty()) name += ' ';
          name += tokens_[at++].word;
        }
        if (name.empty()) return fail(line, "expected a joint name after " + std::string(word));
        if (const int c = firstControlCharacter(name); c >= 0) {
          return fail(line, "joint name " + quoted(std::string_view(name)) +
                                " holds control character " + std::to_string(c) +
                                "; names must be printable text");
        }
        if (!names_.insert(name).second) {
          return fail(line, "duplicate joint name '" + name + "'; joint names must be unique");
        }
        const Token* open = next();
        if (open == nullptr || open->word != "{") {
          return fail(open ? lineNumber(*open) : lastLine(),
                      "expected '{' after " + std::string(word) + " " + name + ", found " +
                          (open ? quoted(open->word) : std::string("end of file")));
        }
        const int parent = stack.empty() ? kNoParent : stack.back().joint;
        const int joint = skeleton_.addJoint(name, parent, glm::dvec3(0.0));
        stack.push_back({joint, line, false, false});
        continue;
      }
      if (stack.empty()) {
        if (word == "}") return fail(line, "unbalanced braces: '}' without a matching '{'");
        return fail(line, "expected ROOT or MOTION, found " + quoted(word));
      }
      PendingJoint& current = stack.back();
      const std::string joint_name = skeleton_.names[current.joint];
      if (word == "OFFSET") {
        if (current.has_offset) return fail(line, "second OFFSET in joint '" + joint_name + "'");
        glm::dvec3 offset;
        if (Status status = readVector(at, *token, "OFFSET of joint '" + joint_name + "'", offset);
            !status.ok()) {
          return status;
        }
        skeleton_.offsets[current.joint] = offset;
        current.has_offset = true;
      } else if (word == "CHANNELS") {
        if (current.has_channels) return fail(line, "second CHANNELS in joint '" + joint_name + "'");
        if (Status status = readChannels(at, *token, current.joint); !status.ok()) return status;
        current.has_channels = true;
      } else if (word == "End") {
        const Token* site = next();
        if (site == nullptr || site->word != "Site") {
          return fail(line, "expected 'End Site', found 'End' followed by " +
                                (site ? quoted(site->word) : std::string("end of file")));
        }
        if (skeleton_.end_sites[current.joint]) {
          return fail(line, "second End Site in joint '" + joint_name + "'");
        }
        const Token* open = next();
        const Token* keyword = open ? next() : nullptr;
        if (open == nullptr || open->word != "{" || keyword == nullptr || keyword->word != "OFFSET") {
          return fail(line, "expected End Site { OFFSET x y z } in joint '" + joint_name + "'");
        }
        glm::dvec3 offset;
        if (Status status = readVector(at, *keyword, "End Site OFFSET of joint '" + joint_name + "'",
                                       offset);
            !status.ok()) {
          return status;
        }
        const Token* close = next();
        if (close == nullptr || close->word != "}") {
          return fail(close ? lineNumber(*close) : lastLine(),
                      "unbalanced braces: expected '}' to close the End Site of joint '" +
                          joint_name + "', found " +
                          (close ? quoted(close->word) : std::string("end of file")));
        }
        skeleton_.end_sites[current.joint] = offset;
      } else if (word == "}") {
        if (!current.has_offset) {
          return fail(line, "joint '" + joint_name + "' (line " + std::to_string(current.open_line) +
                                ") has no OFFSET");
        }
        stack.pop_back();
      } else {
        return fail(line, "expected OFFSET, CHANNELS, JOINT, End Site or '}' in joint '" +
                              joint_name + "', found " + quoted(word));
      }
    }
    if (!stack.empty()) {
      return fail(lastLine(), "unbalanced braces: file ends inside joint '" +
                                  skeleton_.names[stack.back().joint] + "' (opened at line " +
                                  std::to_string(stack.back().open_line) +
                                  "); expected '}' and then MOTION");
    }
    return fail(lastLine(), "no MOTION section; expected MOTION after the hierarchy");
  }

  // Three numbers on the keyword's line.
  Status readVector(size_t& at, const Token& keyword, const std::string& what, glm::dvec3& out) {
    for (int n = 0; n < 3; ++n) {
      if (at >= tokens_.size() || tokens_[at].line_index != keyword.line_index) {
        return fail(lineNumber(keyword), "expected 3 numbers for " + what + ", found " +
                                             std::to_string(n));
      }
      if (!parseNumber(tokens_[at].word, out[n])) {
        return fail(lineNumber(keyword), "expected a number for " + what + ", found " +
                                             quoted(tokens_[at].word));
      }
      if (std::abs(out[n]) > kMaxValue) {
        return fail(lineNumber(keyword), what + ": " + quoted(tokens_[at].word) +
                                             " is beyond the limit of 1e6 (file units)");
      }
      ++at;
    }
    return {};
  }

  Status readChannels(size_t& at, const Token& keyword, int joint) {
    const int line = lineNumber(keyword);
    const std::string joint_name = skeleton_.names[joint];
    double declared = 0.0;
    if (at >= tokens_.size() || tokens_[at].line_index != keyword.line_index ||
        !parseNumber(tokens_[at].word, declared) || declared != std::floor(declared) ||
        declared < 0 || declared > 6) {
      return fail(line, "expected a channel count from 0 to 6 after CHANNELS in joint '" +
                            joint_name + "'");
    }
    ++at;
    ChannelLayout layout;
    bool seen[6] = {false, false, false, false, false, false};
    while (at < tokens_.size() && tokens_[at].line_index == keyword.line_index) {
      const std::optional<ChannelType> type = channelFromName(tokens_[at].word);
      if (!type) {
        return fail(line, "expected a channel name (Xposition ... Zrotation) in joint '" +
                              joint_name + "', found " + quoted(tokens_[at].word));
      }
      if (seen[static_cast<int>(*type)]) {
        return fail(line, std::string("channel ") + channelName(*type) + " appears twice in joint '" +
                              joint_name + "'");
      }
      seen[static_cast<int>(*type)] = true;
      layout.types.push_back(*type);
      ++at;
    }
    if (static_cast<int>(layout.types.size()) != static_cast<int>(declared)) {
      return fail(line, "CHANNELS count " + std::to_string(static_cast<int>(declared)) +
                            " does not match the " + std::to_string(layout.types.size()) +
                            " channel names that follow, in joint '" + joint_name + "'");
    }
    if (layout.rotationCount() != 0 && layout.rotationCount() != 3) {
      return fail(line, "joint '" + joint_name + "' has " +
                            std::to_string(layout.rotationCount()) +
                            " rotation channels; expected 0 or 3");
    }
    skeleton_.channels[joint] = std::move(layout);
    return {};
  }

  // After MOTION: "Frames: N", "Frame Time: t", then N lines of numbers.
  Status parseMotion() {
    channel_count_ = skeleton_.channelCount();
    const int motion_number = lines_[motion_line_].number;
    if (channel_count_ == 0) return fail(motion_number, "the hierarchy declares no channels");
    // Anything after MOTION on its own line is not expected.
    int l = motion_line_ + 1;
    const auto skipBlank = [&]() {
      while (l < static_cast<int>(lines_.size()) && words(lines_[l].text).empty()) ++l;
    };
    skipBlank();
    if (l >= static_cast<int>(lines_.size())) {
      return fail(motion_number, "truncated MOTION: expected 'Frames: N' after MOTION");
    }
    std::vector<std::string_view> w = words(lines_[l].text);
    double frames = 0.0;
    if (w.size() != 2 || w[0] != "Frames:" || !parseNumber(w[1], frames) ||
        frames != std::floor(frames)) {
      return fail(lines_[l].number, "expected 'Frames: N' with a whole number N");
    }
    if (frames < 1) {
      return fail(lines_[l].number, "zero frames: 'Frames:' must be at least 1, found " +
                                        quoted(w[1]));
    }
    if (frames > 1e8) return fail(lines_[l].number, "'Frames:' " + quoted(w[1]) + " is too large");
    frame_count_ = static_cast<int>(frames);
    const int frames_line = lines_[l].number;
    ++l;
    skipBlank();
    if (l >= static_cast<int>(lines_.size())) {
      return fail(frames_line, "truncated MOTION: expected 'Frame Time: t' after 'Frames:'");
    }
    w = words(lines_[l].text);
    if (w.size() != 3 || w[0] != "Frame" || w[1] != "Time:" || !parseNumber(w[2], frame_time_)) {
      return fail(lines_[l].number, "expected 'Frame Time: t' with t in seconds");
    }
    if (!(frame_time_ >= kMinFrameTime_s && frame_time_ <= kMaxFrameTime_s)) {
      return fail(lines_[l].number,
                  "frame time must be from 0.0001 to 60 seconds, found " + quoted(w[2]));
    }
    ++l;
    values_.clear();
    int frame = 0;
    for (; l < static_cast<int>(lines_.size()); ++l) {
      std::string_view text = lines_[l].text;
      size_t count = 0;
      size_t n = 0;
      bool any = false;
      while (true) {
        while (n < text.size() && isSpace(text[n])) ++n;
        if (n >= text.size()) break;
        const size_t start = n;
        while (n < text.size() && !isSpace(text[n])) ++n;
        const std::string_view word = text.substr(start, n - start);
        if (!any && frame == frame_count_) {
          return fail(lines_[l].number, "more frame lines than 'Frames: " +
                                            std::to_string(frame_count_) + "' declares (line " +
                                            std::to_string(frames_line) + ")");
        }
        any = true;
        double value = 0.0;
        if (!parseNumber(word, value)) {
          return fail(lines_[l].number, "frame " + std::to_string(frame + 1) + ": " +
                                            quoted(word) + " is not a number (value " +
                                            std::to_string(count + 1) + " of " +
                                            std::to_string(channel_count_) + ")");
        }
        if (std::abs(value) > kMaxValue) {
          return fail(lines_[l].number, "frame " + std::to_string(frame + 1) + ": " + quoted(word) +
                                            " (value " + std::to_string(count + 1) +
                                            ") is beyond the limit of 1e6 (file units or degrees)");
        }
        if (static_cast<int>(count) < channel_count_) values_.push_back(value);
        ++count;
      }
      if (!any) continue;  // blank line
      if (static_cast<int>(count) != channel_count_) {
        return fail(lines_[l].number, "frame " + std::to_string(frame + 1) + ": expected " +
                                          std::to_string(channel_count_) + " numbers, found " +
                                          std::to_string(count));
      }
      ++frame;
    }
    if (frame < frame_count_) {
      return fail(lines_.empty() ? 1 : lines_.back().number,
                  "truncated MOTION: file ends after " + std::to_string(frame) + " of " +
                      std::to_string(frame_count_) + " frames ('Frames:' at line " +
                      std::to_string(frames_line) + ")");
    }
    return {};
  }

  // Poses from channel values, frame detection, conversion to metres and Y-up.
  Result<MotionAsset> build(const ImportOptions& options) {
    const int joints = skeleton_.jointCount();
    Clip clip;
    clip.frame_time = frame_time_;
    clip.frame_count = frame_count_;
    clip.joint_count = joints;
    clip.rotations.resize(static_cast<size_t>(frame_count_) * joints);
    clip.translations.resize(static_cast<size_t>(frame_count_) * joints);
    clip.euler_start.assign(joints, glm::dvec3(0.0));
    constexpr double kRadians = 3.14159265358979323846 / 180.0;
    for (int f = 0; f < frame_count_; ++f) {
      const double* value = values_.data() + static_cast<size_t>(f) * channel_count_;
      for (int j = 0; j < joints; ++j) {
        glm::dvec3 translation = skeleton_.offsets[j];
        glm::dvec3 angles(0.0);
        int rotation = 0;
        for (ChannelType type : skeleton_.channels[j].types) {
          const double v = *value++;
          if (isRotation(type)) {
            angles[rotation++] = v * kRadians;
            if (std::abs(v) > 180.0) clip.euler_range = EulerRange::kContinuous;
          } else {
            translation[channelAxis(type)] = v;  // position channels replace the offset
          }
        }
        const size_t n = static_cast<size_t>(f) * joints + j;
        clip.translations[n] = translation;
        clip.rotations[n] = eulerToQuat(skeleton_.channels[j].eulerOrder(), angles);
        if (f == 0) clip.euler_start[j] = angles;
      }
    }

    // Units and up axis by anatomy (anatomy.h): the pelvis and its subtree posed by the clip, so
    // a root rotation that stands a Z-up rest pose upright counts, and joints above the pelvis
    // (Bandai's joint_Root at the world origin) do not.
    MotionAsset asset;
    asset.detection = detectFrame(skeleton_, clip);
    if (options.unit) {
      asset.detection.frame.unit = *options.unit;
      asset.detection.height_m = asset.detection.height_in_file_units * metresPerUnit(*options.unit);
      asset.detection.reason = "unit set by the user; " + asset.detection.reason;
    }
    if (options.up) {
      asset.detection.frame.up = *options.up;
      asset.detection.reason = "up axis set by the user; " + asset.detection.reason;
    }
    const SourceFrame& frame = asset.detection.frame;
    skeleton_.source = frame;
    for (int j = 0; j < joints; ++j) {
      skeleton_.offsets[j] = frame.pointToEngine(skeleton_.offsets[j]);
      if (skeleton_.end_sites[j]) skeleton_.end_sites[j] = frame.pointToEngine(*skeleton_.end_sites[j]);
    }
    for (size_t n = 0; n < clip.rotations.size(); ++n) {
      clip.translations[n] = frame.pointToEngine(clip.translations[n]);
      clip.rotations[n] = frame.rotationToEngine(clip.rotations[n]);
    }
    std::string stem(source_);
    if (const size_t slash = stem.find_last_of('/'); slash != std::string::npos) stem.erase(0, slash + 1);
    if (const size_t dot = stem.rfind('.'); dot != std::string::npos) stem.erase(dot);
    clip.name = toUtf8(stem);  // a path is bytes; a name is text
    asset.skeleton = std::move(skeleton_);
    asset.clips.push_back(std::move(clip));
    return asset;
  }

  std::string_view source_;
  std::vector<Line> lines_;
  std::vector<Token> tokens_;
  int motion_line_ = -1;
  Skeleton skeleton_;
  std::unordered_set<std::string> names_;
  int channel_count_ = 0;
  int frame_count_ = 0;
  double frame_time_ = 0.0;
  std::vector<double> values_;  // (frames x channels) as written in the file
};

}  // namespace

Result<MotionAsset> readBvh(std::string_view text, std::string_view source_name,
                            const ImportOptions& options) {
  const std::string utf8 = textAsUtf8(text);  // names are UTF-8 whatever the file's encoding
  BvhParser parser(utf8, source_name);
  return parser.run(options);
}

}  // namespace sinew::motion
