// The search over simulated characters: the genome around the DFT prior, determinism across
// thread counts, stop latency, pause and checkpoint-resume equal to an uninterrupted run, and the
// outcome on the creatures and the default biped.
#include "sinew/search/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "physics/physics_test_util.h"
#include "sinew/search/problem.h"

namespace sinew::search {
namespace {

Problem makeProblem(const physics::test_util::Character& c, double window_s,
                    bool no_prior = false) {
  physics::SimulationSettings simulation;
  simulation.seconds = window_s;
  GenomeSettings genome;
  genome.no_prior = no_prior;
  Result<Problem> p = Problem::create(c.plan, c.asset.skeleton, c.target, genome, simulation);
  EXPECT_TRUE(p.ok()) << p.message();
  return std::move(p).value();
}

TEST(SearchGenome, ThePriorPointIsTheAnalysedMotion) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const Problem p = makeProblem(biped, 2.0);
  const GenomeLayout& layout = p.layout;
  std::printf("biped genome: %d coordinates (%s ... %s)\n", layout.size(),
              layout.names().front().c_str(), layout.names().back().c_str());
  EXPECT_GT(layout.size(), 300);
  const std::vector<double> x = layout.startPoint(1);
  int at_centre = 0;
  for (double v : x) at_centre += std::abs(v - 0.5) < 1e-12 ? 1 : 0;
  // The rest are harmonics of (nearly) still joints below 1e-4 rad, at the bottom of their linear
  // range; the decode below proves every coordinate gives the prior back.
  std::printf("%d of %d prior coordinates at the centre of their range\n", at_centre, layout.size());
  EXPECT_GT(at_centre, layout.size() * 3 / 4);
  const spectral::TargetMotion decoded = layout.decodeTarget(x);
  EXPECT_NEAR(decoded.omega0, biped.target.omega0, 1e-12);
  for (size_t c = 0; c < decoded.channels.size(); ++c) {
    EXPECT_NEAR(decoded.channels[c].mean, biped.target.channels[c].mean, 1e-12);
    for (size_t t = 0; t < decoded.channels[c].terms.size(); ++t) {
      EXPECT_NEAR(decoded.channels[c].terms[t].amplitude, biped.target.channels[c].terms[t].amplitude, 1e-12);
      EXPECT_NEAR(decoded.channels[c].terms[t].phase, biped.target.channels[c].terms[t].phase, 1e-12);
    }
  }
  // The start holds the default gains, every one of them (the stance yield too: off).
  physics::BalanceGains gains = layout.decodeGains(x), defaults;
  for (int g = 0; g < physics::kBalanceGainCount; ++g)
    EXPECT_NEAR(physics::balanceGain(gains, g), physics::balanceGain(defaults, g), 1e-12)
        << physics::balanceGainName(g);
  // A point decodes and encodes back; the ends of the ranges are where the header says.
  std::vector<double> y(x.size());
  for (size_t i = 0; i < y.size(); ++i) y[i] = std::fmod(0.37 * static_cast<double>(i), 1.0);
  const std::vector<double> back = layout.encode(layout.decodeTarget(y), layout.decodeGains(y));
  for (size_t i = 0; i < y.size(); ++i) ASSERT_NEAR(back[i], y[i], 1e-9) << layout.names()[i];
  std::vector<double> top(x.size(), 1.0);
  EXPECT_NEAR(layout.decodeTarget(top).omega0, 1.05 * biped.target.omega0, 1e-12);
  // Without a prior the start is random and the rest pose replaces the clip's mean rotations.
  const Problem blind = makeProblem(biped, 2.0, true);
  const std::vector<double> r = blind.layout.startPoint(7);
  EXPECT_NE(r, blind.layout.startPoint(8));
  EXPECT_EQ(r, blind.layout.startPoint(7));
}

// The starts a search may try: the prior, and the prior with the legs yielding by half on
// landing (the stance yield, the one gene they differ in); without a prior, the random start.
TEST(SearchGenome, TheStartsAreThePriorAndTheYieldingLegs) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const Problem p = makeProblem(biped, 2.0);
  const std::vector<GenomeLayout::Start> starts = p.layout.startPoints(1);
  ASSERT_EQ(starts.size(), 2u);
  EXPECT_EQ(starts[0].name, "the prior");
  EXPECT_EQ(starts[0].point, p.layout.startPoint(1));
  EXPECT_EQ(starts[1].name, "stance yield 0.5");
  const std::vector<std::string>& names = p.layout.names();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] != "balance.stance_yield") {
      EXPECT_EQ(starts[1].point[i], starts[0].point[i]) << names[i];
    }
  }
  EXPECT_EQ(p.layout.decodeGains(starts[0].point).stance_yield, 0.0);
  EXPECT_NEAR(p.layout.decodeGains(starts[1].point).stance_yield, 0.5, 1e-12);
  const Problem blind = makeProblem(biped, 2.0, true);
  ASSERT_EQ(blind.layout.startPoints(7).size(), 1u);
  EXPECT_EQ(blind.layout.startPoints(7)[0].point, blind.layout.startPoint(7));
}

