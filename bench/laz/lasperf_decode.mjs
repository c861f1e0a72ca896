#!/usr/bin/env node
// laz-perf's decode rate (points/s, one thread: laz-perf compiled to wasm, through copc.js) on
// LAZ files, the referee of bench/laz_decode.sh. Best of several runs of decoding every record
// of the file held in memory (file reading not timed). No code of ours runs here.
// Usage (from a folder with the lasval npm packages): node lasperf_decode.mjs FILE... ; prints
// one line per file: <file> <points> <points per second>.
import fs from 'node:fs';
import { createRequire } from 'node:module';
const require = createRequire(import.meta.url);
const { Las } = require('copc');

for (const file of process.argv.slice(2)) {
  const buf = new Uint8Array(fs.readFileSync(file));
  const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  const minor = buf[25];
  let count = dv.getUint32(107, true);
  if (minor >= 4) count = Number(dv.getBigUint64(247, true)) || count;
  let best = Infinity;
  const start = performance.now();
  for (let run = 0; run < 20 && (run < 3 || performance.now() - start < 3000); ++run) {
    const t0 = performance.now();
    const records = await Las.PointData.decompressFile(buf);
    const t = (performance.now() - t0) / 1000;
    if (records.length === 0) throw new Error(`${file}: nothing decoded`);
    best = Math.min(best, t);
  }
  console.log(`${file} ${count} ${(count / best).toFixed(0)}`);
}
