#include "sinew/search/wire.h"

#include <cstring>

namespace sinew::search::wire {
namespace {

class Writer {
 public:
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void text(const std::string& s) {
    u64(s.size());
    raw(s.data(), s.size());
  }
  Bytes take() { return std::move(bytes_); }

 private:
  void raw(const void* p, size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    bytes_.insert(bytes_.end(), b, b + n);
  }
  Bytes bytes_;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  bool u64(std::uint64_t& v) { return raw(&v, sizeof v); }
  bool f64(double& v) { return raw(&v, sizeof v); }
  bool text(std::string& s) {
    std::uint64_t n = 0;
    if (!u64(n) || n > bytes_.size() - at_) return false;
    s.assign(reinterpret_cast<const char*>(bytes_.data() + at_), n);
    at_ += n;
    return true;
  }
  bool done() const { return at_ == bytes_.size(); }
  size_t left() const { return bytes_.size() - at_; }

 private:
  bool raw(void* p, size_t n) {
    if (n > bytes_.size() - at_) return false;
    std::memcpy(p, bytes_.data() + at_, n);
    at_ += n;
    return true;
  }
  std::span<const std::uint8_t> bytes_;
  size_t at_ = 0;
};

// The doubles of FitnessTerms, in one fixed order.
constexpr double FitnessTerms::*kDoubles[] = {&FitnessTerms::fall,
                                              &FitnessTerms::tracking,
                                              &FitnessTerms::speed,
                                              &FitnessTerms::heading,
                                              &FitnessTerms::placement,
                                              &FitnessTerms::upright,
                                              &FitnessTerms::energy,
                                              &FitnessTerms::style,
                                              &FitnessTerms::total,
                                              &FitnessTerms::survived_s,
                                              &FitnessTerms::distance_m,
                                              &FitnessTerms::speed_m_s,
                                              &FitnessTerms::track_err_rad_rms};

void mix(std::uint64_t& h, const void* p, size_t n) {
  const auto* b = static_cast<const std::uint8_t*>(p);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ULL;  // FNV-1a
}
void mix(std::uint64_t& h, double v) {
  mix(h, &v, sizeof v);
}

}  // namespace

Bytes packPoints(std::uint64_t id, std::span<const std::vector<double>> points) {
  Writer w;
  w.u64(id);
  w.u64(points.size());
  w.u64(points.empty() ? 0 : points.front().size());
  for (const std::vector<double>& p : points)
    for (double v : p) w.f64(v);
  return w.take();
}

Result<Points> unpackPoints(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  Points out;
  std::uint64_t count = 0, dim = 0;
  if (!r.u64(out.id) || !r.u64(count) || !r.u64(dim) ||
      (dim > 0 && count > r.left() / sizeof(double) / dim) ||
      count * dim * sizeof(double) != r.left())
    return Status::error("a generation's points arrived cut or malformed");
  out.points.assign(count, std::vector<double>(dim));
  for (std::vector<double>& p : out.points)
    for (double& v : p) (void)r.f64(v);
  return out;
}

Bytes packResults(std::uint64_t id, std::span<const Evaluation> results) {
  Writer w;
  w.u64(id);
  w.u64(results.size());
  for (const Evaluation& e : results) {
    for (double FitnessTerms::*d : kDoubles) w.f64(e.terms.*d);
    w.u64((e.terms.fell ? 1u : 0u) | (e.terms.diverged ? 2u : 0u) | (e.cancelled ? 4u : 0u));
    w.text(e.terms.fall_reason);
  }
  return w.take();
}

Result<Results> unpackResults(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  Results out;
  std::uint64_t count = 0;
  const Status cut = Status::error("a worker's results arrived cut or malformed");
  if (!r.u64(out.id) || !r.u64(count) || count > r.left()) return cut;
  out.results.resize(count);
  for (Evaluation& e : out.results) {
    for (double FitnessTerms::*d : kDoubles)
      if (!r.f64(e.terms.*d)) return cut;
    std::uint64_t flags = 0;
    if (!r.u64(flags) || !r.text(e.terms.fall_reason)) return cut;
    e.terms.fell = (flags & 1u) != 0;
    e.terms.diverged = (flags & 2u) != 0;
    e.cancelled = (flags & 4u) != 0;
  }
  if (!r.done()) return cut;
  return out;
}

std::uint64_t fingerprint(const Problem& problem) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const GenomeLayout& layout = problem.layout;
  for (const std::string& name : layout.names()) mix(h, name.data(), name.size());
  const std::vector<double> middle(static_cast<size_t>(layout.size()), 0.5);
  const spectral::TargetMotion prior = layout.decodeTarget(middle);
  mix(h, prior.omega0);
  for (const spectral::ChannelModel& c : prior.channels) {
    mix(h, c.mean);
    for (const spectral::Harmonic& t : c.terms) mix(h, t.amplitude), mix(h, t.phase);
  }
  physics::BalanceGains gains = layout.decodeGains(middle);
  for (int i = 0; i < physics::kBalanceGainCount; ++i) mix(h, physics::balanceGain(gains, i));
  for (const physics::Link& link : problem.plan.links) mix(h, link.mass_kg);
  mix(h, problem.simulation.seconds);
  mix(h, problem.simulation.tracking.servo_lead_s);
  mix(h, problem.simulation.tracking.lead_yielding_legs ? 1.0 : 0.0);
  FitnessWeights weights = problem.weights;
  for (int k = 0; k < kFitnessTermCount; ++k) mix(h, fitnessWeight(weights, k));
  for (const auto* pushes : {&problem.simulation.pushes, &problem.trial_pushes}) {
    for (const physics::Push& push : *pushes)
      mix(h, push.time_s), mix(h, push.impulse_ns.x), mix(h, push.impulse_ns.y),
          mix(h, push.impulse_ns.z);
  }
  return h;
}

}  // namespace sinew::search::wire
