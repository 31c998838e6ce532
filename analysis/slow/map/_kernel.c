/*
 * Compiled step loop of the reversible drift-kick-drift slow map (analysis/slow/prediction.py).
 *
 * The step of analysis.slow.map.compiled_map.iterate_slow_map, in C so that it costs ~1 us instead of the ~15 us
 * of interpreter overhead of a Python loop.  It evaluates the run-time tables built by
 * analysis.averaging._FastTable (values on a fine uniform grid in xi, 6-point Lagrange interpolation
 * between them, Chebyshev series in eta; the table's chart is u = U x with x = sinh(alpha xi)/sinh(alpha)
 * and v = c(x) + tau w(x) with tau = sinh(beta eta)/sinh(beta), the identity for alpha, beta = 0) and solves the implicit midpoint kick m = a + (eps/2) k(m) by
 * simplified Newton: the explicit kick as first iterate, the Jacobian I - (eps/2) dk/dm once at that
 * iterate, and a stop when the change of the end point 2m - a is within 1e-13 of the kick (+ 4 ulp of |Q| + U) or
 * the observed contraction eta puts the remaining error eta/(1 - eta) x change below 1e-3 of that
 * (Hairer & Wanner, Solving ODEs II, IV.8); an iterate outside the table is moved halfway back towards the last one
 * inside (the start, to begin with), which leaves the solution as it is.  The time and phi kicks at the midpoint are
 * corrected to first order by the last Newton correction.  It computes no formula of its own: every number comes
 * from the tables.  tests/test_averaging.py::_reference_map evaluates the same map plainly in NumPy
 * (fixed-point kick) and the tests compare the two.
 *
 * iterate(rows, rows_jac, geom, out, U, alpha, beta, dx, nv, eps, u, v, Th, t, phi, t_end[, rows2, tangent,
 *         rows_dw, rows_kt, rows2_kt, scale])
 *     rows      C-contiguous float64 buffer (Nf, 18 * nv): the 18 run-time functions (Chebyshev in eta)
 *     rows_jac  C-contiguous float64 buffer (Nf, 48 * nv): those, their xi-derivatives at fixed eta divided
 *               by U, and their eta-derivatives, for the kick functions 0-14
 *     geom      C-contiguous float64 buffer (Nf, 4): the chart c(x), w(x) > 0, c'(x)/U, w'(x)/U
 *     out       writable C-contiguous float64 buffer (n_max, 5): rows (t, u, v, Theta, phi)
 *     the state (u, v, Theta, t, phi) at a maximum, and t_end
 *     rows2     optional C-contiguous float64 buffer (Nf, 25 * nv): the second-order kick k2 (harmonics c0, c1, s1,
 *               c2, s2 in Theta of its u, v, Theta, t and phi components); the kick function is then k1 + eps k2
 *     tangent   optional writable C-contiguous float64 buffer of 4: a tangent vector w = (w_u, w_v, w_Theta) and its
 *               accumulated logarithmic growth l, carried through the steps (in and out); then out has 6 columns
 *               (t, u, v, Theta, phi, l) and rows_dw, rows_kt (and with rows2, rows2_kt) must be given:
 *     rows_dw   (Nf, 3 * nv): the drift W and dW/du, dW/dv (tabulated like rows_jac)
 *     rows_kt   (Nf, 27 * nv): the kick functions 0-8 (u, v, Theta harmonics), their d/du and d/dv
 *     rows2_kt  (Nf, 45 * nv): the second-order kick's u, v, Theta harmonics (15), their d/du and d/dv
 *     scale     the norm of w is sqrt(scale^2 (w_u^2 + w_v^2) + w_Theta^2); w is renormalised to 1 every step and
 *               the logarithms of the norms added to l (see tangent_step)
 * returns (n, status, u_bad, v_bad, n_jacobian, n_plain): n rows written; status 0 = t_end reached,
 *     1 = out is full, 2 = the orbit left the table at (u_bad, v_bad), 3 = the implicit kick did not
 *     converge; the numbers of table evaluations with and without the Jacobian rows.
 *
 * evaluate(rows, geom, width, nv, U, alpha, beta, dx, u, v)
 *     the `width` (18, 48, 25, 3, 27 or 45) functions of rows at (u, v), or None outside the table; with width
 *     48, 3, 27 or 45 the tabulated derivatives (the last 2 x 15, 2 x 1, 2 x 9, 2 x 15 functions) are d/du and d/dv
 *     at (u, v).
 *
 * The tangent map (tangent_step) is the derivative of the step as implemented: the drifts' dW, and the implicit
 * midpoint's by the implicit function theorem, dm = (I - (eps/2) dk/dm)^-1 da at the converged midpoint m, with
 * dk/dm from the tabulated d/du, d/dv and the analytic Theta-derivative of the harmonics.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

#define N_FUN 18    /* run-time functions: 0-14 kick harmonics, 15-17 drifts T, W, dphi */
#define N_KICK 15
#define N_JAC 48    /* N_FUN + 2 * N_KICK */
#define N_K2 25     /* second order: the harmonics (c0, c1, s1, c2, s2) of k2_u, k2_v, k2_Theta, k2_t, k2_phi */
#define N_DW 3      /* tangent: W, dW/du, dW/dv */
#define N_KT 27     /* tangent: kick functions 0-8, their d/du (9) and d/dv (9) */
#define N_K2T 45    /* tangent: second-order kick functions 0-14 (u, v, Theta), their d/du (15) and d/dv (15) */
#define MAX_NV 128
#define MAX_ITER 60
#define KICK_RTOL 1e-13
#define NEWTON_SAFETY 1e-3
#define MAX_SHORTENINGS 60 /* halvings of iterates outside the table in one kick (2^-60 of the first step) */

