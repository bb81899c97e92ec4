// Several starts tried in turn, the best going on: a search whose start decides where it ends.
//
// A CMA-ES seeded from a prior starts every coordinate at the same small step size (0.02), so a
// structural gene (the stance yield: legs that give on landing, or stiff ones) stays near where it
// starts for the whole budget, and which start is right depends on the clip (docs/physics.md
// "The stance yield": the Bandai tired run stands only with the yield, the iClone walk only
// without). The portfolio runs each member optimiser (one per start, the same seed) for
// `trial_generations` generations in turn, then keeps the member whose best cost is lowest (the
// first of equals) and runs it alone to the end of the budget. The caller may keep a member
// sooner (keep(): the search keeps a start as soon as its best walks the whole window, so a start
// that works costs nothing more than a plain search from it). The other members' evaluations are
// the price (measured in docs/search.md "Trying starts").
//
// A member that converges within its trial ends its trial there. Deterministic: the same members
// give the same points and results bit for bit, checkpoints included.
#pragma once

#include <memory>
#include <vector>

#include "sinew/search/optimizer.h"

namespace sinew::search {

inline constexpr int kMaxPortfolioMembers = 8;

class Portfolio final : public Optimizer {
 public:
  // Fails unless 2 to kMaxPortfolioMembers members of one dimension, none of them a portfolio,
  // none of them told anything yet, and trial_generations >= 1.
  static Result<std::unique_ptr<Portfolio>> create(std::vector<std::unique_ptr<Optimizer>> members,
                                                   int trial_generations);
  // A state saved by a Portfolio (kind "portfolio"); the message names the field that is wrong.
  static Result<std::unique_ptr<Portfolio>> load(const nlohmann::json& state);

  const char* kind() const override { return "portfolio"; }
  bool converged() const override {
    return chosen_ >= 0 && members_[static_cast<size_t>(chosen_)]->converged();
  }

  int members() const { return static_cast<int>(members_.size()); }
  int current() const { return current_; }  // the member asking now
  int chosen() const { return chosen_; }    // the member that goes on, -1 while trying
  int trialGenerations() const { return trial_generations_; }
  // Ends the trials: member i goes on alone, from its next generation. Precondition: chosen() < 0
  // and 0 <= i < members().
  void keep(int i);
  const Optimizer& member(int i) const { return *members_[static_cast<size_t>(i)]; }
  // Its own best, then each member's (what nextMember() compares when the trials end).
  std::vector<std::vector<double>> bests() const override;
  void rescore(std::span<const double> costs) override;

 private:
  Portfolio(int dimension, std::vector<std::unique_ptr<Optimizer>> members, int trial_generations);
  // After a member's generation: the next member's trial, or the choice once every member had its.
  void nextMember();

  void advance(std::span<const double> costs, const std::vector<int>& order) override;
  void saveDetails(nlohmann::json& state) const override;

  std::vector<std::unique_ptr<Optimizer>> members_;
  int trial_generations_ = 1;
  int current_ = 0;
  int chosen_ = -1;
};

}  // namespace sinew::search
