#include "rl/selfplay/self_play.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rl/core/archive_io.h"
#include "rl/env_api/uniform_random.h"

namespace rlt {

SelfPlay::SelfPlay(std::vector<OnPolicyTrainer*> trainers, uint64_t seed)
    : trainers_(std::move(trainers)), rng_(seed) {
  for (int b = 0; b < int(trainers_.size()); ++b) {
    if (!trainers_[b]->config().self_play) continue;
    Pool pool;
    pool.behavior = b;
    pool.elo = settings(b).initial_elo;
    pool.snapshots.push_back(snapshot_of(b));  // the initial policy is the first opponent
    pool.snapshots.back().elo = pool.elo;
    pool.next_slot = 1 % settings(b).window;
    pools_.push_back(std::move(pool));
  }
}

const SelfPlaySettings& SelfPlay::settings(int behavior) const {
  return *trainers_[behavior]->config().self_play;
}

SelfPlay::Pool* SelfPlay::pool_of(int behavior) {
  for (auto& p : pools_)
    if (p.behavior == behavior) return &p;
  return nullptr;
}

SelfPlay::Snapshot SelfPlay::snapshot_of(int behavior) const {
  Snapshot s;
  for (const auto& p : trainers_[behavior]->network()->parameters()) s.weights.push_back(p.detach().clone());
  if (const auto* n = trainers_[behavior]->normalizer()) s.normalizer = n->serialize();
  return s;
}

FastActor SelfPlay::actor_of(int behavior, const Snapshot& s) const {
  // load the snapshot into the trainer's own network for the copy, then put its weights back
  torch::NoGradGuard no_grad;
  auto params = trainers_[behavior]->network()->parameters();
  std::vector<torch::Tensor> saved;
  for (size_t i = 0; i < params.size(); ++i) {
    saved.push_back(params[i].detach().clone());
    params[i].copy_(s.weights[i]);
  }
  FastActor actor;
  if (s.normalizer.empty()) {
    actor.copy_from(*trainers_[behavior]->network(), nullptr);
  } else {
    RunningNormalizer normalizer = RunningNormalizer::deserialize(s.normalizer);
    actor.copy_from(*trainers_[behavior]->network(), &normalizer);
  }
  for (size_t i = 0; i < params.size(); ++i) params[i].copy_(saved[i]);
  return actor;
}

bool SelfPlay::is_learning(int behavior, int group) const {
  if (teams_.empty()) return true;
  const Team& t = teams_[learning_team_];
  return t.behavior == behavior && t.group == group;
}

bool SelfPlay::learns(int behavior) const {
  const bool self_play = std::any_of(pools_.begin(), pools_.end(),
                                     [&](const Pool& p) { return p.behavior == behavior; });
  return teams_.empty() || !self_play || teams_[learning_team_].behavior == behavior;
}

void SelfPlay::select_rows(const std::vector<BehaviorBuffers*>& buffers,
                           std::vector<std::vector<uint8_t>>& learner_rows) {
  // discover the teams of self-play behaviors from the agents present
  const size_t known = teams_.size();
  for (const auto& pool : pools_) {
    const BehaviorBuffers& buf = *buffers[pool.behavior];
    for (int r = 0; r < buf.rows; ++r) {
      if (buf.step_type[r] == StepType::kAbsent) continue;
      Team t{pool.behavior, buf.group_id[r]};
      auto it = std::find_if(teams_.begin(), teams_.end(),
                             [&](const Team& x) { return x.behavior == t.behavior && x.group == t.group; });
      if (it == teams_.end()) teams_.push_back(t);
    }
  }
  if (teams_.size() != known) {
    std::sort(teams_.begin(), teams_.end(), [](const Team& a, const Team& b) {
      return a.behavior != b.behavior ? a.behavior < b.behavior : a.group < b.group;
    });
    if (known == 0) {
      learning_team_ = 0;
      last_team_change_ = trainers_[teams_[0].behavior]->step();
      swap_opponents();
    }
  }
  learner_rows.resize(buffers.size());
  for (size_t b = 0; b < buffers.size(); ++b) {
    const BehaviorBuffers& buf = *buffers[b];
    learner_rows[b].assign(buf.rows, 1);
    if (!pool_of(int(b))) continue;
    for (int r = 0; r < buf.rows; ++r) learner_rows[b][r] = is_learning(int(b), buf.group_id[r]);
  }
}

void SelfPlay::act_opponents(std::vector<BehaviorBuffers*>& buffers,
                             const std::vector<std::vector<uint8_t>>& learner_rows) {
  for (auto& pool : pools_) {
    BehaviorBuffers& buf = *buffers[pool.behavior];
    opponent_rows_.assign(buf.rows, 0);
    for (int r = 0; r < buf.rows; ++r) {
      opponent_rows_[r] = !learner_rows[pool.behavior][r];
      ghost_steps_ += opponent_rows_[r] && needs_action(buf.step_type[r]);
    }
    pool.opponent_policy->act(buf, &opponent_rows_);
  }
}

double SelfPlay::opponent_elo() const {
  // the other team's behavior pool; with one behavior, the same pool
  const Team& learner = teams_[learning_team_];
  for (const auto& team : teams_) {
    if (team.behavior == learner.behavior && team.group == learner.group) continue;
    for (const auto& pool : pools_)
      if (pool.behavior == team.behavior)
        return pool.opponent >= 0 ? pool.snapshots[pool.opponent].elo : pool.elo;
  }
  return 0;
}

void SelfPlay::after_step(const std::vector<BehaviorBuffers*>& buffers,
                          const std::vector<std::vector<uint8_t>>& learner_rows) {
  if (teams_.empty()) return;
  const Team learner = teams_[learning_team_];
  Pool& pool = *pool_of(learner.behavior);
  const SelfPlaySettings& sp = settings(learner.behavior);
  // ELO from every learning agent that just finished its episode
  const BehaviorBuffers& buf = *buffers[learner.behavior];
  for (int r = 0; r < buf.rows; ++r) {
    if (!learner_rows[learner.behavior][r] || buf.step_type[r] != StepType::kLast) continue;
    const float final_reward = buf.reward[r] + buf.group_reward[r];
    const double result = final_reward > 0 ? 1.0 : (final_reward < 0 ? 0.0 : 0.5);
    const double mine = std::pow(10.0, pool.elo / 400.0), theirs = std::pow(10.0, opponent_elo() / 400.0);
    const double change = 16.0 * (result - mine / (mine + theirs));
    pool.elo += change;
    // the opponent snapshot's rating moves the other way (not when it is the learner itself)
    for (const auto& team : teams_) {
      if (team.behavior == learner.behavior && team.group == learner.group) continue;
      Pool* other = pool_of(team.behavior);
      if (other->opponent >= 0) other->snapshots[other->opponent].elo -= change;
      break;
    }
  }
  // snapshots of the learning behavior
  const int64_t steps = trainers_[learner.behavior]->step();
  if (steps - pool.last_save >= sp.save_steps) {
    Snapshot s = snapshot_of(learner.behavior);
    s.elo = pool.elo;
    if (int(pool.snapshots.size()) < sp.window)
      pool.snapshots.push_back(std::move(s));
    else
      pool.snapshots[pool.next_slot] = std::move(s);
    pool.next_slot = (pool.next_slot + 1) % sp.window;
    pool.last_save = steps;
  }
  // the learning team changes every team_change steps of its behavior, and as soon as its
  // behavior reached max_steps (its steps would otherwise run on, unused, until team_change)
  bool swap = ghost_steps_ - last_swap_ >= sp.swap_steps;
  const bool learner_done = trainers_[learner.behavior]->finished();
  if (teams_.size() > 1 && (steps - last_team_change_ >= sp.team_change || learner_done)) {
    const int n = int(teams_.size());
    int next = (learning_team_ + 1) % n;
    // the next team whose behavior still trains (the same team when every other one is done)
    for (int k = 1; k < n && trainers_[teams_[next].behavior]->finished(); ++k) next = (next + 1) % n;
    if (next != learning_team_ && !(learner_done && trainers_[teams_[next].behavior]->finished())) {
      // the team that stops learning ends its running trajectories here, bootstrapped from where
      // they stopped: a snapshot plays its rows from now on, and its next turn starts in other
      // episodes, which must not be appended to these
      trainers_[learner.behavior]->interrupt_all(*buffers[learner.behavior]);
      learning_team_ = next;
      last_team_change_ = trainers_[teams_[learning_team_].behavior]->step();
      ++team_changes_;
      swap = true;
    }
  }
  if (swap) {
    swap_opponents();
    last_swap_ = ghost_steps_;
  }
}

void SelfPlay::set_opponent(Pool& pool, int index, uint64_t policy_seed) {
  pool.opponent = index;
  if (index < 0) pool.current = snapshot_of(pool.behavior);
  const Snapshot& s = index < 0 ? pool.current : pool.snapshots[index];
  pool.opponent_policy = std::make_unique<NetworkPolicy>(
      actor_of(pool.behavior, s), trainers_[pool.behavior]->obs_size(), false, policy_seed);
}

void SelfPlay::swap_opponents() {
  for (auto& pool : pools_) {
    const double u = uniform01(rng_);
    int index = -1;
    if (u >= settings(pool.behavior).play_against_latest_model_ratio)
      index = uniform_int(rng_, int(pool.snapshots.size()));
    set_opponent(pool, index, rng_());
  }
}

std::vector<double> SelfPlay::elo_state() const {
  std::vector<double> state;
  for (const Pool& pool : pools_) {
    state.push_back(pool.elo);
    const int window = settings(pool.behavior).window;  // [window] snapshot ratings, 0 if empty
    for (int i = 0; i < window; ++i)
      state.push_back(i < int(pool.snapshots.size()) ? pool.snapshots[i].elo : 0.0);
  }
  return state;
}

void SelfPlay::set_elo_state(const std::vector<double>& state) {
  size_t at = 0;
  for (Pool& pool : pools_) {
    pool.elo = state.at(at++);
    const int window = settings(pool.behavior).window;
    for (int i = 0; i < window; ++i, ++at)
      if (i < int(pool.snapshots.size())) pool.snapshots[i].elo = state.at(at);
  }
}

double SelfPlay::elo(int b) const {
  for (const auto& p : pools_)
    if (p.behavior == b) return p.elo;
  return trainers_[b]->config().self_play ? settings(b).initial_elo : 0.0;
}

std::string SelfPlay::learning_team_name() const {
  if (teams_.empty()) return "";
  const Team& t = teams_[learning_team_];
  return trainers_[t.behavior]->behavior() + ":" + std::to_string(t.group);
}

const std::map<std::string, float>& SelfPlay::turn_parameters() const {
  static const std::map<std::string, float> none;
  if (teams_.empty()) return none;
  const int b = teams_[learning_team_].behavior;
  return trainers_[b]->config().self_play ? settings(b).turn_parameters : none;
}

void SelfPlay::save(torch::serialize::OutputArchive& a) const {
  std::ostringstream rng;
  rng << rng_;
  write_string(a, "rng", rng.str());
  write_vector(a, "counters", std::vector<int64_t>{learning_team_, last_team_change_, ghost_steps_, last_swap_});
  std::vector<int32_t> teams;
  for (const auto& t : teams_) teams.insert(teams.end(), {t.behavior, t.group});
  write_vector(a, "teams", teams);
  for (size_t p = 0; p < pools_.size(); ++p) {
    const Pool& pool = pools_[p];
    const std::string key = "pool" + std::to_string(p) + ".";
    write_vector(a, key + "state", std::vector<double>{pool.elo, double(pool.opponent),
                                                       double(pool.next_slot), double(pool.last_save)});
    write_vector(a, key + "size", std::vector<int64_t>{int64_t(pool.snapshots.size())});
    auto save_snapshot = [&](const std::string& k, const Snapshot& s) {
      for (size_t w = 0; w < s.weights.size(); ++w) a.write(k + "w" + std::to_string(w), s.weights[w]);
      write_string(a, k + "normalizer", s.normalizer);
      write_vector(a, k + "elo", std::vector<double>{s.elo});
    };
    for (size_t s = 0; s < pool.snapshots.size(); ++s) save_snapshot(key + "s" + std::to_string(s) + ".", pool.snapshots[s]);
    if (pool.opponent < 0) save_snapshot(key + "current.", pool.current);
    write_string(a, key + "opponent_rng", pool.opponent_policy ? pool.opponent_policy->engine_state() : "");
  }
}

void SelfPlay::load(torch::serialize::InputArchive& a) {
  std::istringstream rng(read_string(a, "rng"));
  rng >> rng_;
  auto counters = read_vector<int64_t>(a, "counters");
  learning_team_ = int(counters.at(0));
  last_team_change_ = counters.at(1);
  ghost_steps_ = counters.at(2);
  last_swap_ = counters.at(3);
  auto teams = read_vector<int32_t>(a, "teams");
  teams_.clear();
  for (size_t i = 0; i + 1 < teams.size(); i += 2) teams_.push_back({teams[i], teams[i + 1]});
  for (size_t p = 0; p < pools_.size(); ++p) {
    Pool& pool = pools_[p];
    const std::string key = "pool" + std::to_string(p) + ".";
    auto state = read_vector<double>(a, key + "state");
    pool.elo = state.at(0);
    pool.opponent = int(state.at(1));
    pool.next_slot = int(state.at(2));
    pool.last_save = int64_t(state.at(3));
    const int64_t size = read_vector<int64_t>(a, key + "size").at(0);
    const size_t weights = trainers_[pool.behavior]->network()->parameters().size();
    auto load_snapshot = [&](const std::string& k) {
      Snapshot s;
      for (size_t w = 0; w < weights; ++w) {
        torch::Tensor t;
        a.read(k + "w" + std::to_string(w), t);
        s.weights.push_back(t);
      }
      s.normalizer = read_string(a, k + "normalizer");
      s.elo = read_vector<double>(a, k + "elo").at(0);
      return s;
    };
    pool.snapshots.clear();
    for (int64_t s = 0; s < size; ++s) pool.snapshots.push_back(load_snapshot(key + "s" + std::to_string(s) + "."));
    if (pool.opponent < 0) pool.current = load_snapshot(key + "current.");
    const Snapshot& s = pool.opponent < 0 ? pool.current : pool.snapshots[pool.opponent];
    pool.opponent_policy = std::make_unique<NetworkPolicy>(
        actor_of(pool.behavior, s), trainers_[pool.behavior]->obs_size(), false, 0);
    const std::string engine = read_string(a, key + "opponent_rng");
    if (!engine.empty()) pool.opponent_policy->set_engine_state(engine);
  }
}

}  // namespace rlt
