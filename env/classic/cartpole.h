// CartPole: a pole hinged on a cart; push the cart left or right to keep the pole upright.
//
// Reproduces Gymnasium's CartPole-v1 (`gymnasium/envs/classic_control/cartpole.py` with the
// TimeLimit of 500 steps from its registration): Euler integration, +1 reward on every step
// including the terminating one, termination when |x| > 2.4 or |theta| > 12 degrees, truncation
// after 500 steps, start state uniform in [-0.05, 0.05]^4. The state is kept in double and written
// as float, as Gymnasium does; the physics uses the same expressions in the same order.
//
// Deliberate differences:
// - random numbers come from std::mt19937_64, not numpy's PCG64: same distribution, other values;
// - one observation bound for all four values (the spec allows one low/high per observation):
//   +-200, which provably holds. Non-terminal states have |theta| <= 0.21, so |theta_dot| stays
//   below 2 * 0.21 / tau + 2 * tau * max|theta_acc| < 22 and |x_acc| < 15; over at most 500 steps
//   |x_dot| < 0.05 + 500 * tau * 15 = 150.05, hence |x| < 2.4 + tau * 150.05 < 5.5.
#pragma once

#include <cstdint>
#include <random>

#include "rl/env_api/env.h"

namespace rlt {

class CartPole : public Env {
 public:
  // physical state, in SI units
  struct State {
    double x = 0;          // cart position (m)
    double x_dot = 0;      // cart velocity (m/s)
    double theta = 0;      // pole angle from upright (rad)
    double theta_dot = 0;  // pole angular velocity (rad/s)
  };

  // constants of CartPole-v1
  static constexpr double kGravity = 9.8;
  static constexpr double kMassCart = 1.0;
  static constexpr double kMassPole = 0.1;
  static constexpr double kTotalMass = kMassPole + kMassCart;
  static constexpr double kLength = 0.5;  // half the pole's length
  static constexpr double kPoleMassLength = kMassPole * kLength;
  static constexpr double kForceMag = 10.0;
  static constexpr double kTau = 0.02;  // seconds per step
  static constexpr double kThetaThreshold = 12 * 2 * 3.141592653589793 / 360;
  static constexpr double kXThreshold = 2.4;
  static constexpr int kMaxEpisodeSteps = 500;
  static constexpr float kObservationBound = 200.f;

  CartPole();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  // one behavior "CartPole", one agent (id 0) observing "state" = (x, x_dot, theta, theta_dot)
  void reset(StepView& out) override;
  // discrete action 0 pushes the cart left, 1 pushes it right
  void step(StepView& io) override;

  // test hooks: the state the next step starts from, and decisions taken in this episode
  void set_state(const State& state) { state_ = state; }
  const State& state() const { return state_; }
  int elapsed_steps() const { return elapsed_steps_; }

 private:
  void write_observation(BehaviorView& view) const;

  EnvSpec spec_;
  std::mt19937_64 engine_;
  State state_;
  int elapsed_steps_ = 0;
};

}  // namespace rlt
