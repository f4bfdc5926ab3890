/* lagcli's explicit Runge-Kutta integrator (RK45, DOP853): see lagcli_ode.h and
 * docs/c-integrator.md. Shipped with lagcli (lagcli/runtime/c/) and copied next to
 * every generated C model; C99 + libm. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "lagcli_ode.h"

/* Step-size control constants of scipy/integrate/_ivp/rk.py. */
static const double LAGCLI_ODE_SAFETY = 0.9;      /* applied to the asymptotic step estimate */
static const double LAGCLI_ODE_MIN_FACTOR = 0.2;  /* largest decrease in one rejection */
static const double LAGCLI_ODE_MAX_FACTOR = 10.0; /* largest increase after one step */

enum { LAGCLI_ODE_MAX_STAGES = 16 }; /* DOP853: 12 stages, FSAL, 3 dense-output stages */
enum { LAGCLI_ODE_KIND_RK45, LAGCLI_ODE_KIND_DOP853 };

/* ---- RK45: Dormand-Prince 5(4), scipy's RK45 class ------------------- */
static const double LAGCLI_ODE_RK45_C[6] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0};
static const double LAGCLI_ODE_RK45_A[6][LAGCLI_ODE_MAX_STAGES] = {
    {0.0},
    {1.0 / 5},
    {3.0 / 40, 9.0 / 40},
    {44.0 / 45, -56.0 / 15, 32.0 / 9},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656}};
static const double LAGCLI_ODE_RK45_B[6] = {
    35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84};
/* Error weights over the 7 rows of K (the 7th is the FSAL f(t+h, y_new)). */
static const double LAGCLI_ODE_RK45_E[7] = {
    -71.0 / 57600, 0.0, 71.0 / 16695, -71.0 / 1920, 17253.0 / 339200, -22.0 / 525, 1.0 / 40};
/* Quartic dense output (Shampine 1986): y(t_old + x h) = y_old + h K^T P [x x^2 x^3 x^4]. */
static const double LAGCLI_ODE_RK45_P[7][4] = {
    {1.0, -8048581381.0 / 2820520608, 8663915743.0 / 2820520608,
     -12715105075.0 / 11282082432},
    {0.0, 0.0, 0.0, 0.0},
    {0.0, 131558114200.0 / 32700410799, -68118460800.0 / 10900136933,
     87487479700.0 / 32700410799},
    {0.0, -1754552775.0 / 470086768, 14199869525.0 / 1410260304,
     -10690763975.0 / 1880347072},
    {0.0, 127303824393.0 / 49829197408, -318862633887.0 / 49829197408,
     701980252875.0 / 199316789632},
    {0.0, -282668133.0 / 205662961, 2019193451.0 / 616988883, -1453857185.0 / 822651844},
    {0.0, 40617522.0 / 29380423, -110615467.0 / 29380423, 69997945.0 / 29380423}};

/* ---- DOP853: coefficients of scipy's dop853_coefficients.py ----------- */
/* Nodes: 12 stages, the FSAL node 1.0, then the 3 extra dense-output stages. */
static const double LAGCLI_ODE_DOP853_C[16] = {
    0.0, 0.526001519587677318785587544488e-01, 0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510, 0.281649658092772603273242802490,
    0.333333333333333333333333333333, 0.25, 0.307692307692307692307692307692,
    0.651282051282051282051282051282, 0.6, 0.857142857142857142857142857142, 1.0, 1.0, 0.1, 0.2,
    0.777777777777777777777777777778
};
/* Row s holds a[s][0..s-1]; row 12 is the solution weights b; rows 13-15
 * are the extra stages evaluated only for dense output. */
