// A TensorBoard event-file reader for tests, written apart from rl/trainer/tensorboard_writer: a
// bit-at-a-time CRC-32C, a generic protocol buffer decoder, and gtest checks of every record's
// framing and CRCs.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace rlt::tensorboard_reader {

// CRC-32C one bit at a time (the writer uses a table).
inline uint32_t crc_bitwise(const std::string& bytes) {
  uint32_t c = ~0u;
  for (unsigned char byte : bytes) {
    c ^= byte;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0x82f63b78u & (0u - (c & 1u)));
  }
  return ~c;
}

inline uint32_t mask(uint32_t c) { return ((c >> 15) | (c << 17)) + 0xa282ead8u; }

template <typename T>
T read_le(const std::string& bytes, size_t at) {
  T value = 0;
  for (size_t i = 0; i < sizeof(T); ++i)
    value |= static_cast<T>(static_cast<unsigned char>(bytes.at(at + i))) << (8 * i);
  return value;
}

// One protocol buffer field as decoded: its number, wire type and raw content.
struct Field {
  int number = 0;
  int type = 0;
  uint64_t integer = 0;  // varint, fixed64 and fixed32 bits
  std::string bytes;     // length-delimited content
};

inline std::vector<Field> decode(const std::string& message) {
  std::vector<Field> fields;
  size_t at = 0;
  auto varint = [&]() {
    uint64_t value = 0;
    for (int shift = 0;; shift += 7) {
      const auto byte = static_cast<unsigned char>(message.at(at++));
      value |= uint64_t(byte & 0x7f) << shift;
      if (!(byte & 0x80)) return value;
    }
  };
  while (at < message.size()) {
    const uint64_t key = varint();
    Field f;
    f.number = int(key >> 3);
    f.type = int(key & 7);
    if (f.type == 0) {
      f.integer = varint();
    } else if (f.type == 1) {
      f.integer = read_le<uint64_t>(message, at);
      at += 8;
    } else if (f.type == 5) {
      f.integer = read_le<uint32_t>(message, at);
      at += 4;
    } else if (f.type == 2) {
      const uint64_t size = varint();
      f.bytes = message.substr(at, size);
      EXPECT_LE(at + size, message.size());
      at += size;
    } else {
      ADD_FAILURE() << "unexpected wire type " << f.type;
      break;
    }
    fields.push_back(f);
  }
  return fields;
}

struct Event {
  double wall_time = 0;
  int64_t step = -1;
  std::string file_version;
  std::map<std::string, float> scalars;
};

// Reads every record of `path`, checking the framing and both CRCs of each.
inline std::vector<Event> read_events(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), {});
  std::vector<Event> events;
  size_t at = 0;
  while (at < data.size()) {
    EXPECT_LE(at + 12, data.size()) << "truncated record header";
    const uint64_t length = read_le<uint64_t>(data, at);
    EXPECT_EQ(read_le<uint32_t>(data, at + 8), mask(crc_bitwise(data.substr(at, 8))));
    const std::string payload = data.substr(at + 12, length);
    EXPECT_EQ(payload.size(), length) << "truncated payload";
    EXPECT_EQ(read_le<uint32_t>(data, at + 12 + length), mask(crc_bitwise(payload)));
    at += 12 + length + 4;
    Event e;
    for (const Field& f : decode(payload)) {
      if (f.number == 1 && f.type == 1) std::memcpy(&e.wall_time, &f.integer, 8);
      if (f.number == 2 && f.type == 0) e.step = int64_t(f.integer);
      if (f.number == 3 && f.type == 2) e.file_version = f.bytes;
      if (f.number == 5 && f.type == 2) {
        for (const Field& value : decode(f.bytes)) {
          EXPECT_EQ(value.number, 1);
          std::string tag;
          float simple = NAN;
          for (const Field& v : decode(value.bytes)) {
            if (v.number == 1 && v.type == 2) tag = v.bytes;
            if (v.number == 2 && v.type == 5) {
              const auto bits = uint32_t(v.integer);
              std::memcpy(&simple, &bits, 4);
            }
          }
          e.scalars[tag] = simple;
        }
      }
    }
    events.push_back(e);
  }
  EXPECT_EQ(at, data.size());
  return events;
}

}  // namespace rlt::tensorboard_reader
