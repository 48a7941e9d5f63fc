//! The Python module `granular_automata`: the crate's engines, spectra,
//! grading and `validate`, called from Python (python/README.md). Every
//! function calls the library's own code, so a run from Python is the run of
//! the binaries, byte for byte.

use ga::analysis::grading::{grade as grade_rule, Claim, Estimate};
use ga::analysis::spectrum::{spctrm, SpectrumParams, Window};
use ga::drivers::spectra::{bin_series_until, bin_spectrum_until, combine, tier_setup};
use ga::hopper::engine::{HopperBuilder, HopperEngine};
use ga::hopper::model::HopperParams;
use ga::pipe::engine::PipeEngine;
use ga::pipe::{Boundary, Engine, Params, Rules};
use ga::run::{ensemble_with_threads, run_seeds, Tier};
use ga::validate::candidate::{Candidate, RunPlan, Sample};
use ga::{Error, ErrorKind};
use granular_automata as ga;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// The library's typed error as a Python exception carrying its message:
/// ValueError for a value out of range, OSError for input or output,
/// KeyboardInterrupt for a stopped run, RuntimeError otherwise.
fn py_err(e: Error) -> PyErr {
    match e.kind {
        ErrorKind::InvalidParameter => PyValueError::new_err(e.message),
        ErrorKind::Io => PyOSError::new_err(e.message),
        ErrorKind::Interrupted => PyKeyboardInterrupt::new_err(e.message),
        _ => PyRuntimeError::new_err(e.message),
    }
}

/// A tier by name.
fn tier(name: &str) -> PyResult<Tier> {
    let tiers = [
        ("quick", Tier::Quick),
        ("standard", Tier::Standard),
        ("paper", Tier::Paper),
        ("acceptance", Tier::Acceptance),
    ];
    named(
        "tier",
        name,
        &tiers,
        "one of quick, standard, paper, acceptance",
    )
}

/// The value that `table` gives the name `name`; otherwise a ValueError
/// naming `what`, `name` and the `names` to use instead.
fn named<T: Copy>(what: &str, name: &str, table: &[(&str, T)], names: &str) -> PyResult<T> {
    match table.iter().find(|(n, _)| *n == name) {
        Some(&(_, v)) => Ok(v),
        None => Err(PyValueError::new_err(format!(
            "{what} '{name}': use {names}"
        ))),
    }
}

/// An engine by name.
fn engine_named(name: &str) -> PyResult<Engine> {
    name.parse().map_err(py_err)
}

/// The pipe's parameters from keyword values, validated.
#[allow(clippy::too_many_arguments)]
fn params_of(
    width: usize,
    length: usize,
    rho: f64,
    p: f64,
    g: f64,
    b: f64,
    bin: usize,
    boundary: &str,
    inject: Option<f64>,
) -> PyResult<Params> {
    let boundary =
        match (boundary, inject) {
            ("periodic", None) => Boundary::Periodic,
            ("open", Some(inject)) => Boundary::Open { inject },
            ("open", None) => {
                return Err(PyValueError::new_err(
                    "boundary 'open' needs inject, the injection probability I in [0, 1]",
                ))
            }
            ("periodic", Some(_)) => return Err(PyValueError::new_err(
                "inject is the open pipe's injection probability; drop it or use boundary='open'",
            )),
            (other, _) => {
                return Err(PyValueError::new_err(format!(
                    "boundary '{other}': use 'periodic' or 'open'"
                )))
            }
        };
    let params = Params {
        width,
        length,
        rho,
        p,
        g,
        b,
        bin,
        boundary,
    };
    params.validate().map_err(py_err)?;
    Ok(params)
}

