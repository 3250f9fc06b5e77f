#pragma once
// Internal to host/scene: what the mesh loader (GltfLoader.cpp) and the light
// reader (GltfLights.cpp) share about a glTF file, so that both read it, walk
// its nodes and report its problems the same way. Every failure is a one-line
// UserError that starts with the file's path.
#include <spdlog/spdlog.h>
#include <tiny_gltf.h>

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "host/scene/GltfLights.hpp"

namespace ml::gltf_model {

// Loader warnings go to stderr, like its errors, so stdout carries only a
// command's results.
spdlog::logger& warnings();

// Collapses tinygltf's multi-line messages to one line and shortens quoted
// data URIs (which can be megabytes of base64).
std::string summarize(const std::string& text);

// Reads a .gltf or .glb (by its magic, whatever its name). decode_images:
// false leaves images undecoded (the light reader needs none of them);
// true decodes them, an undecodable one dropped with a warning.
tinygltf::Model readModel(const std::string& path, bool decode_images);

// The nodes a scene starts from: the default scene's (or scene 0's) roots; in
// a file without scenes, every node that is no other node's child.
std::vector<int> sceneRoots(const tinygltf::Model& model, const std::string& path);

// A node's matrix, or its translation * rotation * scale; `where` names the
// node in errors (wrong array lengths).
glm::mat4 localTransform(const tinygltf::Node& node, const std::string& path, const std::string& where);

// The model's KHR_lights_punctual point lights (host/scene/GltfLights.hpp);
// the model must have been read by readModel (which keeps the extensions'
// JSON text that the table is checked against).
GltfLightTable readLights(const tinygltf::Model& model, const std::string& path, float threshold);

}  // namespace ml::gltf_model
