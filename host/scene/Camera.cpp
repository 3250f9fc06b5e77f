#include "host/scene/Camera.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "host/scene/SceneJson.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

using scene_json::json;

void validate(const Camera& c, const std::string& where) {
  const glm::vec3 forward = c.center - c.eye;
  const float scale = std::max({1.0f, glm::length(c.eye), glm::length(c.center)});
  if (!(glm::length(forward) > 1e-6f * scale)) throw UserError(where + ": \"eye\" and \"center\" coincide");
  if (!(glm::length(c.up) > 0.0f)) throw UserError(where + ": \"up\" is a zero vector");
  const glm::vec3 side = glm::cross(glm::normalize(forward), glm::normalize(c.up));
  if (!(glm::length(side) > 1e-6f)) throw UserError(where + ": \"up\" is parallel to the view direction");
  if (!(c.fovy_degrees > 0.0f && c.fovy_degrees < 180.0f))
    throw UserError(where + ": \"fovy\" must be in (0, 180) degrees (got " + std::to_string(c.fovy_degrees) + ")");
  checkDepthRange(c, where);
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Reads eye/center/up and the optional lens fields of `obj` over `base`, so path
// frames inherit the path-level fovy/near/far unless they override them.
Camera readCamera(const json& obj, const Camera& base, const std::string& where, bool need_pose) {
  if (!obj.is_object()) throw UserError(where + ": must be an object");
  Camera c = base;
  if (need_pose) {
    c.eye = scene_json::toVec3(scene_json::member(obj, "eye", where), where, "eye");
    c.center = scene_json::toVec3(scene_json::member(obj, "center", where), where, "center");
    if (auto it = obj.find("up"); it != obj.end()) c.up = scene_json::toVec3(*it, where, "up");
  }
  if (auto it = obj.find("fovy"); it != obj.end()) c.fovy_degrees = scene_json::toFloat(*it, where, "fovy");
  if (auto it = obj.find("near"); it != obj.end()) c.near_plane = scene_json::toFloat(*it, where, "near");
  if (auto it = obj.find("far"); it != obj.end()) c.far_plane = scene_json::toFloat(*it, where, "far");
  return c;
}

nlohmann::ordered_json pose(const Camera& c) {
  nlohmann::ordered_json j;
  j["eye"] = scene_json::storable(c.eye);
  j["center"] = scene_json::storable(c.center);
  j["up"] = scene_json::storable(c.up);
  return j;
}

void addLens(nlohmann::ordered_json& j, const Camera& c, const Camera* inherited) {
  if (!inherited || c.fovy_degrees != inherited->fovy_degrees) j["fovy"] = scene_json::storable(c.fovy_degrees);
  if (!inherited || c.near_plane != inherited->near_plane) j["near"] = scene_json::storable(c.near_plane);
  if (!inherited || c.far_plane != inherited->far_plane) j["far"] = scene_json::storable(c.far_plane);
}

}  // namespace

void checkDepthRange(const Camera& c, const std::string& where) {
  const float n = c.near_plane, f = c.far_plane;
  if (!(n > 0.0f)) throw UserError(where + ": \"near\" must be > 0 (got " + num(n) + ")");
  if (!(f > n)) throw UserError(where + ": \"far\" must exceed \"near\" (got near " + num(n) + ", far " + num(f) + ")");
  if (n < kMinNearPlane)
    throw UserError(where + ": \"near\" " + num(n) + " is below " + num(kMinNearPlane) +
                    ", the smallest the float depth buffer resolves");
  if (!(f / n <= kMaxFarOverNear))
    throw UserError(where + ": \"far\" / \"near\" = " + num(double(f) / n) + " (near " + num(n) + ", far " + num(f) +
                    ") exceeds " + num(kMaxFarOverNear) + ", the largest ratio the float depth buffer resolves");
}

// The explicit RH variant keeps the GL convention even if some translation
// unit defines GLM_FORCE_LEFT_HANDED.
glm::mat4 Camera::view() const { return glm::lookAtRH(eye, center, up); }

// Reversed-Z (host/shared/depth_convention.h): clip z = p22 z_view + p32, w = -z_view,
// so near maps to 1 and far to 0. Written through r = n / f so that n f cannot
// overflow for any far a float holds.
glm::mat4 Camera::projection(float aspect) const {
  const float t = std::tan(glm::radians(fovy_degrees) * 0.5f);
  const float r = near_plane / far_plane;
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f / (aspect * t);
  p[1][1] = 1.0f / t;
  p[2][2] = r / (1.0f - r);
  p[2][3] = -1.0f;
  p[3][2] = near_plane / (1.0f - r);
  return p;
}

gpu::CameraParams Camera::params(unsigned width, unsigned height) const {
  gpu::CameraParams p{};
  // A minimised window reports 0x0; keep the matrices finite rather than NaN.
  const float aspect = static_cast<float>(std::max(width, 1u)) / static_cast<float>(std::max(height, 1u));
  const glm::mat4 v = view();
  const glm::mat4 pr = projection(aspect);
  std::memcpy(p.view, glm::value_ptr(v), sizeof p.view);
  std::memcpy(p.proj, glm::value_ptr(pr), sizeof p.proj);
  p.near_plane = near_plane;
  p.far_plane = far_plane;
  p.tan_half_fovy = std::tan(glm::radians(fovy_degrees) * 0.5f);
  p.aspect = aspect;
  p.width = width;
  p.height = height;
  return p;
}

CameraPath loadCameraJson(const std::string& path) {
  const json doc = scene_json::readFile(path, "camera");
  if (!doc.is_object()) throw UserError(path + ": camera file needs a top-level object");
  CameraPath out;
  auto frames = doc.find("frames");
  if (frames == doc.end()) {
    Camera c = readCamera(doc, Camera{}, path, true);
    validate(c, path);
    out.frames.push_back(c);
    return out;
  }
  if (!frames->is_array() || frames->empty()) throw UserError(path + ": \"frames\" must be a non-empty array");
  const Camera lens = readCamera(doc, Camera{}, path, false);
  out.frames.reserve(frames->size());
  for (std::size_t i = 0; i < frames->size(); ++i) {
    const std::string where = path + ": frame " + std::to_string(i);
    Camera c = readCamera((*frames)[i], lens, where, true);
    validate(c, where);
    out.frames.push_back(c);
  }
  return out;
}

void saveCameraJson(const std::string& path, const CameraPath& path_data) {
  if (path_data.frames.empty()) throw UserError(path + ": refusing to save an empty camera path");
  std::string text;
  if (path_data.frames.size() == 1) {
    nlohmann::ordered_json j = pose(path_data.frames[0]);
    addLens(j, path_data.frames[0], nullptr);
    text = j.dump(2) + "\n";
  } else {
    const Camera& first = path_data.frames[0];
    nlohmann::ordered_json lens;
    addLens(lens, first, nullptr);
    text = lens.dump();
    text.pop_back();  // reopen the object to append the frames one per line
    text += ", \"frames\": [";
    for (std::size_t i = 0; i < path_data.frames.size(); ++i) {
      nlohmann::ordered_json f = pose(path_data.frames[i]);
      addLens(f, path_data.frames[i], &first);
      text += (i ? ",\n  " : "\n  ") + f.dump();
    }
    text += "\n]}\n";
  }
  scene_json::writeFile(path, text, "camera");
}

}  // namespace ml
