#include "host/app/GiOptions.hpp"

#include <cstdio>
#include <filesystem>

#include "host/bench/OutputFiles.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/util/Error.hpp"

namespace ml {

void addGiFlags(CLI::App& cmd, GiArgs& a) {
  cmd.add_option("--gi", a.mode,
                 "global illumination: none, or reference (ray-traced one-bounce diffuse indirect light, "
                 "written as <out>_gi_reference.exr/.png)")
      ->capture_default_str();
  cmd.add_option("--gi-samples", a.samples, "--gi reference: hemisphere samples per pixel (1.." +
                                                std::to_string(kMaxGiSamples) + ")")
      ->capture_default_str();
  cmd.add_option("--gi-shadows", a.shadows,
                 "--gi reference: visibility of the lights from the bounce points (none|ray)")
      ->capture_default_str();
  cmd.add_option("--gi-seed", a.seed, "--gi reference: seed of the hemisphere samples")->capture_default_str();
}

std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext) {
  std::filesystem::path p(out);
  p.replace_extension();
  return p.string() + "_gi_" + kind + ext;
}

void checkGiFlags(const GiArgs& a, const std::string& out) {
  if (a.mode != "none" && a.mode != "reference")
    throw UserError("--gi: expected none|reference, got '" + a.mode + "'");
  if (a.samples == 0 || a.samples > kMaxGiSamples)
    throw UserError("--gi-samples: expected 1.." + std::to_string(kMaxGiSamples) + ", got " + std::to_string(a.samples));
  if (a.shadows != "none" && a.shadows != "ray")
    throw UserError("--gi-shadows: expected none|ray, got '" + a.shadows + "'");
  if (a.mode == "none" || out.empty()) return;
  requireImageFile("--out", giOutputPath(out, a.mode, ".exr"));
  requireImageFile("--out", giOutputPath(out, a.mode, ".png"));
}

namespace {

std::vector<float> toneMapped(const IndirectImage& img) {
  double sum = 0;
  std::size_t covered = 0;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4)
    if (img.rgba[i + 3] > 0) {
      sum += 0.2126 * img.rgba[i] + 0.7152 * img.rgba[i + 1] + 0.0722 * img.rgba[i + 2];
      ++covered;
    }
  const float key = covered && sum > 0 ? float(sum / double(covered)) : 1.0f;
  std::vector<float> px(img.rgba);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = i % 4 == 3 ? 1.0f : px[i] / (px[i] + key);
  return px;
}

}  // namespace

GiResult runGi(const GiArgs& a, const SceneInputs& inputs, const Camera& camera, unsigned width, unsigned height,
               const std::string& out) {
  GiResult r;
  if (a.mode != "reference") return r;
  const IndirectOptions o{a.samples, a.seed, a.shadows == "ray"};
  const IndirectImage img = traceIndirectReference(inputs.scene, inputs.lights, camera, width, height, o);
  r.ran = true;
  r.ms = img.ms;
  std::printf("\ngi reference: %u samples/pixel, shadows %s: %.1f ms\n", a.samples, a.shadows.c_str(), img.ms);
  if (out.empty()) return r;
  r.files = {giOutputPath(out, a.mode, ".exr"), giOutputPath(out, a.mode, ".png")};
  writeImageAtomically("--out", r.files[0], width, height, 4, img.rgba);
  writeImageAtomically("--out", r.files[1], width, height, 4, toneMapped(img));
  for (const auto& f : r.files) std::printf("wrote %s\n", f.c_str());
  return r;
}

}  // namespace ml
