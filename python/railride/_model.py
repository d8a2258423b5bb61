"""The library's main entry points as numpy arrays: modes, the stability
index and its map, robust indices, critical speed, FRFs, PSDs and ride
indices (ctypes over librailride; see include/railride/*.h)."""
import ctypes
import threading

import numpy as np

from . import _close_guarded, _locked  # noqa: E402  (defined before this module is imported)

KMH = 3.6
MODE_NAME_MAX = 48
NGROUPS = 3
RIDE_POINTS_MAX = 16
c_double_p = ctypes.POINTER(ctypes.c_double)
_INDEX_SOURCE = {0: "none", 1: "hunting", 2: "unstable_outside_hunting"}


class _Error(ctypes.Structure):
    _fields_ = [("code", ctypes.c_int), ("msg", ctypes.c_char * 512)]


class _ModalOpts(ctypes.Structure):
    _fields_ = [("fmax_hz", ctypes.c_double), ("w_min", ctypes.c_double), ("r_max", ctypes.c_double),
                ("tracking", ctypes.c_int)]


class _Mode(ctypes.Structure):
    _fields_ = [("re", ctypes.c_double), ("im", ctypes.c_double), ("freq_hz", ctypes.c_double),
                ("zeta", ctypes.c_double), ("energy", ctypes.c_double * NGROUPS), ("roll_share", ctypes.c_double),
                ("frame_roll_share", ctypes.c_double), ("oscillatory", ctypes.c_int), ("hunting", ctypes.c_int), ("in_index", ctypes.c_int),
                ("self_consistent", ctypes.c_int), ("sdf_k", ctypes.c_double), ("name", ctypes.c_char * MODE_NAME_MAX)]


class _ModalResult(ctypes.Structure):
    _fields_ = [("n", ctypes.c_int), ("cap", ctypes.c_int), ("modes", ctypes.POINTER(_Mode)), ("ndof", ctypes.c_int),
                ("shapes", ctypes.c_void_p), ("stability_index", ctypes.c_double), ("index_mode", ctypes.c_int),
                ("index_source", ctypes.c_int), ("hunting_index", ctypes.c_double), ("hunting_mode", ctypes.c_int),
                ("zeta_max", ctypes.c_double), ("max_mode", ctypes.c_int), ("fmax_hz", ctypes.c_double)]


class _Stability(ctypes.Structure):
    _fields_ = [("index", ctypes.c_double), ("index_freq_hz", ctypes.c_double), ("source", ctypes.c_int),
                ("hunting_index", ctypes.c_double), ("zeta_max", ctypes.c_double), ("max_freq_hz", ctypes.c_double),
                ("fmax_hz", ctypes.c_double)]


class _RobustOpts(ctypes.Structure):
    _fields_ = [("v_low_ms", ctypes.c_double), ("conicity_low", ctypes.c_double), ("v_high_ms", ctypes.c_double),
                ("conicity_high", ctypes.c_double), ("conicity_min", ctypes.c_double),
                ("conicity_max", ctypes.c_double), ("n_conicity", ctypes.c_int)]


class _Robust(ctypes.Structure):
    _fields_ = [("zeta_low", ctypes.c_double), ("zeta_high", ctypes.c_double), ("std_zeta", ctypes.c_double),
                ("zeta_max", ctypes.c_double), ("n_unstable", ctypes.c_int), ("unstable_speed_ms", ctypes.c_double),
                ("unstable_conicity", ctypes.c_double)]


class _CriticalOpts(ctypes.Structure):
    _fields_ = [("v_min_ms", ctypes.c_double), ("v_max_ms", ctypes.c_double), ("step_ms", ctypes.c_double),
                ("tol_ms", ctypes.c_double), ("index_modes", ctypes.c_int)]


class _Critical(ctypes.Structure):
    _fields_ = [("found", ctypes.c_int), ("speed_ms", ctypes.c_double), ("mode", _Mode)]


class _FrfOpts(ctypes.Structure):
    _fields_ = [("nfreq", ctypes.c_int), ("freqs_hz", c_double_p), ("f_lo_hz", ctypes.c_double),
                ("f_hi_hz", ctypes.c_double), ("npoints", ctypes.c_int), ("rows", c_double_p), ("rows0", c_double_p),
                ("method", ctypes.c_int)]


