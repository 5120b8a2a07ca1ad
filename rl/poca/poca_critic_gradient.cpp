#include "rl/poca/poca_critic_gradient.h"

#include <algorithm>
#include <cmath>

#include "rl/core/eigen_layers.h"
#include "rl/ppo/ppo_loss.h"

namespace rlt {

namespace {

using Segment = Eigen::Map<Eigen::VectorXf>;  // one head's d floats of a row
using ConstSegment = Eigen::Map<const Eigen::VectorXf>;

// out = x W^T + b for a linear layer (weight [out, in])
void linear_forward(const torch::nn::LinearImpl& layer, const RowMatrix& x, RowMatrix& out) {
  out.resize(x.rows(), layer.weight.size(0));
  multiply(x, Transpose::kNo, matrix_of(layer.weight), Transpose::kYes, out);
  out.rowwise() += row_of(layer.bias);
}

// writes the layer's weight and bias gradients from d out [R, out] and its input x [R, in];
// with d_x, also d x = d out W (added to d_x when accumulate)
void linear_backward(const torch::nn::LinearImpl& layer, const RowMatrix& x, const RowMatrix& d_out,
                     RowMatrix* d_x = nullptr, bool accumulate = false) {
  MatrixMap weight_gradient = matrix_grad(layer.weight);
  multiply(d_out, Transpose::kYes, x, Transpose::kNo, weight_gradient);
  row_grad(layer.bias) = d_out.colwise().sum();
  if (d_x)
    multiply(d_out, Transpose::kNo, matrix_of(layer.weight), Transpose::kNo, *d_x, accumulate);
}

}  // namespace

CriticLossValues PocaCriticGradient::compute(const CriticMinibatchView& mb, float epsilon,
                                             float value_coef, float baseline_coef) {
  const auto& shape = critic_.shape();
  const int64_t B = mb.rows, U = mb.others, N = 1 + U, R = 2 * B;
  const int64_t D = shape.obs_size, A = shape.action_size, H = shape.hidden_units;

  // forward: embeddings, the own observations' once for the value and the baseline
  obs_in_.resize(B + B * U, D);
  obs_in_.topRows(B) = ConstMatrixMap(mb.obs, B, D);
  if (U > 0) obs_in_.bottomRows(B * U) = ConstMatrixMap(mb.others_obs, B * U, D);
  linear_forward(*critic_.obs_embedding_, obs_in_, obs_z_);
  activate(shape.activation, obs_z_, obs_y_);
  if (U > 0) {
    action_in_.resize(B * U, D + A);
    action_in_.leftCols(D) = ConstMatrixMap(mb.others_obs, B * U, D);
    action_in_.rightCols(A) = ConstMatrixMap(mb.others_actions, B * U, A);
    linear_forward(*critic_.obs_action_embedding_, action_in_, action_z_);
    activate(shape.activation, action_z_, action_y_);
  }
  // the distinct entities: the own embeddings [B], the others' observation embeddings [B U],
  // their (observation, action) embeddings [B U]; the values' rows 0..B-1 have the own and the
  // others' observation embeddings as members, the baselines' rows B..2B-1 the own and the
  // (observation, action) embeddings
  units_.resize(B + 2 * B * U, H);
  units_.topRows(B + B * U) = obs_y_;
  if (U > 0) units_.bottomRows(B * U) = action_y_;
  unit_of_.resize(R * N);
  present_.resize(R, N);
  for (int64_t b = 0; b < B; ++b) {
    unit_of_[b * N] = unit_of_[(B + b) * N] = b;
    present_(b, 0) = present_(B + b, 0) = 1.f;
    for (int64_t u = 0; u < U; ++u) {
      unit_of_[b * N + 1 + u] = B + b * U + u;
      unit_of_[(B + b) * N + 1 + u] = B + B * U + b * U + u;
      present_(b, 1 + u) = present_(B + b, 1 + u) = mb.others_present[b * U + u];
    }
  }
  const Eigen::VectorXf out = head_forward(R, N);  // [2B]

  // losses and their gradient with respect to the outputs
  const ConstMatrixMap old(mb.old, B, 3);  // old value, old baseline, return
  CriticLossValues losses;
  Eigen::VectorXf d_out(R);
  for (int64_t b = 0; b < B; ++b) {
    const ClippedValueTerm v = clipped_value_term(out[b], old(b, 0), old(b, 2), epsilon);
    const ClippedValueTerm base = clipped_value_term(out[B + b], old(b, 1), old(b, 2), epsilon);
    losses.value += v.loss / B;
    losses.baseline += base.loss / B;
    d_out[b] = float(value_coef * v.gradient / B);
    d_out[B + b] = float(baseline_coef * base.gradient / B);
  }
  head_backward(R, N, d_out);

  // backward: embeddings (the own embedding got the value's and the baseline's share)
  const RowMatrix d_obs_y = d_units_.topRows(B + B * U);
  linear_backward(*critic_.obs_embedding_, obs_in_,
                  activation_backward(shape.activation, obs_z_, obs_y_, d_obs_y));
  if (U > 0) {
    linear_backward(*critic_.obs_action_embedding_, action_in_,
                    activation_backward(shape.activation, action_z_, action_y_,
                                        RowMatrix(d_units_.bottomRows(B * U))));
  } else {
    critic_.obs_action_embedding_->weight.grad().zero_();
    critic_.obs_action_embedding_->bias.grad().zero_();
  }
  return losses;
}

Eigen::VectorXf PocaCriticGradient::head_forward(int64_t rows, int64_t members) {
  const auto& shape = critic_.shape();
  const int64_t R = rows, N = members, H = shape.hidden_units;
  const int64_t heads = shape.heads, d = H / heads;
  const float scale = float(1.0 / std::sqrt(double(d)));

  // multi-head attention over the entities, absent keys masked out
  // projections of the distinct entities; member i of row r is unit_of_[r N + i]
  linear_forward(*critic_.query_, units_, q_);
  linear_forward(*critic_.key_, units_, k_);
  linear_forward(*critic_.value_, units_, v_);
  attention_.resize(R * heads * N, N);
  attended_.setZero(R * N, H);
  for (int64_t r = 0; r < R; ++r) {
    for (int64_t h = 0; h < heads; ++h) {
      for (int64_t i = 0; i < N; ++i) {
        const ConstSegment q(q_.row(unit_of_[r * N + i]).data() + h * d, d);
        float* a = attention_.row((r * heads + h) * N + i).data();  // [N] weights of row i
        float top = -INFINITY;
        for (int64_t j = 0; j < N; ++j) {
          const ConstSegment k(k_.row(unit_of_[r * N + j]).data() + h * d, d);
          a[j] = present_(r, j) < 0.5f ? -1e9f : q.dot(k) * scale;
          top = std::max(top, a[j]);
        }
        float total = 0.f;
        for (int64_t j = 0; j < N; ++j) total += (a[j] = std::exp(a[j] - top));
        Segment o(attended_.row(r * N + i).data() + h * d, d);
        for (int64_t j = 0; j < N; ++j) {
          a[j] /= total;
          o += a[j] * ConstSegment(v_.row(unit_of_[r * N + j]).data() + h * d, d);
        }
      }
    }
  }
  // residual, then layer norm
  RowMatrix sum;
  linear_forward(*critic_.out_, attended_, sum);
  for (int64_t row = 0; row < R * N; ++row) sum.row(row) += units_.row(unit_of_[row]);
  const float eps = float(critic_.norm_->options.eps());
  normed_.resize(R * N, H);
  inverse_sigma_.resize(R * N);
  for (int64_t row = 0; row < R * N; ++row) {
    const float mean = sum.row(row).mean();
    normed_.row(row) = sum.row(row).array() - mean;
    inverse_sigma_[row] = 1.f / std::sqrt(normed_.row(row).squaredNorm() / float(H) + eps);
    normed_.row(row) *= inverse_sigma_[row];
  }
  x_ = (normed_.array().rowwise() * row_of(critic_.norm_->weight).array()).rowwise() +
       row_of(critic_.norm_->bias).array();
  // masked mean over the members present
  pooled_.setZero(R, H);
  for (int64_t r = 0; r < R; ++r) {
    float count = 0.f;
    for (int64_t i = 0; i < N; ++i) {
      pooled_.row(r) += present_(r, i) * x_.row(r * N + i);
      count += present_(r, i);
    }
    pooled_.row(r) /= std::max(1.f, count);
  }
  // MLP and head
  const auto& mlp = *critic_.mlp_;
  mlp_z_.resize(mlp.size());
  mlp_y_.resize(mlp.size());
  for (size_t l = 0; l < mlp.size(); ++l) {
    linear_forward(*mlp[l]->as<torch::nn::Linear>(), l == 0 ? pooled_ : mlp_y_[l - 1], mlp_z_[l]);
    activate(shape.activation, mlp_z_[l], mlp_y_[l]);
  }
  const RowMatrix& last = mlp.size() ? mlp_y_.back() : pooled_;
  Eigen::VectorXf out = last * matrix_of(critic_.value_head_->weight).row(0).transpose();
  out.array() += critic_.value_head_->bias.data_ptr<float>()[0];
  return out;
}

void PocaCriticGradient::head_backward(int64_t rows, int64_t members,
                                       const Eigen::VectorXf& d_out) {
  const auto& shape = critic_.shape();
  const int64_t R = rows, N = members, H = shape.hidden_units;
  const int64_t heads = shape.heads, d = H / heads;
  const float scale = float(1.0 / std::sqrt(double(d)));

  // head and MLP
  const auto& mlp = *critic_.mlp_;
  const RowMatrix& last = mlp.size() ? mlp_y_.back() : pooled_;
  matrix_grad(critic_.value_head_->weight).row(0).noalias() = d_out.transpose() * last;
  critic_.value_head_->bias.grad().data_ptr<float>()[0] = d_out.sum();
  RowMatrix dy = d_out * matrix_of(critic_.value_head_->weight).row(0);  // [R, H]
  for (size_t l = mlp.size(); l-- > 0;) {
    const RowMatrix dz = activation_backward(shape.activation, mlp_z_[l], mlp_y_[l], dy);
    linear_backward(*mlp[l]->as<torch::nn::Linear>(), l == 0 ? pooled_ : mlp_y_[l - 1], dz, &dy);
  }
  // masked mean
  RowMatrix dx(R * N, H);
  for (int64_t r = 0; r < R; ++r) {
    const float count = std::max(1.f, present_.row(r).sum());
    for (int64_t i = 0; i < N; ++i) dx.row(r * N + i) = present_(r, i) / count * dy.row(r);
  }
  // layer norm
  row_grad(critic_.norm_->weight) = (dx.array() * normed_.array()).colwise().sum();
  row_grad(critic_.norm_->bias) = dx.colwise().sum();
  const RowMatrix d_normed = dx.array().rowwise() * row_of(critic_.norm_->weight).array();
  RowMatrix d_sum(R * N, H);  // d loss / d (entities + out projection)
  for (int64_t row = 0; row < R * N; ++row) {
    const float mean_d = d_normed.row(row).mean();
    const float mean_dx = d_normed.row(row).dot(normed_.row(row)) / float(H);
    d_sum.row(row) =
        inverse_sigma_[row] *
        (d_normed.row(row).array() - mean_d - normed_.row(row).array() * mean_dx).matrix();
  }
  // the out projection, and the residual: each distinct entity gets its members' shares
  RowMatrix d_attended(R * N, H);
  linear_backward(*critic_.out_, attended_, d_sum, &d_attended);
  d_units_.setZero(units_.rows(), H);
  for (int64_t row = 0; row < R * N; ++row) d_units_.row(unit_of_[row]) += d_sum.row(row);
  // attention
  const int64_t units = units_.rows();
  RowMatrix dq = RowMatrix::Zero(units, H), dk = RowMatrix::Zero(units, H),
            dv = RowMatrix::Zero(units, H);
  std::vector<float> da(N);
  for (int64_t r = 0; r < R; ++r) {
    for (int64_t h = 0; h < heads; ++h) {
      for (int64_t i = 0; i < N; ++i) {
        const float* a = attention_.row((r * heads + h) * N + i).data();
        const ConstSegment d_o(d_attended.row(r * N + i).data() + h * d, d);
        float weighted = 0.f;
        for (int64_t j = 0; j < N; ++j) {
          da[j] = d_o.dot(ConstSegment(v_.row(unit_of_[r * N + j]).data() + h * d, d));
          weighted += a[j] * da[j];
        }
        const int64_t unit_i = unit_of_[r * N + i];
        Segment d_q(dq.row(unit_i).data() + h * d, d);
        const ConstSegment q(q_.row(unit_i).data() + h * d, d);
        for (int64_t j = 0; j < N; ++j) {
          if (a[j] == 0.f) continue;
          const float ds = a[j] * (da[j] - weighted) * scale;
          const int64_t unit_j = unit_of_[r * N + j];
          Segment(dv.row(unit_j).data() + h * d, d) += a[j] * d_o;
          d_q += ds * ConstSegment(k_.row(unit_j).data() + h * d, d);
          Segment(dk.row(unit_j).data() + h * d, d) += ds * q;
        }
      }
    }
  }
  linear_backward(*critic_.query_, units_, dq, &d_units_, /*accumulate=*/true);
  linear_backward(*critic_.key_, units_, dk, &d_units_, /*accumulate=*/true);
  linear_backward(*critic_.value_, units_, dv, &d_units_, /*accumulate=*/true);
}

}  // namespace rlt
