#include "kernels/nn/nn_models.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pensight::kernels {
namespace {

// Unique constant names (prefix + value count); built in steps to dodge a GCC 12 -Wrestrict
// false positive on "literal" + std::string.
std::string const_name(const char* prefix, size_t n) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%s%zu", prefix, n);
  return buf;
}

class Builder {
 public:
  explicit Builder(uint64_t seed) : rng_(seed) {}
  Graph g;

  int weight(Dims shape, float scale) {
    std::normal_distribution<float> n(0.f, scale);
    Tensor t{std::move(shape), {}};
    t.data.resize(static_cast<size_t>(num_elements(t.shape)));
    for (float& v : t.data) v = n(rng_);
    return g.add_constant(const_name("w", g.values().size()), std::move(t));
  }
  int scalar(float v) { return g.add_constant(const_name("s", g.values().size()), {{1}, {v}}); }

  // Conv + optional activation; He-style init keeps activations in range through deep stacks.
  int conv(int x, int cout, int k, int stride = 1, int group = 1, Op act = Op::kRelu,
           int dilation = 1) {
    const int64_t cin = g.value(x).shape[1];
    Attrs a;
    a.stride = {stride, stride};
    a.dilation = {dilation, dilation};
    const int pad = dilation * (k - 1) / 2;
    a.pads = {pad, pad, pad, pad};
    a.group = group;
    const float scale = std::sqrt(2.f / static_cast<float>(cin / group * k * k));
    int y =
        g.add(Op::kConv, {x, weight({cout, cin / group, k, k}, scale), weight({cout}, 0.05f)}, a);
    if (act == Op::kClip) {
      Attrs c;
      c.alpha = 0;
      c.beta = 6;
      y = g.add(Op::kClip, {y}, c);
    } else if (act != Op::kSqrt) {  // kSqrt: "no activation" marker
      y = g.add(act, {y});
    }
    return y;
  }
  int linear_conv(int x, int cout, int k, int stride = 1, int group = 1) {
    return conv(x, cout, k, stride, group, Op::kSqrt);
  }
  int resize(int x, int64_t h, int64_t w, ResizeMode mode = ResizeMode::kLinearHalfPixel) {
    Attrs a;
    a.resize = mode;
    a.sizes = {h, w};
    return g.add(Op::kResize, {x}, a);
  }
  int concat(std::vector<int> xs, int axis = 1) {
    Attrs a;
    a.axis = axis;
    return g.add(Op::kConcat, std::move(xs), a);
  }
  int matmul_const(int x, int64_t k, int64_t n) {
    return g.add(Op::kMatMul, {x, weight({k, n}, 1.f / std::sqrt(float(k)))});
  }
  int layer_norm(int x, int64_t c) {
    Attrs a;
    a.axis = -1;
    std::vector<float> ones(static_cast<size_t>(c), 1.f);
    return g.add(
        Op::kLayerNorm,
        {x, g.add_constant(const_name("ln", g.values().size()), {{c}, ones}), weight({c}, 0.02f)},
        a);
  }
  const Dims& shape(int v) const { return g.value(v).shape; }

 private:
  std::mt19937_64 rng_;
};

int ch(int c, float mult) {
  return std::max(4, static_cast<int>(std::lround(static_cast<float>(c) * mult / 4.f)) * 4);
}

}  // namespace

Graph compact_depth_net(ModelSize size, uint64_t seed) {
  Builder b(seed);
  const int64_t H = size.height, W = size.width;
  const int image = b.g.add_input("image", {1, 1, H, W});
  const int prior = b.g.add_input("prior", {1, 2, H, W});
  const int e0 = b.conv(b.concat({image, prior}), 16, 3, 1);
  const int e1 = b.conv(b.conv(e0, 32, 3, 2), 32, 3);
  const int e2 = b.conv(b.conv(e1, 64, 3, 2), 64, 3);
  const int e3 = b.conv(b.conv(e2, 96, 3, 2), 96, 3);
  int d = e3;
  for (int skip : {e2, e1, e0}) {
    const Dims s = b.shape(skip);
    d = b.resize(d, s[2], s[3]);
    const int p = s[2] == H ? prior : b.resize(prior, s[2], s[3]);
    d = b.conv(b.concat({d, skip, p}), static_cast<int>(s[1]), 3);
  }
  const int depth = b.g.add(Op::kSoftplus, {b.linear_conv(d, 1, 3)});
  b.g.mark_output(depth);
  b.g.values()[static_cast<size_t>(depth)].name = std::string("depth");
  return std::move(b.g);
}

