#!/usr/bin/env python3
"""Checks that no include runs back up a layer. Each source folder has a rank; a file may include its own folder
and folders of lower rank, never a sibling or a higher one (tests/ and examples/ are not checked). Usage:
check_layers.py ROOT. Exit 1 listing each offending include."""
import os
import re
import sys

# Lowest first. The rasterizer sits on the runtime alone (it takes plain arrays, raster/geometry.h), beside the scene
# and the I/O it may not include; the filtering stages on the runtime and the scene; the views on the rasterizer
# and the scene (host/views/raster_scene.h is where they meet); techniques compose views and stages; the Renderer
# and the metrics use techniques; the public API, the Python module and the tools sit on top, the selftest's checks and
# references (tools/selftest/) below the other tools, which may use them (sat_precision, the benchmarks).
RANKS = {
    'kernels': 0,
    'host/cl': 1, 'host': 1,
    'host/io': 2, 'host/scene': 2, 'raster': 2,
    'host/stages': 3,
    'host/views': 4,
    'host/techniques': 5,
    'host/pipeline': 6, 'host/eval': 6,
    'include/penumbra': 7,
    'tools/selftest': 7.5,
    'api': 8, 'python': 8, 'tools/reference': 8, 'tools/bench': 8, 'tools/eval': 8, 'tools/cli': 9,
}
SOURCES = ('.h', '.hpp', '.cpp', '.c', '.cl', '.h.in')
INCLUDE = re.compile(r'^\s*#\s*include\s+["<]([^">]+)[">]')


def layer_of(path):
    """The deepest RANKS key that is a folder prefix of path (a repository-relative path with '/')."""
    parts = path.split('/')
    for n in range(len(parts) - 1, 0, -1):
        key = '/'.join(parts[:n])
        if key in RANKS:
            return key
    return None


def included_layer(name):
    if name.startswith('penumbra/'):
        return 'include/penumbra'
    return layer_of(name)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else '.')
    problems = []
    checked = 0
    for top in ('kernels', 'host', 'raster', 'include', 'api', 'python', 'tools'):
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith(SOURCES):
                    continue
                rel = os.path.relpath(os.path.join(folder, name), root).replace(os.sep, '/')
                own = layer_of(rel)
                if own is None:
                    continue
                checked += 1
                with open(os.path.join(folder, name), encoding='utf-8', errors='replace') as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        other = included_layer(m.group(1)) if m else None
                        if other and other != own and RANKS[other] >= RANKS[own]:
                            problems.append(f'{rel}:{number}: {own} (rank {RANKS[own]}) includes {m.group(1)} '
                                            f'({other}, rank {RANKS[other]})')
    for p in problems:
        print(p)
    print(f'check_layers: {checked} files, {len(problems)} include(s) running up a layer')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
