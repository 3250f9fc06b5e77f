#pragma once
// Named per-pass times of one frame, in submission order. Several timings with
// the same name add up (e.g. the two halves of a multi-launch sort).
// A time the device could not measure is missing, never 0: it is NaN here
// (isMissing), "n/a" in tables and null in JSON, and a sum with a missing part
// is missing. A time taken on the host clock (the pass bracketed by finish
// calls, because the device's own clock is unusable) is marked PassClock::Host
// so that reports can say so: it includes launch overhead a device time lacks.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace ml {

enum class PassClock { Device, Host };

class PassTimings {
 public:
  static constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();
  static bool isMissing(double ms) { return std::isnan(ms); }

  // Adding host time to a pass makes the whole pass host-timed.
  void add(const std::string& name, double ms, PassClock clock = PassClock::Device) {
    for (std::size_t i = 0; i < entries_.size(); ++i)
      if (entries_[i].first == name) {
        entries_[i].second += ms;  // NaN (missing) stays NaN
        if (clock == PassClock::Host) host_[i] = true;
        return;
      }
    entries_.emplace_back(name, ms);
    host_.push_back(clock == PassClock::Host);
  }
  void addMissing(const std::string& name, PassClock clock = PassClock::Device) { add(name, kMissing, clock); }
  void merge(const PassTimings& other) {
    for (std::size_t i = 0; i < other.entries_.size(); ++i)
      add(other.entries_[i].first, other.entries_[i].second, other.clockAt(i));
  }
  // Missing (NaN) when any pass is.
  double total() const {
    double t = 0;
    for (const auto& e : entries_) t += e.second;
    return t;
  }
  // 0 for a pass that did not run, NaN for one whose time is missing.
  double get(const std::string& name) const {
    for (const auto& [n, v] : entries_)
      if (n == name) return v;
    return 0.0;
  }
  PassClock clock(const std::string& name) const {
    for (std::size_t i = 0; i < entries_.size(); ++i)
      if (entries_[i].first == name) return clockAt(i);
    return PassClock::Device;
  }
  PassClock clockAt(std::size_t i) const { return host_[i] ? PassClock::Host : PassClock::Device; }
  bool anyHost() const {
    for (bool h : host_)
      if (h) return true;
    return false;
  }
  bool anyMissing() const { return isMissing(total()); }
  const std::vector<std::pair<std::string, double>>& entries() const { return entries_; }
  void clear() {
    entries_.clear();
    host_.clear();
  }

 private:
  std::vector<std::pair<std::string, double>> entries_;
  std::vector<bool> host_;  // parallel to entries_
};

// "12.345" with `decimals` places, "n/a" for a missing time.
inline std::string passTimeText(double ms, int decimals = 3) {
  if (PassTimings::isMissing(ms)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, ms);
  return buf;
}

// Every pass on one line, " name=1.23 other=n/a sort=0.50(host)": the form the
// bench tables print, so a missing or host-clock time reads the same everywhere.
inline std::string passListText(const PassTimings& t, int decimals = 2) {
  std::string out;
  for (std::size_t i = 0; i < t.entries().size(); ++i) {
    const auto& [name, ms] = t.entries()[i];
    out += " " + name + "=" + passTimeText(ms, decimals) + (t.clockAt(i) == PassClock::Host ? "(host)" : "");
  }
  return out;
}

}  // namespace ml
