//! Candidates of `validate`: anything that runs the pipe automaton from a
//! [`RunPlan`] and returns [`Sample`]s. Rust engines go through the
//! [`EngineBuilder`] contract ([`Builtin`]); engines in any language through
//! the external-program contract of VALIDATION.md ([`External`]).

use crate::error::{Error, ErrorKind, Result};
use crate::hopper::engine::HopperBuilder;
use crate::pipe::engine::{EngineBuilder, PipeEngine};
use crate::pipe::{Flux, Params, Rules};
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::os::unix::process::CommandExt;
use std::process::{Command, Stdio};
use std::time::Duration;

/// What a candidate runs: one run of the automaton and what to record.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunPlan {
    /// The pipe (MODEL.md A8).
    pub params: Params,
    /// The rule reading, as its name (e.g. `default`).
    pub rules: String,
    /// The seed of the run.
    pub seed: u64,
    /// Steps to run.
    pub steps: u64,
    /// A sample after every `every` steps (t = every, 2 every, ...).
    pub every: u64,
    /// If given: the pipe is emptied and these sites (x, y, state byte) set
    /// before the first step, instead of the random start.
    pub init: Option<Vec<(usize, usize, u8)>>,
    /// Whether each sample lists the occupied sites.
    pub sites: bool,
}

/// One sample of a run, after `t` steps (one NDJSON line of the external
/// contract).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Steps done.
    pub t: u64,
    /// Bin densities n_i (MODEL.md A9).
    pub bins: Vec<f64>,
    /// Particles in each channel 0..=6.
    pub channels: [u64; 7],
    /// Injected, out at the bottom, out at the top, so far.
    pub flux: [u64; 3],
    /// Occupied sites (x, y, state byte), when the plan asks for them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sites: Option<Vec<(usize, usize, u8)>>,
}

/// An implementation of the automaton under test.
pub trait Candidate: Sync {
    /// Name for reports (`reference`, `mutant:NAME`, `cmd:...`).
    fn name(&self) -> String;
    /// Run `plan` and return its samples in time order.
    fn run(&self, plan: &RunPlan) -> Result<Vec<Sample>>;
    /// Its hopper engine (MODEL.md Part B), if it provides one; the
    /// external-program contract serves one too; none by default.
    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        None
    }
}

/// A Rust engine behind the [`EngineBuilder`] contract.
pub struct Builtin<B>(pub B);

impl<B: EngineBuilder> Candidate for Builtin<B> {
    fn name(&self) -> String {
        self.0.name()
    }

    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        self.0.hopper()
    }

    fn run(&self, plan: &RunPlan) -> Result<Vec<Sample>> {
        let mut out = Vec::new();
        self.run_each(plan, &mut |s| {
            out.push(s);
            Ok(())
        })?;
        Ok(out)
    }
}

impl<B: EngineBuilder> Builtin<B> {
    /// Run `plan`, handing each sample to `each` as it is taken (so that a
    /// long plan is streamed, not held in memory).
    pub fn run_each(
        &self,
        plan: &RunPlan,
        each: &mut dyn FnMut(Sample) -> Result<()>,
    ) -> Result<()> {
        check_plan(plan)?;
        let rules: Rules = plan.rules.parse()?;
        let mut e = self.0.build(plan.params, rules, plan.seed)?;
        if let Some(init) = &plan.init {
            prepare(e.as_mut(), init)?;
        }
        let mut bins = vec![0.0; plan.params.bins()];
        for t in 1..=plan.steps {
            e.step()?;
            if t % plan.every == 0 {
                e.fill_bin_counts(&mut bins);
                each(sample(e.as_ref(), t, &bins, plan.sites))?;
            }
        }
        Ok(())
    }
}

/// Check a plan: its pipe, steps in 1..=[`crate::run::MAX_STEPS`], and a
/// sampling interval in 1..=steps (a plan that asks for no sample is an
/// error, not an empty answer).
fn check_plan(plan: &RunPlan) -> Result<()> {
    plan.params.validate()?;
    let max = crate::run::MAX_STEPS;
    if !(1..=max).contains(&plan.steps) {
        return Err(Error::out_of_range(
            "steps",
            plan.steps,
            &format!("[1, {max}]"),
        ));
    }
    if !(1..=plan.steps).contains(&plan.every) {
        return Err(Error::out_of_range(
            "sampling interval every",
            plan.every,
            &format!("[1, steps = {}]", plan.steps),
        ));
    }
    Ok(())
}

