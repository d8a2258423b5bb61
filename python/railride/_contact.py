"""Contact geometry and the equivalent conicity (EN 15302) from wheel and rail
profiles as numpy arrays (ctypes over include/railride/contact.h; lengths in mm)."""
import ctypes

import numpy as np

c_double_p = ctypes.POINTER(ctypes.c_double)


class _Polyline(ctypes.Structure):
    _fields_ = [("n", ctypes.c_int), ("x", c_double_p), ("z", c_double_p)]


class _ContactOpts(ctypes.Structure):
    _fields_ = [("gauge_mm", ctypes.c_double), ("flange_back_mm", ctypes.c_double),
                ("wheel_origin_mm", ctypes.c_double), ("inclination", ctypes.c_double),
                ("gmp_depth_mm", ctypes.c_double), ("gmp_right_mm", ctypes.c_double),
                ("gmp_left_mm", ctypes.c_double), ("lateral_offset_mm", ctypes.c_double),
                ("r0_right_mm", ctypes.c_double), ("r0_left_mm", ctypes.c_double), ("roll", ctypes.c_int)]


class _Side(ctypes.Structure):
    _fields_ = [("rail_v_mm", ctypes.c_double), ("rail_z_mm", ctypes.c_double), ("wheel_u_mm", ctypes.c_double),
                ("wheel_z_mm", ctypes.c_double), ("r_mm", ctypes.c_double), ("gamma_rad", ctypes.c_double),
                ("lift_mm", ctypes.c_double), ("valid", ctypes.c_int)]


class _State(ctypes.Structure):
    _fields_ = [("y_mm", ctypes.c_double), ("dr_mm", ctypes.c_double), ("roll_rad", ctypes.c_double),
                ("roll_implied_rad", ctypes.c_double), ("side", _Side * 2), ("valid", ctypes.c_int)]


class _Conicity(ctypes.Structure):
    _fields_ = [("amplitude_mm", ctypes.c_double), ("tan_gamma_e", ctypes.c_double),
                ("turning_mm", ctypes.c_double * 2), ("energy", ctypes.c_double), ("wavelength_mm", ctypes.c_double),
                ("tan_gamma_e_harmonic", ctypes.c_double), ("harmonic_centre_mm", ctypes.c_double),
                ("tan_gamma_e_regression", ctypes.c_double)]


def _declare(lib):
    P, E = ctypes.c_void_p, ctypes.c_void_p
    sig = {"rr_polyline_load": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(_Polyline), E]),
           "rr_polyline_free": (None, [ctypes.POINTER(_Polyline)]),
           "rr_contact_opts_default": (_ContactOpts, []),
           "rr_contact_plan_new": (ctypes.c_int, [ctypes.POINTER(_Polyline)] * 4 + [ctypes.POINTER(_ContactOpts),
                                                                               ctypes.POINTER(P), E]),
           "rr_contact_plan_free": (None, [P]),
           "rr_contact_execute": (ctypes.c_int, [P, c_double_p, ctypes.c_int, ctypes.POINTER(_State), E]),
           "rr_contact_range": (ctypes.c_long, [ctypes.c_double, ctypes.c_double, ctypes.c_double, c_double_p,
                                                ctypes.c_long]),
           "rr_conicity_plan_new": (ctypes.c_int, [c_double_p, c_double_p, ctypes.POINTER(ctypes.c_int), ctypes.c_int,
                                                   ctypes.POINTER(P), E]),
           "rr_conicity_plan_free": (None, [P]), "rr_conicity_y0": (ctypes.c_double, [P]),
           "rr_conicity_eval": (None, [P, ctypes.c_double, ctypes.c_double, ctypes.c_double,
                                       ctypes.POINTER(_Conicity)])}
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args


def _range(lib, a, b, step):
    n = lib.rr_contact_range(a, b, step, None, 0)
    if n < 1:
        raise ValueError("range %g:%g:%g is empty" % (a, b, step))
    out = np.empty(n)
    lib.rr_contact_range(a, b, step, out.ctypes.data_as(c_double_p), n)
    return out


