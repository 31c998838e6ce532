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
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>

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
    /* The points in rounds, one point of each lane per round (each lane's in the order given): the lanes'
     * coefficients of a step share cache lines, so a lane's points one after the other would fetch the whole output
     * once per lane, while lanes at the same place in their (time-ordered) points fetch it about once. */
    Py_ssize_t *count = NULL, *order = NULL;
    int no_memory = 0;
    if (bad == NULL) {
        count = PyMem_Calloc(2 * (size_t)W + 1, sizeof(Py_ssize_t)); /* then each lane's last step */
        order = PyMem_Malloc((size_t)(m > 0 ? m : 1) * sizeof(Py_ssize_t));
        no_memory = count == NULL || order == NULL;
        if (no_memory)
            bad = "";
    }
    if (bad == NULL) {
        Py_BEGIN_ALLOW_THREADS /* the buffers are held: other threads may run */
        Py_ssize_t rounds = 0, *last = count + W + 1;
        for (Py_ssize_t k = 0; k < m; k++)
            count[col[k] + 1]++;
        for (Py_ssize_t j = 0; j < W; j++) {
            rounds = count[j + 1] > rounds ? count[j + 1] : rounds;
            count[j + 1] += count[j]; /* count[j]: the first of lane j's points in order */
        }
        for (Py_ssize_t k = 0; k < m; k++)
            order[count[col[k]]++] = k; /* now count[j]: the end of lane j's */
        for (Py_ssize_t r = 0; r < rounds; r++) {
            for (Py_ssize_t j = 0; j < W; j++) {
                const Py_ssize_t first = j == 0 ? 0 : count[j - 1];
                if (first + r >= count[j])
                    continue;
                const Py_ssize_t k = order[first + r];
                const double tk = t[k];
                const Py_ssize_t lo = step_of(times, S, W, j, tk, last[j]);
                last[j] = lo;
                const double h = tk - times[lo * W + j];
                const double *c = tcs + lo * V * P * W + j;
                for (Py_ssize_t v = 0; v < V; v++) {
                    const double *cv = c + v * P * W;
                    double acc = cv[(P - 1) * W];
                    for (Py_ssize_t p = P - 2; p >= 0; p--)
                        acc = acc * h + cv[p * W];
                    out[k * V + v] = acc;
                }
            }
        }
        Py_END_ALLOW_THREADS
    }
    PyMem_Free(count);
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

static PyMethodDef methods[] = {
    {"states", states, METH_VARARGS, "states(tcs, times, t, col, out): the states at times t of lanes col."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_dense", NULL, -1, methods};

PyMODINIT_FUNC PyInit__dense(void) { return PyModule_Create(&module); }
