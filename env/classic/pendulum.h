// Pendulum: swing a pendulum up from a random angle and hold it upright with a limited torque.
//
// Reproduces Gymnasium's Pendulum-v1 (`gymnasium/envs/classic_control/pendulum.py` with the
// TimeLimit of 200 steps from its registration): max speed 8, max torque 2, dt 0.05, m = l = 1,
// reward -(angle_normalize(th)^2 + 0.1 thdot^2 + 0.001 u^2) for the state before the step,
// observation (cos th, sin th, thdot), start th uniform in [-pi, pi], thdot uniform in [-1, 1];
// it never terminates and is truncated after 200 steps. Parameter "g" (default 10) is read at
// reset.
//
// Deliberate differences:
// - the action is one continuous value in [-1, 1] (clipped to it), scaled by the max torque 2;
// - every operation is in double (with NumPy 2, Gymnasium rounds the torque terms through float32:
//   differences stay below 1e-6); "g" is a float parameter, so g = 9.81 means float(9.81);
// - random numbers come from std::mt19937_64, not numpy's PCG64.
#pragma once

#include <cstdint>
#include <random>

#include "rl/env_api/env.h"

namespace rlt {

class Pendulum : public Env {
 public:
  struct State {
    double theta = 0;      // angle from upright (rad), not wrapped
    double theta_dot = 0;  // angular velocity (rad/s), in [-8, 8]
  };

  // constants of Pendulum-v1
  static constexpr double kMaxSpeed = 8.0;
  static constexpr double kMaxTorque = 2.0;
  static constexpr double kDt = 0.05;
  static constexpr double kMass = 1.0;
  static constexpr double kLength = 1.0;
  static constexpr float kDefaultGravity = 10.f;
  static constexpr int kMaxEpisodeSteps = 200;

  Pendulum();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  // one behavior "Pendulum", one agent (id 0) observing "state" = (cos th, sin th, thdot)
  void reset(StepView& out) override;
  // continuous action in [-1, 1]: torque = 2 * clip(action, -1, 1)
  void step(StepView& io) override;

  // angle wrapped into [-pi, pi), as Python's ((x + pi) % (2 pi)) - pi
  static double angle_normalize(double x);

  // test hooks: the state the next step starts from, gravity in use, decisions in this episode
  void set_state(const State& state) { state_ = state; }
  const State& state() const { return state_; }
  double gravity() const { return gravity_; }
  int elapsed_steps() const { return elapsed_steps_; }

 private:
  void write_observation(BehaviorView& view) const;

  EnvSpec spec_;
  std::mt19937_64 engine_;
  State state_;
  double gravity_ = kDefaultGravity;
  int elapsed_steps_ = 0;
};

}  // namespace rlt