Graph trudepth_net(ModelSize size, float wm, uint64_t seed, DepthHead head) {
  Builder b(seed);
  const int64_t H = size.height, W = size.width;
  const int image = b.g.add_input("image", {1, 3, H, W});
  const int prior = b.g.add_input("prior", {1, 2, H, W});

  // MobileNetV2 encoder: stem, then inverted residual stages (t, c, n, s).
  int x = b.conv(image, ch(32, wm), 3, 2, 1, Op::kClip);
  std::vector<int> skips = {x};  // stride 2
  struct Stage {
    int t, c, n, s;
  };
  for (const Stage& st :
       {Stage{1, 16, 1, 1}, {6, 24, 2, 2}, {6, 32, 3, 2}, {6, 64, 2, 2}, {6, 96, 1, 1}}) {
    for (int i = 0; i < st.n; ++i) {
      const int cin = static_cast<int>(b.shape(x)[1]), cout = ch(st.c, wm), hidden = cin * st.t;
      int y = st.t == 1 ? x : b.conv(x, hidden, 1, 1, 1, Op::kClip);
      y = b.conv(y, hidden, 3, i == 0 ? st.s : 1, hidden, Op::kClip);  // depthwise
      y = b.linear_conv(y, cout, 1);
      x = (i > 0 && cin == cout) ? b.g.add(Op::kAdd, {x, y}) : y;
    }
    if (st.s == 2 && st.c != 64) skips.push_back(x);  // strides 4, 8
  }
  // x: stride 16. Decoder: bilinear up, concat skip + prior at that scale, conv.
  int d = b.conv(x, ch(96, wm), 1);
  for (auto it = skips.rbegin(); it != skips.rend(); ++it) {
    const Dims s = b.shape(*it);
    d = b.resize(d, s[2], s[3]);
    d = b.conv(b.concat({d, *it, b.resize(prior, s[2], s[3])}), ch(48, wm), 3);
  }
  if (head == DepthHead::kConvSoftplus) {
    const int out = b.resize(b.g.add(Op::kSoftplus, {b.linear_conv(d, 1, 3)}), H, W);
    b.g.mark_output(out);
    b.g.values()[static_cast<size_t>(out)].name = std::string("depth");
    return std::move(b.g);
  }
  // d: stride 2, E channels. AdaBins head: patch embedding (8x8 patches), one encoder layer.
  const int64_t E = b.shape(d)[1], nbins = 32;
  const int emb = b.linear_conv(d, static_cast<int>(E), 8, 8);  // [1,E,h,w]
  const int64_t L = b.shape(emb)[2] * b.shape(emb)[3];
  Attrs r;
  r.ints = {1, E, L};
  Attrs t;
  t.ints = {0, 2, 1};
  const int tokens = b.g.add(Op::kTranspose, {b.g.add(Op::kReshape, {emb}, r)}, t);  // [1,L,E]
  const int ln1 = b.layer_norm(tokens, E);
  const int q = b.matmul_const(ln1, E, E), k = b.matmul_const(ln1, E, E),
            v = b.matmul_const(ln1, E, E);
  const int kt = b.g.add(Op::kTranspose, {k}, t);  // [1,E,L]
  Attrs sm;
  sm.axis = -1;
  const int att = b.g.add(Op::kSoftmax,
                          {b.g.add(Op::kDiv, {b.g.add(Op::kMatMul, {q, kt}),
                                              b.scalar(std::sqrt(static_cast<float>(E)))})},
                          sm);
  const int h1 = b.g.add(Op::kAdd, {tokens, b.matmul_const(b.g.add(Op::kMatMul, {att, v}), E, E)});
  const int mlp =
      b.matmul_const(b.g.add(Op::kRelu, {b.matmul_const(b.layer_norm(h1, E), E, 2 * E)}), 2 * E, E);
  const int enc = b.g.add(Op::kAdd, {h1, mlp});  // [1,L,E]
  // Bin widths from token 0: Gemm -> ReLU + eps -> normalise -> cumulative sum (triangular MatMul).
  Attrs s0;
  s0.starts = {0};
  s0.ends = {1};
  s0.axes = {1};
  Attrs fl;
  fl.axis = 1;
  const int tok0 = b.g.add(Op::kFlatten, {b.g.add(Op::kSlice, {enc}, s0)}, fl);  // [1,E]
  Attrs gm;
  gm.alpha = 1;
  gm.beta = 1;
  gm.trans_b = true;
  const int raw =
      b.g.add(Op::kGemm, {tok0, b.weight({nbins, E}, 0.1f), b.weight({nbins}, 0.05f)}, gm);
  const int wpos = b.g.add(Op::kAdd, {b.g.add(Op::kRelu, {raw}), b.scalar(0.1f)});
  Attrs rm;
  rm.axes = {1};
  const int widths = b.g.add(
      Op::kDiv,
      {wpos, b.g.add(Op::kMul, {b.g.add(Op::kReduceMean, {wpos}, rm), b.scalar(float(nbins))})});
  std::vector<float> tri(static_cast<size_t>(nbins * nbins), 0.f);
  for (int64_t i = 0; i < nbins; ++i)
    for (int64_t j = i; j < nbins; ++j) tri[static_cast<size_t>(i * nbins + j)] = 1.f;
  const int cum = b.g.add(Op::kMatMul, {widths, b.g.add_constant("cumsum", {{nbins, nbins}, tri})});
  const float min_depth = 0.1f, max_depth = 10.f;
  const int centres = b.g.add(
      Op::kAdd,
      {b.g.add(Op::kMul, {b.g.add(Op::kSub, {cum, b.g.add(Op::kMul, {widths, b.scalar(0.5f)})}),
                          b.scalar(max_depth - min_depth)}),
       b.scalar(min_depth)});  // [1,nbins]
  // Range attention: pixel features . query tokens 1..Q, then per-pixel bin logits.
  const int64_t Q = std::min<int64_t>(16, L - 1);
  Attrs sq;
  sq.starts = {1};
  sq.ends = {1 + Q};
  sq.axes = {1};
  const int queries = b.g.add(Op::kSlice, {enc}, sq);  // [1,Q,E]
  const Dims ds = b.shape(d);
  Attrs rf;
  rf.ints = {1, E, ds[2] * ds[3]};
  const int feat =
      b.g.add(Op::kReshape, {b.linear_conv(d, static_cast<int>(E), 3)}, rf);  // [1,E,HW]
  Attrs rb;
  rb.ints = {1, Q, ds[2], ds[3]};
  const int ram = b.g.add(Op::kReshape, {b.g.add(Op::kMatMul, {queries, feat})}, rb);  // [1,Q,h,w]
  const int logits =
      b.linear_conv(b.conv(ram, ch(32, wm), 1, 1, 1, Op::kLeakyRelu), static_cast<int>(nbins), 1);
  Attrs sc;
  sc.axis = 1;
  const int prob = b.g.add(Op::kSoftmax, {logits}, sc);  // [1,nbins,h,w]
  Attrs rc;
  rc.ints = {1, nbins, 1, 1};
  Attrs rmc;
  rmc.axes = {1};
  const int weighted = b.g.add(Op::kMul, {prob, b.g.add(Op::kReshape, {centres}, rc)});
  const int half =
      b.g.add(Op::kMul, {b.g.add(Op::kReduceMean, {weighted}, rmc), b.scalar(float(nbins))});
  const int depth = b.resize(half, H, W);
  b.g.mark_output(depth);
  b.g.values()[static_cast<size_t>(depth)].name = std::string("depth");
  return std::move(b.g);
}

