#include "env/toy/escape.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rl/env_api/uniform_random.h"

namespace rlt {

Escape::Escape() {
  BehaviorSpec behavior;
  behavior.name = "EscapeAgent";
  behavior.observations.push_back(
      {"state", {kObservationSize}, ObservationKind::kVector, -1.f, 1.f});
  behavior.action.discrete_branches = {kActions};
  behavior.agent_slots = kAgents;
  spec_.name = "Escape";
  spec_.behaviors.push_back(behavior);
  spec_.max_episode_steps = kEpisodeSteps;
  spec_.default_parameters = {{"grid_size", kDefaultGrid}};
}

void Escape::seed(uint64_t seed) { engine_.seed(seed); }

Escape::Cell Escape::moved(Cell c, int action, int n) {
  switch (action) {
    case 1:
      c.y = std::min(c.y + 1, n - 1);
      break;
    case 2:
      c.y = std::max(c.y - 1, 0);
      break;
    case 3:
      c.x = std::max(c.x - 1, 0);
      break;
    case 4:
      c.x = std::min(c.x + 1, n - 1);
      break;
    default:
      break;
  }
  return c;
}

void Escape::write_observation(BehaviorView& view, int slot) const {
  const float scale = 1.f / static_cast<float>(grid_ - 1);
  const Cell& me = agents_[slot];
  auto rel = [&](const Cell& c, float* out) {
    out[0] = static_cast<float>(c.x - me.x) * scale;
    out[1] = static_cast<float>(c.y - me.y) * scale;
  };
  float* obs = view.observation(slot, 0);  // [19]
  std::fill(obs, obs + kObservationSize, 0.f);

  // own position and time
  obs[0] = static_cast<float>(me.x) * scale;
  obs[1] = static_cast<float>(me.y) * scale;
  obs[2] = static_cast<float>(elapsed_) / static_cast<float>(kEpisodeSteps);
  // guard
  if (guard_alive_) {
    rel(guard_, obs + 3);
    obs[5] = 1.f;
  }
  // key: on the floor, with me, or with a teammate (then it is where the teammate is)
  if (key_on_floor_) {
    rel(key_, obs + 6);
    obs[8] = 1.f;
  } else if (key_holder_ == slot) {
    obs[9] = 1.f;
  } else if (key_holder_ >= 0) {
    rel(agents_[key_holder_], obs + 6);
    obs[10] = 1.f;
  }
  // door
  rel(door_, obs + 11);
  // teammates, in slot order after mine
  for (int k = 1; k < kAgents; ++k) {
    const int other = (slot + k) % kAgents;
    float* mate = obs + 13 + 3 * (k - 1);  // [3]
    if (!present_[other]) continue;
    rel(agents_[other], mate);
    mate[2] = 1.f;
  }
}

void Escape::reset(StepView& out) {
  grid_ = std::clamp(static_cast<int>(std::lround(parameter("grid_size"))), kMinGrid, kMaxGrid);

  // five different cells: agents 0-2, guard, door (a partial Fisher-Yates draw over the cells)
  std::array<int, kMaxGrid * kMaxGrid> cells{};
  const int num_cells = grid_ * grid_;
  for (int i = 0; i < num_cells; ++i) cells[i] = i;
  for (int i = 0; i < kAgents + 2; ++i)
    std::swap(cells[i], cells[i + uniform_int(engine_, num_cells - i)]);
  auto cell = [&](int i) { return Cell{cells[i] % grid_, cells[i] / grid_}; };
  for (int s = 0; s < kAgents; ++s) {
    agents_[s] = cell(s);
    present_[s] = true;
  }
  guard_ = cell(kAgents);
  door_ = cell(kAgents + 1);
  guard_alive_ = true;
  key_ = guard_;
  key_on_floor_ = false;
  key_holder_ = -1;
  elapsed_ = 0;
  success_ = false;

  BehaviorView& view = out[0];
  for (int s = 0; s < kAgents; ++s) {
    view.step_type(s) = StepType::kFirst;
    view.agent_id(s) = s;
    view.group_id(s) = 0;
    view.reward(s) = 0.f;
    view.group_reward(s) = 0.f;
    view.terminated(s) = 0;
    std::fill(view.action_mask(s), view.action_mask(s) + kActions, uint8_t{1});
    write_observation(view, s);
  }
}

void Escape::step(StepView& io) {
  BehaviorView& view = io[0];

  // agents that left (or never were) stay absent until the next reset
  std::array<bool, kAgents> acting{};
  for (int s = 0; s < kAgents; ++s) {
    acting[s] = needs_action(view.step_type(s));
    if (acting[s]) continue;
    view.step_type(s) = StepType::kAbsent;
    view.agent_id(s) = -1;
  }

  // 1. moves
  for (int s = 0; s < kAgents; ++s) {
    if (!acting[s]) continue;
    const int action = view.discrete_action(s)[0];
    if (action < 0 || action >= kActions)
      throw std::invalid_argument("Escape: action " + std::to_string(action) + " of slot " +
                                  std::to_string(s) + " is outside [0, 5)");
    agents_[s] = moved(agents_[s], action, grid_);
  }
  ++elapsed_;

  // 2. sacrifice: the guard takes the first agent on its cell and drops the key there
  int sacrificed = -1;
  if (guard_alive_) {
    for (int s = 0; s < kAgents && sacrificed < 0; ++s)
      if (acting[s] && agents_[s] == guard_) sacrificed = s;
    if (sacrificed >= 0) {
      present_[sacrificed] = false;
      guard_alive_ = false;
      key_ = guard_;
      key_on_floor_ = true;
    }
  }

  // 3. pick-up by the first other agent on the key
  if (key_on_floor_) {
    for (int s = 0; s < kAgents; ++s) {
      if (!acting[s] || s == sacrificed || !(agents_[s] == key_)) continue;
      key_holder_ = s;
      key_on_floor_ = false;
      break;
    }
  }

  // 4. escape through the door with the key
  success_ = key_holder_ >= 0 && agents_[key_holder_] == door_;
  const bool truncated = !success_ && elapsed_ >= kEpisodeSteps;
  const float escape_reward =
      1.f - 0.5f * static_cast<float>(elapsed_) / static_cast<float>(kEpisodeSteps);

  // step data of every agent that acted
  for (int s = 0; s < kAgents; ++s) {
    if (!acting[s]) continue;
    write_observation(view, s);
    if (s == sacrificed) {
      view.step_type(s) = StepType::kLast;
      view.terminated(s) = 1;
    } else if (success_) {
      view.group_reward(s) = escape_reward;
      view.step_type(s) = StepType::kLast;
      view.terminated(s) = 1;
    } else if (truncated) {
      view.step_type(s) = StepType::kLast;
      view.terminated(s) = 0;
    } else {
      view.step_type(s) = StepType::kMid;
    }
  }
}

EpisodeMetrics Escape::episode_metrics() const {
  return {{"success_rate", success_ ? 1.f : 0.f}, {"sacrificed", guard_alive_ ? 0.f : 1.f}};
}

}  // namespace rlt
