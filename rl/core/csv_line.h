// The fields of one line of the comma-separated files rlt writes (metrics, episodes): no quoting,
// since rlt's own fields hold no commas.
#pragma once

#include <string>
#include <vector>

namespace rlt {

// The fields of `line` between its commas, an empty last one after a trailing comma ("a,,b," has
// four fields; "" has none).
std::vector<std::string> split_csv_line(const std::string& line);

}  // namespace rlt