enum { DONE = 0, FULL = 1, LEFT_TABLE = 2, NO_CONVERGENCE = 3 };

typedef struct {
    const double *rows, *rows_jac, *geom, *rows2; /* rows2: NULL (first order) or the N_K2 second-order rows */
    const double *rows_dw, *rows_kt, *rows2_kt; /* the tangent's rows (NULL without a tangent vector) */
    Py_ssize_t n_fine;
    double U, alpha, beta, sinh_alpha, sinh_beta, dx;
    int nv;
} table_t;

#define N_GEOM 4

/* the stretched coordinate s of z = sinh(a s)/sinh(a) (s = z for a = 0), and ds/dz there */
static double unstretch(double z, double a, double sinh_a, double *ds_dz)
{
    if (a == 0.0) {
        *ds_dz = 1.0;
        return z;
    }
    double s = asinh(z * sinh_a) / a;
    *ds_dz = sinh_a / (a * cosh(a * s));
    return s;
}

/* 1/prod_{j != k}(k - j) for the stencil offsets k, j = -2 .. 3, set when the module is loaded */
static double LAGRANGE_INV[6];

static double ulp(double x)
{
    x = fabs(x);
    return nextafter(x, INFINITY) - x;
}

/* the number of tabulated derivative pairs of a row layout of `width` functions (the last 2 n_deriv functions are
   d/du and d/dv of n_deriv of them), or -1 for an unknown width */
static int n_deriv(int width)
{
    switch (width) {
    case N_FUN:
    case N_K2:
        return 0;
    case N_JAC:
        return N_KICK;
    case N_DW:
        return 1;
    case N_KT:
        return 9;
    case N_K2T:
        return 15;
    default:
        return -1;
    }
}

/* the `width` functions of `rows` (stride width * nv) at (u, v); 0 if inside the table.  With a width that has
   derivatives (n_deriv; e.g. N_JAC) the tabulated (d/dxi at fixed eta)/U and d/deta become d/du and d/dv by the
   chain rule through the chart:
   d/du = (d/dxi)(dxi/dx)/U + (d/deta) deta/du, d/dv = (d/deta) deta/dv, with deta/dv = (deta/dtau)/w and
   deta/du = -(c'/U + tau w'/U) deta/dv (v = c(x) + tau w(x)). */
