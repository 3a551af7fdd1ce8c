"""The rtgi Python module against rtgi-bench (issue 27; run by ctest as "python").

The oracle of every test is rtgi-bench itself, run as a separate process on the
same configuration: the PFM files it writes (parsed here by an independent
reader), the numbers of ``--compare``, its error sentences, the rows of
``--sweep``. Images are tiny (64x64, a few frames) so that llvmpipe is fast.
"""
import json
import os
import struct
import subprocess

import numpy as np
import pytest

import rtgi

BENCH = os.environ.get("RTGI_BENCH", "build/rtgi-bench")
SCENE = "builtin:cornell"
RES = (64, 48)  # not square: a transposed array would not fit
FRAMES, WARMUP = 2, 1


def bench(*args, check=True):
    """Runs rtgi-bench; returns (exit code, stdout, stderr)."""
    p = subprocess.run([BENCH, *args], capture_output=True, text=True, timeout=300)
    if check and p.returncode != 0:
        raise AssertionError("rtgi-bench %s failed (%d): %s" % (" ".join(args), p.returncode, p.stderr))
    return p.returncode, p.stdout, p.stderr


def bench_error(*args):
    """The sentence rtgi-bench prints for a bad invocation (without its "rtgi-bench: " prefix)."""
    rc, _, err = bench(*args, check=False)
    assert rc != 0, "rtgi-bench %s should have failed" % " ".join(args)
    line = err.strip().splitlines()[0]
    assert line.startswith("rtgi-bench: ")
    return rc, line[len("rtgi-bench: "):]


def read_pfm(path):
    """PFM per its definition: "PF" (RGB) or "Pf" (grey), width height, scale
    (negative: little endian), raw floats with the bottom row first. Returns
    H x W x C float32 with row 0 at the top."""
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos].decode())
    pos += 1  # the single whitespace byte before the data
    magic, w, h, scale = fields[0], int(fields[1]), int(fields[2]), float(fields[3])
    c = 3 if magic == "PF" else 1
    dtype = "<f4" if scale < 0 else ">f4"
    px = np.frombuffer(data, dtype=dtype, count=w * h * c, offset=pos).reshape(h, w, c)
    return np.flipud(px).astype(np.float32)


def write_pfm(path, img):
    img = np.asarray(img, dtype="<f4")
    h, w, c = img.shape
    assert c == 3
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.flipud(img).tobytes())


def same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


# --------------------------------------------------------------------------
# Rendering: the arrays are the data of rtgi-bench's PFM files.

def test_render_images_equal_bench_pfm_files(tmp_path):
    out = tmp_path / "bench"
    bench("--scene", SCENE, "--res", "%dx%d" % RES, "--frames", str(FRAMES), "--warmup", str(WARMUP),
          "--set", "lpv=on", "--out", str(out))
    with rtgi.Renderer(scenes=[SCENE], resolution=RES, settings={"lpv": "on"}) as r:
        res = r.render(frames=FRAMES, warmup=WARMUP)
    hdr = res.images["hdr"]
    assert hdr.dtype == np.float32 and hdr.shape == (RES[1], RES[0], 3)
    assert same_bits(hdr, read_pfm(out / "final.pfm"))
    assert same_bits(res.images["indirect"], read_pfm(out / "indirect.pfm"))
    assert np.any(hdr > 0) and np.any(res.images["indirect"] > 0)  # not two black images
    # The same configuration and the same frame as results.json says.
    cli = json.loads((out / "results.json").read_text())
    assert res.json["config"] == cli["config"]
    assert [p["name"] for p in res.json["passes"]] == [p["name"] for p in cli["passes"]]
    assert res.json["skipped"] == cli["skipped"] and res.json["camera"] == cli["camera"]
    assert set(res.timings) == {p["name"] for p in cli["passes"]}
    for name, t in res.timings.items():
        assert set(t) == {"median", "min", "max", "mean", "dispatches"}
        assert t["min"] <= t["median"] <= t["max"]
    assert res.total_ms == res.json["total_ms"] and res.total_ms > 0
    # final: the tonemapped LDR image in [0,1]; depth: one channel.
    assert res.images["final"].shape == hdr.shape and 0 <= res.images["final"].min() <= res.images["final"].max() <= 1
    assert res.images["depth"].shape == (RES[1], RES[0], 1)


