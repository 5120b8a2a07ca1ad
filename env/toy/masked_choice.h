// MaskedChoice: a one-agent toy task with two discrete branches and changing action masks.
//
// No external reference: a test env for action masking (ML-Agents' "discrete action masking").
//
// Each decision, every option of branch 0 (4 options) and branch 1 (3 options) is allowed with
// probability 1/2, redrawn until each branch allows at least one option; then one allowed option
// per branch is the bonus option, uniform among the allowed ones. The agent observes "options" =
// (mask of both branches, onehot of both bonus options), 7 + 7 values in {0, 1}, and the mask is
// also written to the action mask (1 = allowed). Reward per branch:
//     -1    for a forbidden option (the mask said 0): detectable, and counted in the episode metric
//           "forbidden_actions";
//     +0.5  for the bonus option;
//     0     for another allowed option.
// Episodes are truncated after 10 decisions and never terminate. Metrics: "forbidden_actions"
// (count in the episode) and "bonus_rate" (share of branch choices that hit the bonus).
// An out-of-range option index throws std::invalid_argument.
//
// Returns per episode, computed analytically (k = allowed options of a branch, Binomial(n, 1/2)
// conditioned on k >= 1):
// - optimal (always the bonus): 10 * (0.5 + 0.5) = 10;
// - uniform among allowed options: 10 * 0.5 * (E[1/k | n=4] + E[1/k | n=3])
//   = 5 * (103/180 + 29/42) = 6.31;
// - uniform over all options, ignoring the mask: per branch 0.5/n - (1 - E[k]/n) with
//   E[k] = (n/2) / (1 - 2^-n), i.e. -41/120 (n=4) and -11/42 (n=3): 10 * (-0.604) = -6.04.
#pragma once

#include <array>
#include <cstdint>
#include <random>

#include "rl/env_api/env.h"

namespace rlt {

class MaskedChoice : public Env {
 public:
  static constexpr int kBranches = 2;
  static constexpr std::array<int, kBranches> kOptions = {4, 3};
  static constexpr int kMaskSize = 7;  // 4 + 3
  static constexpr int kEpisodeSteps = 10;
  static constexpr float kForbiddenReward = -1.f;
  static constexpr float kBonusReward = 0.5f;

  MaskedChoice();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;

  // the current situation: allowed options [7] (1 = allowed) and bonus option of each branch
  const std::array<uint8_t, kMaskSize>& allowed() const { return allowed_; }
  int bonus(int branch) const { return bonus_[branch]; }

 private:
  void draw_situation();
  void write_situation(BehaviorView& view) const;

  EnvSpec spec_;
  std::mt19937_64 engine_;
  std::array<uint8_t, kMaskSize> allowed_{};  // [7] branch 0 options, then branch 1 options
  std::array<int, kBranches> bonus_{};        // bonus option index within each branch
  int elapsed_steps_ = 0;
  int forbidden_actions_ = 0;  // forbidden choices in this episode
  int bonus_hits_ = 0;         // bonus choices in this episode
};

}  // namespace rlt
