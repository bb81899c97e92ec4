#include "sinew/search/problem.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "sinew/core/assert.h"
#include "sinew/physics/tracking.h"
#include "sinew/search/random.h"
#include "sinew/spectral/style.h"

namespace sinew::search {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kAmplitudeFloor = 1e-4;  // radians: below it a geometric range collapses
const char* const kAxes = "xyz";
constexpr double kSwingLiftRange = 0.05;  // swing_lift searched in [0, this] (per rig size)
constexpr int kSwingLiftGain = 7;         // physics::balanceGain's index of `swing_lift`
constexpr int kHeadingGain = 8;           // and of `heading`
constexpr int kStanceYawGain = 12;        // and of `stance_yaw`
constexpr int kStanceYieldGain = 13;      // and of `stance_yield`
// The stance yield's second start (startPoints): legs that give by half on landing, where the
// Bandai tired run stood (docs/physics.md "The stance yield").
constexpr double kStanceYieldAlternative = 0.5;
constexpr double kHeadingPrior = 1.0;

// The search range of balance gain i.
std::pair<double, double> gainRange(int i, double gain_range) {
  if (i == kSwingLiftGain) return {0.0, kSwingLiftRange};
  if (physics::balanceGainIsShare(i)) return {0.0, physics::balanceGainLimit(i, gain_range)};
  return {-gain_range, gain_range};
}

}  // namespace

Status GenomeSettings::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(offset_range_rad)) return Status::error("offset_range_rad must be > 0");
  if (!(std::isfinite(amplitude_factor) && amplitude_factor > 1.0))
    return Status::error("amplitude_factor must be > 1");
  if (!positive(phase_range_rad)) return Status::error("phase_range_rad must be > 0");
  if (!(std::isfinite(omega_range) && omega_range >= 0.0 && omega_range <= 0.9))
    return Status::error("omega_range must be in [0, 0.9]");
  if (!positive(gain_range)) return Status::error("gain_range must be > 0");
  return Status();
}

