#include "rl/core/bad_numbers.h"

#include <cmath>
#include <sstream>

namespace rlt {

int64_t first_non_finite(const float* data, int64_t n) {
  for (int64_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i])) return i;
  return -1;
}

void require_finite(const float* data, int64_t n, const std::string& what) {
  const int64_t i = first_non_finite(data, n);
  if (i < 0) return;
  std::ostringstream os;
  os << what << "[" << i << "] is " << data[i];
  throw BadNumberError(os.str());
}

}  // namespace rlt