// The heading share is a gene only where two or more leg pairs balance (the trot's forelegs and
// hind legs), starting at 1; a biped's genome has no such gene and decodes it as off.
TEST(SearchGenome, OnlyCharactersWithTwoLegPairsSearchTheHeadingShare) {
  for (const char* name : {"biped_walk.bvh", "quadruped_trot.bvh"}) {
    const physics::test_util::Character c = physics::test_util::loadCharacter(name);
    ASSERT_FALSE(c.plan.links.empty());
    const bool quadruped = physics::findLegPairs(c.plan).size() >= 2;
    const Problem p = makeProblem(c, 2.0);
    const std::vector<std::string>& names = p.layout.names();
    const bool has_gene = std::find(names.begin(), names.end(), "balance.heading") != names.end();
    EXPECT_EQ(has_gene, quadruped) << name;
    EXPECT_EQ(p.layout.decodeGains(p.layout.startPoint(1)).heading, quadruped ? 1.0 : 0.0) << name;
    const std::vector<double> top(static_cast<size_t>(p.layout.size()), 1.0);
    const std::vector<double> bottom(static_cast<size_t>(p.layout.size()), 0.0);
    EXPECT_EQ(p.layout.decodeGains(top).heading, quadruped ? 1.0 : 0.0) << name;
    EXPECT_EQ(p.layout.decodeGains(bottom).heading, 0.0) << name;
  }
  EXPECT_EQ(physics::findLegPairs(physics::test_util::loadCharacter("quadruped_trot.bvh").plan).size(),
            2u);
}

// Robustness trials: the cost is the mean over the nominal run and one run per trial push (to
// the left, then the right of the reference direction, 0.3 m/s of the body's mass); the figures
// stay the nominal run's.
// The speed, heading and step-length references are the seed's travel over a stride: a surge and
// a sway that peak at t = 0 (0.5 and 0.3 m/s here; the real walks' reach 0.4 m/s and 13 deg) must
// not move them.
TEST(SearchProblem, TheReferencesAreTheSeedsTravelNotItsVelocityAtTheStart) {
  physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  spectral::TargetMotion& target = biped.target;
  const auto travel = std::max_element(
      target.channels.begin(), target.channels.end(),
      [](const spectral::ChannelModel& a, const spectral::ChannelModel& b) {
        return std::abs(a.trend) < std::abs(b.trend);
      });
  ASSERT_GT(std::abs(travel->trend), 0.5);
  const int joint = travel->joint;
  const double w = target.omega0;
  glm::dvec3 trend(0.0);
  for (int axis : {0, 2}) {
    auto channel = std::find_if(target.channels.begin(), target.channels.end(), [&](auto& c) {
      return c.joint == joint && c.kind == spectral::SignalKind::kTranslation && c.axis == axis;
    });
    if (channel == target.channels.end()) {
      target.channels.push_back({joint, spectral::SignalKind::kTranslation, axis, 0.0, {}, 0.0});
      channel = target.channels.end() - 1;
    }
    trend[axis] = channel->trend;
    const int n = axis == 2 ? 2 : 1;  // the surge at twice the stride, the sway at the stride
    const double peak = axis == 2 ? 0.5 : 0.3;  // m/s
    channel->terms.push_back({n, peak / (n * w), 0.0});  // B sin(n w t): its rate peaks at t = 0
  }
  const Problem p = makeProblem(biped, 2.0);
  EXPECT_NEAR(p.reference_speed_m_s, glm::length(trend), 1e-6);
  EXPECT_NEAR(glm::dot(p.reference_direction, trend / glm::length(trend)), 1.0, 1e-9);
  EXPECT_NEAR(p.reference_step_m, glm::length(trend) * target.period() / 2.0, 1e-6);
}

