// Writing files so that a failed write (a full disk) loses nothing: readers see either the old
// contents or the new ones, never a partial file or a partial row.
#pragma once

#include <string>

namespace rlt {

// Writes `contents` to `path` through a temporary file and a rename. A failed write (a full disk)
// throws std::runtime_error naming the file and the reason, removes the temporary file and leaves
// `path` as it was.
void write_file_atomically(const std::string& path, const std::string& contents);

// Appends `text` (whole rows) to `path`, creating it if needed. A failed write throws
// std::runtime_error naming the file and the reason, after cutting the file back to its size
// before the call, so that no partial row is left.
void append_to_file(const std::string& path, const std::string& text);

}  // namespace rlt
