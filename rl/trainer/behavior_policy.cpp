#include "rl/trainer/behavior_policy.h"

#include <stdexcept>

#include <cstring>
#include <sstream>

#include "rl/core/action_distribution.h"

namespace rlt {

void NetworkPolicy::act(BehaviorBuffers& buf, const std::vector<uint8_t>* only) {
  const auto& spec = buf.spec;
  std::vector<int> rows;
  for (int r = 0; r < buf.rows; ++r)
    if (needs_action(buf.step_type[r]) && (!only || (*only)[r])) rows.push_back(r);
  if (rows.empty()) return;
  const int m = spec.action.mask_size(), c = spec.action.continuous_size, k = spec.action.num_branches();
  RowMatrix obs(int64_t(rows.size()), obs_size_);
  std::vector<uint8_t> masks(rows.size() * m);
  for (size_t i = 0; i < rows.size(); ++i) {
    float* dst = obs.data() + i * obs_size_;
    for (size_t o = 0; o < spec.observations.size(); ++o) {
      const int n = spec.observations[o].size();
      std::memcpy(dst, buf.observations[o].data() + size_t(rows[i]) * n, sizeof(float) * n);
      dst += n;
    }
    std::memcpy(masks.data() + i * m, buf.action_mask.data() + size_t(rows[i]) * m, m);
  }
  ActBatch out;
  actor_.act(obs, m ? masks.data() : nullptr, deterministic_, rng_, out);
  for (size_t i = 0; i < rows.size(); ++i) {
    for (int j = 0; j < c; ++j)
      buf.continuous_actions[size_t(rows[i]) * c + j] = clip_continuous_action(out.continuous(i, j));
    for (int j = 0; j < k; ++j) buf.discrete_actions[size_t(rows[i]) * k + j] = out.discrete(i, j);
  }
}

std::string NetworkPolicy::engine_state() const {
  std::ostringstream os;
  os << rng_;
  return os.str();
}

void NetworkPolicy::set_engine_state(const std::string& text) {
  std::istringstream is(text);
  is >> rng_;
}

void RandomPolicy::act(BehaviorBuffers& buf, const std::vector<uint8_t>* only) {
  const auto& a = buf.spec.action;
  const int m = a.mask_size(), c = a.continuous_size, k = a.num_branches();
  for (int r = 0; r < buf.rows; ++r) {
    if (!needs_action(buf.step_type[r]) || (only && !(*only)[r])) continue;
    for (int j = 0; j < c; ++j)
      buf.continuous_actions[size_t(r) * c + j] = float(2.0 * uniform01(rng_) - 1.0);
    int offset = 0;
    for (int j = 0; j < k; ++j) {
      const int n = a.discrete_branches[j];
      const uint8_t* allowed = buf.action_mask.data() + size_t(r) * m + offset;
      int count = 0;
      for (int o = 0; o < n; ++o) count += allowed[o] != 0;
      int pick = int(uniform01(rng_) * count), choice = 0;
      for (int o = 0; o < n; ++o)
        if (allowed[o] && pick-- == 0) {
          choice = o;
          break;
        }
      buf.discrete_actions[size_t(r) * k + j] = choice;
      offset += n;
    }
  }
}

void StillPolicy::act(BehaviorBuffers& buf, const std::vector<uint8_t>* only) {
  for (int r = 0; r < buf.rows; ++r)
    if (needs_action(buf.step_type[r]) && !(only && !(*only)[r])) buf.write_still_action(r);
}

void ScriptedPolicy::act(BehaviorBuffers& /*buf*/, const std::vector<uint8_t>* rows) {
  if (rows != nullptr)
    throw std::invalid_argument("ScriptedPolicy: acting for a subset of rows is not supported");
  if (!env_.write_scripted_actions(behavior_))
    throw std::invalid_argument("env " + env_.spec().name + " has no scripted policy for behavior " +
                                env_.spec().behaviors[behavior_].name);
}

}  // namespace rlt