Result<GenomeLayout> GenomeLayout::create(const physics::BodyPlan& plan,
                                          const motion::Skeleton& skeleton,
                                          const spectral::TargetMotion& seed,
                                          const GenomeSettings& settings) {
  if (Status s = settings.validate(); !s.ok()) return Status::error("genome: " + s.message());
  if (Status s = seed.validate(skeleton); !s.ok()) return Status::error("seed motion: " + s.message());
  // Joints that move a body: in some actuated link's chain, or on the way to the base.
  std::vector<char> moves(static_cast<size_t>(skeleton.jointCount()), 0);
  for (const physics::Link& link : plan.links)
    if (link.type == physics::JointType::kBall || link.type == physics::JointType::kHinge)
      for (int j : link.chain) moves[static_cast<size_t>(j)] = 1;
  for (int j : plan.base_chain) moves[static_cast<size_t>(j)] = 1;

  GenomeLayout g;
  g.seed_ = seed;
  g.settings_ = settings;
  if (settings.no_prior) g.seed_.base_rotations = skeleton.rest_rotations;
  auto add = [&](Kind kind, int channel, int term, int gain, double lo, double hi, double prior,
                 std::string name) {
    g.genes_.push_back({kind, channel, term, gain});
    g.lo_.push_back(lo);
    g.hi_.push_back(hi);
    g.prior_.push_back(prior);
    g.names_.push_back(std::move(name));
  };
  for (size_t c = 0; c < seed.channels.size(); ++c) {
    const spectral::ChannelModel& ch = seed.channels[c];
    if (ch.kind != spectral::SignalKind::kRotation || !moves[static_cast<size_t>(ch.joint)]) continue;
    const std::string base = skeleton.names[static_cast<size_t>(ch.joint)] + "." + kAxes[ch.axis];
    const int ci = static_cast<int>(c);
    if (settings.no_prior)
      add(Kind::kOffset, ci, -1, -1, -1.0, 1.0, 0.0, base + ".A");
    else
      add(Kind::kOffset, ci, -1, -1, ch.mean - settings.offset_range_rad,
          ch.mean + settings.offset_range_rad, ch.mean, base + ".A");
    for (size_t t = 0; t < ch.terms.size(); ++t) {
      const spectral::Harmonic& h = ch.terms[t];
      const std::string n = std::to_string(h.n);
      const int ti = static_cast<int>(t);
      if (settings.no_prior) {
        add(Kind::kAmplitude, ci, ti, -1, 0.0, 0.5, 0.0, base + ".B" + n);
        add(Kind::kPhase, ci, ti, -1, -kPi, kPi, 0.0, base + ".D" + n);
      } else {
        if (h.amplitude >= kAmplitudeFloor) {
          add(Kind::kAmplitude, ci, ti, -1, h.amplitude / settings.amplitude_factor,
              h.amplitude * settings.amplitude_factor, h.amplitude, base + ".B" + n);
          g.genes_.back().geometric = true;
        } else {
          add(Kind::kAmplitude, ci, ti, -1, 0.0, kAmplitudeFloor * settings.amplitude_factor,
              h.amplitude, base + ".B" + n);
        }
        add(Kind::kPhase, ci, ti, -1, h.phase - settings.phase_range_rad,
            h.phase + settings.phase_range_rad, h.phase, base + ".D" + n);
      }
    }
  }
  if (settings.no_prior)
    add(Kind::kOmega, -1, -1, -1, 0.5 * seed.omega0, 2.0 * seed.omega0, seed.omega0, "omega0");
  else
    add(Kind::kOmega, -1, -1, -1, seed.omega0 * (1.0 - settings.omega_range),
        seed.omega0 * (1.0 + settings.omega_range), seed.omega0, "omega0");
  // The heading share and the stance legs' turn only where two or more leg pairs balance (a
  // quadruped: feet ahead of and behind the centre of mass); the share from 1, the best measured
  // on the dog (docs/physics.md). A character with no leg that balances (neither paired nor a
  // ball-hipped leg alone, physics::findLegPairs) has no balance feedback: of the gains only the
  // swing lift acts on it. The stance yield starts at 0 (off) for every character: from 0.5 the
  // Bandai tired run stood on more seeds, but iClone, which stood from 0, fell on two of three,
  // and the angry and tired walks tracked 1.1-1.3 deg worse (docs/physics.md "The stance yield");
  // startPoints() offers 0.5 as a second start, for a search to try.
  physics::BalanceGains defaults;
  const size_t pairs = physics::findLegPairs(plan).size();
  if (pairs >= 2) defaults.heading = kHeadingPrior;
  for (int i = 0; i < physics::kBalanceGainCount; ++i) {
    const bool turns = i == kHeadingGain || i == kStanceYawGain;
    if ((turns && pairs < 2) || (pairs == 0 && i != kSwingLiftGain)) continue;
    const auto [lo, hi] = gainRange(i, settings.gain_range);
    add(Kind::kGain, -1, -1, i, lo, hi, physics::balanceGain(defaults, i),
        std::string("balance.") + physics::balanceGainName(i));
  }
  return g;
}

double GenomeLayout::value(size_t i, double x) const {
  x = std::clamp(x, 0.0, 1.0);
  if (genes_[i].geometric) {
    // Geometric: x = 0.5 is the prior, each end a factor away.
    return prior_[i] * std::pow(settings_.amplitude_factor, 2.0 * x - 1.0);
  }
  if (genes_[i].kind == Kind::kOmega && settings_.no_prior)
    return prior_[i] * std::pow(2.0, 2.0 * x - 1.0);
  return lo_[i] + x * (hi_[i] - lo_[i]);
}

double GenomeLayout::coordinate(size_t i, double v) const {
  double x = 0.5;
  if (genes_[i].geometric) {
    x = v > 0.0
            ? 0.5 * (1.0 + std::log(v / prior_[i]) / std::log(settings_.amplitude_factor))
            : 0.0;
  } else if (genes_[i].kind == Kind::kOmega && settings_.no_prior) {
    x = 0.5 * (1.0 + std::log2(v / prior_[i]));
  } else if (hi_[i] > lo_[i]) {
    x = (v - lo_[i]) / (hi_[i] - lo_[i]);
  }
  return std::clamp(x, 0.0, 1.0);
}

