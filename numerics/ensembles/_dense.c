/*
 * The dense output of heyoka's batch integrator evaluated point by point (numerics/ensembles/batch.py).
 *
 * heyoka's continuous output of a batch evaluates a grid of times (rows, lanes) row by row, every lane of every row;
 * the lanes' bookkeeping asks for a few thousand points of each lane per stretch, and for a few points of a few lanes
 * at a time (the turning points' Newton iterations, the unwrapping's bisections), which as rows would evaluate every
 * lane.  This evaluates each (time, lane) pair asked, and only those, from the output's Taylor coefficients: the
 * step of the lane that holds t (the first that ends at or after t, the last step after them, as heyoka
 * extrapolates; so a time at the end of a lane's stretch is its last step's, not one of the empty steps that follow
 * while longer lanes finish theirs, and a lane's states do not depend on its lane mates), then the step's Taylor
 * polynomial of each variable at h = t - t_step by Horner's rule, as heyoka evaluates it.  heyoka keeps the start
 * of a step as a double-length number and this takes its leading double: the polynomial is evaluated at a time
 * shifted by at most half an ulp of t (the state moved along the trajectory by as much: no error in the invariants;
 * tests/numerics/ensembles/test_dense.py).
 *
 * states(tcs, times, t, col, out)
 *     tcs    C-contiguous float64 buffer (S, V, P, W): the Taylor coefficients of S steps, V variables, order P - 1,
 *            W lanes (heyoka's continuous_output_batch.tcs)
 *     times  C-contiguous float64 buffer (S + 1, W): the steps' ends (its .times, ascending in each lane)
 *     t      C-contiguous float64 buffer (m,): the times
 *     col    C-contiguous int64 buffer (m,): the lane of each time, in [0, W)
 *     out    writable C-contiguous float64 buffer (m, V): the states
 * returns None; ValueError on a shape mismatch or a lane out of range.
 *
 * The unwrapping of φ and ψ on a stretch's sample grids (numerics/trajectory.py, whose numpy functions this follows
 * step for step: the same points, the same tests, the same arithmetic, and so the same turns, bit for bit;
 * tests/numerics/ensembles/test_turns.py), each lane's points in one pass instead of one numpy pass per level of
 * bisection over all lanes:
 *
 * turns(tcs, times, t, col, y, fine, limit, max_bisections, shortest, out)
 *     tcs, times, t, col   as states(); each lane's points together and in time order
 *     y      C-contiguous float64 buffer (m, V): the states at t (states()), V >= 9
 *     fine   C-contiguous float64 buffer (m,): the width below which the rate test stops, of each point's lane
 *     limit, max_bisections, shortest   trajectory._UNWRAP_LIMIT, _MAX_BISECTIONS, _SHORTEST
 *     out    writable C-contiguous float64 buffer (2, m): the whole turns of φ and ψ since the lane's first point
 * Each interval between a lane's consecutive points that trajectory._unresolved would refine is bisected depth
 * first, its midpoints evaluated as states() evaluates them, down to max_bisections levels; the steps of the refined
 * sequence counted as trajectory._turns counts them (a step that still jumps after bisection down to round-off is a
 * passage through θ = 0: ψ takes the opposite of φ's jump).  The angles are atan2's, as angles_from_frame's; the
 * turns depend on an angle only through which side of the cut it lies and which steps exceed limit, so an atan2
 * that differs from numpy's in the last bit gives the same turns unless a step lies within that bit of limit.
 * returns None; ValueError on a shape mismatch, a lane out of range or max_bisections outside [0, 1000];
 * RuntimeError if an interval is still unresolved after max_bisections levels.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>

static const double PI = 3.141592653589793;
static const double TWO_PI = 2.0 * 3.141592653589793;

static int get_buffer(PyObject *obj, Py_buffer *view, int writable, const char *fmt, int ndim, const char *name)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0)
        return -1;
    /* int64: 'l' on LP64 platforms, 'q' where long has 32 bits */
    const int same = view->format != NULL && view->format[1] == '\0' && view->itemsize == 8 &&
                     (view->format[0] == fmt[0] || (fmt[0] == 'l' && view->format[0] == 'q'));
    if (view->ndim != ndim || !same) {
        PyErr_Format(PyExc_ValueError, "%s: a C-contiguous %d-dimensional buffer of format '%s' expected", name,
                     ndim, fmt);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

/* The first step i in [0, S - 1] of lane j that ends at or after tk (else S - 1), looked for from the lane's last
 * one: a lane's points mostly come in time order, a step or two apart (then a few steps forward), else by bisection
 * (the same step either way). */
static Py_ssize_t step_of(const double *times, Py_ssize_t S, Py_ssize_t W, Py_ssize_t j, double tk, Py_ssize_t last)
{
    Py_ssize_t lo = 0, hi = S - 1;
    if (times[last * W + j] < tk) { /* the answer is at or after last */
        lo = last;
        for (int walk = 0; walk < 8 && lo < hi && times[(lo + 1) * W + j] < tk; walk++)
            lo++;
        if (lo == hi || times[(lo + 1) * W + j] >= tk)
            return lo;
    }
    while (lo < hi) {
        const Py_ssize_t mid = (lo + hi) / 2;
        if (times[(mid + 1) * W + j] >= tk)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The state (V,) of lane j at time tk in step lo into row: the step's Taylor polynomial by Horner's rule. */
static void eval_in_step(const double *tcs, const double *times, Py_ssize_t V, Py_ssize_t P, Py_ssize_t W,
                         Py_ssize_t j, Py_ssize_t lo, double tk, double *row)
{
    const double h = tk - times[lo * W + j];
    const double *c = tcs + lo * V * P * W + j;
    for (Py_ssize_t v = 0; v < V; v++) {
        const double *cv = c + v * P * W;
        double acc = cv[(P - 1) * W];
        for (Py_ssize_t p = P - 2; p >= 0; p--)
            acc = acc * h + cv[p * W];
        row[v] = acc;
    }
}

/* The state (V,) of lane j at time tk into row, its step looked for from the hint last (step_of); returns the step. */
static Py_ssize_t state_at(const double *tcs, const double *times, Py_ssize_t S, Py_ssize_t V, Py_ssize_t P,
                           Py_ssize_t W, Py_ssize_t j, double tk, Py_ssize_t last, double *row)
{
    const Py_ssize_t lo = step_of(times, S, W, j, tk, last);
    eval_in_step(tcs, times, V, P, W, j, lo, tk, row);
    return lo;
}

static PyObject *states(PyObject *self, PyObject *args)
{
    PyObject *o_tcs, *o_times, *o_t, *o_col, *o_out;
    Py_buffer b_tcs, b_times, b_t, b_col, b_out;
    if (!PyArg_ParseTuple(args, "OOOOO", &o_tcs, &o_times, &o_t, &o_col, &o_out))
        return NULL;
    if (get_buffer(o_tcs, &b_tcs, 0, "d", 4, "tcs") < 0)
        return NULL;
    if (get_buffer(o_times, &b_times, 0, "d", 2, "times") < 0) {
        PyBuffer_Release(&b_tcs);
        return NULL;
    }
    if (get_buffer(o_t, &b_t, 0, "d", 1, "t") < 0) {
        PyBuffer_Release(&b_tcs);
        PyBuffer_Release(&b_times);
        return NULL;
    }
    if (get_buffer(o_col, &b_col, 0, "l", 1, "col") < 0) {
        PyBuffer_Release(&b_tcs);
        PyBuffer_Release(&b_times);
        PyBuffer_Release(&b_t);
        return NULL;
    }
    if (get_buffer(o_out, &b_out, 1, "d", 2, "out") < 0) {
        PyBuffer_Release(&b_tcs);
        PyBuffer_Release(&b_times);
        PyBuffer_Release(&b_t);
        PyBuffer_Release(&b_col);
        return NULL;
    }
    const Py_ssize_t S = b_tcs.shape[0], V = b_tcs.shape[1], P = b_tcs.shape[2], W = b_tcs.shape[3];
    const Py_ssize_t m = b_t.shape[0];
    const char *bad = NULL;
    if (S < 1 || P < 1)
        bad = "tcs: no steps";
    else if (b_times.shape[0] != S + 1 || b_times.shape[1] != W)
        bad = "times: shape (S + 1, W) of tcs (S, V, P, W) expected";
    else if (b_col.shape[0] != m || b_out.shape[0] != m || b_out.shape[1] != V)
        bad = "col (m,) and out (m, V) expected for t (m,)";
    const double *tcs = (const double *)b_tcs.buf, *times = (const double *)b_times.buf;
    const double *t = (const double *)b_t.buf;
    const int64_t *col = (const int64_t *)b_col.buf;
    double *out = (double *)b_out.buf;
    for (Py_ssize_t k = 0; bad == NULL && k < m; k++)
        if (col[k] < 0 || col[k] >= W)
            bad = "col: a lane out of range";
    /* The points in the order of their steps: the lanes' coefficients of a step share cache lines (W lanes of each
     * coefficient in one), so all the points in one step, of every lane, are evaluated from one fetch of the step's
     * coefficients, which a lane's points one after the other would fetch once per lane.  Each point's step is found
     * first, lane by lane from its last one (step_of), then the points sorted by step (a counting sort). */
    Py_ssize_t *step = NULL, *order = NULL, *first = NULL;
    int no_memory = 0;
    if (bad == NULL) {
        step = PyMem_Malloc((size_t)(m > 0 ? m : 1) * sizeof(Py_ssize_t));
        order = PyMem_Malloc((size_t)(m > 0 ? m : 1) * sizeof(Py_ssize_t));
        first = PyMem_Calloc((size_t)S + 1 + (size_t)W, sizeof(Py_ssize_t)); /* then each lane's last step */
        no_memory = step == NULL || order == NULL || first == NULL;
        if (no_memory)
            bad = "";
    }
    if (bad == NULL) {
        Py_BEGIN_ALLOW_THREADS /* the buffers are held: other threads may run */
        Py_ssize_t *last = first + S + 1;
        for (Py_ssize_t k = 0; k < m; k++) {
            step[k] = last[col[k]] = step_of(times, S, W, col[k], t[k], last[col[k]]);
            first[step[k] + 1]++;
        }
        for (Py_ssize_t i = 0; i < S; i++)
            first[i + 1] += first[i]; /* first[i]: the first of step i's points in order */
        for (Py_ssize_t k = 0; k < m; k++)
            order[first[step[k]]++] = k;
        for (Py_ssize_t i = 0; i < m; i++) {
            const Py_ssize_t k = order[i];
            eval_in_step(tcs, times, V, P, W, col[k], step[k], t[k], out + k * V);
        }
        Py_END_ALLOW_THREADS
    }
    PyMem_Free(step);
    PyMem_Free(first);
    PyMem_Free(order);
    PyBuffer_Release(&b_tcs);
    PyBuffer_Release(&b_times);
    PyBuffer_Release(&b_t);
    PyBuffer_Release(&b_col);
    PyBuffer_Release(&b_out);
    if (bad != NULL) {
        if (no_memory)
            PyErr_NoMemory();
        else
            PyErr_SetString(PyExc_ValueError, bad);
        return NULL;
    }
    Py_RETURN_NONE;
}

/* A point of the unwrapping: its time, φ and ψ (in (−π, π]) and max(|φ̇|, |ψ̇|) (inf where undefined), from its state
 * (γ in columns 0-2, ω in 3-5, the space X axis in 6-8), as trajectory.angles_from_frame and _angle_rates compute
 * them. */
typedef struct {
    double t, phi, psi, rate;
    int depth; /* on the stack of a bisection: the bisections that made the interval that ends here */
} Point;

static Point point_of(double t, const double *y)
{
    const double g1 = y[0], g2 = y[1], g3 = y[2], w1 = y[3], w2 = y[4], w3 = y[5], x1 = y[6], x2 = y[7], x3 = y[8];
    const double ey3 = g1 * x2 - g2 * x1;
    const double phi_dot = (w1 * g1 + w2 * g2) / (g1 * g1 + g2 * g2);
    const double a = fabs(phi_dot), b = fabs(w3 - phi_dot * g3);
    Point q = {t, atan2(x3, -ey3), atan2(g1, g2), (isnan(a) || isnan(b)) ? INFINITY : (a > b ? a : b), 0};
    return q;
}

/* angle mod 2π in (−π, π], as analysis.model.diagnostics.wrap_angle (numpy's remainder: the sign of the divisor). */
static double wrap(double a)
{
    double r = fmod(PI - a, TWO_PI);
    if (r < 0)
        r += TWO_PI;
    else if (r == 0)
        r = 0.0;
    return PI - r;
}

/* trajectory._unresolved for one interval (lo, hi). */
static int unresolved(const Point *lo, const Point *hi, double fine, double limit, double shortest)
{
    const double width = hi->t - lo->t;
    const int jumps = fabs(wrap(hi->phi - lo->phi)) > limit || fabs(wrap(hi->psi - lo->psi)) > limit;
    const double rate = lo->rate > hi->rate ? lo->rate : hi->rate; /* inf if either is */
    const int fast = rate * width > limit && width > fine;
    const double scale = fabs(hi->t) > 1.0 ? fabs(hi->t) : 1.0;
    return (jumps || fast) && width > shortest * scale;
}

/* The whole turns taken by the step lo -> hi (trajectory._turns): the wrapped steps of φ and ψ, through θ = 0 (a
 * step that still jumps) with ψ taking the opposite of φ's jump so that φ + ψ stays continuous. */
static void add_turns(const Point *lo, const Point *hi, double limit, double *turns)
{
    const double raw_phi = hi->phi - lo->phi, raw_psi = hi->psi - lo->psi;
    const double s_phi = wrap(raw_phi);
    double s_psi = wrap(raw_psi);
    if (fabs(s_phi) > limit || fabs(s_psi) > limit)
        s_psi = wrap(s_phi + s_psi) - s_phi;
    turns[0] += nearbyint((s_phi - raw_phi) / TWO_PI);
    turns[1] += nearbyint((s_psi - raw_psi) / TWO_PI);
}

/* turns(tcs, times, t, col, y, fine, limit, max_bisections, shortest, out): see the module comment. */
static PyObject *turns(PyObject *self, PyObject *args)
{
    PyObject *obj[7];
    double limit, shortest;
    int max_bisections;
    if (!PyArg_ParseTuple(args, "OOOOOOdidO", &obj[0], &obj[1], &obj[2], &obj[3], &obj[4], &obj[5], &limit,
                          &max_bisections, &shortest, &obj[6]))
        return NULL;
    static const char *names[7] = {"tcs", "times", "t", "col", "y", "fine", "out"};
    static const char *fmts[7] = {"d", "d", "d", "l", "d", "d", "d"};
    static const int dims[7] = {4, 2, 1, 1, 2, 1, 2};
    Py_buffer b[7];
    int got = 0;
    for (; got < 7; got++)
        if (get_buffer(obj[got], &b[got], got == 6, fmts[got], dims[got], names[got]) < 0)
            break;
    const char *bad = NULL;
    int no_memory = 0, unresolvable = 0;
    Point *stack = NULL;
    double *scratch = NULL;
    if (got == 7) {
        const Py_ssize_t S = b[0].shape[0], V = b[0].shape[1], P = b[0].shape[2], W = b[0].shape[3];
        const Py_ssize_t m = b[2].shape[0];
        if (S < 1 || P < 1 || V < 9)
            bad = "tcs: no steps, or fewer than 9 variables";
        else if (b[1].shape[0] != S + 1 || b[1].shape[1] != W)
            bad = "times: shape (S + 1, W) of tcs (S, V, P, W) expected";
        else if (b[3].shape[0] != m || b[4].shape[0] != m || b[4].shape[1] != V || b[5].shape[0] != m ||
                 b[6].shape[0] != 2 || b[6].shape[1] != m)
            bad = "col (m,), y (m, V), fine (m,) and out (2, m) expected for t (m,)";
        else if (max_bisections < 0 || max_bisections > 1000)
            bad = "max_bisections: in [0, 1000]";
        const double *tcs = (const double *)b[0].buf, *times = (const double *)b[1].buf;
        const double *t = (const double *)b[2].buf, *y = (const double *)b[4].buf, *fine = (const double *)b[5].buf;
        const int64_t *col = (const int64_t *)b[3].buf;
        double *out = (double *)b[6].buf;
        for (Py_ssize_t k = 0; bad == NULL && k < m; k++)
            if (col[k] < 0 || col[k] >= W)
                bad = "col: a lane out of range";
        if (bad == NULL) {
            stack = PyMem_Malloc(((size_t)max_bisections + 1) * sizeof(Point));
            scratch = PyMem_Malloc((size_t)V * sizeof(double));
            no_memory = stack == NULL || scratch == NULL;
            if (no_memory)
                bad = "";
        }
        if (bad == NULL) {
            Py_BEGIN_ALLOW_THREADS
            Py_ssize_t last = 0;
            double sum[2] = {0.0, 0.0};
            Point lo = {0.0, 0.0, 0.0, 0.0, 0}; /* set at each lane's first point */
            for (Py_ssize_t k = 0; k < m && !unresolvable; k++) {
                if (k == 0 || col[k] != col[k - 1]) { /* a lane's first point: its count starts at 0 */
                    sum[0] = sum[1] = 0.0;
                    last = 0;
                    lo = point_of(t[k], y + k * V);
                } else { /* the interval (lo, point k), bisected in order, depth first: stack[0..n) its right ends */
                    int n = 1;
                    stack[0] = point_of(t[k], y + k * V);
                    while (n > 0) {
                        const Point *hi = &stack[n - 1];
                        if (!unresolved(&lo, hi, fine[k], limit, shortest)) {
                            add_turns(&lo, hi, limit, sum);
                            lo = *hi;
                            n--;
                            continue;
                        }
                        if (hi->depth == max_bisections) {
                            unresolvable = 1;
                            break;
                        }
                        const double t_mid = 0.5 * (lo.t + hi->t);
                        last = state_at(tcs, times, S, V, P, W, col[k], t_mid, last, scratch);
                        stack[n - 1].depth++; /* (mid, hi], once (lo, mid] is done */
                        stack[n] = point_of(t_mid, scratch);
                        stack[n].depth = stack[n - 1].depth;
                        n++;
                    }
                }
                out[k] = sum[0];
                out[m + k] = sum[1];
            }
            Py_END_ALLOW_THREADS
        }
    }
    PyMem_Free(stack);
    PyMem_Free(scratch);
    for (int i = 0; i < got; i++)
        PyBuffer_Release(&b[i]);
    if (got < 7)
        return NULL;
    if (no_memory)
        return PyErr_NoMemory();
    if (bad != NULL) {
        PyErr_SetString(PyExc_ValueError, bad);
        return NULL;
    }
    if (unresolvable) {
        PyErr_SetString(PyExc_RuntimeError, "could not resolve the branch of phi/psi after repeated bisection");
        return NULL;
    }
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"states", states, METH_VARARGS, "states(tcs, times, t, col, out): the states at times t of lanes col."},
    {"turns", turns, METH_VARARGS,
     "turns(tcs, times, t, col, y, fine, limit, max_bisections, shortest, out): the whole turns of phi and psi."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_dense", NULL, -1, methods};

PyMODINIT_FUNC PyInit__dense(void) { return PyModule_Create(&module); }
