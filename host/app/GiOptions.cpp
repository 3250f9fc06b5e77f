#include "host/app/GiOptions.hpp"

#include <cstdio>
#include <filesystem>

#include "host/bench/OutputFiles.hpp"
#include "host/util/Error.hpp"
#include "host/util/GiToneMap.hpp"
#include "host/vct/VctSettingsTable.hpp"
#include "host/vct/VoxelView.hpp"

namespace ml {

namespace {

// The voxel view's file: <out>_gi_vct_<this>.exr/.png.
std::string voxelViewFile(const GiArgs& a) { return a.voxel_slice.empty() ? "voxels" : "slice"; }

// A switch given a value (--KEY=off): the table's words only. CLI11 turns the
// value into a count before the flag's function sees it and aborts on words
// it does not know, so they are refused here first (CLI11 names the flag).
CLI::Validator switchValue(const vct::VctSetting& s) {
  return CLI::Validator(
      [&s](std::string& text) -> std::string {
        if (text == "true") return "";  // CLI11's value for the bare flag
        vct::VctGiSettings scratch;
        try {
          s.set(scratch, s.key, text);
        } catch (const UserError& e) {
          const std::string line = e.what(), prefix = s.flag() + ": ";
          return line.rfind(prefix, 0) == 0 ? line.substr(prefix.size()) : line;
        }
        return "";
      },
      "");
}

// From the one VCT settings table (host/vct/VctSettingsTable.hpp): parsed
// here, checked as a whole by checkGiFlags (a flag's range can depend on another's).
void addVctFlags(CLI::App& cmd, vct::VctGiSettings& v, bool& with_reference) {
  const vct::VctGiSettings defaults;
  for (const vct::VctSetting& s : vct::vctSettings()) {
    const std::string help = "--gi vct: " + s.help;
    auto parse = [&v, &s](const std::string& text) {
      try {
        s.set(v, s.key, text);
      } catch (const UserError& e) {
        throw CLI::ValidationError(e.what());  // reported by the parser as one line, exit 2
      }
    };
    if (s.type == vct::VctSettingType::Switch)
      cmd.add_flag_function(s.flag(), [parse](std::int64_t on) { parse(on > 0 ? "on" : "off"); }, help)
          ->check(switchValue(s));
    else
      cmd.add_option_function<std::string>(s.flag(), parse, help + " (default " + s.get(defaults) + ")");
  }
  cmd.add_flag("--gi-reference", with_reference,
               "--gi vct: also trace the Embree reference (--gi-samples, --gi-seed) and report gi_rel_rmse");
}

void addVoxelViewFlags(CLI::App& cmd, std::string& view, unsigned& level, std::string& slice) {
  cmd.add_option("--voxel-view", view,
                 std::string("--gi vct: write the voxel volume seen from the camera as cubes (") + vct::kVoxelViewNames +
                     ") as <out>_gi_vct_voxels.exr/.png");
  cmd.add_option("--voxel-level", level, "--voxel-view: the level shown (0..--levels - 1)")->capture_default_str();
  cmd.add_option("--voxel-slice", slice,
                 std::string("--voxel-view: show the plane ") + vct::kVoxelSliceSyntax +
                     " of the level (nearest voxels) instead of cubes, as <out>_gi_vct_slice.exr/.png");
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
                 "--gi reference: visibility of the lights from the bounce points (none|ray; default: none, "
                 "or ray for --gi vct --vct-shadows voxel --gi-reference)");
  cmd.add_option("--gi-seed", a.seed, "--gi reference: seed of the hemisphere samples")->capture_default_str();
  addVctFlags(cmd, a.vct, a.with_reference);
  addVoxelViewFlags(cmd, a.voxel_view, a.voxel_level, a.voxel_slice);
}

const GiDescriptor& vctGiDescriptor() {
  static const GiDescriptor d = [] {
    GiDescriptor g;
    g.mode = "vct";
    for (const vct::VctSetting& s : vct::vctSettings()) g.keys.push_back(s.key);
    g.resolve = [](const SettingList& given, const std::string& flag) {
      vct::VctGiSettings s;
      try {
        for (const auto& [key, value] : given) vct::parseVctSetting(s, key, value);
        vct::checkVctGiSettings(s);
      } catch (const UserError& e) {
        throw UserError(flag + " " + paramsText(given) + ": " + e.what());
      }
      GiVariant v;
      v.mode = "vct";
      for (const vct::VctSetting& t : vct::vctSettings()) v.settings.emplace_back(t.key, t.get(s));
      v.make = [s](ClRuntime& cl, const Scene& scene) -> std::unique_ptr<GiPass> {
        return std::make_unique<vct::VctGiPass>(cl, s, scene.bounds);
      };
      v.voxel_bytes = vct::voxelBytes(s.grid);
      return v;
    };
    return g;
  }();
  return d;
}

std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext) {
  std::filesystem::path p(out);
  p.replace_extension();
  return p.string() + "_gi_" + kind + ext;
}