/// The parameters as a dict (the keywords of `Pipe`).
fn params_dict<'py>(py: Python<'py>, p: &Params) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("width", p.width)?;
    d.set_item("length", p.length)?;
    d.set_item("rho", p.rho)?;
    d.set_item("p", p.p)?;
    d.set_item("g", p.g)?;
    d.set_item("b", p.b)?;
    d.set_item("bin", p.bin)?;
    match p.boundary {
        Boundary::Periodic => d.set_item("boundary", "periodic")?,
        Boundary::Open { inject } => {
            d.set_item("boundary", "open")?;
            d.set_item("inject", inject)?;
        }
    }
    Ok(d)
}

/// A JSON value of the library as Python objects.
fn from_json(py: Python<'_>, value: &impl serde::Serialize) -> PyResult<PyObject> {
    let text = serde_json::to_string(value).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// Run `work` without the GIL on a thread of its own while this thread
/// watches for Ctrl-C; on Ctrl-C `stop` is set and the work, which checks
/// it, ends with an interrupted error.
fn interruptible<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    work: impl FnOnce() -> ga::Result<T> + Send,
) -> PyResult<T> {
    std::thread::scope(|s| {
        let handle = s.spawn(work);
        loop {
            py.allow_threads(|| std::thread::sleep(Duration::from_millis(50)));
            if handle.is_finished() {
                break;
            }
            if let Err(e) = py.check_signals() {
                stop.store(true, Ordering::Relaxed);
                let _ = handle.join();
                return Err(e);
            }
        }
        match handle.join() {
            Ok(r) => r.map_err(py_err),
            Err(_) => Err(PyRuntimeError::new_err("the run stopped unexpectedly")),
        }
    })
}

/// One run of the pipe lattice gas (MODEL.md Part A) with the reference or
/// the fast engine.
#[pyclass(name = "Pipe", module = "granular_automata")]
struct PyPipe {
    /// The run (a mutex: a Python object may be shared between threads).
    engine: Mutex<Box<dyn PipeEngine>>,
    name: String,
}

impl PyPipe {
    /// The run, for reading.
    fn e(&self) -> std::sync::MutexGuard<'_, Box<dyn PipeEngine>> {
        self.engine.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The run, for changing.
    fn m(&mut self) -> &mut Box<dyn PipeEngine> {
        self.engine.get_mut().unwrap_or_else(|p| p.into_inner())
    }

    fn check_site(&self, x: usize, y: usize) -> PyResult<()> {
        let e = self.e();
        let p = e.params();
        if x >= p.width || y >= p.length {
            return Err(PyValueError::new_err(format!(
                "site ({x}, {y}) is outside the {} x {} pipe (x < W, y < L)",
                p.width, p.length
            )));
        }
        Ok(())
    }
}