/// Empty the pipe and set the sites of `init` (coordinates checked).
pub fn prepare(e: &mut dyn PipeEngine, init: &[(usize, usize, u8)]) -> Result<()> {
    let (w, l) = (e.params().width, e.params().length);
    for x in 0..w {
        for y in 0..l {
            e.set_site(x, y, 0);
        }
    }
    for &(x, y, s) in init {
        if x >= w || y >= l || s > 0x7f {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!("init site ({x}, {y}) state {s}: outside the {w} x {l} pipe or not a 7-bit state"),
            ));
        }
        e.set_site(x, y, s);
    }
    Ok(())
}

fn sample(e: &dyn PipeEngine, t: u64, bins: &[f64], with_sites: bool) -> Sample {
    let Flux {
        injected,
        out_bottom,
        out_top,
    } = e.flux();
    let sites = with_sites.then(|| e.occupied_sites());
    Sample {
        t,
        bins: bins.to_vec(),
        channels: e.channel_counts(),
        flux: [injected, out_bottom, out_top],
        sites,
    }
}

/// An engine in another program (VALIDATION.md): started once per run as
/// `sh -c '<command> "$@"' run --plan <json>`, it prints one [`Sample`] per
/// line (NDJSON) on stdout and exits 0.
#[derive(Debug, Clone)]
pub struct External {
    /// The command line (run by `sh -c`, arguments appended).
    pub command: String,
    /// The wall-time limit of one run (`validate --run-timeout`); `None`:
    /// [`default_time_limit`] of its plan.
    pub time_limit: Option<Duration>,
    /// The error of the first run that stalled or broke the contract:
    /// every later run fails with it at once, so that a level stops within
    /// about one limit instead of waiting out the limit of each of its runs.
    pub stalled: std::sync::Arc<std::sync::OnceLock<String>>,
}

impl External {
    /// An external candidate running `command`, each run limited to
    /// `time_limit` (`None`: [`default_time_limit`]).
    pub fn new(command: &str, time_limit: Option<Duration>) -> Self {
        External {
            command: command.to_string(),
            time_limit,
            stalled: Default::default(),
        }
    }
}

/// The wall-time limit of one external run of `plan` unless one is given:
/// one minute plus 10 microseconds per site update, so a program slower
/// than 100000 site updates per second, or one that stalls, is stopped
/// and named instead of stalling `validate` with it.
pub fn default_time_limit(plan: &RunPlan) -> Duration {
    let updates = plan.steps as f64 * plan.params.sites() as f64;
    Duration::from_secs_f64(60.0 + 1e-5 * updates)
}

/// The process groups of the external candidates running now, so that an
/// interrupted `validate` stops them too ([`running::kill_all`]).
pub mod running {
    use std::collections::BTreeMap;
    use std::sync::Mutex;

    /// A running candidate: the pipes it was given and its start time.
    #[derive(Clone)]
    struct Group {
        pipes: Vec<String>,
        since: u64,
    }

    /// Each running candidate's process group.
    static GROUPS: Mutex<BTreeMap<u32, Group>> = Mutex::new(BTreeMap::new());

    /// Held while a candidate starts and while one is stopped: a process
    /// being started holds copies of the other runs' pipes until its `exec`
    /// closes them, and must not be taken for their holder.
    pub static SPAWN: Mutex<()> = Mutex::new(());

    /// A candidate's process group started, with its pipes ([`pipe_id`]).
    pub fn add(pid: u32, pipes: Vec<String>) {
        let since = stat(pid).map_or(0, |s| s.1);
        GROUPS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(pid, Group { pipes, since });
    }

