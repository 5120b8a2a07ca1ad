#include "env/classic/cartpole.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "rl/env_api/uniform_random.h"

namespace rlt {

CartPole::CartPole() {
  BehaviorSpec behavior;
  behavior.name = "CartPole";
  behavior.observations.push_back(
      {"state", {4}, ObservationKind::kVector, -kObservationBound, kObservationBound});
  behavior.action.discrete_branches = {2};
  behavior.agent_slots = 1;
  spec_.name = "CartPole";
  spec_.behaviors.push_back(behavior);
  spec_.max_episode_steps = kMaxEpisodeSteps;
}

void CartPole::seed(uint64_t seed) { engine_.seed(seed); }

void CartPole::write_observation(BehaviorView& view) const {
  float* obs = view.observation(0);  // [4]
  obs[0] = static_cast<float>(state_.x);
  obs[1] = static_cast<float>(state_.x_dot);
  obs[2] = static_cast<float>(state_.theta);
  obs[3] = static_cast<float>(state_.theta_dot);
}

void CartPole::reset(StepView& out) {
  // start state uniform in [-0.05, 0.05]^4, drawn in the order x, x_dot, theta, theta_dot
  state_.x = uniform(engine_, -0.05, 0.05);
  state_.x_dot = uniform(engine_, -0.05, 0.05);
  state_.theta = uniform(engine_, -0.05, 0.05);
  state_.theta_dot = uniform(engine_, -0.05, 0.05);
  elapsed_steps_ = 0;

  BehaviorView& view = out[0];
  view.step_type(0) = StepType::kFirst;
  view.agent_id(0) = 0;
  view.group_id(0) = 0;
  view.reward(0) = 0.f;
  view.group_reward(0) = 0.f;
  view.terminated(0) = 0;
  view.action_mask(0)[0] = view.action_mask(0)[1] = 1;
  write_observation(view);
}

void CartPole::step(StepView& io) {
  BehaviorView& view = io[0];
  // a finished agent does not come back before the next reset
  if (!needs_action(view.step_type(0))) {
    view.step_type(0) = StepType::kAbsent;
    view.agent_id(0) = -1;
    return;
  }
  const int action = view.discrete_action(0)[0];
  if (action != 0 && action != 1)
    throw std::invalid_argument("CartPole: action " + std::to_string(action) + " is not 0 or 1");

  // cart-pole equations of motion (Florian 2007), same operation order as Gymnasium
  const double force = action == 1 ? kForceMag : -kForceMag;
  const double costheta = std::cos(state_.theta);
  const double sintheta = std::sin(state_.theta);
  const double temp =
      (force + kPoleMassLength * (state_.theta_dot * state_.theta_dot) * sintheta) / kTotalMass;
  const double thetaacc = (kGravity * sintheta - costheta * temp) /
                          (kLength * (4.0 / 3.0 - kMassPole * (costheta * costheta) / kTotalMass));
  const double xacc = temp - kPoleMassLength * thetaacc * costheta / kTotalMass;

  // explicit Euler
  state_.x = state_.x + kTau * state_.x_dot;
  state_.x_dot = state_.x_dot + kTau * xacc;
  state_.theta = state_.theta + kTau * state_.theta_dot;
  state_.theta_dot = state_.theta_dot + kTau * thetaacc;
  ++elapsed_steps_;

  // +1 for every step, the terminating one included
  const bool terminated = state_.x < -kXThreshold || state_.x > kXThreshold ||
                          state_.theta < -kThetaThreshold || state_.theta > kThetaThreshold;
  const bool truncated = elapsed_steps_ >= kMaxEpisodeSteps;
  view.reward(0) = 1.f;
  write_observation(view);
  if (terminated || truncated) {
    view.step_type(0) = StepType::kLast;
    view.terminated(0) = terminated ? 1 : 0;
  } else {
    view.step_type(0) = StepType::kMid;
  }
}

}  // namespace rlt
