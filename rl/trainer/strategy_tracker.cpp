#include "rl/trainer/strategy_tracker.h"

#include <numeric>
#include <stdexcept>

namespace rlt {

StrategyTracker::StrategyTracker(std::vector<StrategySpec> strategies)
    : strategies_(std::move(strategies)), windows_(strategies_.size()) {
  for (const auto& s : strategies_) {
    if (s.window < 1)
      throw std::invalid_argument("strategy " + s.name + ": window must be at least 1");
    Emergence e;
    e.strategy = s.name;
    e.metric = s.metric;
    e.behavior = s.behavior;
    emergences_.push_back(e);
  }
}

std::vector<int> StrategyTracker::add_episode(
    const std::map<std::string, float>& metrics,
    const std::function<float(const std::string&)>& parameter,
    const std::map<std::string, int64_t>& steps, double elapsed_s) {
  std::vector<int> emerged;
  for (size_t i = 0; i < strategies_.size(); ++i) {
    const StrategySpec& s = strategies_[i];
    auto m = metrics.find(s.metric);
    if (m == metrics.end()) continue;
    bool counts = true;
    for (const StrategySpec::AtLeast& c : s.conditions) {
      auto reported = metrics.find(c.parameter);
      const float value = reported != metrics.end() ? reported->second : parameter(c.parameter);
      counts = counts && value >= c.value;
    }
    if (!counts) continue;
    auto& w = windows_[i];
    w.push_back(m->second);
    while (int(w.size()) > s.window) w.pop_front();
    Emergence& e = emergences_[i];
    if (e.step >= 0 || int(w.size()) < s.window) continue;  // a full window before it can emerge
    const double r = rate(int(i));
    auto st = steps.find(s.behavior);
    if (r > s.threshold && st != steps.end()) {
      e.step = st->second;
      e.elapsed_s = elapsed_s;
      e.rate = r;
      emerged.push_back(int(i));
    }
  }
  return emerged;
}

double StrategyTracker::rate(int i) const {
  const auto& w = windows_.at(i);
  if (w.empty()) return 0;
  return std::accumulate(w.begin(), w.end(), 0.0) / double(w.size());
}

void StrategyTracker::set_emergences(const std::vector<Emergence>& given) {
  for (const auto& g : given)
    for (auto& e : emergences_)
      if (e.strategy == g.strategy) e = g;
}

void StrategyTracker::load_window(int i, const std::vector<float>& values) {
  windows_.at(i).assign(values.begin(), values.end());
}

}  // namespace rlt
