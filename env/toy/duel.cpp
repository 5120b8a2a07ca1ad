#include "env/toy/duel.h"

#include <algorithm>
#include <cmath>

#include "rl/env_api/uniform_random.h"

namespace rlt {

namespace {
constexpr double kTwoPi = 6.283185307179586;
}  // namespace

Duel::Duel() {
  BehaviorSpec behavior;
  behavior.name = "Duelist";
  behavior.observations.push_back(
      {"state", {kObservationSize}, ObservationKind::kVector, -1.f, 1.f});
  behavior.action.continuous_size = 2;
  behavior.agent_slots = kPlayers;
  spec_.name = "Duel";
  spec_.behaviors.push_back(behavior);
  spec_.max_episode_steps = kEpisodeSteps;
}

void Duel::seed(uint64_t seed) { engine_.seed(seed); }

void Duel::write_observation(BehaviorView& view, int slot) const {
  const Vec2& me = players_[slot];
  const Vec2& other = players_[1 - slot];
  const double dx = target_.x - me.x, dy = target_.y - me.y;
  const double d = std::hypot(dx, dy);
  float* obs = view.observation(slot, 0);  // [10]
  obs[0] = static_cast<float>(me.x);
  obs[1] = static_cast<float>(me.y);
  obs[2] = static_cast<float>(other.x);
  obs[3] = static_cast<float>(other.y);
  obs[4] = static_cast<float>(target_.x);
  obs[5] = static_cast<float>(target_.y);
  obs[6] = d > 1e-9 ? static_cast<float>(dx / d) : 0.f;
  obs[7] = d > 1e-9 ? static_cast<float>(dy / d) : 0.f;
  obs[8] = static_cast<float>(d / kDiagonal);
  obs[9] = static_cast<float>(elapsed_) / static_cast<float>(kEpisodeSteps);
}

void Duel::reset(StepView& out) {
  // a target, then one distance and two directions that keep both players in the square
  target_ = {uniform(engine_, -kTargetRange, kTargetRange),
             uniform(engine_, -kTargetRange, kTargetRange)};
  const double d = uniform(engine_, kMinDistance, kMaxDistance);
  for (int s = 0; s < kPlayers; ++s) {
    Vec2 p;
    do {
      const double angle = uniform(engine_, 0.0, kTwoPi);
      p = {target_.x + d * std::cos(angle), target_.y + d * std::sin(angle)};
    } while (std::fabs(p.x) > 1.0 || std::fabs(p.y) > 1.0);
    players_[s] = p;
  }
  elapsed_ = 0;
  winner_ = -1;

  BehaviorView& view = out[0];
  for (int s = 0; s < kPlayers; ++s) {
    view.step_type(s) = StepType::kFirst;
    view.agent_id(s) = s;
    view.group_id(s) = s;
    view.reward(s) = 0.f;
    view.group_reward(s) = 0.f;
    view.terminated(s) = 0;
    write_observation(view, s);
  }
}

void Duel::step(StepView& io) {
  BehaviorView& view = io[0];
  // both players always end together: a slot that did not act stays absent
  if (!needs_action(view.step_type(0))) {
    for (int s = 0; s < kPlayers; ++s) {
      view.step_type(s) = StepType::kAbsent;
      view.agent_id(s) = -1;
    }
    return;
  }

  // moves: velocity clipped per axis and to length 1
  std::array<bool, kPlayers> touch{};
  for (int s = 0; s < kPlayers; ++s) {
    const float* a = view.continuous_action(s);  // [2]
    double vx = std::clamp(static_cast<double>(a[0]), -1.0, 1.0);
    double vy = std::clamp(static_cast<double>(a[1]), -1.0, 1.0);
    const double norm = std::sqrt(vx * vx + vy * vy);
    if (norm > 1.0) {
      vx /= norm;
      vy /= norm;
    }
    Vec2& p = players_[s];
    p.x = std::clamp(p.x + kSpeed * vx, -1.0, 1.0);
    p.y = std::clamp(p.y + kSpeed * vy, -1.0, 1.0);
    touch[s] = std::hypot(p.x - target_.x, p.y - target_.y) < kTouchRadius;
  }
  ++elapsed_;

  // outcome
  const bool decided = touch[0] || touch[1];
  if (touch[0] != touch[1]) winner_ = touch[0] ? 0 : 1;
  const bool timeout = !decided && elapsed_ >= kEpisodeSteps;
  for (int s = 0; s < kPlayers; ++s) {
    write_observation(view, s);
    if (winner_ >= 0) view.reward(s) = winner_ == s ? 1.f : -1.f;
    if (decided || timeout) {
      view.step_type(s) = StepType::kLast;
      view.terminated(s) = decided ? 1 : 0;
    } else {
      view.step_type(s) = StepType::kMid;
    }
  }
}

EpisodeMetrics Duel::episode_metrics() const {
  const float win = winner_ == 0 ? 1.f : winner_ == 1 ? 0.f : 0.5f;
  return {{"win_team0", win}, {"draw", winner_ < 0 ? 1.f : 0.f}};
}

}  // namespace rlt
