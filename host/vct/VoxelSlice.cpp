#include "host/vct/VoxelSlice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host/util/Error.hpp"

namespace ml::vct {

VoxelSlice parseVoxelSlice(const std::string& text, const std::string& flag) {
  const auto bad = [&] { return UserError(flag + ": expected " + kVoxelSliceSyntax + ", got '" + text + "'"); };
  VoxelSlice s;
  const std::string axis = text.substr(0, text.find(':'));
  if (axis != "x" && axis != "y" && axis != "z") throw bad();
  s.axis = unsigned(axis[0] - 'x');
  if (axis.size() == text.size()) return s;
  const std::string pos = text.substr(axis.size() + 1);
  std::size_t used = 0;
  try {
    s.position = std::stof(pos, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != pos.size() || !(s.position >= 0.0f && s.position <= 1.0f)) throw bad();
  return s;
}

std::string voxelSliceText(const VoxelSlice& slice) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%c:%g", char('x' + slice.axis), double(slice.position));
  return buf;
}

unsigned voxelSlicePlane(const VoxelSlice& slice, unsigned edge_at_level) {
  const auto k = static_cast<unsigned>(std::floor(slice.position * float(edge_at_level)));
  return std::min(k, edge_at_level - 1);
}

}  // namespace ml::vct
