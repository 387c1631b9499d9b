#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz harnesses into corpus/HARNESS/ (committed; rerun after changing it).

gltf: Debian's assimp-testmodels glTF 2.0 files under 12 KB (valid and malformed), plus hostile inputs made here:
deep and wide JSON, node chains and cycles, overflowed counts, huge but finite coordinates, scale-0 nodes, GLB
headers that lie. scene_file: the bundled scenes/*.json and hostile variants. cli_values: one seed per parser (the
first byte picks it, fuzz_cli_values.cpp). Usage: make_corpus.py [ASSIMP_MODELS_DIR]
"""
import base64
import json
import os
import pathlib
import shutil
import struct
import sys

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
ASSIMP = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "/usr/share/assimp/models/glTF2")
MAX_SEED = 12000


def triangle(positions=(0, 0, 0, 1, 0, 0, 0, 1, 0), nodes=None, scene_nodes=(0,), accessor_extra=None):
    data = struct.pack("<9f", *positions)
    xyz = [positions[i::3] for i in range(3)]
    accessor = {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [min(c) for c in xyz], "max": [max(c) for c in xyz]}
    accessor.update(accessor_extra or {})
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(scene_nodes)}],
            "nodes": nodes if nodes is not None else [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," +
                         base64.b64encode(data).decode()}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}], "accessors": [accessor]}


def chain(depth):
    nodes = [{"mesh": 0}] + [{"children": [i + 1 if i < depth else 0]} for i in range(1, depth + 1)]
    return triangle(nodes=nodes, scene_nodes=(1,))


def glb(doc, extra=b""):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + extra
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def hostile_gltf():
    compact = lambda d: json.dumps(d, separators=(",", ":")).encode()
    yield "triangle.gltf", compact(triangle())
    yield "triangle.glb", glb(triangle())
    yield "deep-json.gltf", b"[" * 200 + b"]" * 200
    yield "wide-empty-objects.gltf", b'{"asset":{"version":"2.0"},"extras":[' + b",".join([b"{}"] * 2000) + b"]}"
    yield "chain-1000.gltf", compact(chain(1000))
    cycle = triangle(nodes=[{"mesh": 0, "children": [1]}, {"children": [0]}], scene_nodes=())
    yield "cycle.gltf", compact(cycle)
    yield "two-parents.gltf", compact(triangle(nodes=[{"mesh": 0}, {"children": [0]}, {"children": [0]}],
                                               scene_nodes=(1, 2)))
    yield "sparse-overflow.gltf", compact(triangle(accessor_extra={"sparse": {
        "count": 2147483648, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0}}}))
    yield "count-huge.gltf", compact(triangle(accessor_extra={"count": 18446744073709551615}))
    yield "positions-3e38.gltf", compact(triangle(positions=(0, 0, 0, 3e38, 0, 0, 0, 3e38, 0)))
    yield "scale-zero.gltf", compact(triangle(nodes=[{"mesh": 0, "scale": [0, 0, 0]}]))
    yield "scale-1e30.gltf", compact(triangle(nodes=[{"mesh": 0, "scale": [1e30, 1e30, 1e30]}]))
    yield "translation-1e300.gltf", compact(triangle(nodes=[{"mesh": 0, "translation": [1e300, 0, 0]}]))
    yield "duplicate-keys.gltf", b'{"asset":{"version":"2.0"},"asset":{"version":"1.0"}}'
    yield "glb-length-lies.glb", struct.pack("<4sII", b"glTF", 2, 0xFFFFFFF0) + struct.pack("<II", 8, 0x4E4F534A)
    yield "glb-chunk-lies.glb", glb(triangle())[:20] + struct.pack("<I", 0x7FFFFFFF)
    yield "bad-utf8.gltf", b'{"asset":{"version":"2.0","generator":"\xff\xfe"}}'
    yield "nul-uri.gltf", compact({**triangle(), "buffers": [{"byteLength": 36, "uri": "a\u0000b.bin"}]})
    yield "escape-uri.gltf", compact({**triangle(), "buffers": [{"byteLength": 36, "uri": "../../etc/passwd"}]})
    # issue 38's verdicts by the specification, and its messages
    tri = triangle()
    yield "nodes-not-array.gltf", compact({**tri, "nodes": "all"})
    yield "min-version-above.gltf", compact({**tri, "asset": {"version": "2.0", "minVersion": "2.1"}})
    yield "byte-stride-0.gltf", compact({**tri, "bufferViews": [{"buffer": 0, "byteLength": 36, "byteStride": 0}]})
    yield "data-uri-bad-base64.gltf", compact({**tri, "buffers": [
        {"byteLength": 36, "uri": "data:application/octet-stream;base64,AA@A"}]})
    yield "data-uri-text.gltf", compact({**tri, "buffers": [{"byteLength": 36, "uri": "data:text/plain;base64,AAAA"}]})
    yield "light-negative-intensity.gltf", compact({**tri, "extensions": {"KHR_lights_punctual": {
        "lights": [{"type": "point", "intensity": -1}]}}})
    yield "animation-bad-sampler.gltf", compact({**tri, "animations": [{
        "channels": [{"sampler": 3, "target": {"node": 0, "path": "translation"}}],
        "samplers": [{"input": 0, "output": 0}]}]})
    yield "dotdot-inside.gltf", compact({**tri, "buffers": [{"byteLength": 36, "uri": "sub/../a.bin"}]})
    js = json.dumps(tri, separators=(",", ":")).encode()
    yield "glb-json-bom.glb", glb(tri)[:20] + b"\xef\xbb\xbf" + glb(tri)[23:]
    yield "glb-json-nul-padding.glb", glb(tri)[:20 + len(js)] + b"\0" * (-len(js) % 4) + glb(tri)[20 + len(js) + (-len(js) % 4):]
    yield "glb-trailing-bytes.glb", glb(tri) + b"trailing"


def hostile_scene_files():
    yield "ground-minus-1e38.json", {"models": [{"path": "triangle.gltf"}], "ground": {"y": -1e38}}
    yield "eye-1e308.json", {"models": [{"path": "triangle.gltf"}], "camera": {"eye": [1e308, 0, 0],
                                                                             "target": [0, 0, 0]}}
    yield "scale-huge.json", {"models": [{"path": "triangle.gltf", "scale": 1e300}]}
    yield "size-too-big.json", {"models": [{"path": "triangle.gltf"}], "camera": {"eye": [0, 0, 5], "target": [0, 0, 0],
                                                                                 "size": [16384, 16384]}}
    yield "builtin.json", {"builtin": [{"name": "box"}], "lights": [{"type": "point", "position": [0, 5, 0]}]}
    yield "escape.json", {"models": [{"path": "../../../etc/passwd"}]}
    # issue 38: checked whole before any geometry, radii bounded, NULs shown
    yield "poles-8-million.json", {"procedural": [{"name": "poles", "rows": 1000, "columns": 1000}] * 8}
    yield "misspelled-after-poles.json", {"procedural": [{"name": "poles", "rows": 1000, "columns": 1000}],
                                          "lightz": []}
    yield "radius-1e300.json", {"models": [{"path": "triangle.gltf"}],
                                "lights": [{"type": "point", "position": [0, 5, 0], "radius": 1e300}]}
    yield "nul-path.json", {"models": [{"path": "tri\u0000angle.gltf"}]}


CLI_SEEDS = [
    (0, "0,2,5:0,0,0:45"), (0, "1e30,0,0:0,0,0"), (0, "nan,1,1:0,0,0"), (1, "8192x8192"), (1, "8193x1"),
    (1, "64x48"), (2, "spot:0,5,0:0,0,0:60:0.5"), (2, "dir:0.3,-1,-0.6:1"), (2, "point:0,3,0:0.2"),
    (3, "4GiB"), (3, "1.5g"), (3, "0x10"), (4, "2"), (4, "trilinear"), (4, "0.2,0.5"), (4, "-1e309"),
    (5, "box"), (5, "steps:count=4"), (5, "nope:x=1"),
    (2, "spot:0,5,0:0,0,0:60:1e30"), (2, "point:0,5,0:1e300"), (0, "0,1,0:0,1,1e-30"), (4, "nan"),
]


def main():
    out = HERE / "corpus"
    shutil.rmtree(out, ignore_errors=True)
    gltf, scene, cli = out / "gltf", out / "scene_file", out / "cli_values"
    for d in (gltf, scene, cli):
        d.mkdir(parents=True)
    for path in sorted(ASSIMP.rglob("*")):
        if path.suffix.lower() in (".gltf", ".glb") and path.stat().st_size <= MAX_SEED:
            name = "assimp-" + "-".join(path.relative_to(ASSIMP).parts).replace(" ", "_")
            shutil.copy(path, gltf / name)
    for name, data in hostile_gltf():
        (gltf / ("hostile-" + name)).write_bytes(data)
    for path in sorted((ROOT / "scenes").glob("*.json")):
        shutil.copy(path, scene / ("bundled-" + path.name))
    for name, doc in hostile_scene_files():
        (scene / ("hostile-" + name)).write_text(json.dumps(doc))
    for i, (which, text) in enumerate(CLI_SEEDS):
        (cli / f"seed-{i:02d}").write_bytes(bytes([which]) + text.encode())
    total = sum(f.stat().st_size for f in out.rglob("*") if f.is_file())
    print(f"corpus: {sum(1 for f in out.rglob('*') if f.is_file())} files, {total // 1024} KiB")


if __name__ == "__main__":
    main()
