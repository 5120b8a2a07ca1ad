// Helpers to keep strings and plain vectors in LibTorch archives (checkpoints).
#pragma once

#include <torch/torch.h>

#include <cstring>
#include <string>
#include <vector>

namespace rlt {

inline void write_string(torch::serialize::OutputArchive& a, const std::string& key,
                         const std::string& s) {
  auto t = torch::empty({int64_t(s.size())}, torch::kUInt8);
  if (!s.empty()) std::memcpy(t.data_ptr<uint8_t>(), s.data(), s.size());
  a.write(key, t);
}

inline std::string read_string(torch::serialize::InputArchive& a, const std::string& key) {
  torch::Tensor t;
  a.read(key, t);
  return std::string(reinterpret_cast<const char*>(t.data_ptr<uint8_t>()), size_t(t.numel()));
}

template <typename T>
void write_vector(torch::serialize::OutputArchive& a, const std::string& key,
                  const std::vector<T>& v) {
  auto t = torch::empty({int64_t(v.size() * sizeof(T))}, torch::kUInt8);
  if (!v.empty()) std::memcpy(t.data_ptr<uint8_t>(), v.data(), v.size() * sizeof(T));
  a.write(key, t);
}

template <typename T>
std::vector<T> read_vector(torch::serialize::InputArchive& a, const std::string& key) {
  torch::Tensor t;
  a.read(key, t);
  std::vector<T> v(size_t(t.numel()) / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), t.data_ptr<uint8_t>(), v.size() * sizeof(T));
  return v;
}

}  // namespace rlt