static int evaluate(const table_t *tb, const double *rows, int width, double u, double v,
                    double *val)
{
    double x = u / tb->U, dxi_dx, deta_dy;
    if (!(x >= -1.0 && x <= 1.0))
        return 1;
    double xi = unstretch(x, tb->alpha, tb->sinh_alpha, &dxi_dx);
    double s = (xi + 1.0) / tb->dx;
    Py_ssize_t i = (Py_ssize_t)s;
    if (i < 2)
        i = 2;
    else if (i > tb->n_fine - 4)
        i = tb->n_fine - 4;
    double r = s - (double)i;
    double d0 = r + 2.0, d1 = r + 1.0, d2 = r, d3 = r - 1.0, d4 = r - 2.0, d5 = r - 3.0;
    double l2 = d0 * d1, r3 = d5 * d4;
    double l3 = l2 * d2, r2 = r3 * d3;
    double l4 = l3 * d3, r1 = r2 * d2;
    double w[6] = {r1 * d1 * LAGRANGE_INV[0], d0 * r1 * LAGRANGE_INV[1], l2 * r2 * LAGRANGE_INV[2],
                   l3 * r3 * LAGRANGE_INV[3], l4 * d5 * LAGRANGE_INV[4], l4 * d4 * LAGRANGE_INV[5]};
    double g[N_GEOM];
    const double *gb = tb->geom + (i - 2) * N_GEOM;
    for (int k = 0; k < N_GEOM; k++)
        g[k] = w[0] * gb[k] + w[1] * gb[N_GEOM + k] + w[2] * gb[2 * N_GEOM + k] + w[3] * gb[3 * N_GEOM + k]
               + w[4] * gb[4 * N_GEOM + k] + w[5] * gb[5 * N_GEOM + k];
    double tau = (v - g[0]) / g[1];
    if (!(tau >= -1.0 && tau <= 1.0))
        return 1;
    double y = unstretch(tau, tb->beta, tb->sinh_beta, &deta_dy);
    double deta_dv = deta_dy / g[1], deta_du = -(g[2] + tau * g[3]) * deta_dv;
    double T[MAX_NV];
    int nv = tb->nv;
    T[0] = 1.0;
    T[1] = y;
    for (int j = 2; j < nv; j++)
        T[j] = 2.0 * y * T[j - 1] - T[j - 2];
    Py_ssize_t stride = (Py_ssize_t)width * nv;
    const double *base = rows + (i - 2) * stride;
    for (int f = 0; f < width; f++) {
        double acc = 0.0;
        for (int j = 0; j < nv; j++) {
            const double *p = base + f * nv + j;
            double c = w[0] * p[0] + w[1] * p[stride] + w[2] * p[2 * stride] + w[3] * p[3 * stride]
                       + w[4] * p[4 * stride] + w[5] * p[5 * stride];
            acc += c * T[j];
        }
        val[f] = acc;
    }
    int nd = n_deriv(width);
    for (int f = width - 2 * nd; f < width - nd; f++) {
        double f_eta = val[f + nd];
        val[f + nd] = f_eta * deta_dv;
        val[f] = val[f] * dxi_dx + f_eta * deta_du;
    }
    return 0;
}

/* sum of the harmonics c0 + c1 cos + s1 sin + c2 cos 2 + s2 sin 2 (cs = cos, sin, cos 2, sin 2 of Theta) */
static double harmonics5(const double *k, const double *cs)
{
    return k[0] + k[1] * cs[0] + k[2] * cs[1] + k[3] * cs[2] + k[4] * cs[3];
}

/* the implicit midpoint kick (see the top); res = (u', v', Theta', eps k_t, eps k_phi).  With second-order rows the
   kick function is k1 + eps k2 (k2 left out of the simplified Newton's Jacobian: it sets the speed of convergence,
   not the converged value) */
