// One training run: a VectorEnv, one trainer per behavior, summaries, metrics, checkpoints, export.
//
// Checkpoints are taken at *boundaries*: every running trajectory is ended as interrupted (with a
// bootstrap), the trainers' state is saved, and every env instance is reseeded from the boundary
// number and restarted. A resumed run restarts from exactly the same point, so a run stopped and
// resumed ends bit-identical to an uninterrupted one with the same seed, for any environment
// (nothing of an env's internal state has to be saved).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rl/config/run_config.h"
#include "rl/curriculum/environment_parameter_manager.h"
#include "rl/env_api/vector_env.h"
#include "rl/selfplay/self_play.h"
#include "rl/trainer/on_policy_trainer.h"
#include "rl/trainer/run_folder.h"
#include "rl/trainer/strategy_tracker.h"
#include "rl/trainer/tensorboard_writer.h"

namespace rlt {

struct TrainOptions {
  std::string run_id;             // overrides checkpoint_settings.run_id when set
  std::string results_dir;        // overrides checkpoint_settings.results_dir when set
  bool resume = false, force = false;
  std::string initialize_from;    // run id (in the results dir) to take initial weights from
  int num_envs = 0;               // overrides env_settings.num_envs when > 0
  int64_t seed = -1;              // overrides env_settings.seed (and a resumed run's) when >= 0
  int64_t max_steps = 0;          // overrides every behavior's max_steps when > 0
  // overrides the named behaviors' max_steps (over max_steps and the lessons' budgets); a name the
  // environment does not have is an error
  std::map<std::string, int64_t> behavior_max_steps;
  Parameters params;              // env parameters over env_settings.params (not curriculum ones)
  // Strategies (names the env declares) after whose emergence training stops, as at max_steps:
  // once every one of them has emerged. Not kept by a resume; not with a communicator.
  std::vector<std::string> until_emerged;
  int threads = 0;                // env and LibTorch threads (0 = number of cores)
  bool write_results = true;      // false: no run folder (benchmarks)
  std::ostream* log = nullptr;    // summary lines (null = std::cout)
  bool progress = true;           // progress indicator on a terminal
  // called for every finished agent episode: (behavior index, behavior's step, episode return)
  std::function<void(int, int64_t, float)> on_episode;
  // called for every finished env episode with the env's episode metrics
  std::function<void(const EpisodeMetrics&)> on_env_episode;
  // Data-parallel training (not owned; null trains alone): this process is one rank, with its own
  // environment instances (seeded apart from the other ranks') and a replica of every learner.
  // The ranks agree after every env step on the steps and on when to update; rank 0 decides the
  // lessons and the ELO, and it alone writes the run folder (the others read it to resume).
  Communicator* communicator = nullptr;
};

struct TrainResult {
  double seconds = 0;
  int64_t env_steps = 0;    // vector-env steps x instances
  int64_t agent_steps = 0;  // decisions of all behaviors
  // where the time went (seconds): choosing actions, stepping envs, building trajectories, updates
  double acting_seconds = 0, env_seconds = 0, trajectory_seconds = 0, update_seconds = 0;
  double update_matmul_flops = 0;  // matrix-product operations of every update (UpdateStats)
  // the same two per trainer (index as TrainingRun::trainer())
  std::vector<double> trainer_update_seconds, trainer_update_matmul_flops;
};

class TrainingRun {
 public:
  // Applies `options` to `config`, validates the environment, and prepares the run folder
  // (throws before writing anything when the config or the options are wrong).
  TrainingRun(RunConfig config, TrainOptions options);
  ~TrainingRun();

  // Trains until every behavior reaches its max_steps (or `stop_after_boundaries` boundaries were
  // written, for tests of interrupted runs; 0 = no limit).
  TrainResult train(int stop_after_boundaries = 0);

  const RunConfig& config() const { return config_; }
  OnPolicyTrainer& trainer(int behavior) { return *trainers_[behavior]; }
  int num_trainers() const { return static_cast<int>(trainers_.size()); }
  const RunFolder* folder() const { return folder_.get(); }
  const SelfPlay& self_play() const { return *self_play_; }
  const EnvironmentParameterManager& parameters() const { return parameters_; }
  // The end-of-training table for people: per behavior its steps, the mean reward of its last
  // summary, ELO; the lessons; each strategy's rate and when it emerged; where the policies and
  // TensorBoard files are.
  std::string summary_table() const;
  // the env's strategies: smoothed rates and emergence steps
  const StrategyTracker& strategies() const { return strategies_; }

