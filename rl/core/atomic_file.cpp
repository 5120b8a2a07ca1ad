#include "rl/core/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace rlt {

void write_file_atomically(const std::string& path, const std::string& contents) {
  const std::string tmp = path + ".tmp";
  auto fail = [&](const std::string& what) {
    const std::string reason = std::strerror(errno);
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error(what + ": " + reason + " (" + path + " was left as it was)");
  };
  errno = 0;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail("cannot write " + tmp);
    out.write(contents.data(), std::streamsize(contents.size()));
    out.flush();
    if (!out) fail("cannot write " + tmp);
    out.close();
    if (!out) fail("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("cannot move " + tmp + " to " + path);
}

void append_to_file(const std::string& path, const std::string& text) {
  std::error_code size_error;
  const auto size_before = fs::exists(path) ? fs::file_size(path, size_error) : 0;
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::app);
  auto fail = [&] {
    const std::string reason = std::strerror(errno ? errno : EIO);
    out.close();
    std::error_code ignored;
    if (!size_error && fs::exists(path)) fs::resize_file(path, size_before, ignored);
    throw std::runtime_error("cannot append to " + path + ": " + reason + " (" + path +
                             " was left as it was)");
  };
  if (!out) fail();
  out.write(text.data(), std::streamsize(text.size()));
  out.flush();
  if (!out) fail();
  out.close();
  if (!out) fail();
}

}  // namespace rlt
