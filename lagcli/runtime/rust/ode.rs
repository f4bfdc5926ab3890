//! lagcli's explicit Runge-Kutta integrator, RK45 (Dormand-Prince 5(4)) and DOP853
//! (Hairer's 8(5,3)), in Rust: the same algorithm as lagcli's C integrator
//! (lagcli_ode.c, docs/c-integrator.md), line for line. The step-size control, error
//! norms and dense output are those of scipy.integrate.solve_ivp, so the same rtol and
//! atol give the same accepted steps as `solve_ivp(t_eval=...)`. Shipped with lagcli
//! (lagcli/runtime/rust/ode.rs) and copied unchanged into every generated crate; no
//! dependencies. The work arrays are allocated once per `integrate` call; nothing is
//! allocated inside the step loop.
//!
//!     integrate(method, rhs, out, t0, y0, t_end, t_out, rtol, atol, max_step)
//!     integrate_bounded(..., max_step, max_steps)   at most max_steps accepted steps (0: no bound)
//!
//! rhs(t, y, dydt) -> bool   false: failure (`OdeError::Rhs`)
//! out(t, y) -> bool         called once per output time with the dense-output value;
//!                           false stops the integration (`OdeError::Interrupted`)
//! t_out                     output times, strictly monotonic towards t_end, inside
//!                           [t0, t_end] (solve_ivp's t_eval)
//! rtol, atol                scalar tolerances; rtol below 100 f64::EPSILON is raised to it
//! max_step                  largest step size; f64::INFINITY for no limit

/// The integration methods: scipy's names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Rk45,
    Dop853,
}

impl Method {
    /// The method called `name` ("RK45" or "DOP853", case-sensitive as in scipy).
    pub fn from_name(name: &str) -> Option<Method> {
        match name {
            "RK45" => Some(Method::Rk45),
            "DOP853" => Some(Method::Dop853),
            _ => None,
        }
    }

    fn tableau(self) -> &'static Tableau {
        match self {
            Method::Rk45 => &RK45,
            Method::Dop853 => &DOP853,
        }
    }
}

/// Why an integration stopped early.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OdeError {
    /// The step size fell below 10 ulp(t) (scipy's status -1).
    StepTooSmall,
    /// The right-hand side reported a failure.
    Rhs,
    /// y0, f(t0, y0) or an accepted state is inf/nan.
    NonFinite,
    /// The output callback returned false.
    Interrupted,
    /// Bad tolerances, max_step, state size or output times.
    Args,
    /// max_steps steps were accepted before t_end (the C integrator's LAGCLI_ODE_ERR_MAX_STEPS).
    MaxSteps,
}

impl OdeError {
    /// The message of lagcli's C integrator for this outcome.
    pub fn message(self) -> &'static str {
        match self {
            OdeError::StepTooSmall => "required step size is less than spacing between numbers",
            OdeError::Rhs => "the right-hand side reported a failure",
            OdeError::NonFinite => "the solution became non-finite (inf or nan)",
            OdeError::Interrupted => "integration stopped by the output callback",
            OdeError::Args => "invalid arguments (tolerances, max_step or output times)",
            OdeError::MaxSteps => "the step budget was reached before t_end",
        }
    }
}

/// What an integration did: the time reached (on failure: the last accepted step),
/// right-hand-side evaluations counted like scipy's nfev, and the step counts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    pub t: f64,
    pub nfev: u64,
    pub n_accepted: u64,
    pub n_rejected: u64,
}

// Step-size control constants of scipy/integrate/_ivp/rk.py.
const SAFETY: f64 = 0.9; // applied to the asymptotic step estimate
const MIN_FACTOR: f64 = 0.2; // largest decrease in one rejection
const MAX_FACTOR: f64 = 10.0; // largest increase after one step

/// RK45: Dormand-Prince 5(4), scipy's RK45 class. Nodes.
const RK45_C: [f64; 6] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0];

/// Row s holds a[s][0..s].
const RK45_A: [&[f64]; 6] = [
    &[0.0],
    &[1.0 / 5.0],
    &[3.0 / 40.0, 9.0 / 40.0],
    &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
    &[19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0],
    &[9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0]];

/// Solution weights.
const RK45_B: [f64; 6] = [
    35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0];

