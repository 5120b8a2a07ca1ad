// TensorBoard event files: scalar summaries that `tensorboard --logdir results` reads, as ML-Agents
// writes them (one folder per behavior inside the run folder, tags such as
// "Environment/Cumulative Reward").
//
// The format is TensorFlow's record file of `Event` protocol buffers
// (tensorflow/core/util/event.proto, tensorflow/core/framework/summary.proto):
// - each record is: length (uint64, little endian), masked CRC-32C of those 8 bytes (uint32),
//   the payload, masked CRC-32C of the payload (uint32); masked(c) = ((c >> 15) | (c << 17)) +
//   0xa282ead8;
// - the first event carries file_version "brain.Event:2"; every later one a wall time, a step and
//   a Summary with one Value per scalar (tag = field 1, simple_value = field 2).
// The protocol buffer encoding is written by hand (a few fields); no protobuf library is needed.
//
// No LibTorch here. Not thread-safe: one thread writes a file.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace rlt {

// CRC-32C (Castagnoli) of `size` bytes, and TensorFlow's masked form of it.
uint32_t crc32c(const void* data, size_t size);
uint32_t masked_crc32c(const void* data, size_t size);

class TensorBoardWriter {
 public:
  // Creates `directory` if needed and a new file events.out.tfevents.<seconds>.<host>.<pid> in
  // it, starting with the file-version event. Throws std::runtime_error naming the path when the
  // file cannot be written.
  explicit TensorBoardWriter(const std::string& directory);

  const std::string& path() const { return path_; }

  // One event at `step` with every (tag, value) of `scalars`; wall time = now. Non-finite values
  // are written as they are (TensorBoard shows them as such). Written through at once, so a run
  // that stops loses nothing already summarised.
  void add_scalars(int64_t step, const std::vector<std::pair<std::string, float>>& scalars);
  void add_scalar(int64_t step, const std::string& tag, float value) {
    add_scalars(step, {{tag, value}});
  }

 private:
  void write_record(const std::string& payload);

  std::string path_;
  std::ofstream out_;
};

}  // namespace rlt
