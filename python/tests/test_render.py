"""beamtrace.render: `beamtrace render` in memory, the same pixels as the CLI's PNG."""

import struct
import subprocess
import zlib

import numpy as np
import pytest

import beamtrace


def read_png_rgb8(path):
    """The pixels of an 8-bit RGB, non-interlaced PNG as (h, w, 3) uint8 (all five filters)."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert (depth, colour, interlace) == (8, 2, 0), header
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(height, 1 + 3 * width)
    out = np.zeros((height, 3 * width), np.int64)
    for y in range(height):
        kind, row = raw[y, 0], raw[y, 1:].astype(np.int64)
        up = out[y - 1] if y > 0 else np.zeros(3 * width, np.int64)
        if kind in (0, 2):
            out[y] = (row + (up if kind == 2 else 0)) % 256
            continue
        for x in range(3 * width):  # Sub, Average, Paeth: left to right
            left = out[y, x - 3] if x >= 3 else 0
            corner = up[x - 3] if x >= 3 else 0
            if kind == 1:
                pred = left
            elif kind == 3:
                pred = (left + up[x]) // 2
            else:
                p = left + up[x] - corner
                pa, pb, pc = abs(p - left), abs(p - up[x]), abs(p - corner)
                pred = left if pa <= pb and pa <= pc else (up[x] if pb <= pc else corner)
            out[y, x] = (row[x] + pred) % 256
    return out.reshape(height, width, 3).astype(np.uint8)


def test_render_equals_the_cli_png(cli, tmp_path):
    subprocess.run([str(cli), "render", "--demo", "--size", "80x60", "--camera", "0,-40,15",
                    "--look-at", "0,0,2", "--quiet", "--output", str(tmp_path / "cli.png")],
                   check=True)
    expected = read_png_rgb8(tmp_path / "cli.png")
    image = beamtrace.render("demo", size=(80, 60), camera=(0, -40, 15), look_at="0,0,2")
    assert image.shape == (60, 80, 3) and image.dtype == np.uint8
    np.testing.assert_array_equal(image, expected)
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 10  # shaded, not flat


def test_render_scene_file_settings(cli, examples, tmp_path):
    scene = examples / "scenes" / "sphere_targets.yaml"
    subprocess.run([str(cli), "render", str(scene), "--size", "48x32", "--exposure", "1.5",
                    "--no-shadows", "--quiet", "--output", str(tmp_path / "spheres.png")],
                   check=True)
    image = beamtrace.render(scene, size=(48, 32), exposure=1.5, shadows=False, threads=1)
    np.testing.assert_array_equal(image, read_png_rgb8(tmp_path / "spheres.png"))
    assert not np.array_equal(image, beamtrace.render(scene, size=(48, 32)))


def test_render_errors(examples):
    with pytest.raises(beamtrace.ConfigError, match="look-at"):
        beamtrace.render("demo", look_at=(1, 2, 3))
    with pytest.raises(beamtrace.InputError, match="nothing.yaml"):
        beamtrace.render(examples / "nothing.yaml")
