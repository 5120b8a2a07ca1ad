// Runs episodes with fixed policies and reports returns and the env's episode metrics.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rl/env_api/vector_env.h"
#include "rl/trainer/behavior_policy.h"

namespace rlt {

struct BehaviorEvaluation {
  std::string behavior;
  std::vector<float> returns;  // per agent episode
  std::vector<float> lengths;  // decisions per agent episode
};

struct Evaluation {
  int episodes = 0;                          // env episodes counted
  std::vector<BehaviorEvaluation> behaviors; // in env spec order
  std::map<std::string, double> metrics;     // mean of each episode metric over the episodes
  std::vector<std::shared_ptr<EpisodeRecording>> recordings;  // of the counted episodes, if on
};

// Plays `episodes` env episodes on `env` (already configured) with one policy per behavior.
// The first `episodes` env episodes to end count (ties broken by env index), with the agent
// episodes that belong to them; results depend only on the env's seeds and the policies.
Evaluation evaluate(VectorEnv& env, std::vector<std::unique_ptr<BehaviorPolicy>>& policies,
                    int episodes);

}  // namespace rlt