static const double LAGCLI_ODE_DOP853_A[16][LAGCLI_ODE_MAX_STAGES] = {
    /*  0 */ {0.0},
    /*  1 */ {5.26001519587677318785587544488e-2},
    /*  2 */ {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2},
    /*  3 */ {2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2},
    /*  4 */ {2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1,
              9.24834003261792003115737966543e-1},
    /*  5 */ {3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1,
              1.25467687566822425016691814123e-1},
    /*  6 */ {3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1,
              6.02165389804559606850219397283e-2, -1.7578125e-2},
    /*  7 */ {3.70920001185047927108779319836e-2, 0.0, 0.0, 1.70383925712239993810214054705e-1,
              1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
              8.27378916381402288758473766002e-3},
    /*  8 */ {6.24110958716075717114429577812e-1, 0.0, 0.0, -3.36089262944694129406857109825,
              -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
              2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1},
    /*  9 */ {4.77662536438264365890433908527e-1, 0.0, 0.0, -2.48811461997166764192642586468,
              -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
              1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
              -2.03312017085086261358222928593e-2},
    /* 10 */ {-9.3714243008598732571704021658e-1, 0.0, 0.0, 5.18637242884406370830023853209,
              1.09143734899672957818500254654, -8.14978701074692612513997267357,
              -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
              2.49360555267965238987089396762, -3.0467644718982195003823669022},
    /* 11 */ {2.27331014751653820792359768449, 0.0, 0.0, -1.05344954667372501984066689879e1,
              -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
              2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
              -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
              6.43392746015763530355970484046e-1},
    /* 12 */ {5.42937341165687622380535766363e-2, 0.0, 0.0, 0.0, 0.0,
              4.45031289275240888144113950566, 1.89151789931450038304281599044,
              -5.8012039600105847814672114227, 3.1116436695781989440891606237e-1,
              -1.52160949662516078556178806805e-1, 2.01365400804030348374776537501e-1,
              4.47106157277725905176885569043e-2},
    /* 13 */ {5.61675022830479523392909219681e-2, 0.0, 0.0, 0.0, 0.0, 0.0,
              2.53500210216624811088794765333e-1, -2.46239037470802489917441475441e-1,
              -1.24191423263816360469010140626e-1, 1.5329179827876569731206322685e-1,
              8.20105229563468988491666602057e-3, 7.56789766054569976138603589584e-3, -8.298e-3},
    /* 14 */ {3.18346481635021405060768473261e-2, 0.0, 0.0, 0.0, 0.0,
              2.83009096723667755288322961402e-2, 5.35419883074385676223797384372e-2,
              -5.49237485713909884646569340306e-2, 0.0, 0.0,
              -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4,
              -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1},
    /* 15 */ {-4.28896301583791923408573538692e-1, 0.0, 0.0, 0.0, 0.0,
              -4.69762141536116384314449447206, 7.68342119606259904184240953878,
              4.06898981839711007970213554331, 3.56727187455281109270669543021e-1, 0.0, 0.0,
              0.0, -1.39902416515901462129418009734e-3, 2.9475147891527723389556272149,
              -9.15095847217987001081870187138}};
/* Error weights over K[0..12]: the 5th-order estimate ... */
static const double LAGCLI_ODE_DOP853_E5[13] = {
    0.1312004499419488073250102996e-1, 0.0, 0.0, 0.0, 0.0, -0.1225156446376204440720569753e+1,
    -0.4957589496572501915214079952, 0.1664377182454986536961530415e+1,
    -0.3503288487499736816886487290, 0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1, -0.2235530786388629525884427845e-1, 0.0
};
/* ... and the 3rd-order one, E3 = b - bhh (bhh from Hairer's dop853.f). */
static const double LAGCLI_ODE_DOP853_E3[13] = {
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
};
/* Rows 3..6 of the 7-term dense-output polynomial, as combinations of K[0..15]. */
static const double LAGCLI_ODE_DOP853_D[4][16] = {
    {-0.84289382761090128651353491142e+1, 0.0, 0.0, 0.0, 0.0, 0.56671495351937776962531783590,
     -0.30689499459498916912797304727e+1, 0.23846676565120698287728149680e+1,
     0.21170345824450282767155149946e+1, -0.87139158377797299206789907490,
     0.22404374302607882758541771650e+1, 0.63157877876946881815570249290,
     -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e+2,
     -0.91946323924783554000451984436e+1, -0.44360363875948939664310572000e+1},
    {0.10427508642579134603413151009e+2, 0.0, 0.0, 0.0, 0.0, 0.24228349177525818288430175319e+3,
     0.16520045171727028198505394887e+3, -0.37454675472269020279518312152e+3,
     -0.22113666853125306036270938578e+2, 0.77334326684722638389603898808e+1,
     -0.30674084731089398182061213626e+2, -0.93321305264302278729567221706e+1,
     0.15697238121770843886131091075e+2, -0.31139403219565177677282850411e+2,
     -0.93529243588444783865713862664e+1, 0.35816841486394083752465898540e+2},
    {0.19985053242002433820987653617e+2, 0.0, 0.0, 0.0, 0.0,
     -0.38703730874935176555105901742e+3, -0.18917813819516756882830838328e+3,
     0.52780815920542364900561016686e+3, -0.11573902539959630126141871134e+2,
     0.68812326946963000169666922661e+1, -0.10006050966910838403183860980e+1,
     0.77771377980534432092869265740, -0.27782057523535084065932004339e+1,
     -0.60196695231264120758267380846e+2, 0.84320405506677161018159903784e+2,
     0.11992291136182789328035130030e+2},
    {-0.25693933462703749003312586129e+2, 0.0, 0.0, 0.0, 0.0,
     -0.15418974869023643374053993627e+3, -0.23152937917604549567536039109e+3,
     0.35763911791061412378285349910e+3, 0.93405324183624310003907691704e+2,
     -0.37458323136451633156875139351e+2, 0.10409964950896230045147246184e+3,
     0.29840293426660503123344363579e+2, -0.43533456590011143754432175058e+2,
     0.96324553959188282948394950600e+2, -0.39177261675615439165231486172e+2,
     -0.14972683625798562581422125276e+3}};

