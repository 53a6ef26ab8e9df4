#pragma once
// Splits a fuzzer's input into typed fields (a small stand-in for LLVM's FuzzedDataProvider,
// which a GCC build of the corpus replay does not have). Exhausted input reads as zeros.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace stereoball::fuzz {

class FuzzInput {
 public:
  FuzzInput(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  /// The next sizeof(T) bytes as a T (any bit pattern: NaN, infinities, huge values).
  template <typename T>
  T take() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value{};
    const size_t n = std::min(sizeof(T), left());
    std::memcpy(&value, data_ + pos_, n);
    pos_ += n;
    return value;
  }
  /// A value in [0, count): enums and choices the DDS deserializer already range-checks.
  uint32_t choice(uint32_t count) { return count == 0 ? 0 : take<uint8_t>() % count; }
  bool flag() { return (take<uint8_t>() & 1) != 0; }
  /// Up to max_bytes bytes (the length is taken from the input too).
  std::vector<uint8_t> bytes(size_t max_bytes) {
    const size_t n = std::min<size_t>({take<uint32_t>(), max_bytes, left()});
    std::vector<uint8_t> out(data_ + pos_, data_ + pos_ + n);
    pos_ += n;
    return out;
  }
  /// Everything not read yet.
  std::vector<uint8_t> rest() { return bytes(left()); }
  std::string text(size_t max_bytes) {
    auto b = bytes(max_bytes);
    std::string s(b.begin(), b.end());
    s.erase(std::find(s.begin(), s.end(), '\0'), s.end());  // DDS strings end at their NUL
    return s;
  }
  template <typename T, size_t N>
  void fill(T (&array)[N]) {
    for (auto& v : array) v = take<T>();
  }
  size_t left() const { return size_ - pos_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

}  // namespace stereoball::fuzz
