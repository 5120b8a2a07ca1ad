// Builds the trainer named by a behavior's `trainer_type`.
#pragma once

#include <memory>
#include <string>

#include "rl/trainer/on_policy_trainer.h"

namespace rlt {

// `ppo` or `poca`; throws std::invalid_argument for anything else.
std::unique_ptr<OnPolicyTrainer> make_trainer(const BehaviorSpec& spec, const BehaviorConfig& config,
                                              int rows, uint64_t seed, const std::string& env_name);

}  // namespace rlt
