#pragma once
// Tests: reading a SharedBuffer (gl/SharedBuffer.hpp) back as typed values,
// poisoning it (every byte 0xFF: NaN as floats) before a pass that must
// overwrite it, and comparing read-backs bit for bit.
#include <cstddef>
#include <cstring>
#include <vector>

#include "gl/SharedBuffer.hpp"

namespace ml::test {

template <class T>
std::vector<T> downloadAll(const SharedBuffer& b, std::size_t count) {
  std::vector<T> out(count);
  b.download(out.data(), count * sizeof(T));
  return out;
}

inline void poison(SharedBuffer* b) {
  if (!b) return;
  const std::vector<unsigned char> nan(b->size(), 0xFF);
  b->upload(nan.data(), nan.size());
}

// The first element whose bytes differ (a.size() when none; b at least as long).
template <class T>
std::size_t firstBitDifference(const std::vector<T>& a, const std::vector<T>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(T)) != 0) return i;
  return a.size();
}

}  // namespace ml::test
