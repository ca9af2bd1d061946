#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora into fuzz/corpus/ (committed; run again
after a format change). Spec and OBJ seeds are copies and small hand-written
cases; the samples and asset seeds come from loom-lab on a tiny fabric; the upload
seeds are protobuf messages encoded by hand (no Python protobuf needed). Seeds
named regression_* are inputs long runs found; they are kept.

  python3 fuzz/make_seeds.py [BUILD_DIR]     (default build; needs build/lab/loom-lab)
"""
import hashlib
import json
import pathlib
import struct
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
CORPUS = ROOT / "fuzz" / "corpus"
LAB = ROOT / (sys.argv[1] if len(sys.argv) > 1 else "build") / "lab" / "loom-lab"


def write(target, name, data):
    path = CORPUS / target / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data if isinstance(data, bytes) else data.encode())


def specs():
    for kind, directories in {
        "fabric_spec_fuzzer": ["examples/fabrics", "bench/scenes/fabrics"],
        "precompute_spec_fuzzer": ["examples/precompute"],
        "scene_spec_fuzzer": ["examples/scenes"],
    }.items():
        for directory in directories:
            for path in sorted((ROOT / directory).glob("*.json")):
                write(kind, path.name, path.read_bytes())
    write("fabric_spec_fuzzer", "basket.json", '{"woven": {"pattern": "WEAVE_PATTERN_BASKET", "n": 2}}')
    write("fabric_spec_fuzzer", "both.json", '{"knit": {}, "woven": {}}')
    write("precompute_spec_fuzzer", "tiny.json",
          '{"spatial_resolution": 2, "view_directions": 4, "light_directions": 4, "lobes": 1, '
          '"lookup_table": false, "indirect_bounces": 0, "supersampling": 1, "mip_levels": "MIP_LEVELS_NONE"}')
    write("scene_spec_fuzzer", "builtins.json", json.dumps({
        "objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE", "segments": 8},
                     "fabric": {"fabric": {"woven": {}}, "repeat": 4}},
                    {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "colour": {"r": 0.5, "g": 0.5, "b": 0.5}}],
        "camera": {"position": {"x": 0, "y": -3, "z": 1}},
        "lights": [{"directional": {"direction": {"x": 0, "y": 1, "z": -1}}}],
        "render": {"method": "RENDER_METHOD_REFERENCE", "width": 32, "height": 24}}))


def objs():
    # The first byte is the piece size the parser is fed in (1 + byte % 64).
    cases = {
        "quad.obj": "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                    "f 1/1/1 2/2/1 3/3/1 4/4/1\n",
        "relative.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf -3/-1 -2/-1 -1/-1\n",
        "hexagon.obj": "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 2 0\nv -1 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1 5/1 6/1\n",
        "variants.obj": "mtllib a.mtl\r\no cloth\r\nv 0 0 0 1 0 0\r\nv +1 0 0 1.0\r\nv 0 1 0 # c\r\nvt 0.5\r\n"
                        "g g1\r\ns off\r\nusemtl m\r\nl 1 2\r\nf 1/1 2/1 3/1",
        "plain.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1//1 2//1 3//1\n",
        "crash.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 100000000/3\n",
    }
    for i, (name, text) in enumerate(cases.items()):
        write("obj_fuzzer", name, bytes([i * 7]) + text.encode())
    grid = ["v %d %d 0" % (x, y) for y in range(5) for x in range(5)]
    grid += ["vt %g %g" % (x / 4, y / 4) for y in range(5) for x in range(5)]
    grid += ["f %d/%d %d/%d %d/%d %d/%d" % (a, a, a + 1, a + 1, a + 6, a + 6, a + 5, a + 5)
             for a in (y * 5 + x + 1 for y in range(4) for x in range(4))]
    write("obj_fuzzer", "grid.obj", bytes([63]) + ("\n".join(grid) + "\n").encode())


def lab_seeds():
    with tempfile.TemporaryDirectory() as work:
        work = pathlib.Path(work)
        (work / "fabric.json").write_text('{"knit": {}}')
        (work / "settings.json").write_text(json.dumps({
            "spatial_resolution": 2, "view_directions": 4, "light_directions": 4, "lobes": 1,
            "indirect_bounces": 0, "supersampling": 1}))
        subprocess.run([LAB, "acquire", work / "fabric.json", "--settings", work / "settings.json",
                        "-o", work / "tiny.samples"], check=True, capture_output=True)
        samples = (work / "tiny.samples").read_bytes()
        write("samples_fuzzer", "tiny_fixed_checksum", b"\0" + samples[:-64])
        write("samples_fuzzer", "tiny_as_is", b"\1" + samples)
        # One asset of each method, its files in the order asset_fuzzer.cpp unpacks them.
        settings = json.loads((work / "settings.json").read_text())
        for method, files in ASSET_FILES.items():
            own = {"method": f"FABRIC_METHOD_{method.upper()}", **METHOD_SETTINGS.get(method, {})}
            (work / f"{method}.json").write_text(json.dumps({**settings, **own}))
            subprocess.run([LAB, "precompute", work / "fabric.json", "--settings", work / f"{method}.json",
                            "-o", work / method], check=True, capture_output=True)
            manifest = (work / method / "manifest.json").read_bytes()
            images = [(work / method / name).read_bytes() for name in files]
            packed = struct.pack("<H", len(manifest)) + manifest
            packed += b"".join(struct.pack("<I", len(image)) + image for image in images[:-1]) + images[-1]
            prefix = "tiny" if method == "svbrdf" else f"tiny_{method}"
            write("asset_fuzzer", f"{prefix}_fixed_checksums", b"\0" + packed)
            write("asset_fuzzer", f"{prefix}_as_is", b"\1" + packed)


# Each method's images, as fuzz/asset_fuzzer.cpp unpacks them.
ASSET_FILES = {
    "svbrdf": ["parameters.exr", "lut.exr"],
    "tabulated": ["table.exr", "views.exr"],
    "factored": ["view_terms.exr", "light_terms.exr", "views.exr"],
    "neural": ["latents.exr", "views.exr"],
}
# The smallest decoder keeps the neural manifest (its parameters) short.
METHOD_SETTINGS = {"neural": {"neural": {"channels": 4, "hidden": 4, "steps": 10}}}


def varint(n):
    out = b""
    while True:
        byte = n & 0x7F
        n >>= 7
        out += bytes([byte | (0x80 if n else 0)])
        if not n:
            return out


def field(number, payload):
    return varint(number << 3 | 2) + varint(len(payload)) + payload


def uploads():
    def header(data, name="mesh.obj", job_id=b"", token=0):
        artifact = field(1, hashlib.sha256(data).hexdigest().encode()) + varint(2 << 3) + varint(len(data))
        artifact += field(3, name.encode())
        body = field(1, artifact) + (field(2, job_id) if job_id else b"")
        if token:
            body += varint(3 << 3) + varint(token)
        return field(1, body)

    def stream(flags, messages):
        return bytes([flags]) + b"".join(struct.pack("<H", len(m)) + m for m in messages)

    data = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"
    write("upload_fuzzer", "whole", stream(0, [header(data), field(2, data)]))
    write("upload_fuzzer", "two_chunks", stream(0, [header(data), field(2, data[:10]), field(2, data[10:])]))
    write("upload_fuzzer", "fixed_header", stream(1, [header(b"x"), field(2, data)]))
    write("upload_fuzzer", "refused", stream(2, [header(data, job_id=b"job-1", token=7), field(2, data)]))
    write("upload_fuzzer", "second_header", stream(0, [header(data), header(data), field(2, data)]))
    write("upload_fuzzer", "no_header", stream(0, [field(2, data)]))


if __name__ == "__main__":
    # regression_* seeds are inputs a long run found (each fixed since): they stay.
    for seed in CORPUS.glob("*/*"):
        if not seed.name.startswith("regression_"):
            seed.unlink()
    specs()
    objs()
    lab_seeds()
    uploads()
    for target in sorted(CORPUS.iterdir()):
        print(target.name, len(list(target.iterdir())), "seeds")