static int implicit_kick(const table_t *tb, double eps, double u, double v, double th, const double *k0,
                         double *res, double *mid, double *bad, Py_ssize_t *counts)
{
    double h = 0.5 * eps;
    double c = cos(th), s = sin(th);
    double mu = u + h * (k0[0] + k0[1] * c + k0[2] * s);
    double mv = v + h * (k0[3] + k0[4] * c + k0[5] * s);
    double mt = th + h * (k0[6] + k0[7] * c + k0[8] * s);
    double k[N_JAC], ji[9], prev = 0.0, k2[N_K2], cs[4];
    const double *kdu = k + N_FUN, *kdv = k + N_FUN + N_KICK;
    /* the last iterate inside the table (the start a, evaluated by the caller, to begin with) */
    double pu = u, pv = v, pt = th;
    int have_jac = 0, shortened = 0;
    for (int it = 0; it < MAX_ITER; it++) {
        if (evaluate(tb, have_jac ? tb->rows : tb->rows_jac, have_jac ? N_FUN : N_JAC, mu, mv, k)
            || (tb->rows2 != NULL && evaluate(tb, tb->rows2, N_K2, mu, mv, k2))) {
            /* an iterate outside the table, where the midpoint itself need not be: near the chart's edge the explicit
               first iterate a + (eps/2) k(a) can overshoot it (at K = 2 the kick's v turns within one step).  The
               iterate is moved halfway back towards the last one inside (the start a, inside, bounds the halvings),
               which leaves the solution of m = a + (eps/2) k(m), and every step whose iterates stay inside, as they
               were; only a midpoint or end point outside the table leaves it */
            bad[0] = mu;
            bad[1] = mv;
            if (shortened++ >= MAX_SHORTENINGS)
                return LEFT_TABLE;
            mu = 0.5 * (mu + pu);
            mv = 0.5 * (mv + pv);
            mt = 0.5 * (mt + pt);
            it--;
            continue;
        }
        pu = mu;
        pv = mv;
        pt = mt;
        counts[have_jac]++;
        c = cos(mt);
        s = sin(mt);
        double ku = k[0] + k[1] * c + k[2] * s;
        double kv = k[3] + k[4] * c + k[5] * s;
        double kth = k[6] + k[7] * c + k[8] * s;
        if (tb->rows2 != NULL) {
            cs[0] = c;
            cs[1] = s;
            cs[2] = c * c - s * s;
            cs[3] = 2.0 * s * c;
            ku += eps * harmonics5(k2, cs);
            kv += eps * harmonics5(k2 + 5, cs);
            kth += eps * harmonics5(k2 + 10, cs);
        }
        if (!have_jac) { /* J = I - h dk/dm at this iterate, inverted by cofactors */
            double a0 = 1.0 - h * (kdu[0] + kdu[1] * c + kdu[2] * s), a1 = -h * (kdv[0] + kdv[1] * c + kdv[2] * s),
                   a2 = -h * (k[2] * c - k[1] * s);
            double a3 = -h * (kdu[3] + kdu[4] * c + kdu[5] * s), a4 = 1.0 - h * (kdv[3] + kdv[4] * c + kdv[5] * s),
                   a5 = -h * (k[5] * c - k[4] * s);
            double a6 = -h * (kdu[6] + kdu[7] * c + kdu[8] * s), a7 = -h * (kdv[6] + kdv[7] * c + kdv[8] * s),
                   a8 = 1.0 - h * (k[8] * c - k[7] * s);
            double c0 = a4 * a8 - a5 * a7, c3 = a5 * a6 - a3 * a8, c6 = a3 * a7 - a4 * a6;
            double det = a0 * c0 + a1 * c3 + a2 * c6;
            ji[0] = c0 / det;
            ji[1] = (a2 * a7 - a1 * a8) / det;
            ji[2] = (a1 * a5 - a2 * a4) / det;
            ji[3] = c3 / det;
            ji[4] = (a0 * a8 - a2 * a6) / det;
            ji[5] = (a2 * a3 - a0 * a5) / det;
            ji[6] = c6 / det;
            ji[7] = (a1 * a6 - a0 * a7) / det;
            ji[8] = (a0 * a4 - a1 * a3) / det;
            have_jac = 1;
        }
        double fu = mu - u - h * ku, fv = mv - v - h * kv, fth = mt - th - h * kth;
        double du = -(ji[0] * fu + ji[1] * fv + ji[2] * fth);
        double dv = -(ji[3] * fu + ji[4] * fv + ji[5] * fth);
        double dth = -(ji[6] * fu + ji[7] * fv + ji[8] * fth);
        mu += du;
        mv += dv;
        mt += dth;
        double u1 = 2.0 * mu - u, v1 = 2.0 * mv - v, th1 = 2.0 * mt - th;
        /* 4 ulp of the chart's extent U at least: at the fixed point Q = 0 (a release at psi0 = pi/2) the kick and
           the end point are round-off, and a floor of 4 ulp of 0 was never reached (NO_CONVERGENCE there) */
        double tol_q = KICK_RTOL * eps * (fabs(ku) + fabs(kv)) + 4.0 * ulp(fabs(u1) + fabs(v1) + tb->U);
        double cq = 2.0 * fmax(fabs(du), fabs(dv)) / tol_q;
        double ct = 2.0 * fabs(dth) / (KICK_RTOL * eps * fabs(kth) + 4.0 * ulp(th1));
        double change = fmax(cq, ct);
        double eta = prev > 0.0 ? change / prev : 1.0;
        if (change <= 1.0 || (eta < 1.0 && eta * change <= NEWTON_SAFETY * (1.0 - eta))) {
            double kt = k[9] + k[10] * c + k[11] * s + (kdu[9] + kdu[10] * c + kdu[11] * s) * du
                        + (kdv[9] + kdv[10] * c + kdv[11] * s) * dv + (k[11] * c - k[10] * s) * dth;
            double kp = k[12] + k[13] * c + k[14] * s + (kdu[12] + kdu[13] * c + kdu[14] * s) * du
                        + (kdv[12] + kdv[13] * c + kdv[14] * s) * dv + (k[14] * c - k[13] * s) * dth;
            if (tb->rows2 != NULL) {
                kt += eps * harmonics5(k2 + 15, cs);
                kp += eps * harmonics5(k2 + 20, cs);
            }
            res[0] = u1;
            res[1] = v1;
            res[2] = th1;
            res[3] = eps * kt;
            res[4] = eps * kp;
            mid[0] = mu;
            mid[1] = mv;
            mid[2] = mt;
            return DONE;
        }
        prev = change;
    }
    return shortened ? LEFT_TABLE : NO_CONVERGENCE; /* pushed back from the edge until the iterations ran out */
}

