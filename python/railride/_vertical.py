"""The vertical model from Python (include/railride/vertical.h): its
matrices, modes, FRFs, floor PSDs, ride indices, 5 s RMS percentiles and
EN 12299's mean comfort, as numpy arrays."""
import ctypes

import numpy as np

from ._model import _Error, _ptr, c_double_p, KMH

VDOF, VINPUTS, POINTS_MAX = 7, 4, 16
DOF_NAMES = ("z_c", "theta_c", "q_b", "z_f1", "theta_f1", "z_f2", "theta_f2")


class _VModel(ctypes.Structure):
    _fields_ = [("M", ctypes.c_double * VDOF), ("K", ctypes.c_double * (VDOF * VDOF)),
                ("C", ctypes.c_double * (VDOF * VDOF)), ("BK", ctypes.c_double * (VDOF * VINPUTS)),
                ("BC", ctypes.c_double * (VDOF * VINPUTS)), ("x_frames", ctypes.c_double * 2),
                ("x_wheelsets", ctypes.c_double * VINPUTS), ("d_wheelsets", ctypes.c_double * VINPUTS),
                ("phi_pivots", ctypes.c_double * 2), ("carbody_length", ctypes.c_double),
                ("carbody_mass", ctypes.c_double)]


class _VMode(ctypes.Structure):
    _fields_ = [("freq_hz", ctypes.c_double), ("natural_hz", ctypes.c_double), ("damping_ratio", ctypes.c_double),
                ("re", ctypes.c_double), ("im", ctypes.c_double), ("energy", ctypes.c_double * VDOF),
                ("name", ctypes.c_char * 64)]


class _VModes(ctypes.Structure):
    _fields_ = [("nmodes", ctypes.c_int), ("nreal", ctypes.c_int), ("mode", _VMode * VDOF),
                ("real", ctypes.c_double * (2 * VDOF)), ("undamped_hz", ctypes.c_double * VDOF)]


class _VOpts(ctypes.Structure):
    _fields_ = [("nfreq", ctypes.c_int), ("f_lo_hz", ctypes.c_double), ("f_hi_hz", ctypes.c_double),
                ("npoints", ctypes.c_int), ("x_points", ctypes.c_double * POINTS_MAX),
                ("window_s", ctypes.c_double), ("freqs_hz", c_double_p)]


class _WindowStats(ctypes.Structure):
    _fields_ = [("rms", ctypes.c_double), ("shape_k", ctypes.c_double), ("dof", ctypes.c_double),
                ("p50", ctypes.c_double), ("p95", ctypes.c_double), ("mean", ctypes.c_double)]


class _VPoint(ctypes.Structure):
    _fields_ = [("x", ctypes.c_double), ("rms", ctypes.c_double), ("sperling", ctypes.c_double),
                ("sperling_gb", ctypes.c_double), ("wk_rms", ctypes.c_double), ("wb_rms", ctypes.c_double),
                ("wb_iso8041_rms", ctypes.c_double), ("wb_5s", _WindowStats), ("n_mv_vertical", ctypes.c_double)]


class _ENInputs(ctypes.Structure):
    _fields_ = [(k, ctypes.c_double) for k in ("ax50", "ax95", "ay50", "ay95", "az50", "az95", "axd95")]


class _EN(ctypes.Structure):
    _fields_ = [(k, ctypes.c_double) for k in ("n_mv", "n_vd", "n_va_rigid_seat")]


MIRRORS = {"rr_en12299_inputs": _ENInputs, "rr_en12299": _EN, "rr_vertical_model": _VModel, "rr_vertical_mode": _VMode, "rr_vertical_modes": _VModes,
           "rr_vertical_opts": _VOpts, "rr_window_stats": _WindowStats, "rr_vertical_point": _VPoint}
WD = 2  # enum rr_iso_weighting: RR_ISO_WD


