#pragma once
// The one parser of an image size flag (--size, --sizes, the bench mains'
// resolution lists): "1280x720" -> (1280, 720), 1..16384 pixels each way;
// anything else is a UserError naming `flag`.
#include <string>

namespace ml {

void parseSize(const std::string& text, const std::string& flag, unsigned& w, unsigned& h);

}  // namespace ml
