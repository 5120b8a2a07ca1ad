// Experiences of one behavior: a running trajectory of one agent, or the update buffer of
// processed experiences waiting for the next update. Every array is row-major so that LibTorch
// wraps it without copying. The group fields are used by MA-POCA only (sizes 0 otherwise).
#pragma once

#include <torch/torch.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rl/core/archive_io.h"

namespace rlt {

struct ExperienceBuffer {
  int obs_size = 0, continuous_size = 0, num_branches = 0, mask_size = 0;
  int others = 0;       // MA-POCA: other member slots of the agent's group (N - 1)
  int action_code = 0;  // MA-POCA: size of an encoded action (continuous + one-hot branches)

  std::vector<float> obs;            // [N, obs_size] raw observations
  std::vector<float> continuous;     // [N, continuous_size] raw sampled actions
  std::vector<int64_t> discrete;     // [N, num_branches] chosen options
  std::vector<float> mask;           // [N, mask_size] 1 = allowed
  std::vector<float> log_prob;       // [N] joint log-probability when acting
  std::vector<float> value;          // [N] value estimate (PPO: when acting; POCA: group value)
  std::vector<float> returns;        // [N] value targets
  std::vector<float> advantages;     // [N]
  std::vector<float> others_obs;     // [N, others, obs_size] groupmates' raw observations
  std::vector<float> others_action;  // [N, others, action_code] groupmates' encoded actions
  std::vector<float> others_present; // [N, others] 1 when the slot held a groupmate
  std::vector<float> baseline;       // [N] counterfactual baseline (POCA)

  int64_t size() const { return static_cast<int64_t>(log_prob.size()); }

  struct Field {
    const char* name;
    std::vector<float>* data;
    int width;  // floats per experience
  };
  // every float field, in a fixed order
  std::array<Field, 11> fields() {
    return {{{"obs", &obs, obs_size},
             {"continuous", &continuous, continuous_size},
             {"mask", &mask, mask_size},
             {"log_prob", &log_prob, 1},
             {"value", &value, 1},
             {"returns", &returns, 1},
             {"advantages", &advantages, 1},
             {"others_obs", &others_obs, others * obs_size},
             {"others_action", &others_action, others * action_code},
             {"others_present", &others_present, others},
             {"baseline", &baseline, 1}}};
  }

  void clear() {
    for (auto& f : fields()) f.data->clear();
    discrete.clear();
  }
  // keeps the first `rows` experiences of every field that has them
  void truncate(int64_t rows) {
    for (auto& f : fields())
      if (int64_t(f.data->size()) > rows * f.width) f.data->resize(rows * f.width);
    if (int64_t(discrete.size()) > rows * num_branches) discrete.resize(rows * num_branches);
  }
  // appends `other`, which has the same layout
  void append(ExperienceBuffer& other) {
    auto mine = fields(), theirs = other.fields();
    for (size_t i = 0; i < mine.size(); ++i)
      mine[i].data->insert(mine[i].data->end(), theirs[i].data->begin(), theirs[i].data->end());
    discrete.insert(discrete.end(), other.discrete.begin(), other.discrete.end());
  }
  void save(torch::serialize::OutputArchive& a, const std::string& prefix) const {
    for (auto& f : const_cast<ExperienceBuffer*>(this)->fields()) write_vector(a, prefix + f.name, *f.data);
    write_vector(a, prefix + "discrete", discrete);
  }
  void load(torch::serialize::InputArchive& a, const std::string& prefix) {
    for (auto& f : fields()) *f.data = read_vector<float>(a, prefix + f.name);
    discrete = read_vector<int64_t>(a, prefix + "discrete");
  }
};

}  // namespace rlt
