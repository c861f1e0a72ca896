#!/usr/bin/env node
// Decodes every point of a LAS/LAZ file with two independent third-party readers, for the tests
// to compare with what beamtrace wrote. No code of ours decodes anything here
// (but the extra bytes' scale and offset, which copc.js reads big-endian):
//   * copc@0.0.8 (Las.Header, Las.Vlr, Las.ExtraBytes, Las.View; LAZ via laz-perf): the header,
//     the VLRs and every point dimension, extra bytes named by the Extra Bytes VLR;
//   * @loaders.gl/las@4.4.5 (laz-rs compiled to wasm): X, Y, Z, intensity, classification.
// Usage: node lasdump.mjs FILE OUT
// Writes OUT.json (header, VLRs with their bytes in hex, the dimension names), OUT.copc.f64
// (point-major float64: one row of the listed dimensions per point) and OUT.loadersgl.f64 (rows
// of X, Y, Z, intensity, classification). Runs from the folder where the npm packages are
// installed (the tests copy it next to shared/tools/lasval's read.mjs).
import fs from 'node:fs';
import { createRequire } from 'node:module';
const require = createRequire(import.meta.url);
const { Las } = require('copc');
const { parse } = await import('@loaders.gl/core');
const { LAZRsLoader } = await import('@loaders.gl/las');
{
  // laz-rs wasm would fetch() its .wasm; hand it the file instead.
  const dir = new URL('./node_modules/@loaders.gl/las/dist/libs/laz-rs-wasm/', import.meta.url);
  const lazrs = await import(new URL('laz_rs_wasm.js', dir).href);
  lazrs.initSync({ module: fs.readFileSync(new URL('laz_rs_wasm_bg.wasm', dir)) });
}

const [file, out] = process.argv.slice(2);
if (!file || !out) {
  console.error('usage: node lasdump.mjs FILE OUT');
  process.exit(64);
}
const buf = new Uint8Array(fs.readFileSync(file));
const hex = (b) => Buffer.from(b).toString('hex');

const header = Las.Header.parse(buf.subarray(0, 375));
const vlrs = await Las.Vlr.walk(async (b, e) => buf.subarray(b, e), header);
const compressed = (buf[104] & 0xc0) !== 0;
const points = compressed
  ? await Las.PointData.decompressFile(buf)
  : buf.subarray(header.pointDataOffset,
      header.pointDataOffset + header.pointCount * header.pointDataRecordLength);
// The Extra Bytes VLR (LASF_Spec / 4) names the extra dimensions. copc.js reads each
// descriptor's scale and offset big-endian (lib/las/extra-bytes.js: getFloat64(112) without the
// little-endian flag); LAS is little-endian, so they are read again here. A VLR copc.js cannot
// parse leaves the extra bytes undecoded, as before.
const extraBytes = (() => {
  const v = Las.Vlr.find(vlrs, 'LASF_Spec', 4);
  if (!v) return [];
  const b = buf.subarray(v.contentOffset, v.contentOffset + v.contentLength);
  try {
    const eb = Las.ExtraBytes.parse(b);
    const dv = new DataView(b.buffer, b.byteOffset, b.byteLength);
    eb.forEach((e, i) => {
      const options = b[192 * i + 3];
      if (options & 8) e.scale = dv.getFloat64(192 * i + 112, true);
      if (options & 16) e.offset = dv.getFloat64(192 * i + 136, true);
    });
    return eb;
  } catch {
    return [];
  }
})();
const view = Las.View.create(points, header, extraBytes);
const dims = Object.keys(view.dimensions);
const getters = dims.map((d) => view.getter(d));
const n = view.pointCount;
const rows = new Float64Array(n * dims.length);
for (let i = 0, k = 0; i < n; i++) {
  for (const g of getters) rows[k++] = g(i);
}
fs.writeFileSync(`${out}.copc.f64`, rows);

const ab = buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength);
const mesh = await parse(ab, LAZRsLoader,
  { worker: false, las: { fp64: true, colorDepth: 16, shape: 'mesh' } });
const P = mesh.attributes.POSITION.value;
const m = P.length / 3;
const lg = new Float64Array(m * 5);
for (let i = 0; i < m; i++) {
  lg[5 * i] = P[3 * i];
  lg[5 * i + 1] = P[3 * i + 1];
  lg[5 * i + 2] = P[3 * i + 2];
  lg[5 * i + 3] = mesh.attributes.intensity.value[i];
  lg[5 * i + 4] = mesh.attributes.classification.value[i];
}
fs.writeFileSync(`${out}.loadersgl.f64`, lg);

const facts = {
  version: [header.majorVersion, header.minorVersion],
  pointFormat: header.pointDataRecordFormat,
  recordLength: header.pointDataRecordLength,
  pointCount: Number(header.pointCount),
  pointCountByReturn: header.pointCountByReturn.map(Number),
  scale: header.scale, offset: header.offset, min: header.min, max: header.max,
  globalEncoding: header.globalEncoding,
  systemIdentifier: header.systemIdentifier, generatingSoftware: header.generatingSoftware,
  vlrs: vlrs.map((v) => ({
    userId: v.userId, recordId: v.recordId, description: v.description, extended: v.isExtended,
    data: hex(buf.subarray(v.contentOffset, v.contentOffset + v.contentLength)),
  })),
  dimensions: dims,
  copcPoints: n,
  loadersglPoints: m,
};
fs.writeFileSync(`${out}.json`, JSON.stringify(facts));
