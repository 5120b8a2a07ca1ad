// Writing a file so that readers see either the old file or the new one, never a partial file.
#pragma once

#include <string>

namespace rlt {

// Writes `contents` to `path` through a temporary file and a rename. A failed write (a full disk)
// throws std::runtime_error naming the file and the reason, removes the temporary file and leaves
// `path` as it was.
void write_file_atomically(const std::string& path, const std::string& contents);

}  // namespace rlt
