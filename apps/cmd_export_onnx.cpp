// pensight export-onnx MODEL --out FILE [--fp16]: writes a TensorRT-ready ONNX file (opset 17,
// static shapes, BN folded, initializers embedded). MODEL is an ONNX file (re-written through
// our importer) or a built-in architecture: builtin:compact or builtin:trudepth (320x240,
// random weights; for engine tests and TensorRT smoke tests), or builtin:all-ops (every op).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "apps/command.h"
#include "core/error.h"
#include "kernels/nn/nn_models.h"
#include "kernels/nn/nn_onnx.h"

namespace pensight::app {
namespace {

kernels::Graph load(const std::string& model) {
  if (model == "builtin:compact") return kernels::compact_depth_net({320, 240}, 1);
  if (model == "builtin:trudepth") return kernels::trudepth_net({320, 240}, 0.5f, 1);
  // Every op of the engine in a few kilobytes: for checking another runtime, and a fuzz seed.
  if (model == "builtin:all-ops") return kernels::all_ops_net(1);
  if (model.starts_with("builtin:")) {
    throw Error("export-onnx: unknown built-in model '" + model +
                "'; use builtin:compact, builtin:trudepth or builtin:all-ops");
  }
  return kernels::import_onnx(model);
}

}  // namespace

int cmd_export_onnx(const Args& args) {
  CLI::App cli("Write a model as TensorRT-compatible ONNX (opset 17, static shapes, BN folded)",
               "pensight export-onnx");
  std::string model, out;
  kernels::OnnxExportOptions options;
  cli.add_option("MODEL", model,
                 "a .onnx file, builtin:compact, builtin:trudepth or builtin:all-ops")
      ->required();
  cli.add_option("--out", out, "ONNX file to write")->required();
  cli.add_flag("--fp16", options.fp16_weights, "store the weights as fp16");
  try {
    cli.parse(std::vector<std::string>(args.rbegin(), args.rend()));
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  const kernels::Graph graph = load(model);
  const std::string bytes = kernels::export_onnx_bytes(graph, options);
  kernels::check_onnx_bytes(bytes);
  kernels::export_onnx(graph, out, options);
  std::printf("wrote %s: %zu nodes, %.3f GFLOP per inference, %s weights, %zu bytes\n", out.c_str(),
              graph.nodes().size(), graph.flops() * 1e-9, options.fp16_weights ? "fp16" : "fp32",
              bytes.size());
  return 0;
}

PENSIGHT_COMMAND("export-onnx",
                 "write a model as TensorRT-compatible ONNX (opset 17, static shapes)",
                 cmd_export_onnx);

}  // namespace pensight::app