/// Error weights over the 7 rows of K (the 7th is the FSAL f(t + h, y_new)).
const RK45_E: [f64; 7] = [
    -71.0 / 57600.0, 0.0, 71.0 / 16695.0, -71.0 / 1920.0, 17253.0 / 339200.0, -22.0 / 525.0, 1.0 / 40.0];

/// Quartic dense output (Shampine 1986): y(t_old + x h) = y_old + h K^T P [x x^2 x^3 x^4].
const RK45_P: [&[f64]; 7] = [
    &[1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0,
     -12715105075.0 / 11282082432.0],
    &[0.0, 0.0, 0.0, 0.0],
    &[0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0,
     87487479700.0 / 32700410799.0],
    &[0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0,
     -10690763975.0 / 1880347072.0],
    &[0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0,
     701980252875.0 / 199316789632.0],
    &[0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0, -1453857185.0 / 822651844.0],
    &[0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0]];

/// DOP853: scipy's dop853_coefficients.py. Nodes: 12 stages, the FSAL node 1.0, then the 3 extra dense-output stages.
const DOP853_C: [f64; 16] = [
    0.0, 0.526001519587677318785587544488e-01, 0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510, 0.281649658092772603273242802490,
    0.333333333333333333333333333333, 0.25, 0.307692307692307692307692307692,
    0.651282051282051282051282051282, 0.6, 0.857142857142857142857142857142, 1.0, 1.0, 0.1, 0.2,
    0.777777777777777777777777777778
];

/// Row s holds a[s][0..s]; row 12 is the solution weights b; rows 13-15 are the extra
/// stages evaluated only for dense output.
const DOP853_A: [&[f64]; 16] = [
     &[0.0],
     &[5.26001519587677318785587544488e-2],
     &[1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2],
     &[2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2],
     &[2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1,
              9.24834003261792003115737966543e-1],
     &[3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1,
              1.25467687566822425016691814123e-1],
     &[3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1,
              6.02165389804559606850219397283e-2, -1.7578125e-2],
     &[3.70920001185047927108779319836e-2, 0.0, 0.0, 1.70383925712239993810214054705e-1,
              1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
              8.27378916381402288758473766002e-3],
     &[6.24110958716075717114429577812e-1, 0.0, 0.0, -3.36089262944694129406857109825,
              -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
              2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1],
     &[4.77662536438264365890433908527e-1, 0.0, 0.0, -2.48811461997166764192642586468,
              -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
              1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
              -2.03312017085086261358222928593e-2],
     &[-9.3714243008598732571704021658e-1, 0.0, 0.0, 5.18637242884406370830023853209,
              1.09143734899672957818500254654, -8.14978701074692612513997267357,
              -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
              2.49360555267965238987089396762, -3.0467644718982195003823669022],
     &[2.27331014751653820792359768449, 0.0, 0.0, -1.05344954667372501984066689879e1,
              -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
              2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
              -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
              6.43392746015763530355970484046e-1],
     &[5.42937341165687622380535766363e-2, 0.0, 0.0, 0.0, 0.0,
              4.45031289275240888144113950566, 1.89151789931450038304281599044,
              -5.8012039600105847814672114227, 3.1116436695781989440891606237e-1,
              -1.52160949662516078556178806805e-1, 2.01365400804030348374776537501e-1,
              4.47106157277725905176885569043e-2],
     &[5.61675022830479523392909219681e-2, 0.0, 0.0, 0.0, 0.0, 0.0,
              2.53500210216624811088794765333e-1, -2.46239037470802489917441475441e-1,
              -1.24191423263816360469010140626e-1, 1.5329179827876569731206322685e-1,
              8.20105229563468988491666602057e-3, 7.56789766054569976138603589584e-3, -8.298e-3],
     &[3.18346481635021405060768473261e-2, 0.0, 0.0, 0.0, 0.0,
              2.83009096723667755288322961402e-2, 5.35419883074385676223797384372e-2,
              -5.49237485713909884646569340306e-2, 0.0, 0.0,
              -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4,
              -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1],
     &[-4.28896301583791923408573538692e-1, 0.0, 0.0, 0.0, 0.0,
              -4.69762141536116384314449447206, 7.68342119606259904184240953878,
              4.06898981839711007970213554331, 3.56727187455281109270669543021e-1, 0.0, 0.0,
              0.0, -1.39902416515901462129418009734e-3, 2.9475147891527723389556272149,
              -9.15095847217987001081870187138]];

