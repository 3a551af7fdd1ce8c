"""rtgi from Python: render, measure and compare, with NumPy arrays (docs/python.md).

The renderer is the one rtgi-bench runs (the native module ``_rtgi`` links the
same library), headless on EGL. Settings take the keys, ranges and error
sentences of ``rtgi-bench --set``; results are the dicts rtgi-bench writes as
results.json; images are float32 arrays H x W x C with row 0 at the top.

    import rtgi
    with rtgi.Renderer(scenes=["builtin:cornell"], resolution=(64, 64)) as r:
        res = r.render(frames=2, warmup=1)
        print(res.total_ms, res.images["hdr"].shape)
"""
import json as _json
import os as _os
import sys as _sys

_SYSTEM_PYTHON = "/usr/bin/python3"


def _reexec_under_system_python():
    """`python3 -c ...` or `python3 script.py` under an interpreter without NumPy
    (a pyenv or venv python first on PATH): run the same command again under
    Debian's interpreter, which has python3-numpy, as benchmarks/report.py
    does. Never in an interactive session or a notebook kernel, never twice,
    and not with RTGI_NO_REEXEC set."""
    argv = getattr(_sys, "orig_argv", None)
    if (not argv or _os.environ.get("RTGI_NO_REEXEC") or _sys.flags.interactive or "ipykernel" in _sys.modules
            or hasattr(_sys, "ps1") or not _os.path.exists(_SYSTEM_PYTHON)
            or _os.path.realpath(_sys.executable) == _os.path.realpath(_SYSTEM_PYTHON)):
        return
    if len(argv) < 2 or argv[1] == "-" or (argv[1] not in ("-c", "-m") and not _os.path.isfile(argv[1])):
        return  # stdin or the REPL: nothing to run again
    _os.environ["RTGI_NO_REEXEC"] = "1"
    _sys.stdout.flush()
    _sys.stderr.flush()
    _os.execv(_SYSTEM_PYTHON, [_SYSTEM_PYTHON] + list(argv[1:]))


try:
    import numpy as _np
except ImportError as _e:  # pragma: no cover - depends on the interpreter
    _reexec_under_system_python()
    raise ImportError(
        "rtgi needs NumPy, which this interpreter (%s) lacks: run it with the interpreter rtgi was built for "
        "(Debian's /usr/bin/python3 with python3-numpy by default; docs/python.md) or install numpy"
        % _sys.executable) from _e

try:
    from . import _rtgi
except ImportError as _e:  # pragma: no cover
    raise ImportError(
        "rtgi's native module does not load in this interpreter (%s, Python %d.%d): it is built for the "
        "interpreter CMake was configured with (-DPython3_EXECUTABLE, default /usr/bin/python3; "
        "docs/python.md): %s" % (_sys.executable, _sys.version_info[0], _sys.version_info[1], _e)) from _e

__all__ = ["Renderer", "RenderResult", "Reference", "compare", "sweep", "version", "list_devices",
           "ConfigError", "SceneError", "GLError", "OutputError"]

#: A bad setting, option or value (rtgi-bench exit code 2); a ValueError.
ConfigError = _rtgi.ConfigError
#: A scene or image that cannot be read (exit code 3); a ValueError.
SceneError = _rtgi.SceneError
#: A GL failure, including out of GPU memory (exit code 4); a RuntimeError.
GLError = _rtgi.GLError
#: A result file that cannot be written (exit code 6); an OSError.
OutputError = _rtgi.OutputError


def version():
    """The project version and git describe, as ``rtgi-bench --version`` prints it."""
    return _rtgi.version()


def list_devices():
    """The EGL devices (index = the ``device`` argument), as ``rtgi-bench --list-devices``."""
    return list(_rtgi.list_devices())


def _assignments(settings, source="settings"):
    """A dict of settings (nested or dotted keys; bools, numbers, strings, [x, y, z])
    as the key=value pairs rtgi-bench's --config makes of the same JSON."""
    if settings is None:
        return []
    if not isinstance(settings, dict):
        raise TypeError("settings must be a dict of key -> value, got %s" % type(settings).__name__)

    def plain(v):
        if isinstance(v, dict):
            return {str(k): plain(x) for k, x in v.items()}
        if isinstance(v, (tuple, list, _np.ndarray)):
            return [plain(x) for x in list(v)]
        if isinstance(v, _np.generic):
            return v.item()
        return v

    return list(_rtgi.flatten_settings(_json.dumps(plain(settings), allow_nan=False), source))


