// ONNX Runtime CPU timing of exported models (the peer of bench/nn_bench.cpp).
// usage: NODE_PATH=.cache/ort/node_modules node bench/ort_bench.js MODEL.onnx RUNS NAME=DxDxDxD...
// e.g. pensight export-onnx builtin:trudepth --out td.onnx
//      node bench/ort_bench.js td.onnx 20 image=1x3x240x320 prior=1x2x240x320
const ort = require('onnxruntime-node');
(async () => {
  const [model, runsArg, ...shapes] = process.argv.slice(2);
  const runs = Number(runsArg || 20);
  const session = await ort.InferenceSession.create(model, {executionProviders: ['cpu']});
  const feeds = {};
  for (const s of shapes) {
    const [name, dims] = s.split('=');
    const shape = dims.split('x').map(Number);
    const n = shape.reduce((a, b) => a * b, 1);
    feeds[name] = new ort.Tensor('float32', Float32Array.from({length: n}, () => Math.random()), shape);
  }
  await session.run(feeds);  // warm-up
  const t0 = process.hrtime.bigint();
  for (let i = 0; i < runs; ++i) await session.run(feeds);
  const ms = Number(process.hrtime.bigint() - t0) / 1e6 / runs;
  console.log(`${model}: ONNX Runtime CPU ${ms.toFixed(2)} ms/inference`);
})().catch((e) => { console.error(e); process.exit(1); });