#[pymethods]
impl PyPipe {
    /// A new run: the pipe (PH94 Fig. 2's by default), a rule reading, a
    /// seed and an engine (`reference` or `fast`).
    #[new]
    #[pyo3(signature = (width=11, length=220, rho=1.0, p=0.5, g=0.5, b=0.5, bin=10, boundary="periodic", inject=None, rules="default", seed=1, engine="reference"))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        width: usize,
        length: usize,
        rho: f64,
        p: f64,
        g: f64,
        b: f64,
        bin: usize,
        boundary: &str,
        inject: Option<f64>,
        rules: &str,
        seed: u64,
        engine: &str,
    ) -> PyResult<Self> {
        let params = params_of(width, length, rho, p, g, b, bin, boundary, inject)?;
        let rules: Rules = rules.parse().map_err(py_err)?;
        let e = engine_named(engine)?;
        Ok(PyPipe {
            engine: Mutex::new(e.build(params, rules, seed).map_err(py_err)?),
            name: e.to_string(),
        })
    }

    /// One time step (MODEL.md A2).
    fn step(&mut self) -> PyResult<()> {
        self.m().step().map_err(py_err)
    }

    /// Advance `steps` steps without the GIL; Ctrl-C stops between blocks
    /// of 10000 steps.
    fn run(&mut self, py: Python<'_>, steps: u64) -> PyResult<()> {
        if steps > ga::run::MAX_STEPS {
            return Err(PyValueError::new_err(format!(
                "steps = {steps}: at most {} in one call (every binary's cap, ga::run::MAX_STEPS)",
                ga::run::MAX_STEPS
            )));
        }
        let mut left = steps;
        while left > 0 {
            let n = left.min(10_000);
            let engine = self.m();
            py.allow_threads(|| engine.run(n)).map_err(py_err)?;
            left -= n;
            py.check_signals()?;
        }
        Ok(())
    }

    /// Steps done.
    #[getter]
    fn time(&self) -> u64 {
        self.e().time()
    }

    /// The parameters, as a dict of the constructor's keywords.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        params_dict(py, self.e().params())
    }

    /// The rule reading's name.
    #[getter]
    fn rules(&self) -> String {
        self.e().rules().to_string()
    }

    /// The engine's name.
    #[getter]
    fn engine(&self) -> String {
        self.name.clone()
    }

    /// The state as a (W, L) uint8 array: bit c of site (x, y) is channel c
    /// (MODEL.md A1). A copy.
    fn state<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u8>> {
        let e = self.e();
        let p = e.params();
        Array2::from_shape_fn((p.width, p.length), |(x, y)| e.site(x, y)).into_pyarray(py)
    }

    /// Set the whole state from a (W, L) array of 7-bit states.
    fn set_state(&mut self, state: numpy::PyReadonlyArray2<u8>) -> PyResult<()> {
        let a = state.as_array();
        let p = *self.e().params();
        if a.shape() != [p.width, p.length] {
            return Err(PyValueError::new_err(format!(
                "state of shape {:?}: the pipe needs ({}, {})",
                a.shape(),
                p.width,
                p.length
            )));
        }
        if let Some(bad) = a.iter().find(|&&s| s > 0x7f) {
            return Err(PyValueError::new_err(format!(
                "state value {bad}: a site holds 7 channels, values 0..=127"
            )));
        }
        let e = self.m();
        for ((x, y), &s) in a.indexed_iter() {
            e.set_site(x, y, s);
        }
        Ok(())
    }

    /// The state byte of site (x, y).
    fn site(&self, x: usize, y: usize) -> PyResult<u8> {
        self.check_site(x, y)?;
        Ok(self.e().site(x, y))
    }

    /// Set the state byte of site (x, y), 0..=127.
    fn set_site(&mut self, x: usize, y: usize, state: u8) -> PyResult<()> {
        self.check_site(x, y)?;
        if state > 0x7f {
            return Err(PyValueError::new_err(format!(
                "state {state}: a site holds 7 channels, values 0..=127"
            )));
        }
        self.m().set_site(x, y, state);
        Ok(())
    }

    /// The bin densities n_i, particles per bin of `bin` rows (MODEL.md A9).
    fn bin_counts<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.e().bin_counts().into_pyarray(py)
    }

    /// Particles in each channel 0..=6.
    fn channel_counts<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        self.e().channel_counts().to_vec().into_pyarray(py)
    }

    /// (injected, out at the bottom, out at the top) so far (open pipe,
    /// MODEL.md A7).
    fn flux(&self) -> (u64, u64, u64) {
        let f = self.e().flux();
        (f.injected, f.out_bottom, f.out_top)
    }

    /// Particles in the pipe.
    fn particle_count(&self) -> u64 {
        self.e().particle_count()
    }

    /// Change the dissipation p mid-run (PH94 Fig. 1c).
    fn set_p(&mut self, p: f64) -> PyResult<()> {
        self.m().set_p(p).map_err(py_err)
    }

    fn __repr__(&self) -> String {
        let e = self.e();
        let p = e.params();
        format!(
            "Pipe(W={}, L={}, rho={}, p={}, g={}, b={}, rules='{}', engine='{}', t={})",
            p.width,
            p.length,
            p.rho,
            p.p,
            p.g,
            p.b,
            e.rules(),
            self.name,
            e.time()
        )
    }
}

