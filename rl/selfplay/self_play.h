// Self-play with ML-Agents' ghost-trainer semantics, for symmetric games (one behavior, teams told
// apart by group id) and asymmetric ones (a different behavior per team, e.g. hiders vs seekers).
//
// Reference: ML-Agents `trainers/ghost/trainer.py` and `ghost/controller.py`.
// - A team is (behavior, group id); the teams of every behavior with a `self_play` block take turns
//   as the *learning team*, `team_change` steps of its behavior each.
// - Agents of the learning team act with the behavior's current policy and their experiences train
//   it; every other team acts with an *opponent*: a snapshot of its own behavior's policy, or with
//   probability `play_against_latest_model_ratio` the current one. Opponents are drawn again every
//   `swap_steps` opponent decisions and whenever the learning team changes.
// - Each behavior keeps its `window` newest snapshots, one added every `save_steps` learning steps.
// - ELO: when an agent of the learning team finishes an episode, its last reward (plus group
//   reward) > 0 is a win, < 0 a loss, 0 a draw; the learner's rating moves by
//   16 (result - expected) and the opponent snapshot's by the opposite.
// Deliberate difference: a behavior's opponents share one draw per swap (ML-Agents draws one per
// team; with two teams this is the same).
#pragma once

#include <torch/torch.h>

#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rl/core/fast_actor.h"
#include "rl/trainer/behavior_policy.h"
#include "rl/trainer/on_policy_trainer.h"

namespace rlt {

class SelfPlay {
 public:
  // `trainers` in env behavior order; behaviors without self_play are always learning.
  SelfPlay(std::vector<OnPolicyTrainer*> trainers, uint64_t seed);

  bool enabled() const { return !pools_.empty(); }

  // Before acting: marks in `learner_rows[b]` the rows of behavior b that learn (the others are
  // played by act_opponents). Discovers teams from the group ids it sees.
  void select_rows(const std::vector<BehaviorBuffers*>& buffers,
                   std::vector<std::vector<uint8_t>>& learner_rows);
  // Chooses the actions of every non-learning row that needs one.
  void act_opponents(std::vector<BehaviorBuffers*>& buffers,
                     const std::vector<std::vector<uint8_t>>& learner_rows);
  // After the env step: ELO from finished learning agents, then snapshots, swaps, team changes
  // (at a change the team that stops learning ends its running trajectories).
  void after_step(const std::vector<BehaviorBuffers*>& buffers,
                  const std::vector<std::vector<uint8_t>>& learner_rows);

  // ELO of behavior b's learner (initial_elo without self_play)
  double elo(int b) const;
  // every rating (learners and snapshots) as numbers, the same length on every rank of a
  // data-parallel run; set_elo_state takes rank 0's
  std::vector<double> elo_state() const;
  void set_elo_state(const std::vector<double>& state);
  // the learning team, as "Behavior:group", for summaries
  std::string learning_team_name() const;
  // the learning behavior's self_play.turn_parameters (empty without self-play)
  const std::map<std::string, float>& turn_parameters() const;
  // whether behavior b learns now: one of its teams is the learning team (behaviors without
  // self_play always learn, and every behavior does before the teams are known)
  bool learns(int behavior) const;
  // how often the learning team has changed since this object was made (not saved: counts turns
  // within one process, e.g. to tell whether an episode was played in one turn)
  int64_t team_changes() const { return team_changes_; }

  void save(torch::serialize::OutputArchive& archive) const;
  void load(torch::serialize::InputArchive& archive);

 private:
  struct Snapshot {
    std::vector<torch::Tensor> weights;  // the actor network's parameters
    std::string normalizer;              // RunningNormalizer::serialize()
    double elo = 0;
  };
  struct Pool {                 // one per behavior with self_play
    int behavior = 0;
    std::vector<Snapshot> snapshots;  // at most `window`, ring order
    int next_slot = 0;
    double elo = 0;             // the current learner's rating
    int opponent = -1;          // snapshot index the opponents play, -1 = current policy
    Snapshot current;           // the learner's weights when the opponent was drawn (opponent -1)
    std::unique_ptr<NetworkPolicy> opponent_policy;
    int64_t last_save = 0;      // learner steps at the last snapshot
  };
  struct Team {
    int behavior = 0;
    int group = 0;
  };

  Pool* pool_of(int behavior);
  const SelfPlaySettings& settings(int behavior) const;
  Snapshot snapshot_of(int behavior) const;
  FastActor actor_of(int behavior, const Snapshot& s) const;
  void swap_opponents();
  void set_opponent(Pool& pool, int index, uint64_t policy_seed);
  // rating of the opponent that learning-team agents now face
  double opponent_elo() const;
  bool is_learning(int behavior, int group) const;

  std::vector<OnPolicyTrainer*> trainers_;
  std::vector<Pool> pools_;
  std::vector<Team> teams_;     // sorted by (behavior, group)
  int learning_team_ = 0;       // index into teams_
  int64_t last_team_change_ = 0;  // learning behavior's steps at the last change
  int64_t team_changes_ = 0;
  int64_t ghost_steps_ = 0, last_swap_ = 0;  // opponent decisions
  std::mt19937_64 rng_;
  std::vector<uint8_t> opponent_rows_;  // scratch
};

}  // namespace rlt
