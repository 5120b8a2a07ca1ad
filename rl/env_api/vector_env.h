// N instances of one environment stepped together on a thread pool, with automatic reset.
//
// Env i is seeded with derived_seed(base_seed, i) (derived_seed.h). An instance whose episode has
// ended (every slot kLast or kAbsent after a step) is reset by the next call to step() instead of
// being stepped: its rows then hold kFirst, and the actions written for them are ignored. Final
// observations therefore stay in the buffers for one step, where trainers read them (bootstrap).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rl/env_api/env.h"
#include "rl/env_api/thread_pool.h"

namespace rlt {

struct FinishedEpisode {
  int env_index = 0;
  EpisodeMetrics metrics;
  std::shared_ptr<EpisodeRecording> recording;  // set when recording is on and the env records
};

class VectorEnv {
 public:
  // Builds `num_envs` instances of registered env `env_id` with construction parameters `params`.
  VectorEnv(const std::string& env_id, int num_envs, uint64_t base_seed,
            const Parameters& params = {}, int threads = 1);

  const EnvSpec& spec() const { return envs_.front()->spec(); }
  int num_envs() const { return static_cast<int>(envs_.size()); }
  int num_behaviors() const { return static_cast<int>(buffers_.size()); }
  BehaviorBuffers& buffers(int behavior) { return buffers_[behavior]; }
  const BehaviorBuffers& buffers(int behavior) const { return buffers_[behavior]; }

  // Parameters for every instance (or one), applied at its next reset.
  void set_parameters(const Parameters& params);
  void set_parameters(int env_index, const Parameters& params);

  // The value of parameter `name` in instance `env_index` (of the episode running or just ended).
  float parameter(int env_index, const std::string& name) const {
    return envs_.at(env_index)->parameter(name);
  }

  // The names of the episode metrics the env reports (instance 0, after a reset), in order (a
  // map's).
  std::vector<std::string> episode_metric_names() const;

  // Seeds env i with derived_seed(base_seed, i) and starts an episode in every instance.
  void reset();
  // Seeds every instance again (env i: derived_seed(seed, i)) and starts new episodes: used to
  // restart from a deterministic point, e.g. at a checkpoint.
  void reseed_and_reset(uint64_t seed);
  // Steps every instance with the actions in the buffers (or resets those whose episode ended).
  void step();
  // Spreads the instances over their episodes: instance i plays i * span / num_envs steps with
  // still actions (every continuous action 0, each branch's first allowed option), so that
  // instances that started together are at different points of their episodes (a trainer whose
  // buffer holds less than an episode then does not learn from one phase of it at a time). Call
  // it right after reset(); the buffers then hold each instance's current step. The episodes
  // played into are partial: take_finished_episodes() leaves them out, and an instance whose
  // episode ends during the warm-up starts a fresh one.
  void stagger(int span);

  // Writes the actions of every slot of `behavior` that needs one with the env's scripted policy
  // (Env::write_scripted_actions) in every instance; false when the env has none.
  bool write_scripted_actions(int behavior);
  // Sum of Env::physics_frames() over the instances.
  uint64_t physics_frames() const;
  // Records every episode from now on (Env::set_recording); finished episodes carry it.
  void set_recording(bool on);

  // Episodes that ended since the last call, in env order (not those stagger() played into).
  std::vector<FinishedEpisode> take_finished_episodes();

 private:
  bool episode_over(int env_index);
  void write_still_actions(int env_index);
  void start_episodes();  // resets every instance without reseeding

  uint64_t base_seed_ = 0;  // the instances' seeds at reset() derive from it
  std::vector<std::unique_ptr<Env>> envs_;
  std::vector<BehaviorBuffers> buffers_;      // one per behavior
  std::vector<StepView> views_;               // one per env
  std::vector<uint8_t> needs_reset_;          // [num_envs]
  std::vector<uint8_t> just_finished_;        // [num_envs]
  std::vector<uint8_t> partial_;              // [num_envs] 1: the episode began before stagger()
  std::vector<EpisodeMetrics> last_metrics_;  // [num_envs]
  std::vector<std::shared_ptr<EpisodeRecording>> last_recording_;  // [num_envs]
  std::vector<FinishedEpisode> finished_;
  bool recording_ = false;
  ThreadPool pool_;
};

}  // namespace rlt
