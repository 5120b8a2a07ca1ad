#include "rl/distributed/communicator.h"

namespace rlt {

std::vector<double> Communicator::all_gather(const std::vector<double>& mine, const char* what) {
  const int64_t n = int64_t(mine.size());
  // each rank fills its own slot; the sum over ranks is then everyone's values
  torch::Tensor slots = torch::zeros({int64_t(world_size()), n}, torch::kFloat64);  // [W, n]
  if (n > 0)
    slots[rank()].copy_(torch::from_blob(const_cast<double*>(mine.data()), {n}, torch::kFloat64));
  all_reduce_sum(slots, what);
  const double* p = slots.data_ptr<double>();
  return std::vector<double>(p, p + world_size() * n);
}

}  // namespace rlt