/// One run of the hopper automaton (MODEL.md Part B).
#[pyclass(name = "Hopper", module = "granular_automata")]
struct PyHopper {
    /// The run (a mutex: a Python object may be shared between threads).
    engine: Mutex<Box<dyn HopperEngine>>,
}

impl PyHopper {
    fn e(&self) -> std::sync::MutexGuard<'_, Box<dyn HopperEngine>> {
        self.engine.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn m(&mut self) -> &mut Box<dyn HopperEngine> {
        self.engine.get_mut().unwrap_or_else(|p| p.into_inner())
    }
}

#[pymethods]
impl PyHopper {
    /// A new hopper run: `params` a JSON text of the parameters (as
    /// `Hopper.default_params()` writes them; None: the quick tier's
    /// hopper), and a seed.
    #[new]
    #[pyo3(signature = (params=None, seed=1))]
    fn new(params: Option<&str>, seed: u64) -> PyResult<Self> {
        let params: HopperParams = match params {
            None => HopperParams::quick(),
            Some(text) => serde_json::from_str(text)
                .map_err(|e| PyValueError::new_err(format!("hopper parameters: {e}")))?,
        };
        Ok(PyHopper {
            engine: Mutex::new(
                ga::hopper::engine::Reference
                    .build(params, seed)
                    .map_err(py_err)?,
            ),
        })
    }

    /// The quick tier's parameters as JSON text, to edit and pass back.
    #[staticmethod]
    fn default_params() -> PyResult<String> {
        serde_json::to_string_pretty(&HopperParams::quick())
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    /// One iteration (MODEL.md B3), with rain when `rain`; returns
    /// (outflow, moved, evaluated, added).
    #[pyo3(signature = (rain=false))]
    fn step(&mut self, rain: bool) -> PyResult<(u32, u32, u32, u32)> {
        let e = self.m();
        let r = e.step(rain);
        e.error().map_err(py_err)?;
        Ok((r.outflow, r.moved, r.evaluated, r.added))
    }

    /// Open the outlet (MODEL.md B5).
    fn open(&mut self) {
        self.m().open();
    }

    /// Rain until `target` grains are in, settling at most `max_settle`
    /// iterations; returns the iterations used.
    #[pyo3(signature = (target, max_iterations=1_000_000, max_settle=10_000))]
    fn fill(&mut self, py: Python<'_>, target: u64, max_iterations: u64, max_settle: u64) -> u64 {
        let engine = self.m();
        py.allow_threads(|| engine.fill(target, max_iterations, max_settle))
    }

    /// The site values, one byte per site (MODEL.md B1), as a uint8 array.
    fn sites<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        self.e().sites().to_vec().into_pyarray(py)
    }

    /// Grains in the container.
    fn grains(&self) -> u64 {
        self.e().grains()
    }

    /// Iterations done.
    #[getter]
    fn iteration(&self) -> u64 {
        self.e().iteration()
    }
}

/// The bin series of one run of a spectrum figure's set-up at `tier` (PH94
/// Fig. 2's pipe by default), as `fig2` records it: the bin's particle
/// count every T0 = 10 steps after a transient of 50000 steps.
#[pyfunction]
#[pyo3(signature = (seed, tier="quick", rules="default", engine="reference", p=0.5, g=0.5, b=0.5, rho=1.0, width=11, length=220))]
#[allow(clippy::too_many_arguments)]
fn bin_series<'py>(
    py: Python<'py>,
    seed: u64,
    tier: &str,
    rules: &str,
    engine: &str,
    p: f64,
    g: f64,
    b: f64,
    rho: f64,
    width: usize,
    length: usize,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let params = params_of(width, length, rho, p, g, b, 10, "periodic", None)?;
    let setup = tier_setup(
        self::tier(tier)?,
        params,
        rules.parse().map_err(py_err)?,
        engine_named(engine)?,
    );
    let stop = AtomicBool::new(false);
    let series = interruptible(py, &stop, || {
        bin_series_until(&setup, seed, &|_| {}, &|| stop.load(Ordering::Relaxed))
    })?;
    Ok(series.into_pyarray(py))
}

