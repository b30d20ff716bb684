#include "sweep/camera_json.h"

#include <cmath>
#include <string>

#include "common/error.h"
#include "common/math_constants.h"

namespace gtbake {

namespace {

nlohmann::ordered_json vector3(const Eigen::Vector3d& v) {
  return nlohmann::ordered_json::array({v.x(), v.y(), v.z()});
}

Eigen::Vector3d readVector3(const nlohmann::json& json, const char* key, const std::string& where) {
  const auto it = json.find(key);
  if (it == json.end() || !it->is_array() || it->size() != 3) {
    throw Error(where + ": camera." + key + " must be an array of 3 numbers");
  }
  Eigen::Vector3d v;
  for (int c = 0; c < 3; ++c) {
    if (!(*it)[c].is_number() || !std::isfinite((*it)[c].get<double>())) {
      throw Error(where + ": camera." + key + " must be an array of 3 finite numbers");
    }
    v[c] = (*it)[c].get<double>();
  }
  return v;
}

}  // namespace

nlohmann::ordered_json cameraJson(const PerspectiveCamera& camera) {
  nlohmann::ordered_json j;
  j["model"] = "perspective";
  j["position"] = vector3(camera.position);
  j["right"] = vector3(camera.basis.col(0));
  j["up"] = vector3(camera.basis.col(1));
  j["backward"] = vector3(camera.basis.col(2));
  j["yfov"] = camera.yfov;
  return j;
}

PerspectiveCamera cameraFromJson(const nlohmann::json& json, const std::string& where) {
  if (!json.is_object()) throw Error(where + ": camera must be an object");
  if (json.value("model", std::string()) != "perspective") {
    throw Error(where + ": camera.model must be \"perspective\"");
  }
  PerspectiveCamera camera;
  camera.position = readVector3(json, "position", where);
  camera.basis.col(0) = readVector3(json, "right", where);
  camera.basis.col(1) = readVector3(json, "up", where);
  camera.basis.col(2) = readVector3(json, "backward", where);
  const Eigen::Matrix3d gram = camera.basis.transpose() * camera.basis;
  if ((gram - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6) {
    throw Error(where + ": camera right/up/backward are not orthonormal");
  }
  const auto yfov = json.find("yfov");
  if (yfov == json.end() || !yfov->is_number() || !(yfov->get<double>() > 0.0) ||
      !(yfov->get<double>() < kPi)) {
    throw Error(where + ": camera.yfov must be a number in (0, pi) radians");
  }
  camera.yfov = yfov->get<double>();
  return camera;
}

}  // namespace gtbake