/// Error weights over K[0..12]: the 5th-order estimate ...
const DOP853_E5: [f64; 13] = [
    0.1312004499419488073250102996e-1, 0.0, 0.0, 0.0, 0.0, -0.1225156446376204440720569753e+1,
    -0.4957589496572501915214079952, 0.1664377182454986536961530415e+1,
    -0.3503288487499736816886487290, 0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1, -0.2235530786388629525884427845e-1, 0.0
];

/// ... and the 3rd-order one, E3 = b - bhh (bhh from Hairer's dop853.f).
const DOP853_E3: [f64; 13] = [
    5.42937341165687622380535766363e-2 - 0.244094488188976377952755905512,
    0.0,
    0.0,
    0.0,
    0.0,
    4.45031289275240888144113950566,
    1.89151789931450038304281599044,
    -5.8012039600105847814672114227,
    3.1116436695781989440891606237e-1 - 0.733846688281611857341361741547,
    -1.52160949662516078556178806805e-1,
    2.01365400804030348374776537501e-1,
    4.47106157277725905176885569043e-2 - 0.220588235294117647058823529412e-1,
    0.0
];

/// Rows 3..6 of the 7-term dense-output polynomial, as combinations of K[0..15].
const DOP853_D: [&[f64]; 4] = [
    &[-0.84289382761090128651353491142e+1, 0.0, 0.0, 0.0, 0.0, 0.56671495351937776962531783590,
     -0.30689499459498916912797304727e+1, 0.23846676565120698287728149680e+1,
     0.21170345824450282767155149946e+1, -0.87139158377797299206789907490,
     0.22404374302607882758541771650e+1, 0.63157877876946881815570249290,
     -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e+2,
     -0.91946323924783554000451984436e+1, -0.44360363875948939664310572000e+1],
    &[0.10427508642579134603413151009e+2, 0.0, 0.0, 0.0, 0.0, 0.24228349177525818288430175319e+3,
     0.16520045171727028198505394887e+3, -0.37454675472269020279518312152e+3,
     -0.22113666853125306036270938578e+2, 0.77334326684722638389603898808e+1,
     -0.30674084731089398182061213626e+2, -0.93321305264302278729567221706e+1,
     0.15697238121770843886131091075e+2, -0.31139403219565177677282850411e+2,
     -0.93529243588444783865713862664e+1, 0.35816841486394083752465898540e+2],
    &[0.19985053242002433820987653617e+2, 0.0, 0.0, 0.0, 0.0,
     -0.38703730874935176555105901742e+3, -0.18917813819516756882830838328e+3,
     0.52780815920542364900561016686e+3, -0.11573902539959630126141871134e+2,
     0.68812326946963000169666922661e+1, -0.10006050966910838403183860980e+1,
     0.77771377980534432092869265740, -0.27782057523535084065932004339e+1,
     -0.60196695231264120758267380846e+2, 0.84320405506677161018159903784e+2,
     0.11992291136182789328035130030e+2],
    &[-0.25693933462703749003312586129e+2, 0.0, 0.0, 0.0, 0.0,
     -0.15418974869023643374053993627e+3, -0.23152937917604549567536039109e+3,
     0.35763911791061412378285349910e+3, 0.93405324183624310003907691704e+2,
     -0.37458323136451633156875139351e+2, 0.10409964950896230045147246184e+3,
     0.29840293426660503123344363579e+2, -0.43533456590011143754432175058e+2,
     0.96324553959188282948394950600e+2, -0.39177261675615439165231486172e+2,
     -0.14972683625798562581422125276e+3]];

/// One embedded pair: its Butcher tableau and how to use it.
struct Tableau {
    method: Method,
    n_stages: usize, // stages per step, not counting the FSAL f(t + h, y_new)
    n_k: usize,      // rows of K: stages, FSAL, extra dense-output stages
    n_dense: usize,  // rows of the dense-output coefficients
    error_order: i32, // error ~ h^(error_order + 1)
    a: &'static [&'static [f64]],
    b: &'static [f64],
    c: &'static [f64],
}

