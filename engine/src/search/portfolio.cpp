#include "sinew/search/portfolio.h"

#include <string>

#include <nlohmann/json.hpp>

#include "sinew/core/assert.h"
#include "state_json.h"

namespace sinew::search {

using nlohmann::json;

namespace {

constexpr int kMaxTrialGenerations = 1000000;

// 2 to kMaxPortfolioMembers members of one dimension, none of them a portfolio.
Status checkMembers(const std::vector<std::unique_ptr<Optimizer>>& members,
                    const std::string& where) {
  if (members.size() < 2 || members.size() > static_cast<size_t>(kMaxPortfolioMembers))
    return Status::error(where + ": expected 2 to " + std::to_string(kMaxPortfolioMembers) +
                         " members, got " + std::to_string(members.size()));
  const int n = members.front()->dimension();
  for (size_t i = 0; i < members.size(); ++i) {
    const std::string which = where + ": member " + std::to_string(i);
    if (members[i]->dimension() != n)
      return Status::error(which + " has " + std::to_string(members[i]->dimension()) +
                           " coordinates, member 0 " + std::to_string(n));
    if (std::string(members[i]->kind()) == "portfolio")
      return Status::error(which + " is a portfolio");
  }
  return {};
}

}  // namespace

Portfolio::Portfolio(int dimension, std::vector<std::unique_ptr<Optimizer>> members,
                     int trial_generations)
    : Optimizer(dimension), members_(std::move(members)), trial_generations_(trial_generations) {
  points_ = members_.front()->ask();
}

Result<std::unique_ptr<Portfolio>> Portfolio::create(
    std::vector<std::unique_ptr<Optimizer>> members, int trial_generations) {
  if (Status s = checkMembers(members, "portfolio"); !s.ok()) return s;
  if (trial_generations < 1 || trial_generations > kMaxTrialGenerations)
    return Status::error("portfolio: trial_generations must be in [1, " +
                         std::to_string(kMaxTrialGenerations) + "]");
  for (size_t i = 0; i < members.size(); ++i)
    if (members[i]->generation() != 0)
      return Status::error("portfolio: member " + std::to_string(i) +
                           " has been told generations already");
  const int n = members.front()->dimension();
  return std::unique_ptr<Portfolio>(new Portfolio(n, std::move(members), trial_generations));
}

void Portfolio::nextMember() {
  if (chosen_ >= 0) return;
  const Optimizer& trying = *members_[static_cast<size_t>(current_)];
  if (trying.generation() < trial_generations_ && !trying.converged()) return;
  if (current_ + 1 < members()) {
    ++current_;
    return;
  }
  chosen_ = 0;
  for (int i = 1; i < members(); ++i)
    if (member(i).bestCost() < member(chosen_).bestCost()) chosen_ = i;
  current_ = chosen_;
}

std::vector<std::vector<double>> Portfolio::bests() const {
  std::vector<std::vector<double>> all = Optimizer::bests();
  for (const auto& m : members_)
    for (std::vector<double>& b : m->bests()) all.push_back(std::move(b));
  return all;
}

void Portfolio::rescore(std::span<const double> costs) {
  size_t used = Optimizer::bests().size();
  Optimizer::rescore(costs.first(used));
  for (const auto& m : members_) {
    const size_t n = m->bests().size();
    m->rescore(costs.subspan(used, n));
    used += n;
  }
  SINEW_ASSERT(used == costs.size(), "Portfolio::rescore: one cost a best");
}

void Portfolio::keep(int i) {
  SINEW_ASSERT(chosen_ < 0 && i >= 0 && i < members(), "Portfolio::keep: a member, once");
  chosen_ = current_ = i;
  points_ = members_[static_cast<size_t>(i)]->ask();
}

void Portfolio::advance(std::span<const double> costs, const std::vector<int>& /*order*/) {
  // The member asked for exactly these points, so it takes the same number of costs.
  const Status told = members_[static_cast<size_t>(current_)]->tell(costs);
  SINEW_ASSERT(told.ok(), "Portfolio: the member takes the costs of its own points");
  nextMember();
  points_ = members_[static_cast<size_t>(current_)]->ask();
}

void Portfolio::saveDetails(json& state) const {
  json members = json::array();
  for (const std::unique_ptr<Optimizer>& m : members_) members.push_back(m->saveState());
  state["members"] = members;
  state["trial_generations"] = trial_generations_;
  state["current"] = current_;
  state["chosen"] = chosen_;
}

Result<std::unique_ptr<Portfolio>> Portfolio::load(const json& state) {
  namespace sj = state_json;
  const std::string where = "optimizer state";
  Result<const json*> members_json = sj::field(state, "members", where);
  if (!members_json.ok()) return members_json.status();
  const json& list = *members_json.value();
  if (!list.is_array()) return Status::error(where + ": members: expected an array");
  std::vector<std::unique_ptr<Optimizer>> members;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string which = where + ": members[" + std::to_string(i) + "]";
    if (list[i].is_object() && list[i].value("kind", "") == "portfolio")
      return Status::error(which + ": a portfolio cannot hold a portfolio");  // no recursion
    Result<std::unique_ptr<Optimizer>> m = Optimizer::load(list[i]);
    if (!m.ok()) return Status::error(which + ": " + m.message());
    members.push_back(std::move(m).value());
  }
  if (Status m = checkMembers(members, where + ": members"); !m.ok()) return m;
  const int n = members.front()->dimension();
  int dimension = 0, trial = 0, current = 0, chosen = 0;
  Status s = sj::readInt(state, "dimension", where, n, n, dimension);
  if (s.ok()) s = sj::readInt(state, "trial_generations", where, 1, kMaxTrialGenerations, trial);
  const int last = static_cast<int>(members.size()) - 1;
  if (s.ok()) s = sj::readInt(state, "current", where, 0, last, current);
  if (s.ok()) s = sj::readInt(state, "chosen", where, -1, last, chosen);
  if (s.ok() && chosen >= 0 && chosen != current)
    s = Status::error(where + ": chosen: the chosen member is the one asking (current)");
  if (!s.ok()) return s;
  std::unique_ptr<Portfolio> p(new Portfolio(n, std::move(members), trial));
  p->current_ = current;
  p->chosen_ = chosen;
  if (Status common = p->loadCommon(state); !common.ok()) return common;
  if (p->points_ != p->members_[static_cast<size_t>(current)]->ask())
    return Status::error(where + ": points: not the current member's (members[" +
                         std::to_string(current) + "]) points");
  return p;
}

}  // namespace sinew::search
