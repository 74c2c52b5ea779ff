#pragma once
// Integer 3D grid coordinates (voxels, blocks, cells) as 63-bit keys, and an open-addressing
// hash table from such keys to int values: the spaced feature selection, the TSDF's block
// index and the mesh evaluation's triangle grid all look cells up this way, and a node-based
// map's allocations and pointer chasing had dominated the first two.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace f2c {

// Each coordinate within +-2^20, two's complement in 21 bits: x, y, z from high to low.
inline uint64_t PackCoords(const Eigen::Vector3i& c) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(c.x()) & 0x1FFFFF) << 42) |
         (static_cast<uint64_t>(static_cast<uint32_t>(c.y()) & 0x1FFFFF) << 21) |
         static_cast<uint64_t>(static_cast<uint32_t>(c.z()) & 0x1FFFFF);
}

inline Eigen::Vector3i UnpackCoords(uint64_t key) {
  auto field = [](uint64_t bits) { return static_cast<int>(static_cast<int64_t>(bits << 43) >> 43); };
  return {field(key >> 42), field(key >> 21), field(key)};
}

// Keys to values (-1: absent), linear probing in a power-of-two array kept at most half full
// (it doubles when it would be more), Fibonacci hashing (the product's top bits: every
// coordinate's bits reach the slot).
class CoordTable {
 public:
  explicit CoordTable(size_t expected = 8) { Reset(expected); }

  int Find(uint64_t key) const { return values_[Slot(key)]; }
  // The value for `key`, inserted as -1 when absent.
  int& At(uint64_t key) {
    if (2 * (size_ + 1) > keys_.size()) Grow();
    const size_t i = Slot(key);
    if (keys_[i] != key) keys_[i] = key, ++size_;
    return values_[i];
  }
  size_t size() const { return size_; }
  // The values of every key, in table order.
  std::vector<int> Values() const {
    std::vector<int> out;
    for (size_t i = 0; i < keys_.size(); ++i) {
      if (keys_[i] != kEmpty) out.push_back(values_[i]);
    }
    return out;
  }
  size_t MemoryBytes() const { return keys_.size() * (sizeof(uint64_t) + sizeof(int)); }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t{0};  // keys use 63 bits

  void Reset(size_t expected) {
    size_t slots = 16;
    shift_ = 60;
    while (slots < 2 * expected) slots *= 2, --shift_;
    keys_.assign(slots, kEmpty);
    values_.assign(slots, -1);
    size_ = 0;
  }
  void Grow() {
    const std::vector<uint64_t> keys = std::move(keys_);
    const std::vector<int> values = std::move(values_);
    Reset(keys.size());
    for (size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] != kEmpty) At(keys[i]) = values[i];
    }
  }
  size_t Slot(uint64_t key) const {
    const size_t mask = keys_.size() - 1;
    size_t i = (key * 0x9E3779B97F4A7C15ULL) >> shift_;
    while (keys_[i] != kEmpty && keys_[i] != key) i = (i + 1) & mask;
    return i;
  }

  int shift_ = 60;
  size_t size_ = 0;
  std::vector<uint64_t> keys_;
  std::vector<int> values_;
};

}  // namespace f2c
