#include "rl/trainer/trainer_factory.h"

#include <stdexcept>

#include "rl/poca/poca_trainer.h"
#include "rl/ppo/ppo_trainer.h"

namespace rlt {

std::unique_ptr<OnPolicyTrainer> make_trainer(const BehaviorSpec& spec, const BehaviorConfig& config,
                                              int rows, uint64_t seed, const std::string& env_name) {
  if (config.trainer_type == "ppo") return std::make_unique<PpoTrainer>(spec, config, rows, seed, env_name);
  if (config.trainer_type == "poca") return std::make_unique<PocaTrainer>(spec, config, rows, seed, env_name);
  throw std::invalid_argument("behavior " + spec.name + ": trainer_type '" + config.trainer_type +
                              "' is not available");
}

}  // namespace rlt
