#!/usr/bin/env python3
"""penumbra's Python example: renders one frame with a technique, saves it as EXR, then blurs the visibility (a numpy
array over the frame's memory) with the blur stage and writes the blurred floats to a raw file, rows bottom-up as the
C and C++ examples write the device buffer.

    render_frame.py SCENE WxH TECHNIQUE out.exr out.blur
"""
import sys

import numpy as np
import penumbra


def main(argv):
    if len(argv) != 6:
        print("usage: render_frame.py SCENE WxH TECHNIQUE out.exr out.blur", file=sys.stderr)
        return 2
    scene_spec, size, technique, exr_path, blur_path = argv[1:]
    width, height = (int(v) for v in size.split("x"))
    print("penumbra", penumbra.__version__)

    context = penumbra.Context()  # PENUMBRA_DEVICE, else the first GPU, else the first CPU
    scene = penumbra.Scene(scene_spec)
    camera = scene.default_camera()
    camera.width, camera.height = width, height
    renderer = penumbra.Renderer(context, scene)
    frame = renderer.render(technique, camera=camera)  # the scene's lights; the GIL is released meanwhile
    frame.save_exr(exr_path)
    print(f"{context.device_name}: {frame.width}x{frame.height}, {len(frame.light_layers)} light(s), "
          f"technique {technique}")

    visibility = frame["visibility.Y"]  # (height, width) float32, top row first, no copy
    blurred = penumbra.blur(context, np.flipud(visibility), filter="box", radius=2)
    blurred.astype(np.float32).tofile(blur_path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