TEST(SearchProblem, TrialsAverageTheNominalAndThePushedRuns) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  Problem p = makeProblem(biped, 2.0);
  EXPECT_FALSE(setTrials(p, 0, 0.3).ok());
  EXPECT_FALSE(setTrials(p, kMaxTrials + 1, 0.3).ok());
  EXPECT_FALSE(setTrials(p, 3, 0.0).ok());
  ASSERT_TRUE(setTrials(p, 3, 0.3).ok());
  ASSERT_EQ(p.trial_pushes.size(), 2u);
  const glm::dvec3 left = glm::cross(glm::dvec3(0.0, 1.0, 0.0), p.reference_direction);
  const double impulse = 0.3 * p.plan.total_mass_kg;
  EXPECT_NEAR(glm::dot(p.trial_pushes[0].impulse_ns, left), impulse, 1e-9);
  EXPECT_NEAR(glm::dot(p.trial_pushes[1].impulse_ns, left), -impulse, 1e-9);
  EXPECT_NEAR(p.trial_pushes[0].time_s, 1.0, 1e-12);
  EXPECT_NEAR(p.trial_pushes[1].time_s, 1.0, 1e-12);  // within the first half of the 2 s window

  const std::vector<double> x = p.layout.startPoint(1);
  const Evaluation robust = evaluate(p, x);
  Problem single = p;
  single.trial_pushes.clear();
  const Evaluation nominal = evaluate(single, x);
  double sum = nominal.terms.total;
  for (const physics::Push& push : p.trial_pushes) {
    Problem pushed = single;
    pushed.simulation.pushes.push_back(push);
    sum += evaluate(pushed, x).terms.total;
  }
  std::printf("nominal %.3f, mean of the three runs %.3f\n", nominal.terms.total, sum / 3.0);
  EXPECT_NEAR(robust.terms.total, sum / 3.0, 1e-9);
  EXPECT_EQ(robust.terms.survived_s, nominal.terms.survived_s);
  EXPECT_EQ(robust.terms.distance_m, nominal.terms.distance_m);
}

// Pushes in every run: four of 0.3 m/s of the body's mass, forward, left, back and right of the
// reference direction at 15/35/55/75% of the window, after the user's own; the run that takes
// them moves differently from the one that does not.
TEST(SearchProblem, RobustPushesJoinEveryRun) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  Problem p = makeProblem(biped, 2.0);
  p.simulation.pushes.push_back({0.5, {0.0, 0.0, 1.0}, ""});
  const Problem unpushed = p;
  EXPECT_FALSE(addRobustPushes(p, -0.1).ok());
  EXPECT_FALSE(addRobustPushes(p, 10.5).ok());
  ASSERT_TRUE(addRobustPushes(p, 0.0).ok());
  EXPECT_EQ(p.simulation.pushes.size(), 1u);
  ASSERT_TRUE(addRobustPushes(p, 0.3).ok());
  ASSERT_EQ(p.simulation.pushes.size(), 5u);
  const glm::dvec3 forward = p.reference_direction;
  const glm::dvec3 left = glm::cross(glm::dvec3(0.0, 1.0, 0.0), forward);
  const double impulse = 0.3 * p.plan.total_mass_kg;
  const glm::dvec3 expected[4] = {forward, left, -forward, -left};
  for (int k = 0; k < 4; ++k) {
    const physics::Push& push = p.simulation.pushes[static_cast<size_t>(k + 1)];
    EXPECT_NEAR(push.time_s, 2.0 * (0.15 + 0.2 * k), 1e-12) << k;
    EXPECT_NEAR(glm::length(push.impulse_ns - impulse * expected[k]), 0.0, 1e-9) << k;
    EXPECT_TRUE(push.link.empty());
  }
  const std::vector<double> x = p.layout.startPoint(1);
  const Evaluation pushed = evaluate(p, x);
  const Evaluation nominal = evaluate(unpushed, x);
  std::printf("pushed %.3f, unpushed %.3f\n", pushed.terms.total, nominal.terms.total);
  EXPECT_NE(pushed.terms.total, nominal.terms.total);
}

EvolveSettings small(int threads, int generations = 2) {
  EvolveSettings s;
  s.population = 6;
  s.generations = generations;
  s.threads = threads;
  s.seed = 3;
  return s;
}

