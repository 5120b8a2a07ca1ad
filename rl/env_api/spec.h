// Specs of a multi-agent environment: what each behavior observes and how it acts.
//
// Follows the shape of Unity ML-Agents' `mlagents_envs/base_env.py` (BehaviorSpec, ActionSpec with
// continuous actions plus discrete branches) and EnvPool's `env_spec.h`. This header, like the rest of
// rl/env_api, never includes LibTorch: environments depend on it alone.
#pragma once

#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

namespace rlt {

// Named float parameters applied at reset (curriculum level, reward sizes, ...).
using Parameters = std::map<std::string, float>;

// Actions of one agent: `continuous_size` floats in [-1, 1] and one integer per discrete branch.
struct ActionSpec {
  int continuous_size = 0;             // number of continuous actions, each in [-1, 1]
  std::vector<int> discrete_branches;  // number of options of each discrete branch

  int num_branches() const { return static_cast<int>(discrete_branches.size()); }
  // total number of discrete options; the width of an action mask row
  int mask_size() const {
    return std::accumulate(discrete_branches.begin(), discrete_branches.end(), 0);
  }
  bool is_hybrid() const { return continuous_size > 0 && num_branches() > 0; }
};

enum class ObservationKind { kVector, kGrid };

struct ObservationSpec {
  std::string name;
  std::vector<int> shape;  // vector: {size}; grid: {height, width, channels}
  ObservationKind kind = ObservationKind::kVector;
  float low = -std::numeric_limits<float>::infinity();   // every value is >= low
  float high = std::numeric_limits<float>::infinity();   // every value is <= high

  // number of floats of one observation
  int size() const {
    return std::accumulate(shape.begin(), shape.end(), 1, [](int a, int b) { return a * b; });
  }
};

// One role in the environment, with a fixed number of agent slots per env instance.
struct BehaviorSpec {
  std::string name;
  std::vector<ObservationSpec> observations;
  ActionSpec action;
  int agent_slots = 1;  // the most agents of this behavior alive at once in one env instance
};

// A behavior the env can recognise in its episode metrics (an emergent strategy, a skill). Training
// follows the metric's mean over the last `window` qualifying episodes and records the first step
// of `behavior` at which it exceeds `threshold`: the step the strategy emerged.
struct StrategySpec {
  std::string name;      // e.g. "running_and_chasing"
  std::string metric;    // key of Env::episode_metrics(), a rate in [0, 1]
  std::string behavior;  // whose steps date the emergence
  float threshold = 0.5f;
  int window = 100;      // episodes in the smoothed rate
  // only episodes in which every listed value is at or above its bound count (empty: all); a
  // value is the episode's metric of that name when the env reports one, else its parameter
  // (a metric can say what a parameter did, e.g. nothing at some levels)
  struct AtLeast {
    std::string parameter;
    float value = 0.f;
  };
  std::vector<AtLeast> conditions;

  // "level >= 2 and prop_start_offset >= 1", or "" without conditions
  std::string describe_conditions() const {
    std::string out;
    for (const AtLeast& c : conditions) {
      if (!out.empty()) out += " and ";
      std::string v = std::to_string(c.value);
      v.erase(v.find_last_not_of('0') + 1);
      if (!v.empty() && v.back() == '.') v.pop_back();
      out += c.parameter + " >= " + v;
    }
    return out;
  }
};

struct EnvSpec {
  std::string name;
  std::vector<BehaviorSpec> behaviors;
  int max_episode_steps = 0;     // decisions after which an episode is truncated
  Parameters default_parameters;  // every parameter the env understands, with its default
  std::vector<StrategySpec> strategies;  // recognised in episode metrics (may be empty)

  // index of the behavior called `name`, or -1
  int behavior_index(const std::string& name) const {
    for (size_t i = 0; i < behaviors.size(); ++i)
      if (behaviors[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

}  // namespace rlt
