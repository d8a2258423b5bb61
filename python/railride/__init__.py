"""railride from Python: batch evaluation of vehicle designs at C speed.

A thin ctypes layer over librailride's design API (include/railride/design.h):
numpy arrays in, numpy arrays out, one C call per batch.

    import numpy as np, railride
    d = railride.Design("type1",
                        variables=["primary.longitudinal_stiffness", "yaw_damper.series_stiffness"],
                        objectives=["zeta_low", "zeta_high", "std_zeta"])
    F = d.evaluate_batch(np.array([[50e6, 10e6], [30e6, 5e6]]))   # SI units

The shared library is found through $RAILRIDE_LIB, inside this package (as
`pip install .` puts it), next to it in a build tree (../../build), installed
(ctypes.util.find_library), or on the loader's path.
"""
import ctypes
import threading
import ctypes.util
import os

import numpy as np

__all__ = ["Design", "Vehicle", "RailrideError", "contact", "wear", "library", "__version__"]
__version__ = "0.1.0"


class RailrideError(Exception):
    """A railride call failed; the message names what was wrong."""


def _find_library():
    env = os.environ.get("RAILRIDE_LIB")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    for cand in (os.path.join(here, "librailride.so"),
                 os.path.join(here, "..", "..", "build", "librailride.so")):
        if os.path.exists(cand):
            return os.path.abspath(cand)
    return ctypes.util.find_library("railride") or "librailride.so.0"


_lib = None


def _check_layout(lib, mirrors=None):
    """The ctypes copies of the library's structs against the library's own
    layout (sizes and every field's offset and size): a C change cannot
    silently misread memory."""
    from . import _model, _contact, _vertical
    mirrors = mirrors or {**_vertical.MIRRORS, "rr_error": _model._Error, "rr_modal_opts": _model._ModalOpts, "rr_mode": _model._Mode,
               "rr_modal_result": _model._ModalResult, "rr_stability": _model._Stability,
               "rr_robust_opts": _model._RobustOpts, "rr_robust": _model._Robust,
               "rr_critical_opts": _model._CriticalOpts, "rr_critical": _model._Critical,
               "rr_frf_opts": _model._FrfOpts, "rr_comfort": _model._Comfort,
               "rr_ride_opts": _model._RideOpts, "rr_ride_point": _model._RidePoint, "rr_polyline": _contact._Polyline,
               "rr_contact_opts": _contact._ContactOpts, "rr_contact_side": _contact._Side,
               "rr_contact_state": _contact._State, "rr_conicity": _contact._Conicity}
    lib.rr_layout.restype = ctypes.c_int
    lib.rr_layout.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_size_t),
                              ctypes.POINTER(ctypes.c_size_t)]
    off, size = ctypes.c_size_t(), ctypes.c_size_t()
    for name, cls in mirrors.items():
        if lib.rr_layout(name.encode(), None, ctypes.byref(off), ctypes.byref(size)) or size.value != ctypes.sizeof(cls):
            raise RailrideError("the binding's %s (%d bytes) is not the library's (%d)" %
                                (name, ctypes.sizeof(cls), size.value))
        for fname, _ in cls._fields_:
            f = getattr(cls, fname)
            if lib.rr_layout(name.encode(), fname.encode(), ctypes.byref(off), ctypes.byref(size)) or \
                    (off.value, size.value) != (f.offset, f.size):
                raise RailrideError("the binding's %s.%s is not the library's" % (name, fname))


