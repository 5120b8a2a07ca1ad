// Running mean and variance of observations (Chan et al.'s parallel update), used to normalize
// vector observations when `network_settings.normalize` is true.
//
// Reference: ML-Agents `mlagents/trainers/torch_entities/encoders.py` (Normalizer): statistics are
// updated with each processed trajectory, normalized values are clipped to [-5, 5].
//
// Our departure from it: a column's statistics begin when the column first takes a second value.
// Until then (every value folded in so far the same) it has no scale to learn, and merging its
// first varied batch into the constant history would give it a variance of about batch / history
// times the true one: a feature that a curriculum switches on late (HideAndSeek's second prop and
// doorway at level 2, after a million level-1 observations of zeros) would reach the network
// clipped at +-5 and shrink toward its true scale only as the new observations outnumber the old.
// So such a column starts over from the batch in which it first varies (its own count), when its
// constant history holds at least as many observations as that batch; a shorter one is merged as
// usual (it weighs less than the batch, and a first chunk of one row stays part of the mean).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rlt {

class RunningNormalizer {
 public:
  RunningNormalizer() = default;
  explicit RunningNormalizer(int size);

  int size() const { return static_cast<int>(mean_.size()); }
  double count() const { return count_; }
  // The observations column i's statistics hold: count() for a column that varied from its first
  // batch on, fewer for one that started over when it first varied (see the header comment).
  double column_count(int i) const { return column_count_[i]; }
  const std::vector<double>& mean() const { return mean_; }      // [size]
  const std::vector<double>& variance() const { return var_; }   // [size]

  // Columns (1 = pass) that keep mean 0 and variance 1 whatever is folded in, so that normalize
  // leaves them as they are: the grid observations, as ML-Agents normalizes only vector
  // observations. [size]; resets their statistics. Not serialized: the kept 0 and 1 are.
  void set_passthrough(const std::vector<uint8_t>& columns);

  // Folds `rows` observations (row-major [rows, size]) into the statistics.
  void update(const float* data, int64_t rows);
  // Folds in the statistics of `rows` observations seen elsewhere (their mean and population
  // variance, [size] each): what update does after computing them.
  void merge(double rows, const std::vector<double>& mean, const std::vector<double>& variance);

  // normalized = clamp((x - mean) / sqrt(var + 1e-8), -5, 5), applied to [rows, size] in place
  void normalize(float* data, int64_t rows) const;
  // 1 / sqrt(var + 1e-8) per element, as float: what the networks multiply by
  std::vector<float> inverse_std() const;
  std::vector<float> mean_float() const;

  // text form for checkpoints (exact: hex floats)
  std::string serialize() const;
  static RunningNormalizer deserialize(const std::string& text);

  static constexpr float kClip = 5.f;
  static constexpr double kEps = 1e-8;
  // A column whose variance is at most this has held one value so far (a constant's batch mean
  // and variance come out exact in double; the margin only keeps a test on 0 off rounding).
  static constexpr double kConstantVariance = 1e-20;

 private:
  double count_ = 0;                  // observations seen
  std::vector<double> column_count_;  // [size] observations each column's statistics hold
  std::vector<double> mean_;          // [size]
  std::vector<double> var_;           // [size] population variance
  std::vector<uint8_t> passthrough_;  // [size] or empty (none)
};

}  // namespace rlt