/// An ensemble of spectrum runs, as `fig2` (and `waves-fig6` with p = 0.8)
/// runs it: the same seeds from base seed `seed`, on `threads` threads (all
/// cores by default). `runs` defaults to the figure's count at the tier
/// (4 quick, 8 standard and paper, 128 acceptance). Returns a dict of the
/// figure's numbers and arrays: alpha, alpha_err, v_peak, v_err, j_peak,
/// alpha_of_mean, mean_spectrum, spectra (runs x m), run_alpha,
/// run_alpha_err, run_v_peak, seeds.
#[pyfunction]
#[pyo3(signature = (tier="quick", seed=1, runs=None, rules="default", engine=None, threads=None, p=0.5, g=0.5, b=0.5, rho=1.0, width=11, length=220))]
#[allow(clippy::too_many_arguments)]
fn spectrum_ensemble(
    py: Python<'_>,
    tier: &str,
    seed: u64,
    runs: Option<usize>,
    rules: &str,
    engine: Option<&str>,
    threads: Option<usize>,
    p: f64,
    g: f64,
    b: f64,
    rho: f64,
    width: usize,
    length: usize,
) -> PyResult<PyObject> {
    let t = self::tier(tier)?;
    let engine = match engine {
        Some(e) => engine_named(e)?,
        None if t.is_acceptance() => Engine::Fast,
        None => Engine::Reference,
    };
    let params = params_of(width, length, rho, p, g, b, 10, "periodic", None)?;
    let setup = tier_setup(t, params, rules.parse().map_err(py_err)?, engine);
    let fixed = ga::drivers::acceptance::margin("fig2", "alpha").map_or(128, |m| m.runs);
    let runs = runs.unwrap_or(match t {
        Tier::Acceptance => fixed,
        other => other.pick(4, 8, 8),
    });
    if !(1..=ga::ensemble::MAX_RUNS).contains(&runs) {
        return Err(PyValueError::new_err(format!(
            "runs = {runs}: use 1..={}",
            ga::ensemble::MAX_RUNS
        )));
    }
    let threads = threads.unwrap_or_else(ga::run::threads);
    if threads == 0 {
        return Err(PyValueError::new_err("threads = 0: use at least 1"));
    }
    let seeds = run_seeds(seed, runs);
    let stop = AtomicBool::new(false);
    let pb = ga::run::progress(runs as u64 * setup.steps(), "spectrum steps");
    let ens = interruptible(py, &stop, || {
        let done = ensemble_with_threads(runs, threads, |i| {
            bin_spectrum_until(&setup, seeds[i], &|n| pb.inc(n), &|| {
                stop.load(Ordering::Relaxed)
            })
        });
        combine(&setup, done.into_iter().collect::<ga::Result<Vec<_>>>()?)
    })?;
    pb.finish_and_clear();
    let d = PyDict::new(py);
    for (key, value) in [
        ("alpha", ens.alpha),
        ("alpha_err", ens.alpha_err),
        ("v_peak", ens.v_peak),
        ("v_err", ens.v_err),
    ] {
        d.set_item(key, value)?;
    }
    d.set_item("j_peak", ens.j_peak)?;
    d.set_item("alpha_of_mean", ens.fit_of_mean.fit.alpha)?;
    d.set_item("mean_spectrum", ens.mean_spectrum.clone().into_pyarray(py))?;
    let m = setup.m;
    let flat: Vec<f64> = ens
        .runs
        .iter()
        .flat_map(|r| r.spectrum.iter().copied())
        .collect();
    let spectra = Array2::from_shape_vec((ens.runs.len(), m), flat)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    d.set_item("spectra", spectra.into_pyarray(py))?;
    let col = |f: fn(&ga::drivers::spectra::SpectrumRun) -> f64| -> Vec<f64> {
        ens.runs.iter().map(f).collect()
    };
    d.set_item("run_alpha", col(|r| r.alpha).into_pyarray(py))?;
    d.set_item("run_alpha_err", col(|r| r.alpha_err).into_pyarray(py))?;
    d.set_item("run_v_peak", col(|r| r.v_peak).into_pyarray(py))?;
    d.set_item("seeds", seeds)?;
    d.set_item("m", m)?;
    d.set_item("engine", engine.to_string())?;
    Ok(d.into_any().unbind())
}

