#include "rl/poca/poca_critic.h"

#include <cmath>

#include "rl/core/policy_network.h"

namespace rlt {

PocaCriticImpl::PocaCriticImpl(const PocaCriticShape& shape) : shape_(shape) {
  const int h = shape.hidden_units;
  if (shape_.heads < 1 || h % shape_.heads != 0) shape_.heads = 1;
  obs_embedding_ = register_module("obs_embedding", torch::nn::Linear(shape.obs_size, h));
  obs_action_embedding_ = register_module(
      "obs_action_embedding", torch::nn::Linear(shape.obs_size + shape.action_size, h));
  query_ = register_module("query", torch::nn::Linear(h, h));
  key_ = register_module("key", torch::nn::Linear(h, h));
  value_ = register_module("value", torch::nn::Linear(h, h));
  out_ = register_module("out", torch::nn::Linear(h, h));
  norm_ = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({h})));
  mlp_ = register_module("mlp", torch::nn::ModuleList());
  for (int l = 0; l < shape.num_layers; ++l) mlp_->push_back(torch::nn::Linear(h, h));
  value_head_ = register_module("value_head", torch::nn::Linear(h, 1));
}

torch::Tensor PocaCriticImpl::head(const torch::Tensor& entities, const torch::Tensor& present) {
  const int64_t b = entities.size(0), n = entities.size(1), h = entities.size(2);
  const int64_t heads = shape_.heads, d = h / heads;
  // multi-head self-attention over entities; absent entities are masked as keys
  auto split = [&](const torch::Tensor& t) { return t.view({b, n, heads, d}).transpose(1, 2); };
  auto q = split(query_->forward(entities));                            // [B, heads, N, d]
  auto k = split(key_->forward(entities));                              // [B, heads, N, d]
  auto v = split(value_->forward(entities));                            // [B, heads, N, d]
  auto scores = torch::matmul(q, k.transpose(2, 3)) / std::sqrt(double(d));  // [B, heads, N, N]
  auto key_mask = present.view({b, 1, 1, n});
  scores = scores.masked_fill(key_mask < 0.5, -1e9);
  auto attended = torch::matmul(torch::softmax(scores, -1), v);         // [B, heads, N, d]
  attended = attended.transpose(1, 2).reshape({b, n, h});               // [B, N, H]
  auto x = norm_->forward(entities + out_->forward(attended));          // [B, N, H]
  // masked mean over the members present
  auto weights = present.unsqueeze(2);                                  // [B, N, 1]
  auto pooled = (x * weights).sum(1) / weights.sum(1).clamp_min(1.f);   // [B, H]
  for (const auto& layer : *mlp_)
    pooled = activate(shape_.activation, layer->as<torch::nn::Linear>()->forward(pooled));
  return value_head_->forward(pooled).squeeze(1);                       // [B]
}

torch::Tensor PocaCriticImpl::value(const torch::Tensor& obs, const torch::Tensor& present) {
  auto entities = activate(shape_.activation, obs_embedding_->forward(obs));  // [B, N, H]
  return head(entities, present);
}

torch::Tensor PocaCriticImpl::baseline(const torch::Tensor& own_obs, const torch::Tensor& others_obs,
                                       const torch::Tensor& others_actions,
                                       const torch::Tensor& others_present) {
  auto own = activate(shape_.activation, obs_embedding_->forward(own_obs)).unsqueeze(1);  // [B, 1, H]
  auto others = activate(shape_.activation,
                         obs_action_embedding_->forward(torch::cat({others_obs, others_actions}, 2)));
  auto entities = torch::cat({own, others}, 1);                                  // [B, N, H]
  auto present = torch::cat({torch::ones({own_obs.size(0), 1}), others_present}, 1);  // [B, N]
  return head(entities, present);
}

}  // namespace rlt
