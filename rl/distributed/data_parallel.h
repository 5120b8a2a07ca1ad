// What data-parallel learners agree on, on top of a Communicator: the gradient of a minibatch is
// the mean of every rank's, the observation normalizer folds in every rank's new observations,
// advantages are normalized with the statistics of all ranks' buffers, and the number of
// minibatches is the one every rank has.
//
// Reference: PyTorch DistributedDataParallel (gradients averaged over ranks before the optimizer
// step, so every replica applies the same update); ML-Agents' normalizer update, per rank.
#pragma once

#include <cstdint>
#include <utility>

#include "rl/core/running_normalizer.h"
#include "rl/distributed/communicator.h"

namespace rlt {

// the mean over ranks of `flat_gradients` ([P]), in place
void average_gradients(Communicator& comm, const torch::Tensor& flat_gradients);

// Folds every rank's `pending` observations into `global` in rank order, the same on every rank,
// and empties `pending`.
void merge_normalizers(Communicator& comm, RunningNormalizer& global, RunningNormalizer& pending);

// mean and standard deviation (Bessel-corrected, as torch::std) of `values` ([N] on this rank)
// over all ranks
std::pair<double, double> global_mean_std(Communicator& comm, const torch::Tensor& values);

// the smallest `count` of any rank
int64_t global_min(Communicator& comm, int64_t count, const char* what);

// FNV-1a over the bytes of a contiguous tensor: equal tensors, equal hashes
uint64_t tensor_hash(const torch::Tensor& tensor);

}  // namespace rlt
