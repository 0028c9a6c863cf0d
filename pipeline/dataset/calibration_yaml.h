#pragma once
// The YAML files of the dataset contract: cam0/sensor.yaml (EuRoC / Kalibr keys),
// dvl0/sensor.yaml and scene.yaml. Parsing checks every key pensight reads and notes the keys it
// does not (other tools write their own; see strict_yaml.h); writing produces files the parser
// reads back exactly.
#include <filesystem>
#include <string>

#include "core/dataset_types.h"

namespace pensight {

CameraCalibration read_camera_yaml(const std::filesystem::path& file);
std::string camera_yaml(const CameraCalibration& calib);

// dvl0/sensor.yaml: sensor_type: dvl, rate_hz, T_BS (4x4, DVL -> body) and beam_directions (4
// unit vectors in the DVL frame), read as {cols: 3, rows: 4, data: [...]} (one per row) or as
// [[x, y, z], ...]; written as the matrix.
DvlCalibration read_dvl_yaml(const std::filesystem::path& file);
std::string dvl_yaml(const DvlCalibration& calib);

SceneConfig read_scene_yaml(const std::filesystem::path& file);
std::string scene_yaml(const SceneConfig& scene);

// Markdown rows (core/params.h) of the numeric keys each file takes; the others (matrices, lists,
// names) are described in ../shared/dataset-format.md.
std::string camera_param_rows();
std::string dvl_param_rows();
std::string scene_param_rows();

}  // namespace pensight