Graph all_ops_net(uint64_t seed) {
  Builder b(seed);
  const int x = b.g.add_input("x", {1, 4, 16, 12});
  Attrs lr;
  lr.alpha = 0.1f;
  int y = b.conv(x, 8, 3, 1, 1, Op::kLeakyRelu);
  y = b.conv(y, 8, 3, 2, 8, Op::kClip, 1);     // depthwise stride 2
  y = b.conv(y, 8, 3, 1, 2, Op::kSigmoid, 2);  // grouped, dilated
  Attrs ct;
  ct.stride = {2, 2};
  ct.pads = {1, 1, 1, 1};
  y = b.g.add(Op::kConvTranspose, {y, b.weight({8, 6, 4, 4}, 0.2f), b.weight({6}, 0.1f)},
              ct);  // [1,6,16,12]
  y = b.g.add(Op::kSoftplus, {y});
  y = b.g.add(Op::kSqrt, {y});
  y = b.g.add(Op::kPow, {y, b.scalar(1.5f)});
  y = b.g.add(Op::kSub, {y, b.g.add(Op::kDiv, {b.linear_conv(x, 6, 1), b.scalar(3.f)})});
  Attrs mp;
  mp.kernel = {3, 3};
  mp.stride = {2, 2};
  mp.pads = {1, 1, 1, 1};
  const int pooled = b.g.add(Op::kMaxPool, {y}, mp);  // [1,6,8,6]
  Attrs ap;
  ap.kernel = {2, 2};
  ap.stride = {2, 2};
  const int avg = b.g.add(Op::kAveragePool, {pooled}, ap);  // [1,6,4,3]
  const int up_n = b.resize(avg, 8, 6, ResizeMode::kNearest);
  const int up_a = b.resize(avg, 8, 6, ResizeMode::kLinearAlignCorners);
  const int up_h = b.resize(avg, 8, 6, ResizeMode::kLinearHalfPixel);
  int z = b.concat({pooled, up_n, up_a, up_h});          // [1,24,8,6]
  const int gap = b.g.add(Op::kGlobalAveragePool, {z});  // [1,24,1,1]
  z = b.g.add(Op::kMul, {z, b.g.add(Op::kSigmoid, {gap})});
  Attrs s;
  s.starts = {2, 1};
  s.ends = {22, 7};
  s.axes = {1, 2};
  s.steps = {2, 1};
  z = b.g.add(Op::kSlice, {z}, s);  // [1,10,6,6]
  Attrs r;
  r.ints = {1, 10, 36};
  Attrs t;
  t.ints = {0, 2, 1};
  int tok = b.g.add(Op::kTranspose, {b.g.add(Op::kReshape, {z}, r)}, t);  // [1,36,10]
  tok = b.layer_norm(tok, 10);
  Attrs sm;
  sm.axis = -1;
  tok = b.g.add(Op::kSoftmax, {b.matmul_const(tok, 10, 10)}, sm);
  Attrs rm;
  rm.axes = {1};
  rm.keepdims = true;
  const int pooled_tok = b.g.add(Op::kReduceMean, {tok}, rm);  // [1,1,10]
  Attrs fl;
  fl.axis = 1;
  Attrs gm;
  gm.alpha = 1;
  gm.beta = 1;
  gm.trans_b = true;
  const int out = b.g.add(
      Op::kGemm,
      {b.g.add(Op::kFlatten, {pooled_tok}, fl), b.weight({5, 10}, 0.3f), b.weight({5}, 0.1f)}, gm);
  // The offset keeps the output away from ReLU's corner: without it some seeds cancel the Gemm's
  // ~0.1 terms to outputs of ~1e-3, whose relative error measures the cancellation, not the
  // engine (docs/validation-log.md).
  b.g.mark_output(b.g.add(Op::kRelu, {b.g.add(Op::kAdd, {out, b.scalar(0.5f)})}));
  b.g.values()[static_cast<size_t>(b.g.outputs()[0])].name = std::string("y");
  return std::move(b.g);
}

}  // namespace pensight::kernels