TEST(SearchSession, SameSeedSameBestOnOneAndTwoThreads) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  std::vector<double> best[2];
  double cost[2] = {0.0, 0.0};
  for (int threads = 1; threads <= 2; ++threads) {
    auto session = Session::create(makeProblem(biped, 1.5), small(threads)).value();
    while (session->runGeneration()) {
    }
    const auto snap = session->snapshot();
    best[threads - 1] = snap->best_point;
    cost[threads - 1] = snap->best_terms.total;
    EXPECT_EQ(snap->generation, 2);
    EXPECT_EQ(snap->history.size(), 2u);
  }
  ASSERT_FALSE(best[0].empty());
  EXPECT_EQ(0, std::memcmp(best[0].data(), best[1].data(), best[0].size() * sizeof(double)));
  EXPECT_EQ(cost[0], cost[1]);
}

// The snapshot carries the best run's joint figures (what the editor's Evolve panel prints): those
// of a replay of the best point, joint for joint.
TEST(SearchSession, TheSnapshotCarriesTheBestRunsJointFigures) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  auto session = Session::create(makeProblem(biped, 1.5), small(2)).value();
  while (session->runGeneration()) {
  }
  const auto snap = session->snapshot();
  ASSERT_FALSE(snap->best_point.empty());
  const physics::SimulationReport replay = evaluate(session->problem(), snap->best_point).report;
  EXPECT_EQ(snap->best_joints.links, replay.links);
  EXPECT_EQ(snap->best_joints.torque_limited_share, replay.torque_limited_share);
  EXPECT_EQ(snap->best_joints.track_err_by_link_rad, replay.track_err_by_link_rad);
  EXPECT_EQ(snap->best_joints.links.size(), biped.plan.links.size());
  EXPECT_NE(physics::furthestJointsLine(snap->best_joints, "the clip"), "");
}

TEST(SearchSession, StopInterruptsEvaluationsInFlightAndPausingChangesNothing) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  // Uninterrupted.
  auto straight = Session::create(makeProblem(biped, 1.5), small(2, 3)).value();
  straight->start();
  straight->wait();
  const auto expected = straight->snapshot();
  EXPECT_EQ(expected->state, SessionState::kFinished);
  // Paused twice mid-generation, then resumed.
  auto paused = Session::create(makeProblem(biped, 1.5), small(2, 3)).value();
  paused->start();
  for (int i = 0; i < 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    paused->pause();
    EXPECT_EQ(paused->snapshot()->state, SessionState::kPaused);
    paused->resume();
  }
  paused->wait();
  const auto got = paused->snapshot();
  EXPECT_EQ(got->best_point, expected->best_point);
  EXPECT_EQ(got->best_terms.total, expected->best_terms.total);
  // Stop latency, with 20 s evaluations in flight: they run on after a fall, so what is in flight
  // does not hang on how soon a sampled genome falls.
  Problem long_problem = makeProblem(biped, 20.0);
  long_problem.simulation.stop_at_fall = false;
  auto long_run = Session::create(std::move(long_problem), small(2, 5)).value();
  long_run->start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto t0 = std::chrono::steady_clock::now();
  long_run->stop();
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("stop() returned after %.2f ms with 2 evaluations of 20 s in flight\n", ms);
  // An evaluation of 20 s takes seconds of wall time: returning within one second proves stop()
  // interrupts the runs in flight. How fast it is (the aim is 100 ms) is search_bench's figure;
  // under the sanitizers on a loaded machine it read 116 ms.
  EXPECT_LT(ms, 1000.0);
  EXPECT_EQ(long_run->snapshot()->generation, 0);
  EXPECT_EQ(long_run->snapshot()->state, SessionState::kStopped);
}