    /// It ended (or was stopped).
    pub fn remove(pid: u32) {
        GROUPS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&pid);
    }

    /// On SIGINT or SIGTERM, stop every running candidate ([`stop`]), then
    /// exit with status 130 (a candidate runs in a group of its own, which
    /// the terminal's interrupt does not reach).
    pub fn stop_on_interrupt() {
        let _ = ctrlc::set_handler(|| {
            kill_all();
            std::process::exit(130);
        });
    }

    /// Stop every running candidate ([`stop`]).
    pub fn kill_all() {
        let groups = GROUPS.lock().unwrap_or_else(|e| e.into_inner()).clone();
        for (pid, g) in groups {
            stop(pid, &g.pipes);
        }
    }

    /// Stop a candidate started as process group `pid` with `pipes`: SIGKILL
    /// to every process of the group (`sh` and what it started) and to
    /// every other process that still holds one of its pipes: a child that
    /// left the group (a daemon, `setsid`) and would keep its output open,
    /// so that reading it never ends. Only processes started since the
    /// candidate (by /proc's start time) are looked at, and nothing is
    /// sent when none is left. Where /proc does not exist, the group alone
    /// is stopped.
    pub fn stop(pid: u32, pipes: &[String]) {
        let _spawning = SPAWN.lock().unwrap_or_else(|e| e.into_inner());
        let victims = match std::fs::read_dir("/proc") {
            Ok(procs) => {
                let since = GROUPS
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .get(&pid)
                    .map_or(0, |g| g.since);
                let me = std::process::id();
                procs
                    .flatten()
                    .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
                    .filter(|&p| p != me)
                    .filter_map(|p| Some((p, stat(p)?)))
                    .filter(|&(_, (_, start))| start >= since)
                    .filter(|&(p, (group, _))| group == pid || holds(p, pipes))
                    .map(|(p, _)| p.to_string())
                    .collect()
            }
            Err(_) => vec![format!("-{pid}")],
        };
        if !victims.is_empty() {
            let _ = std::process::Command::new("kill")
                .arg("-KILL")
                .arg("--")
                .args(victims)
                .stderr(std::process::Stdio::null())
                .status();
        }
    }

    /// The process group and start time (clock ticks since boot) of
    /// process `pid`, from /proc/PID/stat.
    pub fn stat(pid: u32) -> Option<(u32, u64)> {
        let text = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
        // the fields after the command name, which may hold spaces: state,
        // ppid, pgrp, ..., starttime (the 22nd field of the line)
        let rest: Vec<&str> = text
            .get(text.rfind(')')? + 1..)?
            .split_whitespace()
            .collect();
        Some((rest.get(2)?.parse().ok()?, rest.get(19)?.parse().ok()?))
    }

    /// The pipe behind this process's file descriptor `fd` (`pipe:[INODE]`),
    /// or `None` where /proc does not show one.
    pub fn pipe_id(fd: i32) -> Option<String> {
        let link = std::fs::read_link(format!("/proc/self/fd/{fd}")).ok()?;
        let link = link.to_string_lossy().into_owned();
        link.starts_with("pipe:").then_some(link)
    }

    /// Whether process `pid` holds one of `pipes` open.
    fn holds(pid: u32, pipes: &[String]) -> bool {
        !pipes.is_empty()
            && std::fs::read_dir(format!("/proc/{pid}/fd"))
                .into_iter()
                .flatten()
                .flatten()
                .filter_map(|fd| std::fs::read_link(fd.path()).ok())
                .any(|l| pipes.iter().any(|p| l.as_os_str() == p.as_str()))
    }
}

/// Read all of `r` in a thread of its own (a program's stdout or stderr,
/// so that a full pipe never blocks it); what was read arrives on the
/// returned channel at end of file.
fn read_all<R: Read + Send + 'static>(mut r: R) -> std::sync::mpsc::Receiver<Vec<u8>> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = r.read_to_end(&mut v);
        let _ = tx.send(v);
    });
    rx
}

/// Read at most `cap` bytes of `r` in a thread of its own; past the cap it
/// sends the byte count on `over` (so the program can be stopped) and
/// reads no more. What was read arrives on the returned channel.
fn read_capped<R: Read + Send + 'static>(
    r: R,
    cap: u64,
    over: std::sync::mpsc::Sender<()>,
) -> std::sync::mpsc::Receiver<Vec<u8>> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = r.take(cap + 1).read_to_end(&mut v);
        if v.len() as u64 > cap {
            let _ = over.send(());
        }
        let _ = tx.send(v);
    });
    rx
}

impl Candidate for External {
    fn name(&self) -> String {
        format!("cmd:{}", self.command)
    }

    /// The same program, called with `hopper` instead of `run`
    /// ([`super::external_hopper`]).
    fn hopper(&self) -> Option<&dyn HopperBuilder> {
        Some(self)
    }

