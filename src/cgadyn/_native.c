/*
 * cgadyn._native: call a compiled algorithm with the data of numpy arrays, from C.
 *
 * A one-sample call of a recursive algorithm computes in about a microsecond; numba's own
 * dispatcher spends more than that on typing, unboxing and boxing its arguments. This module
 * holds a table of C entry points (numba cfuncs, one per algorithm, see
 * cgadyn/algorithms/entries/) and calls them with the arrays' data pointers:
 *
 *     register(slot, address, inputs, outputs, forces, options)
 *         inputs:  the size code of each input vector;
 *         outputs: the shape of each output, a tuple of size codes;
 *         forces:  whether the entry takes external wrenches (an (n, 6) array or None);
 *         options: how many integer arguments follow (a link, a frame, ...).
 *         A size code is a number >= 0, or -1, -2, -3, -4 for the model's n, nq, nv, nl,
 *         read from the header of the packed model (cgadyn/multibody/packed.py).
 *     call(slot, packed, x..., [f,] option...)
 *         The outputs, freshly allocated (one array, or a tuple of them), when the call has
 *         the registered number of arguments, every input is a C-contiguous aligned float64
 *         numpy array of its size, f (where the entry takes it) is None or an (n, 6) array,
 *         every option an int, and the entry returns status 0; the status (an int) when it
 *         returns another; None when an argument is anything else or the slot is empty,
 *         and the Python caller then takes its checked path.
 *
 * The entry point is called as entry(packed, x, f, nf, o, options): x and o arrays of data
 * pointers (inputs, outputs), f the nf wrenches, options the integers, so that an
 * algorithm may have any number of each up to the bounds below.
 *
 * It never raises for bad input (only MemoryError), never keeps a reference, and holds the
 * GIL throughout (releasing it costs more than a call computes).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#define SLOTS 64
#define MAX_IN 8
#define MAX_OUT 8
#define MAX_OPT 8
#define MAX_DIMS 4
#define HEADER 5 /* n, nq, nv, nl, length */
#define ABI 2      /* the calling convention above; cgadyn.algorithms.calls checks it */

typedef long long (*entry_t)(double *packed, double **x, double *f, long long nf, double **o,
                             long long *options);

typedef struct {
    entry_t fn;
    int n_in;
    long long in[MAX_IN];
    int n_out;
    int ndim[MAX_OUT];
    long long dims[MAX_OUT][MAX_DIMS];
    int forces;
    int n_opt;
} slot_t;

static slot_t slots[SLOTS];

static long long resolve(long long code, const long long *header) {
    return code >= 0 ? code : header[-code - 1]; /* -1 n, -2 nq, -3 nv, -4 nl */
}

static int read_codes(PyObject *seq, long long *out, int max, const char *what) {
    PyObject *fast = PySequence_Fast(seq, what);
    if (!fast) return -1;
    Py_ssize_t k = PySequence_Fast_GET_SIZE(fast);
    if (k > max) {
        Py_DECREF(fast);
        PyErr_Format(PyExc_ValueError, "at most %d %s", max, what);
        return -1;
    }
    for (Py_ssize_t i = 0; i < k; i++) {
        out[i] = PyLong_AsLongLong(PySequence_Fast_GET_ITEM(fast, i));
        if (out[i] == -1 && PyErr_Occurred()) {
            Py_DECREF(fast);
            return -1;
        }
    }
    Py_DECREF(fast);
    return (int)k;
}

static PyObject *register_entry(PyObject *self, PyObject *args) {
    int slot, forces, options;
    unsigned long long address;
    PyObject *inputs, *outputs;
    if (!PyArg_ParseTuple(args, "iKOOpi", &slot, &address, &inputs, &outputs, &forces,
                          &options))
        return NULL;
    if (slot < 0 || slot >= SLOTS) {
        PyErr_Format(PyExc_ValueError, "slot %d outside 0..%d", slot, SLOTS - 1);
        return NULL;
    }
    if (options < 0 || options > MAX_OPT) {
        PyErr_Format(PyExc_ValueError, "0 to %d options", MAX_OPT);
        return NULL;
    }
    slot_t s = {0};
    s.fn = (entry_t)address;
    s.forces = forces;
    s.n_opt = options;
    if ((s.n_in = read_codes(inputs, s.in, MAX_IN, "inputs")) < 0) return NULL;
    PyObject *fast = PySequence_Fast(outputs, "outputs");
    if (!fast) return NULL;
    s.n_out = (int)PySequence_Fast_GET_SIZE(fast);
    if (s.n_out < 1 || s.n_out > MAX_OUT) {
        Py_DECREF(fast);
        PyErr_Format(PyExc_ValueError, "1 to %d outputs", MAX_OUT);
        return NULL;
    }
    for (int i = 0; i < s.n_out; i++) {
        s.ndim[i] = read_codes(PySequence_Fast_GET_ITEM(fast, i), s.dims[i], MAX_DIMS, "dims");
        if (s.ndim[i] < 0) {
            Py_DECREF(fast);
            return NULL;
        }
    }
    Py_DECREF(fast);
    slots[slot] = s;
    Py_RETURN_NONE;
}

