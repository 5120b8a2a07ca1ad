// A finished or running training run read back from its folder: the resolved configuration and
// each behavior's network from one of its checkpoints, the newest unless told (for eval and
// export).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rl/config/run_config.h"
#include "rl/curriculum/environment_parameter_manager.h"
#include "rl/env_api/spec.h"
#include "rl/trainer/on_policy_trainer.h"
#include "rl/trainer/run_folder.h"

namespace rlt {

struct SavedRun {
  std::unique_ptr<RunFolder> folder;
  RunConfig config;
  EnvSpec env_spec;
  std::string checkpoint;                           // path of the checkpoint that was loaded
  std::vector<std::unique_ptr<OnPolicyTrainer>> trainers;  // weights and normalizers loaded
  EnvironmentParameterManager parameters;  // environment_parameters at the checkpoint's lessons
};

// checkpoint_index is the N of checkpoints/checkpoint-N.pt as training_status.json lists it; 0
// loads the newest. Throws with a message naming the folder or file when the run cannot be read,
// and listing the run's checkpoints when it has none numbered checkpoint_index.
SavedRun load_saved_run(const std::string& run_dir, int64_t checkpoint_index = 0);

}  // namespace rlt