def test_settings_camera_and_views_follow_the_cli(tmp_path):
    with rtgi.Renderer(scenes=[SCENE], resolution=RES) as r:
        r.set("lpv.grid", 16)
        r.camera = dict(position=[0.1, 0.9, 3.0], target=[0.0, 0.8, 0.0], fov=50)
        s = r.settings
        assert s["lpv.grid"] == 16
        cam = r.camera
        assert cam["position"] == pytest.approx([0.1, 0.9, 3.0]) and cam["fov"] == pytest.approx(50)
        res = r.render(frames=1, warmup=0)
    out = tmp_path / "cli"
    bench("--scene", SCENE, "--res", "%dx%d" % RES, "--frames", "1", "--warmup", "0", "--set", "lpv.grid=16",
          "--set", "camera.position=0.1,0.9,3", "--set", "camera.target=0,0.8,0", "--set", "camera.fov=50",
          "--out", str(out))
    assert same_bits(res.images["hdr"], read_pfm(out / "final.pfm"))
    assert res.json["config"] == json.loads((out / "results.json").read_text())["config"]


def test_named_views_are_the_views_file(tmp_path):
    src = os.environ.get("RTGI_SOURCE_DIR", ".")
    with open(os.path.join(src, "benchmarks", "views", "atrium.json")) as f:
        views = json.load(f)["views"]
    with rtgi.Renderer(scenes=["builtin:atrium"], resolution=(16, 16)) as r:
        assert sorted(r.views) == sorted(views)
        for name, v in views.items():
            r.view = name
            cam = r.camera
            assert r.view == name
            assert cam["position"] == pytest.approx(v["position"]) and cam["target"] == pytest.approx(v["target"])
            assert cam["fov"] == pytest.approx(v["fov"])
        # rtgi-bench says so when it renders; the module already at set().
        rc, sentence = bench_error("--scene", "builtin:atrium", "--set", "view=no-such-view", "--res", "8x8",
                                   "--frames", "1", "--warmup", "0", "--no-images", "--out", str(tmp_path))
        assert rc == 2
        with pytest.raises(ValueError) as e:
            r.view = "no-such-view"
        assert str(e.value) == sentence and r.view == name


# --------------------------------------------------------------------------
# Errors: Python exceptions with the CLI's sentences; the interpreter lives on.

@pytest.mark.parametrize("key,value,cli", [
    ("no.such.key", 1, "no.such.key=1"),
    ("lpv.grid", "abc", "lpv.grid=abc"),
    ("lpv.grid", 0, "lpv.grid=0"),
    ("ao", "nope", "ao=nope"),
])
def test_bad_setting_raises_value_error_with_cli_sentence(key, value, cli):
    rc, sentence = bench_error("--scene", SCENE, "--set", cli, "--validate-only")
    assert rc == 2
    with pytest.raises(ValueError) as e:
        rtgi.Renderer(scenes=[SCENE], resolution=RES, settings={key: value})
    assert str(e.value) == sentence
    assert isinstance(e.value, rtgi.ConfigError)
    # On an open renderer: the same sentence, and the settings stay as they were.
    with rtgi.Renderer(scenes=[SCENE], resolution=RES) as r:
        before = r.settings
        with pytest.raises(ValueError) as e2:
            r.set(key, value)
        assert str(e2.value) == sentence
        assert r.settings == before


def test_bad_scenes_raise_scene_error_with_cli_sentence(tmp_path):
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {}}]}]}')
    for spec in ["builtin:no-such-scene", str(broken), str(tmp_path / "missing.glb")]:
        rc, sentence = bench_error("--scene", spec, "--validate-only")
        assert rc == 3
        with pytest.raises(ValueError) as e:
            rtgi.Renderer(scenes=[spec], resolution=RES)
        assert isinstance(e.value, rtgi.SceneError)
        assert str(e.value) == sentence


def test_memory_budget_raises_before_the_first_frame(tmp_path):
    rc, sentence = bench_error("--scene", SCENE, "--res", "%dx%d" % RES, "--max-memory", "64K", "--frames", "1",
                               "--warmup", "0", "--out", str(tmp_path))
    assert rc == 2
    with rtgi.Renderer(scenes=[SCENE], resolution=RES, max_memory="64K") as r:
        with pytest.raises(ValueError) as e:
            r.render(frames=1, warmup=0)
        assert str(e.value) == sentence


# --------------------------------------------------------------------------
# Resources: with/close release the context; two renderers in one process.

