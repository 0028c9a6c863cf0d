#pragma once
// ONNX import and TensorRT-compatible export of kernels::Graph (ONNX protobuf from Debian libonnx).
#include <filesystem>
#include <string>

#include "kernels/nn/nn.h"

namespace pensight::kernels {

// Loads an ONNX model with static input shapes. BatchNormalization after a Conv is folded into
// the Conv's weights; Identity, Dropout and Cast-to-float are dropped; Constant nodes and
// initializers become constants. An unsupported op, a dynamic shape or a non-constant shape
// input throws pensight::Error naming the op, the node and a hint.
Graph import_onnx(const std::filesystem::path& file);
Graph import_onnx_bytes(const std::string& bytes, const std::string& what = "model");

struct OnnxExportOptions {
  bool fp16_weights = false;  // FLOAT16 initializers, each followed by a Cast to FLOAT
  std::string producer = "pensight";
};

// Opset 17, static shapes, initializers embedded, only ops on TensorRT's supported list.
std::string export_onnx_bytes(const Graph& graph, const OnnxExportOptions& options = {});
// Writes to a temporary name next to `file`, then renames (no partial file on failure).
void export_onnx(const Graph& graph, const std::filesystem::path& file,
                 const OnnxExportOptions& options = {});

// The same model for OpenCV 4.6's ONNX importer, which reads Clip only in its opset-6 form: Clip
// nodes get min/max attributes instead of inputs (same function; not a valid opset-17 file, so
// use it only to hand a model to cv::dnn::readNetFromONNX).
std::string opencv_dnn_compatible(const std::string& onnx_bytes);

// Runs the ONNX checker (libonnx C++) on serialized model bytes; throws pensight::Error with the
// checker's message when the model is invalid.
void check_onnx_bytes(const std::string& bytes);

}  // namespace pensight::kernels
