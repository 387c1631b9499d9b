"""The installed Python module (ctest api-python, after api-install): frames bit for bit equal to the installed
CLI's, channels as read-only numpy views that keep their frame alive, the GIL released while rendering, penumbra's
errors as Python exceptions with the library's messages, the stages on numpy arrays against numpy references,
pyopencl's contexts, queues and arrays used in place, and a Shader on the caller's own map and a frame's G-buffer."""
import os
import shutil
import subprocess
import threading
import time
import unittest

import numpy as np
import penumbra

CLI = os.environ["PENUMBRA_TEST_CLI"]
EXR_EQUAL = os.environ["PENUMBRA_TEST_EXR_EQUAL"]
SCRATCH = os.environ["PENUMBRA_TEST_SCRATCH"]


def box_blur_reference(image, radius):
    """Clamp-to-edge box filter along rows, then columns, in double precision."""
    out = image.astype(np.float64)
    for axis in (1, 0):
        padded = np.concatenate([np.repeat(np.take(out, [0], axis), radius, axis), out,
                                 np.repeat(np.take(out, [-1], axis), radius, axis)], axis)
        out = sum(np.take(padded, range(k, k + out.shape[axis]), axis) for k in range(2 * radius + 1))
        out /= 2 * radius + 1
    return out


class Module(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        os.makedirs(SCRATCH, exist_ok=True)
        cls.context = penumbra.Context()
        cls.scene = penumbra.Scene("builtin:box")
        cls.renderer = penumbra.Renderer(cls.context, cls.scene)

    def camera(self, width, height):
        camera = self.scene.default_camera()
        camera.width, camera.height = width, height
        return camera

    def test_version_is_the_clis(self):
        cli = subprocess.run([CLI, "--version"], check=True, capture_output=True, text=True).stdout.strip()
        self.assertEqual(cli, "penumbra " + penumbra.__version__)

    def test_frame_equals_the_clis_bit_for_bit(self):
        frame = self.renderer.render("pcss", {"pcss-filter-taps": 6}, camera=self.camera(64, 48))
        ours, theirs = os.path.join(SCRATCH, "python-pcss.exr"), os.path.join(SCRATCH, "cli-pcss.exr")
        frame.save_exr(ours)
        subprocess.run([CLI, "render", "builtin:box", "--size", "64x48", "-t", "pcss", "--pcss-filter-taps", "6",
                        "-o", theirs, "--png", "none", "-q"], check=True)
        subprocess.run([EXR_EQUAL, theirs, ours, "visibility.Y", "R", "depth.Z"], check=True)
        self.assertEqual(frame.attribute("penumbra:technique"), "pcss")
        self.assertEqual(frame.attribute("penumbra:version"), penumbra.__version__)

    def test_channels_on_request_equal_the_downloaded_ones(self):
        frame = self.renderer.render("pcf", camera=self.camera(40, 30))
        later = self.renderer.render("pcf", camera=self.camera(40, 30), channels="on_request")
        for name in ("visibility.Y", "R", "P.X", "depth.Z"):
            np.testing.assert_array_equal(later[name], frame[name])
        self.assertLess(len(later.channel_names), len(frame.channel_names))  # no debug channels
        with self.assertRaisesRegex(ValueError, "channels 'some' is not all or on_request"):
            self.renderer.render("pcf", channels="some")

    def test_outputs_leave_out_what_the_caller_does_not_read(self):
        frame = self.renderer.render("pcf", camera=self.camera(40, 30))
        for channels in ("all", "on_request"):
            bare = self.renderer.render("pcf", camera=self.camera(40, 30), channels=channels, outputs=[])
            self.assertEqual(sorted(bare.channel_names),
                             sorted(n for n in frame.channel_names if n.startswith("visibility.")))
            self.assertEqual(len(bare.channel_names), 2)  # visibility.Y and the light's layer
            np.testing.assert_array_equal(bare["visibility.Y"], frame["visibility.Y"])
        kept = self.renderer.render("pcf", camera=self.camera(40, 30), outputs=["preview"])
        np.testing.assert_array_equal(kept["R"], frame["R"])
        self.assertNotIn("P.X", kept.channel_names)
        with self.assertRaisesRegex(ValueError, 'output "shadow" is none of preview, surfaces, debug'):
            self.renderer.render("pcf", outputs=["shadow"])

    def test_channels_are_read_only_views_that_keep_the_frame(self):
        frame = self.renderer.render("sm", camera=self.camera(40, 30))
        visibility = frame["visibility.Y"]
        self.assertEqual(visibility.shape, (30, 40))
        self.assertEqual(visibility.dtype, np.float32)
        self.assertFalse(visibility.flags.writeable)
        self.assertFalse(visibility.flags.owndata)
        self.assertIs(visibility.base, frame)  # zero-copy: the frame's own memory
        copy = np.array(visibility)
        del frame
        np.testing.assert_array_equal(visibility, copy)  # still valid: the view keeps its frame
        self.assertTrue(np.all((visibility >= 0) & (visibility <= 1)))
        with self.assertRaises(ValueError):
            visibility[0, 0] = 2.0

    def test_device_buffers_are_the_frames_own(self):
        frame = self.renderer.render("sm", camera=self.camera(40, 30))
        handles = [frame.visibility_buffer(0)] + [frame.device_buffer(name)
                                                  for name in ("preview", "position", "normal", "depth")]
        self.assertTrue(all(isinstance(h, int) and h != 0 for h in handles))
        self.assertEqual(len(set(handles)), len(handles))  # one cl_mem per output
        with self.assertRaisesRegex(ValueError, "is none of preview, position, normal, depth"):
            frame.device_buffer("albedo")

    def test_a_scene_of_numpy_arrays(self):
        ground = np.array([[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]], dtype=np.float32)
        quad = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
        card = {"positions": ground * [0.2, 1, 0.2] + [0, 1, 0], "indices": quad, "name": "card",
                "transform": np.array([[1, 0, 0, 3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])}  # x + 3
        scene = penumbra.Scene.from_meshes([{"positions": ground, "indices": quad}, card],
                                           lights=[penumbra.Light.parse("dir:1,-1,0")])
        self.assertEqual(scene.triangle_count, 4)
        camera = penumbra.Camera.parse("0,20,0.001:0,0,0:30")
        camera.width = camera.height = 64
        frame = penumbra.Renderer(self.context, scene).render("sm", {"map-size": 512}, camera=camera)
        px, py, pz = frame["P.X"], frame["P.Y"], frame["P.Z"]
        ground_pixels = np.abs(py) < 1e-3
        shadowed = ground_pixels & (px > 3.2) & (px < 4.8) & (np.abs(pz) < 0.8)  # the card's shadow: x in [3, 5]
        lit = ground_pixels & (px < 2.0)
        self.assertTrue(shadowed.any() and lit.any())
        self.assertTrue(np.all(frame["visibility.Y"][shadowed] == 0))
        self.assertTrue(np.all(frame["visibility.Y"][lit] == 1))
        with self.assertRaisesRegex(penumbra.SceneError, r'mesh 0: triangle 0 index 2 is 9, out of range'):
            penumbra.Scene.from_meshes([{"positions": ground, "indices": [[0, 1, 9]]}])
        with self.assertRaisesRegex(ValueError, r'must be an \(N, 3\) array'):
            penumbra.Scene.from_meshes([{"positions": [1, 2, 3], "indices": quad}])

    def test_render_releases_the_gil(self):
        # Large enough that the scheduler's own stalls of the spinning loop (tens of ms on a loaded 2-core machine:
        # 48 ms of a 77 ms frame at 480x360 once) stay well below half a frame.
        camera = self.camera(960, 720)
        self.renderer.render("pcss", camera=camera)  # kernels built: the timed frames only render
        start = time.perf_counter()
        self.renderer.render("pcss", camera=camera)
        duration = time.perf_counter() - start
        worker = threading.Thread(target=self.renderer.render, args=("pcss",), kwargs={"camera": camera})
        longest, last = 0.0, time.perf_counter()
        worker.start()
        while worker.is_alive():  # holding the GIL, render would stop this loop for its whole duration
            now = time.perf_counter()
            longest, last = max(longest, now - last), now
        worker.join()
        self.assertLess(longest, 0.5 * duration, f"the loop stalled {longest:.3f} s of a {duration:.3f} s render")

    def test_errors_are_python_exceptions_with_the_librarys_messages(self):
        with self.assertRaisesRegex(ValueError, r"^unknown technique 'nope' \(known: sm, pcf, pcss"):
            self.renderer.render("nope")
        with self.assertRaisesRegex(ValueError, r"^pcf-radius: 99 is outside \[0, 16\]"):
            self.renderer.render("pcf", {"pcf-radius": 99})
        with self.assertRaises(penumbra.SceneError) as caught:
            penumbra.Scene("no/such/model.gltf")
        self.assertIn("no/such/model.gltf", str(caught.exception))
        self.assertIsInstance(caught.exception, penumbra.Error)
        self.assertIsInstance(caught.exception, RuntimeError)
        with self.assertRaises(penumbra.NoDeviceError):
            penumbra.Context("no-such-device-anywhere")
        light = penumbra.Light.parse("point:0,5,0")  # six cube faces
        self.assertIn("visibility.Y", self.renderer.render("sm", lights=[light]).channel_names)

    def test_context_options_prebuild_and_log(self):
        # Options instead of the environment; prebuild builds what a technique runs, so a frame after it builds
        # nothing; the log (a Python callable, called with the GIL taken) names each program.
        cache = os.path.join(SCRATCH, "prebuild-cache")
        shutil.rmtree(cache, ignore_errors=True)  # a new folder: every program built, none loaded
        messages = []
        context = penumbra.Context(cache_dir=cache, log=messages.append)
        context.prebuild(["sm"])
        self.assertTrue(any(m.startswith("built kernels/") for m in messages), messages)
        built = len(messages)
        penumbra.Renderer(context, self.scene).render("sm", camera=self.camera(24, 16))
        self.assertEqual(len(messages), built, messages[built:])
        self.assertTrue(os.listdir(cache))
        with self.assertRaisesRegex(ValueError, r'unknown item "nope" \(known: '):
            context.prebuild(["nope"])
        with self.assertRaisesRegex(ValueError, r"work-group layouts 'amd'"):
            penumbra.Context(layouts="amd")

    def test_a_context_on_existing_opencl_handles(self):
        # The integer handles pyopencl's int_ptr would give; here those of another context's objects.
        shared = penumbra.Context.from_cl(self.context.cl_context, self.context.cl_device, self.context.cl_queue)
        self.assertEqual(shared.cl_queue, self.context.cl_queue)  # no second queue
        ours = penumbra.Renderer(shared, self.scene).render("sm", camera=self.camera(40, 30))
        theirs = self.renderer.render("sm", camera=self.camera(40, 30))
        np.testing.assert_array_equal(ours["visibility.Y"], theirs["visibility.Y"])

    def test_lights_with_their_own_techniques(self):
        key, sun = penumbra.Light.parse("spot:2,6,1:0,0,0:50:0.3"), penumbra.Light.parse("dir:-0.3,-1,0.2:2")
        key.name, sun.name = "Key", "Sun"
        frame = self.renderer.render("sm", camera=self.camera(40, 30),
                                     lights=[key, (sun, "pcf", {"pcf-radius": 1})])
        self.assertEqual(frame.light_layers, ["Key", "Sun"])
        self.assertIn("visibility.Sun.Y", frame)
        self.assertIn("Sun=pcf", frame.attribute("penumbra:light-techniques"))

    def test_stages_on_numpy_arrays(self):
        rng = np.random.default_rng(5)
        image = rng.random((23, 37), dtype=np.float32)
        blurred = penumbra.blur(self.context, image, filter="box", radius=3)
        np.testing.assert_allclose(blurred, box_blur_reference(image, 3), atol=2e-6)

        table, offset = penumbra.sat(self.context, image, precision="float64")
        np.testing.assert_allclose(table, image.astype(np.float64).cumsum(0).cumsum(1), rtol=1e-12)
        fixed, _ = penumbra.sat(self.context, np.floor(image * 8), precision="fixed32", fraction_bits=0)
        np.testing.assert_array_equal(fixed, np.floor(image * 8).astype(np.int64).cumsum(0).cumsum(1))

        depth = rng.uniform(2, 10, (23, 37)).astype(np.float32)
        moments = penumbra.moments(self.context, depth, kind="vsm", depth_near=2, depth_far=10)
        z = (depth.astype(np.float64) - 2) / 8
        np.testing.assert_allclose(moments, np.stack([z, z * z], -1), atol=1e-6, rtol=1e-6)
        half = penumbra.moments(self.context, depth, kind="vsm", depth_near=2, depth_far=10, storage="float16")
        self.assertEqual(half.dtype, np.float16)
        np.testing.assert_allclose(half.astype(np.float64), np.stack([z, z * z], -1), rtol=1.0 / 2048, atol=1e-6)
        esm = penumbra.moments(self.context, depth, kind="esm", depth_near=2, depth_far=10, esm_exponent=20)
        np.testing.assert_allclose(esm, np.exp(20 * (z - 1))[..., None], rtol=1e-5, atol=1e-12)
        log_space = penumbra.moments(self.context, depth, kind="esm", depth_near=2, depth_far=10, esm_exponent=400)
        np.testing.assert_allclose(log_space, z[..., None], atol=1e-6)
        blurred = penumbra.blur_moments(self.context, depth, kind="esm", depth_near=2, depth_far=10,
                                        esm_exponent=400, filter="box", radius=1)
        self.assertEqual(blurred.shape, (23, 37, 1))
        # Log space: D = m + ln(mean of e^(c (z - m))) / c over each 3x3 box (clamp-to-edge), m its largest tap.
        padded = np.pad(z, 1, mode="edge")
        taps = np.stack([padded[i:i + 23, j:j + 37] for i in range(3) for j in range(3)])
        m = taps.max(0)
        expected = m + np.log(np.exp(400 * (taps - m)).mean(0)) / 400
        np.testing.assert_allclose(blurred[..., 0], expected, atol=2e-6)

        levels = penumbra.minmax_pyramid(self.context, depth)
        self.assertEqual([level.shape for level in levels], [(23, 37, 2), (11, 18, 2), (5, 9, 2), (2, 4, 2),
                                                             (1, 2, 2), (1, 1, 2)])
        self.assertEqual(levels[-1][0, 0, 0], depth.min())
        self.assertEqual(levels[-1][0, 0, 1], depth.max())
        even = rng.random((16, 20, 2), dtype=np.float32)
        mips = penumbra.moment_mips(self.context, even)
        np.testing.assert_allclose(mips[0], even.reshape(8, 2, 10, 2, 2).mean((1, 3)), atol=1e-6)

        x, w = rng.random(5000, dtype=np.float32), rng.random(5000, dtype=np.float32)
        stats = penumbra.lloyd_stats(self.context, x, w, np.array([0.5], np.float32))
        low = x < 0.5
        np.testing.assert_allclose(stats["sum_w"], [w[low].sum(), w[~low].sum()], rtol=1e-5)
        np.testing.assert_array_equal(stats["samples"], [low.sum(), (~low).sum()])

        with self.assertRaisesRegex(ValueError, "filter 'median' is not gaussian or box"):
            penumbra.blur(self.context, image, filter="median")


class PyOpenCL(unittest.TestCase):
    """pyopencl's own objects: a penumbra.Context on a pyopencl queue, the stages on pyopencl arrays in place (results
    on the same queue, ordered by events, equal to the numpy path's), a frame's buffers as pyopencl arrays."""

    @classmethod
    def setUpClass(cls):
        import pyopencl
        import pyopencl.array
        cls.cl = pyopencl
        penumbra_device = penumbra.Context().device_name  # the device the suite runs on (PENUMBRA_DEVICE)
        device = next(d for p in pyopencl.get_platforms() for d in p.get_devices() if d.name == penumbra_device)
        cls.queue = pyopencl.CommandQueue(pyopencl.Context([device]))
        cls.context = penumbra.Context.from_queue(cls.queue)
        cls.host = penumbra.Context()  # the numpy path, on a context of its own

    def device(self, array):
        return self.cl.array.to_device(self.queue, array)

    def test_a_context_on_pyopencl_objects(self):
        self.assertEqual(self.context.cl_queue, self.queue.int_ptr)
        self.assertEqual(self.context.cl_context, self.queue.context.int_ptr)
        shared = penumbra.Context.from_cl(self.queue.context, self.queue.device, self.queue)
        self.assertEqual(shared.cl_queue, self.queue.int_ptr)
        with self.assertRaisesRegex(TypeError, "from_cl: device: an integer handle or a pyopencl object"):
            penumbra.Context.from_cl(self.queue.context, "cpu", self.queue)

    def test_stages_on_pyopencl_arrays_in_place(self):
        rng = np.random.default_rng(11)
        image = rng.random((23, 37), dtype=np.float32)
        depth = rng.uniform(2, 10, (23, 37)).astype(np.float32)
        blurred = penumbra.blur(self.context, self.device(image), filter="box", radius=3)
        self.assertIsInstance(blurred, self.cl.array.Array)
        self.assertEqual(blurred.queue, self.queue)
        self.assertTrue(blurred.events)  # the stage's event: pyopencl's own operations wait for it
        np.testing.assert_array_equal(blurred.get(), penumbra.blur(self.host, image, filter="box", radius=3))

        # Chained on the device, no host copy between: moments, then a blur of them.
        moments = penumbra.moments(self.context, self.device(depth), kind="vsm", depth_near=2, depth_far=10)
        self.assertEqual(moments.shape, (23, 37, 2))
        chained = penumbra.blur(self.context, moments, filter="gaussian", sigma=1.5, radius=3)
        host_moments = penumbra.moments(self.host, depth, kind="vsm", depth_near=2, depth_far=10)
        np.testing.assert_array_equal(chained.get(), penumbra.blur(self.host, host_moments, sigma=1.5, radius=3))
        half = penumbra.moments(self.context, self.device(depth), kind="vsm", depth_near=2, depth_far=10,
                                storage="float16")
        self.assertEqual(half.dtype, np.float16)
        np.testing.assert_array_equal(half.get(), penumbra.moments(self.host, depth, kind="vsm", depth_near=2,
                                                                   depth_far=10, storage="float16"))

        table, offset = penumbra.sat(self.context, self.device(image), precision="fixed64")
        host_table, host_offset = penumbra.sat(self.host, image, precision="fixed64")
        self.assertEqual(table.dtype, np.uint64)
        np.testing.assert_array_equal(table.get(), host_table)
        np.testing.assert_array_equal(offset.get(), host_offset)

        levels = penumbra.minmax_pyramid(self.context, self.device(depth))
        host_levels = penumbra.minmax_pyramid(self.host, depth)
        self.assertEqual([level.shape for level in levels], [level.shape for level in host_levels])
        for level, host_level in zip(levels, host_levels):
            np.testing.assert_array_equal(level.get(), host_level)
        mips = penumbra.moment_mips(self.context, self.device(host_moments))
        for level, host_level in zip(mips, penumbra.moment_mips(self.host, host_moments)):
            np.testing.assert_array_equal(level.get(), host_level)

        x, w = rng.random(3000, dtype=np.float32), rng.random(3000, dtype=np.float32)
        bounds = np.array([0.25, 0.5], np.float32)
        stats = penumbra.lloyd_stats(self.context, self.device(x), self.device(w), self.device(bounds))
        host_stats = penumbra.lloyd_stats(self.host, x, w, bounds)
        for key in ("sum_w", "sum_wx", "sum_wx2", "samples"):
            np.testing.assert_array_equal(stats[key], host_stats[key])

    def test_results_into_the_callers_arrays_and_buffers(self):
        rng = np.random.default_rng(12)
        image = rng.random((19, 33), dtype=np.float32)
        expected = penumbra.blur(self.host, image, filter="box", radius=2)
        target = self.cl.array.empty(self.queue, (19, 33), np.float32)
        result = penumbra.blur(self.context, self.device(image), filter="box", radius=2, out=target)
        self.assertIs(result, target)
        np.testing.assert_array_equal(target.get(), expected)
        # A raw Buffer: written in place, returned as an array over it; as an input, wrapped without a copy.
        buffer = self.cl.Buffer(self.queue.context, self.cl.mem_flags.READ_WRITE, size=image.nbytes)
        over = penumbra.blur(self.context, self.device(image), filter="box", radius=2, out=buffer)
        self.assertEqual(over.base_data.int_ptr, buffer.int_ptr)
        np.testing.assert_array_equal(over.get(), expected)
        wrapped = self.cl.array.Array(self.queue, image.shape, np.float32, data=buffer)
        np.testing.assert_array_equal(penumbra.blur(self.context, wrapped, filter="box", radius=2).get(),
                                      penumbra.blur(self.host, expected, filter="box", radius=2))
        moments = self.cl.array.empty(self.queue, (19, 33, 2), np.float32)
        penumbra.moments(self.context, self.device(image + 2), kind="vsm", depth_near=2, depth_far=3, out=moments)
        np.testing.assert_array_equal(moments.get(), penumbra.moments(self.host, image + 2, kind="vsm",
                                                                      depth_near=2, depth_far=3))
        with self.assertRaisesRegex(ValueError, r"blur: out has the shape \(33, 19\), not \(19, 33\)"):
            penumbra.blur(self.context, self.device(image), out=self.cl.array.empty(self.queue, (33, 19), np.float32))
        small = self.cl.Buffer(self.queue.context, self.cl.mem_flags.READ_WRITE, size=16)
        with self.assertRaisesRegex(ValueError, "blur: out is a pyopencl Buffer of 16 bytes; the result takes 2508"):
            penumbra.blur(self.context, self.device(image), out=small)
        with self.assertRaisesRegex(ValueError, "which needs a pyopencl array as the input"):
            penumbra.blur(self.context, image, out=buffer)
        with self.assertRaisesRegex(TypeError, "blur: out: a pyopencl array or Buffer, not"):
            penumbra.blur(self.context, self.device(image), out=np.empty((19, 33), np.float32))

    def test_pyopencl_arrays_penumbra_cannot_use_in_place(self):
        image = np.ones((8, 8), np.float32)
        with self.assertRaisesRegex(ValueError, "blur: image is a pyopencl array of float64, not float32"):
            penumbra.blur(self.context, self.device(image.astype(np.float64)))
        with self.assertRaisesRegex(ValueError, "blur: image is a pyopencl view at an offset"):
            penumbra.blur(self.context, self.device(image)[2:])
        other = self.cl.CommandQueue(self.cl.Context([self.queue.device]))
        with self.assertRaisesRegex(ValueError, "another cl_context than the penumbra.Context's"):
            penumbra.blur(self.context, self.cl.array.to_device(other, image))

    def test_frame_buffers_as_pyopencl_arrays(self):
        scene = penumbra.Scene("builtin:box")
        camera = scene.default_camera()
        camera.width, camera.height = 40, 30
        frame = penumbra.Renderer(self.context, scene).render("sm", camera=camera)
        visibility = frame.visibility_array(self.queue)
        depth = frame.device_array("depth", self.queue)
        expected = np.flipud(np.array(frame["visibility.Y"]))  # device rows are bottom-up
        self.assertEqual((visibility.shape, depth.shape), ((30, 40), (30, 40)))
        self.assertEqual(frame.device_array("normal", self.queue).shape, (30, 40, 4))
        del frame
        np.testing.assert_array_equal(visibility.get(), expected)  # the array keeps the buffer
        with self.assertRaisesRegex(ValueError, "the queue's context is not the frame's"):
            other = self.cl.CommandQueue(self.cl.Context([self.queue.device]))
            penumbra.Renderer(self.host, scene).render("sm", camera=camera).visibility_array(other)

    def test_a_shader_on_the_callers_map_and_a_frames_buffers(self):
        scene = penumbra.Scene("builtin:box")
        camera = scene.default_camera()
        camera.width, camera.height = 40, 30
        frame = penumbra.Renderer(self.context, scene).render("sm", camera=camera)
        positions = frame.device_array("position", self.queue)
        normals = frame.device_array("normal", self.queue)
        # A sun straight down: eye (0, 20, 0) looking along -y, an orthographic window 40 wide and 40 deep.
        view = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, -20], [0, 0, 0, 1]], np.float32)
        projection = np.array([[0.05, 0, 0, 0], [0, 0.05, 0, 0], [0, 0, -0.05, -1], [0, 0, 0, 1]], np.float32)
        shader = penumbra.Shader(self.context)
        seen = np.flipud(np.array(frame["A"])) > 0  # device rows are bottom-up
        for texel in (1.0, 0.0):  # nothing drawn (the cleared value), then everything at the near plane
            light_map = np.full((64, 64), texel, np.float32)
            common = dict(light_view=view, light_projection=projection, light_type="directional")
            on_device = shader.shade("sm", light_map=self.device(light_map), positions=positions, normals=normals,
                                     **common)
            self.assertIsInstance(on_device, self.cl.array.Array)
            on_host = penumbra.Shader(self.host).shade("sm", light_map=light_map, positions=positions.get(),
                                                       normals=normals.get(), **common)
            self.assertIsInstance(on_host, np.ndarray)
            np.testing.assert_array_equal(on_device.get(), on_host)
            np.testing.assert_array_equal(on_host, np.where(seen & (texel == 0.0), 0.0, 1.0))
            # Rows from the top: the same image, flipped in and out.
            flipped = penumbra.Shader(self.host).shade("sm", light_map=np.flipud(light_map),
                                                       positions=np.flipud(positions.get()), top_down=True, **common)
            np.testing.assert_array_equal(np.flipud(flipped), on_host)
        self.assertTrue(shader.attribute("penumbra:light-fit").startswith("caller 64x64"))
        self.assertIsNone(shader.attribute("no such attribute"))
        self.assertEqual(penumbra.takes_caller_map("pcss"), (True, ""))
        self.assertFalse(penumbra.takes_caller_map("izb")[0])
        with self.assertRaisesRegex(ValueError, "technique izb cannot shade from a caller's map"):
            shader.shade("izb", light_map=light_map, positions=positions, **common)
        with self.assertRaisesRegex(ValueError, "normals has the shape"):
            shader.shade("sm", light_map=light_map, positions=positions, normals=light_map, **common)


if __name__ == "__main__":
    unittest.main()
