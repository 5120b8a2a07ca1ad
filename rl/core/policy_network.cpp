#include "rl/core/policy_network.h"

#include <cmath>

namespace rlt {

torch::Tensor activate(Activation a, const torch::Tensor& x) {
  switch (a) {
    case Activation::kTanh:
      return torch::tanh(x);
    case Activation::kRelu:
      return torch::relu(x);
    case Activation::kSwish:
      return torch::silu(x);
  }
  return x;
}

PolicyNetworkImpl::PolicyNetworkImpl(const NetworkShape& shape) : shape_(shape) {
  const double hidden_gain = std::sqrt(2.0);
  const int h = shape.hidden_units;
  int in = shape.obs_size;
  for (int l = 0; l < shape.num_layers; ++l, in = h)
    actor_body.push_back(make_layer("actor" + std::to_string(l), in, h, hidden_gain));
  if (shape.action.continuous_size > 0) {
    mean_head = make_layer("mean_head", h, shape.action.continuous_size, 0.01);
    log_std = register_parameter("log_std", torch::zeros({shape.action.continuous_size}));
  }
  if (shape.action.num_branches() > 0)
    logits_head = make_layer("logits_head", h, shape.action.mask_size(), 0.01);
  if (!shape.with_critic) return;
  if (!shape.shared_critic) {
    in = shape.obs_size;
    for (int l = 0; l < shape.num_layers; ++l, in = h)
      critic_body.push_back(make_layer("critic" + std::to_string(l), in, h, hidden_gain));
  }
  value_head = make_layer("value_head", h, 1, 1.0);
}

DenseLayer PolicyNetworkImpl::make_layer(const std::string& name, int in, int out, double gain) {
  // orthogonal init of the [out, in] matrix, stored transposed
  auto w = torch::empty({out, in});
  torch::nn::init::orthogonal_(w, gain);
  DenseLayer layer;
  layer.weight = register_parameter(name + "_weight", w.t().contiguous());
  layer.bias = register_parameter(name + "_bias", torch::zeros({out}));
  return layer;
}

torch::Tensor PolicyNetworkImpl::run_body(const std::vector<DenseLayer>& body,
                                          torch::Tensor x) const {
  for (const auto& layer : body) x = activate(shape_.activation, torch::addmm(layer.bias, x, layer.weight));
  return x;
}

PolicyNetworkImpl::ActorOutput PolicyNetworkImpl::actor(const torch::Tensor& obs) const {
  ActorOutput out;
  out.hidden = run_body(actor_body, obs);
  if (shape_.action.continuous_size > 0)
    out.mean = torch::addmm(mean_head.bias, out.hidden, mean_head.weight);
  if (shape_.action.num_branches() > 0)
    out.logits = torch::addmm(logits_head.bias, out.hidden, logits_head.weight);
  return out;
}

torch::Tensor PolicyNetworkImpl::value(const torch::Tensor& obs,
                                       const torch::Tensor& actor_hidden) const {
  torch::Tensor hidden;
  if (shape_.shared_critic)
    hidden = actor_hidden.defined() ? actor_hidden : run_body(actor_body, obs);
  else
    hidden = run_body(critic_body, obs);
  return torch::addmm(value_head.bias, hidden, value_head.weight).squeeze(1);
}

}  // namespace rlt
