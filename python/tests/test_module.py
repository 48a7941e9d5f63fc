"""Tests of the Python module: the same runs as the Rust crate, typed errors
as exceptions, the grading rule, and validate with a Python candidate."""

import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import granular_automata as ga

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python" / "examples"))


def golden_series(name):
    """The bin series of golden/NAME.snap (tests/pipe_engine.rs)."""
    lines = (ROOT / "golden" / f"{name}.snap").read_text().split("---\n", 2)[2].splitlines()
    rows = [list(map(float, line.split())) for line in lines if line and not line.startswith("rules")]
    return np.array(rows)


def test_a_run_is_the_crates_run_byte_for_byte():
    # tests/pipe_engine.rs: W = 5, L = 60, p = 0.5, seed 20261125, 20 x 25 steps
    pipe = ga.Pipe(width=5, length=60, p=0.5, seed=20_261_125)
    rows = []
    for _ in range(20):
        pipe.run(25)
        rows.append(pipe.bin_counts())
    assert np.array_equal(np.array(rows), golden_series("pipe_bin_series_default"))
    assert pipe.time == 500
    # the fast engine draws otherwise; it conserves the particles too
    fast = ga.Pipe(width=5, length=60, p=0.5, seed=1, engine="fast")
    n = fast.particle_count()
    fast.run(300)
    assert fast.particle_count() == n and fast.engine == "fast"


def test_the_state_is_a_numpy_array_and_can_be_set():
    pipe = ga.Pipe(width=3, length=10, rho=0.5, g=0.0, p=0.0, b=0.0)
    state = pipe.state()
    assert state.shape == (3, 10) and state.dtype == np.uint8
    state[:] = 0
    state[1, 5] = 1 << 4  # a down-mover
    pipe.set_state(state)
    pipe.step()
    assert pipe.site(1, 4) == 1 << 4
    assert list(pipe.channel_counts()) == [0, 0, 0, 0, 1, 0, 0]
    assert pipe.bin_counts().sum() == 1


def test_bad_input_raises_the_typed_error_as_an_exception():
    with pytest.raises(ValueError, match="p"):
        ga.Pipe(p=1.5)
    with pytest.raises(ValueError, match="rules"):
        ga.Pipe(rules="nonsense")
    with pytest.raises(ValueError, match="outside"):
        ga.Pipe(width=3, length=10).site(3, 0)
    with pytest.raises(ValueError, match="shape"):
        ga.Pipe(width=3, length=10).set_state(np.zeros((2, 10), dtype=np.uint8))
    with pytest.raises(ValueError, match="0..=127"):
        ga.Pipe(width=3, length=10).set_site(0, 0, 200)
    with pytest.raises(ValueError, match="inject"):
        ga.Pipe(boundary="open")
    with pytest.raises(ValueError, match="tier"):
        ga.spectrum_ensemble(tier="fast")


def test_the_open_pipe_keeps_its_books():
    pipe = ga.Pipe(width=5, length=60, boundary="open", inject=0.5, seed=3)
    pipe.run(500)
    injected, out_bottom, out_top = pipe.flux()
    assert pipe.particle_count() == injected - out_bottom - out_top
    assert injected > 0


def test_the_spectrum_and_the_fit_are_the_figures():
    series = ga.bin_series(seed=5, tier="quick", length=220)
    assert series.shape == (4 * 4 * 4096,)
    p = ga.spectrum(series, m=4096, k=4)
    assert p.shape == (4096,)
    fit = ga.fit_alpha(p)
    assert 0.0 < fit["alpha"] < 3.0 and fit["alpha_err"] > 0
    with pytest.raises(ValueError):
        ga.spectrum(series, m=1000)


def test_the_ensemble_is_fig2s_ensemble():
    """One quick-tier run: the numbers fig2 writes for the same seed."""
    exe = ROOT / "target" / "release" / "fig2"
    if not exe.exists():
        pytest.skip("target/release/fig2 not built")
    out = pathlib.Path(os.environ.get("TMPDIR", "/tmp")) / "ga-pytest-fig2"
    subprocess.run(
        [str(exe), "--tier", "quick", "--seed", "7", "--runs", "1", "--out", str(out)],
        check=True, capture_output=True,
    )
    metrics = json.loads((out / "fig2" / "summary.json").read_text())["metrics"]
    ens = ga.spectrum_ensemble(tier="quick", seed=7, runs=1)
    assert ens["alpha"] == metrics["alpha"]
    assert ens["v_peak"] == metrics["v_peak"]
    assert ens["spectra"].shape == (1, 4096)


def test_the_grading_rule_and_the_claims():
    assert ga.grade(1.30, 0.01, 10, target=1.33, margin=0.059) == "reproduced"
    assert ga.grade(1.00, 0.01, 10, target=1.33, margin=0.059) == "not-reproduced"
    assert ga.grade(1.30, 0.01, 2, target=1.33, margin=0.059) == "undecided"
    assert ga.grade(0.5, 0.1, 10, above=0.0) == "reproduced"
    with pytest.raises(ValueError):
        ga.grade(1.0, 0.1, 10)
    claims, margins = ga.claims()
    assert len(claims) >= 39 and claims[0][0] == "waves_1a"
    assert any(m["figure"] == "fig2" and m["check"] == "alpha" for m in margins)


def test_the_hopper_fills():
    h = ga.Hopper(seed=2)
    h.fill(50)
    assert h.grains() >= 50
    assert h.sites().dtype == np.uint8
    params = json.loads(ga.Hopper.default_params())
    assert "geometry" in params


def test_validate_passes_the_fast_engine_and_fails_a_mutant():
    report = ga.validate("fast", level="1")
    assert report["pass"] is True
    report = ga.validate("mutant:r1-same-side", level="1")
    assert report["pass"] is False


def test_a_numpy_engine_passes_level_1_and_a_wrong_one_fails():
    from numpy_engine import NumpyPipe, WrongPipe

    good = ga.validate(NumpyPipe, level="1", name="numpy")
    assert good["pass"] is True, good["level1"]
    wrong = ga.validate(WrongPipe, level="1", name="wrong")
    assert wrong["pass"] is False


def test_an_exception_of_the_candidate_is_raised_again():
    def broken(params, rules, seed):
        raise ZeroDivisionError("the candidate broke")

    with pytest.raises(ZeroDivisionError, match="broke"):
        ga.validate(broken, level="1")


def test_a_long_run_releases_the_gil_and_stops_on_ctrl_c():
    """In a process of its own (bounded by a timeout): another thread keeps
    running while the engine steps, then sends SIGINT, as Ctrl-C does."""
    script = """
import os, signal, threading, time
import granular_automata as ga
# as in an interactive Python (a shell's background job starts with SIGINT ignored)
signal.signal(signal.SIGINT, signal.default_int_handler)
ticks = []
def other():
    for _ in range(5):
        ticks.append(time.monotonic())
        time.sleep(0.05)
    os.kill(os.getpid(), signal.SIGINT)
pipe = ga.Pipe(seed=4)
threading.Thread(target=other).start()
try:
    pipe.run(10**9)
except KeyboardInterrupt:
    print("interrupted", len(ticks), pipe.time)
"""
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    word, ticks, steps = done.stdout.split()
    assert word == "interrupted" and ticks == "5" and 0 < int(steps) < 10**9