/* The data of a C-contiguous, aligned float64 array of exactly this shape, or NULL. */
static double *data(PyObject *o, int ndim, const long long *dims) {
    if (!PyArray_CheckExact(o)) return NULL;
    PyArrayObject *a = (PyArrayObject *)o;
    if (PyArray_TYPE(a) != NPY_DOUBLE || PyArray_NDIM(a) != ndim) return NULL;
    if (!PyArray_IS_C_CONTIGUOUS(a) || !PyArray_ISALIGNED(a)) return NULL;
    npy_intp *shape = PyArray_DIMS(a);
    for (int i = 0; i < ndim; i++)
        if (shape[i] != dims[i]) return NULL;
    return (double *)PyArray_DATA(a);
}

static PyObject *call(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs < 2) {
        PyErr_SetString(PyExc_TypeError, "call(slot, packed, x..., [f,] option...)");
        return NULL;
    }
    long slot = PyLong_AsLong(args[0]);
    if (slot < 0 || slot >= SLOTS) {
        if (PyErr_Occurred()) PyErr_Clear();
        Py_RETURN_NONE;
    }
    const slot_t *s = &slots[slot];
    if (!s->fn || nargs != 2 + s->n_in + s->forces + s->n_opt || !PyArray_CheckExact(args[1]))
        Py_RETURN_NONE;
    PyArrayObject *p = (PyArrayObject *)args[1];
    if (PyArray_TYPE(p) != NPY_DOUBLE || PyArray_NDIM(p) != 1 || !PyArray_IS_C_CONTIGUOUS(p) ||
        !PyArray_ISALIGNED(p) || PyArray_DIMS(p)[0] < HEADER)
        Py_RETURN_NONE;
    double *packed = (double *)PyArray_DATA(p);
    const long long *header = (const long long *)packed;
    if (header[HEADER - 1] != PyArray_DIMS(p)[0]) Py_RETURN_NONE;

    double *x[MAX_IN];
    for (int i = 0; i < s->n_in; i++) {
        long long size = resolve(s->in[i], header);
        if (!(x[i] = data(args[2 + i], 1, &size))) Py_RETURN_NONE;
    }
    double *f = packed;
    long long nf = 0;
    if (s->forces && args[2 + s->n_in] != Py_None) {
        long long dims[2] = {header[0], 6};
        if (!(f = data(args[2 + s->n_in], 2, dims))) Py_RETURN_NONE;
        nf = header[0];
    }
    long long options[MAX_OPT];
    for (int i = 0; i < s->n_opt; i++) {
        PyObject *o = args[2 + s->n_in + s->forces + i];
        if (!PyLong_CheckExact(o)) Py_RETURN_NONE;
        options[i] = PyLong_AsLongLong(o);
        if (options[i] == -1 && PyErr_Occurred()) {
            PyErr_Clear();
            Py_RETURN_NONE;
        }
    }

    PyObject *out[MAX_OUT];
    double *o[MAX_OUT];
    for (int i = 0; i < s->n_out; i++) {
        npy_intp dims[MAX_DIMS];
        for (int d = 0; d < s->ndim[i]; d++) dims[d] = (npy_intp)resolve(s->dims[i][d], header);
        out[i] = PyArray_SimpleNew(s->ndim[i], dims, NPY_DOUBLE);
        if (!out[i]) {
            for (int k = 0; k < i; k++) Py_DECREF(out[k]);
            return NULL;
        }
        o[i] = (double *)PyArray_DATA((PyArrayObject *)out[i]);
    }
    long long status = s->fn(packed, x, f, nf, o, options);
    if (status != 0) {
        for (int i = 0; i < s->n_out; i++) Py_DECREF(out[i]);
        return PyLong_FromLongLong(status);
    }
    if (s->n_out == 1) return out[0];
    PyObject *tuple = PyTuple_New(s->n_out);
    if (!tuple) {
        for (int i = 0; i < s->n_out; i++) Py_DECREF(out[i]);
        return NULL;
    }
    for (int i = 0; i < s->n_out; i++) PyTuple_SET_ITEM(tuple, i, out[i]);
    return tuple;
}

static PyMethodDef methods[] = {
    {"register", register_entry, METH_VARARGS,
     "register(slot, address, inputs, outputs, forces, options): an entry point, its array "
     "sizes, whether it takes wrenches and how many integer options."},
    {"call", (PyCFunction)(void (*)(void))call, METH_FASTCALL,
     "call(slot, packed, x..., [f,] option...): outputs, a status, or None."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_native",
                                    "Call compiled algorithms with array data, from C.", -1,
                                    methods};

PyMODINIT_FUNC PyInit__native(void) {
    import_array();
    PyObject *m = PyModule_Create(&module);
    if (m && PyModule_AddIntConstant(m, "ABI", ABI) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