/* One embedded pair: its Butcher tableau and how to use it. */
typedef struct {
    const char *name;  /* scipy's method name */
    int kind;          /* LAGCLI_ODE_KIND_*: selects the error norm and dense output */
    int n_stages;      /* stages per step, not counting the FSAL f(t + h, y_new) */
    int n_k;           /* rows of K: stages, FSAL, extra dense-output stages */
    int n_dense;       /* rows of the dense-output coefficients */
    int error_order;   /* error ~ h^(error_order + 1) */
    const double (*a)[LAGCLI_ODE_MAX_STAGES];
    const double *b;
    const double *c;
} lagcli_ode_tableau;

static const lagcli_ode_tableau LAGCLI_ODE_TABLEAUS[] = {
    {"RK45", LAGCLI_ODE_KIND_RK45, 6, 7, 4, 4, LAGCLI_ODE_RK45_A, LAGCLI_ODE_RK45_B, LAGCLI_ODE_RK45_C},
    {"DOP853", LAGCLI_ODE_KIND_DOP853, 12, 16, 7, 7, LAGCLI_ODE_DOP853_A, LAGCLI_ODE_DOP853_A[12], LAGCLI_ODE_DOP853_C}};

/* Integrator state; all arrays point into one malloc'ed block. */
typedef struct {
    const lagcli_ode_tableau *tab;
    lagcli_ode_rhs_fn rhs;
    void *ctx;
    int n;
    double rtol, atol, max_step;
    long max_steps;        /* accepted steps allowed (0: no bound) */
    double direction;      /* +1 or -1 */
    double t_end;
    double error_exponent; /* -1 / (error_order + 1) */
    double t, t_old;       /* the last accepted step went from t_old to t */
    double h_abs;          /* size proposed for the next step */
    double h_prev;         /* signed size of the last accepted step */
    double *y, *y_old;     /* state at t and t_old */
    double *y_new;         /* trial state at t + h */
    double *y_stage;       /* argument of the current stage evaluation */
    double *y_out;         /* dense-output value handed to the output callback */
    double *K;             /* n_k rows of n: stage derivatives; K[0] = f(t, y) */
    double *F;             /* n_dense rows of n: dense-output coefficients */
    long nfev, n_accepted, n_rejected;
    int nonfinite;         /* the last step attempt produced inf or nan */
} lagcli_ode_solver;

const char *lagcli_ode_message(int code)
{
    switch (code) {
    case LAGCLI_ODE_OK: return "the solver successfully reached the end of the integration interval";
    case LAGCLI_ODE_ERR_STEP_TOO_SMALL: return "required step size is less than spacing between numbers";
    case LAGCLI_ODE_ERR_RHS: return "the right-hand side reported a failure";
    case LAGCLI_ODE_ERR_NONFINITE: return "the solution became non-finite (inf or nan)";
    case LAGCLI_ODE_INTERRUPTED: return "integration stopped by the output callback";
    case LAGCLI_ODE_ERR_ARGS: return "invalid arguments (method, tolerances, max_step or output times)";
    case LAGCLI_ODE_ERR_NOMEM: return "out of memory";
    case LAGCLI_ODE_ERR_MAX_STEPS: return "the bound on the number of steps was reached";
    default: return "unknown error";
    }
}

/* Python's min(a, b) and max(a, b), including how they treat nan, so the
 * control below makes exactly scipy's decisions. */
static double lagcli_ode_pymin(double a, double b) { return b < a ? b : a; }
static double lagcli_ode_pymax(double a, double b) { return b > a ? b : a; }

/* numpy.maximum: nan if either argument is nan. */
static double lagcli_ode_npmax(double a, double b) { return (a > b || a != a) ? a : b; }