def declare(lib):
    P, E = ctypes.c_void_p, ctypes.POINTER(_Error)
    sig = {
        "rr_vertical_model_build": (ctypes.c_int, [P, ctypes.POINTER(_VModel), E]),
        "rr_vertical_modes_compute": (ctypes.c_int, [ctypes.POINTER(_VModel), ctypes.POINTER(_VModes), E]),
        "rr_vertical_opts_default": (_VOpts, []),
        "rr_vertical_plan_new": (ctypes.c_int, [ctypes.POINTER(_VOpts), ctypes.POINTER(P), E]),
        "rr_vertical_plan_free": (None, [P]),
        "rr_vertical_freqs": (c_double_p, [P]), "rr_vertical_psd": (c_double_p, [P]),
        "rr_vertical_track_psd": (c_double_p, [P]), "rr_vertical_frf_H": (c_double_p, [P]),
        "rr_vertical_frf_Q": (c_double_p, [P]), "rr_vertical_npoints": (ctypes.c_int, [P]),
        "rr_vertical_frf_execute": (ctypes.c_int, [P, ctypes.POINTER(_VModel), ctypes.c_double, E]),
        "rr_vertical_ride_execute": (ctypes.c_int, [P, ctypes.POINTER(_VModel), ctypes.c_double, P,
                                                    ctypes.POINTER(_VPoint), E]),
        "rr_en12299_indices": (_EN, [ctypes.POINTER(_ENInputs)]),
        "rr_vertical_window_stats": (ctypes.c_int, [P, c_double_p, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                                                    ctypes.POINTER(_WindowStats), E]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args


def _array(p, n):
    return np.ctypeslib.as_array(p, shape=(n,)).copy()


class _Plan:
    """A vertical plan for one call: points (None: +L, 0, -L), grid, window."""

    def __init__(self, veh, points, nfreq, f_lo, f_hi, window):
        self.veh, self.lib = veh, veh._lib
        o = self.lib.rr_vertical_opts_default()
        o.nfreq, o.f_lo_hz, o.f_hi_hz, o.window_s = int(nfreq), float(f_lo), float(f_hi), float(window)
        pts = [] if points is None else [float(x) for x in points]
        if len(pts) > POINTS_MAX:
            raise veh._Err("at most %d floor points" % POINTS_MAX)
        o.npoints = len(pts)
        for i, x in enumerate(pts):
            o.x_points[i] = x
        self.m, self.p = model(veh), ctypes.c_void_p()
        veh._call("rr_vertical_plan_new", ctypes.byref(o), ctypes.byref(self.p))
        self.nfreq = int(nfreq)

    def close(self):
        self.lib.rr_vertical_plan_free(self.p)

    def complex(self, ptr, n):
        return _array(ptr, 2 * n).view(np.complex128)


def model(veh):
    """The vertical model of a Vehicle (its matrices as a ctypes struct)."""
    veh._live()
    m = _VModel()
    veh._call("rr_vertical_model_build", veh._veh, ctypes.byref(m))
    return m


def matrices(veh):
    m = model(veh)
    mat = lambda a, r, c: np.ctypeslib.as_array(a).reshape(r, c).copy()  # noqa: E731
    return {"M": np.diag(np.ctypeslib.as_array(m.M)), "K": mat(m.K, VDOF, VDOF), "C": mat(m.C, VDOF, VDOF),
            "BK": mat(m.BK, VDOF, VINPUTS), "BC": mat(m.BC, VDOF, VINPUTS),
            "x_wheelsets": np.array(m.x_wheelsets), "phi_pivots": np.array(m.phi_pivots), "dofs": DOF_NAMES}


def modes(veh):
    m, md = model(veh), _VModes()
    veh._call("rr_vertical_modes_compute", ctypes.byref(m), ctypes.byref(md))
    ms = md.mode[:md.nmodes]
    return {"freq_hz": np.array([x.freq_hz for x in ms]), "natural_hz": np.array([x.natural_hz for x in ms]),
            "damping_ratio": np.array([x.damping_ratio for x in ms]),
            "eigenvalue": np.array([complex(x.re, x.im) for x in ms]),
            "energy": np.array([list(x.energy) for x in ms]).reshape(-1, VDOF),
            "name": [x.name.decode() for x in ms], "overdamped_real": np.array(md.real[:md.nreal]),
            "undamped_hz": np.array(md.undamped_hz)}


def frf(veh, speed_kmh, points=None, nfreq=400, f_lo=0.3, f_hi=30.0):
    pl = _Plan(veh, points, nfreq, f_lo, f_hi, 5.0)
    try:
        veh._call("rr_vertical_frf_execute", pl.p, ctypes.byref(pl.m), speed_kmh / KMH)
        n, np_ = pl.nfreq, veh._lib.rr_vertical_npoints(pl.p)
        f = _array(veh._lib.rr_vertical_freqs(pl.p), n)
        H = pl.complex(veh._lib.rr_vertical_frf_H(pl.p), n * np_).reshape(n, np_)
        Q = pl.complex(veh._lib.rr_vertical_frf_Q(pl.p), n * VDOF).reshape(n, VDOF)
    finally:
        pl.close()
    return f, H, Q


def ride(veh, speed_kmh, spectrum="tbt3352-vertical", points=None, window=5.0, lateral=None):
    """Every vertical index per floor point; with lateral=(conicity, spectrum)
    also the lateral Wd 5 s percentiles and EN 12299's N_MV, N_VD, N_VA."""
    pl, sp = _Plan(veh, points, 400, 0.3, 30.0, window), ctypes.c_void_p()
    try:
        veh._call("rr_spectrum_new", spectrum.encode(), ctypes.byref(sp))
        np_ = len(points) if points is not None else 3
        pts = (_VPoint * np_)()
        veh._call("rr_vertical_ride_execute", pl.p, ctypes.byref(pl.m), speed_kmh / KMH, sp, pts)
        n = pl.nfreq
        out = {"f": _array(veh._lib.rr_vertical_freqs(pl.p), n),
               "track_psd": _array(veh._lib.rr_vertical_track_psd(pl.p), n),
               "psd": _array(veh._lib.rr_vertical_psd(pl.p), n * np_).reshape(n, np_)}
        for k in ("x", "rms", "sperling", "sperling_gb", "wk_rms", "wb_rms", "wb_iso8041_rms", "n_mv_vertical"):
            out[k] = np.array([getattr(p, k) for p in pts])
        for k in ("shape_k", "p50", "p95", "mean"):
            out["wb_" + k] = np.array([getattr(p.wb_5s, k) for p in pts])
        if lateral is not None:
            _lateral(veh, pl, out, speed_kmh, lateral)
    finally:
        if sp:
            veh._lib.rr_spectrum_delete(sp)
        pl.close()
    return out


def _lateral(veh, pl, out, speed_kmh, lateral):
    conicity, spectrum = lateral if isinstance(lateral, tuple) else (lateral, "wuhan-guangzhou")
    f, G, pts = veh._ride_run(speed_kmh, conicity, spectrum, tuple(out["x"]), 1.2, 400, 0.3, 30.0, "undefined")
    if f.size != out["f"].size or not np.allclose(f, out["f"], rtol=1e-12, atol=0):
        raise veh._Err("the lateral and vertical grids differ")
    G = np.ascontiguousarray(G)
    ws = (_WindowStats * G.shape[1])()
    veh._call("rr_vertical_window_stats", pl.p, _ptr(G), G.shape[1], G.shape[1], WD, ws)
    out["lateral_stable"] = bool(pts[0].stable == 1)
    if pts[0].stable == 0:  # the lateral model unstable: its side undefined, EN 12299 with it
        for w in ws:
            w.p50 = w.p95 = float("nan")
    out["lateral_psd"] = G
    out["wd_p50"], out["wd_p95"] = np.array([w.p50 for w in ws]), np.array([w.p95 for w in ws])
    en = [veh._lib.rr_en12299_indices(ctypes.byref(_ENInputs(0, 0, w.p50, w.p95, a, b)))
          for w, a, b in zip(ws, out["wb_p50"], out["wb_p95"])]  # longitudinal 0, rigid seat
    for k in ("n_mv", "n_vd", "n_va_rigid_seat"):
        out[k] = np.array([getattr(e, k) for e in en])