std::string giShadows(const GiArgs& a) {
  if (!a.shadows.empty()) return a.shadows;
  return a.mode == "vct" && a.vct.shadows == "voxel" ? "ray" : "none";
}

void checkGiFlags(const GiArgs& a, const std::string& out) {
  if (a.mode != "none" && a.mode != "reference" && a.mode != "vct")
    throw UserError("--gi: expected none|reference|vct, got '" + a.mode + "'");
  if (a.samples == 0 || a.samples > kMaxGiSamples)
    throw UserError("--gi-samples: expected 1.." + std::to_string(kMaxGiSamples) + ", got " + std::to_string(a.samples));
  if (!a.shadows.empty() && a.shadows != "none" && a.shadows != "ray")
    throw UserError("--gi-shadows: expected none|ray, got '" + a.shadows + "'");
  vct::checkVctGiSettings(a.vct);
  if (a.with_reference && a.mode != "vct") throw UserError("--gi-reference: only with --gi vct");
  if (a.with_reference && giShadows(a) != (a.vct.shadows == "voxel" ? "ray" : "none"))
    throw UserError("--gi-shadows: the reference must model vct's transport (--vct-shadows none: none, voxel: ray)");
  if (!a.voxel_view.empty()) {
    vct::parseVoxelView(a.voxel_view);
    vct::checkVoxelLevel(a.voxel_level, a.vct.grid.levels);
    if (!a.voxel_slice.empty()) vct::parseVoxelSlice(a.voxel_slice, "--voxel-slice");
    if (a.mode != "vct") throw UserError("--voxel-view: only with --gi vct");
    if (out.empty())
      throw UserError("--voxel-view: needs --out (the image is <out>_gi_vct_" + voxelViewFile(a) + ".png)");
  } else if (a.voxel_level != 0) {
    throw UserError("--voxel-level: only with --voxel-view");
  } else if (!a.voxel_slice.empty()) {
    throw UserError("--voxel-slice: only with --voxel-view (the values shown)");
  }
  if (a.mode == "none" || out.empty()) return;
  const bool reference = a.mode == "reference" || a.with_reference;
  for (const char* ext : {".exr", ".png"}) {
    if (reference) requireImageFile("--out", giOutputPath(out, "reference", ext));
    if (a.mode == "vct") requireImageFile("--out", giOutputPath(out, "vct", ext));
  }
  if (a.mode == "vct") requireImageFile("--out", giOutputPath(out, "vct_ao", ".png"));
  if (!a.voxel_view.empty())
    for (const char* ext : {".exr", ".png"})
      requireImageFile("--out", giOutputPath(out, "vct_" + voxelViewFile(a), ext));
}

std::unique_ptr<GiPass> makeGiPass(const GiArgs& a, ClRuntime& cl, const Scene& scene) {
  if (a.mode != "vct") return nullptr;
  return std::make_unique<vct::VctGiPass>(cl, a.vct, scene.bounds);
}

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