static RK45: Tableau = Tableau {
    method: Method::Rk45, n_stages: 6, n_k: 7, n_dense: 4, error_order: 4,
    a: &RK45_A, b: &RK45_B, c: &RK45_C,
};
static DOP853: Tableau = Tableau {
    method: Method::Dop853, n_stages: 12, n_k: 16, n_dense: 7, error_order: 7,
    a: &DOP853_A, b: DOP853_A[12], c: &DOP853_C,
};

/// Python's min(a, b) and max(a, b), including how they treat nan, so the control
/// below makes exactly scipy's decisions.
fn pymin(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}
fn pymax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}
/// numpy.maximum: nan if either argument is nan.
fn npmax(a: f64, b: f64) -> f64 {
    if a > b || a.is_nan() { a } else { b }
}
fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Integrator state; K and F are row-major (rows of n).
struct Solver<'a, R> {
    tab: &'static Tableau,
    rhs: &'a mut R,
    n: usize,
    rtol: f64,
    atol: f64,
    max_step: f64,
    max_steps: u64,
    direction: f64,
    t_end: f64,
    error_exponent: f64,
    t: f64,
    t_old: f64,
    h_abs: f64,
    h_prev: f64,
    y: Vec<f64>,
    y_old: Vec<f64>,
    y_new: Vec<f64>,
    y_stage: Vec<f64>,
    y_out: Vec<f64>,
    k: Vec<f64>,
    f: Vec<f64>,
    stats: Stats,
    nonfinite: bool,
}

impl<'a, R: FnMut(f64, &[f64], &mut [f64]) -> bool> Solver<'a, R> {
    fn eval(&mut self, t: f64, which: Arg, row: usize) -> Result<(), OdeError> {
        self.stats.nfev += 1;
        let n = self.n;
        let dydt = &mut self.k[row * n..(row + 1) * n];
        let y = match which {
            Arg::Y => &self.y,
            Arg::Stage => &self.y_stage,
            Arg::YNew => &self.y_new,
        };
        if (self.rhs)(t, y, dydt) { Ok(()) } else { Err(OdeError::Rhs) }
    }

    /// sum_j K[j][i] w[j] over the rows of w.
    fn kdot(&self, i: usize, w: &[f64]) -> f64 {
        w.iter().enumerate().fold(0.0, |acc, (j, wj)| acc + self.k[j * self.n + i] * wj)
    }

    /// K[st] = f(t + c[st] h, y + h sum_{j<st} a[st][j] K[j]), as scipy's rk_step; from
    /// (t, y) or, for the dense-output stages, (t_old, y_old).
    fn stage(&mut self, st: usize, old: bool, h: f64) -> Result<(), OdeError> {
        let n = self.n;
        let a = self.tab.a[st];
        let (t, y) = if old { (self.t_old, &self.y_old) } else { (self.t, &self.y) };
        for i in 0..n {
            let mut dy = 0.0;
            for (j, aj) in a.iter().enumerate() {
                dy += self.k[j * n + i] * aj;
            }
            self.y_stage[i] = y[i] + dy * h;
        }
        self.eval(t + self.tab.c[st] * h, Arg::Stage, st)
    }

    /// One trial step from (t, y) with K[0] = f(t, y): fills K[1..n_stages - 1], y_new,
    /// and the FSAL row K[n_stages] = f(t + h, y_new).
    fn rk_step(&mut self, h: f64) -> Result<(), OdeError> {
        let ns = self.tab.n_stages;
        for st in 1..ns {
            self.stage(st, false, h)?;
        }
        for i in 0..self.n {
            let mut acc = 0.0;
            for j in 0..ns {
                acc += self.k[j * self.n + i] * self.tab.b[j];
            }
            self.y_new[i] = self.y[i] + h * acc;
        }
        self.eval(self.t + h, Arg::YNew, ns)
    }