TEST(SearchSession, CheckpointResumeEqualsAnUninterruptedRun) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  for (const OptimizerKind kind : {OptimizerKind::kCmaes, OptimizerKind::kGa}) {
    const char* optimizer = optimizerName(kind);
    EvolveSettings settings = small(2, 4);
    settings.optimizer = kind;
    auto whole = Session::create(makeProblem(biped, 1.0), settings).value();
    while (whole->runGeneration()) {
    }
    auto first = Session::create(makeProblem(biped, 1.0), settings).value();
    ASSERT_TRUE(first->runGeneration());
    ASSERT_TRUE(first->runGeneration());
    const std::string text = first->checkpoint().dump();
    auto second = Session::resume(makeProblem(biped, 1.0), nlohmann::json::parse(text)).value();
    while (second->runGeneration()) {
    }
    EXPECT_EQ(second->snapshot()->generation, 4) << optimizer;
    EXPECT_EQ(second->snapshot()->best_point, whole->snapshot()->best_point) << optimizer;
    EXPECT_EQ(second->snapshot()->best_terms.total, whole->snapshot()->best_terms.total) << optimizer;
    nlohmann::json a = second->checkpoint(), b = whole->checkpoint();
    EXPECT_EQ(a["optimizer"], b["optimizer"]) << optimizer;
    // A checkpoint of another search is refused, naming why.
    nlohmann::json wrong = nlohmann::json::parse(text);
    wrong["genome_size"] = 3;
    Result<std::unique_ptr<Session>> refused = Session::resume(makeProblem(biped, 1.0), wrong);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.message().find("not the same search"), std::string::npos) << refused.message();
  }
}

// Trying starts (EvolveSettings::start_generations): a start whose best walks the whole window is
// kept at once, so the search is the one from that start alone, bit for bit; when every run
// falls (a push no gait survives), each start has its generations, then the better goes on, and
// a checkpoint within the trials resumes to the uninterrupted result.
TEST(SearchSession, AStartThatWalksIsKeptAndFallingStartsEachHaveTheirTrial) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  EvolveSettings trying = small(2, 3);
  trying.start_generations = 2;
  EvolveSettings one = trying;
  one.start_generations = 0;
  auto walks = Session::create(makeProblem(biped, 1.0), trying).value();
  auto alone = Session::create(makeProblem(biped, 1.0), one).value();
  EXPECT_EQ(walks->snapshot()->start, "trying start 1 of 2 (the prior)");
  EXPECT_EQ(alone->snapshot()->start, "");
  while (walks->runGeneration() && alone->runGeneration()) {
  }
  EXPECT_FALSE(walks->snapshot()->best_terms.fell);
  EXPECT_EQ(walks->snapshot()->start, "start 1 of 2 (the prior) kept");
  EXPECT_EQ(walks->snapshot()->best_point, alone->snapshot()->best_point);
  EXPECT_EQ(walks->snapshot()->best_terms.total, alone->snapshot()->best_terms.total);

  auto pushed = [&biped] {
    Problem p = makeProblem(biped, 1.5);
    p.simulation.pushes.push_back({0.2, glm::dvec3(600.0, 0.0, 0.0), ""});
    return p;
  };
  EvolveSettings settings = small(2, 6);
  settings.start_generations = 2;
  auto whole = Session::create(pushed(), settings).value();
  std::vector<std::string> notes;
  while (whole->runGeneration()) notes.push_back(whole->snapshot()->start);
  ASSERT_EQ(notes.size(), 6u);
  EXPECT_TRUE(whole->snapshot()->best_terms.fell);
  EXPECT_EQ(notes[0], "trying start 1 of 2 (the prior)");
  EXPECT_EQ(notes[1], "trying start 2 of 2 (stance yield 0.5)");
  EXPECT_EQ(notes[2], "trying start 2 of 2 (stance yield 0.5)");
  EXPECT_NE(notes[3].find(" kept"), std::string::npos) << notes[3];
  EXPECT_EQ(notes[5], notes[3]);
  std::printf("every run pushed over: %s, best %.2f\n", notes[5].c_str(),
              whole->snapshot()->best_terms.total);

  auto first = Session::create(pushed(), settings).value();
  for (int g = 0; g < 3; ++g) ASSERT_TRUE(first->runGeneration());
  const std::string text = first->checkpoint().dump();
  auto second = Session::resume(pushed(), nlohmann::json::parse(text)).value();
  EXPECT_EQ(second->snapshot()->start, "trying start 2 of 2 (stance yield 0.5)");
  while (second->runGeneration()) {
  }
  EXPECT_EQ(second->snapshot()->generation, 6);
  EXPECT_EQ(second->snapshot()->start, notes[5]);
  EXPECT_EQ(second->snapshot()->best_point, whole->snapshot()->best_point);
  EXPECT_EQ(second->checkpoint()["optimizer"], whole->checkpoint()["optimizer"]);
}

