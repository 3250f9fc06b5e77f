#pragma once
// Point lights in glTF files (KHR_lights_punctual), read and written.
//
// Reading: the extension's light table (the file's "extensions" JSON, checked
// here field by field: tinygltf's typed table turns a malformed colour or
// range into a default) and the lights the nodes of the default scene place
// ({"extensions": {"KHR_lights_punctual": {"light": i}}}), in the order the
// mesh loader visits nodes (depth first, parent before children). A light
// placed by two nodes is two lights. Point lights become gpu::PointLight:
//  - position: the node's world transform applied to the origin;
//  - colour: glTF colour (default [1, 1, 1]) x intensity (default 1, candela),
//    per metre squared: the renderer's colour is the illuminance the glTF
//    light gives at 1 m, in the renderer's unit scale where 1 is a full-white
//    light. The renderer then replaces the inverse-square falloff by its
//    window I (1 - d/r)^2 (host/shared/shading_model.h);
//  - radius: "range" (as glTF says, unaffected by the node's scale). A light
//    without range (glTF: infinite) gets the distance at which its
//    inverse-square contribution max(colour x intensity) / d^2 falls to the
//    threshold T, r = sqrt(max(colour x intensity) / T): beyond it the glTF
//    light adds less than T, and the renderer's window ends there. Such a
//    light with zero intensity has no radius and is skipped.
// Spot and directional lights, lights no node places and dark range-less
// lights are skipped and counted (GltfLightTable::skippedNote: one line).
// Malformed entries are one-line UserErrors naming the file: a light that is
// not an object; a type other than point, spot or directional; a colour that
// is present but not 3 finite numbers >= 0 (an absent colour is white, as
// glTF says); an intensity that is not a finite number >= 0; a range that is
// not a finite number > 0; a node whose extension is malformed or names a
// light that does not exist; a non-finite position or colour x intensity.
//
// Writing: one node per light (translation, "name": "light i") and one
// table entry per light, type point with its range, so that the file opens
// beside the scene in other tools and reads back to the identical set: a
// colour within [0, 1] is written as it is with intensity 1, a brighter one
// divided by its largest component m with intensity m (each quotient the
// shortest decimal whose product with m, in double as the reader multiplies,
// is the float again, else the exact quotient, which always is).
#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "host/shared/gpu_types.h"

namespace ml {

// The default T of --light-threshold: below one step of an 8-bit display
// (1/256 of a full-white light). A white 1 cd light gets r = 16 m.
constexpr float kDefaultLightThreshold = 1.0f / 256.0f;

// sqrt(max(intensity) / threshold): the radius of a light without range.
// 0 for a dark light.
float thresholdRadius(const glm::vec3& intensity, float threshold);

struct GltfLightTable {
  std::vector<gpu::PointLight> lights;  // the placed point lights, in node order
  std::size_t table_size = 0;           // entries in the extension's light table
  std::size_t spot = 0;                 // placements skipped, by reason
  std::size_t directional = 0;
  std::size_t dark = 0;                 // point lights without range and intensity
  std::size_t unplaced = 0;             // table entries no node of the scene places
  // "" when nothing was skipped, else one line (without the file name) that
  // says how many lights were skipped and why.
  std::string skippedNote() const;
};

// The point lights of any .gltf/.glb (meshes ignored, images not decoded);
// the skipped note goes to stderr. UserError naming the file on malformed
// input (see above) or a threshold that is not finite and > 0.
GltfLightTable loadGltfLights(const std::string& path, float threshold = kDefaultLightThreshold);

// The light set as a glTF document (.glb container when `binary`), as
// described above. UserError for a light that cannot be written (non-finite
// values, radius <= 0, a negative colour).
std::string gltfLightsDocument(const std::vector<gpu::PointLight>& lights, bool binary);

// True for a path ending in .gltf or .glb.
bool isGltfPath(const std::string& path);

}  // namespace ml