    /// Scaled RMS error of the trial step (accept when < 1): RK45 || h K^T E / scale ||_rms,
    /// DOP853 scipy's DOP853._estimate_error_norm; scale = atol + max(|y|, |y_new|) rtol.
    fn error_norm(&self, h: f64) -> f64 {
        let (mut sum5, mut sum3) = (0.0, 0.0);
        for i in 0..self.n {
            let scale = self.atol + npmax(self.y[i].abs(), self.y_new[i].abs()) * self.rtol;
            if self.tab.method == Method::Rk45 {
                let e = self.kdot(i, &RK45_E) * h / scale;
                sum5 += e * e;
            } else {
                let e5 = self.kdot(i, &DOP853_E5) / scale;
                let e3 = self.kdot(i, &DOP853_E3) / scale;
                sum5 += e5 * e5;
                sum3 += e3 * e3;
            }
        }
        let n = self.n as f64;
        if self.tab.method == Method::Rk45 {
            return sum5.sqrt() / n.sqrt();
        }
        // scipy squares np.linalg.norm, i.e. sqrt(sum) ** 2: keep that rounding.
        let norm5_2 = sum5.sqrt() * sum5.sqrt();
        let norm3_2 = sum3.sqrt() * sum3.sqrt();
        if norm5_2 == 0.0 && norm3_2 == 0.0 {
            return 0.0;
        }
        h.abs() * norm5_2 / ((norm5_2 + 0.01 * norm3_2) * n).sqrt()
    }

