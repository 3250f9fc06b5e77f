#include "host/app/GiOptions.hpp"

#include <cstdio>
#include <filesystem>

#include "host/bench/OutputFiles.hpp"
#include "host/util/Error.hpp"

namespace ml {

namespace {

void addVctFlags(CLI::App& cmd, vct::VctGiSettings& v, bool& with_reference) {
  cmd.add_option("--voxels", v.grid.voxels, "--gi vct: level-0 voxels per axis (a power of two up to 512)")
      ->capture_default_str();
  cmd.add_option("--levels", v.grid.levels, "--gi vct: mip levels (1..log2(voxels) + 1)")->capture_default_str();
  cmd.add_flag("--anisotropic", v.grid.anisotropic, "--gi vct: anisotropic voxels (6 directions per voxel)");
  cmd.add_option("--cones", v.cones, "--gi vct: diffuse cones per pixel (1..32)")->capture_default_str();
  cmd.add_option("--cone-aperture", v.aperture_deg, "--gi vct: diffuse cone aperture in degrees (0..180)")
      ->capture_default_str();
  cmd.add_option("--gi-scale", v.gi_scale, "--gi vct: trace resolution as a fraction of --size, (0, 1]")
      ->capture_default_str();
  cmd.add_flag("--specular", v.specular, "--gi vct: add a specular cone (reflectance 0.04, aperture 10 degrees)");
  cmd.add_option("--vct-shadows", v.shadows,
                 "--gi vct: visibility of the lights in the injected direct light (none; voxel is not available)")
      ->capture_default_str();
  cmd.add_flag("--gi-reference", with_reference,
               "--gi vct: also trace the Embree reference (--gi-samples, --gi-seed) and report gi_rel_rmse");
}

}  // namespace

void addGiFlags(CLI::App& cmd, GiArgs& a) {
  cmd.add_option("--gi", a.mode,
                 "global illumination: none, reference (ray-traced one-bounce diffuse indirect light, "
                 "written as <out>_gi_reference.exr/.png) or vct (voxel cone tracing added to the frame, "
                 "its indirect image as <out>_gi_vct.exr/.png)")
      ->capture_default_str();
  cmd.add_option("--gi-samples", a.samples, "--gi reference: hemisphere samples per pixel (1.." +
                                                std::to_string(kMaxGiSamples) + ")")
      ->capture_default_str();
  cmd.add_option("--gi-shadows", a.shadows,
                 "--gi reference: visibility of the lights from the bounce points (none|ray)")
      ->capture_default_str();
  cmd.add_option("--gi-seed", a.seed, "--gi reference: seed of the hemisphere samples")->capture_default_str();
  addVctFlags(cmd, a.vct, a.with_reference);
}

std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext) {
  std::filesystem::path p(out);
  p.replace_extension();
  return p.string() + "_gi_" + kind + ext;
}

void checkGiFlags(const GiArgs& a, const std::string& out) {
  if (a.mode != "none" && a.mode != "reference" && a.mode != "vct")
    throw UserError("--gi: expected none|reference|vct, got '" + a.mode + "'");
  if (a.samples == 0 || a.samples > kMaxGiSamples)
    throw UserError("--gi-samples: expected 1.." + std::to_string(kMaxGiSamples) + ", got " + std::to_string(a.samples));
  if (a.shadows != "none" && a.shadows != "ray")
    throw UserError("--gi-shadows: expected none|ray, got '" + a.shadows + "'");
  vct::checkVctGiSettings(a.vct);
  if (a.with_reference && a.mode != "vct") throw UserError("--gi-reference: only with --gi vct");
  if (a.with_reference && a.shadows != "none")
    throw UserError("--gi-shadows: vct injects light without visibility, so its reference must too (none)");
  if (a.mode == "none" || out.empty()) return;
  const bool reference = a.mode == "reference" || a.with_reference;
  for (const char* ext : {".exr", ".png"}) {
    if (reference) requireImageFile("--out", giOutputPath(out, "reference", ext));
    if (a.mode == "vct") requireImageFile("--out", giOutputPath(out, "vct", ext));
  }
  if (a.mode == "vct") requireImageFile("--out", giOutputPath(out, "vct_ao", ".png"));
}

