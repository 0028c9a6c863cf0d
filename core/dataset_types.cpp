#include "core/dataset_types.h"

namespace pensight {

const char* to_string(MeshType type) {
  return type == MeshType::kDiamond ? "diamond" : "square";
}

double net_curvature_per_m(const SceneConfig& scene) {
  return scene.flat_panel ? 0.0 : 1 / scene.pen_radius_m;
}

std::optional<MeshType> parse_mesh_type(const std::string& name) {
  for (MeshType t : {MeshType::kSquare, MeshType::kDiamond}) {
    if (name == to_string(t)) return t;
  }
  return std::nullopt;
}

}  // namespace pensight