class RenderResult:
    """What one ``Renderer.render`` call measured.

    ``timings``: pass -> {median, min, max, mean, dispatches} (milliseconds,
    per frame); ``total_ms``: median frame time; ``images``: name -> float32
    array (H x W x C, row 0 at the top); ``json``: the results.json dict;
    ``error``: the error dict when rendered with ``reference=True``.
    """

    def __init__(self, results, images):
        self.json = results
        self.images = images
        self.total_ms = results["total_ms"]
        self.timings = {p["name"]: dict(p["gpu_ms"], dispatches=p["dispatches"]) for p in results["passes"]}
        self.error = results.get("error")

    def __repr__(self):
        return "<rtgi.RenderResult %s %s: %.4f ms/frame, %d passes, images %s>" % (
            self.json["scene"], self.json["resolution"], self.total_ms, len(self.timings), sorted(self.images))


class Reference:
    """A ray-traced reference: ``image`` (mean), ``stderr`` (per-pixel standard
    error of the mean), both float32 H x W x C, and ``info`` (results.json's
    error.reference: spp, cache, settings). Unpacks as ``image, stderr``."""

    def __init__(self, image, stderr, info):
        self.image, self.stderr, self.info = image, stderr, info

    def __iter__(self):
        return iter((self.image, self.stderr))

    def __repr__(self):
        return "<rtgi.Reference %s, %s spp>" % (self.image.shape, self.info.get("spp"))


class Renderer:
    """A renderer of one scene list at one resolution, headless on EGL.

    ``scenes``: ``builtin:NAME`` or glTF/GLB paths (merged, as repeated
    ``--scene``); ``settings``: dict of configuration keys (``--set``);
    ``device``: EGL device index (None: NVIDIA preferred, else Mesa);
    ``max_memory``: GPU memory budget such as ``"4G"`` (``--max-memory``).
    Renderers in one process share one GL context; ``close()`` (or leaving a
    ``with`` block) frees this renderer's GPU resources and, with the last
    one, the context.
    """

    def __init__(self, scenes=("builtin:atrium",), resolution=(1280, 720), settings=None, device=None,
                 max_memory=None, debug=False):
        if isinstance(scenes, (str, _os.PathLike)):
            scenes = [scenes]
        scenes = [_os.fspath(s) for s in scenes]
        w, h = (int(x) for x in resolution)
        self._r = _rtgi.Renderer(scenes, w, h, _assignments(settings), -1 if device is None else int(device),
                                 "" if max_memory is None else str(max_memory), bool(debug))
        for w_ in self._r.warnings:
            import warnings
            warnings.warn("rtgi: " + w_, stacklevel=2)

    # -- resources -------------------------------------------------------
    def close(self):
        """Frees the GPU resources (and the GL context with the last renderer); idempotent."""
        self._r.close()

    @property
    def closed(self):
        return self._r.closed

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    # -- settings and camera ---------------------------------------------
    def set(self, key, value=None):
        """``set("lpv.grid", 32)`` or ``set({"ao": "gtao", "ao.samples": 8})``: the
        same keys, ranges and ValueError sentences as ``rtgi-bench --set``."""
        self._r.set(_assignments(key if isinstance(key, dict) else {key: value}))

    @property
    def settings(self):
        """Every key with its effective value (results.json "config"); a copy."""
        return _json.loads(self._r.settings_json())

    @property
    def scene(self):
        return self._r.scene

    @property
    def resolution(self):
        return tuple(self._r.resolution)

    @property
    def views(self):
        """Named views of benchmarks/views/ for this scene (``r.view = name``)."""
        return list(self._r.views)

    @property
    def view(self):
        return self.settings.get("view", "")

    @view.setter
    def view(self, name):
        self.set("view", name or "")

    @property
    def camera(self):
        """The camera the next frame uses: dict(position, target, fov, near, far)."""
        return _json.loads(self._r.camera_json())

    @camera.setter
    def camera(self, cam):
        """``dict(position=..., target=..., fov=...)``; a missing key keeps its value,
        None returns it to the scene's (``auto``)."""
        if cam is None:
            cam = dict(position=None, target=None, fov=None)
        known = {"position", "target", "fov", "near", "far"}
        unknown = set(cam) - known
        if unknown:
            raise ConfigError("camera: unknown key(s) %s (position, target, fov, near, far)" % sorted(unknown))
        self.set({"camera." + k: ("auto" if v is None else v) for k, v in cam.items()})

    # -- rendering --------------------------------------------------------
    def render(self, frames=100, warmup=20, debug_images=False, check=False, reference=False):
        """Renders ``warmup`` + ``frames`` frames and times the measured ones, as
        rtgi-bench does. ``reference=True`` adds the error against the matching
        ray-traced reference (``--reference``) as ``res.error``; ``check``
        counts NaN/Inf per pass output (``--check``); ``debug_images`` adds the
        passes' debug images to ``res.images``."""
        text, images = self._r.render(int(frames), int(warmup), bool(debug_images), bool(check), bool(reference))
        return RenderResult(_json.loads(text), dict(images))

    def reference(self, kind="full", spp=None, settings=None):
        """The ray-traced reference of this scene, camera and settings: ``kind``
        ao | indirect | full; ``spp`` (reference.spp) and further reference.*
        ``settings`` override the renderer's. Cached on disk like rtgi-bench's."""
        extra = dict(settings or {})
        if spp is not None:
            extra["reference.spp"] = int(spp)
        image, stderr, info = self._r.reference(str(kind), _assignments(extra))
        return Reference(image, stderr, _json.loads(info))

    def __repr__(self):
        return "<rtgi.Renderer %s %dx%d%s>" % (self.scene, *self.resolution, " closed" if self.closed else "")