/* the derivative of the Theta-harmonics c0 + c1 cos + s1 sin (+ c2 cos 2 + s2 sin 2 with n = 5) of k at cs */
static double harmonics_dtheta(const double *k, const double *cs, int n)
{
    double d = k[2] * cs[0] - k[1] * cs[1];
    return n == 5 ? d + 2.0 * (k[4] * cs[2] - k[3] * cs[3]) : d;
}

/* The tangent map of one step, w <- M w, with M the derivative of (u, v, Theta) -> (u', v', Theta') as implemented:
   a = (u, v, Theta + W(u, v)/2), m = a + h k(m) (h = eps/2; k = k1 + eps k2), x = 2m - a, Theta' = x_Theta +
   W(x_u, x_v)/2.  By the implicit function theorem dm = (I - h dk/dm)^-1 da at the converged m (its error, the
   kick tolerance 1e-13, is far below any finite difference of the step), dx = 2 dm - da.  dwa, dwb: (dW/du, dW/dv)
   at the start and at the end of the step.  Returns LEFT_TABLE if m is outside the tangent rows' table. */
static int tangent_step(const table_t *tb, double eps, const double *m, const double *dwa, const double *dwb,
                        double *w)
{
    double kt[N_KT], k2[N_K2T], A[9], cs[4];
    if (evaluate(tb, tb->rows_kt, N_KT, m[0], m[1], kt))
        return LEFT_TABLE;
    cs[0] = cos(m[2]);
    cs[1] = sin(m[2]);
    cs[2] = cs[0] * cs[0] - cs[1] * cs[1];
    cs[3] = 2.0 * cs[1] * cs[0];
    double h = 0.5 * eps;
    for (int i = 0; i < 3; i++) { /* row i of dk/dm: d/du, d/dv, d/dTheta of component i (u, v, Theta) */
        A[3 * i] = kt[9 + 3 * i] + kt[10 + 3 * i] * cs[0] + kt[11 + 3 * i] * cs[1];
        A[3 * i + 1] = kt[18 + 3 * i] + kt[19 + 3 * i] * cs[0] + kt[20 + 3 * i] * cs[1];
        A[3 * i + 2] = harmonics_dtheta(kt + 3 * i, cs, 3);
    }
    if (tb->rows2 != NULL) {
        if (evaluate(tb, tb->rows2_kt, N_K2T, m[0], m[1], k2))
            return LEFT_TABLE;
        for (int i = 0; i < 3; i++) {
            A[3 * i] += eps * harmonics5(k2 + 15 + 5 * i, cs);
            A[3 * i + 1] += eps * harmonics5(k2 + 30 + 5 * i, cs);
            A[3 * i + 2] += eps * harmonics_dtheta(k2 + 5 * i, cs, 5);
        }
    }
    for (int j = 0; j < 9; j++) /* I - h dk/dm */
        A[j] = (j % 4 == 0 ? 1.0 : 0.0) - h * A[j];
    double da[3] = {w[0], w[1], w[2] + 0.5 * (dwa[0] * w[0] + dwa[1] * w[1])};
    /* dm = A^-1 da by Cramer's rule (cofactors, as the simplified Newton's Jacobian) */
    double c0 = A[4] * A[8] - A[5] * A[7], c3 = A[5] * A[6] - A[3] * A[8], c6 = A[3] * A[7] - A[4] * A[6];
    double det = A[0] * c0 + A[1] * c3 + A[2] * c6;
    double dm0 = (c0 * da[0] + (A[2] * A[7] - A[1] * A[8]) * da[1] + (A[1] * A[5] - A[2] * A[4]) * da[2]) / det;
    double dm1 = (c3 * da[0] + (A[0] * A[8] - A[2] * A[6]) * da[1] + (A[2] * A[3] - A[0] * A[5]) * da[2]) / det;
    double dm2 = (c6 * da[0] + (A[1] * A[6] - A[0] * A[7]) * da[1] + (A[0] * A[4] - A[1] * A[3]) * da[2]) / det;
    double dx0 = 2.0 * dm0 - da[0], dx1 = 2.0 * dm1 - da[1], dx2 = 2.0 * dm2 - da[2];
    w[0] = dx0;
    w[1] = dx1;
    w[2] = dx2 + 0.5 * (dwb[0] * dx0 + dwb[1] * dx1);
    return DONE;
}

