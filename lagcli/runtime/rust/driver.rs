//! The command-line driver of a generated lagcli crate: options, output times, the CSV of
//! `lagcli simulate`. Shipped with lagcli (lagcli/runtime/rust/) and copied unchanged into
//! every generated crate, as lagcli_driver.c is next to a generated C model; the model is
//! a `Model` table (the crate's `MODEL`).
//!
//!     <name> [--t-end T] [--dt DT] [--method RK45|DOP853] [--rtol R] [--atol A]
//!            [--set NAME=VALUE]... [--init NAME=VALUE]... [--baumgarte ALPHA BETA]
//!            [--max-steps N]
//!                               (--set: a parameter, or an input held at VALUE; inputs
//!                               not set keep the spec's defaults, as in the C driver)
//!     <name> --rhs              read lines "t y... p..." on stdin, print dy/dt per line
//!     <name> --bench-rhs N      the same states: N right-hand-side calls, ns per call on stderr
//!
//! Defaults: the model's (the spec's simulate: and initial: blocks). Integrates from t = 0
//! with `ode` and prints a header (t, state, multipliers, invariants), then one row per
//! output time t_k = k dt, k = 0 .. floor(t_end/dt + OUTPUT_SLACK), and t_end if not
//! reached, every value with 17 significant digits (C's %.17g). Constrained models: the
//! multipliers are those of the Baumgarte-stabilised system integrated, the step is capped
//! at 1/|lambda| of its constraint-error mode, and an initial state violating the
//! constraints by more than CONSTRAINT_TOLERANCE is integrated as given, with a warning.
//! A run takes at most --max-steps accepted steps (default STEP_BUDGET_BASE plus
//! STEP_BUDGET_PER_OUTPUT per output interval, as the C driver and `lagcli simulate`).
//! On failure: "error: at t = ...: reason" on stderr, exit status 1, the rows so far
//! kept; bad options, or a spec's method this driver does not implement: exit status 2. The numbers below are lagcli/interface.py's
//! (tests/test_codegen_rust.py checks that both say the same).

use std::io::{BufRead, BufWriter, Write};

use crate::ode;

const OUTPUT_SLACK: f64 = 1e-9; // t_end/dt this close below an integer reaches it
const END_TOLERANCE: f64 = 1e-12; // relative: a last t_k this close to t_end is t_end
const CONSTRAINT_TOLERANCE: f64 = 1e-8; // largest |constraint| of a consistent initial state
const STEP_BUDGET_BASE: u64 = 20000; // default --max-steps: this many steps ...
const STEP_BUDGET_PER_OUTPUT: u64 = 1000; // ... plus this many per output interval (t_end/dt)

/// Why a model function failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelError {
    /// The mass matrix or the constraint matrix is singular.
    Singular,
    /// A result is inf or nan.
    NonFinite,
}

impl ModelError {
    pub fn message(self) -> &'static str {
        match self {
            ModelError::Singular => "singular mass matrix or constraint matrix",
            ModelError::NonFinite => "the accelerations are not finite (inf/nan)",
        }
    }
}

/// The right-hand side on slices: (t, y, p, u, alpha, beta, dydt, lambda).
pub type RhsFn = fn(f64, &[f64], &[f64], &[f64], f64, f64, &mut [f64], &mut [f64]) -> Result<(), ModelError>;
/// The invariants on slices: (t, y, p, u, out).
pub type InvariantsFn = fn(f64, &[f64], &[f64], &[f64], &mut [f64]) -> Result<(), ModelError>;

/// A generated model as one table: names, defaults, settings and its functions.
pub struct Model {
    pub name: &'static str,
    pub state_names: &'static [&'static str],
    pub parameter_names: &'static [&'static str],
    pub parameter_defaults: &'static [f64],
    pub input_names: &'static [&'static str],
    pub input_defaults: &'static [f64],
    pub multiplier_names: &'static [&'static str],
    pub invariant_names: &'static [&'static str],
    pub residual_column: Option<usize>,
    pub initial_state: &'static [f64],
    pub t_end: f64,
    pub dt: f64,
    pub method: &'static str,
    pub rtol: f64,
    pub atol: f64,
    pub baumgarte: [f64; 2],
    pub rhs_stabilized: RhsFn,
    pub invariants: InvariantsFn,
}

struct Settings {
    t_end: f64,
    dt: f64,
    method: Option<ode::Method>,
    rtol: f64,
    atol: f64,
    alpha: f64,
    beta: f64,
    max_steps: u64,
    p: Vec<f64>,
    u: Vec<f64>,
    y0: Vec<f64>,
    mode: Mode,
}

