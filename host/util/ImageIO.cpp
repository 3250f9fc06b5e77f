#include "host/util/ImageIO.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <memory>

#include "host/util/Error.hpp"

namespace ml {

void writeImage(const std::string& path, unsigned width, unsigned height, unsigned channels,
                const std::vector<float>& pixels) {
  if (pixels.size() < static_cast<size_t>(width) * height * channels)
    throw std::logic_error("writeImage: pixel buffer smaller than the image");
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw UserError(path + ": cannot write this image format (use .png or .exr): " + OIIO::geterror());
  const bool is_float = path.size() >= 4 && path.substr(path.size() - 4) == ".exr";
  OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), static_cast<int>(channels),
                       is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec)) throw UserError(path + ": cannot open for writing: " + out->geterror());
  const size_t row = static_cast<size_t>(width) * channels;
  std::vector<float> flipped(static_cast<size_t>(height) * row);
  for (unsigned y = 0; y < height; ++y)
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * row), row,
                flipped.begin() + static_cast<std::ptrdiff_t>(y * row));
  if (!is_float)
    for (float& v : flipped) v = std::clamp(v, 0.0f, 1.0f);
  if (!out->write_image(OIIO::TypeDesc::FLOAT, flipped.data()) || !out->close())
    throw UserError(path + ": writing failed: " + out->geterror());
}

std::vector<float> readImageRgba(const std::string& path, unsigned& width, unsigned& height) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw UserError(path + ": cannot read image: " + OIIO::geterror());
  const auto& spec = in->spec();
  width = static_cast<unsigned>(spec.width);
  height = static_cast<unsigned>(spec.height);
  const int ch = spec.nchannels;
  std::vector<float> raw(static_cast<size_t>(width) * height * ch);
  if (!in->read_image(0, 0, 0, ch, OIIO::TypeDesc::FLOAT, raw.data()))
    throw UserError(path + ": reading failed: " + in->geterror());
  std::vector<float> out(static_cast<size_t>(width) * height * 4, 1.0f);
  for (unsigned y = 0; y < height; ++y)
    for (unsigned x = 0; x < width; ++x)
      for (int c = 0; c < std::min(ch, 4); ++c)
        out[((height - 1 - y) * width + x) * 4 + c] = raw[(static_cast<size_t>(y) * width + x) * ch + c];
  return out;
}

}  // namespace ml