    fn run(&self, plan: &RunPlan) -> Result<Vec<Sample>> {
        check_plan(plan)?;
        let json = serde_json::to_string(plan).expect("a plan serialises");
        let limit = self.time_limit.unwrap_or_else(|| default_time_limit(plan));
        let what = || {
            format!(
                "plan seed {}, {} steps of a {} x {} pipe, a sample every {} steps",
                plan.seed, plan.steps, plan.params.length, plan.params.width, plan.every
            )
        };
        // a sample line lists its bins and counts (and its sites, if asked)
        let sites = if plan.sites { plan.params.sites() } else { 0 };
        let max_line = 4096 + 32 * plan.params.bins() + 32 * sites;
        let text = self.call(
            "run",
            json,
            limit,
            &what,
            (max_line, plan.steps / plan.every),
        )?;
        read_samples(plan, &text).map_err(|what| self.broke(&what))
    }
}

/// The samples of a run of the checked `plan` from the NDJSON `text` its
/// candidate printed (blank lines skipped): each line's shape checked
/// (VALIDATION.md, "Sample"), and as many samples as the plan asks for;
/// otherwise what is wrong, naming the line and quoting its start.
pub fn read_samples(plan: &RunPlan, text: &str) -> std::result::Result<Vec<Sample>, String> {
    let samples: Vec<Sample> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .enumerate()
        .map(|(i, (n, l))| {
            read_sample(plan, i, l)
                .map_err(|why| format!("line {} {why}; the line reads: {}", n + 1, excerpt(l)))
        })
        .collect::<std::result::Result<_, String>>()?;
    let want = plan.steps / plan.every;
    if samples.len() as u64 != want {
        return Err(format!(
            "printed {} samples, the plan asks for {want}",
            samples.len()
        ));
    }
    Ok(samples)
}

impl External {
    /// The error of a run that broke the contract; it is kept, so that
    /// every later run of this candidate fails with it at once (a level
    /// stops at its first bad run instead of running all of them).
    fn broke(&self, what: &str) -> Error {
        let _ = self.stalled.set(what.to_string());
        external_error(
            &self.command,
            self.stalled.get().map_or(what, |s| s.as_str()),
        )
    }