def contact(wheel, rail, wheel_left=None, rail_left=None, gauge=1435.0, flange_back=1360.0, wheel_origin=70.0,
            inclination=0.0, rail_gmp=None, gmp_depth=14.0, lateral_offset=None, radius=(460.0, 460.0),
            roll="none", y_range=(-10.0, 10.0, 0.01), amplitudes=(0.5, 10.0, 0.1), e0=None):
    """The contact geometry of a wheelset on its track (profile files, mm) and
    the equivalent conicity function, as `railride contact` computes them: a
    dict of numpy arrays y_mm, dr_mm, r_right_mm, r_left_mm, gamma_right_rad,
    gamma_left_rad, roll_rad, valid; amplitude_mm, tan_gamma_e (EN 15302's
    method), tan_gamma_e_harmonic, tan_gamma_e_regression, turning_points_mm
    (n x 2), wavelength_mm; y0_mm and tan_gamma_e_3mm. Undefined values are NaN.
    y_range: a (from, to, step) tuple; amplitudes: a (from, to, step) tuple or a
    list of amplitudes."""
    from . import library, RailrideError
    from ._model import _Error
    lib = library()
    if not getattr(lib, "_contact_declared", False):
        _declare(lib)
        lib._contact_declared = True
    err = _Error()
    names = [wheel, wheel_left or wheel, rail, rail_left or rail]
    polys = [_Polyline() for _ in names]
    loaded, plan, cp = [], ctypes.c_void_p(), ctypes.c_void_p()
    try:
        for name, p in zip(names, polys):
            if lib.rr_polyline_load(str(name).encode(), ctypes.byref(p), ctypes.byref(err)):
                raise RailrideError(err.msg.decode())
            loaded.append(p)
        o = lib.rr_contact_opts_default()
        o.gauge_mm, o.flange_back_mm, o.wheel_origin_mm = gauge, flange_back, wheel_origin
        o.inclination, o.gmp_depth_mm = inclination, gmp_depth
        o.gmp_right_mm = o.gmp_left_mm = float("nan") if rail_gmp is None else rail_gmp
        o.lateral_offset_mm = float("nan") if lateral_offset is None else lateral_offset
        r = np.atleast_1d(np.asarray(radius, dtype=np.float64))
        o.r0_right_mm, o.r0_left_mm = r[0], r[-1]
        o.roll = {"none": 0, "rigid": 1}[roll]
        if lib.rr_contact_plan_new(*[ctypes.byref(p) for p in polys], ctypes.byref(o), ctypes.byref(plan),
                                   ctypes.byref(err)):
            raise RailrideError(err.msg.decode())
        y = _range(lib, *y_range)
        st = (_State * y.size)()
        if lib.rr_contact_execute(plan, y.ctypes.data_as(c_double_p), y.size, st, ctypes.byref(err)):
            raise RailrideError(err.msg.decode())
        out = {"y_mm": y, "dr_mm": np.array([s.dr_mm for s in st]),
               "r_right_mm": np.array([s.side[0].r_mm for s in st]), "r_left_mm": np.array([s.side[1].r_mm for s in st]),
               "gamma_right_rad": np.array([s.side[0].gamma_rad for s in st]),
               "gamma_left_rad": np.array([s.side[1].gamma_rad for s in st]),
               "roll_rad": np.array([s.roll_rad for s in st]), "valid": np.array([bool(s.valid) for s in st])}
        valid = np.ascontiguousarray(out["valid"].astype(np.intc))
        dr = np.ascontiguousarray(out["dr_mm"])
        if lib.rr_conicity_plan_new(y.ctypes.data_as(c_double_p), dr.ctypes.data_as(c_double_p),
                                    valid.ctypes.data_as(ctypes.POINTER(ctypes.c_int)), y.size, ctypes.byref(cp),
                                    ctypes.byref(err)):
            raise RailrideError(err.msg.decode())
        amps = _range(lib, *amplitudes) if len(amplitudes) == 3 and not np.ndim(amplitudes[0]) and \
            isinstance(amplitudes, tuple) else np.asarray(amplitudes, dtype=np.float64)
        b = flange_back / 2 + wheel_origin
        e0v, r0v = (b if e0 is None else e0), (r[0] + r[-1]) / 2
        cs = []
        for a in list(amps) + [3.0]:
            c = _Conicity()
            lib.rr_conicity_eval(cp, float(a), e0v, r0v, ctypes.byref(c))
            cs.append(c)
        c3, cs = cs[-1], cs[:-1]
        out.update({"amplitude_mm": amps, "tan_gamma_e": np.array([c.tan_gamma_e for c in cs]),
                    "tan_gamma_e_harmonic": np.array([c.tan_gamma_e_harmonic for c in cs]),
                    "tan_gamma_e_regression": np.array([c.tan_gamma_e_regression for c in cs]),
                    "turning_points_mm": np.array([list(c.turning_mm) for c in cs]).reshape(-1, 2),
                    "wavelength_mm": np.array([c.wavelength_mm for c in cs]),
                    "y0_mm": lib.rr_conicity_y0(cp), "tan_gamma_e_3mm": c3.tan_gamma_e})
        return out
    finally:
        lib.rr_conicity_plan_free(cp)
        lib.rr_contact_plan_free(plan)
        for p in loaded:  # each file was read into its own polyline
            lib.rr_polyline_free(ctypes.byref(p))


