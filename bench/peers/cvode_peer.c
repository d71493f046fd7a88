/* Peer implementation of the clapper model in C with SUNDIALS CVODE.
 *
 * What a numerical engineer would write in C from the paper and
 * docs/model.md: equations (5) and (6) in mass-matrix form, integrated by
 * CVODE (variable-order Adams with fixed-point iteration, or BDF with a
 * dense Newton solver) with CVODE's own root finding for the events, and
 * the rigid impact law restarting the integration after each impact
 * (CVodeReInit). The stroke is the one bench/peers/scipy_peer.py and
 * clapper simulate: from rest at +theta0 to the turning point after the
 * bottom; the clapper comes to rest when its next flight would be shorter
 * than 1e-7 s, rides with the bell, and lifts off when the holding force
 * changes sign (docs/model.md section 3).
 *
 * It prints, for each stroke, the first strike angle (deg), the clapper
 * rate before it (rad/s), whether the style is sustained and the
 * right-hand-side calls, one JSON object a line as scipy_peer.py does, and
 * the time the strokes took.
 *
 *   cc -O2 -o cvode_peer cvode_peer.c -lsundials_cvode -lsundials_nvecserial \
 *      -lsundials_sunlinsoldense -lsundials_sunmatrixdense \
 *      -lsundials_sunnonlinsolfixedpoint -lm
 *   ./cvode_peer --chart 20 --method bdf --rtol 1e-8
 *   ./cvode_peer --bell lab --method adams --rtol 1e-10
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#define G 9.81
#define PI 3.14159265358979323846
#define NROOTS 4

typedef struct {
    double M, m, a, b, Ib, Ic, r, phimax;
    double j0, mrb, gb, gc, tb;
} Bell;

static Bell bell_new(double M, double m, double a, double b, double Ib, double Ic, double r, double phimax) {
    Bell B = {M, m, a, b, Ib, Ic, r, phimax, 0, 0, 0, 0, 0};
    B.j0 = Ib + Ic + m * r * r;
    B.mrb = m * r * b;
    B.gb = (M * a + m * r) * G;
    B.gc = m * b * G;
    B.tb = 2 * PI * sqrt(Ib / (M * a) / G);
    return B;
}

static Bell lab(void) { return bell_new(45.8, 1.65, 0.24, 0.25, 4.1, 0.093, 0.10, 26 * PI / 180); }

/* The paper's construction of a bell at chart point (r/L_c, L_b/L_c). */
static Bell chart_bell(double x, double y) {
    double tb = 1.8, M = 45.8, m = 1.65, a = 0.24, Ic = 0.20;
    double lb = G * tb * tb / (4 * PI * PI), lc = lb / y;
    return bell_new(M, m, a, Ic / (m * lc), M * a * lb, Ic, x * lc, 26 * PI / 180);
}

/* theta'', phi'' in flight, and the mass matrix's w11, w12 and determinant. */
static void accel(const Bell *B, const double *y, double *tdd, double *pdd, double *w11o, double *w12o, double *deto) {
    double sp = sin(y[1]), cp = cos(y[1]), sth = sin(y[0] + y[1]);
    double w11 = B->j0 + 2 * B->mrb * cp, w12 = B->Ic + B->mrb * cp;
    double f1 = B->mrb * y[3] * (2 * y[2] + y[3]) * sp - B->gb * sin(y[0]) - B->gc * sth;
    double f2 = -B->mrb * y[2] * y[2] * sp - B->gc * sth;
    double det = w11 * B->Ic - w12 * w12;
    *tdd = (B->Ic * f1 - w12 * f2) / det;
    *pdd = (w11 * f2 - w12 * f1) / det;
    if (w11o) { *w11o = w11; *w12o = w12; *deto = det; }
}

/* theta'' and the holding force Q_phi with the clapper held at rest. */
static void resting(const Bell *B, const double *y, double *tdd, double *q) {
    double sp = sin(y[1]), cp = cos(y[1]), sth = sin(y[0] + y[1]);
    double w11 = B->j0 + 2 * B->mrb * cp, w12 = B->Ic + B->mrb * cp;
    *tdd = (-B->gb * sin(y[0]) - B->gc * sth) / w11;
    *q = w12 * *tdd + B->mrb * y[2] * y[2] * sp + B->gc * sth;
}

/* The rigid impact: phi' -> -e phi', the bell's rate by the impulse. */
static void impact(const Bell *B, const double *y, double e, double *out) {
    double tdd, pdd, w11, w12, det;
    accel(B, y, &tdd, &pdd, &w11, &w12, &det);
    double winv12 = -w12 / det, winv22 = w11 / det;
    double p = -(1 + e) * y[3] / winv22;
    out[0] = y[0]; out[1] = y[1]; out[2] = y[2] + winv12 * p; out[3] = -e * y[3];
}

