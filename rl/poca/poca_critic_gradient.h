// MA-POCA's critic losses on one minibatch and their gradient, written out by hand in Eigen (its
// large matrix products go through the BLAS, see matrix_product.h): the fast path of
// PocaTrainer::update, next to MlpPpoGradient for the actor.
//
// The losses are exactly clipped_value_loss() over PocaCriticImpl::value() and ::baseline() (see
// poca_critic.h); the autograd version is the reference, and the tests compare the two gradients
// with absent members, several heads and the value clip active on both sides.
// Two ways it does less than autograd, with the same result:
// - The own observation's embedding is the same in the value (first entity) and in the baseline
//   (first entity): computed once, its gradient the sum of both.
// - The value's and the baseline's entities go through the shared attention, norm, MLP and head
//   as one batch of 2B rows, so each layer is one product of twice the rows; the query, key and
//   value projections run once per distinct entity (B + 2BU of the 2B(1 + U) members: the own
//   entity is in both rows), the rest per member.
//
// Backward through the head, per row r of the 2B (N entities, present mask P, n_r = max(1, sum P)):
//   pooled:     dX_ri = P_ri / n_r * d pooled_r
//   layer norm: dX0 = (dxh - mean(dxh) - xh mean(dxh * xh)) / sigma, dxh = dX * gamma
//   residual:   dE = dX0 + (through out, then the attention) ...
//   attention:  per head, A = softmax(Q K^T / sqrt(d)) over the present keys, O = A V;
//               dA = dO V^T, dS = A * (dA - rowsum(A * dA)), dQ = dS K / sqrt(d),
//               dK = dS^T Q / sqrt(d), dV = A^T dO (an absent key has A = 0, so no gradient)
// then through the query, key and value projections and the embeddings' activation.
#pragma once

#include <cstdint>
#include <vector>

#include "rl/core/matrix_product.h"
#include "rl/poca/poca_critic.h"

namespace rlt {

// One minibatch, row-major, B rows, U other-member slots (the slots some row uses).
struct CriticMinibatchView {
  int64_t rows = 0;                       // B
  int64_t others = 0;                     // U
  const float* obs = nullptr;             // [B, D] normalized own observations
  const float* others_obs = nullptr;      // [B, U, D] normalized observations of the others
  const float* others_actions = nullptr;  // [B, U, A] their encoded actions
  const float* others_present = nullptr;  // [B, U] 1 or 0
  const float* old = nullptr;             // [B, 3] old value, old baseline, return
};

struct CriticLossValues {
  double value = 0, baseline = 0;  // clipped_value_loss of each
};

class PocaCriticGradient {
 public:
  explicit PocaCriticGradient(PocaCriticImpl& critic) : critic_(critic) {}

  // Computes both losses and writes the gradient of value_coef * value + baseline_coef *
  // baseline into every critic parameter's .grad() (overwriting it).
  CriticLossValues compute(const CriticMinibatchView& mb, float epsilon, float value_coef,
                           float baseline_coef);

 private:
  // the forward pass of head() over R rows of N members, member i of row r being the distinct
  // entity units_[unit_of_[r N + i]], with present_ [R, N]; keeps what the backward pass needs
  // and returns the R outputs
  Eigen::VectorXf head_forward(int64_t rows, int64_t members);
  // given d loss / d output [R], writes the head's parameter gradients and leaves
  // d loss / d (distinct entities) in d_units_
  void head_backward(int64_t rows, int64_t members, const Eigen::VectorXf& d_out);

  PocaCriticImpl& critic_;
  // scratch, kept between minibatches (R = 2B rows: the values', then the baselines')
  RowMatrix obs_in_, obs_z_, obs_y_;           // [B + B U, D], [B + B U, H] x 2: own, then others
  RowMatrix action_in_, action_z_, action_y_;  // [B U, D + A], [B U, H] x 2
  RowMatrix units_, present_;       // [B + 2 B U, H] distinct entities (see compute()), [R, N]
  std::vector<int64_t> unit_of_;    // [R N] the distinct entity of each member of each row
  RowMatrix q_, k_, v_;             // [B + 2 B U, H] each: the distinct entities' projections
  RowMatrix attention_, attended_;  // [R heads N, N] weights, [R N, H] attended values
  RowMatrix normed_, x_;            // [R N, H]: the norm's standardized input, output
  Eigen::VectorXf inverse_sigma_;   // [R N]
  RowMatrix pooled_;                // [R, H]
  std::vector<RowMatrix> mlp_z_, mlp_y_;  // [R, H] per layer
  RowMatrix d_units_;                     // [B + 2 B U, H]
};

}  // namespace rlt