def test_with_releases_the_context_and_renderers_coexist():
    with rtgi.Renderer(scenes=[SCENE], resolution=RES) as r:
        assert rtgi._rtgi.context_users() == 1
        first = r.render(frames=1, warmup=0).images["hdr"]
    assert r.closed and rtgi._rtgi.context_users() == 0
    with pytest.raises(RuntimeError):
        r.render(frames=1, warmup=0)
    r.close()  # idempotent
    # A second renderer after the first was released: a new context, same frame.
    with rtgi.Renderer(scenes=[SCENE], resolution=RES) as r2:
        assert same_bits(r2.render(frames=1, warmup=0).images["hdr"], first)
    assert rtgi._rtgi.context_users() == 0
    # Two open at once, of different scenes, rendered in turns: each frame is
    # the one it renders alone.
    a = rtgi.Renderer(scenes=[SCENE], resolution=RES)
    b = rtgi.Renderer(scenes=["builtin:box-on-plane"], resolution=RES, settings={"ao": "gtao"})
    assert rtgi._rtgi.context_users() == 2
    ib = b.render(frames=1, warmup=0).images["hdr"]
    ia = a.render(frames=1, warmup=0).images["hdr"]
    a.close()
    assert rtgi._rtgi.context_users() == 1
    assert same_bits(ia, first)
    ib2 = b.render(frames=1, warmup=0).images["hdr"]  # b still works after a's close
    b.close()
    with rtgi.Renderer(scenes=["builtin:box-on-plane"], resolution=RES, settings={"ao": "gtao"}) as alone:
        assert same_bits(ib, alone.render(frames=1, warmup=0).images["hdr"])
    assert same_bits(ib, ib2)


# --------------------------------------------------------------------------
# compare: the numbers of rtgi-bench --compare.

METRICS = ["rmse", "mae", "bias", "psnr", "ssim", "rel_rmse", "pixels", "nan_pixels", "inf_pixels", "rmse_zero",
           "peak", "heatmap_max"]


def check_same_metrics(py, cli):
    for k in METRICS:
        if k in cli:
            assert py[k] == cli[k], k
    assert py["compared"] == cli["compared"] | {"pixels": py["compared"]["pixels"]}
    assert py["flip"] == cli["flip"]


@pytest.mark.parametrize("quantity", ["radiance", "ldr", "ao"])
def test_compare_equals_cli_compare(tmp_path, quantity):
    rng = np.random.default_rng(27)
    ref = (rng.random((24, 40, 3)) * 3).astype(np.float32)
    if quantity != "radiance":
        ref = np.clip(ref / 3, 0, 1).astype(np.float32)
    img = (ref + rng.normal(0, 0.05, ref.shape)).astype(np.float32)
    if quantity != "radiance":
        img = np.clip(img, 0, 1).astype(np.float32)
    write_pfm(tmp_path / "img.pfm", img)
    write_pfm(tmp_path / "ref.pfm", ref)
    mask = np.zeros(ref.shape[:2], np.float32)
    mask[3:20, 5:31] = 1
    write_pfm(tmp_path / "mask.pfm", np.repeat(mask[..., None], 3, axis=2))
    for with_mask in (False, True):
        args = ["--compare", str(tmp_path / "img.pfm"), str(tmp_path / "ref.pfm"), "--quantity", quantity,
                "--out", str(tmp_path / "out")]
        if with_mask:
            args += ["--mask", str(tmp_path / "mask.pfm")]
        bench(*args)
        cli = json.loads((tmp_path / "out" / "compare.json").read_text())
        py = rtgi.compare(img, ref, mask=mask if with_mask else None, quantity=quantity)
        check_same_metrics(py, cli)
        if with_mask:
            assert py["compared"]["compared_pixels"] == int(mask.sum())
    # The oracle itself: an image against itself has no error.
    same = rtgi.compare(ref, ref, quantity=quantity)
    assert same["rmse"] == 0 and same["mae"] == 0


def test_compare_errors_are_the_clis():
    a = np.zeros((8, 8, 3), np.float32)
    with pytest.raises(ValueError) as e:
        rtgi.compare(a, np.zeros((8, 9, 3), np.float32))
    assert "is 8x8 but" in str(e.value)
    with pytest.raises(ValueError) as e:
        rtgi.compare(a, a, quantity="hdr")
    assert str(e.value) == "--quantity 'hdr': expected auto|ao|ldr|radiance"
    with pytest.raises(ValueError) as e:
        rtgi.compare(a, a, mask=np.zeros((8, 8), np.float32))
    assert "the mask leaves no pixel to compare" in str(e.value)


# --------------------------------------------------------------------------
# sweep: the rows of rtgi-bench --sweep.

SWEEP = {
    "name": "pytest-sweep",
    "scenes": [SCENE],
    "resolutions": ["32x24"],
    "frames": 1,
    "warmup": 0,
    "base": {"lpv": "on", "ao": "off", "ssr": "off", "shadow.size": 256},
    "axes": [{"lpv.grid": [8, 16]}, {"lpv.iterations": [2, 4]}],
}

