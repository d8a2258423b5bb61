"""numpy doing the equivalent conicity of a dr(y) table as docs/contact.md
defines it, vectorised over the amplitudes: the equilibrium y0; (a) EN
15302's reference method (the kinematic wavelength against Klingel's: the
energy integral's turning points by one bisection on C for all amplitudes
at once, the wavelength integral by 8-point Gauss-Legendre in theta on the
pieces between grid points, all amplitudes' pieces in one array); (b) the
harmonic linearisation (closed form per segment, every segment of every
amplitude as one array, one bisection on the centre for all); (c) the
linear regression (closed form). Written from the contract independently of
railride's C (src/contact/conicity.c), as its side-by-side reference.
"""
import numpy as np

GL_X, GL_W = np.polynomial.legendre.leggauss(8)


def valid_run(y, dr, valid):
    """The run of valid points containing the grid point nearest y = 0."""
    k = int(np.argmin(np.abs(y)))
    if not valid[k]:
        return None
    lo, hi = k, k
    while lo > 0 and valid[lo - 1]:
        lo -= 1
    while hi < len(y) - 1 and valid[hi + 1]:
        hi += 1
    return y[lo:hi + 1], dr[lo:hi + 1]


def equilibrium(y, d):
    """y0: the sign change of dr from - to + nearest 0 (runs of exact zeros: their middle)."""
    cand = []
    i, n = 0, len(y)
    while i < n - 1:
        if d[i] < 0 < d[i + 1]:
            cand.append(y[i] - d[i] * (y[i + 1] - y[i]) / (d[i + 1] - d[i]))
        elif d[i] < 0 and d[i + 1] == 0:
            j = i + 1
            while j + 1 < n and d[j + 1] == 0:
                j += 1
            if j + 1 < n and d[j + 1] > 0:
                cand.append(y[i + 1] if j == i + 1 else 0.5 * (y[i + 1] + y[j]))
            i = j
            continue
        i += 1
    if not cand:
        return np.nan
    cand = np.array(cand)
    return cand[np.lexsort((cand, np.abs(cand)))[0]]


class Table:
    """dr on the valid run, with the potential S and the segment slopes."""

    def __init__(self, y, d, y0):
        self.y, self.d, self.y0 = y, d, y0
        self.h = np.diff(y)
        self.m = np.diff(d) / self.h
        n = len(y)
        self.i0 = i0 = int(np.clip(np.searchsorted(y, y0, "right") - 1, 0, n - 2))
        S = np.empty(n)
        trap = self.h * (d[:-1] + d[1:]) / 2
        S[i0 + 1] = (y[i0 + 1] - y0) * d[i0 + 1] / 2
        S[i0 + 2:] = S[i0 + 1] + np.cumsum(trap[i0 + 1:])
        S[i0] = -(y0 - y[i0]) * d[i0] / 2
        if i0 > 0:
            S[:i0] = S[i0] - np.cumsum(trap[:i0][::-1])[::-1]
        self.S = S
        self.right_max = np.maximum.accumulate(S[i0 + 1:])
        self.left_max = np.maximum.accumulate(S[:i0 + 1][::-1])
        self.trap_cum = np.concatenate(([0.0], np.cumsum(trap)))

    def dr(self, x, k):
        return self.d[k] + self.m[k] * (x - self.y[k])

    def turning(self, C, zero=False):
        """yL, yR for the energy levels C (array)."""
        y, S, d, m, i0, y0 = self.y, self.S, self.d, self.m, self.i0, self.y0
        side = "right" if zero else "left"
        # right: first grid point k >= i0 + 1 with running max >= C (> 0 for C = 0)
        kr = np.searchsorted(self.right_max, C, side) + i0 + 1
        out_r = kr >= len(y)
        kr = np.minimum(kr, len(y) - 1)
        first = kr == i0 + 1
        ya = np.where(first, y0, y[kr - 1])
        Sa = np.where(first, 0.0, S[kr - 1])
        da = np.where(first, 0.0, d[kr - 1])
        mk = m[kr - 1]
        q = C - Sa
        den = da + np.sqrt(np.maximum(da * da + 2 * mk * q, 0))
        t = np.where(den > 0, 2 * q / np.where(den > 0, den, 1), 0)
        yR = np.where(out_r, np.inf, np.minimum(ya + t, y[kr]))
        # left: mirror-wise from i0 down
        kl = i0 - np.searchsorted(self.left_max, C, side)
        out_l = kl < 0
        kl = np.maximum(kl, 0)
        first = kl == i0
        ya = np.where(first, y0, y[np.minimum(kl + 1, len(y) - 1)])
        Sa = np.where(first, 0.0, S[np.minimum(kl + 1, len(y) - 1)])
        da = np.where(first, 0.0, d[np.minimum(kl + 1, len(y) - 1)])
        mk = m[np.minimum(kl, len(m) - 1)]
        q = C - Sa
        den = -da + np.sqrt(np.maximum(da * da + 2 * mk * q, 0))
        t = np.where(den > 0, 2 * q / np.where(den > 0, den, 1), 0)
        yL = np.where(out_l, -np.inf, np.maximum(ya - t, y[kl]))
        return yL, yR


