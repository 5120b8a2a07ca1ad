#include "rl/distributed/data_parallel.h"

#include <algorithm>
#include <cmath>

namespace rlt {

void average_gradients(Communicator& comm, const torch::Tensor& flat_gradients) {
  torch::Tensor g = flat_gradients;  // [P], shares the storage
  comm.all_reduce_sum(g, "averaging the gradients");
  g.div_(double(comm.world_size()));
}

void merge_normalizers(Communicator& comm, RunningNormalizer& global, RunningNormalizer& pending) {
  const int n = pending.size();
  // [count, mean[n], variance[n]] of every rank
  std::vector<double> mine{pending.count()};
  mine.insert(mine.end(), pending.mean().begin(), pending.mean().end());
  mine.insert(mine.end(), pending.variance().begin(), pending.variance().end());
  const std::vector<double> all = comm.all_gather(mine, "merging the observation normalizers");
  const size_t stride = mine.size();
  for (int r = 0; r < comm.world_size(); ++r) {
    const double* p = all.data() + r * stride;
    global.merge(p[0], std::vector<double>(p + 1, p + 1 + n),
                 std::vector<double>(p + 1 + n, p + 1 + 2 * n));
  }
  pending = RunningNormalizer(n);
}

std::pair<double, double> global_mean_std(Communicator& comm, const torch::Tensor& values) {
  torch::Tensor v = values.to(torch::kFloat64);  // [N]
  torch::Tensor sums =
      torch::stack({v.sum(), (v * v).sum(), torch::tensor(double(v.numel()), torch::kFloat64)});
  comm.all_reduce_sum(sums, "normalizing the advantages");
  const double s = sums[0].item<double>(), ss = sums[1].item<double>(),
               count = sums[2].item<double>();
  const double mean = s / std::max(1.0, count);
  const double var = count > 1 ? std::max(0.0, (ss - count * mean * mean) / (count - 1)) : 0.0;
  return {mean, std::sqrt(var)};
}

int64_t global_min(Communicator& comm, int64_t count, const char* what) {
  const std::vector<double> all = comm.all_gather({double(count)}, what);
  return int64_t(*std::min_element(all.begin(), all.end()));
}

uint64_t tensor_hash(const torch::Tensor& tensor) {
  const torch::Tensor t = tensor.contiguous();
  const auto* bytes = static_cast<const uint8_t*>(t.data_ptr());
  uint64_t hash = 1469598103934665603ull;
  for (size_t i = 0; i < size_t(t.numel()) * t.element_size(); ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace rlt
