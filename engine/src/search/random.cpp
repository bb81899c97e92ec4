#include "sinew/search/random.h"

#include <cmath>
#include <limits>
#include <locale>
#include <numbers>
#include <sstream>

#include "state_json.h"

namespace sinew::search {

double Random::uniform() {
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

int Random::below(int n) {
  const std::uint64_t range = static_cast<std::uint64_t>(n);
  // The largest multiple of range that fits: draws at or above it would favour small values.
  const std::uint64_t limit =
      std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % range;
  std::uint64_t draw = engine_();
  while (draw >= limit) draw = engine_();
  return static_cast<int>(draw % range);
}

double Random::normal() {
  if (has_cached_) {
    has_cached_ = false;
    return cached_;
  }
  const double u1 = 1.0 - uniform();  // (0, 1]: the logarithm stays finite
  const double u2 = uniform();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  cached_ = radius * std::sin(angle);
  has_cached_ = true;
  return radius * std::cos(angle);
}

nlohmann::json Random::saveState() const {
  std::ostringstream text;
  text.imbue(std::locale::classic());
  text << engine_;
  // cached_normal only when there is one: no null where a number belongs.
  nlohmann::json state = {{"engine", text.str()}};
  if (has_cached_) state["cached_normal"] = cached_;
  return state;
}

Result<Random> Random::load(const nlohmann::json& state, const std::string& where) {
  Random random;
  std::string text;
  if (Status s = state_json::readString(state, "engine", where, text); !s.ok()) return s;
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  in >> random.engine_;
  if (in.fail() || !(in >> std::ws).eof())
    return Status::error(where +
                         ": engine: expected the text of a std::mt19937_64 (312 numbers "
                         "and a position)");
  // Absent (or null, as checkpoints before this version wrote it): no cached half.
  if (state.contains("cached_normal") && !state.at("cached_normal").is_null()) {
    if (Status s = state_json::readNumber(state, "cached_normal", where, random.cached_); !s.ok())
      return Status::error(where + ": cached_normal: expected a finite number or null");
    random.has_cached_ = true;
  }
  return random;
}

}  // namespace sinew::search
