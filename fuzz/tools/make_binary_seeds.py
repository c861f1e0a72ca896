#!/usr/bin/env python3
"""Writes the binary seeds of fuzz/corpus/ (PLY, STL, glTF/GLB, GeoTIFF) from scratch, so that the
corpus holds only files we made. usage: make_binary_seeds.py [CORPUS_DIR]  (default: fuzz/corpus)"""
import base64
import json
import struct
import sys
from pathlib import Path

TRIANGLE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 1.0, 0.5)]


def ply(endian):
    fmt = "binary_little_endian" if endian == "<" else "binary_big_endian"
    head = (f"ply\nformat {fmt} 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
            "property double z\nproperty short extra\nelement face 2\n"
            "property list uchar uint vertex_indices\nend_header\n").encode()
    body = b"".join(struct.pack(endian + "dddh", *v, 7) for v in TRIANGLE)
    body += struct.pack(endian + "BIII", 3, 0, 1, 2) + struct.pack(endian + "BIIII", 4, 0, 1, 3, 2)
    return head + body


def stl_binary():
    facets = [((0, 0, 1), TRIANGLE[0], TRIANGLE[1], TRIANGLE[2]),
              ((0, 0, 1), TRIANGLE[1], TRIANGLE[3], TRIANGLE[2])]
    out = b"binary seed".ljust(80, b"\0") + struct.pack("<I", len(facets))
    for facet in facets:
        out += b"".join(struct.pack("<3f", *v) for v in facet) + struct.pack("<H", 0)
    return out


def gltf_parts():
    """The JSON and buffer of two nodes sharing an indexed quad mesh (one with a TRS transform)."""
    positions = b"".join(struct.pack("<3f", *v) for v in TRIANGLE)
    indices = struct.pack("<6H", 0, 1, 2, 1, 3, 2) + b"\0\0"
    buffer = positions + indices
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"children": [1], "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1]},
                  {"mesh": 0, "translation": [0, 2, 0], "rotation": [0, 0, 0.7071068, 0.7071068],
                   "scale": [2, 2, 2]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0.5]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "buffers": [{"byteLength": len(buffer)}],
    }
    return doc, buffer


def gltf_data_uri():
    doc, buffer = gltf_parts()
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(buffer).decode()
    return json.dumps(doc).encode()


def glb():
    doc, buffer = gltf_parts()
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    chunks += struct.pack("<II", len(buffer), 0x004E4942) + buffer
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def tiff(width, height, fmt, sample_format, values, georef):
    """A little-endian strip TIFF, one row per strip, with GeoTIFF tags when georef is set."""
    bits = struct.calcsize(fmt) * 8
    rows = [struct.pack("<%d%s" % (width, fmt), *values[r * width:(r + 1) * width]) for r in range(height)]
    entries, extra = [], b""  # (tag, type, count, payload bytes)
    def add(tag, typ, count, payload):
        entries.append((tag, typ, count, payload))
    add(256, 3, 1, struct.pack("<H", width))
    add(257, 3, 1, struct.pack("<H", height))
    add(258, 3, 1, struct.pack("<H", bits))
    add(259, 3, 1, struct.pack("<H", 1))
    add(262, 3, 1, struct.pack("<H", 1))
    add(273, 4, height, None)  # strip offsets: filled below
    add(277, 3, 1, struct.pack("<H", 1))
    add(278, 3, 1, struct.pack("<H", 1))
    add(279, 4, height, struct.pack("<%dI" % height, *[len(r) for r in rows]))
    add(339, 3, 1, struct.pack("<H", sample_format))
    if georef:
        add(33550, 12, 3, struct.pack("<3d", 30.0, 30.0, 0.0))
        add(33922, 12, 6, struct.pack("<6d", 0, 0, 0, 478000.0, 5474000.0, 0))
        add(42113, 2, 6, b"-9999\0")
    entries.sort()
    ifd_size = 2 + 12 * len(entries) + 4
    data_start = 8 + ifd_size
    # Layout after the IFD: out-of-line payloads, then the strips.
    out_of_line = sum(len(p) if p is not None else 4 * height for _, _, _, p in entries
                      if (p is None and 4 * height > 4) or (p is not None and len(p) > 4))
    strip_start = data_start + out_of_line
    offsets, at = [], strip_start
    for r in rows:
        offsets.append(at)
        at += len(r)
    ifd, blob = struct.pack("<H", len(entries)), b""
    for tag, typ, count, payload in entries:
        if payload is None:
            payload = struct.pack("<%dI" % height, *offsets)
        if len(payload) <= 4:
            ifd += struct.pack("<HHI", tag, typ, count) + payload.ljust(4, b"\0")
        else:
            ifd += struct.pack("<HHII", tag, typ, count, data_start + len(blob))
            blob += payload
    ifd += struct.pack("<I", 0)
    return b"II*\0" + struct.pack("<I", 8) + ifd + blob + b"".join(rows)


def main():
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent / "corpus"
    files = {
        "ply/quad_le.ply": ply("<"), "ply/quad_be.ply": ply(">"),
        "stl/quad_binary.stl": stl_binary(),
        "gltf/quad_data_uri.gltf": gltf_data_uri(), "gltf/quad.glb": glb(),
        "geotiff/float32_georef.tif": tiff(4, 3, "f", 3, [float(i) for i in range(11)] + [-9999.0], True),
        "geotiff/uint16_plain.tif": tiff(3, 2, "H", 1, [10, 20, 30, 40, 50, 60], False),
        "geotiff/int16_georef.tif": tiff(2, 2, "h", 2, [-5, 0, 5, 1000], True),
    }
    for name, data in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_bytes(data)
        print(f"{root / name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
