#include "core/dataset_types.h"

#include "core/enum_names.h"

namespace pensight {

namespace {

constexpr EnumName<MeshType> kMeshTypeNames[] = {
    {MeshType::kSquare, "square"},
    {MeshType::kDiamond, "diamond"},
};

}  // namespace

const char* to_string(MeshType type) {
  return enum_name<MeshType>(kMeshTypeNames, type);
}

double net_curvature_per_m(const SceneConfig& scene) {
  return scene.flat_panel ? 0.0 : 1 / scene.pen_radius_m;
}

std::optional<MeshType> parse_mesh_type(const std::string& name) {
  return parse_enum_name<MeshType>(kMeshTypeNames, name);
}

}  // namespace pensight