// Weights changed while a search runs apply from the next generation, not to the one before.
TEST(SearchSession, NewWeightsApplyFromTheNextGeneration) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  auto session = Session::create(makeProblem(biped, 1.0), small(2, 2)).value();
  ASSERT_TRUE(session->runGeneration());
  FitnessWeights weights;
  weights.energy = 0.0;
  session->setWeights(weights);
  ASSERT_TRUE(session->runGeneration());
  const auto snap = session->snapshot();
  EXPECT_GT(snap->history[0].terms[6].best, 0.0);   // energy weighed in generation 1
  EXPECT_EQ(snap->history[1].terms[6].worst, 0.0);  // and nowhere in generation 2
  EXPECT_EQ(session->problem().weights.energy, 0.0);
}

// And the kept best is scored again under them: its cost on the new scale, the one every new point
// is compared with. With its old cost kept, tripling the tracking weight left it unbeatable.
TEST(SearchSession, NewWeightsScoreTheKeptBestAgain) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  auto session = Session::create(makeProblem(biped, 1.0), small(2, 2)).value();
  ASSERT_TRUE(session->runGeneration());
  const FitnessTerms before = session->snapshot()->best_terms;
  FitnessWeights weights;
  weights.tracking *= 3.0;
  session->setWeights(weights);
  ASSERT_TRUE(session->runGeneration());
  const auto snap = session->snapshot();
  const Evaluation again = evaluate(session->problem(), snap->best_point);
  EXPECT_EQ(snap->best_terms.total, again.terms.total);
  EXPECT_EQ(snap->best_terms.tracking, again.terms.tracking);
  EXPECT_GT(snap->best_terms.total, before.total);  // every term is at least as heavy as before
  // So are the bests the optimiser compares with: the portfolio's and its trying member's (the
  // costs that choose the start that goes on), each its point's cost under the new weights.
  // The generation after the change may have beaten them: only then is a cost a new point's.
  const nlohmann::json optimizer = session->checkpoint()["optimizer"];
  ASSERT_EQ(optimizer["kind"], "portfolio");
  std::vector<nlohmann::json> states = {optimizer};
  for (const nlohmann::json& m : optimizer["members"]) states.push_back(m);
  int scored = 0;
  for (const nlohmann::json& state : states) {
    if (state["best"].empty()) continue;
    const Evaluation cost = evaluate(session->problem(), state["best"].get<std::vector<double>>());
    EXPECT_EQ(state["best_cost"].get<double>(), cost.terms.total);
    ++scored;
  }
  EXPECT_GE(scored, 2);
}

// A checkpoint resumed with robustness trials (`sinew evolve --resume --trials`: hardening a gait
// found without pushes) scores its best again under them before the first generation.
TEST(SearchSession, AResumedBestIsScoredUnderTheProblemAsItIsNow) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  auto first = Session::create(makeProblem(biped, 1.0), small(2, 2)).value();
  ASSERT_TRUE(first->runGeneration());
  Problem pushed = makeProblem(biped, 1.0);
  ASSERT_TRUE(setTrials(pushed, 3, 0.5).ok());
  auto resumed = Session::resume(pushed, first->checkpoint()).value();
  ASSERT_TRUE(resumed->runGeneration());
  const auto snap = resumed->snapshot();
  const Evaluation again = evaluate(resumed->problem(), snap->best_point);
  EXPECT_EQ(snap->best_terms.total, again.terms.total);
  EXPECT_NE(snap->best_terms.total, first->snapshot()->best_terms.total);
}