    /// scipy's select_initial_step (Hairer, Norsett & Wanner, Sec. II.4), with
    /// K[0] = f(t0, y0); uses K[1] for f(t0 + h0, y1).
    fn initial_step(&mut self) -> Result<f64, OdeError> {
        let n = self.n;
        let interval = (self.t_end - self.t).abs();
        let (mut d0, mut d1, mut d2) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            let scale = self.atol + self.y[i].abs() * self.rtol;
            d0 += (self.y[i] / scale) * (self.y[i] / scale);
            d1 += (self.k[i] / scale) * (self.k[i] / scale);
        }
        d0 = d0.sqrt() / (n as f64).sqrt();
        d1 = d1.sqrt() / (n as f64).sqrt();
        let mut h0 = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
        h0 = pymin(h0, interval);
        for i in 0..n {
            self.y_stage[i] = self.y[i] + h0 * self.direction * self.k[i];
        }
        self.eval(self.t + h0 * self.direction, Arg::Stage, 1)?;
        for i in 0..n {
            let scale = self.atol + self.y[i].abs() * self.rtol;
            let r = (self.k[n + i] - self.k[i]) / scale;
            d2 += r * r;
        }
        d2 = d2.sqrt() / (n as f64).sqrt() / h0;
        let h1 = if d1 <= 1e-15 && d2 <= 1e-15 {
            pymax(1e-6, h0 * 1e-3)
        } else {
            (0.01 / pymax(d1, d2)).powf(1.0 / (self.tab.error_order + 1) as f64)
        };
        Ok(pymin(pymin(pymin(100.0 * h0, h1), interval), self.max_step))
    }

    /// One accepted step with scipy's RungeKutta._step_impl control.
    fn step(&mut self) -> Result<(), OdeError> {
        let t = self.t;
        // Steps below 10 ulp(t) cannot advance t meaningfully.
        let next = if self.direction > 0.0 { t.next_up() } else { t.next_down() };
        let min_step = 10.0 * (next - t).abs();
        let mut h_abs = self.h_abs;
        if h_abs > self.max_step {
            h_abs = self.max_step;
        } else if h_abs < min_step {
            h_abs = min_step;
        }
        let mut rejected = false;
        let (mut h, mut t_new);
        loop {
            if !(h_abs >= min_step) {
                // also stops on a nan step size
                return Err(if self.nonfinite { OdeError::NonFinite } else { OdeError::StepTooSmall });
            }
            h = h_abs * self.direction;
            t_new = t + h;
            if self.direction * (t_new - self.t_end) > 0.0 {
                t_new = self.t_end;
            }
            h = t_new - t;
            h_abs = h.abs();
            self.rk_step(h)?;
            let err = self.error_norm(h);
            self.nonfinite = !err.is_finite();
            if err < 1.0 {
                let mut factor = if err == 0.0 {
                    MAX_FACTOR
                } else {
                    pymin(MAX_FACTOR, SAFETY * err.powf(self.error_exponent))
                };
                if rejected {
                    factor = pymin(1.0, factor); // do not grow right after a rejection
                }
                h_abs *= factor;
                break;
            }
            h_abs *= pymax(MIN_FACTOR, SAFETY * err.powf(self.error_exponent));
            rejected = true;
            self.stats.n_rejected += 1;
        }
        // A non-finite state must never be accepted.
        let ns = self.tab.n_stages;
        if !all_finite(&self.y_new) || !all_finite(&self.k[ns * self.n..(ns + 1) * self.n]) {
            return Err(OdeError::NonFinite);
        }
        // Accept: y_new becomes y, the old y is kept for dense output.
        std::mem::swap(&mut self.y_old, &mut self.y);
        std::mem::swap(&mut self.y, &mut self.y_new);
        self.t_old = t;
        self.t = t_new;
        self.h_prev = h;
        self.h_abs = h_abs;
        self.stats.n_accepted += 1;
        Ok(())
    }

    /// Coefficients of the interpolant over the last accepted step (scipy's
    /// _dense_output_impl); DOP853 spends 3 more rhs evaluations here.
    fn dense_prepare(&mut self) -> Result<(), OdeError> {
        let n = self.n;
        let h = self.h_prev;
        if self.tab.method == Method::Rk45 {
            // F[k] = K^T P[:, k], scipy's Q = K.T @ P
            for kk in 0..self.tab.n_dense {
                for i in 0..n {
                    let mut acc = 0.0;
                    for j in 0..self.tab.n_k {
                        acc += self.k[j * n + i] * RK45_P[j][kk];
                    }
                    self.f[kk * n + i] = acc;
                }
            }
            return Ok(());
        }
        for st in self.tab.n_stages + 1..self.tab.n_k {
            self.stage(st, true, h)?;
        }
        let ns = self.tab.n_stages;
        for i in 0..n {
            let f_old = self.k[i];
            let f_new = self.k[ns * n + i];
            let dy = self.y[i] - self.y_old[i];
            self.f[i] = dy;
            self.f[n + i] = h * f_old - dy;
            self.f[2 * n + i] = 2.0 * dy - h * (f_new + f_old);
            for (kk, d) in DOP853_D.iter().enumerate() {
                let value = h * self.kdot(i, d);
                self.f[(3 + kk) * n + i] = value;
            }
        }
        Ok(())
    }

    /// y_out = the interpolant at t, with t inside the last accepted step.
    fn dense_eval(&mut self, t: f64) {
        let n = self.n;
        let h = self.t - self.t_old;
        let x = (t - self.t_old) / h;
        for i in 0..n {
            let mut acc = 0.0;
            if self.tab.method == Method::Rk45 {
                // y_old + h sum_k F[k] x^(k+1)
                let mut xp = x;
                for r in 0..4 {
                    acc += self.f[r * n + i] * xp;
                    xp *= x;
                }
                self.y_out[i] = h * acc + self.y_old[i];
            } else {
                // Hairer's contd8: alternate factors x and (1 - x), from F[6] down.
                for r in 0..7 {
                    acc += self.f[(6 - r) * n + i];
                    acc *= if r % 2 == 0 { x } else { 1.0 - x };
                }
                self.y_out[i] = acc + self.y_old[i];
            }
        }
    }

    /// Integrate from the state in y; emit every output time.
    fn run<O: FnMut(f64, &[f64]) -> bool>(&mut self, out: &mut O, t_out: &[f64]) -> Result<(), OdeError> {
        self.eval(self.t, Arg::Y, 0)?;
        if !all_finite(&self.k[..self.n]) {
            return Err(OdeError::NonFinite);
        }
        let mut next = 0;
        if self.t == self.t_end {
            // empty interval: every output time is t0
            for &t in t_out {
                if !out(t, &self.y) {
                    return Err(OdeError::Interrupted);
                }
            }
            return Ok(());
        }
        self.h_abs = self.initial_step()?;
        loop {
            let mut dense_ready = false;
            if self.max_steps > 0 && self.stats.n_accepted >= self.max_steps {
                return Err(OdeError::MaxSteps);
            }
            self.step()?;
            // Output times up to and including t come from this step's interpolant.
            while next < t_out.len() && self.direction * (t_out[next] - self.t) <= 0.0 {
                if !dense_ready {
                    self.dense_prepare()?;
                    dense_ready = true;
                }
                self.dense_eval(t_out[next]);
                if !out(t_out[next], &self.y_out) {
                    return Err(OdeError::Interrupted);
                }
                next += 1;
            }
            if self.direction * (self.t - self.t_end) >= 0.0 {
                return Ok(());
            }
            // First same as last: f(t, y) of the next step is this step's FSAL row.
            let ns = self.tab.n_stages;
            self.k.copy_within(ns * self.n..(ns + 1) * self.n, 0);
        }
    }
}