std::vector<double> GenomeLayout::startPoint(std::uint64_t seed) const {
  std::vector<double> x(genes_.size());
  if (settings_.no_prior) {
    Random random(seed);
    for (double& v : x) v = random.uniform();
    return x;
  }
  for (size_t i = 0; i < genes_.size(); ++i) x[i] = coordinate(i, prior_[i]);
  return x;
}

std::vector<GenomeLayout::Start> GenomeLayout::startPoints(std::uint64_t seed) const {
  std::vector<Start> starts{{settings_.no_prior ? "a random point" : "the prior", startPoint(seed)}};
  if (settings_.no_prior) return starts;
  for (size_t i = 0; i < genes_.size(); ++i) {
    if (genes_[i].kind != Kind::kGain || genes_[i].gain != kStanceYieldGain) continue;
    Start yielding{"stance yield 0.5", starts.front().point};
    yielding.point[i] = coordinate(i, kStanceYieldAlternative);
    starts.push_back(std::move(yielding));
  }
  return starts;
}

spectral::TargetMotion GenomeLayout::decodeTarget(std::span<const double> x) const {
  SINEW_ASSERT(x.size() == lo_.size(), "decodeTarget: a point of this layout's size");
  spectral::TargetMotion target = seed_;
  for (size_t i = 0; i < genes_.size(); ++i) {
    const Gene& g = genes_[i];
    const double v = value(i, x[i]);
    switch (g.kind) {
      case Kind::kOffset:
        target.channels[static_cast<size_t>(g.channel)].mean = v;
        break;
      case Kind::kAmplitude:
        target.channels[static_cast<size_t>(g.channel)].terms[static_cast<size_t>(g.term)].amplitude = v;
        break;
      case Kind::kPhase:
        target.channels[static_cast<size_t>(g.channel)].terms[static_cast<size_t>(g.term)].phase = v;
        break;
      case Kind::kOmega:
        target.omega0 = v;
        break;
      case Kind::kGain:
        break;
    }
  }
  return target;
}

physics::BalanceGains GenomeLayout::decodeGains(std::span<const double> x) const {
  SINEW_ASSERT(x.size() == lo_.size(), "decodeGains: a point of this layout's size");
  physics::BalanceGains gains;
  for (size_t i = 0; i < genes_.size(); ++i)
    if (genes_[i].kind == Kind::kGain) physics::balanceGain(gains, genes_[i].gain) = value(i, x[i]);
  return gains;
}

std::vector<double> GenomeLayout::encode(const spectral::TargetMotion& target,
                                         const physics::BalanceGains& gains) const {
  std::vector<double> x(genes_.size(), 0.5);
  physics::BalanceGains copy = gains;
  for (size_t i = 0; i < genes_.size(); ++i) {
    const Gene& g = genes_[i];
    double v = 0.0;
    switch (g.kind) {
      case Kind::kOffset:
        v = target.channels[static_cast<size_t>(g.channel)].mean;
        break;
      case Kind::kAmplitude:
        v = target.channels[static_cast<size_t>(g.channel)].terms[static_cast<size_t>(g.term)].amplitude;
        break;
      case Kind::kPhase:
        v = target.channels[static_cast<size_t>(g.channel)].terms[static_cast<size_t>(g.term)].phase;
        break;
      case Kind::kOmega:
        v = target.omega0;
        break;
      case Kind::kGain:
        v = physics::balanceGain(copy, g.gain);
        break;
    }
    x[i] = coordinate(i, v);
  }
  return x;
}

Status FitnessWeights::validate() const {
  for (double w : {fall, tracking, speed, heading, placement, upright, energy, style})
    if (!(std::isfinite(w) && w >= 0.0))
      return Status::error("fitness weights (fall, tracking, speed, heading, placement, upright, "
                           "energy, style) must be finite and >= 0");
  return Status();
}

double& fitnessWeight(FitnessWeights& w, int term) {
  double* weights[kFitnessTermCount] = {&w.fall,      &w.tracking, &w.speed,  &w.heading,
                                        &w.placement, &w.upright,  &w.energy, &w.style};
  return *weights[std::clamp(term, 0, kFitnessTermCount - 1)];
}

