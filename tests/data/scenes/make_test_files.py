#!/usr/bin/env python3
"""Writes the small glTF test files in this folder (stdlib only, deterministic).

Run from this folder: python3 make_test_files.py. Valid files sit here; malformed/ holds files each
broken in one way, named for the way (see tests/scene_gltf_malformed_test.cpp for the expected errors).
"""
import base64, copy, json, math, struct

POS = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
NRM = [(0, 0, 1)] * 3
IDX = [0, 1, 2]


def triangle_bin():
    data = b"".join(struct.pack("<3f", *p) for p in POS) + b"".join(struct.pack("<3f", *n) for n in NRM)
    return data + struct.pack("<3H", *IDX) + b"\0\0"  # 80 bytes


def base_doc(uri):
    return {
        "asset": {"version": "2.0", "generator": "penumbra make_test_files.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "tri", "mesh": 0}],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [{"uri": uri, "byteLength": 80}] if uri is not None else [{"byteLength": 80}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "byteStride": 12},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
    }


def data_uri(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


def write_json(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def glb(doc, bin_data):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    out = struct.pack("<II", len(js), 0x4E4F534A) + js
    if bin_data is not None:
        out += struct.pack("<II", len(bin_data), 0x004E4942) + bin_data
    return struct.pack("<4sII", b"glTF", 2, 12 + len(out)) + out


def transforms_doc():
    doc = base_doc(data_uri(triangle_bin()))
    s = math.sqrt(0.5)
    doc["nodes"] = [
        {"name": "translated", "mesh": 0, "translation": [10, 0, 0]},
        {"name": "rotated", "mesh": 0, "rotation": [0, s, 0, s]},  # +90 degrees about +Y
        {"name": "mirrored", "mesh": 0, "scale": [-1, 1, 1]},
        {"name": "parent", "children": [4],
         "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1]},  # column-major translation (0, 5, 0)
        {"name": "child", "mesh": 0, "translation": [0, 0, 2]},
    ]
    doc["scenes"] = [{"nodes": [0, 1, 2, 3]}]
    return doc


def valid_files():
    with open("triangle.bin", "wb") as f:
        f.write(triangle_bin())
    write_json("triangle.gltf", base_doc("triangle.bin"))
    write_json("sub/inner.gltf", base_doc("../triangle.bin"))  # ".." is refused even when it stays inside
    write_json("transforms.gltf", transforms_doc())
    with open("triangle.glb", "wb") as f:
        f.write(glb(base_doc(None), triangle_bin()))
    doc = base_doc(data_uri(triangle_bin()))  # no NORMAL: flat normals
    del doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]
    write_json("no_normals.gltf", doc)
    # Sparse: vertex 2 moved from (0, 1, 0) to (0, 3, 0) through a sparse substitution.
    data = triangle_bin() + struct.pack("<I", 2) + struct.pack("<3f", 0, 3, 0)
    doc = base_doc(data_uri(data))
    doc["buffers"][0]["byteLength"] = len(data)
    doc["bufferViews"] += [{"buffer": 0, "byteOffset": 80, "byteLength": 4},
                           {"buffer": 0, "byteOffset": 84, "byteLength": 12}]
    doc["accessors"][0]["sparse"] = {"count": 1, "indices": {"bufferView": 2, "componentType": 5125},
                                     "values": {"bufferView": 3}}
    write_json("sparse.gltf", doc)
    doc = base_doc(data_uri(triangle_bin()))  # no scenes: every root node is drawn
    del doc["scene"], doc["scenes"]
    doc["nodes"].append({"name": "second", "mesh": 0, "translation": [0, 0, -1]})
    write_json("no_scene.gltf", doc)


def malformed(name, edit, uri="triangle.bin"):
    doc = base_doc(uri)
    edit(doc)
    write_json("malformed/" + name, doc)


def malformed_files():
    with open("malformed/triangle.bin", "wb") as f:
        f.write(triangle_bin())
    malformed("traversal.gltf", lambda d: None, uri="../triangle.bin")
    malformed("traversal_encoded.gltf", lambda d: None, uri="%2e%2e/triangle.bin")
    malformed("absolute_uri.gltf", lambda d: None, uri="/etc/passwd")
    malformed("file_uri.gltf", lambda d: None, uri="file:///etc/passwd")
    malformed("missing_bin.gltf", lambda d: None, uri="nowhere.bin")
    malformed("count_overflow.gltf", lambda d: d["accessors"][0].update(count=2**64 - 1))
    malformed("index_out_of_range.gltf", lambda d: d["accessors"][2].update(count=3, byteOffset=8)
              or d["bufferViews"][1].update(byteOffset=36, byteLength=36))  # indices read from float bytes
    def cycle(d):
        d["nodes"] += [{"name": "a", "children": [2]}, {"name": "b", "children": [3]}, {"name": "c", "children": [1]}]
    malformed("node_cycle.gltf", cycle)
    def two_parents(d):
        d["nodes"] = [{"children": [2]}, {"children": [2]}, {"mesh": 0}]
        d["scenes"] = [{"nodes": [0, 1]}]
    malformed("two_parents.gltf", two_parents)
    malformed("draco_required.gltf", lambda d: d.update(extensionsUsed=["KHR_draco_mesh_compression"],
                                                        extensionsRequired=["KHR_draco_mesh_compression"]))
    malformed("meshopt_required.gltf", lambda d: d.update(extensionsUsed=["EXT_meshopt_compression"],
                                                          extensionsRequired=["EXT_meshopt_compression"]))
    malformed("non_affine_matrix.gltf", lambda d: d["nodes"][0].update(
        matrix=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0]))
    malformed("matrix_length.gltf", lambda d: d["nodes"][0].update(matrix=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]))
    def world_overflow(d):
        d["nodes"] = [{"scale": [1e200, 1e200, 1e200], "children": [1]}, {"scale": [1e200, 1, 1], "mesh": 0}]
    malformed("world_overflow.gltf", world_overflow)
    malformed("missing_position.gltf", lambda d: d["meshes"][0]["primitives"][0].update(attributes={"NORMAL": 1}))
    malformed("position_type.gltf", lambda d: d["accessors"][0].update(componentType=5123))
    malformed("index_type.gltf", lambda d: d["accessors"][2].update(componentType=5126))
    malformed("view_past_buffer.gltf", lambda d: d["bufferViews"][1].update(byteLength=600))
    malformed("accessor_past_view.gltf", lambda d: d["accessors"][0].update(count=7))
    malformed("stride_too_small.gltf", lambda d: d["bufferViews"][0].update(byteStride=8))
    malformed("bad_mode.gltf", lambda d: d["meshes"][0]["primitives"][0].update(mode=9))
    malformed("bad_scene.gltf", lambda d: d.update(scene=3))
    malformed("normal_count.gltf", lambda d: d["accessors"][1].update(count=2))
    with open("malformed/nan_matrix.gltf", "w") as f:  # JSON has no NaN: the closest a file can get
        f.write(json.dumps(base_doc("triangle.bin")).replace('"mesh": 0}', '"mesh": 0, "matrix": '
                '[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e999, 0, 0, 1]}', 1))
    with open("malformed/nan_token.gltf", "w") as f:
        f.write(json.dumps(base_doc("triangle.bin")).replace('"mesh": 0}', '"mesh": 0, "translation": [NaN, 0, 0]}', 1))
    good = glb(base_doc(None), triangle_bin())
    files = {
        "truncated.glb": good[: len(good) // 2],
        "header_only.glb": good[:12],
        "bad_json_chunk_length.glb": good[:12] + struct.pack("<I", 0x7FFFFFF0) + good[16:],
        "bad_bin_chunk_length.glb": good[:-88] + struct.pack("<I", 0x7FFFFFF0) + good[-84:],
        "bin_not_aligned.glb": glb(base_doc(None), triangle_bin()[:78]),
        "wrong_version.glb": good[:4] + struct.pack("<I", 1) + good[8:],
        "length_mismatch.glb": good + b"\0\0\0\0",
        "no_bin_chunk.glb": glb(base_doc(None), None),
    }
    for name, data in files.items():
        with open("malformed/" + name, "wb") as f:
            f.write(data)


if __name__ == "__main__":
    valid_files()
    malformed_files()
