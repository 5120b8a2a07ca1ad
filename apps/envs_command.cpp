#include <iostream>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "rl/core/policy_export.h"
#include "rl/env_api/env_registry.h"

namespace rlt {

const char* const kEnvsHelp = R"(Usage: rlt envs [--json]

Lists the registered environments: their behaviors (observation shapes, action spec, agent slots),
episode length, parameters with defaults and the strategies training watches for (the episode
metric whose smoothed rate marks it, and whose steps date it). --json prints one JSON object per environment.
)";

int run_envs(const std::vector<std::string>& args) {
  CommandLine cl(args, {"--json"}, {});
  auto& registry = EnvRegistry::instance();
  for (const auto& name : registry.names()) {
    auto env = registry.make(name);
    const EnvSpec& spec = env->spec();
    if (cl.has("--json")) {
      std::cout << "{\"env\":\"" << name << "\",\"max_episode_steps\":" << spec.max_episode_steps
                << ",\"behaviors\":[";
      for (size_t b = 0; b < spec.behaviors.size(); ++b)
        std::cout << (b ? "," : "") << behavior_spec_json(spec.behaviors[b]);
      std::cout << "],\"parameters\":{";
      size_t i = 0;
      for (const auto& [k, v] : spec.default_parameters) std::cout << (i++ ? "," : "") << "\"" << k << "\":" << v;
      std::cout << "},\"strategies\":[";
      i = 0;
      for (const auto& s : spec.strategies)
        std::cout << (i++ ? "," : "") << "{\"name\":\"" << s.name << "\",\"metric\":\"" << s.metric
                  << "\",\"behavior\":\"" << s.behavior << "\",\"threshold\":" << s.threshold << "}";
      std::cout << "]}\n";
      continue;
    }
    std::cout << name << " (at most " << spec.max_episode_steps << " decisions)\n";
    for (const auto& b : spec.behaviors) {
      std::cout << "  behavior " << b.name << ", " << b.agent_slots << " agent slot(s)\n";
      for (const auto& o : b.observations) {
        std::cout << "    observation " << o.name << " [";
        for (size_t d = 0; d < o.shape.size(); ++d) std::cout << (d ? ", " : "") << o.shape[d];
        std::cout << "] " << (o.kind == ObservationKind::kGrid ? "grid" : "vector") << "\n";
      }
      std::cout << "    actions: " << b.action.continuous_size << " continuous, discrete branches [";
      for (size_t d = 0; d < b.action.discrete_branches.size(); ++d)
        std::cout << (d ? ", " : "") << b.action.discrete_branches[d];
      std::cout << "]\n";
    }
    if (!spec.default_parameters.empty()) {
      std::cout << "  parameters:";
      for (const auto& [k, v] : spec.default_parameters) std::cout << " " << k << "=" << v;
      std::cout << "\n";
    }
    for (const auto& s : spec.strategies) {
      std::cout << "  strategy " << s.name << ": " << s.metric << " over the last " << s.window
                << " episodes > " << s.threshold << ", dated in " << s.behavior << " steps";
      if (!s.conditions.empty()) std::cout << ", episodes with " << s.describe_conditions();
      std::cout << "\n";
    }
  }
  return 0;
}

}  // namespace rlt