    /// Start the program as `sh -c 'COMMAND "$@"' sh MODE --plan -`, write
    /// `json` on its stdin, and return its stdout; stop it after `limit`
    /// (its plan described by `what` in the error) and fail every later
    /// call at once.
    /// Its output is capped at `max_lines` lines of at most `max_line`
    /// bytes each (what the plan asks for, with room): a program that
    /// prints more is stopped and named, and a longer line is refused, so a
    /// runaway program never fills the memory of `validate`.
    pub(crate) fn call(
        &self,
        mode: &str,
        json: String,
        limit: Duration,
        what: &dyn Fn() -> String,
        (max_line, max_lines): (usize, u64),
    ) -> Result<String> {
        if let Some(first) = self.stalled.get() {
            return Err(external_error(&self.command, first));
        }
        let spawning = running::SPAWN.lock().unwrap_or_else(|e| e.into_inner());
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(format!("{} \"$@\"", self.command))
            .arg("sh")
            .arg(mode)
            .arg("--plan")
            .arg("-")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .process_group(0) // so that a stopped run takes its children with it
            .spawn()
            .map_err(|e| external_error(&self.command, &format!("cannot start: {e}")))?;
        drop(spawning);
        // its three pipes: whoever still holds one when the run ends is
        // stopped with it (a child it forked, also one that left its group)
        let pipes: Vec<String> = {
            use std::os::fd::AsRawFd;
            [
                child.stdin.as_ref().map(|p| p.as_raw_fd()),
                child.stdout.as_ref().map(|p| p.as_raw_fd()),
                child.stderr.as_ref().map(|p| p.as_raw_fd()),
            ]
            .into_iter()
            .flatten()
            .filter_map(running::pipe_id)
            .collect()
        };
        // a program that exits without reading the plan closes the pipe
        // (EPIPE): what it printed says more than "Broken pipe"
        let mut stdin = child.stdin.take().expect("stdin is piped");
        let (sent_tx, sent_rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || sent_tx.send(stdin.write_all(json.as_bytes())));
        let cap = (max_lines + 2).saturating_mul(max_line as u64 + 1);
        let (over_tx, over_rx) = std::sync::mpsc::channel();
        let stdout = read_capped(child.stdout.take().expect("stdout is piped"), cap, over_tx);
        let stderr = read_all(child.stderr.take().expect("stderr is piped"));
        // wait in a thread of its own, so that the limit needs no polling
        let pid = child.id();
        running::add(pid, pipes.clone());
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || tx.send(child.wait()));
        let stop = || running::stop(pid, &pipes);
        let deadline = std::time::Instant::now() + limit;
        let left = || deadline.saturating_duration_since(std::time::Instant::now());
        let waited = loop {
            match rx.recv_timeout(left().min(Duration::from_millis(50))) {
                Ok(done) => break Some(done),
                Err(_) if over_rx.try_recv().is_ok() => {
                    stop();
                    running::remove(pid);
                    return Err(self.broke(&format!(
                        "printed more than {cap} bytes, more than its plan asks for ({max_lines} lines of at most {max_line} bytes), and was stopped: {}",
                        what()
                    )));
                }
                Err(_) if left().is_zero() => break None,
                Err(_) => {}
            }
        };
        // whatever it left running (a child in the background, a daemon
        // holding its output) ends with the run, at the limit or before
        stop();
        running::remove(pid);
        let timed_out = || {
            let what = format!(
                "did not finish its run within the time limit of {} s and was stopped: {} (set the limit with --run-timeout)",
                limit.as_secs_f64(),
                what()
            );
            let _ = self.stalled.set(what.clone());
            external_error(&self.command, &what)
        };
        let status = match waited {
            Some(done) => {
                done.map_err(|e| external_error(&self.command, &format!("did not finish: {e}")))?
            }
            None => return Err(timed_out()),
        };
        // the pipes close once their holders are stopped; never wait on
        // them past the limit (a holder /proc does not show)
        let grace = || left().max(Duration::from_millis(500));
        let (Ok(stdout), Ok(stderr)) = (stdout.recv_timeout(grace()), stderr.recv_timeout(grace()))
        else {
            return Err(timed_out());
        };
        let sent = sent_rx.recv_timeout(grace()).unwrap_or(Ok(()));
        let out = std::process::Output {
            status,
            stdout,
            stderr,
        };
        if out.stdout.len() as u64 > cap {
            return Err(self.broke(&format!(
                "printed more than {cap} bytes, more than its plan asks for ({max_lines} lines of at most {max_line} bytes): {}",
                what()
            )));
        }
        if let Some((n, l)) = out
            .stdout
            .split(|&b| b == b'\n')
            .enumerate()
            .find(|(_, l)| l.len() > max_line)
        {
            return Err(self.broke(&format!(
                "printed line {} of {} bytes, longer than the {max_line} its plan allows: {}",
                n + 1,
                l.len(),
                what()
            )));
        }
        let text = String::from_utf8_lossy(&out.stdout);
        let printed = || match text.trim() {
            "" => "nothing on stdout".to_string(),
            t => format!("on stdout: {}", excerpt(t)),
        };
        if !out.status.success() {
            let err = String::from_utf8_lossy(&out.stderr);
            return Err(self.broke(&format!(
                "exited with {}: {}; it printed {}",
                out.status,
                err.trim(),
                printed()
            )));
        }
        if let Err(e) = sent {
            return Err(self.broke(&format!(
                "did not read the plan on stdin ({e}) and printed {}",
                printed()
            )));
        }
        Ok(text.into_owned())
    }
}

/// At most the first 200 characters of `text` (what a program printed,
/// quoted in an error).
fn excerpt(text: &str) -> String {
    let mut chars = text.chars();
    let head: String = chars.by_ref().take(200).collect();
    if chars.next().is_some() {
        format!("{head:?}...")
    } else {
        format!("{head:?}")
    }
}

/// A sample as printed, before its shape is checked.
#[derive(Deserialize)]
struct Printed {
    t: u64,
    bins: Vec<f64>,
    channels: Vec<u64>,
    flux: Vec<u64>,
    #[serde(default)]
    sites: Option<Vec<(usize, usize, u8)>>,
}