typedef struct {
    const Bell *B;
    double s0;        /* side of the bottom the stroke starts on */
    int bottom_passed;
    int resting;      /* 0 flying, else the side (+1/-1) it rests on */
} Ctx;

static int rhs(sunrealtype t, N_Vector yv, N_Vector ydot, void *ud) {
    (void)t;
    Ctx *c = ud;
    double *y = N_VGetArrayPointer(yv), *d = N_VGetArrayPointer(ydot);
    d[0] = y[2];
    if (c->resting) {
        double tdd, q;
        resting(c->B, y, &tdd, &q);
        d[1] = 0; d[2] = tdd; d[3] = 0;
    } else {
        double tdd, pdd;
        accel(c->B, y, &tdd, &pdd, NULL, NULL, NULL);
        d[1] = y[3]; d[2] = tdd; d[3] = pdd;
    }
    return 0;
}

/* Events, all rising: over the balance; the bottom, then the turning
 * point; in flight the two stops, at rest the holding force's sign. */
static int roots(sunrealtype t, N_Vector yv, sunrealtype *g, void *ud) {
    (void)t;
    Ctx *c = ud;
    double *y = N_VGetArrayPointer(yv);
    g[0] = -c->s0 * y[0] - PI;
    g[1] = c->bottom_passed ? c->s0 * y[2] : -c->s0 * y[0];
    if (c->resting) {
        double tdd, q;
        resting(c->B, y, &tdd, &q);
        g[2] = c->resting * q;
        g[3] = -1.0;
    } else {
        g[2] = y[1] - c->B->phimax;
        g[3] = -y[1] - c->B->phimax;
    }
    return 0;
}

typedef struct {
    void *mem;
    N_Vector y;
    SUNContext sun;
    SUNMatrix A;
    SUNLinearSolver LS;
    SUNNonlinearSolver NLS;
    int bdf;
    int initialised;
    double rtol;
} Solver;

static void solver_open(Solver *s, int bdf, double rtol) {
    memset(s, 0, sizeof *s);
    s->bdf = bdf;
    s->rtol = rtol;
    if (SUNContext_Create(NULL, &s->sun)) { fprintf(stderr, "SUNContext_Create failed\n"); exit(1); }
    s->y = N_VNew_Serial(4, s->sun);
    s->mem = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, s->sun);
}

/* Start (or restart, after an event) at (t, y). */
static void solver_start(Solver *s, Ctx *c, double t, const double *y) {
    memcpy(N_VGetArrayPointer(s->y), y, 4 * sizeof(double));
    if (!s->initialised) {
        int dir[NROOTS] = {1, 1, 1, 1};
        CVodeInit(s->mem, rhs, t, s->y);
        CVodeSStolerances(s->mem, s->rtol, s->rtol);
        CVodeRootInit(s->mem, NROOTS, roots);
        CVodeSetRootDirection(s->mem, dir);
        CVodeSetMaxNumSteps(s->mem, 1000000);
        if (s->bdf) {
            s->A = SUNDenseMatrix(4, 4, s->sun);
            s->LS = SUNLinSol_Dense(s->y, s->A, s->sun);
            CVodeSetLinearSolver(s->mem, s->LS, s->A);
        } else {
            s->NLS = SUNNonlinSol_FixedPoint(s->y, 0, s->sun);
            CVodeSetNonlinearSolver(s->mem, s->NLS);
        }
        s->initialised = 1;
    } else {
        CVodeReInit(s->mem, t, s->y);
    }
    CVodeSetUserData(s->mem, c);
}

static long solver_rhs_calls(Solver *s) {
    long n = 0, nl = 0;
    CVodeGetNumRhsEvals(s->mem, &n);
    if (s->bdf) CVodeGetNumLinRhsEvals(s->mem, &nl);
    return n + nl;
}

/* Integrate to the first event: its index, or -1 (end time or failure). */
static int segment(Solver *s, double t_end, double *t, double *y, long *calls) {
    sunrealtype tr;
    int flag = CVode(s->mem, t_end, s->y, &tr, CV_NORMAL);
    *calls += solver_rhs_calls(s);
    *t = tr;
    memcpy(y, N_VGetArrayPointer(s->y), 4 * sizeof(double));
    if (flag != CV_ROOT_RETURN) return -1;
    int info[NROOTS];
    CVodeGetRootInfo(s->mem, info);
    for (int i = 0; i < NROOTS; i++)
        if (info[i]) return i;
    return -1;
}

/* The style the next stroke starts in: where the clapper is, relative to the bell. */
static int continues_right(const double *y, int rest_side) {
    int side = rest_side ? rest_side : (y[1] >= 0 ? 1 : -1);
    return side == (y[0] >= 0 ? 1 : -1);
}

typedef struct {
    int struck, sustained;
    double theta_deg, phidot;
    long calls;
} Result;

