// Actor and critic MLPs of one behavior, written with explicit matrix products so that a forward pass
// costs as few LibTorch calls as possible.
//
// Reference: CleanRL ppo.py / ppo_continuous_action.py (separate actor and critic MLPs, orthogonal
// initialization with gain sqrt(2) for hidden layers, 0.01 for the policy head, 1 for the value head,
// state-independent log-std initialized at 0) and ML-Agents `networks.py` (shared_critic option).
// Layer weights are stored [in, out] so that a layer is one addmm: y = b + x W.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "rl/config/run_config.h"
#include "rl/env_api/spec.h"

namespace rlt {

struct NetworkShape {
  int obs_size = 0;          // flattened, concatenated observations
  ActionSpec action;
  int hidden_units = 128;
  int num_layers = 2;
  Activation activation = Activation::kSwish;
  bool shared_critic = false;  // critic head on the actor's body
  bool with_critic = true;     // false: actor only (MA-POCA keeps its critic elsewhere)
};

struct DenseLayer {
  torch::Tensor weight;  // [in, out]
  torch::Tensor bias;    // [out]
};

class PolicyNetworkImpl : public torch::nn::Module {
 public:
  explicit PolicyNetworkImpl(const NetworkShape& shape);

  const NetworkShape& shape() const { return shape_; }

  struct ActorOutput {
    torch::Tensor mean;    // [B, C] (undefined when C = 0)
    torch::Tensor logits;  // [B, M] (undefined without discrete branches)
    torch::Tensor hidden;  // [B, H] last hidden layer of the actor body
  };
  // obs: [B, obs_size], already normalized
  ActorOutput actor(const torch::Tensor& obs) const;
  // obs: [B, obs_size] -> [B]; reuses `actor_hidden` when the critic is shared
  torch::Tensor value(const torch::Tensor& obs, const torch::Tensor& actor_hidden = {}) const;

  torch::Tensor log_std;  // [C] state-independent log standard deviation

  std::vector<DenseLayer> actor_body;   // num_layers hidden layers
  DenseLayer mean_head;                 // [H, C]
  DenseLayer logits_head;               // [H, M]
  std::vector<DenseLayer> critic_body;  // empty when shared_critic or without critic
  DenseLayer value_head;                // [H, 1] (undefined without critic)

 private:
  DenseLayer make_layer(const std::string& name, int in, int out, double gain);
  torch::Tensor run_body(const std::vector<DenseLayer>& body, torch::Tensor x) const;

  NetworkShape shape_;
};
TORCH_MODULE(PolicyNetwork);

// activation applied elementwise
torch::Tensor activate(Activation a, const torch::Tensor& x);

}  // namespace rlt