void writeAo(const std::string& out, unsigned w, unsigned h, const std::vector<float>& ao, GiResult& r) {
  if (out.empty()) return;
  std::vector<float> px;
  for (float v : ao) px.insert(px.end(), {v, v, v, 1.0f});
  r.files.push_back(giOutputPath(out, "vct_ao", ".png"));
  writeImageAtomically("--out", r.files.back(), w, h, 4, px);
}

// --voxel-view: linear EXR (alpha: hit) and the PNG as displayed.
void writeVoxelView(const GiArgs& a, const vct::VctGiPass& pass, const Camera& camera, unsigned w, unsigned h,
                    const std::string& out, GiResult& r) {
  const vct::VoxelViewKind kind = vct::parseVoxelView(a.voxel_view);
  const vct::VoxelVolume& volume = pass.pipeline().volume();
  std::vector<float> rgba;
  if (a.voxel_slice.empty()) {
    const vct::VoxelViewCamera cam{camera.view(), camera.projection(float(w) / float(h)), w, h};
    rgba = vct::VoxelViewPass().render(volume, kind, a.voxel_level, cam);
  } else {
    const vct::VoxelSlice slice = vct::parseVoxelSlice(a.voxel_slice, "--voxel-slice");
    rgba = vct::VoxelViewPass().renderSlice(volume, kind, a.voxel_level, slice, w, h);
  }
  const std::vector<float> png = vct::voxelViewDisplay(rgba, kind);
  const std::string file = "vct_" + voxelViewFile(a);
  const std::string exr = giOutputPath(out, file, ".exr"), png_file = giOutputPath(out, file, ".png");
  writeImageAtomically("--voxel-view", exr, w, h, 4, rgba);
  writeImageAtomically("--voxel-view", png_file, w, h, 4, png);
  r.files.insert(r.files.end(), {exr, png_file});
  std::printf("voxel view: %s of level %u (%u voxels per axis)%s%s\n", a.voxel_view.c_str(), a.voxel_level,
              a.vct.grid.voxels >> a.voxel_level, a.voxel_slice.empty() ? ", cubes" : ", slice ",
              a.voxel_slice.c_str());
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
    r.vct_updates = v->pipeline().updates();
    r.vct_voxelizations = v->pipeline().voxelizations();
    r.vct_reused = v->volumeReuses();
    std::printf("\ngi vct: %zu voxelizations in %zu updates%s; %zu frames reused the volume (unchanged lights)\n",
                r.vct_voxelizations, r.vct_updates,
                a.vct.revoxelize ? " (--revoxelize: every frame)" : " (static geometry: the first frame only)",
                r.vct_reused);
    const vct::VctPipeline& p = v->pipeline();
    if (p.listBuilds() > 0) {
      r.list_builds = p.listBuilds();
      r.list_updates = p.listUpdates();
      r.list_update_bytes = r.list_updates ? p.listUpdateBytes() / r.list_updates : 0;
      r.list_image_bytes = p.lists().linkless().gpuBytes();
      std::printf("\nvct lists: %zu builds, %zu incremental updates uploading %zu bytes each (mean) of %zu\n",
                  r.list_builds, r.list_updates, r.list_update_bytes, r.list_image_bytes);
    }
    writeGiImages(out, "vct", width, height, vct_image, r);
    writeAo(out, width, height, v->ambientOcclusion(), r);
    if (!a.voxel_view.empty()) writeVoxelView(a, *v, camera, width, height, out, r);
  }
  if (a.mode == "reference" || a.with_reference) {
    const IndirectOptions o{a.samples, a.seed, giShadows(a) == "ray"};
    const IndirectImage img = traceIndirectReference(inputs.scene, inputs.lights, camera, width, height, o);
    r.has_reference = true;
    r.ms = img.ms;
    std::printf("\ngi reference: %u samples/pixel, shadows %s: %.1f ms\n", a.samples, giShadows(a).c_str(), img.ms);
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
