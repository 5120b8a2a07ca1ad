// The environment interface: one instance runs one episode at a time, for any number of behaviors
// and agents. Many instances are batched by VectorEnv.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "rl/env_api/recording.h"
#include "rl/env_api/spec.h"
#include "rl/env_api/step_buffers.h"

namespace rlt {

// Scalar results of one finished episode, e.g. {"success": 1} or {"tag_rate": 0}.
using EpisodeMetrics = std::map<std::string, float>;

class Env {
 public:
  virtual ~Env() = default;

  virtual const EnvSpec& spec() const = 0;

  // Reseeds the instance's random engine. The same seed and the same actions give the same
  // trajectory, bit for bit.
  virtual void seed(uint64_t seed) = 0;

  // Parameters take effect at the next reset. Names must be keys of spec().default_parameters.
  void set_parameters(const Parameters& p) {
    for (const auto& [k, v] : p) parameters_[k] = v;
  }
  float parameter(const std::string& name) const {
    auto it = parameters_.find(name);
    return it != parameters_.end() ? it->second : spec().default_parameters.at(name);
  }

  // Starts an episode: every slot becomes kFirst (an agent) or kAbsent. Rewards are 0.
  virtual void reset(StepView& out) = 0;

  // Applies the actions of every kFirst/kMid slot and writes the next step of those slots:
  // kMid, or kLast once for an agent that leaves or when the episode ends. kLast and kAbsent slots
  // become kAbsent. The vector env has already zeroed rewards and `terminated`.
  virtual void step(StepView& io) = 0;

  // Metrics of the episode that just ended (called once all agents are kLast or kAbsent). The
  // same names in every episode; also callable any time after reset() (the episode so far), which
  // is how training learns the names before its first episode ends.
  virtual EpisodeMetrics episode_metrics() const { return {}; }

  // Physics frames this instance has simulated since it was built, for envs whose step runs
  // several frames of a physics engine (`rlt bench env` reports frames per second); 0 = not counted.
  virtual uint64_t physics_frames() const { return 0; }

  // A hand-written policy for behavior `behavior` that may read the env's own state (a baseline
  // for `rlt eval --policy NAME=scripted`): writes the actions of every slot that needs one into
  // `view`. Returns false, writing nothing, when the env has none for that behavior.
  virtual bool write_scripted_actions(int /*behavior*/, BehaviorView& /*view*/) { return false; }

  // Recording for replay viewers: once on, every episode is recorded frame by frame; after an
  // episode ended, take_recording() moves it into `out`. Envs without recording return false.
  virtual void set_recording(bool /*on*/) {}
  virtual bool take_recording(EpisodeRecording& /*out*/) { return false; }

 private:
  Parameters parameters_;
};

}  // namespace rlt
