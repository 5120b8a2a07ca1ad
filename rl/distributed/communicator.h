// The processes of one data-parallel training run, as the learners see them: every rank runs its
// own environment instances and a replica of every learner, and the ranks agree through a few
// collectives (sum, broadcast). GlooCommunicator implements them on LibTorch's c10d with Gloo.
#pragma once

#include <torch/torch.h>

#include <string>
#include <vector>

namespace rlt {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int world_size() const = 0;

  // Element-wise sum over the ranks, in place (contiguous CPU float or double tensor). Every rank
  // ends with the same bits. Throws naming the rank that stopped answering.
  virtual void all_reduce_sum(torch::Tensor& tensor, const char* what) = 0;
  // `root`'s values on every rank, in place.
  virtual void broadcast(torch::Tensor& tensor, int root, const char* what) = 0;

  // every rank's `mine` (all of the same length), rank by rank: [world_size * mine.size()]
  std::vector<double> all_gather(const std::vector<double>& mine, const char* what);
};

}  // namespace rlt