def library():
    """The loaded librailride (ctypes.CDLL)."""
    global _lib
    if _lib is None:
        lib = ctypes.CDLL(_find_library())
        from ._model import _Error
        lib.rr_design_open.restype = ctypes.c_int
        lib.rr_design_open.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p,
                                       ctypes.POINTER(ctypes.c_void_p), ctypes.POINTER(_Error)]
        lib.rr_design_free.argtypes = [ctypes.c_void_p]
        lib.rr_design_nvar.argtypes = [ctypes.c_void_p]
        lib.rr_design_nobj.argtypes = [ctypes.c_void_p]
        dptr = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        lib.rr_design_evaluate_batch.argtypes = [ctypes.c_void_p, ctypes.c_int, dptr, dptr, ctypes.c_int,
                                                 ctypes.POINTER(ctypes.c_int), ctypes.POINTER(_Error)]
        lib.rr_design_evaluate_batch.restype = ctypes.c_int
        from ._model import declare
        from ._vertical import declare as declare_vertical
        declare(lib)
        declare_vertical(lib)
        _check_layout(lib)
        lib.rr_version.restype = ctypes.c_char_p
        if lib.rr_version().decode() != __version__:
            raise RailrideError("librailride %s loaded, this package is %s" % (lib.rr_version().decode(), __version__))
        try:  # BLAS threads only cost at this size, and fight OpenMP's
            lib_blas = ctypes.CDLL("libopenblas.so.0")
            lib_blas.openblas_set_num_threads(1)
        except OSError:
            pass
        _lib = lib
    return _lib


def _locked(method):
    """A handle's method, run under the handle's lock (a Design or a Vehicle
    is safe to share between threads: calls on one handle run one at a time;
    for parallel work give each thread its own handle, or use the threads of
    evaluate_batch)."""
    def call(self, *args, **kw):
        with self._lock:
            return method(self, *args, **kw)
    call.__name__, call.__doc__ = method.__name__, method.__doc__
    return call


def _close_guarded(self, free, what):
    """Frees the handle unless another thread is using it (then an error:
    never a crash); closing twice is harmless."""
    lock = getattr(self, "_lock", None)
    if lock is None:
        return
    if not lock.acquire(blocking=False):
        raise RailrideError("this %s is in use by another thread: close it when that call returns" % what)
    try:
        free()
    finally:
        lock.release()


class Design:
    """A design context: base vehicle, varying keys, objectives (see design.h).

    vehicle: built-in name ("type1", "type2") or a vehicle file path.
    variables: "section.key" vehicle-file keys; values passed in SI units.
    objectives: e.g. "zeta_low", "index@350,0.17", "critical_speed@0.4",
                "sperling@350,0.17,8.6875;sdf=paper".
    threads: OpenMP threads per batch (0: all cores).
    """

    def __init__(self, vehicle="type1", variables=(), objectives=("zeta_low", "zeta_high", "std_zeta"), threads=0):
        lib = library()
        from ._model import _Error
        err, h = _Error(), ctypes.c_void_p()
        if lib.rr_design_open(vehicle.encode(), "\n".join(variables).encode(), "\n".join(objectives).encode(),
                              ctypes.byref(h), ctypes.byref(err)):
            raise RailrideError(err.msg.decode())
        self._h = h.value
        self._lock = threading.RLock()
        self.variables = list(variables)
        self.objectives = list(objectives)
        self.threads = int(threads)

    @property
    def nvar(self):
        return len(self.variables)

    @property
    def nobj(self):
        return len(self.objectives)

    @_locked
    def evaluate_batch(self, x):
        """Objectives (n x nobj) for designs x (n x nvar); failed designs give NaN rows."""
        if not getattr(self, "_h", None):
            raise RailrideError("this Design is closed")
        x = np.ascontiguousarray(np.atleast_2d(np.asarray(x, dtype=np.float64)))
        if x.shape[1] != self.nvar:
            raise ValueError("x has %d columns, the design has %d variables" % (x.shape[1], self.nvar))
        f = np.empty((x.shape[0], self.nobj), dtype=np.float64)
        from ._model import _Error
        err = _Error()
        if library().rr_design_evaluate_batch(self._h, x.shape[0], x, f, self.threads, None, ctypes.byref(err)):
            raise RailrideError(err.msg.decode())
        return f

    def evaluate(self, x):
        """Objectives of one design (1-D array)."""
        return self.evaluate_batch(np.asarray(x, dtype=np.float64)[None, :])[0]

    def close(self):
        def free():
            if getattr(self, "_h", None):
                library().rr_design_free(self._h)
                self._h = None
        _close_guarded(self, free, "Design")

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


from ._model import Vehicle  # noqa: E402  (needs RailrideError and library above)
from ._contact import contact, wear  # noqa: E402
