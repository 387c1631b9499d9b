#!/usr/bin/env python3
"""Loader verdicts against the Khronos glTF validator on the glTF corpus: prints a Markdown table of the files where
they disagree (penumbra refuses what the validator passes, or loads what it reports errors in), with both messages.

Usage: compare_validator.py REPLAY_BINARY [FOLDER] (default: the committed corpus; e.g. Debian's
/usr/share/assimp/models/glTF2 to load each file beside its buffers). Needs node and the npm package gltf-validator where node
finds it (NODE_PATH, or `npm install gltf-validator` in this folder or a parent)."""
import json
import os
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent


def penumbra_verdicts(replay, files):
    env = dict(os.environ, PENUMBRA_FUZZ_VERDICTS="1", PENUMBRA_FUZZ_IN_PLACE="1")
    out = subprocess.run([replay, *map(str, files)], env=env, capture_output=True, check=True).stdout
    out = out.decode("utf-8", errors="replace")  # messages quote the file's bytes
    verdicts, current = {}, None
    for line in out.splitlines():
        if line.startswith("input: "):
            current = line[len("input: "):]
        elif line.startswith("verdict: ") and current:
            verdicts[current] = line[len("verdict: "):]
    return verdicts


def validator_verdicts(files):
    out = subprocess.run(["node", str(HERE / "validate.js"), *map(str, files)], capture_output=True, text=True,
                         check=True).stdout
    return {r["file"]: r for r in map(json.loads, out.splitlines())}


def main():
    replay = sys.argv[1]
    corpus = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else HERE / "corpus" / "gltf")
    files = sorted(p for p in corpus.rglob("*") if p.is_file() and p.suffix.lower() in (".gltf", ".glb", ""))
    ours, theirs = penumbra_verdicts(replay, files), validator_verdicts(files)
    rows, agree = [], 0
    for f in map(str, files):
        refused = ours.get(f, "?").startswith("refused")
        invalid = theirs[f]["errors"] != 0
        if refused == invalid:
            agree += 1
            continue
        rows.append(f"| {pathlib.Path(f).name} | {ours.get(f, '?')[:140]} | "
                    f"{theirs[f]['errors']} errors; {theirs[f]['first'][:140]} |")
    print(f"{len(files)} files, {agree} agree, {len(rows)} differ\n")
    print("| file | penumbra | glTF validator |\n|---|---|---|")
    print("\n".join(r.replace("\n", " ") for r in rows))


if __name__ == "__main__":
    main()