def wavelength_method(T, amps):
    """(a) tan gamma_e for each amplitude (NaN: undefined, 0: dead zone)."""
    amps = np.asarray(amps, float)
    out = np.full(amps.shape, np.nan)
    cmax = min(T.right_max[-1], T.left_max[-1])
    yl0, yr0 = T.turning(np.zeros(1), zero=True)
    a0 = (yr0[0] - yl0[0]) / 2
    yl1, yr1 = T.turning(np.array([cmax]))
    amax = (yr1[0] - yl1[0]) / 2
    dead = a0 >= amps
    out[dead] = 0.0
    todo = ~dead & (amax >= amps)
    if not todo.any():
        return out
    A = amps[todo]
    lo, hi = np.zeros(A.size), np.full(A.size, cmax)
    for _ in range(400):
        mid = (lo + hi) / 2
        live = (mid > lo) & (mid < hi)
        if not live.any():
            break
        yl, yr = T.turning(mid)
        below = (yr - yl) / 2 < A
        lo = np.where(live & below, mid, lo)
        hi = np.where(live & ~below, mid, hi)
    yl, yr = T.turning(hi)
    ok = np.abs((yr - yl) / 2 - A) <= 1e-9
    I = integral(T, hi, yl, yr)
    res = np.where(ok, (np.pi / I) ** 2, np.nan)
    out[np.flatnonzero(todo)] = res
    return out


