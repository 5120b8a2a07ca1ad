#include "rl/env_api/vector_env.h"

#include <algorithm>
#include <stdexcept>

#include "rl/env_api/derived_seed.h"
#include "rl/env_api/env_registry.h"

namespace rlt {

VectorEnv::VectorEnv(const std::string& env_id, int num_envs, uint64_t base_seed,
                     const Parameters& params, int threads)
    : base_seed_(base_seed), pool_(std::min(threads, num_envs)) {
  if (num_envs < 1) throw std::invalid_argument("num_envs must be at least 1");
  for (int i = 0; i < num_envs; ++i) envs_.push_back(EnvRegistry::instance().make(env_id, params));
  for (const auto& b : spec().behaviors) buffers_.emplace_back(b, num_envs);
  for (int i = 0; i < num_envs; ++i) {
    StepView view;
    for (auto& b : buffers_) view.emplace_back(&b, i);
    views_.push_back(std::move(view));
    envs_[i]->seed(derived_seed(base_seed, i));
  }
  needs_reset_.assign(num_envs, 1);
  just_finished_.assign(num_envs, 0);
  partial_.assign(num_envs, 0);
  last_metrics_.resize(num_envs);
  last_recording_.resize(num_envs);
}

void VectorEnv::set_parameters(const Parameters& params) {
  for (int i = 0; i < num_envs(); ++i) set_parameters(i, params);
}

void VectorEnv::set_parameters(int env_index, const Parameters& params) {
  const auto& known = spec().default_parameters;
  for (const auto& [k, v] : params)
    if (!known.count(k))
      throw std::invalid_argument("environment '" + spec().name + "' has no parameter '" + k + "'");
  envs_[env_index]->set_parameters(params);
}

bool VectorEnv::episode_over(int i) {
  for (auto& v : views_[i])
    for (int s = 0; s < v.slots(); ++s)
      if (needs_action(v.step_type(s))) return false;
  return true;
}

void VectorEnv::reset() {
  for (int i = 0; i < num_envs(); ++i) envs_[i]->seed(derived_seed(base_seed_, i));
  start_episodes();
}

void VectorEnv::reseed_and_reset(uint64_t seed) {
  for (int i = 0; i < num_envs(); ++i) envs_[i]->seed(derived_seed(seed, i));
  start_episodes();
}

void VectorEnv::start_episodes() {
  pool_.parallel_for(num_envs(), [this](int i) {
    for (auto& v : views_[i]) {
      v.clear_step();
      v.clear_agents();
    }
    envs_[i]->reset(views_[i]);
    needs_reset_[i] = 0;
    partial_[i] = 0;
  });
}

void VectorEnv::write_still_actions(int i) {
  for (BehaviorBuffers& b : buffers_) {
    const int first = i * b.spec.agent_slots;
    for (int r = first; r < first + b.spec.agent_slots; ++r)
      if (needs_action(b.step_type[r])) b.write_still_action(r);
  }
}

void VectorEnv::stagger(int span) {
  if (span <= 0) return;
  pool_.parallel_for(num_envs(), [this, span](int i) {
    const int64_t steps = int64_t(i) * span / num_envs();
    for (int64_t k = 0; k < steps; ++k) {
      write_still_actions(i);
      for (auto& v : views_[i]) v.clear_step();
      envs_[i]->step(views_[i]);
      partial_[i] = 1;
      if (!episode_over(i)) continue;
      // ended during the warm-up: a whole episode from here on
      for (auto& v : views_[i]) {
        v.clear_step();
        v.clear_agents();
      }
      envs_[i]->reset(views_[i]);
      partial_[i] = 0;
    }
    for (auto& v : views_[i]) v.clear_step();  // the warm-up's rewards are nobody's
  });
}

void VectorEnv::step() {
  pool_.parallel_for(num_envs(), [this](int i) {
    for (auto& v : views_[i]) v.clear_step();
    if (needs_reset_[i]) {
      for (auto& v : views_[i]) v.clear_agents();
      envs_[i]->reset(views_[i]);
      needs_reset_[i] = 0;
      return;
    }
    envs_[i]->step(views_[i]);
    if (episode_over(i)) {
      needs_reset_[i] = 1;
      just_finished_[i] = 1;
      last_metrics_[i] = envs_[i]->episode_metrics();
      if (recording_) {
        auto recording = std::make_shared<EpisodeRecording>();
        if (envs_[i]->take_recording(*recording)) last_recording_[i] = std::move(recording);
      }
    }
  });
  for (int i = 0; i < num_envs(); ++i) {
    if (!just_finished_[i]) continue;
    just_finished_[i] = 0;
    if (!partial_[i])
      finished_.push_back({i, std::move(last_metrics_[i]), std::move(last_recording_[i])});
    partial_[i] = 0;
    last_recording_[i].reset();
  }
}

bool VectorEnv::write_scripted_actions(int behavior) {
  bool all = true;
  for (int i = 0; i < num_envs(); ++i)
    all = envs_[i]->write_scripted_actions(behavior, views_[i][behavior]) && all;
  return all;
}

std::vector<std::string> VectorEnv::episode_metric_names() const {
  std::vector<std::string> names;
  for (const auto& [name, value] : envs_.front()->episode_metrics()) names.push_back(name);
  return names;
}

uint64_t VectorEnv::physics_frames() const {
  uint64_t n = 0;
  for (const auto& env : envs_) n += env->physics_frames();
  return n;
}

void VectorEnv::set_recording(bool on) {
  recording_ = on;
  for (auto& env : envs_) env->set_recording(on);
}

std::vector<FinishedEpisode> VectorEnv::take_finished_episodes() {
  std::vector<FinishedEpisode> out;
  out.swap(finished_);
  return out;
}

}  // namespace rlt