 private:
  void boundary(bool final);
  // TrainOptions::until_emerged: names the env declares, and no communicator (throws otherwise)
  void check_until_emerged() const;
  // every strategy of TrainOptions::until_emerged has emerged (false when there are none)
  bool awaited_strategies_emerged() const;
  // a fresh self-play controller over the trainers (its pool starts from their current weights)
  void reset_self_play();
  // draws every instance's parameters for its next reset
  void sample_all_parameters();
  // Each trainer's max_steps: its own, raised by the behavior_max_steps of the lessons reached
  // (not for a behavior whose steps the command line sets: --max-steps N or BEHAVIOR=N).
  void apply_step_budgets();
  // the steps the command line gives a behavior (--max-steps NAME=N, else N), 0 when none
  int64_t command_line_max_steps(const std::string& behavior) const;
  // the curriculum's values for one env's next episode, with the learning team's turn_parameters
  // over them
  Parameters next_parameters();
  // curriculum: records finished episodes, advances lessons, resets envs when a lesson asks to
  void update_curriculum(const std::vector<FinishedEpisode>& finished,
                         const std::vector<EpisodeStats>& episodes);
  void keep_the_runs_seed();  // --resume without --seed: the seed the run began with
  // Resets the envs with each lesson of each curriculum (the other curricula at their first), so
  // that a value the env rejects is an error naming its lesson before anything is written, not
  // when the lesson is reached hours in. Leaves the envs to be set and reset again.
  void check_every_lesson();
  // appends this start or resume to the status's sessions (when, from which steps, on which
  // machine and build); on resume, says so when the machine or build changed
  void begin_session(bool resumed);
  void save_checkpoint();
  void load_checkpoint(const std::string& path, bool weights_only);
  void export_policies();
  void log_update(int b, const UpdateStats& stats);
  void summarize(int b);
  // the summary's scalars into <run>/<Behavior>/events.out.tfevents.* (ML-Agents' tags)
  void write_tensorboard(int b);
  // strategies and the episode-metrics window of the finished env episodes
  void track_episodes(const std::vector<FinishedEpisode>& finished);
  // appends a row to metrics/episodes.csv with the episodes since the last row
  void log_episode_metrics();
  // metrics/episodes.csv's header (the env's episode metrics in name order)
  std::string episode_metrics_header() const;
  // appends a row per change to metrics/lessons.csv, at the steps of the change
  void log_lesson_changes(const std::vector<LessonChange>& changes);
  std::string lesson_changes_header() const;
  int64_t total_steps() const;
  void show_progress(bool force);
  double elapsed() const;
  // the seed of the env's restart at update boundary `index` (derived from rank_seed_)
  uint64_t boundary_seed(int64_t index) const;
  // data-parallel: sums the ranks' new decisions into every trainer's step, decides which
  // behaviors update now (ready_), and makes the other ranks follow rank 0's lessons and ELO
  void sync_ranks();
  // data-parallel: after an update every rank's parameters of behavior b hash alike, else throws
  void check_replicas(int b);
  bool distributed() const { return options_.communicator != nullptr; }
  int rank() const { return distributed() ? options_.communicator->rank() : 0; }

  RunConfig config_;
  TrainOptions options_;
  uint64_t seed_ = 0;
  uint64_t rank_seed_ = 0;  // derived_seed(seed_, rank): this rank's env and sampling streams
  std::vector<int64_t> synced_step_;  // per behavior: the steps the ranks agreed at the last sync
  std::vector<uint8_t> ready_;        // per behavior: the ranks update it now (sync_ranks)
  LessonUpdate pending_follow_;       // ranks other than 0: rank 0's lesson change, to apply
  int threads_ = 1;  // cores for env stepping and large learner updates
  std::unique_ptr<RunFolder> folder_;
  std::unique_ptr<VectorEnv> env_;
  std::vector<std::unique_ptr<OnPolicyTrainer>> trainers_;
  std::unique_ptr<SelfPlay> self_play_;
  EnvironmentParameterManager parameters_;  // environment_parameters: samplers and lessons
  std::mt19937_64 parameter_rng_;           // sampling at every env reset
  Parameters turn_fallback_;  // each turn parameter's value outside those turns (env_settings'
                              // or the env's default) unless the curriculum sets it; empty when
                              // no behavior sets turn_parameters
  std::vector<std::vector<uint8_t>> learner_rows_;  // per behavior: rows that act for learning
  TrainingStatus status_;
  int64_t boundary_index_ = 0;
  int64_t lesson_resets_ = 0;  // environment restarts asked by lessons (require_reset)
  int64_t lesson_epoch_ = 0;   // lesson changes so far
  std::vector<int64_t>
      episode_epoch_;  // per env instance: lesson_epoch_ when its episode's parameters were drawn
  std::vector<int64_t> episode_turn_;  // per env instance: self-play team changes then
  double elapsed_before_ = 0;  // seconds trained before a resume
  std::chrono::steady_clock::time_point start_;
  std::vector<int64_t> next_summary_, next_checkpoint_;  // per behavior
  std::vector<int64_t> summarized_step_;  // per behavior: its step at its last summary
  std::vector<std::vector<float>> summary_returns_;       // per behavior
  std::vector<std::vector<float>> summary_group_returns_; // per behavior
  std::vector<std::map<std::string, std::pair<double, int>>> summary_metrics_;  // per behavior: sum, count
  std::vector<EpisodeStats> update_window_;               // per behavior: episodes since last row
  std::vector<std::vector<float>> summary_lengths_;       // per behavior: episode lengths
  struct UpdateSums {  // the updates since the last summary, for TensorBoard
    double policy_loss = 0, value_loss = 0, baseline_loss = 0, entropy = 0;
    double learning_rate = 0, epsilon = 0, beta = 0;
    int count = 0;
    double approx_kl = 0, clip_fraction = 0;
  };
  std::vector<UpdateSums> summary_updates_;  // per behavior
  struct LastSummary {  // the newest summary with episodes (summary line, TensorBoard, table)
    bool any = false;
    double reward = 0, group_reward = 0, length = 0;
    int64_t episodes = 0;
  };
  std::vector<LastSummary> last_summary_;  // per behavior
  std::vector<std::unique_ptr<TensorBoardWriter>>
      tensorboard_;  // per behavior, made at its first summary
  StrategyTracker strategies_;
  std::map<std::string, std::pair<double, int>> episode_window_;  // metric: sum, count since last row
  int64_t episode_window_count_ = 0;                              // env episodes since last row
  double last_progress_ = -1;
  std::ostream* log_;
};

}  // namespace rlt