def integral(T, C, yL, yR):
    """I = int dy / sqrt(C - S(y)) over (yL, yR) for each level, exact for the table."""
    y, d, m, y0 = T.y, T.d, T.m, T.y0
    L = yR - yL
    # the pieces: theta of yL, every grid point strictly inside, y0, yR
    # every amplitude's piece ends at once: yL, the grid points strictly inside, y0, yR
    ilo = np.searchsorted(y, yL, "right")
    ihi = np.searchsorted(y, yR, "left")
    cnt = np.maximum(ihi - ilo, 0)
    lab = np.repeat(np.arange(C.size), cnt)
    start = np.repeat(ilo - np.concatenate(([0], np.cumsum(cnt)[:-1])), cnt)
    inner = y[start + np.arange(lab.size)]
    k = np.arange(C.size)
    pts = np.concatenate((yL, inner, np.full(C.size, y0), yR))
    who = np.concatenate((k, lab, k, k))
    order = np.lexsort((pts, who))
    pts, who = pts[order], who[order]
    keep = np.concatenate(([True], (np.diff(pts) != 0) | (np.diff(who) != 0)))
    pts, who = pts[keep], who[keep]
    same = who[1:] == who[:-1]  # consecutive ends of one amplitude: a piece
    thp = 2 * np.arctan2(np.sqrt(np.maximum(pts - yL[who], 0)), np.sqrt(np.maximum(yR[who] - pts, 0)))
    ta, tb = thp[:-1][same], thp[1:][same]
    left_end = pts[:-1][same]  # each piece's left end, as given (not from its theta)
    amp = who[:-1][same]
    half = (tb - ta) / 2
    mid = (tb + ta) / 2
    th = mid[:, None] + half[:, None] * GL_X[None, :]
    La, yLa, yRa = L[amp][:, None], yL[amp][:, None], yR[amp][:, None]
    yy = yLa + La * np.sin(th / 2) ** 2
    # each piece's segment from its left end
    seg = np.clip(np.searchsorted(y, left_end, "right") - 1, 0, len(y) - 2)[:, None]
    segL = np.clip(np.searchsorted(y, yL, "right") - 1, 0, len(y) - 2)[amp][:, None]
    segR = np.clip(np.searchsorted(y, yR, "right") - 1, 0, len(y) - 2)[amp][:, None]
    drY = d[seg] + m[seg] * (yy - y[seg])
    drL = d[segL] + m[segL] * (yLa - y[segL])
    drR = d[segR] + m[segR] * (yRa - y[segR])
    leftside = (left_end < y0)[:, None]
    # left of y0: Q = -int_yL^y dr
    j1 = segL + 1
    PLj = -((y[j1] - yLa) * (drL + d[j1]) / 2 + (T.trap_cum[seg] - T.trap_cum[j1]))
    QL = PLj - (yy - y[seg]) * (d[seg] + drY) / 2
    FL_first = np.sqrt(La) * np.cos(th / 2) / np.sqrt(np.maximum(-(drL + drY) / 2, 1e-300))
    FL = np.where(seg == segL, FL_first, (La / 2) * np.sin(th) / np.sqrt(np.maximum(QL, 1e-300)))
    # right of y0: Q = int_y^yR dr
    PRj1 = (T.trap_cum[segR] - T.trap_cum[seg + 1]) + (yRa - y[segR]) * (d[segR] + drR) / 2
    QR = PRj1 + (y[seg + 1] - yy) * (drY + d[seg + 1]) / 2
    FR_first = np.sqrt(La) * np.sin(th / 2) / np.sqrt(np.maximum((drY + drR) / 2, 1e-300))
    FR = np.where(seg == segR, FR_first, (La / 2) * np.sin(th) / np.sqrt(np.maximum(QR, 1e-300)))
    F = np.where(leftside, FL, FR)
    piece = (F * GL_W[None, :]).sum(axis=1) * half
    return np.bincount(amp, weights=piece, minlength=C.size)


def segment_integrals(T, centre, amps):
    """Per amplitude, over every segment clipped to [centre - a, centre + a]: the pieces' theta,
    alpha and beta (dr = alpha + beta s, s = y - centre)."""
    y, d, m = T.y, T.d, T.m
    c, a = centre[:, None], amps[:, None]
    ya = np.maximum(y[None, :-1], c - a)
    yb = np.minimum(y[None, 1:], c + a)
    live = yb > ya
    sa = np.where(ya == c - a, -1.0, np.clip((ya - c) / a, -1, 1))  # the window's ends exactly
    sb = np.where(yb == c + a, 1.0, np.clip((yb - c) / a, -1, 1))
    alpha = d[None, :-1] + m[None, :] * (c - y[None, :-1])
    return sa, sb, alpha, np.broadcast_to(m[None, :], sa.shape), live


def harmonic_mean(T, yc, amps):
    sa, sb, alpha, beta, live = segment_integrals(T, yc, amps)
    ta, tb = np.arcsin(sa), np.arcsin(sb)
    terms = alpha * (tb - ta) - beta * amps[:, None] * (np.cos(tb) - np.cos(ta))
    return np.where(live, terms, 0).sum(axis=1) / np.pi