/// Sample `i` (0-based) of a run of `plan` from its NDJSON `line`, its
/// shape checked (VALIDATION.md, "Sample"): t = (i + 1) every, L / bin
/// bins (finite, non-negative), 7 channels, 3 flux counts, and the sites
/// (inside the pipe, 7-bit states) when the plan asks for them; otherwise
/// what is wrong.
fn read_sample(plan: &RunPlan, i: usize, line: &str) -> std::result::Result<Sample, String> {
    let s: Printed = serde_json::from_str(line).map_err(|e| format!("is not a sample: {e}"))?;
    let p = &plan.params;
    let t = (i as u64 + 1) * plan.every;
    if s.t != t {
        return Err(format!("has t = {}, the plan asks for t = {t}", s.t));
    }
    if s.bins.len() != p.bins() {
        return Err(format!(
            "has {} bins, the plan asks for L / bin = {} / {} = {}",
            s.bins.len(),
            p.length,
            p.bin,
            p.bins()
        ));
    }
    if let Some((k, v)) = s.bins.iter().enumerate().find(|(_, v)| **v < 0.0) {
        return Err(format!("has bin {k} = {v}, not a density >= 0"));
    }
    let channels: [u64; 7] = s.channels.try_into().map_err(|c: Vec<u64>| {
        format!("has {} channel counts, the contract asks for 7", c.len())
    })?;
    check_identity(&s.bins, &channels)?;
    let flux: [u64; 3] = s.flux.try_into().map_err(|f: Vec<u64>| {
        format!(
            "has {} flux counts, the contract asks for 3 (injected, out at the bottom, out at the top)",
            f.len()
        )
    })?;
    let sites = if plan.sites {
        let sites = s.sites.ok_or("lists no sites, the plan asks for them")?;
        if let Some((x, y, state)) = sites
            .iter()
            .find(|&&(x, y, state)| x >= p.width || y >= p.length || state > 0x7f)
        {
            return Err(format!(
                "lists site [{x}, {y}, {state}]: outside the {} x {} pipe or not a 7-bit state",
                p.width, p.length
            ));
        }
        Some(sites)
    } else {
        None
    };
    Ok(Sample {
        t: s.t,
        bins: s.bins,
        channels,
        flux,
        sites,
    })
}

/// The contract's identity on every sample: a bin holds a whole number of
/// particles, and the bins together hold every particle, the sum of the
/// seven channel counts (MODEL.md A9). A candidate whose bins are shifted
/// or scaled breaks it, however well its series match in distribution.
pub fn check_identity(bins: &[f64], channels: &[u64; 7]) -> std::result::Result<(), String> {
    if let Some((k, v)) = bins
        .iter()
        .enumerate()
        .find(|(_, v)| v.fract() != 0.0 || !v.is_finite())
    {
        return Err(format!(
            "has bin {k} = {v}, not a whole number of particles"
        ));
    }
    // summed without wrap-around: counts past 2^64 are refused, not folded
    let Some(in_channels) = channels.iter().try_fold(0u64, |a, &c| a.checked_add(c)) else {
        return Err(format!(
            "has channel counts {channels:?} whose sum overflows 64 bits: no pipe holds so many particles"
        ));
    };
    let in_bins = bins.iter().sum::<f64>();
    if in_bins != in_channels as f64 {
        return Err(format!(
            "has bins summing to {in_bins} particles but channel counts summing to {in_channels}: the bins must hold every particle"
        ));
    }
    Ok(())
}

fn external_error(cmd: &str, what: &str) -> Error {
    Error::new(
        ErrorKind::Io,
        format!("external candidate `{cmd}` {what} (see VALIDATION.md for the contract)"),
    )
}

/// A plan of type `T` (named `name` in the error) as JSON from `input`.
pub(crate) fn read_plan<T: serde::de::DeserializeOwned>(
    input: &mut dyn std::io::Read,
    name: &str,
) -> Result<T> {
    let mut text = String::new();
    input.read_to_string(&mut text)?;
    serde_json::from_str(&text).map_err(|e| {
        Error::new(
            ErrorKind::InvalidParameter,
            format!("the plan is not valid JSON of a {name}: {e}"),
        )
    })
}

/// The external side of the contract for a Rust engine: read a [`RunPlan`]
/// as JSON from `input`, run it with `builder`, write NDJSON samples to
/// `output` (what `validate-example` does with the reference).
pub fn serve<B: EngineBuilder>(
    builder: B,
    input: &mut dyn std::io::Read,
    output: &mut dyn Write,
) -> Result<()> {
    let plan: RunPlan = read_plan(input, "RunPlan")?;
    Builtin(builder).run_each(&plan, &mut |s| {
        let line = serde_json::to_string(&s).expect("a sample serialises");
        writeln!(output, "{line}")?;
        Ok(())
    })
}