class _Comfort(ctypes.Structure):
    _fields_ = [("rms", ctypes.c_double), ("sperling", ctypes.c_double), ("sperling_gb", ctypes.c_double),
                ("wd_rms", ctypes.c_double)]


class _RideOpts(ctypes.Structure):
    _fields_ = [("nfreq", ctypes.c_int), ("f_lo_hz", ctypes.c_double), ("f_hi_hz", ctypes.c_double),
                ("freqs_hz", c_double_p), ("npoints", ctypes.c_int), ("x_points", ctypes.c_double * RIDE_POINTS_MAX),
                ("floor_height_m", ctypes.c_double), ("roll_gravity", ctypes.c_int), ("method", ctypes.c_int),
                ("when_unstable", ctypes.c_int)]


class _RidePoint(ctypes.Structure):
    _fields_ = [("x", ctypes.c_double), ("rms", ctypes.c_double), ("sperling", ctypes.c_double),
                ("sperling_gb", ctypes.c_double), ("wd_rms", ctypes.c_double), ("n_mv", ctypes.c_double),
                ("stable", ctypes.c_int), ("zeta_max", ctypes.c_double)]


# rr_ride_unstable: what a ride gives where some mode is unstable
_WHEN_UNSTABLE = {"undefined": 0, "linear": 1}