_WEAR_AMPS = np.arange(1.0, 7.5 + 1e-9, 0.5)  # the conicity function's amplitudes (mm), as `railride wear`


def _declare_vehicle(lib):
    P, E = ctypes.c_void_p, ctypes.c_void_p
    sig = {"rr_vehicle_set_profiles": (ctypes.c_int, [P, ctypes.c_char_p, ctypes.c_char_p, E]),
           "rr_vehicle_profile_conicity": (ctypes.c_int, [P, c_double_p, ctypes.c_char_p, ctypes.c_size_t, E]),
           "rr_vehicle_profile_conicity_function": (ctypes.c_int, [P, c_double_p, ctypes.c_int, c_double_p, E]),
           "rr_vehicle_key_find": (P, [ctypes.c_char_p]), "rr_vehicle_field": (c_double_p, [P, P])}
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args


def wear(wheels, rail=None, vehicle="type1", speed_kmh=350.0, spectrum="wuhan-guangzhou"):
    """The wear study of `railride wear`: each wheel profile (the wear stages,
    in order) on the rail (or the vehicle file's [contact] rail, with its
    placement keys), as numpy arrays over the profiles: tan_gamma_e_3mm, the
    conicity function tan_gamma_e (profiles x amplitude_mm, NaN where
    undefined), stability_index (NaN where undefined), zeta_max, stable,
    critical_speed_kmh (NaN when none up to 600 km/h) and sperling (profiles x
    the floor points +L, 0, -L); wheel names the files."""
    from . import library, RailrideError
    from ._model import Vehicle, _Error
    lib = library()
    if not getattr(lib, "_wear_declared", False):
        _declare_vehicle(lib)
        lib._wear_declared = True
    wheels = [str(w) for w in ([wheels] if isinstance(wheels, (str, bytes)) else wheels)]
    n, na = len(wheels), _WEAR_AMPS.size
    out = {"wheel": wheels, "amplitude_mm": _WEAR_AMPS.copy(), "tan_gamma_e_3mm": np.empty(n),
           "tan_gamma_e": np.empty((n, na)), "stability_index": np.empty(n), "zeta_max": np.empty(n),
           "stable": np.empty(n, dtype=bool), "critical_speed_kmh": np.empty(n), "sperling": np.empty((n, 3))}
    err = _Error()
    with Vehicle(vehicle) as v:
        def call(name, *args):
            if getattr(lib, name)(*args, ctypes.byref(err)):
                raise RailrideError(err.msg.decode())
        L = lib.rr_vehicle_field(v._veh, lib.rr_vehicle_key_find(b"layout.bogie_half_spacing"))[0]
        amps = np.ascontiguousarray(_WEAR_AMPS)
        for i, w in enumerate(wheels):
            call("rr_vehicle_set_profiles", v._veh, w.encode(), None if rail is None else str(rail).encode())
            tg3, tg = ctypes.c_double(), np.empty(na)
            call("rr_vehicle_profile_conicity", v._veh, ctypes.byref(tg3), None, 0)
            call("rr_vehicle_profile_conicity_function", v._veh, amps.ctypes.data_as(c_double_p), na,
                 tg.ctypes.data_as(c_double_p))
            out["tan_gamma_e_3mm"][i], out["tan_gamma_e"][i] = tg3.value, tg
            out["stability_index"][i] = v.map([speed_kmh], [tg3.value])[0, 0]
            out["zeta_max"][i] = v.map([speed_kmh], [tg3.value], what="zeta_max")[0, 0]
            out["stable"][i] = out["zeta_max"][i] < 0  # rr_modal_stable
            out["critical_speed_kmh"][i] = v.critical_speed(tg3.value)
            out["sperling"][i] = v.ride(speed_kmh, tg3.value, spectrum=spectrum, points=(L, 0.0, -L))["sperling"]
    return out