const char* fitnessTermName(int term) {
  static const char* const names[kFitnessTermCount] = {
      "fall", "tracking", "speed", "heading", "placement", "upright", "energy", "style"};
  return term >= 0 && term < kFitnessTermCount ? names[term] : "";
}

double fitnessTerm(const FitnessTerms& t, int term) {
  switch (term) {
    case 0:
      return t.fall;
    case 1:
      return t.tracking;
    case 2:
      return t.speed;
    case 3:
      return t.heading;
    case 4:
      return t.placement;
    case 5:
      return t.upright;
    case 6:
      return t.energy;
    case 7:
      return t.style;
    default:
      return 0.0;
  }
}

nlohmann::json fitnessJson(const FitnessTerms& t) {
  nlohmann::json j;
  for (int k = 0; k < kFitnessTermCount; ++k) j[fitnessTermName(k)] = fitnessTerm(t, k);
  j["total"] = t.total;
  j["survived_s"] = t.survived_s;
  j["distance_m"] = t.distance_m;
  j["speed_m_s"] = t.speed_m_s;
  j["track_err_rad_rms"] = t.track_err_rad_rms;
  j["fell"] = t.fell;
  if (t.fell) j["fall_reason"] = t.fall_reason;
  return j;
}

Result<FitnessTerms> fitnessFromJson(const nlohmann::json& j) {
  FitnessTerms t;
  double* terms[kFitnessTermCount] = {&t.fall,      &t.tracking, &t.speed,  &t.heading,
                                      &t.placement, &t.upright,  &t.energy, &t.style};
  const auto number = [&j](const char* key, double& out) -> Status {
    if (!j.is_object() || !j.contains(key) || !j.at(key).is_number() ||
        !std::isfinite(j.at(key).get<double>()))
      return Status::error(std::string(key) + ": expected a finite number");
    out = j.at(key).get<double>();
    return {};
  };
  for (int k = 0; k < kFitnessTermCount; ++k) {
    if (k == 7 && j.is_object() && !j.contains("style")) continue;  // from before the term
    if (Status s = number(fitnessTermName(k), *terms[k]); !s.ok()) return s;
  }
  const char* keys[5] = {"total", "survived_s", "distance_m", "speed_m_s", "track_err_rad_rms"};
  double* values[5] = {&t.total, &t.survived_s, &t.distance_m, &t.speed_m_s, &t.track_err_rad_rms};
  for (int k = 0; k < 5; ++k)
    if (Status s = number(keys[k], *values[k]); !s.ok()) return s;
  if (!j.contains("fell") || !j.at("fell").is_boolean())
    return Status::error("fell: expected true or false");
  t.fell = j.at("fell").get<bool>();
  if (j.contains("fall_reason")) {
    if (!j.at("fall_reason").is_string()) return Status::error("fall_reason: expected text");
    t.fall_reason = j.at("fall_reason").get<std::string>();
  }
  return t;
}

Result<Problem> Problem::create(const physics::BodyPlan& plan, const motion::Skeleton& skeleton,
                                const spectral::TargetMotion& seed, const GenomeSettings& genome,
                                const physics::SimulationSettings& simulation,
                                const FitnessWeights& weights) {
  if (Status s = weights.validate(); !s.ok()) return s;
  if (Status s = simulation.validate(); !s.ok()) return Status::error("simulation: " + s.message());
  Result<GenomeLayout> layout = GenomeLayout::create(plan, skeleton, seed, genome);
  if (!layout.ok()) return layout.status();
  Problem p{plan, skeleton, seed, std::move(layout).value(), simulation, weights, 0.0,
            glm::dvec3(0.0, 0.0, 1.0), 0.0, {}};
  // The seed's travel: the base's displacement over one stride. Its velocity at t = 0 would carry
  // the stride's surge and sway (on the real walks up to 44% and 13 deg off the mean, which the
  // speed, heading and step terms then asked the search to match).
  const double period = seed.period();
  glm::dvec3 v = (physics::targetState(plan, skeleton, seed, period).pose.base_position -
                  physics::targetState(plan, skeleton, seed, 0.0).pose.base_position) /
                 period;
  v.y = 0.0;
  p.reference_speed_m_s = glm::length(v);
  if (p.reference_speed_m_s > 1e-6) p.reference_direction = v / p.reference_speed_m_s;
  p.reference_step_m = p.reference_speed_m_s * seed.period() / 2.0;
  return p;
}