/// The power spectrum of `series` by the Numerical Recipes `spctrm`
/// estimator the figures use (MODEL.md A9): m output frequencies, 2k
/// segments of 2m samples, the window `parzen` (NR 1988, the default),
/// `bartlett` (NR 1992) or `square`.
#[pyfunction]
#[pyo3(signature = (series, m=16384, k=4, window="parzen"))]
fn spectrum<'py>(
    py: Python<'py>,
    series: PyReadonlyArray1<f64>,
    m: usize,
    k: usize,
    window: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let windows = [
        ("parzen", Window::Parzen1988),
        ("bartlett", Window::Bartlett1992),
        ("square", Window::Square),
    ];
    let window = named("window", window, &windows, "parzen, bartlett or square")?;
    let s = series.as_slice()?;
    let p = spctrm(s, &SpectrumParams { m, k, window }).map_err(py_err)?;
    Ok(p.into_pyarray(py))
}

/// The exponent alpha of P(j) ~ j^-alpha with the sharp peak removed, as
/// the figures fit it (MODEL.md A9): a dict of alpha, alpha_err, j_peak and
/// the peak's contrast.
#[pyfunction]
fn fit_alpha(py: Python<'_>, spectrum: PyReadonlyArray1<f64>) -> PyResult<PyObject> {
    let e = ga::analysis::fit::estimate_alpha(spectrum.as_slice()?).map_err(py_err)?;
    let d = PyDict::new(py);
    d.set_item("alpha", e.fit.alpha)?;
    d.set_item("alpha_err", e.fit.alpha_err)?;
    d.set_item("j_peak", e.j_peak)?;
    d.set_item("contrast", e.contrast)?;
    Ok(d.into_any().unbind())
}

/// The one grading rule (`analysis::grading`): a mean with its SE over n
/// runs against a claim, `within` (target, margin), `above` or `below` (a
/// threshold). Returns `reproduced`, `not-reproduced` or `undecided`.
/// Raises ValueError for what the rule cannot read: a mean, target or
/// threshold that is not finite, an SE that is negative or not finite (NaN
/// only for n = 1), n = 0, a margin that is negative or not finite.
#[pyfunction]
#[pyo3(signature = (mean, se, n, target=None, margin=None, above=None, below=None))]
fn grade(
    mean: f64,
    se: f64,
    n: usize,
    target: Option<f64>,
    margin: Option<f64>,
    above: Option<f64>,
    below: Option<f64>,
) -> PyResult<&'static str> {
    // a value the rule cannot read is an error, never "undecided"
    let finite = |name: &str, x: f64| -> PyResult<f64> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(PyValueError::new_err(format!(
                "{name} = {x}: a finite number"
            )))
        }
    };
    finite("mean", mean)?;
    // one run has no spread: its SE may be NaN (it grades as undecided)
    let readable = (se.is_finite() && se >= 0.0) || (se.is_nan() && n == 1);
    if !readable {
        return Err(PyValueError::new_err(format!(
            "se = {se}: a standard error, finite and >= 0 (NaN only for n = 1)"
        )));
    }
    if n == 0 {
        return Err(PyValueError::new_err(
            "n = 0: the number of runs behind the mean, at least 1 (fewer than 3 grade as undecided)",
        ));
    }
    let claim = match (target, margin, above, below) {
        (Some(target), Some(margin), None, None) => {
            finite("target", target)?;
            if !(margin.is_finite() && margin >= 0.0) {
                return Err(PyValueError::new_err(format!(
                    "margin = {margin}: a finite number >= 0"
                )));
            }
            Claim::Within { target, margin }
        }
        (None, None, Some(threshold), None) => Claim::Above {
            threshold: finite("above", threshold)?,
        },
        (None, None, None, Some(threshold)) => Claim::Below {
            threshold: finite("below", threshold)?,
        },
        _ => {
            return Err(PyValueError::new_err(
                "name one claim: target and margin, or above, or below",
            ))
        }
    };
    Ok(grade_rule(Estimate::new(mean, se, n), claim).status())
}

