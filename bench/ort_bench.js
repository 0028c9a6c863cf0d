// ONNX Runtime CPU timing of exported models (the peer of bench/nn_bench.cpp).
// usage: NODE_PATH=.cache/ort/node_modules node bench/ort_bench.js MODEL.onnx [runs]
// Export the models first: pensight export-onnx builtin:compact --out compact.onnx (and trudepth).
const ort = require('onnxruntime-node');
(async () => {
  const [model, runsArg] = process.argv.slice(2);
  const runs = Number(runsArg || 20);
  const s = await ort.InferenceSession.create(model, {executionProviders: ['cpu']});
  const feeds = {};
  for (const name of s.inputNames) {
    const shape = name === 'prior' ? [1, 2, 240, 320] : (model.includes('compact') ? [1, 1, 240, 320] : [1, 3, 240, 320]);
    const n = shape.reduce((a, b) => a * b, 1);
    feeds[name] = new ort.Tensor('float32', Float32Array.from({length: n}, () => Math.random()), shape);
  }
  await s.run(feeds);
  const t0 = process.hrtime.bigint();
  for (let i = 0; i < runs; ++i) await s.run(feeds);
  const ms = Number(process.hrtime.bigint() - t0) / 1e6 / runs;
  console.log(`${model}: ONNX Runtime CPU ${ms.toFixed(2)} ms/inference`);
})().catch((e) => { console.error(e); process.exit(1); });
