#include "env/classic/pendulum.h"

#include <algorithm>
#include <cmath>

#include "rl/env_api/uniform_random.h"

namespace rlt {

namespace {
constexpr double kPi = 3.141592653589793;
}  // namespace

Pendulum::Pendulum() {
  BehaviorSpec behavior;
  behavior.name = "Pendulum";
  behavior.observations.push_back({"state",
                                   {3},
                                   ObservationKind::kVector,
                                   -static_cast<float>(kMaxSpeed),
                                   static_cast<float>(kMaxSpeed)});
  behavior.action.continuous_size = 1;
  behavior.agent_slots = 1;
  spec_.name = "Pendulum";
  spec_.behaviors.push_back(behavior);
  spec_.max_episode_steps = kMaxEpisodeSteps;
  spec_.default_parameters = {{"g", kDefaultGravity}};
}

void Pendulum::seed(uint64_t seed) { engine_.seed(seed); }

double Pendulum::angle_normalize(double x) {
  // Python's float modulo takes the sign of the divisor
  const double two_pi = 2 * kPi;
  double r = std::fmod(x + kPi, two_pi);
  if (r < 0) r += two_pi;
  return r - kPi;
}

void Pendulum::write_observation(BehaviorView& view) const {
  float* obs = view.observation(0);  // [3]
  obs[0] = static_cast<float>(std::cos(state_.theta));
  obs[1] = static_cast<float>(std::sin(state_.theta));
  obs[2] = static_cast<float>(state_.theta_dot);
}

void Pendulum::reset(StepView& out) {
  gravity_ = parameter("g");
  // start state: th uniform in [-pi, pi], then thdot uniform in [-1, 1]
  state_.theta = uniform(engine_, -kPi, kPi);
  state_.theta_dot = uniform(engine_, -1.0, 1.0);
  elapsed_steps_ = 0;

  BehaviorView& view = out[0];
  view.step_type(0) = StepType::kFirst;
  view.agent_id(0) = 0;
  view.group_id(0) = 0;
  view.reward(0) = 0.f;
  view.group_reward(0) = 0.f;
  view.terminated(0) = 0;
  write_observation(view);
}

void Pendulum::step(StepView& io) {
  BehaviorView& view = io[0];
  // a finished agent does not come back before the next reset
  if (!needs_action(view.step_type(0))) {
    view.step_type(0) = StepType::kAbsent;
    view.agent_id(0) = -1;
    return;
  }
  const double u = kMaxTorque * std::clamp(double(view.continuous_action(0)[0]), -1.0, 1.0);
  const double th = state_.theta;
  const double thdot = state_.theta_dot;

  // cost of the state the action was taken in
  const double norm_th = angle_normalize(th);
  const double costs = norm_th * norm_th + 0.1 * (thdot * thdot) + 0.001 * (u * u);

  // semi-implicit Euler: new speed (clipped), then new angle from the new speed
  const double g = gravity_;
  double newthdot =
      thdot + (3 * g / (2 * kLength) * std::sin(th) + 3.0 / (kMass * kLength * kLength) * u) * kDt;
  newthdot = std::clamp(newthdot, -kMaxSpeed, kMaxSpeed);
  state_.theta = th + newthdot * kDt;
  state_.theta_dot = newthdot;
  ++elapsed_steps_;

  view.reward(0) = static_cast<float>(-costs);
  write_observation(view);
  // never terminates; truncated after 200 steps
  view.step_type(0) = elapsed_steps_ >= kMaxEpisodeSteps ? StepType::kLast : StepType::kMid;
  view.terminated(0) = 0;
}

}  // namespace rlt