/// The published claims of the pipe papers graded by the reproduction
/// matrix: a list of (id, what it says), and the acceptance tier's margins:
/// a list of dicts (figure, check, source, margin Delta, runs).
#[pyfunction]
fn claims(py: Python<'_>) -> PyResult<(Vec<(&'static str, &'static str)>, PyObject)> {
    let margins: Vec<serde_json::Value> = ga::drivers::acceptance::MARGINS
        .iter()
        .map(|m| {
            serde_json::json!({
                "figure": m.figure, "check": m.check, "source": m.source,
                "published": m.published, "margin": m.delta(), "runs": m.runs,
            })
        })
        .collect();
    Ok((
        ga::drivers::claims::CLAIMS.to_vec(),
        from_json(py, &margins)?,
    ))
}

/// A candidate written in Python: `factory(params, rules, seed)` returns an
/// object with the methods of `Pipe` that `validate` reads: `step()`,
/// `state()`, `set_state(array)`, `bin_counts()`, `channel_counts()` and
/// `flux()`.
struct PyCandidate {
    factory: Py<PyAny>,
    name: String,
    /// The first Python exception the candidate raised (re-raised after the
    /// validation, so Ctrl-C stops it).
    raised: Mutex<Option<PyErr>>,
}

impl PyCandidate {
    fn run_py(&self, py: Python<'_>, plan: &RunPlan) -> PyResult<Vec<Sample>> {
        let params = params_dict(py, &plan.params)?;
        let obj = self
            .factory
            .bind(py)
            .call1((params, plan.rules.as_str(), plan.seed))?;
        if obj.is_none() || !obj.hasattr("step")? {
            return Err(PyTypeError::new_err(format!(
                "the candidate's factory(params, rules, seed) returned {}, not an engine object with step(), state(), set_state(), bin_counts(), channel_counts() and flux()",
                obj.repr()?
            )));
        }
        let (w, l) = (plan.params.width, plan.params.length);
        if let Some(init) = &plan.init {
            let mut a = Array2::<u8>::zeros((w, l));
            for &(x, y, s) in init {
                a[[x, y]] = s;
            }
            obj.call_method1("set_state", (a.into_pyarray(py),))?;
        }
        let np = py.import("numpy")?;
        let mut out = Vec::new();
        for t in 1..=plan.steps {
            obj.call_method0("step")?;
            if t % 1000 == 0 {
                py.check_signals()?;
            }
            if t % plan.every != 0 {
                continue;
            }
            let bins: Vec<f64> = np
                .call_method1("asarray", (obj.call_method0("bin_counts")?, "float64"))?
                .call_method0("tolist")?
                .extract()?;
            let channels: Vec<u64> = np
                .call_method1("asarray", (obj.call_method0("channel_counts")?, "uint64"))?
                .call_method0("tolist")?
                .extract()?;
            let channels: [u64; 7] = channels.try_into().map_err(|c: Vec<u64>| {
                PyValueError::new_err(format!("channel_counts() gave {} values, not 7", c.len()))
            })?;
            let flux: (u64, u64, u64) = obj.call_method0("flux")?.extract()?;
            let sites = if plan.sites {
                let state = np.call_method1("asarray", (obj.call_method0("state")?, "uint8"))?;
                let state = state.downcast::<PyArray2<u8>>()?.readonly();
                let a = state.as_array();
                if a.shape() != [w, l] {
                    return Err(PyValueError::new_err(format!(
                        "state() of shape {:?}: the pipe is ({w}, {l})",
                        a.shape()
                    )));
                }
                let mut v = Vec::new();
                for x in 0..w {
                    for y in 0..l {
                        let state = a[[x, y]];
                        if state > 0x7f {
                            return Err(PyValueError::new_err(format!(
                                "state() has {state} at site ({x}, {y}) after {t} steps: not a 7-bit site state (0..=127), as the contract asks (VALIDATION.md)"
                            )));
                        }
                        if state != 0 {
                            v.push((x, y, state));
                        }
                    }
                }
                Some(v)
            } else {
                None
            };
            out.push(Sample {
                t,
                bins,
                channels,
                flux: [flux.0, flux.1, flux.2],
                sites,
            });
        }
        Ok(out)
    }
}