std::unique_ptr<GiPass> makeGiPass(const GiArgs& a, ClRuntime& cl, const Scene& scene) {
  if (a.mode != "vct") return nullptr;
  return std::make_unique<vct::VctGiPass>(cl, a.vct, scene.bounds);
}

namespace {

// c / (c + mean luminance of the covered pixels); alpha 1.
std::vector<float> toneMapped(const std::vector<float>& rgba) {
  double sum = 0;
  std::size_t covered = 0;
  for (std::size_t i = 0; i < rgba.size(); i += 4)
    if (rgba[i + 3] > 0) {
      sum += 0.2126 * rgba[i] + 0.7152 * rgba[i + 1] + 0.0722 * rgba[i + 2];
      ++covered;
    }
  const float key = covered && sum > 0 ? float(sum / double(covered)) : 1.0f;
  std::vector<float> px(rgba);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = i % 4 == 3 ? 1.0f : px[i] / (px[i] + key);
  return px;
}

// Linear EXR and tone-mapped PNG of `rgba` as <out stem>_gi_<kind>.
void writeGiImages(const std::string& out, const std::string& kind, unsigned w, unsigned h,
                   const std::vector<float>& rgba, GiResult& r) {
  if (out.empty()) return;
  const std::string exr = giOutputPath(out, kind, ".exr"), png = giOutputPath(out, kind, ".png");
  writeImageAtomically("--out", exr, w, h, 4, rgba);
  writeImageAtomically("--out", png, w, h, 4, toneMapped(rgba));
  r.files.insert(r.files.end(), {exr, png});
}

void writeAo(const std::string& out, unsigned w, unsigned h, const std::vector<float>& ao, GiResult& r) {
  if (out.empty()) return;
  std::vector<float> px;
  for (float v : ao) px.insert(px.end(), {v, v, v, 1.0f});
  r.files.push_back(giOutputPath(out, "vct_ao", ".png"));
  writeImageAtomically("--out", r.files.back(), w, h, 4, px);
}

}  // namespace

GiResult runGi(const GiArgs& a, const SceneInputs& inputs, const Camera& camera, unsigned width, unsigned height,
               const std::string& out, const GiPass* pass) {
  GiResult r;
  if (a.mode == "none") return r;
  r.ran = true;
  std::vector<float> vct_image;
  if (const auto* v = dynamic_cast<const vct::VctGiPass*>(pass)) {
    vct_image = v->indirectRgba();
    r.voxel_bytes = vct::voxelBytes(a.vct.grid);
    writeGiImages(out, "vct", width, height, vct_image, r);
    writeAo(out, width, height, v->ambientOcclusion(), r);
  }
  if (a.mode == "reference" || a.with_reference) {
    const IndirectOptions o{a.samples, a.seed, a.shadows == "ray"};
    const IndirectImage img = traceIndirectReference(inputs.scene, inputs.lights, camera, width, height, o);
    r.has_reference = true;
    r.ms = img.ms;
    std::printf("\ngi reference: %u samples/pixel, shadows %s: %.1f ms\n", a.samples, a.shadows.c_str(), img.ms);
    writeGiImages(out, "reference", width, height, img.rgba, r);
    if (!vct_image.empty()) {
      r.error = indirectRelRmse(vct_image, img.rgba);
      std::printf("gi vct vs reference: relative RMSE %.4f over %zu pixels (%zu covered in one image only)\n",
                  r.error.rel_rmse, r.error.pixels, r.error.mismatched);
    }
  }
  for (const auto& f : r.files) std::printf("wrote %s\n", f.c_str());
  return r;
}

}  // namespace ml