enum Mode {
    Simulate,
    Rhs,
    Bench(u64),
}

/// Run the driver on `model` with the process's arguments; the exit status.
pub fn main(model: &Model) -> i32 {
    let args: Vec<String> = std::env::args().collect();
    match parse(model, &args) {
        Ok(settings) => match settings.mode {
            Mode::Simulate => simulate(model, &settings),
            Mode::Rhs => evaluate(model, None),
            Mode::Bench(calls) => evaluate(model, Some(calls)),
        },
        Err(message) => {
            if message.is_empty() {
                println!("{}", usage(&args[0]));
                return 0;
            }
            eprintln!("error: {}\n{}", message, usage(&args[0]));
            2
        }
    }
}

fn usage(program: &str) -> String {
    format!("usage: {} [--t-end T] [--dt DT] [--method RK45|DOP853] [--rtol R] [--atol A]\n       \
             [--set NAME=VALUE]... [--init NAME=VALUE]... [--baumgarte ALPHA BETA] [--max-steps N] [--rhs]",
            program)
}

/// A finite number, the whole of `text`.
fn number(text: &str) -> Option<f64> {
    text.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// NAME=VALUE into values[position of NAME in names].
fn assign(option: &str, item: &str, names: &[&str], what: &str, values: &mut [f64]) -> Result<(), String> {
    let (name, value) = item.split_once('=').filter(|(n, _)| !n.is_empty())
        .ok_or_else(|| format!("{} {}: expected NAME=VALUE", option, item))?;
    let index = names.iter().position(|n| *n == name)
        .ok_or_else(|| format!("{} {}: unknown {} '{}'", option, item, what, name))?;
    values[index] = number(value).ok_or_else(|| format!("{} {}: '{}' is not a number", option, item, value))?;
    Ok(())
}

/// The options (`--opt VALUE` or `--opt=VALUE`); Err("") for --help.
fn parse(model: &Model, args: &[String]) -> Result<Settings, String> {
    let mut s = Settings {
        t_end: model.t_end, dt: model.dt,
        method: ode::Method::from_name(model.method),
        rtol: model.rtol, atol: model.atol, alpha: model.baumgarte[0], beta: model.baumgarte[1], max_steps: 0,
        p: model.parameter_defaults.to_vec(), u: model.input_defaults.to_vec(),
        y0: model.initial_state.to_vec(), mode: Mode::Simulate,
    };
    let mut i = 1;
    while i < args.len() {
        let (option, inline) = match args[i].split_once('=') {
            Some((o, v)) if o.starts_with("--") => (o.to_string(), Some(v.to_string())),
            _ => (args[i].clone(), None),
        };
        let flag = matches!(option.as_str(), "-h" | "--help" | "--rhs" | "--baumgarte");
        let value = if flag {
            String::new()
        } else if let Some(v) = inline {
            v
        } else {
            i += 1;
            args.get(i).cloned().ok_or_else(|| format!("{}: missing value", option))?
        };
        let positive = |what: &str| number(&value).filter(|v| *v > 0.0)
            .ok_or_else(|| format!("{}: expected a positive number", what));
        match option.as_str() {
            "-h" | "--help" => return Err(String::new()),
            "--t-end" => s.t_end = number(&value).filter(|v| *v >= 0.0)
                .ok_or("--t-end: expected a non-negative number")?,
            "--dt" => s.dt = positive("--dt")?,
            "--rtol" => s.rtol = positive("--rtol")?,
            "--atol" => s.atol = positive("--atol")?,
            "--method" => s.method = Some(ode::Method::from_name(&value)
                .ok_or("--method: the Rust driver implements RK45 and DOP853")?),
            "--max-steps" => s.max_steps = number(&value).filter(|v| *v >= 1.0 && *v <= 1e15 && v.fract() == 0.0)
                .ok_or("--max-steps: expected a whole number of steps from 1 to 1e15")? as u64,
            "--set" if model.input_names.iter().any(|n| value.split_once('=').map_or(false, |(name, _)| name == *n)) =>
                assign("--set", &value, model.input_names, "input", &mut s.u)?,
            "--set" => assign("--set", &value, model.parameter_names,
                              if model.input_names.is_empty() { "parameter" } else { "parameter or input" }, &mut s.p)?,
            "--init" => assign("--init", &value, model.state_names, "coordinate or velocity", &mut s.y0)?,
            "--rhs" => s.mode = Mode::Rhs,
            "--bench-rhs" => s.mode = Mode::Bench(number(&value).filter(|v| *v >= 1.0 && *v <= 1e9)
                .ok_or("--bench-rhs: expected a count from 1 to 1e9")? as u64),
            "--baumgarte" => {
                let pair = (args.get(i + 1).and_then(|a| number(a)), args.get(i + 2).and_then(|a| number(a)));
                match pair {
                    (Some(a), Some(b)) => (s.alpha, s.beta) = (a, b),
                    _ => return Err("--baumgarte: expected two numbers ALPHA BETA".into()),
                }
                i += 2;
            }
            _ => return Err(format!("{}: unknown option", args[i])),
        }
        i += 1;
    }
    if s.method.is_none() && matches!(s.mode, Mode::Simulate) {
        return Err(format!("the spec's method '{}' is not implemented by the Rust driver (RK45 and DOP853 \
                            are); choose one with --method", model.method));
    }
    Ok(s)
}

/// The steps a run may take: --max-steps, else STEP_BUDGET_BASE plus STEP_BUDGET_PER_OUTPUT
/// per output interval (lagcli.interface.default_max_steps).
fn step_budget(s: &Settings) -> u64 {
    if s.max_steps > 0 {
        return s.max_steps;
    }
    STEP_BUDGET_BASE + STEP_BUDGET_PER_OUTPUT * (s.t_end / s.dt - OUTPUT_SLACK).ceil().max(0.0) as u64
}

/// The output times t_k = k dt, k = 0 .. floor(t_end/dt + OUTPUT_SLACK), then t_end if
/// not reached.
pub fn output_times(t_end: f64, dt: f64) -> Vec<f64> {
    let count = (t_end / dt + OUTPUT_SLACK).floor() as usize;
    let mut times: Vec<f64> = (0..=count).map(|k| k as f64 * dt).collect();
    if times[count] < t_end - END_TOLERANCE * t_end.max(1.0) {
        times.push(t_end);
    }
    times
}

/// Largest step on a constrained system: h |lambda| <= 1 for the eigenvalues
/// lambda = -alpha +- sqrt(alpha^2 - beta^2) of the Baumgarte-damped constraint error.
fn max_step(model: &Model, alpha: f64, beta: f64) -> f64 {
    let (a, b) = (alpha.abs(), beta.abs());
    let rate = (a + (a * a - b * b).max(0.0).sqrt()).max(b);
    if model.multiplier_names.is_empty() || !(rate > 0.0) { f64::INFINITY } else { 1.0 / rate }
}

/// `x` as C's printf("%.17g", x).
pub fn g17(x: f64) -> String {
    if !x.is_finite() {
        return (if x.is_nan() { "nan" } else if x > 0.0 { "inf" } else { "-inf" }).to_string();
    }
    if x == 0.0 {
        return (if x.is_sign_negative() { "-0" } else { "0" }).to_string();
    }
    let scientific = format!("{:.16e}", x);
    let (mantissa, exponent) = scientific.split_once('e').unwrap_or((&scientific, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    if !(-4..17).contains(&exponent) {
        let mantissa = trim_zeros(mantissa);
        let sign = if exponent < 0 { '-' } else { '+' };
        return format!("{}e{}{:02}", mantissa, sign, exponent.abs());
    }
    trim_zeros(&format!("{:.*}", (16 - exponent) as usize, x)).to_string()
}

fn trim_zeros(text: &str) -> &str {
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.') } else { text }
}

fn simulate(model: &Model, s: &Settings) -> i32 {
    let (nlambda, ninv) = (model.multiplier_names.len(), model.invariant_names.len());
    let u = s.u.as_slice();
    let (mut dydt, mut lambda, mut inv) = (vec![0.0; s.y0.len()], vec![0.0; nlambda], vec![0.0; ninv]);
    if let Some(column) = model.residual_column {
        let _ = (model.invariants)(0.0, &s.y0, &s.p, u, &mut inv);
        if !(inv[column] <= CONSTRAINT_TOLERANCE) {
            eprintln!("warning: the initial state violates the constraints: constraint_residual = {:.3e} \
                       (more than {:e}); integrating it as given", inv[column], CONSTRAINT_TOLERANCE);
        }
    }
    let stdout = std::io::stdout();
    let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
    let header: Vec<&str> = std::iter::once("t").chain(model.state_names.iter().copied())
        .chain(model.multiplier_names.iter().copied()).chain(model.invariant_names.iter().copied()).collect();
    let _ = writeln!(out, "{}", header.join(","));
    let mut failure: Option<(f64, ModelError)> = None;
    let mut row = |t: f64, y: &[f64]| -> bool {
        if let Err(e) = (model.rhs_stabilized)(t, y, &s.p, u, s.alpha, s.beta, &mut dydt, &mut lambda) {
            failure = Some((t, e));
            return false;
        }
        let _ = (model.invariants)(t, y, &s.p, u, &mut inv); // non-finite values are printed as such
        let values: Vec<String> = std::iter::once(t).chain(y.iter().copied()).chain(lambda.iter().copied())
            .chain(inv.iter().copied()).map(g17).collect();
        writeln!(out, "{}", values.join(",")).is_ok()
    };
    if !row(0.0, &s.y0) {
        drop(row);
        return fail(failure.map_or(0.0, |f| f.0), failure.map_or("", |f| f.1.message()));
    }
    let times = output_times(s.t_end, s.dt);
    let mut rhs_failure: Option<(f64, ModelError)> = None;
    let mut stage_lambda = vec![0.0; nlambda];
    let rhs = |t: f64, y: &[f64], d: &mut [f64]| -> bool {
        match (model.rhs_stabilized)(t, y, &s.p, u, s.alpha, s.beta, d, &mut stage_lambda) {
            Ok(()) => true,
            Err(e) => {
                rhs_failure = Some((t, e));
                false
            }
        }
    };
    let result = if times.len() > 1 {
        ode::integrate_bounded(s.method.unwrap_or(ode::Method::Dop853), rhs, &mut row, 0.0, &s.y0, s.t_end,
                               &times[1..], s.rtol, s.atol, max_step(model, s.alpha, s.beta), step_budget(s))
    } else {
        Ok(ode::Stats::default())
    };
    drop(row);
    match result {
        Ok(_) => 0,
        Err((ode::OdeError::Rhs, stats)) => fail(stats.t, rhs_failure.map_or("", |f| f.1.message())),
        Err((ode::OdeError::Interrupted, stats)) => match failure {
            Some((t, e)) => fail(t, e.message()),
            None => fail(stats.t, "cannot write the output"),
        },
        Err((ode::OdeError::MaxSteps, stats)) => fail(stats.t, &format!(
            "the integration reached its bound of {} steps before t_end (a stiff or blowing-up solution?); \
             raise the bound with --max-steps N", step_budget(s))),
        Err((e, stats)) => fail(stats.t, e.message()),
    }
}

fn fail(t: f64, reason: &str) -> i32 {
    let _ = std::io::stdout().flush();
    eprintln!("error: at t = {}: {}", g17(t), reason);
    1
}

/// --rhs: one line of dy/dt (shortest round-trip decimals) per line "t y... p..." of
/// stdin; --bench-rhs N: N calls cycling over those states, ns per call on stderr.
fn evaluate(model: &Model, bench: Option<u64>) -> i32 {
    let (nstate, nparam) = (model.state_names.len(), model.parameter_names.len());
    let u = model.input_defaults; // --rhs reads t, y, p: the inputs keep their defaults
    let mut points = Vec::new();
    for (k, line) in std::io::stdin().lock().lines().enumerate() {
        let line = line.unwrap_or_default();
        let values: Option<Vec<f64>> = line.split_whitespace().map(|v| v.parse().ok()).collect();
        match values {
            Some(v) if v.len() == 1 + nstate + nparam => points.push(v),
            Some(v) if v.is_empty() => {}
            _ => {
                eprintln!("error: stdin line {}: expected {} numbers (t, y, p)", k + 1, 1 + nstate + nparam);
                return 2;
            }
        }
    }
    let mut dydt = vec![0.0; nstate];
    let mut lambda = vec![0.0; model.multiplier_names.len()];
    if let Some(calls) = bench {
        if points.is_empty() {
            eprintln!("error: --bench-rhs needs states on stdin");
            return 2;
        }
        let mut sink = 0.0;
        let start = std::time::Instant::now();
        for k in 0..calls as usize {
            let v = &points[k % points.len()];
            let _ = (model.rhs_stabilized)(v[0], &v[1..1 + nstate], &v[1 + nstate..], u, 0.0, 0.0, &mut dydt, &mut lambda);
            sink += dydt[nstate - 1];
        }
        let ns = start.elapsed().as_secs_f64() * 1e9 / calls as f64;
        eprintln!("rhs: calls {}, ns_per_call {:.3}, checksum {:e}", calls, ns, sink);
        return 0;
    }
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    for v in &points {
        let line = match (model.rhs_stabilized)(v[0], &v[1..1 + nstate], &v[1 + nstate..], u, 0.0, 0.0, &mut dydt, &mut lambda) {
            Ok(()) => dydt.iter().map(|x| format!("{:e}", x)).collect::<Vec<_>>().join(" "),
            Err(e) => format!("error: {}", e.message()),
        };
        let _ = writeln!(out, "{}", line);
    }
    0
}
