#include "host/run/ImageSize.hpp"

#include <charconv>
#include <string_view>

#include "host/util/Error.hpp"

namespace ml {

void parseSize(const std::string& text, const std::string& flag, unsigned& w, unsigned& h) {
  const auto x = text.find('x');
  auto num = [&](std::string_view s, unsigned& v) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && p == s.data() + s.size();
  };
  if (x == std::string::npos || !num(std::string_view(text).substr(0, x), w) ||
      !num(std::string_view(text).substr(x + 1), h) || w == 0 || h == 0 || w > 16384 || h > 16384)
    throw UserError(flag + ": expected WIDTHxHEIGHT with 1..16384 pixels each, got '" + text + "'");
}

}  // namespace ml