FitnessTerms scoreRun(const Problem& problem, const physics::SimulationReport& r, double omega) {
  const FitnessWeights& w = problem.weights;
  const double window = problem.simulation.seconds;
  FitnessTerms t;
  t.fell = r.fell;
  if (r.fell) t.fall_reason = r.fall_reason;
  t.survived_s = r.fell ? r.fall_time_s : r.seconds;
  t.distance_m = r.distance_m;
  t.speed_m_s = r.speed_m_s;
  t.track_err_rad_rms = r.track_err_rad_rms;
  t.fall = w.fall * std::max(0.0, window - t.survived_s);
  t.tracking = w.tracking * r.track_err_rad_rms;
  t.speed = w.speed * std::abs(r.speed_m_s - problem.reference_speed_m_s);
  if (r.com.size() >= 2 && problem.reference_speed_m_s > 1e-6) {
    glm::dvec3 d = r.com.back() - r.com.front();
    d.y = 0.0;
    const double length = glm::length(d);
    const double cosine =
        length > 1e-6 ? std::clamp(glm::dot(d / length, problem.reference_direction), -1.0, 1.0) : -1.0;
    t.heading = w.heading * std::acos(cosine);
  }
  // Step length: between consecutive footfalls of different feet, along the reference direction.
  double steps = 0.0, sum = 0.0;
  for (size_t i = 1; i < r.footfalls.size(); ++i) {
    if (r.footfalls[i].foot == r.footfalls[i - 1].foot) continue;
    sum += std::abs(glm::dot(r.footfalls[i].position - r.footfalls[i - 1].position,
                             problem.reference_direction));
    steps += 1.0;
  }
  const double step = steps > 0.0 ? sum / steps : 0.0;
  t.placement = w.placement * std::abs(step - problem.reference_step_m);
  t.upright = w.upright * (1.0 - r.min_uprightness);
  t.energy = w.energy * r.torque_sq_per_kg / std::max(r.seconds, 1e-3);
  if (w.style > 0.0 && r.motion.frame_count > 1) {
    // The run's spectrum at its own stride, after the first (settling) stride.
    const double stride = omega > 0.0 ? omega : problem.seed.omega0;
    t.style = w.style * spectral::runStyleDistance(problem.skeleton, r.motion, problem.seed, stride,
                                                   2.0 * kPi / stride);
  }
  t.total =
      t.fall + t.tracking + t.speed + t.heading + t.placement + t.upright + t.energy + t.style;
  return t;
}

Status setTrials(Problem& problem, int trials, double push_m_s) {
  if (trials < 1 || trials > kMaxTrials)
    return Status::error("trials: must be 1.." + std::to_string(kMaxTrials));
  if (!(std::isfinite(push_m_s) && push_m_s > 0.0 && push_m_s <= 10.0))
    return Status::error("trial push: must be in (0, 10] m/s");
  const glm::dvec3 forward = problem.reference_direction;
  const glm::dvec3 left = glm::cross(glm::dvec3(0.0, 1.0, 0.0), forward);
  const glm::dvec3 directions[4] = {left, -left, -forward, forward};
  const double impulse = push_m_s * problem.plan.total_mass_kg;
  const double last = std::max(0.5, problem.simulation.seconds / 2.0);
  problem.trial_pushes.clear();
  for (int k = 1; k < trials; ++k) {
    const double time = std::min(last, 1.0 + 0.7 * (k - 1));
    problem.trial_pushes.push_back({time, impulse * directions[(k - 1) % 4], ""});
  }
  return Status();
}

Status addRobustPushes(Problem& problem, double push_m_s) {
  if (!(std::isfinite(push_m_s) && push_m_s >= 0.0 && push_m_s <= 10.0))
    return Status::error("robust push: must be in [0, 10] m/s");
  if (push_m_s == 0.0) return Status();
  const glm::dvec3 forward = problem.reference_direction;
  const glm::dvec3 left = glm::cross(glm::dvec3(0.0, 1.0, 0.0), forward);
  const glm::dvec3 directions[4] = {forward, left, -forward, -left};
  const double impulse = push_m_s * problem.plan.total_mass_kg;
  for (int k = 0; k < 4; ++k) {
    const double time = problem.simulation.seconds * (0.15 + 0.2 * k);
    problem.simulation.pushes.push_back({time, impulse * directions[k], ""});
  }
  return Status();
}