impl Candidate for PyCandidate {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn run(&self, plan: &RunPlan) -> ga::Result<Vec<Sample>> {
        Python::with_gil(|py| self.run_py(py, plan)).map_err(|e| {
            let message = format!("the Python candidate raised {e}");
            let mut raised = self.raised.lock().unwrap_or_else(|p| p.into_inner());
            raised.get_or_insert(e);
            Error::new(ErrorKind::Interrupted, message)
        })
    }
}

/// Validate a candidate against the reference engine (VALIDATION.md):
/// `candidate` is `reference`, `fast`, `mutant:NAME`, or a Python callable
/// `factory(params, rules, seed)` returning an engine object; `level` is
/// `1`, `2` or `all`. Returns the report as a dict (its `pass` is the
/// verdict). An exception the candidate raised is raised again.
#[pyfunction]
#[pyo3(signature = (candidate, level="1", tier="quick", rules="default", seed=1, name="python"))]
fn validate(
    py: Python<'_>,
    candidate: &Bound<'_, PyAny>,
    level: &str,
    tier: &str,
    rules: &str,
    seed: u64,
    name: &str,
) -> PyResult<PyObject> {
    use ga::validate::{Level, Model, Plan, Size};
    let levels = [("1", Level::One), ("2", Level::Two), ("all", Level::All)];
    let levels = named("level", level, &levels, "1, 2 or all")?;
    let t = self::tier(tier)?;
    let plan = Plan::new(rules, levels, Model::Pipe, t, Size::for_tier(t), seed);
    let report = if let Ok(spec) = candidate.extract::<String>() {
        let cand = ga::validate::candidate_from(&spec, None).map_err(py_err)?;
        py.allow_threads(|| ga::validate::validate(cand.as_ref(), &plan, &|| {}))
            .map_err(py_err)?
    } else if candidate.is_callable() {
        let cand = PyCandidate {
            factory: candidate.clone().unbind(),
            name: format!("python:{name}"),
            raised: Mutex::new(None),
        };
        let report = py
            .allow_threads(|| ga::validate::validate(&cand, &plan, &|| {}))
            .map_err(py_err)?;
        if let Some(e) = cand.raised.into_inner().unwrap_or_else(|p| p.into_inner()) {
            return Err(e);
        }
        report
    } else {
        return Err(PyValueError::new_err(
            "candidate: a name (reference, fast, mutant:NAME) or a callable factory(params, rules, seed)",
        ));
    };
    from_json(py, &report)
}

/// The module.
#[pymodule]
#[pyo3(name = "granular_automata")]
fn granular_automata_py(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyPipe>()?;
    m.add_class::<PyHopper>()?;
    m.add_function(wrap_pyfunction!(bin_series, m)?)?;
    m.add_function(wrap_pyfunction!(spectrum_ensemble, m)?)?;
    m.add_function(wrap_pyfunction!(spectrum, m)?)?;
    m.add_function(wrap_pyfunction!(fit_alpha, m)?)?;
    m.add_function(wrap_pyfunction!(grade, m)?)?;
    m.add_function(wrap_pyfunction!(claims, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