def declare(lib):
    """Argument and result types of the calls used here."""
    P = ctypes.c_void_p
    E = ctypes.POINTER(_Error)
    sig = {
        "rr_vehicle_new": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(P), E]), "rr_vehicle_delete": (None, [P]),
        "rr_model_from_vehicle": (ctypes.c_int, [P, ctypes.POINTER(P), E]), "rr_model_free": (None, [P]),
        "rr_model_set_operating": (ctypes.c_int, [P, ctypes.c_double, ctypes.c_double, E]),
        "rr_model_ndof": (ctypes.c_int, [P]), "rr_model_ninputs": (ctypes.c_int, [P]),
        "rr_modal_ws_new": (ctypes.c_int, [P, ctypes.POINTER(P), E]), "rr_modal_ws_free": (None, [P]),
        "rr_modal_opts_default": (_ModalOpts, []),
        "rr_modal_result_alloc": (ctypes.c_int, [P, ctypes.POINTER(_ModalResult), E]),
        "rr_modal_result_free": (None, [ctypes.POINTER(_ModalResult)]),
        "rr_modal_solve": (ctypes.c_int, [P, ctypes.POINTER(_ModalOpts), P, ctypes.POINTER(_ModalResult), E]),
        "rr_modal_stability_batch": (ctypes.c_int, [P, ctypes.POINTER(_ModalOpts), P, ctypes.c_int, c_double_p,
                                                    c_double_p, ctypes.POINTER(_Stability), E]),
        "rr_modal_band_edge_at": (ctypes.c_double, [P, ctypes.POINTER(_ModalOpts), ctypes.c_double, ctypes.c_double]),
        "rr_robust_opts_default": (_RobustOpts, []),
        "rr_robust_indices": (ctypes.c_int, [P, ctypes.POINTER(_ModalOpts), ctypes.POINTER(_RobustOpts), P,
                                             ctypes.POINTER(_Robust), E]),
        "rr_critical_opts_default": (_CriticalOpts, []),
        "rr_critical_speed": (ctypes.c_int, [P, ctypes.c_double, ctypes.POINTER(_ModalOpts),
                                             ctypes.POINTER(_CriticalOpts), P, ctypes.POINTER(_Critical), E]),
        "rr_frf_opts_default": (_FrfOpts, []),
        "rr_frf_plan_new": (ctypes.c_int, [P, ctypes.POINTER(_FrfOpts), ctypes.POINTER(P), E]),
        "rr_frf_plan_free": (None, [P]), "rr_frf_plan_execute": (ctypes.c_int, [P, P, E]),
        "rr_frf_nfreq": (ctypes.c_int, [P]), "rr_frf_freqs": (c_double_p, [P]), "rr_frf_H": (c_double_p, [P]),
        "rr_vehicle_floor_rows": (ctypes.c_int, [P, P, c_double_p, ctypes.c_int, ctypes.c_double, ctypes.c_int,
                                                 c_double_p, c_double_p, E]),
        "rr_spectrum_new": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(P), E]), "rr_spectrum_delete": (None, [P]),
        "rr_pem_psd": (ctypes.c_int, [P, P, P, c_double_p, E]),
        "rr_comfort_plan_new": (ctypes.c_int, [c_double_p, ctypes.c_int, ctypes.c_int, ctypes.POINTER(P), E]),
        "rr_comfort_plan_free": (None, [P]),
        "rr_model_dof_name": (ctypes.c_char_p, [P, ctypes.c_int]),
        "rr_comfort_execute": (ctypes.c_int, [P, c_double_p, ctypes.c_int, ctypes.POINTER(_Comfort), E]),
        "rr_spectrum_require": (ctypes.c_int, [P, ctypes.c_char_p, ctypes.c_char_p, E]),
        "rr_ride_opts_default": (_RideOpts, []),
        "rr_ride_plan_new": (ctypes.c_int, [P, P, ctypes.POINTER(_RideOpts), ctypes.POINTER(P), E]),
        "rr_ride_plan_free": (None, [P]),
        "rr_ride_execute": (ctypes.c_int, [P, P, P, ctypes.POINTER(_RidePoint), E]),
        "rr_ride_nfreq": (ctypes.c_int, [P]), "rr_ride_npoints": (ctypes.c_int, [P]),
        "rr_ride_freqs": (c_double_p, [P]), "rr_ride_psd": (c_double_p, [P]),
        "rr_ride_points": (c_double_p, [P]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args


def _ptr(a):
    return a.ctypes.data_as(c_double_p)


class Vehicle:
    """A vehicle (built-in name or file) and its linear model, for the
    library's analyses. Speeds in km/h, everything else SI.

        v = railride.Vehicle("type1")
        v.modes(350, 0.17)["freq_hz"]; v.stability_index(350, 0.17)
        v.map(np.linspace(100, 500, 41), np.linspace(0.02, 0.5, 25))
        f, G = v.psd(350, 0.17); v.ride(350, 0.17)["sperling"]
    """

    def __init__(self, spec="type1"):
        from . import library, RailrideError
        self._lib, self._Err = library(), RailrideError
        err, veh = _Error(), ctypes.c_void_p()
        if self._lib.rr_vehicle_new(spec.encode(), ctypes.byref(veh), ctypes.byref(err)):
            raise RailrideError(err.msg.decode())
        self._veh = veh
        self._lock = threading.RLock()
        self._m, self._ws = ctypes.c_void_p(), ctypes.c_void_p()
        self._call("rr_model_from_vehicle", self._veh, ctypes.byref(self._m))
        self._call("rr_modal_ws_new", self._m, ctypes.byref(self._ws))

    def _call(self, name, *args):
        err = _Error()
        st = getattr(self._lib, name)(*args, ctypes.byref(err))
        if st:
            raise self._Err(err.msg.decode())

    def _live(self):
        if not getattr(self, "_veh", None):
            raise self._Err("this Vehicle is closed")

    def _at(self, speed_kmh, conicity):
        self._live()
        self._call("rr_model_set_operating", self._m, speed_kmh / KMH, float(conicity))

    def _opts(self, fmax, wmin, rmax):
        o = self._lib.rr_modal_opts_default()
        # fmax None: the library's band edge, max(10 Hz, f_K) at each operating point
        o.fmax_hz, o.w_min, o.r_max = (0.0 if fmax is None else float(fmax)), wmin, rmax
        return o

    @_locked
    def modes(self, speed_kmh, conicity, fmax=None, wmin=1e-3, rmax=0.5):
        """Every mode: arrays freq_hz, real, imag, zeta, energy (n x 3: carbody,
        frames, wheelsets), roll_share, frame_roll_share, oscillatory (False for
        real roots, whose freq_hz and zeta mean nothing), hunting, in_index, name
        (no two alike), shape (n x ndof complex: the mode's q part, unit norm,
        largest component real) and dofs (the DOF names); with the vehicle
        stability_index (NaN when undefined), index_source ("hunting",
        "unstable_outside_hunting", "none"), index_mode (row, -1 when undefined)
        and zeta_max (any oscillatory mode)."""
        self._at(speed_kmh, conicity)
        res = _ModalResult()
        self._call("rr_modal_result_alloc", self._m, ctypes.byref(res))
        try:
            o = self._opts(fmax, wmin, rmax)
            self._call("rr_modal_solve", self._m, ctypes.byref(o), self._ws, ctypes.byref(res))
            ms = [res.modes[i] for i in range(res.n)]
            out = {"freq_hz": np.array([m.freq_hz for m in ms]), "real": np.array([m.re for m in ms]),
                   "imag": np.array([m.im for m in ms]), "zeta": np.array([m.zeta for m in ms]),
                   "energy": np.array([list(m.energy) for m in ms]).reshape(-1, NGROUPS),
                   "roll_share": np.array([m.roll_share for m in ms]),
                   "frame_roll_share": np.array([m.frame_roll_share for m in ms]),
                   "oscillatory": np.array([bool(m.oscillatory) for m in ms]),
                   "hunting": np.array([bool(m.hunting) for m in ms]),
                   "in_index": np.array([bool(m.in_index) for m in ms]),
                   "name": [m.name.decode() for m in ms],
                   "stability_index": res.stability_index if res.index_mode >= 0 else float("nan"),
                   "index_source": _INDEX_SOURCE[res.index_source], "index_mode": res.index_mode,
                   "zeta_max": res.zeta_max, "fmax_hz": res.fmax_hz}
            ndof = res.ndof
            buf = (ctypes.c_double * (2 * res.n * ndof)).from_address(res.shapes)
            out["shape"] = np.frombuffer(buf, dtype=np.float64).copy().view(np.complex128).reshape(res.n, ndof)
            out["dofs"] = [self._lib.rr_model_dof_name(self._m, i).decode() for i in range(ndof)]
        finally:
            self._lib.rr_modal_result_free(ctypes.byref(res))
        return out

    @_locked
    def map(self, speeds_kmh, conicities, fmax=None, wmin=1e-3, rmax=0.5, what="index"):
        """The stability index (or what="zeta_max") over speeds x conicities:
        an array (len(speeds), len(conicities)). The index's sign is the verdict;
        NaN where it is undefined (no hunting-related mode, all stable)."""
        self._live()
        v = np.ascontiguousarray(np.atleast_1d(np.asarray(speeds_kmh, dtype=np.float64)))
        lam = np.ascontiguousarray(np.atleast_1d(np.asarray(conicities, dtype=np.float64)))
        o = self._opts(fmax, wmin, rmax)
        out = np.empty((v.size, lam.size))
        res = (_Stability * lam.size)()
        for i, s in enumerate(v):
            vs = np.full(lam.size, s / KMH)
            self._call("rr_modal_stability_batch", self._m, ctypes.byref(o), self._ws, lam.size, _ptr(vs), _ptr(lam), res)
            for j in range(lam.size):
                if what == "index":
                    out[i, j] = res[j].index  # NaN: undefined (no hunting mode, all stable)
                else:  # NaN where no mode is oscillatory
                    out[i, j] = res[j].zeta_max if np.isfinite(res[j].max_freq_hz) else float("nan")
        return out

    @_locked
    def band_edge(self, speed_kmh, conicity, fmax=None):
        """The stability index's band edge (Hz) at an operating point:
        max(10 Hz, f_K), f_K the free wheelset's kinematic frequency, or
        fmax when given (as every index of this Vehicle takes it)."""
        self._live()
        o = self._opts(fmax, 1e-3, 0.5)
        return self._lib.rr_modal_band_edge_at(self._m, ctypes.byref(o), speed_kmh / KMH, float(conicity))

    @_locked
    def stability_index(self, speed_kmh, conicity, **kw):
        """The vehicle stability index at one point (NaN when undefined)."""
        return float(self.map([speed_kmh], [conicity], **kw)[0, 0])

    @_locked
    def robust(self, fmax=None, wmin=1e-3, rmax=0.5):
        """zeta_low, zeta_high, std_zeta (the paper's Table 1), zeta_max, n_unstable."""
        self._live()
        o, r, out = self._opts(fmax, wmin, rmax), self._lib.rr_robust_opts_default(), _Robust()
        self._call("rr_robust_indices", self._m, ctypes.byref(o), ctypes.byref(r), self._ws, ctypes.byref(out))
        return {"zeta_low": out.zeta_low, "zeta_high": out.zeta_high, "std_zeta": out.std_zeta,
                "zeta_max": out.zeta_max, "n_unstable": out.n_unstable}

    @_locked
    def critical_speed(self, conicity, vmin=10.0, vmax=600.0, index_modes=False, fmax=None, wmin=1e-3, rmax=0.5):
        """The lowest speed (km/h) at which an oscillatory mode has zeta >= 0; NaN when stable to vmax."""
        self._live()
        co = self._lib.rr_critical_opts_default()
        co.v_min_ms, co.v_max_ms, co.index_modes = vmin / KMH, vmax / KMH, int(index_modes)
        o, out = self._opts(fmax, wmin, rmax), _Critical()
        self._call("rr_critical_speed", self._m, float(conicity), ctypes.byref(o), ctypes.byref(co), self._ws,
                   ctypes.byref(out))
        return out.speed_ms * KMH if out.found else float("nan")

    def _plan(self, points, height, nfreq, f_lo, f_hi):
        x = np.ascontiguousarray(np.atleast_1d(np.asarray(points, dtype=np.float64)))
        n = self._lib.rr_model_ndof(self._m)
        rows, rows0 = np.zeros(x.size * n), np.zeros(x.size * n)
        self._call("rr_vehicle_floor_rows", self._m, self._veh, _ptr(x), x.size, float(height), 0, _ptr(rows), _ptr(rows0))
        o = self._lib.rr_frf_opts_default()
        o.nfreq, o.f_lo_hz, o.f_hi_hz, o.npoints, o.rows = nfreq, f_lo, f_hi, x.size, _ptr(rows)
        plan = ctypes.c_void_p()
        self._call("rr_frf_plan_new", self._m, ctypes.byref(o), ctypes.byref(plan))
        return plan, rows, x

    @_locked
    def frf(self, speed_kmh, conicity, points=(0.0,), height=1.2, nfreq=400, f_lo=0.3, f_hi=30.0):
        """Frequencies (Hz) and the floor's lateral acceleration FRFs H (nfreq x
        points x wheelsets, complex, (m/s^2)/m) at floor points x (m from the centre)."""
        self._at(speed_kmh, conicity)
        plan, rows, x = self._plan(points, height, nfreq, f_lo, f_hi)
        try:
            self._call("rr_frf_plan_execute", plan, self._m)
            nf, ni = self._lib.rr_frf_nfreq(plan), self._lib.rr_model_ninputs(self._m)
            f = np.ctypeslib.as_array(self._lib.rr_frf_freqs(plan), shape=(nf,)).copy()
            H = np.ctypeslib.as_array(self._lib.rr_frf_H(plan), shape=(nf * x.size * ni * 2,)).copy()
        finally:
            self._lib.rr_frf_plan_free(plan)
        return f, H.view(np.complex128).reshape(nf, x.size, ni)

    def _ride_run(self, speed_kmh, conicity, spectrum, points, height, nfreq, f_lo, f_hi, when_unstable):
        """The library's ride plan (rr_ride_plan) executed once: the same
        composition, checks and defaults as the CLI's."""
        if when_unstable not in _WHEN_UNSTABLE:
            raise self._Err("when_unstable: 'undefined' or 'linear' (got %r)" % (when_unstable,))
        self._at(speed_kmh, conicity)
        o = self._lib.rr_ride_opts_default()
        o.nfreq, o.f_lo_hz, o.f_hi_hz, o.floor_height_m = int(nfreq), float(f_lo), float(f_hi), float(height)
        o.when_unstable = _WHEN_UNSTABLE[when_unstable]
        if points is not None:
            x = np.atleast_1d(np.asarray(points, dtype=np.float64))
            if not 1 <= x.size <= RIDE_POINTS_MAX:
                raise self._Err("points: 1 to %d floor points (got %d)" % (RIDE_POINTS_MAX, x.size))
            o.npoints = x.size
            for i, xi in enumerate(x):
                o.x_points[i] = xi
        sp, plan = ctypes.c_void_p(), ctypes.c_void_p()
        self._call("rr_spectrum_new", str(spectrum).encode(), ctypes.byref(sp))
        try:
            self._call("rr_spectrum_require", sp, b"lateral", b"the lateral track input")
            self._call("rr_ride_plan_new", self._m, self._veh, ctypes.byref(o), ctypes.byref(plan))
            npt = self._lib.rr_ride_npoints(plan)
            pts = (_RidePoint * npt)()
            self._call("rr_ride_execute", plan, self._m, sp, pts)
            nf = self._lib.rr_ride_nfreq(plan)
            f = np.ctypeslib.as_array(self._lib.rr_ride_freqs(plan), shape=(nf,)).copy()
            G = np.ctypeslib.as_array(self._lib.rr_ride_psd(plan), shape=(nf * npt,)).copy().reshape(nf, npt)
        finally:
            self._lib.rr_ride_plan_free(plan)
            self._lib.rr_spectrum_delete(sp)
        return f, G, list(pts)

    @_locked
    def psd(self, speed_kmh, conicity, spectrum="wuhan-guangzhou", points=None, height=1.2, nfreq=400,
            f_lo=0.3, f_hi=30.0):
        """Frequencies (Hz) and the floor's lateral acceleration PSD G (nfreq x
        points, (m/s^2)^2/Hz) by the pseudo-excitation method; points None:
        the library's floor points x = +L, 0, -L (m from the carbody centre)."""
        f, G, _ = self._ride_run(speed_kmh, conicity, spectrum, points, height, nfreq, f_lo, f_hi, "linear")
        return f, G

    @_locked
    def ride(self, speed_kmh, conicity, spectrum="wuhan-guangzhou", points=None, height=1.2,
             when_unstable="undefined"):
        """Ride indices at each floor point (points None: the library's x = +L,
        0, -L): arrays x (m), rms (m/s^2), sperling (filter method),
        sperling_gb (GB/T 5599), wd_rms (ISO 2631-1 Wd, m/s^2), and the
        verdict stable (bool) with zeta_max (any oscillatory mode). Where some
        mode is unstable the indices are NaN (a linear response of an unstable
        vehicle is not a ride comfort) unless when_unstable="linear"."""
        _, _, pts = self._ride_run(speed_kmh, conicity, spectrum, points, height, 400, 0.3, 30.0,
                                   when_unstable)
        out = {k: np.array([getattr(p, k) for p in pts]) for k in ("x", "rms", "sperling", "sperling_gb", "wd_rms")}
        out["stable"] = bool(pts[0].stable == 1)
        out["zeta_max"] = pts[0].zeta_max
        return out

    def vertical_matrices(self):
        """The vertical model's M, C, K, BK, BC (DOF order z_c, theta_c, q_b,
        z_f1, theta_f1, z_f2, theta_f2; wheelsets front to rear)."""
        from . import _vertical
        with self._lock:
            return _vertical.matrices(self)

    def vertical_modes(self):
        """The vertical model's modes: freq_hz, natural_hz, damping_ratio
        (positive when stable), eigenvalue, energy (n x 7), name, undamped_hz."""
        from . import _vertical
        with self._lock:
            return _vertical.modes(self)

    def vertical_frf(self, speed_kmh, points=None, nfreq=400, f_lo=0.3, f_hi=30.0):
        """f (Hz), H (nfreq x points: floor vertical acceleration per m of track
        at the leading wheelset) and Q (nfreq x 7: every coordinate's).
        points None: +L, 0, -L."""
        from . import _vertical
        with self._lock:
            return _vertical.frf(self, speed_kmh, points, nfreq, f_lo, f_hi)

    def vertical_ride(self, speed_kmh, spectrum="tbt3352-vertical", points=None, window=5.0, lateral=None):
        """The vertical ride at each floor point (None: +L, 0, -L): f, track_psd,
        psd, x, rms, sperling, sperling_gb, wk_rms, wb_rms, wb_iso8041_rms,
        wb_shape_k, wb_p50, wb_p95, wb_mean, n_mv_vertical. lateral=conicity or
        (conicity, spectrum) adds lateral_psd, wd_p50, wd_p95 and EN 12299's
        n_mv, n_vd, n_va_rigid_seat (longitudinal 0, rigid seat)."""
        from . import _vertical
        with self._lock:
            return _vertical.ride(self, speed_kmh, spectrum, points, window, lateral)

    def close(self):
        def free():
            if getattr(self, "_veh", None):
                self._lib.rr_modal_ws_free(self._ws)
                self._lib.rr_model_free(self._m)
                self._lib.rr_vehicle_delete(self._veh)
                self._veh = None
        _close_guarded(self, free, "Vehicle")

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