static Result stroke(Solver *s, const Bell *B, double theta0, double R, int right) {
    Result res = {0, 0, 0, 0, 0};
    Ctx c = {B, theta0 >= 0 ? 1.0 : -1.0, 0, 0};
    int side = right ? (int)c.s0 : -(int)c.s0;
    double y[4] = {theta0, side * B->phimax, 0, 0}, t = 0, t_end = 20 * B->tb;
    double e = sqrt(R), tdd, q;
    resting(B, y, &tdd, &q);
    c.resting = side * q < 0 ? side : 0;
    /* Every loop has a bound: a stroke has far fewer events than this. */
    for (int events = 0; events < 100000; events++) {
        solver_start(s, &c, t, y);
        int which = segment(s, t_end, &t, y, &res.calls);
        if (which < 0 || which == 0) return res;
        if (which == 1 && !c.bottom_passed) {
            c.bottom_passed = 1;
            continue;
        }
        if (which == 1) {
            res.sustained = res.struck && continues_right(y, c.resting) == right;
            return res;
        }
        if (c.resting) {
            c.resting = 0;
            continue;
        }
        int hit = which == 2 ? 1 : -1;
        if (hit != side && !res.struck) {
            res.struck = 1;
            res.theta_deg = y[0] * 180 / PI;
            res.phidot = y[3];
        }
        y[1] = hit * B->phimax;
        double bounced[4], stuck[4], pdd;
        impact(B, y, e, bounced);
        accel(B, bounced, &tdd, &pdd, NULL, NULL, NULL);
        double toward = hit * pdd, away = -hit * bounced[3];
        impact(B, y, 0.0, stuck);
        resting(B, stuck, &tdd, &q);
        if (toward > 0 && 2 * away < 1e-7 * toward && hit * q < 0) {
            memcpy(y, stuck, sizeof y);
            c.resting = hit;
        } else {
            memcpy(y, bounced, sizeof y);
        }
    }
    return res;
}

static double axis(double a, double b, int n, int i) { return n == 1 ? 0.5 * (a + b) : a + (b - a) * i / (n - 1); }

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void print_result(const char *where, int right, Result r) {
    printf("{\"point\": %s, \"style\": \"%s\", \"sustained\": %s, \"rhs_evals\": %ld, ", where,
           right ? "right" : "wrong", r.sustained ? "true" : "false", r.calls);
    if (r.struck)
        printf("\"strike_theta_deg\": %.17g, \"strike_phidot_rad_s\": %.17g}\n", r.theta_deg, r.phidot);
    else
        printf("\"strike_theta_deg\": null, \"strike_phidot_rad_s\": null}\n");
}

static void usage(void) {
    fprintf(stderr, "usage: cvode_peer (--chart N | --bell lab [--style right|wrong] [--repeat K])\n"
                    "                  [--method adams|bdf] [--rtol TOL] [--theta0 DEG] [--restitution R]\n");
    exit(2);
}

int main(int argc, char **argv) {
    int chart = 0, bdf = 1, right = 1, repeat = 1;
    double rtol = 1e-8, theta0 = 171, R = 0.2;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v && strcmp(a, "--help") != 0) usage();
        if (!strcmp(a, "--chart")) chart = atoi(v);
        else if (!strcmp(a, "--bell")) { if (strcmp(v, "lab")) usage(); }
        else if (!strcmp(a, "--style")) right = !strcmp(v, "right");
        else if (!strcmp(a, "--method")) bdf = !strcmp(v, "bdf");
        else if (!strcmp(a, "--rtol")) rtol = atof(v);
        else if (!strcmp(a, "--theta0")) theta0 = atof(v);
        else if (!strcmp(a, "--restitution")) R = atof(v);
        else if (!strcmp(a, "--repeat")) repeat = atoi(v);
        else usage();
        i++;
    }
    if (!(rtol > 0) || repeat < 1 || chart < 0) usage();
    Solver s;
    solver_open(&s, bdf, rtol);
    double th0 = theta0 * PI / 180;
    long strokes = 0;
    double start = now();
    if (chart) {
        char where[64];
        for (int j = 0; j < chart; j++)
            for (int i = 0; i < chart; i++)
                for (int st = 1; st >= 0; st--) {
                    double x = axis(-0.3, 0.7, chart, i), y = axis(0.5, 2.5, chart, j);
                    Bell B = chart_bell(x, y);
                    Result r = stroke(&s, &B, th0, R, st);
                    snprintf(where, sizeof where, "[%.17g, %.17g]", x, y);
                    print_result(where, st, r);
                    strokes++;
                }
    } else {
        /* One stroke, repeated so that its time can be read. */
        Bell B = lab();
        Result r = {0};
        for (int k = 0; k < repeat; k++) r = stroke(&s, &B, th0, R, right), strokes++;
        print_result("\"lab\"", right, r);
    }
    double secs = now() - start;
    printf("{\"strokes\": %ld, \"seconds\": %.9g, \"seconds_per_stroke\": %.9g}\n", strokes, secs, secs / strokes);
    return 0;
}