static int get_buffer(PyObject *obj, Py_buffer *view, int writable, const char *name)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0)
        return -1;
    if (view->itemsize != 8 || view->format == NULL || strcmp(view->format, "d") != 0) {
        PyErr_Format(PyExc_TypeError, "%s must be a C-contiguous float64 buffer", name);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

/* the buffers of iterate; the optional ones: rows2, tangent, rows_dw, rows_kt, rows2_kt */
enum { B_ROWS, B_JAC, B_GEOM, B_OUT, B_ROWS2, B_TAN, B_DW, B_KT, B_K2T, N_BUF };

static void release_all(Py_buffer *b, const int *held)
{
    for (int k = 0; k < N_BUF; k++)
        if (held[k])
            PyBuffer_Release(&b[k]);
}

static PyObject *iterate(PyObject *self, PyObject *args)
{
    static const char *names[N_BUF] = {"rows", "rows_jac", "geom", "out", "rows2", "tangent", "rows_dw", "rows_kt",
                                       "rows2_kt"};
    PyObject *o[N_BUF] = {NULL, NULL, NULL, NULL, Py_None, Py_None, Py_None, Py_None, Py_None};
    double U, alpha, beta, dx, eps, u, v, Th, t, phi, t_end, scale = 1.0;
    int nv;
    if (!PyArg_ParseTuple(args, "OOOOddddiddddddd|OOOOOd", &o[B_ROWS], &o[B_JAC], &o[B_GEOM], &o[B_OUT], &U, &alpha,
                          &beta, &dx, &nv, &eps, &u, &v, &Th, &t, &phi, &t_end, &o[B_ROWS2], &o[B_TAN], &o[B_DW],
                          &o[B_KT], &o[B_K2T], &scale))
        return NULL;
    if (nv < 2 || nv > MAX_NV) {
        PyErr_Format(PyExc_ValueError, "nv must be in [2, %d], got %d", MAX_NV, nv);
        return NULL;
    }
    int second = o[B_ROWS2] != Py_None, tangent = o[B_TAN] != Py_None;
    if (tangent && (o[B_DW] == Py_None || o[B_KT] == Py_None || (second && o[B_K2T] == Py_None)
                    || !(isfinite(scale) && scale > 0.0))) {
        PyErr_SetString(PyExc_ValueError, "a tangent vector needs rows_dw, rows_kt (and with rows2, rows2_kt) and "
                                          "a finite scale > 0");
        return NULL;
    }
    Py_buffer b[N_BUF];
    int held[N_BUF] = {0};
    for (int k = 0; k < N_BUF; k++) {
        if (o[k] == Py_None || (!second && k == B_K2T) || (!tangent && k > B_TAN))
            continue;
        if (get_buffer(o[k], &b[k], k == B_OUT || k == B_TAN, names[k]) < 0) {
            release_all(b, held);
            return NULL;
        }
        held[k] = 1;
    }
    const double *buf[N_BUF] = {NULL};
    for (int k = 0; k < N_BUF; k++)
        buf[k] = held[k] ? (const double *)b[k].buf : NULL;
    Py_ssize_t n_fine = b[B_ROWS].len / (8 * N_FUN * nv);
    table_t tb = {buf[B_ROWS], buf[B_JAC], buf[B_GEOM], buf[B_ROWS2], buf[B_DW], buf[B_KT], buf[B_K2T], n_fine, U,
                  alpha, beta, sinh(alpha), sinh(beta), dx, nv};
    int width = tangent ? 6 : 5;
    Py_ssize_t n_max = b[B_OUT].len / (8 * width);
    if (n_fine < 6 || b[B_ROWS].len != n_fine * 8 * N_FUN * nv || b[B_JAC].len != n_fine * 8 * N_JAC * nv
        || b[B_GEOM].len != n_fine * 8 * N_GEOM || (second && b[B_ROWS2].len != n_fine * 8 * N_K2 * nv)
        || (tangent && (b[B_TAN].len != 4 * 8 || b[B_DW].len != n_fine * 8 * N_DW * nv
                        || b[B_KT].len != n_fine * 8 * N_KT * nv
                        || (second && b[B_K2T].len != n_fine * 8 * N_K2T * nv)))) {
        release_all(b, held);
        PyErr_SetString(PyExc_ValueError, "rows, rows_jac, geom (and rows2) must hold (Nf >= 6) x 18 x nv, "
                                          "Nf x 48 x nv and Nf x 4 (and Nf x 25 x nv) values; a tangent 4 values, "
                                          "rows_dw, rows_kt (and rows2_kt) Nf x 3, 27 (and 45) x nv");
        return NULL;
    }
    double *out = (double *)b[B_OUT].buf, *tv = tangent ? (double *)b[B_TAN].buf : NULL;
    double f[N_FUN], f1[N_FUN], res[5], mid[3], bad[2] = {NAN, NAN}, w[3], dwa[N_DW], dwb[N_DW];
    Py_ssize_t n = 0, counts[2] = {0, 0}; /* evaluations with and without the Jacobian */
    int status = DONE;
    Py_BEGIN_ALLOW_THREADS
    if (evaluate(&tb, tb.rows, N_FUN, u, v, f) || (tangent && evaluate(&tb, tb.rows_dw, N_DW, u, v, dwa))) {
        bad[0] = u;
        bad[1] = v;
        status = LEFT_TABLE;
    }
    counts[1]++;
    while (status == DONE) {
        if (n >= n_max) {
            status = FULL;
            break;
        }
        status = implicit_kick(&tb, eps, u, v, Th + 0.5 * f[N_KICK + 1], f, res, mid, bad, counts);
        if (status != DONE)
            break;
        if (evaluate(&tb, tb.rows, N_FUN, res[0], res[1], f1)
            || (tangent && evaluate(&tb, tb.rows_dw, N_DW, res[0], res[1], dwb))) {
            bad[0] = res[0];
            bad[1] = res[1];
            status = LEFT_TABLE;
            break;
        }
        counts[1]++;
        double t_next = t + 0.5 * (f[N_KICK] + f1[N_KICK]) + res[3];
        if (t_next > t_end)
            break;
        if (tangent) {
            memcpy(w, tv, sizeof w);
            if (tangent_step(&tb, eps, mid, dwa + 1, dwb + 1, w)) {
                bad[0] = mid[0];
                bad[1] = mid[1];
                status = LEFT_TABLE;
                break;
            }
            counts[0]++;
            double norm = sqrt(scale * scale * (w[0] * w[0] + w[1] * w[1]) + w[2] * w[2]);
            tv[0] = w[0] / norm;
            tv[1] = w[1] / norm;
            tv[2] = w[2] / norm;
            tv[3] += log(norm);
            memcpy(dwa, dwb, sizeof dwa);
        }
        phi += 0.5 * (f[N_KICK + 2] + f1[N_KICK + 2]) + res[4];
        t = t_next;
        u = res[0];
        v = res[1];
        memcpy(f, f1, sizeof f);
        Th = res[2] + 0.5 * f[N_KICK + 1];
        double *row = out + width * n++;
        row[0] = t;
        row[1] = u;
        row[2] = v;
        row[3] = Th;
        row[4] = phi;
        if (tangent)
            row[5] = tv[3];
    }
    Py_END_ALLOW_THREADS
    release_all(b, held);
    return Py_BuildValue("niddnn", n, status, bad[0], bad[1], counts[0], counts[1]);
}

static PyObject *evaluate_py(PyObject *self, PyObject *args)
{
    PyObject *o_rows, *o_geom;
    double U, alpha, beta, dx, u, v;
    int width, nv;
    if (!PyArg_ParseTuple(args, "OOiidddddd", &o_rows, &o_geom, &width, &nv, &U, &alpha, &beta, &dx, &u, &v))
        return NULL;
    if (nv < 2 || nv > MAX_NV || n_deriv(width) < 0) {
        PyErr_Format(PyExc_ValueError, "nv must be in [2, %d] and width one of %d, %d, %d, %d, %d, %d", MAX_NV, N_FUN,
                     N_JAC, N_K2, N_DW, N_KT, N_K2T);
        return NULL;
    }
    Py_buffer b, bg;
    if (get_buffer(o_rows, &b, 0, "rows") < 0)
        return NULL;
    if (get_buffer(o_geom, &bg, 0, "geom") < 0) {
        PyBuffer_Release(&b);
        return NULL;
    }
    table_t tb = {(const double *)b.buf, NULL, (const double *)bg.buf, NULL, NULL, NULL, NULL,
                  b.len / (8 * (Py_ssize_t)width * nv), U, alpha, beta, sinh(alpha), sinh(beta), dx, nv};
    double val[N_JAC]; /* N_JAC is the widest layout */
    int out = (tb.n_fine < 6 || bg.len != tb.n_fine * 8 * N_GEOM) ? -1 : evaluate(&tb, tb.rows, width, u, v, val);
    PyBuffer_Release(&b);
    PyBuffer_Release(&bg);
    if (out < 0) {
        PyErr_SetString(PyExc_ValueError, "rows must hold at least 6 grid points and geom 4 values for each");
        return NULL;
    }
    if (out)
        Py_RETURN_NONE;
    PyObject *list = PyList_New(width);
    if (list == NULL)
        return NULL;
    for (int f = 0; f < width; f++) {
        PyObject *x = PyFloat_FromDouble(val[f]);
        if (x == NULL) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SET_ITEM(list, f, x);
    }
    return list;
}

static PyMethodDef methods[] = {
    {"iterate", iterate, METH_VARARGS,
     "iterate(rows, rows_jac, geom, out, U, alpha, beta, dx, nv, eps, u, v, Theta, t, phi, t_end[, rows2, tangent, "
     "rows_dw, rows_kt, rows2_kt, scale])\n"
     "    -> (n, status, u_bad, v_bad, n_jacobian, n_plain)\n\n"
     "Step the slow map from a maximum until t_end; see analysis/slow/map/_kernel.c."},
    {"evaluate", evaluate_py, METH_VARARGS,
     "evaluate(rows, geom, width, nv, U, alpha, beta, dx, u, v) -> list of width values, or None outside "
     "the table"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_kernel",
                                    "Compiled step loop of analysis.slow.map.compiled_map.iterate_slow_map.", -1, methods};

PyMODINIT_FUNC PyInit__kernel(void)
{
    for (int k = 0; k < 6; k++) {
        double d = 1.0;
        for (int j = 0; j < 6; j++)
            if (j != k)
                d *= (double)(k - j);
        LAGRANGE_INV[k] = 1.0 / d;
    }
    return PyModule_Create(&module);
}
