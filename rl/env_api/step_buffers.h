// Batched step data of one behavior, owned by the vector env and written in place by environments.
//
// Layout is batch-first: row r = env_index * agent_slots + slot. Trainers wrap these vectors as
// tensors without copying. An environment sees only its own rows through a BehaviorView.
//
// Life of a slot (the dm_env / PettingZoo contract, one row per agent slot):
//   kAbsent  no agent in this slot now (not spawned, or already left): every field is to be ignored.
//   kFirst   first observation of a new agent; reward fields are 0; the agent must act.
//   kMid     reward for the agent's previous action and its next observation; the agent must act.
//   kLast    the agent's final step: reward for its last action and its final observation. The agent
//            takes no action and never comes back; `terminated` = 1 means the episode ended for it
//            (discount 0), 0 means it was truncated (interrupted: bootstrap from the observation).
// Action masks: 1 = the option is allowed, 0 = forbidden. Every branch has at least one allowed option.
#pragma once

#include <cstdint>
#include <vector>

#include "rl/env_api/spec.h"

namespace rlt {

enum class StepType : uint8_t { kAbsent = 0, kFirst = 1, kMid = 2, kLast = 3 };

// true when the agent in this slot must be given an action
inline bool needs_action(StepType t) { return t == StepType::kFirst || t == StepType::kMid; }

struct BehaviorBuffers {
  BehaviorSpec spec;
  int rows = 0;  // num_envs * agent_slots

  std::vector<std::vector<float>> observations;  // per observation spec k: [rows, obs_size_k]
  std::vector<float> reward;                     // [rows] reward of the agent's last action
  std::vector<float> group_reward;               // [rows] reward shared by the agent's group
  std::vector<int32_t> agent_id;                 // [rows] unique within one episode of one env
  std::vector<int32_t> group_id;                 // [rows] team of the agent
  std::vector<StepType> step_type;               // [rows]
  std::vector<uint8_t> terminated;               // [rows] for kLast: 1 terminated, 0 truncated
  std::vector<uint8_t> action_mask;              // [rows, mask_size] 1 = allowed
  std::vector<float> continuous_actions;         // [rows, continuous_size] written by the learner
  std::vector<int32_t> discrete_actions;         // [rows, num_branches] written by the learner

  BehaviorBuffers() = default;
  BehaviorBuffers(const BehaviorSpec& behavior, int num_envs)
      : spec(behavior), rows(num_envs * behavior.agent_slots) {
    for (const auto& o : behavior.observations) observations.emplace_back(size_t(rows) * o.size());
    reward.assign(rows, 0.f);
    group_reward.assign(rows, 0.f);
    agent_id.assign(rows, -1);
    group_id.assign(rows, 0);
    step_type.assign(rows, StepType::kAbsent);
    terminated.assign(rows, 0);
    action_mask.assign(size_t(rows) * behavior.action.mask_size(), 1);
    continuous_actions.assign(size_t(rows) * behavior.action.continuous_size, 0.f);
    discrete_actions.assign(size_t(rows) * behavior.action.num_branches(), 0);
  }

  // Doing nothing, for row r: continuous actions 0 and, on each branch, the first option the mask
  // allows.
  void write_still_action(int r) {
    const ActionSpec& a = spec.action;
    const int m = a.mask_size(), c = a.continuous_size, k = a.num_branches();
    for (int j = 0; j < c; ++j) continuous_actions[size_t(r) * c + j] = 0.0f;
    for (int j = 0, offset = 0; j < k; offset += a.discrete_branches[j++]) {
      const uint8_t* allowed = action_mask.data() + size_t(r) * m + offset;
      int choice = 0;
      while (choice < a.discrete_branches[j] - 1 && !allowed[choice]) ++choice;
      discrete_actions[size_t(r) * k + j] = choice;
    }
  }
};

// The rows of one env instance inside a BehaviorBuffers: what an environment reads and writes.
class BehaviorView {
 public:
  BehaviorView(BehaviorBuffers* buffers, int env_index)
      : b_(buffers), row0_(env_index * buffers->spec.agent_slots) {}

  int slots() const { return b_->spec.agent_slots; }
  const BehaviorSpec& spec() const { return b_->spec; }

  float* observation(int slot, int k = 0) {
    return b_->observations[k].data() + size_t(row0_ + slot) * b_->spec.observations[k].size();
  }
  float& reward(int slot) { return b_->reward[row0_ + slot]; }
  float& group_reward(int slot) { return b_->group_reward[row0_ + slot]; }
  int32_t& agent_id(int slot) { return b_->agent_id[row0_ + slot]; }
  int32_t& group_id(int slot) { return b_->group_id[row0_ + slot]; }
  StepType& step_type(int slot) { return b_->step_type[row0_ + slot]; }
  uint8_t& terminated(int slot) { return b_->terminated[row0_ + slot]; }
  uint8_t* action_mask(int slot) {
    return b_->action_mask.data() + size_t(row0_ + slot) * b_->spec.action.mask_size();
  }
  const float* continuous_action(int slot) const {
    return b_->continuous_actions.data() + size_t(row0_ + slot) * b_->spec.action.continuous_size;
  }
  const int32_t* discrete_action(int slot) const {
    return b_->discrete_actions.data() + size_t(row0_ + slot) * b_->spec.action.num_branches();
  }

  // where a policy writes the actions (the learner, or Env::write_scripted_actions)
  float* continuous_action_out(int slot) {
    return b_->continuous_actions.data() + size_t(row0_ + slot) * b_->spec.action.continuous_size;
  }
  int32_t* discrete_action_out(int slot) {
    return b_->discrete_actions.data() + size_t(row0_ + slot) * b_->spec.action.num_branches();
  }

  // Zeroes rewards and flags of every slot; called by the vector env before each reset or step.
  void clear_step() {
    for (int s = 0; s < slots(); ++s) {
      reward(s) = 0.f;
      group_reward(s) = 0.f;
      terminated(s) = 0;
    }
  }
  // Marks every slot of this env absent (start of a reset).
  void clear_agents() {
    for (int s = 0; s < slots(); ++s) {
      step_type(s) = StepType::kAbsent;
      agent_id(s) = -1;
    }
  }

 private:
  BehaviorBuffers* b_;
  int row0_;
};

// All behaviors of one env instance, in the order of EnvSpec::behaviors.
using StepView = std::vector<BehaviorView>;

}  // namespace rlt