namespace {

// One run of a point's controller with these settings, scored; diverged runs cost +inf.
Evaluation runOnce(const Problem& problem, const spectral::TargetMotion& target,
                   const physics::SimulationSettings& settings) {
  Evaluation e;
  Result<physics::SimulationReport> run =
      physics::simulate(problem.plan, problem.skeleton, target, settings);
  if (!run.ok()) {
    e.terms.diverged = true;
    e.terms.total = std::numeric_limits<double>::infinity();
    return e;
  }
  e.report = std::move(run).value();
  e.cancelled = e.report.cancelled;
  if (e.cancelled) return e;  // partial figures: not a fitness, and not worth scoring
  e.terms = scoreRun(problem, e.report, target.omega0);
  if (e.report.diverged) {
    e.terms.diverged = true;
    e.terms.total = std::numeric_limits<double>::infinity();
  }
  return e;
}

// The weighted terms and their total: what a point's trials are averaged over.
constexpr double FitnessTerms::*kWeightedTerms[] = {
    &FitnessTerms::fall,      &FitnessTerms::tracking, &FitnessTerms::speed,
    &FitnessTerms::heading,   &FitnessTerms::placement, &FitnessTerms::upright,
    &FitnessTerms::energy,    &FitnessTerms::style,    &FitnessTerms::total};

}  // namespace

Evaluation evaluate(const Problem& problem, std::span<const double> x,
                    const std::atomic<bool>* cancel, bool record) {
  physics::SimulationSettings settings = problem.simulation;
  settings.tracking.balance = problem.layout.decodeGains(x);
  settings.cancel = cancel;
  settings.reference = &problem.seed;  // the style to keep, whatever the genome tracks
  const bool measure_style = problem.weights.style > 0.0;  // needs the motion at 30 fps
  if (!record && !measure_style) settings.record_fps = std::min(settings.record_fps, 5.0);
  const spectral::TargetMotion target = problem.layout.decodeTarget(x);
  Evaluation e = runOnce(problem, target, settings);
  if (!record) e.report.motion = {};
  if (problem.trial_pushes.empty() || e.terms.diverged || e.cancelled) return e;
  // Robustness trials: the cost is the mean over the nominal run and each pushed one.
  FitnessTerms sum = e.terms;
  if (!measure_style) settings.record_fps = std::min(settings.record_fps, 5.0);
  for (const physics::Push& push : problem.trial_pushes) {
    physics::SimulationSettings pushed = settings;
    pushed.pushes.push_back(push);
    const Evaluation trial = runOnce(problem, target, pushed);
    if (trial.cancelled) {
      e.cancelled = true;
      return e;
    }
    if (trial.terms.diverged) {
      e.terms.diverged = true;
      e.terms.total = std::numeric_limits<double>::infinity();
      return e;
    }
    for (double FitnessTerms::*term : kWeightedTerms) sum.*term += trial.terms.*term;
  }
  const double runs = static_cast<double>(problem.trial_pushes.size() + 1);
  for (double FitnessTerms::*term : kWeightedTerms) e.terms.*term = sum.*term / runs;
  return e;
}

std::vector<Evaluation> evaluateAll(const Problem& problem,
                                    const std::vector<std::vector<double>>& points, int threads,
                                    const std::atomic<bool>* cancel, bool record) {
  std::vector<Evaluation> results(points.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next.fetch_add(1); i < points.size(); i = next.fetch_add(1)) {
      // Once cancelled, the points not yet started are marked, not simulated: building each
      // one's world only to stop at its first step is what made stop() slow under load.
      if (cancel != nullptr && cancel->load(std::memory_order_relaxed))
        results[i].cancelled = true;
      else
        results[i] = evaluate(problem, points[i], cancel, record);
    }
  };
  const int workers = std::clamp(threads, 1, static_cast<int>(std::max<size_t>(1, points.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  return results;
}

}  // namespace sinew::search
