#include "host/app/InputFlags.hpp"

#include "host/run/InputChecks.hpp"
#include "host/util/ThesisSeed.hpp"

namespace ml {
namespace {

void addSceneFlags(CLI::App& cmd, SceneInputArgs& a, unsigned groups) {
  if (groups & kSceneFlag) {
    cmd.add_option("--scene,--suite", a.scene,
                   "scene: a .gltf/.glb file, a folder with scene.glb + camera.json + lights.json, or a thesis "
                   "scene-suite folder (geometry/ obj/ lights/ camera/); default: data/default");
    cmd.add_option("--camera", a.camera, "camera or camera-path JSON; default: the scene folder's camera.json");
    cmd.add_option("--light-threshold", a.light_threshold,
                   "glTF point lights without range get the radius where their inverse-square contribution "
                   "max(colour x intensity)/d^2 falls to this (renderer units, 1 = full white)")
        ->check(finitePositive())
        ->capture_default_str();
  }
  if (groups & kLightFlag)
    cmd.add_option("--lights", a.lights,
                   "light count to generate (in the scene's light volumes), a light JSON file or a .gltf/.glb "
                   "(its KHR_lights_punctual point lights); default: the scene folder's lights.json, else the "
                   "glTF scene's own lights, else data/default/lights.json");
  if (groups & kWriteLightsFlag)
    cmd.add_option("--write-lights", a.write_lights,
                   "write the light set in use (generated or loaded) to this .gltf/.glb as KHR_lights_punctual "
                   "point lights, to open beside the scene in other tools");
  if (groups & kGenerateFlags) {
    cmd.add_option("--light-volumes", a.light_volumes, "JSON boxes that generated lights are placed in");
    cmd.add_option("--light-radius", a.light_radius, "radius of generated lights (default: from the volume file)")
        ->check(finitePositive());
    cmd.add_option("--light-density", a.light_density, kLightDensityHelp)->check(finitePositive());
    cmd.add_option("--seed", a.seed, "seed for generated lights (default " + std::to_string(kThesisSeed) + ", the thesis's)");
  }
  if (groups & kSuiteFlags) {
    cmd.add_option("--geometry", a.geometry,
                   "suite: geometry file under geometry/ (default deferred_attenuated.json)");
    cmd.add_flag("--allow-missing-meshes", a.allow_missing_meshes,
                 "suite: skip objects whose OBJ mesh is missing (warns) instead of failing");
  }
}

}  // namespace

void addInputFlags(CLI::App& cmd, const InputFlags& f) {
  if (f.inputs) addSceneFlags(cmd, *f.inputs, f.groups);
  if ((f.groups & kDeviceFlag) && f.device)
    cmd.add_option("--device", *f.device, "OpenCL device: gpu, cpu or an index from `manylights devices`");
  if ((f.groups & kProgressFlag) && f.progress)
    cmd.add_option("--progress", *f.progress, "progress on stderr: auto|bar|lines|none")->capture_default_str();
}

}  // namespace ml
