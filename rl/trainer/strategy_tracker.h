// Follows the emergent strategies an env declares (EnvSpec::strategies, SPEC section 8) through
// training: per strategy the mean of its metric over the last `window` qualifying episodes, and the
// first step of its behavior at which that mean exceeded the threshold (the step it emerged).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "rl/env_api/spec.h"

namespace rlt {

struct Emergence {
  std::string strategy, metric, behavior;
  int64_t step = -1;       // behavior's step when it emerged; -1: not yet
  double elapsed_s = 0;    // training time then
  double rate = 0;         // the smoothed rate that crossed the threshold
};

class StrategyTracker {
 public:
  StrategyTracker() = default;
  explicit StrategyTracker(std::vector<StrategySpec> strategies);

  bool empty() const { return strategies_.empty(); }
  const std::vector<StrategySpec>& strategies() const { return strategies_; }

  // One finished episode: its metrics, the value of the strategy's condition parameter in that
  // episode (looked up through `parameter`), the behaviors' steps and the elapsed time. Returns the
  // indices of strategies that emerged with this episode.
  std::vector<int> add_episode(const std::map<std::string, float>& metrics,
                               const std::function<float(const std::string&)>& parameter,
                               const std::map<std::string, int64_t>& steps, double elapsed_s);

  // smoothed rate of strategy i (mean of the window; 0 before any qualifying episode)
  double rate(int i) const;
  const std::vector<Emergence>& emergences() const { return emergences_; }
  void set_emergences(const std::vector<Emergence>& e);

  // the windows, for checkpoints (so that a resumed run dates emergence as an uninterrupted one)
  std::vector<float> save_window(int i) const { return {windows_[i].begin(), windows_[i].end()}; }
  void load_window(int i, const std::vector<float>& values);

 private:
  std::vector<StrategySpec> strategies_;
  std::vector<std::deque<float>> windows_;
  std::vector<Emergence> emergences_;
};

}  // namespace rlt
