#include "rl/env_api/conformance.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <random>
#include <set>
#include <sstream>

#include "rl/env_api/uniform_random.h"
#include "rl/env_api/vector_env.h"

namespace rlt {

namespace {

const char* step_type_name(StepType t) {
  switch (t) {
    case StepType::kAbsent:
      return "kAbsent";
    case StepType::kFirst:
      return "kFirst";
    case StepType::kMid:
      return "kMid";
    case StepType::kLast:
      return "kLast";
  }
  return "invalid";
}

// "[a, b, c]"
std::string join(const std::vector<std::string>& names) {
  std::string out = "[";
  for (size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out + "]";
}

// Collects violation messages, keeping the first `max` of them.
class Report {
 public:
  Report(std::string prefix, int max) : prefix_(std::move(prefix)), max_(max) {}

  void add(const std::string& message) {
    if (static_cast<int>(messages_.size()) < max_) messages_.push_back(prefix_ + message);
    ++count_;
  }
  int count() const { return count_; }

  std::vector<std::string> finish() {
    const int hidden = count_ - static_cast<int>(messages_.size());
    if (hidden > 0) messages_.push_back(prefix_ + std::to_string(hidden) + " more violations");
    return std::move(messages_);
  }

 private:
  std::string prefix_;
  int max_;
  int count_ = 0;
  std::vector<std::string> messages_;
};

// Random actions that obey the masks: continuous uniform in [-1, 1], discrete uniform among the
// allowed options of each branch (option 0 when a broken mask allows none).
class RandomActor {
 public:
  explicit RandomActor(uint64_t seed) : engine_(seed) {}

  void act(BehaviorBuffers& b) {
    const ActionSpec& action = b.spec.action;
    const int cont_size = action.continuous_size;
    const int branches = action.num_branches();
    const int mask_size = action.mask_size();
    for (int r = 0; r < b.rows; ++r) {
      float* cont = b.continuous_actions.data() + size_t(r) * cont_size;   // [cont_size]
      int32_t* disc = b.discrete_actions.data() + size_t(r) * branches;    // [branches]
      const uint8_t* mask = b.action_mask.data() + size_t(r) * mask_size;  // [mask_size]
      const bool acts = needs_action(b.step_type[r]);
      for (int c = 0; c < cont_size; ++c)
        cont[c] = acts ? static_cast<float>(uniform(engine_, -1.0, 1.0)) : 0.f;
      int offset = 0;
      for (int br = 0; br < branches; ++br) {
        const int n = action.discrete_branches[br];
        disc[br] = 0;
        int allowed = 0;
        for (int k = 0; k < n; ++k) allowed += mask[offset + k] != 0;
        if (acts && allowed > 0) {
          int j = uniform_int(engine_, allowed);
          for (int k = 0; k < n; ++k) {
            if (mask[offset + k] == 0) continue;
            if (j-- == 0) {
              disc[br] = k;
              break;
            }
          }
        }
        offset += n;
      }
    }
  }

 private:
  std::mt19937_64 engine_;
};

// FNV-1a over raw bytes: a fingerprint of the buffers after one step
uint64_t fnv1a(uint64_t h, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

template <typename T>
uint64_t hash_vector(uint64_t h, const std::vector<T>& v) {
  return fnv1a(h, v.data(), v.size() * sizeof(T));
}

// everything an env writes: observations, rewards, ids, step types, flags and masks
uint64_t hash_buffers(const VectorEnv& venv) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (int b = 0; b < venv.num_behaviors(); ++b) {
    const BehaviorBuffers& buf = venv.buffers(b);
    for (const auto& obs : buf.observations) h = hash_vector(h, obs);
    h = hash_vector(h, buf.reward);
    h = hash_vector(h, buf.group_reward);
    h = hash_vector(h, buf.agent_id);
    h = hash_vector(h, buf.group_id);
    h = hash_vector(h, buf.step_type);
    h = hash_vector(h, buf.terminated);
    h = hash_vector(h, buf.action_mask);
  }
  return h;
}

// Follows every slot of every env through its life cycle and checks each step's data.
class LifeCycleChecker {
 public:
  LifeCycleChecker(const EnvSpec& spec, int num_envs, Report* report)
      : spec_(spec), report_(report), envs_(num_envs) {
    for (auto& e : envs_)
      for (const auto& b : spec.behaviors) e.slots.emplace_back(b.agent_slots);
  }

  // checks the buffers after vector step `step` (0 = the initial reset)
  void observe(VectorEnv& venv, int step) {
    if (step == 0) metric_names_ = venv.episode_metric_names();
    for (int i = 0; i < static_cast<int>(envs_.size()); ++i) observe_env(venv, step, i);
  }

  // cross-checks the episodes the vector env reported as finished after step `step`
  void check_finished(const std::vector<FinishedEpisode>& finished, int step) {
    for (const auto& f : finished) {
      if (f.env_index < 0 || f.env_index >= static_cast<int>(envs_.size())) {
        report_->add("step " + std::to_string(step) + ": finished episode of unknown env " +
                     std::to_string(f.env_index));
        continue;
      }
      ++envs_[f.env_index].episodes_reported;
      std::vector<std::string> names;
      for (const auto& [name, value] : f.metrics) names.push_back(name);  // in order: a map
      if (names != metric_names_)
        report_->add(
            where(step, f.env_index) + "episode metrics " + join(names) +
            " differ from the names episode_metrics() gave after reset: " + join(metric_names_));
      for (const auto& [name, value] : f.metrics) {
        if (name.empty())
          report_->add(where(step, f.env_index) + "episode metric with an empty name");
        if (!std::isfinite(value))
          report_->add(where(step, f.env_index) + "episode metric '" + name +
                       "' = " + std::to_string(value) + " is not finite");
      }
    }
  }

  // after the last step: every episode the checker saw end was reported by the vector env
  void check_totals() {
    for (int i = 0; i < static_cast<int>(envs_.size()); ++i) {
      const EnvTrack& e = envs_[i];
      if (e.broken || e.episodes_ended == e.episodes_reported) continue;
      report_->add("env " + std::to_string(i) + ": " + std::to_string(e.episodes_ended) +
                   " episodes ended but " + std::to_string(e.episodes_reported) +
                   " were reported by take_finished_episodes()");
    }
  }

 private:
  struct SlotTrack {
    StepType type = StepType::kAbsent;
    int32_t id = -1;
  };
  struct EnvTrack {
    bool expect_reset = true;       // the next step starts a new episode
    bool broken = false;            // stop following an env whose reset produced no agent
    int decisions = 0;              // steps taken in the current episode
    bool overdue_reported = false;  // "longer than max_episode_steps" already said
    std::set<int32_t> ended;        // ids that had their kLast in this episode
    std::vector<std::vector<SlotTrack>> slots;  // [behavior][slot]
    int episodes_ended = 0;
    int episodes_reported = 0;
  };

  static std::string where(int step, int env) {
    return "step " + std::to_string(step) + ", env " + std::to_string(env) + ": ";
  }
  std::string where(int step, int env, int behavior, int slot) const {
    return "step " + std::to_string(step) + ", env " + std::to_string(env) + ", behavior '" +
           spec_.behaviors[behavior].name + "', slot " + std::to_string(slot) + ": ";
  }

  void observe_env(VectorEnv& venv, int step, int i) {
    EnvTrack& e = envs_[i];
    if (e.broken) return;
    const bool is_reset = e.expect_reset;
    if (is_reset) {
      e.ended.clear();
      e.decisions = 0;
      e.overdue_reported = false;
    } else {
      ++e.decisions;
    }

    std::set<int32_t> present;  // ids of the agents present in this env now
    bool anyone_acts = false;
    for (int b = 0; b < venv.num_behaviors(); ++b) {
      BehaviorBuffers& buf = venv.buffers(b);
      const int slots = buf.spec.agent_slots;
      for (int s = 0; s < slots; ++s) {
        const int row = i * slots + s;
        const std::string at = where(step, i, b, s);
        const StepType type = buf.step_type[row];
        SlotTrack& prev = e.slots[b][s];
        if (static_cast<int>(type) > static_cast<int>(StepType::kLast)) {
          report_->add(at + "invalid step type " + std::to_string(int(type)));
          prev = {StepType::kAbsent, -1};
          continue;
        }
        check_transition(at, is_reset, prev.type, type);
        if (type == StepType::kAbsent) {
          prev = {type, -1};
          continue;
        }

        // identity of the agent in this slot
        const int32_t id = buf.agent_id[row];
        if (id < 0) report_->add(at + "agent id " + std::to_string(id) + " is negative");
        if (!present.insert(id).second)
          report_->add(at + "agent id " + std::to_string(id) + " is used by two present agents");
        if (e.ended.count(id))
          report_->add(at + "agent id " + std::to_string(id) + " came back (" +
                       step_type_name(type) + ") after its kLast in this episode");
        if (!is_reset && needs_action(prev.type) && id != prev.id)
          report_->add(at + "agent id changed from " + std::to_string(prev.id) + " to " +
                       std::to_string(id) + " while the agent was alive");

        check_data(at, buf, row, type);
        if (needs_action(type)) anyone_acts = true;
        if (type == StepType::kLast) e.ended.insert(id);
        prev = {type, id};
      }
    }

    // episode boundaries
    if (is_reset && !anyone_acts) {
      report_->add(where(step, i) + "reset produced no agent that must act");
      e.broken = true;
      return;
    }
    const int max_steps = spec_.max_episode_steps;
    if (!anyone_acts) {
      e.expect_reset = true;
      ++e.episodes_ended;
      if (e.decisions > max_steps)
        report_->add(where(step, i) + "episode ended after " + std::to_string(e.decisions) +
                     " steps, more than max_episode_steps = " + std::to_string(max_steps));
    } else {
      e.expect_reset = false;
      if (e.decisions >= max_steps && !e.overdue_reported) {
        report_->add(where(step, i) + "agents still act after " + std::to_string(e.decisions) +
                     " steps; max_episode_steps = " + std::to_string(max_steps));
        e.overdue_reported = true;
      }
    }
  }

  void check_transition(const std::string& at, bool is_reset, StepType prev, StepType type) {
    bool ok;
    if (is_reset) {
      ok = type == StepType::kFirst || type == StepType::kAbsent;
    } else if (prev == StepType::kAbsent || prev == StepType::kLast) {
      ok = type == StepType::kAbsent;
    } else {
      ok = type == StepType::kMid || type == StepType::kLast;
    }
    if (ok) return;
    report_->add(at + (is_reset ? std::string("reset") : std::string(step_type_name(prev))) +
                 " followed by " + step_type_name(type) +
                 " (expected: reset -> kFirst|kAbsent, kFirst|kMid -> kMid|kLast, "
                 "kLast|kAbsent -> kAbsent until the next reset)");
  }

  // observations, rewards, flags and masks of one present slot
  void check_data(const std::string& at, const BehaviorBuffers& buf, int row, StepType type) {
    const BehaviorSpec& spec = buf.spec;
    for (size_t k = 0; k < spec.observations.size(); ++k) {
      const ObservationSpec& o = spec.observations[k];
      const float* obs = buf.observations[k].data() + size_t(row) * o.size();  // [obs_size]
      for (int j = 0; j < o.size(); ++j) {
        const float v = obs[j];
        if (std::isfinite(v) && v >= o.low && v <= o.high) continue;
        std::ostringstream msg;
        msg << at << "observation '" << o.name << "'[" << j << "] = " << v
            << (std::isfinite(v) ? " is outside [" : " is not finite; bounds [") << o.low << ", "
            << o.high << "]";
        report_->add(msg.str());
        break;  // one message per observation
      }
    }
    if (!std::isfinite(buf.reward[row]) || !std::isfinite(buf.group_reward[row]))
      report_->add(at + "reward " + std::to_string(buf.reward[row]) + " / group reward " +
                   std::to_string(buf.group_reward[row]) + " is not finite");
    if (type == StepType::kFirst && (buf.reward[row] != 0.f || buf.group_reward[row] != 0.f))
      report_->add(at + "kFirst carries a nonzero reward");
    const uint8_t terminated = buf.terminated[row];
    if (terminated > 1)
      report_->add(at + "terminated = " + std::to_string(terminated) + " is not 0 or 1");
    if (type != StepType::kLast && terminated != 0)
      report_->add(at + "terminated is set on a " + step_type_name(type) + " step");

    // masks of agents that must act: values 0/1, at least one allowed option per branch
    if (!needs_action(type)) return;
    const ActionSpec& action = spec.action;
    const uint8_t* mask = buf.action_mask.data() + size_t(row) * action.mask_size();
    int offset = 0;
    for (int br = 0; br < action.num_branches(); ++br) {
      int allowed = 0;
      for (int k = 0; k < action.discrete_branches[br]; ++k) {
        const uint8_t m = mask[offset + k];
        if (m > 1) report_->add(at + "action mask value " + std::to_string(m) + " is not 0 or 1");
        allowed += m != 0;
      }
      if (allowed == 0)
        report_->add(at + "action mask allows no option of branch " + std::to_string(br));
      offset += action.discrete_branches[br];
    }
  }

  const EnvSpec& spec_;
  Report* report_;
  std::vector<EnvTrack> envs_;
  std::vector<std::string> metric_names_;  // episode_metrics() names after the reset, in order
};

// Runs `steps` random-action steps after a reset (or a reseed_and_reset when `reseed`), returning
// the buffer fingerprint after the reset and after each step. `checker` may be null.
std::vector<uint64_t> rollout(VectorEnv& venv, const ConformanceOptions& opts, int steps,
                              bool reseed, LifeCycleChecker* checker) {
  std::vector<uint64_t> hashes;
  RandomActor actor(opts.seed);
  if (reseed) {
    venv.reseed_and_reset(opts.seed);
  } else {
    venv.reset();
  }
  hashes.push_back(hash_buffers(venv));
  if (checker) checker->observe(venv, 0);
  for (int t = 1; t <= steps; ++t) {
    for (int b = 0; b < venv.num_behaviors(); ++b) actor.act(venv.buffers(b));
    venv.step();
    hashes.push_back(hash_buffers(venv));
    auto finished = venv.take_finished_episodes();
    if (checker) {
      checker->observe(venv, t);
      checker->check_finished(finished, t);
    }
  }
  if (checker) checker->check_totals();
  return hashes;
}

// index of the first differing fingerprint, or -1
int first_difference(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b) {
  for (size_t t = 0; t < a.size() && t < b.size(); ++t)
    if (a[t] != b[t]) return static_cast<int>(t);
  return a.size() == b.size() ? -1 : static_cast<int>(std::min(a.size(), b.size()));
}

}  // namespace

std::vector<std::string> check_env_spec(const EnvSpec& spec) {
  std::vector<std::string> out;
  if (spec.name.empty()) out.push_back("spec: the env name is empty");
  if (spec.behaviors.empty()) out.push_back("spec: no behavior");
  if (spec.max_episode_steps <= 0)
    out.push_back("spec: max_episode_steps = " + std::to_string(spec.max_episode_steps) +
                  " must be positive");
  for (const auto& [name, value] : spec.default_parameters)
    if (name.empty() || !std::isfinite(value))
      out.push_back("spec: default parameter '" + name + "' is unnamed or not finite");

  std::set<std::string> behavior_names;
  for (const auto& b : spec.behaviors) {
    const std::string at = "spec: behavior '" + b.name + "': ";
    if (b.name.empty()) out.push_back("spec: a behavior has an empty name");
    if (!behavior_names.insert(b.name).second) out.push_back(at + "name used twice");
    if (b.agent_slots < 1)
      out.push_back(at + "agent_slots = " + std::to_string(b.agent_slots) + " must be >= 1");
    if (b.observations.empty()) out.push_back(at + "no observation");

    // observations
    std::set<std::string> obs_names;
    for (const auto& o : b.observations) {
      const std::string oat = at + "observation '" + o.name + "': ";
      if (o.name.empty()) out.push_back(at + "an observation has an empty name");
      if (!obs_names.insert(o.name).second) out.push_back(oat + "name used twice");
      const size_t dims = o.kind == ObservationKind::kGrid ? 3 : 1;
      if (o.shape.size() != dims)
        out.push_back(oat + "shape has " + std::to_string(o.shape.size()) + " dims, expected " +
                      std::to_string(dims) +
                      (dims == 3 ? " (height, width, channels)" : " (size)"));
      for (int d : o.shape)
        if (d <= 0)
          out.push_back(oat + "shape dimension " + std::to_string(d) + " is not positive");
      if (std::isnan(o.low) || std::isnan(o.high) || o.low > o.high)
        out.push_back(oat + "bounds [" + std::to_string(o.low) + ", " + std::to_string(o.high) +
                      "] are not an interval");
    }

    // actions
    const ActionSpec& a = b.action;
    if (a.continuous_size < 0)
      out.push_back(at + "continuous_size = " + std::to_string(a.continuous_size) + " is negative");
    if (a.continuous_size <= 0 && a.num_branches() == 0) out.push_back(at + "no action");
    for (int n : a.discrete_branches)
      if (n < 1) out.push_back(at + "a discrete branch has " + std::to_string(n) + " options");
  }
  return out;
}

std::vector<std::string> check_env_conformance(const std::string& env_id, const Parameters& params,
                                               const ConformanceOptions& opts) {
  Report report(env_id + ": ", opts.max_violations);
  if (opts.num_envs < 1) {
    report.add("options: num_envs must be at least 1");
    return report.finish();
  }
  // stage names say where an exception came from
  std::string stage = "construction";
  try {
    VectorEnv first(env_id, opts.num_envs, opts.seed, params, /*threads=*/1);
    const EnvSpec spec = first.spec();

    // spec sanity; rollouts on a broken spec could not be trusted
    stage = "spec check";
    for (const auto& v : check_env_spec(spec)) report.add(v);
    if (report.count() > 0) return report.finish();
    const int steps = opts.steps > 0 ? opts.steps : 2 * (spec.max_episode_steps + 1);

    // life cycle and data of every step, on one thread
    stage = "rollout (seed " + std::to_string(opts.seed) + ", 1 thread)";
    LifeCycleChecker checker(spec, opts.num_envs, &report);
    const auto reference = rollout(first, opts, steps, /*reseed=*/false, &checker);

    // same seed on more threads: bit-identical
    stage = "rollout (seed " + std::to_string(opts.seed) + ", " + std::to_string(opts.threads) +
            " threads)";
    VectorEnv second(env_id, opts.num_envs, opts.seed, params, opts.threads);
    int diff = first_difference(reference, rollout(second, opts, steps, false, nullptr));
    if (diff >= 0)
      report.add("same seed " + std::to_string(opts.seed) + " on 1 and " +
                 std::to_string(opts.threads) + " threads: trajectories differ from step " +
                 std::to_string(diff));

    // same seed again through reseed_and_reset on a used vector env: bit-identical
    stage = "rollout after reseed_and_reset(" + std::to_string(opts.seed) + ")";
    diff = first_difference(reference, rollout(second, opts, steps, /*reseed=*/true, nullptr));
    if (diff >= 0)
      report.add("reseed_and_reset(" + std::to_string(opts.seed) +
                 ") did not repeat the trajectory: it differs from step " + std::to_string(diff));

    // another seed: a different trajectory
    if (opts.expect_seed_divergence) {
      const uint64_t other_seed = opts.seed + 1000003;
      stage = "rollout (seed " + std::to_string(other_seed) + ")";
      VectorEnv third(env_id, opts.num_envs, other_seed, params, 1);
      if (first_difference(reference, rollout(third, opts, steps, false, nullptr)) < 0)
        report.add("seeds " + std::to_string(opts.seed) + " and " + std::to_string(other_seed) +
                   " gave the same trajectory: the env ignores its seed");
    }
  } catch (const std::exception& e) {
    report.add("threw during " + stage + ": " + e.what());
  } catch (...) {
    report.add("threw a non-standard exception during " + stage);
  }
  return report.finish();
}

}  // namespace rlt
