// render's GI outputs after the frames (GiOptions.hpp: runGi): the pass's
// report, its indirect, extra and view images, the reference and the error.
#include <cstdio>

#include "host/app/GiOptions.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/gi/Registry.hpp"
#include "host/reference/ReferenceCache.hpp"
#include "host/util/GiToneMap.hpp"

namespace ml {
namespace {

// Linear EXR and tone-mapped PNG of `rgba` as <out stem>_gi_<kind>.
void writeGiImages(const std::string& out, const std::string& kind, unsigned w, unsigned h,
                   const std::vector<float>& rgba, GiResult& r) {
  if (out.empty()) return;
  const std::string exr = giOutputPath(out, kind, ".exr"), png = giOutputPath(out, kind, ".png");
  writeImageAtomically("--out", exr, w, h, 4, rgba);
  writeImageAtomically("--out", png, w, h, 4, giToneMapped(rgba));
  r.files.insert(r.files.end(), {exr, png});
}

// The view parameters given: <out>_gi_<pass>_<suffix>.exr (linear) and .png (as displayed).
void writeView(const GiArgs& a, const GiDescriptor& d, GiPass& pass, const Camera& camera, unsigned w, unsigned h,
               const std::string& out, GiResult& r) {
  const ParamValues view = giViewParams(d, giPassParams(a), a.view);
  const std::string flag = d.view_params.front().renderFlag();
  const GiViewImage img = pass.view(view, {camera.view(), camera.projection(float(w) / float(h)), w, h});
  const std::string kind = d.name + "_" + img.suffix;
  const std::string exr = giOutputPath(out, kind, ".exr"), png = giOutputPath(out, kind, ".png");
  writeImageAtomically(flag, exr, w, h, 4, img.linear);
  writeImageAtomically(flag, png, w, h, 4, img.display);
  r.files.insert(r.files.end(), {exr, png});
  if (!img.line.empty()) std::printf("%s\n", img.line.c_str());
}

// The pass's report, indirect image, extra images and views; returns the indirect image.
std::vector<float> passOutputs(const GiArgs& a, GiPass& pass, const Camera& camera, unsigned w, unsigned h,
                               const std::string& out, GiResult& r) {
  const GiDescriptor& d = *giPassOf(a);
  r.has_pass = true;
  r.stats = pass.stats();
  for (const std::string& line : r.stats.lines) std::printf("\n%s\n", line.c_str());
  std::vector<float> image = pass.indirectRgba();
  writeGiImages(out, d.name, w, h, image, r);
  if (!out.empty())
    for (const GiImage& extra : pass.extraImages()) {
      r.files.push_back(giOutputPath(out, d.name + "_" + extra.suffix, ".png"));
      writeImageAtomically("--out", r.files.back(), w, h, 4, extra.rgba);
    }
  if (!a.view.empty()) writeView(a, d, pass, camera, w, h, out, r);
  return image;
}

}  // namespace

GiResult runGi(const GiArgs& a, const SceneInputs& inputs, const Camera& camera, unsigned width, unsigned height,
               const std::string& out, GiPass* pass) {
  GiResult r;
  if (a.mode == "none") return r;
  r.ran = true;
  std::vector<float> image;
  if (pass) image = passOutputs(a, *pass, camera, width, height, out, r);
  if (a.mode == "reference" || a.with_reference) {
    const IndirectOptions o{a.samples, a.seed, giShadows(a) == "ray", a.bounces};
    const CachedReference ref = cachedIndirectReference(inputs.scene, inputs.lights, camera, width, height, o);
    const IndirectImage& img = ref.image;
    r.has_reference = true;
    r.reference_cached = ref.from_cache;
    r.ms = img.ms;
    std::printf("\ngi reference: %u samples/pixel, %u bounce%s, shadows %s: %.1f ms%s\n", a.samples, a.bounces,
                a.bounces == 1 ? "" : "s", giShadows(a).c_str(), img.ms,
                ref.from_cache ? " (read from the reference cache)" : "");
    writeGiImages(out, "reference", width, height, img.rgba, r);
    if (!image.empty()) {
      r.error = compareWithReference(image, img);
      std::printf("gi %s vs reference: relative RMSE %.4f over %zu pixels (%zu covered in one image only)\n",
                  a.mode.c_str(), r.error.error.rel_rmse, r.error.error.pixels, r.error.error.mismatched);
      if (r.error.ref_noise >= 0)
        std::printf("gi reference noise: relative RMSE %.4f; %s error without it: %.4f\n", r.error.ref_noise,
                    a.mode.c_str(), r.error.corrected);
    }
  }
  for (const auto& f : r.files) std::printf("wrote %s\n", f.c_str());
  return r;
}

}  // namespace ml
