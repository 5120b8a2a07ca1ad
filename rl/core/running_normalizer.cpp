#include "rl/core/running_normalizer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace rlt {

RunningNormalizer::RunningNormalizer(int size)
    : column_count_(size, 0.0), mean_(size, 0.0), var_(size, 1.0) {}

void RunningNormalizer::update(const float* data, int64_t rows) {
  if (rows <= 0) return;
  const int n = size();
  // batch mean and variance
  std::vector<double> bmean(n, 0.0), bvar(n, 0.0);
  for (int64_t r = 0; r < rows; ++r)
    for (int i = 0; i < n; ++i) bmean[i] += data[r * n + i];
  for (int i = 0; i < n; ++i) bmean[i] /= double(rows);
  for (int64_t r = 0; r < rows; ++r)
    for (int i = 0; i < n; ++i) {
      double d = data[r * n + i] - bmean[i];
      bvar[i] += d * d;
    }
  for (int i = 0; i < n; ++i) bvar[i] /= double(rows);
  merge(double(rows), bmean, bvar);
}

void RunningNormalizer::set_passthrough(const std::vector<uint8_t>& columns) {
  if (static_cast<int>(columns.size()) != size())
    throw std::invalid_argument("RunningNormalizer: passthrough has " +
                                std::to_string(columns.size()) + " columns, expected " +
                                std::to_string(size()));
  passthrough_ = columns;
  for (int i = 0; i < size(); ++i) {
    if (!passthrough_[i]) continue;
    mean_[i] = 0.0;
    var_[i] = 1.0;
  }
}

void RunningNormalizer::merge(double rows, const std::vector<double>& bmean,
                              const std::vector<double>& bvar) {
  if (rows <= 0) return;
  const int n = size();
  const double total = count_ + rows;
  for (int i = 0; i < n; ++i) {
    if (!passthrough_.empty() && passthrough_[i]) {
      column_count_[i] = total;
      continue;
    }
    const double count = column_count_[i];
    const double delta = bmean[i] - mean_[i];
    // one value so far, held by at least as many observations as the batch (a shorter history
    // weighs less than the batch and is merged as usual, so small first chunks stay exact)
    const bool constant_so_far = var_[i] <= kConstantVariance && count >= rows;
    const bool varies_now = bvar[i] > kConstantVariance || delta * delta > kConstantVariance;
    if (count == 0 || (constant_so_far && varies_now)) {  // its statistics begin here
      mean_[i] = bmean[i];
      var_[i] = bvar[i];
      column_count_[i] = rows;
      continue;
    }
    const double sum = count + rows;
    const double m2 = var_[i] * count + bvar[i] * double(rows) + delta * delta * count * rows / sum;
    mean_[i] += delta * rows / sum;
    var_[i] = m2 / sum;
    column_count_[i] = sum;
  }
  count_ = total;
}

void RunningNormalizer::normalize(float* data, int64_t rows) const {
  const int n = size();
  auto inv = inverse_std();
  auto mean = mean_float();
  for (int64_t r = 0; r < rows; ++r)
    for (int i = 0; i < n; ++i) {
      float v = (data[r * n + i] - mean[i]) * inv[i];
      data[r * n + i] = std::clamp(v, -kClip, kClip);
    }
}

std::vector<float> RunningNormalizer::inverse_std() const {
  std::vector<float> out(size());
  for (int i = 0; i < size(); ++i) out[i] = float(1.0 / std::sqrt(var_[i] + kEps));
  return out;
}

std::vector<float> RunningNormalizer::mean_float() const {
  return std::vector<float>(mean_.begin(), mean_.end());
}

std::string RunningNormalizer::serialize() const {
  std::ostringstream os;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", count_);
  os << size() << ' ' << buf;
  for (int i = 0; i < size(); ++i) {
    std::snprintf(buf, sizeof buf, " %a", mean_[i]);
    os << buf;
    std::snprintf(buf, sizeof buf, " %a", var_[i]);
    os << buf;
  }
  // the columns' own counts follow (a state written before they existed ends here)
  for (int i = 0; i < size(); ++i) {
    std::snprintf(buf, sizeof buf, " %a", column_count_[i]);
    os << buf;
  }
  return os.str();
}

RunningNormalizer RunningNormalizer::deserialize(const std::string& text) {
  std::istringstream is(text);
  int n = 0;
  std::string tok;
  if (!(is >> n) || n < 0) throw std::runtime_error("corrupt normalizer state");
  RunningNormalizer out(n);
  auto next = [&]() {
    if (!(is >> tok)) throw std::runtime_error("corrupt normalizer state");
    return std::strtod(tok.c_str(), nullptr);
  };
  out.count_ = next();
  for (int i = 0; i < n; ++i) {
    out.mean_[i] = next();
    out.var_[i] = next();
  }
  // Written before the columns had counts of their own: every column held them all.
  if (n == 0 || !(is >> tok)) {
    std::fill(out.column_count_.begin(), out.column_count_.end(), out.count_);
    return out;
  }
  out.column_count_[0] = std::strtod(tok.c_str(), nullptr);
  for (int i = 1; i < n; ++i) out.column_count_[i] = next();
  return out;
}

}  // namespace rlt