def compare(image, reference, mask=None, quantity="radiance", background=None):
    """The error dict ``rtgi-bench --compare`` writes (compare.json): RMSE, MAE,
    bias, PSNR, SSIM, FLIP, ... of ``image`` against ``reference`` (float arrays
    H x W x C, or H x W, row 0 at the top). ``quantity``: radiance (HDR rgb,
    the default, as for a PFM/EXR reference), ldr (rgb in [0,1], linear), ao
    (channel 0); ``mask``: compare where mask > 0.5; ``background``: compare
    where the reference is not this value."""
    if isinstance(reference, Reference):
        reference = reference.image
    out = _rtgi.compare(_np.asarray(image, dtype=_np.float32), _np.asarray(reference, dtype=_np.float32),
                        None if mask is None else _np.asarray(mask, dtype=_np.float32), str(quantity),
                        None if background is None else float(background))
    return _json.loads(out)


def _progress_bar(progress, total, name):
    if progress is not True:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc=name, unit="config")


def sweep(spec, shard=None, progress=None, check=False, out=None, device=None):
    """Runs a sweep (a dict in the sweep-file format, or the path of one) and
    yields one row per configuration: the results.jsonl lines ``rtgi-bench
    --sweep`` writes (results.json plus "sweep" and "wall_s", or "failed").
    ``pandas.json_normalize(list(rtgi.sweep(...)))`` makes a table.

    ``shard``: (i, n) or "i/n" (``--shard``); ``progress``: a callable
    ``progress(done, total, row)``, or True for a tqdm bar when tqdm is
    installed; ``out``: a directory for the per-configuration images when
    the sweep asks for them (``"images": true``)."""
    if isinstance(shard, str):
        i, _, n = shard.partition("/")
        try:
            shard = (int(i), int(n))
        except ValueError:
            raise ConfigError("--shard '%s': expected i/n, e.g. 0/4" % shard) from None
    i, n = shard if shard is not None else (0, 1)
    if isinstance(spec, dict):
        engine = _rtgi.Sweep(_json.dumps(spec), False, int(i), int(n), -1 if device is None else int(device),
                             bool(check), "" if out is None else _os.fspath(out))
    else:
        engine = _rtgi.Sweep(_os.fspath(spec), True, int(i), int(n), -1 if device is None else int(device),
                             bool(check), "" if out is None else _os.fspath(out))
    return _SweepIterator(engine, progress)


class _SweepIterator:
    """The rows of ``sweep``; ``len()`` is the number of configurations of the shard."""

    def __init__(self, engine, progress):
        self._engine, self._progress, self._k = engine, progress, 0
        self._bar = _progress_bar(progress, len(engine), engine.name)
        self.name = engine.name

    def __len__(self):
        return len(self._engine)

    def __iter__(self):
        return self

    def __next__(self):
        if self._k >= len(self._engine):
            self.close()
            raise StopIteration
        try:
            row = _json.loads(self._engine.run(self._k))
        except BaseException:
            self.close()
            raise
        self._k += 1
        if self._bar is not None:
            self._bar.update(1)
        elif callable(self._progress):
            self._progress(self._k, len(self._engine), row)
        return row

    def close(self):
        """Frees the sweep's renderer and GL context (also at the end of the iteration)."""
        self._engine.close()
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass
