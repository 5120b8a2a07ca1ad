// NaN and infinity guards: a non-finite observation, reward or loss stops training with a message
// naming where it came from, before anything is written.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace rlt {

class BadNumberError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// index of the first non-finite value of data[0, n), or -1
int64_t first_non_finite(const float* data, int64_t n);

// throws BadNumberError("<what>[i] is nan") when data has a non-finite value; `what` names the source
void require_finite(const float* data, int64_t n, const std::string& what);

}  // namespace rlt
