#include <iostream>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "rl/core/policy_export.h"
#include "rl/trainer/saved_run.h"

namespace rlt {

const char* const kExportHelp = R"(Usage: rlt export RUN_DIR

Writes RUN_DIR/<Behavior>.pt for every behavior from the run's newest checkpoint: a TorchScript
module whose forward(observations: List[Tensor], action_mask: Optional[Tensor]) returns the
deterministic action (continuous [B, C] in [-1, 1], discrete [B, K]). Its attribute spec_json holds
the observation and action specs. Load it with torch::jit::load (C++) or torch.jit.load (Python).
)";

int run_export(const std::vector<std::string>& args) {
  CommandLine cl(args, {}, {});
  if (cl.positional().size() != 1) throw UsageError("expected one RUN_DIR");
  SavedRun run = load_saved_run(cl.positional()[0]);
  for (auto& t : run.trainers) {
    const std::string path = run.folder->policy_path(t->behavior());
    export_policy(*t->network(), t->normalizer(), t->spec(), path);
    std::cout << path << std::endl;
  }
  return 0;
}

}  // namespace rlt
