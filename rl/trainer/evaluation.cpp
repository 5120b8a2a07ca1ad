#include "rl/trainer/evaluation.h"

namespace rlt {

Evaluation evaluate(VectorEnv& env, std::vector<std::unique_ptr<BehaviorPolicy>>& policies,
                    int episodes) {
  Evaluation ev;
  const int nb = env.num_behaviors();
  std::vector<std::vector<double>> running(nb);  // [behavior][row] return of the running episode
  std::vector<std::vector<int>> length(nb);
  // agent episodes of each env's running episode, kept until that env episode counts or not
  std::vector<std::vector<std::pair<int, std::pair<float, float>>>> pending(env.num_envs());
  for (int b = 0; b < nb; ++b) {
    ev.behaviors.push_back({env.spec().behaviors[b].name, {}, {}});
    running[b].assign(env.buffers(b).rows, 0.0);
    length[b].assign(env.buffers(b).rows, 0);
  }
  std::map<std::string, double> sums;
  env.reset();
  while (ev.episodes < episodes) {
    for (int b = 0; b < nb; ++b) policies[b]->act(env.buffers(b));
    env.step();
    for (int b = 0; b < nb; ++b) {
      auto& buf = env.buffers(b);
      const int slots = buf.spec.agent_slots;
      for (int r = 0; r < buf.rows; ++r) {
        const StepType st = buf.step_type[r];
        if (st == StepType::kFirst) {
          running[b][r] = 0;
          length[b][r] = 0;
        }
        if (st != StepType::kMid && st != StepType::kLast) continue;
        running[b][r] += buf.reward[r] + buf.group_reward[r];
        length[b][r] += 1;
        if (st == StepType::kLast)
          pending[r / slots].push_back({b, {float(running[b][r]), float(length[b][r])}});
      }
    }
    for (auto& f : env.take_finished_episodes()) {
      auto finished = std::move(pending[f.env_index]);
      pending[f.env_index].clear();
      if (ev.episodes >= episodes) continue;
      ++ev.episodes;
      for (const auto& [k, v] : f.metrics) sums[k] += v;
      if (f.recording) ev.recordings.push_back(f.recording);
      for (const auto& [b, rl] : finished) {
        ev.behaviors[b].returns.push_back(rl.first);
        ev.behaviors[b].lengths.push_back(rl.second);
      }
    }
  }
  for (const auto& [k, v] : sums) ev.metrics[k] = v / ev.episodes;
  return ev;
}

}  // namespace rlt
