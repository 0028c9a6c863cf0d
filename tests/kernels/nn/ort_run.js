// Runs an ONNX model with ONNX Runtime (Node.js binding) on raw float32 inputs.
// usage: node ort_run.js MODEL OUT_DIR NAME=FILE...   writes OUT_DIR/<output index>.bin
const fs = require('fs');
const ort = require('onnxruntime-node');
(async () => {
  const [model, outDir, ...pairs] = process.argv.slice(2);
  const session = await ort.InferenceSession.create(model, {executionProviders: ['cpu']});
  const feeds = {};
  for (const p of pairs) {
    const [name, file, dims] = p.split('=');
    const buf = fs.readFileSync(file);
    const data = new Float32Array(buf.buffer, buf.byteOffset, buf.byteLength / 4);
    feeds[name] = new ort.Tensor('float32', Float32Array.from(data), dims.split('x').map(Number));
  }
  const results = await session.run(feeds);
  session.outputNames.forEach((name, i) => {
    const t = results[name];
    fs.writeFileSync(`${outDir}/${i}.bin`, Buffer.from(t.data.buffer, t.data.byteOffset, t.data.byteLength));
  });
})().catch((e) => { console.error(e); process.exit(1); });
