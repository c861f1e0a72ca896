#!/usr/bin/env node
// Writes the raw point records of a LAZ file as decoded by copc.js (laz-perf compiled to wasm),
// for the tests to compare with ours where laz-rs cannot open the file (COPC). No code of ours
// decodes anything here. Usage: node laz_records.mjs IN.laz OUT.bin (run from the folder where
// the npm packages are installed).
import fs from 'node:fs';
import { createRequire } from 'node:module';
const require = createRequire(import.meta.url);
const { Las } = require('copc');

const [inp, outp] = process.argv.slice(2);
const buf = new Uint8Array(fs.readFileSync(inp));
const records = await Las.PointData.decompressFile(buf);
fs.writeFileSync(outp, records);