// A checkpoint keeps the servo lead its search ran with, and one from before the lead resumes
// without it: a search goes on as it was searched, whatever the problem it is resumed into.
TEST(SearchSession, ACheckpointKeepsItsServoLeadAndOneFromBeforeHasNone) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  Problem led = makeProblem(biped, 1.0);
  led.simulation.tracking.servo_lead_s = 0.02;
  led.simulation.tracking.lead_yielding_legs = true;
  auto first = Session::create(led, small(2, 2)).value();
  nlohmann::json checkpoint = first->checkpoint();
  EXPECT_EQ(checkpoint["servo_lead_s"].get<double>(), 0.02);
  EXPECT_TRUE(checkpoint["lead_yielding_legs"].get<bool>());
  auto resumed = Session::resume(makeProblem(biped, 1.0), checkpoint).value();
  EXPECT_EQ(resumed->problem().simulation.tracking.servo_lead_s, 0.02);
  EXPECT_TRUE(resumed->problem().simulation.tracking.lead_yielding_legs);
  checkpoint.erase("lead_yielding_legs");  // from before the yielding legs were led further
  resumed = Session::resume(led, checkpoint).value();
  EXPECT_FALSE(resumed->problem().simulation.tracking.lead_yielding_legs);
  checkpoint.erase("servo_lead_s");
  resumed = Session::resume(led, checkpoint).value();
  EXPECT_EQ(resumed->problem().simulation.tracking.servo_lead_s, 0.0);
  checkpoint["servo_lead_s"] = -1.0;
  EXPECT_EQ(Session::resume(led, checkpoint).message(),
            "checkpoint: servo_lead_s: expected seconds in [0, 1]");
  checkpoint["servo_lead_s"] = 0.02;
  checkpoint["lead_yielding_legs"] = "yes";
  EXPECT_EQ(Session::resume(led, checkpoint).message(),
            "checkpoint: lead_yielding_legs: expected true or false");
}

// The issue: on the stepper and the hopper a short run improves the fitness by a printed margin
// within a few generations.
TEST(SearchSession, ShortRunsImproveTheStepperAndTheHopper) {
  for (const char* file : {"stepper_step.bvh", "hopper_hop.bvh"}) {
    const physics::test_util::Character c = physics::test_util::loadCharacter(file);
    ASSERT_FALSE(c.plan.links.empty());
    EvolveSettings settings;
    // 10 generations: the hopper's sole is fitted to its clip now, and its first generation
    // starts better (28.0) and improves 8% in 6, 13% in 10 (22% in 6 before).
    settings.generations = 10;
    settings.seed = 1;
    auto session = Session::create(makeProblem(c, 4.0), settings).value();
    while (session->runGeneration()) {
    }
    const auto snap = session->snapshot();
    const double first = snap->history.front().total.best;
    const double last = snap->best_terms.total;
    std::printf("%-18s %d coordinates: best cost %.2f in generation 1 -> %.2f after %d (%.0f%% "
                "better), up %.1f of 4 s\n",
                file, session->problem().layout.size(), first, last, snap->generation,
                100.0 * (1.0 - last / first), snap->best_terms.survived_s);
    EXPECT_LT(last, 0.9 * first) << file;
  }
}

// The outcome, on a fixed budget that stays well inside 5 minutes on 2 cores: the default
// biped evolved from the DFT prior walks the 10 s window without falling, travels at least 5 m and
// keeps the style (tracking error printed and bounded).
TEST(SearchSession, TheDefaultBipedEvolvesToWalkTenSeconds) {
#ifdef SINEW_SANITIZED
  GTEST_SKIP() << "minutes of simulation under the sanitizers; the Release run measures it";
#endif
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  EvolveSettings settings;
  settings.generations = 14;
  settings.seed = 1;
  const auto t0 = std::chrono::steady_clock::now();
  auto session = Session::create(makeProblem(biped, 10.0), settings).value();
  while (session->runGeneration()) {
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto snap = session->snapshot();
  const FitnessTerms& best = snap->best_terms;
  int first_walk = 0;
  for (const GenerationRecord& r : snap->history)
    if (first_walk == 0 && r.best_survived_s >= 10.0) first_walk = r.generation;
  std::printf("biped, %d coordinates, %d generations (%lld evaluations) in %.0f s on %d threads: "
              "first 10 s walk in generation %d; best walks %.1f s, %.2f m (%.2f m/s), tracking "
              "%.2f deg RMS\n",
              session->problem().layout.size(), snap->generation, snap->evaluations, seconds,
              hardwareThreads(), first_walk, best.survived_s, best.distance_m, best.speed_m_s,
              best.track_err_rad_rms * 180.0 / 3.14159265358979);
  EXPECT_FALSE(best.fell);
  EXPECT_GE(best.distance_m, 5.0);
  // Against the clip's own motion (not the evolved target): measured 5.6 deg here, 5.3 after a
  // 5-minute run; the prior's controller tracks its target to 3.5 deg before it falls.
  EXPECT_LT(best.track_err_rad_rms * 180.0 / 3.14159265358979, 8.0);
  // The wall time is printed, not asserted: the budget is in generations, so a loaded machine
  // is slower but reaches the same result (search_bench measures the speed).
}

}  // namespace
}  // namespace sinew::search