static int lagcli_ode_all_finite(int n, const double *v)
{
    int i;
    for (i = 0; i < n; ++i)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static double *lagcli_ode_krow(const lagcli_ode_solver *s, int row) { return s->K + (size_t)row * s->n; }

static int lagcli_ode_eval(lagcli_ode_solver *s, double t, const double *y, double *dydt)
{
    s->nfev++;
    return s->rhs(t, y, dydt, s->ctx) ? LAGCLI_ODE_ERR_RHS : LAGCLI_ODE_OK;
}

/* K[st] = f(t + c[st] h, y + h sum_{j<st} a[st][j] K[j]), as scipy's rk_step. */
static int lagcli_ode_stage(lagcli_ode_solver *s, int st, double t, const double *y, double h)
{
    const double *a = s->tab->a[st];
    int i, j;
    for (i = 0; i < s->n; ++i) {
        double dy = 0.0;
        for (j = 0; j < st; ++j)
            dy += s->K[(size_t)j * s->n + i] * a[j];
        s->y_stage[i] = y[i] + dy * h;
    }
    return lagcli_ode_eval(s, t + s->tab->c[st] * h, s->y_stage, lagcli_ode_krow(s, st));
}

/* One trial step from (t, y) with K[0] = f(t, y): fills K[1..n_stages - 1],
 * y_new, and the FSAL row K[n_stages] = f(t + h, y_new). */
static int lagcli_ode_rk_step(lagcli_ode_solver *s, double h)
{
    const int ns = s->tab->n_stages;
    int i, j, st, rc;
    for (st = 1; st < ns; ++st)
        if ((rc = lagcli_ode_stage(s, st, s->t, s->y, h)) != LAGCLI_ODE_OK)
            return rc;
    for (i = 0; i < s->n; ++i) {
        double acc = 0.0;
        for (j = 0; j < ns; ++j)
            acc += s->K[(size_t)j * s->n + i] * s->tab->b[j];
        s->y_new[i] = s->y[i] + h * acc;
    }
    return lagcli_ode_eval(s, s->t + h, s->y_new, lagcli_ode_krow(s, ns));
}

/* sum_j K[j][i] w[j] over the first `rows` rows of K. */
static double lagcli_ode_kdot(const lagcli_ode_solver *s, int i, const double *w, int rows)
{
    double acc = 0.0;
    int j;
    for (j = 0; j < rows; ++j)
        acc += s->K[(size_t)j * s->n + i] * w[j];
    return acc;
}

/* Scaled RMS error of the trial step (accept when < 1):
 * RK45:   || h K^T E / scale ||_rms
 * DOP853: scipy's DOP853._estimate_error_norm, err5 damped by err3;
 * with scale = atol + max(|y|, |y_new|) rtol. */
static double lagcli_ode_error_norm(const lagcli_ode_solver *s, double h)
{
    const int rows = s->tab->n_stages + 1;
    double sum5 = 0.0, sum3 = 0.0, norm5_2, norm3_2;
    int i;
    for (i = 0; i < s->n; ++i) {
        double scale = s->atol + lagcli_ode_npmax(fabs(s->y[i]), fabs(s->y_new[i])) * s->rtol;
        if (s->tab->kind == LAGCLI_ODE_KIND_RK45) {
            double e = lagcli_ode_kdot(s, i, LAGCLI_ODE_RK45_E, rows) * h / scale;
            sum5 += e * e;
        } else {
            double e5 = lagcli_ode_kdot(s, i, LAGCLI_ODE_DOP853_E5, rows) / scale;
            double e3 = lagcli_ode_kdot(s, i, LAGCLI_ODE_DOP853_E3, rows) / scale;
            sum5 += e5 * e5;
            sum3 += e3 * e3;
        }
    }
    if (s->tab->kind == LAGCLI_ODE_KIND_RK45)
        return sqrt(sum5) / sqrt((double)s->n);
    /* scipy squares np.linalg.norm, i.e. sqrt(sum) ** 2: keep that rounding. */
    norm5_2 = sqrt(sum5) * sqrt(sum5);
    norm3_2 = sqrt(sum3) * sqrt(sum3);
    if (norm5_2 == 0.0 && norm3_2 == 0.0)
        return 0.0;
    return fabs(h) * norm5_2 / sqrt((norm5_2 + 0.01 * norm3_2) * s->n);
}

/* scipy's select_initial_step (Hairer, Norsett & Wanner, Sec. II.4), with
 * K[0] = f(t0, y0); uses K[1] as scratch for f(t0 + h0, y1). */
static int lagcli_ode_initial_step(lagcli_ode_solver *s, double *h_abs)
{
    const double interval = fabs(s->t_end - s->t);
    const double *f0 = s->K;
    double *f1 = lagcli_ode_krow(s, 1);
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, h0, h1;
    int i, rc;

    for (i = 0; i < s->n; ++i) {
        double scale = s->atol + fabs(s->y[i]) * s->rtol;
        d0 += (s->y[i] / scale) * (s->y[i] / scale);
        d1 += (f0[i] / scale) * (f0[i] / scale);
    }
    d0 = sqrt(d0) / sqrt((double)s->n);
    d1 = sqrt(d1) / sqrt((double)s->n);
    h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = lagcli_ode_pymin(h0, interval);

    for (i = 0; i < s->n; ++i)
        s->y_stage[i] = s->y[i] + h0 * s->direction * f0[i];
    if ((rc = lagcli_ode_eval(s, s->t + h0 * s->direction, s->y_stage, f1)) != LAGCLI_ODE_OK)
        return rc;
    for (i = 0; i < s->n; ++i) {
        double scale = s->atol + fabs(s->y[i]) * s->rtol;
        double r = (f1[i] - f0[i]) / scale;
        d2 += r * r;
    }
    d2 = sqrt(d2) / sqrt((double)s->n) / h0;

    if (d1 <= 1e-15 && d2 <= 1e-15)
        h1 = lagcli_ode_pymax(1e-6, h0 * 1e-3);
    else
        h1 = pow(0.01 / lagcli_ode_pymax(d1, d2), 1.0 / (s->tab->error_order + 1));
    *h_abs = lagcli_ode_pymin(lagcli_ode_pymin(lagcli_ode_pymin(100 * h0, h1), interval), s->max_step);
    return LAGCLI_ODE_OK;
}

/* One accepted step with scipy's RungeKutta._step_impl control. */
static int lagcli_ode_step(lagcli_ode_solver *s)
{
    const double t = s->t;
    /* Steps below 10 ulp(t) cannot advance t meaningfully. */
    const double min_step = 10.0 * fabs(nextafter(t, s->direction * HUGE_VAL) - t);
    double h_abs = s->h_abs, h = 0.0, t_new = t, *swap;
    int rejected = 0, rc;

    if (h_abs > s->max_step)
        h_abs = s->max_step;
    else if (h_abs < min_step)
        h_abs = min_step;

    for (;;) {
        double err, factor;
        if (!(h_abs >= min_step)) /* also stops on a nan step size */
            return s->nonfinite ? LAGCLI_ODE_ERR_NONFINITE : LAGCLI_ODE_ERR_STEP_TOO_SMALL;
        h = h_abs * s->direction;
        t_new = t + h;
        if (s->direction * (t_new - s->t_end) > 0)
            t_new = s->t_end;
        h = t_new - t;
        h_abs = fabs(h);

        if ((rc = lagcli_ode_rk_step(s, h)) != LAGCLI_ODE_OK)
            return rc;
        err = lagcli_ode_error_norm(s, h);
        s->nonfinite = !isfinite(err);
        if (err < 1.0) {
            factor = err == 0.0 ? LAGCLI_ODE_MAX_FACTOR
                                : lagcli_ode_pymin(LAGCLI_ODE_MAX_FACTOR,
                                            LAGCLI_ODE_SAFETY * pow(err, s->error_exponent));
            if (rejected) /* do not grow right after a rejection */
                factor = lagcli_ode_pymin(1.0, factor);
            h_abs *= factor;
            break;
        }
        h_abs *= lagcli_ode_pymax(LAGCLI_ODE_MIN_FACTOR, LAGCLI_ODE_SAFETY * pow(err, s->error_exponent));
        rejected = 1;
        s->n_rejected++;
    }

    /* An error norm below 1 cannot normally come with inf/nan, but a
     * non-finite state must never be accepted. */
    if (!lagcli_ode_all_finite(s->n, s->y_new) || !lagcli_ode_all_finite(s->n, lagcli_ode_krow(s, s->tab->n_stages)))
        return LAGCLI_ODE_ERR_NONFINITE;

    /* Accept: y_new becomes y, the old y is kept for dense output. */
    swap = s->y_old;
    s->y_old = s->y;
    s->y = s->y_new;
    s->y_new = swap;
    s->t_old = t;
    s->t = t_new;
    s->h_prev = h;
    s->h_abs = h_abs;
    s->n_accepted++;
    return LAGCLI_ODE_OK;
}

/* Coefficients of the interpolant over the last accepted step (scipy's
 * _dense_output_impl).  DOP853 spends 3 more rhs evaluations here, which is
 * why this runs only for steps that contain an output time, as in scipy. */
static int lagcli_ode_dense_prepare(lagcli_ode_solver *s)
{
    const int n = s->n;
    const double h = s->h_prev;
    int i, k, st, rc;

    if (s->tab->kind == LAGCLI_ODE_KIND_RK45) {
        /* F[k] = K^T P[:, k], scipy's Q = K.T @ P */
        for (k = 0; k < s->tab->n_dense; ++k)
            for (i = 0; i < n; ++i) {
                double acc = 0.0;
                int j;
                for (j = 0; j < s->tab->n_k; ++j)
                    acc += s->K[(size_t)j * n + i] * LAGCLI_ODE_RK45_P[j][k];
                s->F[(size_t)k * n + i] = acc;
            }
        return LAGCLI_ODE_OK;
    }

    for (st = s->tab->n_stages + 1; st < s->tab->n_k; ++st)
        if ((rc = lagcli_ode_stage(s, st, s->t_old, s->y_old, h)) != LAGCLI_ODE_OK)
            return rc;
    for (i = 0; i < n; ++i) {
        const double f_old = s->K[i];
        const double f_new = s->K[(size_t)s->tab->n_stages * n + i];
        const double dy = s->y[i] - s->y_old[i];
        s->F[i] = dy;
        s->F[(size_t)n + i] = h * f_old - dy;
        s->F[(size_t)2 * n + i] = 2 * dy - h * (f_new + f_old);
        for (k = 0; k < 4; ++k)
            s->F[(size_t)(3 + k) * n + i] = h * lagcli_ode_kdot(s, i, LAGCLI_ODE_DOP853_D[k], s->tab->n_k);
    }
    return LAGCLI_ODE_OK;
}

/* y_out = interpolant at t, with t inside the last accepted step. */
static void lagcli_ode_dense_eval(lagcli_ode_solver *s, double t)
{
    const int n = s->n;
    const double h = s->t - s->t_old;
    const double x = (t - s->t_old) / h;
    int i, r;

    for (i = 0; i < n; ++i) {
        double acc = 0.0;
        if (s->tab->kind == LAGCLI_ODE_KIND_RK45) {
            /* y_old + h sum_k F[k] x^(k+1) */
            double xp = x;
            for (r = 0; r < 4; ++r) {
                acc += s->F[(size_t)r * n + i] * xp;
                xp *= x;
            }
            s->y_out[i] = h * acc + s->y_old[i];
        } else {
            /* Hairer's contd8: alternate factors x and (1 - x), from F[6] down. */
            for (r = 0; r < 7; ++r) {
                acc += s->F[(size_t)(6 - r) * n + i];
                acc *= (r % 2 == 0) ? x : 1 - x;
            }
            s->y_out[i] = acc + s->y_old[i];
        }
    }
}

static const lagcli_ode_tableau *lagcli_ode_find_method(const char *name)
{
    size_t m;
    for (m = 0; name && m < sizeof LAGCLI_ODE_TABLEAUS / sizeof LAGCLI_ODE_TABLEAUS[0]; ++m)
        if (strcmp(name, LAGCLI_ODE_TABLEAUS[m].name) == 0)
            return &LAGCLI_ODE_TABLEAUS[m];
    return NULL;
}

/* Output times must lie in the integration interval and move strictly
 * towards t_end, as solve_ivp requires of t_eval. */
static int lagcli_ode_check_times(double t0, double t_end, const double *t_out, size_t n_out)
{
    const double lo = t0 < t_end ? t0 : t_end, hi = t0 < t_end ? t_end : t0;
    size_t i;
    if (n_out > 0 && !t_out)
        return 0;
    for (i = 0; i < n_out; ++i) {
        if (!(t_out[i] >= lo && t_out[i] <= hi))
            return 0;
        if (i > 0 && t_end > t0 && !(t_out[i] > t_out[i - 1]))
            return 0;
        if (i > 0 && t_end < t0 && !(t_out[i] < t_out[i - 1]))
            return 0;
    }
    return 1;
}

/* Integrate from the state already in s->y; emit every output time. */
static int lagcli_ode_run(lagcli_ode_solver *s, lagcli_ode_out_fn out, const double *t_out, size_t n_out,
                   void *ctx)
{
    size_t next = 0;
    int rc;

    if ((rc = lagcli_ode_eval(s, s->t, s->y, s->K)) != LAGCLI_ODE_OK)
        return rc;
    if (!lagcli_ode_all_finite(s->n, s->K))
        return LAGCLI_ODE_ERR_NONFINITE;
    if (s->t == s->t_end) { /* empty interval: every output time is t0 */
        for (; next < n_out; ++next)
            if (out(t_out[next], s->y, ctx))
                return LAGCLI_ODE_INTERRUPTED;
        return LAGCLI_ODE_OK;
    }
    if ((rc = lagcli_ode_initial_step(s, &s->h_abs)) != LAGCLI_ODE_OK)
        return rc;

    for (;;) {
        int dense_ready = 0;
        if (s->max_steps > 0 && s->n_accepted >= s->max_steps)
            return LAGCLI_ODE_ERR_MAX_STEPS;
        if ((rc = lagcli_ode_step(s)) != LAGCLI_ODE_OK)
            return rc;
        /* Output times up to and including t come from this step's interpolant. */
        while (next < n_out && s->direction * (t_out[next] - s->t) <= 0) {
            if (!dense_ready) {
                if ((rc = lagcli_ode_dense_prepare(s)) != LAGCLI_ODE_OK)
                    return rc;
                dense_ready = 1;
            }
            lagcli_ode_dense_eval(s, t_out[next]);
            if (out(t_out[next], s->y_out, ctx))
                return LAGCLI_ODE_INTERRUPTED;
            ++next;
        }
        if (s->direction * (s->t - s->t_end) >= 0)
            return LAGCLI_ODE_OK;
        /* First same as last: f(t, y) of the next step is this step's FSAL row. */
        memcpy(s->K, lagcli_ode_krow(s, s->tab->n_stages), (size_t)s->n * sizeof *s->K);
    }
}

int lagcli_ode_integrate(const char *method, lagcli_ode_rhs_fn rhs, lagcli_ode_out_fn out, void *ctx,
                         int n, double t0, const double *y0, double t_end,
                         const double *t_out, size_t n_out, double rtol, double atol,
                         double max_step, lagcli_ode_stats *stats)
{
    return lagcli_ode_integrate_bounded(method, rhs, out, ctx, n, t0, y0, t_end, t_out, n_out, rtol, atol,
                                        max_step, 0, stats);
}

int lagcli_ode_integrate_bounded(const char *method, lagcli_ode_rhs_fn rhs, lagcli_ode_out_fn out, void *ctx,
                                 int n, double t0, const double *y0, double t_end,
                                 const double *t_out, size_t n_out, double rtol, double atol,
                                 double max_step, long max_steps, lagcli_ode_stats *stats)
{
    lagcli_ode_stats ignored;
    lagcli_ode_solver s;
    double *work;
    size_t rows;
    int rc = LAGCLI_ODE_OK;

    if (!stats)
        stats = &ignored;
    memset(&s, 0, sizeof s);
    s.tab = lagcli_ode_find_method(method);
    s.t = t0;

    if (!s.tab || !rhs || (n_out > 0 && !out) || n < 1 || !y0 || !isfinite(t0)
        || !isfinite(t_end) || isnan(rtol) || !(atol >= 0) || !(max_step > 0) || max_steps < 0
        || !lagcli_ode_check_times(t0, t_end, t_out, n_out))
        rc = LAGCLI_ODE_ERR_ARGS;
    else if (!lagcli_ode_all_finite(n, y0))
        rc = LAGCLI_ODE_ERR_NONFINITE;
    if (rc != LAGCLI_ODE_OK) {
        stats->t = t0;
        stats->nfev = stats->n_accepted = stats->n_rejected = 0;
        stats->message = lagcli_ode_message(rc);
        return rc;
    }

    /* Work arrays: y, y_old, y_new, y_stage, y_out, K, F. */
    rows = 5 + (size_t)s.tab->n_k + (size_t)s.tab->n_dense;
    work = (double *)malloc(rows * (size_t)n * sizeof *work);
    if (!work) {
        rc = LAGCLI_ODE_ERR_NOMEM;
    } else {
        s.rhs = rhs;
        s.ctx = ctx;
        s.n = n;
        s.rtol = rtol < 100 * DBL_EPSILON ? 100 * DBL_EPSILON : rtol; /* as scipy */
        s.atol = atol;
        s.max_step = max_step;
        s.max_steps = max_steps;
        s.direction = t_end >= t0 ? 1.0 : -1.0;
        s.t_end = t_end;
        s.error_exponent = -1.0 / (s.tab->error_order + 1);
        s.t_old = t0;
        s.y = work;
        s.y_old = work + (size_t)n;
        s.y_new = work + 2 * (size_t)n;
        s.y_stage = work + 3 * (size_t)n;
        s.y_out = work + 4 * (size_t)n;
        s.K = work + 5 * (size_t)n;
        s.F = s.K + (size_t)s.tab->n_k * n;
        memcpy(s.y, y0, (size_t)n * sizeof *s.y);
        rc = lagcli_ode_run(&s, out, t_out, n_out, ctx);
        free(work);
    }
    stats->t = s.t;
    stats->nfev = s.nfev;
    stats->n_accepted = s.n_accepted;
    stats->n_rejected = s.n_rejected;
    stats->message = lagcli_ode_message(rc);
    return rc;
}

/* ---- step by step (lagcli_ode.h) ------------------------------------------------------ */

struct lagcli_ode_stepper {
    lagcli_ode_solver s;
    double *work;
    int stepped;       /* a step was taken since the start: K[0] comes from its FSAL row */
    int dense_ready;   /* F holds the last step's interpolant */
};

lagcli_ode_stepper *lagcli_ode_stepper_new(const char *method, lagcli_ode_rhs_fn rhs, void *ctx, int n,
                                           double rtol, double atol, double max_step)
{
    const lagcli_ode_tableau *tab = lagcli_ode_find_method(method);
    lagcli_ode_stepper *st;
    size_t rows;
    if (!tab || !rhs || n < 1 || isnan(rtol) || !(atol >= 0) || !(max_step > 0))
        return NULL;
    st = (lagcli_ode_stepper *)calloc(1, sizeof *st);
    rows = 5 + (size_t)tab->n_k + (size_t)tab->n_dense;
    if (!st || !(st->work = (double *)malloc(rows * (size_t)n * sizeof *st->work))) {
        free(st);
        return NULL;
    }
    st->s.tab = tab;
    st->s.rhs = rhs;
    st->s.ctx = ctx;
    st->s.n = n;
    st->s.rtol = rtol < 100 * DBL_EPSILON ? 100 * DBL_EPSILON : rtol; /* as scipy */
    st->s.atol = atol;
    st->s.max_step = max_step;
    st->s.error_exponent = -1.0 / (tab->error_order + 1);
    st->s.y = st->work;
    st->s.y_old = st->work + (size_t)n;
    st->s.y_new = st->work + 2 * (size_t)n;
    st->s.y_stage = st->work + 3 * (size_t)n;
    st->s.y_out = st->work + 4 * (size_t)n;
    st->s.K = st->work + 5 * (size_t)n;
    st->s.F = st->s.K + (size_t)tab->n_k * n;
    return st;
}

int lagcli_ode_stepper_start(lagcli_ode_stepper *st, double t0, const double *y0, double t_end)
{
    lagcli_ode_solver *s = &st->s;
    int rc;
    if (!isfinite(t0) || !isfinite(t_end))
        return LAGCLI_ODE_ERR_ARGS;
    /* y0 may point into this stepper's own arrays (the state at an event): copy first */
    memmove(s->y_new, y0, (size_t)s->n * sizeof *y0);
    memcpy(s->y, s->y_new, (size_t)s->n * sizeof *s->y);
    s->t = s->t_old = t0;
    s->t_end = t_end;
    s->direction = t_end >= t0 ? 1.0 : -1.0;
    s->nfev = s->n_accepted = s->n_rejected = 0;
    s->nonfinite = 0;
    st->stepped = st->dense_ready = 0;
    if (!lagcli_ode_all_finite(s->n, s->y))
        return LAGCLI_ODE_ERR_NONFINITE;
    if ((rc = lagcli_ode_eval(s, s->t, s->y, s->K)) != LAGCLI_ODE_OK)
        return rc;
    if (!lagcli_ode_all_finite(s->n, s->K))
        return LAGCLI_ODE_ERR_NONFINITE;
    return t0 == t_end ? LAGCLI_ODE_OK : lagcli_ode_initial_step(s, &s->h_abs);
}

int lagcli_ode_stepper_step(lagcli_ode_stepper *st)
{
    lagcli_ode_solver *s = &st->s;
    if (st->stepped) /* first same as last */
        memcpy(s->K, lagcli_ode_krow(s, s->tab->n_stages), (size_t)s->n * sizeof *s->K);
    st->dense_ready = 0;
    if (s->t == s->t_end) { /* nothing left: a step of length zero, as scipy's */
        s->t_old = s->t;
        memcpy(s->y_old, s->y, (size_t)s->n * sizeof *s->y);
        st->stepped = 0;
        return LAGCLI_ODE_OK;
    }
    st->stepped = 1;
    return lagcli_ode_step(s);
}

int lagcli_ode_stepper_dense(lagcli_ode_stepper *st, double t, double *y)
{
    lagcli_ode_solver *s = &st->s;
    int rc;
    if (s->t == s->t_old) {
        memcpy(y, s->y, (size_t)s->n * sizeof *y);
        return LAGCLI_ODE_OK;
    }
    if (!st->dense_ready) {
        if ((rc = lagcli_ode_dense_prepare(s)) != LAGCLI_ODE_OK)
            return rc;
        st->dense_ready = 1;
    }
    lagcli_ode_dense_eval(s, t);
    memcpy(y, s->y_out, (size_t)s->n * sizeof *y);
    return LAGCLI_ODE_OK;
}

double lagcli_ode_stepper_t(const lagcli_ode_stepper *st) { return st->s.t; }

double lagcli_ode_stepper_t_old(const lagcli_ode_stepper *st) { return st->s.t_old; }

const double *lagcli_ode_stepper_y(const lagcli_ode_stepper *st) { return st->s.y; }

void lagcli_ode_stepper_stats(const lagcli_ode_stepper *st, lagcli_ode_stats *stats)
{
    stats->t = st->s.t;
    stats->nfev = st->s.nfev;
    stats->n_accepted = st->s.n_accepted;
    stats->n_rejected = st->s.n_rejected;
    stats->message = "";
}

void lagcli_ode_stepper_free(lagcli_ode_stepper *st)
{
    if (st) {
        free(st->work);
        free(st);
    }
}