def harmonic_method(T, amps):
    """(b) first-harmonic fit about the centre where the mean of dr vanishes."""
    amps = np.asarray(amps, float)
    y = T.y
    lo = np.maximum(T.y0 - amps, y[0] + amps)
    hi = np.minimum(T.y0 + amps, y[-1] - amps)
    ok = (lo <= hi) & (harmonic_mean(T, lo, amps) <= 0) & (harmonic_mean(T, hi, amps) >= 0)
    # the centre where M = 0, bracketed: regula falsi with the Illinois halving (the same
    # root as the contract's bisection, to its 1e-12 mm, in a few evaluations)
    mlo, mhi = harmonic_mean(T, lo, amps), harmonic_mean(T, hi, amps)
    side = np.zeros(amps.shape, int)
    for _ in range(100):
        live = ok & (hi - lo > 1e-12)
        if not live.any():
            break
        den = mhi - mlo
        x = np.where(den != 0, hi - mhi * (hi - lo) / np.where(den != 0, den, 1), (lo + hi) / 2)
        x = np.where((x > lo) & (x < hi), x, (lo + hi) / 2)
        mx = harmonic_mean(T, x, amps)
        exact = live & (mx == 0)
        lo, hi = np.where(exact, x, lo), np.where(exact, x, hi)
        neg = live & ~exact & (mx < 0)
        pos = live & ~exact & (mx > 0)
        mhi = np.where(neg & (side == -1), mhi / 2, mhi)  # the kept end twice in a row: halve it
        mlo = np.where(pos & (side == 1), mlo / 2, mlo)
        lo, mlo = np.where(neg, x, lo), np.where(neg, mx, mlo)
        hi, mhi = np.where(pos, x, hi), np.where(pos, mx, mhi)
        side = np.where(neg, -1, np.where(pos, 1, side))
        # a bracket that has stopped shrinking around a root well within the tolerance
        tiny = live & (np.abs(mx) <= 1e-15 * np.maximum(np.abs(mlo), np.abs(mhi)))
        lo, hi = np.where(tiny, x, lo), np.where(tiny, x, hi)
    yc = (lo + hi) / 2
    sa, sb, alpha, beta, live = segment_integrals(T, yc, amps)
    ta, tb = np.arcsin(sa), np.arcsin(sb)
    A = amps[:, None]
    terms = -(alpha / A) * (np.cos(tb) - np.cos(ta)) + beta * (
        (tb - ta) / 2 - (np.sin(2 * tb) - np.sin(2 * ta)) / 4)
    tg = np.where(live, terms, 0).sum(axis=1) / np.pi
    return np.where(ok, tg, np.nan)


def regression_method(T, amps):
    """(c) half the slope of the least-squares line through dr over y0 +- a."""
    amps = np.asarray(amps, float)
    inside = (T.y0 - amps >= T.y[0]) & (T.y0 + amps <= T.y[-1])
    sa, sb, alpha, beta, live = segment_integrals(T, np.full(amps.shape, T.y0), amps)
    A = amps[:, None]
    sa, sb = sa * A, sb * A
    terms = alpha * (sb ** 2 - sa ** 2) / 2 + beta * (sb ** 3 - sa ** 3) / 3
    tg = 3 / (4 * amps ** 3) * np.where(live, terms, 0).sum(axis=1)
    return np.where(inside, tg, np.nan)


def conicity(y, dr, valid, amps):
    """y0 and the three methods' tan gamma_e at each amplitude."""
    run = valid_run(y, dr, valid)
    nan = np.full(len(amps), np.nan)
    if run is None:
        return np.nan, nan, nan, nan
    yv, dv = run
    y0 = equilibrium(yv, dv)
    if not np.isfinite(y0):
        return y0, nan, nan, nan
    T = Table(yv, dv, y0)
    return y0, wavelength_method(T, amps), harmonic_method(T, amps), regression_method(T, amps)
