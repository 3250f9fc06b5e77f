#pragma once
// Image files through OpenImageIO: .png (8-bit, clamped) or .exr (float),
// chosen by extension. Pixel rows are given bottom-up (GL order) and written
// top-down. Errors are UserErrors naming the file.
#include <string>
#include <vector>

namespace ml {

void writeImage(const std::string& path, unsigned width, unsigned height, unsigned channels,
                const std::vector<float>& pixels_bottom_up);

// Reads any OIIO format as float RGBA, rows bottom-up (for tests and tools).
std::vector<float> readImageRgba(const std::string& path, unsigned& width, unsigned& height);

}  // namespace ml
