#pragma once
// Named per-pass times of one frame, in submission order. Several timings with
// the same name add up (e.g. the two halves of a multi-launch sort).
#include <string>
#include <utility>
#include <vector>

namespace ml {

class PassTimings {
 public:
  void add(const std::string& name, double ms) {
    for (auto& [n, v] : entries_)
      if (n == name) {
        v += ms;
        return;
      }
    entries_.emplace_back(name, ms);
  }
  void merge(const PassTimings& other) {
    for (const auto& [n, v] : other.entries_) add(n, v);
  }
  double total() const {
    double t = 0;
    for (const auto& e : entries_) t += e.second;
    return t;
  }
  double get(const std::string& name) const {
    for (const auto& [n, v] : entries_)
      if (n == name) return v;
    return 0.0;
  }
  const std::vector<std::pair<std::string, double>>& entries() const { return entries_; }
  void clear() { entries_.clear(); }

 private:
  std::vector<std::pair<std::string, double>> entries_;
};

}  // namespace ml
