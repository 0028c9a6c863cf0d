#pragma once
// Models built in code with random weights (tests, benchmarks, the export-onnx command): the
// architectures matter here, not the weights. The trained, shipped network is models/*.onnx
// (scripts/train_depth.py, models/README.md), read through nn_onnx.h.
#include <cstdint>
#include <random>

#include "kernels/nn/nn.h"

namespace pensight::kernels {

struct ModelSize {
  int width = 320;  // network input resolution
  int height = 240;
};

// Compact depth-completion net with the two-channel prior the depth stage also accepts: inputs
// "image" [1,1,H,W] and "prior" [1,2,H,W] (S1, S2); a 3-level conv encoder, bilinear decoder with
// the prior concatenated at every scale; output "depth" [1,1,H,W] (softplus). It is not the
// shipped model's architecture: models/compact_depth.onnx takes "prior" [1,3,H,W] (S1, S2 and the
// prior surface Q) and is the U-Net of scripts/train_depth.py.
Graph compact_depth_net(ModelSize size, uint64_t seed);

// TRUDepth architecture at reduced width (width_mult scales every channel count): inputs
// "image" [1,3,H,W] and "prior" [1,2,H,W]; MobileNetV2 encoder (inverted residuals, ReLU6),
// bilinear decoder concatenating the resized prior at every scale, AdaBins-style head (patch
// embedding, one transformer encoder layer, bin widths -> centres, range-attention logits,
// per-pixel softmax over bins); output "depth" [1,1,H,W]. DepthHead::kConvSoftplus ends the
// decoder in a 3x3 conv + softplus, upsampled (for peers that cannot run the transformer, e.g.
// OpenCV 4.6).
enum class DepthHead { kAdaBins, kConvSoftplus };
Graph trudepth_net(ModelSize size, float width_mult, uint64_t seed,
                   DepthHead head = DepthHead::kAdaBins);

// Small random graph that uses every op of the engine at least once (export/import coverage).
Graph all_ops_net(uint64_t seed);

}  // namespace pensight::kernels