/// Which state a right-hand-side evaluation reads.
#[derive(Clone, Copy)]
enum Arg {
    Y,
    Stage,
    YNew,
}

/// Output times must lie in the integration interval and move strictly towards t_end,
/// as solve_ivp requires of t_eval.
fn times_ok(t0: f64, t_end: f64, t_out: &[f64]) -> bool {
    let (lo, hi) = if t0 < t_end { (t0, t_end) } else { (t_end, t0) };
    t_out.iter().all(|t| *t >= lo && *t <= hi)
        && t_out.windows(2).all(|w| if t_end > t0 { w[1] > w[0] } else if t_end < t0 { w[1] < w[0] } else { true })
}

/// Integrate y' = rhs(t, y) from (t0, y0) to t_end, calling `out` at every time of
/// `t_out` (see the top of this file). Returns the statistics, or the reason it stopped
/// with the statistics so far.
#[allow(clippy::too_many_arguments)]
pub fn integrate<R, O>(method: Method, rhs: R, out: O, t0: f64, y0: &[f64], t_end: f64,
                       t_out: &[f64], rtol: f64, atol: f64, max_step: f64)
                       -> Result<Stats, (OdeError, Stats)>
where
    R: FnMut(f64, &[f64], &mut [f64]) -> bool,
    O: FnMut(f64, &[f64]) -> bool,
{
    integrate_bounded(method, rhs, out, t0, y0, t_end, t_out, rtol, atol, max_step, 0)
}

/// `integrate`, stopping with `OdeError::MaxSteps` before a step beyond `max_steps`
/// accepted ones (0: no bound), as lagcli_ode_integrate_bounded does.
#[allow(clippy::too_many_arguments)]
pub fn integrate_bounded<R, O>(method: Method, mut rhs: R, mut out: O, t0: f64, y0: &[f64], t_end: f64,
                               t_out: &[f64], rtol: f64, atol: f64, max_step: f64, max_steps: u64)
                               -> Result<Stats, (OdeError, Stats)>
where
    R: FnMut(f64, &[f64], &mut [f64]) -> bool,
    O: FnMut(f64, &[f64]) -> bool,
{
    let stopped = Stats { t: t0, ..Stats::default() };
    if y0.is_empty() || !t0.is_finite() || !t_end.is_finite() || rtol.is_nan() || !(atol >= 0.0)
        || !(max_step > 0.0) || !times_ok(t0, t_end, t_out)
    {
        return Err((OdeError::Args, stopped));
    }
    if !all_finite(y0) {
        return Err((OdeError::NonFinite, stopped));
    }
    let tab = method.tableau();
    let n = y0.len();
    let mut solver = Solver {
        tab,
        rhs: &mut rhs,
        n,
        rtol: if rtol < 100.0 * f64::EPSILON { 100.0 * f64::EPSILON } else { rtol }, // as scipy
        atol,
        max_step,
        max_steps,
        direction: if t_end >= t0 { 1.0 } else { -1.0 },
        t_end,
        error_exponent: -1.0 / (tab.error_order + 1) as f64,
        t: t0,
        t_old: t0,
        h_abs: 0.0,
        h_prev: 0.0,
        y: y0.to_vec(),
        y_old: vec![0.0; n],
        y_new: vec![0.0; n],
        y_stage: vec![0.0; n],
        y_out: vec![0.0; n],
        k: vec![0.0; tab.n_k * n],
        f: vec![0.0; tab.n_dense * n],
        stats: stopped,
        nonfinite: false,
    };
    let result = solver.run(&mut out, t_out);
    solver.stats.t = solver.t;
    match result {
        Ok(()) => Ok(solver.stats),
        Err(e) => Err((e, solver.stats)),
    }
}