# Measured, so different from run to run: GPU times and wall-clock seconds.
def comparable(row):
    row = json.loads(json.dumps(row))
    for k in ("total_ms", "wall_s", "command_line"):
        row.pop(k, None)
    for p in row.get("passes", []):
        p.pop("gpu_ms")
    return row


def test_sweep_yields_the_rows_of_cli_sweep(tmp_path):
    spec_path = tmp_path / "sweep.json"
    spec_path.write_text(json.dumps(SWEEP))
    bench("--sweep", str(spec_path), "--out", str(tmp_path / "cli"))
    cli = [json.loads(l) for l in (tmp_path / "cli" / "results.jsonl").read_text().splitlines()]
    assert len(cli) == 4 and not any("failed" in r for r in cli)
    seen = []
    rows = list(rtgi.sweep(SWEEP, progress=lambda done, total, row: seen.append((done, total, row["sweep"]["id"]))))
    assert [comparable(r) for r in rows] == [comparable(r) for r in cli]
    assert seen == [(k + 1, 4, r["sweep"]["id"]) for k, r in enumerate(cli)]
    # From the file, in two shards: the CLI's shards, together the whole sweep.
    for i in range(2):
        bench("--sweep", str(spec_path), "--shard", "%d/2" % i, "--out", str(tmp_path / ("shard%d" % i)))
        part = [json.loads(l) for l in (tmp_path / ("shard%d" % i) / "results.jsonl").read_text().splitlines()]
        mine = list(rtgi.sweep(spec_path, shard="%d/2" % i))
        assert [comparable(r) for r in mine] == [comparable(r) for r in part]
    assert rtgi._rtgi.context_users() == 0
    # A bad sweep raises the CLI's sentence.
    bad = dict(SWEEP, axes=[{"lpv.grid": [0]}])
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    rc, sentence = bench_error("--sweep", str(tmp_path / "bad.json"), "--out", str(tmp_path / "bad"))
    assert rc == 2
    with pytest.raises(ValueError) as e:
        list(rtgi.sweep(tmp_path / "bad.json"))
    assert str(e.value) == sentence


# --------------------------------------------------------------------------
# Reference and GL errors.

def test_reference_equals_bench_reference_files(tmp_path):
    """r.reference() traces what --reference traces (same settings, same seed:
    the same bits, without the cache), and render(reference=True) gives
    --reference's error."""
    sets = {"ao": "gtao", "reference.cache": "off", "reference.spp": 16}
    out = tmp_path / "bench"
    bench("--scene", SCENE, "--res", "%dx%d" % RES, "--frames", "1", "--warmup", "0", "--reference",
          *[a for k, v in sets.items() for a in ("--set", "%s=%s" % (k, v))], "--out", str(out))
    cli = json.loads((out / "results.json").read_text())
    assert cli["error"]["kind"] == "ao"
    with rtgi.Renderer(scenes=[SCENE], resolution=RES, settings=sets) as r:
        ref = r.reference(kind="ao", spp=16)
        assert ref.image.shape == (RES[1], RES[0], 1) and ref.info["spp"] == 16
        assert same_bits(ref.image, read_pfm(out / "reference.pfm")[..., :1].copy())
        assert same_bits(ref.stderr, read_pfm(out / "reference.stderr.pfm")[..., :1].copy())
        res = r.render(frames=1, warmup=0, reference=True)
    for k in ("rmse", "mae", "ssim", "rmse_debiased", "skill"):
        assert res.error[k] == cli["error"][k], k
    assert res.error["rmse"] > 0


def test_shader_error_raises_gl_error_and_the_interpreter_goes_on(tmp_path, monkeypatch):
    broken = tmp_path / "data" / "compute" / "post"
    broken.mkdir(parents=True)
    (broken / "compose.comp").write_text("#version 450 core\nthis is not glsl;\n")
    monkeypatch.setenv("RTGI_DATA_DIR", str(tmp_path / "data"))
    rc, _, err = bench("--scene", SCENE, "--res", "16x16", "--frames", "1", "--warmup", "0", "--no-images",
                       "--out", str(tmp_path / "out"), check=False)
    assert rc == 4
    sentence = err.strip().splitlines()[0][len("rtgi-bench: "):]
    with pytest.raises(RuntimeError) as e:
        with rtgi.Renderer(scenes=[SCENE], resolution=(16, 16)) as r:
            r.render(frames=1, warmup=0)
    assert isinstance(e.value, rtgi.GLError) and str(e.value) == sentence
    assert rtgi._rtgi.context_users() == 0
    monkeypatch.delenv("RTGI_DATA_DIR")
    with rtgi.Renderer(scenes=[SCENE], resolution=(16, 16)) as r:  # the process renders on
        assert r.render(frames=1, warmup=0).images["hdr"].shape == (16, 16, 3)
