"""tests/python/test_aquarelle.py — the Python module (docs/python.md): shapes and dtypes, zero
copy and lifetimes, errors, determinism across threads, equality with the CLI, G-buffers from
arrays, reference counts over many runs."""
import gc
import json
import os
import subprocess

import numpy as np
import pytest
from PIL import Image

import aquarelle as aq
from conftest import BIN, BOTTLE, BUSH, OAK

W, H = 160, 96


@pytest.fixture(scope="module")
def bottle():
    return aq.load_scene(BOTTLE)


@pytest.fixture(scope="module")
def gb(bottle):
    return aq.rasterize(bottle, W, H, threads=2)


def png_pixels(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.uint8)


def as_png_codes(img):
    """The 8-bit codes a PNG of this display-encoded image holds (to_unorm8: round half up)."""
    return np.floor(np.clip(img, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def cli(*args):
    # The CLI runs as itself: under the sanitizer run the interpreter has the ASan runtime
    # preloaded, which an instrumented CLI must not get twice.
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    r = subprocess.run([BIN, *args, "--quiet"], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    return r


# --- shapes, dtypes, zero copy ------------------------------------------------------------------

def test_gbuffer_targets_are_float32_views(gb):
    for name, c in [("color", 4), ("depth.linear", 1), ("normal", 3), ("object_id", 1), ("ctrl.pigment", 4)]:
        a = gb[name]
        assert a.dtype == np.float32 and a.shape == (H, W, c), name
        assert not a.flags.writeable and not a.flags.owndata
    assert gb.width == W and gb.height == H and len(gb) == len(gb.keys()) >= 10
    assert "depth.linear" in gb and "nope" not in gb
    with pytest.raises(KeyError):
        gb["nope"]


def test_views_share_the_targets_memory(gb):
    a, b = gb["depth.linear"], gb["depth.linear"]
    assert np.shares_memory(a, b)
    assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
    with pytest.raises(ValueError):
        a[0, 0, 0] = 1.0  # read-only: the library's memory


def test_a_run_gives_every_target_and_the_final_image(gb):
    out = aq.style("wc18").run(gb)
    final = out["final"]
    assert final.dtype == np.float32 and final.shape == (H, W, 3)
    assert np.isfinite(final).all() and final.min() >= 0.0
    steps = [s["id"] for s in aq.style("wc18").steps()]
    assert len(out.step_ms) == len(steps)
    assert "final" in out and len(out) > 3
    assert np.shares_memory(out["final"], out["final"])


def test_arrays_outlive_their_owners(bottle):
    g = aq.rasterize(bottle, W, H, threads=1)
    depth = g["depth.linear"]
    out = aq.style("wc18").run(g)
    final = out["final"]
    keep_depth, keep_final = depth.copy(), final.copy()
    del g, out
    gc.collect()
    junk = [np.ones((H, W, 4), np.float32) * k for k in range(20)]  # reuse freed memory if it were freed
    assert np.array_equal(depth, keep_depth) and np.array_equal(final, keep_final)
    del junk


# --- the same as the CLI ----------------------------------------------------------------------

def test_render_writes_the_clis_bytes_manifest_included(bottle, tmp_path):
    st = aq.style("wc18").with_params({"edge_darken.intensity": 2.5}).with_variant("bleed", "naive")
    (tmp_path / "py").mkdir()
    (tmp_path / "cli").mkdir()
    aq.render(bottle, str(tmp_path / "py" / "x.png"), style=st, width=W, height=H, threads=2)
    cli("render", BOTTLE, "--style", "wc18", "--set", "edge_darken.intensity=2.5", "--variant", "bleed=naive",
        "--width", str(W), "--height", str(H), "--out", str(tmp_path / "cli" / "x.png"))
    for f in ("x.png", "x.png.json"):  # the image with its embedded manifest, and the sidecar
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    r = cli("reproduce", str(tmp_path / "py" / "x.png.json"))
    assert "identical" in r.stdout


def test_a_style_run_has_the_clis_pixels(gb, tmp_path):
    st = aq.style("wc18").with_params({"edge_darken.intensity": 2.0})
    final = st.run(gb)["final"]
    cli("render", BOTTLE, "--set", "edge_darken.intensity=2", "--width", str(W), "--height", str(H), "--out", str(tmp_path / "c.png"))
    assert np.array_equal(as_png_codes(final), png_pixels(tmp_path / "c.png"))
    aq.save(str(tmp_path / "s.png"), np.ascontiguousarray(final))
    assert np.array_equal(png_pixels(tmp_path / "s.png"), png_pixels(tmp_path / "c.png"))


def test_ld06_on_a_plant_has_the_clis_pixels(tmp_path):
    bush = aq.load_scene(BUSH)
    g = aq.rasterize(bush, 128, 128, style="ld06", threads=2)
    final = aq.style("ld06").with_params({"wash.kappa": 0.5}).run(g)["final"]
    cli("render", BUSH, "--style", "ld06", "--set", "wash.kappa=0.5", "--width", "128", "--height", "128", "--out", str(tmp_path / "b.png"))
    assert np.array_equal(as_png_codes(final), png_pixels(tmp_path / "b.png"))


def test_scene_edits_are_the_clis_scene_set(tmp_path):
    oak = aq.load_scene(OAK, edits={"/layers/1/color": [0.8, 0.3, 0.2]})
    assert oak.edits == {"/layers/1/color": [0.8, 0.3, 0.2]}
    assert any(v["pointer"] == "/foliage/T" for v in oak.values())
    (tmp_path / "py").mkdir()
    (tmp_path / "cli").mkdir()
    aq.render(oak, str(tmp_path / "py" / "e.png"), width=96, height=96)
    cli("render", OAK, "--scene-set", "/layers/1/color=[0.8,0.3,0.2]", "--width", "96", "--height", "96", "--out", str(tmp_path / "cli" / "e.png"))
    assert (tmp_path / "py" / "e.png").read_bytes() == (tmp_path / "cli" / "e.png").read_bytes()


def test_the_same_bytes_at_any_thread_count(bottle):
    st = aq.style("wc18")
    one = st.run(aq.rasterize(bottle, W, H, threads=1), threads=1)["final"].copy()
    two = st.run(aq.rasterize(bottle, W, H, threads=2), threads=2)["final"]
    assert np.array_equal(one, two)


# --- G-buffers from arrays ------------------------------------------------------------------

def arrays_of(gb):
    return {k: np.array(gb[k]) for k in gb.keys()}


def test_a_gbuffer_from_arrays_runs_a_style(gb):
    mine = aq.GBuffer.from_arrays(arrays_of(gb))
    assert sorted(mine.keys()) == sorted(gb.keys())
    out = aq.style("wc17").run(mine)
    assert out["final"].shape == (H, W, 3)
    # strided and negative-stride inputs are copied: the same image as contiguous ones
    flipped = {k: np.ascontiguousarray(v[::-1])[::-1] for k, v in arrays_of(gb).items()}
    strided = {k: np.repeat(v, 2, axis=1)[:, ::2] for k, v in arrays_of(gb).items()}
    a = aq.style("wc17").run(aq.GBuffer.from_arrays(flipped))["final"]
    b = aq.style("wc17").run(aq.GBuffer.from_arrays(strided))["final"]
    assert np.array_equal(a, out["final"]) and np.array_equal(b, out["final"])
    with pytest.raises(aq.Error, match="raster passes"):
        aq.style("ld06").run(mine)


@pytest.mark.parametrize("bad, message", [
    ({"color": np.zeros((8, 8, 4), np.float64)}, "float32"),
    ({"color": np.zeros((8, 8, 3), np.float32)}, "4 channel"),
    ({"color": np.zeros((8, 8, 4, 1), np.float32)}, "dimensions"),
    ({"color": np.zeros((0, 8, 4), np.float32)}, "empty"),
    ({"color": np.full((8, 8, 4), np.nan, np.float32)}, "non-finite"),
    ({"color": np.full((8, 8, 4), np.inf, np.float32)}, "non-finite"),
    ({"colour": np.zeros((8, 8, 4), np.float32)}, "not a G-buffer target"),
    ({"color": np.zeros((8, 8, 4), np.float32), "depth.linear": np.zeros((9, 8, 1), np.float32)}, "the other targets"),
    ({}, "no targets"),
])
def test_bad_arrays_are_clear_errors(bad, message):
    with pytest.raises(aq.Error, match=message):
        aq.GBuffer.from_arrays(bad)


def test_huge_arrays_are_refused_before_copying():
    huge = np.lib.stride_tricks.as_strided(np.zeros(1, np.float32), shape=(20000, 20000, 4), strides=(0, 0, 0))
    with pytest.raises(aq.Error, match="larger than"):
        aq.GBuffer.from_arrays({"color": huge})


def test_named_parameter_values_are_the_numbers_they_name(gb):
    named = aq.style("wc18").with_params({"edge_detect.border": "mirror"})
    numbered = aq.style("wc18").with_params({"edge_detect.border": 1})
    assert np.array_equal(named.run(gb)["final"], numbered.run(gb)["final"])
    with pytest.raises(aq.Error, match="clamp, mirror"):
        aq.style("wc18").with_params({"edge_detect.border": "wrap"})
    border = next(p for s in aq.stages() if s["stage"] == "edge_detect" for p in s["params"] if p["name"] == "border")
    assert border["names"] == ["clamp", "mirror"] and border["kind"] == "int"


# --- errors ----------------------------------------------------------------------------------

def test_errors_carry_the_librarys_messages(gb):
    with pytest.raises(aq.Error, match="not found"):
        aq.load_scene("/nonexistent/scene.gltf")
    with pytest.raises(aq.Error, match="nope"):
        aq.style("nope")
    with pytest.raises(aq.Error, match=r"outside \[0, 50\]"):
        aq.style("wc18").with_params({"edge_darken.intensity": 999})
    with pytest.raises(aq.Error, match="unknown"):
        aq.style("wc18").with_params({"edge_darken.nope": 1})
    with pytest.raises(aq.Error, match="finite"):
        aq.style("wc18").with_params({"edge_darken.intensity": float("nan")})
    with pytest.raises(aq.Error):
        aq.style("wc18").with_variant("bleed", "nope")
    with pytest.raises(aq.Error, match="not an editable value"):
        aq.load_scene(OAK, edits={"/gltf": 1})
    with pytest.raises(aq.Error, match="width and height"):
        aq.rasterize(aq.load_scene("procedural:swatches"), 100000, 10)
    with pytest.raises(aq.Error, match="view"):
        aq.rasterize(aq.load_scene("procedural:swatches"), 32, 32, view=[0, 100, 1])
    assert issubclass(aq.Error, RuntimeError)


# --- the registry, compare, save ---------------------------------------------------------------

def test_the_registry():
    st = aq.stages()
    bleed = [s for s in st if s["stage"] == "bleed"]
    assert len(bleed) >= 2
    for s in st:
        for p in s["params"]:
            assert p["min"] <= p["default"] <= p["max"], (s["stage"], p["name"])
            assert p["kind"] in ("float", "int", "bool") and p["doc"]
    assert {"wc18", "wc17", "wc16", "mnpr", "ld06"} <= set(aq.styles())


def test_compare_and_save(gb, tmp_path):
    a = aq.style("wc18").run(gb)["final"]
    b = aq.style("wc18").with_params({"edge_darken.intensity": 3.0}).run(gb)["final"]
    same = aq.compare(a, a)
    assert same["max_abs"] == 0 and same["mean_abs"] == 0
    diff = aq.compare(a, b)
    assert diff["max_abs"] > 0 and 0 < diff["frac_over"] <= 1
    with pytest.raises(aq.Error, match="compare"):
        aq.compare(a, a[:10])
    aq.save(str(tmp_path / "x.png"), a)
    assert png_pixels(tmp_path / "x.png").shape == (H, W, 3)
    with pytest.raises(aq.Error):
        aq.save(str(tmp_path / "no_such_dir" / "x.png"), a)


# --- reference counts --------------------------------------------------------------------------

def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024


def test_no_leak_over_a_thousand_runs(bottle):
    import sys
    g = aq.rasterize(bottle, 64, 40, threads=2)
    st = aq.style("wc17")
    refs = sys.getrefcount(g)
    for _ in range(50):  # warm up: the style's job, the image pool
        st.run(g)["final"]
    before = rss_mb()
    for i in range(1000):
        out = st.run(g)
        f = out["final"]
        assert f.shape == (40, 64, 3)
    del out, f
    gc.collect()
    assert sys.getrefcount(g) == refs
    # Under AddressSanitizer (tests/python/sanitize.sh) freed memory sits in its quarantine: there
    # the sanitizer checks the lifetimes and leaks, here the resident memory.
    if not os.environ.get("AQ_SANITIZER"):
        assert rss_mb() - before < 40, "memory grew by %.0f MB over 1000 runs" % (rss_mb() - before)


# --- a stage prototyped in Python --------------------------------------------------------------

def posterize(inputs, params):
    c = inputs["color"]
    k = params["levels"]
    out = np.floor(c * k) / k
    out[..., 3] = c[..., 3]
    return {"color": out.astype(np.float32)}


def test_a_python_stage_runs_between_cpp_stages(gb):
    aq.register_stage("py_posterize", posterize, inputs=[("color", 4)], outputs=[("color", 4)],
                      params={"levels": (4.0, 2.0, 32.0, "levels per channel")}, doc="posterize (a test)")
    st = aq.style("wc18").with_step("py_posterize", after="edge_darken", params={"levels": 3.0})
    ids = [s["id"] for s in st.steps()]
    assert ids[ids.index("edge_darken") + 1] == "py_posterize"
    out = st.run(gb)
    # the stage saw edge darkening's output and the steps after it read the stage's
    want = posterize({"color": np.array(out["color.darkened"])}, {"levels": 3.0})["color"]
    assert np.array_equal(out["py_posterize.color"], want)
    plain = aq.style("wc18").run(gb)["final"]
    assert aq.compare(out["final"], plain)["max_abs"] > 0
    # the same run twice: the same image
    assert np.array_equal(st.run(gb)["final"], out["final"])
    # parameters are checked against the declared range
    with pytest.raises(aq.Error, match="levels"):
        aq.style("wc18").with_step("py_posterize", after="edge_darken", params={"levels": 100.0})
    with pytest.raises(aq.Error, match="no stage 'nope' registered"):
        aq.style("wc18").with_step("nope", after="edge_darken")
    with pytest.raises(aq.Error, match="no step"):
        aq.style("wc18").with_step("py_posterize", after="nope")
    with pytest.raises(aq.Error, match="manifest"):
        aq.render(aq.load_scene(BOTTLE), "never.png", style=st)


def raises(inputs, params):
    raise ValueError("a prototype's bug")


def wrong_shape(inputs, params):
    return {"color": np.zeros((3, 3, 4), np.float32)}


def wrong_type(inputs, params):
    return [1, 2]


kept = []


def keeps_its_input(inputs, params):
    kept.append(inputs["color"])
    return {"color": inputs["color"]}


@pytest.mark.parametrize("fn, message", [(raises, "a prototype's bug"), (wrong_shape, "3 x 3"), (wrong_type, "expected a dict")])
def test_a_bad_python_stage_is_a_clear_error(gb, fn, message):
    aq.register_stage("py_bad", fn, inputs=[("color", 4)], outputs=[("color", 4)])
    with pytest.raises(aq.Error, match=message):
        aq.style("wc18").with_step("py_bad", after="edge_darken").run(gb)
    assert aq.style("wc18").run(gb)["final"].shape == (H, W, 3)  # the G-buffer is intact


def test_a_python_stage_may_keep_its_input(gb):
    aq.register_stage("py_keep", keeps_its_input, inputs=[("color", 4)], outputs=[("color", 4)])
    st = aq.style("wc18").with_step("py_keep", after="edge_darken")
    a = st.run(gb)["final"].copy()
    assert np.array_equal(a, aq.style("wc18").run(gb)["final"])  # an identity stage changes nothing
    kept[0][:] = 7.0  # its copy: the library's images are untouched
    assert np.array_equal(st.run(gb)["final"], a)
    with pytest.raises(aq.Error, match="built-in"):
        aq.register_stage("bleed", posterize, inputs=[("color", 4)], outputs=[("color", 4)])


def test_coherence_of_two_frames(bottle, tmp_path):
    st = aq.style("wc18")
    g0 = aq.rasterize(bottle, W, H, threads=2, view=[0, 0, 1])
    g1 = aq.rasterize(bottle, W, H, threads=2, view=[2, 0, 1])
    i0, i1 = st.run(g0)["final"], st.run(g1)["final"]
    same = aq.coherence(g0, i0, g0, i0)
    assert same["static_mean"] == 0 and same["warp_mean"] < 1e-9 and same["static_pixels"] == W * H  # reprojection: rounding only
    moved = aq.coherence(g0, i0, g1, i1)
    assert 0 < moved["warped_pixels"] <= moved["object_pixels"] <= W * H
    assert moved["static_pixels"] < W * H and 0 <= moved["warp_changed"] <= 1
    with pytest.raises(aq.Error, match="rasterize"):
        aq.coherence(aq.GBuffer.from_arrays({k: np.array(g0[k]) for k in g0.keys()}), i0, g1, i1)
    # the files of a --frames run, as `aquarelle coherence` reads them
    cli("render", BOTTLE, "--frames", "0-2", "--orbit", "2", "--width", "64", "--height", "40", "--targets", str(tmp_path / "t"),
        "--out", str(tmp_path / "f_####.png"))
    report = aq.coherence_report([str(tmp_path / ("f_%04d.png" % k)) for k in range(3)], str(tmp_path / "t"))
    assert "total" in report
